//! Ashikhmin–Shirley anisotropic Phong distribution (Ashikhmin & Shirley 2000).
//!
//! Exponent `e(h) = nu cos²φ_h + nv sin²φ_h = (nu hx² + nv hy²)/(hx² + hy²)` (local frame, x = tangent).
//! Two normalisations of `(n·h)^e` are exact, and they answer different questions:
//! - [`pdf_h`] `= √((nu+1)(nv+1))/(2π) · (n·h)^e` integrates to 1 over the hemisphere *without* the
//!   cosine: it is AS2000's density of half vectors, the one their BRDF (`models::ashikhmin_shirley`)
//!   and their sampling routine use (the density of their warp is exactly this).
//! - [`d`] `= √((nu+2)(nv+2))/(2π) · (n·h)^e` satisfies the microfacet normalisation
//!   `∫ D cosθ dω = 1` (the extra cosine raises each exponent by one); it reduces to the normalised
//!   Blinn–Phong D for nu = nv.
//!
//! Some course texts print `√((e_x+1)(e_y+1)) (h·n)^…` without the 1/(2π) and with the pdf's constant.

use glam::Vec3A;

use crate::simd::{Lane, V3};

/// Exponent `nu cos²φ_h + nv sin²φ_h` for a unit local half vector; `(nu + nv)/2` at h = n, where
/// the power is 1 whatever the exponent.
#[inline]
pub fn exponent(h: Vec3A, nu: f32, nv: f32) -> f32 {
    exponent_lanes(V3::from(h), nu, nv)
}

/// [`exponent`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn exponent_lanes<F: Lane>(h: V3<F>, nu: f32, nv: f32) -> F {
    let (x2, y2) = (h.x * h.x, h.y * h.y);
    let s2 = x2 + y2;
    let e = (F::splat(nu) * x2 + F::splat(nv) * y2) / s2;
    F::select(s2.gt(F::splat(0.0)), e, F::splat(0.5 * (nu + nv)))
}

/// Microfacet-normalised AS distribution [1/sr]: `√((nu+2)(nv+2))/(2π) · (n·h)^e`; 0 for `hz ≤ 0`.
/// Exponents are clamped to ≥ 0.
#[inline]
pub fn d(h: Vec3A, nu: f32, nv: f32) -> f32 {
    d_lanes(V3::from(h), nu, nv)
}

/// [`d`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_lanes<F: Lane>(h: V3<F>, nu: f32, nv: f32) -> F {
    let (nu, nv) = (nu.max(0.0), nv.max(0.0));
    normalised_power(h, nu, nv, ((nu + 2.0) * (nv + 2.0)).sqrt())
}

/// `k/(2π) · (n·h)^e`, 0 for `hz ≤ 0`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn normalised_power<F: Lane>(h: V3<F>, nu: f32, nv: f32, k: f32) -> F {
    let c = h.z.min(F::splat(1.0));
    // Isotropic: one exponent for every lane (binary powering where it is an integer).
    let power = if nu == nv { c.powf_uniform(nu) } else { c.powf(exponent_lanes(h, nu, nv)) };
    let p = F::splat(k * (0.5 * std::f32::consts::FRAC_1_PI)) * power;
    F::select(h.z.gt(F::splat(0.0)), p, F::splat(0.0))
}

/// AS2000's half-vector density [1/sr]: `√((nu+1)(nv+1))/(2π) · (n·h)^e`, `∫ pdf_h dω_h = 1`;
/// 0 for `hz ≤ 0`. Exponents are clamped to ≥ 0.
#[inline]
pub fn pdf_h(h: Vec3A, nu: f32, nv: f32) -> f32 {
    pdf_h_lanes(V3::from(h), nu, nv)
}

/// [`pdf_h`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn pdf_h_lanes<F: Lane>(h: V3<F>, nu: f32, nv: f32) -> F {
    let (nu, nv) = (nu.max(0.0), nv.max(0.0));
    normalised_power(h, nu, nv, ((nu + 1.0) * (nv + 1.0)).sqrt())
}
