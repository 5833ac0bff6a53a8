"""CAN frame -> frame drawn, bounded at p99: the controller in the VM on vcan0 replays the ft86
log's ID_141 frames alone with the gear stepping every 0.23 s (tests/vcan/latency_steps.py), and
meter-view (--fps 10, --dump-every 1 with the default --dump-policy drop: the encoder never holds a
frame back) draws each new gear: the frame showing it is the first one begun after the change was
applied. Two bounds, figures in
docs/pipeline.md:

- CAN frame (kernel stamp in the guest) -> frame drawn (host), p99 <= LATENCY_P99_MS. Most of it is
  the TCG guest: its stalls put up to 212 ms between a frame's kernel stamp and its decode on this
  shared host, so the figure is the worst p99 measured plus room for such a stall.
- The view's own part, change applied -> frame drawn, p99 <= VIEW_P99_MS: the steps are sparse
  (0.23 s apart, more than the 100 ms frame period), so a latency-aware view starts the frame as
  soon as the change is applied; what is left is the render of the gear text. A view on a fixed frame clock waits for its
  next tick, uniformly over the period: more than 80 ms for a fifth of the changes, so its p99
  is above this bound (METER_LATENCY_PIPELINE=sequential runs this test against the old loop and
  fails).
"""
import json
import os
import signal
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import e2e  # noqa: E402
import e2e_session  # noqa: E402
import latency_steps as ls  # noqa: E402
import vcanlib as v  # noqa: E402

SECONDS = 25.0
STEP_S = 0.23
# p99 bounds (docs/pipeline.md#latency-aware-frames). CAN -> drawn: p99 measured 46-115 ms over
# four runs; + 85 ms for a TCG stall (rx -> decode p99 up to 64 ms, max 212 ms). Applied -> drawn:
# p99 measured 12-74 ms (render under host load up to 76 ms at load average 10, and, in runs with
# --dump-policy block, waits for the PNG writer); 80 ms is four fifths of the frame period, which a
# fixed-tick loop's wait alone exceeds for a fifth of the changes (its p99 measured 96-100 ms).
LATENCY_P99_MS = 200.0
VIEW_P99_MS = 80.0
PIPELINE = os.environ.get("METER_LATENCY_PIPELINE", "concurrent")


def drive(session=None):
    run = e2e.Run("latency_frame_drawn", ["go", f"replay:0.0:{SECONDS}", "sleep:1"], v.FT86_LOG, v.FT86_DBC,
                  e2e.FT86_MAP, timeout=int(SECONDS) + 90,
                  view_args=["--pipeline", PIPELINE, "--dump-policy", "drop"], session=session)
    run.log, gears = ls.make_stimulus(run.out, 30.0, SECONDS, STEP_S, gear_only=True)
    with open(os.path.join(run.out, "gears.json"), "w") as f:
        json.dump(gears, f)
    return run.drive()


# The drive of the shared boot (tests/vcan/e2e_session.py). Its view runs the default pipeline: a
# run with METER_LATENCY_PIPELINE set drives in a VM of its own.
DRIVES = [("latency_frame_drawn", drive)]


class LatencyOverVcan(unittest.TestCase):
    def test_a_sparse_change_is_drawn_within_the_bound(self):
        if "METER_LATENCY_PIPELINE" in os.environ:
            run, (rc, view_rcs, result) = drive()
        else:
            run, (rc, view_rcs, result) = e2e_session.shared_or_drive("latency_frame_drawn", drive)
        viewdir = run.views[0][0]
        with open(os.path.join(run.out, "gears.json")) as f:
            gears = [tuple(g) for g in json.load(f)]
        self.assertEqual(result, "ok", f"guest scenario: {result} (see {run.out}/controller.log)")
        self.assertEqual(rc, 0)
        for r in view_rcs:
            self.assertIn(r, (0, -signal.SIGTERM, 128 + signal.SIGTERM), "meter-view crashed")
        st, missed = ls.measure(run, viewdir, gears, dumped_only=False)
        steps = sum(1 for i in range(1, len(gears)) if gears[i][1] != gears[i - 1][1])
        print(f"latency ({PIPELINE}): {len(st)} of {steps} gear steps measured, {missed} missed; out {run.out}")
        print(ls.report(st, PIPELINE))
        # Every step that reached the view is measured; a few may fall in the start-up (the first
        # seconds while the view connects) or the end of the replay.
        self.assertGreaterEqual(len(st), steps * 0.8, "too few gear steps reached a drawn frame")
        p99 = ls.pct(st[:, -2], 99)
        view_p99 = ls.pct(st[:, 4] + st[:, 5], 99)   # wait for frame + render
        print(f"latency ({PIPELINE}): CAN frame -> frame drawn p99 {p99:.1f} ms, applied -> drawn p99 {view_p99:.1f} ms")
        self.assertLessEqual(view_p99, VIEW_P99_MS, f"change applied -> frame drawn p99 {view_p99:.1f} ms")
        self.assertLessEqual(p99, LATENCY_P99_MS, f"CAN frame -> frame drawn p99 {p99:.1f} ms")


if __name__ == "__main__":
    unittest.main()
