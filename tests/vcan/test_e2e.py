"""End-to-end tests: recorded CAN logs replayed on vcan0 through meter-controller (in the
VM on this kernel) and meter-view (on the host, over TCP through the VM boundary), judged against
python3-canmatrix decoding the same log; then the faults. Run one class per CTest test."""
import csv
import os
import re
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import e2e  # noqa: E402
import e2e_session  # noqa: E402
import vcanlib as v  # noqa: E402

# Pixel proof tolerance: a live frame and the offline render of the values its frames.csv row
# claims come from the same renderer and state; they differ only by what the row does not carry
# (needle smoothing in flight, blink phase of a telltale). 30 dB on a 1280x480 cluster still
# fails for a needle off by a few degrees or a wrong digit.
PIXEL_PSNR_DB = 30.0
MAX_OUTSIDE_SHARE = 0.05     # rows allowed outside the envelope (frames caught mid-transition)


def guest_events(run):
    """Guest event times mapped to host time: the guest's clock is consistent with itself, and the
    host knows when the guest received its 'go' (to within the forwarder's latency)."""
    ev = {}
    go_at = None
    with open(os.path.join(run.out, "events.log")) as f:
        for line in f:
            t, _, what = line.strip().partition(" ")
            t = float(t)
            if what == "go received":
                go_at = t
            ev.setdefault(what, []).append(t)
    assert go_at is not None, "the guest never reached its go phase"
    return {k: [run.t_go + (t - go_at) for t in ts] for k, ts in ev.items()}


