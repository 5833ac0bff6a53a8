#!/usr/bin/env python3
"""Converts one committed scene with meter-convert, renders it with meter-view on one backend and
checks the frames against what the scene was built to show.

  render_check.py CONVERT VIEW SCENE_DIR SCENE BACKEND WORKDIR

Checks per scene (pixels are read with ImageMagick `convert ... rgb:`, no Python packages):
- every scene: the frame has the config's size and is not a flat colour;
- minimal-gauge: at 100 and 200 km/h the red needle's angle, measured from pixels with the
  geometry in scenes/minimal-gauge/README.md, is within 1.5 deg of -120 + 240 v / 260; the 100 km/h
  frame against the committed Blender render reference-100kmh.png (>= 34 dB full frame; the
  reference's own needle within 0.5 deg of 100 km/h);
- cluster: bulb check (every lamp on): every telltale window shows its ISO colour class; driving
  state: the speedometer needle angle matches 100 km/h and lamps that are off stay dark;
  failsafe (--link-lost): the safety lamps (brake, ABS, ESC, airbag) light, turn signals do not;
- feature scenes: PSNR against the Blender reference (full frame and over the object's pixels) is
  printed; the test fails below 18 dB full-frame, a floor that separates "the scene rendered,
  framed as authored" from a black / wrong-camera frame (10-14 dB against these references). The
  paper's acceptance levels (30 dB acceptable, 40 dB indistinguishable) are the engine's
  benchmark, not this test's.
"""
import json
import math
import os
import subprocess
import sys

GOLDEN_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "golden")
# Golden-frame tolerance (full-frame PSNR). Measured on the committed goldens (engine 98fbc41):
# EGL and OSMesa frames are bit-identical (llvmpipe both); the states differ from each other by
# 21 dB; the bulb-check state with one lamp off scores 34.2 (FuelLow) to 40.6 dB (CoolantTemp, a
# thin icon) against the bulb-check golden, so 42 dB fails any single dark lamp. Rasteriser /
# rounding differences between Mesa versions move a few edge pixels by a few levels (thousands
# of pixels by 8 levels would still be 51 dB). A deliberate change of the look (shading, scene)
# fails it by design: rewrite the goldens (METER_UPDATE_GOLDEN=1, see docs/scenes.md). The old
# 36 dB let an engine change through unnoticed (38.1 dB) and no longer failed a dark lamp.
GOLDEN_MIN_PSNR = 42.0

