//! Inverse trigonometric functions: `asin`, `acos`, `atan`, `atan2`, from the reductions and minimax
//! polynomials of Cephes `asinf.c`, `acosf.c`, `atanf.c` (S. L. Moshier, *Methods and Programs for
//! Mathematical Functions*, 1989): `asin` on [0, ½] directly and as `π/2 − 2 asin √((1 − |x|)/2)`
//! above; `atan` on [0, tan π/8] directly, `π/4 + atan((x − 1)/(x + 1))` up to tan 3π/8 and
//! `π/2 − atan(1/x)` beyond; `atan2` from `atan(min/max)` of |x|, |y| and the octant. The multiples
//! of π are added in two parts (an f32 and its rounding error) so that they cost no accuracy.

use crate::simd::Lane;

/// π/2, π/4 and π as f32 plus the f32 of their rounding errors.
const PIO2: (f32, f32) = (std::f32::consts::FRAC_PI_2, -4.371_139e-8);
const PIO4: (f32, f32) = (std::f32::consts::FRAC_PI_4, -2.185_569_4e-8);
const PI: (f32, f32) = (std::f32::consts::PI, -8.742_278e-8);

/// `c − v` for a two-part constant c (the small part first).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn minus<F: Lane>(c: (f32, f32), v: F) -> F {
    F::splat(c.0) + (F::splat(c.1) - v)
}

/// `c + v` for a two-part constant c (the small part first).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn plus<F: Lane>(c: (f32, f32), v: F) -> F {
    F::splat(c.0) + (F::splat(c.1) + v)
}

/// Cephes `asinf` on [0, ½]: asin w = w + w z P(z), z = w².
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn asin_poly<F: Lane>(w: F, z: F) -> F {
    let mut p = F::splat(4.216_32e-2);
    for c in [2.418_131_1e-2, 4.547_002_6e-2, 7.495_300_3e-2, 1.666_675_2e-1] {
        p = p * z + F::splat(c);
    }
    p * z * w + w
}

/// `(asin w, big)` for a = |x|: `big` where a > ½ and w = √((1 − a)/2) (so asin a = π/2 − 2 asin w).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn asin_core<F: Lane>(a: F) -> (F, F::Mask) {
    let big = a.gt(F::splat(0.5));
    let z = F::select(big, F::splat(0.5) * (F::splat(1.0) - a), a * a);
    let w = F::select(big, z.sqrt(), a);
    (asin_poly(w, z), big)
}

/// `asin x`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn asin<F: Lane>(x: F) -> F {
    let (p, big) = asin_core(x.abs());
    F::select(big, minus(PIO2, p + p), p).copysign(x)
}

/// `acos x`: `π/2 − asin x` for |x| ≤ ½, `2 asin √((1 − x)/2)` above ½, `π − 2 asin √((1 + x)/2)`
/// below −½.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn acos<F: Lane>(x: F) -> F {
    let (p, big) = asin_core(x.abs());
    let outer = F::select(x.lt(F::splat(0.0)), minus(PI, p + p), p + p);
    F::select(big, outer, minus(PIO2, p.copysign(x)))
}

/// Cephes `atanf` polynomial: atan t for |t| ≤ tan π/8, z = t².
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn atan_poly<F: Lane>(t: F) -> F {
    let z = t * t;
    let p = ((F::splat(8.053_744_5e-2) * z - F::splat(1.387_768_5e-1)) * z + F::splat(1.997_771_1e-1)) * z
        - F::splat(3.333_295e-1);
    p * z * t + t
}

/// atan a for a ≥ 0 (or NaN), by the three Cephes ranges.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn atan_abs<F: Lane>(a: F) -> F {
    let one = F::splat(1.0);
    let big = a.gt(F::splat(2.414_213_5));
    let mid = a.gt(F::splat(0.414_213_57));
    let t = F::select(big, -(one / a), F::select(mid, (a - one) / (a + one), a));
    let p = atan_poly(t);
    F::select(big, plus(PIO2, p), F::select(mid, plus(PIO4, p), p))
}

/// `atan x`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn atan<F: Lane>(x: F) -> F {
    atan_abs(x.abs()).copysign(x)
}

/// `atan2(y, x)`: `t = atan(min(|x|, |y|)/max(|x|, |y|))`, then `π/2 ∓ t` where |y| > |x| and
/// `π − t` where x is negative otherwise (the sign bit: x = −0 counts), with the sign of y. The ratio is 0 for
/// two zeros and 1 for two infinities, which gives IEEE's special cases (±0, ±π, ±π/4, ±3π/4, …).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn atan2<F: Lane>(y: F, x: F) -> F {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    let inf = F::splat(f32::INFINITY);
    let ratio = F::select(hi.eq(F::splat(0.0)), F::splat(0.0), lo / hi);
    let ratio = F::select(lo.eq(inf), F::splat(1.0), ratio);
    let t = atan_abs(ratio);
    // The octant: t, π/2 − t, π/2 + t or π − t (each constant added once, in two parts).
    let negative = x.has_bits(0x8000_0000);
    let steep = ay.gt(ax);
    let t = F::select(
        steep,
        F::select(negative, plus(PIO2, t), minus(PIO2, t)),
        F::select(negative, minus(PI, t), t),
    );
    // min/max return the other operand where one is NaN: NaN restored here.
    F::select(x.eq(x) & y.eq(y), t.copysign(y), x + y)
}
