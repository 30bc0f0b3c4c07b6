"""Generators of plausible and hostile argument values, driven by one ``random.Random``.

The same generators serve hypothesis (``st.randoms()`` hands them a Random whose draws it records and
shrinks) and the long campaign of ``benchmarks/fuzz.py`` (a plain seeded Random, so that a call is a pure
function of ``(seed, index)`` and can be replayed).

Each parameter *kind* (a 3-vector array, a scalar array, a float, an int, a name, a path, a model, a
mesh, ...) has a generator of plausible values; :func:`value` returns, with probability ``hostile``, a
hostile value instead — of the same kind with poison in it (NaN/±inf/denormals in arrays, absurd sizes,
wrong shapes, dtypes object/str/complex/float16/bool, Fortran order and strides), or of another kind
altogether (``None``, a string, an object, a complex number, a huge integer).
"""

from __future__ import annotations

import math
import os
import random
import tempfile
from collections.abc import Callable
from typing import Any

import numpy as np

#: Floats that break arithmetic: zero, signs, denormals, the float32 edges, float64 beyond float32, NaN, ±∞.
HOSTILE_FLOATS = [
    0.0,
    -0.0,
    -1.0,
    1e-45,
    -1e-45,
    1e-38,
    1.17549435e-38,
    3.4028235e38,
    1e38,
    -1e38,
    1e39,
    1e308,
    -1e308,
    5e-324,
    math.nan,
    math.inf,
    -math.inf,
    1e9,
    -1e9,
    0.5,
    2.0**24 + 1,
]

#: Integers that break sizes and indices.
HOSTILE_INTS = [0, -1, 1, 2, -(2**31), 2**31, 2**32, 2**63, 2**64, -(2**64), 10**12, 10**30, 2**16 + 1, 7, 3]


class Opaque:
    """An object no API function should accept (and whose repr says what it is)."""

    def __repr__(self) -> str:
        return "Opaque()"


def hostile_other(r: random.Random) -> Any:
    """A value of the wrong kind for almost any parameter."""
    return r.choice(
        [
            None,
            "x",
            "",
            "nan",
            b"\x00",
            Opaque(),
            1 + 2j,
            True,
            r.choice(HOSTILE_INTS),
            r.choice(HOSTILE_FLOATS),
            [],
            [[]],
            [1, "a"],
            {"a": 1},
            (),
            np.array([], dtype=object),
            np.array(["a", "b", "c"]),
            np.array([1 + 1j, 2, 3]),
            np.float16(1.0),
            np.int8(-1),
            np.bool_(True),
            float,
            print,
            slice(None),
            range(3),
        ]
    )


def _poison(r: random.Random, a: np.ndarray) -> np.ndarray:
    """Put special values into a float array (in place if writable)."""
    if a.size and a.dtype.kind == "f":
        flat = a.reshape(-1)
        for _ in range(1 + r.randrange(3)):
            flat[r.randrange(flat.size)] = r.choice(HOSTILE_FLOATS)
    return a


def _layout(r: random.Random, a: np.ndarray) -> np.ndarray:
    """The same values in another memory layout: Fortran order, a strided or reversed view, read-only."""
    k = r.randrange(6)
    if k == 0:
        return np.asfortranarray(a)
    if k == 1 and a.ndim >= 1:
        doubled = np.repeat(a, 2, axis=0)
        return doubled[::2]
    if k == 2 and a.ndim >= 1:
        return a[::-1]
    if k == 3:
        b = a.copy()
        b.setflags(write=False)
        return b
    if k == 4 and a.ndim >= 2:
        return np.swapaxes(np.swapaxes(a, 0, -2).copy(), 0, -2)
    return a


DTYPES = [
    np.float32,
    np.float64,
    np.float16,
    np.int32,
    np.int64,
    np.uint8,
    np.bool_,
    np.complex64,
    object,
    str,
]


def _cast(r: random.Random, a: np.ndarray) -> np.ndarray:
    dtype = r.choice(DTYPES)
    if dtype is str:
        return a.astype(str)
    with np.errstate(all="ignore"):
        return a.astype(dtype)


