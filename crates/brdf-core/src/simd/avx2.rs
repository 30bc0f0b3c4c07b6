//! Eight lanes in one AVX register, for CPUs that have AVX2 (checked at run time).
//!
//! [`wide::f32x8`] chooses its instructions when `wide` is compiled: without `-C target-feature=+avx`
//! (the portable default) it is two SSE registers even inside an AVX2 function, which costs about a
//! third of Cook–Torrance throughput (twice the instructions, register spills). This module gives the batch
//! evaluator a lane type built on the AVX intrinsics themselves, used only behind run-time detection.
//!
//! # Soundness
//! The AVX intrinsics are `unsafe` because executing them on a CPU without AVX is undefined
//! behaviour. Every `unsafe` block below calls one such intrinsic on values of [`Avx8`]/[`AvxMask`],
//! which are private to this module. The only way any code outside it gets to handle them is
//! [`dispatch`]: it checks `is_x86_feature_detected!("avx2")` (AVX2 implies AVX) and only then runs
//! the kernel's `run::<Avx8>()`; the kernel returns `()`, so no value outlives that call. Hence every
//! intrinsic below executes on a CPU that has AVX. Values are built and read through `bytemuck`
//! casts of `[f32; 8]` (plain data, no instruction-set requirement). The operations are the
//! correctly rounded IEEE ones (`+ − × ÷ √`), ordered non-signalling comparisons and bitwise
//! blends, so results equal the scalar path bit for bit (see [`crate::simd`]). The same holds for
//! [`Avx64`], the float64 halves of [`Avx8`] (`Lane::Wide`), and for the AVX2 integer instructions
//! of the bit-level primitives (`pow2i`, `frexp`, `has_bits`): they are reached only through values
//! of these private types, and their integer results are exact. Conversions between `f32` and
//! `f64` round to nearest-even, Rust's `as` (the default MXCSR mode, which Rust code never changes).

#![allow(unsafe_code)]

use std::arch::x86_64::{
    __m128, __m256, __m256d, __m256i, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ,
    _CMP_NEQ_UQ, _mm256_add_epi32, _mm256_add_pd, _mm256_add_ps, _mm256_and_ps, _mm256_and_si256,
    _mm256_andnot_ps, _mm256_blendv_ps, _mm256_castps_si256, _mm256_castps256_ps128, _mm256_castsi256_ps,
    _mm256_cmp_ps, _mm256_cmpeq_epi32, _mm256_cvtepi32_ps, _mm256_cvtpd_ps, _mm256_cvtps_epi32,
    _mm256_cvtps_pd, _mm256_div_pd, _mm256_div_ps, _mm256_extractf128_ps, _mm256_movemask_ps, _mm256_mul_pd,
    _mm256_mul_ps, _mm256_or_ps, _mm256_or_si256, _mm256_set_m128, _mm256_set1_epi32, _mm256_shuffle_ps,
    _mm256_slli_epi32, _mm256_sqrt_ps, _mm256_srli_epi32, _mm256_sub_pd, _mm256_sub_ps, _mm256_xor_ps,
};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use glam::Vec3;

use super::{Lane, Lane64, LaneKernel, V3};

/// `_MM_SHUFFLE(a, b, c, d)`: the immediate of `_mm256_shuffle_ps` that takes, in each 128-bit half,
/// elements `d`, `c` of the first operand and `b`, `a` of the second.
const fn sh(a: i32, b: i32, c: i32, d: i32) -> i32 {
    (a << 6) | (b << 4) | (c << 2) | d
}

/// Run `k` with eight AVX lanes if this CPU has AVX2 and return `None`; else give `k` back.
#[inline]
pub(crate) fn dispatch<K: LaneKernel>(k: K) -> Option<K> {
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: `run_avx2` only requires AVX2, which was detected just above.
        unsafe { run_avx2(k) };
        None
    } else {
        Some(k)
    }
}

/// `k.run::<Avx8>()` compiled with AVX2 enabled, so that every intrinsic inlines into it.
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<K: LaneKernel>(k: K) {
    k.run::<Avx8>();
}

/// Eight `f32` in one AVX register (see the module docs for when it exists).
#[derive(Clone, Copy)]
struct Avx8(__m256);

/// Eight lane masks (all bits set for `true`).
#[derive(Clone, Copy)]
struct AvxMask(__m256);

/// Four `f64` in one AVX register: half of an [`Avx8`] widened (`Lane::Wide`).
#[derive(Clone, Copy)]
struct Avx64(__m256d);

