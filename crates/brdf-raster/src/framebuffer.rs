//! The rendered frame: an HDR linear-RGB float image plus depth, normal and triangle-id buffers, all
//! row-major with row 0 at the top; supersampling resolve; tone mapping → sRGB → 8 bits.

use brdf_core::tonemap::{self, Operator};
use glam::Vec3;
use rayon::prelude::*;

use crate::tiles::NO_TRI;

/// Sample buffers of one band at the supersampled resolution, reused from band to band.
#[derive(Debug, Default)]
pub(crate) struct BandScratch {
    pub depth: Vec<f32>,
    pub tri: Vec<u32>,
    pub hdr: Vec<Vec3>,
    pub normal: Vec<Vec3>,
    pub face: Vec<u32>,
}

impl BandScratch {
    /// Clear for `n` samples: depth to 1 (far), no triangle.
    pub fn reset(&mut self, n: usize) {
        self.depth.clear();
        self.depth.resize(n, 1.0);
        self.tri.clear();
        self.tri.resize(n, NO_TRI);
        self.hdr.resize(n, Vec3::ZERO);
        self.normal.resize(n, Vec3::ZERO);
        self.face.resize(n, NO_TRI);
    }
}

/// The output slices of one band (image resolution).
pub(crate) struct BandOut<'a> {
    pub hdr: &'a mut [Vec3],
    pub depth: &'a mut [f32],
    pub normal: &'a mut [Vec3],
    pub triangle_id: &'a mut [u32],
}

/// Box-filter `s × s` samples into each output pixel of the band (`width` pixels wide): the HDR colour
/// is the mean of the samples; depth, normal and triangle id are those of the **nearest** sample (the
/// smallest depth, the first in row-major order on ties), so they describe one real surface point.
pub(crate) fn resolve_band(scratch: &BandScratch, s: usize, width: usize, out: BandOut<'_>) {
    let rows = out.depth.len() / width;
    let sw = width * s;
    let inv = 1.0 / (s * s) as f32;
    for y in 0..rows {
        for x in 0..width {
            let mut sum = Vec3::ZERO;
            let mut best = (y * s) * sw + x * s;
            for j in 0..s {
                let row = (y * s + j) * sw + x * s;
                for i in 0..s {
                    sum += scratch.hdr[row + i];
                    if scratch.depth[row + i] < scratch.depth[best] {
                        best = row + i;
                    }
                }
            }
            let o = y * width + x;
            out.hdr[o] = sum * inv;
            out.depth[o] = scratch.depth[best];
            out.normal[o] = scratch.normal[best];
            out.triangle_id[o] = scratch.face[best];
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
    /// render when [`crate::RenderOptions::encode_rgb8`] asked for it; empty otherwise. It is not updated
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
    /// and exposure: `to_u8(srgb_encode(op(c · 2^ev)))` per channel (SCENE.md "Output" with
    /// `op = clamp`, `ev = 0`).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.to_rgb8_with(self.tonemap, self.exposure)
    }

    /// [`Frame::to_rgb8`] with another operator and exposure. Bit-identical for any thread count.
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
        tonemap::encode_srgb8(self.hdr_at(x, y) * self.exposure.exp2(), self.tonemap)
    }

    /// Number of pixels some triangle covers.
    pub fn covered_pixels(&self) -> usize {
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
