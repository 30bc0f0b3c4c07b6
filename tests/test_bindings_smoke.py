"""The binding layer as a user meets it: shapes, dtypes and layouts in, float32 out, errors that name the
argument, the thread pool, pickling and fork safety. (The numbers themselves are checked against the oracle
in test_models.py and friends.)"""

from __future__ import annotations

import multiprocessing as mp
import pickle
import sys

import brdfpy
import numpy as np
import pytest

DIRS = np.array([[0.3, 0.2, 1.0], [-0.4, 0.1, 0.9], [0.0, -0.7, 0.7], [0.9, 0.0, 0.1]])


def test_single_vectors_give_a_single_rgb_and_batches_give_n_by_3_float32():
    m = brdfpy.model("lambert", kd=(0.8, 0.5, 0.2))
    one = m.eval([0, 0, 1], [0, 0.6, 0.8], [0, 0, 1])
    assert one.shape == (3,) and one.dtype == np.float32
    np.testing.assert_allclose(one, np.array([0.8, 0.5, 0.2]) / np.pi, rtol=1e-6)
    many = m.shade(DIRS, [0, 0, 1], [0, 0, 1])
    assert many.shape == (4, 3) and many.dtype == np.float32
    # (1, 3) is a batch of one, not a single vector.
    assert m.eval([[0, 0, 1]], [0, 0, 1], [0, 0, 1]).shape == (1, 3)


def test_float64_integer_strided_and_fortran_inputs_give_the_same_bits_as_float32():
    m = brdfpy.model("cook_torrance", kd=0.3, roughness=0.2)
    rng = np.random.default_rng(1)
    l64 = rng.normal(size=(500, 3))
    v64 = rng.normal(size=(500, 3))
    n64 = np.abs(rng.normal(size=(500, 3)))
    ref = m.eval(l64.astype(np.float32), v64.astype(np.float32), n64.astype(np.float32))
    np.testing.assert_array_equal(m.eval(l64, v64, n64), ref)
    np.testing.assert_array_equal(m.eval(np.asfortranarray(l64), v64, n64), ref)
    wide = np.zeros((500, 6), dtype=np.float32)
    wide[:, ::2] = l64
    np.testing.assert_array_equal(m.eval(wide[:, ::2], v64, n64), ref)
    assert m.eval([0, 0, 2], [1, 0, 1], [0, 0, 5]).dtype == np.float32  # integers are fine


def test_results_are_bit_identical_at_1_2_and_4_threads():
    m = brdfpy.model("ward")
    rng = np.random.default_rng(2)
    l, v, t = (rng.normal(size=(100_003, 3)).astype(np.float32) for _ in range(3))
    before = brdfpy.get_num_threads()
    try:
        outs = []
        for k in (1, 2, 4):
            brdfpy.set_num_threads(k)
            assert brdfpy.get_num_threads() == k
            outs.append(m.eval(l, v, [0, 0, 1], t))
        for o in outs[1:]:
            np.testing.assert_array_equal(o, outs[0])
    finally:
        brdfpy.set_num_threads(before)


@pytest.mark.parametrize("n", [0, -1, 10**6])
def test_set_num_threads_refuses_nonsense(n):
    with pytest.raises(ValueError, match="n:"):
        brdfpy.set_num_threads(n)


@pytest.mark.parametrize(
    ("kwargs", "exc", "needle"),
    [
        ({"l": np.zeros((5, 4))}, ValueError, r"l: expected an array of shape \(\.\.\., 3\).*got \(5, 4\)"),
        ({"v": [[0, 0, 1], [1, 2]]}, ValueError, "v: "),
        ({"n": np.zeros((0, 3))}, ValueError, "n: is empty"),
        ({"l": ["a", "b", "c"]}, TypeError, "l: "),
        ({"v": np.ones(3, dtype=complex)}, TypeError, "v: "),
        ({"v": np.ones(3, dtype=bool)}, TypeError, "v: "),
        ({"n": np.array([None, 1, 2], dtype=object)}, TypeError, "n: "),
        ({"l": [0, 0, np.nan]}, ValueError, "l: .*non-finite"),
        ({"v": np.full((10_000, 3), 1e39)}, ValueError, "v: .*beyond the float32 range"),
        ({"l": np.ones((4, 3)), "v": np.ones((5, 3))}, ValueError, "does not broadcast"),
        ({"tangent": [np.inf, 0, 0]}, ValueError, "tangent: .*non-finite"),
        ({"l": None}, TypeError, "l: "),
    ],
)
def test_bad_arrays_raise_an_error_that_names_the_argument(kwargs, exc, needle):
    args = {"l": [0, 0, 1], "v": [0, 0, 1], "n": [0, 0, 1], **kwargs}
    with pytest.raises(exc, match=needle):
        brdfpy.model("ward").eval(**args)


