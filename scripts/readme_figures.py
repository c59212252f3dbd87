#!/usr/bin/env python3
"""Regenerates the figures README.md quotes from runs, and checks them (issue 28, item 1).

    python3 scripts/readme_figures.py --motionblocks build/release/tools/motionblocks           # rewrites README.md
    python3 scripts/readme_figures.py --motionblocks build/release/tools/motionblocks --check   # only compares

What is run (from the repository root, into a temporary folder, never into out/; no shell):
  - the demo's compare steps 1-4, parsed from scripts/demo.sh as it is written ("$BIN" compare ... --out
    "$OUT/1_base" etc., $OUT standing for the temporary folder);
  - the README's own commands behind the other figures, taken from its ```sh blocks by their --out folder:
    improve (out/improve), the ODrive compare (out/odrive), the closed loop (out/cl), stability (out/stab) and
    reproduce (out/reproduce), the --out folder replaced by one in the temporary folder.
Each writes its JSON record (compare.json, improve.json, stability.json, results.json); the figures are read there.

Where the figures are: README.md holds regions between HTML comments, invisible in the rendered page,
    <!-- readme-figures:begin NAME -->
    ... hand-written Markdown with numbers in it ...
    <!-- readme-figures:end NAME -->
FIGURES below gives, per region, the README's words around each number ("M = {} kg", "{}" a number, "{w}" a word,
any whitespace matching any whitespace, so rewrapping the README does not matter) and where the run gives it. Only
the numbers are rewritten, each at the precision the README writes it (2.503 stays three decimals); the words are
the README's. A reworded sentence that no longer matches its pattern is an error naming it: update FIGURES with it.
The Python repr line (region python) is step 1's compare.json: mb.compare on the same diagram and record is the
same computation (python/tests/test_workflow.py checks the repr itself).

The picture of a report (region report-picture): the compare report's static figures (gnuplot PNGs, what
report.html shows without script) of demo step 1, copied to docs/images/ (PICTURES below). --check does not compare
PNG bytes (gnuplot versions draw differently): it checks that the README shows each picture, that the file is a PNG
and that the run still draws that figure, as a PNG of the same size.

Not checked, because no run gives them: durations ("about 30 s on 2 cores"), the minimal diagram's F/B = 0.5 m/s
(arithmetic), the number of hidden-effect cases (make bench-diagnosis). The paper's Table 2 values in brackets are
checked against reproduce's results.json, which holds them.

Modes: by default README.md (or --readme PATH) is rewritten in place and the pictures copied beside it under
docs/images/; --check changes nothing and exits 1 listing every figure that drifted (README.md:LINE, what it says,
what the run gives), 0 when all agree. Exit 2: a run failed, or the README lacks a region or a pattern.
The ctest readme_figures runs --check with the build's binary; tests/readme/readme_figures_test.py (ctest
readme_figures_script) checks that a drifted figure is caught, with a stand-in for motionblocks.

Usage: readme_figures.py [--motionblocks BINARY] [--check] [--readme PATH] [--root DIR] [--jobs N] [--keep]
"""

import argparse
import concurrent.futures
import json
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MOTIONBLOCKS_PATH = "build/release/tools/motionblocks"


# -- The runs -------------------------------------------------------------------------------------------------------

class Run:
    """One motionblocks command. argv[0] is the binary; `record` the JSON file it writes in its --out folder."""

    def __init__(self, name, what, argv, out, record, after=()):
        self.name, self.what, self.argv, self.out, self.record, self.after = name, what, argv, out, record, after


# The demo's compare steps, by their --out folder in scripts/demo.sh; each waits for the runs it reads the output of.
DEMO_STEPS = [
    ("demo1", "1_base", ()),
    ("demo2", "2_suggested", ("demo1",)),
    ("demo3", "3_validate_base", ("demo1",)),
    ("demo4", "4_validate_suggested", ("demo2",)),
]
# The README's commands, by their --out folder, and the record each writes.
README_RUNS = [
    ("reproduce", "out/reproduce", "results.json"),
    ("closed_loop", "out/cl", "compare.json"),
    ("improve", "out/improve", "improve.json"),
    ("odrive", "out/odrive", "compare.json"),
    ("brfd", "out/brfd", "compare.json"),
    ("stability", "out/stab", "stability.json"),
]