def unit_vectors(r: random.Random, count: int, upper: bool = True) -> np.ndarray:
    g = np.random.default_rng(r.randrange(2**32))
    v = g.normal(size=(count, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    if upper:
        v[:, 2] = np.abs(v[:, 2])
    return v


def vec3(r: random.Random, hostile: bool) -> Any:
    """Directions, normals, points: shape (3,), (k, 3) or (a, b, 3), float32 or float64."""
    shapes: list[tuple[int, ...]] = [(3,), (r.randrange(1, 9), 3), (2, r.randrange(1, 4), 3)]
    shape = r.choice(shapes)
    count = int(np.prod(shape[:-1])) if len(shape) > 1 else 1
    a = unit_vectors(r, count).reshape(shape) * r.choice([1.0, 1.0, 0.5, 3.0])
    a = a.astype(r.choice([np.float32, np.float64]))
    if r.random() < 0.15:
        return [float(x) for x in a.reshape(-1)[:3]]
    if not hostile:
        return a
    k = r.randrange(10)
    if k == 0:
        return _poison(r, a.copy())
    if k == 1:
        return _cast(r, a)
    if k == 2:
        return _layout(r, a)
    if k == 3:
        return np.zeros(r.choice([(0, 3), (3,), (4, 3), (0,)]), dtype=np.float32)
    if k == 4:
        return np.ones(r.choice([(2,), (4,), (5, 2), (3, 3, 4), (1, 1, 1, 1, 1, 3), ()]), dtype=np.float32)
    if k == 5:
        return [[1.0, 2.0, 3.0], [1.0, 2.0]]  # ragged
    if k == 6:
        # Broadcasts against nothing else of the call (leading 7 vs anything).
        return np.ones((7, 5, 3), np.float32)
    if k == 7:
        return np.full(shape, r.choice([1e-45, 1e38, 3e38, 1e-38]), dtype=np.float32)
    if k == 8:
        return np.broadcast_to(np.float32([0.0, 0.0, 1.0]), (r.randrange(1, 5), 3))
    return hostile_other(r)


def scalars(r: random.Random, hostile: bool, lo: float = -1.0, hi: float = 1.0) -> Any:
    """Numbers of any shape (cosines, values to tone map, ...)."""
    shape = r.choice([(), (r.randrange(1, 9),), (2, r.randrange(1, 4))])
    g = np.random.default_rng(r.randrange(2**32))
    a = g.uniform(lo, hi, size=shape).astype(r.choice([np.float32, np.float64]))
    if r.random() < 0.1:
        return float(a.reshape(-1)[0]) if a.size else 0.5
    if not hostile:
        return a
    k = r.randrange(7)
    if k == 0:
        return _poison(r, np.atleast_1d(a).copy())
    if k == 1:
        return _cast(r, np.atleast_1d(a))
    if k == 2:
        return _layout(r, np.atleast_2d(a))
    if k == 3:
        return np.zeros((0,), np.float32)
    if k == 4:
        return np.full((3,), r.choice(HOSTILE_FLOATS), np.float32)
    return hostile_other(r)


def number(r: random.Random, hostile: bool, lo: float, hi: float, log: bool = False) -> Any:
    """One float in a plausible range, or a hostile one."""
    if hostile:
        return r.choice(HOSTILE_FLOATS) if r.random() < 0.7 else hostile_other(r)
    if log:
        return float(math.exp(r.uniform(math.log(lo), math.log(hi))))
    return r.uniform(lo, hi)


def integer(r: random.Random, hostile: bool, lo: int, hi: int) -> Any:
    """One int in a plausible range, or a hostile one (absurd sizes included)."""
    if hostile:
        return r.choice(HOSTILE_INTS) if r.random() < 0.7 else hostile_other(r)
    return r.randint(lo, hi)


def name(r: random.Random, hostile: bool, choices: list[str]) -> Any:
    if hostile or not choices:
        return (
            r.choice(["", "ABC", "nonexistent", "ggx ", "GGX", "\x00", "é" * 3, "x" * 300])
            if r.random() < 0.6
            else hostile_other(r)
        )
    return r.choice(choices)


def rgb(r: random.Random, hostile: bool) -> Any:
    if not hostile:
        return r.choice([r.uniform(0, 1), (r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1))])
    return (
        r.choice([(-1.0, 0.0, 0.0), (math.nan, 0, 0), (1.0, 2.0), (math.inf,) * 3, "red", [1, 2, 3, 4]])
        if r.random() < 0.6
        else hostile_other(r)
    )


def bools(r: random.Random, hostile: bool) -> Any:
    return r.random() < 0.5 if not hostile else hostile_other(r)


_TMP = tempfile.mkdtemp(prefix="brdfpy-fuzz-")


def path(r: random.Random, hostile: bool, suffixes: tuple[str, ...]) -> Any:
    """A path in a private temporary folder (files there may or may not exist), or a non-path."""
    if hostile:
        return r.choice([0, 1, 3, -1, 2.5, None, b"", "", _TMP, "/nonexistent/x.obj", Opaque(), os.devnull])
    return os.path.join(_TMP, f"f{r.randrange(4)}{r.choice(suffixes)}")


def tmp_dir() -> str:
    return _TMP


Generator = Callable[[random.Random, bool], Any]
