//! Beckmann distribution and its Smith Λ (Beckmann & Spizzichino 1963; Cook & Torrance 1982;
//! Walter et al. 2007 §5.1).
//!
//! `D(h) = exp(−tan²θ/α²) / (π α² cos⁴θ)`, normalised so that `∫ D(h) cosθ_h dω_h = 1`.
//! Course texts print `1/(4 m² cos⁴θ)` or `1/(m² cos⁴θ)`: both miss the π of the normalised
//! form (the 4 belongs with a π in the BRDF denominator; never pair 1/(π…) with π).
//!
//! Smith Λ: the exact form `Λ(a) = (erf(a) − 1)/2 + exp(−a²)/(2a√π)`, `a = 1/(α tanθ)` (Walter et
//! al. 2007 eq. 25), evaluated as `e^{−a²} (1/(a√π) − e^{a²} erfc a)/2` with the lane error
//! functions of [`crate::simd::math`] (relative error of a few f32 ulps in each term).
//! Walter et al. 2007's rational approximation is [`lambda_rational`] (used by Mitsuba / pbrt-v3);
//! the tests measure its error against the exact form.
//!
//! Every formula is written once, generic over [`Lane`] (`*_lanes`); the scalar functions are those
//! with `F = f32`.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, HalfVector};
use crate::simd::{Lane, V3, math};

/// Isotropic Beckmann `D` [1/sr] at `cos_h` = n·h, roughness α = RMS slope (clamped to ≥
/// [`ALPHA_MIN`]); 0 for `cos_h ≤ 0`.
#[inline]
pub fn d(cos_h: f32, alpha: f32) -> f32 {
    d_lanes(cos_h, alpha)
}

/// [`d`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_lanes<F: Lane>(cos_h: F, alpha: f32) -> F {
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let c2 = (cos_h * cos_h).min(F::splat(1.0));
    let tan2 = (F::splat(1.0) - c2) / c2;
    let d = (-tan2 / F::splat(a2)).exp() * F::splat(std::f32::consts::FRAC_1_PI) / (F::splat(a2) * c2 * c2);
    F::select(cos_h.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// Isotropic Beckmann `D` [1/sr] from the un-normalised half vector `h̃ = l + v` ([`HalfVector`]):
/// `exp(−tan²θ/α²)/(π α² cos⁴θ)` with `tan²θ = |h̃⊥|²/(n·h̃)²` and `1/cos²θ = |h̃|²/(n·h̃)²` — the same
/// function as [`d`], with no `1 − cos²θ` (accurate for nearly opposite `l`, `v`; see
/// [`crate::microfacet::half`]). 0 for `n·h̃ ≤ 0` and where the exponential underflows.
#[inline]
pub fn d_half(h: &HalfVector<f32>, alpha: f32) -> f32 {
    d_half_lanes(h, alpha)
}

/// [`d_half`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_half_lanes<F: Lane>(h: &HalfVector<F>, alpha: f32) -> F {
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let hn2 = h.n_dot * h.n_dot;
    let e = h.perp2 / (F::splat(a2) * hn2); // tan²θ/α²
    let sec2 = h.len2 / hn2; // 1/cos²θ
    let d = (-e).exp() * F::splat(std::f32::consts::FRAC_1_PI / a2) * (sec2 * sec2);
    // e^{−104} is below f32's smallest subnormal: D is 0 there, and 1/cos⁴θ may be huge (0 · ∞).
    F::select(h.n_dot.gt(F::splat(0.0)) & e.lt(F::splat(104.0)), d, F::splat(0.0))
}

/// Anisotropic Beckmann `D` [1/sr] for a unit local half vector (z = normal, x = tangent):
/// `exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy hz⁴)` (= `exp(−tan²θ (cos²φ/αx² + sin²φ/αy²))/(π αx αy
/// cos⁴θ)`; Ward 1992's elliptical Gaussian over the slope plane).
#[inline]
pub fn d_aniso(h: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    d_aniso_lanes(V3::from(h), alpha_x, alpha_y)
}

