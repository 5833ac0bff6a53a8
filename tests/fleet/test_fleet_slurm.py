"""meter-fleet on a real Slurm (slurm-wlm 22.05: munged, slurmctld, slurmd on this machine, set up
by the test in its own folder and stopped by their pid files at the end, also on failure):

- 22 drives (21 variations of the demo drive cycle from meter-drivecycle, the ft86 MoTeC log read
  from ../shared) in one sbatch --array; one drive's cruise-speed expectation is doctored and must
  be reported failed with what was drawn and what was expected;
- slurmd is killed in the middle of the array (a node lost with tasks on it) and comes back after
  slurmctld declared it down: every drive is in the summary, passed, failed or lost with a reason,
  none silently missing;
- with no node left at all, the pending drives are reported lost with Slurm's reason;
- a task cancelled while it runs is submitted again and its drive passes on the second attempt;
- Ctrl-C cancels the array: nothing left in the queue, every unfinished drive reported cancelled.
"""
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

import fleetlib as fl
from slurm_cluster import SlurmCluster

DOCTORED = "demo-44s-doctored"


def results_on_disk(run_dir):
    d = os.path.join(run_dir, "drives")
    return sum(1 for n in os.listdir(d) if os.path.isfile(os.path.join(d, n, "result.json"))) if os.path.isdir(d) else 0


def node_state(cluster):
    p = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=cluster.env)
    return p.stdout.strip()


