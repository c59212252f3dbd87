"""sweep: the rows of `motionblocks sweep` as dicts, and the diagram's set() calls applied to every run."""

import pytest

import motionblocks as mb
from conftest import CONVENTIONAL, DIAGRAMS, read_json

GRID = {"grid": {"plant.payload_mass": [0.0, 0.2621]}, "set": {"defaultExperiment.stopTime": 1.0}}


def test_sweep_rows_are_the_runs_with_their_values_and_metrics():
    rows = mb.sweep(mb.Diagram.load(CONVENTIONAL), GRID, jobs=2)
    assert [r["id"] for r in rows] == ["0000", "0001"]
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert rows[1]["plant.payload_mass"] == 0.2621
    alone = mb.Diagram.load(CONVENTIONAL)
    alone.set("plant.payload_mass", 0.2621)
    alone.set("defaultExperiment.stopTime", 1.0)
    assert rows[1]["tracking_rmse"] == pytest.approx(mb.simulate(alone).metrics["tracking_rmse"], rel=1e-12)
    assert rows[1]["tracking_rmse"] > rows[0]["tracking_rmse"]


def test_the_diagrams_settings_apply_to_every_run():
    diagram = mb.Diagram.load(CONVENTIONAL)
    diagram.set("defaultExperiment.stopTime", 0.5)
    rows = mb.sweep(diagram, {"list": [{"plant.payload_mass": 0.1}]})
    alone = mb.Diagram.load(CONVENTIONAL)
    alone.set("plant.payload_mass", 0.1)
    alone.set("defaultExperiment.stopTime", 0.5)
    assert rows[0]["tracking_rmse"] == pytest.approx(mb.simulate(alone).metrics["tracking_rmse"], rel=1e-12)


def test_a_sweep_file_and_an_output_folder_as_the_command(tmp_path):
    spec = DIAGRAMS / "paper" / "sweeps" / "payload_conventional.json"
    diagram = mb.Diagram.load(CONVENTIONAL)
    diagram.set("defaultExperiment.stopTime", 0.3)
    rows = mb.sweep(diagram, spec, out=tmp_path)
    assert len(rows) == 7
    written = read_json(tmp_path / "runs.json")
    assert len(written["runs"]) == 7
    assert (tmp_path / "runs.csv").exists()


def test_a_bad_sweep_names_its_json_pointer():
    with pytest.raises(ValueError) as e:
        mb.sweep(mb.Diagram.load(CONVENTIONAL), {"grid": {"plant.payload_mass": []}})
    assert str(e.value) == BAD_SWEEP


def test_negative_jobs_are_refused_as_the_command_line_refuses_them():
    with pytest.raises(ValueError) as e:
        mb.sweep(mb.Diagram.load(CONVENTIONAL), GRID, jobs=-1)
    assert str(e.value) == "sweep(): jobs = -1: give the number of parallel runs, 0 for all cores"


def test_an_unknown_element_in_a_sweep_is_a_diagram_error():
    with pytest.raises(mb.DiagramError) as e:
        mb.sweep(mb.Diagram.load(CONVENTIONAL), {"grid": {"plnat.payload_mass": [0.1]}})
    assert "plnat" in str(e.value)


BAD_SWEEP = "<sweep dict>: /grid/plant.payload_mass: give a non-empty array of values"
