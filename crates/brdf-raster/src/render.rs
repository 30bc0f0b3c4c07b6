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
//! ## Hooks for ambient occlusion and shadows
//! [`render_with`] takes an [`Occlusion`] provider: its obscurance `w(p)` multiplies the ambient term
//! and its visibility `δ_j` multiplies light `j`'s contribution (seed 004 eq. 12.75), evaluated at each
//! shaded point (samples, or vertices in Gouraud mode). [`render`] uses [`NoOcclusion`] (`w = δ = 1`).

use std::sync::atomic::{AtomicUsize, Ordering};

use brdf_core::illumination::{SurfacePoint, Terms, radiance};
use brdf_core::lights::Incident;
use brdf_core::models::{Bxdf, ModelVisitor};
use brdf_core::tonemap::Operator;
use glam::{Mat3, Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use crate::RasterError;
use crate::ao::AoOptions;
use crate::camera::Camera;
use crate::clip::{ClipVertex, GuardBand, clip_triangle, code};
use crate::framebuffer::{BandOut, BandScratch, Frame, resolve_band};
use crate::occlusion::SceneOcclusion;
use crate::scene::Scene;
use crate::setup::{Culling, SetupVertex, Viewport, setup_triangle};
use crate::shading::{ShadingMode, face_normal, linear_normal, quadratic_normal};
use crate::tiles::{
    BAND_ROWS, CHUNK_FACES, Chunk, CoverageCount, DepthTest, MAX_CHUNKS, NO_TRI, raster_band, split_ref,
};

/// Largest accepted image width or height in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest accepted number of samples per frame, `width · height · samples_per_pixel` (2^28: the
/// frame's buffers then take at most about 10 GB; a 16384² image fits only without supersampling).
pub const MAX_SAMPLES: u64 = 1 << 28;

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

impl Occlusion for NoOcclusion {}

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
    let prep = Prepared::new(scene, camera, options, occlusion)?;
    let (w, h) = (options.width as usize, options.height as usize);
    let mut frame = Frame {
        width: options.width,
        height: options.height,
        hdr: vec![Vec3::ZERO; w * h],
        depth: vec![1.0; w * h],
        normal: vec![Vec3::ZERO; w * h],
        triangle_id: vec![NO_TRI; w * h],
        tonemap: options.tonemap,
        exposure: options.exposure,
    };
    let band_px = BAND_ROWS as usize * w;
    let n_bands = h.div_ceil(BAND_ROWS as usize);
    let done = AtomicUsize::new(0);
    frame
        .hdr
        .par_chunks_mut(band_px)
        .zip(frame.depth.par_chunks_mut(band_px))
        .zip(frame.normal.par_chunks_mut(band_px))
        .zip(frame.triangle_id.par_chunks_mut(band_px))
        .enumerate()
        .for_each_init(BandScratch::default, |scratch, (band, (((hdr, depth), normal), triangle_id))| {
            let rows = depth.len() / w;
            prep.band(band, rows, scratch, occlusion);
            resolve_band(scratch, prep.s, w, BandOut { hdr, depth, normal, triangle_id });
            if let Some(cb) = progress {
                cb((done.fetch_add(1, Ordering::Relaxed) + 1) as f32 / n_bands as f32);
            }
        });
    Ok(frame)
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

/// A vertex after the vertex stage.
#[derive(Debug, Clone, Copy)]
struct Vertex {
    world: Vec3,
    normal: Vec3,
    clip: Vec4,
    code: u16,
    /// Snapped screen position, valid when `code & MUST_CLIP == 0`.
    x: i32,
    y: i32,
    z: f32,
    inv_w: f32,
}

impl Vertex {
    #[inline]
    fn setup(&self, k: usize) -> SetupVertex {
        let mut bary = Vec3::ZERO;
        bary[k] = 1.0;
        SetupVertex { x: i64::from(self.x), y: i64::from(self.y), z: self.z, inv_w: self.inv_w, bary }
    }
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
    camera: &'a Camera,
    shading: ShadingMode,
    viewport: Viewport,
    s: usize,
    band_samples: u32,
    vertices: Vec<Vertex>,
    instances: Vec<InstanceData>,
    /// Gouraud: the illumination at every vertex.
    vertex_color: Vec<Vec3>,
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

        // Vertex stage.
        let mut instances = Vec::with_capacity(scene.instances.len());
        let mut vertices: Vec<Vertex> =
            Vec::with_capacity(scene.instances.iter().map(|i| i.mesh.positions.len()).sum());
        let mut face_base = 0u32;
        for inst in &scene.instances {
            let m = inst.transform;
            let affine = m.row(3) == Vec4::W;
            let nm = inst.normal_matrix();
            let mesh = &inst.mesh;
            instances.push(InstanceData {
                vertex_base: vertices.len(),
                face_base,
                mirrored: inst.mirrors(),
                terms: Terms {
                    emission: inst.material.emission,
                    ambient: inst.material.ambient,
                    ambient_light: scene.ambient_light,
                },
            });
            face_base += mesh.indices.len() as u32;
            vertices.par_extend(
                mesh.positions
                    .par_iter()
                    .zip(mesh.normals.par_iter())
                    .with_min_len(4096)
                    .map(|(&p, &n)| vertex_stage(p, n, &m, affine, &nm, &view_proj, &guard, viewport)),
            );
        }

        let mut prep = Prepared {
            scene,
            camera,
            shading: options.shading,
            viewport,
            s: s as usize,
            band_samples: BAND_ROWS * s,
            vertices,
            instances,
            vertex_color: Vec::new(),
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

    /// Clip, cull and set up faces `start..end` of instance `k`.
    fn setup_chunk(&self, k: usize, start: usize, end: usize, cull: bool, guard: &GuardBand) -> Chunk {
        let inst = &self.instances[k];
        let mesh = &self.scene.instances[k].mesh;
        let culling = Culling { back: cull, mirrored: inst.mirrored };
        let verts = &self.vertices[inst.vertex_base..inst.vertex_base + mesh.positions.len()];
        let mut chunk = Chunk::default();
        chunk.raster.reserve(end - start);
        chunk.interp.reserve(end - start);
        for (f, idx) in mesh.indices[start..end].iter().enumerate() {
            let face = (start + f) as u32;
            let v = idx.map(|i| &verts[i as usize]);
            let any = v[0].code | v[1].code | v[2].code;
            if v[0].code & v[1].code & v[2].code & code::REJECT != 0 {
                continue;
            }
            if any & code::MUST_CLIP == 0 {
                if let Some((r, i)) = setup_triangle(
                    [v[0].setup(0), v[1].setup(1), v[2].setup(2)],
                    self.viewport,
                    culling,
                    face,
                    k as u32,
                ) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
                continue;
            }
            let tri = [0, 1, 2].map(|j| {
                let mut bary = Vec3::ZERO;
                bary[j] = 1.0;
                ClipVertex { pos: v[j].clip, bary }
            });
            let poly = clip_triangle(tri, any & code::MUST_CLIP, guard);
            if poly.len < 3 {
                continue;
            }
            let snapped: Vec<SetupVertex> =
                poly.v[..poly.len].iter().map(|c| self.viewport.snap(c.pos, c.bary)).collect();
            for j in 1..poly.len - 1 {
                if let Some((r, i)) = setup_triangle(
                    [snapped[0], snapped[j], snapped[j + 1]],
                    self.viewport,
                    culling,
                    face,
                    k as u32,
                ) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
            }
        }
        chunk
    }

    /// Gouraud: the illumination model at every vertex with its vertex normal.
    fn vertex_colors<O: Occlusion>(&self, occlusion: &O) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.vertices.len()];
        for (k, inst) in self.scene.instances.iter().enumerate() {
            let data = &self.instances[k];
            let n = inst.mesh.positions.len();
            let colors = inst.mesh.colors.as_deref();
            struct Job<'b, O> {
                prep: &'b Prepared<'b>,
                k: usize,
                colors: Option<&'b [Vec3]>,
                out: &'b mut [Vec3],
                occlusion: &'b O,
            }
            impl<O: Occlusion> ModelVisitor for Job<'_, O> {
                type Output = ();
                fn visit<M: Bxdf>(self, m: &M) {
                    let data = &self.prep.instances[self.k];
                    let verts = &self.prep.vertices[data.vertex_base..];
                    self.out.par_iter_mut().enumerate().with_min_len(1024).for_each(|(i, out)| {
                        let vx = &verts[i];
                        let n = vx.normal;
                        let at = ShadePoint {
                            p: vx.world,
                            n,
                            instance: self.k as u32,
                            face: NO_TRI,
                            vertex: i as u32,
                            bary: Vec3::ZERO,
                        };
                        let tint = self.colors.map(|c| c[i]);
                        *out = self.prep.illuminate(m, &data.terms, &at, tint, self.occlusion);
                    });
                }
            }
            let out_slice = &mut out[data.vertex_base..data.vertex_base + n];
            inst.material.model.visit(Job { prep: self, k, colors, out: out_slice, occlusion });
        }
        out
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
        let v: Vec3A = self.camera.view_vector(at.p).into();
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

    /// Coverage and shading of one band (`rows` image rows) into `scratch` at the sample resolution.
    fn band<O: Occlusion>(&self, band: usize, rows: usize, scratch: &mut BandScratch, occlusion: &O) {
        let ws = self.viewport.width as usize;
        let rows_s = rows * self.s;
        let row0 = (band * BAND_ROWS as usize * self.s) as i32;
        scratch.reset(rows_s * ws);
        let BandScratch { depth, tri, hdr, normal, face } = scratch;
        raster_band(&self.chunks, band, row0, rows_s as i32, ws, &mut DepthTest { depth, tri });

        // Group the covered samples by instance (stable), so each material's model is dispatched once.
        let mut samples: Vec<u32> = Vec::new();
        let mut single = None;
        let mut mixed = false;
        for (i, (&t, h)) in tri.iter().zip(hdr.iter_mut()).enumerate() {
            if t == NO_TRI {
                *h = self.scene.background;
                normal[i] = Vec3::ZERO;
                face[i] = NO_TRI;
                continue;
            }
            let inst = self.interp(t).instance;
            match single {
                None => single = Some(inst),
                Some(s) if s != inst => mixed = true,
                _ => {}
            }
            samples.push(i as u32);
        }
        let Some(first) = single else { return };
        if mixed {
            samples.sort_by_key(|&i| self.interp(tri[i as usize]).instance);
        }
        let mut start = 0;
        while start < samples.len() {
            let k = if mixed { self.interp(tri[samples[start] as usize]).instance } else { first };
            let end = if mixed {
                start + samples[start..].partition_point(|&i| self.interp(tri[i as usize]).instance == k)
            } else {
                samples.len()
            };
            let job = ShadeSamples {
                prep: self,
                k: k as usize,
                samples: &samples[start..end],
                tri,
                hdr,
                normal,
                face,
                row0,
                width: ws,
                occlusion,
            };
            self.scene.instances[k as usize].material.model.visit(job);
            start = end;
        }
    }

    #[inline(always)]
    fn interp(&self, t: u32) -> &crate::setup::InterpTri {
        let (c, l) = split_ref(t);
        &self.chunks[c].interp[l]
    }
}

