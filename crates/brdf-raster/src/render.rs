//! The rendering pipeline: vertex stage → clipping and triangle setup, binned into bands → per band, a
//! coverage pass (depth test into a visibility buffer) and a shading pass (each visible sample shaded
//! exactly once, with the material's model dispatched once per band and instance) → supersampling
//! resolve.
//!
//! ```text
//! vertices ──(par, per vertex)──▶ world pos/normal, clip pos, outcode, snapped screen pos
//! faces ──(par, chunks of 4096)──▶ reject / clip (near, far, guard band) / cull / setup / bin
//! bands ──(par, 16 rows each)──▶ coverage: depth "less" → nearest triangle per sample
//!                                shading: barycentrics → attributes → illumination model
//!                                resolve: s×s box filter → frame rows of the band
//! ```
//!
//! Every stage is a pure function of its input chunk or band, and bands see triangles in submission
//! order, so the frame is bit-identical for any number of threads.
//!
//! ## Example
//! ```
//! use std::sync::Arc;
//! use brdf_core::{Model, lights::{Attenuation, Light}};
//! use brdf_raster::{Camera, Material, RenderOptions, Scene, ShadingMode, procedural, render};
//! use glam::{Mat4, Vec3};
//!
//! let mut scene = Scene::new();
//! let sphere = Arc::new(procedural::icosphere(3).unwrap());
//! let material = Material::new(Model::build("lambert", &[]).unwrap()).with_ambient(Vec3::splat(0.05));
//! scene.add(sphere, material, Mat4::IDENTITY);
//! scene.add_light(Light::point(Vec3::new(2.0, 2.0, 2.0), Vec3::splat(10.0), Attenuation::InverseSquare).unwrap());
//! let camera = Camera::perspective(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.8, 0.1, 100.0).unwrap();
//! let options = RenderOptions { shading: ShadingMode::Phong, ..RenderOptions::new(64, 48) };
//! let frame = render(&scene, &camera, &options).unwrap();
//! let rgb: Vec<u8> = frame.to_rgb8(); // 48 rows × 64 columns × 3, row 0 at the top
//! assert_eq!(rgb.len(), 64 * 48 * 3);
//! assert_ne!(frame.triangle_id[24 * 64 + 32], u32::MAX); // the centre pixel sees the sphere
//! ```
//!
//! ## Hooks for ambient occlusion and shadows
//! [`render_with`] takes an [`Occlusion`] provider: its obscurance `w(p)` multiplies the ambient term
//! and its visibility `δ_j` multiplies light `j`'s contribution (seed 004 eq. 12.75), evaluated at each
//! shaded point (samples, or vertices in Gouraud mode). [`render`] uses [`NoOcclusion`] (`w = δ = 1`).

use std::sync::atomic::{AtomicUsize, Ordering};

use brdf_core::illumination::{SurfacePoint, Terms, radiance, radiance_lanes};
use brdf_core::lights::Incident;
use brdf_core::models::{Bxdf, ModelVisitor};
use brdf_core::simd::{Lane, LaneKernel, V3, run_widest};
use brdf_core::tonemap::{self, Operator};
use brdf_core::vector::normalize_or_zero;
use glam::{DVec3, Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use crate::RasterError;
use crate::ao::AoOptions;
use crate::camera::Camera;
use crate::clip::{ClipVertex, GuardBand, MAX_POLY, clip_triangle, code};
use crate::framebuffer::{BandOut, BandScratch, Frame, resolve_band};
use crate::occlusion::SceneOcclusion;
use crate::scene::Scene;
use crate::setup::{Culling, SetupVertex, Viewport, setup_triangle};
use crate::shading::{ShadingMode, face_normal, linear_normal, quadratic_normal};
use crate::tiles::{
    BAND_ROWS, CHUNK_FACES, Chunk, CoverageCount, DepthTest, LOCAL_BITS, MAX_CHUNKS, NO_TRI, raster_band,
};

/// Largest accepted image width or height in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest accepted number of samples per frame, `width · height · samples_per_pixel` (2^26, e.g.
/// 8192 × 8192 at one sample per pixel or 2048 × 2048 at 16). A frame holds 32 bytes per pixel (HDR
/// colour, depth, normal, triangle id), so the limit keeps it near 2 GB; each band being drawn needs
/// 8 more bytes per sample of its rows (24 with supersampling).
pub const MAX_SAMPLES: u64 = 1 << 26;

/// How to render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub width: u32,
    /// Image height in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub height: u32,
    /// Shading algorithm (seed 004).
    pub shading: ShadingMode,
    /// Skip triangles whose back (clockwise side) faces the camera.
    pub cull_back_faces: bool,
    /// Supersampling: 1, 4, 9 or 16 samples per pixel on a regular `s × s` grid (`s² = samples`),
    /// resolved by a box filter.
    pub samples_per_pixel: u32,
    /// Tone-mapping operator of [`Frame::to_rgb8`].
    pub tonemap: Operator,
    /// Exposure in stops of [`Frame::to_rgb8`].
    pub exposure: f32,
    /// Ambient obscurance (seed 004 eq. 12.72) weighting the ambient term, per vertex or per pixel;
    /// `None`: off. Used by [`render`] (see [`crate::occlusion::SceneOcclusion`]).
    pub ao: Option<AoOptions>,
    /// Light visibility δ by shadow rays (seed 004 eq. 12.75). Used by [`render`].
    pub shadows: bool,
    /// Also encode the 8-bit image ([`Frame::rgb8`]) during the render, band by band while each band's
    /// HDR colours are still in the cache — cheaper than [`Frame::to_rgb8`] afterwards, which reads the
    /// whole HDR buffer again.
    pub encode_rgb8: bool,
}

