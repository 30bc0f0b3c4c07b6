//! The rendered frame: an HDR linear-RGB float image plus depth, normal and triangle-id buffers, all
//! row-major with row 0 at the top; supersampling resolve; tone mapping → sRGB → 8 bits.

use brdf_core::tonemap::{self, Operator};
use glam::Vec3;
use rayon::prelude::*;

use crate::render::Outputs;
use crate::tiles::NO_TRI;

/// Per-thread scratch of one band, reused from band to band: the visibility buffer, and whatever the
/// band needs that is not an output of the render (depth and colour at sample resolution, the colour of
/// the band's pixels for the 8-bit encode, the normals and face ids of supersamples).
#[derive(Debug, Default)]
pub(crate) struct BandScratch {
    pub depth: Vec<f32>,
    pub tri: Vec<u32>,
    pub hdr: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub face: Vec<u32>,
    /// Resolved colour of the band's pixels when HDR is not an output (supersampling).
    pub pixels: Vec<Vec3>,
    /// The covered span of each pixel row of the band ([`covered_spans`]).
    pub spans: Vec<Span>,
}

/// The pixels `start..end` of one image row that hold every pixel of the row some triangle covers
/// (`start == end` for a row of background only). Outside it every pixel is the background.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Span {
    pub start: u32,
    pub end: u32,
}

/// The covered span of every pixel row of a band from its visibility buffer `tri` (`s × s` samples
/// per pixel, `width` pixels wide): a pixel is inside when one of its samples has a triangle.
///
/// Why: most frames show their objects on a background, and the background's pixels all have the same
/// colour and the same 8-bit value; the band encodes and shades only inside the spans.
pub(crate) fn covered_spans(tri: &[u32], s: usize, width: usize, spans: &mut Vec<Span>) {
    let sw = width * s;
    spans.clear();
    for rows in tri.chunks(sw * s) {
        let (mut first, mut last) = (sw, 0);
        for row in rows.chunks(sw) {
            if let Some(a) = row[..first].iter().position(|&t| t != NO_TRI) {
                first = a;
            }
            if let Some(b) = row[last.max(first)..].iter().rposition(|&t| t != NO_TRI) {
                last = last.max(first) + b + 1;
            }
        }
        spans.push(if first < last {
            Span { start: (first / s) as u32, end: last.div_ceil(s) as u32 }
        } else {
            Span::default()
        });
    }
}

/// What [`resolve_band`] gives a pixel all of whose `s × s` samples hold `background` (the same
/// additions in the same order, so the same bits).
pub(crate) fn resolved_background(background: Vec3, s: usize) -> Vec3 {
    if s == 1 {
        return background;
    }
    let mut sum = Vec3::ZERO;
    for _ in 0..s * s {
        sum += background;
    }
    sum * (1.0 / (s * s) as f32)
}

/// The 8-bit encode of the band's pixels `hdr` (`width` pixels a row) into `rgb` (3 bytes a pixel),
/// inside each row's span only; outside it the pixels are the background, whose bytes `background`
/// are encoded once. Every channel is encoded on its own, so the bytes are those of encoding the
/// whole band.
pub(crate) fn encode_band(
    hdr: &[Vec3],
    width: usize,
    spans: &[Span],
    background: [u8; 3],
    scale: f32,
    op: Operator,
    rgb: &mut [u8],
) {
    let src: &[f32] = bytemuck::cast_slice(hdr);
    for (y, (dst, span)) in rgb.chunks_mut(3 * width).zip(spans).enumerate() {
        let (a, b) = (3 * span.start as usize, 3 * span.end as usize);
        let (left, rest) = dst.split_at_mut(a);
        let (inside, right) = rest.split_at_mut(b - a);
        fill_pixels(left, background);
        fill_pixels(right, background);
        if a < b {
            let row = 3 * y * width;
            tonemap::encode_srgb8_channels(&src[row + a..row + b], scale, op, inside);
        }
    }
}

