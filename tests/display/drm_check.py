"""The host's part of the DRM/KMS display check (tests/display/drm_guest.sh runs in the VM): a
watcher thread that takes QMP screendumps when the guest asks, and the judgement of the run. Used
by tests/vcan/test_harness_vm.py, whose VM boot it shares (run-in-vm --display 1280x480 --qmp)."""
import csv
import os
import re
import subprocess
import threading
import time

from qmp_screendump import read_ppm, screendump

DISPLAY = "1280x480"
HERE = os.path.dirname(os.path.abspath(__file__))


FRAME = 320 * 240        # the gauge's size in the guest, pixels
RAMP_FRAMES = 8          # frames of the played ramp (one a state)
# The removed device noticed and the view gone within this (under TCG on this loaded host: the
# hold asks the device every 50-100 ms; the rest is the guest's process exit and the script's
# 0.1 s polls, 2.5-3.5 s measured).
UNPLUG_BOUND_MS = 8000


def prepare(convert, source_dir, out):
    """The gauge package (drawn at 320x240 by drm_guest.sh: centred on the 1280x480 mode), converted
    on the host, and the ramp the partial step plays."""
    msp = os.path.join(out, "gauge.msp")
    scene = os.path.join(source_dir, "scenes", "minimal-gauge")
    subprocess.run([convert, os.path.join(scene, "minimal-gauge.glb"), "-c",
                    os.path.join(scene, "minimal-gauge.scene.json"), "-o", msp, "-q"], check=True, timeout=120)
    ramp(os.path.join(out, "ramp.rec"))
    return msp


def ramp(path):
    """A link recording: Vehicle.Speed up by 0.5 km/h every 1/25 s (exact in decimal: frame k of
    --fps 25 takes state k), RAMP_FRAMES states (the needle moves a little each frame: only part of
    the frame changes)."""
    with open(path, "w") as f:
        f.write("# Vehicle.Speed up 0.5 km/h a frame at 25 frames/s\n")
        f.write("(100.000000000) SNAPSHOT seq=1 sent=100.000000000 complete=1 Vehicle.Speed=60:valid\n")
        for k in range(1, RAMP_FRAMES):
            t = 100 + k * 0.04
            f.write(f"({t:.9f}) DELTA seq={k + 1} sent={t:.9f} Vehicle.Speed={60 + 0.5 * k}:valid\n")


def guest_command(view, msp, out):
    rec = os.path.join(os.path.dirname(msp), "ramp.rec")
    return f"{os.path.join(HERE, 'drm_guest.sh')} {view} {msp} {rec} {out}"


class ScreenWatcher(threading.Thread):
    """Takes screendump N when OUT/shotN.ready appears, then writes OUT/shotN.done."""

    def __init__(self, qmp, out, shots=("shot1", "shot2"), timeout=230):
        super().__init__(daemon=True)
        self.qmp, self.out, self.shots, self.timeout, self.errors = qmp, out, shots, timeout, []

    def run(self):
        end = time.monotonic() + self.timeout
        for shot in self.shots:
            while not os.path.exists(os.path.join(self.out, shot + ".ready")):
                if time.monotonic() > end:
                    return
                time.sleep(0.1)
            try:
                screendump(self.qmp, os.path.join(self.out, shot + ".ppm"))
            except (OSError, RuntimeError, ValueError) as e:
                self.errors.append(f"{shot}: {e}")
            open(os.path.join(self.out, shot + ".done"), "w").close()


def rgb_png(path):
    return subprocess.run(["convert", path, "-depth", "8", "rgb:-"], check=True, capture_output=True).stdout


def compare(out, shot, step, png_name="frame.png"):
    """Errors: the screendump against the PNG dump of the view that showed it (320x240, centred)."""
    ppm, png = os.path.join(out, shot + ".ppm"), os.path.join(out, step, png_name)
    if not os.path.exists(ppm) or not os.path.exists(png):
        return [f"{shot}: missing {ppm if not os.path.exists(ppm) else png}"]
    w, h, screen = read_ppm(ppm)
    frame, fw, fh = rgb_png(png), 320, 240
    if (w, h) != (1280, 480) or len(frame) != fw * fh * 3:
        return [f"{shot}: screen {w}x{h}, frame {len(frame)} bytes"]
    x0, y0, errors, differ = (w - fw) // 2, (h - fh) // 2, [], 0
    for y in range(fh):
        row = screen[((y0 + y) * w + x0) * 3:((y0 + y) * w + x0 + fw) * 3]
        differ += sum(a != b for a, b in zip(row, frame[y * fw * 3:(y + 1) * fw * 3]))
    inside = {(y0 + y) * w + x0 + x for y in range(fh) for x in range(fw)}
    lit = sum(1 for i in range(w * h) if i not in inside and screen[i * 3:i * 3 + 3] != b"\0\0\0")
    if differ:
        errors.append(f"{shot}: {differ} bytes of the scanout differ from {step}'s offscreen render")
    if lit:
        errors.append(f"{shot}: {lit} pixels of the border around the centred frame are not black")
    return errors


