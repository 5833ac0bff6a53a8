#!/bin/bash
# The guest's part of the DRM/KMS display check (tests/display/drm_check.py is the host's), run in
# the qemu VM of vcan/vm/run-in-vm --display 1280x480 --qmp: meter-view --output drm on
# /dev/dri/card0 (virtio-gpu, Mesa's GBM + EGL with softpipe: llvmpipe's shader compiles take
# ~45 s under TCG, softpipe's interpreter a few seconds for the gauge at 320x240), each state held
# until the host has taken its QMP screendump. The frame is 320x240: centred on the 1280x480 mode.
#   usage: drm_guest.sh METER_VIEW SCENE.msp RAMP.rec OUT
# Steps (each writes OUT/<step>.rc and OUT/<step>.log):
#   first   Vehicle.Speed=88 shown (atomic modesetting); the host's screendump taken
#           (OUT/shot1.ready -> shot1.done);
#   second  a second view on the same card while the first holds it: refused (exit 1);
#   killed  the first view killed with SIGKILL (no clean-up of its own);
#   probe   the card the killed view left: a new opener becomes its DRM master (the KMS device is
#           not hung);
#   partial one view, legacy modesetting forced (--drm-modeset legacy): RAMP.rec played (the needle
#           moving by small steps: only part of each frame changes), a line per frame shown with
#           the pixels copied (--info), its last frame held (--hold) for the host's screendump
#           (shot2); then the virtio-gpu PCI device removed under it (the display ends here:
#           last): OUT/unplug.noticed and OUT/unplug.ms are how long the view took to log the lost
#           display and to exit after the removal, unplug.ms "hung" when it did not within 15 s;
#           OUT/partial.ms the whole step (start, frames, screendump, removal, exit).
set -u
view=$1 msp=$2 rec=$3 out=$4
export GALLIUM_DRIVER=softpipe
mkdir -p "$out"

# Starts a holding view for step $1 (its state: the arguments after the third); waits for its frame
# on the display, then for the host's screendump $3.
show() {
  local step=$1 shot=$2
  shift 2
  "$view" --scene "$msp" --size 320x240 "$@" --output drm --out "$out/$step" --info 2>"$out/$step.log" &
  pid=$!
  for _ in $(seq 1 600); do
    grep -q "on the display" "$out/$step.log" 2>/dev/null && break
    kill -0 "$pid" 2>/dev/null || { wait "$pid"; echo $? >"$out/$step.rc"; return 1; }
    sleep 0.1
  done
  touch "$out/$shot.ready"
  for _ in $(seq 1 300); do [ -f "$out/$shot.done" ] && break; sleep 0.1; done
}

show first shot1 --set Vehicle.Speed=88 || exit 0
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

started=$(date +%s%N)
show partial shot2 --play "$rec" --fps 25 --dump-last --timing-csv "$out/partial.csv" --drm-modeset legacy --hold ||
  exit 0
# The PCI device of card0 (its virtio device's parent), removed while the view holds its frame.
dev=$(readlink -f /sys/class/drm/card0/device)
[ -e "$dev/remove" ] || dev=$(dirname "$dev")
echo "$dev" >"$out/unplug.dev"
began=$(date +%s%N)
echo 1 >"$dev/remove" &
for _ in $(seq 1 150); do
  [ -f "$out/unplug.noticed" ] || ! grep -q "the display went away" "$out/partial.log" ||
    echo $((($(date +%s%N) - began) / 1000000)) >"$out/unplug.noticed"
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$pid" 2>/dev/null; then
  echo hung >"$out/unplug.ms"
  kill -KILL "$pid"
else
  echo $((($(date +%s%N) - began) / 1000000)) >"$out/unplug.ms"
fi
wait "$pid"
echo $? >"$out/partial.rc"
echo $((($(date +%s%N) - started) / 1000000)) >"$out/partial.ms"
exit 0
