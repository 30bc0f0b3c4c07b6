//! Binning triangles into screen tiles and the coverage pass over one tile.
//!
//! ## Tiles are full-width bands
//! A tile is a band of about [`BAND_ROWS`] **sample** rows across the whole width: [`band_rows`]`(s)`
//! image rows at `s × s` samples per pixel (16, 8, 5, 4 rows for 1, 4, 9, 16 samples per pixel), so a
//! band's sample buffers hold about `16 · width · s` samples whatever `s` (memory grows with `s`, not
//! `s²`). A band is one contiguous slice of every row-major buffer (colour, depth, normal,
//! triangle id), so rayon hands each band its own `&mut` slices — no locks, no `unsafe`, no copy from
//! tile storage to the image — and 1080p gives 68 units of work, enough to balance two or more threads.
//! A band's depth and id scratch (1920 × 16 samples ≈ 240 KB) stays in L2 while its triangles are drawn.
//!
//! ## Binning in parallel, deterministically
//! Triangles are set up in fixed chunks of [`CHUNK_FACES`] faces of one instance (the chunk size never
//! depends on the thread count). Each chunk bins its own triangles into per-band lists by a counting
//! sort. A band then walks chunk 0's list, chunk 1's list, …: every band sees its triangles in
//! submission order, so the depth test's ties and the output are bit-identical for any number of
//! threads.
//!
//! A triangle is referenced as `(chunk << LOCAL_BITS) | local` (a [`TriRef`]).

use crate::setup::{InterpTri, RasterTri};

/// Sample rows per band (tile height) without supersampling; see [`band_rows`].
pub const BAND_ROWS: u32 = 16;

/// Image rows per band at `s × s` samples per pixel: `BAND_ROWS / s`, at least 1. Which rows a band
/// holds changes no result (every sample is rasterized and shaded on its own), only memory and work.
#[inline]
pub const fn band_rows(s: u32) -> u32 {
    let r = BAND_ROWS / s;
    if r == 0 { 1 } else { r }
}
/// Mesh faces per setup chunk.
pub const CHUNK_FACES: usize = 4096;
/// Bits of a [`TriRef`] for the triangle within its chunk (a face clips into at most 7 triangles).
pub const LOCAL_BITS: u32 = 15;
/// Most chunks a frame can have (keeps every [`TriRef`] below [`NO_TRI`]).
pub const MAX_CHUNKS: usize = (1 << (32 - LOCAL_BITS)) - 1;

/// Reference to a set-up triangle: `(chunk << LOCAL_BITS) | index in the chunk`.
pub type TriRef = u32;
/// "No triangle" in id buffers.
pub const NO_TRI: u32 = u32::MAX;

/// The set-up triangles of one chunk, binned into bands.
#[derive(Debug, Default)]
pub struct Chunk {
    /// The instance whose faces the chunk holds.
    pub instance: u32,
    /// Coverage data, in submission order.
    pub raster: Vec<RasterTri>,
    /// Interpolation data, parallel to `raster`.
    pub interp: Vec<InterpTri>,
    /// `band_start[b]..band_start[b+1]` indexes `band_tris` for band `b`.
    pub band_start: Vec<u32>,
    /// Local triangle indices, grouped by band, in submission order within a band.
    pub band_tris: Vec<u16>,
    /// Flat shading: what the reflectance model gives at each triangle's face (a fixed number of
    /// values per triangle, parallel to `raster`); empty otherwise.
    pub flat: Vec<glam::Vec3>,
}

impl Chunk {
    /// Bin the chunk's triangles into `n_bands` bands of `band_samples` rows each (counting sort, stable).
    pub fn bin(&mut self, band_samples: u32, n_bands: usize) {
        let bs = band_samples as i32;
        let mut count = vec![0u32; n_bands + 1];
        for t in &self.raster {
            for b in (t.min_y / bs)..=(t.max_y / bs) {
                count[b as usize + 1] += 1;
            }
        }
        for b in 0..n_bands {
            count[b + 1] += count[b];
        }
        let mut fill = count.clone();
        self.band_tris = vec![0; count[n_bands] as usize];
        for (i, t) in self.raster.iter().enumerate() {
            for b in (t.min_y / bs)..=(t.max_y / bs) {
                let slot = &mut fill[b as usize];
                self.band_tris[*slot as usize] = i as u16;
                *slot += 1;
            }
        }
        self.band_start = count;
    }

