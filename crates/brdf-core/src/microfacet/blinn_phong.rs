//! Normalised Blinn–Phong distribution `D(h) = (m + 2)/(2π) · (n·h)^m` (Blinn 1977;
//! Walter et al. 2007 eq. 30).
//!
//! `∫ D cosθ dω = (m+2)/(2π) · 2π/(m+2) = 1` exactly. This is the *microfacet* normalisation; the
//! BRDF normalisation `(m+8)/(8π)` of the `blinn_phong` model is a different thing (Akenine-Möller et al., *Real-Time Rendering*).
//! Walter et al. 2007 relate the exponent to Beckmann's roughness by `m = 2/α² − 2`
//! ([`exponent_from_alpha`]); the same relation gives a Smith Λ for this D (see `masking`).

use crate::microfacet::{ALPHA_MIN, HalfVector};
use crate::simd::Lane;

/// Largest exponent used: the one of [`ALPHA_MIN`] (`2/α² − 2 ≈ 2e8`); keeps `(m+2)/(2π)` finite and
/// consistent with the roughness floor of the other distributions.
pub const EXPONENT_MAX: f32 = 2.0 / (ALPHA_MIN * ALPHA_MIN) - 2.0;

/// Blinn–Phong `D` [1/sr] at `cos_h` = n·h for exponent `m` (clamped to [0, [`EXPONENT_MAX`]]);
/// 0 for `cos_h ≤ 0`.
#[inline]
pub fn d(cos_h: f32, exponent: f32) -> f32 {
    d_lanes(cos_h, exponent)
}

/// [`d`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_lanes<F: Lane>(cos_h: F, exponent: f32) -> F {
    let m = exponent.clamp(0.0, EXPONENT_MAX);
    let d =
        F::splat((m + 2.0) * (0.5 * std::f32::consts::FRAC_1_PI)) * cos_h.min(F::splat(1.0)).powf_uniform(m);
    F::select(cos_h.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Blinn–Phong `D` [1/sr] from the un-normalised half vector `h̃ = l + v` ([`HalfVector`]):
/// `(n·h)^m = (1 + tan²θ)^{−m/2} = exp(−(m/2) ln(1 + tan²θ))` with `tan²θ = |h̃⊥|²/(n·h̃)²` — the same
/// function as [`d`], but `ln_1p` of an accurate `tan²θ` does not amplify the rounding of `n·h` by the
/// exponent m (up to ~800 at α = 0.05) as `powf(n·h, m)` does (and see [`crate::microfacet::half`]).
/// 0 for `n·h̃ ≤ 0`.
#[inline]
pub fn d_half(h: &HalfVector<f32>, exponent: f32) -> f32 {
    d_half_lanes(h, exponent)
}

/// [`d_half`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_half_lanes<F: Lane>(h: &HalfVector<F>, exponent: f32) -> F {
    let m = exponent.clamp(0.0, EXPONENT_MAX);
    let tan2 = h.tan2();
    // m = 0 is the uniform (n·h)⁰ = 1, also where tan²θ = ∞ (0 · ∞ would be NaN).
    // Flushed to 0 below e^{−80} (Lane::exp_neg_normal): the lobe's far tail, in subnormal floats, is slow.
    let power = if m == 0.0 { F::splat(1.0) } else { (F::splat(0.5 * m) * tan2.ln_1p()).exp_neg_normal() };
    let d = F::splat((m + 2.0) * (0.5 * std::f32::consts::FRAC_1_PI)) * power;
    F::select(h.n_dot.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Walter et al. 2007 §5.2: the Blinn–Phong exponent equivalent to Beckmann roughness α,
/// `m = 2/α² − 2`, clamped to [0, [`EXPONENT_MAX`]] (α ≥ √2 gives the uniform-projected-area m = 0).
#[inline]
pub fn exponent_from_alpha(alpha: f32) -> f32 {
    let a = alpha.max(ALPHA_MIN);
    (2.0 / (a * a) - 2.0).clamp(0.0, EXPONENT_MAX)
}

/// Inverse of [`exponent_from_alpha`]: `α = √(2/(m + 2))`.
#[inline]
pub fn alpha_from_exponent(exponent: f32) -> f32 {
    (2.0 / (exponent.clamp(0.0, EXPONENT_MAX) + 2.0)).sqrt()
}