/// [`d_aniso`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_aniso_lanes<F: Lane>(h: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let z2 = h.z * h.z;
    let (x, y) = (h.x / F::splat(ax), h.y / F::splat(ay));
    let e = (x * x + y * y) / z2;
    let d = (-e).exp() * F::splat(std::f32::consts::FRAC_1_PI) / (F::splat(ax * ay) * z2 * z2);
    F::select(h.z.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// The error function `erf x` ([`Lane::erf`]: within 1.3 ulp of the float64 value).
#[inline]
pub fn erf(x: f32) -> f32 {
    Lane::erf(x)
}

/// Exact Beckmann Smith Λ as a function of `a = 1/(α tanθ)` (Walter et al. 2007 eq. 25 via
/// G1 = 1/(1+Λ)): `Λ = (erf(a) − 1)/2 + e^{−a²}/(2a√π) = e^{−a²} (1/(a√π) − e^{a²} erfc a)/2`, the
/// difference taken before the exponential underflows. 0 for `a = ∞` (normal incidence) and a > 9
/// (below f32's normals), +∞ for `a ≤ 0`.
#[inline]
pub fn lambda_of_a(a: f32) -> f32 {
    lambda_of_a_lanes(a)
}

/// [`lambda_of_a`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_of_a_lanes<F: Lane>(a: F) -> F {
    const INV_SQRT_PI: f32 = 0.564_189_6; // 1/√π
    let one = F::splat(1.0);
    let x = a.min(F::splat(9.0));
    let e = math::exp_neg_square(x);
    let inv = F::splat(INV_SQRT_PI) / x;
    // erfc x as 1 − erf x below ½ (no cancellation: Λ > 0.2 there); scaled erfc above.
    let small = e * inv - (one - math::erf_small(x));
    let large = e * (inv - math::erfcx_large(x));
    let v = (F::splat(0.5) * F::select(x.lt(F::splat(0.5)), small, large)).max(F::splat(0.0));
    let v = F::select(a.gt(F::splat(9.0)), F::splat(0.0), v);
    // A direction just above the horizon (a → 0⁺) has Λ ≈ 1/(2a√π) beyond float32: saturated, so that
    // +∞ keeps meaning "below the surface".
    F::select(a.gt(F::splat(0.0)), v.min(F::splat(f32::MAX)), F::splat(f32::INFINITY))
}

/// Exact Beckmann Smith Λ for a direction at `cos_theta` = n·w (see [`lambda_of_a`]).
#[inline]
pub fn lambda(cos_theta: f32, alpha: f32) -> f32 {
    lambda_lanes(cos_theta, alpha)
}

/// [`lambda`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_lanes<F: Lane>(cos_theta: F, alpha: f32) -> F {
    let c = cos_theta.min(F::splat(1.0));
    let sin = (F::splat(1.0) - c * c).max(F::splat(0.0)).sqrt();
    let l = lambda_of_a_lanes(c / (F::splat(alpha.max(ALPHA_MIN)) * sin));
    let l = F::select(sin.eq(F::splat(0.0)), F::splat(0.0), l);
    F::select(cos_theta.gt(F::splat(0.0)), l, F::splat(f32::INFINITY))
}

/// Anisotropic exact Beckmann Λ for a unit local direction: `a = wz / √(wx² αx² + wy² αy²)`.
#[inline]
pub fn lambda_aniso(w: Vec3A, alpha_x: f32, alpha_y: f32) -> f32 {
    lambda_aniso_lanes(V3::from(w), alpha_x, alpha_y)
}

/// [`lambda_aniso`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_aniso_lanes<F: Lane>(w: V3<F>, alpha_x: f32, alpha_y: f32) -> F {
    let (x, y) = (w.x * F::splat(alpha_x.max(ALPHA_MIN)), w.y * F::splat(alpha_y.max(ALPHA_MIN)));
    let s = (x * x + y * y).sqrt();
    let l = F::select(s.eq(F::splat(0.0)), F::splat(0.0), lambda_of_a_lanes(w.z / s));
    F::select(w.z.gt(F::splat(0.0)), l, F::splat(f32::INFINITY))
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