/// Every 3-byte pixel of `dst` (whole pixels) set to `px`: one `memset` when the three bytes are equal
/// (a grey or black background, the usual case), else whole 32-pixel tiles. A pixel-by-pixel copy of the
/// background took a twentieth of a 1080p frame of a sphere (`examples/canonical.rs` under `perf`).
fn fill_pixels(dst: &mut [u8], px: [u8; 3]) {
    if px[0] == px[1] && px[1] == px[2] {
        dst.fill(px[0]);
        return;
    }
    let tile: [u8; 96] = std::array::from_fn(|i| px[i % 3]);
    let mut tiles = dst.chunks_exact_mut(tile.len());
    for t in &mut tiles {
        t.copy_from_slice(&tile);
    }
    let rest = tiles.into_remainder();
    rest.copy_from_slice(&tile[..rest.len()]);
}

/// `buf` resized to `n` elements (old contents kept or zero: every caller overwrites them).
#[inline]
pub(crate) fn sized<T: Copy + Default>(buf: &mut Vec<T>, n: usize) -> &mut [T] {
    buf.resize(n, T::default());
    &mut buf[..n]
}

/// The output slices of one band (image resolution); `None` for a buffer the render does not write.
pub(crate) struct BandOut<'a> {
    pub hdr: Option<&'a mut [Vec3]>,
    pub depth: Option<&'a mut [f32]>,
    pub normal: Option<&'a mut [Vec3]>,
    pub triangle_id: Option<&'a mut [u32]>,
    pub rgb8: Option<&'a mut [u8]>,
}

/// The sample buffers of a band (`s × s` samples per pixel) that [`resolve_band`] reads.
pub(crate) struct BandSamples<'a> {
    pub depth: &'a [f32],
    pub hdr: &'a [Vec3],
    pub normal: Option<&'a [Vec3]>,
    pub face: Option<&'a [u32]>,
}

/// Box-filter `s × s` samples into each output pixel of the band (`width` pixels wide): the HDR colour
/// is the mean of the samples; depth, normal and triangle id are those of the **nearest** sample (the
/// smallest depth, the first in row-major order on ties), so they describe one real surface point.
/// Writes the buffers given (`hdr` always).
pub(crate) fn resolve_band(
    samples: &BandSamples<'_>,
    s: usize,
    width: usize,
    hdr: &mut [Vec3],
    mut depth: Option<&mut [f32]>,
    mut normal: Option<&mut [Vec3]>,
    mut triangle_id: Option<&mut [u32]>,
) {
    let rows = hdr.len() / width;
    let sw = width * s;
    let inv = 1.0 / (s * s) as f32;
    let nearest = depth.is_some() || normal.is_some() || triangle_id.is_some();
    for y in 0..rows {
        for x in 0..width {
            let mut sum = Vec3::ZERO;
            let mut best = (y * s) * sw + x * s;
            for j in 0..s {
                let row = (y * s + j) * sw + x * s;
                for i in 0..s {
                    sum += samples.hdr[row + i];
                    if nearest && samples.depth[row + i] < samples.depth[best] {
                        best = row + i;
                    }
                }
            }
            let o = y * width + x;
            hdr[o] = sum * inv;
            if let Some(d) = depth.as_deref_mut() {
                d[o] = samples.depth[best];
            }
            if let (Some(n), Some(sn)) = (normal.as_deref_mut(), samples.normal) {
                n[o] = sn[best];
            }
            if let (Some(t), Some(sf)) = (triangle_id.as_deref_mut(), samples.face) {
                t[o] = sf[best];
            }
        }
    }
}

