"""sweep: the rows of `motionblocks sweep` as dicts and as a DataFrame, and the diagram's set() calls applied to every
run."""

import math

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


def test_the_sweep_result_is_a_table_with_units():
    rows = mb.sweep(mb.Diagram.load(CONVENTIONAL), GRID, jobs=2)
    assert len(rows) == 2 and rows[-1]["id"] == "0001" and [r["id"] for r in rows[0:1]] == ["0000"]
    assert rows.rows == list(rows) and rows.swept == ["plant.payload_mass"]
    df = rows.to_pandas()
    assert df.index.name == "id" and list(df.index) == ["0000", "0001"]
    assert list(df.columns) == ["status", "plant.payload_mass", "tracking_rmse", "tracking_max_abs", "wall_time_s",
                                "error"]
    assert list(df["plant.payload_mass"]) == [0.0, 0.2621]
    assert df.loc["0001", "tracking_rmse"] == rows[1]["tracking_rmse"]
    assert df["tracking_rmse"].idxmax() == "0001"  # the heavier payload tracks worse
    assert df.attrs["units"] == {"status": "", "plant.payload_mass": "kg", "tracking_rmse": "m",
                                 "tracking_max_abs": "m", "wall_time_s": "s", "error": ""}
    low, high = sorted(r["tracking_rmse"] for r in rows)
    low_max, high_max = sorted(r["tracking_max_abs"] for r in rows)
    assert repr(rows) == (f"<SweepResult 2 runs (2 ok, 0 failed) over plant.payload_mass; tracking_rmse {low:.3g} … "
                          f"{high:.3g} m, tracking_max_abs {low_max:.3g} … {high_max:.3g} m>")


def test_a_failed_run_is_a_row_with_nan_metrics_and_its_error():
    rows = mb.sweep(mb.Diagram.load(CONVENTIONAL), {"list": [{"plant.payload_mass": 0.1},
                                                             {"plant.payload_mass": -1.0}],
                                                    "set": {"defaultExperiment.stopTime": 0.2}})
    df = rows.to_pandas()
    assert list(df["status"]) == ["ok", "failed"]
    assert math.isnan(df.loc["0001", "tracking_rmse"]) and df.loc["0000", "tracking_rmse"] > 0
    assert "payload_mass" in df.loc["0001", "error"]
    assert repr(rows).startswith("<SweepResult 2 runs (1 ok, 1 failed) over plant.payload_mass; tracking_rmse ")


BAD_SWEEP = "<sweep dict>: /grid/plant.payload_mass: give a non-empty array of values"
