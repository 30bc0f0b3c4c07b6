//! Fresnel reflectance: exact dielectric (s, p, unpolarised), exact conductor with a complex index
//! of refraction, Schlick's approximation, F0 ↔ IOR, a table of metal F0 colours (Hoffman 2010), Cook and
//! Torrance's colour-shift interpolation, and the reflected/transmitted split at a smooth interface.
//!
//! Every function returns a *power* ratio in [0, 1] (dimensionless). Cosines are of the angle
//! between the incident direction and the (micro)surface normal; in a microfacet BRDF that is
//! `c = v·h = l·h` (Walter et al. 2007 eq. 22).
//!
//! # Which form and why (course texts vs physics)
//! - Dielectric: the s/p form `R = (R_s + R_p)/2` with `R_s = ((cos_i − η cos_t)/(cos_i + η cos_t))²`,
//!   `R_p = ((η cos_i − cos_t)/(η cos_i + cos_t))²` (Born & Wolf, *Principles of Optics*, §1.5; pbrt-v4 `FrDielectric`). It is
//!   *algebraically identical* to Cook and Torrance's
//!   `F = ½ (g−c)²/(g+c)² · [1 + (c(g+c) − 1)² / (c(g−c) + 1)²]`, `g = √(η² + c² − 1)`, because
//!   `g = η cos_t` ([`dielectric_cook_torrance`] evaluates that form and the tests check
//!   the equality). Course texts print three slips of that form, none of which we follow:
//!   `g = √(n² + c²) − 1` (the −1 belongs under the root); a shader that clamps
//!   `g²` to `[1e−6, 1]` (wrong for any `η > 1` away from grazing) and uses `(c(g+c)+1)²` in the
//!   denominator; `[c(g−c) − 1]²` in the denominator. The correct denominator is
//!   `[c(g−c) + 1]²` (Cook & Torrance 1982; Walter et al. 2007 eq. 22).
//! - Conductor: `n − iκ` (the sign convention of the imaginary part does not change
//!   the reflectance), evaluated with the closed form for `|r_s|²`, `|r_p|²` that pbrt-v3
//!   `FrConductor` and Mitsuba's `fresnel_conductor` use (K. D. Möller, *Optics*); it equals the
//!   unpolarised `a², b²` form of the textbooks.
//! - Schlick: `F0 + (1 − F0)(1 − cos)^5` (Schlick 1994).

use glam::{Vec3, Vec3A};

use crate::simd::{Lane, V3};
use crate::vector::{reflect, refract};

/// Exact dielectric Fresnel reflectance for s- and p-polarised light, `(R_s, R_p)`.
///
/// `cos_i` = cos θ_i of the incident direction with the normal on the *outside*; `eta` = η_t/η_i =
/// η_inside/η_outside (e.g. 1.5 for air → glass). `cos_i < 0` means the light arrives from inside:
/// η → 1/η and cos_i → −cos_i (pbrt-v4 `FrDielectric`). Total internal reflection gives `(1, 1)`.
/// Grazing incidence (`cos_i = 0`) gives `(1, 1)` for every η. `eta` must be
/// finite and > 0; for other values the result is `(0, 0)` (no interface is defined; the bindings
/// refuse such input). Source: the Fresnel equations (Born & Wolf, *Principles of Optics*, §1.5).
#[inline]
pub fn dielectric_sp(cos_i: f32, eta: f32) -> (f32, f32) {
    dielectric_sp_lanes(cos_i, eta)
}

/// [`dielectric_sp`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn dielectric_sp_lanes<F: Lane>(cos_i: F, eta: f32) -> (F, F) {
    let (zero, one) = (F::splat(0.0), F::splat(1.0));
    if !(eta > 0.0 && eta.is_finite()) {
        return (zero, zero);
    }
    let inside = cos_i.lt(zero);
    let eta = F::select(inside, F::splat(1.0 / eta), F::splat(eta));
    let c = F::select(inside, -cos_i, cos_i).min(one);
    // Snell: sin θ_t = sin θ_i / η; total internal reflection when that exceeds 1.
    let sin2_t = (one - c * c) / (eta * eta);
    let cos_t = (one - sin2_t).max(zero).sqrt();
    let r_s = (c - eta * cos_t) / (c + eta * cos_t);
    let r_p = (eta * c - cos_t) / (eta * c + cos_t);
    let total = c.eq(zero) | sin2_t.ge(one);
    (F::select(total, one, r_s * r_s), F::select(total, one, r_p * r_p))
}

