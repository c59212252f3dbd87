"""motionblocks.linearize on the HIL plant subsystem (a rigid body, M ẍ = f − B ẋ): A, B, C, D against the body's
own parameters read from the diagram, the frequency response 1/(M s² + B s), and an unknown input refused."""

import numpy as np
import pytest

import motionblocks as mb
from conftest import DIAGRAMS

PLANT = DIAGRAMS / "hil" / "subsystems" / "plant.json"


def test_a_rigid_body_linearises_to_its_state_space_model():
    d = mb.Diagram.load(PLANT)
    mass, damping = d.get("body.mass"), d.get("body.damping")
    model = mb.linearize(d, inputs={"f": 1.0})
    np.testing.assert_allclose(model.a, [[0.0, 1.0], [0.0, -damping / mass]], atol=1e-8)
    np.testing.assert_allclose(model.b, [[0.0], [1.0 / mass]], atol=1e-8)
    np.testing.assert_allclose(model.c, [[1.0, 0.0]], atol=1e-8)
    np.testing.assert_allclose(model.d, [[0.0]], atol=1e-12)
    assert model.input_names == ["f"] and model.output_names == ["x"]
    assert model.u0[0] == 1.0
    f = np.array([0.1, 1.0, 10.0])
    s = 2j * np.pi * f
    np.testing.assert_allclose(model.frequency_response(0, 0, f), 1.0 / (mass * s**2 + damping * s), rtol=1e-6)
    assert model.to_dict()["A"][1][1] == pytest.approx(-damping / mass)


def test_an_unknown_input_is_refused_with_the_known_ones():
    with pytest.raises(ValueError, match="no input connector 'force'; its inputs: f"):
        mb.linearize(mb.Diagram.load(PLANT), inputs={"force": 1.0})
