#!/usr/bin/env python3
"""Every command README.md shows runs as written on a fresh clone (issue 28, item 1).

What is run, in README order:
  - every line of a ```sh block (a line ending in "\\" continues on the next);
  - the commands written inline in the prose, `build/release/tools/motionblocks ...` and `PYTHONPATH=... python3 ...`;
  - a ```json block whose paragraph says "Save this as `NAME`" is written to NAME first (the minimal diagram).

What is skipped, and why (each is said in the output):
  - `make ...` (make demo, make test, make bench...): they install Debian packages and build everything; the
    README's other commands stand for them, and CI runs `make test` itself;
  - `apt`, `apt-get`, `sudo`, `pip` lines: they change the machine, not the checkout;
  - `hil` with a board other than `udp` (a Quanser board is hardware); the `udp` board talks to the virtual stage
    started by the line before, which needs no hardware, so it runs, except in a sanitizer build (--sanitizers; the
    asan preset and make test's UBSan build): there the 1 kHz loop misses its deadlines (ASan: 10 overruns in a row
    within 0.13 s; under ctest both processes share the test's one core) and safe-stops with exit 1, as it is meant
    to; MB_README_REALTIME=1 runs the pair anyway;
  - an inline command with a placeholder (an upper-case word such as COMMAND, FILE, N, or "..."/"…");
  - the Python lines when no module folder is given (--python-path), i.e. a build without MB_PYTHON;
  - the slowest commands (SLOW below) unless MB_README_SLOW=1: `reproduce` takes ~10 s in a Release build and
    ~45 s under AddressSanitizer, where the rest of the README takes ~160 s on 2 cores.
  - in a sanitizer build, the commands whose --out folder is one of scripts/readme_figures.py's README_RUNS: the
    `readme_figures` test runs each of them as written and checks its figures, and under the sanitizers the two
    tests running them twice cost ~5 min (improve alone 163 s); MB_README_SLOW=1 runs them here too.

How: the repository's tracked files (git ls-files; their working-tree contents, so an edited README is what is
tested) are copied into a temporary folder, which stands for the clone's root: the commands write their out/ there,
never into the checkout. `build/release/tools/motionblocks` there is a link to the binary under test, which is also
first on PATH as `motionblocks`; `build/release/python` links to the Python module's folder. So each command runs
exactly as the README writes it. No shell is involved: a line is split with shlex (comments dropped), leading
NAME=value words become the environment, `&&` and `;` chain commands, `|` pipes them, a trailing `&` starts a
background process (stopped by its process id at the end of its block). Any other shell syntax (redirection, `$`,
backquotes, `||`, globs) is an error here: write the README's command without it. A command that exits non-zero,
or runs over its timeout, fails the test naming its README line.

Usage: readme_commands_test.py --motionblocks BUILD/tools/motionblocks [--source DIR] [--python-path DIR]
           [--python-env NAME=VALUE ...] [--sanitizers] [--timeout SECONDS] [--keep]
"""

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

# Commands slower than ~1 min under AddressSanitizer (a few seconds in a Release build): run only with
# MB_README_SLOW=1. Matched against the command's words after the program.
SLOW = [
    ("reproduce", "the paper's whole reproduction: ~10 s Release, ~45 s under ASan"),
]
SLOW_ENV = "MB_README_SLOW"
# Commands that keep a real-time deadline (and the server started for them): not in a sanitizer build unless
# MB_README_REALTIME=1.
REALTIME = ("hil", "virtual-stage")
REALTIME_ENV = "MB_README_REALTIME"

MOTIONBLOCKS_PATH = "build/release/tools/motionblocks"
PYTHON_PATH = "build/release/python"
OPERATORS = {"&&", ";", "|", "&"}
PLACEHOLDER = re.compile(r"(^|\s)[A-Z][A-Z_]*(\s|$)|\.\.\.|…")


class Command:
    """One README command: where it is and what it says."""

    def __init__(self, line, text, block, inline=False):
        self.line = line      # 1-based line of README.md where it starts
        self.text = text      # as written (continuations joined)
        self.block = block    # index of its code block (inline commands: their own)
        self.inline = inline  # written in the prose, not in a code block

    def where(self):
        return f"README.md:{self.line}"


