#!/usr/bin/env python3
"""Hostile-input harness for the motionblocks command line (issue 30, item 8: "Nothing silently wrong").

Generates hostile or extreme inputs programmatically (families x variants) in a temporary folder, runs each case
as its own process (an argument vector, never a shell; standard input closed; a time limit) and classifies the
outcome:

  CRASH     killed by a signal that was not the harness's own time-limit kill, exit code >= 128, or sanitizer
            output ("AddressSanitizer", "runtime error:", "LeakSanitizer") or "terminate called" on stderr
  HANG      did not end within the time limit (killed)
  LOSS      a file that existed before the command ran (an input of the case) changed or vanished
  SILENT    a case that must be refused exited 0; a refusal whose message is empty, leaks internal text
            ("map::at", "basic_filebuf", "[json.exception", "std::", ...) or does not name the input it refuses;
            a raw ESC/BEL byte on the terminal; an accepted case whose results hold NaN/Infinity (or a check of its
            result failed: a unit read wrongly, a prediction outside the trained range not flagged, ...)
  REFUSED   a control case (a valid input, expected to work) failed: the harness's fixtures are wrong or the
            program regressed
  ERROR     the harness could not prepare the case (a fixture that needs the program failed to build)
  OK        otherwise

Each case declares its expectation: "refuse" (must exit non-zero with a clear message), "accept" (a control: must
exit 0) or "either" (may be accepted or refused, but clearly; when accepted its outputs must hold finite numbers).

    python3 tests/hostile/hostile_inputs.py --motionblocks build/asan/tools/motionblocks [--quick] [--out DIR]
            [--jobs N] [--timeout S] [--family NAME] [--case SUBSTRING] [--list] [--keep]

Prints one line per case that is not OK (id, class, command, first line of stderr), then the counts per class and
per family and the summary line "hostile: N passed, M failed"; exits 1 if any case is not OK. --out DIR gets
report.json (every case: class, reason, exit code, time, command, stderr head) and the folders of the failed cases.
--quick runs a deterministic subset spread over every family (about 90 cases, one to two minutes under ASan).
Python 3 standard library only. docs/hostile-inputs.md describes the families and the latest counts.
"""

import argparse
import concurrent.futures
import hashlib
import json
import math
import os
import random
import re
import select
import shlex
import shutil
import signal
import socket
import stat
import struct
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

REPO = Path(__file__).resolve().parents[2]

OK, SILENT, HANG, LOSS, CRASH, REFUSED, ERROR = "OK", "SILENT", "HANG", "LOSS", "CRASH", "REFUSED", "ERROR"
CLASSES = [OK, SILENT, HANG, LOSS, CRASH, REFUSED, ERROR]

REFUSE, ACCEPT, EITHER = "refuse", "accept", "either"

DEFAULT_TIMEOUT = 60.0
OUTPUT_CAP = 1 << 20  # bytes of stdout/stderr kept per case

# Text of libraries and internals that must never reach a user (issue 30, item 6).
INTERNAL_TEXTS = [
    "map::at", "basic_filebuf", "basic_string", "basic_ios", "[json.exception", "json.exception", "Unable to cast",
    "std::", "vector::", "_M_", "bad_alloc", "bad_optional_access", "bad_variant_access", "bad_function_call",
    "what():", "Assertion `", "Eigen::", "boost::", "nlohmann", "CLI::", "stoi", "stod", "stoul", "Chi Square",
    "Error in function", "unknown exception", "(null)",
]
# An internal function name opening a message ("ResidualAutocorrelation: ...", "ZeroPhaseLowPass: ...").
INTERNAL_NAME = re.compile(r"(?<![\w./\-'\"`])((?:[A-Z][a-z0-9]+){2,})(?:::|: |\(\))")
SANITIZER_TEXTS = ["AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:",
                   "terminate called", "ThreadSanitizer", "MemorySanitizer"]
NONFINITE_WORD = re.compile(rb"(?<![\w.])[-+]?(?:nan|inf|infinity)(?![\w])", re.IGNORECASE)
NONFINITE_CELL = re.compile(rb"(?:^|,)\s*[-+]?(?:nan|inf|infinity)\s*(?=,|\r?$)", re.IGNORECASE | re.MULTILINE)
MESSAGE_LIMIT = 64 * 1024  # a refusal longer than this floods the terminal (a message quotes at most 200 chars)


# ---------------------------------------------------------------------------------------------------------------
# Cases

@dataclass
class Context:
    binary: str
    fixtures: Path
    env: dict
    shards_ok: bool = False
    shard_note: str = ""
    python_module: Optional[Path] = None  # the folder of the built Python module (python_module family)
    python_env: Optional[dict] = None
    python_interpreter: str = ""          # the interpreter the module was built for (its CMakeCache's Python_EXECUTABLE)
    python_note: str = ""


@dataclass
class Result:
    returncode: Optional[int]
    stdout: bytes
    stderr: bytes
    seconds: float
    timed_out: bool = False
    killed_on_purpose: bool = False  # the case's own runner killed it (an interruption test)
    note: str = ""


@dataclass
class Case:
    id: str
    family: str
    argv: list
    expect: str
    files: tuple = ()              # fixture files or folders copied into the case folder
    make: Optional[Callable] = None  # make(case_dir, ctx): writes the case's own (hostile) files
    mention: tuple = ()            # texts a refusal must contain (the input it refuses)
    check: Optional[Callable] = None  # check(case_dir, result) -> None or the reason an accepted run is wrong
    mutable: tuple = ()            # files present before the run that the command may change (relative paths)
    timeout: Optional[float] = None  # a case-specific limit (else --timeout)
    slow: bool = False             # never in --quick
    runner: Optional[Callable] = None  # runner(case, case_dir, ctx, timeout) -> Result
    nonfinite_ok: bool = False     # its outputs may hold NaN by design (predict-gpr copies non-finite inputs)
    quick: bool = False
    needs_shards: bool = False
    deadline: Optional[float] = None  # must end within this many seconds whatever --timeout says (a bound promised)
    exit_code: Optional[int] = None   # the exit code a refusal must have (e.g. 2: bad input)


def P(*parts):
    return "/".join(parts)


# ---------------------------------------------------------------------------------------------------------------
# Fixtures: small, fast versions of the repository's diagrams and data, written once per harness run.

def csv_text(header, rows):
    return ",".join(header) + "\n" + "".join(",".join(repr_num(v) for v in row) + "\n" for row in rows)


def repr_num(v):
    if isinstance(v, str):
        return v
    if isinstance(v, int):
        return str(v)
    return "%.10g" % v


SIM = {
    "schemaVersion": "1.0",
    "name": "hostile_sim",
    "description": "a constant force (plus an optional measured one) on a rigid body written in grams",
    "defaultExperiment": {"startTime": 0.0, "stopTime": 0.2},
    "solver": {"type": "rk4", "step": 0.001},
    "connectors": [
        {"name": "f", "kind": "input", "unit": "N", "measurement": "force_N", "optional": True, "default": 0.0},
        {"name": "position", "kind": "output", "unit": "m", "measurement": "position_m"},
    ],
    "elements": [
        {"name": "push", "type": "constant", "parameters": {"value": 2.0}},
        {"name": "total", "type": "sum", "parameters": {"signs": "++"}},
        {"name": "mass", "type": "rigid_body", "parameters": {"mass": {"value": 500, "unit": "g"}, "damping": 4.0}},
    ],
    "connections": [
        {"startElement": "push", "startConnector": "y", "endElement": "total", "endConnector": "u1"},
        {"startConnector": "f", "endElement": "total", "endConnector": "u2"},
        {"startElement": "total", "startConnector": "y", "endElement": "mass", "endConnector": "f"},
        {"startElement": "mass", "startConnector": "x", "endConnector": "position"},
    ],
    "metrics": [{"name": "final_position", "type": "final", "signal": "position", "unit": "m"}],
    "log": ["mass.v"],
}

SWEEP_DIAGRAM = {
    "schemaVersion": "1.0",
    "name": "hostile_sweep",
    "defaultExperiment": {"startTime": 0.0, "stopTime": 0.01},
    "solver": {"type": "rk4", "step": 0.001},
    "elements": [
        {"name": "c", "type": "constant", "parameters": {"value": 1.0}},
        {"name": "k", "type": "gain", "parameters": {"gain": 1.0}},
    ],
    "connections": [{"startElement": "c", "startConnector": "y", "endElement": "k", "endConnector": "u"}],
    "metrics": [{"name": "k_final", "type": "final", "signal": "k.y", "unit": "1"}],
    "log": ["k.y"],
}

GPR_DIAGRAM = {
    "schemaVersion": "1.0",
    "name": "hostile_gpr",
    "defaultExperiment": {"startTime": 0.0, "stopTime": 0.02},
    "solver": {"type": "rk4", "step": 0.001},
    "elements": [
        {"name": "x", "type": "constant", "parameters": {"value": 0.01}},
        {"name": "v", "type": "constant", "parameters": {"value": 0.1}},
        {"name": "gpr", "type": "gpr", "parameters": {"model": "model.json"}},
    ],
    "connections": [
        {"startElement": "x", "startConnector": "y", "endElement": "gpr", "endConnector": "x"},
        {"startElement": "v", "startConnector": "y", "endElement": "gpr", "endConnector": "xdot"},
    ],
    "metrics": [{"name": "gp_mean", "type": "final", "signal": "gpr.mean", "unit": "N"}],
    "log": ["gpr.mean"],
}


def from_file_diagram(file_value, column="force_N"):
    return {
        "schemaVersion": "1.0",
        "name": "hostile_from_file",
        "defaultExperiment": {"startTime": 0.0, "stopTime": 0.05},
        "solver": {"type": "rk4", "step": 0.001},
        "elements": [
            {"name": "src", "type": "from_file", "parameters": {"file": file_value, "column": column}},
            {"name": "k", "type": "gain", "parameters": {"gain": 2.0}},
        ],
        "connections": [{"startElement": "src", "startConnector": "y", "endElement": "k", "endConnector": "u"}],
        "metrics": [{"name": "k_final", "type": "final", "signal": "k.y", "unit": "N"}],
        "log": ["k.y"],
    }


def subsystem_leaf(name="leaf"):
    return {
        "schemaVersion": "1.0",
        "name": name,
        "connectors": [{"name": "y", "kind": "output", "unit": "m"}],
        "elements": [{"name": "c", "type": "constant", "parameters": {"value": 0.5}}],
        "connections": [{"startElement": "c", "startConnector": "y", "endConnector": "y"}],
    }


def subsystem_parent(diagram_value, name="parent", top=True):
    d = {
        "schemaVersion": "1.0",
        "name": name,
        "elements": [
            {"name": "s", "type": "subsystem", "diagram": diagram_value},
            {"name": "g", "type": "gain", "parameters": {"gain": 2.0}},
        ],
        "connections": [{"startElement": "s", "startConnector": "y", "endElement": "g", "endConnector": "u"}],
    }
    if top:
        d["defaultExperiment"] = {"startTime": 0.0, "stopTime": 0.01}
        d["solver"] = {"type": "rk4", "step": 0.001}
        d["metrics"] = [{"name": "g_final", "type": "final", "signal": "g.y", "unit": "m"}]
        d["log"] = ["g.y"]
    else:
        d["connectors"] = [{"name": "y", "kind": "output", "unit": "m"}]
        d["connections"].append({"startElement": "g", "startConnector": "y", "endConnector": "y"})
    return d


def dump(obj):
    return json.dumps(obj, indent=1, ensure_ascii=False) + "\n"


def gp_table_rows():
    rows = []
    for v in (0.05, 0.1):
        for i in range(60):
            x = 0.002 * i
            rows.append([x, v, 2.0 * math.sin(2.0 * math.pi * x / 0.0225) + 0.5 * v + 0.02 * math.sin(7.3 * i)])
    return rows


def smooth_rows():
    rows = []
    t = 0.0
    for v in (0.05, -0.05):
        x = 0.0 if v > 0 else 0.1
        for _ in range(200):
            f = 3.0 * v + 0.4 * math.sin(2.0 * math.pi * x / 0.0225)
            rows.append([t, x, v, f])
            t += 0.01
            x += v * 0.01
    return rows


def write_fixtures(fix: Path):
    """The shared fixtures every case copies from (never the repository itself)."""
    fix.mkdir(parents=True, exist_ok=True)
    (fix / "sim.json").write_text(dump(SIM))
    long_sim = json.loads(json.dumps(SIM))
    # 9e7 steps (under the default limit of 1e8): ~9 s in Release on this machine, so the harness's interrupt at 4 s
    # finds it running (4e7 steps had ended in 3.8 s)
    long_sim["defaultExperiment"]["stopTime"] = 9000.0
    long_sim["solver"]["step"] = 1e-4
    (fix / "long.json").write_text(dump(long_sim))
    shutil.copy(REPO / "diagrams/emps/rigid_body.json", fix / "ee.json")
    for src, dst in (("DATA_EMPS.csv", "log.csv"), ("DATA_EMPS_PULSES.csv", "val.csv")):
        with open(REPO / "diagrams/emps/data" / src) as f:
            lines = [next(f) for _ in range(6301)]  # 6.3 s: one stroke out and back (both signs of velocity)
        (fix / dst).write_text("".join(lines))
    (fix / "table.csv").write_text(csv_text(["x_m", "v_m_s", "dob_N"], gp_table_rows()))
    (fix / "smooth.csv").write_text(csv_text(["time_s", "position_m", "velocity_m_s", "force_N"], smooth_rows()))
    shutil.copy(REPO / "diagrams/paper/models/gpr_ps_d2.json", fix / "model.json")
    (fix / "gprd.json").write_text(dump(GPR_DIAGRAM))
    shutil.copy(REPO / "diagrams/paper/conventional.json", fix / "loop.json")
    (fix / "hil" / "subsystems").mkdir(parents=True, exist_ok=True)
    shutil.copy(REPO / "diagrams/hil/pd_rigid_body.json", fix / "hil" / "pd.json")
    for name in ("plant.json", "hil_io.json"):
        shutil.copy(REPO / "diagrams/hil/subsystems" / name, fix / "hil" / "subsystems" / name)
    (fix / "sweep").mkdir(exist_ok=True)
    (fix / "sweep" / "d.json").write_text(dump(SWEEP_DIAGRAM))
    (fix / "sweep" / "grid.json").write_text(dump({"diagram": "d.json", "grid": {"k.gain": [1, 2, 3, 4]}}))


def build_shards(ctx: Context):
    """Two shard folders of a tiny sweep (sweep --shard 1/2 and 2/2), for the sweep-merge tampering cases."""
    fix = ctx.fixtures
    notes = []
    for k in (1, 2):
        out = fix / "shards" / ("s%d" % k)
        r = run_process(ctx, ["sweep", "sweep/d.json", "sweep/grid.json", "--shard", "%d/2" % k, "--out",
                              str(out.relative_to(fix)), "--jobs", "1"], fix, 300.0)
        if r.returncode != 0 or not (out / "sweep-shard.json").exists():
            notes.append("sweep --shard %d/2 failed (exit %s): %s" % (k, r.returncode, first_line(r.stderr)))
    ctx.shards_ok = not notes
    if ctx.shards_ok:
        # The harness's copy of the content hash must agree with the program's (else tampering with the hash
        # recomputed only tests the hash).
        m = json.loads((fix / "shards/s1/sweep-shard.json").read_text())
        if shard_content_hash(m, fix / "shards/s1") != m.get("content"):
            ctx.shard_note = "the harness's content hash differs from the program's: rehashed tampering is shallow"
    ctx.shard_note = "; ".join(notes) or ctx.shard_note


