#!/usr/bin/env python3
"""meter-preview under Xvfb (the script starts its own X server, `Xvfb -displayfd`, which picks a
free display number itself, so cases running side by side never race for one): the window shows
what meter-view renders offscreen, saves are on screen within a second, a bad save shows the
converter's error and keeps the last good scene, a values CSV plays to its state.

  preview_check.py CONVERT VIEW PREVIEW SCENE_DIR CASE WORKDIR

Cases:
  same_pixels.minimal-gauge, same_pixels.cluster: the scene area read back from the window's
      framebuffer (--screenshot) and, for the cluster, captured from the X screen with xwd, against
      meter-view's EGL render of the same state: PSNR >= 50 dB;
  reload_on_save: edits of the scene config saved by rename (a colour, then a binding) and a
      re-export of the .glb (a material recoloured) are on screen within 1 s of the save, with the
      signal values kept;
  reload_on_save.cluster: the product scene's config colour edits and re-exports (a material
      recoloured) within a CPU bound per reload and a wall bound, the X screen afterwards against
      meter-view's render of the edited files;
  bad_save: a save that does not convert shows the error in the panel and the scene area keeps the
      last good scene; the fix replaces it;
  bad_start: a scene that does not convert at start opens the window with the error; the fix shows it;
  playback: --values plays a CSV to the state meter-view --values renders at its end;
  runtime_links: meter-view links neither the converter nor GLFW (ldd), meter-preview does;
  link: --link follows meter-linkplay (beside meter-view in the build's bin folder) replaying a
      recording, and shows the failsafe look once it goes away.

Pixels are read with ImageMagick (`convert ... rgb:`) and xwd's own format; no Python packages.
"""
import json
import os
import re
import select
import shutil
import statistics
import struct
import subprocess
import sys
import threading
import time

# Same-pixels floor. The window runs the engine's own code with the same API (OpenGL ES 3.2
# through EGL on the same llvmpipe) as meter-view's offscreen EGL backend, and copies the frame 1:1
# with an exact sRGB round trip, so the two are expected to be near-identical (measured: equal bit
# for bit, PSNR infinite). 50 dB still allows a few edge pixels to differ by a few levels (a driver
# that rasterises a window surface slightly differently), while any real difference fails it: the
# minimal gauge's needle at 100.2 instead of 100 km/h scores 43.8 dB (101 km/h: 34.8 dB), a
# one-level shift of the whole frame 48.1 dB, a frame copied without its sRGB encode 19.5 dB.
SAME_PIXELS_MIN_PSNR = 50.0
# The artist's loop: a save must be on screen within a second (the preview's stated goal).
RELOAD_BOUND_S = 1.0
# The cluster (163 draws, 13 programs, 1280x480): CLUSTER_SAVES config edits and as many .glb
# re-exports. A reload cost 0.20-0.31 s of CPU with the box resolve; with the film filter the
# cluster has had since 2026-12-04, 0.27-0.39 s over three runs alone, and once 0.467 s at the end of
# a whole-suite run (over the bound below). Since the renderer takes its GL programs from the
# preview's program cache and the preview keeps the memory it frees (docs/scenes.md): 0.21-0.33 s
# alone, 0.25-0.34 s beside `stress-ng --cpu 2`. (Conversion with the programs from the cache ~35 ms
# of its thread, plus a re-exported material's program; renderer ~25 ms; the first frame ~110 ms of
# llvmpipe rasterising the whole frame at MSAA 4, what meter-view's frame costs too); before the
# program cache it was 0.60-0.64 s. The one-second goal is asserted load-independently as CPU time:
# at most CLUSTER_CPU_S (1.5 times the slowest measured; it fails the reload without the cache),
# which is on screen within the second whenever the preview gets half a core (about 0.3 s with a
# core to spare). The wall time is printed against RELOAD_BOUND_S but bounded only by
# CLUSTER_SLOWEST_S: on this 2-core machine shared with six other builds (load average 6-12, 7 runs
# alone) the reloads took 0.52-1.30 s, medians of three 0.56-1.05 s, so the second holds at the
# median in most runs and not with a margin; what is left is the first frame (0.39-0.55 s of wall time here, the
# rasteriser threads waiting for a core), then the conversion (0.10-0.22 s). ctest runs the case
# alone (RUN_SERIAL): beside the other preview cases its medians were 1.2-1.3 s, slowest 1.44 s
# (CLUSTER_SLOWEST_S keeps 39 % over that; the old code's reloads took 0.9-2.9 s).
CLUSTER_SAVES = 3
CLUSTER_SLOWEST_S = 2.0
CLUSTER_CPU_S = 0.45
CLUSTER_RECOLOURED = ("Needle", "RedZone", "Chrome")