/// Exact unpolarised dielectric Fresnel reflectance `R = (R_s + R_p)/2` (see [`dielectric_sp`] for
/// the arguments, the inside convention and TIR → 1). At normal incidence it is
/// `((η − 1)/(η + 1))²` ([`f0_from_ior`]); at grazing incidence it is 1.
#[inline]
pub fn dielectric(cos_i: f32, eta: f32) -> f32 {
    dielectric_lanes(cos_i, eta)
}

/// [`dielectric`] on lanes.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn dielectric_lanes<F: Lane>(cos_i: F, eta: f32) -> F {
    let (rs, rp) = dielectric_sp_lanes(cos_i, eta);
    F::splat(0.5) * (rs + rp)
}

/// [`dielectric`] per RGB channel, with one relative index per channel.
#[inline]
pub fn dielectric_rgb(cos_i: f32, eta: Vec3) -> Vec3 {
    dielectric_rgb_lanes(cos_i, eta).into()
}

/// [`dielectric_rgb`] on lanes (one evaluation when the three indices are equal).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn dielectric_rgb_lanes<F: Lane>(cos_i: F, eta: Vec3) -> V3<F> {
    let x = dielectric_lanes(cos_i, eta.x);
    if eta.x == eta.y && eta.y == eta.z {
        return V3 { x, y: x, z: x };
    }
    V3 { x, y: dielectric_lanes(cos_i, eta.y), z: dielectric_lanes(cos_i, eta.z) }
}

/// Cook and Torrance's form of the exact dielectric Fresnel term (Cook & Torrance 1982):
/// `F = ½ (g−c)²/(g+c)² · [1 + (c(g+c) − 1)² / (c(g−c) + 1)²]`, `g = √(η² + c² − 1)`, `c = |cos_i|`.
///
/// Light is taken to arrive from the side η is relative to (no inside flip: pass 1/η yourself);
/// `η² + c² − 1 < 0` is total internal reflection → 1. Equal to [`dielectric`] up to rounding
/// (`g = η cos_t`), kept as a separate function so the equality is documented and tested; the
/// renderers use [`dielectric`].
#[inline]
pub fn dielectric_cook_torrance(cos_i: f32, eta: f32) -> f32 {
    let c = cos_i.abs().min(1.0);
    let g2 = eta * eta + c * c - 1.0;
    if g2 < 0.0 || c == 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = (g - c) / (g + c);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    0.5 * a * a * (1.0 + b * b)
}

/// Exact conductor Fresnel reflectance for s- and p-polarised light, per channel, for the complex
/// relative index `η − iκ` (the sign of the imaginary part does not change the result).
///
/// `cos_i` is taken as `|cos_i|` (a conductor is only lit from outside). `eta` > 0, `k` ≥ 0 per
/// channel. With `k = 0` this is the dielectric result (without TIR, since light comes from outside).
/// Closed form (K. D. Möller, *Optics*; pbrt-v3 `FrConductor`):
/// `a² + b² = √((η² − κ² − sin²θ)² + 4η²κ²)`, `a = √((a² + b² + η² − κ² − sin²θ)/2)`,
/// `R_s = (a² + b² + cos²θ − 2a cosθ)/(a² + b² + cos²θ + 2a cosθ)`,
/// `R_p = R_s (cos²θ (a² + b²) + sin⁴θ − 2a cosθ sin²θ)/(cos²θ (a² + b²) + sin⁴θ + 2a cosθ sin²θ)`.
#[inline]
pub fn conductor_sp(cos_i: f32, eta: Vec3, k: Vec3) -> (Vec3, Vec3) {
    let (rs, rp) = conductor_sp_lanes(cos_i, eta, k);
    (rs.into(), rp.into())
}

/// [`conductor_sp`] on lanes (the one place its formula is written), per channel.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn conductor_sp_lanes<F: Lane>(cos_i: F, eta: Vec3, k: Vec3) -> (V3<F>, V3<F>) {
    let (c, c2, s2) = cosines(cos_i);
    let (x, y, z) = (
        conductor_channel(c, c2, s2, eta.x, k.x),
        conductor_channel(c, c2, s2, eta.y, k.y),
        conductor_channel(c, c2, s2, eta.z, k.z),
    );
    (V3 { x: x.0, y: y.0, z: z.0 }, V3 { x: x.1, y: y.1, z: z.1 })
}

