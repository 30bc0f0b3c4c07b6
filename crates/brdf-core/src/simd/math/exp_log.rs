//! Exponentials and logarithms: `exp`, `exp2`, `ln`, `log2`, `ln_1p`, `powf`.
//!
//! `exp`, `exp2`, `ln`: Cody–Waite argument reduction and the minimax polynomials of S. L. Moshier's
//! Cephes library (`expf.c`, `exp2f.c`, `logf.c`; Moshier, *Methods and Programs for Mathematical
//! Functions*, 1989), as used in most SIMD math libraries (e.g. Agner Fog's VCL): `eˣ = 2ⁿ eʳ` with
//! `n = round(x log₂e)` and `r = x − n ln2` in two parts (the high part has 9 significant bits, so
//! `n · LN2_HI` and the subtraction are exact for every n that occurs); `ln x = e ln2 + ln m` with
//! `m` in [√½, √2). `ln_1p` is Goldberg's correction `ln(u) · x/(u − 1)`, `u = 1 + x` (D. Goldberg,
//! "What every computer scientist should know about floating-point arithmetic", 1991, thm. 4).
//! `powf` evaluates `2^(y log₂x)` in float64 lanes (`Lane::Wide`): `log₂x` by the `atanh` series
//! `ln m = 2 (s + s³/3 + … + s¹³/13)`, `s = (m − 1)/(m + 1)`, and `2ʳ` by its Taylor series, both
//! truncated below 2⁻³² relative, so the float64 result is within 2⁻³⁰ of `xʸ` and one rounding to
//! f32 gives ≤ 1 ulp (0.5 + 2⁻⁶) even for `y log₂x` near ±150; a float32 logarithm would lose
//! `log₂|y log₂x|` bits there (up to 7), which the sharp Blinn–Phong lobes (exponents ~10³–10⁸)
//! amplify. `powf_uniform` is `powf` for one exponent shared by every lane, as the models have it
//! (a shininess, a lobe exponent): for integer y in [1, 2¹⁶] binary powering of the float64 x
//! (square and multiply, ≤ 2 log₂y products instead of a logarithm, an exponential and a division).
//! Each product rounds once, so x^k computed as x^i · x^j (i + j = k) carries at most k − 1 roundings
//! (by induction: (i − 1) + (j − 1) + 1), a relative error below (1 + 2⁻⁵³)^y − 1 < 2⁻³⁶ for
//! y ≤ 2¹⁶, and the one rounding to f32 gives ≤ 0.5 + 2⁻¹² ulp. No intermediate leaves float64's
//! range unless the result leaves float32's (every x^k lies between x and x^y). `one_minus_powi` is
//! the same binary powering of `1 − d` formed in float64 (one more rounding, within the same bound),
//! for Phong lobes written on the mirror deficit d.

use crate::simd::{Lane, Lane64};

const LOG2_E: f32 = std::f32::consts::LOG2_E;
/// ln 2 = LN2_HI + LN2_LO (Cephes); LN2_HI has 9 significant bits.
const LN2_HI: f32 = 0.693_359_375;
const LN2_LO: f32 = -2.121_944_4e-4;
/// 2²³: scales a subnormal into the normal range exactly.
const TWO_23: f32 = 8_388_608.0;

/// `round(x)` (halves to even) for |x| < 2²²: adding 1.5 · 2²³ leaves no fraction bits, and the
/// subtraction is exact.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn round_even<F: Lane>(x: F) -> F {
    let magic = F::splat(12_582_912.0);
    (x + magic) - magic
}

/// `p · 2ⁿ` for integer-valued n in [−151, 129], rounded once: `2ⁿ` in two exact factors
/// (`2ᵃ`, a in [−64, 127], then `2ⁿ⁻ᵃ`), so `p · 2ᵃ` is exact for p in [½, 2] and only the second
/// product rounds (into the subnormals, or to ∞).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn scale<F: Lane>(p: F, n: F) -> F {
    let a = n.max(F::splat(-64.0)).min(F::splat(127.0));
    p * F::pow2i(a) * F::pow2i(n - a)
}