def joined_lines(lines):
    """(first line number, text) of each logical line: a line ending in a backslash continues on the next."""
    out, pending, start = [], "", 0
    for number, line in enumerate(lines, start=1):
        if not pending:
            start = number
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        out.append((start, pending + line))
        pending = ""
    return out


def demo_runs(root, binary, work):
    """Steps 1-4 of scripts/demo.sh as it is written, $OUT the work folder."""
    path = os.path.join(root, "scripts", "demo.sh")
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    variables = {"BIN": binary, "OUT": work}
    for line in lines:
        assigned = re.match(r"^(DATA)=(\S+)$", line.strip())
        if assigned:
            variables[assigned.group(1)] = assigned.group(2)
    commands = {}
    for number, text in joined_lines(lines):
        if not text.strip().startswith('"$BIN"'):
            continue
        words = [re.sub(r"\$\{?(\w+)\}?", lambda m: variables.get(m.group(1), m.group(0)), word)
                 for word in shlex.split(text, comments=True)]
        if "--out" in words[:-1]:
            commands[os.path.relpath(words[words.index("--out") + 1], work)] = (number, words)
    runs = []
    for name, folder, after in DEMO_STEPS:
        if folder not in commands:
            raise SetupError(f"scripts/demo.sh: no \"$BIN\" command with --out \"$OUT/{folder}\" "
                             f"(demo step {name[-1]})")
        number, words = commands[folder]
        runs.append(Run(name, f"demo step {name[-1]} (scripts/demo.sh:{number})", words,
                        os.path.join(work, folder), "compare.json", after))
    return runs


def readme_runs(readme_text, binary, work):
    """The README's ```sh commands behind the figures, found by their --out folder, writing into `work`."""
    commands = {}
    in_sh = False
    block = []
    for number, line in enumerate(readme_text.splitlines(), start=1):
        fence = re.match(r"^\s*```(\w*)\s*$", line)
        if fence:
            if in_sh:
                for start, text in joined_lines([l for _, l in block]):
                    first = block[start - 1][0]
                    words = shlex.split(text, comments=True)
                    if words and words[0] == MOTIONBLOCKS_PATH and "--out" in words[:-1]:
                        commands[words[words.index("--out") + 1]] = (first, words)
                in_sh = False
            else:
                in_sh, block = fence.group(1) == "sh", []
            continue
        if in_sh:
            block.append((number, line))
    runs = []
    for name, out, record in README_RUNS:
        if out not in commands:
            raise SetupError(f"README.md: no ```sh command `{MOTIONBLOCKS_PATH} ... --out {out}` (the {name} figures)")
        number, words = commands[out]
        folder = os.path.join(work, name)
        words = [binary] + words[1:]
        words[words.index("--out") + 1] = folder
        runs.append(Run(name, f"{words[1]} (README.md:{number})", words, folder, record))
    return runs


def run_all(runs, root, jobs, log):
    """Runs every command (at most `jobs` at once, each after those it reads); returns {name: its JSON record}."""
    env = dict(os.environ, MOTIONBLOCKS_DATA=root)
    futures = {}
    lock = threading.Lock()

    def one(run):
        for name in run.after:
            futures[name].result()  # raises if it failed
        started = time.monotonic()
        process = subprocess.run(run.argv, cwd=root, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, check=False)
        with lock:
            log(f"  {run.what}: exit {process.returncode}, {time.monotonic() - started:.0f} s")
        if process.returncode != 0:
            tail = "\n".join(process.stdout.decode(errors="replace").splitlines()[-15:])
            raise SetupError(f"{run.what} failed (exit {process.returncode}): {shlex.join(run.argv)}\n{tail}")
        with open(os.path.join(run.out, run.record), encoding="utf-8") as f:
            return json.load(f)

    # Submitted in an order where every run comes after those it waits for: a run only starts once all earlier
    # ones have, so a waiting run never waits on one that cannot start.
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for run in runs:
            futures[run.name] = pool.submit(one, run)
        return {name: future.result() for name, future in futures.items()}


