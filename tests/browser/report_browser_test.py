#!/usr/bin/env python3
"""Each kind of interactive report opens in a real browser without a fault (issue 27, item 8).

What is run: `motionblocks compare` and `motionblocks improve --max-effects 1` on the shipped EMPS data
(diagrams/emps/rigid_body.json, DATA_EMPS.csv, improve validated on DATA_EMPS_PULSES.csv), and `motionblocks sweep` of
a 3 × 2 grid (controller gains, 0.3 s each) over diagrams/hil/pd_rigid_body.json, in a temporary folder;
each report.html is then opened in headless Chromium (Debian's `chromium`; nothing is downloaded) driven through its
DevTools protocol over a pipe (devtools.py), and checked:
  - no uncaught exception, no console.error or console.assert, no error in the browser's log (a file that does not
    load, a blocked script);
  - the charting library loaded, and every chart the report embeds (the JSON in #mb-charts) is drawn: its dygraph
    object exists (the page keeps it as the chart box's `mbDygraph`), holds as many rows as the embedded data (> 0),
    and its box is not marked failed;
  - the charts respond: unticking a series' toggle hides it, and zooming one chart of a linked group moves the others;
  - the diagram's picture is present (inline SVG whose block nodes the page's script made clickable), and its blocks
    respond: a mouse click (a real one, through the protocol's Input domain, at the centre of the block's node) shows
    the panel with that block's name and one row per parameter the report embeds for it, each with its unit; in the
    compare report the block is EMPS's `friction`, whose panel must show viscous in N·s/m and coulomb in N (item 5).
  - every in-page link ("#…") has its target; compare shows an evidence figure (id fig-effect_<k>) per ranked effect
    of compare.json, and improve's step table links to each step after step 0 (ids step-<i>, items 2 and 3).
The checker must be able to fail: the compare report is also loaded in broken copies (one chart's data emptied, a
script that throws, the diagram's picture missing, blocks that no longer answer a click), and each must be caught for
what it is.

Without a browser the test fails and says how to install one, unless MB_NO_BROWSER=1 is set: then it prints why it
skips and exits 77 (CTest's SKIP_RETURN_CODE).

--screenshots DIR also writes DIR/compare-report.png and DIR/improve-report.png (a 1200 × 900 viewport drawn at
960 × 720, each scrolled to where the report shows what fails and what fell): scripts/report_screenshots.py regenerates docs/images/ this way.

Usage: report_browser_test.py --motionblocks BUILD/tools/motionblocks [--source DIR] [--chromium PATH]
           [--timeout SECONDS] [--keep] [--screenshots DIR]
"""

import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import devtools  # noqa: E402

SKIP = 77
# The screenshots: a 1200 × 900 viewport at 0.8 (960 × 720 px, about the width a README shows; under 300 KB each).
SCREENSHOT_SCALE = 0.8
NO_BROWSER_ENV = "MB_NO_BROWSER"

# What the page holds, read in the page (one expression; returns plain JSON).
INSPECT = r"""(() => {
  const json = document.getElementById('mb-charts');
  const specs = json ? JSON.parse(json.textContent) : [];
  const charts = Array.from(document.querySelectorAll('.mb-chart')).map(box => {
    const i = +box.getAttribute('data-chart'), g = box.mbDygraph, spec = specs[i];
    return {index: i, title: spec ? spec.title : null, expected: spec ? spec.data.length : -1,
            rows: g ? g.numRows() : -1, failed: /mb-failed/.test(box.parentNode.className),
            link: spec ? spec.link : '', series: spec ? spec.labels.length - 1 : 0};
  });
  const images = Array.from(document.images).filter(img => getComputedStyle(img).display !== 'none')
      .map(img => ({src: img.getAttribute('src'), complete: img.complete, width: img.naturalWidth}));
  const dangling = Array.from(document.querySelectorAll('a[href^="#"]')).map(a => a.getAttribute('href'))
      .filter(h => !document.getElementById(h.slice(1)));
  return {specs: specs.length, charts: charts, images: images, library: typeof Dygraph,
          diagram_blocks: document.querySelectorAll('figure.mb-diagram svg g.mb-block').length,
          dangling_links: dangling,
          evidence: document.querySelectorAll('[id^="fig-effect_"]').length,
          step_links: document.querySelectorAll('td a[href^="#step-"]').length};
})()"""

