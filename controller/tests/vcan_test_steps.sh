# Sourced by the controller's vcan tests (socketcan_vcan, two_bus_vcan, socketcan_buses): their STEP
# argument resolved once. `vcan_test_step STEP OUT GUEST_COMMAND` prints OUT and GUEST_COMMAND and
# exits for STEP guest (what vcan_session_test.sh runs in the shared boot); turns STEP shared into
# judge when the shared boot ran this test's part (OUT/shared-boot), else into all; and leaves the
# resolved step in $step. Any other STEP (all, prepare, judge) stays as it is.
vcan_test_step() {
  step=$1
  local out=$2 guest_command=$3
  if [[ $step == guest ]]; then   # where it writes, then the command
    echo "$out"
    echo "$guest_command"
    exit 0
  fi
  if [[ $step == shared ]]; then
    if [[ -f $out/shared-boot ]]; then step=judge; else step=all; fi
  fi
}