impl RenderOptions {
    /// `width × height`, Phong shading, back faces culled, one sample per pixel, clamp, exposure 0.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            shading: ShadingMode::Phong,
            cull_back_faces: true,
            samples_per_pixel: 1,
            tonemap: Operator::Clamp,
            exposure: 0.0,
            ao: None,
            shadows: false,
            encode_rgb8: false,
        }
    }

    /// The supersampling factor per axis `s` (`samples_per_pixel = s²`).
    pub fn ssaa_factor(&self) -> u32 {
        match self.samples_per_pixel {
            4 => 2,
            9 => 3,
            16 => 4,
            _ => 1,
        }
    }

    /// Check the image size against the documented limits and the other options.
    pub fn validate(&self) -> Result<(), RasterError> {
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || v > MAX_IMAGE_SIDE {
                return Err(RasterError::arg(
                    name,
                    format!("must be in 1..={MAX_IMAGE_SIDE} pixels, got {v}"),
                ));
            }
        }
        if ![1, 4, 9, 16].contains(&self.samples_per_pixel) {
            return Err(RasterError::arg(
                "samples_per_pixel",
                format!("must be 1, 4, 9 or 16 (an s×s grid), got {}", self.samples_per_pixel),
            ));
        }
        let samples = u64::from(self.width) * u64::from(self.height) * u64::from(self.samples_per_pixel);
        if samples > MAX_SAMPLES {
            return Err(RasterError::arg(
                "width",
                format!(
                    "{}×{} pixels × {} samples = {samples} samples exceeds the limit of {MAX_SAMPLES}",
                    self.width, self.height, self.samples_per_pixel
                ),
            ));
        }
        if !self.exposure.is_finite() {
            return Err(RasterError::arg("exposure", format!("must be finite, got {}", self.exposure)));
        }
        if let Some(ao) = &self.ao {
            ao.validate()?;
        }
        Ok(())
    }
}

/// A point being shaded, as the [`Occlusion`] hooks see it (world space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadePoint {
    /// Position.
    pub p: Vec3,
    /// Unit shading normal.
    pub n: Vec3,
    /// Instance index in the scene.
    pub instance: u32,
    /// Face index within the instance's mesh ([`NO_TRI`] when shading a vertex in Gouraud mode).
    pub face: u32,
    /// Vertex index within the instance's mesh when shading a vertex (Gouraud), else [`NO_TRI`].
    pub vertex: u32,
    /// Perspective-correct barycentric coordinates in the face (zero when shading a vertex).
    pub bary: Vec3,
}

/// Ambient occlusion and shadow providers (seed 004 eq. 12.75), called at every shaded point.
pub trait Occlusion: Sync {
    /// `true` promises `obscurance = 1`, `visibility = 1` and `indirect = 0` everywhere, so that the
    /// renderer may shade eight samples at a time without calling the hooks (same bits).
    const TRIVIAL: bool = false;

    /// Obscurance `w(p) ∈ [0, 1]` multiplying the ambient term (1 = fully open).
    fn obscurance(&self, _at: &ShadePoint) -> f32 {
        1.0
    }
    /// Visibility `δ ∈ [0, 1]` of light `light` (index into `Scene::lights`) from the point, given
    /// what arrives from it (`incident.l`, `incident.distance` bound a shadow ray). 1 = unshadowed.
    fn visibility(&self, _at: &ShadePoint, _light: usize, _incident: &Incident) -> f32 {
        1.0
    }
    /// Extra ambient-like radiance at the point, given its obscurance `w` (linear RGB, tinted by vertex
    /// colours like the rest): eq. 12.75's `k_d ∘ I_d(p) · w(p)` in the combined mode of
    /// [`crate::occlusion::SceneOcclusion`]. None by default.
    fn indirect(&self, _at: &ShadePoint, _w: f32) -> Vec3 {
        Vec3::ZERO
    }
}

/// No occlusion: `w = δ = 1` everywhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoOcclusion;

impl Occlusion for NoOcclusion {
    const TRIVIAL: bool = true;
}

/// Render `scene` through `camera`, with the obscurance and shadows that `options.ao` and
/// `options.shadows` ask for ([`crate::occlusion::SceneOcclusion`]).
pub fn render(scene: &Scene, camera: &Camera, options: &RenderOptions) -> Result<Frame, RasterError> {
    if options.ao.is_some() || options.shadows {
        options.validate()?;
        let occlusion = SceneOcclusion::new(scene, options.ao, options.shadows)?;
        return render_with(scene, camera, options, &occlusion, None);
    }
    render_with(scene, camera, options, &NoOcclusion, None)
}

/// Render with ambient-occlusion / shadow providers and an optional progress callback (called with the
/// fraction of bands done, from worker threads, in no particular order).
pub fn render_with<O: Occlusion>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    occlusion: &O,
    progress: Option<&(dyn Fn(f32) + Sync)>,
) -> Result<Frame, RasterError> {
    // An empty frame: `render_with_into` allocates its buffers zeroed (pages are mapped lazily, on first
    // write, by the band that owns them).
    let mut frame = Frame::default();
    render_with_into(scene, camera, options, occlusion, progress, &mut frame)?;
    Ok(frame)
}

/// [`render`] into an existing frame, reusing its buffers (resized when the image size changed), as an
/// interactive application redraws its framebuffer: no per-frame allocation of the output.
pub fn render_into(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    frame: &mut Frame,
) -> Result<(), RasterError> {
    if options.ao.is_some() || options.shadows {
        options.validate()?;
        let occlusion = SceneOcclusion::new(scene, options.ao, options.shadows)?;
        return render_with_into(scene, camera, options, &occlusion, None, frame);
    }
    render_with_into(scene, camera, options, &NoOcclusion, None, frame)
}