/// `num/den`, or 1 where `den ≤ 0`: 0/0 only happens for η = 1, κ = 0 at grazing incidence, where the
/// Fresnel terms' limit is 1.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn ratio<F: Lane>(num: F, den: F) -> F {
    F::select(den.gt(F::splat(0.0)), num / den.max(F::splat(f32::MIN_POSITIVE)), F::splat(1.0))
}

/// `(c, c², s²)`: `c = |cos_i|` clamped to 1, `s² = 1 − c²`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn cosines<F: Lane>(cos_i: F) -> (F, F, F) {
    let c = cos_i.abs().min(F::splat(1.0));
    let c2 = c * c;
    (c, c2, F::splat(1.0) - c2)
}

/// The terms of [`conductor_sp`]'s closed form for one channel, `R_s = (t1 − t2)/(t1 + t2)` and
/// `R_p = R_s (t3 − t4)/(t3 + t4)`: `t1 = a² + b² + cos²θ`, `t2 = 2a cosθ`, `t3 = cos²θ (a² + b²) + sin⁴θ`,
/// `t4 = t2 sin²θ`; `c2 = cos²θ`, `s2 = sin²θ`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn conductor_terms<F: Lane>(c: F, c2: F, s2: F, eta: f32, k: f32) -> [F; 4] {
    let zero = F::splat(0.0);
    let (eta2, k2) = (eta * eta, k * k);
    let t0 = F::splat(eta2 - k2) - s2;
    let a2b2 = (t0 * t0 + F::splat(4.0 * eta2 * k2)).max(zero).sqrt();
    let a = (F::splat(0.5) * (a2b2 + t0)).max(zero).sqrt();
    let t2 = F::splat(2.0) * c * a;
    [a2b2 + c2, t2, c2 * a2b2 + s2 * s2, t2 * s2]
}

/// `(R_s, R_p)` of one channel (see [`conductor_sp`]); `c2 = cos²θ`, `s2 = sin²θ`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn conductor_channel<F: Lane>(c: F, c2: F, s2: F, eta: f32, k: f32) -> (F, F) {
    let [t1, t2, t3, t4] = conductor_terms(c, c2, s2, eta, k);
    let rs = ratio(t1 - t2, t1 + t2).clamp(0.0, 1.0);
    let rp = (rs * ratio(t3 - t4, t3 + t4)).clamp(0.0, 1.0);
    (rs, rp)
}

/// Exact unpolarised conductor Fresnel reflectance `(R_s + R_p)/2` per channel (see
/// [`conductor_sp`]). At normal incidence `((η − 1)² + κ²)/((η + 1)² + κ²)`; at grazing incidence 1.
#[inline]
pub fn conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    conductor_lanes(cos_i, eta, k).into()
}

/// [`conductor`] on lanes.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn conductor_lanes<F: Lane>(cos_i: F, eta: Vec3, k: Vec3) -> V3<F> {
    // (R_s + R_p)/2 = R_s (1 + q)/2 with R_p = R_s q, q = (t3 − t4)/(t3 + t4), so that
    // (1 + q)/2 = t3/(t3 + t4) and the average is one quotient, (t1 − t2) t3/((t1 + t2)(t3 + t4)):
    // one division per channel instead of two, 9 divisions and square roots for the three channels
    // instead of 12 (the divider is what bounds an exact-conductor Cook–Torrance: GGX-Au went from 113
    // to 133 M evaluations/s on one thread, `examples/batch_throughput.rs`).
    let (c, c2, s2) = cosines(cos_i);
    V3 {
        x: conductor_average(c, c2, s2, eta.x, k.x),
        y: conductor_average(c, c2, s2, eta.y, k.y),
        z: conductor_average(c, c2, s2, eta.z, k.z),
    }
}

/// `(R_s + R_p)/2` of one channel as one quotient (see [`conductor_lanes`]).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn conductor_average<F: Lane>(c: F, c2: F, s2: F, eta: f32, k: f32) -> F {
    let [t1, t2, t3, t4] = conductor_terms(c, c2, s2, eta, k);
    ratio((t1 - t2) * t3, (t1 + t2) * (t3 + t4)).clamp(0.0, 1.0)
}

/// [`conductor`] for one channel.
#[inline]
pub fn conductor_scalar(cos_i: f32, eta: f32, k: f32) -> f32 {
    conductor(cos_i, Vec3::splat(eta), Vec3::splat(k)).x
}

