//! Visible-normal sampling of the (anisotropic) Beckmann distribution (Heitz & d'Eon 2014,
//! "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals", EGSR; the
//! numerically robust inversion of W. Jakob 2014, "An Improved Visible Normal Sampling Routine for the
//! Beckmann Distribution", ETH Zürich technical note; pbrt-v3 §8.4 `BeckmannSample11`).
//!
//! Stretching `v` to roughness 1 makes the problem isotropic, and rotating it into the x–z plane at
//! polar angle θ separates it: with the slopes `(x̃, ỹ)` of a microfacet normal `∝ (−x̃, −ỹ, 1)`, the
//! visible-slope density is `∝ (cos θ − x̃ sin θ)⁺ e^{−x̃² − ỹ²}`. So `ỹ` is Gaussian,
//! `ỹ = erfinv(2u₂ − 1)`, and `x̃ < cot θ` has the CDF (in the variable `b = erf x̃`)
//!
//! ```text
//! C(b) = (1 + b + tan θ/√π · e^{−erfinv(b)²}) / (1 + erf(cot θ) + tan θ/√π · e^{−cot²θ}),
//! C'(b) ∝ 1 − erfinv(b) tan θ,
//! ```
//!
//! solved for `C(b) = u₁` by Newton's method safeguarded by bisection on `[−1, erf(cot θ)]`, started
//! from Jakob's fitted guess. Every lane runs the same iteration on its own values, and a lane whose
//! residual is below [`TOLERANCE`] keeps its value, so the result does not depend on the other lanes
//! (batch = scalar bits). Rotating back, un-stretching and normalising gives `h` with density
//! `D_v(h) = G1(v) max(0, v·h) D(h)/(n·v)`; reflecting `v` gives `p(l) = G1(v) D(h)/(4 n·v)` with the
//! exact (erf) Smith `G1` of [`crate::microfacet::beckmann`].
//!
//! `u` is kept in `[1e-6, 1 − 1e-6]` (the inverse error function is infinite at ±1): a fraction
//! 4e-6 of the slope distribution's far tails is folded onto its edge, far below what any test resolves.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3A;

use super::cosine_power::{half, reflect};
use super::neg;
use crate::microfacet::{ALPHA_MIN, beckmann};
use crate::simd::{Lane, V3};

/// Residual of the CDF inversion `|C(b) − u|` below which a lane stops iterating.
pub const TOLERANCE: f32 = 1e-6;
/// Most Newton–bisection steps per sample (measured: ≤ 6 suffice from Jakob's guess).
pub const MAX_STEPS: usize = 12;

/// The stretched slope `x̃` along the incidence plane and `ỹ` across it for polar angle θ
/// (`cos θ`, `sin θ` given), from `(u1, u2)`.
#[inline(always)]
fn slopes<F: Lane>(cos: F, sin: F, u1: F, u2: F) -> (F, F) {
    let one = F::splat(1.0);
    let u1 = u1.clamp(1e-6, 1.0 - 1e-6);
    let u2 = u2.clamp(1e-6, 1.0 - 1e-6);
    let tan = sin / cos;
    let cot = cos / sin; // +∞ at normal incidence: erf(∞) = 1, e^{−∞} = 0, and the CDF is (1 + b)/2.
    let k = tan * F::splat(1.0 / PI.sqrt());
    let hi = cot.erf();
    let norm = one / (one + hi + k * neg(cot * cot).exp());
    // Jakob's fitted initial guess b = c − (1 + c)(1 − u)^fit(θ).
    let theta = sin.atan2(cos);
    let fit = one + theta * (F::splat(-0.876) + theta * (F::splat(0.4265) - F::splat(0.0594) * theta));
    let mut b = hi - (one + hi) * (one - u1).powf(fit);
    let (mut lo, mut up) = (F::splat(-1.0), hi);
    let mut done = F::mask_splat(false);
    for _ in 0..MAX_STEPS {
        // Outside the bracket (or NaN): bisect.
        let inside = b.ge(lo) & b.le(up);
        b = F::select(inside, b, F::splat(0.5) * (lo + up));
        let x = b.erfinv();
        let value = norm * (one + b + k * neg(x * x).exp()) - u1;
        done = done | value.abs().lt(F::splat(TOLERANCE));
        if F::mask_all(done) {
            break;
        }
        let deriv = norm * (one - x * tan);
        let positive = value.gt(F::splat(0.0));
        up = F::select(done, up, F::select(positive, b, up));
        lo = F::select(done, lo, F::select(positive, lo, b));
        b = F::select(done, b, b - value / deriv);
    }
    (b.erfinv(), (F::splat(2.0) * u2 - one).erfinv())
}

