"""Every registry model of COMMON.md / SPEC.md as plain float64 NumPy, plus ``evaluate``.

Conventions (SPEC.md): ``l``, ``v`` point away from the surface, ``n`` is the normal;
``eval`` = ``f_r`` [1/sr]; ``shade`` = ``f_r max(n.l, 0)`` for physical models and the course formula
itself for the classic models of seeds 000/004, whose ``f_r`` is then ``shade/(n.l)`` (0 where n.l <= 0).
Physical models are 0 unless ``n.l > 0`` and ``n.v > 0``. Zero-length or non-finite vectors give 0.

Each model function takes a :class:`Geo` and the model's parameters and returns an (N, 3) array:
``f_r`` for physical models, the course formula (``shade``) for classic models.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from oracle import fresnel as fr
from oracle import microfacet as mf
from oracle.vectors import dot, frame, halfway, normalize, reflect

F64 = NDArray[np.float64]
PI = np.pi


@dataclass
class Geo:
    """Unit vectors (N, 3), the tangent frame, the cosines and a validity mask."""

    l: F64
    v: F64
    n: F64
    t: F64
    b: F64
    nl: F64
    nv: F64
    valid: NDArray[np.bool_]

    @property
    def h(self) -> F64:
        return halfway(self.l, self.v)

    def loc(self, w: F64) -> tuple[F64, F64, F64]:
        return mf.local(w, self.t, self.b, self.n)


def geometry(l: ArrayLike, v: ArrayLike, n: ArrayLike, tangent: ArrayLike | None = None) -> Geo:
    """Normalise and broadcast the inputs; ``valid`` is False where l, v or n is degenerate."""
    l, okl = normalize(l)
    v, okv = normalize(v)
    n, okn = normalize(n)
    shape = np.broadcast_shapes(l.shape, v.shape, n.shape)
    l, v, n = (np.broadcast_to(a, shape).copy() for a in (l, v, n))
    valid = np.broadcast_to(okl & okv & okn, shape[:1]).copy()
    tg = None
    if tangent is not None:
        tg, okt = normalize(tangent)
        tg = np.where(okt[..., None], np.broadcast_to(tg, shape), np.nan)
    t, b = frame(np.where(valid[..., None], n, [0.0, 0.0, 1.0]), tg if tg is None else np.nan_to_num(tg))
    if tg is not None:
        # rows whose tangent hint was degenerate fall back to the normal-only frame
        t0, b0 = frame(np.where(valid[..., None], n, [0.0, 0.0, 1.0]), None)
        bad = ~np.isfinite(tg).all(axis=-1)
        t = np.where(bad[..., None], t0, t)
        b = np.where(bad[..., None], b0, b)
    return Geo(l, v, n, t, b, dot(n, l), dot(n, v), valid)


def color(x: Any) -> F64:
    """A colour parameter: one number (gray) or three."""
    a = np.asarray(x, dtype=np.float64).reshape(-1)
    return np.repeat(a, 3) if a.size == 1 else a.reshape(3)


def _rgb(scalar: F64, c: Any) -> F64:
    """(N,) x colour -> (N, 3)."""
    return np.asarray(scalar, dtype=np.float64)[..., None] * color(c)


# ------------------------------------------------------------------------------ diffuse models


def lambert(g: Geo, albedo: Any) -> F64:
    """``rho/pi`` (seed 004 eq. 12.18: f_d = 1/pi for a white Lambertian surface)."""
    return np.broadcast_to(color(albedo) / PI, (len(g.nl), 3)).copy()


def lambert_classic(g: Geo, color_: Any) -> F64:
    """Seed 000: ``C max(n.l, 0)`` (a course formula: this is the shade)."""
    return _rgb(np.maximum(g.nl, 0.0), color_)


def _azimuth_cos(g: Geo) -> F64:
    """cos(phi_r - phi_i) with each azimuth taken explicitly by arctan2 in the tangent frame."""
    lx, ly, _ = g.loc(g.l)
    vx, vy, _ = g.loc(g.v)
    return np.cos(np.arctan2(vy, vx) - np.arctan2(ly, lx))


def _angles(g: Geo) -> tuple[F64, F64]:
    th_i = np.arccos(np.clip(g.nl, -1.0, 1.0))
    th_r = np.arccos(np.clip(g.nv, -1.0, 1.0))
    return np.maximum(th_i, th_r), np.minimum(th_i, th_r)


def oren_nayar(g: Geo, albedo: Any, sigma: float, variant: str = "qualitative") -> F64:
    """Qualitative Oren-Nayar (seed 000; seed 001 "Oren-Nayar model"; Oren & Nayar 1994 eq. 30):
    ``rho/pi (A + B max(0, cos(phi_r - phi_i)) sin(alpha) tan(beta))``, ``A = 1 - 0.5 s^2/(s^2 + c)``,
    ``c = 0.33`` ("qualitative") or ``0.57`` ("compensated", seed 001: "value in denominator up to 0.57";
    notes b4), ``B = 0.45 s^2/(s^2 + 0.09)``; angles by arccos, azimuths by arctan2."""
    s2 = sigma * sigma
    c = {"qualitative": 0.33, "compensated": 0.57}[variant]
    a = 1.0 - 0.5 * s2 / (s2 + c)
    bb = 0.45 * s2 / (s2 + 0.09)
    alpha, beta = _angles(g)
    term = a + bb * np.maximum(0.0, _azimuth_cos(g)) * np.sin(alpha) * np.tan(beta)
    return _rgb(term / PI, albedo)


def oren_nayar_full(g: Geo, albedo: Any, sigma: float, interreflection: bool = True) -> F64:
    """Full Oren-Nayar (Oren & Nayar 1994 eqs. 27-29, 39; seed 004 "Oren-Nayar (7)"; notes b4).

    ``f = L1 + L2`` with
    ``L1 = rho/pi [C1 + cos(dphi) C2 tan(beta) + (1 - |cos dphi|) C3 tan((alpha+beta)/2)]``
    and ``L2 = 0.17 rho^2/pi s^2/(s^2 + 0.13) [1 - cos(dphi) (2 beta/pi)^2]``.
    Seed 004 prints ``C1 = 1 - 0.5 s^2/(s^2 + 0.3)`` and ``rho`` (not ``rho^2``) in L2: both are slips,
    the paper has 0.33 and rho^2 (the interreflected light is reflected twice).
    """
    s2 = sigma * sigma
    alpha, beta = _angles(g)
    cd = _azimuth_cos(g)
    c1 = 1.0 - 0.5 * s2 / (s2 + 0.33)
    c2_base = 0.45 * s2 / (s2 + 0.09)
    c2 = np.where(cd >= 0, c2_base * np.sin(alpha), c2_base * (np.sin(alpha) - (2.0 * beta / PI) ** 3))
    c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * alpha * beta / PI**2) ** 2
    l1 = c1 + cd * c2 * np.tan(beta) + (1.0 - np.abs(cd)) * c3 * np.tan(0.5 * (alpha + beta))
    rho = color(albedo)
    out = _rgb(l1 / PI, rho)
    if interreflection:
        l2 = 0.17 / PI * s2 / (s2 + 0.13) * (1.0 - cd * (2.0 * beta / PI) ** 2)
        out = out + _rgb(l2, rho * rho)
    return out


def toon(
    g: Geo,
    diffuse_color: Any,
    diffuse_mid_color: Any,
    diffuse_threshold: float,
    dark_threshold: float,
    dark_scale: float,
    specular_color: Any,
    specular_threshold: float,
    specular_mode: str = "phong",
    specular_gate: bool = True,
) -> F64:
    """Seed 000 toon shading, exactly its GLSL (a course formula: this is the shade).

    Diffuse: ``n.l < dark_threshold -> dark_scale * C``; ``n.l < diffuse_threshold -> C_mid``; else ``C``.
    Specular: ``s < specular_threshold -> 0`` else ``C_s``, with ``s = v.r`` ("phong", seed 000
    ``Toon_Specular_BRDF``) or ``s = n.h`` ("blinn", Blinn's half vector with gamma = 1, seed 000).
    ``specular_gate`` drops the highlight where ``n.l <= 0`` (seed 000's GLSL does not gate).
    """
    nl = g.nl
    c = color(diffuse_color)
    diff = np.where(
        (nl < dark_threshold)[..., None],
        dark_scale * c,
        np.where((nl < diffuse_threshold)[..., None], color(diffuse_mid_color), c),
    )
    s = dot(g.v, reflect(g.l, g.n)) if specular_mode == "phong" else dot(g.n, g.h)
    spec = np.where((s < specular_threshold)[..., None], 0.0, color(specular_color))
    if specular_gate:
        spec = np.where((nl > 0)[..., None], spec, 0.0)
    return diff + spec


def phong_classic(g: Geo, kd: Any, ks: Any, shininess: float, specular_gate: bool = True) -> F64:
    """Seed 004 eq. 12.23 / seed 000: ``kd max(n.l, 0) + ks clamp(v.r, 0, 1)^gamma`` (course formula).
    ``specular_gate`` drops the specular where ``n.l <= 0`` (the light is behind the surface)."""
    rv = np.clip(dot(g.v, reflect(g.l, g.n)), 0.0, 1.0)
    spec = rv**shininess
    if specular_gate:
        spec = np.where(g.nl > 0, spec, 0.0)
    return _rgb(np.maximum(g.nl, 0.0), kd) + _rgb(spec, ks)


def blinn_phong_classic(g: Geo, kd: Any, ks: Any, shininess: float) -> F64:
    """SCENE.md: ``kd max(n.l,0) + (ks max(n.h,0)^s if n.l > 0 else 0)`` (seed 004 eq. 12.25)."""
    nh = np.maximum(dot(g.n, g.h), 0.0)
    spec = np.where(g.nl > 0, nh**shininess, 0.0)
    return _rgb(np.maximum(g.nl, 0.0), kd) + _rgb(spec, ks)


# ----------------------------------------------------------------------------- physical lobes


def phong(g: Geo, kd: Any, ks: Any, shininess: float) -> F64:
    """Energy-normalised modified Phong (Lewis 1994; seed 002 "Normalization"; notes b6):
    ``kd/pi + ks (gamma+2)/(2 pi) max(r.v, 0)^gamma``."""
    rv = np.maximum(dot(reflect(g.l, g.n), g.v), 0.0)
    return _rgb(np.full_like(g.nl, 1.0 / PI), kd) + _rgb((shininess + 2) / (2 * PI) * rv**shininess, ks)


def blinn_phong_norm(m: float, normalization: str) -> float:
    """``(m+8)/(8 pi)`` (seed 002, Real-Time Rendering) or Giesen 2009's exact
    ``(m+2)(m+4) / (8 pi (2^(-m/2) + m))`` (notes b6)."""
    if normalization == "rtr":
        return (m + 8.0) / (8.0 * PI)
    return (m + 2.0) * (m + 4.0) / (8.0 * PI * (2.0 ** (-m / 2.0) + m))


def blinn_phong(g: Geo, kd: Any, ks: Any, shininess: float, normalization: str = "exact") -> F64:
    """Seed 002 "Blinn-Phong Model": ``kd/pi + ks N(m) (n.h)^m``."""
    nh = np.maximum(dot(g.n, g.h), 0.0)
    spec = blinn_phong_norm(shininess, normalization) * nh**shininess
    return _rgb(np.full_like(g.nl, 1.0 / PI), kd) + _rgb(spec, ks)


def distribution(name: str, hx: F64, hy: F64, hz: F64, alpha: float, alpha_y: float | None = None) -> F64:
    """D by name, roughness ``alpha`` (Blinn-Phong: exponent 2/alpha^2 - 2; Ashikhmin-Shirley: alpha is
    the exponent)."""
    if name == "beckmann":
        return mf.beckmann(hx, hy, hz, alpha, alpha_y)
    if name == "ggx":
        return mf.ggx(hx, hy, hz, alpha, alpha_y)
    if name == "gaussian":
        return mf.gaussian(hz, alpha)
    if name == "blinn_phong":
        return mf.blinn_phong(hz, mf.blinn_phong_exponent(alpha))
    if name == "ward":
        return mf.ward(hx, hy, hz, alpha, alpha_y)
    if name == "ashikhmin_shirley":
        # as a microfacet D it must project to unit area: sqrt((nu+2)(nv+2))/(2 pi), not the paper's
        # half-vector pdf constant sqrt((nu+1)(nv+1))/(2 pi)
        return mf.ashikhmin_shirley_projected(hx, hy, hz, alpha, alpha_y)
    raise ValueError(f"unknown distribution {name!r}")


def smith_lambda(dist: str, wx: F64, wy: F64, wz: F64, alpha: float) -> F64:
    """Smith Lambda matched to the distribution: GGX's closed form for "ggx", Beckmann's (erf) for
    the Beckmann-like lobes (Walter 2007 section 5.2 pairs Blinn-Phong with Beckmann's G)."""
    if dist == "ggx":
        return mf.lambda_ggx(wx, wy, wz, alpha)
    return mf.lambda_beckmann(wx, wy, wz, alpha)


def masking(name: str, g: Geo, alpha: float, dist: str = "ggx") -> F64:
    """G by name for the geometry ``g`` (see :mod:`oracle.microfacet`)."""
    h = g.h
    nh, vh, lh = dot(g.n, h), dot(g.v, h), dot(g.l, h)
    if name == "v_groove":
        return mf.v_groove(g.nl, g.nv, nh, vh)
    if name == "kelemen":
        return mf.kelemen(g.nl, g.nv, lh)
    if name == "none":
        return np.ones_like(g.nl)
    lam_l = smith_lambda(dist, *g.loc(g.l), alpha)
    lam_v = smith_lambda(dist, *g.loc(g.v), alpha)
    if name == "smith":
        return mf.smith_correlated(lam_l, lam_v)
    if name == "smith_separable":
        return mf.smith_separable(lam_l, lam_v)
    raise ValueError(f"unknown masking {name!r}")


def cook_torrance(
    g: Geo,
    kd: Any = 0.0,
    ks: Any = 1.0,
    distribution: str = "ggx",
    roughness: float = 0.3,
    masking: str = "smith",
    fresnel: str = "schlick",
    f0: Any = 0.04,
    ior: float = 1.5,
    eta: Any = 1.5,
    k: Any = 0.0,
    metal: str = "none",
    roughness2: float = 0.3,
    weight2: float = 0.0,
    **_: Any,
) -> F64:
    """``kd/pi + ks D G F / (4 (n.l)(n.v))`` (seed 002 "Cook-Torrance Model"; notes b2: the 4 goes
    with a normalised D; seed 004's ``1/pi`` goes with its un-normalised Beckmann). F at ``c = v.h``.
    D may be a two-lobe mixture ``(1-w) D(alpha) + w D(alpha2)`` (seed 001 "mixtures")."""
    h = g.h
    hx, hy, hz = g.loc(h)
    d = globals()["distribution"](distribution, hx, hy, hz, roughness)
    if weight2 > 0:
        d = (1 - weight2) * d + weight2 * globals()["distribution"](distribution, hx, hy, hz, roughness2)
    gg = globals()["masking"](masking, g, roughness, distribution)
    c = dot(g.v, h)
    if fresnel == "none":
        f = np.ones((len(c), 3))
    elif fresnel == "schlick":
        f = fr.schlick(c[..., None], _metal_f0(metal) if metal != "none" else color(f0))
    elif fresnel == "dielectric":
        if metal == "none":
            f = np.repeat(fr.dielectric(c, ior)[..., None], 3, axis=-1)
        else:
            # Registry doc: a metal preset drives every Fresnel choice. Dielectric: one index per channel
            # that reproduces F0 at normal incidence, F0 = ((eta-1)/(eta+1))^2 solved for eta (seed 004).
            r = np.sqrt(np.minimum(_metal_f0(metal), 0.9999))
            etas = (1.0 + r) / (1.0 - r)
            f = np.stack([fr.dielectric(c, e) for e in etas], axis=-1)
    elif fresnel == "conductor":
        if metal == "none":
            f = fr.conductor(c[..., None], color(eta), color(k))
        else:
            # eta = 1 and F0 = k^2 / (4 + k^2) at normal incidence (complex Fresnel with n = 1 + ik), solved
            # for k: the conductor that reflects exactly F0 head-on (pbrt-v4 ConductorMaterial).
            f0m = np.minimum(_metal_f0(metal), 0.9999)
            f = fr.conductor(c[..., None], np.ones(3), np.sqrt(4.0 * f0m / (1.0 - f0m)))
    elif fresnel == "color_shift":
        # Cook & Torrance's colour shift (seed 004 "Cook-Torrance (15)"; seed 001): the angular shape comes
        # from the exact Fresnel of one reference wavelength; brdfpy's convention takes the mean of the
        # three F0 channels as that reference, with eta_ref = ior_from_f0(F0_ref). c0 = F0, c90 = 1.
        f0c = _metal_f0(metal) if metal != "none" else color(f0)
        ref = float(np.mean(f0c))
        f_ref = fr.dielectric(c, fr.ior_from_f0(ref))
        f = fr.color_shift(f_ref[..., None], ref, f0c, 1.0)
    else:
        raise NotImplementedError(f"oracle: fresnel {fresnel!r}")
    with np.errstate(divide="ignore", invalid="ignore"):
        spec = (d * gg / (4.0 * g.nl * g.nv))[..., None] * f
    return color(kd) / PI + color(ks) * spec


# --------------------------------------------------------------------------------- Strauss


def _metal_f0(metal: str) -> F64:
    """Seed 001's metal F0, clipped to 1: gold's red 1.022 there is an artifact of its colour conversion
    (a reflectance cannot exceed 1)."""
    return np.minimum(color(fr.METAL_F0[metal]), 1.0)


def _strauss_f(x: F64, kf: float) -> F64:
    """Strauss 1990's Fresnel-like curve (seed 004 "Strauss (6)"), x = angle / (pi/2)."""
    return (1.0 / (x - kf) ** 2 - 1.0 / kf**2) / (1.0 / (1.0 - kf) ** 2 - 1.0 / kf**2)


def _strauss_g(x: F64, kg: float) -> F64:
    """Strauss 1990's shadowing curve (seed 004 "Strauss (6)"), x = angle / (pi/2)."""
    return (1.0 / (1.0 - kg) ** 2 - 1.0 / (x - kg) ** 2) / (1.0 / (1.0 - kg) ** 2 - 1.0 / kg**2)


def strauss(
    g: Geo,
    color_: Any,
    smoothness: float,
    metalness: float,
    transparency: float,
    kf: float = 1.12,
    ks: float = 1.01,
    kj: float = 0.1,
    fresnel_angle: str = "incidence",
) -> F64:
    """Strauss 1990 "A Realistic Lighting Model for Computer Animators" (seed 004 "Strauss (3)-(6)"):
    the light's contribution ``Q_d + Q_s`` (no ambient) per unit light colour, i.e. the shade.

    ``Q_d = (n.l) d r_d C``, ``r_d = (1 - s^3)(1 - t)``, ``d = 1 - m s``;
    ``Q_s = max(0, r.v)^h r_j C_s``, ``h = 3/(1 - s)``, ``r_n = 1 - t - r_d``,
    ``r_j = min(1, r_n + (r_n + k_j) F(th_i) G(th_i) G(th_r))``,
    ``C_s = W + m (1 - F(th_i)) (C - W)`` with W white (Strauss 1990; seed 004 only says "interpolated
    between the surface colour and the light colour"). Angles enter F and G as ``theta / (pi/2)``;
    ``ks`` is the shadow constant (seed 004's ``k_g``); ``fresnel_angle="mean"`` feeds F with
    ``(theta_i + theta_r)/2`` instead of ``theta_i``.
    """
    kg = ks
    c = color(color_)
    s, m, t = smoothness, metalness, transparency
    rd = (1 - s**3) * (1 - t)
    d = 1 - m * s
    qd = _rgb(np.maximum(g.nl, 0.0) * d * rd, c)
    xi = np.arccos(np.clip(g.nl, 0.0, 1.0)) / (PI / 2)
    xr = np.arccos(np.clip(g.nv, 0.0, 1.0)) / (PI / 2)
    rn = 1 - t - rd
    fi = _strauss_f(xi if fresnel_angle == "incidence" else 0.5 * (xi + xr), kf)
    rj = np.minimum(1.0, rn + (rn + kj) * fi * _strauss_g(xi, kg) * _strauss_g(xr, kg))
    h = 3.0 / (1.0 - s)
    rs = np.maximum(0.0, dot(reflect(g.l, g.n), g.v)) ** h * rj
    cs = 1.0 + m * (1 - fi)[..., None] * (c - 1.0)
    # Strauss lights only what both the light and the viewer see: 0 unless n.l > 0 and n.v > 0.
    seen = ((g.nl > 0) & (g.nv > 0))[..., None]
    return np.where(seen, qd + rs[..., None] * cs, 0.0)


# ------------------------------------------------------------------------------- anisotropic


def ward(
    g: Geo, rho_d: Any, rho_s: Any, alpha_x: float, alpha_y: float, normalization: str = "walter"
) -> F64:
    """Ward 1992 ("Measuring and Modeling Anisotropic Reflection", eq. 5; seed 001 "Anisotropic Ward"):
    ``rho_d/pi + rho_s exp(-tan^2 th_h (cos^2 ph_h/ax^2 + sin^2 ph_h/ay^2))
    / (4 pi ax ay sqrt(cos i cos o))``: the exact tan^2 exponent (eq. 5a, "walter": Walter 2005 "Notes on
    the Ward BRDF" points out that the paper's eq. 5b is not the same function) or eq. 5b,
    ``exp(-2 ((h.x/ax)^2 + (h.y/ay)^2)/(1 + h.n))`` ("ward").
    """
    hx, hy, hz = g.loc(g.h)
    tan2, c2, s2 = mf._trig(hx, hy, hz)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        if normalization == "walter":
            e = np.exp(-tan2 * (c2 / alpha_x**2 + s2 / alpha_y**2))
        else:
            e = np.exp(-2.0 * ((hx / alpha_x) ** 2 + (hy / alpha_y) ** 2) / (1.0 + hz))
        spec = e / (4 * PI * alpha_x * alpha_y * np.sqrt(g.nl * g.nv))
    return color(rho_d) / PI + _rgb(spec, rho_s)


def ashikhmin_shirley(g: Geo, rd: Any, rs: Any, nu: float, nv: float) -> F64:
    """Ashikhmin & Shirley 2000 ("An Anisotropic Phong BRDF Model", eqs. 4 and 5):
    ``sqrt((nu+1)(nv+1))/(8 pi) (n.h)^(nu cos^2 ph + nv sin^2 ph) / ((h.v) max(n.l, n.v)) F(h.v)``
    with Schlick's F(rs), plus ``28 rd/(23 pi) (1 - rs)(1 - (1 - n.l/2)^5)(1 - (1 - n.v/2)^5)``."""
    h = g.h
    hx, hy, hz = g.loc(h)
    _, c2, s2 = mf._trig(hx, hy, hz)
    hv = dot(h, g.v)
    rs_c = color(rs)
    with np.errstate(invalid="ignore", divide="ignore"):
        lobe = np.sqrt((nu + 1) * (nv + 1)) / (8 * PI) * np.maximum(hz, 0.0) ** (nu * c2 + nv * s2)
        lobe = lobe / (hv * np.maximum(g.nl, g.nv))
    spec = lobe[..., None] * fr.schlick(hv[..., None], rs_c)
    diff = (
        28.0
        / (23.0 * PI)
        * (1 - (1 - g.nl / 2) ** 5)[..., None]
        * (1 - (1 - g.nv / 2) ** 5)[..., None]
        * color(rd)
        * (1 - rs_c)
    )
    return diff + spec


def lafortune(g: Geo, rho_d: Any, rho_s: Any, lobes: Any, power: str = "exact") -> F64:
    """Lafortune et al. 1997 generalised cosine lobes (seed 001 "General plausible cosine lobe"):
    ``rho_d/pi + sum_i rho_s max(0, Cx lx vx + Cy ly vy + Cz lz vz)^n_i`` in the local (t, b, n) frame.
    ``power="schlick"`` replaces ``S^n`` by Schlick's rational ``S/(n - nS + S)`` (seed 001).
    """
    lx, ly, lz = g.loc(g.l)
    vx, vy, vz = g.loc(g.v)
    total = np.zeros_like(g.nl)
    for cx, cy, cz, ex in np.asarray(lobes, dtype=np.float64).reshape(-1, 4):
        base = np.maximum(0.0, cx * lx * vx + cy * ly * vy + cz * lz * vz)
        if power == "exact":
            total += base**ex
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                total += np.where(base > 0, base / (ex - ex * base + base), 0.0)
    return color(rho_d) / PI + _rgb(total, rho_s)


# ----------------------------------------------------------------------------------- registry

#: name -> (function, classic?, parameter renames registry-name -> function-argument: the oracle keeps
#: the papers' symbols)
MODELS: dict[str, tuple[Callable[..., F64], bool, dict[str, str]]] = {
    "lambert": (lambert, False, {"kd": "albedo"}),
    "lambert_classic": (lambert_classic, True, {"kd": "color_"}),
    "oren_nayar": (oren_nayar, False, {"kd": "albedo"}),
    "oren_nayar_full": (oren_nayar_full, False, {"kd": "albedo"}),
    "toon": (toon, True, {"kd": "diffuse_color", "kd_mid": "diffuse_mid_color", "ks": "specular_color"}),
    "phong_classic": (phong_classic, True, {}),
    "blinn_phong_classic": (blinn_phong_classic, True, {}),
    "phong": (phong, False, {}),
    "blinn_phong": (blinn_phong, False, {}),
    "cook_torrance": (cook_torrance, False, {}),
    # physical: False in the registry (empirical)
    "strauss": (
        strauss,
        True,
        {"base_color": "color_", "k_fresnel": "kf", "k_shadow": "ks", "k_offspecular": "kj"},
    ),
    "ward": (ward, False, {"kd": "rho_d", "ks": "rho_s"}),
    "ashikhmin_shirley": (ashikhmin_shirley, False, {"kd": "rd", "ks": "rs"}),
    "lafortune": (lafortune, False, {"kd": "rho_d", "ks": "rho_s"}),
}


def evaluate(
    name: str,
    params: dict[str, Any],
    l: ArrayLike,
    v: ArrayLike,
    n: ArrayLike,
    tangent: ArrayLike | None = None,
    quantity: str = "eval",
) -> F64:
    """The oracle value of model ``name`` with (fully resolved) ``params``: ``f_r`` for
    ``quantity="eval"``, what multiplies the light colour for ``"shade"``. Returns (N, 3) float64."""
    fn, classic, rename = MODELS[name]
    g = geometry(l, v, n, tangent)
    kwargs = {rename.get(k, k): val for k, val in params.items()}
    with np.errstate(all="ignore"):
        raw = fn(g, **kwargs)
    valid = g.valid[..., None]
    if classic:
        shade = np.where(valid, raw, 0.0)
        with np.errstate(all="ignore"):
            f = np.where((g.nl > 0)[..., None], shade / g.nl[..., None], 0.0)
        out = f if quantity == "eval" else shade
    else:
        above = valid & ((g.nl > 0) & (g.nv > 0))[..., None]
        f = np.where(above, raw, 0.0)
        out = f if quantity == "eval" else f * np.maximum(g.nl, 0.0)[..., None]
    return np.where(valid, out, 0.0)
