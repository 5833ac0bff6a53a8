#!/bin/sh
# Runs where vcan0 exists (inside the vcan VM on kernels without CAN): replays $OUT/head.log on
# vcan0 with canplayer while meter-controller reads SocketCAN, then stops it with SIGTERM.
set -u
"$METER_BIN" run -v --dbc "$METER_SRC/controller/vehicles/demo/demo.dbc" --map "$METER_SRC/controller/vehicles/demo/demo.map" \
  --input can:vcan0 --link tcp:127.0.0.1:0 > "$OUT/ctl.out" 2> "$OUT/ctl.err" &
pid=$!
# Until the controller has its CAN socket open (its -v line "... -> tcp:..." comes after it): a fixed
# sleep raced with its start-up on the guest's instruction clock, where the guest's waits for the
# host's 9p share take no guest time, and the replay began before the controller listened (2255 of
# 2500 frames received). run-in-vm's timeout bounds the wait.
until grep -q " -> " "$OUT/ctl.err" 2>/dev/null; do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
canplayer -I "$OUT/head.log"
sleep 0.3
kill -TERM $pid
wait $pid
echo "exit=$?" >> "$OUT/ctl.err"