def test_a_nan_deep_inside_a_large_batch_is_reported_with_its_row():
    l = np.tile(np.float32([0, 0, 1]), (200_000, 1))
    l[123_456, 2] = np.nan
    with pytest.raises(ValueError, match=r"at l\[123456\]: \[0\.0, 0\.0, nan\]"):
        brdfpy.model("lambert").eval(l, [0, 0, 1], [0, 0, 1])


def test_degenerate_directions_give_zero_not_nan():
    out = brdfpy.model("cook_torrance").eval([[0, 0, 0], [0, 0, 1]], [0, 0, 1], [[0, 0, 1], [0, 0, 0]])
    np.testing.assert_array_equal(out, 0.0)


@pytest.mark.parametrize(
    ("name", "params", "exc", "needle"),
    [
        ("nope", {}, ValueError, "nope.*lambert"),
        ("lambert", {"kdd": 0.5}, ValueError, "kdd"),
        ("lambert", {"albedo": 0.5}, ValueError, "no parameter 'albedo': the diffuse reflectance is 'kd'"),
        ("cook_torrance", {"roughness": -0.1}, ValueError, "roughness"),
        ("oren_nayar", {"sigma": -0.1}, ValueError, "sigma"),
        ("cook_torrance", {"ior": 0.0}, ValueError, "ior"),
        ("cook_torrance", {"distribution": "nope"}, ValueError, "distribution"),
        ("lambert", {"kd": {}}, TypeError, "kd"),
        ("lambert", {"kd": [0.1, 0.2]}, ValueError, "kd"),
        ("lambert", {"kd": float("nan")}, ValueError, "kd"),
        ("lafortune", {"lobes": [[-1, -1, 1, 20], [1, 2]]}, ValueError, "lobes"),
    ],
)
def test_bad_models_and_parameters_raise_an_error_that_names_them(name, params, exc, needle):
    with pytest.raises(exc, match=needle):
        brdfpy.model(name, **params)


def test_brdf_errors_are_value_errors():
    assert issubclass(brdfpy.BrdfError, ValueError)
    with pytest.raises(brdfpy.BrdfError):
        brdfpy.model("lambert", kd=2.0)


def test_params_are_echoed_resolved_and_the_repr_rebuilds_the_model():
    m = brdfpy.model("cook_torrance", roughness=0.25, metal="AU", kd=0.1)
    assert m.name == "cook_torrance" and m.physical and not m.anisotropic
    assert m.params["roughness"] == 0.25 and m.params["metal"] == "au" and m.params["kd"] == (0.1, 0.1, 0.1)
    assert set(m.params) == {p["name"] for p in brdfpy.model_info("cook_torrance")["params"]}
    again = eval(repr(m), {"brdfpy": brdfpy})
    assert again.params == m.params
    lob = brdfpy.model("lafortune", lobes=np.array([[-1.0, -1.0, 1.0, 10.0], [0.5, 0.5, 1.0, 3.0]]))
    assert lob.params["lobes"] == [[-1.0, -1.0, 1.0, 10.0], [0.5, 0.5, 1.0, 3.0]]
    assert isinstance(brdfpy.model("ward"), brdfpy.Model) and brdfpy.model("ward").anisotropic


