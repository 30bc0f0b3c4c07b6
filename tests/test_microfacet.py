"""brdfpy.microfacet (D and G terms) and brdfpy.vectors against the oracle."""

from __future__ import annotations

from typing import Any

import brdfpy
import numpy as np
import pytest

from conftest import assert_close, hemisphere, unit
from oracle import microfacet as omf
from oracle import models as om
from oracle import vectors as ovec


def half_vectors(rng: np.random.Generator, count: int) -> dict[str, np.ndarray]:
    """Half vectors spread from the normal to 89.9 degrees (dense near the normal where lobes peak)."""
    n = unit(rng.normal(size=(count, 3)))
    cos_t = np.concatenate([rng.uniform(0.001, 1, count // 2), 1 - rng.exponential(0.02, count - count // 2)])
    h = hemisphere(rng, n, np.clip(cos_t, 0.001, 1))
    t = rng.normal(size=(count, 3))
    return {"h": h.astype(np.float32), "n": n.astype(np.float32), "tangent": t.astype(np.float32)}


def oracle_d(name: str, g: dict[str, np.ndarray], alpha: float, alpha_y: float | None) -> np.ndarray:
    h, n = g["h"].astype(np.float64), unit(g["n"].astype(np.float64))
    h = unit(h)
    t, b = ovec.frame(n, g["tangent"].astype(np.float64) if alpha_y is not None else None)
    hx, hy, hz = omf.local(h, t, b, n)
    return om.distribution(name, hx, hy, hz, alpha, alpha_y)


D_CASES: list[tuple[str, float, float | None]] = [
    ("beckmann", 0.05, None),
    ("beckmann", 0.3, None),
    ("beckmann", 0.9, None),
    ("beckmann", 0.1, 0.5),
    ("ggx", 0.05, None),
    ("ggx", 0.3, None),
    ("ggx", 1.0, None),
    ("ggx", 0.5, 0.1),
    ("gaussian", 0.1, None),
    ("gaussian", 0.5, None),
    ("blinn_phong", 0.1, None),
    ("blinn_phong", 0.6, None),
    ("ward", 0.2, None),
    ("ward", 0.1, 0.4),
    ("ashikhmin_shirley", 20.0, None),
    ("ashikhmin_shirley", 100.0, 10.0),
]


@pytest.mark.parametrize(("name", "alpha", "alpha_y"), D_CASES)
def test_distribution_matches_oracle(
    name: str, alpha: float, alpha_y: float | None, rng: np.random.Generator
) -> None:
    g = half_vectors(rng, 5000)
    kwargs: dict[str, Any] = {} if alpha_y is None else {"alpha_y": alpha_y, "tangent": g["tangent"]}
    got = np.asarray(brdfpy.microfacet.distribution(g["h"], g["n"], alpha, distribution=name, **kwargs))
    assert got.shape == (5000,) and got.dtype == np.float32
    want = oracle_d(name, g, alpha, alpha_y)
    assert_close(got, want, what=f"D {name} alpha={alpha} alpha_y={alpha_y}")


def test_isotropic_distribution_ignores_the_tangent(rng: np.random.Generator) -> None:
    g = half_vectors(rng, 1000)
    a = brdfpy.microfacet.distribution(g["h"], g["n"], 0.3)
    b = brdfpy.microfacet.distribution(g["h"], g["n"], 0.3, alpha_y=0.3, tangent=g["tangent"])
    np.testing.assert_allclose(a, b, rtol=1e-5)


def test_distribution_is_zero_below_the_surface() -> None:
    h = np.array([[0.0, 0.6, -0.8], [1.0, 0.0, 0.0]], np.float32)
    n = np.array([0.0, 0.0, 1.0], np.float32)
    for name in ("beckmann", "ggx", "gaussian", "blinn_phong", "ward"):
        d = brdfpy.microfacet.distribution(h, n, 0.3, distribution=name)
        assert np.all(d == 0), name


def pairs(rng: np.random.Generator, count: int) -> dict[str, np.ndarray]:
    n = unit(rng.normal(size=(count, 3)))
    l = hemisphere(rng, n, rng.uniform(0.002, 1, count))
    v = hemisphere(rng, n, rng.uniform(0.002, 1, count))
    return {"l": l.astype(np.float32), "v": v.astype(np.float32), "n": n.astype(np.float32)}


@pytest.mark.parametrize("masking", ["smith", "smith_separable", "v_groove", "kelemen"])
@pytest.mark.parametrize(
    ("dist", "alpha"), [("ggx", 0.1), ("ggx", 0.7), ("beckmann", 0.2), ("beckmann", 0.8)]
)
def test_masking_matches_oracle(masking: str, dist: str, alpha: float, rng: np.random.Generator) -> None:
    g = pairs(rng, 5000)
    got = np.asarray(
        brdfpy.microfacet.masking(g["l"], g["v"], g["n"], alpha, masking=masking, distribution=dist)
    )
    assert got.shape == (5000,)
    geo = om.geometry(*(g[k].astype(np.float64) for k in ("l", "v", "n")))
    want = om.masking(masking, geo, alpha, dist)
    assert_close(got, want, what=f"G {masking} {dist} alpha={alpha}")
    if masking != "kelemen":  # Kelemen's cheap G is not bounded by 1 (it is 1/(l.h)^2 times n.l n.v)
        assert np.all((got >= 0) & (got <= 1 + 1e-6))


def test_smith_forms_agree_in_the_smooth_limit_and_separable_is_smaller() -> None:
    """Notes b5: separable <= height-correlated, equal when one side is unmasked."""
    n = np.array([0.0, 0.0, 1.0], np.float32)
    l = np.array([0.954, 0.0, 0.3], np.float32)
    v = np.array([-0.954, 0.0, 0.3], np.float32)
    for alpha in (1.0, 0.5, 0.1):
        corr = brdfpy.microfacet.masking(l, v, n, alpha, masking="smith", distribution="ggx")
        sep = brdfpy.microfacet.masking(l, v, n, alpha, masking="smith_separable", distribution="ggx")
        assert np.all(sep <= corr + 1e-7)
    up = np.array([0.0, 0.0, 1.0], np.float32)
    corr = brdfpy.microfacet.masking(l, up, n, 0.5, masking="smith", distribution="ggx")
    sep = brdfpy.microfacet.masking(l, up, n, 0.5, masking="smith_separable", distribution="ggx")
    np.testing.assert_allclose(corr, sep, rtol=1e-6)


def test_seed_001_ggx_g1_is_the_smith_lambda_form() -> None:
    """Oracle self-check: seed 001's 2/(1 + sqrt(1 + m^2 tan^2)) equals 1/(1 + Lambda_GGX)."""
    theta = np.linspace(0, 1.55, 100)
    w = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
    lam = omf.lambda_ggx(w[:, 0], w[:, 1], w[:, 2], 0.4)
    np.testing.assert_allclose(omf.g1_ggx_seed(np.tan(theta), 0.4), 1 / (1 + lam), rtol=1e-12)


# ------------------------------------------------------------------------------------- vectors


def test_reflect_halfway_refract_match(rng: np.random.Generator) -> None:
    g = pairs(rng, 2000)
    n = unit(g["n"].astype(np.float64)).astype(np.float32)
    l = unit(g["l"].astype(np.float64)).astype(np.float32)
    v = unit(g["v"].astype(np.float64)).astype(np.float32)
    assert_close(brdfpy.vectors.reflect(l, n), ovec.reflect(l.astype(np.float64), n.astype(np.float64)))
    assert_close(brdfpy.vectors.halfway(l, v), ovec.halfway(l.astype(np.float64), v.astype(np.float64)))
    for eta in (1.5, 1 / 1.5):
        t, ok = brdfpy.vectors.refract(l, n, eta)
        wt, wok = ovec.refract(l.astype(np.float64), n.astype(np.float64), eta)
        ok = np.asarray(ok, bool)
        # the TIR boundary itself is ill conditioned: compare the decision away from it
        cos_i = np.einsum("ij,ij->i", l.astype(np.float64), n.astype(np.float64))
        sin2_t = (1 - cos_i**2) / eta**2
        clear = np.abs(sin2_t - 1) > 1e-4
        np.testing.assert_array_equal(ok[clear], wok[clear])
        both = ok & wok & clear
        assert_close(np.asarray(t)[both], wt[both], what=f"refract eta={eta}")


def test_refraction_obeys_snell() -> None:
    n = np.array([0.0, 0.0, 1.0], np.float32)
    w = np.array([0.6, 0.0, 0.8], np.float32)
    t, ok = brdfpy.vectors.refract(w, n, 1.5)
    t = np.asarray(t, np.float64).reshape(3)
    assert bool(np.asarray(ok).reshape(-1)[0])
    assert t[2] < 0 and abs(np.linalg.norm(t) - 1) < 1e-6
    assert abs(t[0]) == pytest.approx(0.6 / 1.5, rel=1e-5)


@pytest.mark.parametrize(
    ("dist", "alpha"), [("ggx", 0.05), ("ggx", 0.6), ("beckmann", 0.1), ("beckmann", 0.9)]
)
def test_smith_lambda_and_g1_match_oracle(dist: str, alpha: float, rng: np.random.Generator) -> None:
    n = unit(rng.normal(size=(3000, 3)))
    w = hemisphere(rng, n, rng.uniform(0.01, 1, 3000))
    lam = np.asarray(
        brdfpy.microfacet.lambda_(w.astype(np.float32), n.astype(np.float32), alpha, distribution=dist)
    )
    g1 = np.asarray(
        brdfpy.microfacet.g1(w.astype(np.float32), n.astype(np.float32), alpha, distribution=dist)
    )
    t, b = ovec.frame(n, None)
    wx, wy, wz = omf.local(w, t, b, n)
    want = om.smith_lambda(dist, wx, wy, wz, alpha)
    # Lambda -> 0 toward the normal: compare with an absolute floor of 1e-6 there
    np.testing.assert_allclose(lam, want, rtol=1e-3, atol=1e-6)
    np.testing.assert_allclose(g1, 1 / (1 + want), rtol=1e-3, atol=1e-6)


def test_mixture_is_the_normalised_weighted_sum(rng: np.random.Generator) -> None:
    g = half_vectors(rng, 3000)
    lobes = [(3.0, "beckmann", 0.1), (1.0, "ggx", 0.4)]
    got = np.asarray(brdfpy.microfacet.mixture(lobes, g["h"], g["n"]))
    want = 0.75 * oracle_d("beckmann", g, 0.1, None) + 0.25 * oracle_d("ggx", g, 0.4, None)
    assert_close(got, want, what="mixture")
