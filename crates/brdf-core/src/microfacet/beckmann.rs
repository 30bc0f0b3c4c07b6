//! Beckmann distribution and its Smith Λ (Beckmann & Spizzichino 1963; Cook & Torrance 1982;
//! Walter et al. 2007 §5.1; seeds 001, 002, 004; notes (b1)).
//!
//! `D(h) = exp(−tan²θ/α²) / (π α² cos⁴θ)`, normalised so that `∫ D(h) cosθ_h dω_h = 1`.
//! Seed 002 prints `1/(4 m² cos⁴θ)` and seed 004 `1/(m² cos⁴θ)`: both miss the π of the normalised
//! form (the 4 of seed 002 belongs with a π in the BRDF denominator; never pair 1/(π…) with π).
//!
//! Smith Λ: the exact form `Λ(a) = (erf(a) − 1)/2 + exp(−a²)/(2a√π)`, `a = 1/(α tanθ)`, with `erf`
//! from Abramowitz & Stegun 7.1.26 (absolute error ≤ 1.5e−7, below f32 resolution of G1).
//! Walter et al. 2007's rational approximation is [`lambda_rational`] (used by Mitsuba / pbrt-v3);
//! the tests measure its error against the exact form.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, HalfVector};

/// Isotropic Beckmann `D` [1/sr] at `cos_h` = n·h, roughness α = RMS slope (clamped to ≥
/// [`ALPHA_MIN`]); 0 for `cos_h ≤ 0`.
#[inline]
pub fn d(cos_h: f32, alpha: f32) -> f32 {
    if !(cos_h > 0.0) {
        return 0.0;
    }
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let c2 = (cos_h * cos_h).min(1.0);
    let tan2 = (1.0 - c2) / c2;
    (-tan2 / a2).exp() * std::f32::consts::FRAC_1_PI / (a2 * c2 * c2)
}

/// Isotropic Beckmann `D` [1/sr] from the un-normalised half vector `h̃ = l + v` ([`HalfVector`]):
/// `exp(−tan²θ/α²)/(π α² cos⁴θ)` with `tan²θ = |h̃⊥|²/(n·h̃)²` and `1/cos²θ = |h̃|²/(n·h̃)²` — the same
/// function as [`d`], with no `1 − cos²θ` (accurate for nearly opposite `l`, `v`; see
/// [`crate::microfacet::half`]). 0 for `n·h̃ ≤ 0` and where the exponential underflows.
#[inline]
pub fn d_half(h: &HalfVector<f32>, alpha: f32) -> f32 {
    if !(h.n_dot > 0.0) {
        return 0.0;
    }
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let hn2 = h.n_dot * h.n_dot;
    let e = h.perp2 / (a2 * hn2); // tan²θ/α²
    // e^{−104} is below f32's smallest subnormal: D is 0 there, and 1/cos⁴θ may be huge (0 · ∞).
    if !(e < 104.0) {
        return 0.0;
    }
    let sec2 = h.len2 / hn2; // 1/cos²θ
    (-e).exp() * std::f32::consts::FRAC_1_PI / a2 * (sec2 * sec2)
}

/// Anisotropic Beckmann `D` [1/sr] for a unit local half vector (z = normal, x = tangent):
/// `exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy hz⁴)` (= `exp(−tan²θ (cos²φ/αx² + sin²φ/αy²))/(π αx αy
/// cos⁴θ)`, notes (b1); Ward 1992's elliptical Gaussian over the slope plane).
#[inline]
pub fn d_aniso(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    if !(h.z > 0.0) {
        return 0.0;
    }
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let z2 = h.z * h.z;
    let e = ((h.x / ax).powi(2) + (h.y / ay).powi(2)) / z2;
    (-e).exp() * std::f32::consts::FRAC_1_PI / (ax * ay * z2 * z2)
}

