//! Lanes: one formula, evaluated on one sample (`f32`) or on eight at once.
//!
//! The hot terms of the benchmarked models (GGX `D`, the GGX Smith visibility, Schlick's Fresnel, the
//! Cook–Torrance and Blinn–Phong lobes, normalisation) are written once, generic over [`Lane`], and
//! the scalar API (`ggx::d`, `CookTorrance::specular`, `Bxdf::f`, …) is that same code instantiated
//! with `F = f32`. The batch evaluator ([`crate::batch`]) instantiates it with eight lanes: one AVX
//! register where the CPU has AVX2 (detected at run time; `avx2.rs`, the only `unsafe` code, with its
//! soundness argument), else [`F32x8`] from the `wide` crate (two SSE registers on baseline x86-64).
//!
//! **Bit-identical to the scalar path.** Every lane type does exactly the IEEE-754 operations the
//! scalar code does, lane by lane and in the same order: `+ − × ÷` and `√` are correctly rounded,
//! `min`/`max`/`abs` have `f32`'s semantics (with the sign of a zero result pinned, see [`Lane::min`]),
//! comparisons and [`Lane::select`] are exact, and Rust never contracts `a·b + c` into a fused
//! multiply-add on its own (no fast-math; FMA is not enabled for the AVX2 build either). The
//! transcendental functions (`exp`, `ln`, `powf`, `sin`/`cos`, `atan2`, `acos`, `erf`, …) are
//! [`Lane`] methods written once over the trait ([`math`]), so they are the same sequence of those
//! operations in every lane type; a term with no generic form runs its scalar function on each lane
//! ([`Lane::map`]). A batch therefore gives the same bits as [`crate::Model::eval`] on
//! each sample, on any x86-64 CPU, with or without AVX, for any thread count (the batch tests check
//! every model against the scalar path bit for bit).
//!
//! Branches become selects: the generic code computes both sides and keeps one per lane. Lanes that a
//! select discards may hold anything (NaN, ∞); they never reach a result.
//!
//! **Inlining.** A lane operation reaches single AVX instructions only when it is inlined into the
//! AVX2-enabled kernel, so the terms (each `D`, `G`, `F`, each function of [`math`]) are
//! `#[inline(always)]` in optimised builds. Closures are not used in lane code: a closure is a
//! function of its own, compiled without the AVX2 feature, and its intrinsics become calls. In
//! builds with debug assertions (unoptimised `cargo build`/`cargo test`) the terms are only
//! `#[inline]`: `inline(always)` is honoured at opt-level 0, where every inlined call keeps its own
//! stack slots, and one batch kernel with every term inlined needs more than a megabyte of stack,
//! more than a 2 MiB test or rayon thread has. Results are the same bits either way (inlining does
//! not change the operations).

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::{Vec3, Vec3A};
use wide::{CmpEq, CmpGe, CmpGt, CmpLe, CmpLt, CmpNe};

#[cfg(target_arch = "x86_64")]
mod avx2;

pub mod math;

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::dispatch as dispatch_avx2;

#[cfg(target_arch = "x86_64")]
pub(crate) mod srgb8_avx2;

/// A computation over lanes of any [`Lane`] type (the batch evaluator's chunk loop, the rasterizer's
/// shading queue), so that the lane type can be chosen at run time by [`run_widest`].
pub trait LaneKernel {
    /// Run with lane type `F`. Mark the implementation `#[inline(always)]`: it is then compiled inside
    /// the AVX2-enabled caller and its lane operations become single AVX instructions.
    fn run<F: Lane>(self);
}

/// Run `k` with eight lanes in one AVX register where this CPU has AVX2 (detected at run time), else
/// with [`F32x8`]. Both give the same bits (module docs).
#[inline]
pub fn run_widest<K: LaneKernel>(k: K) {
    #[cfg(target_arch = "x86_64")]
    let Some(k) = dispatch_avx2(k) else { return };
    k.run::<F32x8>();
}