/// `eˣ` (Cephes `expf`).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn exp<F: Lane>(x: F) -> F {
    // Beyond these e^x is 0 or ∞ in f32; the clamp keeps n in the range of `scale` (NaN → −104,
    // restored below).
    let xc = x.max(F::splat(-104.0)).min(F::splat(89.0));
    let n = round_even(xc * F::splat(LOG2_E));
    let r = (xc - n * F::splat(LN2_HI)) - n * F::splat(LN2_LO); // |r| ≤ 0.36
    let z = r * r;
    let mut p = F::splat(1.987_569_15e-4);
    for c in [1.398_199_95e-3, 8.333_451_9e-3, 4.166_579_6e-2, 1.666_666_55e-1, 5.000_000_1e-1] {
        p = p * r + F::splat(c);
    }
    let e = p * z + r + F::splat(1.0);
    F::select(x.eq(x), scale(e, n), x)
}

/// Where [`Lane::exp_neg_normal`] stops: `e^{−80} ≈ 1.8 · 10⁻³⁵`, so that its result, and that result's
/// products with a model's other factors (prefactors, G, F, cosines: rarely below 10⁻³ together), stay
/// normal floats.
pub const EXP_NEG_CUT: f32 = 80.0;

/// `e^{−x}` where `x <` [`EXP_NEG_CUT`], 0 from there on (+∞ included), NaN for NaN: the decaying
/// exponential of the Beckmann, Gaussian and Ward lobes without its last 24 binary orders of
/// magnitude. Those would be subnormal floats, and an operation with a subnormal operand or result
/// costs an x86 core a microcode assist of ~10² cycles: on random directions, at α = 0.3, the
/// Beckmann D ran 1.5× slower with them (`examples/batch_throughput.rs`). What is dropped is below
/// 2 · 10⁻³⁵ of the lobe's prefactor.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn exp_neg_normal<F: Lane>(x: F) -> F {
    let cut = F::splat(EXP_NEG_CUT);
    // Clamped first: the exponential of the dropped lanes must not make subnormals either.
    let e = exp(x.min(cut) * F::splat(-1.0));
    F::select(x.ge(cut), F::splat(0.0), F::select(x.eq(x), e, x))
}

/// `2ˣ` (Cephes `exp2f`): `2ⁿ · 2ʳ`, `n = round(x)`, `r = x − n` exact.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn exp2<F: Lane>(x: F) -> F {
    let xc = x.max(F::splat(-151.0)).min(F::splat(129.0));
    let n = round_even(xc);
    let r = xc - n; // |r| ≤ 1/2, exact
    let mut p = F::splat(1.535_336_2e-4);
    for c in [1.339_887_4e-3, 9.618_437_4e-3, 5.550_332_5e-2, 2.402_264_8e-1, 6.931_472e-1] {
        p = p * r + F::splat(c);
    }
    let e = p * r + F::splat(1.0);
    F::select(x.eq(x), scale(e, n), x)
}

/// `x = m · 2ᵉ` with m in [√½, √2) for positive finite x (subnormals scaled up first): the
/// reduction of every logarithm here.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn reduce<F: Lane>(x: F) -> (F, F) {
    let tiny = x.lt(F::splat(f32::MIN_POSITIVE));
    let (m, e) = F::select(tiny, x * F::splat(TWO_23), x).frexp();
    let e = F::select(tiny, e - F::splat(23.0), e);
    let big = m.gt(F::splat(std::f32::consts::SQRT_2));
    (F::select(big, m * F::splat(0.5), m), F::select(big, e + F::splat(1.0), e))
}

/// The logarithm's value where x is 0, negative, +∞ or NaN, and `r` elsewhere.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn ln_edges<F: Lane>(x: F, r: F) -> F {
    let inf = F::splat(f32::INFINITY);
    let edge = F::select(x.eq(F::splat(0.0)), -inf, F::select(x.eq(inf), inf, F::splat(f32::NAN)));
    F::select(x.gt(F::splat(0.0)) & x.lt(inf), r, edge)
}

