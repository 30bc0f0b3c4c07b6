"""Fresnel reflectance, float64, from seeds 001/002/004 and the papers they cite.

Deliberately different formulations from the usual renderer code:

* ``dielectric``: Cook & Torrance 1982 (seed 004 "Cook-Torrance (12)", seed 001 "Fresnel term F")
  ``F = 1/2 (g-c)^2/(g+c)^2 [1 + (c(g+c)-1)^2/(c(g-c)+1)^2]``, ``g = sqrt(eta^2 + c^2 - 1)``.
  Seed 001 prints the denominator as ``[c(g-c)-1]^2`` and seed 004 prints ``g = sqrt(n^2 + c^2) - 1``;
  both are slips: the published form (Cook & Torrance 1982 eq. 8; notes section b3) has ``+1`` and the
  square root over ``n^2 + c^2 - 1``.
* ``dielectric_sp``: the angle form of seed 001 ("Fresnel equations"),
  ``Rs = [sin(b-a)/sin(b+a)]^2``, ``Rp = [tan(b-a)/tan(b+a)]^2`` with Snell's ``sin b = sin a / eta``.
* ``conductor``: complex arithmetic with ``eta~ = eta + i k`` (seed 001 writes ``n - i k``; the sign
  convention does not change ``|r|^2``), ``cos t = sqrt(1 - sin^2 i / eta~^2)``,
  ``r_s = (cos i - eta~ cos t)/(cos i + eta~ cos t)``, ``r_p = (eta~ cos i - cos t)/(eta~ cos i + cos t)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]

#: Seed 001 "Fresnel - base specular color", linear F(0) column (Ti, Cr, Fe, Ni, Pt, Cu, Pd, Zn, Au, Al, Ag).
METAL_F0: dict[str, tuple[float, float, float]] = {
    "ti": (0.542, 0.497, 0.449),
    "cr": (0.549, 0.556, 0.554),
    "fe": (0.562, 0.565, 0.578),
    "ni": (0.660, 0.609, 0.526),
    "pt": (0.673, 0.637, 0.585),
    "cu": (0.955, 0.638, 0.538),
    "pd": (0.733, 0.697, 0.652),
    "zn": (0.664, 0.824, 0.850),
    "au": (1.022, 0.782, 0.344),
    "al": (0.913, 0.922, 0.924),
    "ag": (0.972, 0.960, 0.915),
}


def _inside_flip(cos_i: ArrayLike, eta: ArrayLike) -> tuple[F64, F64]:
    """A negative cosine means the ray arrives from inside: use ``|cos|`` and ``1/eta``."""
    c = np.asarray(cos_i, dtype=np.float64)
    e = np.asarray(eta, dtype=np.float64)
    inside = c < 0
    return np.abs(c), np.where(inside, 1.0 / e, e)


def dielectric(cos_i: ArrayLike, eta: ArrayLike) -> F64:
    """Unpolarised exact dielectric Fresnel reflectance in the Cook-Torrance g/c form; TIR -> 1."""
    c, e = _inside_flip(cos_i, eta)
    c = np.minimum(c, 1.0)
    g2 = e * e + c * c - 1.0
    tir = g2 < 0
    g = np.sqrt(np.where(tir, 0.0, g2))
    with np.errstate(divide="ignore", invalid="ignore"):
        f = 0.5 * (g - c) ** 2 / (g + c) ** 2 * (1.0 + (c * (g + c) - 1.0) ** 2 / (c * (g - c) + 1.0) ** 2)
    # c = 0 (grazing) with eta > 1: (g-c)/(g+c) = 1 and the bracket is 2 -> F = 1 (seed 001 "Remarks").
    f = np.where(c == 0, 1.0, f)
    return np.where(tir, 1.0, f)


def dielectric_sp(cos_i: ArrayLike, eta: ArrayLike) -> tuple[F64, F64]:
    """(Rs, Rp) of seed 001's angle form; at normal incidence the 0/0 limit ((eta-1)/(eta+1))^2."""
    c, e = _inside_flip(cos_i, eta)
    a = np.arccos(np.clip(c, 0.0, 1.0))
    sin_b = np.sin(a) / e
    tir = sin_b >= 1.0
    b = np.arcsin(np.clip(sin_b, 0.0, 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        rs = (np.sin(b - a) / np.sin(b + a)) ** 2
        rp = (np.tan(b - a) / np.tan(b + a)) ** 2
    # Near normal incidence both ratios are 0/0; seed 001 "Remarks": R0 = ((n2-n1)/(n2+n1))^2.
    r0 = ((e - 1.0) / (e + 1.0)) ** 2
    small = a < 1e-6
    rs = np.where(small, r0, rs)
    rp = np.where(small, r0, rp)
    # Grazing (a = pi/2): tan(b+a) may be +-inf or the ratio 1; both reflectances are 1.
    graze = np.isclose(a, np.pi / 2, rtol=0, atol=1e-15)
    rs = np.where(graze | tir, 1.0, rs)
    rp = np.where(graze | tir, 1.0, rp)
    return rs, rp


def conductor(cos_i: ArrayLike, eta: ArrayLike, k: ArrayLike) -> F64:
    """Unpolarised conductor reflectance with complex IOR ``eta + i k`` (complex NumPy arithmetic)."""
    c = np.clip(np.asarray(cos_i, dtype=np.float64), 0.0, 1.0)
    et = np.asarray(eta, dtype=np.float64) + 1j * np.asarray(k, dtype=np.float64)
    sin2_i = 1.0 - c * c
    cos_t = np.sqrt(1.0 - sin2_i / (et * et))
    rs = (c - et * cos_t) / (c + et * cos_t)
    rp = (et * c - cos_t) / (et * c + cos_t)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def conductor_ab(cos_i: ArrayLike, eta: ArrayLike, k: ArrayLike) -> F64:
    """Seed 001's real closed form ("Unpolarized light", a^2/b^2 with u = cos i), kept as a second
    reference for :func:`conductor` (the two must agree)."""
    u = np.clip(np.asarray(cos_i, dtype=np.float64), 1e-9, 1.0)  # 1/u is singular at grazing
    n = np.asarray(eta, dtype=np.float64)
    kk = np.asarray(k, dtype=np.float64)
    t = n * n - kk * kk + u * u - 1.0
    root = np.sqrt(t * t + 4.0 * n * n * kk * kk)
    a = np.sqrt(np.maximum(0.5 * (root + t), 0.0))
    b2 = np.maximum(0.5 * (root - t), 0.0)
    first = ((a - u) ** 2 + b2) / ((a + u) ** 2 + b2)
    second = ((a + u - 1.0 / u) ** 2 + b2) / ((a - u + 1.0 / u) ** 2 + b2)
    return 0.5 * first * (second + 1.0)


def schlick(cos_i: ArrayLike, f0: ArrayLike) -> F64:
    """Schlick 1994: ``F0 + (1 - F0)(1 - cos)^5`` (seeds 001, 002), cos clamped to [0, 1]."""
    c = np.clip(np.asarray(cos_i, dtype=np.float64), 0.0, 1.0)
    f0 = np.asarray(f0, dtype=np.float64)
    return f0 + (1.0 - f0) * (1.0 - c) ** 5


def f0_from_ior(eta: ArrayLike) -> F64:
    """Normal-incidence reflectance ``((eta-1)/(eta+1))^2`` (seed 001 "Wavelength")."""
    e = np.asarray(eta, dtype=np.float64)
    return ((e - 1.0) / (e + 1.0)) ** 2


def ior_from_f0(f0: ArrayLike) -> F64:
    """Inverse of :func:`f0_from_ior`: ``(1 + sqrt F0)/(1 - sqrt F0)`` (seed 001 "Wavelength")."""
    s = np.sqrt(np.asarray(f0, dtype=np.float64))
    return (1.0 + s) / (1.0 - s)


def color_shift(f_theta: ArrayLike, f0_ref: ArrayLike, c0: ArrayLike, c90: ArrayLike) -> F64:
    """Cook & Torrance's colour-shift interpolation (seed 004 "Cook-Torrance (15)", seed 001):
    ``c = c0 + (c90 - c0) max(0, F_theta - F0)/(1 - F0)`` with ``F`` the reference-wavelength Fresnel."""
    ft = np.asarray(f_theta, dtype=np.float64)
    f0 = np.asarray(f0_ref, dtype=np.float64)
    w = np.maximum(0.0, ft - f0) / (1.0 - f0)
    return np.asarray(c0) + (np.asarray(c90) - np.asarray(c0)) * w
