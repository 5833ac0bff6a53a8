#!/usr/bin/env python3
"""meter-view --output wayland against a real compositor: Weston 10's headless backend with its GL
renderer (llvmpipe), one Weston for every case, in a private XDG_RUNTIME_DIR.

  usage: wayland_check.py METER_CONVERT METER_VIEW SCENES_DIR WORKDIR METER_CONTROLLER CLUSTER_MSP

Cases, in order (the last one stops Weston):
  screenshot  one state (--set) held on the display; Weston's own screenshot (weston-screenshooter,
              weston --debug) holds meter-view's offscreen render of that state (its PNG dump) byte
              for byte, centred on the 1280x480 output (the 640x480 gauge; the compositor's fill around it);
  pacing      a recording played (40 frames at 60 fps): every frame presented (presentation
              feedback in the timing CSV), the times strictly increasing and never two frames in one
              refresh; each frame presented after its render ended;
  live        the cluster live from meter-controller replaying the demo drive, the integrity monitor on
              the shown buffer: the display's copy of frames 20-40 lost (--inject-fault display@20-40;
              the renderer's own target stays right) is caught by the monitor reading the back buffer
              (integrity faults from frame 20, none before it or from frame 50 on), those frames have
              no presentation time in frames.csv, the others do, increasing; Weston stopped (SIGSTOP)
              for 2 s: the frame callback that does not come is a frozen display, logged and sent in
              STATUS (the controller logs "display-frozen", and "integrity" for the lost copies); the
              view ends normally on SIGTERM after SIGCONT;
  no_compositor  --output wayland:NAME with no compositor there: exit 1 naming the socket;
  compositor_gone  Weston killed while a frame is shown: meter-view exits 3 ("the display went away").
Pixels are read with ImageMagick (`convert ... rgb:`), no Python packages.
"""
import csv
import os
import re
import shutil
import signal
import subprocess
import sys
import time

REFRESH_NS = 1e9 / 60  # Weston headless's output mode: 60 Hz
WESTON_INI = """[core]
idle-time=0
# Repaint as soon as the last frame finished: the headless backend's frame takes 16 ms of timer
# after its repaint, so the default window (7 ms) makes its cycle ~26 ms instead of ~17.
repaint-window=16
[shell]
startup-animation=none
animation=none
close-animation=none
panel-position=none
background-color=0xff000000
"""


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def rgb(path):
    out = subprocess.run(["convert", path, "-depth", "8", "rgb:-"], check=True, capture_output=True).stdout
    size = subprocess.run(["identify", "-format", "%w %h", path], check=True, capture_output=True, text=True).stdout
    w, h = map(int, size.split())
    return w, h, out


class View:
    """One meter-view process whose stderr is read line by line."""

    def __init__(self, argv, env, log):
        self.log_path = log
        self.proc = subprocess.Popen(argv, env=env, stderr=open(log, "w"), stdout=subprocess.DEVNULL)

    def text(self):
        with open(self.log_path) as f:
            return f.read()

    def wait_for(self, needle, timeout=60):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if needle in self.text():
                return
            if self.proc.poll() is not None:
                fail(f"meter-view exited {self.proc.returncode} before '{needle}':\n{self.text()}")
            time.sleep(0.05)
        fail(f"no '{needle}' in {timeout} s:\n{self.text()}")

    def wait(self, timeout=60):
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            fail(f"meter-view hung:\n{self.text()}")


