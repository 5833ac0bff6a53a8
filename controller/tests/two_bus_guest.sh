#!/bin/sh
# Runs where vcan0 and vcan1 exist (inside the vcan VM on kernels without CAN): one controller reads
# both buses, link_probe subscribes over TCP, canplayer replays $OUT/split.log (can0 -> vcan0,
# can1 -> vcan1), then the controller is stopped with SIGTERM.
set -u
dbc="$METER_SRC/controller/vehicles/demo/demo.dbc"
"$METER_BIN/meter-controller" run -v --input body=can:vcan0 --input chassis=can:vcan1 \
  --dbc "body=$dbc" --dbc "chassis=$dbc" --map "$OUT/two-bus.map" --link tcp:127.0.0.1:7411 \
  > "$OUT/ctl.out" 2> "$OUT/ctl.err" &
pid=$!
# Until the controller has its CAN socket open (its -v line "... -> tcp:..." comes after it): a fixed
# sleep raced with its start-up on the guest's instruction clock, where the guest's waits for the
# host's 9p share take no guest time, and the replay began before the controller listened (2255 of
# 2500 frames received). run-in-vm's timeout bounds the wait.
until grep -q " -> " "$OUT/ctl.err" 2>/dev/null; do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
"$METER_BIN/link_probe" tcp:127.0.0.1:7411 16 > "$OUT/probe.out" 2> "$OUT/probe.err" &
probe=$!
sleep 0.5
canplayer -I "$OUT/split.log" vcan0=can0 vcan1=can1
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/ctl.err"
wait $probe
