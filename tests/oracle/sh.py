"""Real spherical harmonics, written independently of brdfpy: associated Legendre functions as derivatives of
the Legendre polynomial (``P_l^m(x) = (1 - x²)^{m/2} dᵐ/dxᵐ P_l(x)``, no Condon–Shortley phase) with the
factorial normalisation ``K_lm = sqrt((2l+1)/(4π) (l-m)!/(l+m)!)`` — not the recurrence brdfpy uses.

Convention as Ramamoorthi & Hanrahan (2001): ``Y_l0 = K P_l^0``, ``Y_lm = √2 K P_l^m cos mφ``,
``Y_l,-m = √2 K P_l^m sin mφ``; index ``l(l+1) + m``. Good to order ~20 in float64.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial import legendre
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]


def basis(directions: ArrayLike, order: int) -> F64:
    """(N, (order+1)²) values of every ``Y_lm`` at unit-normalised (N, 3) directions."""
    d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    x = d[:, 2]
    phi = np.arctan2(d[:, 1], d[:, 0])
    s = np.sqrt(np.maximum(0.0, 1.0 - x * x))
    out = np.zeros((d.shape[0], (order + 1) ** 2))
    for l in range(order + 1):
        pl = legendre.Legendre.basis(l)
        for m in range(l + 1):
            p = s**m * pl.deriv(m)(x) if m > 0 else pl(x)
            k = math.sqrt((2 * l + 1) / (4 * math.pi) * math.factorial(l - m) / math.factorial(l + m))
            if m == 0:
                out[:, l * (l + 1)] = k * p
            else:
                out[:, l * (l + 1) + m] = math.sqrt(2) * k * p * np.cos(m * phi)
                out[:, l * (l + 1) - m] = math.sqrt(2) * k * p * np.sin(m * phi)
    return out


def clamped_cosine_zonal(l: int) -> float:
    """``Â_l`` of ``max(cos θ, 0)`` by exact polynomial integration: ``2π ∫_0^1 μ P_l(μ) dμ`` (the projection
    onto ``Y_l0`` times ``sqrt(4π/(2l+1))``), with the antiderivative of the Legendre series."""
    poly = legendre.Legendre.basis(l) * legendre.Legendre([0.0, 1.0])  # μ·P_l(μ)
    anti = poly.integ()
    return float(2.0 * math.pi * (anti(1.0) - anti(0.0)))