/// Schlick's approximation `F = F0 + (1 − F0)(1 − |cos_i|)⁵` (Schlick 1994), per
/// channel. `|cos_i|` is clamped to [0, 1]. Valid from the optically thinner side; inside a denser
/// medium use [`dielectric`] (Schlick's form has no η and cannot show total internal reflection).
/// The fifth power is four multiplications, no `powf`.
#[inline]
pub fn schlick(cos_i: f32, f0: Vec3) -> Vec3 {
    schlick_lanes(cos_i, f0).into()
}

/// Schlick's weight `(1 − |cos_i|)⁵` (|cos_i| clamped to [0, 1]), the one place it is written.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn schlick_weight_lanes<F: Lane>(cos_i: F) -> F {
    let m = F::splat(1.0) - cos_i.abs().min(F::splat(1.0));
    let m2 = m * m;
    m2 * m2 * m
}

/// [`schlick`] on lanes: `F0 + (1 − F0) w` per channel with [`schlick_weight_lanes`].
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn schlick_lanes<F: Lane>(cos_i: F, f0: Vec3) -> V3<F> {
    V3::splat(f0) + V3::splat(Vec3::ONE - f0).scale(schlick_weight_lanes(cos_i))
}

/// [`schlick`] for one channel.
#[inline]
pub fn schlick_scalar(cos_i: f32, f0: f32) -> f32 {
    f0 + (1.0 - f0) * schlick_weight_lanes(cos_i)
}