def main():
    convert, view, scenes, work, controller, cluster = sys.argv[1:7]
    for tool in ("weston", "weston-screenshooter", "convert"):
        if not shutil.which(tool):
            fail(f"{tool} not found: run scripts/install-deps test (weston, imagemagick)")
    shutil.rmtree(work, ignore_errors=True)
    xdg = os.path.join(work, "xdg")
    os.makedirs(xdg, mode=0o700)
    ini = os.path.join(work, "weston.ini")
    with open(ini, "w") as f:
        f.write(WESTON_INI)
    msp = os.path.join(work, "gauge.msp")
    subprocess.run([convert, os.path.join(scenes, "minimal-gauge", "minimal-gauge.glb"), "-c",
                    os.path.join(scenes, "minimal-gauge", "minimal-gauge.scene.json"), "-o", msp, "-q"], check=True)
    socket = f"meter-display-{os.getpid()}"
    env = dict(os.environ, XDG_RUNTIME_DIR=xdg, WAYLAND_DISPLAY=socket)
    weston = subprocess.Popen(["weston", "--config=" + ini, "--backend=headless-backend.so", "--use-gl", "--width=1280",
                               "--height=480", "--socket=" + socket, "--debug"],
                              env=env, stdout=subprocess.DEVNULL, stderr=open(os.path.join(work, "weston.log"), "w"))
    try:
        end = time.monotonic() + 20
        while not os.path.exists(os.path.join(xdg, socket)):
            if weston.poll() is not None or time.monotonic() > end:
                fail("weston did not start: " + open(os.path.join(work, "weston.log")).read()[-2000:])
            time.sleep(0.05)
        target = "wayland:" + socket
        for case, run in (("screenshot", lambda: screenshot(view, msp, target, env, work)),
                          ("pacing", lambda: pacing(view, msp, target, env, work)),
                          ("live", lambda: live(view, controller, cluster, os.path.dirname(scenes), target, env, work,
                                                weston)),
                          ("no_compositor", lambda: no_compositor(view, msp, env, work)),
                          ("compositor_gone", lambda: compositor_gone(view, msp, target, env, work, weston))):
            began = time.monotonic()
            run()
            print(f"  ({case}: {time.monotonic() - began:.1f} s)")
    finally:
        if weston.poll() is None:
            weston.terminate()
            weston.wait(10)
    print("PASS")