    /// The local indices binned into band `b`.
    #[inline]
    pub fn band(&self, b: usize) -> &[u16] {
        &self.band_tris[self.band_start[b] as usize..self.band_start[b + 1] as usize]
    }
}

/// Receives the samples a triangle covers during the coverage pass.
pub trait Fragments {
    /// Sample `index` (row-major within the band) is covered by triangle `tri` at window depth `z`.
    fn fragment(&mut self, index: usize, z: f32, tri: TriRef);
}

/// Depth test "less" against a depth buffer cleared to 1 (far), keeping the id of the nearest
/// triangle: a visibility buffer. Equal depths keep the earlier triangle (submission order).
#[derive(Debug)]
pub struct DepthTest<'a> {
    /// Window depth per sample.
    pub depth: &'a mut [f32],
    /// Nearest triangle per sample, [`NO_TRI`] where none.
    pub tri: &'a mut [TriRef],
}

impl Fragments for DepthTest<'_> {
    #[inline(always)]
    fn fragment(&mut self, index: usize, z: f32, tri: TriRef) {
        if z < self.depth[index] {
            self.depth[index] = z;
            self.tri[index] = tri;
        }
    }
}

/// Counts how many triangles cover each sample, without a depth test (the watertightness check of
/// dEQP's fill-rule tests and piglit's overdraw fan).
#[derive(Debug)]
pub struct CoverageCount<'a> {
    /// Count per sample.
    pub count: &'a mut [u32],
}

impl Fragments for CoverageCount<'_> {
    #[inline(always)]
    fn fragment(&mut self, index: usize, _z: f32, _tri: TriRef) {
        self.count[index] += 1;
    }
}

/// Rasterize band `band` (sample rows `row0..row0 + rows`, `width` samples wide) from every chunk, in
/// submission order, into `sink`. Edge functions are stepped incrementally in `i64`; a sample is
/// covered when all three (fill-rule-biased) edge functions are ≥ 0.
pub fn raster_band<S: Fragments>(
    chunks: &[Chunk],
    band: usize,
    row0: i32,
    rows: i32,
    width: usize,
    sink: &mut S,
) {
    let row_end = row0 + rows - 1;
    for (ci, chunk) in chunks.iter().enumerate() {
        let base = (ci as u32) << LOCAL_BITS;
        for &local in chunk.band(band) {
            let t = &chunk.raster[local as usize];
            let tri = base | u32::from(local);
            let r_first = t.min_y.max(row0);
            let r_last = t.max_y.min(row_end);
            let dr0 = i64::from(r_first - t.min_y);
            let (sx, sy) = ([0, 1, 2].map(|k| t.step_x(k)), [0, 1, 2].map(|k| t.step_y(k)));
            let mut e_row = [0, 1, 2].map(|k| t.e[k] + dr0 * sy[k]);
            let n_cols = (t.max_x - t.min_x + 1) as usize;
            for r in r_first..=r_last {
                let row_base = (r - row0) as usize * width + t.min_x as usize;
                // Depth straight from the plane (not accumulated), so it equals `Plane::at`.
                let z_row = t.z.a0 + (r - t.min_y) as f32 * t.z.dy;
                let mut e = e_row;
                for i in 0..n_cols {
                    if (e[0] | e[1] | e[2]) >= 0 {
                        sink.fragment(row_base + i, z_row + i as f32 * t.z.dx, tri);
                    }
                    e[0] += sx[0];
                    e[1] += sx[1];
                    e[2] += sx[2];
                }
                e_row[0] += sy[0];
                e_row[1] += sy[1];
                e_row[2] += sy[2];
            }
        }
    }
}

/// Split a [`TriRef`] into (chunk, local index).
#[inline(always)]
pub fn split_ref(r: TriRef) -> (usize, usize) {
    ((r >> LOCAL_BITS) as usize, (r & ((1 << LOCAL_BITS) - 1)) as usize)
}
