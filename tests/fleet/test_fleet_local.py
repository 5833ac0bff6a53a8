"""meter-fleet's local executor end to end, from a TOML manifest: golden frames (one doctored),
signal expectations, a command check writing its own JUnit, the same drive twice giving the same
frames bit for bit, a bad manifest named by file, drive and field, and Ctrl-C stopping the run with
every drive still in the summary."""
import filecmp
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

import fleetlib as fl

# A command check as meter-verify plugs in (exit status + a JUnit file at {junit}): this one
# passes when frames.csv has a row per dumped PNG.
CHECKER = r'''
import csv, os, sys
run, junit = sys.argv[1], sys.argv[2]
frames = os.path.join(run, "frames")
rows = list(csv.DictReader(open(os.path.join(frames, "frames.csv"))))
pngs = sorted(f for f in os.listdir(frames) if f.startswith("frame_") and f.endswith(".png"))
ok = sorted(r["png"] for r in rows) == pngs
open(junit, "w").write('<testsuite name="rows"><testcase classname="rows" name="one row per png">%s</testcase></testsuite>'
                       % ("" if ok else '<failure message="rows and PNGs differ"/>'))
print("rows", len(rows), "pngs", len(pngs))
sys.exit(0 if ok else 1)
'''


def toml_drive(name, log, golden=None, checker=None, extra=""):
    text = f'''
[[drive]]
name = "{name}"
logs = ["{log}"]
{extra}[[drive.signal]]
signal = "Vehicle.Speed"
at = {fl.CRUISE_AT}
value = {fl.CRUISE_SHOWN}
tolerance = 0.5
[[drive.signal]]
signal = "Vehicle.Speed"
at = {fl.IDLE_AT}
status = "valid"
'''
    if golden:
        # Frames of the same binary on the same machine are equal; the bounds leave room for
        # another GPU driver's rounding (PSNR 40 dB, any channel off by at most 16 of 255).
        text += f'[[drive.golden]]\nframe = 100\npng = "{golden}"\nmin_psnr = 40\nmax_abs_diff = 16\n'
    if checker:
        text += (f'[[drive.command]]\nname = "rows"\nargv = ["{fl.PYTHON}", "{checker}", "{{run}}", "{{junit}}"]\n')
    return text


