//! From linear HDR radiance to display values: clamping, HDR tone-mapping operators that
//! map `[0, ∞)` into `[0, 1]`, exposure, the sRGB transfer function and 8-bit quantisation.
//!
//! The pipeline for writing an 8-bit image is `exposure → operator → sRGB OETF → to_u8`
//! ([`encode_srgb8`]). Each step is a separate, explicit function: nothing in the shading code clamps.
//!
//! Every function works per channel on linear RGB. Inputs that are negative or NaN are treated as 0
//! and `+∞` as the largest finite value, so that no operator ever returns NaN (a NaN pixel would
//! otherwise poison every later image operation).
//!
//! ```
//! use brdf_core::tonemap::{Operator, encode_srgb8};
//! use glam::Vec3;
//! // A lit orange pixel in linear RGB, clamped and sRGB-encoded.
//! assert_eq!(encode_srgb8(Vec3::new(0.810225, 0.311365, 0.211593), Operator::Clamp), [232, 151, 127]);
//! ```

use glam::Vec3;

use crate::BrdfError;

/// Replace NaN and negative values by 0 and `+∞` by `f32::MAX` (`f32::max` ignores a NaN operand).
// `f32::clamp` would propagate NaN; `max`/`min` map it to 0 on purpose.
#[allow(clippy::manual_clamp)]
#[inline]
fn sanitize(x: f32) -> f32 {
    x.max(0.0).min(f32::MAX)
}

