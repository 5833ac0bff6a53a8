# Sourced (POSIX sh) by the controller's vcan guest scripts. `controller_ready ERR_FILE PID` waits
# until the meter-controller PID has its CAN sockets open: its -v line "... -> tcp:..." on ERR_FILE
# comes after them. A fixed sleep raced with its start-up on the guest's instruction-counted clock,
# where the guest's waits for the host's 9p share take no guest time, and the replay began before
# the controller listened (2255 of 2500 frames received). It returns when the controller has exited
# too (the caller checks that); run-in-vm's timeout bounds the wait.
controller_ready() {
  until grep -q " -> " "$1" 2>/dev/null; do
    kill -0 "$2" 2>/dev/null || return 0
    sleep 0.1
  done
}
