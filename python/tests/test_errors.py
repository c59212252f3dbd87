"""Library exceptions reach Python with the command line's wording (tools/workflow/error_text.h): no internal
function name, library tag or C++ type leaks out bare, and the Python type says what kind of error it is."""

import numpy as np
import pytest

import motionblocks as mb


def test_a_length_mismatch_in_predict_is_a_value_error_without_a_cxx_signature():
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 0.1, 400)
    xdot = rng.choice([0.05, 0.1], 400) + rng.normal(0.0, 0.001, 400)
    model = mb.fit_gpr(x, xdot, np.sin(2 * np.pi * x / 0.0225), restarts=0)
    with pytest.raises(ValueError) as e:
        model.predict(np.array([0.01, 0.02]), np.array([0.05]))
    text = str(e.value)
    assert "must have one length" in text, text
    # The internal check is named once, as the check that failed, after the rewording's own words.
    assert text.startswith("internal check GprModel::Predict failed"), text
    assert "check their values and units" in text, text
