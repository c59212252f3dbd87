"""Diagram, simulate and the exceptions: the module against `motionblocks run` on the same diagram; get/set with
one dotted key, simulate(log=…), the result as a mapping with units and as a pandas DataFrame."""

import gc
import sys

import numpy as np
import pytest

import motionblocks as mb
from conftest import CONVENTIONAL, DIAGRAMS, read_json

PD = DIAGRAMS / "hil" / "pd_rigid_body.json"  # a PD loop around a subsystem plant/body (rigid_body: x [m], v [m/s])


@pytest.fixture(scope="module")
def conventional():
    return mb.Diagram.load(CONVENTIONAL)


def test_blocks_lists_the_elements_with_their_types(conventional):
    blocks = {b["name"]: b["type"] for b in conventional.blocks()}
    assert blocks["plant"] == "linear_motor"
    assert blocks["dob"] == "dob"
    assert conventional.get("plant.payload_mass") == 0.0


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
    assert diagram.get("plant.payload_mass") == 0.2621
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
    assert copy.get("plant.payload_mass") == 0.1
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
    assert str(e.value).startswith("set('plant.payload_mass', …): value: a object is no JSON value; give a number, "
                                   "str, bool, None")
    with pytest.raises(TypeError) as e:
        mb.Diagram.from_dict({"name": {1, 2}})
    assert str(e.value).startswith("from_dict(): diagram: a dict is no JSON value")
    emps = mb.Diagram.load(DIAGRAMS / "emps" / "rigid_body.json")
    with pytest.raises(TypeError) as e:
        mb.simulate(emps, stop_time=0.1, inputs={"velocity": 5})
    assert str(e.value) == ("simulate(): inputs['velocity']: a int is no (time, values) pair; give two 1-D sequences "
                            "of numbers of one length, time [s] increasing")
    assert "Unable to cast" not in str(e.value)


GAIN = {"schemaVersion": "1.0", "defaultExperiment": {"stopTime": 0.01}, "solver": {"type": "rk4", "step": 0.001},
        "elements": [{"name": "c", "type": "constant", "parameters": {"value": 1.0}},
                     {"name": "k", "type": "gain", "parameters": {"gain": 1.0}}],
        "connections": [{"startElement": "c", "startConnector": "y", "endElement": "k", "endConnector": "u"}],
        "log": ["k.y"]}


def test_set_refuses_a_non_finite_value_naming_the_key_and_the_value():  # issue 41
    d = mb.Diagram.from_dict(GAIN)
    for value, text in ((float("nan"), "nan"), (float("inf"), "inf"), (np.array([1.0, np.nan]), "nan"),
                        (np.float64("-inf"), "-inf")):
        with pytest.raises(ValueError) as e:
            d.set("k.gain", value)
        assert str(e.value).startswith("set('k.gain', …): value: ")
        assert f"{text}" in str(e.value) and "is not finite: NaN and infinity are no parameter's" in str(e.value)
        assert "parse error" not in str(e.value)
    with pytest.raises(ValueError) as e:
        d.set("solver.step", float("nan"))
    assert str(e.value).startswith("set('solver.step', …): value: nan is not finite")
    assert d.get("k.gain") == 1.0


def test_set_builds_the_element_with_the_value_and_keeps_it_unchanged_when_refused():  # issue 41
    d = mb.Diagram.from_dict(GAIN)
    with pytest.raises(mb.DiagramError) as e:
        d.set("k.gain", np.array([1.0, 2.0, 3.0]))
    assert "/elements/k/parameters/gain: k.gain = [1.0,2.0,3.0] does not fit element 'k' (gain): gain has 3 " \
           "entries; give one or `width` entries" in str(e.value)
    assert d.get("k.gain") == 1.0  # unchanged
    d.set("k.gain", np.array([2.5]))  # one entry: a scalar gain
    d.set("k.width", 3)
    d.set("k.gain", np.array([1.0, 2.0, 3.0]))  # three entries on a gain of width 3
    assert d.get("k.gain") == [1.0, 2.0, 3.0]


def test_load_refuses_a_subsystem_that_includes_itself(tmp_path):  # issue 41: the command line refused it already
    inner = dict(GAIN, connectors=[{"name": "y", "kind": "output", "unit": "1"}],
                 elements=GAIN["elements"] + [{"name": "s", "type": "subsystem", "diagram": "self.json"}])
    inner.pop("log")
    (tmp_path / "self.json").write_text(__import__("json").dumps(inner))
    top = dict(GAIN, elements=GAIN["elements"] + [{"name": "s", "type": "subsystem", "diagram": "self.json"}])
    (tmp_path / "top.json").write_text(__import__("json").dumps(top))
    with pytest.raises(mb.DiagramError) as e:
        mb.Diagram.load(tmp_path / "top.json")
    assert "self.json" in str(e.value)


