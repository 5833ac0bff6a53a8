"""Rewrites the demo drive's golden frames (tests/vcan/golden/demo_<state>.png) from the current
scene and renderer: run after a deliberate change to either, then look at the images before
committing them. Needs a build (METER_BINARY_DIR, default build/release); no VM, no CAN.

    METER_BINARY_DIR=build/release /usr/bin/python3 tests/vcan/regen_golden.py"""
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
os.environ.setdefault("METER_SOURCE_DIR", ROOT)
os.environ.setdefault("METER_BINARY_DIR", os.path.join(ROOT, "build", "release"))
os.environ.setdefault("METER_SHARED_DIR", os.path.join(os.path.dirname(ROOT), "shared"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import e2e  # noqa: E402

pkg = e2e.scene_package()
os.makedirs(e2e.GOLDEN_DIR, exist_ok=True)
with tempfile.TemporaryDirectory() as tmp:
    for name, state in e2e.GOLDEN_STATES.items():
        img = e2e.golden_state_render(pkg, name, os.path.join(tmp, name))
        e2e.Image.fromarray(img).save(e2e.golden_path(name))
        print(f"{e2e.golden_path(name)}: {state}")