/// A number type the model formulas are written over: `f32` (one sample) or eight lanes.
///
/// Every operation has the semantics of the `f32` operation of the same name, applied lane by lane.
pub trait Lane:
    Copy
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A per-lane boolean (`bool` for `f32`).
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask> + Not<Output = Self::Mask>;
    /// Number of samples held.
    const LANES: usize;

    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// The value of lane `i < LANES`.
    fn lane(self, i: usize) -> f32;
    /// `√x` (correctly rounded).
    fn sqrt(self) -> Self;
    /// `f32::min` per lane (the other operand where one is NaN; `self` when equal, so `min(−0, +0)`
    /// is −0).
    fn min(self, o: Self) -> Self;
    /// `f32::max` per lane (as [`Lane::min`]).
    fn max(self, o: Self) -> Self;
    /// `|x|`.
    fn abs(self) -> Self;
    /// `self > o`.
    fn gt(self, o: Self) -> Self::Mask;
    /// `self < o`.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self == o`.
    fn eq(self, o: Self) -> Self::Mask;
    /// `self >= o` (false where either is NaN).
    fn ge(self, o: Self) -> Self::Mask;
    /// `self <= o` (false where either is NaN).
    fn le(self, o: Self) -> Self::Mask;
    /// `f32::is_finite` per lane.
    fn is_finite(self) -> Self::Mask;
    /// A mask with every lane `b`.
    fn mask_splat(b: bool) -> Self::Mask;
    /// Lane `i` of a mask.
    fn mask_lane(m: Self::Mask, i: usize) -> bool;
    /// `true` when every lane of `m` is set.
    #[inline(always)]
    fn mask_all(m: Self::Mask) -> bool {
        (0..Self::LANES).all(|i| Self::mask_lane(m, i))
    }
    /// `a` where `m`, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;

    // Bit-level primitives of the transcendental functions ([`math`]): integer operations on the
    // IEEE-754 fields, exact, hence the same bits in every lane type.

    /// `2ⁿ` (exact) for integer-valued `n` in [−126, 127]: the biased exponent `n + 127` shifted into
    /// place. Callers clamp `n` into that range first (other values are not defined to agree across
    /// lane types).
    fn pow2i(n: Self) -> Self;
    /// `(m, e)` with `x = m · 2ᵉ`, `m` in [1, 2) and integer `e`, for positive normal `x`: `e` is the
    /// exponent field minus 127 and `m` the significand with a zero exponent. For other `x` the same
    /// field manipulation (exact, and equal in every lane type; callers select those lanes away).
    fn frexp(self) -> (Self, Self);
    /// Lanes where `self.to_bits() & bits != 0` (e.g. the sign bit, or the low bits of an integer
    /// held in the significand of a float shifted by 1.5 · 2²³).
    fn has_bits(self, bits: u32) -> Self::Mask;
    /// float64 lanes holding this type's lanes in two halves (a float64 of the sample, and an unused
    /// one, for `f32`): the extended precision inside [`Lane::powf`].
    type Wide: Lane64;
    /// Lanes as float64 (exact), in two halves: lanes `0..LANES/2` and the rest.
    fn widen(self) -> (Self::Wide, Self::Wide);
    /// The inverse of [`Lane::widen`], each lane rounded to the nearest f32 (ties to even).
    fn narrow(lo: Self::Wide, hi: Self::Wide) -> Self;

    /// `f` applied to each lane: how terms without a wide form join a wide computation (bit-identical to
    /// calling `f` on each sample).
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::from_fn(|i| f(self.lane(i)))
    }

    /// `rows` (exactly `LANES` of them) transposed into lanes: lane `j` of `x` is `rows[j].x`, …
    #[inline(always)]
    fn load_rows(rows: &[Vec3]) -> V3<Self> {
        V3 {
            x: Self::from_fn(|j| rows[j].x),
            y: Self::from_fn(|j| rows[j].y),
            z: Self::from_fn(|j| rows[j].z),
        }
    }

    /// The inverse of [`Lane::load_rows`]: lane `j` of `v` into `rows[j]` (exactly `LANES` rows).
    #[inline(always)]
    fn store_rows(v: V3<Self>, rows: &mut [Vec3]) {
        for (j, r) in rows.iter_mut().enumerate() {
            *r = v.lane(j);
        }
    }

    // Transcendental functions ([`math`]): one generic body each, never overridden by a lane type,
    // so every lane type computes the same bits. Special values as the `f32` method of the same
    // name unless stated; accuracy against float64 in ulps (units in the last place of the f32
    // result) over the stated domain, measured as [`math`] describes.

    /// `eˣ` (≤ 0.96 ulp). 0 for x < −103.97 (below the smallest subnormal), +∞ for x > 88.72, 1 at ±0.
    #[inline(always)]
    fn exp(self) -> Self {
        math::exp(self)
    }
    /// `e^{−x}` as [`Lane::exp`] of `−x` where `x < 80`, and 0 from 80 on (`e^{−80} ≈ 1.8 · 10⁻³⁵`):
    /// the decaying exponentials of the reflectance lobes, kept out of the subnormal floats, which cost
    /// an x86 core ~10² cycles per operation. NaN stays NaN.
    #[inline(always)]
    fn exp_neg_normal(self) -> Self {
        math::exp_neg_normal(self)
    }
    /// `2ˣ` (≤ 1.2 ulp). 0 for x < −150, +∞ for x ≥ 128.
    #[inline(always)]
    fn exp2(self) -> Self {
        math::exp2(self)
    }
    /// `ln x` (≤ 0.82 ulp) for x ≥ 0: −∞ at ±0, NaN for x < 0, +∞ at +∞; subnormal x accurate.
    #[inline(always)]
    fn ln(self) -> Self {
        math::ln(self)
    }
    /// `log₂ x` (≤ 1.75 ulp) for x ≥ 0 (edge values as [`Lane::ln`]).
    #[inline(always)]
    fn log2(self) -> Self {
        math::log2(self)
    }
    /// `ln(1 + x)` (≤ 2.4 ulp) for x ≥ −1, accurate near 0 (≈ x for tiny x, ±0 kept): −∞ at −1, NaN below.
    #[inline(always)]
    fn ln_1p(self) -> Self {
        math::ln_1p(self)
    }
    /// `xʸ` (≤ 0.51 ulp: correctly rounded but within 2⁻⁶ ulp of a tie) for a base x ≥ 0 (the lane form of `f32::powf` where it matters for BRDFs: cosines raised
    /// to exponents up to ~10⁸). −0 counts as +0; x < 0 gives NaN (unlike `f32::powf`, which has
    /// real results for integer y: use multiplication for those). `x⁰ = 1` and `1ʸ = 1` for every x,
    /// y (NaN included), `0ʸ` is 0 for y > 0 and +∞ for y < 0, `∞ʸ` is +∞ for y > 0 and 0 for y < 0.
    #[inline(always)]
    fn powf(self, y: Self) -> Self {
        math::powf(self, y)
    }
    /// `xʸ` for one exponent `y` shared by every lane (a model's shininess): for integer y in
    /// [1, 2¹⁶] binary powering in float64 lanes (≤ 0.5 + 2⁻¹² ulp, a few products instead of a
    /// logarithm and an exponential), else [`Lane::powf`]; [`Lane::powf`]'s special values either way.
    #[inline(always)]
    fn powf_uniform(self, y: f32) -> Self {
        math::powf_uniform(self, y)
    }
    /// `sin x` (≤ 1.6 ulp), x in radians; accurate for |x| ≤ 1.6 · 10⁶, in [−1, 1] for any finite x;
    /// NaN for ±∞.
    #[inline(always)]
    fn sin(self) -> Self {
        math::sin(self)
    }
    /// `cos x` (as [`Lane::sin`]).
    #[inline(always)]
    fn cos(self) -> Self {
        math::cos(self)
    }
    /// `(sin x, cos x)` sharing the argument reduction; the same bits as [`Lane::sin`] and
    /// [`Lane::cos`].
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        math::sin_cos(self)
    }
    /// `tan x` (≤ 2.7 ulp; domain as [`Lane::sin`]).
    #[inline(always)]
    fn tan(self) -> Self {
        math::tan(self)
    }
    /// `asin x` (≤ 2.3 ulp) in [−π/2, π/2] for |x| ≤ 1, NaN outside.
    #[inline(always)]
    fn asin(self) -> Self {
        math::asin(self)
    }
    /// `acos x` (≤ 1.2 ulp) in [0, π] for |x| ≤ 1, NaN outside.
    #[inline(always)]
    fn acos(self) -> Self {
        math::acos(self)
    }
    /// `atan x` (≤ 2.3 ulp) in [−π/2, π/2].
    #[inline(always)]
    fn atan(self) -> Self {
        math::atan(self)
    }
    /// `atan2(self, x)` (≤ 2.6 ulp): the angle of the point (x, self) in [−π, π], with `f32::atan2`'s signed-zero
    /// and infinity cases.
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        math::atan2(self, x)
    }
    /// The error function `erf x = (2/√π) ∫₀ˣ e^{−t²} dt` (≤ 1.3 ulp); ±1 beyond |x| ≈ 3.92, ±0 kept.
    #[inline(always)]
    fn erf(self) -> Self {
        math::erf(self)
    }
    /// `erfc x = 1 − erf x` (≤ 4.7 ulp), accurate where it is tiny (x up to ≈ 10.05, 0 beyond); 2 at −∞.
    #[inline(always)]
    fn erfc(self) -> Self {
        math::erfc(self)
    }
    /// The inverse error function (≤ 2.8 ulp) for |x| ≤ 1 (±∞ at ±1, NaN outside; Giles 2011 and a
    /// Newton step): for samplers (Beckmann visible normals).
    #[inline(always)]
    fn erfinv(self) -> Self {
        math::erfinv(self)
    }
    /// `√(x² + y²)` (≤ 1.2 ulp) without overflow or underflow in the squares.
    #[inline(always)]
    fn hypot(self, y: Self) -> Self {
        math::hypot(self, y)
    }
    /// Largest integer ≤ x (exact).
    #[inline(always)]
    fn floor(self) -> Self {
        math::floor(self)
    }
    /// Smallest integer ≥ x (exact).
    #[inline(always)]
    fn ceil(self) -> Self {
        math::ceil(self)
    }
    /// Nearest integer, halves away from zero, like `f32::round` (exact).
    #[inline(always)]
    fn round(self) -> Self {
        math::round(self)
    }
    /// `|x|` with the sign bit of `sign` (exact; NaN signs too).
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        Self::select(sign.has_bits(0x8000_0000), -self.abs(), self.abs())
    }

    /// `f32::clamp(lo, hi)` per lane (NaN stays NaN).
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> Self {
        let (lo, hi) = (Self::splat(lo), Self::splat(hi));
        Self::select(self.lt(lo), lo, Self::select(self.gt(hi), hi, self))
    }
}