/// [`render_with`] into an existing frame (see [`render_into`]).
pub fn render_with_into<O: Occlusion>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    occlusion: &O,
    progress: Option<&(dyn Fn(f32) + Sync)>,
    frame: &mut Frame,
) -> Result<(), RasterError> {
    let prep = Prepared::new(scene, camera, options, occlusion)?;
    let n = options.width as usize * options.height as usize;
    frame.width = options.width;
    frame.height = options.height;
    frame.tonemap = options.tonemap;
    frame.exposure = options.exposure;
    // Every element is overwritten by its band, so the old contents need neither clearing nor, when a
    // buffer is too small, copying into a larger one (a fresh zeroed allocation maps its pages lazily).
    fn fit<T: bytemuck::Zeroable + Clone>(buf: &mut Vec<T>, n: usize) {
        if buf.capacity() < n {
            *buf = bytemuck::zeroed_vec(n);
        } else {
            buf.resize(n, T::zeroed());
        }
    }
    fit(&mut frame.hdr, n);
    fit(&mut frame.depth, n);
    fit(&mut frame.normal, n);
    fit(&mut frame.triangle_id, n);
    if options.encode_rgb8 {
        fit(&mut frame.rgb8, 3 * n);
    } else {
        frame.rgb8.clear();
    }
    prep.draw(frame, occlusion, progress);
    prep.release();
    Ok(())
}

/// How many triangles cover each sample (no depth test), for checking the fill rule and clipping: on a
/// closed, non-overlapping tiling every count is exactly 1. Row-major over the sample grid
/// (`width·s × height·s` for `samples_per_pixel = s²`); the shading options are ignored.
pub fn coverage_counts(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<Vec<u32>, RasterError> {
    let prep = Prepared::new(scene, camera, options, &NoOcclusion)?;
    let ws = prep.viewport.width as usize;
    let band_samples = prep.band_samples as usize * ws;
    let mut counts = vec![0u32; ws * prep.viewport.height as usize];
    counts.par_chunks_mut(band_samples).enumerate().for_each(|(band, count)| {
        let rows = (count.len() / ws) as i32;
        raster_band(
            &prep.chunks,
            band,
            band as i32 * prep.band_samples as i32,
            rows,
            ws,
            &mut CoverageCount { count },
        );
    });
    Ok(counts)
}

/// What triangle setup needs of a vertex (16 bytes, so the setup loop streams through little memory).
#[derive(Debug, Clone, Copy, Default, bytemuck::Zeroable)]
struct ScreenVertex {
    /// Snapped screen position and window depth, valid when `code & MUST_CLIP == 0`.
    x: i32,
    y: i32,
    z: f32,
    code: u16,
}

impl ScreenVertex {
    #[inline]
    fn setup(&self) -> SetupVertex {
        SetupVertex { x: i64::from(self.x), y: i64::from(self.y), z: self.z }
    }
}

/// What shading needs of a vertex: world position and unit world normal.
#[derive(Debug, Clone, Copy, Default, bytemuck::Zeroable)]
struct WorldVertex {
    p: Vec3,
    n: Vec3,
}

/// Per-instance data of the frame.
struct InstanceData {
    vertex_base: usize,
    face_base: u32,
    mirrored: bool,
    terms: Terms,
}

/// Everything the bands need: transformed vertices, binned triangles, per-vertex colours.
struct Prepared<'a> {
    scene: &'a Scene,
    shading: ShadingMode,
    viewport: Viewport,
    s: usize,
    band_samples: u32,
    screen: Vec<ScreenVertex>,
    clip: Vec<Vec4>,
    world: Vec<WorldVertex>,
    instances: Vec<InstanceData>,
    /// Gouraud: the illumination at every vertex.
    vertex_color: Vec<Vec3>,
    rays: Rays,
    /// The eye, and `normalize(eye − target)`: the constant view vector of an orthographic camera.
    eye: Vec3A,
    backward: Vec3A,
    ortho_view: Option<Vec3A>,
    chunks: Vec<Chunk>,
}

impl<'a> Prepared<'a> {
    fn new<O: Occlusion>(
        scene: &'a Scene,
        camera: &'a Camera,
        options: &RenderOptions,
        occlusion: &O,
    ) -> Result<Self, RasterError> {
        options.validate()?;
        camera.validate()?;
        scene.validate()?;
        let s = options.ssaa_factor();
        let viewport = Viewport { width: options.width * s, height: options.height * s };
        let guard = GuardBand::new(viewport.width, viewport.height);
        let view_proj = camera.view_projection(options.width as f32 / options.height as f32);

        // Vertex stage, written in parallel straight into three arrays.
        let n_vertices: usize = scene.instances.iter().map(|i| i.mesh.positions.len()).sum();
        // Zeroed allocations: the pages are touched first by the parallel writers below.
        let mut screen: Vec<ScreenVertex> = bytemuck::zeroed_vec(n_vertices);
        let mut clip: Vec<Vec4> = bytemuck::zeroed_vec(n_vertices);
        let mut world: Vec<WorldVertex> = bytemuck::zeroed_vec(n_vertices);
        let mut instances = Vec::with_capacity(scene.instances.len());
        let (mut vertex_base, mut face_base) = (0usize, 0u32);
        for inst in &scene.instances {
            let m = inst.transform;
            let nm = inst.normal_matrix();
            let mesh = &inst.mesh;
            let n = mesh.positions.len();
            instances.push(InstanceData {
                vertex_base,
                face_base,
                mirrored: inst.mirrors(),
                terms: Terms {
                    emission: inst.material.emission,
                    ambient: inst.material.ambient,
                    ambient_light: scene.ambient_light,
                },
            });
            let range = vertex_base..vertex_base + n;
            screen[range.clone()]
                .par_iter_mut()
                .zip(clip[range.clone()].par_iter_mut())
                .zip(world[range].par_iter_mut())
                .zip(mesh.positions.par_iter().zip(mesh.normals.par_iter()))
                .with_min_len(4096)
                .for_each(|(((sv, cv), wv), (&p, &n))| {
                    let p = m.transform_point3(p);
                    *wv = WorldVertex { p, n: (nm * n).normalize_or_zero() };
                    *cv = view_proj * p.extend(1.0);
                    let code = guard.outcode(*cv);
                    *sv = ScreenVertex { code, ..ScreenVertex::default() };
                    if code & code::MUST_CLIP == 0 {
                        let snapped = viewport.snap(*cv);
                        (sv.x, sv.y, sv.z) = (snapped.x as i32, snapped.y as i32, snapped.z);
                    }
                });
            vertex_base += n;
            face_base += mesh.indices.len() as u32;
        }

        let mut prep = Prepared {
            scene,
            shading: options.shading,
            viewport,
            s: s as usize,
            band_samples: BAND_ROWS * s,
            screen,
            clip,
            world,
            instances,
            vertex_color: Vec::new(),
            rays: Rays::new(&view_proj, viewport, (!camera.is_orthographic()).then_some(camera.eye)),
            eye: camera.eye.into(),
            backward: camera.backward().into(),
            ortho_view: camera.is_orthographic().then(|| camera.backward().into()),
            chunks: Vec::new(),
        };
        if prep.shading == ShadingMode::Gouraud {
            prep.vertex_color = prep.vertex_colors(occlusion);
        }

        // Setup and binning, in chunks of faces of one instance.
        let mut jobs = Vec::new();
        for (k, inst) in scene.instances.iter().enumerate() {
            let n = inst.mesh.indices.len();
            jobs.extend((0..n).step_by(CHUNK_FACES).map(|start| (k, start, (start + CHUNK_FACES).min(n))));
        }
        if jobs.len() > MAX_CHUNKS {
            return Err(RasterError::arg(
                "scene",
                format!("too many faces ({} chunks of {CHUNK_FACES})", jobs.len()),
            ));
        }
        let n_bands = viewport.height.div_ceil(prep.band_samples) as usize;
        let cull = options.cull_back_faces;
        prep.chunks = jobs
            .par_iter()
            .map(|&(k, start, end)| {
                let mut chunk = prep.setup_chunk(k, start, end, cull, &guard);
                chunk.bin(prep.band_samples, n_bands);
                chunk
            })
            .collect();
        Ok(prep)
    }

