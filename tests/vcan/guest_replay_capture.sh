#!/usr/bin/env bash
# Runs where vcan exists (in the VM or on a CAN-capable host): capture IFACE with candump -L while
# vcan/replay plays INPUT onto it. Sentinel frames with extended ids the logs never use mark the
# start (candump is provably listening before the replay begins) and the end (every replayed frame
# has been written out before candump is stopped), so no sleep decides the outcome.
# Usage: guest_replay_capture.sh IFACE INPUT CAPTURE [replay options...]
set -euo pipefail
iface=$1 input=$2 capture=$3; shift 3
root=$(cd "$(dirname "$0")/../.." && pwd)
start_id=1FFFFFF0 end_id=1FFFFFF1
# candump writes into a local file and the result is copied at the end: writing every line
# straight to a 9p share costs a round trip per frame under TCG, candump falls behind and the
# socket's receive queue overflows (frames lost before the capture, not on the bus). A large
# receive buffer absorbs the log's bursts as well.
local_cap=$(mktemp)
candump -L -r 8388608 "$iface" >"$local_cap" &
dump=$!
trap 'kill $dump 2>/dev/null || true; rm -f "$local_cap"' EXIT
wait_for() {  # wait until the capture holds frame id $1, at most $2 tenths of a second
  for ((i = 0; i < $2; i++)); do
    grep -q " $iface $1#" "$local_cap" && return 0
    [[ $1 == "$start_id" ]] && cansend "$iface" "$start_id#53544152"   # "STAR"; repeat until seen
    sleep 0.1
  done
  echo "guest_replay_capture: sentinel $1 never reached the capture on $iface" >&2
  return 1
}
wait_for "$start_id" 300
"$root/vcan/replay" -i "$iface" "$@" "$input"
cansend "$iface" "$end_id#454E44"
wait_for "$end_id" 300
kill "$dump" && wait "$dump" 2>/dev/null || true
cp "$local_cap" "$capture"