def extract(readme_lines):
    """Returns (commands, files): the commands in README order, and {name: text} of the files to save first."""
    commands, files = [], {}
    in_block, language, block_start, block_lines = False, "", 0, []
    block_index = 0
    paragraph, last_paragraph = [], []
    for number, raw in enumerate(readme_lines, start=1):
        line = raw.rstrip("\n")
        fence = re.match(r"^\s*```(\w*)\s*$", line)
        if fence and not in_block:
            in_block, language, block_start, block_lines = True, fence.group(1), number, []
            continue
        if fence and in_block:
            in_block = False
            block_index += 1
            if language == "sh":
                pending, start = "", 0
                for offset, text in enumerate(block_lines):
                    if not pending:
                        start = block_start + 1 + offset
                    if text.rstrip().endswith("\\"):
                        pending += text.rstrip()[:-1] + " "
                        continue
                    command = " ".join((pending + text).split())
                    pending = ""
                    if command and not command.startswith("#"):
                        commands.append(Command(start, command, block_index))
            elif language == "json":  # the paragraph just before the block says what to save it as
                saved = re.search(r"[Ss]ave this as `([^`/]+)`", " ".join(paragraph or last_paragraph))
                if saved:
                    files[saved.group(1)] = "\n".join(block_lines) + "\n"
            paragraph, last_paragraph = [], []
            continue
        if in_block:
            block_lines.append(line)
            continue
        if line.strip():
            paragraph.append(line)
        elif paragraph:
            last_paragraph, paragraph = paragraph, []
        for span in re.findall(r"`([^`]+)`", line):
            if span.startswith(MOTIONBLOCKS_PATH + " ") or span.startswith("PYTHONPATH="):
                block_index += 1
                commands.append(Command(number, span, block_index, inline=True))
    return commands, files