/// Clamp one channel to `[0, 1]` (`clamp(y) = 0 if y < 0, y if y ∈ [0, 1], 1 if y > 1`);
/// NaN → 0.
#[allow(clippy::manual_clamp)] // NaN → 0, which `f32::clamp` would not do
#[inline]
pub fn clamp_f32(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// Clamp every channel to `[0, 1]` (what a scan-line renderer does at the end of the computation).
///
/// This is the scan-line renderer's answer to values above 1: it loses all detail in bright regions,
/// which is what the HDR operators below avoid.
#[inline]
pub fn clamp(c: Vec3) -> Vec3 {
    Vec3::new(clamp_f32(c.x), clamp_f32(c.y), clamp_f32(c.z))
}

/// Simple Reinhard operator of one channel, `x / (1 + x)` (Reinhard, Stark, Shirley, Ferwerda 2002,
/// "Photographic Tone Reproduction for Digital Images", eq. 3).
#[inline]
pub fn reinhard_f32(x: f32) -> f32 {
    // For x = f32::MAX, 1 + x rounds to x and the quotient is exactly 1, so +∞ maps to 1.
    let x = sanitize(x);
    x / (1.0 + x)
}

/// Simple Reinhard operator `x / (1 + x)`, per channel (Reinhard et al. 2002, eq. 3).
///
/// Maps `[0, ∞)` onto `[0, 1)`; it is applied to each RGB channel independently here (the paper applies
/// it to luminance), which desaturates very bright colours toward white.
#[inline]
pub fn reinhard(c: Vec3) -> Vec3 {
    Vec3::new(reinhard_f32(c.x), reinhard_f32(c.y), reinhard_f32(c.z))
}

/// Extended Reinhard operator of one channel with white point `white` (> 0):
/// `x (1 + x / w²) / (1 + x)`, and 1 for `x ≥ w` (Reinhard et al. 2002, eq. 4).
#[inline]
pub fn reinhard_extended_f32(x: f32, white: f32) -> f32 {
    let x = sanitize(x);
    if !(x < white) {
        // At and above the white point the operator burns out to white (and a non-positive or NaN
        // `white` makes every positive value "above white").
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    // Here 0 ≤ x < white, so white > 0; dividing twice by `white` avoids underflow of white².
    (x * (1.0 + (x / white) / white) / (1.0 + x)).min(1.0)
}

/// Extended Reinhard operator `x (1 + x/w²) / (1 + x)` per channel, with white point `white` [same unit
/// as `x`] (Reinhard et al. 2002, eq. 4). Radiance `w` maps exactly to 1, larger values clamp to 1;
/// `w → ∞` gives the simple operator.
#[inline]
pub fn reinhard_extended(c: Vec3, white: f32) -> Vec3 {
    Vec3::new(
        reinhard_extended_f32(c.x, white),
        reinhard_extended_f32(c.y, white),
        reinhard_extended_f32(c.z, white),
    )
}

/// ACES filmic curve of one channel, `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)` clamped to `[0, 1]`.
#[inline]
pub fn aces_f32(x: f32) -> f32 {
    // The curve reaches 1 at x ≈ 7.24 and tends to 2.51/2.43 > 1; capping the input at 1e6 changes no
    // clamped output and keeps x² finite.
    let x = sanitize(x).min(1.0e6);
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).min(1.0)
}

/// ACES filmic tone curve, per channel: Krzysztof Narkowicz's 2015 rational fit to the ACES reference
/// rendering transform + sRGB output transform ("ACES Filmic Tone Mapping Curve", blog post,
/// 2016-01-06): `x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14)`, clamped to `[0, 1]`.
///
/// Narkowicz fitted the curve to ACES with the input pre-scaled by 0.6; apply
/// [`exposure`]`(c, log2(0.6))` first to match ACES' own exposure. The raw curve is given here, as most
/// engines use it.
#[inline]
pub fn aces(c: Vec3) -> Vec3 {
    Vec3::new(aces_f32(c.x), aces_f32(c.y), aces_f32(c.z))
}

/// Exposure: multiply linear radiance by `2^ev` (`ev` in stops, photographic exposure value offset).
///
/// `ev` must be finite (callers validate it). A finite value stays finite: where `c · 2^ev` is beyond
/// float32 the result saturates at `±f32::MAX` (`ev = 10³⁸` gave ∞, and 0 · ∞ = NaN for black).
#[inline]
pub fn exposure(c: Vec3, ev: f32) -> Vec3 {
    Vec3::new(exposure_f32(c.x, ev), exposure_f32(c.y, ev), exposure_f32(c.z, ev))
}

/// [`exposure`] of one value.
#[inline]
pub fn exposure_f32(c: f32, ev: f32) -> f32 {
    let y = c * ev.exp2();
    if (y.is_finite() && (y != 0.0 || c == 0.0)) || !c.is_finite() {
        return y;
    }
    if c == 0.0 {
        return c;
    }
    // 2^ev overflowed or underflowed float32 while c · 2^ev may not: in f64 (exact for |ev| < 1022),
    // then saturated.
    let max = f64::from(f32::MAX);
    (f64::from(c) * f64::from(ev).exp2()).clamp(-max, max) as f32
}

/// sRGB opto-electronic transfer function (IEC 61966-2-1) of one channel, after clamping to `[0, 1]`:
/// `v = 12.92 c` if `c ≤ 0.0031308`, else `v = 1.055 c^(1/2.4) − 0.055`.
#[inline]
pub fn srgb_encode_f32(c: f32) -> f32 {
    let c = clamp_f32(c);
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// sRGB OETF per channel (linear → encoded, both in `[0, 1]`), exactly IEC 61966-2-1's formula;
/// the input is clamped to `[0, 1]` first.
#[inline]
pub fn srgb_encode(c: Vec3) -> Vec3 {
    Vec3::new(srgb_encode_f32(c.x), srgb_encode_f32(c.y), srgb_encode_f32(c.z))
}

/// Inverse of [`srgb_encode_f32`] (IEC 61966-2-1): `c = v / 12.92` if `v ≤ 0.04045`, else
/// `c = ((v + 0.055) / 1.055)^2.4`; the input is clamped to `[0, 1]`.
#[inline]
pub fn srgb_decode_f32(v: f32) -> f32 {
    let v = clamp_f32(v);
    if v <= 0.040_45 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// sRGB decoding per channel (encoded → linear), inverse of [`srgb_encode`] on `[0, 1]`.
#[inline]
pub fn srgb_decode(v: Vec3) -> Vec3 {
    Vec3::new(srgb_decode_f32(v.x), srgb_decode_f32(v.y), srgb_decode_f32(v.z))
}

/// Quantise an encoded value to 8 bits: `floor(255 v + 0.5)` after clamping `v` to `[0, 1]`
/// (round half up, as GL's UNORM8 conversion). NaN → 0.
#[inline]
pub fn to_u8(v: f32) -> u8 {
    // In [0, 255.5] after the clamp, so the cast never saturates.
    (255.0 * clamp_f32(v) + 0.5).floor() as u8
}

/// A tone-mapping operator: maps linear HDR RGB (any non-negative value) to `[0, 1]` per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Operator {
    /// [`clamp`]: values above 1 saturate.
    Clamp,
    /// [`reinhard`]: `x / (1 + x)`.
    Reinhard,
    /// [`reinhard_extended`] with this white point (> 0).
    ReinhardExtended {
        /// Radiance that maps to 1.
        white: f32,
    },
    /// [`aces`]: Narkowicz's ACES filmic fit.
    Aces,
}

impl Operator {
    /// The names [`Operator::from_name`] accepts.
    pub const NAMES: &'static [&'static str] = &["clamp", "reinhard", "reinhard_extended", "aces"];

    /// Operator by name (one of [`Operator::NAMES`], case-insensitive). `white` is the white point of
    /// `"reinhard_extended"` (default 4.0; must be finite and > 0) and is ignored by the others.
    pub fn from_name(name: &str, white: Option<f32>) -> Result<Self, BrdfError> {
        match name.to_ascii_lowercase().as_str() {
            "clamp" => Ok(Self::Clamp),
            "reinhard" => Ok(Self::Reinhard),
            "aces" => Ok(Self::Aces),
            "reinhard_extended" => {
                let white = white.unwrap_or(4.0);
                if white > 0.0 && white.is_finite() {
                    Ok(Self::ReinhardExtended { white })
                } else {
                    Err(BrdfError::param("white", format!("must be finite and > 0, got {white}")))
                }
            }
            _ => Err(BrdfError::param(
                "operator",
                format!("expected one of {}, got {name:?}", Self::NAMES.join(", ")),
            )),
        }
    }

    /// Registry name of the operator.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Clamp => "clamp",
            Self::Reinhard => "reinhard",
            Self::ReinhardExtended { .. } => "reinhard_extended",
            Self::Aces => "aces",
        }
    }

    /// Map one linear RGB value into `[0, 1]` per channel.
    #[inline]
    pub fn apply(&self, c: Vec3) -> Vec3 {
        match *self {
            Self::Clamp => clamp(c),
            Self::Reinhard => reinhard(c),
            Self::ReinhardExtended { white } => reinhard_extended(c, white),
            Self::Aces => aces(c),
        }
    }

    /// The operator on one channel (every operator here works per channel: `apply(c).x =
    /// apply_f32(c.x)`).
    #[inline]
    pub fn apply_f32(&self, x: f32) -> f32 {
        match *self {
            Self::Clamp => clamp_f32(x),
            Self::Reinhard => reinhard_f32(x),
            Self::ReinhardExtended { white } => reinhard_extended_f32(x, white),
            Self::Aces => aces_f32(x),
        }
    }
}