class FleetOnSlurm(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="meter-fleet-slurm-")
        os.chmod(cls.work, 0o755)  # munged's socket folder must be reachable by every user
        cls.scene = fl.scene_package(cls.work)

    @classmethod
    def tearDownClass(cls):
        if os.environ.get("METER_FLEET_KEEP"):  # to read the daemons' logs and the run folder
            fl.note(f"kept {cls.work}")
        else:
            shutil.rmtree(cls.work, ignore_errors=True)

    def assert_stopped(self, cluster, pids):
        for name, pid in pids.items():
            if pid is None:
                continue
            with self.assertRaises(ProcessLookupError, msg=f"{name} (pid {pid}) still runs"):
                os.kill(pid, 0)

    def test_fleet_with_a_failing_drive_and_a_lost_node(self):
        drives = []
        for k, seconds in enumerate(range(36, 57)):
            log = fl.drivecycle(self.work, seconds)
            # Variations: the log's length, the frame rate and the dump interval.
            fps, every = (5, 5) if k % 2 == 0 else (4, 4)
            name = DOCTORED if seconds == 44 else f"demo-{seconds}s"
            d = fl.demo_drive(name, log, fps=fps, dump_every=every)
            if name == DOCTORED:
                d["signal"][1]["value"] = 140.0  # the cruise shows 133.6: this expectation cannot hold
            drives.append(d)
        drives.append(fl.ft86_drive())
        self.assertGreaterEqual(len(drives), 20)
        manifest = fl.write_manifest(os.path.join(self.work, "fleet.json"), self.scene, drives)
        run_dir = os.path.join(self.work, "run")
        cluster = SlurmCluster(os.path.join(self.work, "slurm"))
        with cluster:
            pids = {n: cluster.pid(n) for n in ("munged", "slurmctld", "slurmd")}
            err = open(os.path.join(self.work, "fleet.stderr"), "w")
            fleet = subprocess.Popen([fl.PYTHON, fl.FLEET, "run", manifest, "--out", run_dir, "--executor", "slurm",
                                      "--poll", "0.5", "--retries", "2", "--bin", fl.BIN, "--stall-timeout", "120"],
                                     stdout=subprocess.PIPE, stderr=err, text=True, env=cluster.env)
            try:
                # The middle of the array: some drives done, the rest running or pending.
                until = time.monotonic() + 300
                while results_on_disk(run_dir) < 4 and fleet.poll() is None and time.monotonic() < until:
                    time.sleep(0.2)
                done_at_kill = results_on_disk(run_dir)
                self.assertLess(done_at_kill, len(drives), "the array ended before slurmd could be stopped")
                self.assertTrue(cluster.stop_daemon("slurmd", signal.SIGKILL), "slurmd was not running")
                fl.note(f"slurmd killed with {done_at_kill} of {len(drives)} results on disk")
                # slurmctld declares the silent node down after SlurmdTimeout (10 s in slurm_cluster.py).
                seen, until = set(), time.monotonic() + 60
                while time.monotonic() < until and not any("down" in s or s.endswith("*") for s in seen):
                    seen.add(node_state(cluster))
                    time.sleep(0.5)
                self.assertTrue(any("down" in s or s.endswith("*") for s in seen), f"node states seen: {seen}")
                cluster.start_slurmd()  # the node comes back (ReturnToService=2)
                pids["slurmd"] = cluster.pid("slurmd")
                out, _ = fleet.communicate(timeout=600)
            finally:
                if fleet.poll() is None:
                    fleet.send_signal(signal.SIGINT)  # the orchestrator cancels its arrays
                    fleet.wait(60)
                err.close()
            with open(os.path.join(self.work, "fleet.stderr")) as f:
                progress = f.read()
            self.assertEqual(fleet.returncode, 1, out + progress)
        self.assert_stopped(cluster, pids)

        s = fl.summary(run_dir)
        names = fl.by_name(s)
        self.assertEqual(sorted(names), sorted(d["name"] for d in drives), "a drive is missing from the summary")
        self.assertEqual(s["total"], len(drives))
        bad = names[DOCTORED]
        self.assertEqual(bad["verdict"], "fail", bad)
        self.assertIn("Vehicle.Speed at 35 s", " ".join(bad["reasons"]))
        self.assertIn("drew 133.6, expected 140 ± 0.5", " ".join(bad["reasons"]))
        for name, d in names.items():
            if name == DOCTORED:
                continue
            # A task lost with the node is run again (Slurm's requeue or a resubmission) or, failing
            # that, reported lost with what Slurm said: never missing, never a silent pass.
            self.assertIn(d["verdict"], ("pass", "lost"), d)
            self.assertTrue(d["verdict"] == "pass" or d["reasons"], d)
        self.assertEqual(s["pass"] + s["fail"] + s["lost"], len(drives), s)
        self.assertGreaterEqual(s["pass"], done_at_kill - 1)
        fl.note(f"summary: {s['pass']} passed, {s['fail']} failed, {s['lost']} lost; retried {s.get('retried')}, "
                f"requeued by slurm {s.get('requeued_by_slurm')}")
        self.assertIn("done", progress)  # the progress line: done/total, failures, ETA
        self.assertRegex(progress, r"\d+/22 done, \d+ failed, \d+ running, elapsed \S+, ETA")
        suites = ET.parse(os.path.join(run_dir, "junit.xml")).getroot().findall("testsuite")
        self.assertEqual(len(suites), len(drives))
        failed = [x.get("name") for x in suites if x.get("failures") != "0" or x.get("errors") != "0"]
        self.assertIn(DOCTORED, failed)

    def small_fleet(self, tag, seconds, count):
        """count drives of `seconds` without checks, their manifest, run folder and own cluster."""
        log = fl.drivecycle(self.work, seconds)
        drives = [fl.demo_drive(f"{tag}-{k}", log, speed_checks=False) for k in range(count)]
        manifest = fl.write_manifest(os.path.join(self.work, f"{tag}.json"), self.scene, drives)
        return manifest, os.path.join(self.work, f"run-{tag}"), SlurmCluster(os.path.join(self.work, f"slurm-{tag}"))

    def test_with_no_node_left_every_drive_is_reported_lost(self):
        manifest, run_dir, cluster = self.small_fleet("lost", 6, 3)
        with cluster:
            pids = {n: cluster.pid(n) for n in ("munged", "slurmctld", "slurmd")}
            cluster.stop_daemon("slurmd", signal.SIGKILL)
            # Two drives per array task: a task lost loses both, and both are reported.
            p = fl.fleet(["run", manifest, "--out", run_dir, "--executor", "slurm", "--poll", "0.5", "--drives-per-task", "2",
                          "--bin", fl.BIN, "--stall-timeout", "20"], env=cluster.env, timeout=300)
        self.assert_stopped(cluster, pids)
        self.assertEqual(p.returncode, 1, p.stdout + p.stderr)
        s = fl.summary(run_dir)
        self.assertEqual(s["lost"], 3, s)
        for d in s["drives"]:
            self.assertIn("slurm task", d["reasons"][0])
        fl.note("with no node: " + s["drives"][0]["reasons"][0])
        self.assertIn("LOST", p.stdout)

    def test_a_task_killed_without_a_result_is_run_again(self):
        # An array task cancelled while it runs (an administrator, the OOM killer) leaves no result:
        # the drive is submitted again (attempt 2) and passes; the summary names the retry.
        manifest, run_dir, cluster = self.small_fleet("killed", 30, 3)
        with cluster:
            pids = {n: cluster.pid(n) for n in ("munged", "slurmctld", "slurmd")}
            fleet = subprocess.Popen([fl.PYTHON, fl.FLEET, "run", manifest, "--out", run_dir, "--executor", "slurm",
                                      "--poll", "0.5", "--bin", fl.BIN, "--retries", "1"], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True, env=cluster.env)
            until, task = time.monotonic() + 120, None
            while time.monotonic() < until and task is None:
                q = subprocess.run(["squeue", "-h", "-t", "RUNNING", "-o", "%i"], capture_output=True, text=True, env=cluster.env)
                task = next(iter(q.stdout.split()), None)
                time.sleep(0.1)
            self.assertIsNotNone(task, "no task started")
            subprocess.run(["scancel", task], check=True, env=cluster.env)
            out, err = fleet.communicate(timeout=300)
        self.assert_stopped(cluster, pids)
        self.assertEqual(fleet.returncode, 0, out + err)
        s = fl.summary(run_dir)
        self.assertEqual(s["pass"], 3, s)
        index = int(task.split("_")[1])
        self.assertEqual(fl.by_name(s)[f"killed-{index}"]["attempt"], 2, s)
        self.assertTrue(any(r.startswith(f"killed-{index} (slurm task {task} CANCELLED") for r in s["retried"]), s["retried"])

    def test_ctrl_c_cancels_the_array(self):
        manifest, run_dir, cluster = self.small_fleet("cancel", 50, 6)
        with cluster:
            pids = {n: cluster.pid(n) for n in ("munged", "slurmctld", "slurmd")}
            fleet = subprocess.Popen([fl.PYTHON, fl.FLEET, "run", manifest, "--out", run_dir, "--executor", "slurm",
                                      "--poll", "0.5", "--bin", fl.BIN], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, env=cluster.env)
            until = time.monotonic() + 120
            while time.monotonic() < until and not subprocess.run(
                    ["squeue", "-h", "-t", "RUNNING"], capture_output=True, text=True, env=cluster.env).stdout.strip():
                time.sleep(0.2)
            fleet.send_signal(signal.SIGINT)
            out, err = fleet.communicate(timeout=120)
            # scancel ends every task of the array: nothing stays queued or running.
            until, queue = time.monotonic() + 30, "?"
            while time.monotonic() < until and queue:
                queue = subprocess.run(["squeue", "-h"], capture_output=True, text=True, env=cluster.env).stdout.strip()
                time.sleep(0.5)
        self.assert_stopped(cluster, pids)
        self.assertEqual(fleet.returncode, 130, out + err)
        self.assertEqual(queue, "", "tasks left in the queue after Ctrl-C")
        s = fl.summary(run_dir)
        self.assertEqual(s["total"], 6)
        self.assertGreaterEqual(s["cancelled"], 4, s)  # at most the two running ones may have finished
        self.assertIn("cancelled (Ctrl-C): scancel", out)


if __name__ == "__main__":
    unittest.main(verbosity=2)