/// A visible normal of the Beckmann distribution for the local view direction `v` (`v_z > 0`).
#[inline(always)]
pub fn sample_normal<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    let (ax, ay) = (F::splat(alpha_x.max(ALPHA_MIN)), F::splat(alpha_y.max(ALPHA_MIN)));
    let (zero, one) = (F::splat(0.0), F::splat(1.0));
    let w = V3 { x: ax * v.x, y: ay * v.y, z: v.z };
    let w = w / w.dot(w).sqrt();
    let sin = (w.x * w.x + w.y * w.y).sqrt();
    let flat = sin.gt(zero);
    let (cos_phi, sin_phi) = (F::select(flat, w.x / sin, one), F::select(flat, w.y / sin, zero));
    let (x, y) = slopes(w.z, sin, u1, u2);
    // Rotate into the azimuth of v, un-stretch; the normal is (−slope_x, −slope_y, 1) normalised.
    let sx = (cos_phi * x - sin_phi * y) * ax;
    let sy = (sin_phi * x + cos_phi * y) * ay;
    let m = V3 { x: neg(sx), y: neg(sy), z: one };
    m / m.dot(m).sqrt()
}

/// A local direction `l`: `v` reflected about a visible normal ([`sample_normal`]).
#[inline(always)]
pub fn sample<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    reflect(v, sample_normal(alpha_x, alpha_y, v, u1, u2))
}

/// Beckmann `D(h)` [1/sr] for a unit local `h`, `h_z > 0`:
/// `exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy hz⁴)` ([`beckmann::d_aniso`] on lanes).
#[inline(always)]
pub fn d<F: Lane>(alpha_x: f32, alpha_y: f32, h: V3<F>) -> F {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let (x, y) = (h.x / F::splat(ax), h.y / F::splat(ay));
    let z2 = h.z * h.z;
    ((x * x + y * y) / z2).exp_neg_normal() * F::splat(FRAC_1_PI / (ax * ay)) / (z2 * z2)
}

/// Exact Smith `G1(v) = 1/(1 + Λ(v))` of the Beckmann distribution ([`beckmann::lambda_aniso`], per
/// lane) for a unit local `v`.
#[inline(always)]
pub fn g1<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>) -> F {
    F::from_fn(|i| {
        let w = Vec3A::new(v.x.lane(i), v.y.lane(i), v.z.lane(i));
        1.0 / (1.0 + beckmann::lambda_aniso(w, alpha_x, alpha_y))
    })
}

/// The density [1/sr] of [`sample`] at the local direction `l`: `G1(v) D(h)/(4 n·v)`,
/// `h = normalize(l + v)`; 0 where `h` does not exist or is not above the surface.
#[inline(always)]
pub fn pdf<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, l: V3<F>) -> F {
    let (h, len2) = half(l, v);
    let zero = F::splat(0.0);
    let ok = len2.gt(F::splat(1e-20)) & h.z.gt(zero) & v.dot(h).gt(zero);
    let p = g1(alpha_x, alpha_y, v) * d(alpha_x, alpha_y, h) / (F::splat(4.0) * v.z);
    F::select(ok, p, zero)
}
