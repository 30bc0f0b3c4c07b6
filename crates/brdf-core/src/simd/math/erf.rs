//! The error function, its complement and its inverse.

use crate::simd::Lane;

/// `erf x = x + x R(x²)` on |x| < 1: `R(u) = erf(√u)/√u − 1`, a degree-6 polynomial fitted for this
/// crate by Lawson's weighted least squares (near-minimax, relative error 1.4 · 10⁻⁹ of erf with the
/// coefficients rounded to f32 one at a time, each refit around the rounded ones).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn erf_small<F: Lane>(x: F) -> F {
    let u = x * x;
    let mut r = F::splat(7.806_903e-5);
    for c in [-7.997_853e-4, 5.187_162_2e-3, -2.685_334_7e-2, 1.128_357_9e-1, -3.761_262_6e-1, 1.283_791_7e-1]
    {
        r = r * u + F::splat(c);
    }
    x + x * r
}

/// `e^{−x²}` for 0 ≤ x ≤ 11 without the rounding of x²: `x² = p + δ` exactly (Dekker's product with
/// Veltkamp's split of x into 12 + 12 bits), and `e^{−x²} = e^{−p} (1 − δ)` to second order in
/// |δ| ≤ 2⁻²⁴ p (the rounding of p would otherwise cost up to 121 · 2⁻²⁴ relative, 60 ulps).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn exp_neg_square<F: Lane>(x: F) -> F {
    let p = x * x;
    let c = x * F::splat(4097.0);
    let hi = c - (c - x);
    let lo = x - hi;
    let delta = ((hi * hi - p) + F::splat(2.0) * hi * lo) + lo * lo;
    (-p).exp() * (F::splat(1.0) - delta)
}

/// `erfc x = e^{−x²} G(s)/(x + 2)` for 0.5 ≤ x ≤ 11 (0 where it underflows), `s = (x − 2)/(x + 2)`:
/// W. H. Press et al., *Numerical Recipes* (3rd ed., 2007) §6.2.2 write `erfc` on this variable
/// (`t = 2/(2 + x)`) as a Chebyshev series; here `G(s) = (x + 2) e^{x²} erfc x` (between 0.67 and
/// 1.54, so that Horner's rule does not cancel) is a degree-9 polynomial in s fitted for this crate on
/// [0.5, 10.06] as [`erf_small`] was (relative error 1.7 · 10⁻⁸; its f32 evaluation adds ≈ 2 · 10⁻⁷).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn erfc_large<F: Lane>(x: F) -> F {
    let x = x.min(F::splat(11.0));
    exp_neg_square(x) * erfcx_large(x)
}

/// The scaled complement `e^{x²} erfc x = G(s)/(x + 2)` of [`erfc_large`], for 0.5 ≤ x ≤ 11.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn erfcx_large<F: Lane>(x: F) -> F {
    let r = F::splat(1.0) / (x + F::splat(2.0));
    let s = (x - F::splat(2.0)) * r;
    let mut g = F::splat(-2.712_381e-5);
    for c in [
        -4.213_692_7e-4,
        -7.910_691e-4,
        2.965_016_5e-3,
        6.470_761_3e-3,
        -2.148_589_5e-2,
        -3.644_196e-2,
        2.794_704_4e-1,
        -6.871_606_7e-1,
        1.021_582_7,
    ] {
        g = g * s + F::splat(c);
    }
    g * r
}

/// `erf x`: [`erf_small`] for |x| < 1, else `±(1 − erfc |x|)`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn erf<F: Lane>(x: F) -> F {
    let a = x.abs();
    let one = F::splat(1.0);
    let r = F::select(a.lt(one), erf_small(x), (one - erfc_large(a)).copysign(x));
    F::select(x.eq(x), r, x)
}

/// `erfc x`: [`erfc_large`] for x ≥ ½, `1 − erf x` for −1 < x < ½, `2 − erfc |x|` for x ≤ −1.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn erfc<F: Lane>(x: F) -> F {
    let one = F::splat(1.0);
    let big = erfc_large(x.abs());
    let r = F::select(x.lt(-one), F::splat(2.0) - big, one - erf_small(x));
    let r = F::select(x.lt(F::splat(0.5)), r, big);
    F::select(x.eq(x), r, x)
}

/// Horner's rule for the nine coefficients `c` (highest degree first).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn horner9<F: Lane>(t: F, c: &[f32; 9]) -> F {
    let mut p = F::splat(c[0]);
    for &k in &c[1..] {
        p = F::splat(k) + p * t;
    }
    p
}

/// The inverse error function: `erfinv(erf x) = x`. M. Giles, "Approximating the erfinv function"
/// (GPU Computing Gems Jade, 2011), single-precision form: with `w = −ln((1 − x)(1 + x))`, a degree-8
/// polynomial in `w − 2.5` for `w < 5` (|x| ≲ 0.9966) and in `√w − 3` beyond, times x (up to ~60
/// ulps off), then one Newton step on [`erf`] (on [`erfc`] for |x| ≥ ½, where `1 − |x|` is exact and
/// the residual keeps its digits).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn erfinv<F: Lane>(x: F) -> F {
    let one = F::splat(1.0);
    let w = -((one - x) * (one + x)).ln();
    let central = horner9(
        w - F::splat(2.5),
        &[
            2.810_226_36e-8,
            3.432_739_39e-7,
            -3.523_387_7e-6,
            -4.391_506_54e-6,
            2.185_808_7e-4,
            -1.253_725_03e-3,
            -4.177_681_64e-3,
            2.466_407_27e-1,
            1.501_409_41,
        ],
    );
    let tail = horner9(
        w.sqrt() - F::splat(3.0),
        &[
            -2.002_142_57e-4,
            1.009_505_58e-4,
            1.349_343_22e-3,
            -3.673_428_44e-3,
            5.739_507_73e-3,
            -7.622_461_3e-3,
            9.438_870_47e-3,
            1.001_674_06,
            2.832_976_82,
        ],
    );
    let p = F::select(w.lt(F::splat(5.0)), central, tail);
    let y = p * x;
    let a = x.abs();
    let tail = (one - a) - erfc(y.abs()); // erf|y| − |x|, with the sign of x below
    let residual = F::select(a.lt(F::splat(0.5)), erf(y) - x, F::select(x.lt(F::splat(0.0)), -tail, tail));
    // erf'(y) = (2/√π) e^{−y²}.
    let y = y - residual * F::splat(0.886_226_9) * (y * y).exp();
    // |x| = 1: w = +∞, where the tail polynomial is −∞ (leading coefficient < 0): ±∞ by hand.
    // |x| > 1 gives the logarithm of a negative number: NaN.
    F::select(a.eq(one), x * F::splat(f32::INFINITY), y)
}