def fnv1a64(data: bytes) -> int:
    h = 0xcbf29ce484222325
    for b in data:
        h ^= b
        h = (h * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return h


def nlohmann_dump(obj) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def shard_content_hash(manifest: dict, folder: Path) -> str:
    m = dict(manifest)
    m.pop("content", None)
    text = (nlohmann_dump(m) + "\n").encode() + (folder / "runs.csv").read_bytes() + b"\n" + \
        (folder / "runs.json").read_bytes()
    return "fnv1a64:%016x" % fnv1a64(text)


def reseal(folder: Path):
    mp = folder / "sweep-shard.json"
    m = json.loads(mp.read_text())
    m["content"] = shard_content_hash(m, folder)
    mp.write_text(nlohmann_dump(m))


# ---------------------------------------------------------------------------------------------------------------
# Hostile files

def valid_text(ctx: Context, fmt: str) -> bytes:
    fix = ctx.fixtures
    return {
        "diagram": (fix / "sim.json").read_bytes(),
        "ee": (fix / "ee.json").read_bytes(),
        "loop": (fix / "loop.json").read_bytes(),
        "plant": (fix / "hil/subsystems/plant.json").read_bytes(),
        "pd": (fix / "hil/pd.json").read_bytes(),
        "io": (fix / "hil/subsystems/hil_io.json").read_bytes(),
        "sweepdiagram": (fix / "sweep/d.json").read_bytes(),
        "csv": b"".join((fix / "log.csv").read_bytes().splitlines(keepends=True)[:301]),
        "table": (fix / "table.csv").read_bytes(),
        "smoothdiagram": (fix / "hil/pd.json").read_bytes(),
        "model": (fix / "model.json").read_bytes(),
        "sweep": (fix / "sweep/grid.json").read_bytes(),
    }[fmt]


def is_json_format(fmt):
    return fmt not in ("csv", "table")


def truncate_mid(data: bytes, json_like: bool) -> bytes:
    cut = int(len(data) * 0.6)
    if json_like:
        return data[:cut]
    comma = data.rfind(b",", 0, cut)
    return data[:comma + 2]  # inside a row: one cell and a digit of the next


def hostile_path(kind: str, fmt: str, case_dir: Path, rel: str, ctx: Context) -> Optional[str]:
    """Creates the hostile input `kind` at case_dir/rel (or names a device) and returns the path to pass."""
    target = case_dir / rel
    target.parent.mkdir(parents=True, exist_ok=True)
    json_like = is_json_format(fmt)
    valid = valid_text(ctx, fmt)
    if kind == "dev_zero":
        return "/dev/zero"
    if kind == "dev_urandom":
        return "/dev/urandom"
    if kind == "dev_null":
        return "/dev/null"
    if kind == "proc_status":
        return "/proc/self/status"
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "directory":
        target.mkdir()
    elif kind == "missing":
        pass
    elif kind == "dangling_symlink":
        os.symlink("nowhere/" + target.name, target)
    elif kind == "symlink_loop":
        os.symlink(target.name + ".b", target)
        os.symlink(target.name, target.parent / (target.name + ".b"))
    elif kind == "symlink_dev_zero":
        os.symlink("/dev/zero", target)
    elif kind == "empty":
        target.write_bytes(b"")
    elif kind == "whitespace":
        target.write_bytes(b" \n\t\r\n  \n")
    elif kind == "garbage":
        target.write_bytes(random.Random(rel + kind).randbytes(4096))
    elif kind == "nul_inside":
        half = len(valid) // 2
        target.write_bytes(valid[:half] + b"\0\0\0" + valid[half:])
    elif kind == "truncated":
        target.write_bytes(truncate_mid(valid, json_like))
    elif kind == "json_array":
        target.write_bytes(b"[]\n")
    elif kind == "json_scalar":
        target.write_bytes(b"42\n")
    elif kind == "json_null":
        target.write_bytes(b"null\n")
    elif kind == "deep_nesting":
        target.write_bytes(b"[" * 200000 + b"]" * 200000 if json_like else b"time_s," + b"[" * 200000 + b"\n0,1\n")
    elif kind == "other_format":
        target.write_bytes(valid_text(ctx, "csv") if json_like else valid_text(ctx, "diagram"))
    elif kind == "oversize":
        if json_like:
            target.write_bytes(valid + b" " * 1_300_000)
        else:
            lines = valid.splitlines(keepends=True)
            body = lines[1:]
            out = [lines[0]]
            size = len(lines[0])
            t = 0.0
            while size < 1_300_000:
                for line in body:
                    cells = line.split(b",")
                    t += 0.001
                    cells[0] = b"%.6f" % t
                    row = b",".join(cells)
                    out.append(row)
                    size += len(row)
            target.write_bytes(b"".join(out))
    elif kind == "bom":
        target.write_bytes(b"\xef\xbb\xbf" + valid)
    elif kind == "invalid_utf8":
        if json_like:
            i = valid.find(b'"name"')
            j = valid.find(b'"', valid.find(b":", i) + 1) + 1 if i >= 0 else -1
            if i < 0 or j <= 0:  # no name: into the first string
                j = valid.find(b'"') + 1
            target.write_bytes(valid[:j] + b"\xff\xfe\xc3(" + valid[j:])
        else:
            lines = valid.splitlines()  # one more column, its name not UTF-8
            lines = [lines[0] + b",note\xff\xfe\xc3("] + [line + b",0" for line in lines[1:]]
            target.write_bytes(b"\n".join(lines) + b"\n")
    elif kind == "long_line":
        if json_like:
            target.write_bytes(b'{"schemaVersion": "1.0", "name": "' + b"a" * 3_000_000 + b'"}\n')
        else:
            target.write_bytes(b"time_s," + b",".join(b"c%d" % i for i in range(400000)) + b"\n0\n")
    else:
        raise ValueError(kind)
    return rel


FILE_KINDS = [
    # kind, expectation
    ("dev_zero", REFUSE), ("dev_urandom", REFUSE), ("dev_null", REFUSE), ("proc_status", REFUSE),
    ("fifo", REFUSE), ("directory", REFUSE), ("missing", REFUSE), ("dangling_symlink", REFUSE),
    ("symlink_loop", REFUSE), ("symlink_dev_zero", REFUSE), ("empty", REFUSE), ("whitespace", REFUSE),
    ("garbage", REFUSE), ("nul_inside", REFUSE), ("truncated", REFUSE), ("json_array", REFUSE),
    ("json_scalar", REFUSE), ("json_null", REFUSE), ("deep_nesting", REFUSE), ("other_format", REFUSE),
    ("oversize", REFUSE), ("bom", EITHER), ("invalid_utf8", EITHER), ("long_line", REFUSE),
]


# ---------------------------------------------------------------------------------------------------------------
# Family 1, input_file: every input a command reads x every hostile file kind.

# slot, format of its valid content, where the hostile file goes, argv with {P}, fixtures
INPUT_SLOTS = [
    ("run.diagram", "diagram", "h.json", ["run", "{P}", "--out", "out"], ()),
    ("run.input", "csv", "h.csv", ["run", "sim.json", "--input", "f={P}:force_N", "--out", "out"], ("sim.json",)),
    ("draw.diagram", "diagram", "h.json", ["draw", "{P}", "-o", "pic.svg"], ()),
    ("compare.diagram", "ee", "h.json", ["compare", "{P}", "--measurement", "log.csv", "--out", "out"], ("log.csv",)),
    ("compare.measurement", "csv", "h.csv", ["compare", "ee.json", "--measurement", "{P}", "--out", "out"],
     ("ee.json",)),
    ("fit.diagram", "ee", "h.json", ["fit", "{P}", "--measurement", "log.csv", "--out", "out"], ("log.csv",)),
    ("fit.measurement", "csv", "h.csv", ["fit", "ee.json", "--measurement", "{P}", "--out", "out"], ("ee.json",)),
    ("improve.diagram", "ee", "h.json",
     ["improve", "{P}", "--measurement", "log.csv", "--max-effects", "0", "--out", "out"], ("log.csv",)),
    ("improve.measurement", "csv", "h.csv",
     ["improve", "ee.json", "--measurement", "{P}", "--max-effects", "0", "--out", "out"], ("ee.json",)),
    ("improve.validation", "csv", "h.csv",
     ["improve", "ee.json", "--measurement", "log.csv", "--validation", "{P}", "--max-effects", "0", "--out", "out"],
     ("ee.json", "log.csv")),
    ("stability.diagram", "loop", "h.json", ["stability", "{P}", "--out", "out"], ()),
    ("stability.gpr", "model", "h.json", ["stability", "loop.json", "--gpr", "{P}", "--out", "out"], ("loop.json",)),
    ("fit-gpr.table", "table", "h.csv",
     ["fit-gpr", "{P}", "--position-column", "x_m", "--velocity-column", "v_m_s", "--disturbance-column", "dob_N",
      "-o", "m.json"], ()),
    ("fit-gpr.diagram", "smoothdiagram", "hil/h.json",
     ["fit-gpr", "smooth.csv", "--target", "smoothed", "--force-column", "force_N", "--position-column",
      "position_m", "--velocity-column", "velocity_m_s", "--diagram", "{P}", "-o", "m.json"], ("smooth.csv", "hil")),
    ("predict-gpr.model", "model", "h.json",
     ["predict-gpr", "{P}", "table.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "-o", "p.csv"],
     ("table.csv",)),
    ("predict-gpr.input", "table", "h.csv",
     ["predict-gpr", "model.json", "{P}", "--position-column", "x_m", "--velocity-column", "v_m_s", "-o", "p.csv"],
     ("model.json",)),
    ("sweep.sweep", "sweep", "sweep/h.json", ["sweep", "sweep/d.json", "{P}", "--out", "out", "--jobs", "1"],
     ("sweep",)),
    ("sweep.diagram", "sweepdiagram", "sweep/h.json",
     ["sweep", "{P}", "sweep/grid.json", "--out", "out", "--jobs", "1"], ("sweep",)),
    ("virtual-stage.diagram", "plant", "hil/subsystems/h.json",
     ["virtual-stage", "{P}", "--io", "hil/subsystems/hil_io.json", "--duration", "0.2"], ("hil",)),
    ("virtual-stage.io", "io", "hil/subsystems/h.json",
     ["virtual-stage", "hil/subsystems/plant.json", "--io", "{P}", "--duration", "0.2"], ("hil",)),
    ("hil.diagram", "pd", "hil/h.json",
     ["hil", "{P}", "--board", "udp", "--port", "9", "--replace", "plant=hil/subsystems/hil_io.json", "--duration",
      "0.05", "--out", "out"], ("hil",)),
    ("hil.replace", "io", "hil/subsystems/h.json",
     ["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace", "plant={P}", "--duration", "0.05", "--out",
      "out"], ("hil",)),
]

SLOW_COMMANDS = ("improve", "compare", "fit")


def subst(argv, **values):
    out = []
    for a in argv:
        for k, v in values.items():
            a = a.replace("{%s}" % k, v)
        out.append(a)
    return out


def family_input_file(ctx):
    cases = []
    for slot, fmt, rel, argv, files in INPUT_SLOTS:
        for kind, expect in FILE_KINDS:
            path = {"dev_zero": "/dev/zero", "dev_urandom": "/dev/urandom", "dev_null": "/dev/null",
                    "proc_status": "/proc/self/status"}.get(kind, rel)
            args = subst(argv, P=path)
            mention = ((path, Path(rel).name),)
            if kind == "oversize":
                args = ["--max-input-mb", "1"] + args
                mention = ("--max-input-mb",)
            if kind == "symlink_dev_zero":
                mention = ((rel, "/dev/zero"),)

            def make(d, c, kind=kind, fmt=fmt, rel=rel):
                hostile_path(kind, fmt, d, rel, c)
            cases.append(Case(id="input_file/%s/%s" % (slot, kind), family="input_file", argv=args, expect=expect,
                              files=files, make=make, mention=mention if expect == REFUSE else (),
                              slow=expect == EITHER and slot.split(".")[0] in SLOW_COMMANDS))
    # The same slots with their valid input: controls (each slot's command works on the fixtures).
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 2, numeric_option: every numeric option x {nan, inf, -inf, -1, 0, 1e300, 1e-300, a huge integer, "", abc}

NUMERIC_VALUES = ["nan", "inf", "-inf", "-1", "0", "1e300", "1e-300", "123456789012345678901234567890", "", "abc"]


def as_number(text):
    try:
        return float(text)
    except ValueError:
        return None


def rng(lo, hi, integer=False, lo_open=False):
    """Values a command may accept: finite, in [lo, hi] ((lo, hi] with lo_open), whole if integer. Outside: refuse."""
    def valid(text):
        v = as_number(text)
        if v is None or not math.isfinite(v):
            return False
        if integer and (not v.is_integer() or re.search(r"[eE.]", text)):
            return False
        return (v > lo if lo_open else v >= lo) and v <= hi
    return valid


RUN = ["run", "sim.json", "--out", "out"]
COMPARE = ["compare", "ee.json", "--measurement", "log.csv", "--no-gpr-fallback", "--out", "out"]
FIT = ["fit", "ee.json", "--measurement", "log.csv", "--out", "out"]
IMPROVE = ["improve", "ee.json", "--measurement", "log.csv", "--max-effects", "0", "--out", "out"]
FITGPR = ["fit-gpr", "table.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "--disturbance-column",
          "dob_N", "-o", "m.json"]
SMOOTH = ["fit-gpr", "smooth.csv", "--target", "smoothed", "--force-column", "force_N", "--position-column",
          "position_m", "--velocity-column", "velocity_m_s", "-o", "m.json"]
STAB = ["stability", "loop.json", "--out", "out"]
SWEEP = ["sweep", "sweep/d.json", "sweep/grid.json", "--out", "out", "--jobs", "1"]
HIL = ["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace", "plant=hil/subsystems/hil_io.json",
       "--duration", "0.05", "--out", "out"]
STAGE = ["virtual-stage", "hil/subsystems/plant.json", "--io", "hil/subsystems/hil_io.json", "--duration", "0.3"]
REPRODUCE = ["reproduce", "--quick", "--out", "out"]

HIL_FILES = ("hil",)


def with_option(base, option, value, before=False):
    """base with `option value` (replacing the option if base has it)."""
    args = list(base)
    if option in args:
        i = args.index(option)
        args[i + 1] = value
        return args
    if before:
        return [option, value] + args
    return args + [option, value]


# label, base argv, option, fixtures, validity, global option (before the command), only invalid values
NUMERIC_OPTIONS = [
    ("global.max-input-mb", RUN, "--max-input-mb", ("sim.json",), rng(1e-6, 1e9), True, False),
    ("global.max-plots", RUN, "--max-plots", ("sim.json",), rng(1, 100000, True), True, False),
    ("run.max-steps", RUN, "--max-steps", ("sim.json",), rng(1, 1e13), False, False),
    ("compare.max-steps", COMPARE, "--max-steps", ("ee.json", "log.csv"), rng(1, 1e13), False, False),
    ("compare.derivative-cutoff-hz", COMPARE, "--derivative-cutoff-hz", ("ee.json", "log.csv"), rng(0, 1e300),
     False, False),
    ("fit.max-steps", FIT, "--max-steps", ("ee.json", "log.csv"), rng(1, 1e13), False, False),
    ("fit.derivative-cutoff-hz", FIT, "--derivative-cutoff-hz", ("ee.json", "log.csv"), rng(0, 1e300), False, False),
    ("improve.max-effects", IMPROVE, "--max-effects", ("ee.json", "log.csv"), rng(0, 1000, True), False, False),
    ("improve.max-trials", IMPROVE, "--max-trials", ("ee.json", "log.csv"), rng(1, 1000, True), False, False),
    ("improve.min-gain", IMPROVE, "--min-gain", ("ee.json", "log.csv"), rng(0, 0.999), False, False),
    ("improve.max-steps", IMPROVE, "--max-steps", ("ee.json", "log.csv"), rng(1, 1e13), False, False),
    ("improve.derivative-cutoff-hz", IMPROVE, "--derivative-cutoff-hz", ("ee.json", "log.csv"), rng(0, 1e300),
     False, False),
    ("fit-gpr.period", FITGPR, "--period", ("table.csv",), rng(1e-6, 1e6), False, False),
    ("fit-gpr.downsample", FITGPR, "--downsample", ("table.csv",), rng(1, 1e6, True), False, False),
    ("fit-gpr.restarts", FITGPR, "--restarts", ("table.csv",), rng(0, 1000, True), False, False),
    ("fit-gpr.seed", FITGPR, "--seed", ("table.csv",), rng(0, 2.0 ** 64 - 1, True), False, False),
    ("fit-gpr.nominal-mass", SMOOTH + ["--nominal-damping", "3"], "--nominal-mass", ("smooth.csv",),
     rng(0, 1e300, lo_open=True), False, False),
    ("fit-gpr.nominal-damping", SMOOTH + ["--nominal-mass", "0.3"], "--nominal-damping", ("smooth.csv",),
     rng(0, 1e300), False, False),
    ("fit-gpr.smoothing-cutoff-hz", SMOOTH + ["--nominal-mass", "0.3", "--nominal-damping", "3"],
     "--smoothing-cutoff-hz", ("smooth.csv",), rng(0, 1e300, lo_open=True), False, False),
    ("stability.bode-points", STAB, "--bode-points", ("loop.json",), rng(2, 100000, True), False, False),
    ("sweep.jobs", SWEEP, "--jobs", ("sweep",), rng(0, 1e6, True), False, False),
    ("sweep.max-runs", SWEEP, "--max-runs", ("sweep",), rng(1, 1e7, True), False, False),
    ("sweep.max-steps", SWEEP, "--max-steps", ("sweep",), rng(1, 1e13), False, False),
    ("reproduce.jobs", REPRODUCE, "--jobs", (), rng(0, 1e6, True), False, True),
    ("reproduce.max-steps", REPRODUCE, "--max-steps", (), rng(1, 1e13), False, True),
    ("hil.duration", HIL, "--duration", HIL_FILES, rng(0, 86400, lo_open=True), False, False),
    ("hil.port", HIL, "--port", HIL_FILES, rng(1, 65535, True), False, False),
    ("hil.reply-timeout-ms", HIL, "--reply-timeout-ms", HIL_FILES, rng(1e-3, 1e3), False, False),
    ("hil.encoders", HIL, "--encoders", HIL_FILES, rng(1, 8, True), False, False),
    ("hil.analog-outputs", HIL, "--analog-outputs", HIL_FILES, rng(0, 8, True), False, False),
    ("hil.hardware-watchdog-ms", HIL, "--hardware-watchdog-ms", HIL_FILES, rng(0.1, 6e4), False, False),
    ("hil.max-missed", HIL, "--max-missed", HIL_FILES, rng(1, 1e6, True), False, False),
    ("hil.max-overruns", HIL, "--max-overruns", HIL_FILES, rng(1, 1e6, True), False, False),
    ("hil.fifo", HIL, "--fifo", HIL_FILES, rng(0, 99, True), False, False),
    ("virtual-stage.port", STAGE, "--port", HIL_FILES, rng(0, 65535, True), False, False),
    ("virtual-stage.period-ms", STAGE, "--period-ms", HIL_FILES, rng(1e-2, 1e3), False, False),
    ("virtual-stage.watchdog-ms", STAGE, "--watchdog-ms", HIL_FILES, rng(0.1, 6e4), False, False),
    ("virtual-stage.duration", STAGE, "--duration", HIL_FILES, rng(0, 86400, lo_open=True), False, False),
    ("virtual-stage.drop-from", STAGE, "--drop-from", HIL_FILES, rng(0, 86400), False, False),
    ("virtual-stage.fifo", STAGE, "--fifo", HIL_FILES, rng(0, 99, True), False, False),
]

# fit-gpr --window xmin,xmax
WINDOWS = [("nan,0.1", REFUSE), ("0,inf", REFUSE), ("0.1,0", REFUSE), ("1e300,1e301", REFUSE),
           ("-1,-0.5", REFUSE), ("0.05,0.05", REFUSE), ("0,1e300", EITHER), ("0", REFUSE), ("0,0.1,0.2", REFUSE),
           (",", REFUSE), ("0.02,0.1", ACCEPT)]

SHARDS = [("0/2", REFUSE), ("3/2", REFUSE), ("1/0", REFUSE), ("-1/2", REFUSE), ("nan/2", REFUSE),
          ("1/99999999999999999999999", REFUSE), ("1/2/3", REFUSE), ("", EITHER), ("auto", REFUSE),
          ("5/5", REFUSE), ("1/5", EITHER), ("1/2", ACCEPT), ("1e0/2", REFUSE)]
SHARD_INDEXES = [("2/2", REFUSE), ("-1/2", REFUSE), ("0/0", REFUSE), ("0/2", ACCEPT)]


def family_numeric_option(ctx):
    cases = []
    for label, base, option, files, valid, global_option, only_invalid in NUMERIC_OPTIONS:
        for value in NUMERIC_VALUES:
            ok = valid(value)
            if ok and only_invalid:
                continue  # an in-range value would start the whole job (reproduce: minutes)
            if global_option:
                args = [option, value] + list(base)
            else:
                args = with_option(base, option, value)
            slow = ok and label.split(".")[0] in SLOW_COMMANDS
            cases.append(Case(id="numeric_option/%s/%s" % (label, value or "empty"), family="numeric_option",
                              argv=args, expect=EITHER if ok else REFUSE, files=files,
                              mention=((option, option.lstrip("-"), value or option),) if not ok and value else (),
                              slow=slow))
    for value, expect in WINDOWS:
        cases.append(Case(id="numeric_option/fit-gpr.window/%s" % value, family="numeric_option",
                          argv=FITGPR + ["--window", value], expect=expect, files=("table.csv",)))
    env_free = dict()
    for value, expect in SHARDS:
        cases.append(Case(id="numeric_option/sweep.shard/%s" % (value or "empty"), family="numeric_option",
                          argv=with_option(SWEEP, "--shard", value), expect=expect, files=("sweep",)))
    for value, expect in SHARD_INDEXES:
        cases.append(Case(id="numeric_option/sweep.shard-index/%s" % value, family="numeric_option",
                          argv=with_option(SWEEP, "--shard-index", value), expect=expect, files=("sweep",)))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 3, set_override: --set on parameters, the solver and the experiment x the hostile numbers (absurd stop
# times and steps), and the unit rule (issue 30, item 1).

def final_position(mass_kg, force=2.0, damping=4.0, t=0.2):
    tau = mass_kg / damping
    return force / damping * (t - tau * (1.0 - math.exp(-t / tau)))


def summary_metric_check(name, expected, rel=1e-3, path="out/summary.json"):
    def check(d, r):
        try:
            value = json.loads((d / path).read_text())["metrics"][name]
        except Exception as e:  # noqa: BLE001
            return "no metric %s in %s (%s)" % (name, path, e)
        if not isinstance(value, (int, float)) or not math.isclose(value, expected, rel_tol=rel):
            return "%s = %r, expected %.6g (a unit read wrongly?)" % (name, value, expected)
        return None
    return check


def number_spellings(text):
    """How a message may quote the number given: as typed, or as printed back (%g, 1e+300)."""
    v = as_number(text)
    if v is None or not text:
        return (text,) if text else ()
    return (text, "%g" % v, "%.6g" % v, repr(v))


def zero_or(valid):
    return lambda text: as_number(text) == 0.0 or valid(text)


SET_KEYS = [
    # key, validity of a number for run (which simulates), for draw (the loader's checks only; None: not drawn)
    ("mass.mass", rng(0, 1e300, lo_open=True), rng(0, 1e300, lo_open=True)),
    ("mass.damping", rng(0, 1e300), rng(0, 1e300)),
    ("push.value", rng(-1e300, 1e300), None),
    ("mass.v0", rng(-1e300, 1e300), None),
    ("solver.step", rng(1e-9, 0.2), rng(0, 1e300, lo_open=True)),
    ("defaultExperiment.stopTime", rng(0, 1e4), None),
    ("defaultExperiment.startTime", rng(-1e4, 0.2 - 1e-9), None),
    ("defaultExperiment.stepSize", zero_or(rng(1e-9, 1e300)), None),
]


def family_set_override(ctx):
    cases = []
    for key, run_valid, draw_valid in SET_KEYS:
        for value in NUMERIC_VALUES:
            for command, valid in ((["run", "sim.json", "--out", "out"], run_valid),
                                   (["draw", "sim.json", "-o", "pic.svg"], draw_valid)):
                if valid is None:
                    continue
                ok = valid(value)
                cases.append(Case(id="set_override/%s/%s/%s" % (command[0], key, value or "empty"),
                                  family="set_override", argv=command + ["--set", "%s=%s" % (key, value)],
                                  expect=EITHER if ok else REFUSE, files=("sim.json",),
                                  mention=((key, key.split(".")[-1]) + number_spellings(value),) if not ok else ()))
    # One meaning per number: SI whatever unit the diagram wrote; a quantity object converted; anything else refused.
    two_kg = summary_metric_check("final_position", final_position(2.0))
    units = [
        ("si_number", "mass.mass=2", ACCEPT, two_kg),
        ("quantity_kg", 'mass.mass={"value": 2, "unit": "kg"}', ACCEPT, two_kg),
        ("quantity_g", 'mass.mass={"value": 2000, "unit": "g"}', ACCEPT, two_kg),
        ("quantity_misspelled_key", 'mass.mass={"value": 2, "unti": "kg"}', REFUSE, None),
        ("quantity_extra_key", 'mass.mass={"value": 2, "unit": "kg", "note": 1}', REFUSE, None),
        ("quantity_other_quantity", 'mass.mass={"value": 2, "unit": "m"}', REFUSE, None),
        ("quantity_unknown_unit", 'mass.mass={"value": 2, "unit": "furlong"}', REFUSE, None),
        ("quantity_string_value", 'mass.mass={"value": "2", "unit": "kg"}', REFUSE, None),
        ("quantity_no_value", 'mass.mass={"unit": "kg"}', REFUSE, None),
        ("quantity_empty", "mass.mass={}", REFUSE, None),
        ("array", "mass.mass=[2]", REFUSE, None),
        ("number_with_unit_text", "mass.mass=2 kg", REFUSE, None),
        ("json_overflow", "mass.mass=1e999", REFUSE, None),
        ("no_value", "mass.mass=", REFUSE, None),
        ("no_equals", "mass.mass", REFUSE, None),
        ("no_key", "=2", REFUSE, None),
        ("no_dot", "mass=2", REFUSE, None),
        ("unknown_element", "nosuch.mass=2", REFUSE, None),
        ("unknown_parameter", "mass.nosuch=2", REFUSE, None),
        ("misspelled_solver_key", "solver.stpe=0.001", REFUSE, None),
        ("unknown_solver", "solver.type=bogus", REFUSE, None),
        ("misspelled_experiment_key", "defaultExperiment.stopTme=1", REFUSE, None),
        ("start_after_stop", "defaultExperiment.startTime=5", REFUSE, None),
        ("string_for_number", "mass.mass=heavy", REFUSE, None),
        ("bool_for_number", "mass.mass=true", REFUSE, None),
        ("null_for_number", "mass.mass=null", REFUSE, None),
        ("cvode_rtol_zero", "solver.rtol=0", REFUSE, None),
        ("long_value", "mass.mass=" + "9" * 100000, REFUSE, None),
    ]
    for name, setting, expect, check in units:
        cases.append(Case(id="set_override/units/%s" % name, family="set_override",
                          argv=["run", "sim.json", "--set", setting, "--out", "out"], expect=expect,
                          files=("sim.json",), check=check))
    # A sweep's number is SI too.
    def sweep_mass(d, c):
        (d / "sweep").mkdir(exist_ok=True)
        (d / "sweep" / "sim.json").write_text(dump(SIM))
        (d / "sweep" / "mass.json").write_text(dump({"diagram": "sim.json", "grid": {"mass.mass": [2]}}))

    def sweep_check(d, r):
        try:
            text = (d / "out" / "runs.json").read_text()
            runs = json.loads(text)
            rows = runs["runs"] if isinstance(runs, dict) else runs
            value = rows[0]["metrics"]["final_position"] if "metrics" in rows[0] else rows[0]["final_position"]
        except Exception as e:  # noqa: BLE001
            return "cannot read final_position from out/runs.json (%s)" % e
        expected = final_position(2.0)
        if not math.isclose(float(value), expected, rel_tol=1e-3):
            return "sweep mass.mass = 2: final_position %r, expected %.6g (read in the diagram's unit, g?)" % (
                value, expected)
        return None
    cases.append(Case(id="set_override/units/sweep_value_is_si", family="set_override",
                      argv=["sweep", "sweep/mass.json", "--out", "out", "--jobs", "1"], expect=ACCEPT,
                      make=sweep_mass, check=sweep_check))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 4, diagram: mutations of a valid diagram (unknown blocks and keys, units, names, wiring, algebraic loops,
# absurd experiments and solvers, subsystem recursion, huge counts, JSON oddities), each run and drawn.

def el(d, name):
    return next(e for e in d["elements"] if e["name"] == name)


def mutate(fn):
    def apply(d):
        fn(d)
        return d
    return apply


def set_param(element, key, value):
    return mutate(lambda d: el(d, element)["parameters"].__setitem__(key, value))


def add_elements(*elements, connections=(), log=()):
    def fn(d):
        d["elements"].extend(json.loads(json.dumps(elements)))
        d["connections"].extend(json.loads(json.dumps(connections)))
        d.setdefault("log", []).extend(log)
    return mutate(fn)


def wire(a, ap, b, bp):
    c = {"startConnector": ap, "endConnector": bp}
    if a:
        c["startElement"] = a
    if b:
        c["endElement"] = b
    return c


def text_replace(old, new):
    def apply(d):
        text = dump(d)
        assert old in text, old
        return text.replace(old, new, 1)
    return apply


def many_blocks(n):
    def fn(d):
        d["elements"].extend({"name": "c%d" % i, "type": "constant", "parameters": {"value": 1.0}} for i in range(n))
    return mutate(fn)


def gain_chain(n):
    def fn(d):
        d["elements"].append({"name": "g0", "type": "constant", "parameters": {"value": 1.0}})
        for i in range(1, n + 1):
            d["elements"].append({"name": "g%d" % i, "type": "gain", "parameters": {"gain": 1.0}})
            d["connections"].append(wire("g%d" % (i - 1), "y", "g%d" % i, "u"))
        d.setdefault("log", []).append("g%d.y" % n)
    return mutate(fn)


def many_logged(n):
    def fn(d):
        for i in range(n):
            d["elements"].append({"name": "s%d" % i, "type": "constant", "parameters": {"value": float(i)}})
        d["log"] = ["s%d.y" % i for i in range(n)]
    return mutate(fn)


def plots_at_most(limit):
    def check(d, r):
        pngs = list((d / "out").glob("signal_*.png")) if (d / "out").is_dir() else []
        if len(pngs) > limit:
            return "%d signal figures drawn: the report should draw at most %d and list the rest" % (len(pngs), limit)
        return None
    return check


def subsystem_files(layout):
    """make() writing extra diagram files: layout = {relative path: dict or text}."""
    def make(d, ctx):
        for rel, content in layout.items():
            p = d / rel
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_text(content if isinstance(content, str) else dump(content))
    return make


def chain_files(n, recursive=False):
    layout = {}
    for i in range(n):
        nxt = "sub%d.json" % (i + 1) if i + 1 < n else ("sub0.json" if recursive else None)
        layout["sub%d.json" % i] = subsystem_parent(nxt, "sub%d" % i, top=False) if nxt else subsystem_leaf()
    return layout


def inline_nesting(depth):
    inner = subsystem_leaf()
    for i in range(depth):
        inner = subsystem_parent(inner, "n%d" % i, top=False)
    return subsystem_parent(inner, "top")


def special_files(d, ctx):
    os.mkfifo(d / "fifo.csv")
    (d / "folder.csv").mkdir()
    os.symlink("/etc/hostname", d / "outside_link.csv")
    shutil.copy(ctx.fixtures / "log.csv", d / "log.csv")


MUTATIONS = [
    # name, expectation, mutation of SIM (dict -> dict or text), extra files, slow, check
    ("control", ACCEPT, mutate(lambda d: None), None, False, None),
    ("unknown_block_type", REFUSE, mutate(lambda d: el(d, "mass").__setitem__("type", "rigid_bodyy")), None, False,
     None),
    ("unknown_top_key", REFUSE, mutate(lambda d: d.__setitem__("elemnts", [])), None, False, None),
    ("unknown_element_key", REFUSE, mutate(lambda d: el(d, "mass").__setitem__("parameter", {})), None, False, None),
    ("unknown_parameter", REFUSE, set_param("mass", "masss", 1.0), None, False, None),
    ("quantity_misspelled_key", REFUSE, set_param("mass", "mass", {"value": 500, "unti": "g"}), None, False, None),
    ("quantity_extra_key", REFUSE, set_param("mass", "mass", {"value": 500, "unit": "g", "x": 1}), None, False, None),
    ("quantity_other_quantity", REFUSE, set_param("mass", "mass", {"value": 500, "unit": "m"}), None, False, None),
    ("quantity_unknown_unit", REFUSE, set_param("mass", "mass", {"value": 500, "unit": "furlong"}), None, False,
     None),
    ("quantity_without_value", REFUSE, set_param("mass", "mass", {"unit": "g"}), None, False, None),
    ("quantity_null_value", REFUSE, set_param("mass", "mass", {"value": None, "unit": "g"}), None, False, None),
    ("unit_on_dimensionless_gain", REFUSE, set_param("push", "value", {"value": 2, "unit": "furlong"}), None, False,
     None),
    ("param_string", REFUSE, set_param("mass", "mass", "heavy"), None, False, None),
    ("param_numeric_string", REFUSE, set_param("mass", "mass", "0.5"), None, False, None),
    ("param_nan_string", REFUSE, set_param("mass", "mass", "NaN"), None, False, None),
    ("param_null", REFUSE, set_param("mass", "mass", None), None, False, None),
    ("param_bool", REFUSE, set_param("mass", "mass", True), None, False, None),
    ("param_array", REFUSE, set_param("mass", "mass", [0.5, 0.5]), None, False, None),
    ("param_object", REFUSE, set_param("mass", "mass", {"a": 1}), None, False, None),
    ("param_json_overflow", REFUSE, text_replace('"damping": 4.0', '"damping": 1e999'), None, False, None),
    ("param_nan_literal", REFUSE, text_replace('"damping": 4.0', '"damping": NaN'), None, False, None),
    ("mass_zero", REFUSE, set_param("mass", "mass", 0.0), None, False, None),
    ("mass_negative", REFUSE, set_param("mass", "mass", -1.0), None, False, None),
    ("mass_tiny", EITHER, set_param("mass", "mass", 1e-300), None, False, None),
    ("mass_huge", EITHER, set_param("mass", "mass", 1e300), None, False, None),
    ("damping_negative", REFUSE, set_param("mass", "damping", -4.0), None, False, None),
    ("signs_wrong_count", REFUSE, set_param("total", "signs", "+++"), None, False, None),
    ("signs_bad_char", REFUSE, set_param("total", "signs", "+*"), None, False, None),
    ("width_zero", REFUSE, set_param("total", "width", 0), None, False, None),
    ("width_huge", REFUSE, set_param("total", "width", 10 ** 12), None, False, None),
    ("width_million_logged", EITHER, add_elements(
        {"name": "wide", "type": "constant", "parameters": {"value": [1.0] * 10}},
        {"name": "big", "type": "gain", "parameters": {"gain": 1.0, "width": 1000000}}, log=["big.y"]),
     None, False, None),
    ("duplicate_element_names", REFUSE, mutate(lambda d: d["elements"].append(dict(el(d, "push")))), None, False,
     None),
    ("duplicate_connector_names", REFUSE, mutate(lambda d: d["connectors"].append(
        {"name": "position", "kind": "output", "unit": "m"})), None, False, None),
    ("output_connector_wrong_unit", REFUSE, mutate(lambda d: d["connectors"][1].__setitem__("unit", "kg")), None,
     False, None),
    ("connector_unknown_unit", REFUSE, mutate(lambda d: d["connectors"][1].__setitem__("unit", "furlong")), None,
     False, None),
    ("connector_bad_kind", REFUSE, mutate(lambda d: d["connectors"][1].__setitem__("kind", "sideways")), None, False,
     None),
    ("connector_bad_quantity", REFUSE, mutate(lambda d: d["connectors"][1].__setitem__("quantity", "colour")), None,
     False, None),
    ("connection_unknown_element", REFUSE, mutate(lambda d: d["connections"][0].__setitem__("startElement", "nope")),
     None, False, None),
    ("connection_unknown_port", REFUSE, mutate(lambda d: d["connections"][0].__setitem__("startConnector", "zz")),
     None, False, None),
    ("connection_input_to_input", REFUSE, mutate(lambda d: d["connections"].append(wire("total", "u1", "mass", "f"))),
     None, False, None),
    ("connection_two_drivers", REFUSE, mutate(lambda d: d["connections"].append(wire("push", "y", "mass", "f"))),
     None, False, None),
    ("connection_missing_fields", REFUSE, mutate(lambda d: d["connections"].append({})), None, False, None),
    ("input_unconnected", EITHER, mutate(lambda d: d["connections"].pop(2)), None, False, None),
    ("algebraic_loop", REFUSE, add_elements(
        {"name": "a", "type": "gain", "parameters": {"gain": 0.5}},
        {"name": "b", "type": "sum", "parameters": {"signs": "++"}},
        connections=[wire("b", "y", "a", "u"), wire("a", "y", "b", "u1"), wire("push", "y", "b", "u2")]),
     None, False, None),
    ("algebraic_self_loop", REFUSE, add_elements(
        {"name": "b", "type": "sum", "parameters": {"signs": "++"}},
        connections=[wire("b", "y", "b", "u1"), wire("push", "y", "b", "u2")]), None, False, None),
    ("name_with_dot", REFUSE, mutate(lambda d: el(d, "push").__setitem__("name", "pu.sh")), None, False, None),
    ("name_empty", REFUSE, mutate(lambda d: el(d, "push").__setitem__("name", "")), None, False, None),
    ("name_megabyte", REFUSE, mutate(lambda d: el(d, "push").__setitem__("name", "p" * 1_000_000)), None, False,
     None),
    ("name_with_escapes", EITHER, mutate(lambda d: d.__setitem__("name", "\x1b[2J\x1b[31mred\x07\r")), None, False,
     None),
    ("element_name_with_escapes", EITHER, mutate(lambda d: (
        el(d, "push").__setitem__("name", "p\x1b]0;title\x07"),
        d["connections"][0].__setitem__("startElement", "p\x1b]0;title\x07"))), None, False, None),
    ("elements_not_array", REFUSE, mutate(lambda d: d.__setitem__("elements", {"a": 1})), None, False, None),
    ("elements_empty", REFUSE, mutate(lambda d: (d.__setitem__("elements", []), d.__setitem__("connections", []),
                                                 d.__setitem__("metrics", []), d.__setitem__("log", []))),
     None, False, None),
    ("hundred_thousand_blocks", EITHER, many_blocks(100000), None, True, None),
    # issue 41: a million blocks ran past 30 s with no word; refused at once, saying the limit
    ("million_blocks", REFUSE, many_blocks(1000000), None, True, None),
    ("ten_thousand_gain_chain", EITHER, gain_chain(10000), None, True, None),
    ("twenty_thousand_logged", EITHER, many_logged(20000), None, True, plots_at_most(100)),
    ("huge_notes_array", REFUSE, text_replace('"schemaVersion"',
                                              '"notes": [' + ",".join(['{"x":1}'] * 300000) + '], "schemaVersion"'),
     None, True, None),
    ("deep_notes", REFUSE, text_replace('"schemaVersion"', '"notes": ' + "[" * 100000 + "]" * 100000 +
                                        ', "schemaVersion"'), None, False, None),
    ("stop_time_huge", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("stopTime", 1e300)), None, False,
     None),
    ("stop_time_negative", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("stopTime", -1.0)), None,
     False, None),
    ("stop_before_start", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("startTime", 1.0)), None,
     False, None),
    ("stop_time_string", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("stopTime", "1")), None, False,
     None),
    ("stop_time_tiny", EITHER, mutate(lambda d: d["defaultExperiment"].__setitem__("stopTime", 1e-300)), None,
     False, None),
    ("stop_time_overflow_literal", REFUSE, text_replace('"stopTime": 0.2', '"stopTime": 1e400'), None, False, None),
    ("step_zero", REFUSE, mutate(lambda d: d["solver"].__setitem__("step", 0.0)), None, False, None),
    ("step_negative", REFUSE, mutate(lambda d: d["solver"].__setitem__("step", -0.001)), None, False, None),
    ("step_tiny", REFUSE, mutate(lambda d: d["solver"].__setitem__("step", 1e-300)), None, False, None),
    ("step_longer_than_run", REFUSE, mutate(lambda d: d["solver"].__setitem__("step", 10.0)), None, False, None),
    ("log_interval_tiny", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("stepSize", 1e-300)), None,
     False, None),
    ("solver_unknown", REFUSE, mutate(lambda d: d["solver"].__setitem__("type", "leapfrog")), None, False, None),
    ("cvode_rtol_zero", REFUSE, mutate(lambda d: d.__setitem__("solver", {"type": "cvode", "rtol": 0})), None, False,
     None),
    ("cvode_rtol_negative", REFUSE, mutate(lambda d: d.__setitem__("solver", {"type": "cvode", "rtol": -1e-6})),
     None, False, None),
    ("cvode_max_step_negative", REFUSE, mutate(lambda d: d.__setitem__("solver", {"type": "cvode", "maxStep": -1})),
     None, False, None),
    ("sample_time_zero", REFUSE, mutate(lambda d: el(d, "push").__setitem__("sampleTime", 0)), None, False, None),
    ("sample_time_negative", REFUSE, add_elements(
        {"name": "z", "type": "zero_order_hold", "sampleTime": -0.001}, connections=[wire("push", "y", "z", "u")]),
     None, False, None),
    ("sample_time_tiny", REFUSE, add_elements(
        {"name": "z", "type": "zero_order_hold", "sampleTime": 1e-300}, connections=[wire("push", "y", "z", "u")]),
     None, False, None),
    ("sample_time_huge", EITHER, add_elements(
        {"name": "z", "type": "zero_order_hold", "sampleTime": 1e300}, connections=[wire("push", "y", "z", "u")]),
     None, False, None),
    ("sample_time_three_entries", REFUSE, add_elements(
        {"name": "z", "type": "zero_order_hold", "sampleTime": [0.001, 0, 1]},
        connections=[wire("push", "y", "z", "u")]), None, False, None),
    ("sample_time_offset_negative", EITHER, add_elements(
        {"name": "z", "type": "zero_order_hold", "sampleTime": [0.001, -0.5]},
        connections=[wire("push", "y", "z", "u")]), None, False, None),
    ("log_unknown_signal", REFUSE, mutate(lambda d: d["log"].append("nosuch.y")), None, False, None),
    ("metric_unknown_type", REFUSE, mutate(lambda d: d["metrics"][0].__setitem__("type", "median")), None, False,
     None),
    ("metric_unknown_signal", REFUSE, mutate(lambda d: d["metrics"][0].__setitem__("signal", "nosuch.y")), None,
     False, None),
    ("metric_window_outside_run", EITHER, mutate(lambda d: d["metrics"][0].update({"from": 5.0, "to": 6.0})), None,
     False, None),
    ("metric_duplicate_name", REFUSE, mutate(lambda d: d["metrics"].append(dict(d["metrics"][0]))), None, False,
     None),
    ("experiment_mode_unknown", REFUSE, mutate(lambda d: d.__setitem__("experiment", {"mode": "bogus"})), None,
     False, None),
    ("free_unknown_parameter", REFUSE, mutate(lambda d: d.__setitem__("free", ["mass.nosuch"])), None, False, None),
    # issue 41: a misspelt "free" entry was ignored by run (fit failed on it later)
    ("free_typo", REFUSE, mutate(lambda d: d.__setitem__("free", ["mass.dampign"])), None, False, None),
    ("free_unknown_element", REFUSE, mutate(lambda d: d.__setitem__("free", ["mas.damping"])), None, False, None),
    # issue 41: a zero log interval was taken for "automatic" without a word
    ("step_size_zero", REFUSE, mutate(lambda d: d["defaultExperiment"].__setitem__("stepSize", 0.0)), None, False,
     None),
    # issue 41: no port is guessed for a connection that names none, even into a block of one input
    ("connection_without_end_connector", REFUSE, mutate(lambda d: d["connections"][2].pop("endConnector")), None,
     False, None),
    ("connection_without_start_connector", REFUSE, mutate(lambda d: d["connections"][2].pop("startConnector")), None,
     False, None),
    ("schema_version_future", REFUSE, mutate(lambda d: d.__setitem__("schemaVersion", "99.0")), None, False, None),
    ("schema_version_number", REFUSE, mutate(lambda d: d.__setitem__("schemaVersion", 1.0)), None, False, None),
    ("trailing_garbage", REFUSE, lambda d: dump(d) + "} {]", None, False, None),
    # issue 41: nlohmann's parser ends at a NUL byte, so a file padded with zeros (or truncated mid-copy) read as whole
    ("trailing_nul_bytes", REFUSE, lambda d: dump(d) + "\0" * 512, None, False, None),
    ("nul_byte_inside", REFUSE, lambda d: dump(d).replace('"elements"', '"elem\0ents"', 1), None, False, None),
    # issue 41: comments are no JSON (the schema, editors, Python's json module and the sweep reader refuse them)
    ("comments", REFUSE, lambda d: "// a comment\n" + dump(d), None, False, None),
    ("block_comment", REFUSE, lambda d: "/* a comment */\n" + dump(d), None, False, None),
    ("duplicate_json_keys", EITHER, text_replace('"name": "hostile_sim"', '"name": "a", "name": "hostile_sim"'),
     None, False, None),
    ("bom", EITHER, lambda d: "\ufeff" + dump(d), None, False, None),
    ("nul_in_string", EITHER, text_replace('"hostile_sim"', '"hostile\\u0000sim"'), None, False, None),
    ("lone_surrogate", EITHER, text_replace('"hostile_sim"', '"hostile\\ud800sim"'), None, False, None),
    # Subsystems: recursion and paths (a diagram names files only inside its folder).
    ("subsystem_self", REFUSE, lambda d: dump(subsystem_parent("self.json")),
     subsystem_files({"self.json": subsystem_parent("self.json", "self", top=False)}), False, None),
    ("subsystem_mutual", REFUSE, lambda d: dump(subsystem_parent("a.json")),
     subsystem_files({"a.json": subsystem_parent("b.json", "a", top=False),
                      "b.json": subsystem_parent("a.json", "b", top=False)}), False, None),
    ("subsystem_cycle_of_five", REFUSE, lambda d: dump(subsystem_parent("sub0.json")),
     subsystem_files(chain_files(5, recursive=True)), False, None),
    ("subsystem_chain_of_three", ACCEPT, lambda d: dump(subsystem_parent("sub0.json")),
     subsystem_files(chain_files(3)), False, None),
    ("subsystem_chain_of_300", EITHER, lambda d: dump(subsystem_parent("sub0.json")),
     subsystem_files(chain_files(300)), True, None),
    ("subsystem_inline_nesting_300", EITHER, lambda d: dump(inline_nesting(300)), None, True, None),
    ("subsystem_escapes_folder", REFUSE, lambda d: dump(subsystem_parent("../../../../../../etc/passwd")), None,
     False, None),
    ("subsystem_absolute_path", REFUSE, lambda d: dump(subsystem_parent("/etc/passwd")), None, False, None),
    ("subsystem_dev_zero", REFUSE, lambda d: dump(subsystem_parent("/dev/zero")), None, False, None),
    ("subsystem_fifo", REFUSE, lambda d: dump(subsystem_parent("fifo.csv")), special_files, False, None),
    ("subsystem_directory", REFUSE, lambda d: dump(subsystem_parent("folder.csv")), special_files, False, None),
    ("subsystem_symlink_outside", REFUSE, lambda d: dump(subsystem_parent("outside_link.csv")), special_files, False,
     None),
    ("subsystem_missing", REFUSE, lambda d: dump(subsystem_parent("nowhere.json")), None, False, None),
    ("subsystem_not_a_diagram", REFUSE, lambda d: dump(subsystem_parent("log.csv")), special_files, False, None),
    ("subsystem_diagram_number", REFUSE, lambda d: dump(subsystem_parent(42)), None, False, None),
    ("from_file_control", ACCEPT, lambda d: dump(from_file_diagram("log.csv")), special_files, False, None),
    ("from_file_escapes_folder", REFUSE, lambda d: dump(from_file_diagram("../../../../../../etc/passwd")), None,
     False, None),
    ("from_file_absolute", REFUSE, lambda d: dump(from_file_diagram("/etc/passwd")), None, False, None),
    ("from_file_dev_zero", REFUSE, lambda d: dump(from_file_diagram("/dev/zero")), None, False, None),
    ("from_file_fifo", REFUSE, lambda d: dump(from_file_diagram("fifo.csv")), special_files, False, None),
    ("from_file_directory", REFUSE, lambda d: dump(from_file_diagram("folder.csv")), special_files, False, None),
    ("from_file_symlink_outside", REFUSE, lambda d: dump(from_file_diagram("outside_link.csv")), special_files,
     False, None),
    ("from_file_unknown_column", REFUSE, lambda d: dump(from_file_diagram("log.csv", "nosuch_N")), special_files,
     False, None),
    ("from_file_time_column_missing", REFUSE, lambda d: dump(json.loads(json.dumps(from_file_diagram("log.csv")) \
        .replace('"column": "force_N"', '"column": "force_N", "time_column": "t_nope"'))), special_files, False,
     None),
]