    /// Free the per-frame arrays on the pool's threads: returning tens of megabytes to the system
    /// (munmap) is slow enough to unbalance the threads when one of them does it all.
    fn release(self) {
        let Prepared { screen, clip, world, vertex_color, chunks, .. } = self;
        rayon::join(
            || chunks.into_par_iter().with_max_len(8).for_each(drop),
            || {
                rayon::join(|| drop(screen), || drop(clip));
                rayon::join(|| drop(world), || drop(vertex_color));
            },
        );
    }

    /// Draw every band of the frame in parallel (each band owns its rows of every buffer).
    fn draw<O: Occlusion>(&self, frame: &mut Frame, occlusion: &O, progress: Option<&(dyn Fn(f32) + Sync)>) {
        let (w, h) = (frame.width as usize, frame.height as usize);
        let band_px = BAND_ROWS as usize * w;
        let n_bands = h.div_ceil(BAND_ROWS as usize);
        let done = AtomicUsize::new(0);
        let (scale, op) = (frame.exposure.exp2(), frame.tonemap);
        let band_work = |scratch: &mut BandScratch, band: usize, out: BandOut<'_>, rgb: Option<&mut [u8]>| {
            let BandOut { hdr, depth, normal, triangle_id } = out;
            self.band(band, scratch, BandOut { hdr: &mut *hdr, depth, normal, triangle_id }, occlusion);
            if let Some(rgb) = rgb {
                tonemap::encode_srgb8_channels(bytemuck::cast_slice(hdr), scale, op, rgb);
            }
            if let Some(cb) = progress {
                cb((done.fetch_add(1, Ordering::Relaxed) + 1) as f32 / n_bands as f32);
            }
        };
        let bands = frame
            .hdr
            .par_chunks_mut(band_px)
            .zip(frame.depth.par_chunks_mut(band_px))
            .zip(frame.normal.par_chunks_mut(band_px))
            .zip(frame.triangle_id.par_chunks_mut(band_px))
            .map(|(((hdr, depth), normal), triangle_id)| BandOut { hdr, depth, normal, triangle_id });
        if frame.rgb8.is_empty() {
            bands.enumerate().for_each_init(BandScratch::default, |scratch, (band, out)| {
                band_work(scratch, band, out, None);
            });
        } else {
            bands
                .zip(frame.rgb8.par_chunks_mut(3 * band_px))
                .enumerate()
                .for_each_init(BandScratch::default, |scratch, (band, (out, rgb))| {
                    band_work(scratch, band, out, Some(rgb))
                });
        }
    }

    /// Reject, clip, cull and set up faces `start..end` of instance `k`.
    fn setup_chunk(&self, k: usize, start: usize, end: usize, cull: bool, guard: &GuardBand) -> Chunk {
        let inst = &self.instances[k];
        let mesh = &self.scene.instances[k].mesh;
        let culling = Culling { back: cull, mirrored: inst.mirrored };
        let range = inst.vertex_base..inst.vertex_base + mesh.positions.len();
        let (screen, clip) = (&self.screen[range.clone()], &self.clip[range]);
        let mut chunk = Chunk { instance: k as u32, ..Chunk::default() };
        chunk.raster.reserve((end - start) / 2);
        chunk.interp.reserve((end - start) / 2);
        for (f, idx) in mesh.indices[start..end].iter().enumerate() {
            let face = (start + f) as u32;
            let v = idx.map(|i| &screen[i as usize]);
            if v[0].code & v[1].code & v[2].code & code::REJECT != 0 {
                continue;
            }
            let any = v[0].code | v[1].code | v[2].code;
            if any & code::MUST_CLIP == 0 {
                let tri = [v[0].setup(), v[1].setup(), v[2].setup()];
                if let Some((r, i)) = setup_triangle(tri, self.viewport, culling, face, k as u32) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
                continue;
            }
            let tri = [0, 1, 2].map(|j| {
                let mut bary = Vec3::ZERO;
                bary[j] = 1.0;
                ClipVertex { pos: clip[idx[j] as usize], bary }
            });
            let poly = clip_triangle(tri, any & code::MUST_CLIP, guard);
            if poly.len < 3 {
                continue;
            }
            let mut snapped = [SetupVertex { x: 0, y: 0, z: 0.0 }; MAX_POLY];
            for (s, c) in snapped.iter_mut().zip(&poly.v[..poly.len]) {
                *s = self.viewport.snap(c.pos);
            }
            for j in 1..poly.len - 1 {
                let tri = [snapped[0], snapped[j], snapped[j + 1]];
                if let Some((r, i)) = setup_triangle(tri, self.viewport, culling, face, k as u32) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
            }
        }
        chunk
    }

    /// Gouraud: the illumination model at every vertex with its vertex normal.
    fn vertex_colors<O: Occlusion>(&self, occlusion: &O) -> Vec<Vec3> {
        struct Job<'b, O> {
            prep: &'b Prepared<'b>,
            k: usize,
            out: &'b mut [Vec3],
            occlusion: &'b O,
        }
        impl<O: Occlusion> ModelVisitor for Job<'_, O> {
            type Output = ();
            fn visit<M: Bxdf>(self, m: &M) {
                let data = &self.prep.instances[self.k];
                let world = &self.prep.world[data.vertex_base..];
                let colors = self.prep.scene.instances[self.k].mesh.colors.as_deref();
                self.out.par_iter_mut().enumerate().with_min_len(1024).for_each(|(i, out)| {
                    let at = ShadePoint {
                        p: world[i].p,
                        n: world[i].n,
                        instance: self.k as u32,
                        face: NO_TRI,
                        vertex: i as u32,
                        bary: Vec3::ZERO,
                    };
                    *out = self.prep.illuminate(m, &data.terms, &at, colors.map(|c| c[i]), self.occlusion);
                });
            }
        }
        let mut out: Vec<Vec3> = bytemuck::zeroed_vec(self.world.len());
        for (k, inst) in self.scene.instances.iter().enumerate() {
            let base = self.instances[k].vertex_base;
            let out = &mut out[base..base + inst.mesh.positions.len()];
            inst.material.model.visit(Job { prep: self, k, out, occlusion });
        }
        out
    }

    /// The unit view direction at `F::LANES` points, as [`Prepared::illuminate`] computes it at one.
    #[inline(always)]
    fn view_lanes<F: Lane>(&self, p: V3<F>) -> V3<F> {
        match self.ortho_view {
            Some(v) => V3::splat(v.into()),
            None => {
                let (v, ok) = (V3::splat(self.eye.into()) - p).normalize_or_zero();
                V3::select(ok, v, V3::splat(self.backward.into()))
            }
        }
    }

    /// The illumination model at a point, with the mesh's vertex colour (if any) tinting everything but
    /// the emission.
    #[inline(always)]
    fn illuminate<M: Bxdf, O: Occlusion>(
        &self,
        m: &M,
        terms: &Terms,
        at: &ShadePoint,
        tint: Option<Vec3>,
        occlusion: &O,
    ) -> Vec3 {
        let v = match self.ortho_view {
            Some(v) => v,
            // Divided by the length (not times its reciprocal), as `view_lanes` does.
            None => {
                let v = normalize_or_zero(self.eye - Vec3A::from(at.p));
                if v == Vec3A::ZERO { self.backward } else { v }
            }
        };
        let sp = SurfacePoint { p: at.p, n: at.n.into(), v, tangent: None };
        let w = occlusion.obscurance(at);
        let vis = |j: usize, inc: &Incident| occlusion.visibility(at, j, inc);
        let indirect = occlusion.indirect(at, w);
        match tint {
            None => radiance(m, terms, &self.scene.lights, &sp, w, vis) + indirect,
            Some(t) => {
                let unlit = Terms { emission: Vec3::ZERO, ..*terms };
                terms.emission + t * (radiance(m, &unlit, &self.scene.lights, &sp, w, vis) + indirect)
            }
        }
    }

    /// Coverage, shading and resolve of one band into its output slices. Without supersampling the
    /// band is drawn straight into the frame's slices; otherwise into sample-resolution scratch
    /// buffers that are then box-filtered.
    fn band<O: Occlusion>(&self, band: usize, scratch: &mut BandScratch, out: BandOut<'_>, occlusion: &O) {
        let ws = self.viewport.width as usize;
        let width = ws / self.s;
        let rows_s = out.depth.len() / width * self.s;
        let row0 = (band * BAND_ROWS as usize * self.s) as i32;
        let n = rows_s * ws;
        if self.s == 1 {
            out.depth.fill(1.0);
            scratch.tri.clear();
            scratch.tri.resize(n, NO_TRI);
            let tri = &mut scratch.tri;
            raster_band(
                &self.chunks,
                band,
                row0,
                rows_s as i32,
                ws,
                &mut DepthTest { depth: out.depth, tri },
            );
            self.shade(band, row0, ws, &scratch.tri, out.hdr, out.normal, out.triangle_id, occlusion);
        } else {
            scratch.reset(n);
            let BandScratch { depth, tri, hdr, normal, face } = scratch;
            raster_band(&self.chunks, band, row0, rows_s as i32, ws, &mut DepthTest { depth, tri });
            self.shade(band, row0, ws, tri, hdr, normal, face, occlusion);
            resolve_band(scratch, self.s, width, out);
        }
    }

    /// Shade a band (`ws` samples wide, first sample row `row0`) from its visibility buffer `tri`.
    ///
    /// Shading runs triangle by triangle in submission order — each triangle's visible samples are found
    /// by scanning its bounding box for its id — rather than sample by sample: a triangle's vertex data
    /// is then fetched once and in mesh order (cache-friendly), per-triangle terms (flat colour, ray
    /// set-up, quadratic coefficients) are computed once, and a chunk (one instance) dispatches its
    /// material's model once.
    fn shade<O: Occlusion>(
        &self,
        band: usize,
        row0: i32,
        ws: usize,
        tri: &[u32],
        hdr: &mut [Vec3],
        normal: &mut [Vec3],
        face: &mut [u32],
        occlusion: &O,
    ) {
        for ((&t, h), (n, f)) in tri.iter().zip(hdr.iter_mut()).zip(normal.iter_mut().zip(face.iter_mut())) {
            if t == NO_TRI {
                *h = self.scene.background;
                *n = Vec3::ZERO;
                *f = NO_TRI;
            }
        }
        let rows = (tri.len() / ws) as i32;
        for (ci, chunk) in self.chunks.iter().enumerate() {
            let list = chunk.band(band);
            if list.is_empty() {
                continue;
            }
            let k = chunk.instance as usize;
            let job = ShadeChunk {
                prep: self,
                k,
                base: (ci as u32) << LOCAL_BITS,
                chunk,
                list,
                tri,
                hdr: &mut *hdr,
                normal: &mut *normal,
                face: &mut *face,
                row0,
                rows,
                ws,
                occlusion,
            };
            self.scene.instances[k].material.model.visit(job);
        }
    }
}

