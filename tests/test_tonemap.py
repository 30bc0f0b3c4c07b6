"""brdfpy.tonemap against the oracle: clamp (seed 000), Reinhard, extended Reinhard, ACES (Narkowicz),
exposure, sRGB both ways, and 8-bit quantisation."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest

from conftest import assert_close
from oracle import tonemap as otm

X = np.concatenate([np.linspace(-1, 2, 300), np.geomspace(1e-6, 1e4, 300)]).astype(np.float32).reshape(-1, 3)


@pytest.mark.parametrize("op", ["clamp", "reinhard", "aces"])
def test_operator_matches(op: str) -> None:
    got = getattr(brdfpy.tonemap, op)(X)
    assert got.shape == X.shape
    assert_close(got, getattr(otm, op)(X.astype(np.float64)), what=op)


@pytest.mark.parametrize("white", [1.0, 4.0, 11.2])
def test_reinhard_extended_matches_and_maps_white_to_one(white: float) -> None:
    got = brdfpy.tonemap.reinhard_extended(X, white)
    assert_close(got, otm.reinhard_extended(X.astype(np.float64), white))
    assert float(brdfpy.tonemap.reinhard_extended(np.array([white], np.float32), white)[0]) == pytest.approx(
        1.0
    )


@pytest.mark.parametrize("ev", [-2.0, 0.0, 1.5])
def test_exposure_scales_by_powers_of_two(ev: float) -> None:
    assert_close(brdfpy.tonemap.exposure(X, ev), otm.exposure(X.astype(np.float64), ev))


def test_hdr_operators_map_everything_into_the_unit_interval() -> None:
    for op in ("clamp", "reinhard", "aces"):
        y = np.asarray(getattr(brdfpy.tonemap, op)(X))
        assert y.min() >= 0.0 and y.max() <= 1.0, op
    # and they are monotonic on non-negative input
    x = np.geomspace(1e-4, 1e4, 1000).astype(np.float32)
    for op in ("reinhard", "aces"):
        assert np.all(np.diff(np.asarray(getattr(brdfpy.tonemap, op)(x), np.float64)) >= 0), op


def test_srgb_encode_and_decode() -> None:
    x = np.linspace(0, 1, 1001, dtype=np.float32)
    enc = brdfpy.tonemap.srgb_encode(x)
    assert_close(enc, otm.srgb_encode(x.astype(np.float64)))
    assert_close(brdfpy.tonemap.srgb_decode(x), otm.srgb_decode(x.astype(np.float64)))
    np.testing.assert_allclose(brdfpy.tonemap.srgb_decode(enc), x, atol=1e-5)


@pytest.mark.parametrize("op", ["clamp", "reinhard", "aces"])
def test_to_uint8(op: str) -> None:
    got = np.asarray(brdfpy.tonemap.to_uint8(X, operator=op))
    assert got.dtype == np.uint8 and got.shape == X.shape
    want = otm.to_uint8(X.astype(np.float64), op)
    # float32 vs float64 may land on the other side of a rounding boundary: at most one level apart
    assert np.max(np.abs(got.astype(int) - want.astype(int))) <= 1
    assert np.mean(got == want) > 0.99


def test_scene_check_value_to_8_bit() -> None:
    """SCENE.md: the centre pixel's linear colour goes through clamp + sRGB + floor(255 v + 0.5)."""
    c = np.array([0.810225, 0.311365, 0.211593], np.float32)
    want = otm.to_uint8(c.astype(np.float64))
    np.testing.assert_array_equal(brdfpy.tonemap.to_uint8(c), want)