# -- The figures ----------------------------------------------------------------------------------------------------

def parameter(record, name, field="estimate"):
    for p in record["fit"]["parameters"]:
        if p["name"] == name:
            return p[field]
    raise KeyError(f"no fitted parameter {name}")


def step(record, effect):
    for s in record["steps"]:
        if s["effect"] == effect and s["accepted"]:
            return s
    raise KeyError(f"no accepted improve step {effect}")


def percent(r, run, when):
    return r[run][f"fit_percent_{when}"]


class Figure:
    """A pattern in a region ("{}" a number, "{w}" a word) and, per hole, (what it is, its value from the records)."""

    def __init__(self, region, pattern, *holes):
        self.region, self.pattern, self.holes = region, pattern, holes


mm, um = 1e3, 1e6
FIGURES = [
    # The demo's table (steps 1-4 of scripts/demo.sh).
    Figure("demo-table", "| 1. the benchmark's model as written (M = {} kg, viscous {} N·s/m, Coulomb {} N), "
                         "on `DATA_EMPS` | {} N ({} %) |",
           ("step 1: M as written [kg]", lambda r: parameter(r["demo1"], "inertia.gain", "initial")),
           ("step 1: viscous friction as written [N·s/m]",
            lambda r: parameter(r["demo1"], "friction.viscous", "initial")),
           ("step 1: Coulomb friction as written [N]", lambda r: parameter(r["demo1"], "friction.coulomb", "initial")),
           ("step 1: force RMSE as written [N]", lambda r: r["demo1"]["rmse_before"]),
           ("step 1: fit as written [%]", lambda r: percent(r, "demo1", "before"))),
    Figure("demo-table", "| 1. refit (M = {} kg, {} N·s/m, {} N, offset {} N) | {} N ({} %) |",
           ("step 1: M refit [kg]", lambda r: parameter(r["demo1"], "inertia.gain")),
           ("step 1: viscous friction refit [N·s/m]", lambda r: parameter(r["demo1"], "friction.viscous")),
           ("step 1: Coulomb friction refit [N]", lambda r: parameter(r["demo1"], "friction.coulomb")),
           ("step 1: force offset refit [N]", lambda r: parameter(r["demo1"], "offset.value")),
           ("step 1: force RMSE refit [N]", lambda r: r["demo1"]["rmse_after"]),
           ("step 1: fit refit [%]", lambda r: percent(r, "demo1", "after"))),
    Figure("demo-table", "| 2. with the suggested `{w}` at {} mm (the screw lead), refit jointly | {} N ({} %) |",
           ("step 1: the suggested effect", lambda r: r["demo1"]["suggested_diagram"]["effect"]),
           ("step 1: the suggested effect's period [mm]",
            lambda r: r["demo1"]["diagnosis"][0]["parameters"]["period"] * mm),
           ("step 2: force RMSE refit [N]", lambda r: r["demo2"]["rmse_after"]),
           ("step 2: fit refit [%]", lambda r: percent(r, "demo2", "after"))),
    Figure("demo-table", "| 3. held-out record `DATA_EMPS_PULSES`, the refit model, nothing refit | {} N ({} %) |",
           ("step 3: force RMSE [N]", lambda r: r["demo3"]["rmse_after"]),
           ("step 3: fit [%]", lambda r: percent(r, "demo3", "after"))),
    Figure("demo-table", "| 4. held-out record, with the ripple (only its position offset, the encoder's zero, refit) "
                         "| {} N ({} %) |",
           ("step 4: force RMSE [N]", lambda r: r["demo4"]["rmse_after"]),
           ("step 4: fit [%]", lambda r: percent(r, "demo4", "after"))),
    # The picture's caption.
    Figure("report-picture", "peak at {} mm",
           ("step 1: the strongest position-periodogram peak [mm]",
            lambda r: r["demo1"]["details"]["position_peaks"][0]["period"] * mm)),
    # improve on EMPS (README, "Compare a model with a measurement, and improve it").
    Figure("improve", "(period refit to {} ± {} mm; fit {} → {} N, held out {} → {} N)",
           ("improve: the ripple's period refit [mm]",
            lambda r: parameter(step(r["improve"], "velocity_dependent_ripple"), "ripple.period") * mm),
           ("improve: its standard error [mm]",
            lambda r: parameter(step(r["improve"], "velocity_dependent_ripple"), "ripple.period",
                                "standard_error") * mm),
           ("improve: train RMSE before the ripple [N]",
            lambda r: step(r["improve"], "velocity_dependent_ripple")["rmse"]["train_before"]),
           ("improve: train RMSE with the ripple [N]",
            lambda r: step(r["improve"], "velocity_dependent_ripple")["rmse"]["train"]),
           ("improve: held-out RMSE before the ripple [N]",
            lambda r: step(r["improve"], "velocity_dependent_ripple")["rmse"]["heldout_before"]),
           ("improve: held-out RMSE with the ripple [N]",
            lambda r: step(r["improve"], "velocity_dependent_ripple")["rmse"]["heldout"])),
    # The ODrive motor's cogging.
    Figure("odrive", "a position period of {} rev: {} cycles per revolution",
           ("odrive: the top effect's period [rev]", lambda r: r["odrive"]["diagnosis"][0]["parameters"]["period"]),
           ("odrive: cycles per revolution", lambda r: 1.0 / r["odrive"]["diagnosis"][0]["parameters"]["period"])),
    # The closed loop in simulation mode.
    Figure("closed-loop", "within {} µm RMS as written and {} µm after the refit",
           ("closed loop: position RMSE as written [µm]", lambda r: r["closed_loop"]["rmse_before"] * um),
           ("closed loop: position RMSE refit [µm]", lambda r: r["closed_loop"]["rmse_after"] * um)),
    Figure("closed-loop", "the model's tracking error r − ŷ fits the measured one {} % → {} %",
           ("closed loop: tracking-error fit as written [%]",
            lambda r: r["closed_loop"]["outputs"][0]["tracking_fit_percent_before"]),
           ("closed loop: tracking-error fit refit [%]",
            lambda r: r["closed_loop"]["outputs"][0]["tracking_fit_percent_after"])),
    # The friction damper's hysteresis (a real record).
    Figure("brfd", "names `{w}` first ({} % of the held-out residual), the force settling {} mm after each reversal;",
           ("brfd: the first effect", lambda r: r["brfd"]["diagnosis"][0]["effect"]),
           ("brfd: its held-out share [%]", lambda r: 100.0 * r["brfd"]["diagnosis"][0]["score"]),
           ("brfd: the stroke [mm]", lambda r: r["brfd"]["diagnosis"][0]["parameters"]["stroke"] * mm)),
    Figure("brfd", "the held-out force error falls from {} N to {} N",
           ("brfd: held-out RMSE, base refit [N]", lambda r: r["brfd"]["details"]["heldout_rmse_base"]),
           ("brfd: held-out RMSE, with the effects [N]",
            lambda r: r["brfd"]["details"]["heldout_rmse_after"])),
    # stability's verdict.
    Figure("stability", "ρ = {} < 1 at α = {} (small gain, DOB loop closed); the largest certified α: α < {}",
           ("stability: ρ", lambda r: r["stability"]["dob"]["rho"]),
           ("stability: α used", lambda r: r["stability"]["verdict"]["alpha_used"]),
           ("stability: the largest certified α", lambda r: r["stability"]["verdict"]["alpha_max"])),
    # reproduce (the full run): Table 2, the payload, PS on the smoothed estimate.
    Figure("reproduce", "| Table 2 | {} ({}) | {} ({}) | {} ({}) |",
           ("reproduce: Table 2 conventional [µm]", lambda r: r["reproduce"]["table2"]["conventional"]),
           ("reproduce: Table 2 conventional, the paper [µm]",
            lambda r: r["reproduce"]["paper"]["table2"]["conventional"]),
           ("reproduce: Table 2 DS [µm]", lambda r: r["reproduce"]["table2"]["DS"]),
           ("reproduce: Table 2 DS, the paper [µm]", lambda r: r["reproduce"]["paper"]["table2"]["DS"]),
           ("reproduce: Table 2 PS [µm]", lambda r: r["reproduce"]["table2"]["PS"]),
           ("reproduce: Table 2 PS, the paper [µm]", lambda r: r["reproduce"]["paper"]["table2"]["PS"])),
    Figure("reproduce", "| payload {} kg (moving mass doubled), not retrained | {} | {} | {} |",
           ("reproduce: the payload [kg]", lambda r: r["reproduce"]["payload"]["payload_mass_kg"]),
           ("reproduce: payload, conventional [µm]", lambda r: r["reproduce"]["payload"]["conventional"]),
           ("reproduce: payload, DS [µm]", lambda r: r["reproduce"]["payload"]["DS"]),
           ("reproduce: payload, PS [µm]", lambda r: r["reproduce"]["payload"]["PS"])),
    Figure("reproduce", "(PS trained on a zero-phase smoothed disturbance estimate: {} µm)",
           ("reproduce: Table 2, PS trained on the smoothed estimate [µm]",
            lambda r: r["reproduce"]["table2"]["ps_trained_on_smoothed_estimate"])),
    # The Python session's repr of mb.compare on EMPS: demo step 1's compare.
    Figure("python", "# <CompareOutcome {w}: RMSE {} → {} N, fit {} % → {} %, top effect {w}>",
           ("python: the compared column", lambda r: r["demo1"]["outputs"][0]["column"]),
           ("python: force RMSE as written [N]", lambda r: r["demo1"]["rmse_before"]),
           ("python: force RMSE refit [N]", lambda r: r["demo1"]["rmse_after"]),
           ("python: fit as written [%]", lambda r: percent(r, "demo1", "before")),
           ("python: fit refit [%]", lambda r: percent(r, "demo1", "after")),
           ("python: the top effect", lambda r: r["demo1"]["diagnosis"][0]["effect"])),
]


