#!/usr/bin/env python3
"""scripts/readme_figures.py catches a drifted README figure (issue 28, item 1), without running motionblocks.

The ctest readme_figures runs the script's --check with the real binary: it fails when the README and a run
disagree, but it passes as long as they agree, so it cannot show by itself that it would fail. This test can: it
gives the script a stand-in for motionblocks that writes fixed records (readme_figures_records.json, the fields the
figures read, from a real run) and PNGs of the report's size, and checks on copies of README.md that
  - every pattern of the script's FIGURES is found in the real README (a reworded sentence fails here first);
  - a copy regenerated from the records passes --check (exit 0), and one figure edited in it fails (exit 1), the
    drift named with its README line, what the README says and what the run gives, the copy left unchanged;
  - regenerating restores the edited figure, and only it;
  - a missing picture, a picture of another size than the run draws, a reworded pattern and a failed run are
    reported (exit 1, 1, 2, 2);
  - numbers are written at the README's precision with its minus sign.

Usage: readme_figures_test.py [unittest options]
"""

import contextlib
import importlib.util
import io
import os
import shutil
import stat
import struct
import sys
import tempfile
import unittest
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
RECORDS = os.path.join(HERE, "readme_figures_records.json")

sys.dont_write_bytecode = True  # no __pycache__ beside the script
spec = importlib.util.spec_from_file_location("readme_figures", os.path.join(SOURCE, "scripts", "readme_figures.py"))
figures = importlib.util.module_from_spec(spec)
spec.loader.exec_module(figures)

# The stand-in for motionblocks: writes the record of the run its --out folder names (the script's folder names:
# the demo's steps as in scripts/demo.sh, the README runs by their name) and, for demo step 1, the report's PNGs.
# FAKE_FAIL=NAME makes that run exit 3; FAKE_PNG=WxH draws the PNGs at another size.
FAKE = r'''#!{python}
import json, os, struct, sys, zlib
RUNS = {{"1_base": "demo1", "2_suggested": "demo2", "3_validate_base": "demo3", "4_validate_suggested": "demo4",
        "reproduce": "reproduce", "closed_loop": "closed_loop", "improve": "improve", "odrive": "odrive", "brfd": "brfd",
        "stability": "stability"}}
FILES = {{"reproduce": "results.json", "improve": "improve.json", "stability": "stability.json"}}
out = sys.argv[sys.argv.index("--out") + 1]
name = RUNS[os.path.basename(out)]
if os.environ.get("FAKE_FAIL") == name:
    print("error: the stand-in fails", name)
    sys.exit(3)
with open({records!r}, encoding="utf-8") as f:
    record = json.load(f)[name]
os.makedirs(out, exist_ok=True)
with open(os.path.join(out, FILES.get(name, "compare.json")), "w", encoding="utf-8") as f:
    json.dump(record, f)
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
if name == "demo1":
    width, height = map(int, os.environ.get("FAKE_PNG", "900x420").split("x"))
    rows = b"".join(b"\0" + b"\xff" * (3 * width) for _ in range(height))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    for picture in ("model_vs_measurement.png", "position_periodogram.png"):
        with open(os.path.join(out, picture), "wb") as f:
            f.write(png)
'''


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def write(path, text):
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