/// Reflectance at normal incidence of a dielectric of relative index η: `F0 = ((η − 1)/(η + 1))²`
/// (Born & Wolf, §1.5). 0.04 for η = 1.5. Non-positive or non-finite η gives 0.
#[inline]
pub fn f0_from_ior(eta: f32) -> f32 {
    if !(eta > 0.0) || !eta.is_finite() {
        return 0.0;
    }
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// Relative index of the dielectric whose normal-incidence reflectance is `f0`:
/// `η = (1 + √F0)/(1 − √F0)`, the root ≥ 1 of [`f0_from_ior`]. `f0` is clamped to
/// [0, 1]; `f0 = 1` gives `+∞` (a perfect mirror has no finite index).
#[inline]
pub fn ior_from_f0(f0: f32) -> f32 {
    let s = f0.clamp(0.0, 1.0).sqrt();
    if s >= 1.0 { f32::INFINITY } else { (1.0 + s) / (1.0 - s) }
}

/// Extinction coefficient κ that, with η = 1, gives a conductor the normal-incidence reflectance `f0`:
/// `κ = 2√F0/√(1 − F0)` (pbrt-v4 `ConductorMaterial`). Lets [`conductor`] be driven by an
/// F0 colour alone. `f0` is clamped to [0, 0.9999] so κ stays finite (pbrt-v4 issue #222: F0 = 1
/// gave NaN there).
#[inline]
pub fn conductor_k_from_f0(f0: Vec3) -> Vec3 {
    let f0 = f0.clamp(Vec3::ZERO, Vec3::splat(0.9999));
    2.0 * f0.sqrt() / (Vec3::ONE - f0).sqrt()
}

/// A table of metal F0 colours (N. Hoffman, "Physics and Math of Shading", SIGGRAPH 2010/2012 course):
/// linear-RGB reflectance
/// at normal incidence, as (lower-case chemical symbol, F0).
///
/// The values are Hoffman's linear-RGB column verbatim (his sRGB column is their sRGB encoding, which
/// we checked to ±1).
/// **Gold's red channel, 1.022, exceeds 1**: no reflectance can; it is an artefact of projecting the
/// measured spectrum into the linear-sRGB gamut (the sRGB column clips it to 255). We keep the
/// published value here so the table is Hoffman's, and clamp to ≤ 1 where a model needs a
/// reflectance ([`metal_f0_clamped`]).
pub const METAL_F0: [(&str, Vec3); 11] = [
    ("ti", Vec3::new(0.542, 0.497, 0.449)),
    ("cr", Vec3::new(0.549, 0.556, 0.554)),
    ("fe", Vec3::new(0.562, 0.565, 0.578)),
    ("ni", Vec3::new(0.660, 0.609, 0.526)),
    ("pt", Vec3::new(0.673, 0.637, 0.585)),
    ("cu", Vec3::new(0.955, 0.638, 0.538)),
    ("pd", Vec3::new(0.733, 0.697, 0.652)),
    ("zn", Vec3::new(0.664, 0.824, 0.850)),
    ("au", Vec3::new(1.022, 0.782, 0.344)),
    ("al", Vec3::new(0.913, 0.922, 0.924)),
    ("ag", Vec3::new(0.972, 0.960, 0.915)),
];

/// English names of the [`METAL_F0`] entries, in the same order (accepted by [`metal_f0`] too).
pub const METAL_NAMES: [&str; 11] = [
    "titanium",
    "chromium",
    "iron",
    "nickel",
    "platinum",
    "copper",
    "palladium",
    "zinc",
    "gold",
    "aluminum",
    "silver",
];

/// F0 of a metal from [`METAL_F0`] by lower-case symbol (`"au"`) or English name (`"gold"`;
/// `"aluminium"` accepted), case-insensitively. `None` for an unknown name. Verbatim table values
/// (gold's red is 1.022, see [`METAL_F0`]).
pub fn metal_f0(name: &str) -> Option<Vec3> {
    let key = name.trim().to_ascii_lowercase();
    let key = if key == "aluminium" { "aluminum".to_string() } else { key };
    METAL_F0
        .iter()
        .zip(METAL_NAMES)
        .find(|((sym, _), long)| *sym == key || *long == key)
        .map(|((_, f0), _)| *f0)
}

/// [`metal_f0`] clamped to [0, 1] per channel, i.e. usable as a reflectance.
pub fn metal_f0_clamped(name: &str) -> Option<Vec3> {
    metal_f0(name).map(|f0| f0.clamp(Vec3::ZERO, Vec3::ONE))
}

/// The reference reflectance of [`color_shift`] for an F0 colour: the channel mean, standing for the
/// single wavelength λ₀ at which Cook & Torrance (1982) evaluate the full Fresnel curve.
#[inline]
pub fn color_shift_reference(f0: Vec3) -> f32 {
    (f0.x + f0.y + f0.z) / 3.0
}

/// Cook and Torrance's colour-shift approximation of a spectrally varying Fresnel term
/// (Cook & Torrance 1982):
///
/// 1. the measured normal-incidence reflectance of a reference wavelength `f0_ref` gives an index
///    `η_ref = (1 + √F0_ref)/(1 − √F0_ref)` ([`ior_from_f0`]);
/// 2. the exact curve `F_ref(θ)` = [`dielectric`]`(cos_i, η_ref)` is computed once;
/// 3. every channel is interpolated between its own F0 (normal incidence) and 1 (grazing):
///    `F_λ(θ) = F0_λ + (1 − F0_λ) · max(0, F_ref(θ) − F0_ref)/(1 − F0_ref)`.
///
/// So `F(0) = f0` exactly and `F(90°) = 1` for every channel, with one Fresnel evaluation instead of
/// one per channel. `f0_ref` is clamped to [0, 0.9999] (at 1 the curve is flat and the ratio 0/0).
/// Some course shaders also multiply by the mean of per-channel F and interpolate towards the
/// *light* colour; we return the reflectance only.
#[inline]
pub fn color_shift(cos_i: f32, f0: Vec3, f0_ref: f32) -> Vec3 {
    let f0_ref = f0_ref.clamp(0.0, 0.9999);
    color_shift_with_ior(cos_i, f0, f0_ref, ior_from_f0(f0_ref))
}

/// [`color_shift`] with the reference index `eta_ref = ior_from_f0(f0_ref)` precomputed (models call
/// this so the square root and division happen once, at construction).
#[inline]
pub fn color_shift_with_ior(cos_i: f32, f0: Vec3, f0_ref: f32, eta_ref: f32) -> Vec3 {
    color_shift_with_ior_lanes(cos_i, f0, f0_ref, eta_ref).into()
}

/// [`color_shift_with_ior`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn color_shift_with_ior_lanes<F: Lane>(cos_i: F, f0: Vec3, f0_ref: f32, eta_ref: f32) -> V3<F> {
    let f_ref = dielectric_lanes(cos_i.abs(), eta_ref);
    let w = ((f_ref - F::splat(f0_ref)).max(F::splat(0.0)) / F::splat(1.0 - f0_ref)).min(F::splat(1.0));
    V3::splat(f0) + V3::splat(Vec3::ONE - f0).scale(w)
}

/// What happens to light meeting a smooth dielectric interface (Pharr et al., PBR 4th ed., §9.3–9.5):
/// reflected and transmitted power fractions and directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FresnelSplit {
    /// Reflected power fraction R (unpolarised exact Fresnel), in [0, 1].
    pub reflectance: f32,
    /// Transmitted power fraction `T = 1 − R` (0 on total internal reflection). This is the power
    /// ratio; the transmitted *radiance* is further scaled by (η_t/η_i)² (radiance compression).
    pub transmittance: f32,
    /// Mirror direction `2(n·w)n − w`, pointing away from the surface on the incident side.
    pub reflected: Vec3A,
    /// Refracted direction (Snell), pointing away from the surface on the other side; `None` on total
    /// internal reflection.
    pub refracted: Option<Vec3A>,
}