/// float64 lanes: the extended-precision companion of a [`Lane`] type ([`Lane::Wide`]), with the
/// correctly rounded arithmetic of `f64`.
pub trait Lane64:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
}

impl Lane64 for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
}

impl Lane64 for wide::f64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        wide::f64x4::splat(x)
    }
}

impl Lane64 for wide::f64x2 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        wide::f64x2::splat(x)
    }
}

impl Lane for f32 {
    type Mask = bool;
    const LANES: usize = 1;
    type Wide = f64;

    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        f32::from_bits(((n as i32 + 127) as u32) << 23)
    }
    #[inline(always)]
    fn frexp(self) -> (Self, Self) {
        let b = self.to_bits();
        (f32::from_bits((b & 0x007f_ffff) | 0x3f80_0000), (b >> 23) as i32 as f32 - 127.0)
    }
    #[inline(always)]
    fn has_bits(self, bits: u32) -> bool {
        self.to_bits() & bits != 0
    }
    #[inline(always)]
    fn widen(self) -> (f64, f64) {
        (f64::from(self), 0.0)
    }
    #[inline(always)]
    fn narrow(lo: f64, _hi: f64) -> Self {
        lo as f32
    }

    #[inline(always)]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _i: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    // `f32::min`/`max` leave the sign of a zero result unspecified; these pin it (the first operand
    // on ties) so that the scalar and wide forms agree bit for bit.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if o < self || self.is_nan() { o } else { self }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        if o > self || self.is_nan() { o } else { self }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn ge(self, o: Self) -> bool {
        self >= o
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self <= o
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn mask_splat(b: bool) -> bool {
        b
    }
    #[inline(always)]
    fn mask_lane(m: bool, _i: usize) -> bool {
        m
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
}

