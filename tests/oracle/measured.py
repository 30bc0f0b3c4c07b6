"""A tabulated isotropic BRDF on the MERL grid, written independently of brdfpy from the layout of Matusik et
al. (2003) and their ``BRDFRead.cpp``: half/difference angles by explicit rotations of the incoming direction
(about the normal by ``-φ_h``, then about the binormal by ``-θ_h``), and trilinear interpolation in index
coordinates (``sqrt`` mapping for ``θ_h``, φ_d periodic with period π).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def _rotate(v: F64, axis: F64, angle: F64) -> F64:
    """Rodrigues' rotation of rows ``v`` about unit ``axis`` by ``angle`` (per row)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + np.cross(axis, v) * s + axis * (v @ axis)[:, None] * (1.0 - c)


def half_diff(l: ArrayLike, v: ArrayLike) -> tuple[F64, F64, F64]:
    """(θ_h, θ_d, φ_d ∈ [0, π)) of unit (N, 3) directions in a frame with ``n = +z``."""
    l = np.asarray(l, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    h = l + v
    h = h / np.linalg.norm(h, axis=1, keepdims=True)
    # Polar angles by atan2 of the tangent-plane and normal components, not arccos: even in float64, arccos
    # of a cosine near 1 is only good to sqrt(2^-52) = 1.5e-8 rad, a quarter of what rounding the directions
    # to float32 does to an angle near 0, where the tests compare (the specular peak, the retro direction).
    theta_h = np.arctan2(np.hypot(h[:, 0], h[:, 1]), h[:, 2])
    phi_h = np.arctan2(h[:, 1], h[:, 0])
    tmp = _rotate(l, np.array([0.0, 0.0, 1.0]), -phi_h)
    d = _rotate(tmp, np.array([0.0, 1.0, 0.0]), -theta_h)
    theta_d = np.arctan2(np.hypot(d[:, 0], d[:, 1]), d[:, 2])
    phi_d = np.mod(np.arctan2(d[:, 1], d[:, 0]), np.pi)
    return theta_h, theta_d, phi_d


def interpolate(table: ArrayLike, theta_h: ArrayLike, theta_d: ArrayLike, phi_d: ArrayLike) -> F64:
    """Trilinear interpolation of a (n_th, n_td, n_pd, 3) table at half/difference angles (radians, θ_h and
    θ_d held at the last node, φ_d modulo π)."""
    t = np.asarray(table, dtype=np.float64)
    n_th, n_td, n_pd, _ = t.shape
    th, td, pd = (np.asarray(a, dtype=np.float64) for a in (theta_h, theta_d, phi_d))
    uh = np.clip(np.sqrt(np.maximum(th, 0) / (np.pi / 2)) * n_th, 0, n_th - 1)
    ud = np.clip(td / (np.pi / 2) * n_td, 0, n_td - 1)
    up = np.mod(pd, np.pi) / np.pi * n_pd
    i0 = np.minimum(uh.astype(int), n_th - 2)
    j0 = np.minimum(ud.astype(int), n_td - 2)
    k0 = np.minimum(up.astype(int), n_pd - 1)
    fh, fd, fp = (uh - i0)[:, None], (ud - j0)[:, None], np.clip(up - k0, 0, 1)[:, None]
    k1 = (k0 + 1) % n_pd
    out = np.zeros((th.shape[0], 3))
    for di, wi in ((0, 1 - fh), (1, fh)):
        for dj, wj in ((0, 1 - fd), (1, fd)):
            a = t[i0 + di, j0 + dj, k0]
            b = t[i0 + di, j0 + dj, k1]
            out += wi * wj * (a * (1 - fp) + b * fp)
    return out


def lookup(table: ArrayLike, l: ArrayLike, v: ArrayLike) -> F64:
    """Trilinear look-up of a (n_th, n_td, n_pd, 3) table at unit directions with ``n = +z``; 0 unless both
    are above the surface."""
    l = np.asarray(l, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    out = interpolate(table, *half_diff(l, v))
    above = (l[:, 2] > 0) & (v[:, 2] > 0)
    return np.where(above[:, None], out, 0.0)