# Unticks the first series' toggle of the first chart; returns whether the chart hid that series (and reticks it).
TOGGLE = r"""(() => {
  const box = document.querySelector('.mb-chart'), g = box && box.mbDygraph;
  const tick = box && box.querySelector('.mb-toggles input[type=checkbox]');
  if (!g || !tick) return 'no chart with a toggle';
  tick.click();
  const hidden = g.visibility()[0] === false;
  tick.click();
  return hidden && g.visibility()[0] === true ? 'ok' : 'the toggle did not hide the series';
})()"""

# Zooms the first chart of a linked group to the middle third of its x range; returns the charts of the group that
# did not follow (their titles), or 'no linked group'.
ZOOM = r"""(() => {
  const boxes = Array.from(document.querySelectorAll('.mb-chart')).filter(b => b.mbDygraph && b.mbDygraph.mbLink);
  if (boxes.length < 2) return 'no linked group';
  const first = boxes[0].mbDygraph, r = first.xAxisRange(), w = (r[1] - r[0]) / 3;
  const window_ = [r[0] + w, r[0] + 2 * w];
  first.updateOptions({dateWindow: window_});
  const stuck = boxes.filter(b => b.mbDygraph.mbLink === first.mbLink).filter(b => {
    const q = b.mbDygraph.xAxisRange();
    return Math.abs(q[0] - window_[0]) > 1e-9 * w || Math.abs(q[1] - window_[1]) > 1e-9 * w;
  });
  first.resetZoom();
  return stuck.map(b => b.parentNode.querySelector('.mb-title').textContent);
})()"""

# The centre of the diagram's node of block `name` (scrolled into view first; name null: the first block with a
# parameter that has a unit), in the viewport's CSS pixels, with the block's name and its parameters as the report
# embeds them ([name, unit]); null if there is no such node.
BLOCK_NODE = r"""((name) => {
  const figure = document.querySelector('figure.mb-diagram');
  if (!figure) return null;
  const blocks = JSON.parse(figure.querySelector('script.mb-blocks').textContent);
  const node = Array.from(figure.querySelectorAll('g.mb-block')).find(g => {
    const b = blocks[+g.dataset.block];
    return name === null ? b.parameters.some(p => p.unit) : b.name === name;
  });
  if (!node) return null;
  node.scrollIntoView({block: 'center', inline: 'center'});
  const r = node.getBoundingClientRect(), b = blocks[+node.dataset.block];
  return {x: r.left + r.width / 2, y: r.top + r.height / 2, name: b.name,
          parameters: b.parameters.map(p => [p.name, p.unit])};
})(%s)"""

# What the block panel shows: whether it is visible, its title, and its rows [parameter, value, unit].
PANEL = r"""(() => {
  const panel = document.querySelector('figure.mb-diagram .mb-block-panel');
  if (!panel) return null;
  const title = panel.querySelector('.mb-block-title');
  return {visible: !panel.hidden && panel.offsetHeight > 0, title: title ? title.textContent : '',
          rows: Array.from(panel.querySelectorAll('tr')).slice(1)
              .map(tr => Array.from(tr.cells).map(td => td.textContent))};
})()"""

# The block clicked in the compare report's diagram of EMPS, and parameters its panel must show with these units
# (the friction block's type declares them; the diagram writes viscous as {"value": 200, "unit": "N·s/m"}).
EMPS_BLOCK = "friction"
EMPS_UNITS = {"viscous": "N·s/m", "coulomb": "N"}
NO_UNIT = "1 (no unit)"  # what the panel writes for a dimensionless parameter


