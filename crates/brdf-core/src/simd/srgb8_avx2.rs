//! Eight channels at a time of [`crate::tonemap::srgb8_f32`] (clamp → sRGB OETF → 8 bits) with AVX2
//! gathers, for CPUs that have AVX2 (checked at run time).
//!
//! Writing an 8-bit image is one table look-up per channel; done one channel at a time it cost more than
//! 2 ns per channel (≈ 14 ms for a 1080p frame on one core), as much as shading a fifth of the frame.
//! The same two look-ups as the scalar path, as two gathers over eight lanes, give the same bytes for
//! a fraction of that.
//!
//! # Soundness
//! The intrinsics are `unsafe` because executing them on a CPU without AVX2 is undefined behaviour, and
//! the gathers and unaligned loads/stores because they dereference raw pointers.
//! - CPU: [`encode`] is the only entry point; it calls the `#[target_feature(enable = "avx2")]` kernel
//!   only after `is_x86_feature_detected!("avx2")` returned true, and the kernel's helpers (private,
//!   `#[inline(always)]`) are called from nowhere else.
//! - Loads and stores: none through raw pointers; lanes are moved in and out of registers by `bytemuck`
//!   casts of checked slices.
//! - Gathers: the bucket index is `trunc(c · 4096)` with `c` clamped to `[0, 1]` first (a NaN becomes 0,
//!   as `_mm256_max_ps` returns its second operand when the first is NaN), so it lies in `0..=4096`,
//!   inside `start` (4097 entries). Every entry of `start` is a level in `0..=255` (the table is built so,
//!   and checked when it is), inside `thresholds` (256 entries).

#![allow(unsafe_code)]

use std::arch::x86_64::{
    __m256, __m256i, _CMP_GE_OQ, _mm256_castps_si256, _mm256_cmp_ps, _mm256_cvttps_epi32,
    _mm256_i32gather_epi32, _mm256_i32gather_ps, _mm256_max_ps, _mm256_min_ps, _mm256_mul_ps,
    _mm256_packs_epi32, _mm256_packus_epi16, _mm256_permutevar8x32_epi32, _mm256_sub_epi32,
};

use crate::tonemap::{SRGB8_BUCKETS, Srgb8Table};

/// `dst[i] = srgb8_f32(src[i] · scale)` for every `i`, eight lanes at a time when this CPU has AVX2.
/// Returns `false` (and writes nothing) when it has not.
pub(crate) fn encode(src: &[f32], scale: f32, table: &Srgb8Table, dst: &mut [u8]) -> bool {
    if !std::is_x86_feature_detected!("avx2") {
        return false;
    }
    // SAFETY: AVX2 was detected just above (module docs).
    unsafe { encode_avx2(src, scale, table, dst) };
    true
}

/// The kernel: 32 channels (four registers) per step, then the scalar function for the tail.
#[target_feature(enable = "avx2")]
unsafe fn encode_avx2(src: &[f32], scale: f32, table: &Srgb8Table, dst: &mut [u8]) {
    assert_eq!(src.len(), dst.len(), "srgb8: source and destination lengths differ");
    let n = src.len();
    let k = Consts {
        scale: bytemuck::cast([scale; 8]),
        zero: bytemuck::cast([0.0f32; 8]),
        one: bytemuck::cast([1.0f32; 8]),
        buckets: bytemuck::cast([SRGB8_BUCKETS as f32; 8]),
        // After packing four registers the bytes sit in 32-bit groups ordered 0 4 1 5 2 6 3 7 (the packs
        // work within 128-bit halves); this permutation restores memory order.
        order: bytemuck::cast([0i32, 4, 1, 5, 2, 6, 3, 7]),
        start: table.start.as_ptr(),
        thresholds: table.thresholds.as_ptr(),
    };
    let mut i = 0;
    while i + 32 <= n {
        let bytes = k.levels32(&src[i..i + 32]);
        dst[i..i + 32].copy_from_slice(&bytes);
        i += 32;
    }
    for (d, &x) in dst[i..].iter_mut().zip(&src[i..]) {
        *d = crate::tonemap::srgb8_f32(x * scale);
    }
}

/// The kernel's constants. Its methods are plain functions inlined into [`encode_avx2`]: each intrinsic
/// sits in its own `unsafe` block, sound because they are reached only from there (module docs).
struct Consts {
    scale: __m256,
    zero: __m256,
    one: __m256,
    buckets: __m256,
    order: __m256i,
    start: *const i32,
    thresholds: *const f32,
}

impl Consts {
    /// The 8-bit levels of eight channels, one per 32-bit lane.
    #[inline(always)]
    fn levels8(&self, src: &[f32; 8]) -> __m256i {
        let x: __m256 = bytemuck::cast(*src);
        // SAFETY (every block below): AVX2 instructions, reached only on AVX2 CPUs; the gathers read
        // `start[0..=4096]` and `thresholds[0..=255]` (index ranges in the module docs).
        unsafe {
            let x = _mm256_mul_ps(x, self.scale);
            // Same order of operations as `clamp_f32`: max(x, 0) maps NaN to 0, then min(·, 1).
            let c = _mm256_min_ps(_mm256_max_ps(x, self.zero), self.one);
            let bucket = _mm256_cvttps_epi32(_mm256_mul_ps(c, self.buckets));
            let k = _mm256_i32gather_epi32::<4>(self.start, bucket);
            let t = _mm256_i32gather_ps::<4>(self.thresholds, k);
            // `c >= t` is all ones (−1) in the lanes one level up: subtracting it adds 1.
            _mm256_sub_epi32(k, _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(c, t)))
        }
    }

    /// The 8-bit levels of 32 channels, in order.
    #[inline(always)]
    fn levels32(&self, src: &[f32]) -> [u8; 32] {
        let lanes: &[[f32; 8]] = bytemuck::cast_slice(src);
        let (a, b, c, d) = (
            self.levels8(&lanes[0]),
            self.levels8(&lanes[1]),
            self.levels8(&lanes[2]),
            self.levels8(&lanes[3]),
        );
        // SAFETY: as above. Levels are in 0..=255, so the saturating packs are exact.
        let bytes = unsafe {
            let packed = _mm256_packus_epi16(_mm256_packs_epi32(a, b), _mm256_packs_epi32(c, d));
            _mm256_permutevar8x32_epi32(packed, self.order)
        };
        bytemuck::cast(bytes)
    }
}
