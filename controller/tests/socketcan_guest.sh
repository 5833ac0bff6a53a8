#!/bin/sh
# Runs where vcan0 exists (inside the vcan VM on kernels without CAN): replays $OUT/head.log on
# vcan0 with canplayer while meter-controller reads SocketCAN, then stops it with SIGTERM. Then the
# E2E attack: a controller protecting one message (e2e_attack/) reads $OUT/attack.log, genuine
# frames followed by forged and replayed ones, from vcan0 (about 2 s).
set -u
. "$METER_SRC/controller/tests/guest_controller_ready.sh"

# replay_into DBC MAP LOG NAME: a controller on vcan0 (stdout NAME.out, stderr NAME.err) while
# canplayer replays LOG, stopped with SIGTERM; its exit status ends NAME.err.
replay_into() {
  "$METER_BIN" run -v --dbc "$1" --map "$2" --input can:vcan0 --link tcp:127.0.0.1:0 --insecure-link > "$OUT/$4.out" 2> "$OUT/$4.err" &
  pid=$!
  controller_ready "$OUT/$4.err" "$pid"
  canplayer -I "$3"
  sleep 0.3
  kill -TERM $pid
  wait $pid
  echo "exit=$?" >> "$OUT/$4.err"
}

replay_into "$METER_SRC/controller/vehicles/demo/demo.dbc" "$METER_SRC/controller/vehicles/demo/demo.map" "$OUT/head.log" ctl
replay_into "$METER_SRC/controller/tests/e2e_attack/attack.dbc" "$METER_SRC/controller/tests/e2e_attack/attack.map" \
  "$OUT/attack.log" e2e