/// Eight `f32` lanes on [`wide::f32x8`] (one AVX register where the crate is compiled for AVX, two
/// SSE registers otherwise). A wrapper rather than `wide`'s type itself so that every operator has
/// `f32`'s semantics: `wide` negates by `0 − x`, which turns −0 into +0 where `f32` flips the sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct F32x8(pub wide::f32x8);

/// Four `f32` lanes on [`wide::f32x4`] (one SSE register; VEX-encoded in the batch evaluator's AVX2
/// build); a wrapper like [`F32x8`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct F32x4(pub wide::f32x4);

/// Lane masks of [`F32x8`] (all bits set for `true`, the layout of SSE/AVX compare results).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M32x8(pub wide::f32x8);

/// Lane masks of [`F32x4`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M32x4(pub wide::f32x4);

/// `Lane` for a `wide` float vector: every operation used is a correctly rounded IEEE operation or
/// an exact bitwise one.
macro_rules! wide_lane {
    ($f:ident, $w:ty, $m:ident, $n:literal, $i:ty, $u:ty, $d:ty) => {
        impl BitAnd for $m {
            type Output = Self;
            #[inline(always)]
            fn bitand(self, o: Self) -> Self {
                Self(self.0 & o.0)
            }
        }
        impl BitOr for $m {
            type Output = Self;
            #[inline(always)]
            fn bitor(self, o: Self) -> Self {
                Self(self.0 | o.0)
            }
        }
        impl Not for $m {
            type Output = Self;
            #[inline(always)]
            fn not(self) -> Self {
                Self(!self.0)
            }
        }
        impl Add for $f {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                Self(self.0 + o.0)
            }
        }
        impl Sub for $f {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                Self(self.0 - o.0)
            }
        }
        impl Mul for $f {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                Self(self.0 * o.0)
            }
        }
        impl Div for $f {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                Self(self.0 / o.0)
            }
        }
        impl Neg for $f {
            type Output = Self;
            /// The sign bit flipped, as `f32`'s negation (−0 for +0).
            #[inline(always)]
            fn neg(self) -> Self {
                Self(self.0 ^ <$w>::splat(-0.0))
            }
        }

        impl Lane for $f {
            type Mask = $m;
            const LANES: usize = $n;
            type Wide = $d;

            #[inline(always)]
            fn pow2i(n: Self) -> Self {
                // Integer-valued n: the conversion is exact whatever its rounding mode.
                Self(bytemuck::cast((n.0.round_int() + <$i>::splat(127)) << 23))
            }
            #[inline(always)]
            fn frexp(self) -> (Self, Self) {
                let b: $u = bytemuck::cast(self.0);
                let m: $w = bytemuck::cast((b & <$u>::splat(0x007f_ffff)) | <$u>::splat(0x3f80_0000));
                let e = <$i>::round_float(bytemuck::cast(b >> 23)) - <$w>::splat(127.0);
                (Self(m), Self(e))
            }
            #[inline(always)]
            fn has_bits(self, bits: u32) -> $m {
                let b: $i = bytemuck::cast(self.0);
                let zero: $w = bytemuck::cast((b & <$i>::splat(bits as i32)).cmp_eq(<$i>::splat(0)));
                $m(!zero)
            }
            #[inline(always)]
            fn widen(self) -> ($d, $d) {
                const H: usize = $n / 2;
                let a = self.0.to_array();
                (
                    <$d>::new(std::array::from_fn(|i| f64::from(a[i]))),
                    <$d>::new(std::array::from_fn(|i| f64::from(a[H + i]))),
                )
            }
            #[inline(always)]
            fn narrow(lo: $d, hi: $d) -> Self {
                const H: usize = $n / 2;
                let (lo, hi) = (lo.to_array(), hi.to_array());
                Self(<$w>::new(std::array::from_fn(|i| if i < H { lo[i] as f32 } else { hi[i - H] as f32 })))
            }

            #[inline(always)]
            fn splat(x: f32) -> Self {
                Self(<$w>::splat(x))
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
                Self(<$w>::new(std::array::from_fn(f)))
            }
            #[inline(always)]
            fn lane(self, i: usize) -> f32 {
                self.0.as_array_ref()[i]
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                Self(self.0.sqrt())
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                // f32::min: the smaller, or the other operand where one is NaN (see `impl Lane for f32`).
                Self::select($m(o.0.cmp_lt(self.0) | self.0.cmp_ne(self.0)), o, self)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                Self::select($m(o.0.cmp_gt(self.0) | self.0.cmp_ne(self.0)), o, self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                Self(self.0.abs())
            }
            #[inline(always)]
            fn gt(self, o: Self) -> $m {
                $m(self.0.cmp_gt(o.0))
            }
            #[inline(always)]
            fn lt(self, o: Self) -> $m {
                $m(self.0.cmp_lt(o.0))
            }
            #[inline(always)]
            fn eq(self, o: Self) -> $m {
                $m(self.0.cmp_eq(o.0))
            }
            #[inline(always)]
            fn ge(self, o: Self) -> $m {
                $m(self.0.cmp_ge(o.0))
            }
            #[inline(always)]
            fn le(self, o: Self) -> $m {
                $m(self.0.cmp_le(o.0))
            }
            #[inline(always)]
            fn is_finite(self) -> $m {
                // `x · 0 = 0` exactly when x is finite (∞ · 0 and NaN · 0 are NaN).
                $m((self.0 * <$w>::ZERO).cmp_eq(<$w>::ZERO))
            }
            #[inline(always)]
            fn mask_splat(b: bool) -> $m {
                $m(<$w>::splat(f32::from_bits(if b { u32::MAX } else { 0 })))
            }
            #[inline(always)]
            fn mask_lane(m: $m, i: usize) -> bool {
                m.0.as_array_ref()[i].to_bits() != 0
            }
            #[inline(always)]
            fn mask_all(m: $m) -> bool {
                m.0.all()
            }
            #[inline(always)]
            fn select(m: $m, a: Self, b: Self) -> Self {
                // A blend on whole-lane masks: exact for every value, NaN payloads included.
                Self(m.0.blend(a.0, b.0))
            }
        }
    };
}
wide_lane!(F32x8, wide::f32x8, M32x8, 8, wide::i32x8, wide::u32x8, wide::f64x4);
wide_lane!(F32x4, wide::f32x4, M32x4, 4, wide::i32x4, wide::u32x4, wide::f64x2);

