//! Oren-Nayar rough diffuse reflection (Oren & Nayar 1994, "Generalization of Lambert's reflectance
//! model", SIGGRAPH '94): the qualitative model ([`OrenNayar`]) and the full model with the
//! interreflection term ([`OrenNayarFull`]).
//!
//! Both are evaluated without building a tangent frame, from the tangent-plane parts
//! `w⊥ = w − (n·w)n` of `l` and `v`: `s = l⊥·v⊥ = sin θ_i sin θ_r cos Δφ`, `sin θ = |w⊥|`, and
//! `cos Δφ = s / (|l⊥||v⊥|)` — a shader's `dot(normalize(L − (L·N)N), normalize(V − (V·N)N))`.
//! At normal incidence (`sin θ = 0`) the azimuth is undefined; every term it multiplies then carries a
//! factor `tan β`, `β²` or `sin β` that is 0, so the value is continuous there and no NaN arises.
//!
//! Why components and not the cosines (`s = l·v − (n·l)(n·v)`, `sin θ = √(1 − cos²θ)`, `θ = acos`):
//! near the normal `l·v` and `(n·l)(n·v)` are both ≈ 1 and their float32 difference keeps only their
//! rounding, and a float32 cosine ≈ 1 is known to `2^-24` absolute, which `√(1 − c²)` and `acos` turn
//! into `~2^-24/θ` of angle (β = 0 for θ below 2.4e-4). With `l` near the normal and `v` far from it
//! the full model's `C2` term `∝ sin α tan β` then came out up to 6 000 ulps off the float64 oracle
//! where rounding the float32 inputs explains 0.7 ulp. `|w⊥|` and `atan2(|w⊥|, n·w)` are accurate to
//! a few ulps at every angle. tests/test_oren_nayar_precision.py bounds both models against the oracle.

use std::f32::consts::{FRAC_1_PI, FRAC_2_PI, FRAC_PI_2};

use glam::Vec3;

use crate::BrdfError;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// `A` of the qualitative model, `1 − 0.5 σ²/(σ² + c)`, with `c` = 0.33 (Oren & Nayar 1994) or
/// 0.57 (the interreflection-compensated constant).
#[inline]
pub fn oren_nayar_a(sigma: f32, c: f32) -> f32 {
    let s2 = sigma * sigma;
    1.0 - 0.5 * s2 / (s2 + c)
}

/// The tangent-plane part `w⊥ = w − (n·w)n` of a unit direction `w` \[dimensionless, length sin θ\],
/// given `nw = n·w`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn tangent_part<F: Lane>(w: V3<F>, n: V3<F>, nw: F) -> V3<F> {
    w - n.scale(nw)
}

/// `(cos Δφ, 1 − |cos Δφ|)` \[dimensionless\] of the azimuth between the tangent-plane parts `lp`, `vp`
/// (of lengths `sin_i`, `sin_r`); `(0, 1)` when either is (nearly) 0, where the azimuth is undefined.
///
/// `1 − |cos Δφ|` is `|ê_l ∓ ê_v|²/2` of the unit azimuth directions `ê = w⊥/|w⊥|` (− for
/// `cos Δφ ≥ 0`), not `1 − |cos Δφ|` itself: at opposite (or equal) azimuths that difference keeps only
/// the rounding of `cos Δφ ≈ ∓1`, and the full model multiplies it by `C3 tan((α+β)/2)`, which grows
/// like `1/cos` at grazing (1 400 ulps of the terms' summed magnitude at σ = π/2, both directions
/// within 0.1 rad of the horizon; 5 ulps this way, in a float32 emulation).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn azimuth_cosines<F: Lane>(lp: V3<F>, vp: V3<F>, sin_i: F, sin_r: F) -> (F, F) {
    let sin_prod = sin_i * sin_r;
    let defined = !sin_prod.lt(F::splat(f32::MIN_POSITIVE));
    let cos_dphi = (lp.dot(vp) / sin_prod).clamp(-1.0, 1.0);
    let (el, ev) = (lp / sin_i, vp / sin_r);
    let d = V3::select(cos_dphi.ge(F::splat(0.0)), el - ev, el + ev);
    let one_minus_abs = (F::splat(0.5) * d.dot(d)).min(F::splat(1.0));
    (F::select(defined, cos_dphi, F::splat(0.0)), F::select(defined, one_minus_abs, F::splat(1.0)))
}

/// `B` of the qualitative model, `0.45 σ²/(σ² + 0.09)` (Oren & Nayar 1994).
#[inline]
pub fn oren_nayar_b(sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    0.45 * s2 / (s2 + 0.09)
}

