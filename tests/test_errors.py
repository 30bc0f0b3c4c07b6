"""The error contract: bad input raises ValueError/TypeError whose message names the argument;
degenerate but legal geometry (zero-length vectors, directions below the horizon) gives 0, never NaN."""

from __future__ import annotations

import re
from typing import Any

import brdfpy
import numpy as np
import pytest

from conftest import REGISTRY_MODELS as MODELS

GOOD = np.array([[0.0, 0.6, 0.8], [0.3, 0.0, 0.95]], np.float32)
N = np.array([0.0, 0.0, 1.0], np.float32)


def names(arg: str) -> str:
    """A regex that finds the argument's name as a word in the message."""
    return rf"(?<![A-Za-z_]){re.escape(arg)}(?![A-Za-z_])"


def call(method: str, **over: Any) -> Any:
    args = {"l": GOOD, "v": GOOD[::-1].copy(), "n": N}
    args.update(over)
    m = brdfpy.model("cook_torrance")
    return getattr(m, method)(**args)


# ---------------------------------------------------------------------------------------- arrays

BAD_ARRAYS: list[tuple[str, Any]] = [
    ("wrong width", np.zeros((5, 4), np.float32)),
    ("1-D of length 2", np.zeros(2, np.float32)),
    ("3-D of width 4", np.zeros((2, 3, 4), np.float32)),
    ("scalar", np.float32(1.0)),
    ("empty", np.zeros((0, 3), np.float32)),
    ("ragged", [[0.0, 0.0, 1.0], [0.0, 1.0]]),
    ("strings", np.array([["a", "b", "c"]])),
    ("objects", np.array([[None, 1.0, 2.0]], dtype=object)),
    ("complex", np.array([[1j, 0.0, 1.0]])),
    ("nan", np.array([[0.0, np.nan, 1.0], [0.0, 0.0, 1.0]], np.float32)),
    ("inf", np.array([[0.0, np.inf, 1.0], [0.0, 0.0, 1.0]], np.float32)),
    ("-inf in float64", np.array([[-np.inf, 0.0, 1.0]], np.float64)),
]


@pytest.mark.parametrize("method", ["eval", "shade"])
@pytest.mark.parametrize("arg", ["l", "v", "n", "tangent"])
@pytest.mark.parametrize(("what", "bad"), BAD_ARRAYS, ids=[w for w, _ in BAD_ARRAYS])
def test_bad_direction_arrays_are_refused_by_name(method: str, arg: str, what: str, bad: Any) -> None:
    with pytest.raises((ValueError, TypeError), match=names(arg)):
        call(method, **{arg: bad})


def test_batches_that_do_not_broadcast_are_refused() -> None:
    with pytest.raises(ValueError, match=names("v")):
        call("eval", l=np.zeros((5, 3), np.float32) + N, v=np.zeros((4, 3), np.float32) + N)


# ------------------------------------------------------------------------------------ parameters


def test_unknown_model_is_refused_by_name() -> None:
    with pytest.raises(ValueError, match="no_such_model"):
        brdfpy.model("no_such_model")
    with pytest.raises(ValueError, match="no_such_model"):
        brdfpy.model_info("no_such_model")


@pytest.mark.parametrize("name", MODELS)
def test_unknown_parameter_is_refused_by_name(name: str) -> None:
    with pytest.raises((ValueError, TypeError), match="shinyness"):
        brdfpy.model(name, shinyness=3.0)


BAD_PARAMS: list[tuple[str, str, Any]] = [
    ("cook_torrance", "roughness", -0.1),
    ("cook_torrance", "roughness", float("nan")),
    ("cook_torrance", "roughness2", -1.0),
    ("cook_torrance", "ior", 0.0),
    ("cook_torrance", "ior", -1.5),
    ("cook_torrance", "eta", [1.0, 0.0, 1.0]),
    ("cook_torrance", "k", -1.0),
    ("cook_torrance", "distribution", "lorentz"),
    ("cook_torrance", "masking", "smithy"),
    ("cook_torrance", "fresnel", "fresh"),
    ("cook_torrance", "metal", "unobtainium"),
    ("oren_nayar", "sigma", -0.2),
    ("oren_nayar", "sigma", float("inf")),
    ("oren_nayar", "variant", "quantitative"),
    ("oren_nayar_full", "sigma", -0.2),
    ("lambert", "kd", "red"),
    ("lambert", "kd", [0.1, 0.2]),
    ("lambert", "kd", [0.1, float("nan"), 0.2]),
    ("phong", "shininess", -1.0),
    ("blinn_phong", "normalization", "none-such"),
    ("ward", "alpha_x", -0.01),
    ("ward", "alpha_y", -0.3),
    ("ashikhmin_shirley", "nu", -5.0),
    ("lafortune", "lobes", [[1.0, 1.0, 1.0]]),
    ("lafortune", "lobes", "many"),
]


