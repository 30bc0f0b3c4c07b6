"""Array-likes → C-contiguous float32 arrays for the compiled module, with errors that name the argument.

Every public function converts its inputs here and nowhere else. Float32 C-contiguous input passes through
without a copy (the same array object); float64, integer or strided input is copied once. Shapes,
broadcasting and finiteness (NaN / inf) are checked by the compiled module (brdf-core's batch rules, the
same for Rust users), inside the evaluation loop, chunk by chunk while the data is in cache, and reported with
the argument's name and the offending index. A finite float64 value beyond the float32 range (``|x| >
3.4028235e38``, e.g. ``1e39``) is refused here, when it is converted, with a ``ValueError`` naming the
argument and the index of the first such element: it would otherwise become ``inf`` silently.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["as_f64", "as_float", "as_int", "as_scalars", "as_str", "as_vec3", "as_vectors"]

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


#: The largest float32, and the range of the integers the helpers take (the compiled module's 64-bit ones).
F32_MAX = float(np.finfo(np.float32).max)
I64_MIN, I64_MAX = -(2**63), 2**63 - 1


def _index(shape: tuple[int, ...], flat: int) -> str:
    return ", ".join(str(int(i)) for i in np.unravel_index(flat, shape)) if shape else ""


def _to_f32(name: str, a: NDArray[Any]) -> F32:
    if a.dtype == np.float32 and a.flags.c_contiguous and a.flags.aligned:
        return a  # the common case: used as it is, no copy (and no cost for small batches)
    # (Unaligned float32 data, e.g. a buffer as it arrives from the network, cannot be read as floats in
    # place by the compiled module: copied like strided input.) np.asarray(order="C") keeps 0-d arrays 0-d
    # (np.ascontiguousarray would make them 1-d).
    with np.errstate(over="ignore", invalid="ignore"):
        out = np.asarray(a, dtype=np.float32, order="C")
    if a.dtype.kind == "f" and a.dtype.itemsize > 4 and out.size:
        # A finite value past the float32 range has just become ±inf: refused, naming where. (±inf and NaN
        # given as such pass on to the compiled module's own check, which knows which arguments take them.)
        past = np.isinf(out)
        if past.any():
            past &= np.isfinite(a)
            if past.any():
                i = int(np.argmax(past.reshape(-1)))
                x = a.reshape(-1)[i]
                at = f" at {name}[{_index(a.shape, i)}]" if a.ndim else ""
                raise ValueError(
                    f"{name}: holds a value beyond the float32 range (|x| <= {F32_MAX:.8g}){at}: {float(x)!r}"
                )
    return out if out.flags.aligned else out.copy()  # (asarray keeps unaligned float32 data as it is)


def as_vectors(name: str, x: ArrayLike | None) -> F32:
    """Convert ``x`` to a C-contiguous float32 array; the compiled module requires shape ``(..., 3)``.

    The input of every batch function: leading dimensions broadcast NumPy-style, the output has the
    broadcast shape followed by the output's own axes (``(3,)`` vectors in, one result out).
    """
    if x is None:
        raise TypeError(f"{name}: expected an array of shape (..., 3), got None")
    return _to_f32(name, _as_numeric(name, x))


def as_vec3(name: str, x: ArrayLike | None) -> tuple[F32, bool]:
    """Convert ``x`` to a C-contiguous float32 ``(k, 3)`` array, ``k >= 1`` (row-based APIs: meshes, rays).

    Returns the array and whether ``x`` was a single vector of shape ``(3,)``.
    """
    if x is None:
        raise TypeError(f"{name}: expected an array of shape (N, 3) or (3,), got None")
    a = _as_numeric(name, x)
    if a.shape == (3,):
        return _to_f32(name, a).reshape(1, 3), True
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (N, 3) or (3,), got {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    return _to_f32(name, a), False


def as_scalars(name: str, x: ArrayLike | None) -> F32:
    """Convert ``x`` (a number or an array of any shape) to a C-contiguous float32 array of that shape."""
    if x is None:
        raise TypeError(f"{name}: expected a number or an array of numbers, got None")
    a = _as_numeric(name, x)
    if a.size == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    return _to_f32(name, a)


def as_f64(name: str, x: ArrayLike | None) -> NDArray[np.float64]:
    """``x`` (a number or an array of real numbers of any shape) as a float64 array: complex, bool, str and
    object input are refused with a ``TypeError`` naming ``name`` (NumPy would drop an imaginary part with
    a warning, or say "could not convert" naming nothing)."""
    if x is None:
        raise TypeError(f"{name}: expected a number or an array of numbers, got None")
    return _as_numeric(name, x).astype(np.float64)


def as_float(name: str, x: object) -> float:
    """One real number (Python or NumPy float or int, not bool), as ``float``; a ``TypeError`` naming
    ``name`` otherwise (``float()`` would say "must be a string or a real number", naming nothing)."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name}: expected a number, got {type(x).__name__}")
    try:
        return float(x)
    except OverflowError:  # an int past the float range (10**400): OverflowError naming nothing
        raise ValueError(
            f"{name}: an integer of {int(x).bit_length()} bits is beyond the float range"
        ) from None


def as_int(name: str, x: object, lo: int, hi: int) -> int:
    """One integer in ``[lo, hi]`` (Python or NumPy int, not bool): a ``TypeError`` or ``ValueError`` naming
    ``name`` otherwise (the compiled module would raise ``OverflowError`` for sizes beyond its integers,
    naming nothing). ``lo`` and ``hi`` are clamped to the 64-bit range: no integer outside it is accepted."""
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(x).__name__}")
    k = int(x)
    lo, hi = max(lo, I64_MIN), min(hi, I64_MAX)
    if not lo <= k <= hi:
        if not I64_MIN <= k <= I64_MAX:
            shown = str(k) if k.bit_length() <= 128 else f"an integer of {k.bit_length()} bits"
            raise ValueError(
                f"{name}: {shown} is outside the 64-bit integer range; expected an integer in [{lo}, {hi}]"
            )
        raise ValueError(f"{name}: expected an integer in [{lo}, {hi}], got {k}")
    return k


def as_str(name: str, x: object, what: str = "a name") -> str:
    """A ``str``; a ``TypeError`` naming ``name`` otherwise."""
    if not isinstance(x, str):
        raise TypeError(f"{name}: expected {what} (str), got {type(x).__name__}")
    return x
