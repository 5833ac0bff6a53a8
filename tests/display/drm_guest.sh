#!/bin/bash
# The guest's part of the DRM/KMS display check (tests/display/drm_check.py is the host's), run in
# the qemu VM of vcan/vm/run-in-vm --display 1280x480 --qmp: meter-view --output drm on
# /dev/dri/card0 (virtio-gpu, Mesa's GBM + EGL with softpipe: llvmpipe's shader compiles take
# ~45 s under TCG, softpipe's interpreter a few seconds for the gauge at 320x240), each state held
# until the host has taken its QMP screendump. The frame is 320x240: centred on the 1280x480 mode.
#   usage: drm_guest.sh METER_VIEW SCENE.msp OUT
# Steps (each writes OUT/<step>.rc and OUT/<step>.log):
#   first   Vehicle.Speed=88 shown; the host's screendump taken (OUT/shot1.ready -> shot1.done);
#   second  a second view on the same card while the first holds it: refused (exit 1);
#   killed  the first view killed with SIGKILL (no clean-up of its own);
#   probe   the card the killed view left: a new opener becomes its DRM master (the KMS device is
#           not hung; a third view would be another ~12 s of start-up under TCG).
set -u
view=$1 msp=$2 out=$3
export GALLIUM_DRIVER=softpipe
mkdir -p "$out"

# Starts a holding view for step $1 with speed $2; waits for its frame on the display, then for the
# host's screendump $3.
show() {
  local step=$1 speed=$2 shot=$3
  "$view" --scene "$msp" --size 320x240 --set "Vehicle.Speed=$speed" --output drm --out "$out/$step" --info 2>"$out/$step.log" &
  pid=$!
  for _ in $(seq 1 600); do
    grep -q "on the display" "$out/$step.log" 2>/dev/null && break
    kill -0 "$pid" 2>/dev/null || { wait "$pid"; echo $? >"$out/$step.rc"; return 1; }
    sleep 0.1
  done
  touch "$out/$shot.ready"
  for _ in $(seq 1 300); do [ -f "$out/$shot.done" ] && break; sleep 0.1; done
}

show first 88 shot1 || exit 0
first=$pid
"$view" --scene "$msp" --set Vehicle.Speed=1 --output drm --out "$out/second" 2>"$out/second.log"
echo $? >"$out/second.rc"
kill -KILL "$first"
wait "$first" 2>/dev/null
echo $? >"$out/killed.rc"
/usr/bin/python3 -c '
import fcntl, os
fd = os.open("/dev/dri/card0", os.O_RDWR)
fcntl.ioctl(fd, 0x641e)  # DRM_IOCTL_SET_MASTER: fails (EINVAL/EBUSY) while another process holds it
print("master")' >"$out/probe.log" 2>&1
echo $? >"$out/probe.rc"
exit 0
