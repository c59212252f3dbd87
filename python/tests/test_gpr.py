"""fit_gpr against the command line's fit-gpr and predict-gpr (the C++ GprModel) on the same samples."""

import csv

import numpy as np
import pytest

import motionblocks as mb
from conftest import read_json

TAU = 0.0225  # pole pitch [m]


@pytest.fixture(scope="module")
def samples():
    rng = np.random.default_rng(7)
    n = 3000
    x = rng.uniform(0.0, 0.2, n)
    xdot = rng.choice([0.05, 0.1, 0.2], n) + rng.normal(0.0, 0.002, n)
    d = 0.5 * np.sin(2 * np.pi * x / TAU) * (1 + xdot) + 0.3 * xdot + rng.normal(0.0, 0.02, n)
    return x, xdot, d


def write_csv(path, **columns):
    names = list(columns)
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(names)
        for row in zip(*columns.values()):
            w.writerow([repr(float(v)) for v in row])


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    values = np.array(rows[1:], dtype=float)
    return {name: values[:, j] for j, name in enumerate(rows[0])}


def test_fit_gpr_predicts_as_the_command_lines_model(samples, command, tmp_path):
    x, xdot, d = samples
    write_csv(tmp_path / "train.csv", position_m=x, velocity_m_s=xdot, disturbance=d)
    command("fit-gpr", tmp_path / "train.csv", "--disturbance-column", "disturbance", "--kernel", "PS", "--period",
            TAU, "-o", tmp_path / "cli_model.json")
    xq = np.linspace(-0.01, 0.21, 101)
    vq = np.full_like(xq, 0.1)
    write_csv(tmp_path / "query.csv", position_m=xq, velocity_m_s=vq)
    command("predict-gpr", tmp_path / "cli_model.json", tmp_path / "query.csv", "-o", tmp_path / "cli_pred.csv")
    cli = read_csv(tmp_path / "cli_pred.csv")

    model = mb.fit_gpr(x, xdot, d, kernel="PS", period=TAU)
    mean, std = model.predict(xq, vq)
    assert mean.shape == (101,) and std.shape == (101,)
    np.testing.assert_allclose(mean, cli["mean"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(std, cli["std"], rtol=1e-9, atol=1e-12)
    cli_h = read_json(tmp_path / "cli_model.json")["hyperparameters"]
    for name, value in model.hyperparameters.items():
        assert value == pytest.approx(cli_h[name], rel=1e-9), name
    # and it learned the ripple: the prediction follows the truth within a few noise levels
    truth = 0.5 * np.sin(2 * np.pi * xq / TAU) * 1.1 + 0.03
    inside = (xq >= 0.0) & (xq <= 0.2)
    assert np.max(np.abs(mean[inside] - truth[inside])) < 0.05


def test_save_writes_the_file_the_gpr_block_loads(samples, tmp_path):
    x, xdot, d = samples
    model = mb.fit_gpr(x, xdot, d, kernel="DS", restarts=0)
    model.save(tmp_path / "m.json")
    again = mb.GprModel.load(tmp_path / "m.json")
    assert again.kernel == "DS" and again.feature_count == model.feature_count
    a, sa = model.predict(x[:50], xdot[:50])
    b, sb = again.predict(x[:50], xdot[:50])
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(sa, sb)
    assert read_json(tmp_path / "m.json")["kernel"] == "DS"


def test_the_models_repr_shows_its_hyperparameters(samples):
    model = mb.fit_gpr(*samples, kernel="PS", period=TAU, restarts=0)
    h = model.hyperparameters
    assert repr(model) == (f"<GprModel PS: period {TAU:.4g} m, ℓ_x {h['length_scale_x']:.3g}, ℓ_ẋ "
                           f"{h['length_scale_xdot']:.3g} m/s; noise σ {np.sqrt(h['noise_variance']):.3g}; "
                           f"{model.feature_count} features, N = 3000 samples>")
    # the samples' noise (σ 0.02) and what of the product sin(2πx/τ)·ẋ a sum of kernels cannot hold
    assert 0.02 <= np.sqrt(h["noise_variance"]) < 0.04
    ds = mb.fit_gpr(*samples, kernel="DS", restarts=0)
    assert repr(ds).startswith(f"<GprModel DS: ℓ_x {ds.hyperparameters['length_scale_x']:.3g} m, ℓ_ẋ ")


def test_bad_samples_raise_value_errors():
    with pytest.raises(ValueError) as e:
        mb.fit_gpr([0.0, 0.1], [0.1, 0.1, 0.1], [1.0, 2.0])
    assert str(e.value) == "fit_gpr: x, xdot and d must have one length (got 2, 3 and 2)"
    with pytest.raises(ValueError) as e:
        mb.fit_gpr([0.0, 0.1, 0.2], [0.1, 0.2, 0.3], [1.0, 2.0, 3.0], kernel="XS")
    assert "PS" in str(e.value) and "DS" in str(e.value)


def test_nan_or_inf_inputs_to_predict_raise_value_errors_naming_the_argument(samples):
    model = mb.fit_gpr(*samples, restarts=0)
    with pytest.raises(ValueError) as e:
        model.predict(np.array([0.1, np.nan]), np.array([0.1, 0.1]))
    assert str(e.value) == "predict(): x[1] is nan: give finite numbers (drop or fill the samples that are not)"
    with pytest.raises(ValueError) as e:
        model.predict(np.array([0.1]), np.array([-np.inf]))
    assert str(e.value).startswith("predict(): xdot[0] is -inf")


def test_a_model_file_that_is_not_json_is_a_value_error(tmp_path):
    (tmp_path / "m.json").write_text("[1, 2")
    with pytest.raises(ValueError) as e:
        mb.GprModel.load(tmp_path / "m.json")
    assert str(e.value).startswith(f"{tmp_path / 'm.json'}: not valid JSON (corrupt or truncated?): parse error at "
                                   "line 1, column 6")


def test_a_missing_model_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError) as e:
        mb.GprModel.load(tmp_path / "none.json")
    assert str(tmp_path / "none.json") in str(e.value)
