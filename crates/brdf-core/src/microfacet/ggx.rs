//! Trowbridge–Reitz / GGX distribution and its Smith Λ (Trowbridge & Reitz 1975; Walter et al. 2007;
//! pbrt-v4 `TrowbridgeReitzDistribution`).
//!
//! `D(h) = α² / (π cos⁴θ (α² + tan²θ)²) = α² / (π ((1 − cos²θ) + α² cos²θ)²)`, normalised so that
//! `∫ D(h) cosθ_h dω_h = 1`. The Trowbridge–Reitz line `1/(π((n·h)²(m²−1)+1)²)` some course texts print lacks the
//! numerator α² (its normalisation constant); with it the two forms are the same function.
//! We evaluate the denominator as `(1 − c²) + α²c²` rather than `c²(α² − 1) + 1`: in f32, `α² − 1`
//! rounds to −1 for α ≲ 3e−4 and the peak would become α²/0.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, HalfVector};
use crate::simd::{Lane, V3};

/// Isotropic GGX `D` [1/sr] at `cos_h` = n·h for roughness α (clamped to ≥ [`ALPHA_MIN`]);
/// 0 for `cos_h ≤ 0` (the χ⁺ of Walter et al. 2007).
#[inline]
pub fn d(cos_h: f32, alpha: f32) -> f32 {
    d_lanes(cos_h, alpha)
}

/// [`d`] on lanes (the one place its formula is written; see [`crate::simd`]).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_lanes<F: Lane>(cos_h: F, alpha: f32) -> F {
    let a2 = {
        let a = alpha.max(ALPHA_MIN);
        a * a
    };
    let c2 = (cos_h * cos_h).min(F::splat(1.0));
    let t = (F::splat(1.0) - c2) + F::splat(a2) * c2;
    let d = F::splat(a2 * std::f32::consts::FRAC_1_PI) / (t * t);
    F::select(cos_h.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Isotropic GGX `D` [1/sr] from the un-normalised half vector `h̃ = l + v` ([`HalfVector`]):
/// `cos⁴θ (α² + tan²θ)² = ((n·h̃)² α² + |h̃⊥|²)² / |h̃|⁴`, so
/// `D = α² |h̃|⁴ / (π (α² (n·h̃)² + |h̃⊥|²)²)` — the same function as [`d`], with no `1 − cos²θ`
/// (accurate for nearly opposite `l`, `v`; see [`crate::microfacet::half`]). 0 for `n·h̃ ≤ 0`.
#[inline]
pub fn d_half(h: &HalfVector<f32>, alpha: f32) -> f32 {
    d_half_lanes(h, alpha)
}

/// [`d_half`] on lanes (the one place its formula is written; see [`crate::simd`]).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_half_lanes<F: Lane>(h: &HalfVector<F>, alpha: f32) -> F {
    let a2 = {
        let a = alpha.max(ALPHA_MIN);
        a * a
    };
    let t = F::splat(a2) * (h.n_dot * h.n_dot) + h.perp2;
    let q = h.len2 / t; // 1/(cos²θ (α² + tan²θ))
    let d = F::splat(a2 * std::f32::consts::FRAC_1_PI) * (q * q);
    F::select(h.n_dot.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Anisotropic GGX `D` [1/sr] for a unit half vector in the local frame (x = tangent, z = normal):
/// `1 / (π αx αy cos⁴θ (1 + tan²θ (cos²φ/αx² + sin²φ/αy²))²)`, written without trigonometry as
/// `1 / (π αx αy (hx²/αx² + hy²/αy² + hz²)²)` (pbrt-v4 `TrowbridgeReitzDistribution::D`).
#[inline]
pub fn d_aniso(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    d_aniso_lanes(V3::from(h), alpha_x, alpha_y)
}

/// [`d_aniso`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_aniso_lanes<F: Lane>(h: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let x = h.x / F::splat(ax);
    let y = h.y / F::splat(ay);
    let t = x * x + y * y + h.z * h.z;
    let d = F::splat(std::f32::consts::FRAC_1_PI) / (F::splat(ax * ay) * t * t);
    F::select(h.z.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Smith `Λ` of GGX for a direction at `cos_theta` = n·w: `Λ = (√(1 + α² tan²θ) − 1)/2`
/// (Walter et al. 2007 eq. 34 via G1 = 1/(1+Λ); Heitz 2014). +∞ for `cos_theta ≤ 0`.
#[inline]
pub fn lambda(cos_theta: f32, alpha: f32) -> f32 {
    lambda_lanes(cos_theta, alpha)
}

/// [`lambda`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_lanes<F: Lane>(cos_theta: F, alpha: f32) -> F {
    let a = alpha.max(ALPHA_MIN);
    let c2 = (cos_theta * cos_theta).min(F::splat(1.0));
    let s2 = F::splat(1.0) - c2;
    let a2_tan2 = F::splat(a * a) * s2 / c2;
    lambda_from_a2_tan2(cos_theta, a2_tan2, || F::splat(a) * s2.sqrt() / cos_theta.abs())
}

/// `Λ = (√(1 + α² tan²θ) − 1)/2`, +∞ where `cos θ ≤ 0`.
///
/// Near grazing, `α² tan²θ` overflows float32 (at `cos θ = 10⁻²⁰`, say) long before `Λ ≈ α tanθ/2`
/// does: past 10³⁰ (where `√(1 + q) − 1 = √q` to float32 precision) `Λ` is taken from `a_tan() = α tanθ`
/// instead, and a `Λ` beyond float32 saturates at `f32::MAX` (so `G1 = 1/(1 + Λ)` is still 0, and a
/// direction above the surface never gets the +∞ that means "below").
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn lambda_from_a2_tan2<F: Lane>(cos_theta: F, a2_tan2: F, a_tan: impl Fn() -> F) -> F {
    let half = F::splat(0.5);
    let l = half * ((F::splat(1.0) + a2_tan2).sqrt() - F::splat(1.0));
    let huge = a2_tan2.gt(F::splat(1e30));
    let l = if F::mask_all(!huge) { l } else { F::select(huge, half * a_tan(), l) };
    F::select(cos_theta.gt(F::splat(0.0)), l.min(F::splat(f32::MAX)), F::splat(f32::INFINITY))
}

/// Anisotropic Smith `Λ` of GGX for a unit local direction: α² tan²θ →
/// `(wx² αx² + wy² αy²)/wz²` (α projected on the direction's azimuth; pbrt-v4 `Lambda`).
#[inline]
pub fn lambda_aniso(w: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    lambda_aniso_lanes(V3::from(w), alpha_x, alpha_y)
}

/// [`lambda_aniso`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_aniso_lanes<F: Lane>(w: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let (ax, ay) = (F::splat(alpha_x.max(ALPHA_MIN)), F::splat(alpha_y.max(ALPHA_MIN)));
    let (x, y) = (w.x * ax, w.y * ay);
    let r2 = x * x + y * y;
    lambda_from_a2_tan2(w.z, r2 / (w.z * w.z), || r2.sqrt() / w.z.abs())
}

/// Smith masking of one direction for GGX, `G1 = 1/(1 + Λ) = 2/(1 + √(1 + α² tan²θ))`
/// (Walter et al. 2007 eq. 34). 0 for `cos_theta ≤ 0`, 1 at normal incidence.
#[inline]
pub fn g1(cos_theta: f32, alpha: f32) -> f32 {
    1.0 / (1.0 + lambda(cos_theta, alpha))
}

/// Height-correlated Smith visibility of GGX, `V = G2/(4 (n·l)(n·v))` with
/// `G2 = 1/(1 + Λ(l) + Λ(v))` (Heitz 2014, "Understanding the Masking-Shadowing Function"):
/// `V = 0.5 / ((n·v) √((n·l)²(1 − α²) + α²) + (n·l) √((n·v)²(1 − α²) + α²))`.
/// The form the Cook–Torrance hot path uses: two square roots, one division, no tan. 0 unless both
/// cosines are positive.
#[inline]
pub fn visibility_height_correlated(nl: f32, nv: f32, alpha: f32) -> f32 {
    visibility_height_correlated_lanes(nl, nv, alpha)
}

/// [`visibility_height_correlated`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn visibility_height_correlated_lanes<F: Lane>(nl: F, nv: F, alpha: f32) -> F {
    let (ll, lv) = lambda_roots(nl, nv, alpha);
    let v = F::splat(0.5) / (nv * ll + nl * lv);
    F::select(both_positive(nl, nv), v, F::splat(0.0))
}

