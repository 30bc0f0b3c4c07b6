//! Transcendental functions on lanes: `exp`, `ln`, `pow`, trigonometry and its inverses, `erf`,
//! each written once, generic over [`Lane`], so that one sample (`f32`) and eight lanes give the same
//! bits (see [`crate::simd`]).
//!
//! Call them as [`Lane`] methods in generic code (`x.exp()`, `x.powf(y)`, `y.atan2(x)` with
//! `x: F`, `F: Lane`). On a concrete `f32` the inherent `f32::exp` of the standard library wins
//! method resolution: write `Lane::exp(x)` there if the value must equal a lane's bit for bit.
//!
//! | function | method | domain (inputs outside give) | max error, ulp | file |
//! |---|---|---|---|---|
//! | [`Lane::exp`] | Cody–Waite + Cephes `expf` | all x (0 below −103.97, +∞ above 88.72) | 0.96 | `exp_log.rs` |
//! | [`Lane::exp2`] | Cephes `exp2f` | all x (0 below −150, +∞ from 128) | 1.19 | `exp_log.rs` |
//! | [`Lane::ln`] | Cephes `logf` | x ≥ 0, subnormals too (−∞ at ±0, NaN for x < 0) | 0.81 | `exp_log.rs` |
//! | [`Lane::log2`] | `e + ln(m) log₂e` | as `ln` | 1.74 | `exp_log.rs` |
//! | [`Lane::ln_1p`] | Goldberg's `ln(u) x/(u − 1)` | x ≥ −1 (−∞ at −1, NaN below) | 2.38 | `exp_log.rs` |
//! | [`Lane::powf`] | `2^(y log₂x)` in float64 lanes | x ≥ 0 (−0 is +0; NaN for x < 0) | 0.51 | `exp_log.rs` |
//! | [`Lane::powf_uniform`] | one y for all lanes: binary powering in float64 for integer y in [1, 2¹⁶], else `powf` | as `powf` | 0.51 | `exp_log.rs` |
//! | [`Lane::sin`], [`Lane::cos`], [`Lane::sin_cos`] | float64 Cody–Waite + Cephes | \|x\| ≤ 1.6 · 10⁶ (finite in [−1, 1] beyond; NaN at ±∞) | 1.53 | `trig.rs` |
//! | [`Lane::tan`] | as `sin`, Cephes `tanf` | as `sin` | 2.63 | `trig.rs` |
//! | [`Lane::asin`] / [`Lane::acos`] | Cephes `asinf` | \|x\| ≤ 1 (NaN outside) | 2.26 / 1.12 | `inverse_trig.rs` |
//! | [`Lane::atan`] / [`Lane::atan2`] | Cephes `atanf`, octants | all (IEEE signed-zero and ∞ cases) | 2.21 / 2.55 | `inverse_trig.rs` |
//! | [`Lane::erf`] / [`Lane::erfc`] | fitted polynomials, `e^{−x²}` without its rounding | all x | 1.23 / 4.69 | `erf.rs` |
//! | [`Lane::erfinv`] | Giles 2011 + one Newton step | \|x\| ≤ 1 (±∞ at ±1, NaN outside) | 2.78 | `erf.rs` |
//! | [`Lane::hypot`] | power-of-two scaling | all | 1.16 | this file |
//! | [`Lane::floor`], [`Lane::ceil`], [`Lane::round`], [`Lane::copysign`] | exact | all | 0 | this file |
//!
//! The errors are in ulps of the f32 result against float64 (the spacing of f32 at the float64
//! value; ∞ counts as 2¹²⁸ past `f32::MAX`), measured over every 61st float32 of the domain (and, for
//! two arguments, a grid of all floats and the hard regions of `powf`): `cargo run --release -p
//! brdf-core --example lane_math_ulps [stride]`. The tests of this module assert these bounds on a
//! sample of the domains and their hard regions in about a second. Special values (±0, ±∞, NaN)
//! give what the `f32` function of the same name in the standard library gives, except where the
//! table says otherwise (`powf` of a negative base, and the finite `sin` of huge arguments).
//!
//! Why not `wide`'s own `f32x8::exp`, `ln`, `pow_f32x8`, `sin`, … (ports of Agner Fog's VCL): they
//! exist only for `wide`'s vector types (scalar `f32` could not share them, and the AVX2 lane type
//! would have to go through `wide`'s SSE path), and they do not meet the contract: in `wide` 0.7.33
//! `exp(87.34)` is 0 (1.7 · 10⁷ ulps) and results below `f32::MIN_POSITIVE` flush to 0, `ln(0)` is
//! +∞, `pow_f32x8(0.8957, 799)` is 4 · 10⁶ ulps off, and `sin` 44 ulps at |x| ≈ 2000 (same example).

