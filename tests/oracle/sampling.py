"""Sampling densities [1/sr] of the published techniques, float64, in the local frame (z = normal).

Written from the papers, with the oracle's own D and Lambda (:mod:`oracle.microfacet`), not from the Rust
sources: the density of a direction ``l`` drawn for the view ``v``.

Sources: Malley's method (cosine-weighted hemisphere; pbrt-v4 §A.5.3); Lafortune & Willems 1994 (Phong lobe
``(n+1)/(2 pi) cos^n``); Walter et al. 2007 eq. 14 (half-vector Jacobian ``1/(4 v.h)``); Heitz & d'Eon 2014
and Heitz 2018 (visible normals: ``D_v = G1(v) max(0, v.h) D(h)/(n.v)``); Walter 2005 (Ward:
``D cos/(4 v.h)``);
Ashikhmin & Shirley 2000 eq. 9-10 (half-vector density over ``4 v.h``); Veach 1997 §9.2 (one-sample mixture).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from oracle import microfacet as mf

F64 = NDArray[np.float64]


def _unit(a: F64) -> F64:
    a = np.asarray(a, dtype=np.float64)
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _half(l: F64, v: F64) -> tuple[F64, F64]:
    """Unit half vector and v.h."""
    h = _unit(l + v)
    return h, np.einsum("...i,...i->...", v, h)


def cosine(l: F64) -> F64:
    """``max(cos theta, 0)/pi``."""
    return np.maximum(l[..., 2], 0.0) / np.pi


def lobe(l: F64, v: F64, exponent: float, c: tuple[float, float, float] = (-1.0, -1.0, 1.0)) -> F64:
    """``(n+1)/(2 pi) max(0, a.l)^n`` about ``a = normalize(C o v)``; ``C = (-1, -1, 1)`` is Phong's
    mirror lobe."""
    a = _unit(np.asarray(c) * v)
    cos = np.einsum("...i,...i->...", a, l)
    return (exponent + 1.0) / (2 * np.pi) * np.where(cos > 0, np.maximum(cos, 0.0) ** exponent, 0.0)


def half_power(l: F64, v: F64, exponent: float) -> F64:
    """Half vectors with density ``(n+1)/(2 pi) cos^n theta_h``, reflected: over ``4 v.h``."""
    h, vh = _half(l, v)
    ph = (exponent + 1.0) / (2 * np.pi) * np.maximum(h[..., 2], 0.0) ** exponent
    return np.where((h[..., 2] > 0) & (vh > 0), ph / (4 * vh), 0.0)


def visible_normals(l: F64, v: F64, distribution: str, ax: float, ay: float | None = None) -> F64:
    """``G1(v) D(h) / (4 n.v)`` for ``"ggx"`` or ``"beckmann"``."""
    h, vh = _half(l, v)
    d_fn, lam_fn = (mf.ggx, mf.lambda_ggx) if distribution == "ggx" else (mf.beckmann, mf.lambda_beckmann)
    d = d_fn(h[..., 0], h[..., 1], h[..., 2], ax, ay)
    g1 = 1.0 / (1.0 + lam_fn(v[..., 0], v[..., 1], v[..., 2], ax, ay))
    return np.where((h[..., 2] > 0) & (vh > 0), g1 * d / (4 * v[..., 2]), 0.0)


def ward(l: F64, v: F64, ax: float, ay: float) -> F64:
    """Ward's half vectors (Walter 2005): ``D_beckmann(h) cos theta_h / (4 v.h)``."""
    h, vh = _half(l, v)
    d = mf.ward(h[..., 0], h[..., 1], h[..., 2], ax, ay)
    return np.where((h[..., 2] > 0) & (vh > 0), d * h[..., 2] / (4 * vh), 0.0)


def ashikhmin_shirley(l: F64, v: F64, nu: float, nv: float) -> F64:
    """AS2000's half-vector density ``sqrt((nu+1)(nv+1))/(2 pi) cos^e theta_h`` over ``4 v.h``."""
    h, vh = _half(l, v)
    ph = mf.ashikhmin_shirley(h[..., 0], h[..., 1], h[..., 2], nu, nv)
    return np.where((h[..., 2] > 0) & (vh > 0), ph / (4 * vh), 0.0)


def mixture(weights: list[float], densities: list[F64]) -> F64:
    """The one-sample mixture ``sum w_i p_i / sum w_i``."""
    return sum(w * p for w, p in zip(weights, densities)) / sum(weights)