/// Shade the samples of one instance in a band, with the model known at compile time.
struct ShadeSamples<'b, O> {
    prep: &'b Prepared<'b>,
    k: usize,
    samples: &'b [u32],
    tri: &'b [u32],
    hdr: &'b mut [Vec3],
    normal: &'b mut [Vec3],
    face: &'b mut [u32],
    row0: i32,
    width: usize,
    occlusion: &'b O,
}

impl<O: Occlusion> ModelVisitor for ShadeSamples<'_, O> {
    type Output = ();

    fn visit<M: Bxdf>(self, m: &M) {
        let prep = self.prep;
        let data = &prep.instances[self.k];
        let inst = &prep.scene.instances[self.k];
        let indices = &inst.mesh.indices;
        let colors = inst.mesh.colors.as_deref();
        let verts = &prep.vertices[data.vertex_base..];
        let vcolor =
            if prep.vertex_color.is_empty() { &[][..] } else { &prep.vertex_color[data.vertex_base..] };
        for &i in self.samples {
            let i = i as usize;
            let it = prep.interp(self.tri[i]);
            let (c, r) = ((i % self.width) as i32, self.row0 + (i / self.width) as i32);
            let b = it.bary(c, r);
            let idx = indices[it.face as usize];
            let v = idx.map(|j| &verts[j as usize]);
            let p = [v[0].world, v[1].world, v[2].world];
            let nv = [v[0].normal, v[1].normal, v[2].normal];
            let tint = colors.map(|col| {
                col[idx[0] as usize] * b.x + col[idx[1] as usize] * b.y + col[idx[2] as usize] * b.z
            });
            let (color, n) = match prep.shading {
                ShadingMode::Gouraud => {
                    let cv = idx.map(|j| vcolor[j as usize]);
                    (cv[0] * b.x + cv[1] * b.y + cv[2] * b.z, linear_normal(nv, b).normalize_or_zero())
                }
                mode => {
                    let (pos, n, tint) = match mode {
                        ShadingMode::Flat => {
                            let n = face_normal(p);
                            let n = if data.mirrored { -n } else { n };
                            let centroid = (p[0] + p[1] + p[2]) / 3.0;
                            let tint = colors.map(|col| {
                                (col[idx[0] as usize] + col[idx[1] as usize] + col[idx[2] as usize]) / 3.0
                            });
                            (centroid, n, tint)
                        }
                        ShadingMode::QuadraticNormals => (
                            p[0] * b.x + p[1] * b.y + p[2] * b.z,
                            quadratic_normal(p, nv, b).normalize_or_zero(),
                            tint,
                        ),
                        _ => (
                            p[0] * b.x + p[1] * b.y + p[2] * b.z,
                            linear_normal(nv, b).normalize_or_zero(),
                            tint,
                        ),
                    };
                    let at = ShadePoint {
                        p: pos,
                        n,
                        instance: self.k as u32,
                        face: it.face,
                        vertex: NO_TRI,
                        bary: b,
                    };
                    (prep.illuminate(m, &data.terms, &at, tint, self.occlusion), n)
                }
            };
            self.hdr[i] = color;
            self.normal[i] = n;
            self.face[i] = data.face_base + it.face;
        }
    }
}

/// World position and normal, clip position, outcode and (when inside the guard band) the snapped
/// screen position of one vertex.
#[inline]
fn vertex_stage(
    p: Vec3,
    n: Vec3,
    m: &Mat4,
    affine: bool,
    nm: &Mat3,
    view_proj: &Mat4,
    guard: &GuardBand,
    viewport: Viewport,
) -> Vertex {
    let world = if affine { m.transform_point3(p) } else { m.project_point3(p) };
    let normal = (*nm * n).normalize_or_zero();
    let clip = *view_proj * world.extend(1.0);
    let code = guard.outcode(clip);
    let (mut x, mut y, mut z, mut inv_w) = (0, 0, 0.0, 0.0);
    if code & code::MUST_CLIP == 0 {
        let sv = viewport.snap(clip, Vec3::ZERO);
        (x, y, z, inv_w) = (sv.x as i32, sv.y as i32, sv.z, sv.inv_w);
    }
    Vertex { world, normal, clip, code, x, y, z, inv_w }
}
