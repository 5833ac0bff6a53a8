#!/bin/sh
# Runs where vcan0 exists (inside the vcan VM on kernels without CAN): replays $OUT/head.log on
# vcan0 with canplayer while meter-controller reads SocketCAN, then stops it with SIGTERM. Then the
# E2E attack: a controller protecting one message (e2e_attack/) reads $OUT/attack.log, genuine
# frames followed by forged and replayed ones, from vcan0 (about 2 s).
set -u
. "$METER_SRC/controller/tests/guest_controller_ready.sh"
"$METER_BIN" run -v --dbc "$METER_SRC/controller/vehicles/demo/demo.dbc" --map "$METER_SRC/controller/vehicles/demo/demo.map" \
  --input can:vcan0 --link tcp:127.0.0.1:0 > "$OUT/ctl.out" 2> "$OUT/ctl.err" &
pid=$!
controller_ready "$OUT/ctl.err" "$pid"
canplayer -I "$OUT/head.log"
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/ctl.err"

"$METER_BIN" run -v --dbc "$METER_SRC/controller/tests/e2e_attack/attack.dbc" --map "$METER_SRC/controller/tests/e2e_attack/attack.map" \
  --input can:vcan0 --link tcp:127.0.0.1:0 > "$OUT/e2e.out" 2> "$OUT/e2e.err" &
pid=$!
controller_ready "$OUT/e2e.err" "$pid"
canplayer -I "$OUT/attack.log"
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/e2e.err"