class E2eBase(unittest.TestCase):
    def check_run(self, run, rcs):
        rc, view_rcs, result = rcs
        self.assertEqual(result, "ok", f"guest scenario: {result} (see {run.out}/controller.log)")
        self.assertEqual(rc, 0)
        for r in view_rcs:
            self.assertIn(r, (0, -signal.SIGTERM, 128 + signal.SIGTERM), "meter-view crashed")

    def judged_drive(self, name, drive):
        """(run, its first view's folder) of drive `name`, shared or driven now, its exit checked."""
        run, rcs = e2e_session.shared_or_drive(name, drive)
        self.check_run(run, rcs)
        return run, run.views[0][0]

    def check_tracking(self, run, rows, envs, view_idx, start_s, t_from, t_to, min_share=0.4):
        """Over the log time [t_from, t_to) the view lived through: at least half the nominal frame
        count dumped, at least min_share of them drawing live valid values (link losses under TCG
        load cost some), at most one 5-s window nearly empty, and in every window at most
        MAX_OUTSIDE_SHARE of the judged frames outside a signal's envelope."""
        t_go_view = run.view_time(view_idx, run.t_go)
        rep = e2e.judge(rows, envs, t_go_view, start_s, t_from, t_to)
        print(f"{run.name}: " + "; ".join(
            f"{w['window']}: {w['rows']} rows, lag {w['lag']} s, outside "
            f"{ {k.rsplit('.', 1)[-1]: n for k, (n, _) in w['bad'].items()} }" for w in rep))
        lived = [w for w in rep if w["frames"] > 0]   # windows the view lived through
        self.assertTrue(lived, "the view dumped no frame during the judged log time")
        frames, judged = sum(w["frames"] for w in lived), sum(w["rows"] for w in lived)
        span = sum(w["window"][1] - w["window"][0] for w in lived)
        self.assertGreaterEqual(frames, 0.5 * span * e2e.FPS, f"the view dumped only {frames} frames")
        self.assertGreaterEqual(judged, min_share * frames,
                                f"only {judged} of {frames} frames drew live valid values")
        # A link loss under TCG load may empty one window; two empty windows are a real outage.
        thin = [w["window"] for w in lived if w["rows"] < 10]
        self.assertLessEqual(len(thin), 1, f"log windows with almost no live valid frames: {thin}")
        for w in lived:
            for s, (bad, worst) in w["bad"].items():
                self.assertLessEqual(bad, MAX_OUTSIDE_SHARE * w["rows"],
                                     f"{s} in log window {w['window']}: {bad}/{w['rows']} frames outside "
                                     f"the reference envelope, e.g. (log time, drawn, allowed) = {worst}")
        return rep

    def check_pixels(self, run, viewdir, rows, n=4):
        pkg = e2e.scene_package()
        # Settled frames whose readouts drew the text their csv values format to: frames.csv holds
        # each needle's smoothed value, the readout draws the newest one, and an offline render of
        # the row can only reproduce the frame when both agree (seen otherwise: csv 47.3, readout
        # "48", 25.5 dB). The text columns themselves are what the view drew, so nothing is hidden.
        bindings = e2e.text_bindings()
        settled = e2e.judged_rows(rows, {e2e.SPEED: None, e2e.RPM: None})
        cand = [r for r in settled if e2e.texts_match_values(r, bindings)]
        self.assertGreaterEqual(len(cand), n, f"only {len(cand)} of {len(settled)} settled frames have readouts "
                                              f"matching their csv values")
        for k in range(n):
            row = cand[(k * (len(cand) - 1)) // (n - 1)]
            ref = e2e.offline_render(pkg, row, os.path.join(run.out, f"offline_{row.frame}"))
            p = e2e.psnr(e2e.live_frame(viewdir, row), ref)
            self.assertGreaterEqual(p, PIXEL_PSNR_DB, f"frame {row.frame}: live vs offline render of its "
                                                      f"csv values: PSNR {p:.1f} dB")


class Ft86OverVcan(E2eBase):
    """ft86 log window with an acceleration from ~20 to ~120 km/h and rpm swings."""
    START, DUR = 30.0, 25.0

    @classmethod
    def drive(cls, session=None):
        return e2e.Run("e2e_ft86", ["go", f"replay:{cls.START}:{cls.DUR}", "sleep:1"],
                       v.FT86_LOG, v.FT86_DBC, e2e.FT86_MAP, session=session).drive()

    def test_values_match_canmatrix(self):
        run, viewdir = self.judged_drive("e2e_ft86", self.drive)
        rows = e2e.read_frames_csv(os.path.join(viewdir, "frames.csv"))
        envs = e2e.ft86_envelopes(v.parse_candump(v.FT86_LOG))
        # Judge from 1.5 s after the replay starts (the needles' settle time) to its end.
        self.check_tracking(run, rows, envs, 0, self.START, self.START + 1.5, self.START + self.DUR)
        self.check_pixels(run, viewdir, rows)
        subprocess.run([os.path.join(v.SOURCE_DIR, "scripts", "make-video"), viewdir], check=True)


class DemoOverVcan(E2eBase):
    """The bundled drive cycle, judged against the controller's own decode (itself checked
    against canmatrix here) and against committed golden frames."""
    START, DUR = 0.0, 40.0
    # The named state's render vs the committed golden: the same scene, renderer and state give
    # the same pixels (inf on one machine); the margin is for another Mesa/llvmpipe build's
    # rasterisation. A wrong scene, colours, needle scale or a readout digit off is ~25 dB or less
    # (measured: one speed digit off, 24.6 dB).
    GOLDEN_PSNR_DB = 30.0

    def reference(self):
        """canmatrix's decode of the demo log, after checking that the project's decoder agrees with
        it on every value of every signal the demo mapping uses."""
        out = subprocess.run([e2e.CONTROLLER, "decode", "--dbc", e2e.DEMO_DBC, e2e.DEMO_LOG,
                              "--map", e2e.DEMO_MAP], check=True, capture_output=True, text=True,
                             timeout=120).stdout
        rows = list(csv.DictReader(out.splitlines()))
        frames = v.parse_candump(e2e.DEMO_LOG)
        wanted = sorted({(r["message"], r["signal"]) for r in rows})
        self.assertIn(("ESP_WheelSpeeds", "VehicleSpeed"), wanted)
        self.assertIn(("ECM_EngineStatus", "EngineSpeed"), wanted)
        ref = v.canmatrix_series(e2e.DEMO_DBC, frames, wanted)
        mine = {}
        for r in rows:
            mine.setdefault((r["message"], r["signal"]), []).append((round(float(r["timestamp"]) * 1e6),
                                                                     float(r["physical"])))
        for key in wanted:
            self.assertEqual(len(mine[key]), len(ref[key]), f"{key}: decoded counts differ")
            for (ta, a), (tb, b) in zip(mine[key], ref[key]):
                self.assertEqual(ta, tb, f"{key}: timestamps differ")
                self.assertAlmostEqual(a, b, delta=1e-6 * max(1.0, abs(b)), msg=f"{key} at {tb} us")
        t0 = frames[0].t_us
        # demo.map: speed shown 2 % + 1 km/h over (inside the UN R39 band), rpm as is.
        return {e2e.SPEED: e2e.Envelope([ref[("ESP_WheelSpeeds", "VehicleSpeed")]], t0,
                                        lambda x: x, lambda x: 1.1 * x + 4.0, tol=1.0),
                e2e.RPM: e2e.Envelope([ref[("ECM_EngineStatus", "EngineSpeed")]], t0,
                                      lambda x: x, lambda x: x, tol=60.0)}

    @classmethod
    def drive(cls, session=None):
        return e2e.Run("e2e_demo", ["go", f"replay:{cls.START}:{cls.DUR}", "sleep:1"],
                       e2e.DEMO_LOG, e2e.DEMO_DBC, e2e.DEMO_MAP, session=session).drive()

    def test_demo_drive(self):
        envs = self.reference()
        run, viewdir = self.judged_drive("e2e_demo", self.drive)
        rows = e2e.read_frames_csv(os.path.join(viewdir, "frames.csv"))
        self.check_tracking(run, rows, envs, 0, self.START, self.START + 3.0, self.START + self.DUR)
        # The pixel proofs compare frames with renders of their rows: not during the start-up sweep
        # (the needles show the sweep there; frames.csv holds the values they show after it).
        self.check_pixels(run, viewdir, e2e.after_sweep(rows))
        self.check_golden(run, viewdir, e2e.after_sweep(rows))
        subprocess.run([os.path.join(v.SOURCE_DIR, "scripts", "make-video"), viewdir], check=True)

    def check_golden(self, run, viewdir, rows):
        """Golden frames: renders of three named states of the drive cycle, committed. The live frame
        nearest each state must equal the render of its own row, and the state's render the golden."""
        pkg = e2e.scene_package()
        bindings = e2e.text_bindings()
        # Live frames whose readouts agree with their csv values (see check_pixels), valid for
        # 0.5 s, not the judge's 2 s: under TCG canplayer sometimes sends a 10-ms message ~0.1 s
        # late, the controller rightly shows rpm TimedOut for a frame, and 2 s of settling after
        # that left no frame near "city" in one run (frames matching their text match their row
        # exactly from the next frame on: measured inf dB).
        live = [r for r in e2e.judged_rows(rows, {e2e.SPEED: None, e2e.RPM: None}, settle=0.5)
                if e2e.texts_match_values(r, bindings)]
        self.assertTrue(live, "no settled live frame to compare with the golden frames")
        for name, state in e2e.GOLDEN_STATES.items():
            # The rpm at a speed depends on the gear the drive is in: 400 rpm either way.
            near = [r for r in live if abs(r.values[e2e.SPEED] - state[e2e.SPEED]) <= 6.0
                    and abs(r.values[e2e.RPM] - state[e2e.RPM]) <= 400.0]
            self.assertTrue(near, f"{name}: no settled live frame within 6 km/h and 400 rpm of {state}")
            base = min(near, key=lambda r: abs(r.values[e2e.SPEED] - state[e2e.SPEED]) / 260
                       + abs(r.values[e2e.RPM] - state[e2e.RPM]) / 8000)
            # The drive passes through each state but a dumped frame rarely sits exactly on it
            # (accelerating through "city" at ~8 km/h per s, a frame every ~0.8 km/h, the readout
            # one digit off: 25 dB), and the rest of a frame's state (odometer, trip, fuel) differs
            # from run to run. So the chain is: the live frame nearest the state equals the render
            # of its own csv row, and the named state itself — speed and rpm valid, nothing else —
            # renders like the committed golden (a regression test of scene and renderer).
            own = e2e.offline_render(pkg, base, os.path.join(run.out, f"golden_frame_{name}"))
            p_own = e2e.psnr(e2e.live_frame(viewdir, base), own)
            ref = e2e.golden_state_render(pkg, name, os.path.join(run.out, f"golden_state_{name}"))
            golden = e2e.golden_path(name)
            if os.environ.get("METER_REGEN_GOLDEN") == "1":
                e2e.Image.fromarray(ref).save(golden)
            self.assertTrue(os.path.exists(golden), f"{golden} missing: run tests/vcan/regen_golden.py")
            g = e2e.np.asarray(e2e.Image.open(golden).convert("RGB"))
            p_golden, p_live = e2e.psnr(ref, g), e2e.psnr(e2e.live_frame(viewdir, base), g)
            print(f"e2e_demo: {name}: frame {base.frame} ({base.values[e2e.SPEED]:.1f} km/h, "
                  f"{base.values[e2e.RPM]:.0f} rpm) vs its row {p_own:.1f} dB; state vs golden {p_golden:.1f} dB; "
                  f"frame vs golden {p_live:.1f} dB (not judged: different state)")
            self.assertGreaterEqual(p_own, PIXEL_PSNR_DB, f"{name}: live frame {base.frame} vs its csv row {p_own:.1f} dB")
            self.assertGreaterEqual(p_golden, self.GOLDEN_PSNR_DB,
                                    f"{name}: the state's render vs {golden}: {p_golden:.1f} dB (after a deliberate "
                                    f"scene or renderer change: tests/vcan/regen_golden.py)")


class Faults(E2eBase):
    START = 30.0

    def envs(self):
        return e2e.ft86_envelopes(v.parse_candump(v.FT86_LOG))

    @classmethod
    def drive_controller_restart(cls, session=None):
        return e2e.Run("e2e_controller_restart",
                       ["go", f"replay-bg:{cls.START}:20", "sleep:6", "kill-controller", "sleep:2",
                        "start-controller"], v.FT86_LOG, v.FT86_DBC, e2e.FT86_MAP, session=session).drive()

    def test_controller_killed_and_restarted(self):
        run, viewdir = self.judged_drive("e2e_controller_restart", self.drive_controller_restart)
        ev = guest_events(run)
        t_kill = run.view_time(0, ev["phase kill-controller"][0])
        t_back = run.view_time(0, ev["phase start-controller"][0])
        rows = e2e.read_frames_csv(os.path.join(viewdir, "frames.csv"))
        # Link loss is declared after 3 missed 100 ms heartbeats; allow 0.7 s for TCG and qemu's
        # forwarder. Until the new controller is up, every frame must show the loss.
        lost = [r for r in rows if t_kill + 0.7 <= r.time < t_back]
        # The new controller's link can be up a little before t_back (the guest's event, mapped to
        # the view's clock); a frame drawn as soon as its snapshot arrives ends the lost stretch.
        back = next((i for i, r in enumerate(lost) if r.link is True), len(lost))
        lost = lost[:back]
        self.assertGreater(len(lost), 5)
        for r in lost:
            self.assertTrue(r.link is False or not r.valid(e2e.SPEED),
                            f"frame {r.frame} at {r.time:.2f} s still shows a live speed after the kill")
        # Recovery: reconnect backoff (<= 2 s) + snapshot; from then on values track the log again.
        after = [r for r in rows if r.time >= t_back + 3.0]
        self.assertTrue(after and all(r.valid(e2e.SPEED) for r in after[:5]), "no recovery after restart")
        # Judge the log time from the restart (+3 s) to the end of the replay.
        self.check_tracking(run, after, self.envs(), 0, self.START, self.START, self.START + 20)

    @classmethod
    def drive_view_restart(cls, session=None):
        run = e2e.Run("e2e_view_restart", ["go", f"replay:{cls.START}:18", "sleep:1"],
                      v.FT86_LOG, v.FT86_DBC, e2e.FT86_MAP, session=session)
        run.start_vm()
        run.wait_ready()
        _, view1 = run.start_view("view1")
        run.wait_link()
        run.go(time.monotonic() + 30)
        time.sleep(5)
        view1.send_signal(signal.SIGKILL)
        view1.wait()
        time.sleep(2)
        run.start_view("view2")
        return run, run.finish()

    def test_view_killed_and_restarted(self):
        run, (rc, view_rcs, result) = e2e_session.shared_or_drive("e2e_view_restart", self.drive_view_restart)
        view2dir = run.views[1][0]
        # The controller is unaffected: the guest checks it stayed alive and stopped cleanly.
        self.assertEqual(result, "ok", f"guest scenario: {result}")
        self.assertEqual(rc, 0)
        self.assertEqual(view_rcs[0], -signal.SIGKILL)
        self.assertIn(view_rcs[1], (0, -signal.SIGTERM, 128 + signal.SIGTERM))
        rows = e2e.read_frames_csv(os.path.join(view2dir, "frames.csv"))
        first_valid = next((r for r in rows if r.valid(e2e.SPEED)), None)
        self.assertIsNotNone(first_valid, "the restarted view never showed a valid speed")
        self.assertLess(first_valid.time, 3.0, "the restarted view took too long to get its snapshot")
        # The new view's whole life during the replay (judged_rows skips its settle time).
        self.check_tracking(run, rows, self.envs(), 1, self.START, self.START, self.START + 18)

    @classmethod
    def drive_bus_silence(cls, session=None):
        return e2e.Run("e2e_bus_silence", ["go", f"replay:{cls.START}:8", "sleep:5"],
                       v.FT86_LOG, v.FT86_DBC, e2e.FT86_MAP, session=session).drive()

    def test_bus_silence(self):
        run, viewdir = self.judged_drive("e2e_bus_silence", self.drive_bus_silence)
        ev = guest_events(run)
        t_quiet = run.view_time(0, ev["phase sleep:5"][0])
        rows = e2e.read_frames_csv(os.path.join(viewdir, "frames.csv"))
        # The guest logs the silence phase when the replay process has exited, which under TCG is
        # up to ~0.5 s after canplayer sent its last frame (seen: 0.5 s): judge the talking bus
        # until 1 s before.
        talking = [r for r in rows if t_quiet - 4 <= r.time < t_quiet - 1.0]
        self.assertGreater(len(talking), 10)
        for r in talking:
            self.assertTrue(r.valid(e2e.SPEED) and r.valid(e2e.RPM),
                            f"frame {r.frame} at {r.time:.2f} s: no live speed/rpm while the bus talks")
        # Timeouts come from the DBC cycle times (ft86: 20-50 ms; the controller's AUTOSAR-style
        # timeout is a few cycles), so 1.5 s later every gauge must show TimedOut — with the link up.
        quiet = [r for r in rows if t_quiet + 1.5 <= r.time < t_quiet + 4.5]
        self.assertGreater(len(quiet), 10)
        for r in quiet:
            self.assertNotEqual(r.link, False, f"frame {r.frame}: link lost during bus silence")
            for s in (e2e.SPEED, e2e.RPM):
                self.assertEqual(r.status.get(s), "timedout", f"frame {r.frame}: {s} not timed out")

    @classmethod
    def drive_flood(cls, session=None):
        return e2e.Run("e2e_flood", ["go", f"replay-bg:{cls.START}:16", "sleep:3", "rss:before",
                                     "flood:8", "rss:after"],
                       v.FT86_LOG, v.FT86_DBC, e2e.FT86_MAP, session=session).drive()

    def test_cangen_flood(self):
        run, viewdir = self.judged_drive("e2e_flood", self.drive_flood)
        rss = run.rss()
        print(f"e2e_flood: controller RSS before {rss['before']} kB, after 8 s of flood {rss['after']} kB")
        # Memory flat: no queue grows with the flood (2 MB covers allocator noise).
        self.assertLess(rss["after"] - rss["before"], 2048)
        # It was a flood: cangen under TCG managed this many frames/s (the ft86 log itself runs at
        # ~900 frames/s, a third of them on ids the gauges use).
        ev = guest_events(run)
        flooded = next(int(k.split()[-1]) for k in ev if k.startswith("flood frames "))
        print(f"e2e_flood: {flooded} frames on vcan0 in 8 s ({flooded / 8:.0f}/s)")
        self.assertGreater(flooded / 8, 2000, "cangen did not flood the bus")
        # The flood is on a mapped id, so the controller meets it: nothing may be lost silently.
        # Every frame on a mapped id (the window's and the flood's) is in the controller's trace
        # or counted in its kernel drops (stats line).
        used = e2e.mapped_ids(v.FT86_DBC, e2e.FT86_MAP)
        self.assertIn(0x154, used, "the flood's id must be one the mapping reads")
        with open(os.path.join(run.out, "window_30.0_16.log")) as f:
            window = [int(line.split()[2].split("#")[0], 16) for line in f if line.strip()]
        tx = {k.split()[1]: int(k.split()[2]) for k in ev if k.startswith("tx ")}
        flood_only = tx["end"] - tx["start"] - len(window)   # every other frame on vcan0 is the flood's
        sent = sum(1 for i in window if i in used) + flood_only
        with open(os.path.join(run.out, "controller-trace-1.csv")) as f:
            got = [int(line.split(",")[3]) for line in f if line.startswith("f,")]
        with open(os.path.join(run.out, "controller.log")) as f:
            m = re.search(r", (\d+) kernel drops", f.read())
        self.assertIsNotNone(m, f"{len(got)} of {sent} frames on mapped ids decoded and the controller's "
                                "stats line reports no kernel drops: frames lost silently")
        drops = int(m.group(1))
        rx_dropped = {k.split()[1]: int(k.split()[2]) for k in ev if k.startswith("rx_dropped ")}
        backlog = rx_dropped["end"] - rx_dropped["start"]
        # The controller reads the same counter itself (from its start, before the guest's first
        # reading, to its stop after the last, with no traffic outside them): the same count.
        # Its final stats line: the periodic "frames lost" lines before it carry the running total
        # (seen: the first said 0, the drops came later in the flood, the stats line said 243).
        with open(os.path.join(run.out, "controller.log")) as f:
            m = re.search(r", (\d+) interface drops", next((line for line in reversed(f.readlines())
                                                              if " kernel drops" in line), ""))
        self.assertIsNotNone(m, "the controller's stats line lacks its interface drops")
        self.assertEqual(int(m.group(1)), backlog, "interface drops: the controller's count vs vcan0's rx_dropped")
        print(f"e2e_flood: {sent} frames on mapped ids ({flood_only} of the flood): {len(got)} decoded, "
              f"{drops} dropped by the kernel from the controller's queues, {backlog} from the interface's "
              f"input backlog (any id, before any socket)")
        # A frame on a mapped id is decoded, or counted by its socket's drop counter, or was dropped
        # on vcan0's receive path before any socket (rx_dropped: netif_rx's backlog overflowing when
        # the guest's softirq falls behind; seen in CI: 1635 of 285 947). Nothing else may vanish.
        self.assertLessEqual(len(got) + drops, sent, "more frames decoded + counted than sent on mapped ids")
        self.assertGreaterEqual(len(got) + drops + backlog, sent,
                                "frames on mapped ids sent vs decoded + counted drops + interface drops")
        self.assertGreater(got.count(0x154), flooded // 8, "the flood did not reach the controller")
        self.assertFalse(set(got) - used, "the controller received ids its mapping does not use")
        # The flood is isolated on its id, as a CAN controller's receive mailboxes isolate it: every
        # frame the log sent on another mapped id (speed, rpm, coolant...) reached the model; the
        # kernel's drops are all the flooded id's.
        lost = {f"0x{i:03X}": (window.count(i), got.count(i)) for i in sorted(used - {0x154})
                if got.count(i) != window.count(i)}
        self.assertFalse(lost, f"ids the flood did not use lost frames (id: (sent, decoded)): {lost}")
        # Keeping up: the gauges keep tracking the log during the flood.
        rows = e2e.read_frames_csv(os.path.join(viewdir, "frames.csv"))
        self.check_tracking(run, rows, self.envs(), 0, self.START, self.START + 3.5, self.START + 11)


# The drives of the shared boot (tests/vcan/e2e_session.py), in its order: (folder, drive).
DRIVES = [("e2e_ft86", Ft86OverVcan.drive), ("e2e_controller_restart", Faults.drive_controller_restart),
          ("e2e_view_restart", Faults.drive_view_restart), ("e2e_bus_silence", Faults.drive_bus_silence),
          ("e2e_flood", Faults.drive_flood), ("e2e_demo", DemoOverVcan.drive)]


if __name__ == "__main__":
    unittest.main(verbosity=2)