impl Lane64 for Avx64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Self(bytemuck::cast([x; 4]))
    }
}

/// The integer view of a float register (a free reinterpretation).
#[inline(always)]
fn bits(x: __m256) -> __m256i {
    // SAFETY: an AVX instruction on values that exist only on AVX2 CPUs (module docs).
    unsafe { _mm256_castps_si256(x) }
}

/// The float view of an integer register.
#[inline(always)]
fn float(x: __m256i) -> __m256 {
    // SAFETY: as above.
    unsafe { _mm256_castsi256_ps(x) }
}

impl Avx8 {
    #[inline(always)]
    fn array(self) -> [f32; 8] {
        bytemuck::cast(self.0)
    }
}

macro_rules! avx_binop {
    ($ty:ident, $tr:ident, $m:ident, $intr:ident) => {
        impl $tr for $ty {
            type Output = Self;
            #[inline(always)]
            fn $m(self, o: Self) -> Self {
                // SAFETY: an AVX instruction on values that exist only on AVX2 CPUs (module docs).
                Self(unsafe { $intr(self.0, o.0) })
            }
        }
    };
}
avx_binop!(Avx8, Add, add, _mm256_add_ps);
avx_binop!(Avx8, Sub, sub, _mm256_sub_ps);
avx_binop!(Avx8, Mul, mul, _mm256_mul_ps);
avx_binop!(Avx8, Div, div, _mm256_div_ps);
avx_binop!(AvxMask, BitAnd, bitand, _mm256_and_ps);
avx_binop!(AvxMask, BitOr, bitor, _mm256_or_ps);
avx_binop!(Avx64, Add, add, _mm256_add_pd);
avx_binop!(Avx64, Sub, sub, _mm256_sub_pd);
avx_binop!(Avx64, Mul, mul, _mm256_mul_pd);
avx_binop!(Avx64, Div, div, _mm256_div_pd);

impl Neg for Avx8 {
    type Output = Self;
    /// Flip the sign bit, as `f32`'s negation does (exact; −0 for +0, NaN stays NaN).
    #[inline(always)]
    fn neg(self) -> Self {
        let sign: __m256 = bytemuck::cast([0x8000_0000_u32; 8]);
        // SAFETY: an AVX instruction on values that exist only on AVX2 CPUs (module docs).
        Self(unsafe { _mm256_xor_ps(self.0, sign) })
    }
}

impl Not for AvxMask {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        let ones: __m256 = bytemuck::cast([u32::MAX; 8]);
        // SAFETY: as above.
        Self(unsafe { _mm256_xor_ps(self.0, ones) })
    }
}

/// Compare with predicate `P` (an `_CMP_*` constant).
#[inline(always)]
fn cmp<const P: i32>(a: Avx8, b: Avx8) -> AvxMask {
    // SAFETY: as above.
    AvxMask(unsafe { _mm256_cmp_ps::<P>(a.0, b.0) })
}

impl Lane for Avx8 {
    type Mask = AvxMask;
    const LANES: usize = 8;
    type Wide = Avx64;

    #[inline(always)]
    fn pow2i(n: Self) -> Self {
        // SAFETY: AVX2 instructions on values that exist only on AVX2 CPUs (module docs). The
        // conversion of an integer-valued float is exact in any rounding mode.
        Self(float(unsafe {
            _mm256_slli_epi32::<23>(_mm256_add_epi32(_mm256_cvtps_epi32(n.0), _mm256_set1_epi32(127)))
        }))
    }
    #[inline(always)]
    fn frexp(self) -> (Self, Self) {
        let b = bits(self.0);
        // SAFETY: as above.
        unsafe {
            let m = _mm256_or_si256(
                _mm256_and_si256(b, _mm256_set1_epi32(0x007f_ffff)),
                _mm256_set1_epi32(0x3f80_0000),
            );
            let e = _mm256_cvtepi32_ps(_mm256_srli_epi32::<23>(b));
            (Self(float(m)), Self(e) - Self::splat(127.0))
        }
    }
    #[inline(always)]
    fn has_bits(self, mask: u32) -> AvxMask {
        // SAFETY: as above.
        let zero = unsafe {
            _mm256_cmpeq_epi32(
                _mm256_and_si256(bits(self.0), _mm256_set1_epi32(mask as i32)),
                _mm256_set1_epi32(0),
            )
        };
        !AvxMask(float(zero))
    }
    #[inline(always)]
    fn widen(self) -> (Avx64, Avx64) {
        // SAFETY: as above.
        unsafe {
            (
                Avx64(_mm256_cvtps_pd(_mm256_castps256_ps128(self.0))),
                Avx64(_mm256_cvtps_pd(_mm256_extractf128_ps::<1>(self.0))),
            )
        }
    }
    #[inline(always)]
    fn narrow(lo: Avx64, hi: Avx64) -> Self {
        // SAFETY: as above.
        Self(unsafe { _mm256_set_m128(_mm256_cvtpd_ps(hi.0), _mm256_cvtpd_ps(lo.0)) })
    }