/// A rendered image and its auxiliary buffers (all `width × height`, row-major, row 0 at the top).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGB radiance before tone mapping (the background colour where nothing was drawn).
    ///
    /// Each buffer is empty when the render did not ask for it ([`crate::Outputs`]).
    pub hdr: Vec<Vec3>,
    /// Window depth in [0, 1] (`(z_ndc + 1)/2`, GL's default depth range); 1 where nothing was drawn.
    pub depth: Vec<f32>,
    /// Unit world-space shading normal; zero where nothing was drawn.
    pub normal: Vec<Vec3>,
    /// Face index, counting the faces of all instances in scene order; [`NO_TRI`] (`u32::MAX`) where
    /// nothing was drawn.
    pub triangle_id: Vec<u32>,
    /// Tone-mapping operator [`Frame::to_rgb8`] applies.
    pub tonemap: Operator,
    /// Exposure in stops applied before tone mapping (`c · 2^exposure`).
    pub exposure: f32,
    /// The 8-bit sRGB image of [`Frame::to_rgb8`] (`height × width × 3` bytes) as encoded during the
    /// render when [`crate::Outputs::RGB8`] asked for it; empty otherwise. It is not updated
    /// when `hdr`, `tonemap` or `exposure` change afterwards: call [`Frame::to_rgb8`] then.
    pub rgb8: Vec<u8>,
}

/// An empty 0 × 0 frame (clamp, exposure 0): a target for [`crate::render::render_into`], which sizes it.
impl Default for Frame {
    fn default() -> Self {
        Self {
            width: 0,
            height: 0,
            hdr: Vec::new(),
            depth: Vec::new(),
            normal: Vec::new(),
            triangle_id: Vec::new(),
            tonemap: Operator::Clamp,
            exposure: 0.0,
            rgb8: Vec::new(),
        }
    }
}

impl Frame {
    /// Bytes held by the frame's buffers (their capacity).
    pub fn heap_bytes(&self) -> usize {
        self.hdr.capacity() * size_of::<Vec3>()
            + self.depth.capacity() * size_of::<f32>()
            + self.normal.capacity() * size_of::<Vec3>()
            + self.triangle_id.capacity() * size_of::<u32>()
            + self.rgb8.capacity()
    }

    /// The buffers the frame holds (those its render asked for): a buffer counts when it has
    /// `width · height` elements (times 3 for the 8-bit image).
    pub fn outputs(&self) -> Outputs {
        let n = self.width as usize * self.height as usize;
        let mut o = Outputs::NONE;
        for (present, x) in [
            (self.rgb8.len() == 3 * n, Outputs::RGB8),
            (self.hdr.len() == n, Outputs::HDR),
            (self.depth.len() == n, Outputs::DEPTH),
            (self.normal.len() == n, Outputs::NORMAL),
            (self.triangle_id.len() == n, Outputs::TRIANGLE_ID),
        ] {
            if present && n > 0 {
                o = o | x;
            }
        }
        o
    }

    /// Pixel index of column `x`, row `y` (from the top).
    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// HDR colour at column `x`, row `y`.
    pub fn hdr_at(&self, x: u32, y: u32) -> Vec3 {
        self.hdr[self.index(x, y)]
    }

    /// The 8-bit sRGB image (`height × width × 3` bytes, row 0 at the top) with the frame's tone map
    /// and exposure: `to_u8(srgb_encode(op(c · 2^ev)))` per channel (the canonical scene's output
    /// uses `op = clamp`, `ev = 0`). Encoded from [`Frame::hdr`]; a frame rendered without HDR but with
    /// [`Outputs::RGB8`] gives a copy of [`Frame::rgb8`] (the same bytes).
    pub fn to_rgb8(&self) -> Vec<u8> {
        if self.hdr.is_empty() {
            return self.rgb8.clone();
        }
        self.to_rgb8_with(self.tonemap, self.exposure)
    }

    /// [`Frame::to_rgb8`] with another operator and exposure, encoded from [`Frame::hdr`] (empty
    /// when the frame has no HDR buffer). Bit-identical for any thread count.
    pub fn to_rgb8_with(&self, op: Operator, exposure: f32) -> Vec<u8> {
        let mut out = vec![0u8; self.hdr.len() * 3];
        let scale = exposure.exp2();
        // Channels are independent: encode the flat HDR buffer in blocks of 16 rows of 1080p.
        let src: &[f32] = bytemuck::cast_slice(&self.hdr);
        const BLOCK: usize = 3 * 1920 * 16;
        out.par_chunks_mut(BLOCK).zip(src.par_chunks(BLOCK)).for_each(|(dst, src)| {
            tonemap::encode_srgb8_channels(src, scale, op, dst);
        });
        out
    }