# What a refusal of these mutations must name (issue 41: "refuse each, with the pointer").
DIAGRAM_MENTIONS = {
    "free_unknown_parameter": ("/free/0", "nosuch"),
    "free_typo": ("/free/0", "did you mean 'damping'"),
    "free_unknown_element": ("/free/0", "no element named 'mas'"),
    "step_size_zero": ("/defaultExperiment/stepSize",),
    "connection_without_end_connector": ("/connections/2/endConnector", "its inputs: f"),
    "connection_without_start_connector": ("/connections/2/startConnector", "its outputs: y"),
    "trailing_nul_bytes": ("h.json", "NUL byte"),
    "nul_byte_inside": ("h.json", "NUL byte"),
    "comments": ("h.json", "comments"),
    "block_comment": ("h.json", "comments"),
    "million_blocks": ("h.json", "elements or more, more than the 200000 a diagram may hold"),
}
# A refusal that must come quickly (issue 41: a million blocks ran past 30 s before any word).
DIAGRAM_DEADLINES = {"million_blocks": 30.0}

DRAWN_ANYWAY = {"stop_time_huge", "stop_time_negative", "stop_before_start", "stop_time_tiny", "step_tiny",
                "step_longer_than_run", "log_interval_tiny", "sample_time_tiny", "width_million_logged",
                "metric_window_outside_run"}


