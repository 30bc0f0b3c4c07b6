"""Hostile inputs that once slipped through the error contract (issue 9), as a specification.

Every bad input gives a ``TypeError`` / ``ValueError`` (``BrdfError`` is one) or ``MemoryError`` whose message
names the argument and the problem: never ``inf`` silently, never an ``OverflowError`` or a warning naming
nothing, never an abort.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import brdfpy
import numpy as np
import pytest
from brdfpy import transforms, vectors

F32_MAX = float(np.finfo(np.float32).max)


# ------------------------------------------------------------------ float64 beyond the float32 range


@pytest.mark.parametrize("bad", [1e39, -1e39, 3.5e38, 1e300])
def test_float64_beyond_the_float32_range_is_refused_naming_the_argument_and_index(bad: float) -> None:
    l = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.3, bad, 1.0]])
    with pytest.raises(ValueError, match=r"^l: .*float32 range.*at l\[2, 1\]") as info:
        vectors.halfway(l, [0.0, 0.0, 1.0])
    assert repr(bad) in str(info.value)


def test_float64_beyond_the_float32_range_is_refused_by_every_kind_of_batch_input() -> None:
    m = brdfpy.model("lambert")
    with pytest.raises(ValueError, match=r"^v: .*float32 range.*at v\[0, 2\]"):
        m.eval([0.0, 0.0, 1.0], np.array([[0.0, 0.0, 1e39]]), [0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match=r"^eta: .*float32 range"):
        brdfpy.fresnel.dielectric(0.5, np.float64(1e39))
    # a 0-d value has no index to show
    with pytest.raises(
        ValueError, match=r"^x: holds a value beyond the float32 range \(\|x\| <= 3.4028235e\+38\): 1e\+39$"
    ):
        brdfpy.tonemap.srgb_decode(np.float64(1e39))


def test_values_at_the_float32_limit_and_infinities_given_as_such_are_not_this_error() -> None:
    # The largest float64 that rounds to a finite float32 passes through.
    r = brdfpy.tonemap.srgb_decode(np.array([F32_MAX], np.float64))
    assert np.isfinite(r).all()
    # ±inf and NaN given as such are the compiled module's to judge: tone mapping documents them.
    assert brdfpy.tonemap.srgb_decode(np.array([np.inf, -np.inf], np.float64)).tolist() == [1.0, 0.0]
    with pytest.raises(ValueError, match=r"^l: contains a non-finite value"):
        vectors.halfway(np.array([np.inf, 0.0, 1.0]), [0.0, 0.0, 1.0])


# --------------------------------------------------------------------------------- complex numbers


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: transforms.rotate(np.array([0, 1j, 1]), 30.0), "axis"),
        (lambda: transforms.translate([1j, 0, 0]), "offset"),
        (lambda: brdfpy.cube().transformed(np.eye(4, dtype=complex)), "matrix"),
        (lambda: vectors.halfway([0, 0, 1 + 0j], [0, 0, 1]), "l"),
        (lambda: transforms.scale(2j), "sx"),
    ],
)
def test_complex_input_is_refused_naming_the_argument_not_cast_with_a_warning(call, name: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(TypeError, match=rf"^{name}: expected real numbers .*complex"):
        call()


# ------------------------------------------------------------------------------------------ integers


@pytest.mark.parametrize("bad", [2**63, -(2**63) - 1, 2**64, 10**40])
def test_integers_beyond_64_bits_are_refused_with_a_clear_message(bad: int) -> None:
    m = brdfpy.model("lambert")
    with pytest.raises(ValueError, match=r"^n: .* is outside the 64-bit integer range"):
        brdfpy.views.polar(m, n=bad)
    with pytest.raises(
        ValueError, match=r"^n_theta: .* outside the 64-bit integer range; expected an integer in \[1, 64\]"
    ):
        brdfpy.checks.directional_albedo(m, 0.5, n_theta=bad)


def test_an_integer_too_large_for_a_float_is_refused_naming_it() -> None:
    with pytest.raises(ValueError, match=r"^phi: an integer of 1329 bits is beyond the float range"):
        brdfpy.views.polar("lambert", phi=10**400)


def test_thread_counts_refuse_bools_and_huge_integers_and_none_restores_the_default() -> None:
    script = textwrap.dedent(
        """
        import brdfpy, numpy as np
        default = brdfpy.get_num_threads()
        for bad, kind in [(True, TypeError), (np.True_, TypeError), (False, TypeError), (1.5, TypeError),
                          ("4", TypeError), (2**64, ValueError), (-(2**70), ValueError), (0, ValueError)]:
            try:
                brdfpy.set_num_threads(bad)
            except kind as e:
                assert str(e).startswith("n: "), (bad, e)
            else:
                raise AssertionError(f"set_num_threads({bad!r}) was accepted")
        assert brdfpy.get_num_threads() == default
        brdfpy.set_num_threads(np.int64(1))
        assert brdfpy.get_num_threads() == 1
        brdfpy.set_num_threads(None)  # documented: back to the default
        assert brdfpy.get_num_threads() == default, (brdfpy.get_num_threads(), default)
        print("ok")
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


# -------------------------------------------------------------------------------- huge batches