def click_block(browser, session, name=None, expected_units=None):
    """Clicks the diagram's node of block `name` (None: the first block with a unit) with the mouse; returns the list
    of what is wrong with the panel it shows (empty: it shows the block's name and every parameter the report
    embeds for it, each with its unit, and `expected_units` {parameter: unit})."""
    node = browser.evaluate(session, BLOCK_NODE % json.dumps(name))
    if node is None:
        return [f"the diagram has no clickable block {name or 'with a unit'}"]
    name = node["name"]
    for kind in ("mousePressed", "mouseReleased"):
        browser.call("Input.dispatchMouseEvent", {"type": kind, "x": node["x"], "y": node["y"], "button": "left",
                                                  "clickCount": 1}, session)
    panel = browser.evaluate(session, PANEL)
    if not panel or not panel["visible"]:
        return [f"clicking block {name!r} showed no panel"]
    problems = []
    if not panel["title"].startswith(name + " "):
        problems.append(f"clicking block {name!r}: the panel is titled {panel['title']!r}")
    shown = [(row[0], row[2]) for row in panel["rows"] if len(row) == 3]
    embedded = [(p, u or NO_UNIT) for p, u in node["parameters"]]
    if shown != embedded:
        problems.append(f"clicking block {name!r}: the panel shows {shown}, the report embeds {embedded}")
    units = dict(shown)
    for parameter, unit in (expected_units or {}).items():
        if units.get(parameter) != unit:
            problems.append(f"clicking block {name!r}: parameter {parameter} shown with unit "
                            f"{units.get(parameter)!r}, expected {unit!r}")
    return problems


# Scrolls to the first heading containing the text; returns whether there was one.
SCROLL_TO = r"""((words) => {
  const h = Array.from(document.querySelectorAll('h2')).find(e => e.textContent.includes(words));
  if (h) h.scrollIntoView();
  return !!h;
})(%s)"""


def check_page(browser, path, diagram_expected=True, linked_expected=True, click=(EMPS_BLOCK, EMPS_UNITS)):
    """Loads `path` and returns the list of what is wrong with it (empty: nothing) and what it holds. A sweep's report
    has neither a diagram nor linked time charts (diagram_expected, linked_expected False). `click`: the block clicked
    in the diagram and the units its panel must show (click_block's arguments)."""
    session = browser.open_page(pathlib.Path(path).resolve().as_uri())
    page = browser.evaluate(session, INSPECT)
    problems = list(browser.page_errors(session))
    if page["library"] != "function":
        problems.append("the charting library (Dygraph) is not loaded")
    if page["specs"] == 0:
        problems.append("the report embeds no chart")
    if len(page["charts"]) != page["specs"]:
        problems.append(f"{page['specs']} charts embedded but {len(page['charts'])} chart boxes on the page")
    for c in page["charts"]:
        name = f"chart {c['index']} ({c['title']!r})"
        if c["failed"]:
            problems.append(f"{name} failed and fell back to its PNG")
        if c["rows"] < 0:
            problems.append(f"{name} has no dygraph object")
        elif c["rows"] == 0 or c["rows"] != c["expected"]:
            problems.append(f"{name} holds {c['rows']} rows, the report embeds {c['expected']}")
    if not problems:  # interaction only on a page whose charts are drawn
        toggled = browser.evaluate(session, TOGGLE)
        if toggled != "ok":
            problems.append(f"series toggle: {toggled}")
        stuck = browser.evaluate(session, ZOOM)
        if stuck == "no linked group":
            if linked_expected:
                problems.append("no linked group of time charts")
        elif stuck:
            problems.append(f"zooming one time chart did not move the linked ones: {', '.join(stuck)}")
    for link in page["dangling_links"]:
        problems.append(f"link {link} goes nowhere")
    for img in page["images"]:
        if not img["complete"] or img["width"] == 0:
            problems.append(f"image {img['src']} did not load")
    if diagram_expected:
        if page["diagram_blocks"] == 0:
            problems.append("no picture of the diagram (no clickable block in an inline SVG)")
        else:
            problems += click_block(browser, session, *click)
    return problems, page, session


# The sweep whose report is opened: a grid of two parameters (so it has heat maps), short runs (a few seconds in all).
SWEEP = {"description": "browser test: PD gains", "set": {"defaultExperiment.stopTime": 0.3},
         "grid": {"controller.kd": [50, 69, 90], "controller.kp": [6000, 9300]}}