/// `√((n·l)²(1 − α²) + α²)` and the same for `n·v`: `(n·w) √(1 + α² tan²θ_w)`, the root in both GGX
/// visibility forms.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn lambda_roots<F: Lane>(nl: F, nv: F, alpha: f32) -> (F, F) {
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let (one_minus_a2, a2) = (F::splat(1.0 - a2), F::splat(a2));
    ((nl * nl * one_minus_a2 + a2).sqrt(), (nv * nv * one_minus_a2 + a2).sqrt())
}

#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn both_positive<F: Lane>(nl: F, nv: F) -> F::Mask {
    nl.gt(F::splat(0.0)) & nv.gt(F::splat(0.0))
}

/// Separable Smith visibility of GGX, `V = G1(l) G1(v)/(4 (n·l)(n·v))`
/// `= 1/((n·l + √((n·l)²(1 − α²) + α²)) (n·v + √((n·v)²(1 − α²) + α²)))` (Walter et al. 2007). 0 unless both cosines are positive.
#[inline]
pub fn visibility_separable(nl: f32, nv: f32, alpha: f32) -> f32 {
    visibility_separable_lanes(nl, nv, alpha)
}

/// [`visibility_separable`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn visibility_separable_lanes<F: Lane>(nl: F, nv: F, alpha: f32) -> F {
    let (ll, lv) = lambda_roots(nl, nv, alpha);
    let v = F::splat(1.0) / ((nl + ll) * (nv + lv));
    F::select(both_positive(nl, nv), v, F::splat(0.0))
}
