#!/usr/bin/env bash
# The guest half of the end-to-end tests (runs where vcan0 exists: in the VM or on a CAN-capable
# host). Starts meter-controller on SocketCAN, serving the protocol over TCP, then executes PHASES
# in order. Everything it observes goes to OUT (a writable share): controller.log, events.log
# (phase timestamps), rss.txt, result.txt.
#
# Usage: guest_scenario.sh OUT BIN_DIR PORT GO_PORT DBC MAP LOG PHASE...
# Phases:
#   go                    wait until the host connects to GO_PORT (the view is up): aligns clocks
#   replay:START:DUR      vcan/replay LOG from START s for DUR s, real time, in the foreground
#   replay-bg:START:DUR   the same in the background (joined at the end)
#   sleep:SEC             bus silence / waiting
#   kill-controller       SIGKILL the controller (a crashed vehicle-control MCU)
#   start-controller      start it again (same state dir: odometer persisted)
#   flood:SEC             cangen at full rate (-g 0) for SEC s on a mapped id (0x154, a telltale's)
#   rss:LABEL             record the controller's VmRSS (kB) under LABEL
set -uo pipefail
out=$1 bin=$2 port=$3 go_port=$4 dbc=$5 map=$6 log=$7; shift 7
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out/state"
ctrl=""
bg=()
starts=0
link_timeout_ms=${METER_E2E_LINK_TIMEOUT_MS:-300}
if [[ -n ${METER_E2E_NETSTAT:-} ]]; then
  # Diagnosis: the guest's TCP queues (tx_queue:rx_queue) every 0.2 s, without forking processes.
  mkfifo "$out/netstat.fifo"
  ( exec 9<>"$out/netstat.fifo"; while :; do echo "$EPOCHREALTIME"; echo "$(</proc/net/tcp)"; read -r -t 0.2 -u 9; done \
      >"$out/tcp.txt" ) & netstat=$!
fi
# $EPOCHREALTIME, not date: every exec costs tens of ms in a TCG guest.
event() { echo "$EPOCHREALTIME $*" >>"$out/events.log"; }
# Whatever way the scenario ends, nothing of it keeps running: in a shared boot the next drive
# starts its own controller on the same port and replays on the same vcan0.
leftovers() {
  [[ -n $ctrl ]] && kill -KILL "$ctrl" 2>/dev/null
  for p in "${bg[@]}"; do kill -KILL "$p" 2>/dev/null; done
  [[ -n ${netstat:-} ]] && kill "$netstat" 2>/dev/null
  return 0
}
trap leftovers EXIT
fail() { event "FAIL $*"; echo "guest_scenario: $*" >&2; echo "fail $*" >"$out/result.txt"; exit 1; }

start_controller() {
  ((++starts))
  "$bin/meter-controller" run --input can:vcan0 --dbc "$dbc" --map "$map" \
      --link "tcp:0.0.0.0:$port" --insecure-link --state-dir "$out/state" --link-timeout "$link_timeout_ms" \
      --trace "$out/controller-trace-$starts.csv" >>"$out/controller.log" 2>&1 &
  ctrl=$!
  event "controller started pid $ctrl"
  sleep 0.5
  kill -0 "$ctrl" 2>/dev/null || fail "meter-controller exited at start (see controller.log)"
}

# A small TCP send buffer in the guest: qemu's user-mode network drains slowly under TCG, and with
# the default buffer (up to 4 MB) seconds of stale deltas queue in the kernel, invisible to the
# publisher's latest-value coalescing (measured: the view 6-7 s behind the bus). A 16 kB buffer
# makes the publisher see back-pressure at once, like a real inter-chip link would.
if [[ ${METER_VCAN_MODE:-} == vm ]]; then
  echo "4096 16384 16384" >/proc/sys/net/ipv4/tcp_wmem || fail "cannot set tcp_wmem"