def make_reports(motionblocks, source, folder, timeout):
    """Runs compare, improve and a small sweep side by side (2 cores: ~55 s under ASan instead of ~90 s); returns
    their reports."""
    sweep = os.path.join(folder, "sweep.json")
    pathlib.Path(sweep).write_text(json.dumps(SWEEP), encoding="utf-8")
    emps = os.path.join(source, "diagrams", "emps")
    diagram = os.path.join(emps, "rigid_body.json")
    data = os.path.join(emps, "data", "DATA_EMPS.csv")
    pulses = os.path.join(emps, "data", "DATA_EMPS_PULSES.csv")
    jobs = {
        "compare": [motionblocks, "compare", diagram, "--measurement", data, "--out",
                    os.path.join(folder, "compare"), "--quiet"],
        "improve": [motionblocks, "improve", diagram, "--measurement", data, "--validation", pulses,
                    "--max-effects", "1", "--out", os.path.join(folder, "improve"), "--quiet"],
        "sweep": [motionblocks, "sweep", os.path.join(source, "diagrams", "hil", "pd_rigid_body.json"), sweep,
                  "--jobs", "1", "--out", os.path.join(folder, "sweep"), "--quiet"],
    }
    started = time.monotonic()
    running = {name: subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
               for name, cmd in jobs.items()}
    failures = []
    for name, process in running.items():
        try:
            output, _ = process.communicate(timeout=max(1.0, timeout - (time.monotonic() - started)))
        except subprocess.TimeoutExpired:
            process.kill()  # the child this test started
            output, _ = process.communicate()
            failures.append(f"{name} ran over {timeout:.0f} s")
            continue
        if process.returncode != 0:
            failures.append(f"{name} exited {process.returncode}:\n{output.decode('utf-8', 'replace')[-3000:]}")
    if failures:
        raise SystemExit("FAIL: " + "\n".join(failures))
    print(f"compare and improve of EMPS, a sweep of 6 runs: {time.monotonic() - started:.1f} s")
    return {name: os.path.join(folder, name, "report.html") for name in jobs}


def broken_copies(report, folder):
    """Copies of `report` (in its own folder, so its pictures resolve) each broken in one way, with the words the
    checker must say about it."""
    text = pathlib.Path(report).read_text(encoding="utf-8")
    start_tag = '<script type="application/json" id="mb-charts">'
    begin = text.index(start_tag) + len(start_tag)
    end = text.index("</script>", begin)
    specs = json.loads(text[begin:end])
    specs[0]["data"] = []
    empty_chart = text[:begin] + json.dumps(specs).replace("<", "\\u003c") + text[end:]
    throwing = text.replace("</body>", "<script>window.mbNoSuchFunction();</script></body>")
    svg_begin = text.find('<div class="mb-diagram-svg">')
    svg_end = text.find("</svg>", svg_begin)
    dead_blocks = text.replace("node.addEventListener('click'", "node.addEventListener('dblclick'")
    if svg_begin < 0 or svg_end < 0 or dead_blocks == text:
        raise SystemExit("FAIL: the compare report shows no clickable diagram to break")
    no_diagram = text[:svg_begin] + text[svg_end + len("</svg>"):]
    cases = {"broken_empty_chart.html": (empty_chart, "chart 0 "),
             "broken_throws.html": (throwing, "uncaught exception"),
             "broken_no_diagram.html": (no_diagram, "no picture of the diagram"),
             "broken_dead_blocks.html": (dead_blocks, f"clicking block {EMPS_BLOCK!r} showed no panel")}
    out = []
    for name, (html, expected) in cases.items():
        path = os.path.join(os.path.dirname(report), name)
        pathlib.Path(path).write_text(html, encoding="utf-8")
        out.append((path, expected))
    return out