def family_diagram(ctx):
    cases = []
    for name, expect, mutation, extra, slow, check in MUTATIONS:
        def make(d, c, mutation=mutation, extra=extra):
            content = mutation(json.loads(json.dumps(SIM)))
            if extra:
                extra(d, c)
            (d / "h.json").write_text(content if isinstance(content, str) else dump(content))
        for command in (["run", "h.json", "--out", "out"], ["draw", "h.json", "-o", "pic.svg"]):
            if command[0] == "draw" and (check is not None or name.startswith("from_file_control")):
                continue
            e = expect
            if command[0] == "draw" and name in DRAWN_ANYWAY:
                e = EITHER  # draw does not simulate: a run's length, step or log interval is not its concern
            cases.append(Case(id="diagram/%s/%s" % (command[0], name), family="diagram", argv=command,
                              expect=e, make=make, slow=slow, check=check if command[0] == "run" else None,
                              timeout=180.0 if slow else None, deadline=DIAGRAM_DEADLINES.get(name),
                              mention=DIAGRAM_MENTIONS.get(name, ()) if e == REFUSE else ()))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 5, measurement_log: NaN, gaps, jitter, units in column names, logs without motion, ... for every command
# that reads a log (compare, fit, improve, run --input), and the GP tables (fit-gpr, predict-gpr).

def read_rows(text):
    lines = text.strip("\n").split("\n")
    return lines[0].split(","), [line.split(",") for line in lines[1:]]


def write_rows(header, rows):
    return ",".join(header) + "\n" + "".join(",".join(r) + "\n" for r in rows)


def col(header, name):
    return header.index(name)


def log_mutation(fn):
    """fn(header, rows) changes the lists in place or returns new text."""
    def apply(text):
        header, rows = read_rows(text)
        out = fn(header, rows)
        return out if isinstance(out, str) else write_rows(header, rows)
    return apply


def set_cell(row_index, column, value):
    return log_mutation(lambda h, r: r[row_index].__setitem__(col(h, column), value))


def scale_column(column, factor, rename=None):
    def fn(h, r):
        i = col(h, column)
        for row in r:
            row[i] = "%.10g" % (float(row[i]) * factor)
        if rename:
            h[i] = rename
    return log_mutation(fn)


def map_column(column, f):
    def fn(h, r):
        i = col(h, column)
        for k, row in enumerate(r):
            row[i] = f(k, float(row[i]))
    return log_mutation(fn)


def drop_rows(start, stop):
    return log_mutation(lambda h, r: r.__delitem__(slice(start, stop)))


def compare_fit_at_least(percent):
    def check(d, r):
        try:
            fit = json.loads((d / "out" / "compare.json").read_text())["fit_percent_after"]
        except Exception as e:  # noqa: BLE001
            return "no fit_percent_after in out/compare.json (%s)" % e
        if not isinstance(fit, (int, float)) or fit < percent:
            return "fit %r %% after refitting, expected at least %.0f %% (a column's unit read wrongly?)" % (
                fit, percent)
        return None
    return check


LOG_MUTATIONS = [
    # name, expectation, mutation of log.csv text, --position-column, check of an accepted compare
    ("control", ACCEPT, lambda t: t, None, "fit80"),
    ("nan_cell", REFUSE, set_cell(100, "force_N", "nan"), None, None),
    ("nan_position", REFUSE, set_cell(100, "position_m", "NaN"), None, None),
    ("inf_cell", REFUSE, set_cell(100, "force_N", "inf"), None, None),
    ("minus_inf_cell", REFUSE, set_cell(100, "force_N", "-Infinity"), None, None),
    ("overflow_cell", REFUSE, set_cell(100, "force_N", "1e999"), None, None),
    ("huge_values", REFUSE, scale_column("force_N", 1e300), None, None),
    ("huge_positions", REFUSE, scale_column("position_m", 1e300), None, None),
    ("empty_cell", REFUSE, set_cell(100, "force_N", ""), None, None),
    ("text_cell", REFUSE, set_cell(100, "force_N", "abc"), None, None),
    ("hex_cell", REFUSE, set_cell(100, "force_N", "0x1p3"), None, None),
    ("missing_cell", REFUSE, log_mutation(lambda h, r: r[100].pop()), None, None),
    ("extra_cell", REFUSE, log_mutation(lambda h, r: r[100].append("1")), None, None),
    ("time_backwards", REFUSE, set_cell(100, "time_s", "0.05"), None, None),
    ("time_all_zero", REFUSE, map_column("time_s", lambda k, v: "0"), None, None),
    ("time_huge_offset", EITHER, map_column("time_s", lambda k, v: "%.17g" % (1e300 + v)), None, None),
    ("time_negative_start", EITHER, map_column("time_s", lambda k, v: "%.10g" % (v - 100.0)), None, None),
    ("repeated_stamps", EITHER, log_mutation(lambda h, r: r.insert(101, list(r[100]))), None, None),
    ("jitter", EITHER, map_column("time_s", lambda k, v: "%.10g" % (v + 1e-5 * math.sin(7.7 * k))), None, None),
    ("gap", EITHER, drop_rows(1000, 1600), None, None),
    ("irregular", EITHER, map_column("time_s", lambda k, v: "%.10g" % (v + (0.0004 if k % 3 == 1 else 0.0))),
     None, None),
    ("header_only", REFUSE, lambda t: t.split("\n")[0] + "\n", None, None),
    ("one_row", REFUSE, lambda t: "\n".join(t.split("\n")[:2]) + "\n", None, None),
    ("three_rows", REFUSE, lambda t: "\n".join(t.split("\n")[:4]) + "\n", None, None),
    ("missing_force_column", REFUSE, log_mutation(lambda h, r: (h.pop(), [row.pop() for row in r])), None, None),
    ("missing_position_column", REFUSE, log_mutation(lambda h, r: h.__setitem__(1, "pos")), None, None),
    ("duplicate_column", REFUSE, log_mutation(lambda h, r: h.__setitem__(2, "position_m")), None, None),
    # "t" is the EMPS benchmark's own name for its time column: read as seconds, as documented.
    ("no_time_column", EITHER, log_mutation(lambda h, r: h.__setitem__(0, "t")), None, None),
    ("time_ms", EITHER, scale_column("time_s", 1000.0, "time_ms"), None, "fit80"),
    ("time_us", EITHER, scale_column("time_s", 1e6, "time_us"), None, "fit80"),
    ("time_unknown_unit", REFUSE, log_mutation(lambda h, r: h.__setitem__(0, "time_fortnight")), None, None),
    ("position_mm", EITHER, scale_column("position_m", 1000.0, "position_mm"), "position_mm", "fit80"),
    ("position_um", EITHER, scale_column("position_m", 1e6, "position_um"), "position_um", "fit80"),
    ("position_unknown_unit", REFUSE, scale_column("position_m", 1.0, "position_furlong"), "position_furlong", None),
    ("position_column_absent", REFUSE, lambda t: t, "position_nowhere_m", None),
    ("force_kN", EITHER, scale_column("force_N", 1e-3, "force_kN"), None, "fit80"),
    ("no_motion", REFUSE, map_column("position_m", lambda k, v: "0.1"), None, None),
    ("crlf", EITHER, lambda t: t.replace("\n", "\r\n"), None, None),
    ("semicolons", REFUSE, lambda t: t.replace(",", ";"), None, None),
    ("quoted_header", EITHER, lambda t: t.replace("time_s,position_m", '"time_s","position_m"', 1), None, None),
    ("bom", EITHER, lambda t: "\ufeff" + t, None, None),
    ("nul_byte", REFUSE, lambda t: t[:5000] + "\0" + t[5000:], None, None),
    ("escape_in_header", EITHER, lambda t: t.replace("input_V", "in\x1b[31mput_V\x07", 1), None, None),
    ("trailing_blank_lines", EITHER, lambda t: t + "\n\n\n", None, None),
    ("comment_lines", EITHER, lambda t: "# logged by a drive\n" + t, None, None),
    ("million_columns", REFUSE, lambda t: "time_s," + ",".join("c%d" % i for i in range(1000000)) + "\n0\n", None,
     None),
]

LOG_COMMANDS = [
    # name, argv with {P}, fixtures, which mutations (None: all)
    ("compare", ["compare", "ee.json", "--measurement", "{P}", "--out", "out"], ("ee.json",), None),
    ("fit", ["fit", "ee.json", "--measurement", "{P}", "--out", "out"], ("ee.json",), None),
    ("improve", ["improve", "ee.json", "--measurement", "{P}", "--max-effects", "0", "--out", "out"], ("ee.json",),
     {"control", "nan_cell", "huge_values", "time_backwards", "no_motion", "gap", "position_mm", "time_ms",
      "header_only", "missing_force_column"}),
    ("run.input", ["run", "sim.json", "--input", "f={P}:force_N", "--out", "out"], ("sim.json",),
     {"control", "nan_cell", "inf_cell", "overflow_cell", "huge_values", "empty_cell", "text_cell",
      "missing_cell", "time_backwards", "time_all_zero", "header_only", "one_row", "missing_force_column",
      "force_kN", "nul_byte", "semicolons", "time_ms", "time_unknown_unit", "jitter", "gap"}),
]


def table_mutations():
    """The GP training table (fit-gpr) and prediction input (predict-gpr)."""
    return [
        ("control", ACCEPT, lambda t: t),
        ("nan_cell", REFUSE, set_cell(10, "dob_N", "nan")),
        ("inf_position", REFUSE, set_cell(10, "x_m", "inf")),
        ("huge_values", REFUSE, scale_column("dob_N", 1e300)),
        ("huge_positions", REFUSE, scale_column("x_m", 1e300)),
        ("text_cell", REFUSE, set_cell(10, "v_m_s", "fast")),
        ("empty_cell", REFUSE, set_cell(10, "v_m_s", "")),
        ("header_only", REFUSE, lambda t: t.split("\n")[0] + "\n"),
        ("one_row", REFUSE, lambda t: "\n".join(t.split("\n")[:2]) + "\n"),
        # issue 41: two rows gave a 56-feature model without a word
        ("two_rows", REFUSE, lambda t: "\n".join(t.split("\n")[:3]) + "\n"),
        ("nine_rows", REFUSE, lambda t: "\n".join(t.split("\n")[:10]) + "\n"),
        ("missing_column", REFUSE, log_mutation(lambda h, r: h.__setitem__(2, "d"))),
        ("constant_disturbance", EITHER, map_column("dob_N", lambda k, v: "1.5")),
        ("constant_position", EITHER, map_column("x_m", lambda k, v: "0.01")),
        ("one_velocity", EITHER, map_column("v_m_s", lambda k, v: "0.1")),
        ("duplicate_rows", EITHER, log_mutation(lambda h, r: r.extend([list(x) for x in r]))),
        ("position_mm", EITHER, scale_column("x_m", 1000.0, "x_mm")),
        ("pandas_index", EITHER, log_mutation(lambda h, r: (h.insert(0, ""), [row.insert(0, str(i))
                                                                              for i, row in enumerate(r)]))),
        ("crlf", EITHER, lambda t: t.replace("\n", "\r\n")),
        ("nul_byte", REFUSE, lambda t: t[:500] + "\0" + t[500:]),
    ]


def extrapolated_flagged(d, r):
    """predict-gpr: a row whose position is not finite or far outside the trained range (|x| > 10 m) is flagged
    extrapolated = 1."""
    try:
        header, rows = read_rows((d / "p.csv").read_text())
        i = header.index("extrapolated")
        xi = header.index("x_m")
    except Exception as e:  # noqa: BLE001
        return "cannot read the extrapolated column of p.csv (%s)" % e
    bad = []
    for k, row in enumerate(rows):
        x = as_number(row[xi])
        if (x is None or not math.isfinite(x) or abs(x) > 10.0) and as_number(row[i]) != 1.0:
            bad.append(k)
    if bad:
        return "rows %s lie outside the trained range but extrapolated is not 1 there" % bad[:5]
    return None


def family_measurement_log(ctx):
    cases = []
    for command, argv, files, only in LOG_COMMANDS:
        for name, expect, fn, position_column, check in LOG_MUTATIONS:
            if only is not None and name not in only:
                continue
            if command == "run.input" and position_column:
                continue

            def make(d, c, fn=fn):
                (d / "m.csv").write_bytes(fn((c.fixtures / "log.csv").read_text()).encode("utf-8", "surrogatepass"))
            args = subst(argv, P="m.csv")
            if position_column and command != "run.input":
                args += ["--position-column", position_column]
            e = expect
            if command == "run.input" and name in ("no_motion", "huge_positions", "missing_position_column",
                                                    "position_unknown_unit"):
                e = EITHER  # run --input reads only force_N
            if command == "fit" and name == "control":
                e = ACCEPT
            cases.append(Case(id="measurement_log/%s/%s" % (command, name), family="measurement_log", argv=args,
                              expect=e, files=files, make=make,
                              mention=(("m.csv",),) if e == REFUSE else (),
                              check=compare_fit_at_least(80.0) if (check == "fit80" and command == "compare")
                              else None,
                              slow=e != REFUSE and command in ("compare", "improve", "fit"),
                              timeout=240.0 if command == "improve" else None))
    # collinear parameters: one-signed velocity (a ramp): Coulomb and offset cannot be told apart
    def ramp(d, c):
        header, rows = read_rows((c.fixtures / "log.csv").read_text())
        ti, xi = col(header, "time_s"), col(header, "position_m")
        for row in rows:
            row[xi] = "%.10g" % (0.05 * float(row[ti]) + 0.001 * math.sin(3.0 * float(row[ti])))
        (d / "m.csv").write_text(write_rows(header, rows))
    cases.append(Case(id="measurement_log/fit/one_signed_velocity_collinear", family="measurement_log",
                      argv=["fit", "ee.json", "--measurement", "m.csv", "--fit", "friction.coulomb,offset.value",
                            "--out", "out"], expect=REFUSE, files=("ee.json",), make=ramp, slow=True))
    for command in ("fit-gpr", "predict-gpr"):
        for name, expect, fn in table_mutations():
            def make(d, c, fn=fn):
                (d / "t.csv").write_bytes(fn((c.fixtures / "table.csv").read_text()).encode())
            xcol = "x_mm" if name == "position_mm" else "x_m"
            if command == "fit-gpr":
                args = ["fit-gpr", "t.csv", "--position-column", xcol, "--velocity-column", "v_m_s",
                        "--disturbance-column", "dob_N", "-o", "m.json"]
                files = ()
            else:
                args = ["predict-gpr", "model.json", "t.csv", "--position-column", xcol, "--velocity-column",
                        "v_m_s", "-o", "p.csv"]
                files = ("model.json",)
            e = expect
            check = None
            nonfinite_ok = False
            if command == "fit-gpr" and name == "huge_positions":
                e = EITHER  # finite: a fit over 1e298 m is odd but not wrong
            if command == "predict-gpr":
                if name in ("header_only", "one_row", "two_rows", "nine_rows"):
                    e = EITHER  # predicting no row or a few rows is no error
                if name in ("nan_cell", "huge_values", "missing_column", "constant_disturbance"):
                    e = EITHER  # predict-gpr does not read the disturbance column
                if name in ("inf_position", "huge_positions"):
                    e = EITHER  # documented: such rows are predicted with extrapolated = 1
                    check = extrapolated_flagged
                    nonfinite_ok = name == "inf_position"
            mention = (("t.csv",),) if e == REFUSE else ()
            if e == REFUSE and name in ("two_rows", "nine_rows"):
                mention = (("t.csv",), ("at least 10",))  # the minimum is said
            cases.append(Case(id="measurement_log/%s/%s" % (command, name), family="measurement_log", argv=args,
                              expect=e, files=files, make=make, check=check, nonfinite_ok=nonfinite_ok,
                              mention=mention))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 6, output_over_input: outputs that would destroy inputs (issue 30, item 2), each reached by several
# spellings of the same path (./x, sub/../x, absolute, a symbolic link, a hard link).

FILE_SPELLINGS = ["plain", "dot", "dotdot", "absolute", "symlink", "hardlink"]
FOLDER_SPELLINGS = ["plain", "dot", "slash", "absolute", "symlink", "dotdot"]


def spell_file(spelling, rel):
    p = Path(rel)
    name = p.name
    parent = str(p.parent) if str(p.parent) != "." else ""
    join = (lambda n: parent + "/" + n) if parent else (lambda n: n)
    return {
        "plain": rel,
        "dot": "./" + rel,
        "dotdot": join("sub/../" + name),
        "absolute": "{dir}/" + rel,
        "symlink": join("lnk_" + name),
        "hardlink": join("hard_" + name),
    }[spelling]


def prepare_spelling(d, spelling, rel):
    p = d / rel
    if spelling == "dotdot":
        (p.parent / "sub").mkdir(exist_ok=True)
    elif spelling == "symlink":
        os.symlink(p.name, p.parent / ("lnk_" + p.name))
    elif spelling == "hardlink":
        os.link(p, p.parent / ("hard_" + p.name))


def spell_folder(spelling, rel):
    return {"plain": rel, "dot": "./" + rel, "slash": rel + "/", "absolute": "{dir}/" + rel, "symlink": "lnk_" + rel,
            "dotdot": "sub/../" + rel}[spelling]


def prepare_folder_spelling(d, spelling, rel):
    if spelling == "symlink":
        os.symlink(rel, d / ("lnk_" + rel))
    elif spelling == "dotdot":
        (d / "sub").mkdir(exist_ok=True)


def copy_as(src, dst):
    def make(d, ctx):
        (d / dst).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ctx.fixtures / src, d / dst)
    return make


def chain(*makers):
    def make(d, ctx):
        for m in makers:
            if m:
                m(d, ctx)
    return make


SMOOTH_ARGS = ["fit-gpr", "smooth.csv", "--target", "smoothed", "--force-column", "force_N", "--position-column",
               "position_m", "--velocity-column", "velocity_m_s"]

