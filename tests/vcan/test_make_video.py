"""scripts/make-video on a synthetic run: frames whose colour encodes their index, a frames.csv
with a --dump-every style gap. Checks the video's frame count and real-time duration, and that the
contact sheet shows exactly the evenly spaced frames it should (found by colour), labelled."""
import json
import os
import subprocess
import sys
import unittest

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(__file__))
import vcanlib as v  # noqa: E402

N = 40          # dumped frames
EVERY = 5       # meter-view --dump-every 5 at 30 fps: one PNG per 1/6 s


def colour(k):
    return (6 * k, 255 - 6 * k, 90)


class MakeVideo(unittest.TestCase):
    def test_video_and_contact_sheet(self):
        out = v.fresh_dir("make_video")
        with open(os.path.join(out, "frames.csv"), "w") as f:
            f.write("frame,time,Vehicle.Speed\n")
            for k in range(N):
                Image.new("RGB", (128, 48), colour(k)).save(os.path.join(out, f"frame_{k * EVERY:06d}.png"))
                f.write(f"{k * EVERY},{k * EVERY / 30:.4f},{k}\n")
        subprocess.run([os.path.join(v.SOURCE_DIR, "scripts", "make-video"), out], check=True)

        probe = json.loads(subprocess.run(
            ["ffprobe", "-v", "error", "-count_frames", "-show_entries",
             "stream=nb_read_frames,avg_frame_rate:format=duration", "-of", "json",
             os.path.join(out, "replay.mp4")], check=True, capture_output=True, text=True).stdout)
        self.assertEqual(int(probe["streams"][0]["nb_read_frames"]), N)
        num, den = map(int, probe["streams"][0]["avg_frame_rate"].split("/"))
        self.assertAlmostEqual(num / den, 30 / EVERY, delta=0.05, msg="video must play in real time")

        sheet = np.asarray(Image.open(os.path.join(out, "contact-sheet.png")).convert("RGB")).astype(int)
        expected = [round(j * (N - 1) / 11) for j in range(12)]
        for k in range(N):
            d = np.abs(sheet - np.array(colour(k))).max(axis=2)
            pixels = int((d <= 2).sum())
            if k in expected:
                self.assertGreater(pixels, 5000, f"frame {k} should be on the contact sheet")
            else:
                self.assertLess(pixels, 50, f"frame {k} should not be on the contact sheet")
        # Labels: white text on the dark background.
        self.assertGreater(int((sheet.min(axis=2) > 200).sum()), 500, "no time labels drawn")

    def test_no_frames_is_a_clear_error(self):
        out = v.fresh_dir("make_video_empty")
        p = subprocess.run([os.path.join(v.SOURCE_DIR, "scripts", "make-video"), out],
                           capture_output=True, text=True)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("no frame_NNNNNN.png", p.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