    /// The 8-bit sRGB value of one pixel (as [`Frame::to_rgb8`]).
    pub fn rgb8_at(&self, x: u32, y: u32) -> [u8; 3] {
        if self.hdr.is_empty() {
            let i = 3 * self.index(x, y);
            return [self.rgb8[i], self.rgb8[i + 1], self.rgb8[i + 2]];
        }
        tonemap::encode_srgb8(self.hdr_at(x, y) * self.exposure.exp2(), self.tonemap)
    }

    /// Number of pixels some triangle covers, from the triangle ids or else the depth (a pixel is
    /// covered exactly when its depth is below the far value 1: the depth test is "less" against 1).
    /// 0 when the frame has neither.
    pub fn covered_pixels(&self) -> usize {
        if self.triangle_id.is_empty() {
            return self.depth.iter().filter(|&&d| d < 1.0).count();
        }
        self.triangle_id.iter().filter(|&&t| t != NO_TRI).count()
    }

    /// Binary PPM (P6) bytes of [`Frame::to_rgb8`] — a dependency-free image format for examples and
    /// debugging (PNG writing belongs to the Python side, through Pillow).
    pub fn to_ppm(&self) -> Vec<u8> {
        let mut out = format!("P6\n{} {}\n255\n", self.width, self.height).into_bytes();
        out.extend_from_slice(&self.to_rgb8());
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_background_fill_sets_every_pixel_of_any_length_to_its_three_bytes() {
        for px in [[0u8, 0, 0], [7, 7, 7], [1, 2, 3], [255, 0, 128]] {
            for n in [0usize, 1, 31, 32, 33, 65, 1000] {
                let mut dst = vec![9u8; 3 * n];
                fill_pixels(&mut dst, px);
                assert!(dst.chunks_exact(3).all(|p| p == px), "{px:?} × {n}");
            }
        }
    }

    #[test]
    fn a_rows_span_holds_every_covered_pixel_and_starts_and_ends_on_one() {
        // Pseudo-random visibility buffers of 3 pixel rows, 1, 2 and 3 samples per pixel.
        let mut state = 0x9e37_79b9_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        for s in 1..=3usize {
            let width = 11;
            for density in [0u32, 1, 8, 60, 100] {
                let tri: Vec<u32> =
                    (0..3 * s * width * s).map(|_| if next() % 100 < density { 7 } else { NO_TRI }).collect();
                let mut spans = vec![Span { start: 5, end: 9 }]; // cleared by the call
                covered_spans(&tri, s, width, &mut spans);
                assert_eq!(spans.len(), 3);
                for (y, span) in spans.iter().enumerate() {
                    let covered: Vec<usize> = (0..width)
                        .filter(|&x| {
                            (0..s).any(|j| (0..s).any(|i| tri[(y * s + j) * width * s + x * s + i] != NO_TRI))
                        })
                        .collect();
                    match (covered.first(), covered.last()) {
                        (Some(&a), Some(&b)) => {
                            assert_eq!((span.start as usize, span.end as usize), (a, b + 1), "s {s} row {y}")
                        }
                        _ => assert_eq!(span.start, span.end, "s {s} row {y}: nothing covered"),
                    }
                }
            }
        }
    }

    #[test]
    fn the_background_resolved_once_has_the_bits_of_the_box_filter() {
        let bg = Vec3::new(0.1, 0.7, 0.33);
        for s in 1..=4 {
            let samples =
                BandSamples { depth: &vec![1.0; s * s], hdr: &vec![bg; s * s], normal: None, face: None };
            let mut hdr = [Vec3::ZERO];
            resolve_band(&samples, s, 1, &mut hdr, None, None, None);
            assert_eq!(
                hdr[0].to_array().map(f32::to_bits),
                resolved_background(bg, s).to_array().map(f32::to_bits)
            );
        }
    }
}