FEATURES = ("ambient", "diffuse", "specular", "shininess", "emission", "bump", "reflection",
            "envmap2d", "skinning", "morphing", "spot", "omni", "shadow")


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(cmd):
    print("+ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.stdout:
        print(r.stdout.rstrip())
    if r.returncode != 0:
        fail(f"{os.path.basename(cmd[0])} exited with {r.returncode}")


class Image:
    def __init__(self, path):
        size = subprocess.run(["identify", "-format", "%w %h", path], check=True,
                              stdout=subprocess.PIPE, text=True).stdout.split()
        self.w, self.h = int(size[0]), int(size[1])
        self.data = subprocess.run(["convert", path, "-depth", "8", "rgb:-"], check=True,
                                   stdout=subprocess.PIPE).stdout
        if len(self.data) != self.w * self.h * 3:
            fail(f"{path}: decoded {len(self.data)} bytes, expected {self.w * self.h * 3}")

    def px(self, x, y):
        i = (y * self.w + x) * 3
        return self.data[i], self.data[i + 1], self.data[i + 2]


def not_flat(img, path):
    first = img.data[0:3]
    differing = sum(1 for i in range(0, len(img.data), 3) if img.data[i:i + 3] != first)
    if differing < 0.01 * img.w * img.h:
        fail(f"{path}: flat frame ({differing} pixels differ from the first)")


def needle_angle(img, cx, cy, r0, r1, is_needle, exclude=lambda x, y: False):
    """Screen angle (clockwise from up, degrees) of the centroid of needle-coloured pixels in the
    annulus r0..r1 around the pivot (cx, cy), skipping pixels where exclude(x, y)."""
    sx = sy = n = 0
    for y in range(max(0, int(cy - r1)), min(img.h, int(cy + r1) + 1)):
        for x in range(max(0, int(cx - r1)), min(img.w, int(cx + r1) + 1)):
            dx, dy = x + 0.5 - cx, y + 0.5 - cy
            if r0 <= math.hypot(dx, dy) <= r1 and is_needle(*img.px(x, y)) and not exclude(x, y):
                sx += dx
                sy += dy
                n += 1
    if n < 30:
        return None, n
    return math.degrees(math.atan2(sx, -sy)), n


def colour_class(r, g, b):
    if b > 150 and r < 90 and g < 160:
        return "blue"
    if g > 150 and r < 110 and b < 130:
        return "green"
    if r > 180 and 80 < g < 200 and b < 90:
        return "amber"
    if r > 180 and g < 70 and b < 70:
        return "red"
    return None


def count_class(img, cx, cy, half, cls):
    return sum(1 for y in range(int(cy - half), int(cy + half))
               for x in range(int(cx - half), int(cx + half)) if colour_class(*img.px(x, y)) == cls)


def psnr(a, b, mask=None):
    se = 0
    n = 0
    for i in range(0, len(a.data), 3):
        if mask is not None and not mask[i // 3]:
            continue
        for c in range(3):
            d = a.data[i + c] - b.data[i + c]
            se += d * d
        n += 3
    if n == 0:
        return float("nan")
    if se == 0:
        return float("inf")
    return 10.0 * math.log10(255.0 * 255.0 / (se / n))


def main():
    if len(sys.argv) != 7:
        print(__doc__)
        sys.exit(2)
    convert, view, scene_dir, scene, backend, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    if scene in FEATURES:
        glb = os.path.join(scene_dir, "features", scene, scene + ".glb")
        config = os.path.join(scene_dir, "features", scene, "scene.json")
    else:
        glb = os.path.join(scene_dir, scene, scene + ".glb")
        config = os.path.join(scene_dir, scene, scene + ".scene.json")
    cfg = json.load(open(config, encoding="utf-8"))
    msp = os.path.join(work, scene + ".msp")
    run([convert, glb, "--config", config, "-o", msp, "-q"])

    def render(name, *args):  # noqa: E306
        run([view, "--scene", msp, "--backend", backend, "--out", work, "--png", name + ".png"]
            + list(args))
        path = os.path.join(work, name + ".png")
        img = Image(path)
        if (img.w, img.h) != tuple(cfg["size"]):
            fail(f"{path}: {img.w}x{img.h}, config says {cfg['size'][0]}x{cfg['size'][1]}")
        not_flat(img, path)
        return img
    render.work = work

    if scene == "minimal-gauge":
        red = lambda r, g, b: r > 180 and g < 90 and b < 90  # noqa: E731
        for v in (100, 200):
            img = render(f"speed{v}", "--set", f"Vehicle.Speed={v}")
            got, n = needle_angle(img, 320.0, 240.0, 100.0, 150.0, red)
            want = -120.0 + 240.0 * v / 260.0
            print(f"minimal-gauge {backend}: {v} km/h -> needle {got} deg ({n} px), expected {want:.2f}")
            if got is None or abs(got - want) > 1.5:
                fail(f"needle at {v} km/h: measured {got}, expected {want:.2f} +- 1.5 deg")
            if v == 100:
                check_minimal_gauge_reference(img, scene_dir, backend, red)
    elif scene == "cluster":
        check_cluster(render, cfg, backend)
    else:
        img = render("frame")
        ref = Image(os.path.join(scene_dir, "features", scene, "reference.png"))
        # Object pixels: anything not black in the reference or the render.
        mask = [max(ref.data[i:i + 3]) > 8 or max(img.data[i:i + 3]) > 8
                for i in range(0, len(ref.data), 3)]
        full, obj = psnr(img, ref), psnr(img, ref, mask)
        share = 100.0 * sum(mask) / len(mask)
        print(f"PSNR {scene} {backend}: full frame {full:.2f} dB, object pixels {obj:.2f} dB "
              f"({share:.1f}% of the frame)")
        if not full >= 18.0:
            fail(f"{scene}: PSNR {full:.2f} dB against the reference is below the 18 dB floor")
    print("ok")


# The committed Blender render of minimal-gauge at 100 km/h (scenes/minimal-gauge/README.md) against
# meter-view's frame of the same state. Measured (EGL and OSMesa alike): 37.46 dB full frame; the
# same frame with the needle at 98 or 102 km/h scores 30.4 dB, at 95 km/h 27.6 dB, so 34 dB fails a
# needle 2 km/h off or a changed look while leaving room for rasteriser rounding.
MINIMAL_GAUGE_REFERENCE_MIN_PSNR = 34.0


def check_minimal_gauge_reference(img, scene_dir, backend, red):
    path = os.path.join(scene_dir, "minimal-gauge", "reference-100kmh.png")
    ref = Image(path)
    if (ref.w, ref.h) != (img.w, img.h):
        fail(f"{path}: {ref.w}x{ref.h}, the render is {img.w}x{img.h}")
    # The reference itself shows 100 km/h by the README's geometry (its -27.70 deg).
    got, n = needle_angle(ref, 320.0, 240.0, 100.0, 150.0, red)
    want = -120.0 + 240.0 * 100 / 260.0
    if got is None or abs(got - want) > 0.5:
        fail(f"{path}: the reference's needle at {got} deg ({n} px), expected {want:.2f} +- 0.5 deg")
    p = psnr(img, ref)
    print(f"minimal-gauge {backend}: 100 km/h against {os.path.basename(path)}: PSNR {p:.2f} dB "
          f"(min {MINIMAL_GAUGE_REFERENCE_MIN_PSNR})")
    if not p >= MINIMAL_GAUGE_REFERENCE_MIN_PSNR:
        fail(f"minimal-gauge at 100 km/h: PSNR {p:.2f} dB against {path}, below "
             f"{MINIMAL_GAUGE_REFERENCE_MIN_PSNR} dB")


# Telltale centres in the cluster (scenes/cluster/build.py TELLTALES), world units; the camera
# maps z = 0 to pixel (640 + 100 x, 240 - 100 y).
TELLTALES = {
    "TurnLeft": ("green", (-1.25, 2.0)), "LowBeam": ("green", (-0.45, 2.0)),
    "HighBeam": ("blue", (0.0, 2.0)), "FrontFog": ("green", (0.45, 2.0)),
    "TurnRight": ("green", (1.25, 2.0)), "ParkingBrake": ("red", (-1.25, -1.6)),
    "BrakeFault": ("red", (-0.75, -1.6)), "Airbag": ("red", (-0.25, -1.6)),
    "SeatBelt": ("red", (0.25, -1.6)), "OilPressure": ("red", (0.75, -1.6)),
    "Battery": ("red", (1.25, -1.6)), "ABS": ("amber", (-1.25, -2.1)),
    "ESC": ("amber", (-0.75, -2.1)), "CheckEngine": ("amber", (-0.25, -2.1)),
    "TPMS": ("amber", (0.25, -2.1)), "FuelLow": ("amber", (0.75, -2.1)),
    "CoolantTemp": ("red", (1.25, -2.1)),
}


def lamp_pixels(img, lamp):
    cls, (x, y) = TELLTALES[lamp]
    return count_class(img, 640 + 100 * x, 240 - 100 * y, 20, cls)


def check_cluster(render, cfg, backend):
    # The telltales' lamps (the shift light's visibility follows the engine speed, not a telltale).
    bound = {b["signal"].split(".")[-1] for b in cfg["bindings"]
             if b["kind"] == "visibility" and b["signal"].startswith("Cluster.Telltale.")}
    if bound != set(TELLTALES):
        fail(f"cluster config binds {sorted(bound)}, this test knows {sorted(TELLTALES)}")
    failsafe_on = {b["node"][3:] for b in cfg["bindings"]
                   if b["kind"] == "visibility" and b["failsafe"]["visible"]}
    # 1. Bulb check: every lamp on.
    sets = []
    for lamp in TELLTALES:
        sets += ["--set", f"Cluster.Telltale.{lamp}=1"]
    img = render("bulbcheck", *sets)
    for lamp in TELLTALES:
        n = lamp_pixels(img, lamp)
        print(f"bulb check {backend}: {lamp} {n} px of {TELLTALES[lamp][0]}")
        if n < 25:
            fail(f"bulb check: {lamp} shows {n} {TELLTALES[lamp][0]} pixels (expected >= 25)")
    # 2. Driving: 100 km/h, 3000 rpm, left turn and low beam on, everything else off.
    on = {"TurnLeft", "LowBeam"}
    sets = ["--set", "Vehicle.Speed=100", "--set", "Vehicle.Powertrain.CombustionEngine.Speed=3000",
            "--set", "Vehicle.Powertrain.FuelSystem.RelativeLevel=60",
            "--set", "Vehicle.Powertrain.CombustionEngine.ECT=90",
            "--set", "Vehicle.Powertrain.Transmission.CurrentGear=4",
            "--set", "Vehicle.TraveledDistance=12345", "--set", "Vehicle.TripMeterReading=123.4",
            "--set", "Vehicle.Exterior.AirTemperature=21"]
    for lamp in TELLTALES:
        sets += ["--set", f"Cluster.Telltale.{lamp}={1 if lamp in on else 0}"]
    img = render("driving", *sets)
    for lamp in TELLTALES:
        n = lamp_pixels(img, lamp)
        if (lamp in on) != (n >= 25):
            fail(f"driving: {lamp} shows {n} lit pixels, expected it {'on' if lamp in on else 'off'}")
    # Orange needle (base/emissive (1, 0.1, 0)): R high, G low-mid, B low. Pivot of the
    # speedometer at world (-3.75, 0.05), needle 0.12 above the face: perspective scale 20/19.88.
    k = 20.0 / 19.88
    cx, cy = 640 + 100 * -3.75 * k, 240 - 100 * 0.05 * k
    orange = lambda r, g, b: r > 200 and 20 < g < 140 and b < 60  # noqa: E731
    # The fuel gauge (pivot 150 px below, same orange needle) overlaps the annulus: skip it.
    fx, fy = 640 + 100 * -3.75, 240 + 100 * 1.45
    got, n = needle_angle(img, cx, cy, 60.0, 130.0, orange,
                          exclude=lambda x, y: math.hypot(x + 0.5 - fx, y + 0.5 - fy) < 85.0)
    want = -120.0 + 240.0 * 100 / 260
    print(f"driving {backend}: speed needle {got} deg ({n} px), expected {want:.2f}")
    if got is None or abs(got - want) > 2.0:
        fail(f"driving: speed needle at {got} deg, expected {want:.2f} +- 2")
    # 3. Failsafe: link lost, the bindings' failsafe looks.
    img = render("failsafe", "--link-lost")
    for lamp in TELLTALES:
        n = lamp_pixels(img, lamp)
        if (lamp in failsafe_on) != (n >= 25):
            fail(f"failsafe: {lamp} shows {n} lit pixels, expected it "
                 f"{'on' if lamp in failsafe_on else 'off'}")
    print(f"failsafe {backend}: lit lamps as configured: {sorted(failsafe_on)}")
    golden_failures = [s for s in ("bulbcheck", "driving", "failsafe")
                       if not compare_golden(render.work, s, backend)]
    if golden_failures:
        fail(f"cluster states differ from their golden frames: {golden_failures}")


def compare_golden(work, state, backend):
    """Compares work/<state>.png with tests/scenes/golden/cluster-<state>.png. With
    METER_UPDATE_GOLDEN=1 in the environment the render becomes the new golden (review the
    picture before committing it)."""
    frame = os.path.join(work, state + ".png")
    golden = os.path.join(GOLDEN_DIR, f"cluster-{state}.png")
    if os.environ.get("METER_UPDATE_GOLDEN") == "1":
        os.makedirs(GOLDEN_DIR, exist_ok=True)
        subprocess.run(["convert", frame, "-define", "png:compression-level=9", golden], check=True)
        print(f"golden {state}: updated {golden}")
        return True
    if not os.path.exists(golden):
        print(f"golden {state}: {golden} missing (METER_UPDATE_GOLDEN=1 creates it)")
        return False
    p = psnr(Image(frame), Image(golden))
    print(f"golden {state} {backend}: PSNR {p:.2f} dB (min {GOLDEN_MIN_PSNR})")
    return p >= GOLDEN_MIN_PSNR


main()
