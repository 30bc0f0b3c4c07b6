//! The band driver: every band of the frame in parallel, each through coverage (depth test into a
//! visibility buffer), shading and the supersampling resolve, then the in-band 8-bit encode. Only the
//! buffers the render asks for are written ([`super::Outputs`]); what a band needs besides them lives
//! in per-thread scratch the size of one band.

use std::sync::atomic::{AtomicUsize, Ordering};

use brdf_core::tonemap;
use glam::Vec3;
use rayon::prelude::*;

use super::Occlusion;
use super::alpha::AlphaTested;
use super::vertex::Prepared;
use crate::framebuffer::{
    BandOut, BandSamples, BandScratch, Frame, Span, covered_spans, encode_band, resolve_band,
    resolved_background, sized,
};
use crate::tiles::{DepthTest, NO_TRI, band_rows, raster_band};

/// `buf` cut into `n` bands of `per` elements (the last one shorter), or `n` times `None` when the
/// buffer is not an output (empty).
fn bands_of<T>(buf: &mut [T], per: usize, n: usize) -> Vec<Option<&mut [T]>> {
    if buf.is_empty() { (0..n).map(|_| None).collect() } else { buf.chunks_mut(per).map(Some).collect() }
}

impl Prepared<'_> {
    /// Draw every band of the frame in parallel (each band owns its rows of every output buffer).
    pub(super) fn draw(
        &self,
        frame: &mut Frame,
        occlusion: &dyn Occlusion,
        progress: Option<&(dyn Fn(f32) + Sync)>,
    ) {
        let (w, h) = (frame.width as usize, frame.height as usize);
        let band_px = band_rows(self.s as u32) as usize * w;
        let n_bands = h.div_ceil(band_rows(self.s as u32) as usize);
        let done = AtomicUsize::new(0);
        let (scale, op) = (frame.exposure.exp2(), frame.tonemap);
        // The 8-bit value of a pixel that shows only background, encoded once.
        let mut background = [0u8; 3];
        let bg = resolved_background(self.scene.background, self.s);
        tonemap::encode_srgb8_channels(&bg.to_array(), scale, op, &mut background);
        let mut hdr = bands_of(&mut frame.hdr, band_px, n_bands).into_iter();
        let mut depth = bands_of(&mut frame.depth, band_px, n_bands).into_iter();
        let mut normal = bands_of(&mut frame.normal, band_px, n_bands).into_iter();
        let mut id = bands_of(&mut frame.triangle_id, band_px, n_bands).into_iter();
        let mut rgb8 = bands_of(&mut frame.rgb8, 3 * band_px, n_bands).into_iter();
        // Every iterator yields exactly `n_bands` items.
        let bands: Vec<(usize, BandOut<'_>)> = (0..n_bands)
            .map(|b| {
                let out = BandOut {
                    hdr: hdr.next().flatten(),
                    depth: depth.next().flatten(),
                    normal: normal.next().flatten(),
                    triangle_id: id.next().flatten(),
                    rgb8: rgb8.next().flatten(),
                };
                (b, out)
            })
            .collect();
        bands.into_par_iter().for_each_init(BandScratch::default, |scratch, (band, out)| {
            let pixels = w * (h - band * band_px / w).min(band_px / w);
            self.band(band, pixels, scratch, out, occlusion, (scale, op, background));
            if let Some(cb) = progress {
                cb((done.fetch_add(1, Ordering::Relaxed) + 1) as f32 / n_bands as f32);
            }
        });
    }

    /// Coverage of one band into its visibility buffer, through the alpha test when an instance has a
    /// mask ([`AlphaTested`]).
    #[inline]
    fn cover(&self, band: usize, row0: i32, rows: i32, width: usize, mut test: DepthTest<'_>) {
        if self.masks.is_empty() {
            raster_band(&self.chunks, band, row0, rows, width, &mut test);
        } else {
            let mut tested = AlphaTested::new(self, test, row0, width);
            raster_band(&self.chunks, band, row0, rows, width, &mut tested);
        }
    }

    /// With an environment the background differs from pixel to pixel: every row is then shaded and
    /// encoded whole.
    #[inline]
    fn widen_spans(&self, spans: &mut [Span], width: usize) {
        if self.scene.environment.is_some() {
            spans.fill(Span { start: 0, end: width as u32 });
        }
    }

    /// Coverage, shading, resolve and encode of one band (`pixels` pixels) into its output slices.
    /// Without supersampling the band is drawn straight into the frame's slices where they are
    /// outputs; otherwise into sample-resolution scratch buffers that are then box-filtered.
    /// `encode`: the exposure scale, the tone map and the 8-bit value of a background pixel.
    ///
    /// Background outside the covered span of each row ([`covered_spans`]) is neither tone mapped nor
    /// encoded (its bytes are copied), nor, when the colour is scratch, written.
    fn band(
        &self,
        band: usize,
        pixels: usize,
        scratch: &mut BandScratch,
        out: BandOut<'_>,
        occlusion: &dyn Occlusion,
        encode: (f32, tonemap::Operator, [u8; 3]),
    ) {
        let (scale, op, background) = encode;
        let ws = self.viewport.width as usize;
        let width = ws / self.s;
        let rows_s = pixels / width * self.s;
        let row0 = (band * self.band_samples as usize) as i32;
        let n = rows_s * ws;
        let BandScratch {
            depth: s_depth,
            tri,
            hdr: s_hdr,
            normal: s_normal,
            face: s_face,
            pixels: s_pixels,
            spans,
        } = scratch;
        tri.clear();
        tri.resize(n, NO_TRI);
        let BandOut { hdr, depth, normal, triangle_id, rgb8 } = out;
        let hdr: &mut [Vec3] = if self.s == 1 {
            let depth: &mut [f32] = match depth {
                Some(d) => d,
                None => sized(s_depth, n),
            };
            depth.fill(1.0);
            self.cover(band, row0, rows_s as i32, ws, DepthTest { depth, tri });
            covered_spans(tri, 1, width, spans);
            self.widen_spans(spans, width);
            // Scratch colour is read only inside the spans (by the encode).
            let (hdr, within) = match hdr {
                Some(h) => (h, None),
                None => (sized(s_hdr, n), Some(&spans[..])),
            };
            self.shade(band, row0, ws, tri, hdr, normal, triangle_id, occlusion, within);
            hdr
        } else {
            let d = sized(s_depth, n);
            d.fill(1.0);
            self.cover(band, row0, rows_s as i32, ws, DepthTest { depth: d, tri });
            let sh = sized(s_hdr, n);
            let sn = normal.is_some().then(|| sized(s_normal, n));
            let sf = triangle_id.is_some().then(|| sized(s_face, n));
            covered_spans(tri, self.s, width, spans);
            self.widen_spans(spans, width);
            self.shade(band, row0, ws, tri, sh, sn, sf, occlusion, None);
            let samples = BandSamples {
                depth: d,
                hdr: sh,
                normal: normal.is_some().then(|| &s_normal[..n]),
                face: triangle_id.is_some().then(|| &s_face[..n]),
            };
            let hdr = match hdr {
                Some(h) => h,
                None => sized(s_pixels, pixels),
            };
            resolve_band(&samples, self.s, width, hdr, depth, normal, triangle_id);
            hdr
        };
        if let Some(rgb) = rgb8 {
            encode_band(hdr, width, spans, background, scale, op, rgb);
        }
    }
}
