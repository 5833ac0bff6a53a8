#!/usr/bin/env bash
# vcan test: meter-controller on a real SocketCAN vcan0 (directly, or in the qemu VM through
# vcan/with-vcan) receives the first 2500 demo-drive frames replayed by canplayer and decodes them;
# then, on the same boot, a controller checking a protected message end to end refuses and counts
# forged frames (wrong checksum) and replayed ones (repeated counter) sent on vcan0.
# usage: socketcan_vcan_test.sh SOURCE_DIR BINARY_DIR [STEP]
#   STEP all (default): prepare, boot, judge; prepare | guest (the command to run where vcan0 is) |
#   judge: the steps alone, for the shared boot of vcan_session_test.sh; shared: judge the shared
#   boot's run when it made one, else all.
set -euo pipefail
src=$1 bin=$2 step=${3:-all}
out=$bin/controller/tests/vcan-out
# shellcheck source=controller/tests/vcan_test_steps.sh
source "$src/controller/tests/vcan_test_steps.sh"
vcan_test_step "$step" "$out" "env METER_BIN=$bin/bin/meter-controller METER_SRC=$src OUT=$out /bin/sh $src/controller/tests/socketcan_guest.sh"
if [[ $step == prepare || $step == all ]]; then
  rm -rf "$out" && mkdir -p "$out"
  # 12.1 s of the drive: the first 2500 frames of its vehicle buses (the head unit's cluster
  # settings, id 0x611, are a stream of their own and left out so the slice keeps its length in time)
  awk '!/ 611#/ && n++ < 2500' "$src/vcan/logs/demo-drive.log" > "$out/head.log"
  /usr/bin/python3 "$src/controller/tests/e2e_attack/attack_log.py" "$out/attack.log"
fi
[[ $step == prepare ]] && exit 0
if [[ $step == all ]]; then
  "$src/vcan/with-vcan" --guest-clock instructions --share-out "$out" --timeout 110 \
    --env "METER_BIN=$bin/bin/meter-controller" --env "METER_SRC=$src" --env "OUT=$out" \
    -- /bin/sh "$src/controller/tests/socketcan_guest.sh"
else
  echo "judging the run of the shared boot (controller.vcan_drives) in $out"
fi
fail() { echo "FAIL: $*"; echo "--- ctl.err"; cat "$out/ctl.err"; echo "--- ctl.out"; cat "$out/ctl.out"; exit 1; }
grep -q "exit=0" "$out/ctl.err" || fail "controller did not exit cleanly on SIGTERM"
grep -q "SocketCAN vcan0" "$out/ctl.err" || fail "controller did not open SocketCAN"
grep -q " 2500 frames (2500 mapped, 0 unknown id" "$out/ctl.out" || fail "not all 2500 frames were received and mapped"
# Gear at 12.1 s is first (held on timeout); speed 130*smoothstep(8,30,12.1 s) = 11.8 km/h, shown
# with the R39 over-read and timed out once the replay stopped.
grep -q "final Vehicle.Powertrain.Transmission.CurrentGear = 1 (valid)" "$out/ctl.err" || fail "gear"
speed=$(sed -n 's/.*final Vehicle.Speed = \([0-9.]*\) (timed-out).*/\1/p' "$out/ctl.err")
[[ -n $speed ]] || fail "speed not reported as timed-out"
awk -v s="$speed" 'BEGIN { exit !(s >= 11.0 && s <= 13.5) }' || fail "speed $speed not near 11.8..13 km/h"
# The E2E attack: 100 genuine frames used, 20 forged (wrong checksum) and 20 replayed (repeated
# counter) refused and counted; the forged 180 km/h never shown.
efail() { echo "FAIL: e2e attack: $*"; echo "--- e2e.err"; cat "$out/e2e.err"; echo "--- e2e.out"; cat "$out/e2e.out"; exit 1; }
grep -q "exit=0" "$out/e2e.err" || efail "controller did not exit cleanly on SIGTERM"
grep -q " 140 frames (100 mapped, 0 unknown id, 0 error frames, 40 refused by e2e checks)" "$out/e2e.out" || efail "not 100 used and 40 refused"
grep -q "e2e: SPEED 40 of 140 refused (20 checksum, 20 repeated, 0 out of sequence; 0 lost)" "$out/e2e.out" || efail "counts per reason"
grep -q "vcan0: e2e: .* frame(s) refused (not used: SPEED" "$out/e2e.err" || efail "no log line for the refused frames"
grep -q "final Vehicle.Speed = 50 (timed-out)" "$out/e2e.err" || efail "the speed is not the genuine 50 km/h, timed out"
echo "PASS: SocketCAN vcan0: 2500 frames, speed $speed km/h; e2e attack: 20 forged and 20 replayed frames refused"