def screenshot(view, msp, target, env, work):
    out = os.path.join(work, "screenshot")
    os.makedirs(out)
    v = View([view, "--scene", msp, "--set", "Vehicle.Speed=88", "--output", target, "--out", out],
             env, os.path.join(work, "screenshot.log"))
    v.wait_for("on the display")
    subprocess.run(["weston-screenshooter"], env=env, cwd=out, check=True, timeout=30)
    shots = [f for f in os.listdir(out) if f.startswith("wayland-screenshot")]
    if len(shots) != 1:
        fail(f"weston-screenshooter wrote {shots}")
    v.proc.send_signal(signal.SIGTERM)
    if v.wait() != 0:
        fail("meter-view did not exit 0 on SIGTERM:\n" + v.text())
    fw, fh, frame = rgb(os.path.join(out, "frame.png"))
    sw, sh, shot = rgb(os.path.join(out, shots[0]))
    if (sw, sh) != (1280, 480) or (fw, fh) != (640, 480):
        fail(f"sizes: screenshot {sw}x{sh}, frame {fw}x{fh}")
    x0 = (sw - fw) // 2
    differ = 0
    for y in range(fh):
        row = shot[(y * sw + x0) * 3:(y * sw + x0 + fw) * 3]
        differ += sum(a != b for a, b in zip(row, frame[y * fw * 3:(y + 1) * fw * 3]))
        border = shot[y * sw * 3:(y * sw + x0) * 3] + shot[(y * sw + x0 + fw) * 3:(y + 1) * sw * 3]
        if border != border[:3] * (len(border) // 3):
            fail(f"row {y}: the compositor's border around the centred frame is not one colour")
    if differ:
        fail(f"{differ} bytes of the displayed frame differ from the offscreen render")
    print(f"screenshot: the displayed {fw}x{fh} frame equals the offscreen render byte for byte, centred at x={x0}")


def ramp(path, frames):
    """A link recording: Vehicle.Speed changing every 1/60 s (a new frame each refresh)."""
    with open(path, "w") as f:
        f.write("# Vehicle.Speed changing every frame at 60 frames/s\n")
        f.write("(100.000000000) SNAPSHOT seq=1 sent=100.000000000 complete=1 Vehicle.Speed=0:valid\n")
        for k in range(1, frames):
            t = 100 + k / 60
            f.write(f"({t:.9f}) DELTA seq={k + 1} sent={t:.9f} Vehicle.Speed={(3 * k) % 250}:valid\n")
    return path


def pacing(view, msp, target, env, work):
    rec = ramp(os.path.join(work, "ramp.rec"), 40)
    timing = os.path.join(work, "pacing.csv")
    v = View([view, "--scene", msp, "--play", rec, "--fps", "60", "--output", target, "--out",
              os.path.join(work, "pacing"), "--timing-csv", timing], env, os.path.join(work, "pacing.log"))
    if v.wait() != 0:
        fail("play exited non-zero:\n" + v.text())
    rows = list(csv.DictReader(open(timing)))
    shown = [int(r["presented_ns"]) for r in rows if r["presented_ns"]]
    if len(rows) != 40 or len(shown) != 40:
        fail(f"{len(rows)} frames, {len(shown)} presented (40 expected):\n" + v.text())
    gaps = [b - a for a, b in zip(shown, shown[1:])]
    if min(gaps) < 0.9 * REFRESH_NS:
        fail(f"two frames within one refresh: gaps (ms) {[round(g / 1e6, 1) for g in gaps]}")
    if any(float(r["to_presented_ms"]) <= 0 for r in rows):
        fail("a frame presented before its render ended")
    if "0 discarded" not in v.text() or "0 stalls" not in v.text():
        fail("frames discarded or callbacks stalled:\n" + v.text())
    gaps_ms = sorted(g / 1e6 for g in gaps)
    print(f"pacing: 40 frames presented, gaps {gaps_ms[0]:.1f} / {gaps_ms[len(gaps_ms) // 2]:.1f} / "
          f"{gaps_ms[-1]:.1f} ms (min / median / max)")


def frames_rows(path):
    try:
        with open(path) as f:
            return list(csv.DictReader(f))
    except FileNotFoundError:
        return []


def live(view, controller, cluster, root, target, env, work, weston):
    d = os.path.join(work, "live")
    os.makedirs(d)
    demo = os.path.join(root, "controller", "vehicles", "demo")
    sock = os.path.join(d, "link.sock")
    ctl_log = os.path.join(d, "controller.log")
    ctl = subprocess.Popen([controller, "run", "--dbc", os.path.join(demo, "demo.dbc"), "--map",
                            os.path.join(demo, "demo.map"), "--input",
                            "log:" + os.path.join(root, "vcan", "logs", "demo-drive.log"), "--link", "unix:" + sock,
                            "--state-dir", os.path.join(d, "state"), "--link-timeout", "5000"],
                           stdout=subprocess.DEVNULL, stderr=open(ctl_log, "w"))
    frames_csv = os.path.join(d, "frames.csv")
    try:
        # A link timeout above the freeze: the view's loop waits in the display meanwhile, and a lost
        # link would take the STATUS that reports the freeze with it.
        v = View([view, "--scene", cluster, "--link", "unix:" + sock, "--link-timeout", "5000", "--msaa", "1",
                  "--output", target, "--latch", "late", "--duration",
                  "60", "--out", d, "--dump-every", "10", "--pipeline", "concurrent",
                  "--inject-fault", "display@20-40"], env,
                 os.path.join(d, "view.log"))
        end = time.monotonic() + 60
        while not any(int(r["frame"]) >= 60 for r in frames_rows(frames_csv)):
            if v.proc.poll() is not None or time.monotonic() > end:
                fail("the live view did not reach frame 60:\n" + v.text())
            time.sleep(0.1)
        weston.send_signal(signal.SIGSTOP)
        time.sleep(2.0)
        weston.send_signal(signal.SIGCONT)
        v.wait_for("frozen display", 20)
        time.sleep(1.0)  # a STATUS or two after the stall
        v.proc.send_signal(signal.SIGTERM)
        if v.wait() != 0:
            fail("the live view did not exit 0 on SIGTERM:\n" + v.text())
    finally:
        ctl.terminate()
        ctl.wait(20)
    text = v.text()
    summary = [line for line in text.splitlines() if line.startswith("meter-view: integrity: ")]
    first = summary[0].split("first at frame ")[1].split(",")[0] if summary and "first at frame" in summary[0] else None
    if first is None or not 20 <= int(first) <= 40:
        fail(f"the lost display copies (frames 20-40) were not caught from frame 20 on (first fault: {first}):\n" + text)
    rows = [r for r in frames_rows(frames_csv) if r["png"]]
    faults = {int(r["frame"]): int(r["integrity_faults"]) for r in rows}
    if faults.get(30, 0) == 0 or any(n for f, n in faults.items() if f < 20 or f >= 50):
        fail(f"integrity faults per dumped frame {faults}: expected some at frame 30, none before 20 or from 50 on")
    shown = [(int(r["frame"]), int(r["presented_ns"])) for r in rows if r["presented_ns"]]
    lost = [int(r["frame"]) for r in rows if 20 <= int(r["frame"]) <= 40 and r["presented_ns"]]
    if lost or len(shown) < 4 or any(b[1] <= a[1] for a, b in zip(shown, shown[1:])):
        fail(f"frames.csv presentation times: shown {shown}, lost frames with a time {lost}")
    ctl_text = open(ctl_log).read()
    raised = " ".join(line for line in ctl_text.splitlines() if "view reports a fault" in line)
    if "display-frozen" not in raised or "integrity" not in raised:
        fail("the controller did not hear of the frozen display and the integrity faults in STATUS:\n" + ctl_text)
    monitor = [line for line in text.splitlines() if "the integrity monitor on the shown buffer" in line]
    if not monitor:
        fail("the monitor did not check the shown buffer:\n" + text)
    # Late latching (--latch late): every frame started either for a predicted latch or at
    # once for a named reason; the stopped compositor is one (its last latch is seconds old: no
    # latch is predicted from it, the frame goes at once).
    latch = [line for line in text.splitlines() if "display pacing: --latch late:" in line]
    counts = {m.group(2).strip(): int(m.group(1)) for m in re.finditer(
        r"(\d+) ([a-z ]+?)(?:[,():]|$)", latch[0].split("--latch late: ")[1].split("; margin")[0])} if latch else {}
    started, missed = counts.get("frames started for a predicted latch", 0), counts.get("missed it by the feedback", 0)
    at_once = sum(n for k, n in counts.items() if k not in ("frames started for a predicted latch", "made it",
                                                            "missed it by the feedback"))
    if started + at_once < 60 or counts.get("compositor idle", 0) < 1 or counts.get("made it", 0) + missed > started:
        fail(f"late latching: {counts} (expected 60 frames or more started, the frozen compositor as idle):\n" + text)
    print(f"live: lost copies caught from frame {first}; {len(shown)} dumped frames with a presentation time; "
          f"controller: {raised.count('display-frozen')} display-frozen; late latching: {started} frames for a "
          f"predicted latch, {missed} missed it; " + monitor[0].split("; the ")[-1])


def no_compositor(view, msp, env, work):
    v = View([view, "--scene", msp, "--set", "Vehicle.Speed=1", "--output", "wayland:nobody-here", "--out",
              os.path.join(work, "none")], env, os.path.join(work, "none.log"))
    if v.wait() != 1 or "cannot connect to the compositor at 'nobody-here'" not in v.text():
        fail("no compositor: expected exit 1 naming the socket:\n" + v.text())
    print("no_compositor: " + v.text().strip().splitlines()[-1])


def compositor_gone(view, msp, target, env, work, weston):
    v = View([view, "--scene", msp, "--set", "Vehicle.Speed=10", "--output", target, "--out",
              os.path.join(work, "gone")], env, os.path.join(work, "gone.log"))
    v.wait_for("on the display")
    weston.kill()
    weston.wait(10)
    rc = v.wait(30)
    if rc != 3 or "the display went away" not in v.text():
        fail(f"compositor gone: expected exit 3, got {rc}:\n" + v.text())
    print("compositor_gone: " + v.text().strip().splitlines()[-1])


if __name__ == "__main__":
    main()