fi
start_controller
# Every frame on vcan0 from here on (the replays' and the floods'): the flood test's ground truth.
read -r tx </sys/class/net/vcan0/statistics/tx_packets; event "tx start $tx"
# Frames the kernel dropped on the receive path before any socket saw them (the per-CPU input
# backlog of netif_rx overflowing, counted as the interface's rx_dropped): no socket counts these.
read -r rxd </sys/class/net/vcan0/statistics/rx_dropped; event "rx_dropped start $rxd"
# The host starts meter-view only now: during the boot it would only take CPU from the guest.
touch "$out/ready"
for phase in "$@"; do
  event "phase $phase"
  case "$phase" in
    go) echo go | timeout 90 busybox nc -l -p "$go_port" >/dev/null || fail "no go from the host"
       event "go received" ;;
    replay:*:*|replay-bg:*:*)
      IFS=: read -r kind start dur <<<"$phase"
      # The host prepares the window (vcan/replay -o, which validates and cuts it) and lists its
      # interfaces, so the guest starts canplayer itself at once: vcan/replay's own passes over
      # the log (cut, sort, wc, ip) took 3.7 s under TCG before the first frame, and the view
      # looked seconds "behind the bus" that had not started yet (measured with --trace: canplayer
      # then keeps time within 1 ms over 25 s).
      win=$out/window_${start}_${dur}
      if [[ -f $win.log && -f $win.ifaces ]]; then
        mapfile -t ifs <"$win.ifaces"
        play=(canplayer -I "$win.log" -l 1)
        for i in "${ifs[@]}"; do play+=("vcan0=$i"); done
      else
        play=("$root/vcan/replay" -i vcan0 --start "$start" --duration "$dur" "$log")
      fi
      event "replay starts"
      if [[ $kind == replay ]]; then
        "${play[@]}" || fail "replay failed"
      else
        "${play[@]}" & bg+=($!)
      fi ;;
    sleep:*) sleep "${phase#sleep:}" ;;
    kill-controller) kill -KILL "$ctrl"; wait "$ctrl" 2>/dev/null; ctrl="" ;;
    start-controller) start_controller ;;
    flood:*)
      # 0x154 is ID_154 in the ft86 DBC: the mapping reads its EBRAKE bit (the parking-brake
      # telltale), so the kernel filter lets the flood in and the controller decodes every frame it
      # gets; no judged gauge reads it. Random payloads, no gap: as fast as the kernel takes them
      # (-i: keep going on ENOBUFS; no -x, since on vcan a frame without local loopback reaches no
      # reader at all).
      read -r tx0 </sys/class/net/vcan0/statistics/tx_packets
      timeout "${phase#flood:}" cangen vcan0 -g 0 -i -I 154 -L 7 -D r 2>>"$out/cangen.log"
      rc=$?; ((rc == 124)) || fail "cangen exited with $rc before its time was up"
      # How hard the bus was flooded (all frames on vcan0 in the phase, the replay's included).
      read -r tx1 </sys/class/net/vcan0/statistics/tx_packets
      event "flood frames $((tx1 - tx0))" ;;
    rss:*)
      [[ -n $ctrl ]] || fail "rss: no controller running"
      echo "${phase#rss:} $(awk '/^VmRSS:/ {print $2}' "/proc/$ctrl/status")" >>"$out/rss.txt" ;;
    *) fail "unknown phase '$phase'" ;;
  esac
done
for p in "${bg[@]}"; do wait "$p" || fail "background replay failed"; done
read -r tx </sys/class/net/vcan0/statistics/tx_packets; event "tx end $tx"
read -r rxd </sys/class/net/vcan0/statistics/rx_dropped; event "rx_dropped end $rxd"
[[ -n ${netstat:-} ]] && kill "$netstat"

# The controller must have survived everything after its last (re)start, and stop cleanly.
[[ -n $ctrl ]] && { kill -0 "$ctrl" 2>/dev/null || fail "meter-controller died during the run (see controller.log)"; }
if [[ -n $ctrl ]]; then
  kill -TERM "$ctrl"
  for _ in $(seq 50); do kill -0 "$ctrl" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$ctrl" 2>/dev/null && { kill -KILL "$ctrl"; fail "meter-controller ignored SIGTERM for 5 s"; }
  wait "$ctrl"; rc=$?
  ((rc == 0)) || fail "meter-controller exited with $rc on SIGTERM"
fi
event done
echo ok >"$out/result.txt"