# name, protected input (relative), how it is made, argv with {V} (the output path spelled to reach it), fixtures
OUTPUT_FILE_COLLISIONS = [
    ("draw_onto_diagram", "d.json", copy_as("sim.json", "d.json"), ["draw", "d.json", "-o", "{V}"], ()),
    ("draw_dot_onto_diagram", "d.json", copy_as("sim.json", "d.json"),
     ["draw", "d.json", "--format", "dot", "-o", "{V}"], ()),
    ("fit-gpr_onto_table", "t.csv", copy_as("table.csv", "t.csv"),
     ["fit-gpr", "t.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "--disturbance-column",
      "dob_N", "-o", "{V}"], ()),
    ("fit-gpr_onto_diagram", "hil/pd.json", None, SMOOTH_ARGS + ["--diagram", "hil/pd.json", "-o", "{V}"],
     ("smooth.csv", "hil")),
    ("predict-gpr_onto_model", "m.json", copy_as("model.json", "m.json"),
     ["predict-gpr", "m.json", "table.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "-o", "{V}"],
     ("table.csv",)),
    ("predict-gpr_onto_input", "t.csv", copy_as("table.csv", "t.csv"),
     ["predict-gpr", "model.json", "t.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "-o", "{V}"],
     ("model.json",)),
    ("compare_suggest_onto_diagram", "e.json", copy_as("ee.json", "e.json"),
     ["compare", "e.json", "--measurement", "log.csv", "--suggest", "{V}", "--out", "out"], ("log.csv",)),
    ("compare_write_fitted_onto_diagram", "e.json", copy_as("ee.json", "e.json"),
     ["compare", "e.json", "--measurement", "log.csv", "--write-fitted", "{V}", "--out", "out"], ("log.csv",)),
    ("compare_suggest_onto_measurement", "l.csv", copy_as("log.csv", "l.csv"),
     ["compare", "ee.json", "--measurement", "l.csv", "--suggest", "{V}", "--out", "out"], ("ee.json",)),
    ("compare_write_fitted_onto_measurement", "l.csv", copy_as("log.csv", "l.csv"),
     ["compare", "ee.json", "--measurement", "l.csv", "--write-fitted", "{V}", "--out", "out"], ("ee.json",)),
]

# name, protected input inside folder o/, how it is made, argv with {V} (the --out folder spelled), fixtures
OUTPUT_FOLDER_COLLISIONS = [
    ("run_input_log_is_signals", "o/signals.csv", copy_as("log.csv", "o/signals.csv"),
     ["run", "sim.json", "--input", "f=o/signals.csv:force_N", "--out", "{V}"], ("sim.json",)),
    ("run_diagram_is_summary", "o/summary.json", copy_as("sim.json", "o/summary.json"),
     ["run", "o/summary.json", "--out", "{V}"], ()),
    ("run_diagram_is_report", "o/report.html", copy_as("sim.json", "o/report.html"),
     ["run", "o/report.html", "--out", "{V}"], ()),
    # The DOT text of the run's drawing lives in plot/ of the output folder (issue 28, item 6).
    ("run_diagram_is_drawing", "o/plot/diagram.dot", copy_as("sim.json", "o/plot/diagram.dot"),
     ["run", "o/plot/diagram.dot", "--out", "{V}"], ()),
    ("run_diagram_is_figure", "o/signal_0.png", copy_as("sim.json", "o/signal_0.png"),
     ["run", "o/signal_0.png", "--out", "{V}"], ()),
    ("compare_measurement_is_result", "o/compare.json", copy_as("log.csv", "o/compare.json"),
     ["compare", "ee.json", "--measurement", "o/compare.json", "--out", "{V}"], ("ee.json",)),
    ("compare_diagram_is_report", "o/report.html", copy_as("ee.json", "o/report.html"),
     ["compare", "o/report.html", "--measurement", "log.csv", "--out", "{V}"], ("log.csv",)),
    ("compare_diagram_is_fallback_model", "o/residual_gpr.json", copy_as("ee.json", "o/residual_gpr.json"),
     ["compare", "o/residual_gpr.json", "--measurement", "log.csv", "--out", "{V}"], ("log.csv",)),
    ("fit_diagram_is_fitted", "o/fitted.json", copy_as("ee.json", "o/fitted.json"),
     ["fit", "o/fitted.json", "--measurement", "log.csv", "--out", "{V}"], ("log.csv",)),
    ("fit_measurement_is_summary", "o/fit.json", copy_as("log.csv", "o/fit.json"),
     ["fit", "ee.json", "--measurement", "o/fit.json", "--out", "{V}"], ("ee.json",)),
    ("improve_diagram_is_improved", "o/improved.json", copy_as("ee.json", "o/improved.json"),
     ["improve", "o/improved.json", "--measurement", "log.csv", "--max-effects", "0", "--out", "{V}"],
     ("log.csv",)),
    ("improve_measurement_is_result", "o/improve.json", copy_as("log.csv", "o/improve.json"),
     ["improve", "ee.json", "--measurement", "o/improve.json", "--max-effects", "0", "--out", "{V}"],
     ("ee.json",)),
    ("improve_validation_is_report", "o/report.html", copy_as("val.csv", "o/report.html"),
     ["improve", "ee.json", "--measurement", "log.csv", "--validation", "o/report.html", "--max-effects", "0",
      "--out", "{V}"], ("ee.json", "log.csv")),
    ("stability_diagram_is_result", "o/stability.json", copy_as("loop.json", "o/stability.json"),
     ["stability", "o/stability.json", "--out", "{V}"], ()),
    ("stability_diagram_is_report", "o/report.html", copy_as("loop.json", "o/report.html"),
     ["stability", "o/report.html", "--out", "{V}"], ()),
    ("stability_gpr_is_result", "o/stability.json", copy_as("model.json", "o/stability.json"),
     ["stability", "loop.json", "--gpr", "o/stability.json", "--out", "{V}"], ("loop.json",)),
    ("sweep_file_is_runs_json", "o/runs.json", copy_as("sweep/grid.json", "o/runs.json"),
     ["sweep", "sweep/d.json", "o/runs.json", "--out", "{V}", "--jobs", "1"], ("sweep",)),
    ("sweep_diagram_is_runs_csv", "o/runs.csv", copy_as("sweep/d.json", "o/runs.csv"),
     ["sweep", "o/runs.csv", "sweep/grid.json", "--out", "{V}", "--jobs", "1"], ("sweep",)),
    ("hil_diagram_is_summary", "o/summary.json",
     chain(copy_as("hil/pd.json", "o/summary.json"), copy_as("hil/subsystems/plant.json", "o/subsystems/plant.json")),
     ["hil", "o/summary.json", "--board", "udp", "--port", "9", "--replace", "plant=hil/subsystems/hil_io.json",
      "--duration", "0.05", "--out", "{V}"], ("hil",)),
    ("hil_replacement_is_signals", "o/signals.csv", copy_as("hil/subsystems/hil_io.json", "o/signals.csv"),
     ["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace", "plant=o/signals.csv", "--duration",
      "0.05", "--out", "{V}"], ("hil",)),
]

OUT_IS_INPUT = [
    ("run_out_is_diagram", ["run", "sim.json", "--out", "sim.json"], ("sim.json",)),
    ("compare_out_is_measurement", ["compare", "ee.json", "--measurement", "log.csv", "--out", "log.csv"],
     ("ee.json", "log.csv")),
    ("fit_out_is_diagram", ["fit", "ee.json", "--measurement", "log.csv", "--out", "ee.json"], ("ee.json", "log.csv")),
    ("improve_out_is_diagram", ["improve", "ee.json", "--measurement", "log.csv", "--out", "ee.json"],
     ("ee.json", "log.csv")),
    ("stability_out_is_diagram", ["stability", "loop.json", "--out", "loop.json"], ("loop.json",)),
    ("sweep_out_is_sweep_file", SWEEP[:3] + ["--out", "sweep/grid.json"], ("sweep",)),
    ("hil_out_is_diagram", with_option(HIL, "--out", "hil/pd.json"), ("hil",)),
    ("fit-gpr_output_is_folder_of_inputs", FITGPR[:-1] + ["."], ("table.csv",)),
]


def family_output_over_input(ctx):
    cases = []
    for name, protected, make0, argv, files in OUTPUT_FILE_COLLISIONS:
        for spelling in FILE_SPELLINGS:
            def make(d, c, make0=make0, spelling=spelling, protected=protected):
                if make0:
                    make0(d, c)
                prepare_spelling(d, spelling, protected)
            target = spell_file(spelling, protected)
            mutable = (target,) if spelling == "hardlink" else ()
            cases.append(Case(id="output_over_input/%s/%s" % (name, spelling), family="output_over_input",
                              argv=subst(argv, V=target), expect=EITHER if spelling == "hardlink" else REFUSE,
                              files=files, make=make, mutable=mutable,
                              mention=((Path(protected).name,),) if spelling != "hardlink" else (),
                              slow=spelling == "hardlink" and name.startswith("compare")))
    for name, protected, make0, argv, files in OUTPUT_FOLDER_COLLISIONS:
        for spelling in FOLDER_SPELLINGS:
            def make(d, c, make0=make0, spelling=spelling):
                make0(d, c)
                prepare_folder_spelling(d, spelling, "o")
            cases.append(Case(id="output_over_input/%s/%s" % (name, spelling), family="output_over_input",
                              argv=subst(argv, V=spell_folder(spelling, "o")), expect=REFUSE, files=files,
                              make=make, mention=((Path(protected).name,),)))
    for name, argv, files in OUT_IS_INPUT:
        cases.append(Case(id="output_over_input/%s" % name, family="output_over_input", argv=argv, expect=REFUSE,
                          files=files))
    # sweep-merge into one of its shards (needs the shard fixtures)
    for spelling in FOLDER_SPELLINGS:
        def make(d, c, spelling=spelling):
            shutil.copytree(c.fixtures / "shards/s1", d / "o")
            shutil.copytree(c.fixtures / "shards/s2", d / "s2")
            prepare_folder_spelling(d, spelling, "o")
        cases.append(Case(id="output_over_input/sweep-merge_out_is_a_shard/%s" % spelling,
                          family="output_over_input",
                          argv=["sweep-merge", "o", "s2", "--out", spell_folder(spelling, "o")], expect=REFUSE,
                          make=make, needs_shards=True))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 7, sweep_file: sweep files from someone else (paths out of their folder, huge or absurd counts, bad
# distributions, unknown keys).

SWEEP_MUTATIONS = [
    # name, expectation, sweep JSON (or text), extra files maker
    ("control_grid", ACCEPT, {"diagram": "d.json", "grid": {"k.gain": [1, 2]}}, None),
    ("control_random", ACCEPT, {"diagram": "d.json", "random": {"seed": 3, "samples": 3, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("diagram_escapes_folder", REFUSE, {"diagram": "../../../../../../etc/passwd", "grid": {"k.gain": [1]}}, None),
    ("diagram_absolute", REFUSE, {"diagram": "/etc/passwd", "grid": {"k.gain": [1]}}, None),
    ("diagram_dev_zero", REFUSE, {"diagram": "/dev/zero", "grid": {"k.gain": [1]}}, None),
    ("diagram_fifo", REFUSE, {"diagram": "fifo.json", "grid": {"k.gain": [1]}},
     lambda d, c: os.mkfifo(d / "sweep" / "fifo.json")),
    ("diagram_directory", REFUSE, {"diagram": "folder", "grid": {"k.gain": [1]}},
     lambda d, c: (d / "sweep" / "folder").mkdir()),
    ("diagram_symlink_outside", REFUSE, {"diagram": "link.json", "grid": {"k.gain": [1]}},
     lambda d, c: os.symlink("../sim.json", d / "sweep" / "link.json")),
    ("diagram_missing", REFUSE, {"grid": {"k.gain": [1]}}, None),
    ("diagram_number", REFUSE, {"diagram": 42, "grid": {"k.gain": [1]}}, None),
    ("no_kind", REFUSE, {"diagram": "d.json"}, None),
    ("two_kinds", REFUSE, {"diagram": "d.json", "grid": {"k.gain": [1]}, "list": [{"k.gain": 2}]}, None),
    ("grid_empty", REFUSE, {"diagram": "d.json", "grid": {}}, None),
    ("grid_empty_axis", REFUSE, {"diagram": "d.json", "grid": {"k.gain": []}}, None),
    ("grid_key_without_dot", REFUSE, {"diagram": "d.json", "grid": {"gain": [1]}}, None),
    ("grid_unknown_element", REFUSE, {"diagram": "d.json", "grid": {"nope.gain": [1]}}, None),
    ("grid_unknown_parameter", REFUSE, {"diagram": "d.json", "grid": {"k.gian": [1]}}, None),
    ("grid_string_value", REFUSE, {"diagram": "d.json", "grid": {"k.gain": ["NaN"]}}, None),
    ("grid_null_value", REFUSE, {"diagram": "d.json", "grid": {"k.gain": [None]}}, None),
    ("grid_overflow_literal", REFUSE, '{"diagram": "d.json", "grid": {"k.gain": [1e999]}}', None),
    ("grid_nan_literal", REFUSE, '{"diagram": "d.json", "grid": {"k.gain": [NaN]}}', None),
    ("grid_billion_runs", REFUSE, {"diagram": "d.json", "grid": {
        "k.gain": list(range(1000)), "c.value": list(range(1000)), "defaultExperiment.stopTime": [
            0.01 + i * 1e-5 for i in range(1000)]}}, None),
    ("grid_solver_step_zero", REFUSE, {"diagram": "d.json", "grid": {"solver.step": [0]}}, None),
    # d.json has no state: 1000 logged points over [0, 1e300] s are its exact answer, as `run --set` gives.
    ("grid_stop_time_huge", EITHER, {"diagram": "d.json", "grid": {"defaultExperiment.stopTime": [1e300]}}, None),
    ("grid_solver_unknown", REFUSE, {"diagram": "d.json", "grid": {"solver.type": ["leapfrog"]}}, None),
    ("grid_quantity_misspelled", REFUSE, {"diagram": "d.json", "grid": {"k.gain": [{"value": 1, "unti": "m"}]}},
     None),
    ("set_unknown_parameter", REFUSE, {"diagram": "d.json", "set": {"k.nope": 1}, "grid": {"k.gain": [1]}}, None),
    ("set_nan_string", REFUSE, {"diagram": "d.json", "set": {"c.value": "nan"}, "grid": {"k.gain": [1]}}, None),
    ("unknown_top_key", REFUSE, {"diagram": "d.json", "gird": {"k.gain": [1]}, "grid": {"k.gain": [1]}}, None),
    ("list_empty", REFUSE, {"diagram": "d.json", "list": []}, None),
    ("list_not_objects", REFUSE, {"diagram": "d.json", "list": [1, 2]}, None),
    ("list_entry_unknown_key", REFUSE, {"diagram": "d.json", "list": [{"k.gian": 1}]}, None),
    ("list_entry_failing_run", EITHER, {"diagram": "d.json", "list": [{"k.gain": 1}, {"solver.step": 1.0}]}, None),
    ("random_samples_1e12", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 1e12, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_samples_ten_million", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 10000000,
                                                                             "parameters": {"k.gain": {
                                                                                 "uniform": [0, 1]}}}}, None),
    ("random_samples_zero", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 0, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_samples_negative", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": -5, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_samples_fraction", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2.5, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_seed_negative", REFUSE, {"diagram": "d.json", "random": {"seed": -1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_seed_huge", REFUSE, {"diagram": "d.json", "random": {"seed": 1e300, "samples": 2, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("random_seed_string", REFUSE, {"diagram": "d.json", "random": {"seed": "x", "samples": 2, "parameters": {
        "k.gain": {"uniform": [0, 1]}}}}, None),
    ("uniform_reversed", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [1, 0]}}}}, None),
    ("uniform_equal_bounds", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [1, 1]}}}}, None),
    ("uniform_one_bound", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [1]}}}}, None),
    ("uniform_infinite_width", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [-1.7e308, 1.7e308]}}}}, None),
    ("log_uniform_negative", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"log_uniform": [-1, 1]}}}}, None),
    ("integer_huge", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"integer": [0, 1e300]}}}}, None),
    ("integer_fraction", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"integer": [0.5, 2.5]}}}}, None),
    ("choice_empty", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"choice": []}}}}, None),
    ("unknown_distribution", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"gaussian": [0, 1]}}}}, None),
    ("two_distributions", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {
        "k.gain": {"uniform": [0, 1], "choice": [1]}}}}, None),
    ("random_no_parameters", REFUSE, {"diagram": "d.json", "random": {"seed": 1, "samples": 2, "parameters": {}}},
     None),
]


