//! Radiance RGBE (`.hdr`) encoding of linear RGB images (G. Ward, "Real Pixels", Graphics Gems II, 1991):
//! a shared 8-bit exponent and three 8-bit mantissas per pixel, `c = (m + ½)·2^(e − 136)`, about 1 %
//! relative precision over 76 orders of magnitude. Scanlines are written flat (uncompressed), which every
//! reader accepts.

use glam::Vec3;

/// The RGBE bytes of one linear RGB value (negative and non-finite channels as 0): with
/// `m = max(r, g, b) = f·2^e`, `f ∈ [½, 1)`, each channel is `⌊c·256/2^e⌋` and the exponent `e + 128`.
#[inline]
pub fn rgbe(c: Vec3) -> [u8; 4] {
    let c = Vec3::select(c.cmpgt(Vec3::ZERO) & c.is_finite_mask(), c, Vec3::ZERO);
    let m = c.max_element();
    if !(m >= 1e-32) {
        return [0; 4];
    }
    // frexp: m = f·2^e with f ∈ [0.5, 1).
    let e = m.log2().floor() as i32 + 1;
    let scale = (256.0f64 / 2f64.powi(e)) as f32;
    let q = |x: f32| (x * scale).min(255.0) as u8;
    [q(c.x), q(c.y), q(c.z), (e + 128).clamp(0, 255) as u8]
}

/// A complete `.hdr` file of a `width × height` image, `pixels` row-major from the top.
pub fn encode(width: usize, height: usize, pixels: &[Vec3]) -> Vec<u8> {
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n").into_bytes();
    out.reserve(4 * pixels.len());
    for p in &pixels[..(width * height).min(pixels.len())] {
        out.extend_from_slice(&rgbe(*p));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(b: [u8; 4]) -> Vec3 {
        if b[3] == 0 {
            return Vec3::ZERO;
        }
        let s = 2f32.powi(i32::from(b[3]) - 136);
        Vec3::new(f32::from(b[0]) + 0.5, f32::from(b[1]) + 0.5, f32::from(b[2]) + 0.5) * s
    }

    #[test]
    fn values_round_trip_to_the_format_precision() {
        for c in [Vec3::new(1.0, 0.5, 0.25), Vec3::new(1e-3, 2e-3, 0.0), Vec3::new(3e4, 1.0, 7.0), Vec3::ONE]
        {
            let d = decode(rgbe(c));
            let m = c.max_element();
            assert!((d - c).abs().max_element() <= m / 128.0, "{c} → {d}");
        }
        assert_eq!(rgbe(Vec3::ZERO), [0; 4]);
        assert_eq!(rgbe(Vec3::new(f32::NAN, -1.0, 0.0)), [0; 4]);
        let f = encode(2, 1, &[Vec3::ONE, Vec3::ZERO]);
        assert!(f.starts_with(b"#?RADIANCE\n"));
        assert_eq!(f.len(), "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".len() + 8);
    }
}