/// Shade the samples of one chunk's triangles in a band, with the model known at compile time.
struct ShadeChunk<'b, O> {
    prep: &'b Prepared<'b>,
    k: usize,
    base: u32,
    chunk: &'b Chunk,
    list: &'b [u16],
    tri: &'b [u32],
    hdr: &'b mut [Vec3],
    normal: &'b mut [Vec3],
    face: &'b mut [u32],
    row0: i32,
    rows: i32,
    ws: usize,
    occlusion: &'b O,
}

impl<O: Occlusion> ModelVisitor for ShadeChunk<'_, O> {
    type Output = ();

    fn visit<M: Bxdf>(self, m: &M) {
        // Per-sample models (Phong, quadratic) without occlusion hooks or vertex colours are shaded
        // eight samples at a time (the hot path of every benchmark); the rest one by one. Same bits.
        let per_sample = matches!(self.prep.shading, ShadingMode::Phong | ShadingMode::QuadraticNormals);
        let colors = self.prep.scene.instances[self.k].mesh.colors.is_some();
        if O::TRIVIAL && per_sample && !colors {
            struct Kernel<'c, 'b, M, O> {
                job: ShadeChunk<'b, O>,
                m: &'c M,
            }
            impl<M: Bxdf, O: Occlusion> LaneKernel for Kernel<'_, '_, M, O> {
                #[inline(always)]
                fn run<F: Lane>(self) {
                    self.job.run::<M, F>(self.m, true);
                }
            }
            run_widest(Kernel { job: self, m });
        } else {
            self.run::<M, f32>(m, false);
        }
    }
}

