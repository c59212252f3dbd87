"""compare, fit, improve on the EMPS record (diagrams/emps/data, as the C++ tests read it): the same outcome as
the command line's compare.json and fit.json, and the measurement taken as a path, a dict or a structured array."""

import csv
import os
import subprocess
import sys

import numpy as np
import pytest

import motionblocks as mb
from conftest import EMPS, SOURCE, read_json

RIGID_BODY = EMPS / "rigid_body.json"
DATA = EMPS / "data" / "DATA_EMPS.csv"

# compare.json's entries that name the files the command wrote.
WRITTEN = {"fitted_diagram", "fitted_diagram_reads_outside_its_folder", "suggested_diagram"}


def read_columns(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, j] for j, name in enumerate(header)}


def approx_json(expected):
    """pytest.approx through nested dicts and lists (numbers to 1e-9 relative)."""
    if isinstance(expected, dict):
        return {k: approx_json(v) for k, v in expected.items()}
    if isinstance(expected, list):
        return [approx_json(v) for v in expected]
    if isinstance(expected, float):
        return pytest.approx(expected, rel=1e-9, abs=1e-12)
    return expected


def first_rows(tmp_path, rows=4000):
    """The record's first `rows` samples (4 s) as a CSV file: enough to compare, a sixth of the record's diagnosis."""
    path = tmp_path / "first_rows.csv"
    path.write_text("\n".join(DATA.read_text().splitlines()[:rows + 1]) + "\n")
    return path


@pytest.fixture(scope="module")
def emps_compare():
    return mb.compare(mb.Diagram.load(RIGID_BODY), DATA)


def test_compare_names_the_same_first_effect_as_the_command_line(emps_compare):
    # tests/tools/commands/compare_command_test.cc: the EMPS record's first effect.
    assert emps_compare.diagnosis[0].effect == "velocity_dependent_ripple"
    assert emps_compare.to_dict()["diagnosis"][0]["effect"] == "velocity_dependent_ripple"
    assert 0.0 < emps_compare.diagnosis[0].score < 1.0
    assert emps_compare.rmse_after < emps_compare.rmse_before
    assert emps_compare.unit == "N" and emps_compare.output == "force"


def test_compare_suggests_in_the_rankings_order_as_the_command_line():
    # tests/tools/commands/compare_command_test.cc: the friction-law replacement first (on EMPS a negative Stribeck
    # hump, which no friction block can be: skipped), then the top missing effect.
    c = mb.compare(mb.Diagram.load(RIGID_BODY), DATA, suggest=True, gpr_fallback=False)
    assert c.suggested_effects == ["velocity_dependent_ripple"]
    types = [e["type"] for e in c.suggested_diagram.to_dict()["elements"]]
    assert "velocity_dependent_ripple" in types


def test_compare_repr_shows_the_readmes_figures(emps_compare):
    # README, demo step 1: the benchmark's model as written, then refit.
    assert repr(emps_compare) == ("<CompareOutcome force_N: RMSE 4.45 → 2.33 N, fit 91.8 % → 95.7 %, top effect "
                                  "velocity_dependent_ripple>")
    assert repr(emps_compare.diagnosis[0]).startswith("<DiagnosedEffect velocity_dependent_ripple: ")
    assert "period = 0.0025" in repr(emps_compare.diagnosis[0])  # the screw lead, 2.5 mm
    mass = next(p for p in emps_compare.parameters if p.name == "inertia.gain")
    assert repr(mass) == f"<FittedParameter inertia.gain = {mass.estimate:.6g} ± {1.96 * mass.standard_error:.3g} (95 %)>"