class ReadmeFigures(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mb_readme_figures_test_")
        self.binary = os.path.join(self.folder, "motionblocks")
        write(self.binary, FAKE.format(python=sys.executable, records=RECORDS))
        os.chmod(self.binary, os.stat(self.binary).st_mode | stat.S_IXUSR)
        self.readme = os.path.join(self.folder, "README.md")
        shutil.copyfile(os.path.join(SOURCE, "README.md"), self.readme)
        for name in ("FAKE_FAIL", "FAKE_PNG"):
            os.environ.pop(name, None)

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def script(self, *options):
        """Runs the script's main() on the copy; returns (exit status, what it printed)."""
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            status = figures.main(["--motionblocks", self.binary, "--readme", self.readme, *options])
        return status, out.getvalue()

    def regenerated(self):
        status, output = self.script()
        self.assertEqual(status, 0, output)
        return read(self.readme)

    def test_every_pattern_is_found_in_the_readme(self):
        text = read(os.path.join(SOURCE, "README.md"))
        found = figures.locate(text)
        self.assertEqual(len(found), sum(len(f.holes) for f in figures.FIGURES))
        runs = figures.demo_runs(SOURCE, "motionblocks", "/work") + figures.readme_runs(text, "motionblocks", "/work")
        self.assertEqual(len(runs), len(figures.DEMO_STEPS) + len(figures.README_RUNS))

    def test_a_drifted_figure_fails_the_check_and_is_regenerated(self):
        agreed = self.regenerated()
        status, output = self.script("--check")
        self.assertEqual(status, 0, output)
        self.assertIn("all agree", output)

        step3 = next(f for f in figures.locate(agreed) if f.label == "step 3: force RMSE [N]")
        wrong = "9.99" if step3.text != "9.99" else "9.98"
        edited = agreed[:step3.start] + wrong + agreed[step3.end:]
        write(self.readme, edited)
        status, output = self.script("--check")
        self.assertEqual(status, 1, output)
        self.assertIn(f"README.md:{step3.line}: step 3: force RMSE [N]: the README says {wrong}, the run gives "
                      f"{step3.text}", output)
        self.assertIn("1 figure(s) drifted, 0 picture problem(s)", output)
        self.assertEqual(read(self.readme), edited, "--check changed the README")

        self.assertEqual(self.regenerated(), agreed)

    def test_a_missing_picture_fails_the_check(self):
        self.regenerated()
        image = figures.PICTURES[1].image
        os.remove(os.path.join(self.folder, image))
        status, output = self.script("--check")
        self.assertEqual(status, 1, output)
        self.assertIn(f"{image}: [Errno 2]", output)

    def test_a_picture_the_readme_does_not_show_fails_the_check(self):
        text = self.regenerated()
        image = figures.PICTURES[0].image
        write(self.readme, text.replace(f"]({image})", "](docs/images/another.png)"))
        status, output = self.script("--check")
        self.assertEqual(status, 1, output)
        self.assertIn(f"does not show {image}", output)

    def test_a_picture_of_another_size_fails_the_check(self):
        self.regenerated()
        os.environ["FAKE_PNG"] = "640x480"
        status, output = self.script("--check")
        self.assertEqual(status, 1, output)
        self.assertIn("is 900×420 px, the run draws model_vs_measurement.png at 640×480", output)

    def test_a_reworded_sentence_is_an_error(self):
        text = read(self.readme)
        write(self.readme, text.replace("(the screw lead), refit jointly", "(the screw's lead), refit jointly"))
        status, output = self.script("--check")
        self.assertEqual(status, 2, output)
        self.assertIn("region demo-table holds 0 matches of the pattern", output)

    def test_a_failed_run_is_an_error(self):
        os.environ["FAKE_FAIL"] = "improve"
        status, output = self.script("--check")
        self.assertEqual(status, 2, output)
        self.assertIn("improve (README.md:", output)
        self.assertIn("failed (exit 3)", output)
        self.assertIn("error: the stand-in fails improve", output)

    def test_numbers_at_the_readmes_precision(self):
        self.assertEqual(figures.formatted(0.0025034277 * 1e3, "2.503"), "2.503")
        self.assertEqual(figures.formatted(0.0025036 * 1e3, "2.503"), "2.504")
        self.assertEqual(figures.formatted(-3.1671, "−3.2"), "−3.2")
        self.assertEqual(figures.formatted(-3.1671, "-3.2"), "-3.2")
        self.assertEqual(figures.formatted(-3.1671, "3.2"), "−3.2")
        self.assertEqual(figures.formatted(-0.01, "0.0"), "0.0")
        self.assertEqual(figures.formatted(1 / 0.1423, "7"), "7")
        self.assertEqual(figures.formatted(12.9899, "13.0"), "13.0")
        self.assertEqual(figures.formatted("velocity_dependent_ripple", "position_periodic"),
                         "velocity_dependent_ripple")


if __name__ == "__main__":
    unittest.main(verbosity=2)