def test_inputs_feed_the_input_connectors():
    emps = mb.Diagram.load(DIAGRAMS / "emps" / "rigid_body.json")
    inputs = {c: ([0.0, 1.0], [0.0, 0.0]) for c in ("position", "velocity", "acceleration")}
    inputs["velocity"] = ([0.0, 1.0], [0.1, 0.1])
    result = mb.simulate(emps, stop_time=1.0, inputs=inputs)
    assert result.time.shape[0] > 10


def test_get_takes_the_dotted_key_that_set_takes():
    diagram = mb.Diagram.load(PD)
    assert diagram.get("controller.kp") == 9300.0
    diagram.set("controller.kp", 12000.0)
    assert diagram.get("controller.kp") == 12000.0
    assert diagram.get("controller.kd") == 69.0
    assert diagram.get("defaultExperiment.stopTime") == 1.0
    assert diagram.get("solver.step") == 1e-4
    assert diagram.get("solver.rtol") == 1e-6  # not in the file: the engine's default
    diagram.set("defaultExperiment.stopTime", 0.25)
    assert diagram.get("defaultExperiment.stopTime") == 0.25


def test_get_gives_the_si_value_of_a_parameter_written_in_another_unit():
    spec = read_json(CONVENTIONAL)
    plant = next(e for e in spec["elements"] if e["name"] == "plant")
    plant["parameters"]["pole_pitch"] = {"value": 22.5, "unit": "mm"}
    diagram = mb.Diagram.from_dict(spec, base_directory=CONVENTIONAL.parent)
    assert diagram.get("plant.pole_pitch") == pytest.approx(0.0225, rel=1e-15)
    diagram.set("plant.pole_pitch", 0.03)  # SI in, written back in the file's mm
    assert diagram.get("plant.pole_pitch") == pytest.approx(0.03, rel=1e-15)
    assert next(e for e in diagram.to_dict()["elements"]
                if e["name"] == "plant")["parameters"]["pole_pitch"] == {"value": pytest.approx(30.0), "unit": "mm"}


def test_get_with_two_arguments_still_works_and_is_deprecated(conventional):
    with pytest.warns(DeprecationWarning, match=r"write get\('plant\.payload_mass'\)"):
        assert conventional.get("plant", "payload_mass") == 0.0


def test_get_refuses_what_set_refuses_naming_the_closest(conventional):
    with pytest.raises(ValueError) as e:
        conventional.get("plnat.payload_mass")
    assert str(e.value) == UNKNOWN_ELEMENT
    with pytest.raises(ValueError) as e:
        conventional.get("plant.payload_mas")
    assert str(e.value) == UNKNOWN_PARAMETER
    with pytest.raises(ValueError) as e:
        conventional.get("payload_mass")
    assert str(e.value) == (
        f"{CONVENTIONAL}: get('payload_mass'): write element.parameter (e.g. plant.payload_mass), "
        "solver.<key> or defaultExperiment.<key>")
    with pytest.raises(ValueError) as e:
        conventional.get("solver.stpe")
    assert str(e.value).startswith(f"{CONVENTIONAL}: get('solver.stpe'): solver has no key 'stpe'; did you mean: "
                                   "step")
    assert str(e.value).endswith("it takes: atol, maxStep, method, rtol, step, type")


def test_simulate_logs_extra_signals_as_the_diagrams_log_list_would():
    diagram = mb.Diagram.load(PD)
    assert mb.simulate(diagram).keys() == ["plant/body.v", "reference", "position", "force", "tracking_error"]
    result = mb.simulate(diagram, log=["controller.u", "plant/body.x"])
    # the names asked, in order, then what the diagram logs (the subsystem's body.v, the connectors)
    assert result.keys() == ["controller.u", "plant/body.x", "plant/body.v", "reference", "position", "force",
                             "tracking_error"]
    assert result.units["plant/body.x"] == "m" and result.units["position"] == "m"
    assert result.units["controller.u"] == "" and result.units["force"] == "N"  # the port declares none, its connector N
    # the same signals as the connectors they drive
    np.testing.assert_array_equal(result["controller.u"], result["force"])
    np.testing.assert_array_equal(result["plant/body.x"], result["position"])
    # Newton on the body (0.2621 kg, 3 N·s/m): the force is m·dv/dt + b·v, to the finite difference's error
    v = result["plant/body.v"]
    newton = 0.2621 * np.gradient(v, result.time) + 3.0 * v
    np.testing.assert_allclose(result["controller.u"][50:-5], newton[50:-5], atol=0.005)
    assert np.max(np.abs(result["controller.u"])) == pytest.approx(0.29, abs=0.01)
    # the same run with the signal written into the diagram's "log"
    spec = read_json(PD)
    spec["log"] = ["controller.u"]
    written = mb.simulate(mb.Diagram.from_dict(spec, base_directory=PD.parent))
    np.testing.assert_array_equal(result["controller.u"], written["controller.u"])
    np.testing.assert_array_equal(result["position"], written["position"])
    # v is the derivative of x: the 2 Hz, 5 mm sine's peak speed 2π·2·0.005 = 0.063 m/s
    dxdt = np.gradient(result["plant/body.x"], result.time)
    np.testing.assert_allclose(v[5:-5], dxdt[5:-5], atol=2e-4)
    assert np.max(np.abs(v)) == pytest.approx(2 * np.pi * 2 * 0.005, rel=0.1)
    # only for that run: the diagram is unchanged
    assert "controller.u" not in mb.simulate(diagram)
    assert diagram.to_dict().get("log") is None
    # a name already logged is logged once (first in the order asked)
    assert mb.simulate(diagram, log=["position", "plant/body.v"]).keys() == [
        "position", "plant/body.v", "reference", "force", "tracking_error"]


