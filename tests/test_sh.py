"""``brdfpy.sh``: the real SH basis against an independent NumPy oracle, and the physics that does not need
one — orthonormality under the quadrature, the clamped cosine's zonal coefficients (Ramamoorthi & Hanrahan
2001), exact round trips of band-limited functions, and convergence of a BRDF lobe's projection."""

from __future__ import annotations

import math

import brdfpy
import numpy as np
import pytest
from brdfpy import sh

from oracle import sh as osh


def test_basis_matches_the_oracle_to_order_12() -> None:
    d = np.random.default_rng(1).normal(size=(300, 3))
    d[0] = [0, 0, 1]  # the pole, where φ is undefined
    d[1] = [0, 0, -2]
    np.testing.assert_allclose(sh.basis(d, 12), osh.basis(d, 12), atol=1e-12)


def test_single_direction_gives_a_row_and_zero_length_gives_zeros() -> None:
    y = sh.basis([0.0, 0.0, 3.0], 1)
    assert y.shape == (4,)
    c = math.sqrt(3 / (4 * math.pi))
    np.testing.assert_allclose(y, [1 / math.sqrt(4 * math.pi), 0.0, c, 0.0], atol=1e-15)
    np.testing.assert_array_equal(sh.basis([[0.0, 0.0, 0.0]], 2), np.zeros((1, 9)))


def test_basis_is_orthonormal_under_the_quadrature_of_its_order() -> None:
    q = sh.quadrature(10)
    y = sh.basis(q.directions, 10)
    gram = (y * q.weights[:, None]).T @ y
    np.testing.assert_allclose(gram, np.eye(121), atol=1e-12)
    assert q.weights.sum() == pytest.approx(4 * math.pi, rel=1e-14)


@pytest.mark.parametrize("l", range(9))
def test_clamped_cosine_projects_onto_its_closed_form_coefficients(l: int) -> None:
    c = sh.project(lambda d: np.maximum(d[:, 2], 0.0), order=8, quad=sh.quadrature(8))
    a_hat = math.sqrt(4 * math.pi / (2 * l + 1)) * c[sh.index(l, 0)]
    # Two independent references: exact polynomial integration (oracle) and R-H's closed form (in brdfpy).
    assert a_hat == pytest.approx(osh.clamped_cosine_zonal(l), abs=1e-13)
    assert a_hat == pytest.approx(sh.clamped_cosine_zonal(l), abs=1e-13)
    others = [c[sh.index(l, m)] for m in range(-l, l + 1) if m != 0]
    np.testing.assert_allclose(others, 0.0, atol=1e-13)


def test_first_zonal_coefficients_are_pi_two_pi_over_three_and_pi_over_four() -> None:
    # Recomputed from ∫ μ P_l(μ) dμ, not copied: P_0 = 1 → 2π·½; P_1 = μ → 2π·⅓; P_2 = (3μ² − 1)/2 → 2π·⅛.
    assert [sh.clamped_cosine_zonal(l) for l in range(3)] == pytest.approx(
        [2 * math.pi / 2, 2 * math.pi / 3, 2 * math.pi / 8], rel=1e-15
    )


def test_band_limited_functions_round_trip_exactly() -> None:
    rng = np.random.default_rng(2)
    coeffs = rng.normal(size=(sh.num_coeffs(6), 3))
    q = sh.quadrature(6)
    values = sh.reconstruct(coeffs, q.directions)
    np.testing.assert_allclose(sh.project(values, 6, q), coeffs, atol=1e-12)
    # Scalars as well as RGB; a callable as well as values.
    scalar = sh.project(lambda d: values[:, 1], 6, q)
    assert scalar.shape == (49,)
    np.testing.assert_allclose(scalar, coeffs[:, 1], atol=1e-12)
    one = sh.reconstruct(coeffs[:, 0], q.directions[5])
    assert one == pytest.approx(values[5, 0], abs=1e-12)


def _lobe_error(order: int, fine: sh.Quadrature, values: np.ndarray) -> float:
    c = sh.project(values, order, fine)
    rec = sh.reconstruct(c, fine.directions)
    num = np.sum(fine.weights[:, None] * (values - rec) ** 2)
    den = np.sum(fine.weights[:, None] * values**2)
    return float(np.sqrt(num / den))


def test_projection_of_a_brdf_lobe_times_cosine_converges_with_the_order() -> None:
    m = brdfpy.model("cook_torrance", roughness=0.3, kd=0.2)
    fine = sh.quadrature(n_mu=96, n_phi=192)
    v = np.array([0.6, 0.0, 0.8])
    values = m.shade(fine.directions, v, [0.0, 0.0, 1.0]).astype(np.float64)
    errs = [_lobe_error(order, fine, values) for order in (1, 2, 4, 8, 16)]
    # Parseval: adding bands can only lower the L2 error; a roughness-0.3 lobe needs ~16 bands for a few %.
    assert all(b < a for a, b in zip(errs, errs[1:])), errs
    assert errs[-1] < 0.03, errs


def test_irradiance_by_coefficients_equals_the_direct_cosine_integral() -> None:
    # Radiance: a band-limited (order 5) random RGB function; E(n) = ∫ L(ω) max(n·ω, 0) dω computed directly
    # with the oracle basis on a fine rule, against reconstruct(irradiance(coefficients)).
    rng = np.random.default_rng(11)
    coeffs = rng.normal(size=(36, 3))
    q = sh.quadrature(n_mu=40, n_phi=80)
    radiance = osh.basis(q.directions, 5) @ coeffs
    normals = rng.normal(size=(5, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    cosine = np.maximum(normals @ q.directions.T, 0.0)  # (5, M): the kink is not at the rule's equator
    direct = cosine @ (q.weights[:, None] * radiance)
    via_sh = sh.reconstruct(sh.irradiance(coeffs), normals)
    # The direct rule is not exact across the tilted kink (measured: 2.6e-5 of the peak); allow 2e-4.
    np.testing.assert_allclose(via_sh, direct, atol=2e-4 * np.abs(direct).max())
    # Constant radiance 1 → E = π for every normal.
    one = np.zeros(4)
    one[0] = math.sqrt(4 * math.pi)
    assert sh.reconstruct(sh.irradiance(one), [0.3, -0.2, 0.9]) == pytest.approx(math.pi, rel=1e-14)


def test_bad_arguments_are_refused_with_their_name() -> None:
    with pytest.raises(ValueError, match="order"):
        sh.basis([0, 0, 1], sh.MAX_ORDER + 1)
    with pytest.raises(TypeError, match="order"):
        sh.basis([0, 0, 1], 2.5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="directions"):
        sh.basis(np.zeros((4, 2)), 2)
    with pytest.raises(ValueError, match="directions"):
        sh.basis([[np.nan, 0, 1]], 2)
    q = sh.quadrature(2)
    with pytest.raises(ValueError, match="f: expected values"):
        sh.project(np.ones(5), 2, q)
    with pytest.raises(ValueError, match="values"):
        sh.project(np.full(len(q.weights), np.inf), 2, q)
    with pytest.raises(ValueError, match="coeffs"):
        sh.reconstruct(np.ones(5), [0, 0, 1])
    with pytest.raises(ValueError, match="n_mu"):
        sh.quadrature(n_mu=0, n_phi=3)
    with pytest.raises(ValueError, match="kernel"):
        sh.convolve(np.ones(9), [1.0, 2.0])
    with pytest.raises(ValueError, match="coeffs"):
        sh.convolve(np.ones(8), [1.0, 2.0])
    with pytest.raises(ValueError, match="either"):
        sh.quadrature(2, n_mu=3, n_phi=3)