/// A 3-vector (an RGB colour or a direction) whose components are lanes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<F> {
    /// First component (x or red).
    pub x: F,
    /// Second component (y or green).
    pub y: F,
    /// Third component (z or blue).
    pub z: F,
}

impl<F: Lane> V3<F> {
    /// The vector `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Self { x: F::splat(v.x), y: F::splat(v.y), z: F::splat(v.z) }
    }

    /// Lane `i` is `f(i)`; `f` is called once per lane.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        // Lane counts are tiny (1 or 8): collect into a fixed buffer of the largest.
        let mut buf = [Vec3::ZERO; 8];
        for (i, b) in buf.iter_mut().enumerate().take(F::LANES) {
            *b = f(i);
        }
        Self { x: F::from_fn(|i| buf[i].x), y: F::from_fn(|i| buf[i].y), z: F::from_fn(|i| buf[i].z) }
    }

    /// Lane `i` as a `Vec3`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }

    /// `x·x' + y·y' + z·z'`, summed left to right like glam's `Vec3A::dot`.
    #[inline(always)]
    pub fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `self × o`, component by component as glam's `Vec3A::cross` (`y·o.z − o.y·z`, …: the same
    /// products, so the same bits).
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    /// Each component multiplied by the per-lane factor `s`.
    #[inline(always)]
    pub fn scale(self, s: F) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// `a` where `m`, else `b`, per lane.
    #[inline(always)]
    pub fn select(m: F::Mask, a: Self, b: Self) -> Self {
        Self { x: F::select(m, a.x, b.x), y: F::select(m, a.y, b.y), z: F::select(m, a.z, b.z) }
    }

    /// Lanes where all three components are finite.
    #[inline(always)]
    pub fn is_finite(self) -> F::Mask {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }

    /// `v / |v|`, or zero where `|v|²` is 0 or not finite; the mask tells which lanes were normalised.
    /// Operation for operation [`crate::vector::normalize_or_zero`]: three divisions by the length, not
    /// one reciprocal and three products — that would save ~5 % of a Cook–Torrance batch but add an
    /// ulp to every direction, which the sharp GGX peak (α = 0.08) amplifies past the test suite's
    /// 1e-3 tolerance near grazing half vectors.
    #[inline(always)]
    pub fn normalize_or_zero(self) -> (Self, F::Mask) {
        let len2 = self.dot(self);
        let ok = len2.gt(F::splat(0.0)) & len2.is_finite();
        let zero = Self { x: F::splat(0.0), y: F::splat(0.0), z: F::splat(0.0) };
        (Self::select(ok, self / len2.sqrt(), zero), ok)
    }
}

