"""Microfacet terms: normal distributions D [1/sr], Smith Λ and G1, and shadowing-masking G (dimensionless).

Conventions: ``h`` is the (unit) microfacet normal / half vector, ``n`` the macro-surface normal, ``l`` and
``v`` point away from the surface. Inputs are array-likes of shape ``(N, 3)`` or ``(3,)`` (broadcast), outputs
float32 of shape ``(N,)``. Anisotropic distributions use ``alpha`` along ``tangent`` and ``alpha_y`` along the
bitangent ``n × t``; without a tangent an arbitrary frame around ``n`` is used. A D is normalised:
``∫ D(h)(n·h) dω_h = 1``. Formulas and sources: brdf-core ``microfacet/`` and ``masking.rs`` (Cook &
Torrance 1982; Walter et al. 2007; Heitz 2014).

Distributions (``alpha`` meaning): ``beckmann`` (RMS slope), ``ggx`` (Trowbridge-Reitz roughness),
``gaussian`` (RMS slope angle m, rad), ``blinn_phong`` (exponent ``2/α² − 2``), ``ward`` (RMS slope),
``ashikhmin_shirley`` (``alpha``, ``alpha_y`` are the exponents nu, nv). Masking terms: ``smith``
(height-correlated), ``smith_separable``, ``v_groove`` (Cook-Torrance), ``kelemen``, ``none``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import as_float, as_vectors
from brdfpy._renamed import name_is_keyword

__all__ = ["DISTRIBUTIONS", "MASKINGS", "distribution", "g1", "lambda_", "masking", "mixture"]

F32 = NDArray[np.float32]
#: A lobe of a mixture: ``(weight, name, alpha)`` or ``(weight, name, alpha, alpha_y)``.
Lobe = Union[tuple[float, str, float], tuple[float, str, float, Optional[float]]]

DISTRIBUTIONS: tuple[str, ...]
MASKINGS: tuple[str, ...]
_d, _g = _brdfpy.microfacet_names()
DISTRIBUTIONS, MASKINGS = tuple(_d), tuple(_g)


def _lobe(name: str, alpha: float, alpha_y: float | None) -> list[tuple[float, str, float, float | None]]:
    if not isinstance(name, str):
        raise TypeError(f"distribution: expected a distribution name (str), got {type(name).__name__}")
    ay = None if alpha_y is None else as_float("alpha_y", alpha_y)
    return [(1.0, name, as_float("alpha", alpha), ay)]


def _lobes(lobes: Sequence[Lobe], name: str = "lobes") -> list[tuple[float, str, float, float | None]]:
    """The lobes of a mixture (the argument ``name``, a list of ``(weight, name, alpha[, alpha_y])``)."""
    if isinstance(lobes, (str, bytes)) or not isinstance(lobes, (list, tuple)):
        raise TypeError(
            f"{name}: expected a list of lobes (weight, name, alpha[, alpha_y]), got {type(lobes).__name__}"
        )
    out = []
    for i, lobe in enumerate(lobes):
        where = f"{name}[{i}]"
        if not isinstance(lobe, (tuple, list)) or len(lobe) not in (3, 4):
            raise TypeError(f"{where}: expected (weight, name, alpha[, alpha_y]), got {lobe!r}")
        ay = lobe[3] if len(lobe) == 4 else None
        if not isinstance(lobe[1], str):
            raise TypeError(f"{where}: expected a distribution name, got {type(lobe[1]).__name__}")
        w, a = as_float(f"{where} weight", lobe[0]), as_float(f"{where} alpha", lobe[2])
        out.append((w, lobe[1], a, None if ay is None else as_float(f"{where} alpha_y", ay)))
    return out


def _tangent(tangent: ArrayLike | None) -> F32 | None:
    return None if tangent is None else as_vectors("tangent", tangent)


@name_is_keyword("distribution", "distribution(h, n, 0.3, distribution='ggx')")
def distribution(
    h: ArrayLike,
    n: ArrayLike,
    alpha: float,
    *,
    distribution: str = "ggx",
    alpha_y: float | None = None,
    tangent: ArrayLike | None = None,
) -> F32:
    """Microfacet normal distribution ``D(h)`` [1/sr]; 0 for ``h`` below the surface.

    E.g. GGX ``D = α² / (π ((n·h)²(α² − 1) + 1)²)``, Beckmann ``D = exp(−tan²θ_h/α²)/(π α² cos⁴θ_h)``.

    Parameters
    ----------
    h, n : array_like, shape (..., 3)
        Half vectors and normals (normalised here), broadcast together.
    alpha : float
        Roughness (> 0; see the module docs for its meaning per distribution).
    distribution : str
        One of :data:`DISTRIBUTIONS` (default ``"ggx"``).
    alpha_y : float, optional
        Roughness along the bitangent for anisotropic distributions (default ``alpha``).
    tangent : array_like, shape (..., 3), optional
        Direction of ``alpha``.

    Returns
    -------
    numpy.ndarray of float32, the broadcast shape of the inputs' leading dimensions
    """
    d = _lobe(distribution, alpha, alpha_y)
    return _brdfpy.distribution(d, as_vectors("h", h), as_vectors("n", n), _tangent(tangent))


def mixture(lobes: Sequence[Lobe], h: ArrayLike, n: ArrayLike, *, tangent: ArrayLike | None = None) -> F32:
    """Weighted sum of distributions ``D = Σ wᵢ Dᵢ(h)`` with weights renormalised to ``Σ wᵢ = 1``
    (Cook & Torrance 1982 used two Beckmann lobes), so it stays normalised.

    ``lobes``: up to 4 of ``(weight, name, alpha)`` or ``(weight, name, alpha, alpha_y)``, weights ≥ 0.
    """
    return _brdfpy.distribution(_lobes(lobes), as_vectors("h", h), as_vectors("n", n), _tangent(tangent))


@name_is_keyword("distribution", "lambda_(w, n, 0.3, distribution='ggx')")
def lambda_(
    w: ArrayLike,
    n: ArrayLike,
    alpha: float,
    *,
    distribution: str = "ggx",
    alpha_y: float | None = None,
    tangent: ArrayLike | None = None,
) -> F32:
    """Smith's ``Λ(w)`` of a distribution (Heitz 2014): GGX ``(−1 + √(1 + α² tan²θ))/2``, Beckmann's erf
    form, others through their Beckmann-equivalent roughness. ``+inf`` below the surface."""
    d = _lobe(distribution, alpha, alpha_y)
    return _brdfpy.smith_lambda(d, as_vectors("w", w), as_vectors("n", n), _tangent(tangent), False)


@name_is_keyword("distribution", "g1(w, n, 0.3, distribution='ggx')")
def g1(
    w: ArrayLike,
    n: ArrayLike,
    alpha: float,
    *,
    distribution: str = "ggx",
    alpha_y: float | None = None,
    tangent: ArrayLike | None = None,
) -> F32:
    """Smith masking of one direction, ``G1(w) = 1/(1 + Λ(w))`` in [0, 1]; 0 below the surface."""
    d = _lobe(distribution, alpha, alpha_y)
    return _brdfpy.smith_lambda(d, as_vectors("w", w), as_vectors("n", n), _tangent(tangent), True)


@name_is_keyword("masking", "masking(l, v, n, 0.3, masking='smith', distribution='ggx')")
def masking(
    l: ArrayLike,
    v: ArrayLike,
    n: ArrayLike,
    alpha: float,
    *,
    masking: str = "smith",
    distribution: str = "ggx",
    alpha_y: float | None = None,
    tangent: ArrayLike | None = None,
) -> F32:
    """Shadowing-masking ``G(l, v)`` (dimensionless); 0 when ``l`` or ``v`` is below the surface.

    ``masking`` is one of :data:`MASKINGS`: ``smith`` (default): ``1/(1 + Λ(l) + Λ(v))`` (height-correlated,
    Heitz 2014); ``smith_separable``: ``G1(l) G1(v)`` (Walter et al. 2007); ``v_groove``:
    ``min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h))`` (Torrance-Sparrow, Cook-Torrance); ``kelemen``:
    ``(n·l)(n·v)/(v·h)²`` (Kelemen & Szirmay-Kalos 2001); ``none``: 1. ``distribution``, ``alpha`` (and
    ``alpha_y``, ``tangent``) give Λ for the Smith terms.
    """
    if not isinstance(masking, str):
        raise TypeError(f"masking: expected a masking name (str), got {type(masking).__name__}")
    d = _lobe(distribution, alpha, alpha_y)
    la, va, na = as_vectors("l", l), as_vectors("v", v), as_vectors("n", n)
    return _brdfpy.masking(masking, d, la, va, na, _tangent(tangent))