def shown_lines(log):
    """(frame, pixels copied, frame's pixels, damaged) of each "frame K shown" line (--info)."""
    return [tuple(int(x) for x in m) for m in re.findall(
        r"display: frame (\d+) shown: copied (\d+) pixels of the frame's (\d+) \((\d+) damaged\)", log)]


def judge_partial(out, read, notes):
    """The legacy KMS view that played the ramp: legacy modesetting said, every frame flipped and
    presented in order (no stall), the copies partial after the first buffers, its held last frame
    on screen equal to its offscreen render, and the removed device ending it with exit 3."""
    log, errors = read("partial.log") or "", []
    if "legacy drmModeSetCrtc + drmModePageFlip (asked for: --drm-modeset legacy)" not in log:
        errors.append(f"partial: no legacy KMS output in its log:\n{log[-3000:]}")
    shown = shown_lines(log)
    rows = []
    if os.path.exists(os.path.join(out, "partial.csv")):
        with open(os.path.join(out, "partial.csv")) as f:
            rows = list(csv.DictReader(f))
    times = [int(r["presented_ns"]) for r in rows if r.get("presented_ns")]
    if len(shown) != RAMP_FRAMES or len(times) != len(shown) or times != sorted(set(times)) or " 0 stalls" not in log:
        errors.append(f"partial: {len(shown)} frames shown, {len(times)} presentation times of {len(rows)} rows "
                      f"(increasing: {times == sorted(set(times))}), {RAMP_FRAMES} expected, no stall:\n{log[-3000:]}")
    # After the two buffers of the double-buffered surface (age 0 at first: copied whole), each copy
    # is the frame's damage and the buffer's missing boxes (age 2: the frame before's).
    later = [c for _, c, f, _ in shown[2:]]
    if not later or "double buffered, buffer age" not in log or max(later) >= FRAME or sum(later) * 2 > FRAME * len(later):
        errors.append(f"partial: copies per frame after the first 2 not partial: {later}")
    else:
        notes.append(f"partial (legacy KMS): copied per frame {[c for _, c, _, _ in shown]} of {FRAME}; "
                     f"after the first 2: {sum(later) / len(later) / FRAME:.1%} of the frame on average")
    pngs = sorted(n for n in os.listdir(os.path.join(out, "partial")) if n.startswith("frame_")) \
        if os.path.isdir(os.path.join(out, "partial")) else []
    errors += compare(out, "shot2", "partial", pngs[-1] if pngs else "frame_missing.png")
    ms = read("unplug.ms")
    if read("partial.rc") != "3" or not (ms or "").isdigit() or int(ms) > UNPLUG_BOUND_MS or \
            "the display went away: drm: /dev/dri/card0" not in log:
        errors.append(f"the device removed under the holding view ({read('unplug.dev')}): rc {read('partial.rc')} "
                      f"(3 expected), exit {ms} ms after the removal (at most {UNPLUG_BOUND_MS}):\n{log[-2000:]}")
    else:
        notes.append(f"unplug: error logged {read('unplug.noticed')} ms and exit 3 {ms} ms after removing {read('unplug.dev')} "
                     f"(the legacy/partial/unplug step: {read('partial.ms')} ms in the guest): "
                     + log[log.index("the display went away"):].splitlines()[0])
    return errors


def judge(out, watcher, notes=None):
    """Every error of the guest's steps and the screendumps; empty when the display did its part.
    What was measured goes into `notes`."""
    notes = [] if notes is None else notes

    def read(name):
        p = os.path.join(out, name)
        if not os.path.exists(p):
            return None
        with open(p) as f:
            return f.read().strip()
    errors = list(watcher.errors)
    first = read("first.log") or ""
    planes = re.search(r"plane properties: ([^;]*)", first)
    if "atomic, primary plane" not in first or not planes:
        errors.append(f"first: no atomic KMS output with its plane's properties in its log:\n{first}")
    else:
        # Whether the plane offers FB_DAMAGE_CLIPS (virtio-gpu on 6.1 does not): said as listed.
        listed = "FB_DAMAGE_CLIPS" in planes.group(1).split()
        if listed != ("no FB_DAMAGE_CLIPS" not in first):
            errors.append(f"first: FB_DAMAGE_CLIPS listed {listed}, but the output line says otherwise:\n{first}")
        notes.append(f"primary plane properties (atomic client): {planes.group(1)}")
    errors += compare(out, "shot1", "first")
    if read("second.rc") != "1" or "one view per card" not in (read("second.log") or ""):
        errors.append(f"second view on the card: rc {read('second.rc')}, log:\n{read('second.log')}")
    if read("killed.rc") != "137":
        errors.append(f"the killed view: rc {read('killed.rc')} (137 expected)")
    if read("probe.rc") != "0":
        errors.append(f"the card after the killed view: not free ({read('probe.log')})")
    return errors + judge_partial(out, read, notes)