/// Each component divided by the per-lane divisor.
impl<F: Lane> Div<F> for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: F) -> Self {
        Self { x: self.x / s, y: self.y / s, z: self.z / s }
    }
}

/// Component-wise product (colour × colour).
impl<F: Lane> Mul for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self { x: self.x * o.x, y: self.y * o.y, z: self.z * o.z }
    }
}

impl<F: Lane> Sub for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl<F: Lane> Add for V3<F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Vec3 {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl From<Vec3A> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3A) -> Self {
        Self { x: v.x, y: v.y, z: v.z }
    }
}

/// Lane geometry lives with the scalar one (one formula for both, see [`crate::geometry`]).
pub use crate::geometry::LaneGeometry;

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward values: signed zeros, subnormals, huge, tiny, NaN, ±∞, ordinary.
    const SPECIALS: [f32; 12] = [
        0.0,
        -0.0,
        1e-40,
        -3e-39,
        3.0e38,
        -1.0e-30,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.5,
        -1.25,
        7.0,
    ];

    fn lanes(base: usize) -> F32x8 {
        F32x8::from_fn(|i| SPECIALS[(base + 5 * i) % SPECIALS.len()])
    }

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn every_lane_operation_equals_the_f32_operation_bit_for_bit() {
        for s in 0..SPECIALS.len() {
            for t in 0..SPECIALS.len() {
                let (a, b) = (lanes(s), lanes(t));
                for i in 0..8 {
                    let (x, y) = (a.lane(i), b.lane(i));
                    assert!(same((a + b).lane(i), x + y));
                    assert!(same((a - b).lane(i), x - y));
                    assert!(same((a * b).lane(i), x * y));
                    assert!(same((a / b).lane(i), x / y));
                    assert!(same(a.sqrt().lane(i), x.sqrt()));
                    assert!(same(Lane::min(a, b).lane(i), Lane::min(x, y)), "min {x} {y}");
                    assert!(same(Lane::max(a, b).lane(i), Lane::max(x, y)), "max {x} {y}");
                    // As values (−0 = +0), the f32 methods' results.
                    let eqv = |p: f32, q: f32| p == q || (p.is_nan() && q.is_nan());
                    assert!(eqv(Lane::min(x, y), x.min(y)), "min {x} {y}");
                    assert!(eqv(Lane::max(x, y), x.max(y)), "max {x} {y}");
                    assert!(same(a.abs().lane(i), x.abs()));
                    assert!(same(a.clamp(-1.0, 1.0).lane(i), Lane::clamp(x, -1.0, 1.0)));
                    assert!(same(Lane::clamp(x, -1.0, 1.0), x.clamp(-1.0, 1.0)));
                    assert_eq!(F32x8::mask_lane(a.gt(b), i), x > y);
                    assert_eq!(F32x8::mask_lane(a.lt(b), i), x < y);
                    assert_eq!(F32x8::mask_lane(a.eq(b), i), x == y);
                    assert_eq!(F32x8::mask_lane(Lane::is_finite(a), i), x.is_finite());
                    let m = a.gt(b);
                    assert!(same(F32x8::select(m, a, b).lane(i), if x > y { x } else { y }));
                }
            }
        }
    }
}
