//! Ward's elliptical Gaussian (Ward 1992).
//!
//! Course texts print `D_w(h) = exp(−tan²δ (cos²φ/αx² + sin²φ/αy²)) / (π αx αy)`. That function is the
//! *slope* distribution P₂₂ (it integrates to 1 over the plane of slopes, [`slope_pdf`]), not a
//! microfacet D: because `dω_h = cos³θ d(slope)`, `∫ P₂₂ cosθ dω_h < 1`. The normalised
//! distribution of normals is `D = P₂₂ / cos⁴θ`, which is exactly the anisotropic Beckmann
//! distribution (Walter 2005 "Notes on the Ward BRDF"; Walter et al. 2007), so [`d`] calls
//! [`crate::microfacet::beckmann::d_aniso`] — one implementation of that formula. Ward's BRDF
//! (`models::ward`) uses [`slope_pdf`] with its own `1/(4 √(cosθ_i cosθ_o))` factor.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, beckmann};
use crate::simd::{Lane, V3};

/// Normalised anisotropic Ward distribution of normals [1/sr] for a unit local half vector
/// (z = normal): `P₂₂/cos⁴θ` = anisotropic Beckmann ([`beckmann::d_aniso`]).
#[inline]
pub fn d(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    beckmann::d_aniso(h, alpha_x, alpha_y)
}

/// Normalised isotropic Ward distribution [1/sr] at `cos_h`: `exp(−tan²θ/α²)/(π α² cos⁴θ)`
/// (= isotropic Beckmann).
#[inline]
pub fn d_iso(cos_h: f32, alpha: f32) -> f32 {
    beckmann::d(cos_h, alpha)
}

/// The Ward function as course texts print it, the slope distribution
/// `P₂₂ = exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy)` (per unit slope-plane area, not per steradian;
/// hx/hz and hy/hz are the two slopes). 0 for `hz ≤ 0`.
#[inline]
pub fn slope_pdf(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    slope_pdf_lanes(V3::from(h), alpha_x, alpha_y)
}

/// [`slope_pdf`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn slope_pdf_lanes<F: Lane>(h: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let e = slopes2(h, alpha_x, alpha_y) / (h.z * h.z);
    gaussian_of(h, e, alpha_x, alpha_y)
}

/// `hx²/αx² + hy²/αy²` (floors applied).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn slopes2<F: Lane>(h: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let (x, y) = (h.x / F::splat(alpha_x.max(ALPHA_MIN)), h.y / F::splat(alpha_y.max(ALPHA_MIN)));
    x * x + y * y
}

/// `exp(−e)/(π αx αy)`, 0 for `hz ≤ 0`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn gaussian_of<F: Lane>(h: V3<F>, e: F, alpha_x: f32, alpha_y: f32) -> F {
    let norm = std::f32::consts::FRAC_1_PI / (alpha_x.max(ALPHA_MIN) * alpha_y.max(ALPHA_MIN));
    F::select(h.z.gt(F::splat(0.0)), e.exp_neg_normal() * F::splat(norm), F::splat(0.0))
}

/// Ward 1992's "computationally convenient" form of the same Gaussian (his eq. 5b):
/// `exp(−2 (hx²/αx² + hy²/αy²)/(1 + hz)) / (π αx αy)` for a unit local half vector. It is *not*
/// identical to [`slope_pdf`]: `2(1 − cos δ)` stands in for `tan²δ` (equal to second order in the
/// half-angle δ), so the two agree near the peak and part for wide lobes; the `ward` model offers it
/// as `normalization = "ward"`. 0 for `hz ≤ 0`.
#[inline]
pub fn slope_pdf_ward1992(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    slope_pdf_ward1992_lanes(V3::from(h), alpha_x, alpha_y)
}

/// [`slope_pdf_ward1992`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn slope_pdf_ward1992_lanes<F: Lane>(h: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let e = F::splat(2.0) * slopes2(h, alpha_x, alpha_y) / (F::splat(1.0) + h.z);
    gaussian_of(h, e, alpha_x, alpha_y)
}
