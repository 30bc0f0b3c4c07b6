//! Sine, cosine and tangent: Cody–Waite reduction `x = q π/2 + r`, |r| ≤ π/4, done in float64 lanes
//! (π/2 in two parts, the first with 33 significant bits so that `q · PIO2_HI` is exact for
//! |q| < 2²⁰), then the minimax polynomials of Cephes `sinf.c`, `cosf.c`, `tanf.c` (S. L. Moshier,
//! *Methods and Programs for Mathematical Functions*, 1989) on the f32 rounding of r. The quadrant
//! q mod 4 comes from the low bits of `q + 1.5 · 2²³`. Accurate for |x| ≤ 2²⁰ π/2 ≈ 1.6 · 10⁶; beyond,
//! the reduction is inexact and the results are only kept in [−1, 1].

use crate::simd::{Lane, Lane64};

const PIO2_HI: f64 = 1.570_796_326_734_125_6;
const PIO2_LO: f64 = 6.077_100_506_506_192e-11;
/// 1.5 · 2²³ and 1.5 · 2⁵²: adding them rounds to an integer in f32 / f64.
const MAGIC32: f32 = 12_582_912.0;
const MAGIC64: f64 = 6_755_399_441_055_744.0;

/// `(r, t)`: `x = q π/2 + r` with |r| ≤ π/4 (+ rounding) and `t = q + 1.5 · 2²³`, whose bit 0 is
/// set for odd q and bit 1 for q mod 4 ∈ {2, 3}.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn reduce<F: Lane>(x: F) -> (F, F) {
    let (lo, hi) = x.widen();
    let ((r_lo, q_lo), (r_hi, q_hi)) = (reduce_wide(lo), reduce_wide(hi));
    (F::narrow(r_lo, r_hi), F::narrow(q_lo, q_hi) + F::splat(MAGIC32))
}

/// `(r, q)` of [`reduce`] in float64.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn reduce_wide<D: Lane64>(x: D) -> (D, D) {
    let q = (x * D::splat(std::f64::consts::FRAC_2_PI) + D::splat(MAGIC64)) - D::splat(MAGIC64);
    ((x - q * D::splat(PIO2_HI)) - q * D::splat(PIO2_LO), q)
}

/// `v` kept in [−1, 1] where x is finite (where the reduction has lost its accuracy too), NaN at ±∞.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn bounded<F: Lane>(x: F, v: F) -> F {
    let one = F::splat(1.0);
    F::select(x.is_finite(), v.max(-one).min(one), F::splat(f32::NAN))
}

/// Cephes `sinf` polynomial: sin r for |r| ≤ π/4, z = r².
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn sin_poly<F: Lane>(r: F, z: F) -> F {
    let p = (F::splat(-1.951_529_6e-4) * z + F::splat(8.332_161e-3)) * z - F::splat(1.666_665_5e-1);
    p * z * r + r
}

/// Cephes `cosf` polynomial: cos r for |r| ≤ π/4, z = r².
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn cos_poly<F: Lane>(z: F) -> F {
    let p = (F::splat(2.443_315_7e-5) * z - F::splat(1.388_731_6e-3)) * z + F::splat(4.166_664_6e-2);
    p * z * z - F::splat(0.5) * z + F::splat(1.0)
}

/// `(sin x, cos x)` from one reduction.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn sin_cos<F: Lane>(x: F) -> (F, F) {
    let (r, t) = reduce(x);
    let z = r * r;
    let (s, c) = (sin_poly(r, z), cos_poly(z));
    let odd = t.has_bits(1);
    // q ≡ 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
    let sin = F::select(odd, c, s);
    let cos = F::select(odd, s, c);
    let sin = F::select(t.has_bits(2), -sin, sin);
    let cos = F::select((t + F::splat(1.0)).has_bits(2), -cos, cos);
    // sin(±0) = ±0 (the polynomial's −0 + +0 would give +0).
    (F::select(x.eq(F::splat(0.0)), x, bounded(x, sin)), bounded(x, cos))
}

/// `sin x`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn sin<F: Lane>(x: F) -> F {
    sin_cos(x).0
}

/// `cos x`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn cos<F: Lane>(x: F) -> F {
    sin_cos(x).1
}

/// `tan x`: Cephes `tanf` polynomial for tan r, and `−1/tan r` in odd quadrants.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn tan<F: Lane>(x: F) -> F {
    let (r, t) = reduce(x);
    let z = r * r;
    let mut p = F::splat(9.385_402e-3);
    for c in [3.119_922_3e-3, 2.443_013_5e-2, 5.341_128e-2, 1.333_88e-1, 3.333_315_7e-1] {
        p = p * z + F::splat(c);
    }
    let tr = p * z * r + r;
    let v = F::select(t.has_bits(1), -(F::splat(1.0) / tr), tr);
    F::select(x.eq(F::splat(0.0)), x, F::select(x.is_finite(), v, F::splat(f32::NAN)))
}
