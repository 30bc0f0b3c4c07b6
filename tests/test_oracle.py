"""The oracle checks itself (no brdfpy): two independent formulations of each disputed formula agree,
and each D is normalised. If these fail, fix the oracle before believing any brdfpy comparison."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import gauss_legendre01
from oracle import fresnel as ofr
from oracle import microfacet as omf
from oracle import models as om
from oracle import tonemap as otm

C = np.linspace(0.0, 1.0, 1001)


@pytest.mark.parametrize("eta", [1.001, 1.33, 1.5, 2.4, 1 / 1.5])
def test_dielectric_gc_form_equals_the_angle_form(eta: float) -> None:
    rs, rp = ofr.dielectric_sp(C, eta)
    np.testing.assert_allclose(ofr.dielectric(C, eta), (rs + rp) / 2, atol=1e-12)


@pytest.mark.parametrize("eta", [1.33, 1.5, 2.4])
def test_conductor_without_absorption_is_the_dielectric(eta: float) -> None:
    np.testing.assert_allclose(ofr.conductor(C, eta, 0.0), ofr.dielectric(C, eta), atol=1e-12)


@pytest.mark.parametrize(("eta", "k"), [(0.2, 3.9), (1.1, 2.2), (2.9, 3.1)])
def test_complex_conductor_equals_seed_001s_real_form(eta: float, k: float) -> None:
    c = C[C > 1e-3]
    np.testing.assert_allclose(ofr.conductor(c, eta, k), ofr.conductor_ab(c, eta, k), rtol=1e-8)


def test_dielectric_limits() -> None:
    assert ofr.dielectric(np.array(1.0), 1.5) == pytest.approx(0.04, rel=1e-12)
    assert ofr.dielectric(np.array(0.0), 1.5) == pytest.approx(1.0)
    assert ofr.dielectric(np.array(-0.5), 1.5) == 1.0  # inside, beyond the critical angle


def _projected_integral(d: np.ndarray, mu: np.ndarray, weights: np.ndarray) -> float:
    return float(np.sum(d * mu * weights))


@pytest.mark.parametrize(
    ("name", "alpha", "alpha_y"),
    [
        ("beckmann", 0.1, None),
        ("beckmann", 0.3, 0.7),
        ("ggx", 0.2, None),
        ("ggx", 0.1, 0.5),
        ("gaussian", 0.05, None),
        ("gaussian", 0.6, None),
        ("blinn_phong", 0.2, None),
        ("ward", 0.3, 0.1),
    ],
)
def test_oracle_distributions_are_normalised(name: str, alpha: float, alpha_y: float | None) -> None:
    mu, w_mu = gauss_legendre01(1024)
    n_phi = 128
    phi = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    mm, pp = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - mm**2)
    d = om.distribution(name, s * np.cos(pp), s * np.sin(pp), mm, alpha, alpha_y)
    assert _projected_integral(d, mm, w_mu[:, None] * 2 * np.pi / n_phi) == pytest.approx(1.0, abs=1e-4)


def test_smith_lambda_beckmann_limits() -> None:
    # Lambda -> 0 for directions near the normal, grows without bound toward grazing
    w = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.999, 0.0, 0.0447]])
    lam = omf.lambda_beckmann(w[:, 0], w[:, 1], w[:, 2], 0.3)
    assert lam[0] == 0.0 and 0 < lam[1] < 1e-3 < lam[2]


def test_tonemap_oracle_round_trips() -> None:
    x = np.linspace(0, 1, 101)
    np.testing.assert_allclose(otm.srgb_decode(otm.srgb_encode(x)), x, atol=1e-12)
    assert otm.reinhard_extended(np.array(4.0), 4.0) == pytest.approx(1.0)


def test_oren_nayar_oracle_at_zero_roughness_is_lambert() -> None:
    rng = np.random.default_rng(0)
    l, v = rng.normal(size=(2, 100, 3)) + np.array([0.0, 0.0, 2.0])
    for name in ("oren_nayar", "oren_nayar_full"):
        f = om.evaluate(name, {"kd": 0.5, "sigma": 0.0}, l, v, [0, 0, 1])
        np.testing.assert_allclose(f[f > 0], 0.5 / np.pi, rtol=1e-12)