class Picture:
    """A figure of a run's report (a gnuplot PNG in its --out folder) shown in the README as `image`."""

    def __init__(self, region, image, run, source):
        self.region, self.image, self.run, self.source = region, image, run, source


PICTURES = [
    Picture("report-picture", "docs/images/emps_compare_model_vs_measurement.png", "demo1", "model_vs_measurement.png"),
    Picture("report-picture", "docs/images/emps_compare_position_periodogram.png", "demo1", "position_periodogram.png"),
]


# -- The README -----------------------------------------------------------------------------------------------------

class SetupError(Exception):
    """Something that keeps the figures from being checked at all (exit 2)."""


BEGIN = re.compile(r"<!-- readme-figures:begin ([\w-]+) -->")
END = re.compile(r"<!-- readme-figures:end ([\w-]+) -->")
NUMBER = r"([−-]?\d+(?:\.\d+)?)"
WORD = r"([A-Za-z_][A-Za-z0-9_]*)"


def regions(text):
    """{name: (start, end)}: the text offsets between each region's markers."""
    found, open_name, open_at = {}, None, 0
    for marker in sorted(list(BEGIN.finditer(text)) + list(END.finditer(text)), key=lambda m: m.start()):
        line = text.count("\n", 0, marker.start()) + 1
        name = marker.group(1)
        if marker.re is BEGIN:
            if open_name:
                raise SetupError(f"README.md:{line}: region {name} begins inside region {open_name}")
            if name in found:
                raise SetupError(f"README.md:{line}: a second region {name}")
            open_name, open_at = name, marker.end()
        else:
            if name != open_name:
                raise SetupError(f"README.md:{line}: the end of region {name}, but {open_name or 'none'} is open")
            found[name] = (open_at, marker.start())
            open_name = None
    if open_name:
        raise SetupError(f"README.md: region {open_name} has no end marker")
    return found