/// Buckets of the direct-index table of [`srgb8_f32`]: `c ∈ [b/N, (b+1)/N)` lands in bucket `b`.
pub(crate) const SRGB8_BUCKETS: usize = 4096;

/// The tables behind [`srgb8_f32`] (also read by the AVX2 encoder, `simd::srgb8_avx2`).
pub(crate) struct Srgb8Table {
    /// `thresholds[k]`: the smallest linear value whose 8-bit level is `k + 1` or more under
    /// `to_u8(srgb_encode_f32(c))`; `thresholds[255] = +∞` stops the search.
    pub thresholds: [f32; 256],
    /// `start[b]`: the level of `b / SRGB8_BUCKETS`, a lower bound of every level in bucket `b` (i32,
    /// the element type of an AVX2 gather).
    pub start: [i32; SRGB8_BUCKETS + 1],
}

/// Built once by bisection over the f32 bit patterns of `[0, 1]`.
///
/// Why: the `powf` of the OETF (and then a binary search) dominated the cost of writing an image. The
/// formula is non-decreasing in `c` (checked at every threshold and on a dense sweep by the tests), so
/// the level of `c` is the number of thresholds `≤ c`: start from the level at the bucket's lower edge
/// and step up. The steepest part of the curve (slope 12.92 · 255 levels per unit) moves less than one
/// level per bucket, so one comparison finishes it.
pub(crate) fn srgb8_table() -> &'static Srgb8Table {
    static TABLE: std::sync::OnceLock<Srgb8Table> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let level = |c: f32| to_u8(srgb_encode_f32(c));
        let mut thresholds = [f32::INFINITY; 256];
        for (k, t) in thresholds.iter_mut().take(255).enumerate() {
            let k = k as u8 + 1;
            // Non-negative f32 order like their bit patterns: bisect on the bits of [0, 1].
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if level(f32::from_bits(mid)) >= k { hi = mid } else { lo = mid + 1 }
            }
            *t = f32::from_bits(lo);
        }
        let mut start = [0i32; SRGB8_BUCKETS + 1];
        for (b, s) in start.iter_mut().enumerate() {
            let edge = b as f32 / SRGB8_BUCKETS as f32;
            *s = thresholds.partition_point(|&t| t <= edge) as i32;
        }
        // The single comparison in `srgb8_f32` relies on this: a bucket spans at most one level step.
        // The AVX2 encoder's gathers rely on every entry being a level, 0..=255.
        assert!(start.iter().all(|&k| (0..=255).contains(&k)), "sRGB table: level out of range");
        assert!(
            start.windows(2).all(|w| w[1] - w[0] <= 1),
            "sRGB table: a bucket spans two level boundaries; use more buckets"
        );
        Srgb8Table { thresholds, start }
    })
}

