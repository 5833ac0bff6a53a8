#!/usr/bin/env bash
# scripts/cpu-time-under, with which scripts/fuzz judges a timeout's replays: a command far past a
# wall-time limit that uses no CPU (a fuzzer descheduled on a loaded host) is under its limit; a
# busy one is not, whatever the load; a failing one is not; bad usage is exit 2.
set -u
tool="$1/scripts/cpu-time-under"
failed=0
check() {
  local want=$1
  shift
  "$tool" "$@" >/dev/null 2>&1
  local rc=$?
  if (( rc != want )); then
    echo "FAIL: cpu-time-under $* exited $rc, expected $want"
    failed=1
  fi
}
check 0 0.5 sleep 1.5  # 1.5 s of wall time, ~0 s of CPU: what the old wall-time check called a hang
# 1.5 s of a busy loop: on 2 cores shared with anything it still gets far over 0.05 s of CPU.
check 1 0.05 bash -c 'end=$((SECONDS + 2)); while (( SECONDS < end )); do :; done'
check 1 10 false
check 2 x true
check 2 0.5
exit "$failed"
