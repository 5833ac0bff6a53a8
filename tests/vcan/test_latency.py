"""CAN frame -> frame drawn, bounded at p99: the controller in the VM on vcan0 replays the ft86
log's ID_141 frames alone with the gear stepping every 0.37 s (tests/vcan/latency_steps.py), and
meter-view (--fps 10, every frame dumped) must draw each new gear within LATENCY_P99_MS of the
kernel's receive stamp of the frame that carried it.

Why the bound can hold: the steps are sparse (0.37 s apart, more than the 100 ms frame period), so
a latency-aware view starts the frame as soon as the change is applied instead of at its next
10-fps tick. What is left is the controller (kernel -> decode under TCG, up to one 10 ms model
tick, the flush), the link through qemu's user-mode network, and a partial redraw of the gear text
at 640x240. A view on a fixed frame clock waits up to a whole period for its tick on top of that:
its p99 is above 100 ms and fails this bound (recorded in docs/pipeline.md with
METER_LATENCY_PIPELINE=sequential, which runs the same test against the old loop).
"""
import os
import signal
import sys
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import e2e  # noqa: E402
import latency_steps as ls  # noqa: E402
import vcanlib as v  # noqa: E402

SECONDS = 25.0
STEP_S = 0.23
# p99 bound, CAN frame (kernel stamp in the guest) -> frame drawn (host). Measured on the 2-core
# host shared with six other builds (docs/pipeline.md): see the figure and its margin there.
LATENCY_P99_MS = 90.0
PIPELINE = os.environ.get("METER_LATENCY_PIPELINE", "concurrent")


class LatencyOverVcan(unittest.TestCase):
    def test_a_sparse_change_is_drawn_within_the_bound(self):
        run = e2e.Run("latency_frame_drawn", ["go", f"replay:0.0:{SECONDS}", "sleep:1"], v.FT86_LOG, v.FT86_DBC,
                      e2e.FT86_MAP, timeout=int(SECONDS) + 90, view_args=["--pipeline", PIPELINE])
        run.log, gears = ls.make_stimulus(run.out, 30.0, SECONDS, STEP_S, gear_only=True)
        viewdir, _ = run.start()
        rc, view_rcs, result = run.finish()
        self.assertEqual(result, "ok", f"guest scenario: {result} (see {run.out}/controller.log)")
        self.assertEqual(rc, 0)
        for r in view_rcs:
            self.assertIn(r, (0, -signal.SIGTERM, 128 + signal.SIGTERM), "meter-view crashed")
        st, missed = ls.measure(run, viewdir, gears)
        steps = sum(1 for i in range(1, len(gears)) if gears[i][1] != gears[i - 1][1])
        print(f"latency ({PIPELINE}): {len(st)} of {steps} gear steps measured, {missed} missed; out {run.out}")
        print(ls.report(st, PIPELINE))
        # Every step that reached the view is measured; a few may fall in the start-up (the first
        # seconds while the view connects) or the end of the replay.
        self.assertGreaterEqual(len(st), steps * 0.8, "too few gear steps reached a drawn frame")
        p99 = ls.pct(st[:, -2], 99)
        self.assertLessEqual(p99, LATENCY_P99_MS, f"CAN frame -> frame drawn p99 {p99:.1f} ms")


if __name__ == "__main__":
    unittest.main()
