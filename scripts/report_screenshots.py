#!/usr/bin/env python3
"""Regenerates the README's pictures of the reports: docs/images/compare-report.png and docs/images/improve-report.png.

It runs the browser test (tests/browser/report_browser_test.py) with --screenshots: `motionblocks compare` and
`motionblocks improve --max-effects 1` on the shipped EMPS data, each report opened in headless Chromium (Debian's
chromium, scripts/install-deps.sh), checked, and captured at 1200 × 900, scrolled to where it shows what fails
(compare: the ranked effects and the first evidence plot) and what fell (improve: measured, before and after).
No shell is involved.

Usage: scripts/report_screenshots.py [--motionblocks BUILD/tools/motionblocks] [--out docs/images]
"""

import argparse
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--motionblocks", default=os.path.join(ROOT, "build", "release", "tools", "motionblocks"),
                        help="the binary (default: the release build's)")
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "images"), help="where the PNGs go")
    args = parser.parse_args()
    if not os.access(args.motionblocks, os.X_OK):
        print(f"report_screenshots: {args.motionblocks} not found; build it (make) or give --motionblocks")
        return 1
    test = os.path.join(ROOT, "tests", "browser", "report_browser_test.py")
    return subprocess.run([sys.executable, test, "--motionblocks", args.motionblocks, "--source", ROOT,
                           "--screenshots", args.out]).returncode


if __name__ == "__main__":
    sys.exit(main())
