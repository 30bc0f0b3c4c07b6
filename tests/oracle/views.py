"""The BRDF Explorer views written independently of brdfpy: the directions each view evaluates, built from
the definitions (in-plane sweep, lobe grid, half/difference angles by rotations, lit-sphere pixels), and a
dense quadrature of the directional albedo. Angles in radians, float64."""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]


def spherical(theta: F64, phi: F64) -> F64:
    """Unit directions at polar angle ``theta`` from +z and azimuth ``phi`` from +x, shape (..., 3)."""
    theta, phi = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)


def in_plane(theta_i: float, phi: float, theta_o: F64) -> tuple[F64, F64]:
    """The light at incidence (theta_i, phi) and the viewer swept through the plane of incidence: at signed
    ``theta_o`` on the mirror side (the plane's azimuth plus pi), at ``-theta_o`` on the light's side."""
    l = spherical(np.array(theta_i), np.array(phi))
    t = np.asarray(theta_o, float)
    v = spherical(np.abs(t), np.where(t >= 0, phi + np.pi, phi))
    return l, v


def lobe_directions(n_theta: int, n_phi: int) -> F64:
    """The pole, then rings k = 1..n_theta at k/n_theta * pi/2, each of n_phi azimuths 2 pi j / n_phi."""
    rings = [
        spherical(np.full(n_phi, k / n_theta * np.pi / 2), 2 * np.pi * np.arange(n_phi) / n_phi)
        for k in range(1, n_theta + 1)
    ]
    return np.concatenate([[[0.0, 0.0, 1.0]], *rings])


def _rot_y(angle: F64, w: F64) -> F64:
    c, s = np.cos(angle)[..., None], np.sin(angle)[..., None]
    x, y, z = w[..., 0:1], w[..., 1:2], w[..., 2:3]
    return np.concatenate([c * x + s * z, y, -s * x + c * z], axis=-1)


def half_diff_directions(theta_h: F64, theta_d: F64, phi_d: float) -> tuple[F64, F64]:
    """(l, v) with half vector at polar angle theta_h in the x-z plane (phi_h = 0, n = +z) and difference
    angles (theta_d, phi_d) about it: the difference vector rotated from the pole to h about +y."""
    d = spherical(theta_d, np.full_like(np.asarray(theta_d, float), phi_d))
    mirrored = d * np.array([-1.0, -1.0, 1.0])
    return _rot_y(np.asarray(theta_h, float), d), _rot_y(np.asarray(theta_h, float), mirrored)


def cell_centres(n: int) -> F64:
    """Centres of n equal cells over [0, pi/2]."""
    return (np.arange(n) + 0.5) / n * np.pi / 2


def albedo(f_cos: Callable[[F64], F64], n_mu: int = 200, n_phi: int = 400) -> F64:
    """∫ g(v) dω_v over the upper hemisphere for g(v) = f_r(l, v) cos θ_v given as ``f_cos(v) -> (N, 3)``:
    Gauss-Legendre in cos θ (n_mu points) times the periodic trapezoid rule in φ (n_phi points). Accurate
    for smooth lobes only (no grading toward a peak)."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, w_mu = (x + 1) / 2, w / 2
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    theta = np.arccos(mu)
    v = spherical(theta[:, None], phi[None, :]).reshape(-1, 3)
    g = f_cos(v).reshape(n_mu, n_phi, 3)
    return np.einsum("ijc,i->c", g, w_mu) * (2 * np.pi / n_phi)


def sphere_normals(size: int) -> tuple[NDArray[np.bool_], F64]:
    """Coverage and normals of the unit sphere filling a size x size image seen along -z (row 0 at the top,
    pixel centres)."""
    c = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(c, -c)
    r2 = x * x + y * y
    mask = r2 < 1
    n = np.stack([x, y, np.sqrt(np.maximum(1 - r2, 0))], axis=-1)
    return mask, n
