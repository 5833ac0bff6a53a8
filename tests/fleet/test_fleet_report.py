"""The HTML report of a fleet run in headless Chromium (Debian's chromium): the index and every
drive page load without a console error or a file they cannot load (a control page with one
missing image shows the check catches it), the failing drive is marked in the table and on its
page, every link and image of every page resolves on disk, the signal plots and the contact sheet
are there, and a screenshot of the index is an image with something drawn on it."""
import os
import re
import shutil
import subprocess
import tempfile
import unittest
from html.parser import HTMLParser
from urllib.parse import unquote, urlparse

import fleetlib as fl


class Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links = []

    def handle_starttag(self, tag, attrs):
        for k, v in attrs:
            if k in ("href", "src") and v:
                self.links.append(v)


def chromium(args, timeout=120):
    return subprocess.run(["chromium", "--headless=new", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr",
                           "--v=1"] + args, capture_output=True, text=True, timeout=timeout)


def load(page):
    """The DOM after load, and the page's console messages (Chromium logs them as INFO:CONSOLE)."""
    p = chromium(["--dump-dom", "file://" + page])
    console = [line for line in p.stderr.splitlines() if ":CONSOLE" in line]
    return p.stdout, console


class FleetReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="meter-fleet-report-")
        scene = fl.scene_package(cls.work)
        log = fl.drivecycle(cls.work, 36)
        drives = [fl.demo_drive("with-video", log, video=True), fl.demo_drive("plain", log, fps=4, dump_every=4),
                  fl.demo_drive("wrong-cruise", log)]
        drives[2]["signal"][1]["value"] = 120.0
        manifest = fl.write_manifest(os.path.join(cls.work, "fleet.json"), scene, drives)
        cls.run_dir = os.path.join(cls.work, "run")
        cls.fleet = fl.fleet(["run", manifest, "--out", cls.run_dir, "--bin", fl.BIN, "--workers", "2"])
        cls.pages = [os.path.join(cls.run_dir, "index.html")] + [
            os.path.join(cls.run_dir, "drives", d["name"], "report.html") for d in drives]

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_run_failed_because_of_the_doctored_drive(self):
        self.assertEqual(self.fleet.returncode, 1, self.fleet.stdout + self.fleet.stderr)
        self.assertIn("FAIL      wrong-cruise: Vehicle.Speed at 35 s", self.fleet.stdout)

    def test_pages_load_without_errors(self):
        for page in self.pages:
            dom, console = load(page)
            self.assertRegex(dom, r'<html[^>]* data-loaded="1"', page)
            self.assertNotRegex(dom, r"<html[^>]* data-load-errors=", page)
            self.assertEqual(console, [], page)

    def test_the_load_check_catches_a_missing_file(self):
        index = self.pages[0]
        with open(index) as f:
            text = f.read()
        control = os.path.join(self.run_dir, "control.html")
        with open(control, "w") as f:
            f.write(text.replace("<h1>", '<img src="drives/no-such-frame.png" alt="missing"><h1>', 1))
        dom, console = load(control)
        self.assertRegex(dom, r'<html[^>]* data-load-errors="1"')
        self.assertTrue(any("cannot load" in c and "no-such-frame.png" in c for c in console), console)

    def test_the_failing_drive_is_marked(self):
        dom, _ = load(self.pages[0])
        rows = {m.group(1): m.group(0) for m in re.finditer(r'<tr class="\w+" data-drive="([\w.-]+)"[^>]*>.*?</tr>', dom, re.S)}
        self.assertEqual(sorted(rows), ["plain", "with-video", "wrong-cruise"])
        self.assertIn('data-verdict="fail"', rows["wrong-cruise"])
        self.assertIn("FAIL ✗", rows["wrong-cruise"])
        self.assertIn("expected 120 ± 0.5", rows["wrong-cruise"])
        self.assertIn('data-verdict="pass"', rows["plain"])
        page, _ = load(self.pages[3])
        self.assertRegex(page, r'id="verdict" data-verdict="fail">FAIL')

    def test_every_link_resolves(self):
        checked = 0
        for page in self.pages:
            parser = Links()
            with open(page) as f:
                parser.feed(f.read())
            self.assertTrue(parser.links, page)
            for link in parser.links:
                u = urlparse(link)
                self.assertEqual(u.scheme, "", f"{page}: {link}: the report must open from disk with relative links")
                target = os.path.normpath(os.path.join(os.path.dirname(page), unquote(u.path)))
                self.assertTrue(os.path.isfile(target), f"{page}: {link} -> {target} does not exist")
                checked += 1
        self.assertGreater(checked, 40)  # thumbnails, drive pages, frames, logs, the video

    def test_drive_page_has_plots_sheet_and_video(self):
        with open(self.pages[1]) as f:
            text = f.read()
        self.assertIn("<svg", text)
        self.assertIn('aria-label="Vehicle.Speed  (checked)"', text)
        self.assertIn('src="frames/contact-sheet.png"', text)
        self.assertIn('src="frames/replay.mp4"', text)
        self.assertIn("Render time per frame", text)

    def test_screenshot_is_not_empty(self):
        shot = os.path.join(self.work, "index.png")
        p = chromium(["--window-size=1200,900", f"--screenshot={shot}", "file://" + self.pages[0]])
        self.assertTrue(os.path.isfile(shot), p.stderr[-2000:])
        self.assertGreater(os.path.getsize(shot), 10000)
        # A blank page is one colour: the table, the thumbnails and the red FAIL cell are not.
        sd = subprocess.run(["identify", "-format", "%[fx:standard_deviation]", shot], capture_output=True, text=True)
        self.assertGreater(float(sd.stdout), 0.02, sd.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
