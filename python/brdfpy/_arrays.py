"""Array-likes → C-contiguous float32 arrays for the compiled module, with errors that name the argument.

Every public function converts its inputs here and nowhere else. Float32 C-contiguous input passes through
without a copy (``np.ascontiguousarray`` returns the same array); float64, integer or strided input is copied
once. Finiteness (NaN / inf, including float64 values beyond the float32 range) is checked by the compiled
module inside the evaluation loop, chunk by chunk while the data is in cache, and reported with the
argument's name and the offending row.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_scalars", "as_vec3", "as_vec3_args"]

F32 = NDArray[np.float32]

# Kinds NumPy uses for real numbers: float, signed and unsigned integer. Booleans, complex numbers, strings,
# objects, dates and raw bytes are refused: none of them is a direction or a cosine.
_NUMERIC_KINDS = frozenset("fiu")


def _as_numeric(name: str, x: ArrayLike) -> NDArray[Any]:
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{name}: expected an array of real numbers, got {type(x).__name__}")
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:
        # NumPy refuses ragged nested sequences ("inhomogeneous shape") with ValueError.
        raise ValueError(f"{name}: expected a rectangular array of numbers ({e})") from None
    if a.dtype.kind not in _NUMERIC_KINDS:
        raise TypeError(f"{name}: expected real numbers (float or int), got dtype {a.dtype}")
    return a


def _to_f32(a: NDArray[Any]) -> F32:
    if a.dtype == np.float32 and a.flags.c_contiguous:
        return a  # the common case: used as it is, no copy (and no cost for small batches)
    # Values beyond the float32 range become inf here and are reported by the compiled module as non-finite;
    # silence NumPy's overflow warning so that the error, not a warning, tells the user. np.asarray(order="C")
    # keeps 0-d arrays 0-d (np.ascontiguousarray would make them 1-d).
    with np.errstate(over="ignore", invalid="ignore"):
        return np.asarray(a, dtype=np.float32, order="C")


def as_vec3(name: str, x: ArrayLike | None) -> tuple[F32, bool]:
    """Convert ``x`` to a C-contiguous float32 ``(k, 3)`` array, ``k >= 1``.

    Returns the array and whether ``x`` was a single vector of shape ``(3,)``.
    """
    if x is None:
        raise TypeError(f"{name}: expected an array of shape (N, 3) or (3,), got None")
    a = _as_numeric(name, x)
    if a.shape == (3,):
        return _to_f32(a).reshape(1, 3), True
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (N, 3) or (3,), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    return _to_f32(a), False


def as_vec3_args(optional: tuple[str, ...] = (), **arrays: ArrayLike | None) -> tuple[list[F32 | None], bool]:
    """Convert several named vector arguments; ``None`` stays ``None`` for the names in ``optional``.

    Returns the arrays in order and whether every given one was a single ``(3,)`` vector.
    """
    out: list[F32 | None] = []
    single = True
    for name, x in arrays.items():
        if x is None and name in optional:
            out.append(None)
            continue
        a, one = as_vec3(name, x)
        out.append(a)
        single = single and one
    return out, single


def as_scalars(name: str, x: ArrayLike | None) -> F32:
    """Convert ``x`` (a number or an array of any shape) to a C-contiguous float32 array of that shape."""
    if x is None:
        raise TypeError(f"{name}: expected a number or an array of numbers, got None")
    a = _as_numeric(name, x)
    if a.size == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    return _to_f32(a)
