"""motionblocks.run_hil_session against the UDP virtual stage (`motionblocks virtual-stage`, started here as a child
process on a free loopback port): the files and summary.json `motionblocks hil` writes, and the error without a
stage."""

import os
import subprocess

import pytest

import motionblocks as mb
from conftest import DIAGRAMS, read_json

HIL = DIAGRAMS / "hil"
IO = HIL / "subsystems" / "hil_io.json"


@pytest.fixture()
def stage_port():
    """Starts the virtual stage of the shipped HIL diagram; yields its port; stops it."""
    exe = os.environ.get("MB_COMMAND")
    if not exe:
        pytest.skip("MB_COMMAND (the motionblocks executable) not set: run through ctest")
    stage = subprocess.Popen([exe, "virtual-stage", str(HIL / "subsystems" / "plant.json"), "--io", str(IO),
                              "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        marker = "listening on 127.0.0.1:"
        for line in stage.stdout:
            if marker in line:
                yield int(line.split(marker)[1])
                break
        else:
            pytest.fail("the virtual stage did not start")
    finally:
        stage.terminate()
        stage.wait(timeout=30)


def test_run_hil_session_writes_what_the_command_writes(stage_port, tmp_path):
    out = tmp_path / "out"
    result = mb.run_hil_session(HIL / "pd_rigid_body.json", replace=[f"plant={IO}"], duration=0.3, board="udp",
                                port=stage_port, max_missed=200, max_overruns=1000, out=out)
    assert result.completed, result.stop_reason
    summary = result.to_dict()
    assert summary == read_json(out / "summary.json")
    assert sorted(summary) == ["diagram", "hil", "metric_units", "metrics", "name", "overrides", "replacements",
                               "samples"]
    assert summary["hil"]["loop"]["ticks"] == 300
    assert summary["hil"]["board"] == f"udp 127.0.0.1:{stage_port}"
    assert set(result.metrics) == {"tracking_rmse", "tracking_max"}
    assert (out / "signals.csv").exists() and (out / "timing.csv").exists()
    assert "300 ticks" in repr(result)


def test_without_a_stage_the_session_says_what_to_start(tmp_path):
    with pytest.raises(RuntimeError, match="no virtual stage answers on 127.0.0.1:9"):
        mb.run_hil_session(HIL / "pd_rigid_body.json", replace=[f"plant={IO}"], port=9, out=tmp_path / "out")
    with pytest.raises(ValueError, match="give --replace"):
        mb.run_hil_session(HIL / "pd_rigid_body.json", replace=[], port=9, out=tmp_path / "out")
