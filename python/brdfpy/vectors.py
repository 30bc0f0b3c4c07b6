"""Reflection, refraction and the half vector over batches of directions.

Every direction points away from the surface (the convention of the whole package): ``w`` and the result of
:func:`reflect` are both on the side the normal points to. Inputs are array-likes of shape ``(..., 3)`` whose
leading dimensions broadcast NumPy-style; outputs are float32 of the broadcast shape followed by 3 (``(3,)``
for single ``(3,)`` vectors).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, as_scalars, as_vectors

__all__ = ["from_spherical", "halfway", "reflect", "refract", "to_spherical"]


def reflect(w: ArrayLike, n: ArrayLike) -> NDArray[np.float32]:
    """Mirror direction of ``w`` about the normal: ``r = 2(n̂·w)n̂ − w``, ``n̂ = n/|n|`` (pbrt-v4 ``Reflect``).

    ``w`` keeps its length (a unit ``w`` gives a unit ``r``): a ``w`` longer than ``f32::MAX / 4``
    (8.5e37), whose mirror image would overflow float32, is refused with a ``ValueError`` naming ``w`` and
    the index. ``n`` may have any finite length; a zero-length ``n`` gives 0.
    """
    return _brdfpy.reflect(as_vectors("w", w), as_vectors("n", n))


def halfway(l: ArrayLike, v: ArrayLike) -> NDArray[np.float32]:
    """Unit half vector ``h = (l̂ + v̂)/|l̂ + v̂|`` (Blinn 1977).

    0 where ``l̂ = −v̂`` or an input has zero length.
    """
    return _brdfpy.halfway(as_vectors("l", l), as_vectors("v", v))


def refract(w: ArrayLike, n: ArrayLike, eta: ArrayLike) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """Refracted direction by Snell's law, ``η_i sin θ_i = η_t sin θ_t`` (pbrt-v4 §9.3, ``Refract``).

    Parameters
    ----------
    w : array_like, shape (..., 3)
        Direction toward where the light comes from, on the side ``n`` points to (normalised here).
    n : array_like, shape (..., 3)
        Surface normal (normalised here).
    eta : float or array_like, shape (...)
        Relative index of refraction ``η_t / η_i`` (> 0), e.g. 1.5 from air into glass; broadcast against
        the leading dimensions of ``w`` and ``n``.

    Returns
    -------
    t : numpy.ndarray of float32, shape (broadcast) + (3,)
        Unit transmitted direction, pointing away from the surface on the far side:
        ``t = −w/η + (cos θ_i/η − cos θ_t) n`` with ``cos θ_t = sqrt(1 − sin²θ_i/η²)``.
    ok : numpy.ndarray of bool, shape (broadcast)
        ``False`` (and ``t = 0``) on total internal reflection (``sin θ_i > η``), when ``w`` is below the
        surface, or for a zero-length input.
    """
    return _brdfpy.refract(as_vectors("w", w), as_vectors("n", n), as_scalars("eta", eta))


def from_spherical(theta: ArrayLike, phi: ArrayLike, *, degrees: bool) -> NDArray[np.float32]:
    """Unit directions from spherical angles: ``(sin θ cos φ, sin θ sin φ, cos θ)``.

    ``θ`` is the polar angle from ``+z`` (the normal of the local frame) and ``φ`` the azimuth from ``+x``
    (the tangent) toward ``+y``. The unit is explicit: ``degrees=True`` or ``degrees=False`` (radians).
    ``theta`` and ``phi`` broadcast against each other (NumPy rules); the result has their shape plus a
    trailing 3, float32, computed in float64 and rounded once.

    >>> brdfpy.vectors.from_spherical(90, 0, degrees=True)
    array([1.000000e+00, 0.000000e+00, 6.123234e-17], dtype=float32)
    """
    t = _angles("theta", theta, degrees)
    p = _angles("phi", phi, degrees)
    try:
        t, p = np.broadcast_arrays(t, p)
    except ValueError:
        raise ValueError(f"theta, phi: shapes {t.shape} and {p.shape} do not broadcast") from None
    st = np.sin(t)
    return np.stack([st * np.cos(p), st * np.sin(p), np.cos(t)], axis=-1).astype(np.float32)


def to_spherical(w: ArrayLike, *, degrees: bool) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Spherical angles ``(θ, φ)`` of directions ``w`` of shape ``(..., 3)`` (need not be unit length).

    ``θ = atan2(|w_xy|, w_z)`` in ``[0, π]`` from ``+z`` and ``φ = atan2(w_y, w_x)`` in ``(−π, π]`` from
    ``+x``, in degrees or radians as asked (``degrees`` is required). The arctangent forms stay accurate
    near the poles, where ``acos(w_z)`` loses half the digits. A zero vector gives ``θ = φ = 0``. float64
    arrays of shape ``w.shape[:-1]``.
    """
    a = _as_numeric("w", w)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"w: expected shape (..., 3), got {a.shape}")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise ValueError("w: contains NaN or infinite values")
    theta = np.arctan2(np.hypot(a[..., 0], a[..., 1]), a[..., 2])
    phi = np.arctan2(a[..., 1], a[..., 0])
    if degrees:
        return np.degrees(theta), np.degrees(phi)
    return theta, phi


def _angles(name: str, x: ArrayLike, degrees: object) -> NDArray[np.float64]:
    if not isinstance(degrees, (bool, np.bool_)):
        raise TypeError(f"degrees: expected True or False, got {degrees!r}")
    a = _as_numeric(name, x).astype(np.float64)  # float64, not the float32 of as_scalars: angles
    if a.size == 0:
        raise ValueError(f"{name}: is empty (shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: contains NaN or infinite values")
    return np.radians(a) if degrees else a