/// `to_u8(srgb_encode_f32(c))` — linear value to its 8-bit sRGB level, bit-identical to the formula
/// (clamp to `[0, 1]`, NaN → 0) but by two table look-ups instead of a `powf`.
#[inline]
pub fn srgb8_f32(c: f32) -> u8 {
    let c = clamp_f32(c);
    let t = srgb8_table();
    // c·N is exact (a power of two), so the bucket's lower edge b/N is ≤ c.
    let k = t.start[(c * SRGB8_BUCKETS as f32) as usize] as usize;
    // At most one level boundary lies inside a bucket (checked when the table is built), so one
    // branch-free comparison finishes the search.
    (k + usize::from(c >= t.thresholds[k])) as u8
}

/// One linear HDR colour to an 8-bit sRGB pixel: `to_u8(srgb_encode(op.apply(c)))` per channel.
#[inline]
pub fn encode_srgb8(c: Vec3, op: Operator) -> [u8; 3] {
    let e = op.apply(c);
    [srgb8_f32(e.x), srgb8_f32(e.y), srgb8_f32(e.z)]
}

/// Linear channels to 8-bit sRGB levels, `dst[i] = srgb8_f32(op.apply_f32(src[i] · scale))` — what
/// [`encode_srgb8`]`(c · scale, op)` does to each channel of `c`, over any number of channels in any
/// layout (e.g. an `H×W×3` image flattened). `scale` is the exposure factor `2^ev`. One thread; eight
/// channels at a time where the CPU has AVX2, with the same bytes as the scalar path.
///
/// # Panics
/// If `src` and `dst` have different lengths.
pub fn encode_srgb8_channels(src: &[f32], scale: f32, op: Operator, dst: &mut [u8]) {
    assert_eq!(src.len(), dst.len(), "encode_srgb8_channels: source and destination lengths differ");
    let table = srgb8_table();
    if op == Operator::Clamp {
        // The encoder clamps: no separate pass.
        #[cfg(target_arch = "x86_64")]
        if crate::simd::srgb8_avx2::encode(src, scale, table, dst) {
            return;
        }
        for (d, &x) in dst.iter_mut().zip(src) {
            *d = srgb8_f32(x * scale);
        }
        return;
    }
    // Other operators: tone-map a block on the stack, then encode it (the operator's output is in [0, 1],
    // so the encoder's clamp leaves it alone).
    const BLOCK: usize = 256;
    let mut mapped = [0.0f32; BLOCK];
    for (src, dst) in src.chunks(BLOCK).zip(dst.chunks_mut(BLOCK)) {
        let mapped = &mut mapped[..src.len()];
        for (m, &x) in mapped.iter_mut().zip(src) {
            *m = op.apply_f32(x * scale);
        }
        #[cfg(target_arch = "x86_64")]
        if crate::simd::srgb8_avx2::encode(mapped, 1.0, table, dst) {
            continue;
        }
        for (d, &m) in dst.iter_mut().zip(mapped.iter()) {
            *d = srgb8_f32(m);
        }
    }
}

