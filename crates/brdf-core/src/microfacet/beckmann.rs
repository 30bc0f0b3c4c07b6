//! Beckmann distribution and its Smith Λ (Beckmann & Spizzichino 1963; Cook & Torrance 1982;
//! Walter et al. 2007 §5.1).
//!
//! `D(h) = exp(−tan²θ/α²) / (π α² cos⁴θ)`, normalised so that `∫ D(h) cosθ_h dω_h = 1`.
//! Course texts print `1/(4 m² cos⁴θ)` or `1/(m² cos⁴θ)`: both miss the π of the normalised
//! form (the 4 belongs with a π in the BRDF denominator; never pair 1/(π…) with π).
//!
//! Smith Λ: the exact form `Λ(a) = (erf(a) − 1)/2 + exp(−a²)/(2a√π)`, `a = 1/(α tanθ)` (Walter et
//! al. 2007 eq. 25), `G1 = 1/(1 + Λ)`. An error function and an exponential per direction made the
//! Beckmann family (Beckmann, and the Gaussian and Blinn–Phong lobes, which borrow its Λ) three
//! times slower than GGX, so it is evaluated as what it is numerically, a smooth function of `a`
//! that reaches 1 in float32: `G1 = a P(a)/Q(a)` on `[0, 3.6]` with P, Q of degree 6 fitted for
//! this crate (near-minimax in relative error, `scripts/fit_beckmann_g1.py`: 3.9e−9 with float64
//! coefficients, 3.7e−8 with the float32 ones, ≤ 3.8e−7 ≈ 6 float32 ulps evaluated in float32;
//! the tests bound it against a float64 erf), and `G1 = 1` (Λ = 0) from a = 3.6 on, where
//! `1 − G1 < 6.5e−9` rounds away in float32 anyway. Walter et al. 2007's own rational approximation
//! is [`lambda_rational`] (eq. 27, used by Mitsuba / pbrt-v3; 0.35 % off); the tests measure it too.
//!
//! Every formula is written once, generic over [`Lane`] (`*_lanes`); the scalar functions are those
//! with `F = f32`.

use glam::Vec3A;

use crate::microfacet::{ALPHA_MIN, HalfVector};
use crate::simd::math::EXP_NEG_CUT;
use crate::simd::{Lane, V3};

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
    let d = (tan2 / F::splat(a2)).exp_neg_normal() * F::splat(std::f32::consts::FRAC_1_PI)
        / (F::splat(a2) * c2 * c2);
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
    let d = e.exp_neg_normal() * F::splat(std::f32::consts::FRAC_1_PI / a2) * (sec2 * sec2);
    // D is 0 where the exponential is ([`Lane::exp_neg_normal`]), and 1/cos⁴θ may be huge there (0 · ∞).
    F::select(h.n_dot.gt(F::splat(0.0)) & e.lt(F::splat(EXP_NEG_CUT)), d, F::splat(0.0))
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
    let d = e.exp_neg_normal() * F::splat(std::f32::consts::FRAC_1_PI) / (F::splat(ax * ay) * z2 * z2);
    F::select(h.z.gt(F::splat(0.0)), d, F::splat(0.0))
}

/// The error function `erf x` ([`Lane::erf`]: within 1.3 ulp of the float64 value).
#[inline]
pub fn erf(x: f32) -> f32 {
    Lane::erf(x)
}

/// `G1 ≈ a P(a)/Q(a)` on `[0, A_ONE]` (module docs), `a⁰` first; fitted and rounded to float32 by
/// `scripts/fit_beckmann_g1.py`.
const G1_P: [f32; 7] =
    [3.5449076, -1.0447211, 1.175305, -0.18446685, 0.100970216, 0.0014746195, 0.00024643008];
const G1_Q: [f32; 7] = [1.0, 1.477743, 0.80919284, 0.24087456, 0.10117842, 0.04805882, 0.006968528];

/// From this `a = 1/(α tanθ)` on the Beckmann G1 is 1 in float32 (`1 − G1(3.6) = 6.4e−9 < 2⁻²⁵`).
pub const A_ONE: f32 = 3.6;

/// Horner's rule for the coefficients `c` (`x⁰` first).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn horner<F: Lane>(x: F, c: &[f32; 7]) -> F {
    let mut p = F::splat(c[6]);
    for &k in c[..6].iter().rev() {
        p = p * x + F::splat(k);
    }
    p
}

/// `(num, den)` with `G1(a) = num/den` (module docs): `(a P(a), Q(a))` below [`A_ONE`], `(1, 1)` from
/// it on (+∞ included). For `a ≥ 0`; both are positive for `a > 0` (a subnormal `a` may give
/// `num = 0`).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn g1_parts_lanes<F: Lane>(a: F) -> (F, F) {
    let x = a.min(F::splat(A_ONE));
    let one = F::splat(1.0);
    let flat = a.ge(F::splat(A_ONE));
    (F::select(flat, one, x * horner(x, &G1_P)), F::select(flat, one, horner(x, &G1_Q)))
}

