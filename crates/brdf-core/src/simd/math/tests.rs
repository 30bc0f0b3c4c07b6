//! The lane math contract: every lane type gives the bits of the `f32` instantiation, and special
//! values behave as documented on the [`Lane`] methods.

use super::super::{F32x4, F32x8, Lane, LaneKernel, run_widest};

/// Awkward inputs: signed zeros, subnormals, the ends of the normal range, ±1, ±∞, NaN, ordinary.
const SPECIALS: [f32; 24] = [
    0.0,
    -0.0,
    1e-45,
    -1e-45,
    1e-40,
    -3e-39,
    f32::MIN_POSITIVE,
    1e-30,
    -1e-30,
    0.5,
    -0.5,
    1.0,
    -1.0,
    0.999_999_9,
    -0.999_999_9,
    2.0,
    -7.25,
    88.7,
    -103.9,
    3.0e38,
    f32::MAX,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
];

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// A function of one argument, by name.
type Unary<F> = (&'static str, fn(F) -> F);
/// A function of two arguments, by name.
type Binary<F> = (&'static str, fn(F, F) -> F);

fn unary<F: Lane>() -> Vec<Unary<F>> {
    vec![
        ("exp", F::exp),
        ("exp_neg_normal", F::exp_neg_normal),
        ("exp2", F::exp2),
        ("ln", F::ln),
        ("log2", F::log2),
        ("ln_1p", F::ln_1p),
        ("sin", F::sin),
        ("cos", F::cos),
        ("sin_cos.0", |x| x.sin_cos().0),
        ("sin_cos.1", |x| x.sin_cos().1),
        ("tan", F::tan),
        ("asin", F::asin),
        ("acos", F::acos),
        ("atan", F::atan),
        ("erf", F::erf),
        ("erfc", F::erfc),
        ("erfinv", F::erfinv),
        ("floor", F::floor),
        ("ceil", F::ceil),
        ("round", F::round),
    ]
}

fn binary<F: Lane>() -> Vec<Binary<F>> {
    vec![("powf", F::powf), ("atan2", F::atan2), ("hypot", F::hypot), ("copysign", F::copysign)]
}

/// Check lane type `F` against the `f32` instantiation on all pairs of specials.
struct SameBits;

impl LaneKernel for SameBits {
    #[inline(always)]
    fn run<F: Lane>(self) {
        same_bits_as_f32::<F>();
    }
}

fn same_bits_as_f32<F: Lane>() {
    let n = SPECIALS.len();
    for s in 0..n {
        let a = F::from_fn(|i| SPECIALS[(s + i) % n]);
        for ((name, f), (_, g)) in unary::<F>().into_iter().zip(unary::<f32>()) {
            let r = f(a);
            for i in 0..F::LANES {
                assert!(same(r.lane(i), g(a.lane(i))), "{name}({}) lanes {}", a.lane(i), F::LANES);
            }
        }
        for t in 0..n {
            let b = F::from_fn(|i| SPECIALS[(t + 7 * i) % n]);
            for ((name, f), (_, g)) in binary::<F>().into_iter().zip(binary::<f32>()) {
                let r = f(a, b);
                for i in 0..F::LANES {
                    let (x, y) = (a.lane(i), b.lane(i));
                    assert!(same(r.lane(i), g(x, y)), "{name}({x}, {y}) lanes {}", F::LANES);
                }
            }
        }
    }
}

#[test]
fn every_lane_type_gives_the_bits_of_the_f32_instantiation() {
    same_bits_as_f32::<F32x8>();
    same_bits_as_f32::<F32x4>();
    run_widest(SameBits);
}

#[test]
fn special_values_are_those_of_the_standard_library() {
    let std_unary: [Unary<f32>; 14] = [
        ("exp", f32::exp),
        ("exp2", f32::exp2),
        ("ln", f32::ln),
        ("log2", f32::log2),
        ("ln_1p", f32::ln_1p),
        ("sin", f32::sin),
        ("cos", f32::cos),
        ("tan", f32::tan),
        ("asin", f32::asin),
        ("acos", f32::acos),
        ("atan", f32::atan),
        ("floor", f32::floor),
        ("ceil", f32::ceil),
        ("round", f32::round),
    ];
    let ours: Vec<_> = unary::<f32>();
    for x in SPECIALS {
        let special = x == 0.0 || !x.is_finite();
        for (name, g) in std_unary {
            let f = ours.iter().find(|(n, _)| *n == name).unwrap().1;
            if special {
                assert!(same(f(x), g(x)), "{name}({x:e}) = {:e}, std {:e}", f(x), g(x));
            }
        }
    }
    // Exact values at 1 and −1.
    for (name, v, want) in [
        ("ln(1)", Lane::ln(1.0f32), 0.0f32),
        ("log2(1)", Lane::log2(1.0f32), 0.0),
        ("log2(2)", Lane::log2(2.0f32), 1.0),
        ("acos(1)", Lane::acos(1.0f32), 0.0),
        ("acos(-1)", Lane::acos(-1.0f32), std::f32::consts::PI),
        ("asin(1)", Lane::asin(1.0f32), std::f32::consts::FRAC_PI_2),
        ("atan(1)", Lane::atan(1.0f32), std::f32::consts::FRAC_PI_4),
        ("exp2(-149)", Lane::exp2(-149.0f32), f32::from_bits(1)),
    ] {
        assert!(same(v, want), "{name} = {v:e}, want {want:e}");
    }
    // erf: odd, ±1 at ±∞; erfc: 0 at +∞, 2 at −∞; erfinv: inverse at the ends.
    for (x, e, c) in [(0.0f32, 0.0f32, 1.0f32), (f32::INFINITY, 1.0, 0.0), (f32::NEG_INFINITY, -1.0, 2.0)] {
        assert!(same(Lane::erf(x), e) && same(Lane::erfc(x), c), "erf/erfc({x})");
    }
    assert!(same(Lane::erf(-0.0f32), -0.0));
    assert_eq!(Lane::erfinv(1.0f32), f32::INFINITY);
    assert_eq!(Lane::erfinv(-1.0f32), f32::NEG_INFINITY);
    assert!(Lane::erfinv(1.5f32).is_nan() && Lane::erfinv(f32::NAN).is_nan());
    assert!(same(Lane::erfinv(0.0f32), 0.0) && same(Lane::erfinv(-0.0f32), -0.0));
    // powf: the documented cases for a base ≥ 0, and NaN for a negative base.
    let nan = f32::NAN;
    for (x, y, want) in [
        (0.0f32, 0.0f32, 1.0f32),
        (-0.0, 3.0, 0.0),
        (0.0, 2.5, 0.0),
        (0.0, -1.0, f32::INFINITY),
        (-0.0, -3.0, f32::INFINITY),
        (1.0, nan, 1.0),
        (nan, 0.0, 1.0),
        (f32::INFINITY, 0.5, f32::INFINITY),
        (f32::INFINITY, -0.5, 0.0),
        (0.5, f32::INFINITY, 0.0),
        (2.0, f32::INFINITY, f32::INFINITY),
        (0.5, f32::NEG_INFINITY, f32::INFINITY),
        (4.0, 0.5, 2.0),
        (-2.0, 2.0, nan),
        (-1e-30, 0.5, nan),
    ] {
        assert!(same(Lane::powf(x, y), want), "powf({x}, {y}) = {}", Lane::powf(x, y));
    }
}

/// Error of `got` against `want` in ulps of f32 at `want` (∞ counts as 2¹²⁸ beyond f32::MAX; a
/// wrong NaN or infinity is an infinite error).
fn ulps(got: f32, want: f64) -> f64 {
    if want.is_nan() || want.is_infinite() || got.is_nan() {
        return if f64::from(got) == want || (got.is_nan() && want.is_nan()) { 0.0 } else { f64::INFINITY };
    }
    let overflow = f64::from(f32::MAX) + 2f64.powi(103);
    if want.abs() >= overflow && f64::from(got) == want.signum() * f64::INFINITY {
        return 0.0;
    }
    let got = if got.is_infinite() { f64::from(got.signum()) * 2f64.powi(128) } else { f64::from(got) };
    let a = want.abs().min(2f64.powi(128));
    let ulp = if a < f64::from(f32::MIN_POSITIVE) {
        2f64.powi(-149)
    } else {
        2f64.powi(a.log2().floor() as i32 - 23)
    };
    (got - want).abs() / ulp
}

/// About `n` floats spread evenly by bit pattern over [lo, hi] (so every binade is sampled), plus the
/// ends.
fn spread(lo: f32, hi: f32, n: i64) -> Vec<f32> {
    let key = |x: f32| {
        let b = i64::from(x.to_bits());
        if b & 0x8000_0000 != 0 { -(b & 0x7fff_ffff) } else { b }
    };
    let unkey =
        |k: i64| if k < 0 { f32::from_bits(((-k) as u32) | 0x8000_0000) } else { f32::from_bits(k as u32) };
    let (a, b) = (key(lo), key(hi));
    let step = ((b - a) / n).max(1);
    let mut v: Vec<f32> = (a..=b).step_by(step as usize).map(unkey).collect();
    v.push(hi);
    v
}

/// The largest error of `f` against `g` over `xs`, asserted ≤ `bound` ulps.
fn check_unary(name: &str, xs: &[f32], f: fn(f32) -> f32, g: impl Fn(f64) -> f64, bound: f64) {
    let (mut worst, mut at) = (0.0, 0.0);
    for &x in xs {
        let e = ulps(f(x), g(f64::from(x)));
        if !(e <= worst) {
            (worst, at) = (e, x);
        }
    }
    assert!(worst <= bound, "{name}: {worst} ulp at {at:e} (bound {bound})");
}

/// 3·10⁴ floats over the domain plus 10⁴ in each listed hard region.
fn samples(lo: f32, hi: f32, hard: &[(f32, f32)]) -> Vec<f32> {
    let mut v = spread(lo, hi, 30_000);
    for &(a, b) in hard {
        v.extend(spread(a, b, 10_000));
    }
    v
}

#[test]
fn exponentials_and_logarithms_are_within_their_ulp_bounds() {
    let e = samples(-104.0, 89.0, &[(-1.0, 1.0), (-104.0, -87.0), (87.0, 88.8)]);
    check_unary("exp", &e, Lane::exp, f64::exp, 1.0);
    let e2 = samples(-151.0, 129.0, &[(-0.5, 0.5), (-151.0, -126.0), (127.0, 128.1)]);
    check_unary("exp2", &e2, Lane::exp2, f64::exp2, 1.25);
    let pos = samples(0.0, f32::MAX, &[(0.5, 2.0), (0.7, 0.71), (1.41, 1.42), (0.0, 1e-37)]);
    check_unary("ln", &pos, Lane::ln, f64::ln, 1.0);
    check_unary("log2", &pos, Lane::log2, f64::log2, 2.0);
    let p1 = samples(-1.0, f32::MAX, &[(-1e-3, 1e-3), (-0.9, 0.5), (0.01, 0.1)]);
    check_unary("ln_1p", &p1, Lane::ln_1p, f64::ln_1p, 2.5);
}

#[test]
fn the_decaying_exponential_is_exp_of_minus_x_until_the_cut_then_zero_and_never_subnormal() {
    use super::EXP_NEG_CUT;
    for x in samples(-88.0, 200.0, &[(-1.0, 1.0), (EXP_NEG_CUT - 1.0, EXP_NEG_CUT + 1.0)]) {
        let got = x.exp_neg_normal();
        if x < EXP_NEG_CUT {
            assert_eq!(got.to_bits(), Lane::exp(-x).to_bits(), "x = {x}");
            assert!(got.is_normal(), "x = {x}: {got:e}");
        } else {
            assert_eq!(got.to_bits(), 0, "x = {x}");
        }
    }
    assert_eq!(f32::INFINITY.exp_neg_normal(), 0.0);
    assert_eq!(f32::NEG_INFINITY.exp_neg_normal(), f32::INFINITY);
    assert!(f32::NAN.exp_neg_normal().is_nan());
}

#[test]
fn powf_is_within_one_ulp_over_the_whole_result_range() {
    // x^y for y log2 x across [−155, 130] (all of f32's results, subnormals and overflow included),
    // cosines to Blinn–Phong exponents, and a grid of all floats.
    let (mut worst, mut at) = (0.0, (0.0, 0.0));
    let mut add = |x: f32, y: f32| {
        let e = ulps(Lane::powf(x, y), f64::from(x).powf(f64::from(y)));
        if !(e <= worst) {
            (worst, at) = (e, (x, y));
        }
    };
    for (k, x) in spread(1e-30, 4.0, 20_000).into_iter().enumerate() {
        let t = -155.0 + 285.0 * ((k as f64 * 0.618_033_988_75) % 1.0);
        let y = (t / f64::from(x).log2()) as f32;
        if y.is_finite() {
            add(x, y);
        }
    }
    for c in spread(0.5, 1.0, 5_000) {
        for m in [0.5f32, 8.0, 100.0, 799.0, 1e4, 1e6, 1e8] {
            add(c, m);
        }
    }
    let all = spread(0.0, f32::MAX, 150);
    let signed = spread(-f32::MAX, f32::MAX, 150);
    for &x in &all {
        for &y in &signed {
            add(x, y);
        }
    }
    assert!(worst <= 0.51, "powf: {worst} ulp at {at:?}");
}

#[test]
fn trigonometric_functions_are_within_their_ulp_bounds() {
    let t = samples(-1.6e6, 1.6e6, &[(-7.0, 7.0), (1.5, 1.6), (3.1, 3.2), (-1e-3, 1e-3)]);
    check_unary("sin", &t, Lane::sin, f64::sin, 1.6);
    check_unary("cos", &t, Lane::cos, f64::cos, 1.6);
    check_unary("sin_cos.0", &t, |x| x.sin_cos().0, f64::sin, 1.6);
    check_unary("sin_cos.1", &t, |x| x.sin_cos().1, f64::cos, 1.6);
    check_unary("tan", &t, Lane::tan, f64::tan, 3.0);
    let u = samples(-1.0, 1.0, &[(0.45, 0.55), (-0.55, -0.45), (0.99, 1.0), (-1.0, -0.99)]);
    check_unary("asin", &u, Lane::asin, f64::asin, 2.5);
    check_unary("acos", &u, Lane::acos, f64::acos, 1.5);
    let a = samples(-f32::MAX, f32::MAX, &[(0.3, 0.5), (2.3, 2.5), (-1.0, 1.0)]);
    check_unary("atan", &a, Lane::atan, f64::atan, 2.5);
    let grid = spread(-f32::MAX, f32::MAX, 300);
    let (mut worst_atan2, mut worst_hypot) = (0.0f64, 0.0f64);
    for &y in &grid {
        for &x in &grid {
            worst_atan2 = worst_atan2.max(ulps(Lane::atan2(y, x), f64::from(y).atan2(f64::from(x))));
            worst_hypot = worst_hypot.max(ulps(Lane::hypot(y, x), f64::from(y).hypot(f64::from(x))));
        }
    }
    assert!(worst_atan2 <= 3.0, "atan2: {worst_atan2} ulp");
    assert!(worst_hypot <= 1.5, "hypot: {worst_hypot} ulp");
}

#[test]
fn error_functions_are_within_their_ulp_bounds() {
    let x = samples(-f32::MAX, f32::MAX, &[(-4.0, 4.0), (0.4, 1.1), (9.0, 10.1)]);
    check_unary("erf", &x, Lane::erf, libm::erf, 1.5);
    check_unary("erfc", &x, Lane::erfc, libm::erfc, 5.0);
    // erfinv against its float64 inverse: Newton on erf (erfc near ±1) from the f32 value.
    let inv = |x: f64| {
        let mut y = f64::from(Lane::erfinv(x as f32));
        for _ in 0..3 {
            let d = std::f64::consts::FRAC_2_SQRT_PI * (-y * y).exp();
            let tail = (1.0 - x.abs()) - libm::erfc(y.abs());
            let r = if x.abs() <= 0.5 {
                libm::erf(y) - x
            } else if x > 0.0 {
                tail
            } else {
                -tail
            };
            y -= r / d;
        }
        y
    };
    let u = samples(-0.999_999_94, 0.999_999_94, &[(0.99, 0.999_999_94), (-1e-3, 1e-3), (0.6, 0.8)]);
    check_unary("erfinv", &u, Lane::erfinv, inv, 3.0);
}

#[test]
fn rounding_functions_are_exact() {
    let x = samples(-f32::MAX, f32::MAX, &[(-3.0, 3.0), (-9e6, -4e6), (4e6, 9e6)]);
    check_unary("floor", &x, Lane::floor, f64::floor, 0.0);
    check_unary("ceil", &x, Lane::ceil, f64::ceil, 0.0);
    check_unary("round", &x, Lane::round, f64::round, 0.0);
    for x in [-0.5f32, 0.5, -0.0, 2.5, -2.5, 0.499_999_97] {
        assert!(
            same(Lane::round(x), x.round())
                && same(Lane::floor(x), x.floor())
                && same(Lane::ceil(x), x.ceil())
        );
    }
}

#[test]
fn atan2_and_hypot_special_values_are_those_of_the_standard_library() {
    for y in SPECIALS {
        for x in SPECIALS {
            let special = x == 0.0 || y == 0.0 || !x.is_finite() || !y.is_finite();
            if special {
                assert!(same(Lane::atan2(y, x), y.atan2(x)), "atan2({y}, {x}) = {}", Lane::atan2(y, x));
                assert!(same(Lane::hypot(y, x), y.hypot(x)), "hypot({y}, {x}) = {}", Lane::hypot(y, x));
            }
        }
    }
}

/// Exponents of [`Lane::powf_uniform`]: integers of binary powering (1 … 2¹⁶) and the others, which
/// go to `powf` (0, non-integers, negative, beyond 2¹⁶, NaN).
const UNIFORM_EXPONENTS: [f32; 17] = [
    1.0,
    2.0,
    3.0,
    5.0,
    20.0,
    32.0,
    33.0,
    255.0,
    799.0,
    10_000.0,
    65_535.0,
    65_536.0,
    65_537.0,
    0.0,
    2.5,
    -3.0,
    f32::NAN,
];

struct UniformSameBits;

impl LaneKernel for UniformSameBits {
    #[inline(always)]
    fn run<F: Lane>(self) {
        uniform_same_bits_as_f32::<F>();
    }
}

fn uniform_same_bits_as_f32<F: Lane>() {
    let n = SPECIALS.len();
    for s in 0..n {
        let a = F::from_fn(|i| SPECIALS[(s + i) % n]);
        for y in UNIFORM_EXPONENTS {
            let r = a.powf_uniform(y);
            for i in 0..F::LANES {
                let x = a.lane(i);
                assert!(
                    same(r.lane(i), Lane::powf_uniform(x, y)),
                    "powf_uniform({x}, {y}) lanes {}",
                    F::LANES
                );
            }
        }
    }
}

#[test]
fn powf_uniform_gives_the_same_bits_in_every_lane_type_and_powf_special_values() {
    uniform_same_bits_as_f32::<F32x8>();
    uniform_same_bits_as_f32::<F32x4>();
    run_widest(UniformSameBits);
    // Special values (±0, ±∞, NaN, negative bases, 1) are powf's for every exponent; other exponents
    // than integers in [1, 2^16] are powf itself.
    for x in SPECIALS {
        for y in UNIFORM_EXPONENTS {
            let (got, want) = (Lane::powf_uniform(x, y), Lane::powf(x, y));
            let special = x == 0.0 || x == 1.0 || x < 0.0 || !x.is_finite();
            if special || super::integer_exponent(y).is_none() {
                assert!(same(got, want), "powf_uniform({x}, {y}) = {got:e}, powf {want:e}");
            }
        }
    }
    assert!(same(Lane::powf_uniform(-0.0f32, 3.0), 0.0));
    assert!(Lane::powf_uniform(-0.5f32, 2.0).is_nan());
    assert_eq!(super::integer_exponent(65_536.0), Some(65_536));
    assert_eq!(super::integer_exponent(65_537.0), None);
    assert_eq!(super::integer_exponent(32.5), None);
}

#[test]
fn powf_uniform_and_one_minus_powi_are_correctly_rounded_for_integer_exponents() {
    // The bound of exp_log.rs: float64 binary powering within 2^-36, then one rounding: 0.5 + 2^-12 ulp.
    let bound = 0.5 + 2f64.powi(-12);
    let (mut worst, mut at) = (0.0, (0.0, 0.0));
    let mut add = |x: f32, n: u32, got: f32, want: f64| {
        let e = ulps(got, want);
        if !(e <= worst) {
            (worst, at) = (e, (x, n as f32));
        }
    };
    let ns = [1u32, 2, 3, 5, 8, 20, 32, 33, 100, 255, 1000, 4097, 10_000, 65_535, super::exp_log::POWI_MAX];
    let bases: Vec<f32> = spread(0.0, f32::MAX, 20_000)
        .into_iter()
        .chain(spread(0.5, 1.0, 20_000))
        .chain(spread(1.0, 1.01, 5_000))
        .collect();
    for &x in &bases {
        for &n in &ns {
            add(x, n, Lane::powf_uniform(x, n as f32), f64::from(x).powf(f64::from(n)));
        }
    }
    // (1 − d)^n for the deficits of Phong lobes: d in [0, 1], near 0 above all.
    for d in spread(0.0, 1.0, 40_000) {
        for &n in &ns {
            add(d, n, super::one_minus_powi(d, n), (1.0 - f64::from(d)).powf(f64::from(n)));
        }
    }
    assert!(worst <= bound, "{worst} ulp at {at:?}");
    assert_eq!(super::one_minus_powi(1.0f32, 7), 0.0);
    assert_eq!(super::one_minus_powi(0.0f32, 65_536), 1.0);
}