def pattern_regex(pattern):
    """A figure's pattern as a regular expression: holes captured, any whitespace matching any whitespace."""
    parts = re.split(r"(\{\}|\{w\})", pattern)
    regex = ""
    for part in parts:
        if part == "{}":
            regex += NUMBER
        elif part == "{w}":
            regex += WORD
        else:
            regex += r"\s+".join(re.escape(piece) for piece in re.split(r"\s+", part))
    return re.compile(regex)


class Found:
    """A figure's hole in the README: where, what it says, what it is."""

    def __init__(self, start, end, text, label, getter, line):
        self.start, self.end, self.text, self.label, self.getter, self.line = start, end, text, label, getter, line


def locate(text, figures=None):
    """Every hole of every figure in `text` (a README); SetupError when a region or a pattern is not there."""
    figures = FIGURES if figures is None else figures
    spans = regions(text)
    known = {f.region for f in figures} | {p.region for p in PICTURES}
    for name in spans:
        if name not in known:
            raise SetupError(f"README.md: region {name} is not one of scripts/readme_figures.py's "
                             f"({', '.join(sorted(known))})")
    found = []
    for figure in figures:
        if figure.region not in spans:
            raise SetupError(f"README.md has no region {figure.region} "
                             f"(<!-- readme-figures:begin {figure.region} --> … "
                             f"<!-- readme-figures:end {figure.region} -->)")
        start, end = spans[figure.region]
        matches = list(pattern_regex(figure.pattern).finditer(text, start, end))
        if len(matches) != 1:
            line = text.count("\n", 0, start) + 1
            raise SetupError(f"README.md:{line}: region {figure.region} holds {len(matches)} matches of the pattern "
                             f"\"{figure.pattern}\", not one; reworded? update FIGURES in scripts/readme_figures.py")
        match = matches[0]
        if len(figure.holes) != len(match.groups()):
            raise SetupError(f"scripts/readme_figures.py: \"{figure.pattern}\" has {len(match.groups())} holes "
                             f"and {len(figure.holes)} values")
        for index, (label, getter) in enumerate(figure.holes, start=1):
            line = text.count("\n", 0, match.start(index)) + 1
            found.append(Found(match.start(index), match.end(index), match.group(index), label, getter, line))
    return found


