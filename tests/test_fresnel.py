"""brdfpy.fresnel against the oracle (Cook-Torrance g/c dielectric, seed 001's angle form for s/p,
complex-arithmetic conductor), over the whole range of cosines including grazing and inside."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

from conftest import assert_close
from oracle import fresnel as ofr

COS = np.concatenate(
    [np.linspace(0.0, 1.0, 2001), np.cos(np.deg2rad(np.linspace(85, 90, 200)))]  # dense near grazing
).astype(np.float32)


@pytest.mark.parametrize("eta", [1.0001, 1.33, 1.5, 2.4, 4.0])
def test_dielectric_matches_the_cook_torrance_form(eta: float) -> None:
    got = brdfpy.fresnel.dielectric(COS, eta)
    assert got.shape == COS.shape and got.dtype == np.float32
    assert_close(got, ofr.dielectric(COS.astype(np.float64), eta), what=f"eta={eta}")


@pytest.mark.parametrize("eta", [1.33, 1.5, 2.4])
def test_dielectric_from_inside_flips_eta_and_saturates_at_tir(eta: float) -> None:
    inside = -COS
    got = brdfpy.fresnel.dielectric(inside, eta)
    want = ofr.dielectric(inside.astype(np.float64), eta)
    # Right at the critical angle F jumps from < 1 to 1 with infinite slope: compare away from it.
    crit = np.sqrt(1 - 1 / eta**2)
    away = np.abs(COS.astype(np.float64) - crit) > 1e-3
    assert_close(got, want, away, what=f"inside eta={eta}")
    assert np.all(got[COS < crit * 0.999] == 1.0)


@pytest.mark.parametrize("eta", [1.33, 1.5, 2.4])
def test_s_and_p_reflectances_match_seed_001s_angle_form(eta: float) -> None:
    rs, rp = brdfpy.fresnel.dielectric_sp(COS, eta)
    wrs, wrp = ofr.dielectric_sp(COS.astype(np.float64), eta)
    assert_close(rs, wrs, what="rs")
    assert_close(rp, wrp, what="rp")
    # unpolarised = mean of the two; p vanishes at Brewster's angle tan(theta_B) = eta
    assert_close((np.asarray(rs, np.float64) + rp) / 2, ofr.dielectric(COS.astype(np.float64), eta))
    cos_b = np.float32(np.cos(np.arctan(eta)))
    assert brdfpy.fresnel.dielectric_sp(np.array([cos_b]), eta)[1][0] < 1e-6


@pytest.mark.parametrize(
    ("eta", "k"),
    [(0.2, 3.9), (1.1, 2.2), (0.14, 3.98), (2.9, 3.1), (1.5, 0.0), ([0.2, 0.9, 1.1], [3.9, 2.4, 2.2])],
)
def test_conductor_matches_complex_arithmetic(eta: float | list[float], k: float | list[float]) -> None:
    got = np.asarray(brdfpy.fresnel.conductor(COS, eta, k))
    rgb = isinstance(eta, list)
    assert got.shape == ((len(COS), 3) if rgb else COS.shape)
    c = COS.astype(np.float64)
    want = ofr.conductor(c[:, None], eta, k) if rgb else ofr.conductor(c, eta, k)
    assert_close(got, want, what=f"eta={eta} k={k}")
    # seed 001's real a^2/b^2 closed form agrees with the complex form (oracle self-check)
    inner = c > 1e-3
    wab = ofr.conductor_ab(c[:, None], eta, k) if rgb else ofr.conductor_ab(c, eta, k)
    np.testing.assert_allclose(wab[inner], want[inner], rtol=1e-9)


@pytest.mark.parametrize("f0", [0.02, 0.04, 0.5, 0.95])
def test_schlick_matches(f0: float) -> None:
    assert_close(brdfpy.fresnel.schlick(COS, f0), ofr.schlick(COS.astype(np.float64), f0))


def test_schlick_with_rgb_f0() -> None:
    f0 = [0.95, 0.64, 0.54]
    got = np.asarray(brdfpy.fresnel.schlick(COS, f0))
    assert got.shape == (len(COS), 3)
    assert_close(got, ofr.schlick(COS.astype(np.float64)[:, None], np.array(f0)))


@pytest.mark.parametrize("eta", [1.2, 1.5, 2.0, 3.0])
def test_f0_and_ior_round_trip(eta: float) -> None:
    f0 = brdfpy.fresnel.f0_from_ior(eta)
    assert f0 == pytest.approx(float(ofr.f0_from_ior(eta)), rel=1e-6)
    assert brdfpy.fresnel.ior_from_f0(f0) == pytest.approx(
        float(ofr.ior_from_f0(ofr.f0_from_ior(eta))), rel=1e-5
    )


def test_metal_f0_table_is_seed_001s() -> None:
    """The table is data (seed 001 "Fresnel - base specular color", linear column), not a computed figure."""
    assert {m.lower() for m in brdfpy.fresnel.METALS} == set(ofr.METAL_F0)
    for name, f0 in ofr.METAL_F0.items():
        np.testing.assert_allclose(brdfpy.fresnel.metal_f0(name), f0, rtol=1e-6, err_msg=name)


def test_any_shape_of_cosines_is_kept() -> None:
    c = np.linspace(0, 1, 24, dtype=np.float32).reshape(2, 3, 4)
    assert np.asarray(brdfpy.fresnel.dielectric(c, 1.5)).shape == (2, 3, 4)
    assert np.asarray(brdfpy.fresnel.schlick(c, 0.04)).shape == (2, 3, 4)
