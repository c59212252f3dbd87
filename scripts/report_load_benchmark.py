#!/usr/bin/env python3
"""How long a long run's report takes to open in a browser (issue 27's done-when: a 10⁶-sample run's report opens in
under 2 s; the figure goes in docs/benchmarks.md).

What it does: `motionblocks run diagrams/hil/pd_rigid_body.json` with the solver at 1 ms and the stop time set so that
the run logs N samples (default 10⁶: 1000 s at 1 kHz), in a temporary folder; then opens the run's report.html in
headless Chromium (Debian's `chromium`, driven over its DevTools pipe by tests/browser/devtools.py, as the browser
test does; nothing is downloaded) `--repeats` times, each in a fresh tab, and measures

  - open: from the navigation's start to the first frame painted after every chart of the page was drawn (the page's
    own clock, performance.now(), read after two animation frames once each chart box holds its dygraph object);
  - load: the navigation's loadEventEnd (the page's script, which draws the charts, has run by then);
  - wall: the same seen from outside, from Page.navigate sent to that painted frame reported back.

The first opening is cold (the browser's caches empty); the median of all is reported. The machine's load (`uptime`)
is printed before and after. Exit status: 0 when the median opening is under the goal (--goal, 2 s), 1 otherwise.

Usage: report_load_benchmark.py [--motionblocks PATH] [--samples N] [--repeats K] [--chromium PATH] [--keep]
"""

import argparse
import json
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "browser"))
import devtools  # noqa: E402

STEP = 0.001  # the run's logging step and solver step [s]
DIAGRAM = ROOT / "diagrams" / "hil" / "pd_rigid_body.json"

# Resolves, once every chart is drawn and a frame painted after that, with the page's clocks [ms since the navigation
# started] and what it drew.
PAINTED = r"""new Promise(resolve => {
  const boxes = Array.from(document.querySelectorAll('.mb-chart'));
  const frame = () => new Promise(r => requestAnimationFrame(() => r()));
  (async () => {
    while (!boxes.every(b => b.mbDygraph || /mb-failed/.test(b.parentNode.className))) await frame();
    await frame(); await frame();
    const nav = performance.getEntriesByType('navigation')[0];
    resolve({open_ms: performance.now(), load_ms: nav.loadEventEnd, dom_ms: nav.domContentLoadedEventEnd,
             charts: boxes.length, rows: boxes.reduce((n, b) => n + (b.mbDygraph ? b.mbDygraph.numRows() : 0), 0),
             blocks: document.querySelectorAll('figure.mb-diagram g.mb-block').length});
  })();
})"""


def default_motionblocks():
    for preset in ("release", "asan"):
        path = ROOT / "build" / preset / "tools" / "motionblocks"
        if os.access(path, os.X_OK):
            return str(path)
    return None


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def make_run(motionblocks, samples, folder):
    """Runs the diagram so that it logs `samples` samples; returns (report path, samples logged, run seconds)."""
    stop = (samples - 1) * STEP
    out = os.path.join(folder, "run")
    command = [motionblocks, "run", str(DIAGRAM), "--set", f"solver.step={STEP}",
               "--set", f"defaultExperiment.stepSize={STEP}", "--set", f"defaultExperiment.stopTime={stop:.3f}",
               "--out", out, "--quiet"]
    print("$ " + " ".join(command))
    started = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.monotonic() - started
    if result.returncode != 0:
        raise SystemExit(f"FAIL: motionblocks run exited {result.returncode}:\n{result.stdout[-3000:]}")
    logged = json.loads(pathlib.Path(out, "summary.json").read_text())["samples"]
    return os.path.join(out, "report.html"), logged, seconds


def open_report(browser, report):
    """Opens `report` in a fresh tab; returns the page's clocks (PAINTED) and the wall time seen from here [ms]."""
    target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    browser.call("Page.enable", {}, session)
    start = len(browser.events)
    sent = time.monotonic()
    browser.call("Page.navigate", {"url": pathlib.Path(report).resolve().as_uri()}, session)
    browser.wait_for_event("Page.loadEventFired", session, start)
    page = browser.evaluate(session, PAINTED)
    page["wall_ms"] = (time.monotonic() - sent) * 1000.0
    browser.call("Target.closeTarget", {"targetId": target})
    return page


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--motionblocks", default=default_motionblocks(),
                        help="the binary (default: build/release/tools/motionblocks, else build/asan/...)")
    parser.add_argument("--samples", type=int, default=1_000_000, help="samples the run logs")
    parser.add_argument("--repeats", type=int, default=5, help="openings of the report, each in a fresh tab")
    parser.add_argument("--goal", type=float, default=2.0, help="the median opening must stay under this [s]")
    parser.add_argument("--chromium", help="the browser (default: Debian's /usr/lib/chromium/chromium, else PATH)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder (its path is printed)")
    args = parser.parse_args()
    if not args.motionblocks:
        raise SystemExit("FAIL: no build/release or build/asan motionblocks; build one or give --motionblocks")
    chromium = devtools.find_chromium(args.chromium)
    if chromium is None:
        raise SystemExit("FAIL: no chromium found; install Debian's chromium (scripts/install-deps.sh does)")

    folder = tempfile.mkdtemp(prefix="mb_report_load_")
    print(f"load before: {uptime()}")
    report, logged, run_seconds = make_run(os.path.abspath(args.motionblocks), args.samples, folder)
    size = os.path.getsize(report)
    print(f"run: {logged} samples logged in {run_seconds:.1f} s; report.html {size / 1e6:.2f} MB "
          f"(signals.csv {os.path.getsize(os.path.join(os.path.dirname(report), 'signals.csv')) / 1e6:.1f} MB)")
    openings = []
    with devtools.Browser(chromium, timeout=120.0) as browser:
        for k in range(args.repeats):
            page = open_report(browser, report)
            openings.append(page)
            print(f"opening {k + 1}{' (cold)' if k == 0 else ''}: painted after {page['open_ms']:.0f} ms "
                  f"(load event {page['load_ms']:.0f} ms, DOM ready {page['dom_ms']:.0f} ms, wall "
                  f"{page['wall_ms']:.0f} ms); {page['charts']} charts, {page['rows']} rows drawn, "
                  f"{page['blocks']} clickable blocks")
    print(f"load after: {uptime()}")
    median = statistics.median(p["open_ms"] for p in openings) / 1000.0
    worst = max(p["open_ms"] for p in openings) / 1000.0
    met = median < args.goal
    print(f"{'OK' if met else 'FAIL'}: a {logged}-sample run's report opens in {median:.2f} s (median of "
          f"{len(openings)}; slowest {worst:.2f} s), goal < {args.goal:g} s")
    if args.keep:
        print(f"kept {folder}")
    else:
        shutil.rmtree(folder, ignore_errors=True)
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
