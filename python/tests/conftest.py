"""Shared fixtures of the Python module's tests: where the sources, data and the command line are.

ctest sets MB_SOURCE_DIR and MB_COMMAND (python/CMakeLists.txt); the command line is run
as the reference the module must agree with (an argument list, no shell)."""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("MB_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DIAGRAMS = SOURCE / "diagrams"
EMPS = DIAGRAMS / "emps"
CONVENTIONAL = DIAGRAMS / "paper" / "conventional.json"


@pytest.fixture(scope="session")
def command():
    """Runs `motionblocks ARGS…` and returns its stdout; fails the test on a non-zero exit."""
    exe = os.environ.get("MB_COMMAND")
    if not exe:
        pytest.skip("MB_COMMAND (the motionblocks executable) not set: run through ctest")

    def run(*args):
        done = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stderr
        return done.stdout

    return run


def read_json(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)