impl<O: Occlusion> ShadeChunk<'_, O> {
    /// Shade the chunk's visible samples; with `lanes`, per-sample illumination goes through a
    /// [`LaneQueue`] flushed `F::LANES` samples at a time.
    #[inline(always)]
    fn run<M: Bxdf, F: Lane>(self, m: &M, lanes: bool) {
        let prep = self.prep;
        let mut queue = LaneQueue::new();
        let data = &prep.instances[self.k];
        let mesh = &prep.scene.instances[self.k].mesh;
        let colors = mesh.colors.as_deref();
        let world = &prep.world[data.vertex_base..];
        let vcolor =
            if prep.vertex_color.is_empty() { &[][..] } else { &prep.vertex_color[data.vertex_base..] };
        for &local in self.list {
            let id = self.base | u32::from(local);
            let t = &self.chunk.raster[local as usize];
            let (r_first, r_last) = (t.min_y.max(self.row0), t.max_y.min(self.row0 + self.rows - 1));
            // Per-triangle data, fetched when the first visible sample is found (many triangles lose
            // the depth test everywhere and need none of it).
            let mut tri_data: Option<TriangleData> = None;
            for r in r_first..=r_last {
                let row = (r - self.row0) as usize * self.ws;
                for c in t.min_x..=t.max_x {
                    let i = row + c as usize;
                    if self.tri[i] != id {
                        continue;
                    }
                    let td = tri_data.get_or_insert_with(|| {
                        let f = self.chunk.interp[local as usize].face;
                        let k = self.k as u32;
                        TriangleData::new(
                            prep,
                            m,
                            data,
                            k,
                            f,
                            (t.min_x, t.min_y),
                            mesh.indices[f as usize],
                            world,
                            colors,
                            self.occlusion,
                        )
                    });
                    let (color, n) = match prep.shading {
                        // Constant per triangle: no barycentrics needed.
                        ShadingMode::Flat => (td.flat_color, td.face_normal),
                        ShadingMode::Gouraud => {
                            let b = td.bary.at(c, r);
                            let cv = td.idx.map(|j| vcolor[j as usize]);
                            (
                                cv[0] * b.x + cv[1] * b.y + cv[2] * b.z,
                                linear_normal(td.n, b).normalize_or_zero(),
                            )
                        }
                        mode => {
                            let b = td.bary.at(c, r);
                            let pos = td.p[0] * b.x + td.p[1] * b.y + td.p[2] * b.z;
                            let n = if mode == ShadingMode::QuadraticNormals {
                                quadratic_normal(td.p, td.n, b)
                            } else {
                                linear_normal(td.n, b)
                            };
                            if lanes {
                                // Normalised in the queue, eight at a time.
                                self.face[i] = data.face_base + td.face;
                                if queue.push(i as u32, pos, n) {
                                    queue.flush::<M, F>(m, prep, &data.terms, self.hdr, self.normal);
                                }
                                continue;
                            }
                            let n = n.normalize_or_zero();
                            let tint = colors.map(|col| {
                                col[td.idx[0] as usize] * b.x
                                    + col[td.idx[1] as usize] * b.y
                                    + col[td.idx[2] as usize] * b.z
                            });
                            let at = ShadePoint {
                                p: pos,
                                n,
                                instance: self.k as u32,
                                face: td.face,
                                vertex: NO_TRI,
                                bary: b,
                            };
                            (prep.illuminate(m, &data.terms, &at, tint, self.occlusion), n)
                        }
                    };
                    self.hdr[i] = color;
                    self.normal[i] = n;
                    self.face[i] = data.face_base + td.face;
                }
            }
        }
        if lanes {
            queue.flush::<M, F>(m, prep, &data.terms, self.hdr, self.normal);
        }
    }
}