def test_compare_to_pandas_gives_measured_model_and_residual_over_time(emps_compare):
    df = emps_compare.to_pandas()
    names = ["force.measured", "force.model_before", "force.model", "force.residual"]
    assert emps_compare.keys() == names and list(df.columns) == names
    assert df.index.name == "time_s" and len(df) == emps_compare.time.shape[0]
    np.testing.assert_array_equal(df.index.to_numpy(), emps_compare.time)
    assert df.attrs["units"] == {name: "N" for name in names} == emps_compare.units
    np.testing.assert_array_equal(df["force.measured"].to_numpy(), emps_compare.measured)
    np.testing.assert_array_equal(df["force.model"].to_numpy(), emps_compare.model)
    np.testing.assert_array_equal(df["force.model_before"].to_numpy(), emps_compare.model_before)
    np.testing.assert_allclose(df["force.residual"], df["force.measured"] - df["force.model"], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(emps_compare["force.residual"], emps_compare.residual)
    # the RMSEs the outcome reports are those of its columns
    assert np.sqrt(np.mean(df["force.residual"] ** 2)) == pytest.approx(emps_compare.rmse_after, rel=1e-9)
    before = df["force.measured"] - df["force.model_before"]
    assert np.sqrt(np.mean(before ** 2)) == pytest.approx(emps_compare.rmse_before, rel=1e-9)
    with pytest.raises(KeyError) as e:
        emps_compare["force"]
    assert "no series 'force'; there are: force.measured, force.model_before" in str(e.value)


def test_compare_to_dict_is_the_commands_compare_json(command, tmp_path):
    data = first_rows(tmp_path)
    command("compare", RIGID_BODY, "--measurement", data, "--out", tmp_path / "out")
    written = read_json(tmp_path / "out" / "compare.json")
    if "nonparametric_fallback" in written:
        written["nonparametric_fallback"].pop("model", None)
    ours = mb.compare(mb.Diagram.load(RIGID_BODY), data).to_dict()
    assert ours["diagnosis"], "a diagnosis to compare"
    for key in WRITTEN:
        written.pop(key, None)
    assert ours.keys() == written.keys()
    assert ours == approx_json(written)


def test_compare_gives_the_fitted_parameters_with_intervals(emps_compare):
    fitted = {p.name: p for p in emps_compare.parameters}
    assert set(fitted) == {"inertia.gain", "friction.viscous", "friction.coulomb", "offset.value"}
    mass = fitted["inertia.gain"]
    low, high = mass.interval
    assert low < mass.estimate < high
    assert high - low == pytest.approx(2 * 1.96 * mass.standard_error)
    assert mass.estimate == pytest.approx(95.1, abs=0.1)  # README, demo step 1
    expected = emps_compare.to_dict()["fit"]
    assert emps_compare.fitted_diagram.get("inertia.gain") == pytest.approx(mass.estimate, rel=1e-12)
    assert len(expected["parameters"]) == 4


def test_the_measurement_as_a_dict_or_a_structured_array_is_the_csv(tmp_path):
    diagram = mb.Diagram.load(RIGID_BODY)
    data = first_rows(tmp_path)
    columns = read_columns(data)
    from_csv = mb.compare(diagram, data, no_fit=True, gpr_fallback=False)
    from_dict = mb.compare(diagram, columns, no_fit=True, gpr_fallback=False)
    table = np.zeros(len(columns["time_s"]), dtype=[(name, "f8") for name in columns])
    for name, values in columns.items():
        table[name] = values
    from_table = mb.compare(diagram, table, no_fit=True, gpr_fallback=False)
    assert from_dict.rmse_before == pytest.approx(from_csv.rmse_before, rel=1e-12)
    assert from_table.rmse_before == pytest.approx(from_csv.rmse_before, rel=1e-12)
    assert from_dict.measured.shape == from_csv.time.shape == (4000,)
    np.testing.assert_array_equal(from_table.measured, from_csv.measured)


def test_map_reads_a_connector_from_another_column(tmp_path):
    columns = read_columns(first_rows(tmp_path))
    columns["f_measured"] = columns.pop("force_N")
    with pytest.raises(ValueError) as e:
        mb.compare(mb.Diagram.load(RIGID_BODY), columns, no_fit=True, gpr_fallback=False)
    assert "force_N" in str(e.value)
    mapped = mb.compare(mb.Diagram.load(RIGID_BODY), columns, no_fit=True, gpr_fallback=False,
                        map={"force": "f_measured"})
    assert mapped.rmse_before > 0


def test_a_bad_cell_in_the_log_names_the_file_line_and_column(tmp_path):
    lines = DATA.read_text().splitlines()[:200]
    lines[5] = lines[5].replace(lines[5].split(",")[4], "nan")
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as e:
        mb.compare(mb.Diagram.load(RIGID_BODY), bad, no_fit=True)
    assert str(bad) in str(e.value) and "line 6" in str(e.value) and "force_N" in str(e.value)


def test_arrays_with_a_nan_or_time_going_back_name_the_column_and_row():
    columns = {name: values[:500].copy() for name, values in read_columns(DATA).items()}
    columns["force_N"][7] = np.nan
    with pytest.raises(ValueError) as e:
        mb.compare(mb.Diagram.load(RIGID_BODY), columns, no_fit=True)
    assert str(e.value) == ("measurement: column 'force_N' row 7 is nan: give finite values (drop or interpolate that "
                            "sample)")
    columns["force_N"][7] = 0.0
    columns["time_s"][9] = 0.0
    with pytest.raises(ValueError) as e:
        mb.compare(mb.Diagram.load(RIGID_BODY), columns, no_fit=True)
    assert str(e.value).startswith("measurement: time 'time_s' decreases at row 9 (0 s after ")


def test_fit_gives_the_commands_fit_json(command, tmp_path):
    names = ["inertia.gain", "friction.viscous"]
    outcome = mb.fit(mb.Diagram.load(RIGID_BODY), DATA, fit=names)
    command("fit", RIGID_BODY, "--measurement", DATA, "--fit", ",".join(names), "--out", tmp_path)
    written = read_json(tmp_path / "fit.json")
    written.pop("fitted_diagram")
    assert outcome.to_dict() == approx_json(written)
    assert [p.name for p in outcome.parameters] == names
    assert outcome.rmse_after < outcome.rmse_before


def test_fit_repr_and_to_pandas():
    names = ["inertia.gain", "friction.viscous"]
    outcome = mb.fit(mb.Diagram.load(RIGID_BODY), DATA, fit=names)
    estimates = ", ".join(f"{p.name} = {p.estimate:.4g}" for p in outcome.parameters)
    assert repr(outcome) == (f"<FitOutcome force_N: RMSE {outcome.rmse_before:.3g} → {outcome.rmse_after:.3g} N, fit "
                             f"{outcome.fit_percent_before:.1f} % → {outcome.fit_percent_after:.1f} %; {estimates}; "
                             f"{outcome.status}>")
    assert repr(outcome).startswith("<FitOutcome force_N: RMSE 4.45 → ")
    df = outcome.to_pandas()
    assert list(df.columns) == outcome.keys() == ["force.measured", "force.model_before", "force.model",
                                                  "force.residual"]
    assert df.index.name == "time_s" and len(df) == outcome.time.shape[0] == len(read_columns(DATA)["time_s"])
    assert df.attrs["units"]["force.model"] == "N" == outcome.unit
    assert np.sqrt(np.mean(df["force.residual"] ** 2)) == pytest.approx(outcome.rmse_after, rel=1e-9)
    np.testing.assert_array_equal(outcome["force.model"], df["force.model"].to_numpy())


def test_improve_refuses_settings_out_of_range_before_fitting():
    with pytest.raises(ValueError) as e:
        mb.improve(mb.Diagram.load(RIGID_BODY), DATA, max_trials=0)
    assert str(e.value) == IMPROVE_BAD_TRIALS


IMPROVE_BAD_TRIALS = "--max-trials must be >= 1"


def test_improve_on_simulated_arrays_finds_the_twins_cogging_as_the_command_does(command, tmp_path):
    # tests/tools/commands/improve_command_test.cc from Python: the twin's closed loop with its cogging is the
    # "measurement" (here simulated and passed as arrays), the model lacks the cogging.
    paper = EMPS.parent / "paper"
    scan = mb.Diagram.load(paper / "cogging_scan.json")
    train = mb.simulate(scan)
    scan.set("reference.velocities", [0.15, 0.25])
    held = mb.simulate(scan)
    as_columns = lambda r: {"time_s": r.time, **r.signals}  # noqa: E731
    outcome = mb.improve(mb.Diagram.load(paper / "motor_rigid_body.json"), as_columns(train),
                         validation=as_columns(held), max_effects=1)
    ours = outcome.to_dict()
    accepted = [s for s in outcome.steps if s.accepted]
    assert len(accepted) == 2 and accepted[1].effect in ("position_periodic", "velocity_dependent_ripple")
    assert accepted[1].rmse_heldout < accepted[0].rmse_heldout
    period = [p for p in accepted[1].parameters if p.name.endswith(".period")][0]
    assert period.estimate == pytest.approx(0.0225, rel=0.02)

    # one row per step, the RMSEs in the output's unit
    df = outcome.to_pandas()
    assert df.index.name == "step" and len(df) == len(outcome.steps)
    assert list(df.columns) == ["round", "accepted", "effect", "element", "rmse_train_before", "rmse_train",
                                "rmse_heldout_before", "rmse_heldout", "verdict"]
    assert list(df["effect"]) == [s.effect for s in outcome.steps]
    assert list(df["accepted"]) == [s.accepted for s in outcome.steps]
    np.testing.assert_array_equal(df["rmse_heldout"].to_numpy(), [s.rmse_heldout for s in outcome.steps])
    assert df.attrs["units"]["rmse_train"] == outcome.unit != ""
    assert df.attrs["units"]["effect"] == ""
    u = outcome.unit
    assert repr(accepted[1]) == (f"<ImproveStep round {accepted[1].round}, {accepted[1].effect} accepted: RMSE "
                                 f"{accepted[1].rmse_train_before:.3g} → {accepted[1].rmse_train:.3g} {u}, held out "
                                 f"{accepted[1].rmse_heldout_before:.3g} → {accepted[1].rmse_heldout:.3g} {u}>")
    first = outcome.steps[0]
    assert u == "N"
    assert repr(outcome) == (f"<ImproveOutcome force_N: {len(outcome.steps) - 1} effects tried, 1 accepted "
                             f"({accepted[1].effect}); RMSE {first.rmse_train:.3g} → {accepted[1].rmse_train:.3g} {u}, held out "
                             f"{first.rmse_heldout:.3g} → {accepted[1].rmse_heldout:.3g} {u}; stop {outcome.stop}>")

    command("run", paper / "cogging_scan.json", "--out", tmp_path / "scan")
    command("run", paper / "cogging_scan.json", "--set", "reference.velocities=[0.15,0.25]", "--out",
            tmp_path / "validation")
    command("improve", paper / "motor_rigid_body.json", "--measurement", tmp_path / "scan" / "signals.csv",
            "--validation", tmp_path / "validation" / "signals.csv", "--max-effects", "1", "--out", tmp_path / "imp")
    written = read_json(tmp_path / "imp" / "improve.json")
    assert [s["effect"] for s in ours["steps"]] == [s["effect"] for s in written["steps"]]
    assert ours["stop"] == written["stop"]
    assert ours.keys() - {"nonparametric_fallback"} == written.keys() - {"nonparametric_fallback"}


def test_the_notebook_example_runs_as_written_from_the_repository_root():
    done = subprocess.run([sys.executable, "examples/python_session.py"], cwd=SOURCE, env=os.environ,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    out = done.stdout
    assert "kp = 9300.0 N/m" in out
    assert "'plant/body.v': 'm/s'" in out
    assert ("<CompareOutcome force_N: RMSE 4.45 → 2.33 N, fit 91.8 % → 95.7 %, top effect "
            "velocity_dependent_ripple>") in out
    assert "<SweepResult 3 runs (3 ok, 0 failed) over controller.kp; tracking_rmse " in out
