//! The accuracy of the lane math functions (`brdf_core::simd::Lane`) in ulps against float64, over
//! every `stride`-th float32 of each function's domain (`stride` = 1 sweeps all of them):
//!
//! `cargo run --release -p brdf-core --example lane_math_ulps [stride]` (default 61).
//!
//! Prints, per function, the largest error in ulps of the float32 result (the spacing of float32 at
//! the float64 value), where it occurs, and the mean. The test suite checks the same bounds on a
//! denser sample of the hard regions at a fraction of the cost. The last lines measure the `wide`
//! crate's own `f32x8` functions the same way, for comparison.

use brdf_core::simd::Lane;

/// Error of `got` against `want` in ulps of f32 at `want` (∞ for a wrong non-finite result).
fn ulps(got: f32, want: f64) -> f64 {
    if want.is_nan() {
        return if got.is_nan() { 0.0 } else { f64::INFINITY };
    }
    // Beyond f32::MAX, ∞ counts as 2¹²⁸ (the convention of ulp error measurements, e.g. CORE-MATH).
    let overflow = f64::from(f32::MAX) + 2f64.powi(103);
    if want.is_infinite() || got.is_nan() {
        return if f64::from(got) == want { 0.0 } else { f64::INFINITY };
    }
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

/// Every `stride`-th float32 between `lo` and `hi` (by bit pattern, both signs).
fn floats(lo: f32, hi: f32, stride: usize) -> impl Iterator<Item = f32> {
    let key = |x: f32| {
        let b = x.to_bits() as i64;
        if b & 0x8000_0000 != 0 { -(b & 0x7fff_ffff) } else { b }
    };
    let unkey =
        |k: i64| if k < 0 { f32::from_bits((-k) as u32 | 0x8000_0000) } else { f32::from_bits(k as u32) };
    (key(lo)..=key(hi)).step_by(stride).map(unkey)
}

struct Stat {
    max: f64,
    at: (f32, f32),
    sum: f64,
    n: u64,
}

impl Stat {
    fn new() -> Self {
        Self { max: 0.0, at: (0.0, 0.0), sum: 0.0, n: 0 }
    }
    fn add(&mut self, e: f64, x: f32, y: f32) {
        if e > self.max || e.is_nan() {
            self.max = e;
            self.at = (x, y);
        }
        self.sum += e.min(1e9);
        self.n += 1;
    }
    fn print(&self, name: &str, domain: &str) {
        println!(
            "{name:8} {domain:32} max {:8.3} ulp at ({:e}, {:e})  mean {:.3}  n {}",
            self.max,
            self.at.0,
            self.at.1,
            self.sum / self.n as f64,
            self.n
        );
    }
}

fn erfinv64(x: f64) -> f64 {
    // Newton on erf (or erfc near ±1, where 1 − |x| is exact), from the f32 estimate.
    let mut y = f64::from(Lane::erfinv(x as f32));
    if !y.is_finite() {
        return y;
    }
    for _ in 0..4 {
        let d = 2.0 / std::f64::consts::PI.sqrt() * (-y * y).exp();
        // erf(y) − x, as (1 − |x|) − erfc|y| with the sign of x near ±1.
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
}

fn main() {
    let stride: usize = std::env::args().nth(1).map_or(61, |s| s.parse().expect("stride"));
    type U = (&'static str, f32, f32, fn(f32) -> f32, fn(f64) -> f64);
    let unary: [U; 16] = [
        ("exp", -104.0, 89.0, Lane::exp, f64::exp),
        ("exp2", -151.0, 129.0, Lane::exp2, f64::exp2),
        ("ln", 0.0, f32::MAX, Lane::ln, f64::ln),
        ("log2", 0.0, f32::MAX, Lane::log2, f64::log2),
        ("ln_1p", -1.0, f32::MAX, Lane::ln_1p, f64::ln_1p),
        ("sin", -1.6e6, 1.6e6, Lane::sin, f64::sin),
        ("cos", -1.6e6, 1.6e6, Lane::cos, f64::cos),
        ("tan", -1.6e6, 1.6e6, Lane::tan, f64::tan),
        ("asin", -1.0, 1.0, Lane::asin, f64::asin),
        ("acos", -1.0, 1.0, Lane::acos, f64::acos),
        ("atan", -f32::MAX, f32::MAX, Lane::atan, f64::atan),
        ("erf", -f32::MAX, f32::MAX, Lane::erf, libm::erf),
        ("erfc", -f32::MAX, f32::MAX, Lane::erfc, libm::erfc),
        ("erfinv", -1.0, 1.0, Lane::erfinv, erfinv64),
        ("floor", -f32::MAX, f32::MAX, Lane::floor, f64::floor),
        ("round", -f32::MAX, f32::MAX, Lane::round, f64::round),
    ];
    for (name, lo, hi, f, g) in unary {
        let mut s = Stat::new();
        for x in floats(lo, hi, stride) {
            s.add(ulps(f(x), g(f64::from(x))), x, 0.0);
        }
        s.print(name, &format!("[{lo:e}, {hi:e}]"));
    }
    // Two arguments: a grid of every (stride · 4096)-th float pair, plus pow's hard region.
    type B = (&'static str, fn(f32, f32) -> f32, fn(f64, f64) -> f64);
    let binary: [B; 3] = [
        ("powf", Lane::powf, f64::powf),
        ("atan2", Lane::atan2, f64::atan2),
        ("hypot", Lane::hypot, f64::hypot),
    ];
    let coarse: Vec<f32> = floats(-f32::MAX, f32::MAX, stride * 4096).collect();
    for (name, f, g) in binary {
        let mut s = Stat::new();
        for &x in &coarse {
            let x = if name == "powf" { x.abs() } else { x };
            for &y in &coarse {
                s.add(ulps(f(x, y), g(f64::from(x), f64::from(y))), x, y);
            }
        }
        s.print(name, "grid of all floats");
    }
    // powf where y log2 x spans the whole result range: x in (0, 4], y = t/log2 x.
    let mut s = Stat::new();
    let mut k = 0u64;
    for x in floats(1e-30, 4.0, stride * 8) {
        k += 1;
        let t = -155.0 + 285.0 * ((k.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 11) as f64 / (1u64 << 53) as f64);
        let y = (t / f64::from(x).log2()) as f32;
        if y.is_finite() {
            s.add(ulps(Lane::powf(x, y), f64::from(x).powf(f64::from(y))), x, y);
        }
    }
    s.print("powf", "x^y over the whole result range");
    // Blinn–Phong: cosines near 1 to exponents up to 1e8.
    let mut s = Stat::new();
    for c in floats(0.5, 1.0, stride.max(1)) {
        for m in [1.0f32, 8.0, 100.0, 799.0, 1e4, 1e6, 1e8] {
            s.add(ulps(Lane::powf(c, m), f64::from(c).powf(f64::from(m))), c, m);
        }
    }
    s.print("powf", "c in [0.5, 1], m in 1 ... 1e8");
    wide_comparison(stride);
}

/// For comparison: the `wide` crate's own f32x8 forms (why this crate has its own; see the report).
fn wide_comparison(stride: usize) {
    use wide::f32x8;
    let one = |f: fn(f32x8) -> f32x8, x: f32| f(f32x8::splat(x)).to_array()[0];
    type W = (&'static str, f32, f32, fn(f32x8) -> f32x8, fn(f64) -> f64);
    let fs: [W; 6] = [
        ("exp", -104.0, 89.0, f32x8::exp, f64::exp),
        ("ln", 0.0, f32::MAX, f32x8::ln, f64::ln),
        ("sin", -1e4, 1e4, f32x8::sin, f64::sin),
        ("acos", -1.0, 1.0, f32x8::acos, f64::acos),
        ("atan", -f32::MAX, f32::MAX, f32x8::atan, f64::atan),
        ("asin", -1.0, 1.0, f32x8::asin, f64::asin),
    ];
    for (name, lo, hi, f, g) in fs {
        let mut s = Stat::new();
        for x in floats(lo, hi, stride) {
            s.add(ulps(one(f, x), g(f64::from(x))), x, 0.0);
        }
        s.print(&format!("wide {name}"), &format!("[{lo:e}, {hi:e}]"));
    }
    let mut s = Stat::new();
    for c in floats(0.5, 1.0, stride) {
        for m in [8.0f32, 100.0, 799.0, 1e4] {
            let got = f32x8::splat(c).pow_f32x8(f32x8::splat(m)).to_array()[0];
            s.add(ulps(got, f64::from(c).powf(f64::from(m))), c, m);
        }
    }
    s.print("wide pow_f32x8", "c in [0.5, 1], m in 8 ... 1e4");
}
