"""What the fleet tests share: paths, the scene package, drive logs from meter-drivecycle, manifests
and running meter-fleet. Debian's /usr/bin/python3, standard library only."""
import json
import os
import subprocess
import sys

SOURCE_DIR = os.environ.get("METER_SOURCE_DIR") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BINARY_DIR = os.environ.get("METER_BINARY_DIR") or os.path.join(SOURCE_DIR, "build")
SHARED_DIR = os.environ.get("METER_SHARED_DIR") or os.path.join(os.path.dirname(SOURCE_DIR), "shared")
BIN = os.path.join(BINARY_DIR, "bin")
FLEET = os.path.join(SOURCE_DIR, "scripts", "meter-fleet")
PYTHON = "/usr/bin/python3"
DEMO_DBC = os.path.join(SOURCE_DIR, "controller", "vehicles", "demo", "demo.dbc")
DEMO_MAP = os.path.join(SOURCE_DIR, "controller", "vehicles", "demo", "demo.map")
FT86_DIR = os.path.join(SHARED_DIR, "data", "can", "ft86_motec")  # read in place, never copied
FT86_MAP = os.path.join(SOURCE_DIR, "controller", "vehicles", "ft86", "ft86.map")

# The demo drive cycle (vcan/drivecycle): idle until 8 s, 130 km/h from 30 s to 42 s. The
# speedometer shows 1.02 v + 1 km/h (the demo map's UN R39 rule): 1 km/h at idle, 133.6 at cruise,
# where the damped needle has settled (it is within 0.01 km/h from 32 s on), so 0.5 km/h is
# room for nothing but rounding.
IDLE_AT, IDLE_SHOWN = 5.0, 1.0
CRUISE_AT, CRUISE_SHOWN = 35.0, 133.6


def run(argv, **kw):
    return subprocess.run(argv, capture_output=True, text=True, **kw)


def scene_package(work):
    msp = os.path.join(work, "cluster.msp")
    p = run([os.path.join(BIN, "meter-convert"), os.path.join(SOURCE_DIR, "scenes", "cluster", "cluster.glb"),
             "--config", os.path.join(SOURCE_DIR, "scenes", "cluster", "cluster.scene.json"), "-o", msp])
    assert p.returncode == 0, p.stderr
    return msp


def drivecycle(work, seconds):
    log = os.path.join(work, "logs", f"demo-{seconds}s.log")
    os.makedirs(os.path.dirname(log), exist_ok=True)
    p = run([os.path.join(BIN, "meter-drivecycle"), "--dbc", DEMO_DBC, "-o", log, "--duration", str(seconds)])
    assert p.returncode == 0, p.stderr
    return log


def demo_drive(name, log, fps=5, dump_every=5, speed_checks=True, **extra):
    d = {"name": name, "logs": [log], "dbcs": [DEMO_DBC], "map": DEMO_MAP, "fps": fps, "dump_every": dump_every}
    if speed_checks:
        d["signal"] = [{"signal": "Vehicle.Speed", "at": IDLE_AT, "value": IDLE_SHOWN, "tolerance": 0.5},
                       {"signal": "Vehicle.Speed", "at": CRUISE_AT, "value": CRUISE_SHOWN, "tolerance": 0.5}]
    d.update(extra)
    return d


def ft86_drive(name="ft86-motec", fps=5):
    # The MoTeC log has every signal of the map: its speed is valid once the wheel speeds arrive.
    return {"name": name, "logs": [os.path.join(FT86_DIR, "can_sample.log")],
            "dbcs": [os.path.join(FT86_DIR, "sample_can_spec.dbc")], "map": FT86_MAP, "fps": fps, "dump_every": 10,
            "signal": [{"signal": "Vehicle.Speed", "at": 30.0, "status": "valid"}]}


def write_manifest(path, scene, drives):
    """JSON here (the TOML reader is exercised by the local test); the same keys either way."""
    with open(path, "w") as f:
        json.dump({"defaults": {"scene": scene, "size": "320x120", "msaa": 1}, "drive": drives}, f, indent=1)
    return path


def fleet(args, env=None, timeout=900):
    return subprocess.run([PYTHON, FLEET] + args, capture_output=True, text=True, env=env, timeout=timeout)


def summary(run_dir):
    with open(os.path.join(run_dir, "summary.json")) as f:
        return json.load(f)


def by_name(summary_json):
    return {d["name"]: d for d in summary_json["drives"]}


def note(text):
    sys.stderr.write(text + "\n")
    sys.stderr.flush()
