"""Diagram, simulate and the exceptions: the module against `motionblocks run` on the same diagram."""

import gc

import numpy as np
import pytest

import motionblocks as mb
from conftest import CONVENTIONAL, DIAGRAMS, read_json


@pytest.fixture(scope="module")
def conventional():
    return mb.Diagram.load(CONVENTIONAL)


def test_blocks_lists_the_elements_with_their_types(conventional):
    blocks = {b["name"]: b["type"] for b in conventional.blocks()}
    assert blocks["plant"] == "linear_motor"
    assert blocks["dob"] == "dob"
    assert conventional.get("plant", "payload_mass") == 0.0


def test_simulate_gives_the_run_commands_metrics_and_statistics(conventional, command, tmp_path):
    result = mb.simulate(conventional)
    command("run", CONVENTIONAL, "--out", tmp_path)
    summary = read_json(tmp_path / "summary.json")
    assert set(result.metrics) == set(summary["metrics"])
    for name, value in summary["metrics"].items():
        assert result.metrics[name] == pytest.approx(value, rel=1e-12, abs=0.0)
    assert result.solver_stats["steps"] == summary["solver"]["steps"]
    assert result.solver_stats["rhs_evaluations"] == summary["solver"]["rhs_evaluations"]
    assert result.time.shape == (summary["samples"],)
    assert result.time[-1] == pytest.approx(3.0)
    assert result.solver == summary["solver"]["type"]


def test_signals_are_read_only_views_that_keep_the_result_alive(conventional):
    result = mb.simulate(conventional, stop_time=0.2)
    x = result["plant.x"]
    assert x.base is result and result.time.base is result
    assert x.dtype == np.float64 and x.shape == result.time.shape
    assert not x.flags.writeable
    expected = float(np.sum(x))
    del result
    gc.collect()
    assert float(np.sum(x)) == expected  # the array still owns the result's memory
    assert list(mb.simulate(conventional, stop_time=0.2).signals) == mb.simulate(conventional, stop_time=0.2).names


def test_set_changes_the_result_as_the_commands_set_does(command, tmp_path):
    diagram = mb.Diagram.load(CONVENTIONAL)
    before = mb.simulate(diagram).metrics["tracking_rmse"]
    diagram.set("plant.payload_mass", 0.2621)
    assert diagram.get("plant", "payload_mass") == 0.2621
    after = mb.simulate(diagram).metrics["tracking_rmse"]
    assert after > 1.2 * before  # the moving mass doubled, the controller unchanged
    command("run", CONVENTIONAL, "--set", "plant.payload_mass=0.2621", "--out", tmp_path)
    assert after == pytest.approx(read_json(tmp_path / "summary.json")["metrics"]["tracking_rmse"], rel=1e-12)


def test_save_writes_a_diagram_that_loads_with_the_settings(tmp_path):
    diagram = mb.Diagram.load(DIAGRAMS / "paper" / "gp_loop.json")  # names a model file beside it
    diagram.set("plant.payload_mass", 0.1)
    outside = diagram.save(tmp_path / "copy.json")
    assert outside and "gpr.model" in outside[0]
    copy = mb.Diagram.from_dict(read_json(tmp_path / "copy.json"), base_directory=tmp_path)
    assert copy.get("plant", "payload_mass") == 0.1
    assert copy.blocks() == diagram.blocks()


def test_set_takes_the_experiment_and_the_solver():
    diagram = mb.Diagram.load(CONVENTIONAL)
    diagram.set("defaultExperiment.stopTime", 0.5)
    diagram.set("solver.type", "euler")
    result = mb.simulate(diagram)
    assert result.time[-1] == pytest.approx(0.5)
    assert result.solver == "euler"


def test_an_unknown_element_is_a_value_error_naming_the_closest():
    diagram = mb.Diagram.load(CONVENTIONAL)
    with pytest.raises(ValueError) as e:
        diagram.set("plnat.payload_mass", 0.25)
    assert str(e.value) == UNKNOWN_ELEMENT


def test_an_unknown_parameter_is_a_value_error_naming_the_closest():
    diagram = mb.Diagram.load(CONVENTIONAL)
    with pytest.raises(ValueError) as e:
        diagram.set("plant.payload_mas", 0.25)
    assert str(e.value) == UNKNOWN_PARAMETER


def test_a_key_without_a_dot_says_how_to_write_it():
    with pytest.raises(ValueError) as e:
        mb.Diagram.load(CONVENTIONAL).set("payload_mass", 0.25)
    assert str(e.value) == (
        f"{CONVENTIONAL}: set('payload_mass'): write element.parameter (e.g. plant.payload_mass), "
        "solver.<key> or defaultExperiment.<key>")


