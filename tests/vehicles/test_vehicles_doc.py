#!/usr/bin/python3
"""docs/vehicles.md, run as written: every ```sh block of the page, in order, in one bash, with
HOME in a temporary folder and the built binaries on PATH, on a candump log that make_log.py
encodes from the corpus DBC with python3-canmatrix. Then what the view drew (frames.csv, the PNGs)
is judged against canmatrix's decode of that log, not against meter's own decoder.

Environment: METER_SOURCE_DIR, METER_BINARY_DIR (ctest sets both).
"""
import csv
import os
import re
import subprocess
import sys
import tempfile
import unittest

import canmatrix.formats
from PIL import Image

SRC = os.environ["METER_SOURCE_DIR"]
BIN = os.path.join(os.environ["METER_BINARY_DIR"], "bin")
DOC = os.path.join(SRC, "docs", "vehicles.md")
DBC = os.path.join(SRC, "..", "shared", "data", "can", "opendbc", "mazda_rx8.dbc")


def doc_script():
    with open(DOC) as f:
        blocks = re.findall(r"^```sh\n(.*?)^```", f.read(), re.S | re.M)
    return "set -euo pipefail\n" + "\n".join(blocks)


def canmatrix_decode(dbc, log):
    """Every (message, signal) -> list of physical values, in log order."""
    db = list(canmatrix.formats.loadp(dbc).values())[0]
    by_id = {fr.arbitration_id.id: fr for fr in db.frames}
    values = {}
    with open(log) as f:
        for line in f:
            ident, data = line.split()[2].split("#")
            fr = by_id[int(ident, 16)]
            for name, sig in fr.decode(bytes.fromhex(data)).items():
                values.setdefault((fr.name, name), []).append(float(sig.phys_value))
    return values


class VehiclesWalkthrough(unittest.TestCase):
    def test_the_page_runs_and_the_view_draws_the_logs_values(self):
        script = doc_script()
        # The page's steps, as the reader meets them.
        for step in ("check-dbc", "decode --dbc", "cat > rx8.map", "meter-convert", "meter-controller run", "meter-view"):
            self.assertIn(step, script)
        with tempfile.TemporaryDirectory(prefix="meter-vehicles-") as home:
            os.makedirs(os.path.join(home, "rx8"))
            log = os.path.join(home, "rx8", "rx8.log")
            subprocess.run([sys.executable, os.path.join(SRC, "tests", "vehicles", "make_log.py"), DBC, log], check=True)
            env = dict(os.environ, HOME=home, PATH=BIN + os.pathsep + os.environ["PATH"])
            run = subprocess.run(["bash", "-c", script], cwd=SRC, env=env, capture_output=True, text=True, timeout=150)
            work = os.path.join(home, "rx8")
            detail = run.stdout + run.stderr
            if os.path.exists(os.path.join(work, "controller.err")):
                with open(os.path.join(work, "controller.err")) as f:
                    detail += "\n--- controller.err\n" + f.read()
            self.assertEqual(run.returncode, 0, detail)
            self.assertIn("mazda_rx8.dbc", run.stdout)  # check-dbc's report (its exit 0: set -e)
            # 6 s at 50 Hz for speed and wheel_speed, 10 Hz for coolant and instrument_cluster;
            # the page's map reads all but wheel_speed.
            self.assertIn("724 frames (423 mapped, 0 unknown id", run.stdout)

            truth = canmatrix_decode(DBC, log)
            want = {  # catalog signal -> the DBC signal the page's map reads
                "Vehicle.Speed": ("speed", "VehicleSpeed"),
                "Vehicle.Powertrain.CombustionEngine.Speed": ("speed", "EngineRPM"),
                "Vehicle.Powertrain.CombustionEngine.ECT": ("coolant", "CoolantTemperature"),
                "Vehicle.Powertrain.FuelSystem.RelativeLevel": ("instrument_cluster", "FuelLevel"),
            }
            with open(os.path.join(work, "frames", "frames.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertGreaterEqual(len(rows), 5, "expected a PNG a second over 9 s")
            # frames.csv prints values with 6 decimals: 1e-6 is its rounding.
            last = rows[-1]
            self.assertEqual(last["link_up"], "1", last)
            for name, source in want.items():
                self.assertEqual(last[name + ".status"], "valid", (name, last))
                self.assertAlmostEqual(float(last[name]), truth[source][-1], delta=1e-6, msg=name)
            # While the log ramps, the needle trails it (the scene smooths Vehicle.Speed over 80 ms):
            # every speed drawn lies within what the log carried, rises frame by frame, and more
            # than the end was seen.
            drawn = [float(r["Vehicle.Speed"]) for r in rows if r["link_up"] == "1" and r["Vehicle.Speed.status"] == "valid"]
            carried = truth[("speed", "VehicleSpeed")]
            for v in drawn:
                self.assertTrue(min(carried) - 1e-6 <= v <= max(carried) + 1e-6, "drew %s km/h, outside the log's speeds" % v)
            self.assertEqual(drawn, sorted(drawn), "the drawn speed fell during a drive that only speeds up")
            self.assertGreaterEqual(len(set(drawn)), 3, "the view saw fewer than 3 speeds of the ramp: %s" % drawn)

            # The PNGs: every listed one exists, all have one size, and the last differs from the
            # first drawn with the link up (the needles moved with the ramp).
            pngs = [os.path.join(work, "frames", r["png"]) for r in rows if r["png"] and r["link_up"] == "1"]
            self.assertGreaterEqual(len(pngs), 2)
            sizes = {Image.open(p).size for p in pngs}
            self.assertEqual(len(sizes), 1, sizes)
            first, final = Image.open(pngs[0]).convert("RGB"), Image.open(pngs[-1]).convert("RGB")
            diff = sum(1 for a, b in zip(first.getdata(), final.getdata()) if a != b)
            self.assertGreater(diff, 1000, "the first and last frames are (nearly) the same picture")

            # The last frame's pixels equal an offline render of the state canmatrix decodes from
            # the log's last frames: the picture shows the log's values, not just "a cluster".
            sets = []
            for name, source in want.items():
                sets += ["--set", "%s=%r" % (name, truth[source][-1])]
            subprocess.run([os.path.join(BIN, "meter-view"), "--scene", os.path.join(work, "cluster.msp"), "--backend", "egl",
                            *sets, "--out", os.path.join(home, "expected"), "--png", "expected.png"], check=True, timeout=60)
            expected = Image.open(os.path.join(home, "expected", "expected.png")).convert("RGB")
            self.assertEqual(expected.size, final.size)
            differing = sum(1 for a, b in zip(expected.getdata(), final.getdata()) if a != b)
            self.assertEqual(differing, 0, "%d pixels of the last live frame differ from the expected state's render" % differing)


if __name__ == "__main__":
    unittest.main()