mod erf;
mod exp_log;
mod inverse_trig;
mod trig;

pub(crate) use erf::{erf, erfc, erfinv};
pub use exp_log::EXP_NEG_CUT;
pub(crate) use exp_log::{
    exp, exp_neg_normal, exp2, integer_exponent, ln, ln_1p, log2, one_minus_powi, powf, powf_uniform,
};
pub(crate) use inverse_trig::{acos, asin, atan, atan2};
pub(crate) use trig::{cos, sin, sin_cos, tan};

use super::Lane;

/// `√(x² + y²)`: both scaled by the same power of two so that the larger is in [1, 4) (exact), the
/// sum of squares cannot overflow or underflow, and the root is scaled back (one rounding where the
/// result is subnormal). +∞ if either is ±∞ (even with a NaN), as `f32::hypot`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn hypot<F: Lane>(x: F, y: F) -> F {
    let (x, y) = (x.abs(), y.abs());
    let big = x.max(y);
    let (_, e) = big.frexp();
    let e = e.max(F::splat(-126.0)).min(F::splat(126.0));
    let s = F::pow2i(-e);
    let (xs, ys) = (x * s, y * s);
    let h = (xs * xs + ys * ys).sqrt() * F::pow2i(e);
    let inf = F::splat(f32::INFINITY);
    F::select(x.eq(inf) | y.eq(inf), inf, h)
}

/// Below this every f32 is an integer.
const TWO_23: f32 = 8_388_608.0;

/// `(|x| rounded to the nearest integer, halves to even, |x| ≥ 2²³ or NaN)`: below 2²³,
/// `|x| + 2²³` has no fraction bits left and the subtraction is exact.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn round_abs<F: Lane>(x: F) -> (F, F::Mask) {
    let a = x.abs();
    let two23 = F::splat(TWO_23);
    ((a + two23) - two23, !a.lt(two23))
}

/// Largest integer ≤ x: the nearest integer, minus 1 where that is above x; the sign of x kept
/// (floor(−0.5) = −1, floor(−0) = −0), and x itself where it is already an integer (|x| ≥ 2²³, ±∞)
/// or NaN.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn floor<F: Lane>(x: F) -> F {
    let (t, whole) = round_abs(x);
    let t = t.copysign(x);
    let f = F::select(t.gt(x), t - F::splat(1.0), t).copysign(x);
    F::select(whole, x, f)
}

/// Smallest integer ≥ x (as [`floor`]: ceil(−0.5) = −0).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn ceil<F: Lane>(x: F) -> F {
    let (t, whole) = round_abs(x);
    let t = t.copysign(x);
    let c = F::select(t.lt(x), t + F::splat(1.0), t).copysign(x);
    F::select(whole, x, c)
}

/// Nearest integer, halves away from zero (`f32::round`): the even rounding of |x|, plus 1 where
/// |x| was exactly halfway (|x| − t is exact).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn round<F: Lane>(x: F) -> F {
    let (t, whole) = round_abs(x);
    let t = F::select((x.abs() - t).eq(F::splat(0.5)), t + F::splat(1.0), t);
    F::select(whole, x, t.copysign(x))
}

#[cfg(test)]
mod tests;