/// [`encode_srgb8`] over a slice (e.g. an `H×W` image in row-major order), in parallel when large;
/// every output depends only on its own input, so the bytes are the same for any thread count.
pub fn encode_srgb8_slice(src: &[Vec3], op: Operator, dst: &mut [[u8; 3]]) -> Result<(), BrdfError> {
    if src.len() != dst.len() {
        return Err(BrdfError::InvalidInput {
            name: "dst",
            problem: format!("has {} pixels, expected {} (the length of the source)", dst.len(), src.len()),
        });
    }
    let src: &[f32] = bytemuck::cast_slice(src);
    let dst: &mut [u8] = bytemuck::cast_slice_mut(dst);
    crate::batch::for_each_chunk(dst, |offset, chunk| {
        encode_srgb8_channels(&src[offset..offset + chunk.len()], 1.0, op, chunk);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_encoding_equals_the_formula() {
        let formula = |c: f32| to_u8(srgb_encode_f32(c));
        // At and just below every threshold: the level steps exactly there.
        for (k, &t) in srgb8_table().thresholds[..255].iter().enumerate() {
            assert_eq!(formula(t), k as u8 + 1, "at threshold {k}");
            assert_eq!(srgb8_f32(t), k as u8 + 1);
            let below = f32::from_bits(t.to_bits() - 1);
            assert_eq!(formula(below), k as u8, "below threshold {k}");
            assert_eq!(srgb8_f32(below), k as u8);
        }
        // A dense sweep of bit patterns over [0, 1], and values outside it.
        for bits in (0..=1.0f32.to_bits()).step_by(997) {
            let c = f32::from_bits(bits);
            assert_eq!(srgb8_f32(c), formula(c), "{c:e}");
        }
        for c in [-1.0, -0.0, 1.0, 1.5, f32::INFINITY, f32::NEG_INFINITY, f32::NAN] {
            assert_eq!(srgb8_f32(c), formula(c), "{c}");
        }
    }

    #[test]
    fn channel_encoder_equals_the_per_pixel_one_for_every_operator_and_exposure() {
        // Every f32 bit pattern class: a sweep of [0, 1] and beyond, negatives, NaN, ±∞, sub-normals;
        // a length that is not a multiple of the vector width leaves a scalar tail.
        let mut src: Vec<f32> = (0..=1.1f32.to_bits()).step_by(4099).map(f32::from_bits).collect();
        src.extend([
            -0.0,
            -1.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-45,
            0.0031308,
            7.0,
        ]);
        src.truncate(src.len() / 3 * 3 - 1);
        let ops =
            [Operator::Clamp, Operator::Reinhard, Operator::ReinhardExtended { white: 4.0 }, Operator::Aces];
        for op in ops {
            for scale in [1.0f32, 0.5, 3.0] {
                let mut got = vec![0u8; src.len()];
                encode_srgb8_channels(&src, scale, op, &mut got);
                for (i, (&x, &g)) in src.iter().zip(&got).enumerate() {
                    let want = encode_srgb8(Vec3::splat(x) * scale, op)[0];
                    assert_eq!(g, want, "{op:?} scale {scale} channel {i} = {x:e}");
                }
            }
        }
    }

    #[test]
    fn decode_inverts_encode_on_the_unit_interval() {
        for i in 0..=1000 {
            let c = i as f32 / 1000.0;
            assert!((srgb_decode_f32(srgb_encode_f32(c)) - c).abs() < 2e-6, "{c}");
        }
    }
}