def family_sweep_file(ctx):
    cases = []
    for name, expect, content, extra in SWEEP_MUTATIONS:
        def make(d, c, content=content, extra=extra):
            if extra:
                extra(d, c)
            (d / "sweep" / "s.json").write_text(content if isinstance(content, str) else dump(content))
            shutil.copy(c.fixtures / "sim.json", d / "sim.json")
        cases.append(Case(id="sweep_file/%s" % name, family="sweep_file",
                          argv=["sweep", "sweep/s.json", "--out", "out", "--jobs", "1"], expect=expect,
                          files=("sweep",), make=make))
        if name.startswith("diagram_"):
            continue
        cases.append(Case(id="sweep_file/with_diagram/%s" % name, family="sweep_file",
                          argv=["sweep", "sweep/d.json", "sweep/s.json", "--out", "out", "--jobs", "1"],
                          expect=expect, files=("sweep",), make=make))
    # Resuming: an "ok" row whose metric is NaN runs again; a runs.csv from another sweep is not mixed in.
    def resumed(tamper):
        def make(d, c):
            r = run_process(c, SWEEP, d, 300.0)
            if r.returncode != 0:
                raise RuntimeError("the first sweep failed: " + first_line(r.stderr))
            tamper(d)
        return make

    def nan_metric(d):
        text = (d / "out" / "runs.csv").read_text().split("\n")
        header = text[0].split(",")
        cells = text[2].split(",")
        cells[header.index("k_final")] = "nan"
        text[2] = ",".join(cells)
        (d / "out" / "runs.csv").write_text("\n".join(text))

    def all_finite_rows(d, r):
        header, rows = read_rows((d / "out" / "runs.csv").read_text())
        k = header.index("k_final")
        bad = [row[0] for row in rows if not math.isfinite(as_number(row[k]) or float("nan"))]
        return "runs %s still hold a non-finite metric after the resume" % bad if bad else None

    def other_values(d):
        text = (d / "out" / "runs.csv").read_text().replace(",2,", ",7,")
        (d / "out" / "runs.csv").write_text(text)

    def garbage_runs(d):
        (d / "out" / "runs.csv").write_bytes(b"\x00\xff garbage\n")

    def runs_fifo(d):
        (d / "out" / "runs.csv").unlink()
        os.mkfifo(d / "out" / "runs.csv")

    for name, tamper, expect, check in (("nan_metric_reruns", nan_metric, EITHER, all_finite_rows),
                                        ("edited_values", other_values, EITHER, all_finite_rows),
                                        ("garbage_runs_csv", garbage_runs, EITHER, None),
                                        ("runs_csv_fifo", runs_fifo, REFUSE, None)):
        cases.append(Case(id="sweep_file/resume/%s" % name, family="sweep_file", argv=SWEEP, expect=expect,
                          files=("sweep",), make=resumed(tamper), check=check,
                          # the first sweep's outputs: a resumed sweep rewrites them, its report too (since issue 27)
                          mutable=("out",)))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 8, sweep_merge: shard folders edited, mixed, damaged or missing (issue 30: sweep-merge merged a shard
# whose values were edited, a NaN metric, conflicting duplicates, manifests that disagree).

def edit_csv_cell(folder, row, column, value):
    header, rows = read_rows((folder / "runs.csv").read_text())
    rows[row][header.index(column) if isinstance(column, str) else column] = value
    (folder / "runs.csv").write_text(write_rows(header, rows))


def edit_manifest(folder, **changes):
    mp = folder / "sweep-shard.json"
    m = json.loads(mp.read_text())
    for k, v in changes.items():
        if v is None:
            m.pop(k, None)
        else:
            m[k] = v
    mp.write_text(nlohmann_dump(m))


def merge_tamper(name):
    def fn(d, rehash=False):
        s1, s2 = d / "s1", d / "s2"
        if name == "control":
            return
        if name == "edited_value":
            edit_csv_cell(s1, 0, "k_final", "7.5")
        elif name == "edited_value_both_files":
            edit_csv_cell(s1, 0, "k_final", "7.5")
            text = (s1 / "runs.json").read_text()
            (s1 / "runs.json").write_text(re.sub(r'"k_final": ?[-0-9.e+]+', '"k_final": 7.5', text, count=1))
        elif name == "nan_metric":
            edit_csv_cell(s1, 0, "k_final", "nan")
        elif name == "inf_metric":
            edit_csv_cell(s1, 0, "k_final", "inf")
        elif name == "empty_metric":
            edit_csv_cell(s1, 0, "k_final", "")
        elif name == "conflicting_duplicate":
            header, rows = read_rows((s1 / "runs.csv").read_text())
            dup = list(rows[0])
            dup[header.index("k_final")] = "123"
            rows.append(dup)
            (s1 / "runs.csv").write_text(write_rows(header, rows))
        elif name == "row_removed":
            header, rows = read_rows((s1 / "runs.csv").read_text())
            (s1 / "runs.csv").write_text(write_rows(header, rows[1:]))
        elif name == "status_failed_to_ok":
            edit_csv_cell(s1, 0, "status", "ok")
        elif name == "extra_column":
            header, rows = read_rows((s1 / "runs.csv").read_text())
            (s1 / "runs.csv").write_text(write_rows(header + ["x"], [r + ["1"] for r in rows]))
        elif name == "header_renamed":
            text = (s1 / "runs.csv").read_text()
            (s1 / "runs.csv").write_text(text.replace("k_final", "k_fine", 1))
        elif name == "manifest_runs_1e12":
            edit_manifest(s1, runs=1000000000000)
        elif name == "manifest_runs_float":
            edit_manifest(s1, runs=4.5)
        elif name == "manifest_runs_negative":
            edit_manifest(s1, runs=-4)
        elif name == "manifest_shards_zero":
            edit_manifest(s1, shards=0)
        elif name == "manifest_shards_huge":
            edit_manifest(s1, shards=10 ** 15)
        elif name == "manifest_shard_out_of_range":
            edit_manifest(s1, shard=7)
        elif name == "manifest_relabelled":
            edit_manifest(s1, shard=1)
        elif name == "manifest_fingerprint":
            edit_manifest(s1, fingerprint="fnv1a64:0000000000000000")
        elif name == "manifest_no_content_hash":
            edit_manifest(s1, content=None)
        elif name == "manifest_garbage":
            (s1 / "sweep-shard.json").write_bytes(b"{\x00\xff")
        elif name == "manifest_array":
            (s1 / "sweep-shard.json").write_text("[]")
        elif name == "manifest_deep":
            (s1 / "sweep-shard.json").write_text("[" * 100000 + "]" * 100000)
        elif name == "manifest_missing":
            (s1 / "sweep-shard.json").unlink()
        elif name == "manifest_fifo":
            (s1 / "sweep-shard.json").unlink()
            os.mkfifo(s1 / "sweep-shard.json")
        elif name == "manifest_dev_zero":
            (s1 / "sweep-shard.json").unlink()
            os.symlink("/dev/zero", s1 / "sweep-shard.json")
        elif name == "runs_csv_missing":
            (s1 / "runs.csv").unlink()
        elif name == "runs_json_missing":
            (s1 / "runs.json").unlink()
        elif name == "runs_csv_fifo":
            (s1 / "runs.csv").unlink()
            os.mkfifo(s1 / "runs.csv")
        elif name == "runs_csv_directory":
            (s1 / "runs.csv").unlink()
            (s1 / "runs.csv").mkdir()
        elif name == "runs_csv_dev_zero":
            (s1 / "runs.csv").unlink()
            os.symlink("/dev/urandom", s1 / "runs.csv")
        elif name == "runs_json_garbage":
            (s1 / "runs.json").write_text('{"runs": 5}')
        else:
            raise ValueError(name)
        if rehash:
            reseal(s1)
    return fn


MERGE_TAMPERS = [
    "edited_value", "edited_value_both_files", "nan_metric", "inf_metric", "empty_metric", "conflicting_duplicate",
    "row_removed", "extra_column", "header_renamed", "manifest_runs_1e12", "manifest_runs_float",
    "manifest_runs_negative", "manifest_shards_zero", "manifest_shards_huge", "manifest_shard_out_of_range",
    "manifest_relabelled", "manifest_fingerprint", "manifest_no_content_hash", "manifest_garbage", "manifest_array",
    "manifest_deep", "manifest_missing", "manifest_fifo", "manifest_dev_zero", "runs_csv_missing",
    "runs_json_missing", "runs_csv_fifo", "runs_csv_directory", "runs_csv_dev_zero", "runs_json_garbage",
]
REHASHABLE = {"edited_value_both_files", "nan_metric", "inf_metric", "empty_metric", "conflicting_duplicate",
              "row_removed", "header_renamed", "manifest_runs_1e12", "manifest_runs_float",
              "manifest_runs_negative", "manifest_shards_zero", "manifest_shards_huge",
              "manifest_shard_out_of_range", "manifest_relabelled", "manifest_fingerprint", "runs_json_garbage",
              "edited_value"}


def family_sweep_merge(ctx):
    cases = []

    def shard_make(tamper, rehash, layout=("s1", "s2")):
        def make(d, c):
            for k, name in enumerate(layout):
                shutil.copytree(c.fixtures / "shards" / ("s%d" % (1 if name == "s1" or name == "s1b" else 2)),
                                d / name, symlinks=True)
            tamper(d, rehash)
        return make

    cases.append(Case(id="sweep_merge/control", family="sweep_merge", argv=["sweep-merge", "s1", "s2", "--out", "m"],
                      expect=ACCEPT, make=shard_make(merge_tamper("control"), False), needs_shards=True))
    for name in MERGE_TAMPERS:
        for rehash in ((False, True) if name in REHASHABLE else (False,)):
            # Both files edited alike and the hash recomputed: a forgery no unkeyed hash can tell from a shard.
            undetectable = rehash and name == "edited_value_both_files"
            cases.append(Case(id="sweep_merge/%s%s" % (name, "/resealed" if rehash else ""), family="sweep_merge",
                              argv=["sweep-merge", "s1", "s2", "--out", "m"], expect=EITHER if undetectable else REFUSE,
                              make=shard_make(merge_tamper(name), rehash), needs_shards=True))
    cases.append(Case(id="sweep_merge/same_shard_twice", family="sweep_merge",
                      argv=["sweep-merge", "s1", "s1b", "--out", "m"], expect=REFUSE,
                      make=shard_make(merge_tamper("control"), False, ("s1", "s1b")), needs_shards=True))
    cases.append(Case(id="sweep_merge/one_shard_missing", family="sweep_merge",
                      argv=["sweep-merge", "s1", "--out", "m"], expect=REFUSE,
                      make=shard_make(merge_tamper("control"), False, ("s1",)), needs_shards=True))
    cases.append(Case(id="sweep_merge/same_folder_twice", family="sweep_merge",
                      argv=["sweep-merge", "s1", "s2", "s1", "--out", "m"], expect=REFUSE,
                      make=shard_make(merge_tamper("control"), False), needs_shards=True))
    cases.append(Case(id="sweep_merge/not_a_shard_folder", family="sweep_merge",
                      argv=["sweep-merge", "s1", "sweep", "--out", "m"], expect=REFUSE, files=("sweep",),
                      make=shard_make(merge_tamper("control"), False, ("s1",)), needs_shards=True))
    cases.append(Case(id="sweep_merge/out_inside_a_shard", family="sweep_merge",
                      argv=["sweep-merge", "s1", "s2", "--out", "s1/merged"], expect=EITHER,
                      make=shard_make(merge_tamper("control"), False), needs_shards=True))
    for kind in ("missing", "dev_null", "fifo", "symlink_loop", "empty_file"):
        def make(d, c, kind=kind):
            shard_make(merge_tamper("control"), False)(d, c)
            if kind == "fifo":
                os.mkfifo(d / "x")
            elif kind == "symlink_loop":
                os.symlink("y", d / "x")
                os.symlink("x", d / "y")
            elif kind == "empty_file":
                (d / "x").write_text("")
        arg = "/dev/null" if kind == "dev_null" else "x"
        cases.append(Case(id="sweep_merge/shard_argument_%s" % kind, family="sweep_merge",
                          argv=["sweep-merge", "s1", "s2", arg, "--out", "m"], expect=REFUSE, make=make,
                          needs_shards=True))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 9, gpr_model: GP model files that mean nothing (weights 1e308, a covariance that is not positive
# semidefinite, zero length scales, huge basis counts) for every reader: predict-gpr, stability --gpr, a gpr block.

def model_mutation(fn):
    def apply(m):
        fn(m)
        return m
    return apply


def mset(path, value):
    def fn(m):
        keys = path.split("/")
        x = m
        for k in keys[:-1]:
            x = x[k]
        if value is KeyError:
            x.pop(keys[-1], None)
        else:
            x[keys[-1]] = value
    return model_mutation(fn)


def negate_covariance(m):
    m["weight_covariance_lower"] = [-abs(v) if i == 0 else v for i, v in enumerate(m["weight_covariance_lower"])]
    # every diagonal entry of the packed lower triangle negative
    n = len(m["weights"])
    k = 0
    for i in range(n):
        k += i
        m["weight_covariance_lower"][k] = -1.0
        k += 1
    return m


def is_diagonal(k):
    """Whether entry k of a packed lower triangle (row by row) lies on the diagonal."""
    row = int((math.isqrt(8 * k + 1) - 1) // 2)
    return k == row * (row + 1) // 2 + row


GPR_MUTATIONS = [
    ("control", ACCEPT, model_mutation(lambda m: None)),
    ("weights_1e308", REFUSE, model_mutation(lambda m: m.__setitem__("weights", [1e308] * len(m["weights"])))),
    ("weights_null", REFUSE, model_mutation(lambda m: m["weights"].__setitem__(3, None))),
    ("weights_string", REFUSE, model_mutation(lambda m: m["weights"].__setitem__(3, "NaN"))),
    ("weights_short", REFUSE, model_mutation(lambda m: m["weights"].pop())),
    ("weights_long", REFUSE, model_mutation(lambda m: m["weights"].append(0.0))),
    ("weights_missing", REFUSE, mset("weights", KeyError)),
    ("covariance_negative_diagonal", REFUSE, negate_covariance),
    ("covariance_short", REFUSE, model_mutation(lambda m: m["weight_covariance_lower"].pop())),
    ("covariance_1e308", REFUSE, model_mutation(lambda m: m.__setitem__(
        "weight_covariance_lower", [1e308] * len(m["weight_covariance_lower"])))),
    # issue 41: 1e200 everywhere is positive semidefinite (rank one) and predicted ± 1e101 without a word
    ("covariance_1e200", REFUSE, model_mutation(lambda m: m.__setitem__(
        "weight_covariance_lower", [1e200] * len(m["weight_covariance_lower"])))),
    ("covariance_diagonal_1e200", REFUSE, model_mutation(lambda m: m.__setitem__(
        "weight_covariance_lower", [1e200 if is_diagonal(k) else v
                                    for k, v in enumerate(m["weight_covariance_lower"])]))),
    ("length_scale_zero", REFUSE, mset("hyperparameters/length_scale_x", 0.0)),
    ("length_scale_negative", REFUSE, mset("hyperparameters/length_scale_xdot", -0.3)),
    ("length_scale_tiny", REFUSE, mset("hyperparameters/length_scale_x", 1e-300)),
    ("period_zero", REFUSE, mset("hyperparameters/period", 0.0)),
    ("period_tiny", REFUSE, mset("hyperparameters/period", 1e-300)),
    ("basis_period_negative", REFUSE, mset("basis/period", -0.0225)),
    ("noise_negative", REFUSE, mset("hyperparameters/noise_variance", -1.0)),
    ("signal_variance_huge", EITHER, mset("hyperparameters/signal_variance_x", 1e300)),
    ("harmonics_billion", REFUSE, mset("basis/harmonics", 1000000000)),
    ("harmonics_negative", REFUSE, mset("basis/harmonics", -1)),
    ("harmonics_fraction", REFUSE, mset("basis/harmonics", 2.5)),
    ("xdot_count_billion", REFUSE, mset("basis/xdot_domain/count", 1000000000)),
    ("xdot_half_width_zero", REFUSE, mset("basis/xdot_domain/half_width", 0.0)),
    ("trained_range_inverted", REFUSE, mset("trained_range/x", [0.3, -0.3])),
    ("trained_range_null", REFUSE, mset("trained_range/x", [None, 0.3])),
    ("mean_null", REFUSE, mset("mean", None)),
    ("mean_huge", EITHER, mset("mean", 1e300)),
    ("kernel_unknown", REFUSE, mset("kernel", "XS")),
    ("format_wrong", REFUSE, mset("format", "something-else")),
    ("version_future", REFUSE, mset("version", 99)),
    ("version_missing", REFUSE, mset("version", KeyError)),
    # issue 41: keys the reader does not know were ignored
    ("unknown_key", REFUSE, mset("extra", 1)),
    ("unknown_nested_key", REFUSE, mset("hyperparameters/lenght_scale_x", 0.1)),
    ("hyperparameters_missing", REFUSE, mset("hyperparameters", KeyError)),
]


def family_gpr_model(ctx):
    cases = []
    readers = [
        ("predict-gpr", ["predict-gpr", "m.json", "table.csv", "--position-column", "x_m", "--velocity-column",
                         "v_m_s", "-o", "p.csv"], ("table.csv",)),
        ("stability", ["stability", "loop.json", "--gpr", "m.json", "--out", "out"], ("loop.json",)),
        ("gpr_block", ["run", "gprd.json", "--set", "gpr.model=m.json", "--out", "out"], ("gprd.json",)),
    ]
    for name, expect, fn in GPR_MUTATIONS:
        def make(d, c, fn=fn):
            m = json.loads((c.fixtures / "model.json").read_text())
            (d / "m.json").write_text(dump(fn(m)))
        for reader, argv, files in readers:
            cases.append(Case(id="gpr_model/%s/%s" % (reader, name), family="gpr_model", argv=argv, expect=expect,
                              files=files, make=make, mention=(("m.json",),) if expect == REFUSE else ()))
    # Predictions far outside the trained range are flagged (issue 30: 1e299 m predicted fully confident).
    def far(d, c):
        rows = [[x, 0.1, 0.0] for x in (0.0, 0.1, 5.0, -40.0, 1e6, 1e299, -1e299)]
        (d / "far.csv").write_text(csv_text(["x_m", "v_m_s", "dob_N"], rows))
    cases.append(Case(id="gpr_model/predict-gpr/far_outside_trained_range", family="gpr_model",
                      argv=["predict-gpr", "model.json", "far.csv", "--position-column", "x_m", "--velocity-column",
                            "v_m_s", "-o", "p.csv"], expect=ACCEPT, files=("model.json",), make=far,
                      check=extrapolated_flagged))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 10, terminal: control bytes (ESC, BEL, CR, OSC) in names, paths, columns and arguments reach the terminal
# escaped, never raw (checked on every case; here they are the point).

ESC = "\x1b[2J\x1b]0;pwned\x07\r"


def family_terminal(ctx):
    cases = []

    def diagram_named(d, c):
        s = json.loads(json.dumps(SIM))
        s["name"] = "n" + ESC
        s["description"] = ESC
        s["metrics"][0]["name"] = "final" + ESC
        (d / "e.json").write_text(dump(s))

    def column_named(d, c):
        (d / "e.csv").write_text((c.fixtures / "log.csv").read_text().replace("force_N", "force" + ESC + "_N", 1))

    def file_named(d, c):
        shutil.copy(c.fixtures / "sim.json", d / ("d" + ESC + ".json"))

    def broken_named(d, c):
        (d / ("d" + ESC + ".json")).write_text("{" + ESC)

    items = [
        ("diagram_name_run", EITHER, ["run", "e.json", "--out", "out"], diagram_named, ()),
        ("diagram_name_draw", EITHER, ["draw", "e.json", "--format", "dot", "-o", "e.dot"], diagram_named, ()),
        ("file_name_run", EITHER, ["run", "d" + ESC + ".json", "--out", "out"], file_named, ()),
        ("missing_file_name", REFUSE, ["run", "no" + ESC + ".json", "--out", "out"], None, ()),
        ("broken_file_name", REFUSE, ["run", "d" + ESC + ".json", "--out", "out"], broken_named, ()),
        ("out_folder_name", EITHER, ["run", "sim.json", "--out", "o" + ESC], None, ("sim.json",)),
        ("set_key", REFUSE, ["run", "sim.json", "--set", "mass" + ESC + ".mass=1", "--out", "out"], None,
         ("sim.json",)),
        ("set_value", REFUSE, ["run", "sim.json", "--set", "mass.mass=1" + ESC, "--out", "out"], None, ("sim.json",)),
        ("unknown_option", REFUSE, ["run", "sim.json", "--b" + ESC], None, ("sim.json",)),
        ("unknown_command", REFUSE, ["r" + ESC + "n"], None, ()),
        ("blocks_type", REFUSE, ["blocks", "rigid" + ESC], None, ()),
        ("map_argument", REFUSE, ["compare", "ee.json", "--measurement", "log.csv", "--map", "x" + ESC, "--out", "o"],
         None, ("ee.json", "log.csv")),
        ("fit_parameter", REFUSE, ["fit", "ee.json", "--measurement", "log.csv", "--fit", "a" + ESC + ".b", "--out",
                                   "o"], None, ("ee.json", "log.csv")),
        ("column_name_compare", EITHER, ["compare", "ee.json", "--measurement", "e.csv", "--no-gpr-fallback",
                                         "--out", "out"], column_named, ("ee.json",)),
        ("position_column_argument", REFUSE, ["compare", "ee.json", "--measurement", "log.csv", "--position-column",
                                              "pos" + ESC, "--out", "out"], None, ("ee.json", "log.csv")),
        ("fit_gpr_column_argument", REFUSE, FITGPR[:5] + ["v" + ESC] + FITGPR[6:], None, ("table.csv",)),
        ("sweep_key", REFUSE, ["sweep", "sweep/s.json", "--out", "out", "--jobs", "1"],
         lambda d, c: (d / "sweep" / "s.json").write_text(dump({"diagram": "d.json", "grid": {
             "k" + ESC + ".gain": [1]}})), ("sweep",)),
        ("sweep_value", REFUSE, ["sweep", "sweep/s.json", "--out", "out", "--jobs", "1"],
         lambda d, c: (d / "sweep" / "s.json").write_text(dump({"diagram": "d.json", "grid": {
             "k.gain": ["x" + ESC]}})), ("sweep",)),
        ("element_name_error", REFUSE, ["run", "e.json", "--out", "out"],
         lambda d, c: (d / "e.json").write_text(dump(dict(SIM, elements=SIM["elements"] + [
             {"name": "x" + ESC, "type": "nosuch"}]))), ()),
    ]
    for name, expect, argv, make, files in items:
        cases.append(Case(id="terminal/%s" % name, family="terminal", argv=argv, expect=expect, make=make,
                          files=files, slow=name == "column_name_compare"))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 11, command_line: unknown commands, options and block types; --help of every command.

COMMANDS = ["run", "compare", "fit", "improve", "blocks", "fit-gpr", "predict-gpr", "hil", "virtual-stage",
            "stability", "sweep", "sweep-merge", "reproduce", "schema", "draw"]


VALID_ARGUMENTS = {
    "run": RUN, "compare": COMPARE, "fit": FIT, "improve": IMPROVE, "blocks": ["blocks"], "fit-gpr": FITGPR,
    "predict-gpr": ["predict-gpr", "model.json", "table.csv", "--position-column", "x_m", "--velocity-column",
                    "v_m_s", "-o", "p.csv"],
    "hil": HIL, "virtual-stage": STAGE, "stability": STAB, "sweep": SWEEP, "sweep-merge": ["sweep-merge", "sweep",
                                                                                          "--out", "m"],
    "reproduce": REPRODUCE, "schema": ["schema"], "draw": ["draw", "sim.json", "-o", "pic.svg"],
}
COMMAND_LINE_FILES = ("sim.json", "ee.json", "log.csv", "val.csv", "table.csv", "smooth.csv", "hil", "sweep",
                      "model.json", "loop.json")


def family_command_line(ctx):
    cases = []
    for command in COMMANDS:
        cases.append(Case(id="command_line/%s/help" % command, family="command_line", argv=[command, "--help"],
                          expect=ACCEPT))
        cases.append(Case(id="command_line/%s/unknown_option" % command, family="command_line",
                          argv=VALID_ARGUMENTS[command] + ["--bogus-option"], expect=REFUSE,
                          mention=("--bogus-option",), files=COMMAND_LINE_FILES))
        cases.append(Case(id="command_line/%s/unexpected_argument" % command, family="command_line",
                          argv=[command, "a", "b", "c", "d"], expect=REFUSE))
    for argv, expect in ((["blocks", "nonexistent_type"], REFUSE), (["blocks", ""], EITHER),
                         (["blocks", "rigid_body"], ACCEPT), (["blocks", "rigid_body", "gain"], REFUSE),
                         (["blocks", "x" * 100000], REFUSE), (["schema"], ACCEPT), (["schema", "--sweep"], ACCEPT),
                         (["--version"], ACCEPT), ([], REFUSE), (["nosuchcommand"], REFUSE), (["RUN"], REFUSE),
                         (["run"], REFUSE), (["compare", "ee.json"], REFUSE), (["--allow-path"], REFUSE),
                         (["--allow-path", "/nonexistent", "run", "sim.json", "--out", "out"], EITHER),
                         (["run", "sim.json", "--out"], REFUSE), (["run", "--", "sim.json"], EITHER),
                         (["run", "sim.json", "--progress", "--quiet", "--out", "out"], REFUSE),
                         (["fit", "ee.json", "--measurement", "log.csv", "--fit", "nosuch.param", "--out", "o"],
                          REFUSE),
                         (["fit", "ee.json", "--measurement", "log.csv", "--fit", ",,,", "--out", "o"], EITHER),
                         (["compare", "ee.json", "--measurement", "log.csv", "--map", "noequals", "--out", "o"],
                          REFUSE),
                         (["compare", "ee.json", "--measurement", "log.csv", "--map", "nosuch=force_N", "--out", "o"],
                          REFUSE),
                         (["compare", "ee.json", "--measurement", "log.csv", "--map", "force=nosuch_N", "--out", "o"],
                          REFUSE),
                         (["compare", "ee.json", "--measurement", "log.csv", "--suggest-effect", "nosuch",
                           "--suggest", "s.json", "--out", "o"], EITHER),
                         (["compare", "ee.json", "--measurement", "log.csv", "--intersample", "xoh", "--out", "o"],
                          REFUSE),
                         (["improve", "ee.json", "--measurement", "log.csv", "--validation-fit", "nosuch.p",
                           "--validation", "val.csv", "--max-effects", "0", "--out", "o"], REFUSE),
                         (["fit-gpr", "table.csv", "--position-column", "x_m", "--velocity-column", "v_m_s",
                           "-o", "m.json"], REFUSE),
                         (["fit-gpr", "table.csv", "--target", "smoothed", "--disturbance-column", "dob_N",
                           "-o", "m.json"], REFUSE),
                         (["fit-gpr", "smooth.csv", "--target", "smoothed", "--force-column", "force_N",
                           "--position-column", "position_m", "--velocity-column", "velocity_m_s", "-o", "m.json"],
                          REFUSE),
                         (["fit-gpr", "smooth.csv", "--target", "smoothed", "--force-column", "force_N",
                           "--position-column", "position_m", "--velocity-column", "velocity_m_s",
                           "--diagram", "sim.json", "-o", "m.json"], REFUSE),
                         (["fit-gpr", "table.csv", "--kernel", "XS", "--disturbance-column", "dob_N", "-o",
                           "m.json"], REFUSE),
                         (["fit-gpr", "table.csv", "--kernel", "DS", "--estimate-period", "--position-column",
                           "x_m", "--velocity-column", "v_m_s", "--disturbance-column", "dob_N", "-o", "m.json"],
                          EITHER),
                         (["stability", "sim.json", "--out", "out"], REFUSE),
                         (["hil", "hil/pd.json", "--board", "quanser", "--replace",
                           "plant=hil/subsystems/hil_io.json", "--duration", "0.05", "--out", "out"], REFUSE),
                         (["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--duration", "0.05"], REFUSE),
                         (["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace", "nosuch=x.json",
                           "--duration", "0.05", "--out", "out"], REFUSE),
                         (["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace", "plant",
                           "--duration", "0.05", "--out", "out"], REFUSE),
                         (["hil", "hil/pd.json", "--board", "udp", "--port", "9", "--replace",
                           "trajectory=hil/subsystems/hil_io.json", "--duration", "0.05", "--out", "out"], REFUSE),
                         (["virtual-stage", "hil/pd.json", "--io", "hil/subsystems/hil_io.json", "--duration",
                           "0.2"], REFUSE),
                         (["virtual-stage", "hil/subsystems/plant.json", "--io", "hil/subsystems/plant.json",
                           "--duration", "0.2"], REFUSE),
                         (["sweep", "sweep/grid.json", "--out", "out", "--shard", "1/2", "--mpi"], REFUSE),
                         (["reproduce", "--quick", "--diagrams", "sweep", "--out", "out"], REFUSE)):
        name = "_".join(a.strip("-") for a in argv if a and a not in ("--out", "out", "o", "-o", "m.json",
                                                                        "--duration", "0.05", "0.2"))
        name = re.sub(r"[^\w.=-]", "_", name)
        name = (name[:60] + "_" + name[-40:] if len(name) > 100 else name) or "no_arguments"
        cases.append(Case(id="command_line/%s" % name, family="command_line", argv=argv, expect=expect,
                          files=COMMAND_LINE_FILES,
                          slow=argv[:1] in (["compare"], ["improve"], ["fit"]) and expect != REFUSE))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 12, output_path: odd output paths (a newline, a quote, very long, a file, under a file, a device, a full
# disk, a folder given as a file).

def family_output_path(ctx):
    cases = []
    outs = [
        ("newline", "o\nx", EITHER), ("quote", "o'\"x", EITHER), ("spaces", "o u t", EITHER),
        ("very_long_component", "o" * 300, REFUSE), ("very_long_path", "/".join(["d" * 200] * 25), REFUSE),
        ("existing_file", "f.txt", REFUSE), ("under_a_file", "f.txt/sub", REFUSE), ("dev_null", "/dev/null", REFUSE),
        ("proc", "/proc/self", REFUSE), ("root_owned_sys", "/sys/kernel", REFUSE), ("empty", "", REFUSE),
        ("dash", "-", EITHER),
        # issue 41: a folder named o*?[x] got a report whose pictures went missing, exit 0: refused now ('?' and '#'
        # end a URL's path, a shell expands * ? [...] in the printed redraw commands)
        ("glob_characters", "o*?[x]", REFUSE),
        ("url_fragment", "o#x", REFUSE),
    ]
    commands = [
        ("run", ["run", "sim.json", "--out", "{O}"], ("sim.json",)),
        ("stability", ["stability", "loop.json", "--out", "{O}"], ("loop.json",)),
        ("sweep", ["sweep", "sweep/d.json", "sweep/grid.json", "--out", "{O}", "--jobs", "1"], ("sweep",)),
    ]
    for cname, argv, files in commands:
        for name, out, expect in outs:
            cases.append(Case(id="output_path/%s/%s" % (cname, name), family="output_path",
                              argv=subst(argv, O=out), expect=expect, files=files,
                              make=lambda d, c: (d / "f.txt").write_text("a file\n"), mutable=(),
                              mention=(("--out",), ("may not hold",)) if name in ("glob_characters", "url_fragment")
                              else ()))
    files_out = [
        ("dev_full", "/dev/full", REFUSE), ("folder", "folder", REFUSE), ("empty", "", EITHER),
        ("under_a_file", "f.txt/x", REFUSE), ("new_folder", "new/deeper/x", EITHER), ("newline", "a\nb", EITHER),
        ("dev_stdout", "/dev/stdout", EITHER), ("trailing_slash", "x/", REFUSE),
        # issue 41: draw -o FIFO waited forever for a reader
        ("fifo_without_reader", "fifo", REFUSE),
    ]
    commands = [
        ("draw", ["draw", "sim.json", "--format", "dot", "-o", "{O}"], ("sim.json",)),
        ("draw_png", ["draw", "sim.json", "--format", "png", "-o", "{O}"], ("sim.json",)),
        ("fit-gpr", FITGPR[:-1] + ["{O}"], ("table.csv",)),
        ("predict-gpr", ["predict-gpr", "model.json", "table.csv", "--position-column", "x_m", "--velocity-column",
                         "v_m_s", "-o", "{O}"], ("model.json", "table.csv")),
        ("compare_suggest", ["compare", "ee.json", "--measurement", "log.csv", "--no-gpr-fallback", "--suggest",
                             "{O}", "--out", "out"], ("ee.json", "log.csv")),
    ]

    def make(d, c):
        (d / "f.txt").write_text("a file\n")
        (d / "folder").mkdir()
        os.mkfifo(d / "fifo")
    for cname, argv, files in commands:
        for name, out, expect in files_out:
            if cname == "draw_png" and name == "dev_stdout":
                continue  # a PNG asked for on standard output is binary there (ESC bytes included) by request
            cases.append(Case(id="output_path/%s/%s" % (cname, name), family="output_path",
                              argv=subst(argv, O=out), expect=expect, files=files, make=make,
                              slow=cname.startswith("compare"),
                              mention=(("fifo",), ("reads",)) if name == "fifo_without_reader" else ()))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 13, interrupted: state that looks complete but is not (issue 30, item 7). The command is killed
# (SIGKILL) mid-run; what it leaves must not pass for a finished result.

def killed_runner(kill_after, argv):
    def runner(case, d, ctx, timeout):
        start = time.monotonic()
        with open(d.parent / (d.name + ".stdout"), "wb") as out, open(d.parent / (d.name + ".stderr"), "wb") as err:
            p = subprocess.Popen([ctx.binary] + argv, cwd=d, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                 env=ctx.env, start_new_session=True)
            try:
                p.wait(timeout=kill_after)
                ended_early = True
            except subprocess.TimeoutExpired:
                ended_early = False
                kill_group(p)
                p.wait()
        r = Result(p.returncode, read_head(d.parent / (d.name + ".stdout")), read_head(d.parent / (d.name + ".stderr")),
                   time.monotonic() - start, killed_on_purpose=not ended_early)
        if ended_early:
            r.note = "ended after %.1f s, before the harness killed it at %.0f s: nothing interrupted" % (
                r.seconds, kill_after)
        return r
    return runner


def interrupted_runner(interrupt_after, argv, sig=signal.SIGINT, grace=30.0):
    """Runs argv, sends `sig` to its process group after `interrupt_after` s (as Ctrl-C in a terminal does) and gives
    it `grace` s to clean up and end; still running then is a hang."""
    def runner(case, d, ctx, timeout):
        start = time.monotonic()
        with open(d.parent / (d.name + ".stdout"), "wb") as out, open(d.parent / (d.name + ".stderr"), "wb") as err:
            p = subprocess.Popen([ctx.binary] + argv, cwd=d, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                 env=ctx.env, start_new_session=True)
            timed_out = False
            try:
                p.wait(timeout=interrupt_after)
                ended_early = True
            except subprocess.TimeoutExpired:
                ended_early = False
                try:
                    os.killpg(p.pid, sig)
                except ProcessLookupError:
                    pass
                try:
                    p.wait(timeout=grace)
                except subprocess.TimeoutExpired:
                    timed_out = True
                    kill_group(p)
                    p.wait()
        r = Result(p.returncode, read_head(d.parent / (d.name + ".stdout")), read_head(d.parent / (d.name + ".stderr")),
                   time.monotonic() - start, timed_out=timed_out, killed_on_purpose=not ended_early)
        if ended_early:
            r.note = "ended after %.1f s, before the harness interrupted it at %.0f s: nothing interrupted" % (
                r.seconds, interrupt_after)
        return r
    return runner


def interrupted_run_cleaned_up(d, r):
    """After an interrupt (SIGINT, SIGTERM): no temporary file left in out/, and the folder marked incomplete
    (summary.json saying "complete": false), never the earlier run's summary.json (issue 41)."""
    if r.note:
        return None
    out = d / "out"
    temporaries = sorted(str(p.relative_to(d)) for p in out.rglob("*") if ".tmp" in p.name) if out.is_dir() else []
    if temporaries:
        return "an interrupted run left its temporary file(s): %s" % ", ".join(temporaries[:3])
    summary = out / "summary.json"
    if not summary.exists():
        return "an interrupted run left no summary.json saying the folder is incomplete"
    try:
        j = json.loads(summary.read_text())
    except ValueError:
        return "an interrupted run left a summary.json that is not JSON"
    if j.get("stale"):
        return "an interrupted run left the earlier run's summary.json"
    if j.get("complete") is not False:
        return "an interrupted run left summary.json with complete = %r" % j.get("complete")
    return None


def stale_run(d, c):
    shutil.copy(c.fixtures / "long.json", d / "long.json")
    (d / "out").mkdir()
    (d / "out" / "summary.json").write_text('{"metrics": {"final_position": 0.5}, "stale": true}\n')
    (d / "out" / "signals.csv").write_text("time_s,position\n0,0\n")
    (d / "out" / "report.html").write_text("<html>an earlier run</html>\n")


def no_stale_run(d, r):
    if r.note:
        return None
    summary = d / "out" / "summary.json"
    if summary.exists() and b'"complete": false' not in summary.read_bytes():
        which = "the earlier run's" if b'"stale"' in summary.read_bytes() else "one that looks complete"
        return "a killed run left out/summary.json (%s)" % which
    return None


def stale_improve(d, c):
    shutil.copy(c.fixtures / "ee.json", d / "ee.json")
    shutil.copy(c.fixtures / "log.csv", d / "log.csv")
    (d / "out").mkdir()
    (d / "out" / "improve.json").write_text('{"complete": true, "stop": "max_effects", "steps": []}\n')


def improve_marked_incomplete(d, r):
    if r.note:
        return None
    p = d / "out" / "improve.json"
    if not p.exists():
        return None
    try:
        j = json.loads(p.read_text())
    except ValueError:
        return "a killed improve left an improve.json that is not JSON"
    if j.get("complete") is not False:
        return "a killed improve left improve.json with complete = %r" % j.get("complete")
    return None


def stale_sweep(d, c):
    shutil.copytree(c.fixtures / "sweep", d / "sweep")
    long_sweep = json.loads(json.dumps(SWEEP_DIAGRAM))
    long_sweep["defaultExperiment"]["stopTime"] = 30.0
    (d / "sweep" / "long.json").write_text(dump(long_sweep))
    (d / "sweep" / "big.json").write_text(dump({"diagram": "long.json", "grid": {"k.gain": list(range(400))}}))


def sweep_rows_whole(d, r):
    if r.note:
        return None
    p = d / "out" / "runs.csv"
    if not p.exists():
        return None
    text = p.read_text()
    if text and not text.endswith("\n"):
        return "a killed sweep left runs.csv with a partial last line"
    header, rows = read_rows(text) if text.strip() else ([], [])
    bad = [row for row in rows if len(row) != len(header)]
    return "a killed sweep left rows of the wrong width in runs.csv" if bad else None


def family_interrupted(ctx):
    return [
        Case(id="interrupted/run_killed_leaves_no_summary", family="interrupted",
             argv=["run", "long.json", "--out", "out"], expect=EITHER, make=stale_run,
             runner=killed_runner(4.0, ["run", "long.json", "--out", "out"]), check=no_stale_run,
             mutable=("out/summary.json", "out/signals.csv", "out/report.html")),
        # issue 41: Ctrl-C left signals.csv.tmpNNNN beside an earlier run's summary.json
        Case(id="interrupted/run_sigint_cleans_up_and_says_incomplete", family="interrupted",
             argv=["run", "long.json", "--out", "out"], expect=EITHER, make=stale_run,
             runner=interrupted_runner(4.0, ["run", "long.json", "--out", "out"]), check=interrupted_run_cleaned_up,
             mutable=("out/summary.json", "out/signals.csv", "out/report.html")),
        Case(id="interrupted/run_sigterm_cleans_up_and_says_incomplete", family="interrupted",
             argv=["run", "long.json", "--out", "out"], expect=EITHER, make=stale_run,
             runner=interrupted_runner(4.0, ["run", "long.json", "--out", "out"], sig=signal.SIGTERM),
             check=interrupted_run_cleaned_up, mutable=("out/summary.json", "out/signals.csv", "out/report.html")),
        Case(id="interrupted/improve_killed_says_incomplete", family="interrupted",
             argv=["improve", "ee.json", "--measurement", "log.csv", "--out", "out"], expect=EITHER,
             make=stale_improve,
             runner=killed_runner(6.0, ["improve", "ee.json", "--measurement", "log.csv", "--out", "out"]),
             check=improve_marked_incomplete, mutable=("out/improve.json",), slow=True),
    ]


# ---------------------------------------------------------------------------------------------------------------
# Family 14, hil_packets: what any local process may send the virtual stage's UDP port (issue 30: one outputs
# packet with NaN, inf or 1e308 volts ended the stage blaming the solver step).

MAGIC, VERSION = 0x4D424856, 1


def packet(kind=3, seq=1, volts=(0.0,) * 8, magic=MAGIC, version=VERSION, counts=(0,) * 8, size=128):
    data = struct.pack("<IHHIQI8i8d8s", magic, version, kind, seq, time.monotonic_ns(), 0, *counts, *volts,
                       b"\0" * 8)
    return (data + b"\0" * max(0, size - len(data)))[:size]


def volts(v, channel=0):
    out = [0.0] * 8
    out[channel] = v
    return tuple(out)


HIL_PACKETS = [
    ("outputs_nan", REFUSE, [packet(volts=volts(float("nan")))]),
    ("outputs_inf", REFUSE, [packet(volts=volts(float("inf")))]),
    ("outputs_minus_inf", REFUSE, [packet(volts=volts(float("-inf")))]),
    ("outputs_1e308", REFUSE, [packet(volts=volts(1e308))]),
    ("outputs_over_limit", REFUSE, [packet(volts=volts(10.5))]),
    ("outputs_under_limit", REFUSE, [packet(volts=volts(-11.0))]),
    ("outputs_at_limit", ACCEPT, [packet(volts=volts(10.0))]),
    ("outputs_nan_unwired_channel", EITHER, [packet(volts=volts(float("nan"), 5))]),
    ("outputs_sequence_jump", ACCEPT, [packet(seq=1), packet(seq=4000000000), packet(seq=2)]),
    ("wrong_magic", ACCEPT, [packet(magic=0xDEADBEEF, volts=volts(float("nan")))]),
    ("wrong_version", ACCEPT, [packet(version=99, volts=volts(float("nan")))]),
    ("unknown_type", ACCEPT, [packet(kind=77)]),
    ("sample_sent_to_stage", ACCEPT, [packet(kind=2)]),
    ("short_datagram", ACCEPT, [packet()[:20]]),
    ("long_datagram", ACCEPT, [packet() + b"\xff" * 900]),
    ("empty_datagram", ACCEPT, [b""]),
    ("request_flood", ACCEPT, [packet(kind=1, seq=k) for k in range(2000)]),
    ("garbage_flood", ACCEPT, [random.Random(k).randbytes(128) for k in range(500)]),
]


def hil_packet_runner(packets):
    def runner(case, d, ctx, timeout):
        start = time.monotonic()
        err_path = d.parent / (d.name + ".stderr")
        with open(err_path, "wb") as err:
            p = subprocess.Popen([ctx.binary] + case.argv, cwd=d, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                 stderr=err, env=ctx.env, start_new_session=True)
            first = b""
            deadline = time.monotonic() + timeout
            while b"\n" not in first and time.monotonic() < deadline:
                ready, _, _ = select.select([p.stdout], [], [], 0.5)
                if ready:
                    chunk = os.read(p.stdout.fileno(), 4096)
                    if not chunk:
                        break
                    first += chunk
            m = re.search(rb"127\.0\.0\.1:(\d+)", first)
            note = ""
            if m:
                sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
                sock.bind(("127.0.0.1", 0))
                for pk in packets:
                    try:
                        sock.sendto(pk, ("127.0.0.1", int(m.group(1))))
                    except OSError as e:
                        note = "send failed: %s" % e
                sock.close()
            else:
                note = "the stage printed no port"
            timed_out = False
            try:
                rest, _ = p.communicate(timeout=max(1.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                timed_out = True
                kill_group(p)
                rest, _ = p.communicate()
        r = Result(p.returncode, (first + rest)[:OUTPUT_CAP], read_head(err_path), time.monotonic() - start,
                   timed_out=timed_out)
        if note and not timed_out and p.returncode == 0:
            r.note = note
        return r
    return runner


def family_hil_packets(ctx):
    cases = []
    argv = ["virtual-stage", "hil/subsystems/plant.json", "--io", "hil/subsystems/hil_io.json", "--port", "0",
            "--duration", "3"]
    for name, expect, packets in HIL_PACKETS:
        cases.append(Case(id="hil_packets/%s" % name, family="hil_packets", argv=argv, expect=expect,
                          files=("hil",), runner=hil_packet_runner(packets),
                          check=lambda d, r: ("packets not delivered: " + r.note) if r.note else None))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 15, odrive_data: a folder the user names explicitly (reproduce --odrive-data DIR) is read or refused (exit 2,
# the file and the reason), never skipped (issue 41: a missing folder, NaN, garbage or a too-short record each gave
# exit 0 with the real-motor step "skipped"). Each refusal comes before the reproduction's long work.

ODRIVE_FILES = ("coggingmap_0_a_16.csv", "slow2_nocomp_0.csv", "slow2_nocomp_1.csv", "slow2_nocomp_2.csv",
                "slow2_slower_nocomp_0.csv")


def odrive_folder(edit=None):
    def make(d, c):
        folder = d / "odrive"
        folder.mkdir()
        for name in ODRIVE_FILES:
            shutil.copy(REPO / "diagrams/odrive/data" / name, folder / name)
        if edit:
            edit(folder)
    return make


def odrive_edit_cell(name, row, column, value):
    def edit(folder):
        header, rows = read_rows((folder / name).read_text())
        rows[row][col(header, column)] = value
        (folder / name).write_text(write_rows(header, rows))
    return edit


def family_odrive_data(ctx):
    items = [
        ("missing_folder", None, "nowhere", ("nowhere",)),
        ("a_file", lambda d, c: (d / "file.csv").write_text("angle_rev,iq_A\n0,0\n"), "file.csv", ("file.csv",)),
        ("empty_folder", lambda d, c: (d / "odrive").mkdir(), "odrive", ("slow2_nocomp_0.csv",)),
        ("record_missing", odrive_folder(lambda f: (f / "slow2_nocomp_1.csv").unlink()), "odrive",
         ("slow2_nocomp_1.csv",)),
        ("nan_cell", odrive_folder(odrive_edit_cell("slow2_nocomp_0.csv", 100, "iq_A", "nan")), "odrive",
         ("slow2_nocomp_0.csv",)),
        ("garbage_record", odrive_folder(lambda f: (f / "slow2_nocomp_2.csv").write_bytes(
            random.Random(41).randbytes(4000))), "odrive", ("slow2_nocomp_2.csv",)),
        ("too_short_record", odrive_folder(lambda f: (f / "slow2_slower_nocomp_0.csv").write_text(
            "".join((f / "slow2_slower_nocomp_0.csv").read_text().splitlines(True)[:6]))), "odrive",
         ("slow2_slower_nocomp_0.csv",)),
        ("map_text_cell", odrive_folder(odrive_edit_cell("coggingmap_0_a_16.csv", 3, "angle_rev", "abc")), "odrive",
         ("coggingmap_0_a_16.csv",)),
    ]
    cases = []
    for name, make, folder, mention in items:
        cases.append(Case(id="odrive_data/reproduce/%s" % name, family="odrive_data",
                          argv=["reproduce", "--quick", "--odrive-data", folder, "--out", "out"], expect=REFUSE,
                          make=make, mention=(("--odrive-data",),) + tuple((m,) for m in mention), exit_code=2,
                          deadline=60.0))
    return cases


# ---------------------------------------------------------------------------------------------------------------
# Family 16, python_module: the same hostile inputs through the Python module (issue 41: Diagram.load took a diagram
# whose subsystem includes itself, which the command line refuses; Diagram.set took a NumPy array for a scalar gain
# and returned None; set(..., nan) said "parse error at line 1, column 1" without the parameter). Each case is a short
# script run by the interpreter that built the module; the error a refusal must raise (ValueError, TypeError, OSError:
# the module's documented types) is printed and exits 2, anything else is a traceback (an internal name: SILENT).

PYTHON_PRELUDE = """
import sys
import numpy
import motionblocks as mb
try:
%s
except (ValueError, TypeError, OSError) as e:
    print("refused [%%s] %%s" %% (type(e).__name__.lower(), e), file=sys.stderr)
    sys.exit(2)
"""


def find_python_module(binary, given):
    """The folder of the motionblocks Python module built beside `binary` (build/<preset>/python), or `given`."""
    folder = Path(given) if given else Path(binary).resolve().parents[1] / "python"
    if any(folder.glob("motionblocks*.so")):
        return folder
    return None


def python_environment(ctx):
    """The interpreter's environment: PYTHONPATH at the module and, for a sanitizer build (the asan preset), the
    sanitizer runtimes preloaded as ctest does (python/CMakeLists.txt)."""
    env = dict(ctx.env)
    env["PYTHONPATH"] = str(ctx.python_module)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    cache = ctx.python_module.parent / "CMakeCache.txt"
    text = cache.read_text(errors="replace") if cache.exists() else ""
    interpreter = re.search(r"^Python_EXECUTABLE:\w+=(.+)$", text, re.MULTILINE)
    ctx.python_interpreter = (interpreter.group(1).strip() if interpreter else
                              "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable)
    if re.search(r"^MB_SANITIZE:BOOL=ON$", text, re.MULTILINE):
        compiler = re.search(r"^CMAKE_CXX_COMPILER:\w+=(.+)$", text, re.MULTILINE)
        compiler = compiler.group(1).strip() if compiler else "c++"
        libraries = []
        for name in ("libasan.so", "libubsan.so"):
            found = subprocess.run([compiler, "-print-file-name=" + name], capture_output=True, text=True,
                                   check=False).stdout.strip()
            if found and os.path.isabs(found):
                libraries.append(found)
        env["LD_PRELOAD"] = ":".join(libraries)
        env["ASAN_OPTIONS"] = "detect_leaks=0"
    return env


def python_runner(script):
    def runner(case, d, ctx, timeout):
        code = PYTHON_PRELUDE % "\n".join("    " + line for line in script.strip("\n").split("\n"))
        r = run_process(ctx, [], d, timeout, command=[ctx.python_interpreter, "-c", code], env=ctx.python_env)
        return r
    return runner


PYTHON_CASES = [
    # name, expectation, script (indented into a try block), extra files, texts a refusal names
    ("load_chain_of_three", ACCEPT, "d = mb.Diagram.load('h.json')\nmb.simulate(d)", "chain", ()),
    ("load_subsystem_including_itself", REFUSE, "mb.Diagram.load('h.json')", "self", ("self.json",)),
    ("load_subsystems_including_each_other", REFUSE, "mb.Diagram.load('h.json')", "mutual", ("a.json",)),
    ("set_scalar_gain", ACCEPT, "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', numpy.float64(2.5))\n"
                                "assert d.get('k.gain') == 2.5", "sweep", ()),
    ("set_numpy_array_on_a_scalar_gain", REFUSE,
     "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', numpy.array([1.0, 2.0, 3.0]))", "sweep",
     ("k.gain", "3 entries")),
    ("set_list_on_a_scalar_gain", REFUSE, "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', [1.0, 2.0])",
     "sweep", ("k.gain",)),
    ("set_nan", REFUSE, "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', float('nan'))", "sweep",
     ("k.gain", "nan")),
    ("set_inf", REFUSE, "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', float('inf'))", "sweep",
     ("k.gain", "inf")),
    ("set_nan_in_a_list", REFUSE,
     "d = mb.Diagram.load('sweep/d.json')\nd.set('k.gain', numpy.array([1.0, numpy.nan]))", "sweep",
     ("k.gain", "nan")),
    ("set_nan_solver_step", REFUSE, "d = mb.Diagram.load('sweep/d.json')\nd.set('solver.step', float('nan'))",
     "sweep", ("solver.step", "nan")),
]


def family_python_module(ctx):
    if ctx.python_module is None:
        ctx.python_note = ("python_module: no motionblocks*.so beside the executable (build the module, e.g. "
                           "cmake --build --preset asan --target motionblocks_python, or give --python-module DIR)")
        return []
    layouts = {
        "chain": lambda d, c: subsystem_files(dict(chain_files(3), **{"h.json": subsystem_parent("sub0.json")}))(d, c),
        "self": subsystem_files({"h.json": subsystem_parent("self.json"),
                                 "self.json": subsystem_parent("self.json", "self", top=False)}),
        "mutual": subsystem_files({"h.json": subsystem_parent("a.json"),
                                   "a.json": subsystem_parent("b.json", "a", top=False),
                                   "b.json": subsystem_parent("a.json", "b", top=False)}),
        "sweep": None,
    }
    cases = []
    for name, expect, script, layout, mention in PYTHON_CASES:
        cases.append(Case(id="python_module/%s" % name, family="python_module", argv=["python3", "-c", script],
                          expect=expect, files=("sweep",) if layout == "sweep" else (), make=layouts[layout],
                          runner=python_runner(script), mention=tuple((m,) for m in mention) if expect == REFUSE
                          else ()))
    return cases


FAMILIES = [
    ("input_file", family_input_file),
    ("numeric_option", family_numeric_option),
    ("set_override", family_set_override),
    ("diagram", family_diagram),
    ("measurement_log", family_measurement_log),
    ("output_over_input", family_output_over_input),
    ("sweep_file", family_sweep_file),
    ("sweep_merge", family_sweep_merge),
    ("gpr_model", family_gpr_model),
    ("terminal", family_terminal),
    ("command_line", family_command_line),
    ("output_path", family_output_path),
    ("interrupted", family_interrupted),
    ("hil_packets", family_hil_packets),
    ("odrive_data", family_odrive_data),
    ("python_module", family_python_module),
]


# ---------------------------------------------------------------------------------------------------------------
# Running and classifying

def kill_group(p):
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def read_head(path, cap=OUTPUT_CAP):
    try:
        with open(path, "rb") as f:
            return f.read(cap)
    except OSError:
        return b""


def first_line(data: bytes) -> str:
    for line in data.decode("utf-8", "backslashreplace").splitlines():
        if line.strip():
            return printable(line.strip())[:300]
    return ""


def printable(text: str) -> str:
    return "".join(c if c.isprintable() or c == " " else "\\x%02x" % ord(c) if ord(c) < 256 else c for c in text)


def printable_block(data: bytes) -> str:
    return "\n".join(printable(line) for line in data.decode("utf-8", "backslashreplace").splitlines())


def display(argv):
    return "motionblocks " + " ".join(printable(shlex.quote(a)) if len(a) < 200 else shlex.quote(a[:60] + "…(%d chars)"
                                      % len(a)) for a in argv)


def run_process(ctx: Context, argv, cwd: Path, timeout: float, command=None, env=None) -> Result:
    start = time.monotonic()
    tag = "%s.%d" % (cwd.name, threading.get_ident())
    out_path = cwd.parent / (tag + ".stdout")
    err_path = cwd.parent / (tag + ".stderr")
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        p = subprocess.Popen(command or [ctx.binary] + list(argv), cwd=cwd, stdin=subprocess.DEVNULL, stdout=out,
                             stderr=err, env=env or ctx.env, start_new_session=True)
        timed_out = False
        try:
            p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
        kill_group(p)  # the time limit, and any child (dot, gnuplot) left behind
        p.wait()
    r = Result(p.returncode, read_head(out_path), read_head(err_path), time.monotonic() - start, timed_out=timed_out)
    for path in (out_path, err_path):
        try:
            path.unlink()
        except OSError:
            pass
    return r


def snapshot(root: Path):
    """Every entry under root: relative path -> (type, content hash or link target). FIFOs are never opened."""
    entries = {}
    for dirpath, dirnames, filenames in os.walk(root):
        for name in dirnames + filenames:
            p = Path(dirpath) / name
            rel = str(p.relative_to(root))
            try:
                st = os.lstat(p)
            except OSError:
                continue
            if stat.S_ISLNK(st.st_mode):
                entries[rel] = ("link", os.readlink(p))
            elif stat.S_ISREG(st.st_mode):
                h = hashlib.sha256()
                with open(p, "rb") as f:
                    for block in iter(lambda: f.read(1 << 20), b""):
                        h.update(block)
                entries[rel] = ("file", h.hexdigest(), st.st_mtime_ns)
            elif stat.S_ISDIR(st.st_mode):
                entries[rel] = ("dir",)
            else:
                entries[rel] = ("special", stat.S_IFMT(st.st_mode))
    return entries


def losses(before, after, mutable):
    lost = []
    for rel, entry in before.items():
        if any(rel == m or rel.startswith(m.rstrip("/") + "/") for m in mutable):
            continue
        now = after.get(rel)
        if now is None:
            lost.append("%s vanished" % rel)
        elif now[:2] != entry[:2]:
            lost.append("%s changed" % rel)
    return lost


def nonfinite_json(value, path=""):
    """Where a parsed JSON result holds NaN or infinity (Python reads NaN/Infinity tokens), or a null among
    numbers (nlohmann writes a non-finite double as null)."""
    found = []
    if isinstance(value, float):
        if not math.isfinite(value):
            found.append(path or "/")
    elif isinstance(value, dict):
        for k, v in value.items():
            if v is None and path.endswith("/metrics"):
                found.append("%s/%s (null metric)" % (path, k))
            found += nonfinite_json(v, "%s/%s" % (path, k))
    elif isinstance(value, list):
        numbers = any(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        for i, v in enumerate(value):
            if v is None and numbers:
                found.append("%s/%d (null among numbers)" % (path, i))
            found += nonfinite_json(v, "%s/%d" % (path, i))
    return found


def nonfinite_outputs(case_dir: Path, before):
    """Non-finite numbers in the JSON and CSV files the command wrote or rewrote."""
    problems = []
    for dirpath, _, filenames in os.walk(case_dir):
        for name in filenames:
            p = Path(dirpath) / name
            rel = str(p.relative_to(case_dir))
            if before.get(rel, ("",))[0] == "file":
                try:
                    st = os.lstat(p)
                except OSError:
                    continue
                if len(before[rel]) > 2 and st.st_mtime_ns == before[rel][2]:
                    continue  # not written by the command
            if not os.path.isfile(p) or os.path.islink(p) or os.path.getsize(p) > 50_000_000:
                continue
            if name.endswith(".json"):
                try:
                    j = json.loads(p.read_bytes())
                except ValueError:
                    problems.append("%s is not valid JSON" % rel)
                    continue
                bad = nonfinite_json(j)
                if bad:
                    problems.append("%s holds non-finite numbers at %s" % (rel, ", ".join(bad[:3])))
            elif name.endswith(".csv"):
                data = p.read_bytes()
                m = NONFINITE_CELL.search(data)
                if m:
                    line = data.count(b"\n", 0, m.start()) + 1
                    problems.append("%s line %d holds %r" % (rel, line, m.group(0).strip(b", ").decode()))
    return problems


def mentions_ok(mention, text):
    missing = []
    for item in mention:
        options = item if isinstance(item, tuple) else (item,)
        options = [o for o in options if o]
        if options and not any(o in text for o in options):
            missing.append(" or ".join(repr(o) for o in options))
    return missing


def classify(case: Case, r: Result, lost, outputs_problems, check_problem):
    err = r.stderr.decode("utf-8", "backslashreplace")
    if r.timed_out:
        return HANG, "no end within %.0f s (killed)" % r.seconds
    if not r.killed_on_purpose:
        if r.returncode is not None and r.returncode < 0:
            return CRASH, "killed by signal %d" % -r.returncode
        if r.returncode is not None and r.returncode >= 128:
            return CRASH, "exit code %d" % r.returncode
    for text in SANITIZER_TEXTS:
        if text in err:
            return CRASH, "stderr has %r" % text
    if lost:
        return LOSS, "; ".join(lost[:3])
    for stream, data in (("stdout", r.stdout), ("stderr", r.stderr)):
        if b"\x1b" in data or b"\x07" in data:
            return SILENT, "a raw %s byte reached the terminal on %s" % (
                "ESC" if b"\x1b" in data else "BEL", stream)
    leak = next((t for t in INTERNAL_TEXTS if t in err), None)
    if leak is None:
        m = INTERNAL_NAME.search(err)
        if m:
            leak = m.group(0)
    if leak:
        return SILENT, "internal text %r in the message" % leak
    if r.killed_on_purpose:
        if check_problem:
            return SILENT, check_problem
        return OK, "interrupted as planned"
    if r.returncode != 0:
        message = re.sub(r"^motionblocks: error:\s*", "", err.strip())
        if case.expect == ACCEPT:
            return REFUSED, "a valid input was refused (exit %d)" % r.returncode
        if len(message.strip()) < 8:
            return SILENT, "refused (exit %d) without a message" % r.returncode
        if len(r.stderr) > MESSAGE_LIMIT:
            return SILENT, "refused with a %d-byte message (it should quote at most 200 characters)" % len(r.stderr)
        missing = mentions_ok(case.mention, err)
        if missing:
            return SILENT, "unclear refusal: the message does not name %s" % ", ".join(missing)
        if case.exit_code is not None and r.returncode != case.exit_code:
            return SILENT, "refused with exit %d, but this is exit %d's case" % (r.returncode, case.exit_code)
        return OK, "refused (exit %d)" % r.returncode
    if case.expect == REFUSE:
        return SILENT, "accepted (exit 0), but must be refused"
    if r.note:
        return ERROR, r.note
    if outputs_problems and not case.nonfinite_ok:
        return SILENT, "exit 0 with " + outputs_problems[0]
    m = NONFINITE_WORD.search(r.stdout)
    if m and not case.nonfinite_ok:
        return SILENT, "exit 0 but stdout prints %r" % m.group(0).decode()
    if check_problem:
        return SILENT, check_problem
    return OK, "accepted"


def copy_fixture(fix: Path, rel: str, d: Path):
    src = fix / rel
    dst = d / rel
    dst.parent.mkdir(parents=True, exist_ok=True)
    if src.is_dir():
        shutil.copytree(src, dst, symlinks=True, dirs_exist_ok=True)
    else:
        shutil.copy(src, dst)


def run_case(case: Case, index: int, ctx: Context, work: Path, timeout: float):
    d = work / ("%04d" % index)
    d.mkdir(parents=True)
    record = {"id": case.id, "family": case.family, "expect": case.expect}
    argv = [a.replace("{dir}", str(d)) for a in case.argv]
    record["command"] = display(argv)
    try:
        if case.needs_shards and not ctx.shards_ok:
            raise RuntimeError("no shard fixtures: " + ctx.shard_note)
        for rel in case.files:
            copy_fixture(ctx.fixtures, rel, d)
        if case.make:
            case.make(d, ctx)
    except Exception as e:  # noqa: BLE001
        record.update({"class": ERROR, "reason": "harness setup failed: %s" % e, "returncode": None, "seconds": 0.0,
                       "stderr": "", "stdout": "", "case_dir": str(d)})
        return record
    before = snapshot(d)
    limit = case.timeout if case.timeout and case.timeout > timeout else timeout
    if case.deadline:
        limit = case.deadline
    if case.runner:
        r = case.runner(case, d, ctx, limit)
    else:
        r = run_process(ctx, argv, d, limit)
    after = snapshot(d)
    lost = losses(before, after, case.mutable)
    outputs = nonfinite_outputs(d, before) if r.returncode == 0 and not r.timed_out else []
    check_problem = None
    if case.check and (r.returncode == 0 or r.killed_on_purpose) and not r.timed_out:
        try:
            check_problem = case.check(d, r)
        except Exception as e:  # noqa: BLE001
            check_problem = "the check of the result failed: %s" % e
    cls, reason = classify(case, r, lost, outputs, check_problem)
    record.update({"class": cls, "reason": reason, "returncode": r.returncode, "seconds": round(r.seconds, 2),
                   "stderr": first_line(r.stderr), "stdout": first_line(r.stdout), "case_dir": str(d)})
    if cls != OK:  # what the user saw, for the report
        record["stderr_text"] = printable_block(r.stderr[:4000])
        record["stdout_text"] = printable_block(r.stdout[:2000])
    return record


def select_quick(cases, per_family=6):
    """A deterministic subset: per family, up to per_family cases spread evenly over its (fast) cases, controls
    first."""
    chosen = []
    by_family = {}
    for c in cases:
        by_family.setdefault(c.family, []).append(c)
    for family, items in by_family.items():
        fast = [c for c in items if not c.slow and not (c.timeout and c.timeout > DEFAULT_TIMEOUT)]
        controls = [c for c in fast if c.expect == ACCEPT][:1]
        rest = [c for c in fast if c not in controls]
        n = min(len(rest), max(0, per_family - len(controls)))
        picks = [rest[int(i * len(rest) / n)] for i in range(n)] if n else []
        chosen += controls + picks
    return chosen


# The share of each family's generated cases that the standard run keeps (spread evenly over the family, controls
# and cases with a result check always kept): about 1000 cases, half an hour under ASan on 2 cores; --all runs
# every generated case (over 2000).
STANDARD_SHARE = {
    "input_file": 0.3, "numeric_option": 0.35, "set_override": 0.5, "diagram": 0.55, "measurement_log": 0.7,
    "output_over_input": 0.4, "sweep_file": 0.6, "sweep_merge": 1.0, "gpr_model": 0.6, "terminal": 1.0,
    "command_line": 0.5, "output_path": 0.5, "interrupted": 1.0, "hil_packets": 1.0,
}


def select_standard(cases):
    chosen = []
    position = {}
    for c in cases:
        k = position.get(c.family, 0)
        position[c.family] = k + 1
        share = STANDARD_SHARE.get(c.family, 1.0)
        if c.expect == ACCEPT or c.check is not None or math.floor((k + 1) * share) != math.floor(k * share):
            chosen.append(c)
    return chosen


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--motionblocks", required=True, help="the motionblocks executable to test")
    ap.add_argument("--quick", action="store_true", help="a deterministic subset over every family (about 100 cases)")
    ap.add_argument("--all", action="store_true",
                    help="every generated case (over 2000) instead of the standard run (about 1000, spread over "
                         "every variant of every family)")
    ap.add_argument("--out", help="folder for report.json and the folders of the cases that failed")
    ap.add_argument("--jobs", type=int, default=1, help="cases run at once (default 1)")
    ap.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT,
                    help="seconds a case may take before it counts as a hang (default %(default)s; a few cases that "
                         "do real work get more)")
    ap.add_argument("--family", action="append", help="run only this family (repeatable)")
    ap.add_argument("--case", action="append", help="run only cases whose id contains this text (repeatable)")
    ap.add_argument("--list", action="store_true", help="list the case ids and exit")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folder of every case")
    ap.add_argument("--python-module", help="folder of the built motionblocks Python module (default: "
                                            "build/<preset>/python beside the executable; the python_module family "
                                            "is skipped, with a note, when there is none)")
    args = ap.parse_args()

    binary = os.path.abspath(args.motionblocks)
    if not os.access(binary, os.X_OK):
        print("hostile: %s is not an executable" % binary, file=sys.stderr)
        return 2
    root = Path(tempfile.mkdtemp(prefix="mb_hostile_"))
    env = dict(os.environ)
    env.pop("MOTIONBLOCKS_DATA", None)
    env["TMPDIR"] = str(root)
    ctx = Context(binary=binary, fixtures=root / "fixtures", env=env,
                  python_module=find_python_module(binary, args.python_module))
    if ctx.python_module is not None:
        ctx.python_env = python_environment(ctx)
    started = time.monotonic()
    try:
        write_fixtures(ctx.fixtures)
        cases = []
        for name, generate in FAMILIES:
            if args.family and name not in args.family:
                continue
            cases += generate(ctx)
        ids = [c.id for c in cases]
        dupes = sorted({i for i in ids if ids.count(i) > 1})
        if dupes:
            print("hostile: duplicate case ids: %s" % dupes[:5], file=sys.stderr)
            return 2
        if args.quick:
            cases = select_quick(cases)
        elif not args.all:
            cases = select_standard(cases)
        if args.case:
            cases = [c for c in cases if any(s in c.id for s in args.case)]
        if args.list:
            for c in cases:
                print("%-80s %-7s %s" % (c.id, c.expect, display(c.argv)))
            print("%d cases" % len(cases))
            return 0
        if any(c.needs_shards for c in cases):
            build_shards(ctx)
        work = root / "cases"
        work.mkdir()
        records = [None] * len(cases)
        done = 0
        lock = threading.Lock()
        progress = sys.stderr.isatty()

        def one(i):
            nonlocal done
            rec = run_case(cases[i], i, ctx, work, args.timeout)
            with lock:
                done += 1
                if progress:
                    print("\r" + " " * 90 + "\r", end="", file=sys.stderr)
                if rec["class"] != OK:  # as soon as it is known: a long run shows its findings as it goes
                    print(failure_line(rec), flush=True)
                if progress:
                    print("[%d/%d] %s" % (done, len(cases), cases[i].id[:70]), end="", file=sys.stderr, flush=True)
            return i, rec
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for i, rec in pool.map(one, range(len(cases))):
                records[i] = rec
                if rec["class"] == OK and not args.keep:
                    shutil.rmtree(rec["case_dir"], ignore_errors=True)
        if progress:
            print("\r" + " " * 90 + "\r", end="", file=sys.stderr)
        elapsed = time.monotonic() - started

        failed = [r for r in records if r["class"] != OK]
        counts = {k: sum(1 for r in records if r["class"] == k) for k in CLASSES}
        families = {}
        for r in records:
            f = families.setdefault(r["family"], {k: 0 for k in CLASSES})
            f[r["class"]] += 1
        print("per family: " + "; ".join("%s %d/%d ok" % (f, v[OK], sum(v.values())) for f, v in families.items()))
        print("per class: " + ", ".join("%s %d" % (k, v) for k, v in counts.items()))
        if ctx.shard_note:
            print("note: " + ctx.shard_note)
        if ctx.python_note and (not args.family or "python_module" in args.family):
            print("note: " + ctx.python_note)
        print("hostile: %d passed, %d failed (%d cases in %.0f s)" % (counts[OK], len(failed), len(records), elapsed))
        if args.out:
            out = Path(args.out)
            out.mkdir(parents=True, exist_ok=True)
            kept = out / "failed_cases"
            if kept.exists():
                shutil.rmtree(kept)
            for r in failed:
                src = Path(r["case_dir"])
                if src.exists():
                    dst = kept / r["id"].replace("/", "__")[:200]
                    shutil.copytree(src, dst, symlinks=True, ignore_dangling_symlinks=True,
                                    copy_function=copy_regular_only)
                    r["case_dir"] = str(dst)
            report = {"motionblocks": binary, "quick": args.quick, "jobs": args.jobs, "timeout_s": args.timeout,
                      "seconds": round(elapsed, 1), "counts": counts, "families": families, "cases": records}
            (out / "report.json").write_text(json.dumps(report, indent=1, ensure_ascii=False) + "\n")
        return 1 if failed else 0
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
        else:
            print("kept %s" % root, file=sys.stderr)


def failure_line(r):
    return "%s  %s  %s  | %s | %s" % (r["id"], r["class"], r["reason"], r["command"][:300],
                                      r["stderr"] or r["stdout"])


def copy_regular_only(src, dst):
    """copytree's copy of one entry: regular files only (a FIFO or a device is not opened)."""
    st = os.lstat(src)
    if stat.S_ISREG(st.st_mode):
        shutil.copy2(src, dst)


if __name__ == "__main__":
    sys.exit(main())
