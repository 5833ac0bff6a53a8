#!/bin/sh
# Runs where vcan0 exists (inside the vcan VM on kernels without CAN): replays $OUT/head.log on
# vcan0 with canplayer while meter-controller reads SocketCAN, then stops it with SIGTERM.
set -u
. "$METER_SRC/controller/tests/guest_controller_ready.sh"
"$METER_BIN" run -v --dbc "$METER_SRC/controller/vehicles/demo/demo.dbc" --map "$METER_SRC/controller/vehicles/demo/demo.map" \
  --input can:vcan0 --link tcp:127.0.0.1:0 --insecure-link > "$OUT/ctl.out" 2> "$OUT/ctl.err" &
pid=$!
controller_ready "$OUT/ctl.err" "$pid"
canplayer -I "$OUT/head.log"
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/ctl.err"