/// Which constant the qualitative model's `A` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrenNayarVariant {
    /// `A = 1 − 0.5 σ²/(σ² + 0.33)`: Oren & Nayar 1994's qualitative model (as in pbrt-v3).
    Qualitative,
    /// `A = 1 − 0.5 σ²/(σ² + 0.57)`: compensates the energy of the interreflection term the qualitative
    /// model leaves out (Portsmouth, Kutz, Hill 2025, "EON", arXiv 2410.18026, "discrepancy-compensated A").
    Compensated,
}

impl OrenNayarVariant {
    /// The constant `c` in `A = 1 − 0.5 σ²/(σ² + c)`.
    pub fn a_constant(self) -> f32 {
        match self {
            Self::Qualitative => 0.33,
            Self::Compensated => 0.57,
        }
    }
}

const KD: ParamSpec = ParamSpec::color(
    "kd",
    [0.8, 0.8, 0.8],
    0.0,
    1.0,
    "reflectance",
    "diffuse reflectance of the facets (rho)",
);
const SIGMA: ParamSpec = ParamSpec::scalar(
    "sigma",
    0.5,
    0.0,
    FRAC_PI_2,
    "radians",
    "roughness: standard deviation of the facet slope angle (0 = Lambert)",
);

/// The qualitative Oren-Nayar BRDF [1/sr] (Oren & Nayar 1994, eq. 30), with `ρ` = `kd`:
///
/// ```text
/// f_r = ρ/π · (A + B · max(0, cos Δφ) · sin α · tan β),   α = max(θ_i, θ_r), β = min(θ_i, θ_r)
/// A = 1 − 0.5 σ²/(σ² + c),  c = 0.33 ("qualitative") or 0.57 ("compensated");  B = 0.45 σ²/(σ² + 0.09)
/// ```
///
/// σ is in **radians** (pbrt-v3 and BRDF Explorer sliders take degrees). Since
/// `sin α sin β = sin θ_i sin θ_r` and `cos β = max(n·l, n·v)`, the angular factor is evaluated
/// without any trigonometric call as `max(0, cos Δφ) sin α tan β = max(0, s) / max(n·l, n·v)` with
/// `s = l⊥·v⊥` (Fujii's "improved" O-N and many shaders write it `l·v − (n·l)(n·v)`, which cancels
/// near the normal: see the module notes). It is
/// reciprocal. It does not conserve energy exactly: at normal view its albedo is `A` (0.865 for
/// σ = 20° with c = 0.33); the compensated constant raises it toward the full model's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrenNayar {
    /// Diffuse reflectance ρ of the facets.
    kd: Vec3,
    /// Roughness σ \[rad\].
    sigma: f32,
    /// Constant used in `A`.
    variant: OrenNayarVariant,
    /// `ρ A / π`.
    a_term: Vec3,
    /// `ρ B / π`.
    b_term: Vec3,
}

impl OrenNayar {
    /// Qualitative Oren-Nayar of facet reflectance `kd`, roughness `sigma` \[rad\] and the given `A`
    /// constant.
    pub fn new(kd: Vec3, sigma: f32, variant: OrenNayarVariant) -> Self {
        let rho_pi = kd * FRAC_1_PI;
        Self {
            kd,
            sigma,
            variant,
            a_term: rho_pi * oren_nayar_a(sigma, variant.a_constant()),
            b_term: rho_pi * oren_nayar_b(sigma),
        }
    }

    /// Diffuse reflectance ρ of the facets.
    #[inline]
    pub fn kd(&self) -> Vec3 {
        self.kd
    }

    /// Roughness σ \[rad\].
    #[inline]
    pub fn sigma(&self) -> f32 {
        self.sigma
    }

    /// Constant used in `A`.
    #[inline]
    pub fn variant(&self) -> OrenNayarVariant {
        self.variant
    }
}

