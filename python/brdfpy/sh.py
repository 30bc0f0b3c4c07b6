"""Real spherical harmonics: basis, an exact quadrature, projection and reconstruction (Sloan, Kautz & Snyder
2002; Green 2003, "Spherical Harmonic Lighting: The Gritty Details").

Convention: orthonormal real harmonics (``∫ Y_i Y_j dω = δ_ij``) without the Condon–Shortley phase, as in
Ramamoorthi & Hanrahan (2001): ``Y_{1,-1} = 0.488603·y``, ``Y_{1,0} = 0.488603·z``, ``Y_{1,1} = 0.488603·x``.
Coefficient ``(l, m)`` is at index ``l(l+1) + m`` (:func:`index`); order ``L`` has ``(L+1)²`` of them.
Everything is float64.

The quadrature (:func:`quadrature`) is Gauss–Legendre in ``cos θ`` on each hemisphere separately times uniform
``φ``: exact for products of harmonics up to its order, and also for functions that vanish below the horizon
with a kink there, such as the clamped cosine and every ``f_r · max(n·l, 0)`` lobe.

>>> import numpy as np
>>> from brdfpy import sh
>>> c = sh.project(lambda d: np.maximum(d[:, 2], 0.0), order=2)
>>> round(float(c[sh.index(0, 0)] * np.sqrt(4 * np.pi)), 6)  # Â_0 = π
3.141593
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, as_int

__all__ = [
    "MAX_ORDER",
    "Quadrature",
    "basis",
    "clamped_cosine_zonal",
    "convolve",
    "index",
    "irradiance",
    "num_coeffs",
    "project",
    "quadrature",
    "reconstruct",
]

F64 = NDArray[np.float64]

#: The highest supported order ``L``.
MAX_ORDER: int = _brdfpy.sh_max_order()


class Quadrature(NamedTuple):
    """Nodes ``directions`` (M, 3), unit, and ``weights`` (M,) in steradians (they sum to 4π)."""

    directions: F64
    weights: F64


def num_coeffs(order: int) -> int:
    """``(order + 1)²``, the number of coefficients of order ``order``."""
    return (_check_order(order) + 1) ** 2


def index(l: int, m: int) -> int:
    """Index of coefficient ``(l, m)``: ``l(l+1) + m``, for ``|m| <= l``."""
    for name, k in (("l", l), ("m", m)):
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise TypeError(f"{name}: expected an int, got {type(k).__name__}")
    l, m = int(l), int(m)
    if l < 0 or abs(m) > l:
        raise ValueError(f"(l, m): expected l >= 0 and |m| <= l, got ({l}, {m})")
    return l * (l + 1) + m


def _check_order(order: int) -> int:
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
        raise TypeError(f"order: expected an int, got {type(order).__name__}")
    if not 0 <= order <= MAX_ORDER:
        raise ValueError(f"order: must be in [0, {MAX_ORDER}], got {order}")
    return int(order)


def _dirs(name: str, x: ArrayLike) -> tuple[F64, tuple[int, ...]]:
    """Directions of shape ``(..., 3)`` as float64 rows ``(N, 3)`` and the leading shape to restore."""
    a = _as_numeric(name, x)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"{name}: expected an array of shape (..., 3), got {np.shape(x)}")
    lead = a.shape[:-1]
    return np.ascontiguousarray(a, dtype=np.float64).reshape(-1, 3), lead


def basis(directions: ArrayLike, order: int) -> F64:
    """``Y_i(ω)`` of every direction (rows) for ``i < (order+1)²`` (columns).

    ``directions`` has shape ``(..., 3)``, any length (normalised; a zero vector gives a zero row). Returns
    float64 ``(..., (order+1)²)``: ``((order+1)²,)`` for a single ``(3,)`` direction.
    """
    order = _check_order(order)
    d, lead = _dirs("directions", directions)
    out = _brdfpy.sh_basis(d, order)
    return out.reshape(*lead, out.shape[1])


def quadrature(order: int | None = None, *, n_mu: int | None = None, n_phi: int | None = None) -> Quadrature:
    """The hemisphere-split Gauss–Legendre × uniform-φ rule.

    With ``order``: the smallest rule exact for products of two functions of that order
    (``n_mu = order + 1`` nodes per hemisphere, ``n_phi = 2·order + 1``). Or give ``n_mu`` and ``n_phi``
    directly (more nodes for functions that are not band-limited, such as glossy lobes).
    """
    if order is not None:
        if n_mu is not None or n_phi is not None:
            raise ValueError("quadrature: give either order or n_mu and n_phi, not both")
        order = _check_order(order)
        n_mu, n_phi = order + 1, 2 * order + 1
    if n_mu is None or n_phi is None:
        raise ValueError("quadrature: give order, or both n_mu and n_phi")
    for name, k in (("n_mu", n_mu), ("n_phi", n_phi)):
        as_int(name, k, 1, 2**32)
    d, w = _brdfpy.sh_quadrature(int(n_mu), int(n_phi))
    return Quadrature(d, w)


#: What :func:`project` accepts: values at the quadrature nodes, or a function of the (M, 3) directions.
Function = Union[ArrayLike, Callable[[F64], ArrayLike]]


def project(f: Function, order: int, quad: Quadrature | None = None) -> F64:
    """Coefficients ``c_i = Σ_k w_k f(ω_k) Y_i(ω_k)`` of ``f`` up to ``order``.

    Parameters
    ----------
    f : callable or array_like
        A function taking the (M, 3) float64 node directions and returning (M,) or (M, 3) values, or those
        values themselves.
    order : int
        Highest band ``L``.
    quad : Quadrature, optional
        Nodes and weights; default ``quadrature(n_mu=2*order + 2, n_phi=4*order + 4)``, exact for
        band-limited ``f`` up to order ``3·order + 3`` (and hemispherical lobes of such degree).

    Returns
    -------
    numpy.ndarray of float64, shape ((L+1)²,) for scalar values, ((L+1)², 3) for RGB
    """
    order = _check_order(order)
    if quad is None:
        quad = quadrature(n_mu=2 * order + 2, n_phi=4 * order + 4)
    elif not isinstance(quad, Quadrature):
        raise TypeError(f"quad: expected a Quadrature (from brdfpy.sh.quadrature), got {type(quad).__name__}")
    d = np.ascontiguousarray(quad.directions, dtype=np.float64)
    w = np.ascontiguousarray(quad.weights, dtype=np.float64)
    vals = np.asarray(f(d.copy()) if callable(f) else f)
    if vals.dtype.kind not in "fiu":
        raise TypeError(f"f: expected real values, got dtype {vals.dtype}")
    m = d.shape[0]
    scalar = vals.shape == (m,)
    if scalar:
        vals = np.repeat(vals.reshape(m, 1), 3, axis=1)
    if vals.shape != (m, 3):
        raise ValueError(f"f: expected values of shape ({m},) or ({m}, 3) at the nodes, got {vals.shape}")
    c = _brdfpy.sh_project(np.ascontiguousarray(vals, dtype=np.float64), d, w, order)
    return np.ascontiguousarray(c[:, 0]) if scalar else c


def reconstruct(coeffs: ArrayLike, directions: ArrayLike) -> F64:
    """``Σ_i c_i Y_i(ω)`` at each direction.

    ``coeffs`` is ((L+1)²,) or ((L+1)², 3); ``directions`` ``(..., 3)``. Returns ``(...)`` for scalar
    coefficients, ``(..., 3)`` for RGB ones (``()`` / ``(3,)`` for a single ``(3,)`` direction).
    """
    c = _as_numeric("coeffs", coeffs)
    scalar = c.ndim == 1
    if scalar:
        c = np.repeat(c.reshape(-1, 1), 3, axis=1)
    if c.ndim != 2 or c.shape[1] != 3:
        raise ValueError(f"coeffs: expected shape ((L+1)^2,) or ((L+1)^2, 3), got {np.shape(coeffs)}")
    d, lead = _dirs("directions", directions)
    out = _brdfpy.sh_reconstruct(np.ascontiguousarray(c, dtype=np.float64), d)
    if scalar:
        return np.ascontiguousarray(out[:, 0]).reshape(lead)
    return out.reshape(*lead, 3)


def convolve(coeffs: ArrayLike, kernel: ArrayLike) -> F64:
    """Convolve with a kernel symmetric about an axis (Funk–Hecke): band ``l`` is scaled by ``kernel[l]``.

    ``kernel[l] = Â_l = 2π ∫ k(t) P_l(t) dt`` over ``[-1, 1]``; ``coeffs`` is ((L+1)²,) or ((L+1)², 3) and
    ``kernel`` has ``L + 1`` values. Same formula as ``brdf_core::sh::convolve_zonal`` (a per-band scaling,
    done here in NumPy).
    """
    c = _as_numeric("coeffs", coeffs).astype(np.float64)
    k = _as_numeric("kernel", kernel).astype(np.float64)
    size = c.shape[0] if c.ndim in (1, 2) else 0
    order = math.isqrt(size) - 1
    if size == 0 or (order + 1) ** 2 != size or (c.ndim == 2 and c.shape[1] != 3):
        raise ValueError(f"coeffs: expected shape ((L+1)^2,) or ((L+1)^2, 3), got {c.shape}")
    if k.shape != (order + 1,):
        raise ValueError(f"kernel: expected one value per band ({order + 1},), got shape {k.shape}")
    if not (np.all(np.isfinite(k)) and np.all(np.isfinite(c))):
        raise ValueError("coeffs, kernel: must be finite")
    scale = np.repeat(k, 2 * np.arange(order + 1) + 1)
    return c * (scale if c.ndim == 1 else scale[:, None])


def irradiance(radiance: ArrayLike) -> F64:
    """Irradiance coefficients ``E(n) = ∫ L(ω) max(n·ω, 0) dω`` from radiance coefficients: :func:`convolve`
    with the clamped cosine's ``Â_l`` (Ramamoorthi & Hanrahan 2001)."""
    c = _as_numeric("radiance", radiance).astype(np.float64)
    order = math.isqrt(c.shape[0]) - 1 if c.ndim in (1, 2) and c.shape[0] > 0 else 0
    return convolve(c, [clamped_cosine_zonal(l) for l in range(order + 1)])


def clamped_cosine_zonal(l: int) -> float:
    """Ramamoorthi & Hanrahan's ``Â_l`` of the clamped cosine ``max(cos θ, 0)`` in closed form
    (``Â_0 = π``, ``Â_1 = 2π/3``, ``Â_2 = π/4``, 0 for odd ``l > 1``): irradiance from radiance multiplies
    band ``l`` by ``Â_l``."""
    return _brdfpy.sh_clamped_cosine_zonal(as_int("l", l, 0, 2**62))
