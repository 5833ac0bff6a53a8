"""The host's part of the DRM/KMS display check (tests/display/drm_guest.sh runs in the VM): a
watcher thread that takes QMP screendumps when the guest asks, and the judgement of the run. Used
by tests/vcan/test_harness_vm.py, whose VM boot it shares (run-in-vm --display 1280x480 --qmp)."""
import os
import subprocess
import threading
import time

from qmp_screendump import read_ppm, screendump

DISPLAY = "1280x480"
HERE = os.path.dirname(os.path.abspath(__file__))


def prepare(convert, source_dir, out):
    """The gauge package (drawn at 320x240 by drm_guest.sh: centred on the 1280x480 mode), converted
    on the host."""
    msp = os.path.join(out, "gauge.msp")
    scene = os.path.join(source_dir, "scenes", "minimal-gauge")
    subprocess.run([convert, os.path.join(scene, "minimal-gauge.glb"), "-c",
                    os.path.join(scene, "minimal-gauge.scene.json"), "-o", msp, "-q"], check=True, timeout=120)
    return msp


def guest_command(view, msp, out):
    return f"{os.path.join(HERE, 'drm_guest.sh')} {view} {msp} {out}"


class ScreenWatcher(threading.Thread):
    """Takes screendump N when OUT/shotN.ready appears, then writes OUT/shotN.done."""

    def __init__(self, qmp, out, shots=("shot1",), timeout=200):
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


def compare(out, shot, step):
    """Errors: the screendump against the PNG dump of the view that showed it (320x240, centred)."""
    ppm, png = os.path.join(out, shot + ".ppm"), os.path.join(out, step, "frame.png")
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


def judge(out, watcher):
    """Every error of the guest's steps and the screendumps; empty when the display did its part."""
    def read(name):
        p = os.path.join(out, name)
        if not os.path.exists(p):
            return None
        with open(p) as f:
            return f.read().strip()
    errors = list(watcher.errors)
    if "atomic, primary plane" not in (read("first.log") or ""):
        errors.append(f"first: no atomic KMS output in its log:\n{read('first.log')}")
    errors += compare(out, "shot1", "first")
    if read("second.rc") != "1" or "one view per card" not in (read("second.log") or ""):
        errors.append(f"second view on the card: rc {read('second.rc')}, log:\n{read('second.log')}")
    if read("killed.rc") != "137":
        errors.append(f"the killed view: rc {read('killed.rc')} (137 expected)")
    if read("probe.rc") != "0":
        errors.append(f"the card after the killed view: not free ({read('probe.log')})")
    return errors