def formatted(value, as_written):
    """`value` written as the README writes `as_written`: a word as is; a number with as many decimals, and the
    README's minus sign (U+2212 unless it wrote '-')."""
    if isinstance(value, str):
        return value
    decimals = len(as_written.split(".")[1]) if "." in as_written else 0
    text = f"{value:.{decimals}f}"
    if re.fullmatch(r"-0\.?0*", text):  # a value rounding to zero is written without a sign
        text = text[1:]
    return text.replace("-", "-" if as_written.startswith("-") else "−")


def compare(text, records, figures=None):
    """[(Found, what the run gives written as the README writes it)] for every hole of every figure."""
    out = []
    for found in locate(text, figures):
        try:
            value = found.getter(records)
        except (KeyError, IndexError, TypeError) as error:
            raise SetupError(f"README.md:{found.line}: {found.label}: not in the run's record ({error!r})")
        out.append((found, formatted(value, found.text), value))
    return out


def rewritten(text, compared):
    """`text` with every hole set to what the run gives."""
    for found, new, _ in sorted(compared, key=lambda c: c[0].start, reverse=True):
        text = text[:found.start] + new + text[found.end:]
    return text


def drifted(compared):
    """The holes whose README text differs from the run's value at the README's precision."""
    return [(found, new, value) for found, new, value in compared
            if found.text.replace("−", "-") != new.replace("−", "-")]