def test_simulate_refuses_an_unknown_or_malformed_log():
    diagram = mb.Diagram.load(PD)
    with pytest.raises(mb.DiagramError) as e:
        mb.simulate(diagram, log=["plant/body.vv"])
    assert e.value.problems == ["/log/0: signal 'plant/body.vv': element 'plant/body' has no output 'vv'; its "
                                "outputs: x, v"]
    with pytest.raises(TypeError) as e:
        mb.simulate(diagram, log=5)
    assert str(e.value).startswith("simulate(): log: a int is no list of signal names")
    with pytest.raises(TypeError) as e:
        mb.simulate(diagram, log=["position", 3])
    assert str(e.value) == "simulate(): log: 3 is no signal name; give str such as 'plant.x'"
    assert "controller.u" in mb.simulate(diagram, stop_time=0.1, log="controller.u")  # one name alone


def test_the_result_is_a_mapping_of_signals_with_units(conventional):
    result = mb.simulate(conventional, stop_time=0.2)
    assert result.keys() == result.names and list(result) == result.names and len(result) == len(result.names)
    assert dict(result).keys() == result.signals.keys()
    units = result.units
    assert list(units) == result.names
    assert units["plant.x"] == "m" and units["plant.velocity"] == "m/s" and units["dob.d_hat"] == "N"
    assert units["plant.disturbance"] == "N"
    assert result.metric_units == {"tracking_rmse": "m", "tracking_max_abs": "m"}
    with pytest.raises(KeyError) as e:
        result["plant.v"]
    assert "'plant.v' is not logged; logged: reference.position" in str(e.value)
    assert "simulate(log=['plant.v']) logs it" in str(e.value)


def test_to_pandas_gives_the_signals_over_time_with_their_units(conventional):
    result = mb.simulate(conventional, stop_time=0.2, log=["pd_p.y"])
    df = result.to_pandas()
    assert df.index.name == "time_s"
    assert df.shape == (result.time.shape[0], len(result.names))
    assert list(df.columns) == result.names
    np.testing.assert_array_equal(df.index.to_numpy(), result.time)
    for name in result.names:
        assert df[name].dtype == np.float64
        np.testing.assert_array_equal(df[name].to_numpy(), result[name])
    assert df.attrs["units"] == result.units
    assert df.attrs["units"]["plant.x"] == "m"
    df["plant.x"] *= 2  # a copy: the result stays as it was
    assert df["plant.x"].iloc[-1] == 2 * result["plant.x"][-1]


def test_to_pandas_without_pandas_says_which_package_to_install(conventional, monkeypatch):
    result = mb.simulate(conventional, stop_time=0.05)
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` now raises ImportError
    with pytest.raises(ImportError) as e:
        result.to_pandas()
    assert str(e.value).startswith("SimulationResult.to_pandas() needs pandas, which this Python (")
    assert "install Debian's python3-pandas (sudo apt install python3-pandas" in str(e.value)
    assert result["plant.x"].shape == result.time.shape  # the arrays need no pandas


def test_the_results_repr_shows_its_span_signals_and_metrics(conventional):
    result = mb.simulate(conventional)
    text = repr(result)
    steps = result.solver_stats["steps"]
    assert text.startswith(f"<SimulationResult 0–3 s, {result.time.shape[0]} samples (rk4, {steps} steps); 8 signals: "
                           "reference.position [m], reference.velocity [m/s], plant.x [m], plant.velocity [m/s], "
                           "error.y, dob.d_hat [N], … (+2); ")  # a sum's output: no unit of its own
    assert f"tracking_rmse = {result.metrics['tracking_rmse']:.4g} m" in text
    assert f"tracking_max_abs = {result.metrics['tracking_max_abs']:.4g} m" in text


UNKNOWN_ELEMENT = f"{CONVENTIONAL}: no element named 'plnat'; did you mean: plant"
UNKNOWN_PARAMETER = (
    f"{CONVENTIONAL}: element 'plant' (linear_motor) has no parameter 'payload_mas'; did you mean: payload_mass, "
    "payload_time; it takes: mass, damping, payload_mass, payload_time, initial_position, initial_velocity, pole_pitch, "
    "cogging_amplitude, cogging_amplitude_velocity, cogging_harmonics, cogging_phases, cogging_offset, cogging_offset_velocity, "
    "cogging_offset_velocity_squared, coulomb_friction, static_friction, stribeck_velocity, viscous_squared, "
    "friction_regularization_velocity, encoder_resolution, resonance_frequency_hz, resonance_damping_ratio, "
    "resonance_modal_gain")