/// Beckmann Smith Λ as a function of `a = 1/(α tanθ)` (Walter et al. 2007 eq. 25, through the
/// rational G1 of the module docs): `Λ = 1/G1 − 1 = (den − num)/num`. 0 from [`A_ONE`] on (normal
/// incidence, `a = ∞`, included), +∞ for `a ≤ 0` or NaN, `f32::MAX` where `a → 0⁺` overflows it.
#[inline]
pub fn lambda_of_a(a: f32) -> f32 {
    lambda_of_a_lanes(a)
}

/// [`lambda_of_a`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_of_a_lanes<F: Lane>(a: F) -> F {
    let (num, den) = g1_parts_lanes(a.max(F::splat(0.0)));
    let v = ((den - num) / num).max(F::splat(0.0)).min(F::splat(f32::MAX));
    F::select(a.gt(F::splat(0.0)), v, F::splat(f32::INFINITY))
}

/// `a = cos θ/(α sin θ)` for `0 < cos θ ≤ 1` (`+∞` at normal incidence).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn a_of_cos<F: Lane>(cos_theta: F, alpha: f32) -> F {
    let c = cos_theta.min(F::splat(1.0));
    let sin = (F::splat(1.0) - c * c).max(F::splat(0.0)).sqrt();
    c / (F::splat(alpha.max(ALPHA_MIN)) * sin)
}

/// The visibility `G/(4 (n·l)(n·v))` of height-correlated Smith masking, `G = 1/(1 + Λ(l) + Λ(v))`
/// (Heitz 2014), for isotropic Beckmann of RMS slope α, from `n·l`, `n·v`: with `G1 = num/den` per
/// direction, `G = num_l num_v/(den_l num_v + den_v num_l − num_l num_v)`, one division for the whole
/// term. 0 unless both cosines are positive.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn visibility_height_correlated_lanes<F: Lane>(nl: F, nv: F, alpha: f32) -> F {
    let zero = F::splat(0.0);
    let ((pl, ql), (pv, qv)) = (g1_parts_lanes(a_of_cos(nl, alpha)), g1_parts_lanes(a_of_cos(nv, alpha)));
    let num = pl * pv;
    // ≥ num (G1 ≤ 1 per direction): 0 only where both directions graze so closely that num underflows.
    let den = F::splat(4.0) * nl * nv * ((ql * pv + qv * pl) - num);
    F::select(nl.gt(zero) & nv.gt(zero) & den.gt(zero), num / den, zero)
}

/// The visibility `G1(l) G1(v)/(4 (n·l)(n·v))` of separable Smith masking (Walter et al. 2007 eq. 23)
/// for isotropic Beckmann, one division as [`visibility_height_correlated_lanes`].
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn visibility_separable_lanes<F: Lane>(nl: F, nv: F, alpha: f32) -> F {
    let zero = F::splat(0.0);
    let ((pl, ql), (pv, qv)) = (g1_parts_lanes(a_of_cos(nl, alpha)), g1_parts_lanes(a_of_cos(nv, alpha)));
    let den = F::splat(4.0) * nl * nv * (ql * qv);
    F::select(nl.gt(zero) & nv.gt(zero) & den.gt(zero), (pl * pv) / den, zero)
}

/// Beckmann Smith Λ for a direction at `cos_theta` = n·w (see [`lambda_of_a`]); +∞ for `cos_theta ≤ 0`.
#[inline]
pub fn lambda(cos_theta: f32, alpha: f32) -> f32 {
    lambda_lanes(cos_theta, alpha)
}

/// [`lambda`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn lambda_lanes<F: Lane>(cos_theta: F, alpha: f32) -> F {
    // a = +∞ at normal incidence, where Λ = 0.
    let l = lambda_of_a_lanes(a_of_cos(cos_theta, alpha));
    F::select(cos_theta.gt(F::splat(0.0)), l, F::splat(f32::INFINITY))
}

/// Anisotropic Beckmann Λ for a unit local direction: `a = wz / √(wx² αx² + wy² αy²)`.
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
/// renderers that use it. The models use [`lambda`] (eq. 25 to float32 precision).
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

/// Smith masking of one direction for Beckmann, `G1 = 1/(1 + Λ)` (eq. 25). 0 for `cos_theta ≤ 0`.
#[inline]
pub fn g1(cos_theta: f32, alpha: f32) -> f32 {
    1.0 / (1.0 + lambda(cos_theta, alpha))
}
