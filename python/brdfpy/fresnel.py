"""Fresnel reflectance: the fraction of light power a smooth interface reflects (dimensionless, in [0, 1]).

``cos_i`` is the cosine between the incident direction and the (micro)surface normal — in a microfacet BRDF
``v·h = l·h`` — as an array of any shape; the result is float32 of the same shape, with a trailing axis of 3
when a parameter is an RGB triple. Indices of refraction ``eta`` are relative: ``η_t / η_i`` (inside over
outside, e.g. 1.5 for air → glass). Sources: the Fresnel equations (Born & Wolf, *Principles of Optics*,
§1.5), Cook & Torrance 1982, Schlick 1994, and pbrt-v4 (Pharr, Jakob & Humphreys 2023, §9.3) for the
conductor and the conventions; brdf-core ``fresnel.rs`` says which form is used where texts differ (e.g. the
exact dielectric denominator ``[c(g − c) + 1]²``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from brdfpy import _brdfpy
from brdfpy._arrays import _as_numeric, _to_f32, as_float, as_scalars, as_vectors

__all__ = [
    "METALS",
    "color_shift",
    "conductor",
    "dielectric",
    "dielectric_sp",
    "f0_from_ior",
    "ior_from_f0",
    "metal_f0",
    "schlick",
    "split",
]

F32 = NDArray[np.float32]
#: A number (gray) or three numbers (linear RGB).
Channels = Union[float, Sequence[float], NDArray[np.floating]]

#: Symbols of the metals in the F0 table (N. Hoffman, "Physics and Math of Shading", SIGGRAPH 2010
#: course); ``metal_f0`` also takes English names, e.g. "gold".
METALS: tuple[str, ...] = tuple(_brdfpy.metal_names())


def _channels(name: str, x: Channels) -> list[float]:
    """One number or three, as floats (ranges are checked by the compiled module; a float64 value beyond
    the float32 range is refused here, naming ``name``, rather than arriving as ``inf``)."""
    if x is None or isinstance(x, (str, bytes)):
        raise TypeError(f"{name}: expected a number or 3 numbers, got {type(x).__name__}")
    a = _as_numeric(name, x)
    if a.shape not in ((), (1,), (3,)):
        raise ValueError(f"{name}: expected a number or 3 numbers (RGB), got shape {a.shape}")
    return [float(v) for v in _to_f32(name, a).reshape(-1)]


def _cos(cos_i: ArrayLike) -> F32:
    return as_scalars("cos_i", cos_i)


def dielectric(cos_i: ArrayLike, eta: Channels) -> F32:
    """Exact unpolarised Fresnel reflectance of a dielectric, ``R = (R_s + R_p)/2`` (Born & Wolf §1.5).

    ``R_s = ((c − η cos_t)/(c + η cos_t))²``, ``R_p = ((η c − cos_t)/(η c + cos_t))²`` with Snell's
    ``sin θ_t = sin θ_i / η``. ``cos_i < 0`` means the light arrives from inside (η → 1/η); total internal
    reflection gives 1, normal incidence ``((η − 1)/(η + 1))²``, grazing incidence 1.

    Parameters
    ----------
    cos_i : array_like, any shape
        Cosine of the angle of incidence, in [-1, 1].
    eta : float or 3 floats
        Relative index ``η_t / η_i`` (> 0); three values give an RGB result of shape ``cos_i.shape + (3,)``.
    """
    return _brdfpy.dielectric(_cos(cos_i), _channels("eta", eta))


def dielectric_sp(cos_i: ArrayLike, eta: float) -> tuple[F32, F32]:
    """The s- and p-polarised reflectances ``(R_s, R_p)`` of :func:`dielectric`.

    ``R_p = 0`` at Brewster's angle, ``tan θ_B = η``.
    """
    e = _channels("eta", eta)
    if len(e) != 1:
        raise ValueError("eta: expected one number")
    return _brdfpy.dielectric_sp(_cos(cos_i), e[0])


def conductor(cos_i: ArrayLike, eta: Channels, k: Channels) -> F32:
    """Exact Fresnel reflectance of a conductor with complex index ``η − iκ`` (pbrt-v4 §9.3.6).

    Unpolarised ``(|r_s|² + |r_p|²)/2`` in the closed form of pbrt / Mitsuba (K. D. Möller, *Optics*);
    ``κ = 0`` gives :func:`dielectric`. ``eta`` > 0 and ``k`` ≥ 0 are numbers or RGB triples; an RGB one
    makes the result ``cos_i.shape + (3,)``.
    """
    return _brdfpy.conductor(_cos(cos_i), _channels("eta", eta), _channels("k", k))


def schlick(cos_i: ArrayLike, f0: Channels) -> F32:
    """Schlick's approximation ``F = F0 + (1 − F0)(1 − |cos_i|)^5`` (Schlick 1994).

    ``f0`` in [0, 1] is the reflectance at normal incidence (gray or RGB). Valid from the optically thinner
    side: it has no η and no total internal reflection.
    """
    return _brdfpy.schlick(_cos(cos_i), _channels("f0", f0))


def color_shift(cos_i: ArrayLike, f0: Channels, f0_ref: float | None = None) -> F32:
    """Cook & Torrance's colour-shift Fresnel (1982), per RGB channel.

    The exact dielectric curve ``F_ref`` of the index ``η_ref = (1 + √F0_ref)/(1 − √F0_ref)`` is computed
    once, and every channel follows it from its own F0 to 1:
    ``F_λ = F0_λ + (1 − F0_λ) · max(0, F_ref − F0_ref)/(1 − F0_ref)``. ``f0_ref`` defaults to the mean of
    ``f0``. Returns ``cos_i.shape + (3,)``.
    """
    ref = None if f0_ref is None else as_float("f0_ref", f0_ref)
    return _brdfpy.color_shift(_cos(cos_i), _channels("f0", f0), ref)


def _scalar_or_array(x: F32, given: ArrayLike) -> float | F32:
    return float(x) if np.ndim(given) == 0 else x


def f0_from_ior(eta: ArrayLike) -> float | F32:
    """Reflectance at normal incidence of a dielectric, ``F0 = ((η − 1)/(η + 1))²``; 0.04 for 1.5.

    A number gives a float, an array an array of its shape. ``eta`` must be finite and > 0.
    """
    return _scalar_or_array(_brdfpy.f0_from_ior(as_scalars("eta", eta)), eta)


def ior_from_f0(f0: ArrayLike) -> float | F32:
    """The index ``η = (1 + √F0)/(1 − √F0)`` ≥ 1 of normal-incidence reflectance ``f0`` ∈ [0, 1).

    A number gives a float, an array an array of its shape.
    """
    return _scalar_or_array(_brdfpy.ior_from_f0(as_scalars("f0", f0)), f0)


def metal_f0(name: str) -> F32:
    """Linear-RGB reflectance at normal incidence of a metal from Hoffman's table (SIGGRAPH 2010), shape (3,).

    ``name`` is a symbol from :data:`METALS` or an English name (``"au"`` or ``"gold"``), any case. Values are
    the table's verbatim: gold's red channel is 1.022, outside [0, 1] because the measured spectrum was
    projected into linear sRGB.
    """
    if not isinstance(name, str):
        raise TypeError(f"name: expected a metal name (str), got {type(name).__name__}")
    return np.asarray(_brdfpy.metal_f0(name), dtype=np.float32)


def split(w: ArrayLike, n: ArrayLike, eta: float) -> tuple[F32, F32, F32, F32]:
    """What happens to light meeting a smooth dielectric interface (Snell's law and the Fresnel equations).

    Parameters
    ----------
    w : array_like, shape (..., 3)
        Direction toward where the light comes from (away from the surface; normalised here).
    n : array_like, shape (..., 3)
        Normal on the outside (normalised here), broadcast against ``w``. ``w`` on the inside flips it and
        inverts ``eta``.
    eta : float
        ``η_inside / η_outside`` (> 0), e.g. 1.5 for glass in air.

    Returns
    -------
    r : float32, shape (broadcast) + (3,)
        Mirror direction ``2(n·w)n − w``.
    t : float32, shape (broadcast) + (3,)
        Refracted direction by Snell's law, pointing away on the other side; 0 on total internal reflection.
    R, T : float32, shape (broadcast)
        Reflected power fraction (exact unpolarised Fresnel) and transmitted ``T = 1 − R`` (0 on TIR). The
        transmitted *radiance* is further scaled by ``(η_t/η_i)²``.
    """
    e = _channels("eta", eta)
    if len(e) != 1:
        raise ValueError("eta: expected one number")
    return _brdfpy.split(as_vectors("w", w), as_vectors("n", n), e[0])