impl Bxdf for OrenNayar {
    const SPEC: ModelSpec = ModelSpec {
        name: "oren_nayar",
        summary: "qualitative Oren-Nayar, f_r = kd/pi*(A + B*max(0,cos dphi)*sin(alpha)*tan(beta))",
        source: "M. Oren, S. K. Nayar, Generalization of Lambert's Reflectance Model, SIGGRAPH (1994), eq. 30; the 0.57 constant: J. Portsmouth, P. Kutz, S. Hill, EON, arXiv:2410.18026 (2025)",
        physical: true,
        anisotropic: false,
        params: &[
            KD,
            SIGMA,
            ParamSpec::choice(
                "variant",
                &["qualitative", "compensated"],
                "qualitative",
                "constant in A = 1 - 0.5 sigma^2/(sigma^2 + c): qualitative c = 0.33, compensated c = 0.57",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted ([`crate::sampling::cosine`]); `f·cos/p = π f` stays within a factor of
    /// `A ± B` of the albedo.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        let variant = match p.choice("variant") {
            "compensated" => OrenNayarVariant::Compensated,
            _ => OrenNayarVariant::Qualitative,
        };
        Ok(Self::new(p.color("kd"), p.scalar("sigma"), variant))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        // max(0, cos Δφ) sin α tan β = max(0, s) / cos β; cos β = max(n·l, n·v) > 0 here. s = l⊥·v⊥
        // from components, not l·v − (n·l)(n·v) (two numbers ≈ 1 near the normal: module notes).
        let s = tangent_part(g.l, g.n, g.nl).dot(tangent_part(g.v, g.n, g.nv));
        let angular = s.max(F::splat(0.0)) / g.nl.max(g.nv);
        V3::splat(self.a_term) + V3::splat(self.b_term).scale(angular)
    }
}

/// The full Oren-Nayar BRDF with the interreflection term [1/sr] (Oren & Nayar 1994, eqs. 27–29;
/// BRDF Explorer `orennayar.brdf`), with `ρ` = `kd`:
///
/// ```text
/// f_r = L1 + L2
/// L1 = ρ/π [C1 + cos Δφ · C2 · tan β + (1 − |cos Δφ|) · C3 · tan((α+β)/2)]
/// L2 = 0.17 ρ²/π · σ²/(σ² + 0.13) · [1 − cos Δφ · (2β/π)²]
/// C1 = 1 − 0.5 σ²/(σ² + 0.33)
/// C2 = 0.45 σ²/(σ² + 0.09) · sin α                  if cos Δφ ≥ 0
///    = 0.45 σ²/(σ² + 0.09) · (sin α − (2β/π)³)      otherwise
/// C3 = 0.125 σ²/(σ² + 0.09) · (4αβ/π²)²
/// ```
///
/// **Where summaries differ.** Some textbook summaries print `C1 = 1 − 0.5 σ²/(σ² + 0.3)` and `L2`
/// with `ρ` instead of `ρ²`. The paper (and BRDF Explorer, OpenPBR's `ON_full`) use 0.33 — the same
/// constant as the qualitative `A` — and `ρ²`, because the interreflected light has been reflected
/// twice by facets of albedo ρ. The paper's form is used here. With `interreflection = false` only `L1` is evaluated.
///
/// Cost: two `atan2` (α and β are needed as angles in `C2`, `C3` and `L2`; `atan2(|w⊥|, n·w)`, not
/// `acos(n·w)`, for the module notes' reason); `tan β` and
/// `tan((α+β)/2) = (sin α + sin β)/(cos α + cos β)` come from the sines `|w⊥|` and cosines `n·w`. Near
/// grazing `sin α − (2β/π)³` is a difference of two numbers ≈ 1 (it vanishes at α = β = π/2, where
/// `tan β` is large), so for `β > π/4` it is evaluated from the complements `u = 1 − 2β/π` (from
/// `atan2(cos β, sin β)`) and `1 − sin α = cos²α/(1 + sin α)` as `u(3 − 3u + u²) − cos²α/(1 + sin α)`;
/// there, at σ = π/2 with both directions within 0.1 rad of the horizon in opposite azimuths, the
/// direct difference left 9 000 ulps of the terms' summed magnitude (the value itself crosses zero
/// there: the model, as published, dips slightly negative) where rounding the float32 inputs explains
/// 5; 8 now. The model is reciprocal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrenNayarFull {
    /// Diffuse reflectance ρ of the facets.
    kd: Vec3,
    /// Roughness σ \[rad\].
    sigma: f32,
    /// Whether the interreflection term `L2` is included.
    interreflection: bool,
    /// `ρ/π`.
    rho_pi: Vec3,
    /// `0.17 ρ²/π · σ²/(σ² + 0.13)` (0 without interreflection).
    l2_term: Vec3,
    /// `C1`.
    c1: f32,
    /// `0.45 σ²/(σ² + 0.09)`.
    c2_scale: f32,
    /// `0.125 σ²/(σ² + 0.09)`.
    c3_scale: f32,
}