    #[inline(always)]
    fn splat(x: f32) -> Self {
        Self(bytemuck::cast([x; 8]))
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        Self(bytemuck::cast(std::array::from_fn::<f32, 8, _>(f)))
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.array()[i]
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as above.
        Self(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // f32::min with the sign of zero pinned, as `impl Lane for f32`.
        Self::select(cmp::<_CMP_LT_OQ>(o, self) | cmp::<_CMP_NEQ_UQ>(self, self), o, self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Self::select(cmp::<_CMP_GT_OQ>(o, self) | cmp::<_CMP_NEQ_UQ>(self, self), o, self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        let sign: __m256 = bytemuck::cast([0x8000_0000_u32; 8]);
        // SAFETY: as above.
        Self(unsafe { _mm256_andnot_ps(sign, self.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> AvxMask {
        cmp::<_CMP_GT_OQ>(self, o)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> AvxMask {
        cmp::<_CMP_LT_OQ>(self, o)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> AvxMask {
        cmp::<_CMP_EQ_OQ>(self, o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> AvxMask {
        cmp::<_CMP_GE_OQ>(self, o)
    }
    #[inline(always)]
    fn le(self, o: Self) -> AvxMask {
        cmp::<_CMP_LE_OQ>(self, o)
    }
    #[inline(always)]
    fn is_finite(self) -> AvxMask {
        // `x · 0 = 0` exactly when x is finite.
        let zero = Self::splat(0.0);
        cmp::<_CMP_EQ_OQ>(self * zero, zero)
    }
    #[inline(always)]
    fn mask_splat(b: bool) -> AvxMask {
        AvxMask(bytemuck::cast([if b { u32::MAX } else { 0 }; 8]))
    }
    #[inline(always)]
    fn mask_lane(m: AvxMask, i: usize) -> bool {
        bytemuck::cast::<__m256, [u32; 8]>(m.0)[i] != 0
    }
    #[inline(always)]
    fn mask_all(m: AvxMask) -> bool {
        // SAFETY: as above.
        unsafe { _mm256_movemask_ps(m.0) == 0xff }
    }
    #[inline(always)]
    fn select(m: AvxMask, a: Self, b: Self) -> Self {
        // SAFETY: as above. Lanes of `m` are all-ones or all-zeros, so the sign-bit blend is exact.
        Self(unsafe { _mm256_blendv_ps(b.0, a.0, m.0) })
    }

    /// Eight rows `x y z` (24 floats) to three registers in six shuffles (the AoS → SoA transposition
    /// of Intel's "3D vector normalization using 256-bit AVX"): each 128-bit half holds rows 0–3 and
    /// 4–7 of the same three quadwords.
    #[inline(always)]
    fn load_rows(rows: &[Vec3]) -> V3<Self> {
        let Ok(rows) = <&[Vec3; 8]>::try_from(rows) else { unreachable!("load_rows takes 8 rows") };
        let f: &[f32; 24] = bytemuck::cast_ref(rows);
        let q = |i: usize| -> __m128 { bytemuck::cast([f[i], f[i + 1], f[i + 2], f[i + 3]]) };
        // SAFETY: AVX shuffles on values that exist only on AVX2 CPUs (module docs).
        unsafe {
            let m03 = _mm256_set_m128(q(12), q(0)); // x0 y0 z0 x1 | x4 y4 z4 x5
            let m14 = _mm256_set_m128(q(16), q(4)); // y1 z1 x2 y2 | y5 z5 x6 y6
            let m25 = _mm256_set_m128(q(20), q(8)); // z2 x3 y3 z3 | z6 x7 y7 z7
            let xy = _mm256_shuffle_ps::<{ sh(2, 1, 3, 2) }>(m14, m25); // x2 y2 x3 y3
            let yz = _mm256_shuffle_ps::<{ sh(1, 0, 2, 1) }>(m03, m14); // y0 z0 y1 z1
            V3 {
                x: Self(_mm256_shuffle_ps::<{ sh(2, 0, 3, 0) }>(m03, xy)),
                y: Self(_mm256_shuffle_ps::<{ sh(3, 1, 2, 0) }>(yz, xy)),
                z: Self(_mm256_shuffle_ps::<{ sh(3, 0, 3, 1) }>(yz, m25)),
            }
        }
    }

    /// The inverse of [`Avx8::load_rows`], six shuffles and six 16-byte stores.
    #[inline(always)]
    fn store_rows(v: V3<Self>, rows: &mut [Vec3]) {
        let Ok(rows) = <&mut [Vec3; 8]>::try_from(rows) else { unreachable!("store_rows takes 8 rows") };
        let f: &mut [f32; 24] = bytemuck::cast_mut(rows);
        let (x, y, z) = (v.x.0, v.y.0, v.z.0);
        // SAFETY: as above.
        let (r03, r14, r25) = unsafe {
            let rxy = _mm256_shuffle_ps::<{ sh(2, 0, 2, 0) }>(x, y); // x0 x2 y0 y2
            let ryz = _mm256_shuffle_ps::<{ sh(3, 1, 3, 1) }>(y, z); // y1 y3 z1 z3
            let rzx = _mm256_shuffle_ps::<{ sh(3, 1, 2, 0) }>(z, x); // z0 z2 x1 x3
            (
                _mm256_shuffle_ps::<{ sh(2, 0, 2, 0) }>(rxy, rzx), // x0 y0 z0 x1
                _mm256_shuffle_ps::<{ sh(3, 1, 2, 0) }>(ryz, rxy), // y1 z1 x2 y2
                _mm256_shuffle_ps::<{ sh(3, 1, 3, 1) }>(rzx, ryz), // z2 x3 y3 z3
            )
        };
        let halves = |r: __m256| -> ([f32; 4], [f32; 4]) {
            // SAFETY: as above.
            unsafe {
                (bytemuck::cast(_mm256_castps256_ps128(r)), bytemuck::cast(_mm256_extractf128_ps::<1>(r)))
            }
        };
        for (k, r) in [r03, r14, r25].into_iter().enumerate() {
            let (lo, hi) = halves(r);
            f[4 * k..4 * k + 4].copy_from_slice(&lo);
            f[12 + 4 * k..16 + 4 * k].copy_from_slice(&hi);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Check;

    impl LaneKernel for Check {
        fn run<F: Lane>(self) {
            let xs = [0.0, -0.0, 1e-40, 3.0e38, -1.0e-30, f32::NAN, f32::INFINITY, -1.25];
            for s in 0..8 {
                let a = F::from_fn(|i| xs[(i + s) % 8]);
                let b = F::from_fn(|i| xs[(3 * i + s) % 8]);
                for i in 0..F::LANES {
                    let (x, y) = (a.lane(i), b.lane(i));
                    let same = |p: f32, q: f32| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan());
                    assert!(same((a + b).lane(i), x + y) && same((a - b).lane(i), x - y));
                    assert!(same((a * b).lane(i), x * y) && same((a / b).lane(i), x / y));
                    assert!(same(a.sqrt().lane(i), x.sqrt()) && same(a.abs().lane(i), x.abs()));
                    assert!(
                        same(a.min(b).lane(i), Lane::min(x, y)) && same(a.max(b).lane(i), Lane::max(x, y))
                    );
                    assert_eq!(F::mask_lane(a.gt(b), i), x > y);
                    assert_eq!(F::mask_lane(a.lt(b), i), x < y);
                    assert_eq!(F::mask_lane(a.eq(b), i), x == y);
                    assert_eq!(F::mask_lane(!a.eq(b), i), x != y);
                    assert_eq!(F::mask_lane(a.gt(b) | a.lt(b), i), x != y && !x.is_nan() && !y.is_nan());
                    assert_eq!(
                        F::mask_lane(a.is_finite() & b.is_finite(), i),
                        x.is_finite() && y.is_finite()
                    );
                    assert!(same(F::select(a.gt(b), a, b).lane(i), if x > y { x } else { y }));
                }
            }
        }
    }

    #[test]
    fn avx_lanes_equal_f32_operations_bit_for_bit() {
        // On a CPU without AVX2 this checks the fallback's contract instead.
        if let Some(k) = dispatch(Check) {
            k.run::<super::super::F32x8>();
        }
    }
}