/// `f·z·P(f)` of Cephes `logf`, z = f²: `ln(1 + f) − f + f²/2` for f in [√½ − 1, √2 − 1).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn ln_tail<F: Lane>(f: F, z: F) -> F {
    let mut p = F::splat(7.037_683_6e-2);
    for c in [
        -1.151_461e-1,
        1.167_699_9e-1,
        -1.242_014_1e-1,
        1.424_932_3e-1,
        -1.666_805_8e-1,
        2.000_071_4e-1,
        -2.499_999_4e-1,
        3.333_333_1e-1,
    ] {
        p = p * f + F::splat(c);
    }
    f * z * p
}

/// `ln x` (Cephes `logf`).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn ln<F: Lane>(x: F) -> F {
    let (m, e) = reduce(x);
    let f = m - F::splat(1.0);
    let z = f * f;
    let y = ln_tail(f, z) + e * F::splat(LN2_LO) - F::splat(0.5) * z;
    ln_edges(x, (f + y) + e * F::splat(LN2_HI))
}

/// `log₂ x = e + ln(m) log₂e`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn log2<F: Lane>(x: F) -> F {
    let (m, e) = reduce(x);
    let f = m - F::splat(1.0);
    let z = f * f;
    let lnm = f + (ln_tail(f, z) - F::splat(0.5) * z);
    ln_edges(x, lnm * F::splat(LOG2_E) + e)
}

/// `ln(1 + x)`: `x` where `1 + x` rounds to 1, else `ln(u) · x/(u − 1)` with `u = 1 + x` (the
/// quotient corrects the rounding of `u`).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn ln_1p<F: Lane>(x: F) -> F {
    let one = F::splat(1.0);
    let u = one + x;
    let r = ln(u) * (x / (u - one));
    let r = F::select(x.eq(F::splat(f32::INFINITY)), x, r);
    F::select(u.eq(one), x, r)
}

/// `xʸ` for x ≥ 0 (see the module docs for the method).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn powf<F: Lane>(x: F, y: F) -> F {
    let (m, e) = reduce(x);
    let (m, e, yw) = (m.widen(), e.widen(), y.widen());
    let t = (y_log2(m.0, e.0, yw.0), y_log2(m.1, e.1, yw.1));
    // y log₂x rounded to f32 picks n (|t − n| ≤ ½ + 2⁻¹⁷ where it matters) and the edge cases.
    let t32 = F::narrow(t.0, t.1);
    let n = round_even(t32.max(F::splat(-151.0)).min(F::splat(129.0)));
    let a = n.max(F::splat(-64.0)).min(F::splat(127.0));
    let (nw, pa, pb) = (n.widen(), F::pow2i(a).widen(), F::pow2i(n - a).widen());
    // 2ʳ · 2ᵃ · 2ⁿ⁻ᵃ is exact in float64; the one rounding is to f32 (also into the subnormals).
    let v = F::narrow(exp2_wide(t.0 - nw.0) * pa.0 * pb.0, exp2_wide(t.1 - nw.1) * pa.1 * pb.1);
    let (zero, one, inf) = (F::splat(0.0), F::splat(1.0), F::splat(f32::INFINITY));
    let v = F::select(t32.lt(F::splat(-151.0)), zero, v);
    let v = F::select(x.eq(zero), F::select(y.lt(zero), inf, zero), v);
    let v = F::select(x.eq(inf), F::select(y.lt(zero), zero, inf), v);
    let v = F::select(x.eq(x) & y.eq(y) & !x.lt(zero), v, F::splat(f32::NAN));
    F::select(x.eq(one) | y.eq(zero), one, v)
}