def png_size(path):
    """(width, height) of a PNG file; ValueError if it is not one."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError("not a PNG file")
    return struct.unpack(">II", head[16:24])


def picture_problems(text, readme_dir, work_outs, check):
    """Copies each picture from its run (unless `check`); returns what is wrong with the pictures."""
    spans = regions(text)
    problems = []
    for picture in PICTURES:
        shown = picture.region in spans and re.search(
            r"\]\(" + re.escape(picture.image) + r"\)", text[spans[picture.region][0]:spans[picture.region][1]])
        if not shown:
            problems.append(f"README.md: region {picture.region} does not show {picture.image} "
                            f"(![…]({picture.image}))")
        source = os.path.join(work_outs[picture.run], picture.source)
        target = os.path.join(readme_dir, picture.image)
        try:
            drawn = png_size(source)
        except (OSError, ValueError) as error:
            problems.append(f"{picture.image}: the run ({picture.run}) drew no {picture.source} ({error}; is gnuplot "
                            f"installed? scripts/install-deps.sh)")
            continue
        if not check:
            os.makedirs(os.path.dirname(target), exist_ok=True)
            shutil.copyfile(source, target)
        try:
            shown_size = png_size(target)
        except (OSError, ValueError) as error:
            problems.append(f"{picture.image}: {error}; the run draws {picture.source} ({drawn[0]}×{drawn[1]}): "
                            f"regenerate without --check")
            continue
        if shown_size != drawn:
            problems.append(f"{picture.image} is {shown_size[0]}×{shown_size[1]} px, the run draws {picture.source} "
                            f"at {drawn[0]}×{drawn[1]}: regenerate without --check")
    return problems


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionblocks", default=MOTIONBLOCKS_PATH,
                        help=f"the motionblocks binary (default: {MOTIONBLOCKS_PATH}, from the current folder)")
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 listing the drifted figures")
    parser.add_argument("--readme", default="", help="the README to check or rewrite (default: ROOT/README.md); "
                                                     "its pictures are beside it (docs/images/)")
    parser.add_argument("--root", default=ROOT, help="the repository the commands run in (default: this script's)")
    parser.add_argument("--jobs", type=int, default=2, help="commands run at once (default 2)")
    parser.add_argument("--keep", action="store_true", help="keep the runs' folder (its path is printed)")
    args = parser.parse_args(argv)

    def log(message):
        print(message, flush=True)

    binary = os.path.abspath(args.motionblocks)
    if not os.access(binary, os.X_OK):
        print(f"{args.motionblocks}: no such executable (build it: cmake --preset release && cmake --build --preset "
              f"release, or give --motionblocks)", file=sys.stderr)
        return 2
    root = os.path.abspath(args.root)
    readme = os.path.abspath(args.readme or os.path.join(root, "README.md"))
    with open(readme, encoding="utf-8") as f:
        text = f.read()
    work = tempfile.mkdtemp(prefix="mb_readme_figures_")
    started = time.monotonic()
    try:
        runs = demo_runs(root, binary, work) + readme_runs(text, binary, work)
        locate(text)  # the README's regions and patterns, before minutes of runs
        log(f"{len(runs)} runs of {binary} in {work} ({args.jobs} at once) …")
        # The longest first, then the demo's steps in order.
        order = {"reproduce": 0, "demo1": 1, "closed_loop": 2, "improve": 3}
        runs.sort(key=lambda run: order.get(run.name, 9))
        records = run_all(runs, root, args.jobs, log)
        compared = compare(text, records)
        problems = picture_problems(text, os.path.dirname(readme), {run.name: run.out for run in runs}, args.check)
    except SetupError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    finally:
        if args.keep:
            log(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    changes = drifted(compared)
    name = os.path.relpath(readme, root) if readme.startswith(root + os.sep) else readme
    log(f"{len(compared)} figures and {len(PICTURES)} pictures in {name}, from runs of "
        f"{time.monotonic() - started:.0f} s")
    if args.check:
        for found, new, value in changes:
            print(f"{name}:{found.line}: {found.label}: the README says {found.text}, the run gives {new} ({value!r})")
        for problem in problems:
            print(problem)
        if changes or problems:
            again = shlex.join(["python3", "scripts/readme_figures.py", "--motionblocks", args.motionblocks]
                               + (["--readme", args.readme] if args.readme else []))
            print(f"{len(changes)} figure(s) drifted, {len(problems)} picture problem(s): regenerate with {again}")
            return 1
        log("all agree")
        return 0
    for found, new, value in changes:
        log(f"{name}:{found.line}: {found.label}: {found.text} → {new} ({value!r})")
    if changes:
        with open(readme, "w", encoding="utf-8") as f:
            f.write(rewritten(text, compared))
    for problem in problems:
        print(problem)
    log(f"{len(changes)} figure(s) rewritten, {len(PICTURES) - len(problems)} picture(s) copied")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