def screenshot(browser, report, headings, path):
    """`report` at 1200 × 900, scrolled to the first of `headings` it has (else its top), written to `path`."""
    session = browser.open_page(pathlib.Path(report).resolve().as_uri())
    for words in headings:
        if browser.evaluate(session, SCROLL_TO % json.dumps(words)):
            break
    time.sleep(0.3)  # one frame after the scroll
    browser.screenshot(session, path, scale=SCREENSHOT_SCALE)
    print(f"screenshot: {path} ({os.path.getsize(path) // 1024} KiB)")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--motionblocks", required=True)
    parser.add_argument("--source", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    parser.add_argument("--chromium", help="the browser (default: Debian's /usr/lib/chromium/chromium, else PATH)")
    parser.add_argument("--timeout", type=float, default=300.0, help="for each command and browser wait [s]")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder (its path is printed)")
    parser.add_argument("--screenshots", help="also write compare-report.png and improve-report.png here")
    args = parser.parse_args()

    chromium = devtools.find_chromium(args.chromium)
    if chromium is None:
        if os.environ.get(NO_BROWSER_ENV) == "1":
            print(f"SKIPPED: no chromium found, and {NO_BROWSER_ENV}=1 says to skip the browser test")
            return SKIP
        where = (f"{args.chromium} is no executable" if args.chromium
                 else f"neither {devtools.DEBIAN_CHROMIUM} nor chromium on PATH")
        print(f"FAIL: no chromium found ({where}). Install Debian's chromium (scripts/install-deps.sh does), or set "
              f"{NO_BROWSER_ENV}=1 to skip this test.")
        return 1

    folder = tempfile.mkdtemp(prefix="mb_report_browser_")
    if args.keep:
        print(f"keeping {folder}")
    reports = make_reports(os.path.abspath(args.motionblocks), os.path.abspath(args.source), folder, args.timeout)
    failed = []
    with devtools.Browser(chromium, timeout=args.timeout) as browser:
        for kind, report in reports.items():
            # compare draws EMPS as given; improve's diagram may have its friction replaced: any block with a unit
            problems, page, session = check_page(browser, report, diagram_expected=kind != "sweep",
                                                 linked_expected=kind != "sweep",
                                                 click=(EMPS_BLOCK, EMPS_UNITS) if kind == "compare" else ())
            rows = sum(c["rows"] for c in page["charts"] if c["rows"] > 0)
            print(f"{kind} report: {len(page['charts'])} charts, {rows} rows drawn, {len(page['images'])} images"
                  f"{'' if not problems else ': ' + str(len(problems)) + ' problems'}")
            if kind == "compare":  # every ranked effect with its evidence plot
                effects = len(json.loads(pathlib.Path(report).with_name("compare.json").read_text())["diagnosis"])
                if page["evidence"] != effects:
                    problems.append(f"{effects} ranked effects but {page['evidence']} evidence figures")
            if kind == "improve":  # the step table links to each step after step 0
                steps = len(json.loads(pathlib.Path(report).with_name("improve.json").read_text())["steps"])
                if page["step_links"] != steps - 1:
                    problems.append(f"{steps} steps but {page['step_links']} links to a step's plots")
            if kind == "sweep":  # a grid of two parameters: a heat map per metric of runs.json
                metrics = len(json.loads(pathlib.Path(report).with_name("runs.json").read_text())["metric_units"])
                heat_maps = browser.evaluate(session, "document.querySelectorAll('table.mb-heatmap').length")
                if heat_maps != metrics:
                    problems.append(f"{metrics} metrics but {heat_maps} heat maps")
            for p in problems:
                print(f"  {kind}: {p}")
            failed += [f"{kind}: {p}" for p in problems]
        for path, expected in broken_copies(reports["compare"], folder):
            problems, _, _ = check_page(browser, path)
            caught = [p for p in problems if expected in p]
            print(f"{os.path.basename(path)}: {'caught' if caught else 'NOT caught'} ({'; '.join(problems)[:300]})")
            if not caught:
                failed.append(f"the checker missed {os.path.basename(path)} (expected a problem naming {expected!r})")
        if args.screenshots:
            os.makedirs(args.screenshots, exist_ok=True)
            screenshot(browser, reports["compare"], ["Where the model fails"],
                       os.path.join(args.screenshots, "compare-report.png"))
            screenshot(browser, reports["improve"], ["Before (step 0", "RMSE per step"],
                       os.path.join(args.screenshots, "improve-report.png"))
    if not args.keep:
        shutil.rmtree(folder, ignore_errors=True)
    if failed:
        print("FAIL:\n  " + "\n  ".join(failed))
        return 1
    print("OK: every report loads without an error, every chart holds its data and responds, the diagram is shown and "
          "a click on a block shows its parameters with their units")
    return 0


if __name__ == "__main__":
    sys.exit(main())
