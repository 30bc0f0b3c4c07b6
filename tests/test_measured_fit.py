"""``brdfpy.measured.fit`` and ``compare``: every continuous parameter free unless fixed, no start needed,
tables fitted directly, standard errors that mean what they say, and the comparison views."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy import measured

from conftest import unit


def _pairs(rng: np.random.Generator, count: int, max_deg: float = 80.0) -> tuple[np.ndarray, np.ndarray]:
    """Unit (l, v) above the +z surface, uniform in solid angle up to ``max_deg``, half the views near the
    mirror direction (as a gonioreflectometer scan of the peak takes them)."""

    def hemi(k: int) -> np.ndarray:
        z = rng.uniform(math.cos(math.radians(max_deg)), 1.0, k)
        phi = rng.uniform(0, 2 * math.pi, k)
        s = np.sqrt(1 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)

    l, v = hemi(count), hemi(count)
    mirror = l * [-1, -1, 1] + rng.normal(scale=0.15, size=(count, 3))
    mirror[:, 2] = np.abs(mirror[:, 2]) + 0.2
    near = rng.uniform(size=count) < 0.5
    return l, np.where(near[:, None], unit(mirror), v)


def _data(model: brdfpy.Model, count: int, noise: float = 0.0, seed: int = 0) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    l, v = _pairs(rng, count)
    f = model.eval(l, v, [0, 0, 1]).astype(np.float64) * np.exp(noise * rng.normal(size=(count, 3)))
    return l, v, np.array([0.0, 0.0, 1.0]), f


TRUTH = {"kd": (0.5, 0.3, 0.1), "f0": (0.04, 0.06, 0.08), "roughness": 0.2}


def test_cook_torrance_is_recovered_with_no_start() -> None:
    """The issue's witness: fit("cook_torrance", l, v, n, values) on data of cook_torrance with known kd, F0
    and roughness recovers all of them with no start (ks stays at its default 1, the upper bound)."""
    truth = brdfpy.model("cook_torrance", **TRUTH)
    l, v, n, f = _data(truth, 3000)
    res = measured.fit("cook_torrance", l, v, n, f)
    assert res.converged, res.message
    assert res.params["roughness"] == pytest.approx(0.2, abs=1e-3)
    assert res.params["kd"] == pytest.approx(TRUTH["kd"], abs=1e-3)
    assert res.params["f0"] == pytest.approx(TRUTH["f0"], abs=1e-3)
    assert res.params["ks"] == pytest.approx((1.0,) * 3, abs=1e-3)
    assert {"ior", "eta", "k", "roughness2", "weight2"} <= set(res.inactive)
    assert all(e.relative_l2 < 1e-3 for e in res.errors)
    # The model is ready to render and evaluates as the data.
    np.testing.assert_allclose(res.model.eval(l, v, n), f, rtol=2e-3, atol=1e-6)
    # The same call with a tuple.
    again = measured.fit("cook_torrance", (l, v, n, f))
    assert again.params == res.params
    text = repr(res)
    assert "roughness" in text and "±" in text and "relative L2" in text


def test_fixed_parameters_stay_fixed() -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.35, kd=0.3, f0=0.05)
    l, v, n, f = _data(truth, 1500, seed=1)
    res = measured.fit("cook_torrance", l, v, n, f, fixed={"f0": 0.05, "roughness": 0.35})
    assert "f0" not in res.params and "roughness" not in res.params
    assert res.model.params["roughness"] == pytest.approx(0.35)
    assert res.model.params["f0"] == pytest.approx((0.05,) * 3)
    assert res.params["kd"] == pytest.approx((0.3,) * 3, abs=1e-4)
    # A wrong fixed value is kept, and the others do what they can: the fit reports its error.
    off = measured.fit("cook_torrance", l, v, n, f, fixed={"roughness": 0.6})
    assert off.model.params["roughness"] == pytest.approx(0.6)
    assert min(e.relative_l2 for e in off.errors) > 0.05


def test_lambert_fit_to_lambert_data_is_exact() -> None:
    l, v, n, f = _data(brdfpy.model("lambert", kd=(0.7, 0.2, 0.05)), 300, seed=2)
    res = measured.fit("lambert", l, v, n, f)
    assert res.params["kd"] == pytest.approx((0.7, 0.2, 0.05), abs=1e-6)
    assert res.cost < 1e-20 and res.converged


@pytest.mark.parametrize("loss", measured.LOSSES)
def test_every_loss_recovers_the_parameters(loss: str) -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.3, kd=(0.2, 0.4, 0.6))
    l, v, n, f = _data(truth, 1500, seed=3)
    res = measured.fit("cook_torrance", l, v, n, f, loss=loss, fixed={"ks": 1.0, "f0": 0.04})
    assert res.loss == loss
    assert res.params["roughness"] == pytest.approx(0.3, abs=1e-3)
    assert res.params["kd"] == pytest.approx((0.2, 0.4, 0.6), abs=1e-3)


def test_a_table_made_from_a_model_is_fitted_directly_and_recovers_it() -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.25, kd=(0.3, 0.2, 0.1))
    table = measured.Tabulated.from_model(truth, (45, 45, 90))
    for strategy in measured.STRATEGIES:
        res = measured.fit("cook_torrance", table, samples=5000, strategy=strategy)
        assert res.samples_used == 5000
        # The table interpolates between nodes: the fit recovers the model to the table's accuracy.
        assert res.params["roughness"] == pytest.approx(0.25, abs=0.01), strategy
        assert res.params["kd"] == pytest.approx((0.3, 0.2, 0.1), abs=0.01), strategy


def test_standard_errors_match_the_spread_of_repeated_noisy_fits_and_shrink_with_more_samples() -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.25, kd=0.4)
    fixed = {"ks": 1.0, "f0": 0.04}

    def spread_and_errors(loss: str, noisy: Any) -> tuple[float, np.ndarray, np.ndarray]:
        fits = [measured.fit("cook_torrance", *noisy(s), fixed=fixed, loss=loss) for s in range(12)]
        rough = np.array([r.params["roughness"] for r in fits])
        se = np.array([r.stderr["roughness"] for r in fits])
        robust = np.array([r.stderr_robust["roughness"] for r in fits])
        assert np.mean(np.abs(rough - 0.25) < robust) > 0.4  # about 2/3 within one standard error
        return float(rough.std(ddof=1)), se, robust

    # Additive noise of one spread under the linear loss: both estimates hold. 12 fits: the sample standard
    # deviation is within about ±40 % of the true one.
    def additive(s: int) -> tuple[np.ndarray, ...]:
        l, v, n, f = _data(truth, 600, seed=10 + s)
        return l, v, n, f + 0.01 * np.random.default_rng(s).normal(size=f.shape)

    spread, se, robust = spread_and_errors("linear", additive)
    assert 0.55 < spread / se.mean() < 1.6, (spread, se.mean())
    assert 0.55 < spread / robust.mean() < 1.6, (spread, robust.mean())
    # Multiplicative noise under the log loss: the residuals' spread grows with the value, and only the
    # sandwich estimate follows (the Gauss-Newton one was half the spread here).
    spread, se, robust = spread_and_errors("log", lambda s: _data(truth, 600, 0.05, 10 + s))
    assert 0.55 < spread / robust.mean() < 1.6, (spread, robust.mean())
    big = measured.fit("cook_torrance", *_data(truth, 4 * 600, 0.05, 99), fixed=fixed)
    # Four times the samples: half the standard error.
    assert big.stderr_robust["roughness"] == pytest.approx(robust.mean() / 2, rel=0.3)
    assert big.stderr["roughness"] == pytest.approx(se.mean() / 2, rel=0.3)


def test_a_choice_search_finds_the_distribution() -> None:
    truth = brdfpy.model("cook_torrance", distribution="beckmann", roughness=0.2)
    l, v, n, f = _data(truth, 1500, seed=4)
    res = measured.fit("cook_torrance", l, v, n, f, choices={"distribution": ["ggx", "beckmann"]})
    assert res.choices == {"distribution": "beckmann"}
    assert res.model.params["distribution"] == "beckmann"
    assert [dict(c)["distribution"] for c, _ in res.tried] == ["ggx", "beckmann"]
    assert res.params["roughness"] == pytest.approx(0.2, abs=1e-3)


def test_the_former_result_keys_still_read() -> None:
    truth = brdfpy.model("lambert", kd=0.5)
    res = measured.fit("lambert", *_data(truth, 100, seed=5))
    assert res["values"] == res.params and res["converged"] is True and res["model"] is res.model
    assert set(dict(res)) == {
        "model",
        "values",
        "rms_log_error",
        "epsilon",
        "iterations",
        "converged",
        "samples_used",
    }
    with pytest.raises(KeyError):
        res["params"]


def test_bad_input_is_refused_naming_the_argument() -> None:
    l, v, n, f = _data(brdfpy.model("cook_torrance"), 50, seed=6)
    fit = measured.fit
    with pytest.raises(ValueError, match=r"fixed: .*roughnes"):
        fit("cook_torrance", l, v, n, f, fixed={"roughnes": 0.2})
    with pytest.raises(ValueError, match=r"start: .*kdd"):
        fit("cook_torrance", l, v, n, f, start={"kdd": 0.2})
    with pytest.raises(ValueError, match=r"start: .*roughness.*\[0, 2\]"):
        fit("cook_torrance", l, v, n, f, start={"roughness": 5.0})
    with pytest.raises(ValueError, match=r"values: .*>= 0"):
        fit("cook_torrance", l, v, n, -f)
    with pytest.raises(ValueError, match="values"):
        fit("cook_torrance", l, v, n, f[:7])
    with pytest.raises(ValueError, match="l:"):
        fit("cook_torrance", l[:, :2], v, n, f)
    with pytest.raises(ValueError, match="weights"):
        fit("cook_torrance", l, v, n, f, weights=np.ones(3))
    with pytest.raises(ValueError, match="loss: expected one of log"):
        fit("cook_torrance", l, v, n, f, loss="l2")
    with pytest.raises(ValueError, match=r"choices: .*ggz"):
        fit("cook_torrance", l, v, n, f, choices={"distribution": ["ggz"]})
    with pytest.raises(ValueError, match="multistart"):
        fit("cook_torrance", l, v, n, f, multistart=-1)
    with pytest.raises(TypeError, match="data"):
        fit("cook_torrance", l)
    with pytest.raises(TypeError, match="model"):
        fit(brdfpy.model("lambert"), l, v, n, f)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="above the surface"):
        fit("lambert", -l, v, n, f)
    with pytest.raises(ValueError, match="nothing to fit"):
        fit("lambert", l, v, n, f, fixed={"kd": 0.5})
    table = measured.Tabulated.from_model(brdfpy.model("lambert"), (4, 4, 4))
    with pytest.raises(ValueError, match="samples"):
        fit("lambert", table, samples=3)
    with pytest.raises(ValueError, match="max_theta"):
        fit("lambert", table, max_theta=95.0)
    with pytest.raises(ValueError, match="strategy"):
        fit("lambert", table, strategy="grid")
    with pytest.raises(ValueError, match="values: every value"):
        fit("lambert", measured.Tabulated(np.zeros((4, 4, 4, 3))))


def test_compare_gives_error_maps_albedo_curves_and_a_lit_sphere_pair(tmp_path: Path) -> None:
    truth = brdfpy.model("cook_torrance", roughness=0.1, kd=(0.1, 0.05, 0.02), f0=0.9)
    table = measured.Tabulated.from_model(truth, (45, 45, 90))
    res = measured.fit("cook_torrance", table, samples=4000, fixed={"roughness": 0.3})
    c = measured.compare(table, res, size=(64, 48), sphere_size=128)
    assert c.log_error.shape == (48, 64, 3) and c.relative_error.shape == (48, 64, 3)
    assert c.valid.shape == (48, 64) and c.valid.any()
    # A too-rough fit: too dark at the peak (θ_h ≈ 0), too bright away from it.
    peak = c.log_error[c.valid[:, 0], 0].mean()
    assert peak < -0.1, peak
    assert c.data_albedo.values.shape == c.model_albedo.values.shape
    assert c.spheres.shape == (128, 256)
    path = tmp_path / "compare.png"
    c.spheres.save(path)
    assert path.stat().st_size > 1000
    # Left half the data, right half the fit: the fit's highlight is broader and dimmer.
    rgb = c.spheres.rgb.astype(np.float64)
    assert rgb[:, :128].max() > rgb[:, 128:].max()
    # A model against itself: no error.
    same = measured.compare(table, table.as_model(), size=16, sphere_size=32)
    assert np.all(same.log_error == 0)


def test_the_analytic_jacobian_and_central_differences_reach_the_same_fit() -> None:
    truth = brdfpy.model("cook_torrance", **TRUTH)
    data = _data(truth, 1500, noise=0.03, seed=7)
    a = measured.fit("cook_torrance", *data)
    b = measured.fit("cook_torrance", *data, jacobian="finite_difference")
    assert (a.jacobian, b.jacobian) == ("analytic", "finite_difference")
    for k, x in a.params.items():
        assert np.asarray(x) == pytest.approx(np.asarray(b.params[k]), abs=1e-4), k
    # Models without an analytic form fall back to differences.
    assert (
        measured.fit("blinn_phong", *_data(brdfpy.model("blinn_phong"), 300)).jacobian == "finite_difference"
    )


ISOTROPIC_TRUTHS = {
    "lambert": {"kd": (0.3, 0.5, 0.2)},
    "oren_nayar": {"kd": (0.3, 0.5, 0.2), "sigma": 0.4},
    "oren_nayar_full": {"kd": (0.3, 0.5, 0.2), "sigma": 0.4},
    "phong": {"kd": (0.3, 0.5, 0.2), "ks": 0.3, "shininess": 80.0},
    "blinn_phong": {"kd": (0.3, 0.5, 0.2), "ks": 0.3, "shininess": 80.0},
    "cook_torrance": {"kd": (0.3, 0.5, 0.2), "ks": 0.7, "roughness": 0.15, "f0": (0.9, 0.6, 0.3)},
}


def test_the_truths_cover_every_isotropic_physical_model() -> None:
    want = {
        m
        for m in brdfpy.models()
        if brdfpy.model_info(m)["physical"] and not brdfpy.model_info(m)["anisotropic"]
    }
    assert set(ISOTROPIC_TRUTHS) == want


@pytest.mark.parametrize("name", sorted(ISOTROPIC_TRUTHS))
def test_every_isotropic_physical_model_is_recovered_with_no_start(name: str) -> None:
    truth = brdfpy.model(name, **ISOTROPIC_TRUTHS[name])
    res = measured.fit(name, *_data(truth, 3000, seed=20))
    assert res.converged, res.message
    for k, x in res.params.items():
        want = np.asarray(truth.params[k], dtype=np.float64)
        # Exponents to a relative 1e-5, the rest to 1e-5 absolute (measured: at most 1.8e-6).
        np.testing.assert_allclose(np.asarray(x), want, rtol=1e-5, atol=1e-5, err_msg=k)