def test_model_info_documents_every_parameter_of_every_model():
    for name in brdfpy.models():
        info = brdfpy.model_info(name)
        assert info["name"] == name and info["summary"] and info["source"]
        assert isinstance(info["physical"], bool) and isinstance(info["anisotropic"], bool)
        for p in info["params"]:
            assert {"name", "kind", "default", "min", "max", "unit", "doc", "choices"} <= set(p)
            assert p["kind"] in ("scalar", "color", "choice", "bool", "array")
            assert (p["choices"] is not None) == (p["kind"] == "choice")
            # Every default is accepted back.
            brdfpy.model(name, **{p["name"]: p["default"]})


def test_models_pickle_by_name_and_parameters():
    m = brdfpy.model("blinn_phong", shininess=64, normalization="exact")
    m2 = pickle.loads(pickle.dumps(m))
    assert type(m2) is brdfpy.Model and m2.params == m.params
    np.testing.assert_array_equal(m2.eval(DIRS, [0, 0, 1], [0, 0, 1]), m.eval(DIRS, [0, 0, 1], [0, 0, 1]))


def _child_eval(q: mp.Queue) -> None:
    l = np.tile(np.float32([0.1, 0.2, 1.0]), (100_000, 1))
    q.put(float(brdfpy.model("lambert").eval(l, [0, 0, 1], [0, 0, 1]).sum()))


@pytest.mark.skipif(sys.platform != "linux", reason="fork start method")
@pytest.mark.filterwarnings("ignore:.*fork.*:DeprecationWarning")  # Python >= 3.12 warns about fork + threads
def test_a_forked_child_can_still_evaluate_large_batches():
    # Use the pool in the parent first, so that the child inherits a pool whose threads it does not have.
    l = np.tile(np.float32([0.1, 0.2, 1.0]), (100_000, 1))
    expected = float(brdfpy.model("lambert").eval(l, [0, 0, 1], [0, 0, 1]).sum())
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    p = ctx.Process(target=_child_eval, args=(q,))
    p.start()
    p.join(timeout=60)
    alive = p.is_alive()
    if alive:
        p.kill()
    assert not alive, "the forked child hung"
    assert p.exitcode == 0 and q.get(timeout=5) == expected


def test_vectors_reflect_refract_halfway():
    np.testing.assert_allclose(brdfpy.vectors.reflect([0.6, 0, 0.8], [0, 0, 1]), [-0.6, 0, 0.8], atol=1e-7)
    np.testing.assert_allclose(
        brdfpy.vectors.halfway([1, 0, 0], [0, 1, 0]), [0.5**0.5, 0.5**0.5, 0], rtol=1e-6
    )
    t, ok = brdfpy.vectors.refract([0.6, 0, 0.8], [0, 0, 1], 1.5)
    assert bool(ok) and t.shape == (3,)
    np.testing.assert_allclose(np.hypot(t[0], t[1]), 0.6 / 1.5, rtol=1e-6)  # Snell
    t, ok = brdfpy.vectors.refract([[0.8, 0, 0.6]], [0, 0, 1], [1 / 1.5])  # sin = 1.2 > 1: TIR
    assert not ok[0] and (t == 0).all()
    with pytest.raises(ValueError, match="eta"):
        brdfpy.vectors.refract([0, 0, 1], [0, 0, 1], -1.0)


def test_float32_c_contiguous_input_reaches_the_core_without_a_copy():
    from brdfpy._arrays import as_vec3

    a = np.zeros((1000, 3), dtype=np.float32)
    assert as_vec3("l", a)[0] is a
    one = np.zeros(3, dtype=np.float32)
    assert np.shares_memory(as_vec3("l", one)[0], one)
    assert not np.shares_memory(as_vec3("l", a.astype(np.float64))[0], a)  # float64 is converted once


def test_fresnel_split_conserves_energy_and_reports_total_internal_reflection():
    r, t, big_r, big_t = brdfpy.fresnel.split([[0.6, 0, 0.8], [0.8, 0, -0.6]], [0, 0, 1], 1.5)
    np.testing.assert_allclose(big_r + big_t, 1.0, rtol=1e-6)
    np.testing.assert_allclose(r[0], [-0.6, 0, 0.8], atol=1e-7)
    assert big_r[1] == 1.0 and (t[1] == 0).all()  # from inside at sin 0.8 > 1/1.5