/// Split light arriving along `w` at a smooth interface into reflected and transmitted parts.
///
/// `w`: unit direction toward where the light comes from (away from the surface, our convention).
/// `n`: unit normal on the *outside*. `eta` = η_inside/η_outside. If `w` is on the inside (`n·w < 0`)
/// the normal is flipped and η → 1/η. Uses [`crate::vector::refract`] for the direction and
/// [`dielectric`] for R; `T = 1 − R`, and `R = 1`, `T = 0` with no refracted ray on total internal
/// reflection. Non-positive η gives `R = 1`, `T = 0` (no transmission is defined).
#[inline]
pub fn split(w: Vec3A, n: Vec3A, eta: f32) -> FresnelSplit {
    let (n, eta) = if n.dot(w) < 0.0 { (-n, 1.0 / eta) } else { (n, eta) };
    let reflected = reflect(w, n);
    match refract(w, n, eta) {
        Some(t) if eta.is_finite() => {
            let r = dielectric(n.dot(w), eta);
            FresnelSplit { reflectance: r, transmittance: 1.0 - r, reflected, refracted: Some(t) }
        }
        _ => FresnelSplit { reflectance: 1.0, transmittance: 0.0, reflected, refracted: None },
    }
}

/// The Fresnel term a microfacet model uses, chosen once at construction (Cook–Torrance's `F`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fresnel {
    /// F = 1 (pure D·G, e.g. for albedo tests).
    None,
    /// [`schlick`] with this F0 colour.
    Schlick {
        /// Reflectance at normal incidence per channel.
        f0: Vec3,
    },
    /// [`dielectric_rgb`] with this relative index per channel.
    Dielectric {
        /// η_inside/η_outside per channel.
        eta: Vec3,
    },
    /// [`conductor`] with the complex index `η − iκ` per channel.
    Conductor {
        /// Real part η per channel.
        eta: Vec3,
        /// Extinction κ per channel.
        k: Vec3,
    },
    /// [`color_shift`] from an F0 colour, the reference precomputed.
    ColorShift {
        /// Reflectance at normal incidence per channel.
        f0: Vec3,
        /// Reference reflectance ([`color_shift_reference`]), clamped to [0, 0.9999].
        f0_ref: f32,
        /// `ior_from_f0(f0_ref)`.
        eta_ref: f32,
    },
}

impl Fresnel {
    /// Colour-shift term for `f0` with the channel-mean reference.
    pub fn color_shift(f0: Vec3) -> Self {
        let f0_ref = color_shift_reference(f0).clamp(0.0, 0.9999);
        Fresnel::ColorShift { f0, f0_ref, eta_ref: ior_from_f0(f0_ref) }
    }

    /// Reflectance per channel at `cos_i` (= v·h in a microfacet model).
    #[inline]
    pub fn eval(&self, cos_i: f32) -> Vec3 {
        self.eval_lanes(cos_i).into()
    }

    /// [`Fresnel::eval`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn eval_lanes<F: Lane>(&self, cos_i: F) -> V3<F> {
        match *self {
            Fresnel::None => V3::splat(Vec3::ONE),
            Fresnel::Schlick { f0 } => schlick_lanes(cos_i, f0),
            Fresnel::Dielectric { eta } => dielectric_rgb_lanes(cos_i, eta),
            Fresnel::Conductor { eta, k } => conductor_lanes(cos_i, eta, k),
            Fresnel::ColorShift { f0, f0_ref, eta_ref } => {
                color_shift_with_ior_lanes(cos_i, f0, f0_ref, eta_ref)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schlick_hits_f0_at_normal_incidence_and_one_at_grazing() {
        assert!((schlick_scalar(1.0, 0.04) - 0.04).abs() < 1e-7);
        assert!((schlick_scalar(0.0, 0.04) - 1.0).abs() < 1e-7);
    }

    #[test]
    fn ior_round_trips_through_f0() {
        for eta in [1.0f32, 1.33, 1.5, 2.4, 4.0] {
            assert!((ior_from_f0(f0_from_ior(eta)) - eta).abs() < 1e-3 * eta, "{eta}");
        }
    }
}