impl OrenNayarFull {
    /// Full Oren-Nayar of facet reflectance `kd`, roughness `sigma` \[rad\], with or without `L2`.
    pub fn new(kd: Vec3, sigma: f32, interreflection: bool) -> Self {
        let s2 = sigma * sigma;
        let k = s2 / (s2 + 0.09);
        let rho_pi = kd * FRAC_1_PI;
        let l2_term = if interreflection { kd * rho_pi * (0.17 * s2 / (s2 + 0.13)) } else { Vec3::ZERO };
        Self {
            kd,
            sigma,
            interreflection,
            rho_pi,
            l2_term,
            c1: oren_nayar_a(sigma, 0.33),
            c2_scale: 0.45 * k,
            c3_scale: 0.125 * k,
        }
    }

    /// Diffuse reflectance ρ of the facets.
    #[inline]
    pub fn kd(&self) -> Vec3 {
        self.kd
    }

    /// Roughness σ \[rad\].
    #[inline]
    pub fn sigma(&self) -> f32 {
        self.sigma
    }

    /// Whether the interreflection term `L2` is included.
    #[inline]
    pub fn interreflection(&self) -> bool {
        self.interreflection
    }
}

impl Bxdf for OrenNayarFull {
    const SPEC: ModelSpec = ModelSpec {
        name: "oren_nayar_full",
        summary: "full Oren-Nayar with C1, C2, C3 and the interreflection term L2 (rho^2)",
        source: "M. Oren, S. K. Nayar, Generalization of Lambert's Reflectance Model, SIGGRAPH (1994), eqs. 27-29 (C1 constant 0.33, rho^2 in L2)",
        physical: true,
        anisotropic: false,
        params: &[KD, SIGMA, ParamSpec::flag("interreflection", true, "include the interreflection term L2")],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted ([`crate::sampling::cosine`]); `f·cos/p = π f` stays within a factor of
    /// `A ± B` of the albedo.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd"), p.scalar("sigma"), p.flag("interreflection")))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let (zero, one) = (F::splat(0.0), F::splat(1.0));
        let (lp, vp) = (tangent_part(g.l, g.n, g.nl), tangent_part(g.v, g.n, g.nv));
        let (cos_i, cos_r) = (g.nl, g.nv);
        let (sin_i, sin_r) = (lp.dot(lp).sqrt(), vp.dot(vp).sqrt());
        // α = max(θi, θr) is the angle with the smaller cosine (ties: the larger sine, so that swapping
        // l and v picks the same pair).
        let i_is_alpha = cos_i.lt(cos_r) | (cos_i.eq(cos_r) & sin_i.gt(sin_r));
        let (cos_a, sin_a) = (F::select(i_is_alpha, cos_i, cos_r), F::select(i_is_alpha, sin_i, sin_r));
        let (cos_b, sin_b) = (F::select(i_is_alpha, cos_r, cos_i), F::select(i_is_alpha, sin_r, sin_i));
        let (alpha, beta) = (sin_a.atan2(cos_a), sin_b.atan2(cos_b));

        // cos Δφ and 1 − |cos Δφ| from the tangent-plane projections; undefined (and irrelevant) at
        // normal incidence, where every term they multiply vanishes: 0 and 1 there.
        let (cos_dphi, one_minus_abs_cos) = azimuth_cosines(lp, vp, sin_i, sin_r);
        let two_beta_pi = beta * F::splat(FRAC_2_PI);
        let near = sin_a - two_beta_pi * two_beta_pi * two_beta_pi;
        // sin α − (2β/π)³ = (1 − (1 − u)³) − (1 − sin α) with u = 1 − 2β/π, both small for β > π/4.
        let u = cos_b.atan2(sin_b) * F::splat(FRAC_2_PI);
        let far = u * (F::splat(3.0) - F::splat(3.0) * u + u * u) - cos_a * cos_a / (one + sin_a);
        let behind = F::select(two_beta_pi.le(F::splat(0.5)), near, far);
        let c2 = F::splat(self.c2_scale) * F::select(cos_dphi.ge(zero), sin_a, behind);
        let four_ab = alpha * beta * F::splat(2.0 * FRAC_2_PI * FRAC_1_PI); // 4αβ/π²
        let c3 = F::splat(self.c3_scale) * four_ab * four_ab;
        let tan_b = sin_b / cos_b;
        let tan_half_sum = (sin_a + sin_b) / (cos_a + cos_b);

        let l1 = F::splat(self.c1) + cos_dphi * c2 * tan_b + one_minus_abs_cos * c3 * tan_half_sum;
        let l2 = one - cos_dphi * two_beta_pi * two_beta_pi;
        V3::splat(self.rho_pi).scale(l1) + V3::splat(self.l2_term).scale(l2)
    }
}
