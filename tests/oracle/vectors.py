"""Vector helpers in brdfpy's convention: every direction points AWAY from the surface point.

Sources: seed 000 ("Phong": ``r = 2(n.l)n - l``), seed 001 ("Refraction (Snell's law)"), seed 003
("Reflection Geometry": ``H = (I + V)/|I + V|``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def as_vec3(x: ArrayLike) -> F64:
    """``x`` as a float64 array of shape (N, 3) (a single vector becomes (1, 3))."""
    a = np.asarray(x, dtype=np.float64)
    return a.reshape(1, 3) if a.ndim == 1 else a


def dot(a: F64, b: F64) -> F64:
    """Row-wise dot product of (N, 3) arrays -> (N,)."""
    return np.einsum("...i,...i->...", a, b)


def normalize(a: ArrayLike) -> tuple[F64, NDArray[np.bool_]]:
    """Unit vectors and a mask of the rows that had a finite, non-zero length (others become 0)."""
    a = as_vec3(a)
    with np.errstate(invalid="ignore", over="ignore"):
        length = np.sqrt(dot(a, a))
    ok = np.isfinite(length) & (length > 0)
    safe = np.where(ok, length, 1.0)
    out = np.where(ok[..., None], a / safe[..., None], 0.0)
    return out, ok


def reflect(w: ArrayLike, n: ArrayLike) -> F64:
    """Mirror direction ``r = 2(n.w)n - w`` (seed 000 "Phong"; seed 002 "Reflection")."""
    w, n = as_vec3(w), as_vec3(n)
    return 2.0 * dot(n, w)[..., None] * n - w


def halfway(l: ArrayLike, v: ArrayLike) -> F64:
    """``h = (l + v)/|l + v|`` (seed 003 "Reflection Geometry"); 0 where ``l = -v``."""
    return normalize(as_vec3(l) + as_vec3(v))[0]


def refract(w: ArrayLike, n: ArrayLike, eta: float | F64) -> tuple[F64, NDArray[np.bool_]]:
    """Refracted direction (pointing away from the surface on the far side) and an ``ok`` mask.

    Seed 001 "Refraction": with ``n12 = 1/eta`` (eta = eta_t/eta_i) and ``w`` on the normal's side,
    ``t = [n12 (n.w) - sqrt(1 - n12^2 (1 - (n.w)^2))] n - n12 w``. ``ok`` is False on total internal
    reflection (the square root's argument is negative), where ``t`` is returned as 0.
    """
    w, n = as_vec3(w), as_vec3(n)
    n12 = 1.0 / np.asarray(eta, dtype=np.float64)
    c = dot(n, w)
    disc = 1.0 - n12**2 * (1.0 - c**2)
    ok = disc >= 0
    root = np.sqrt(np.where(ok, disc, 0.0))
    t = (n12 * c - root)[..., None] * n - np.asarray(n12)[..., None] * w
    return np.where(ok[..., None], t, 0.0), ok


def frame_from_normal(n: F64) -> tuple[F64, F64]:
    """Tangent and bitangent of the branchless orthonormal basis of Duff et al. 2017 ("Building an
    Orthonormal Basis, Revisited", JCGT 6(1), Listing 3); brdfpy documents that anisotropic models use
    this frame when no tangent is given."""
    n = as_vec3(n)
    x, y, z = n[:, 0], n[:, 1], n[:, 2]
    sign = np.where(z >= 0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    t = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    bt = np.stack([b, sign + y * y * a, -y], axis=-1)
    return t, bt


def frame(n: F64, tangent: F64 | None) -> tuple[F64, F64]:
    """(t, b) with ``b = n x t``: the tangent hint Gram-Schmidt orthogonalised against ``n``, or the
    Duff et al. frame where there is no usable hint."""
    n = as_vec3(n)
    t0, b0 = frame_from_normal(n)
    if tangent is None:
        return t0, b0
    tg = np.broadcast_to(as_vec3(tangent), n.shape)
    t = tg - dot(tg, n)[..., None] * n
    t, ok = normalize(t)
    ok &= dot(tg - dot(tg, n)[..., None] * n, tg - dot(tg, n)[..., None] * n) > 1e-12
    t = np.where(ok[..., None], t, t0)
    b = np.where(ok[..., None], np.cross(n, t), b0)
    return t, b