/// The error function, Abramowitz & Stegun 7.1.26: `erf(x) = 1 − (a₁t + … + a₅t⁵) e^{−x²}`,
/// `t = 1/(1 + p x)`, absolute error ≤ 1.5e−7 for x ≥ 0; odd extension for x < 0.
#[inline]
pub fn erf(x: f32) -> f32 {
    let y = 1.0 - erfc_poly(x.abs()) * (-x * x).exp();
    y.copysign(x)
}

/// The A&S 7.1.26 polynomial `a₁t + … + a₅t⁵`, `t = 1/(1 + 0.3275911 x)`; `erfc(x) ≈ poly · e^{−x²}`.
#[inline]
fn erfc_poly(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    t * (0.254_829_6 + t * (-0.284_496_74 + t * (1.421_413_8 + t * (-1.453_152 + t * 1.061_405_4))))
}

/// Exact Beckmann Smith Λ as a function of `a = 1/(α tanθ)` (Walter et al. 2007 eq. 25 via
/// G1 = 1/(1+Λ)): `Λ = (erf(a) − 1)/2 + e^{−a²}/(2a√π) = e^{−a²} (1/(2a√π) − poly(a)/2)`, with the
/// A&S polynomial so that the difference of nearly equal terms is taken before the exponential
/// underflows. 0 for `a = ∞` (normal incidence), +∞ for `a ≤ 0`.
#[inline]
pub fn lambda_of_a(a: f32) -> f32 {
    if !(a > 0.0) {
        return f32::INFINITY;
    }
    if a > 9.0 {
        // e^{−81} is below f32's smallest normal: Λ is 0 to f32 precision.
        return 0.0;
    }
    const INV_2_SQRT_PI: f32 = 0.282_094_8; // 1/(2√π)
    let v = (-a * a).exp() * (INV_2_SQRT_PI / a - 0.5 * erfc_poly(a));
    v.max(0.0)
}

/// Exact Beckmann Smith Λ for a direction at `cos_theta` = n·w (see [`lambda_of_a`]).
#[inline]
pub fn lambda(cos_theta: f32, alpha: f32) -> f32 {
    if !(cos_theta > 0.0) {
        return f32::INFINITY;
    }
    let c = cos_theta.min(1.0);
    let sin = (1.0 - c * c).max(0.0).sqrt();
    if sin == 0.0 {
        return 0.0;
    }
    lambda_of_a(c / (alpha.max(ALPHA_MIN) * sin))
}

/// Anisotropic exact Beckmann Λ for a unit local direction: `a = wz / √(wx² αx² + wy² αy²)`.
#[inline]
pub fn lambda_aniso(w: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    if !(w.z > 0.0) {
        return f32::INFINITY;
    }
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let s = ((w.x * ax).powi(2) + (w.y * ay).powi(2)).sqrt();
    if s == 0.0 {
        return 0.0;
    }
    lambda_of_a(w.z / s)
}

/// Walter et al. 2007 eq. 27's rational approximation of the Beckmann Λ:
/// `Λ ≈ (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²)` for `a < 1.6`, else 0. Its error against
/// [`lambda`] is measured in the tests (G1 within 0.4 % absolute); offered for comparison with
/// renderers that use it. The models use the exact [`lambda`].
#[inline]
pub fn lambda_rational(cos_theta: f32, alpha: f32) -> f32 {
    if !(cos_theta > 0.0) {
        return f32::INFINITY;
    }
    let c = cos_theta.min(1.0);
    let sin = (1.0 - c * c).max(0.0).sqrt();
    if sin == 0.0 {
        return 0.0;
    }
    let a = c / (alpha.max(ALPHA_MIN) * sin);
    if a >= 1.6 {
        return 0.0;
    }
    (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
}

/// Smith masking of one direction for Beckmann, `G1 = 1/(1 + Λ)` (exact Λ). 0 for `cos_theta ≤ 0`.
#[inline]
pub fn g1(cos_theta: f32, alpha: f32) -> f32 {
    1.0 / (1.0 + lambda(cos_theta, alpha))
}