/// `y · log₂(m · 2ᵉ)` in float64 for m in [√½, √2): `ln m = 2 atanh(s)`, `s = (m − 1)/(m + 1)`,
/// |s| ≤ 0.1716, `w = s²` ≤ 0.0295, so the series to s¹³/13 leaves a relative error below 2⁻³⁹
/// (w⁷/15). Estrin's scheme: the products pair up, half the latency of Horner's rule.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn y_log2<D: Lane64>(m: D, e: D, y: D) -> D {
    let c = D::splat;
    let s = (m - c(1.0)) / (m + c(1.0));
    let w = s * s;
    let (w2, w4) = (w * w, w * w * (w * w));
    let p = (c(1.0) + w * c(1.0 / 3.0))
        + w2 * (c(1.0 / 5.0) + w * c(1.0 / 7.0))
        + w4 * ((c(1.0 / 9.0) + w * c(1.0 / 11.0)) + w2 * c(1.0 / 13.0));
    y * (e + s * p * c(2.0 * std::f64::consts::LOG2_E))
}

/// `2ʳ` in float64 for |r| ≤ ½ (a little more where `n` came from the rounded t): the Taylor series
/// of `e^{u}`, `u = r ln 2`, to degree 8 (the next term, u⁹/9! ≤ 2⁻³², is below the 2⁻³⁰ that keeps
/// the final rounding to f32 within 2⁻⁶ ulp of correct), by Estrin's scheme.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn exp2_wide<D: Lane64>(r: D) -> D {
    let c = D::splat;
    let u = r * c(std::f64::consts::LN_2);
    let (u2, u4) = (u * u, u * u * (u * u));
    let lo = (c(1.0) + u) + u2 * (c(1.0 / 2.0) + u * c(1.0 / 6.0));
    let hi = (c(1.0 / 24.0) + u * c(1.0 / 120.0)) + u2 * (c(1.0 / 720.0) + u * c(1.0 / 5040.0));
    lo + u4 * (hi + u4 * c(1.0 / 40320.0))
}

/// Largest exponent [`powf_uniform`] takes by binary powering (2¹⁶: the error bound of the module
/// docs, ≤ 32 products).
pub(crate) const POWI_MAX: u32 = 1 << 16;

/// `Some(n)` when `y` is an integer `n` in [1, [`POWI_MAX`]] (the exponents of binary powering).
#[inline(always)]
pub(crate) fn integer_exponent(y: f32) -> Option<u32> {
    ((1.0..=POWI_MAX as f32).contains(&y) && y == y.floor()).then_some(y as u32)
}

/// `xⁿ` for n ≥ 1 by binary powering in float64 lanes (module docs): the lowest set bit's power of
/// x starts the product, the higher ones multiply in.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn powi_wide<D: Lane64>(x: D, n: u32) -> D {
    let mut n = n;
    let mut base = x;
    while n & 1 == 0 {
        base = base * base;
        n >>= 1;
    }
    let mut acc = base;
    n >>= 1;
    while n > 0 {
        base = base * base;
        if n & 1 == 1 {
            acc = acc * base;
        }
        n >>= 1;
    }
    acc
}

/// `xʸ` with one exponent `y` for every lane: binary powering in float64 for integer y in
/// [1, [`POWI_MAX`]] (≤ 0.5 + 2⁻¹² ulp, module docs), else [`powf`]. Special values as [`powf`]:
/// −0 counts as +0, x < 0 gives NaN, NaN stays NaN, `0ʸ = 0` and `∞ʸ = ∞` for y ≥ 1.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn powf_uniform<F: Lane>(x: F, y: f32) -> F {
    let Some(n) = integer_exponent(y) else { return powf(x, F::splat(y)) };
    let (lo, hi) = x.abs().widen();
    let v = F::narrow(powi_wide(lo, n), powi_wide(hi, n));
    F::select(x.lt(F::splat(0.0)), F::splat(f32::NAN), v)
}

/// `(1 − d)ⁿ` for `d ≤ 1` and `n ≥ 1`, with `1 − d` formed in float64 (one rounding of 2⁻⁵³ relative at
/// most) and raised by binary powering (module docs): ≤ 0.5 + 2⁻¹² ulp for n ≤ [`POWI_MAX`], the only
/// error left being that of `d` itself. NaN for NaN d.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn one_minus_powi<F: Lane>(d: F, n: u32) -> F {
    let (lo, hi) = d.widen();
    let one = <F::Wide as Lane64>::splat(1.0);
    F::narrow(powi_wide(one - lo, n), powi_wide(one - hi, n))
}
