#!/usr/bin/env bash
# One VM boot for the controller's vcan tests (socketcan_vcan, two_bus_vcan, socketcan_buses):
# each test prepares its inputs, the guest runs their guest scripts one after another (vcan0 and
# vcan1; socketcan_buses last, since it sets vcan0's MTU for CAN FD) and marks each part it ran
# (shared-boot in the test's folder), and each test then judges its own part (its STEP "shared").
# A test whose part the boot did not reach boots a VM of its own. Not a verdict itself: it fails
# only when the VM harness does (no boot, timeout).
# usage: vcan_session_test.sh SOURCE_DIR BINARY_DIR
set -euo pipefail
src=$1 bin=$2
here=$src/controller/tests
guest=""
for t in socketcan_vcan_test.sh two_bus_vcan_test.sh socketcan_buses_test.sh; do
  "$here/$t" "$src" "$bin" prepare
  { read -r out; read -r cmd; } < <("$here/$t" "$src" "$bin" guest)
  guest+="$cmd; touch $out/shared-boot; "
done
# Each test's own bound (110 s, 110 s, the flood plus 120 s) and the boot.
timeout=$((30 + 110 + 110 + ${METER_FLOOD_S:-60} + 120))
rc=0
# The guest's clock counts its instructions (run-in-vm --guest-clock instructions, one vCPU): these
# tests meet nothing on the host in real time, and what they time (the flood's kernel stamp ->
# decoded latency, the signals' timeouts after the replay) is then the guest's own work, not the
# time a busy host took the guest's CPU away.
"$src/vcan/with-vcan" --guest-clock instructions --vcan vcan0 --vcan vcan1 --share-out "$bin/controller/tests" \
  --timeout "$timeout" \
  -- /bin/bash -c "$guest" || rc=$?
echo "vcan_session: guest parts run, exit $rc (each test judges its own part)"
((rc != 124 && rc != 125)) || exit "$rc"
