#!/usr/bin/env bash
# The guest half of a shared boot (tests/vcan/e2e_session.py): one VM runs the end-to-end drives
# one after another, each a guest_scenario.sh run of its own, so the boot is paid once.
# The host asks for drive N by writing SESSION/next-N (guest_scenario.sh's arguments, one per line,
# written to a temporary name and renamed, so a file that exists is complete), or SESSION/end to
# stop; the guest answers SESSION/done-N with the scenario's exit code. Drives share vcan0 and the
# forwarded ports, never at the same time.
# Usage: guest_session.sh SESSION
set -uo pipefail
session=$1
here=$(cd "$(dirname "$0")" && pwd)
n=1
while :; do
  if [[ -f $session/next-$n ]]; then
    mapfile -t args <"$session/next-$n"
    "$here/guest_scenario.sh" "${args[@]}"
    echo $? >"$session/done-$n.tmp" && mv "$session/done-$n.tmp" "$session/done-$n"
    n=$((n + 1))
  elif [[ -f $session/end ]]; then
    exit 0
  else
    sleep 0.2   # only between drives: during one the scenario itself runs
  fi
done
