#!/bin/sh
# Runs where vcan0 and vcan1 exist (inside the vcan VM on kernels without CAN): one controller reads
# both buses, link_probe subscribes over TCP, canplayer replays $OUT/split.log (can0 -> vcan0,
# can1 -> vcan1), then the controller is stopped with SIGTERM.
set -u
. "$METER_SRC/controller/tests/guest_controller_ready.sh"
dbc="$METER_SRC/controller/vehicles/demo/demo.dbc"
"$METER_BIN/meter-controller" run -v --input body=can:vcan0 --input chassis=can:vcan1 \
  --dbc "body=$dbc" --dbc "chassis=$dbc" --map "$OUT/two-bus.map" --link tcp:127.0.0.1:7411 --insecure-link \
  > "$OUT/ctl.out" 2> "$OUT/ctl.err" &
pid=$!
controller_ready "$OUT/ctl.err" "$pid"
"$METER_BIN/link_probe" tcp:127.0.0.1:7411 16 > "$OUT/probe.out" 2> "$OUT/probe.err" &
probe=$!
sleep 0.5
canplayer -I "$OUT/split.log" vcan0=can0 vcan1=can1
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/ctl.err"
wait $probe
