"""Microfacet distributions D [1/sr] and masking-shadowing terms G [1], float64.

Every D is written on the local half vector ``(hx, hy, hz)`` (z = normal, x = tangent) and is normalised
so that the projected microfacet area is one, ``int D(h) (n.h) dw_h = 1`` (notes section b1). The
isotropic forms are written with ``tan^2 theta_h`` and explicit azimuths (``arctan2``), as in the papers.

Sources: seed 001 ("Microfacet theory": Gaussian, Beckmann, Blinn-Phong, Trowbridge-Reitz/GGX, Ward,
Ashikhmin-Shirley, mixtures; "G alternative (GGX)"; "Cheap G (Kelemen-Szirmay-Kalos)"),
seed 002 / 004 ("Geometric Attenuation", Torrance-Sparrow V-groove), Walter et al. 2007 ("Microfacet
Models for Refraction", eqs. 27-34), Heitz 2014 ("Understanding the Masking-Shadowing Function", JCGT 3(2),
height-correlated Smith eq. 99), Ashikhmin & Shirley 2000.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]

_erf = np.vectorize(math.erf, otypes=[np.float64])


def _trig(hx: F64, hy: F64, hz: F64) -> tuple[F64, F64, F64]:
    """tan^2 theta, cos^2 phi, sin^2 phi of a local direction (phi from the tangent, by arctan2)."""
    hz = np.asarray(hz, dtype=np.float64)
    sin2 = np.maximum(0.0, np.asarray(hx) ** 2 + np.asarray(hy) ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        tan2 = sin2 / (hz * hz)
    phi = np.arctan2(hy, hx)
    return tan2, np.cos(phi) ** 2, np.sin(phi) ** 2


def beckmann(hx: F64, hy: F64, hz: F64, ax: float, ay: float | None = None) -> F64:
    """Beckmann-Spizzichino, ``exp(-tan^2 th (cos^2 ph/ax^2 + sin^2 ph/ay^2)) / (pi ax ay cos^4 th)``
    (seed 001 "Beckmann's distribution"; notes b1; seed 002 prints 1/(4 m^2 ..) which needs a pi
    denominator in the BRDF and seed 004 omits the pi: both are the un-normalised form)."""
    ay = ax if ay is None else ay
    tan2, c2, s2 = _trig(hx, hy, hz)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        d = np.exp(-tan2 * (c2 / ax**2 + s2 / ay**2)) / (np.pi * ax * ay * np.asarray(hz) ** 4)
    return np.where(np.asarray(hz) > 0, np.nan_to_num(d, nan=0.0, posinf=0.0), 0.0)


def ggx(hx: F64, hy: F64, hz: F64, ax: float, ay: float | None = None) -> F64:
    """Trowbridge-Reitz / GGX, seed 001 ("GGX (Walter et al. 2007)") ``m^2/(pi cos^4 (m^2 + tan^2)^2)``,
    anisotropic as ``1/(pi ax ay cos^4 (1 + tan^2 (cos^2 ph/ax^2 + sin^2 ph/ay^2))^2)``."""
    ay = ax if ay is None else ay
    tan2, c2, s2 = _trig(hx, hy, hz)
    hz = np.asarray(hz)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        e = tan2 * (c2 / ax**2 + s2 / ay**2)
        d = 1.0 / (np.pi * ax * ay * hz**4 * (1.0 + e) ** 2)
    return np.where(hz > 0, np.nan_to_num(d, nan=0.0, posinf=0.0), 0.0)


@lru_cache(maxsize=256)
def gaussian_norm(m: float) -> float:
    """The constant ``c`` of seed 004's ``D = c exp(-(theta/m)^2)`` that makes ``int D cos dw = 1``:
    ``1 / (2 pi int_0^{pi/2} exp(-(t/m)^2) cos t sin t dt)`` by composite Gauss-Legendre quadrature,
    16 panels of 32 points (the integrand is smooth; the result is exact to ~1e-15 for m >= 0.01)."""
    x, w = np.polynomial.legendre.leggauss(32)
    # Integrate over [0, min(pi/2, 12 m)]: beyond 12 m the integrand is below e^-144.
    top = min(np.pi / 2, 12.0 * m)
    panels = 16
    left = np.arange(panels)[:, None] * top / panels
    t = (left + 0.5 * (x + 1.0) * top / panels).reshape(-1)
    wt = np.tile(0.5 * w * top / panels, panels)
    val = np.sum(wt * np.exp(-((t / m) ** 2)) * np.cos(t) * np.sin(t))
    return 1.0 / (2.0 * np.pi * val)


def gaussian(hz: F64, m: float) -> F64:
    """Gaussian in the half-angle (seed 004 "Cook-Torrance (7)"; seed 001): ``c exp(-(theta_h/m)^2)``,
    theta_h = arccos(n.h), ``c`` from :func:`gaussian_norm`."""
    hz = np.asarray(hz, dtype=np.float64)
    th = np.arccos(np.clip(hz, -1.0, 1.0))
    return np.where(hz > 0, gaussian_norm(float(m)) * np.exp(-((th / m) ** 2)), 0.0)


def blinn_phong(hz: F64, exponent: float) -> F64:
    """Normalised Blinn-Phong D ``(e+2)/(2 pi) (n.h)^e`` (seed 001 "Blinn-Phong (normalised)")."""
    hz = np.asarray(hz, dtype=np.float64)
    return np.where(hz > 0, (exponent + 2.0) / (2.0 * np.pi) * np.maximum(hz, 0.0) ** exponent, 0.0)


def blinn_phong_exponent(alpha: float) -> float:
    """Walter et al. 2007 (section 5.2) exponent matching a Beckmann roughness: ``e = 2/alpha^2 - 2``."""
    return 2.0 / alpha**2 - 2.0


def ward(hx: F64, hy: F64, hz: F64, ax: float, ay: float | None = None) -> F64:
    """Ward 1992's microfacet distribution (seed 001 "Anisotropic Ward"), which once normalised over
    projected area is the anisotropic Beckmann distribution: the seed's ``1/(pi mx my)`` lacks the
    ``1/cos^3`` a slope distribution needs (Ward 1992 eq. 5; Walter 2005 "Notes on the Ward BRDF")."""
    return beckmann(hx, hy, hz, ax, ay)


def ashikhmin_shirley(hx: F64, hy: F64, hz: F64, nu: float, nv: float | None = None) -> F64:
    """Ashikhmin & Shirley 2000 (seed 001): ``sqrt((nu+1)(nv+1))/(2 pi) (n.h)^(nu cos^2 ph + nv sin^2 ph)``.

    Note: this is the paper's half-vector density, normalised as ``int D dw = 1`` *without* the
    projection cosine; the projected-area normalisation needs ``sqrt((nu+2)(nv+2))`` instead (exact when
    nu = nv). :func:`ashikhmin_shirley_projected` gives that form.
    """
    nv = nu if nv is None else nv
    _, c2, s2 = _trig(hx, hy, hz)
    hz = np.asarray(hz, dtype=np.float64)
    e = nu * c2 + nv * s2
    return np.where(hz > 0, np.sqrt((nu + 1.0) * (nv + 1.0)) / (2 * np.pi) * np.maximum(hz, 0.0) ** e, 0.0)


def ashikhmin_shirley_projected(hx: F64, hy: F64, hz: F64, nu: float, nv: float | None = None) -> F64:
    """Ashikhmin-Shirley lobe normalised over projected area: ``sqrt((nu+2)(nv+2))/(2 pi) (n.h)^e``."""
    nv = nu if nv is None else nv
    _, c2, s2 = _trig(hx, hy, hz)
    hz = np.asarray(hz, dtype=np.float64)
    e = nu * c2 + nv * s2
    return np.where(hz > 0, np.sqrt((nu + 2.0) * (nv + 2.0)) / (2 * np.pi) * np.maximum(hz, 0.0) ** e, 0.0)


# ----------------------------------------------------------------------------------------- masking


def lambda_ggx(wx: F64, wy: F64, wz: F64, ax: float, ay: float | None = None) -> F64:
    """Smith Lambda for GGX, ``(-1 + sqrt(1 + alpha(phi)^2 tan^2 theta))/2``,
    ``alpha(phi)^2 = cos^2 phi ax^2 + sin^2 phi ay^2`` (Walter 2007 eq. 34 via G1; Heitz 2014 eq. 86)."""
    ay = ax if ay is None else ay
    tan2, c2, s2 = _trig(wx, wy, wz)
    a2 = c2 * ax**2 + s2 * ay**2
    with np.errstate(invalid="ignore", over="ignore"):
        lam = 0.5 * (-1.0 + np.sqrt(1.0 + a2 * tan2))
    return np.where(np.isfinite(lam), lam, np.inf)


def lambda_beckmann(wx: F64, wy: F64, wz: F64, ax: float, ay: float | None = None) -> F64:
    """Exact Smith Lambda for Beckmann, ``(erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi))``, ``a = 1/(alpha tan)``
    (Walter 2007 eq. 25 written as Lambda; Heitz 2014 eq. 80). No rational approximation."""
    ay = ax if ay is None else ay
    tan2, c2, s2 = _trig(wx, wy, wz)
    alpha = np.sqrt(c2 * ax**2 + s2 * ay**2)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / (alpha * np.sqrt(tan2))
        erf_a = _erf(np.where(np.isfinite(a), a, 0.0))
        lam = 0.5 * (erf_a - 1.0) + np.exp(-(a**2)) / (2.0 * a * np.sqrt(np.pi))
    lam = np.where(np.isinf(a) | (a > 30), 0.0, lam)  # theta = 0 (a = inf): no masking
    return np.where(np.asarray(wz) > 0, lam, np.inf)


def g1_ggx_seed(tan_theta: F64, m: float) -> F64:
    """Seed 001 "G alternative (GGX)": ``2 / (1 + sqrt(1 + m^2 tan^2 theta))`` (= 1/(1 + Lambda))."""
    return 2.0 / (1.0 + np.sqrt(1.0 + m * m * np.asarray(tan_theta) ** 2))


def smith_correlated(lam_l: F64, lam_v: F64) -> F64:
    """Height-correlated Smith ``1/(1 + Lambda(l) + Lambda(v))`` (Heitz 2014 eq. 99; notes b5)."""
    return 1.0 / (1.0 + lam_l + lam_v)


def smith_separable(lam_l: F64, lam_v: F64) -> F64:
    """Separable Smith ``G1(l) G1(v) = 1/((1 + Lambda(l))(1 + Lambda(v)))`` (Walter 2007 eq. 23)."""
    return 1.0 / ((1.0 + lam_l) * (1.0 + lam_v))


def v_groove(nl: F64, nv: F64, nh: F64, vh: F64) -> F64:
    """Torrance-Sparrow / Cook-Torrance V-groove (seed 002 "Geometric Attenuation"; seed 004 (10)):
    ``min(1, 2 (n.h)(n.v)/(v.h), 2 (n.h)(n.l)/(v.h))``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.minimum(1.0, np.minimum(2 * nh * nv / vh, 2 * nh * nl / vh))
    return np.where(vh > 0, g, 0.0)


def kelemen(nl: F64, nv: F64, lh: F64) -> F64:
    """Kelemen & Szirmay-Kalos 2001 (seed 001 "Cheap G"): ``G/((n.l)(n.v)) = 1/(l.h)^2``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(lh > 0, nl * nv / lh**2, 0.0)


def local(w: F64, t: F64, b: F64, n: F64) -> tuple[F64, F64, F64]:
    """Local coordinates (w.t, w.b, w.n) of world vectors (all (N, 3))."""
    return (
        np.einsum("ij,ij->i", w, t),
        np.einsum("ij,ij->i", w, b),
        np.einsum("ij,ij->i", w, n),
    )