PANEL_W = 380  # PreviewOptions::panel_width
# Pause between two captures while waiting for an edit: the capture loop must not take the CPU
# the preview needs for the reload it measures (the test machine may have 2 cores).
POLL_PAUSE_S = 0.025


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


def run(cmd):
    print("+ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.stdout:
        print(r.stdout.rstrip(), flush=True)
    if r.returncode != 0:
        fail(f"{os.path.basename(cmd[0])} exited with {r.returncode}")
    return r.stdout


class Rgb:
    """An RGB8 image: width, height, bytes (top-down rows)."""

    def __init__(self, w, h, data):
        self.w, self.h, self.data = w, h, data
        if len(data) != w * h * 3:
            fail(f"image data {len(data)} bytes, expected {w * h * 3}")

    @staticmethod
    def from_png(path):
        size = subprocess.run(["identify", "-format", "%w %h", path], check=True,
                              stdout=subprocess.PIPE, text=True).stdout.split()
        data = subprocess.run(["convert", path, "-depth", "8", "rgb:-"], check=True,
                              stdout=subprocess.PIPE).stdout
        return Rgb(int(size[0]), int(size[1]), data)

    def crop(self, x, y, w, h):
        rows = [self.data[((y + r) * self.w + x) * 3:((y + r) * self.w + x + w) * 3] for r in range(h)]
        return Rgb(w, h, b"".join(rows))

    def px(self, x, y):
        i = (y * self.w + x) * 3
        return tuple(self.data[i:i + 3])


def psnr(a, b):
    if (a.w, a.h) != (b.w, b.h):
        fail(f"sizes differ: {a.w}x{a.h} vs {b.w}x{b.h}")
    se = sum((x - y) * (x - y) for x, y in zip(a.data, b.data))
    if se == 0:
        return float("inf")
    return 10.0 * __import__("math").log10(255.0 * 255.0 / (se / len(a.data)))


def xwd_screen():
    """The X screen as an Rgb, from `xwd -root` (ZPixmap, 24/32 bpp, masks from the header)."""
    raw = subprocess.run(["xwd", "-root", "-silent"], check=True, stdout=subprocess.PIPE).stdout
    f = struct.unpack(">25I", raw[:100])
    header_size, fmt, w, h = f[0], f[2], f[4], f[5]
    byte_order, bpp, bpl = f[7], f[11], f[12]
    masks, ncolors = f[14:17], f[19]
    if fmt != 2 or bpp not in (24, 32):
        fail(f"xwd: unsupported format {fmt}, {bpp} bits per pixel")
    pixels = raw[header_size + 12 * ncolors:]
    step = bpp // 8
    out = bytearray(w * h * 3)
    shifts = [(m & -m).bit_length() - 1 for m in masks]
    endian = "little" if byte_order == 0 else "big"
    o = 0
    for y in range(h):
        row = pixels[y * bpl:y * bpl + w * step]
        for x in range(0, w * step, step):
            v = int.from_bytes(row[x:x + step], endian)
            out[o] = (v & masks[0]) >> shifts[0]
            out[o + 1] = (v & masks[1]) >> shifts[1]
            out[o + 2] = (v & masks[2]) >> shifts[2]
            o += 3
    return Rgb(w, h, bytes(out))


def xwd_pixel(x, y):
    """One pixel of the X screen (a cheap xwd of a 1x1 box is not offered: read the root, take it)."""
    raw = subprocess.run(["xwd", "-root", "-silent"], check=True, stdout=subprocess.PIPE).stdout
    f = struct.unpack(">25I", raw[:100])
    header_size, byte_order, bpp, bpl, masks, ncolors = f[0], f[7], f[11], f[12], f[14:17], f[19]
    step = bpp // 8
    at = header_size + 12 * ncolors + y * bpl + x * step
    v = int.from_bytes(raw[at:at + step], "little" if byte_order == 0 else "big")
    return tuple((v & m) >> ((m & -m).bit_length() - 1) for m in masks)


class Scene:
    def __init__(self, scene_dir, name):
        if name in ("minimal-gauge", "cluster"):
            self.glb = os.path.join(scene_dir, name, name + ".glb")
            self.config = os.path.join(scene_dir, name, name + ".scene.json")
        else:
            self.glb = os.path.join(scene_dir, "features", name, name + ".glb")
            self.config = os.path.join(scene_dir, "features", name, "scene.json")


class Tools:
    def __init__(self, convert, view, preview, workdir):
        self.convert, self.view, self.preview, self.workdir = convert, view, preview, workdir

    def offscreen(self, glb, config, args, name):
        """meter-view's EGL render of `args` (--set/--values) for glb + config, as an Rgb."""
        msp = os.path.join(self.workdir, name + ".msp")
        run([self.convert, glb, "-c", config, "-o", msp, "-q"])
        run([self.view, "--scene", msp, "--backend", "egl", "--out", self.workdir, "--png", name + ".png"] + args)
        return Rgb.from_png(os.path.join(self.workdir, name + ".png"))

    def scripted(self, glb, config, args, name):
        """meter-preview's scene area read back from its window's framebuffer, as an Rgb."""
        shot = os.path.join(self.workdir, name + ".png")
        run([self.preview, glb, "-c", config, "--screenshot", shot] + args)
        return Rgb.from_png(shot)


class LivePreview:
    """A running meter-preview whose log lines are collected as they come."""

    def __init__(self, tools, glb, config, args):
        cmd = [tools.preview, glb, "-c", config] + args
        print("+ " + " ".join(cmd), flush=True)
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.lines = []
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            print("  preview: " + line.rstrip(), flush=True)
            with self.lock:
                self.lines.append(line)

    def wait_for(self, text, timeout=120.0):
        until = time.monotonic() + timeout
        while time.monotonic() < until:
            with self.lock:
                for line in self.lines:
                    if text in line:
                        return line
            if self.proc.poll() is not None:
                fail(f"meter-preview exited with {self.proc.returncode} before logging '{text}'")
            time.sleep(POLL_PAUSE_S)
        fail(f"meter-preview did not log '{text}' within {timeout} s")

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
                fail("meter-preview did not stop on SIGTERM")
        return self.proc.returncode


def save_by_rename(path, text):
    """As editors save: a temporary file beside the target, renamed over it (a new inode)."""
    tmp = os.path.join(os.path.dirname(path), "." + os.path.basename(path) + ".saving")
    with open(tmp, "w") as f:
        f.write(text)
    os.rename(tmp, path)


def working_copy(tools, scene):
    """The scene's .glb and config copied into the work folder: the artist's files to edit."""
    glb = os.path.join(tools.workdir, "scene.glb")
    config = os.path.join(tools.workdir, "scene.scene.json")
    shutil.copyfile(scene.glb, glb)
    shutil.copyfile(scene.config, config)
    with open(config) as f:
        return glb, config, f.read()


def glb_with_material(glb_bytes, name, base, emissive):
    """The .glb with material `name` recoloured (its JSON chunk rewritten, as an export would)."""
    magic, version, _ = struct.unpack("<4sII", glb_bytes[:12])
    json_len, json_type = struct.unpack("<II", glb_bytes[12:20])
    if magic != b"glTF" or version != 2 or json_type != 0x4E4F534A:
        fail("not a glTF 2.0 binary")
    doc = json.loads(glb_bytes[20:20 + json_len])
    hits = [m for m in doc["materials"] if m.get("name") == name]
    if len(hits) != 1:
        fail(f"the export has no single material {name}")
    hits[0]["pbrMetallicRoughness"]["baseColorFactor"] = base
    hits[0]["emissiveFactor"] = emissive
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    rest = glb_bytes[20 + json_len:]
    return struct.pack("<4sII", magic, version, 12 + 8 + len(text) + len(rest)) + \
        struct.pack("<II", len(text), json_type) + text + rest


def export_recoloured(glb, material):
    """The .glb re-exported with `material` green, written beside it and renamed over it as an
    exporter does; returns the time of the rename."""
    with open(glb, "rb") as f:
        exported = glb_with_material(f.read(), material, [0, 1, 0, 1], [0, 1, 0])
    tmp = os.path.join(os.path.dirname(glb), "." + os.path.basename(glb) + ".saving")
    with open(tmp, "wb") as f:
        f.write(exported)
    t0 = time.monotonic()
    os.rename(tmp, glb)
    return t0


def replaced(text, old, new):
    if old not in text:
        fail(f"the config has no '{old}' to edit")
    return text.replace(old, new, 1)


def expect_same(what, got, want):
    p = psnr(got, want)
    print(f"{what}: PSNR {p:.2f} dB against meter-view's offscreen EGL render (floor {SAME_PIXELS_MIN_PSNR} dB)",
          flush=True)
    if p < SAME_PIXELS_MIN_PSNR:
        fail(f"{what}: {p:.2f} dB < {SAME_PIXELS_MIN_PSNR} dB")


STATES = {
    "minimal-gauge": ["--set", "Vehicle.Speed=100"],
    "cluster": ["--set", "Vehicle.Speed=100", "--set", "Vehicle.Powertrain.CombustionEngine.Speed=3000",
                "--set", "Vehicle.Powertrain.FuelSystem.RelativeLevel=60",
                "--set", "Vehicle.Powertrain.CombustionEngine.ECT=90",
                "--set", "Vehicle.Powertrain.Transmission.CurrentGear=4", "--set", "Cluster.Telltale.TurnLeft=1"],
}


def case_same_pixels(tools, scene_dir, name):
    scene = Scene(scene_dir, name)
    want = tools.offscreen(scene.glb, scene.config, STATES[name], "offscreen")
    got = tools.scripted(scene.glb, scene.config, STATES[name] + ["--exit-after-frames", "5"], "window")
    expect_same(f"{name}, window framebuffer", got, want)
    if name != "cluster":
        return
    # The X screen after the swap: what the artist sees (the window sits at the screen's origin).
    live = LivePreview(tools, scene.glb, scene.config, STATES[name])
    try:
        live.wait_for("scene 1 on screen")
        time.sleep(0.5)
        screen = xwd_screen()
        expect_same(f"{name}, X screen (xwd)", screen.crop(0, 0, want.w, want.h), want)
    finally:
        code = live.stop()
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")


def wait_pixel(x, y, want, t0, bound):
    """Polls the X screen until pixel (x, y) is within 2 levels of `want`; returns the seconds from
    t0 to the end of the capture that showed it (an upper bound of the true latency)."""
    last = None
    while time.monotonic() - t0 < 10 * bound:
        last = xwd_pixel(x, y)
        if all(abs(a - b) <= 2 for a, b in zip(last, want)):
            return time.monotonic() - t0
        time.sleep(POLL_PAUSE_S)
    fail(f"pixel ({x}, {y}) is {last}, not {want}, {10 * bound} s after the save")


def case_reload_on_save(tools, scene_dir):
    scene_glb_original = Scene(scene_dir, "minimal-gauge").glb
    glb, config, text = working_copy(tools, Scene(scene_dir, "minimal-gauge"))
    live = LivePreview(tools, glb, config, STATES["minimal-gauge"])
    try:
        live.wait_for("scene 1 on screen")
        time.sleep(0.3)
        corner = xwd_pixel(5, 5)
        if corner != (0, 0, 0):
            fail(f"the background corner is {corner} before the edit, expected the config's black")
        # A colour edit: clear_color linear (0, 0.2, 0.5) is sRGB (0, 124, 188).
        text = replaced(text, '"clear_color": [0.0, 0.0, 0.0, 1.0]', '"clear_color": [0.0, 0.2, 0.5, 1.0]')
        t0 = time.monotonic()
        save_by_rename(config, text)
        latency = wait_pixel(5, 5, (0, 124, 188), t0, RELOAD_BOUND_S)
        logged = live.wait_for("scene 2 on screen")
        print(f"colour edit on the X screen {latency * 1000:.0f} ms after the save "
              f"(bound {RELOAD_BOUND_S * 1000:.0f} ms); the preview logged: {logged.strip()}", flush=True)
        if latency > RELOAD_BOUND_S:
            fail(f"the colour edit took {latency:.3f} s > {RELOAD_BOUND_S} s to appear")
        # A binding edit: the needle's range halved, so 100 km/h now points where 200 did. The
        # speed set at start is kept across the reload.
        text = replaced(text, '"input": [0, 260]', '"input": [0, 130]')
        t0 = time.monotonic()
        save_by_rename(config, text)
        logged = live.wait_for("scene 3 on screen")
        latency = time.monotonic() - t0
        print(f"binding edit logged on screen {latency * 1000:.0f} ms after the save: {logged.strip()}", flush=True)
        if latency > RELOAD_BOUND_S:
            fail(f"the binding edit took {latency:.3f} s > {RELOAD_BOUND_S} s to appear")
        # A new export of the .glb: the needle recoloured green.
        t0 = export_recoloured(glb, "NeedleRed")
        logged = live.wait_for("scene 4 on screen")
        latency = time.monotonic() - t0
        print(f"re-export of the .glb logged on screen {latency * 1000:.0f} ms after the save: {logged.strip()}",
              flush=True)
        if latency > RELOAD_BOUND_S:
            fail(f"the re-exported .glb took {latency:.3f} s > {RELOAD_BOUND_S} s to appear")
        time.sleep(0.3)
        screen = xwd_screen()
    finally:
        code = live.stop()
    want = tools.offscreen(glb, config, STATES["minimal-gauge"], "edited")
    before = tools.offscreen(scene_glb_original, config, STATES["minimal-gauge"], "red_needle")
    if psnr(want, before) > 40:
        fail("the recoloured needle looks like the red one; the .glb check would prove nothing")
    expect_same("minimal-gauge after the three edits, X screen", screen.crop(0, 0, want.w, want.h), want)
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")


def case_reload_on_save_cluster(tools, scene_dir):
    """The product scene: config edits and re-exported .glb files on screen within the bounds, and
    the X screen afterwards equal to meter-view's render of the edited files (the programs the
    preview kept across the reloads are the ones a fresh conversion makes)."""
    scene = Scene(scene_dir, "cluster")
    glb, config, text = working_copy(tools, scene)
    live = LivePreview(tools, glb, config, STATES["cluster"])
    took = {"config edit": [], "re-export of the .glb": []}
    cpu = []
    generation = 1
    try:
        live.wait_for("scene 1 on screen")
        time.sleep(0.5)
        for i in range(CLUSTER_SAVES):
            # A colour edit of the config: the background behind the panels.
            text = replaced(text, f'"clear_color": [0.0, {i / 10:.1f}, 0.5, 1.0]' if i else '"clear_color": [0.0, 0.0, 0.0, 1.0]',
                            f'"clear_color": [0.0, {(i + 1) / 10:.1f}, 0.5, 1.0]')
            t0 = time.monotonic()
            save_by_rename(config, text)
            generation += 1
            logged = live.wait_for(f"scene {generation} on screen")
            took["config edit"].append(time.monotonic() - t0)
            cpu.append(logged_cpu_s(logged))
            time.sleep(0.5)
            # A new export of the .glb: a material recoloured green (its program optimized afresh,
            # the others from the cache).
            t0 = export_recoloured(glb, CLUSTER_RECOLOURED[i % len(CLUSTER_RECOLOURED)])
            generation += 1
            logged = live.wait_for(f"scene {generation} on screen")
            took["re-export of the .glb"].append(time.monotonic() - t0)
            cpu.append(logged_cpu_s(logged))
            time.sleep(0.5)
        screen = xwd_screen()
    finally:
        code = live.stop()
    for what, seconds in took.items():
        print(f"cluster {what}: on screen (the preview's log line read) "
              f"{', '.join(f'{t * 1000:.0f}' for t in seconds)} ms after the save; median "
              f"{statistics.median(seconds) * 1000:.0f} ms (the goal {RELOAD_BOUND_S * 1000:.0f} ms), "
              f"slowest {max(seconds) * 1000:.0f} ms (bound {CLUSTER_SLOWEST_S * 1000:.0f} ms)", flush=True)
    print(f"cluster reloads' CPU time: {', '.join(f'{c * 1000:.0f}' for c in cpu)} ms "
          f"(bound {CLUSTER_CPU_S * 1000:.0f} ms)", flush=True)
    want = tools.offscreen(glb, config, STATES["cluster"], "edited")
    before = tools.offscreen(scene.glb, scene.config, STATES["cluster"], "original")
    if psnr(want, before) > 40:
        fail("the edited cluster looks like the original; the check would prove nothing")
    expect_same("cluster after the edits and re-exports, X screen", screen.crop(0, 0, want.w, want.h), want)
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")
    for what, seconds in took.items():
        if max(seconds) > CLUSTER_SLOWEST_S:
            fail(f"a cluster {what} took {max(seconds):.3f} s > {CLUSTER_SLOWEST_S} s to appear")
    if max(cpu) > CLUSTER_CPU_S:
        fail(f"a cluster reload took {max(cpu):.3f} s of CPU > {CLUSTER_CPU_S} s")


def logged_cpu_s(line):
    """The CPU seconds of a reload from the preview's 'scene N on screen ...; C ms of CPU)' line."""
    m = re.search(r"; (\d+) ms of CPU\)", line)
    if not m:
        fail("the preview's reload line gives no CPU time: " + line.strip())
    return int(m.group(1)) / 1000.0


def error_pixels(screen, x0, w, h):
    """Pixels of the panel in the error text's colour (ImGui (1, 0.4, 0.35) -> about (255, 102, 89))."""
    n = 0
    for y in range(h):
        for x in range(x0, x0 + w):
            r, g, b = screen.px(x, y)
            if r > 200 and 70 < g < 140 and 50 < b < 130:
                n += 1
    return n


def case_bad_save(tools, scene_dir):
    glb, config, good = working_copy(tools, Scene(scene_dir, "minimal-gauge"))
    want = tools.offscreen(glb, config, STATES["minimal-gauge"], "good")
    live = LivePreview(tools, glb, config, STATES["minimal-gauge"])
    try:
        live.wait_for("scene 1 on screen")
        time.sleep(0.3)
        before = error_pixels(xwd_screen(), want.w, PANEL_W, 480)
        save_by_rename(config, replaced(good, '"SpeedNeedle"', '"SpeedNeedel"'))
        logged = live.wait_for("does not convert")
        if "SpeedNeedel" not in logged:
            fail("the log does not carry the converter's message naming the bad animation: " + logged)
        time.sleep(0.5)
        screen = xwd_screen()
        during = error_pixels(screen, want.w, PANEL_W, 480)
        print(f"error-coloured panel pixels: {before} before the bad save, {during} after", flush=True)
        if before != 0 or during < 200:
            fail("the panel does not show the error text after the bad save")
        expect_same("minimal-gauge during the bad save (the last good scene)", screen.crop(0, 0, want.w, want.h), want)
        save_by_rename(config, good)
        live.wait_for("scene 2 on screen")
        time.sleep(0.3)
        after = error_pixels(xwd_screen(), want.w, PANEL_W, 480)
        if after != 0:
            fail(f"the error stays on the panel after the fix ({after} pixels)")
    finally:
        code = live.stop()
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")


def case_bad_start(tools, scene_dir):
    """A scene that does not convert at start: the window opens with the error and shows the scene
    once a save converts."""
    glb, config, good = working_copy(tools, Scene(scene_dir, "minimal-gauge"))
    want = tools.offscreen(glb, config, STATES["minimal-gauge"], "good")
    save_by_rename(config, replaced(good, '"SpeedNeedle"', '"SpeedNeedel"'))
    live = LivePreview(tools, glb, config, STATES["minimal-gauge"])
    try:
        live.wait_for("does not convert")
        time.sleep(0.5)
        during = error_pixels(xwd_screen(), want.w, PANEL_W, 480)
        print(f"error-coloured panel pixels before any scene converted: {during}", flush=True)
        if during < 200:
            fail("the panel does not show the error of the first conversion")
        save_by_rename(config, good)
        live.wait_for("scene 1 on screen")
        time.sleep(0.3)
        screen = xwd_screen()
        if error_pixels(screen, want.w, PANEL_W, 480) != 0:
            fail("the error stays on the panel after the fix")
        expect_same("minimal-gauge after the fixing save", screen.crop(0, 0, want.w, want.h), want)
    finally:
        code = live.stop()
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")


def case_playback(tools, scene_dir):
    scene = Scene(scene_dir, "cluster")
    csv = os.path.join(tools.workdir, "drive.csv")
    with open(csv, "w") as f:
        f.write("time,signal,value,status\n"
                "0,Vehicle.Speed,0\n0,Vehicle.Powertrain.CombustionEngine.Speed,800\n"
                "0.3,Vehicle.Speed,60\n0.3,Cluster.Telltale.TurnLeft,1\n"
                "0.6,Vehicle.Speed,140\n0.6,Vehicle.Powertrain.CombustionEngine.Speed,4500\n"
                "0.6,Vehicle.Powertrain.Transmission.CurrentGear,5\n"
                "0.9,Cluster.Telltale.TurnLeft,0\n0.9,Cluster.Telltale.HighBeam,1\n")
    start = tools.offscreen(scene.glb, scene.config, ["--values", csv, "--at", "0"], "start")
    want = tools.offscreen(scene.glb, scene.config, ["--values", csv], "end")
    # The check can fail: the played state is far from the file's first state.
    if psnr(start, want) > 40:
        fail("the CSV's first and last states look alike; the playback check would prove nothing")
    got = tools.scripted(scene.glb, scene.config, ["--values", csv, "--exit-after-playback"], "played")
    expect_same("cluster after playing drive.csv", got, want)


def case_link(tools, scene_dir):
    """--link follows a controller (meter-linkplay replaying a recording): its updates drive the
    scene, and when it goes away the failsafe look shows, as in meter-view."""
    linkplay = os.path.join(os.path.dirname(tools.view), "meter-linkplay")
    scene = Scene(scene_dir, "minimal-gauge")
    rec = os.path.join(tools.workdir, "drive.rec")
    with open(rec, "w") as f:
        f.write("(1.000000000) SNAPSHOT seq=1 sent=1.000000000 complete=1 Vehicle.Speed=100:valid\n"
                "(1.300000000) DELTA seq=2 sent=1.300000000 Vehicle.Speed=150:valid\n")
    endpoint = "unix:" + os.path.join(tools.workdir, "link.sock")
    want = tools.offscreen(scene.glb, scene.config, ["--set", "Vehicle.Speed=150"], "linked")
    lost = tools.offscreen(scene.glb, scene.config, ["--set", "Vehicle.Speed=150", "--link-lost"], "lost")
    if psnr(want, lost) > 40:
        fail("the failsafe look and the linked state look alike; the check would prove nothing")
    player = subprocess.Popen([linkplay, rec, "--link", endpoint, "--linger", "60"])
    live = LivePreview(tools, scene.glb, scene.config, ["--link", endpoint])
    try:
        live.wait_for("link " + endpoint + " up")
        time.sleep(1.0)  # the DELTA comes 0.3 s after the SNAPSHOT
        expect_same("minimal-gauge following the link", xwd_screen().crop(0, 0, want.w, want.h), want)
        player.terminate()
        player.wait(timeout=20)
        live.wait_for("link " + endpoint + " down")
        time.sleep(0.3)
        expect_same("minimal-gauge after the link went down", xwd_screen().crop(0, 0, lost.w, lost.h), lost)
    finally:
        if player.poll() is None:
            player.kill()
            player.wait()
        code = live.stop()
    if code != 0:
        fail(f"meter-preview exited with {code} on SIGTERM")


# Libraries of the offline side and of the window: the target's meter-view must load none of them.
PC_ONLY_LIBRARIES = ("libglslang", "libSPIRV", "libspirv-cross", "libtinygltf", "libmeshoptimizer", "libglfw")


def case_runtime_links(tools):
    """meter-preview converts in-process and opens a window; meter-view, the target's process,
    still links neither the converter nor the window toolkit (ldd)."""
    def libraries(binary):
        out = run(["ldd", binary])
        return [line.split()[0] for line in out.splitlines() if line.strip()]
    view_libs = libraries(tools.view)
    preview_libs = libraries(tools.preview)
    # The names are matched on the preview first, so a renamed library cannot make the check pass.
    for name in ("libtinygltf", "libglfw"):
        if not any(lib.startswith(name) for lib in preview_libs):
            fail(f"meter-preview does not link {name}*: the check's library names are stale")
    found = [lib for lib in view_libs if lib.startswith(PC_ONLY_LIBRARIES)]
    if found:
        fail("meter-view links PC-only libraries: " + ", ".join(found))
    print(f"meter-view links none of {', '.join(PC_ONLY_LIBRARIES)} ({len(view_libs)} libraries)", flush=True)


def start_xvfb(screen):
    """A private X server of `screen` (WxHxDepth); DISPLAY is set to it. Returns the process."""
    xvfb = shutil.which("Xvfb")
    if not xvfb:
        fail("Xvfb not found: install the Debian package xvfb (scripts/install-deps)")
    r, w = os.pipe()
    proc = subprocess.Popen([xvfb, "-displayfd", str(w), "-screen", "0", screen, "-nolisten", "tcp"],
                            pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(w)
    data = b""
    until = time.monotonic() + 30
    while not data.endswith(b"\n"):
        ready, _, _ = select.select([r], [], [], max(0.0, until - time.monotonic()))
        chunk = os.read(r, 64) if ready else b""
        if not chunk:
            code = proc.poll()
            proc.kill()
            fail("Xvfb did not name its display within 30 s" if code is None else f"Xvfb exited with {code}")
        data += chunk
    os.close(r)
    os.environ["DISPLAY"] = ":" + data.decode().strip()
    print(f"Xvfb on DISPLAY={os.environ['DISPLAY']}, screen {screen}", flush=True)
    return proc


def main():
    if len(sys.argv) != 7:
        fail(__doc__)
    convert, view, preview, scene_dir, case, workdir = sys.argv[1:]
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    tools = Tools(convert, view, preview, workdir)
    if case == "runtime_links":
        case_runtime_links(tools)
        print("PASS", flush=True)
        return
    # The screen holds the scene beside the panel: the cluster is 1280x480, the minimal gauge
    # 640x480 (a small screen keeps each xwd capture of the polling cases cheap).
    xvfb = start_xvfb("1700x600x24" if "cluster" in case or case == "playback" else "1024x600x24")
    try:
        run_case(tools, scene_dir, case)
    finally:
        xvfb.terminate()
        xvfb.wait()
    print("PASS", flush=True)


def run_case(tools, scene_dir, case):
    cases = {"reload_on_save": case_reload_on_save, "reload_on_save.cluster": case_reload_on_save_cluster,
             "bad_save": case_bad_save, "bad_start": case_bad_start,
             "playback": case_playback, "link": case_link}
    if case.startswith("same_pixels."):
        case_same_pixels(tools, scene_dir, case.split(".", 1)[1])
    elif case in cases:
        cases[case](tools, scene_dir)
    else:
        fail("unknown case " + case)


if __name__ == "__main__":
    main()