class LocalFleet(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="meter-fleet-local-")
        cls.scene = fl.scene_package(cls.work)
        cls.log = fl.drivecycle(cls.work, 40)
        cls.header = (f'[defaults]\nscene = "{cls.scene}"\ndbcs = ["{fl.DEMO_DBC}"]\nmap = "{fl.DEMO_MAP}"\n'
                      'fps = 5\ndump_every = 5\nsize = "320x120"\nmsaa = 1\n')

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def write(self, name, text):
        path = os.path.join(self.work, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_checks_goldens_and_determinism(self):
        # The golden: frame 100 (t = 20 s, accelerating) of a first run of the drive.
        first = self.write("first.toml", self.header + toml_drive("first", self.log))
        p = fl.fleet(["run", first, "--out", os.path.join(self.work, "first"), "--bin", fl.BIN, "--no-report"])
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        golden = os.path.join(self.work, "golden.png")
        shutil.copy(os.path.join(self.work, "first", "drives", "first", "frames", "frame_000100.png"), golden)
        doctored = os.path.join(self.work, "doctored.png")
        subprocess.run(["convert", golden, "-fill", "red", "-draw", "rectangle 10,10,60,50", doctored], check=True)
        checker = self.write("checker.py", CHECKER)
        manifest = self.write("fleet.toml", self.header
                              + toml_drive("same-a", self.log, golden, checker)
                              + toml_drive("same-b", self.log, golden)
                              + toml_drive("doctored-golden", self.log, doctored)
                              + toml_drive("ft86", os.path.join(fl.FT86_DIR, "can_sample.log"),
                                           extra=f'dbcs = ["{fl.FT86_DIR}/sample_can_spec.dbc"]\nmap = "{fl.FT86_MAP}"\n')
                              .replace(f"value = {fl.CRUISE_SHOWN}\ntolerance = 0.5\n", "status = \"valid\"\n"))
        run_dir = os.path.join(self.work, "run")
        p = fl.fleet(["run", manifest, "--out", run_dir, "--bin", fl.BIN, "--workers", "2"])
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        s = fl.summary(run_dir)
        d = fl.by_name(s)
        self.assertEqual(s["executor"], "local x2")
        self.assertEqual((s["total"], s["pass"], s["fail"]), (4, 3, 1), p.stdout)
        self.assertEqual(d["doctored-golden"]["verdict"], "fail")
        reason = " ".join(d["doctored-golden"]["reasons"])
        self.assertIn("golden frame 100", reason)
        self.assertRegex(reason, r"PSNR \d+\.\d+ dB < 40 dB; max abs diff \d+ > 16")
        self.assertIn("FAIL      doctored-golden: golden frame 100", p.stdout)
        # One drive, one result: the same recording and frames on every run, bit for bit.
        a, b = (os.path.join(run_dir, "drives", n) for n in ("same-a", "same-b"))
        self.assertTrue(filecmp.cmp(os.path.join(a, "link.rec"), os.path.join(b, "link.rec"), shallow=False))
        pngs = sorted(f for f in os.listdir(os.path.join(a, "frames")) if f.endswith(".png"))
        self.assertEqual(len(pngs), 40)  # 40 s at 5 fps, every 5th frame: one a second, 0..39 s
        match, mismatch, errors = filecmp.cmpfiles(os.path.join(a, "frames"), os.path.join(b, "frames"),
                                                   pngs + ["frames.csv"], shallow=False)
        self.assertEqual((mismatch, errors), ([], []))
        # The command check's own JUnit is inside the drive's and the run's JUnit.
        suites = {x.get("name"): x for x in ET.parse(os.path.join(run_dir, "junit.xml")).getroot()}
        names = [c.get("name") for c in suites["same-a"].iter("testcase")]
        self.assertIn("one row per png", names)
        self.assertEqual(suites["doctored-golden"].get("failures"), "1")

    def test_a_bad_manifest_names_file_drive_and_field(self):
        bad = self.write("bad.toml", self.header + toml_drive("x", self.log).replace("tolerance = 0.5", "tolerence = 0.5"))
        p = fl.fleet(["run", bad, "--out", os.path.join(self.work, "bad"), "--bin", fl.BIN])
        self.assertEqual(p.returncode, 2)
        self.assertIn(f"{bad}: drive 'x'.signal[0]: unknown key 'tolerence'", p.stderr)
        missing = self.write("missing.toml", self.header + toml_drive("y", "/nonexistent/drive.log"))
        p = fl.fleet(["run", missing, "--out", os.path.join(self.work, "bad"), "--bin", fl.BIN])
        self.assertEqual(p.returncode, 2)
        self.assertIn("drive 'y': no such file /nonexistent/drive.log", p.stderr)
        # A log's channel (FILE#N, as meter-controller's log:FILE#N): the file is what must exist.
        channel = self.write("channel.toml", self.header + toml_drive("z", "/nonexistent/drive.blf#2"))
        p = fl.fleet(["run", channel, "--out", os.path.join(self.work, "bad"), "--bin", fl.BIN])
        self.assertIn("drive 'z': no such file /nonexistent/drive.blf\n", p.stderr)

    def test_a_process_that_fails_is_an_error_with_its_message(self):
        # Not a scene package: meter-view exits 1 naming the file; the drive is an error, not a pass.
        bogus = self.write("not-a-package.msp", "this is not a scene package\n")
        manifest = self.write("error.toml", self.header.replace(self.scene, bogus) + toml_drive("broken-scene", self.log))
        run_dir = os.path.join(self.work, "error")
        p = fl.fleet(["run", manifest, "--out", run_dir, "--bin", fl.BIN, "--no-report"])
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        d = fl.by_name(fl.summary(run_dir))["broken-scene"]
        self.assertEqual(d["verdict"], "error")
        self.assertIn("meter-view exit 1: meter-view: error:", d["reasons"][0])
        self.assertIn("not-a-package.msp", d["reasons"][0])

    def test_drives_run_by_another_scheduler_are_collected(self):
        # What a Kubernetes Indexed Job does: plan, one `drive` per index from the environment,
        # collect. Drive 1 never ran: it is reported lost, not left out.
        manifest = self.write("k8s.toml", self.header + toml_drive("k0", self.log) + toml_drive("k1", self.log))
        run_dir = os.path.join(self.work, "k8s")
        self.assertEqual(fl.fleet(["plan", manifest, "--out", run_dir, "--bin", fl.BIN]).returncode, 0)
        p = fl.fleet(["drive", "--run", run_dir], env=dict(os.environ, JOB_COMPLETION_INDEX="0"))
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("meter-fleet drive k0: pass", p.stdout)
        p = fl.fleet(["collect", run_dir])
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        d = fl.by_name(fl.summary(run_dir))
        self.assertEqual((d["k0"]["verdict"], d["k1"]["verdict"]), ("pass", "lost"))
        self.assertIn("k1/result.json", d["k1"]["reasons"][0])

    def test_ctrl_c_stops_the_run_and_reports_every_drive(self):
        text = self.header + "".join(toml_drive(f"d{k}", self.log) for k in range(6))
        manifest = self.write("many.toml", text)
        run_dir = os.path.join(self.work, "many")
        proc = subprocess.Popen([fl.PYTHON, fl.FLEET, "run", manifest, "--out", run_dir, "--bin", fl.BIN, "--workers", "1"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        until = time.monotonic() + 120
        while not os.path.isdir(os.path.join(run_dir, "drives", "d0", "frames")) and time.monotonic() < until:
            time.sleep(0.1)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
        self.assertEqual(proc.returncode, 130, out + err)
        s = fl.summary(run_dir)
        self.assertEqual(s["total"], 6)
        self.assertGreaterEqual(s["cancelled"], 5, s)  # d0 may have finished; the rest never ran
        self.assertIn("cancelled (Ctrl-C)", out)


if __name__ == "__main__":
    unittest.main(verbosity=2)