def split_line(text):
    """shlex words of a line, operators apart: [[stage words], op, [stage words], ...]; ValueError for shell
    syntax this test does not run."""
    # What a shell would expand: $ and backquotes outside single quotes, globs outside any quotes.
    outside_single = re.sub(r"'[^']*'", "''", text)
    outside_quotes = re.sub(r'"[^"]*"', '""', outside_single)
    outside_single, outside_quotes = re.sub(r"#.*", "", outside_single), re.sub(r"#.*", "", outside_quotes)
    if re.search(r"[$`]", outside_single) or re.search(r"[*?\[]", outside_quotes):
        raise ValueError("variables, backquotes or globs need a shell")
    lexer = shlex.shlex(text, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    words = list(lexer)
    parts, current = [], []
    for word in words:
        if word in OPERATORS:
            if not current:
                raise ValueError(f"'{word}' with no command before it")
            parts += [current, word]
            current = []
        elif set(word) <= set("&|;<>()"):
            raise ValueError(f"the shell syntax '{word}' (write the command without it)")
        else:
            current.append(word)
    if current:
        parts.append(current)
    elif parts and parts[-1] != "&":
        raise ValueError(f"'{parts[-1]}' ends the line")
    return parts


def figure_run_folders(source):
    """The --out folders of the README commands that scripts/readme_figures.py runs (its README_RUNS)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("readme_figures", os.path.join(source, "scripts", "readme_figures.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return {folder for _, folder, _ in module.README_RUNS}


def skip_reason(command, python_path, sanitizers=False, figure_runs=frozenset()):
    words = command.text.split()
    program = next((w for w in words if "=" not in w), "")
    if program == "make":
        return "make builds and installs everything (the README's other commands stand for its steps)"
    if program in ("apt", "apt-get", "sudo", "pip", "pip3"):
        return "changes the machine, not the checkout"
    if "hil" in words and "--board" in words and words[words.index("--board") + 1] != "udp":
        return "a hardware board"
    if sanitizers and os.environ.get(REALTIME_ENV) != "1" and any(w in words[1:3] for w in REALTIME):
        return (f"real time at the diagram's sample time: a sanitizer build misses its deadlines and safe-stops; "
                f"{REALTIME_ENV}=1 runs it")
    if command.inline and PLACEHOLDER.search(command.text):
        return "a placeholder, not a command"
    if "PYTHONPATH=" + PYTHON_PATH in words and not python_path:
        return "no Python module given (--python-path: a build without MB_PYTHON)"
    if os.environ.get(SLOW_ENV) != "1":
        for needle, why in SLOW:
            if needle in words[1:3]:
                return f"slow ({why}); {SLOW_ENV}=1 runs it"
        if sanitizers and "--out" in words[:-1] and words[words.index("--out") + 1] in figure_runs:
            return (f"run as written by the readme_figures test, which checks its figures; "
                    f"{SLOW_ENV}=1 runs it here too")
    return ""


def copy_tracked_files(source, root):
    listed = subprocess.run(["git", "-C", source, "ls-files", "-z"], check=True, capture_output=True).stdout
    count = 0
    for name in listed.decode().split("\0"):
        if not name:
            continue
        src, dst = os.path.join(source, name), os.path.join(root, name)
        if not os.path.lexists(src):  # deleted in the working tree: not in a clone made now
            continue
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        if os.path.islink(src):
            os.symlink(os.readlink(src), dst)
        else:
            shutil.copy2(src, dst)
        count += 1
    return count


def link(target, name):
    os.makedirs(os.path.dirname(name), exist_ok=True)
    os.symlink(os.path.abspath(target), name)


def tail(text, lines=15):
    return "\n".join(text.decode(errors="replace").splitlines()[-lines:])


def run_command(command, root, env, python_env, timeout, background):
    """Runs one README command (its chains and pipelines) in `root`; returns "" or why it failed."""
    try:
        parts = split_line(command.text)
    except ValueError as error:
        return f"cannot be run without a shell: {error}"
    # Chains separated by && or ; (each a pipeline of stages joined by |); a trailing & puts the last in the background.
    chains, pipeline = [], []
    for part in parts:
        if part in ("&&", ";", "&"):
            chains.append((pipeline, part == "&"))
            pipeline = []
        elif part != "|":
            pipeline.append(part)
    if pipeline:
        chains.append((pipeline, False))
    for stages, in_background in chains:
        processes = []
        log = None
        if in_background:
            log = tempfile.NamedTemporaryFile(prefix="background_", suffix=".log", dir=root, delete=False)
        for index, words in enumerate(stages):
            stage_env = dict(env)
            while words and re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", words[0]):
                name, value = words[0].split("=", 1)
                stage_env[name] = value
                words = words[1:]
            if not words:
                return "an assignment with no command"
            if "python" in os.path.basename(words[0]):
                stage_env.update(python_env)
            last = index == len(stages) - 1
            try:
                process = subprocess.Popen(
                    words, cwd=root, env=stage_env, stdin=processes[-1].stdout if processes else subprocess.DEVNULL,
                    stdout=log if (last and log) else subprocess.PIPE, stderr=subprocess.STDOUT)
            except OSError as error:
                return f"{words[0]}: {error}"
            if processes:
                processes[-1].stdout.close()  # the next stage holds it now
            processes.append(process)
        if in_background:
            log.close()
            background.append(processes[-1])
            # As a reader waits before typing the next line: until the port it names is bound (a server), or its
            # first output, at most 10 s.
            words = stages[-1]
            port = int(words[words.index("--port") + 1]) if "--port" in words[:-1] else None
            deadline = time.monotonic() + 10.0
            while time.monotonic() < deadline and processes[-1].poll() is None:
                if (port is not None and port_bound(port)) or (port is None and os.path.getsize(log.name) > 0):
                    break
                time.sleep(0.05)
            if processes[-1].poll() is not None:
                with open(log.name, "rb") as f:
                    return f"the background command exited {processes[-1].returncode}:\n{tail(f.read())}"
            continue
        try:
            output, _ = processes[-1].communicate(timeout=timeout)
            for p in processes[:-1]:
                p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            for p in processes:
                p.kill()
                p.wait()
            return f"ran over {timeout:.0f} s"
        failed = [p.returncode for p in processes if p.returncode != 0]
        if failed:
            return f"exited {failed[-1]}:\n{tail(output)}"
    return ""


def port_bound(port):
    """Whether a local UDP or TCP socket is bound to `port` (Linux: /proc/net)."""
    for table in ("udp", "udp6", "tcp", "tcp6"):
        try:
            with open(f"/proc/net/{table}", encoding="ascii") as f:
                next(f)
                for row in f:
                    if int(row.split()[1].rsplit(":", 1)[1], 16) == port:
                        return True
        except OSError:
            continue
    return False


def stop_background(background):
    """Stops the background processes this test started (by their process ids), as `kill %1` would."""
    for process in background:
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
    background.clear()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionblocks", required=True, help="the motionblocks binary under test")
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--source", default=os.path.dirname(os.path.dirname(here)),
                        help="the repository (default: this file's)")
    parser.add_argument("--python-path", default="", help="the folder of the built Python module (optional)")
    parser.add_argument("--python-env", action="append", default=[], metavar="NAME=VALUE",
                        help="environment for the Python lines only (LD_PRELOAD of the sanitizers' runtime)")
    parser.add_argument("--timeout", type=float, default=600.0, help="seconds per command")
    parser.add_argument("--sanitizers", action="store_true",
                        help="the binary is a sanitizer build: real-time commands are skipped (see REALTIME)")
    parser.add_argument("--keep", action="store_true", help="keep the temporary clone (its path is printed)")
    args = parser.parse_args()

    binary = os.path.abspath(args.motionblocks)
    if not os.access(binary, os.X_OK):
        sys.exit(f"{binary}: no such executable")
    with open(os.path.join(args.source, "README.md"), encoding="utf-8") as f:
        commands, files = extract(f.readlines())
    if not commands:
        sys.exit("README.md: no commands found")

    figure_runs = figure_run_folders(args.source)
    root = tempfile.mkdtemp(prefix="mb_readme_")
    started = time.monotonic()
    failures, ran, skipped = [], 0, 0
    background = []
    try:
        print(f"{copy_tracked_files(args.source, root)} tracked files copied to {root}", flush=True)
        link(binary, os.path.join(root, MOTIONBLOCKS_PATH))
        bin_dir = os.path.join(root, ".readme-bin")
        link(binary, os.path.join(bin_dir, "motionblocks"))
        if args.python_path:
            link(args.python_path, os.path.join(root, PYTHON_PATH))
        for name, text in files.items():
            with open(os.path.join(root, name), "w", encoding="utf-8") as f:
                f.write(text)
            print(f"saved {name} from README.md", flush=True)
        env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ.get("PATH", ""), MOTIONBLOCKS_DATA=root,
                   PYTHONDONTWRITEBYTECODE="1", MPLBACKEND="Agg")
        python_env = dict(item.split("=", 1) for item in args.python_env)
        block = None
        for command in commands:
            if command.block != block:
                stop_background(background)
                block = command.block
            reason = skip_reason(command, args.python_path, args.sanitizers, figure_runs)
            if reason:
                skipped += 1
                print(f"skip {command.where()}: {command.text}\n     ({reason})", flush=True)
                continue
            t0 = time.monotonic()
            error = run_command(command, root, env, python_env, args.timeout, background)
            ran += 1
            status = "FAIL" if error else "ok"
            print(f"{status:4} {command.where()} ({time.monotonic() - t0:.1f} s): {command.text}", flush=True)
            if error:
                failures.append(f"{command.where()}: `{command.text}` {error}")
        stop_background(background)
    finally:
        stop_background(background)
        if args.keep:
            print(f"kept {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)
    print(f"{ran} README commands run, {skipped} skipped, {len(failures)} failed in "
          f"{time.monotonic() - started:.0f} s")
    if failures:
        print("\n".join(["", "Failed (fix README.md if the command is wrong):"] + failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
