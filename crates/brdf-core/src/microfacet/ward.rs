//! Ward's elliptical Gaussian (Ward 1992; seed 001 "Isotropic Ward", "Anisotropic Ward").
//!
//! Seed 001 prints `D_w(h) = exp(−tan²δ (cos²φ/αx² + sin²φ/αy²)) / (π αx αy)`. That function is the
//! *slope* distribution P₂₂ (it integrates to 1 over the plane of slopes, [`slope_pdf`]), not a
//! microfacet D: because `dω_h = cos³θ d(slope)`, `∫ P₂₂ cosθ dω_h < 1`. The normalised
//! distribution of normals is `D = P₂₂ / cos⁴θ`, which is exactly the anisotropic Beckmann
//! distribution (Walter 2005 "Notes on the Ward BRDF"; Walter et al. 2007), so [`d`] calls
//! [`crate::microfacet::beckmann::d_aniso`] — one implementation of that formula. Ward's BRDF
//! (`models::ward`) uses [`slope_pdf`] with its own `1/(4 √(cosθ_i cosθ_o))` factor.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, beckmann};

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

/// Seed 001's printed Ward function, the slope distribution
/// `P₂₂ = exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy)` (per unit slope-plane area, not per steradian;
/// hx/hz and hy/hz are the two slopes). 0 for `hz ≤ 0`.
#[inline]
pub fn slope_pdf(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    if !(h.z > 0.0) {
        return 0.0;
    }
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let e = ((h.x / ax).powi(2) + (h.y / ay).powi(2)) / (h.z * h.z);
    (-e).exp() * std::f32::consts::FRAC_1_PI / (ax * ay)
}

/// Ward 1992's "computationally convenient" form of the same Gaussian (his eq. 5b):
/// `exp(−2 (hx²/αx² + hy²/αy²)/(1 + hz)) / (π αx αy)` for a unit local half vector. It is *not*
/// identical to [`slope_pdf`]: `2(1 − cos δ)` stands in for `tan²δ` (equal to second order in the
/// half-angle δ), so the two agree near the peak and part for wide lobes; the `ward` model offers it
/// as `normalization = "ward"`. 0 for `hz ≤ 0`.
#[inline]
pub fn slope_pdf_ward1992(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    if !(h.z > 0.0) {
        return 0.0;
    }
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let e = 2.0 * ((h.x / ax).powi(2) + (h.y / ay).powi(2)) / (1.0 + h.z);
    (-e).exp() * std::f32::consts::FRAC_1_PI / (ax * ay)
}
