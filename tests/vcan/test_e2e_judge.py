"""The end-to-end tests' judge, checked without any process: a correct pipeline (filtered,
converted, time-shifted reference values) passes; the classic failures (unit not converted, stuck
needle, wrong scale, wrong signal) are caught. Proves the vcan e2e assertions can fail."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import e2e  # noqa: E402
import vcanlib as v  # noqa: E402

START, DUR, T_GO_VIEW, LAG = 30.0, 25.0, 12.0, 0.4


def damped(series, t0_us, times, tau=0.12):
    """Critically damped second-order filter (what a needle does), exact per step."""
    pts = [((t - t0_us) / 1e6, x) for t, x in series]
    out, y, yd, k, t_prev = [], pts[0][1], 0.0, 0, pts[0][0]
    for t in times:
        while k + 1 < len(pts) and pts[k + 1][0] <= t:
            k += 1
        u, dt = pts[k][1], t - t_prev
        e, w = y - u, 1.0 / tau
        a = math.exp(-w * dt)
        y, yd = u + (e + (yd + w * e) * dt) * a, (yd - (yd + w * e) * w * dt) * a
        out.append(y)
        t_prev = t
    return out


class Judge(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        frames = v.parse_candump(v.FT86_LOG)
        cls.t0 = frames[0].t_us
        cls.envs = e2e.ft86_envelopes(frames)
        ref = v.canmatrix_series(v.FT86_DBC, frames, [("ID_D1", "SPEED"), ("ID_140", "RPM")])
        cls.log_t = [START + i / e2e.FPS for i in range(int(DUR * e2e.FPS))]
        cls.speed = damped(ref[("ID_D1", "SPEED")], cls.t0, cls.log_t)
        cls.rpm = damped(ref[("ID_140", "RPM")], cls.t0, cls.log_t)

    def rows(self, speed_fn, rpm_fn):
        # The view draws LAG s late.
        return [e2e.Row(i, t - START + T_GO_VIEW + LAG, {e2e.SPEED: speed_fn(s), e2e.RPM: rpm_fn(r)},
                        {e2e.SPEED: "valid", e2e.RPM: "valid"}, True)
                for i, (t, s, r) in enumerate(zip(self.log_t, self.speed, self.rpm))]

    def judge(self, rows):
        """Returns (lags per window, worst share of rows outside an envelope in any window)."""
        envs = {k: self.envs[k] for k in (e2e.SPEED, e2e.RPM)}
        rep = e2e.judge(rows, envs, T_GO_VIEW, START, START + 1.5, START + DUR)
        self.assertTrue(rep)
        worst = max((bad / w["rows"] if w["rows"] else 1.0) for w in rep for bad, _ in w["bad"].values()) \
            if all(w["rows"] for w in rep) else 1.0
        return [w["lag"] for w in rep], worst

    def test_correct_pipeline_passes_and_lag_is_recovered(self):
        lags, worst = self.judge(self.rows(lambda s: 3.6 * s * 1.03 + 1.0, lambda r: r))
        for lag in lags:
            self.assertAlmostEqual(lag, LAG, delta=0.6)
        self.assertLessEqual(worst, 0.03)

    def test_replay_falling_behind_passes(self):   # TCG under load: 25 s of log over 30 s
        rows = self.rows(lambda s: 3.6 * s, lambda r: r)
        for r in rows:
            r.time = T_GO_VIEW + (r.time - T_GO_VIEW) * 1.2
        self.assertLessEqual(self.judge(rows)[1], 0.05)

    def test_speed_left_in_metres_per_second_fails(self):
        self.assertGreater(self.judge(self.rows(lambda s: s, lambda r: r))[1], 0.5)

    def test_stuck_needle_fails(self):
        self.assertGreater(self.judge(self.rows(lambda s: 3.6 * self.speed[0], lambda r: self.rpm[0]))[1], 0.5)

    def test_rpm_scaled_wrong_fails(self):
        self.assertGreater(self.judge(self.rows(lambda s: 3.6 * s, lambda r: 1.25 * r))[1], 0.2)

    def test_speed_below_true_speed_fails(self):   # UN R39: never show less than the true speed
        self.assertGreater(self.judge(self.rows(lambda s: 3.6 * s * 0.9, lambda r: r))[1], 0.2)

    def test_pipeline_lagging_far_behind_fails(self):   # e.g. a queue building up
        rows = self.rows(lambda s: 3.6 * s, lambda r: r)
        for r in rows:
            r.time += 10.0
        self.assertGreater(self.judge(rows)[1], 0.2)

    def test_view_seconds_behind_from_the_start_fails(self):   # 6 s of frame latency, not replay slip
        rows = self.rows(lambda s: 3.6 * s, lambda r: r)
        for r in rows:
            r.time += 6.0
        self.assertGreater(self.judge(rows)[1], 0.2)

    def test_frames_csv_reader(self):
        path = os.path.join(v.fresh_dir("judge_csv"), "frames.csv")
        with open(path, "w") as f:
            f.write("frame,time_s,png,link_up,drawn,Vehicle.Speed,Vehicle.Speed.status,Vehicle.Speed.failsafe,"
                    "Vehicle.Powertrain.Transmission.CurrentGear\n"
                    "0,0.0000,frame_000000.png,1,1,12.5,valid,0,N\n"
                    "3,0.3000,frame_000003.png,1,1,0,timed-out,1,3\n")
        rows = e2e.read_frames_csv(path)
        self.assertEqual([r.frame for r in rows], [0, 3])
        self.assertTrue(rows[0].valid(e2e.SPEED) and rows[0].link)
        self.assertFalse(rows[1].valid(e2e.SPEED))
        self.assertEqual(rows[1].status[e2e.SPEED], "timedout")
        self.assertEqual(set(rows[0].values), {e2e.SPEED})   # no meta or text columns
        self.assertEqual(rows[1].values["Vehicle.Powertrain.Transmission.CurrentGear"], 3.0)
        with open(path, "w") as f:
            f.write("idx,when\n1,2\n")
        with self.assertRaisesRegex(AssertionError, "frames.csv:1: expected frame and time"):
            e2e.read_frames_csv(path)


if __name__ == "__main__":
    unittest.main(verbosity=2)
