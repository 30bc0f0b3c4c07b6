"""``Model.eval/shade(..., out=array)``: the result written into a caller's float32 array of exactly the
result's shape, with the bits of a fresh result at any size and thread count, and every unusable ``out``
refused naming it (before anything is computed, never a silent copy)."""

from __future__ import annotations

import brdfpy
import numpy as np
import pytest


def directions(rng: np.random.Generator, *shape: int) -> np.ndarray:
    d = rng.normal(size=(*shape, 3))
    d[..., 2] = np.abs(d[..., 2]) + 0.05
    return d.astype(np.float32)


@pytest.mark.parametrize("rows", [1, 7, 100, 40_000])
@pytest.mark.parametrize("shade", [False, True])
def test_out_receives_the_bits_of_a_fresh_result_and_is_returned(rows: int, shade: bool) -> None:
    rng = np.random.default_rng(rows)
    l, v = directions(rng, rows), directions(rng, rows)
    m = brdfpy.model("cook_torrance", distribution="beckmann", fresnel="conductor")
    f = m.shade if shade else m.eval
    want = f(l, v, [0, 0, 1])
    out = np.full((rows, 3), np.nan, dtype=np.float32)
    got = f(l, v, [0, 0, 1], out=out)
    assert got is out
    assert want.tobytes() == out.tobytes()


def test_out_takes_the_broadcast_shape_and_a_single_vector() -> None:
    rng = np.random.default_rng(3)
    l = directions(rng, 4, 5)
    m = brdfpy.model("ward")
    out = np.empty((4, 5, 3), np.float32)
    m.eval(l, [0.1, 0, 1], [0, 0, 1], tangent=[1, 0, 0], out=out)
    assert out.tobytes() == m.eval(l, [0.1, 0, 1], [0, 0, 1], tangent=[1, 0, 0]).tobytes()
    one = np.empty(3, np.float32)
    assert m.eval([0, 0.2, 1], [0.1, 0, 1], [0, 0, 1], out=one) is one
    assert one.tobytes() == m.eval([0, 0.2, 1], [0.1, 0, 1], [0, 0, 1]).tobytes()


def test_a_reused_buffer_and_a_slice_of_a_larger_array() -> None:
    rng = np.random.default_rng(4)
    m = brdfpy.model("lambert", kd=0.5)
    big = np.zeros((10, 3), np.float32)
    l = directions(rng, 4)
    m.eval(l, [0, 0, 1], [0, 0, 1], out=big[3:7])  # a C-contiguous slice
    assert big[3:7].tobytes() == m.eval(l, [0, 0, 1], [0, 0, 1]).tobytes()
    assert not big[:3].any() and not big[7:].any()
    buf = np.empty((4, 3), np.float32)
    for k in range(3):
        m.eval(l * (k + 1), [0, 0, 1], [0, 0, 1], out=buf)
        assert buf.tobytes() == m.eval(l, [0, 0, 1], [0, 0, 1]).tobytes()


def test_out_is_bit_identical_at_any_thread_count() -> None:
    rng = np.random.default_rng(5)
    l, v = directions(rng, 100_003), directions(rng, 100_003)
    m = brdfpy.model("cook_torrance")
    before = brdfpy.get_num_threads()
    try:
        results = []
        for threads in (1, 2, 3):
            brdfpy.set_num_threads(threads)
            out = np.empty((100_003, 3), np.float32)
            m.shade(l, v, [0, 0, 1], out=out)
            results.append(out.tobytes())
    finally:
        brdfpy.set_num_threads(before)
    assert results[0] == results[1] == results[2]


NOT_F32 = "out: expected a numpy.ndarray of dtype float32"


@pytest.mark.parametrize(
    ("out", "error", "words"),
    [
        (
            np.empty((4, 3), np.float64),
            TypeError,
            ["out: expected a numpy.ndarray of dtype float32", "float64"],
        ),
        ([[0.0] * 3] * 4, TypeError, ["out: expected a numpy.ndarray of dtype float32", "list"]),
        (np.empty((4,), np.float32), ValueError, ["out: expected shape (4, 3)", "got (4,)"]),
        (np.empty((3, 3), np.float32), ValueError, ["out: expected shape (4, 3)", "got (3, 3)"]),
        (np.empty((1, 4, 3), np.float32), ValueError, ["out: expected shape (4, 3)", "got (1, 4, 3)"]),
        (np.empty((4, 6), np.float32)[:, ::2], ValueError, ["out: expected a C-contiguous array"]),
        (np.empty((3, 4), np.float32).T, ValueError, ["out: expected a C-contiguous array"]),
        (np.empty((3, 4), np.float32), ValueError, ["out: expected shape (4, 3)", "got (3, 4)"]),
    ],
)
def test_an_unusable_out_is_refused_naming_it(out: object, error: type, words: list[str]) -> None:
    l = np.tile(np.float32([0, 0.3, 1]), (4, 1))
    with pytest.raises(error) as e:
        brdfpy.model("lambert").eval(l, [0, 0, 1], [0, 0, 1], out=out)  # type: ignore[arg-type]
    assert all(w in str(e.value) for w in words), str(e.value)


def test_a_read_only_out_and_an_out_that_is_an_input_are_refused() -> None:
    m = brdfpy.model("lambert")
    l = np.tile(np.float32([0, 0.3, 1]), (4, 1))
    ro = np.empty((4, 3), np.float32)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="out: the array is read-only"):
        m.eval(l, [0, 0, 1], [0, 0, 1], out=ro)
    with pytest.raises(ValueError, match="out: overlaps an input"):
        m.eval(l, [0, 0, 1], [0, 0, 1], out=l)
    with pytest.raises(ValueError, match="out: overlaps an input"):
        v = l.copy()
        m.eval(l, v, [0, 0, 1], out=v)
    assert (l == np.float32([0, 0.3, 1])).all()  # nothing was written


def test_bad_input_with_out_names_the_input() -> None:
    l = np.tile(np.float32([0, 0.3, 1]), (4, 1))
    l[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"l: .*at l\[2\]"):
        brdfpy.model("lambert").eval(l, [0, 0, 1], [0, 0, 1], out=np.empty((4, 3), np.float32))