@pytest.mark.parametrize(
    ("name", "param", "value"), BAD_PARAMS, ids=[f"{a}-{b}-{c}" for a, b, c in BAD_PARAMS]
)
def test_bad_parameter_values_are_refused_by_name(name: str, param: str, value: Any) -> None:
    with pytest.raises((ValueError, TypeError), match=names(param)):
        brdfpy.model(name, **{param: value})


# --------------------------------------------------------------------------- standalone functions


@pytest.mark.parametrize("eta", [0.0, -1.5, float("nan")])
def test_fresnel_refuses_non_positive_ior(eta: float) -> None:
    c = np.array([0.5], np.float32)
    with pytest.raises(ValueError, match=names("eta")):
        brdfpy.fresnel.dielectric(c, eta)
    with pytest.raises(ValueError, match=names("eta")):
        brdfpy.fresnel.conductor(c, eta, 1.0)
    with pytest.raises(ValueError, match=names("eta")):
        brdfpy.fresnel.f0_from_ior(eta)


def test_fresnel_refuses_bad_cosines_and_metals() -> None:
    with pytest.raises((ValueError, TypeError), match=names("cos_i")):
        brdfpy.fresnel.schlick(np.array(["x"]), 0.04)
    with pytest.raises(ValueError, match=names("cos_i")):
        brdfpy.fresnel.dielectric(np.array([np.nan], np.float32), 1.5)
    with pytest.raises(ValueError, match="unobtainium"):
        brdfpy.fresnel.metal_f0("unobtainium")
    with pytest.raises(ValueError, match=names("k")):
        brdfpy.fresnel.conductor(np.array([0.5], np.float32), 1.0, -2.0)


def test_microfacet_refuses_bad_roughness_and_names() -> None:
    h = GOOD
    with pytest.raises(ValueError, match=names("alpha")):
        brdfpy.microfacet.distribution(h, N, -0.3)
    with pytest.raises(ValueError, match=names("alpha")):
        brdfpy.microfacet.distribution(h, N, 0.0, distribution="beckmann")
    with pytest.raises(ValueError, match="lorentz"):
        brdfpy.microfacet.distribution(h, N, 0.3, distribution="lorentz")
    with pytest.raises(ValueError, match="smithy"):
        brdfpy.microfacet.masking(h, h, N, 0.3, masking="smithy")
    with pytest.raises(ValueError, match=names("h")):
        brdfpy.microfacet.distribution(np.zeros((3, 2), np.float32), N, 0.3)


def test_tonemap_refuses_bad_white_point_and_operator() -> None:
    x = np.array([0.5, 2.0], np.float32)
    with pytest.raises(ValueError, match=names("white")):
        brdfpy.tonemap.reinhard_extended(x, 0.0)
    with pytest.raises(ValueError, match="filmic-ish"):
        brdfpy.tonemap.to_uint8(x, operator="filmic-ish")


# ---------------------------------------------------------------- degenerate but legal geometry


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("zero", ["l", "v", "n"])
def test_zero_length_vectors_shade_to_black(name: str, zero: str) -> None:
    args = {"l": GOOD.copy(), "v": GOOD[::-1].copy(), "n": np.repeat(N[None], 2, axis=0)}
    args[zero][0] = 0.0
    m = brdfpy.model(name)
    for q in ("eval", "shade"):
        out = getattr(m, q)(**args)
        assert np.all(np.isfinite(out)), (name, q)
        np.testing.assert_array_equal(out[0], 0.0, err_msg=f"{name}.{q} with zero {zero}")
        assert np.all(out[1] >= 0)


@pytest.mark.parametrize("name", MODELS)
def test_degenerate_tangent_and_opposite_directions_stay_finite(name: str) -> None:
    m = brdfpy.model(name)
    l = np.array([[0.0, 0.6, 0.8], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], np.float32)
    v = np.array([[0.0, -0.6, -0.8], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]], np.float32)  # l = -v, l = v, grazing
    tangent = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [np.float32(1e-30), 0.0, 0.0]], np.float32)
    for q in ("eval", "shade"):
        out = getattr(m, q)(l, v, N, tangent=tangent)
        assert np.all(np.isfinite(out)) and np.all(out >= 0), (name, q, out)


@pytest.mark.parametrize("name", MODELS)
def test_extreme_parameters_stay_finite(name: str, rng: np.random.Generator) -> None:
    """Every numeric parameter at its documented minimum and maximum: no NaN, no inf, no crash."""
    info = brdfpy.model_info(name)
    l = rng.normal(size=(2000, 3)).astype(np.float32)
    v = rng.normal(size=(2000, 3)).astype(np.float32)
    for p in info["params"]:
        if p["kind"] not in ("scalar", "color"):
            continue
        for bound in (p["min"], p["max"]):
            if bound is None or not np.isfinite(bound):
                continue
            m = brdfpy.model(name, **{p["name"]: bound})
            for q in ("eval", "shade"):
                out = getattr(m, q)(l, v, N)
                assert np.all(np.isfinite(out)), (name, p["name"], bound, q)
