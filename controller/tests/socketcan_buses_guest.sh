#!/bin/bash
# Runs where vcan0 exists (inside the vcan VM on kernels without CAN). Two phases, each with a
# fresh meter-controller on the socketcan_buses vehicle (CAN FD + extended ids + J1939):
#   A  $OUT/buses.log (FD frames, J1939 groups from two source addresses, unmapped and unknown ids,
#      a remote frame, error frames) replayed by canplayer;
#   B  cangen floods a mapped id (Body, 0x123) at full rate for $FLOOD_S seconds.
# Everything observed goes to $OUT: ctlA.*, ctlB.*, flood.txt, rss.txt, latency.txt.
set -u
. "$METER_SRC/controller/tests/guest_controller_ready.sh"
dbc=$METER_SRC/controller/tests/data/socketcan_buses.dbc
map=$METER_SRC/controller/tests/data/socketcan_buses.map
# CAN FD needs MTU 72; vcan takes a new MTU only while down.
ip link set dev vcan0 down && ip link set dev vcan0 mtu 72 && ip link set dev vcan0 up || { echo "mtu 72 failed" >&2; exit 1; }

start() {  # start NAME [extra args]: a controller on vcan0, stdout/stderr to $OUT/NAME.out/.err
  local name=$1; shift
  "$METER_BIN" run -v --dbc "$dbc" --map "$map" --input can:vcan0 --link tcp:127.0.0.1:0 --insecure-link "$@" \
    >"$OUT/$name.out" 2>"$OUT/$name.err" &
  pid=$!
  controller_ready "$OUT/$name.err" "$pid"
  kill -0 $pid 2>/dev/null || { echo "controller $name exited at start" >&2; cat "$OUT/$name.err" >&2; exit 1; }
}
stop() {
  kill -TERM $pid
  wait $pid
  echo "exit=$?" >>"$OUT/$1.err"
}

# ---- A: the replayed log ----
start ctlA
canplayer -I "$OUT/buses.log" vcan0=can0 2>"$OUT/canplayer.err" || { echo "canplayer failed" >&2; cat "$OUT/canplayer.err" >&2; }
sleep 0.3
stop ctlA

# ---- B: a flood on a mapped id ----
trace=/tmp/flood-trace.csv   # guest-private: a 9p share would slow the controller down
start ctlB --trace "$trace"
read -r tx0 </sys/class/net/vcan0/statistics/tx_packets
t0=$EPOCHREALTIME
# -g 0: no gap; -i: go on after ENOBUFS (that frame never reached the bus, tx_packets does not count
# it); -D i: an incrementing payload, so Body.Ignition changes with every frame.
timeout "$FLOOD_S" cangen vcan0 -g 0 -i -I 123 -L 8 -D i 2>>"$OUT/cangen.err" &
gen=$!
sleep 5
echo "early $(awk '/^VmRSS:/ {print $2}' /proc/$pid/status)" >>"$OUT/rss.txt"
wait $gen
t1=$EPOCHREALTIME
# The kernel stamps its drop count (SO_RXQ_OVFL) on each frame as it queues it, so drops after the
# last frame queued are only told by a later frame: once the flood is over and the queue has room,
# one more frame on the mapped id carries the final count (a bus that goes on carries it the same way).
sleep 0.5
cansend vcan0 123#0000000000000000
read -r tx1 </sys/class/net/vcan0/statistics/tx_packets
echo "late $(awk '/^VmRSS:/ {print $2}' /proc/$pid/status)" >>"$OUT/rss.txt"
sleep 1   # the controller drains what is queued
stop ctlB
echo "frames $((tx1 - tx0)) seconds $(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.2f", b - a}')" >"$OUT/flood.txt"
# Latency of each flood frame: decoded (t_ns) minus the kernel receive stamp, in microseconds.
awk -F, '$1 == "f" && $4 == 291 { d = ($2 - $3) / 1000; print d }' "$trace" | sort -n >/tmp/lat.txt
n=$(wc -l </tmp/lat.txt)
if ((n > 0)); then
  p50=$(sed -n "$(( (n + 1) / 2 ))p" /tmp/lat.txt)
  p99=$(sed -n "$(( (n * 99 + 99) / 100 ))p" /tmp/lat.txt)
  max=$(tail -n 1 /tmp/lat.txt)
  echo "n $n p50_us $p50 p99_us $p99 max_us $max" >"$OUT/latency.txt"
fi
grep -c '^h,' "$trace" >"$OUT/trace_health_rows.txt"
grep -E '^h,[0-9]*,(kernel|interface)_drops' "$trace" | tail -n 1 >"$OUT/trace_drops.txt"
exit 0
