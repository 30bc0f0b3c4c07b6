"""The batch rules, the same for every function over arrays (brdf-core ``batch``): inputs of shape
``(..., 3)`` (directions) or ``(...)`` (numbers) whose leading dimensions broadcast NumPy-style, outputs of
the broadcast shape followed by the output's own axes, errors that name the argument and the index of a bad
value, and results that do not depend on the layout of the same values or on the thread count."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import brdfpy
import numpy as np
import pytest
from brdfpy import fresnel, microfacet, vectors
from brdfpy._arrays import as_vectors

from conftest import REGISTRY_MODELS


def grid(rng: np.random.Generator, *shape: int) -> np.ndarray:
    """Directions in the upper hemisphere (and a few below), float32, shape ``shape + (3,)``."""
    d = rng.normal(size=(*shape, 3))
    d[..., 2] = np.abs(d[..., 2]) + 0.05
    return d.astype(np.float32)


#: Every direction-taking function, as (name, call with three direction arrays a, b, c) — each takes what it
#: needs, in the roles (l, v, n) / (w, n) / (h, n).
FUNCTIONS: list[tuple[str, Callable[[Any, Any, Any], Any]]] = [
    ("Model.eval", lambda a, b, c: brdfpy.model("cook_torrance").eval(a, b, c)),
    ("Model.shade", lambda a, b, c: brdfpy.model("ward").shade(a, b, c, tangent=[1, 0, 0])),
    ("Tabulated.eval", lambda a, b, c: _TABLE.eval(a, b, c)),
    ("vectors.reflect", lambda a, b, c: vectors.reflect(a, c)),
    ("vectors.halfway", lambda a, b, c: vectors.halfway(a, b)),
    ("vectors.refract", lambda a, b, c: vectors.refract(a, c, 1.5)),
    ("microfacet.distribution", lambda a, b, c: microfacet.distribution(a, c, 0.3)),
    ("microfacet.mixture", lambda a, b, c: microfacet.mixture([(1, "ggx", 0.2), (1, "beckmann", 0.5)], a, c)),
    ("microfacet.lambda_", lambda a, b, c: microfacet.lambda_(a, c, 0.3, distribution="beckmann")),
    ("microfacet.g1", lambda a, b, c: microfacet.g1(a, c, 0.3)),
    ("microfacet.masking", lambda a, b, c: microfacet.masking(a, b, c, 0.3, masking="v_groove")),
    ("fresnel.split", lambda a, b, c: fresnel.split(a, c, 1.5)),
]
_TABLE = brdfpy.measured.Tabulated.from_model(brdfpy.model("cook_torrance", roughness=0.4), (16, 16, 32))
IDS = [name for name, _ in FUNCTIONS]


def outputs(x: Any) -> tuple[np.ndarray, ...]:
    return tuple(x) if isinstance(x, tuple) else (x,)


@pytest.mark.parametrize(("name", "f"), FUNCTIONS, ids=IDS)
def test_a_grid_needs_no_reshaping_and_gives_the_rows_bits(name: str, f: Callable[..., Any], rng) -> None:
    """A (9, 40, 3) grid gives the (9, 40, ...) result whose elements are exactly those of the same
    directions as (360, 3) rows."""
    a, b, c = grid(rng, 9, 40), grid(rng, 9, 40), grid(rng, 9, 40)
    on_grid = outputs(f(a, b, c))
    rows = outputs(f(a.reshape(-1, 3), b.reshape(-1, 3), c.reshape(-1, 3)))
    for g, r in zip(on_grid, rows):
        assert g.shape[:2] == (9, 40), (name, g.shape)
        assert g.shape[2:] == r.shape[1:]
        np.testing.assert_array_equal(g.reshape(r.shape), r, err_msg=name)


@pytest.mark.parametrize(("name", "f"), FUNCTIONS, ids=IDS)
def test_leading_dimensions_broadcast_like_numpy(name: str, f: Callable[..., Any], rng) -> None:
    """(7, 1, 3) against (1, 5, 3) against (5, 3) gives (7, 5, ...): the result of the inputs broadcast by
    NumPy (a function reading only two of them broadcasts those two)."""
    a, b, c = grid(rng, 7, 1), grid(rng, 1, 5), grid(rng, 5)
    got = outputs(f(a, b, c))
    full = [np.ascontiguousarray(np.broadcast_to(x, (7, 5, 3))) for x in (a, b, c)]
    want = outputs(f(*full))
    for g, w in zip(got, want):
        assert g.shape == w.shape and g.shape[:2] == (7, 5), (name, g.shape)
        np.testing.assert_array_equal(g, w, err_msg=name)


#: What single (3,) vectors give: the output's own axes only.
SINGLE_SHAPES = {
    "Model.eval": [(3,)],
    "Model.shade": [(3,)],
    "Tabulated.eval": [(3,)],
    "vectors.reflect": [(3,)],
    "vectors.halfway": [(3,)],
    "vectors.refract": [(3,), ()],
    "fresnel.split": [(3,), (3,), (), ()],
}


@pytest.mark.parametrize(("name", "f"), FUNCTIONS, ids=IDS)
def test_single_vectors_give_a_single_result(name: str, f: Callable[..., Any]) -> None:
    l, v, n = [0.3, 0.0, 0.9], [-0.2, 0.1, 0.95], [0.0, 0.0, 1.0]
    got = outputs(f(l, v, n))
    # Microfacet terms are numbers: a 0-d array, as a (3,) input to Model.eval gives one (3,) colour.
    assert [g.shape for g in got] == SINGLE_SHAPES.get(name, [()]), name
    rows = outputs(f([l], [v], [n]))
    for g, r in zip(got, rows):
        np.testing.assert_array_equal(g, r[0])


@pytest.mark.parametrize(("name", "f"), FUNCTIONS, ids=IDS)
def test_shapes_that_do_not_broadcast_are_refused_naming_both(name: str, f: Callable[..., Any], rng) -> None:
    a, c = grid(rng, 4, 6), grid(rng, 5, 1)
    # The second direction each function reads is the one refused; the message shows both shapes.
    with pytest.raises(
        ValueError, match=r"has shape \(5, 1, 3\), which does not broadcast against \(4, 6, 3\)"
    ):
        f(a, c, c)


def test_the_broadcast_message_names_the_argument() -> None:
    m = brdfpy.model("lambert")
    with pytest.raises(
        ValueError, match=r"^v: has shape \(5, 3\), which does not broadcast against \(4, 3\)"
    ):
        m.eval(np.ones((4, 3)), np.ones((5, 3)), [0, 0, 1])
    with pytest.raises(ValueError, match=r"^tangent: has shape \(2, 3\)"):
        m.eval(np.ones((4, 3)), [0, 0, 1], [0, 0, 1], tangent=np.ones((2, 3)))


def test_a_last_axis_other_than_3_is_refused() -> None:
    m = brdfpy.model("lambert")
    for bad in (np.ones((4, 2)), np.ones((2, 3, 4)), np.float32(1.0)):
        with pytest.raises(ValueError, match=r"^l: expected an array of shape \(\.\.\., 3\)"):
            m.eval(bad, [0, 0, 1], [0, 0, 1])


def test_a_non_finite_value_is_reported_at_its_index_in_the_arguments_own_shape() -> None:
    m = brdfpy.model("cook_torrance")
    l = np.tile(np.float32([0.1, 0.2, 1.0]), (4, 5, 1))
    l[2, 3, 1] = np.inf
    with pytest.raises(
        ValueError, match=r"^l: contains a non-finite value .* at l\[2, 3\]: \[0\.1, inf, 1\.0\]"
    ):
        m.eval(l, [0, 0, 1], [0, 0, 1])
    # In a broadcast input (a (5, 3) row against the (4, 5) grid): its own index.
    v = np.tile(np.float32([0.0, 0.0, 1.0]), (5, 1))
    v[1, 0] = np.nan
    with pytest.raises(ValueError, match=r"^v: .* at v\[1\]: \[nan, 0\.0, 1\.0\]"):
        m.eval(np.ones((4, 5, 3)), v, [0, 0, 1])
    # The first argument in order holding one is reported, whichever is checked first.
    with pytest.raises(ValueError, match=r"^l: .* at l\[2, 3\]"):
        m.eval(l, v, [0, 0, 1])
    with pytest.raises(ValueError, match=r"^n: contains a non-finite value[^\[]*: \[0\.0, 0\.0, nan\]"):
        m.eval(np.ones((4, 5, 3)), [0, 0, 1], [0, 0, np.nan])


def test_numbers_broadcast_too_and_name_their_index() -> None:
    cos = np.linspace(0, 1, 20, dtype=np.float32).reshape(4, 5)
    assert fresnel.schlick(cos, 0.04).shape == (4, 5)
    assert fresnel.schlick(cos, [0.9, 0.6, 0.2]).shape == (4, 5, 3)
    t, ok = vectors.refract(np.ones((4, 5, 3)), [0, 0, 1], np.full((5,), 1.5))
    assert t.shape == (4, 5, 3) and ok.shape == (4, 5)
    bad = cos.copy()
    bad[1, 2] = 1.5
    with pytest.raises(
        ValueError, match=r"^cos_i: must hold finite cosines in \[-1, 1\] at cos_i\[1, 2\]: 1\.5"
    ):
        fresnel.schlick(bad, 0.04)
    with pytest.raises(
        ValueError, match=r"^eta: must be a relative index of refraction in \[1e-6, 1e6\] at eta\[3\]: 0\.0"
    ):
        vectors.refract([0, 0, 1], [0, 0, 1], [1.5, 1.5, 1.5, 0.0])


def test_empty_input_is_refused_by_name() -> None:
    with pytest.raises(ValueError, match=r"^n: is empty \(shape \(0, 3\)\)"):
        brdfpy.model("lambert").eval([0, 0, 1], [0, 0, 1], np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"^h: is empty \(shape \(2, 0, 3\)\)"):
        microfacet.distribution(np.zeros((2, 0, 3)), [0, 0, 1], 0.3)


def test_float32_c_contiguous_input_is_used_as_it_is() -> None:
    a = np.ones((4, 5, 3), np.float32)
    assert as_vectors("l", a) is a
    out = brdfpy.model("lambert").eval(a, a, a)
    assert out.dtype == np.float32 and out.flags.c_contiguous and out.shape == (4, 5, 3)
    # Other layouts and types are converted once (the values as float32).
    np.testing.assert_array_equal(brdfpy.model("lambert").eval(a.astype(np.float64), a[:, ::-1], a), out)


@pytest.mark.parametrize("name", REGISTRY_MODELS)
def test_partly_broadcast_grids_are_bit_identical_at_any_thread_count(
    name: str, rng, restore_threads
) -> None:
    """A (300, 1) x (1, 200) grid is 60 000 samples: parallel chunks, inputs read through the broadcast."""
    m = brdfpy.model(name)
    l, v = grid(rng, 300, 1), grid(rng, 1, 200)
    results = []
    for threads in (1, 2, 3):
        brdfpy.set_num_threads(threads)
        results.append(m.shade(l, v, [0, 0, 1], tangent=[1, 0, 0]))
    assert results[0].shape == (300, 200, 3)
    for r in results[1:]:
        np.testing.assert_array_equal(r, results[0])
    full = m.shade(
        np.broadcast_to(l, (300, 200, 3)), np.broadcast_to(v, (300, 200, 3)), [0, 0, 1], tangent=[1, 0, 0]
    )
    np.testing.assert_array_equal(full, results[0])


def test_sh_basis_takes_any_leading_shape() -> None:
    d = np.random.default_rng(1).normal(size=(4, 5, 3))
    b = brdfpy.sh.basis(d, 2)
    assert b.shape == (4, 5, 9)
    np.testing.assert_array_equal(b.reshape(-1, 9), brdfpy.sh.basis(d.reshape(-1, 3), 2))
    c = brdfpy.sh.project(lambda x: x[:, 2], order=2)
    assert brdfpy.sh.reconstruct(c, d).shape == (4, 5)


# ----------------------------------------------------------------------------- one name per concept


def test_the_sample_count_of_the_checks_is_samples_not_n() -> None:
    m = brdfpy.model("lambert")
    assert brdfpy.checks.positivity(m, samples=100) >= 0
    assert brdfpy.checks.reciprocity_error(m, samples=100) < 1e-5
    for f in (brdfpy.checks.positivity, brdfpy.checks.reciprocity_error):
        with pytest.raises(TypeError, match=r"n= is now samples="):
            f(m, n=100)  # type: ignore[call-arg]
    with pytest.raises(ValueError, match=r"^samples: expected an integer in \[1, "):
        brdfpy.checks.positivity(m, samples=0)


def test_every_microfacet_term_takes_its_choice_as_a_keyword() -> None:
    h = np.float32([[0.1, 0.0, 1.0]])
    z = [0.0, 0.0, 1.0]
    beck = microfacet.distribution(h, z, 0.3, distribution="beckmann")
    assert beck != microfacet.distribution(h, z, 0.3)  # default ggx
    for old in (
        lambda: microfacet.distribution("beckmann", h, z, 0.3),  # type: ignore[arg-type]
        lambda: microfacet.lambda_("beckmann", h, z, 0.3),  # type: ignore[arg-type]
    ):
        with pytest.raises(TypeError, match=r"goes in the keyword distribution= now"):
            old()
    with pytest.raises(TypeError, match=r"goes in the keyword masking= now"):
        microfacet.masking("smith", h, h, z, 0.3)  # type: ignore[arg-type]
    smith = microfacet.masking(h, h, z, 0.3)
    np.testing.assert_array_equal(
        smith, microfacet.masking(h, h, z, 0.3, masking="smith", distribution="ggx")
    )
    assert microfacet.masking(h, h, z, 0.3, masking="none") == 1.0