def test_a_batch_beyond_max_batch_len_is_refused_before_anything_is_allocated() -> None:
    # (65537, 1) x (1, 65536) rows broadcast to 4 295 032 832 > 2^32 elements: 51 GB of output.
    l = np.zeros((65537, 1, 3), np.float32)
    v = np.zeros((1, 65536, 3), np.float32)
    with pytest.raises(
        ValueError, match=r"^v: broadcasting gives shape \(65537, 65536, 3\), 4295032832 elements"
    ) as info:
        vectors.halfway(l, v)
    assert "4294967296 (2^32" in str(info.value) and "split" in str(info.value)
    with pytest.raises(ValueError, match=r"^n: broadcasting gives shape"):
        brdfpy.model("lambert").eval(l, [0.0, 0.0, 1.0], v)


def test_a_large_output_that_cannot_be_allocated_is_a_memory_error_not_an_abort() -> None:
    # 40000 x 40000 directions (1.6e9 < 2^32 elements, 19 GB of output) under a 2 GiB address-space limit.
    script = textwrap.dedent(
        """
        import resource, numpy as np, brdfpy
        with open("/proc/self/statm") as f:
            in_use = int(f.read().split()[0]) * resource.getpagesize()
        hard = resource.getrlimit(resource.RLIMIT_AS)[1]
        resource.setrlimit(resource.RLIMIT_AS, (in_use + (2 << 30), hard))
        l = np.zeros((40000, 1, 3), np.float32)
        v = np.zeros((1, 40000, 3), np.float32)
        m = brdfpy.model("lambert")
        for f in (lambda: brdfpy.vectors.halfway(l, v), lambda: m.eval(l, v, [0, 0, 1])):
            try:
                f()
            except MemoryError:
                pass
            else:
                raise AssertionError("a 19 GB output was allocated under a 2 GiB limit")
        print("ok")
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0 and out.stdout.strip() == "ok", (out.returncode, out.stderr[-2000:])


# ------------------------------------------------------------------------------ vector magnitudes


def test_reflect_refuses_a_w_whose_mirror_image_would_overflow() -> None:
    w = np.array([[0.6, 0.0, 0.8], [3e38, 0.0, 3e38]], np.float32)
    with pytest.raises(
        ValueError, match=r"^w: must hold finite vectors of length at most 8.5e37.* at w\[1\]"
    ):
        vectors.reflect(w, [0.0, 0.0, 1.0])
    edge = np.array([0.0, 0.0, F32_MAX / 4], np.float32)
    r = vectors.reflect(edge, [0.0, 0.0, 1.0])
    assert np.isfinite(r).all() and r[2] == edge[2]


def test_normalised_inputs_keep_their_direction_at_any_finite_length() -> None:
    huge = np.array([3e38, 0.0, 3e38], np.float32)
    up = np.array([0.0, 0.0, 1e30], np.float32)
    r = vectors.reflect([0.6, 0.0, 0.8], huge)  # only n̂ matters
    np.testing.assert_allclose(r, [0.8, 0.0, 0.6], atol=1e-6)  # n̂ = (1, 0, 1)/√2
    h = vectors.halfway(huge, up)
    np.testing.assert_allclose(
        h, np.array([1.0, 0.0, 1.0 + np.sqrt(2.0)]) / np.sqrt(4.0 + 2.0 * np.sqrt(2.0)), atol=1e-6
    )
    t, ok = vectors.refract(huge, up, 1.0)
    assert ok and np.allclose(t, [-np.sqrt(0.5), 0.0, -np.sqrt(0.5)], atol=1e-6)


# ------------------------------------------------------------------------------------- transforms


@pytest.mark.parametrize(
    ("sx", "kind", "pattern"),
    [
        ([[1.0, 2.0], [3.0]], ValueError, r"^sx: expected a rectangular array of numbers"),
        ("2", TypeError, r"^sx: expected an array of real numbers, got str"),
        ([1.0, 2.0], ValueError, r"^sx: expected three numbers, got shape \(2,\)"),
        (0.0, ValueError, r"^sx: scale factors must be finite and non-zero"),
        (None, TypeError, r"^sx: "),
    ],
)
def test_scale_names_sx_for_every_bad_factor(sx: object, kind: type[Exception], pattern: str) -> None:
    with pytest.raises(kind, match=pattern):
        transforms.scale(sx)


def test_scale_by_three_factors_names_them() -> None:
    with pytest.raises(ValueError, match=r"^\(sx, sy, sz\): scale factors must be finite and non-zero"):
        transforms.scale(1.0, 0.0, 2.0)
    np.testing.assert_array_equal(transforms.scale([1, 2, 3]), np.diag([1.0, 2.0, 3.0, 1.0]))


# ----------------------------------------------------------------------------------------- views


def test_log_range_checks_the_shape_of_z_and_decades() -> None:
    s = brdfpy.views.half_diff_slice("lambert", size=8)
    with pytest.raises(ValueError, match=r"^z: expected the slice's shape \(8, 8\), got \(\)"):
        s.log_range(np.float32(1.0))
    with pytest.raises(TypeError, match=r"^z: "):
        s.log_range("abc")
    with pytest.raises(ValueError, match=r"^decades: must be a positive finite number"):
        s.log_range(decades=float("nan"))
    low, high = s.log_range(s.luminance)
    assert 0 < low < high