/// Samples waiting to be shaded eight at a time: their index in the band and, in structure-of-arrays
/// form, the interpolated world position and (not yet normalised) normal.
struct LaneQueue {
    len: usize,
    index: [u32; LaneQueue::CAPACITY],
    p: [[f32; LaneQueue::CAPACITY]; 3],
    n: [[f32; LaneQueue::CAPACITY]; 3],
}

impl LaneQueue {
    /// A multiple of every lane count; large enough that flushing is not per sample.
    const CAPACITY: usize = 64;

    #[inline(always)]
    fn new() -> Self {
        Self {
            len: 0,
            index: [0; Self::CAPACITY],
            p: [[0.0; Self::CAPACITY]; 3],
            n: [[0.0; Self::CAPACITY]; 3],
        }
    }

    /// Add a sample; `true` when the queue is full and must be flushed.
    #[inline(always)]
    fn push(&mut self, index: u32, p: Vec3, n: Vec3) -> bool {
        let k = self.len;
        self.index[k] = index;
        (self.p[0][k], self.p[1][k], self.p[2][k]) = (p.x, p.y, p.z);
        (self.n[0][k], self.n[1][k], self.n[2][k]) = (n.x, n.y, n.z);
        self.len += 1;
        self.len == Self::CAPACITY
    }

    /// Normalise the queued normals into `normal`, shade every queued sample into `hdr` and empty the
    /// queue: [`Prepared::illuminate`] without tint or occlusion, on `F::LANES` samples at a time (the
    /// last group padded with copies of its last sample, masked off).
    #[inline(always)]
    fn flush<M: Bxdf, F: Lane>(
        &mut self,
        m: &M,
        prep: &Prepared<'_>,
        terms: &Terms,
        hdr: &mut [Vec3],
        normal: &mut [Vec3],
    ) {
        if self.len == 0 {
            return;
        }
        // Pad the last group with copies of the last sample, so that every group is a contiguous
        // load (CAPACITY is a multiple of every lane count).
        let padded = self.len.next_multiple_of(F::LANES);
        for k in self.len..padded {
            for a in self.p.iter_mut().chain(self.n.iter_mut()) {
                a[k] = a[self.len - 1];
            }
        }
        let mut start = 0;
        while start < self.len {
            let count = F::LANES.min(self.len - start);
            let load = |a: &[f32; Self::CAPACITY]| F::from_fn(|i| a[start + i]);
            let p = V3 { x: load(&self.p[0]), y: load(&self.p[1]), z: load(&self.p[2]) };
            let n = unit_or_zero(V3 { x: load(&self.n[0]), y: load(&self.n[1]), z: load(&self.n[2]) });
            let active = if count == F::LANES {
                F::mask_splat(true)
            } else {
                F::from_fn(|i| if i < count { 1.0 } else { 0.0 }).gt(F::splat(0.5))
            };
            let c = radiance_lanes(m, terms, &prep.scene.lights, p, n, prep.view_lanes(p), active);
            // `illuminate` adds `indirect`, zero without occlusion: adding 0 changes no bit (the
            // radiance starts from non-negative terms, so it is never −0).
            for j in 0..count {
                let i = self.index[start + j] as usize;
                hdr[i] = c.lane(j);
                normal[i] = n.lane(j);
            }
            start += count;
        }
        self.len = 0;
    }
}

/// glam's `Vec3::normalize_or_zero` (the one-sample path's) on lanes, operation for operation:
/// `v · (1/|v|)` where that reciprocal is finite and positive, else zero.
#[inline(always)]
fn unit_or_zero<F: Lane>(v: V3<F>) -> V3<F> {
    let rcp = F::splat(1.0) / v.dot(v).sqrt();
    let ok = rcp.is_finite() & rcp.gt(F::splat(0.0));
    V3::select(ok, v.scale(rcp), V3::splat(Vec3::ZERO))
}

/// What shading needs of one mesh face, gathered once per triangle.
struct TriangleData {
    face: u32,
    idx: [u32; 3],
    p: [Vec3; 3],
    n: [Vec3; 3],
    bary: BaryPlanes,
    face_normal: Vec3,
    /// Flat shading: the illumination model at the centroid with the face normal.
    flat_color: Vec3,
}

impl TriangleData {
    #[inline(always)]
    fn new<M: Bxdf, O: Occlusion>(
        prep: &Prepared<'_>,
        m: &M,
        data: &InstanceData,
        instance: u32,
        face: u32,
        anchor: (i32, i32),
        idx: [u32; 3],
        world: &[WorldVertex],
        colors: Option<&[Vec3]>,
        occlusion: &O,
    ) -> Self {
        let v = idx.map(|j| world[j as usize]);
        let p = [v[0].p, v[1].p, v[2].p];
        let fnorm = face_normal(p);
        let face_normal = if data.mirrored { -fnorm } else { fnorm };
        let mut flat_color = Vec3::ZERO;
        if prep.shading == ShadingMode::Flat {
            let centroid = (p[0] + p[1] + p[2]) / 3.0;
            let tint = colors.map(|c| (c[idx[0] as usize] + c[idx[1] as usize] + c[idx[2] as usize]) / 3.0);
            let at = ShadePoint {
                p: centroid,
                n: face_normal,
                instance,
                face,
                vertex: NO_TRI,
                bary: Vec3::splat(1.0 / 3.0),
            };
            flat_color = prep.illuminate(m, &data.terms, &at, tint, occlusion);
        }
        let bary = BaryPlanes::new(&prep.rays, p, anchor.0, anchor.1);
        Self { face, idx, p, n: [v[0].n, v[1].n, v[2].n], bary, face_normal, flat_color }
    }
}