def test_a_value_the_parameter_refuses_is_a_diagram_error_with_its_problems():
    diagram = mb.Diagram.load(CONVENTIONAL)
    with pytest.raises(mb.DiagramError) as e:
        diagram.set("plant.payload_mass", "heavy")
    assert isinstance(e.value, ValueError)
    problem = '/elements/plant/parameters/payload_mass: must be a number [kg], got "heavy"'
    assert e.value.problems == [problem]
    assert str(e.value) == f"{CONVENTIONAL}: 1 problem in the diagram:\n  {problem}"


def test_a_diagram_with_problems_raises_every_problem_with_its_json_pointer():
    spec = read_json(CONVENTIONAL)
    spec["elements"][0].setdefault("parameters", {})["not_a_parameter"] = 1
    diagram = mb.Diagram.from_dict(spec, base_directory=CONVENTIONAL.parent)
    with pytest.raises(mb.DiagramError) as e:
        mb.simulate(diagram)
    assert any("/elements/0/parameters" in p for p in e.value.problems)


def test_an_algebraic_loop_is_its_own_diagram_error():
    loop = {
        "schemaVersion": "1.0", "name": "loop",
        "elements": [{"name": "a", "type": "gain", "parameters": {"gain": 2.0}},
                     {"name": "b", "type": "gain", "parameters": {"gain": 0.5}}],
        "connections": [{"startElement": "a", "startConnector": "y", "endElement": "b", "endConnector": "u"},
                        {"startElement": "b", "startConnector": "y", "endElement": "a", "endConnector": "u"}]}
    with pytest.raises(mb.AlgebraicLoopError) as e:
        mb.simulate(mb.Diagram.from_dict(loop))
    assert isinstance(e.value, mb.DiagramError)
    assert "a.y" in str(e.value) and "b.y" in str(e.value)


def test_a_missing_file_is_an_os_error_with_the_path(tmp_path):
    missing = tmp_path / "nope.json"
    with pytest.raises(OSError) as e:
        mb.Diagram.load(missing)
    assert str(e.value) == f"{missing}: cannot open the diagram file (does it exist?)"


def test_a_json_syntax_error_is_a_diagram_error_naming_the_line(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{\n  "name": "x",\n  oops\n}\n')
    with pytest.raises(mb.DiagramError) as e:  # a ValueError, as the diagram's other problems (issue 30)
        mb.Diagram.load(bad)
    assert str(e.value).startswith(f"{bad}: 1 problem in the diagram:\n  not valid JSON: parse error at line 3, "
                                   "column 3:")
    assert "json.exception" not in str(e.value)


def test_values_json_cannot_hold_are_type_errors_naming_the_argument(conventional):
    with pytest.raises(TypeError) as e:
        conventional.set("plant.payload_mass", object())
    assert str(e.value).startswith("set(): value: a object is no JSON value; give a number, str, bool, None")
    with pytest.raises(TypeError) as e:
        mb.Diagram.from_dict({"name": {1, 2}})
    assert str(e.value).startswith("from_dict(): diagram: a dict is no JSON value")
    emps = mb.Diagram.load(DIAGRAMS / "emps" / "rigid_body.json")
    with pytest.raises(TypeError) as e:
        mb.simulate(emps, stop_time=0.1, inputs={"velocity": 5})
    assert str(e.value) == ("simulate(): inputs['velocity']: a int is no (time, values) pair; give two 1-D sequences "
                            "of numbers of one length, time [s] increasing")
    assert "Unable to cast" not in str(e.value)


def test_inputs_feed_the_input_connectors():
    emps = mb.Diagram.load(DIAGRAMS / "emps" / "rigid_body.json")
    inputs = {c: ([0.0, 1.0], [0.0, 0.0]) for c in ("position", "velocity", "acceleration")}
    inputs["velocity"] = ([0.0, 1.0], [0.1, 0.1])
    result = mb.simulate(emps, stop_time=1.0, inputs=inputs)
    assert result.time.shape[0] > 10


UNKNOWN_ELEMENT = f"{CONVENTIONAL}: no element named 'plnat'; did you mean: plant"
UNKNOWN_PARAMETER = (
    f"{CONVENTIONAL}: element 'plant' (linear_motor) has no parameter 'payload_mas'; did you mean: payload_mass, "
    "payload_time; it takes: mass, damping, payload_mass, payload_time, initial_position, initial_velocity, pole_pitch, "
    "cogging_amplitude, cogging_amplitude_velocity, cogging_harmonics, cogging_phases, cogging_offset, cogging_offset_velocity, "
    "cogging_offset_velocity_squared, coulomb_friction, static_friction, stribeck_velocity, viscous_squared, "
    "friction_regularization_velocity, encoder_resolution, resonance_frequency_hz, resonance_damping_ratio, "
    "resonance_modal_gain")