/// Perspective-correct barycentrics of one triangle as three affine functions of the sample
/// position, `D`, `U`, `V` (value at the anchor sample and change per column and per row, f64):
/// `u = U/D`, `v = V/D`, `b = (1 − u − v, u, v)`.
///
/// They are the Möller–Trumbore quantities of the sample's view ray against the world-space triangle,
/// `D = e1·(d × e2)`, `U = (o − p0)·(d × e2)`, `V = d·((o − p0) × e1)`: with a perspective camera the
/// origin `o` is the eye (fixed) and the direction `d` is affine in the sample position; with an
/// orthographic one `d` is fixed and `o` affine. Either way D, U and V are affine, so three exact
/// evaluations at the anchor and its two neighbours give their planes, and each sample costs six
/// multiply-adds and a division instead of a full intersection.
struct BaryPlanes {
    c0: i32,
    r0: i32,
    /// (value at anchor, per column, per row) of D, U, V.
    d: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
}

impl BaryPlanes {
    fn new(rays: &Rays, p: [Vec3; 3], c0: i32, r0: i32) -> Self {
        let p0 = p[0].as_dvec3();
        let (e1, e2) = (p[1].as_dvec3() - p0, p[2].as_dvec3() - p0);
        let (o, d) = rays.ray(c0, r0);
        let t = o - p0;
        let plane = |at: f64, per_c: f64, per_r: f64| [at, per_c, per_r];
        if rays.perspective {
            // o fixed: D = d·(e2×e1), U = d·(e2×t), V = d·(t×e1), linear in d.
            let (a, b, c) = (e2.cross(e1), e2.cross(t), t.cross(e1));
            let (dc, dr) = (rays.d_c, rays.d_r);
            Self {
                c0,
                r0,
                d: plane(d.dot(a), dc.dot(a), dr.dot(a)),
                u: plane(d.dot(b), dc.dot(b), dr.dot(b)),
                v: plane(d.dot(c), dc.dot(c), dr.dot(c)),
            }
        } else {
            // d fixed: D = e1·(d×e2) constant, U = t·(d×e2), V = t·(e1×d), linear in o.
            let (pv, qv) = (d.cross(e2), e1.cross(d));
            let (oc, or) = (rays.o_c, rays.o_r);
            Self {
                c0,
                r0,
                d: plane(e1.dot(pv), 0.0, 0.0),
                u: plane(t.dot(pv), oc.dot(pv), or.dot(pv)),
                v: plane(t.dot(qv), oc.dot(qv), or.dot(qv)),
            }
        }
    }

    /// Barycentrics at sample `(c, r)`; the centroid if the ray is parallel to the triangle's plane.
    /// Slightly outside [0, 1] for samples the snapped triangle covers beyond the exact one, as GL
    /// extrapolates too.
    #[inline(always)]
    fn at(&self, c: i32, r: i32) -> Vec3 {
        let (dc, dr) = (f64::from(c - self.c0), f64::from(r - self.r0));
        let d = self.d[0] + dc * self.d[1] + dr * self.d[2];
        if d == 0.0 || !d.is_finite() {
            return Vec3::splat(1.0 / 3.0);
        }
        let inv = 1.0 / d;
        let u = (self.u[0] + dc * self.u[1] + dr * self.u[2]) * inv;
        let v = (self.v[0] + dc * self.v[1] + dr * self.v[2]) * inv;
        Vec3::new((1.0 - u - v) as f32, u as f32, v as f32)
    }
}

/// The view ray of every sample: origin and direction affine in the sample's NDC `(x_n, y_n)` (the
/// inverse of a perspective or orthographic projection has a `w` row independent of x and y), built
/// from unprojected points in f64. A perspective camera's rays all start at the eye.
#[derive(Debug, Clone, Copy)]
struct Rays {
    /// Perspective: every ray starts at the eye (`o_x = o_y = 0`); orthographic: `d` is constant.
    perspective: bool,
    /// Change of origin and direction per sample column and per sample row.
    o_c: DVec3,
    o_r: DVec3,
    d_c: DVec3,
    d_r: DVec3,
    o: DVec3,
    o_x: DVec3,
    o_y: DVec3,
    d: DVec3,
    d_x: DVec3,
    d_y: DVec3,
    sx: f64,
    sy: f64,
}

impl Rays {
    fn new(view_proj: &Mat4, viewport: Viewport, eye: Option<Vec3>) -> Self {
        let inv = view_proj.as_dmat4().inverse();
        let un = |x: f64, y: f64, z: f64| inv.project_point3(DVec3::new(x, y, z));
        let (o, f) = (un(0.0, 0.0, -1.0), un(0.0, 0.0, 1.0));
        let (ox, fx) = (un(1.0, 0.0, -1.0), un(1.0, 0.0, 1.0));
        let (oy, fy) = (un(0.0, 1.0, -1.0), un(0.0, 1.0, 1.0));
        let d = f - o;
        let (o, o_x, o_y) = match eye {
            Some(e) => (e.as_dvec3(), DVec3::ZERO, DVec3::ZERO),
            None => (o, ox - o, oy - o),
        };
        let (d_x, d_y) = (fx - ox - d, fy - oy - d);
        let sx = 2.0 / f64::from(viewport.width);
        let sy = 2.0 / f64::from(viewport.height);
        Self {
            perspective: eye.is_some(),
            o_c: o_x * sx,
            o_r: -o_y * sy,
            d_c: d_x * sx,
            d_r: -d_y * sy,
            o,
            o_x,
            o_y,
            d,
            d_x,
            d_y,
            sx,
            sy,
        }
    }

    /// Origin and direction of the ray through the centre of sample `(c, r)`.
    #[inline]
    fn ray(&self, c: i32, r: i32) -> (DVec3, DVec3) {
        let xn = (f64::from(c) + 0.5) * self.sx - 1.0;
        let yn = 1.0 - (f64::from(r) + 0.5) * self.sy;
        (self.o + xn * self.o_x + yn * self.o_y, self.d + xn * self.d_x + yn * self.d_y)
    }
}
