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
//!                                encode: 8-bit sRGB inside each row's covered span, the
//!                                        background's bytes (encoded once) outside it
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
//! scene.add_light(Light::point(Vec3::new(2.0, 2.0, 2.0), Vec3::splat(10.0),
//! Attenuation::InverseSquare).unwrap());
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
//! and its visibility `δ_j` multiplies light `j`'s contribution (Theoharis et al. 2008 eq. 12.75), evaluated
//! at each
//! shaded point (samples, or vertices in Gouraud mode). [`render`] uses [`NoOcclusion`] (`w = δ = 1`).

mod alpha;
mod interpolate;
mod options;
mod raster;
mod shade;
mod vertex;

use brdf_core::lights::Incident;
use glam::Vec3;
use rayon::prelude::*;

pub use options::{MAX_IMAGE_SIDE, MAX_PIXELS, Outputs, RenderOptions};

use crate::RasterError;
use crate::area_lighting::AreaLighting;
use crate::camera::Camera;
use crate::environment::lighting::EnvironmentLighting;
use crate::framebuffer::Frame;
use crate::occlusion::SceneOcclusion;
use crate::scene::Scene;
use crate::tiles::{CoverageCount, raster_band};
use vertex::Prepared;

/// A point being shaded, as the [`Occlusion`] hooks see it (world space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadePoint {
    /// Position.
    pub p: Vec3,
    /// Unit shading normal.
    pub n: Vec3,
    /// Instance index in the scene.
    pub instance: u32,
    /// Face index within the instance's mesh ([`NO_TRI`](crate::tiles::NO_TRI) for a vertex).
    pub face: u32,
    /// Vertex index within the instance's mesh for a point that is a vertex, else
    /// [`NO_TRI`](crate::tiles::NO_TRI). The renderer always shades samples (faces); providers may be
    /// asked about vertices by other callers.
    pub vertex: u32,
    /// Perspective-correct barycentric coordinates in the face (zero when shading a vertex).
    pub bary: Vec3,
}

/// Ambient occlusion and shadow providers (Theoharis et al. 2008 eq. 12.75), called at every shaded sample
/// whatever the shading mode: flat and Gouraud shading evaluate the reflectance model per triangle or
/// per vertex, but obscurance and light visibility are asked for at each sample's own position (the
/// face's perspective-correct barycentrics, its face or interpolated normal), so shadow edges and
/// per-pixel obscurance are as sharp in every mode.
pub trait Occlusion: Sync {
    /// `true` promises `obscurance = 1`, `visibility = 1` and `indirect = 0` everywhere, so that the
    /// renderer may shade eight samples at a time without calling the hooks (same bits).
    fn is_trivial(&self) -> bool {
        false
    }

    /// Obscurance `w(p) ∈ [0, 1]` multiplying the ambient term (1 = fully open).
    fn obscurance(&self, _at: &ShadePoint) -> f32 {
        1.0
    }
    /// Visibility `δ ∈ [0, 1]` of light `light` (index into `Scene::lights`) from the point, given
    /// what arrives from it (`incident.l`, `incident.distance` bound a shadow ray). 1 = unshadowed.
    fn visibility(&self, _at: &ShadePoint, _light: usize, _incident: &Incident) -> f32 {
        1.0
    }
    /// [`Occlusion::visibility`] of light `light` at several points at once (`out[k]` for `at[k]`
    /// with `incident[k]`): the renderer asks for the points of up to 64 neighbouring samples
    /// together, so that a provider may trace their shadow rays in packets. The answers must be those
    /// of [`Occlusion::visibility`] (the default asks it point by point).
    fn visibility_each(&self, at: &[ShadePoint], light: usize, incident: &[Incident], out: &mut [f32]) {
        for ((a, inc), o) in at.iter().zip(incident).zip(out.iter_mut()) {
            *o = self.visibility(a, light, inc);
        }
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
    fn is_trivial(&self) -> bool {
        true
    }
}

/// Render `scene` through `camera`, with the obscurance and shadows that `options.ao` and
/// `options.shadows` ask for ([`crate::occlusion::SceneOcclusion`]) and the scene's environment
/// lighting, if it has one ([`render_lit_into`]).
pub fn render(scene: &Scene, camera: &Camera, options: &RenderOptions) -> Result<Frame, RasterError> {
    let mut frame = Frame::default();
    render_into(scene, camera, options, &mut frame)?;
    Ok(frame)
}

/// [`render_with_into`] with the scene's environment (if it has one) lighting it in
/// `options.environment`'s mode, its reflected radiance added to `occlusion`'s hooks
/// ([`crate::environment::lighting::EnvironmentLighting`]), and the scene's area lights (if any) with
/// `options.area`'s samples ([`crate::area_lighting::AreaLighting`]); without either, exactly
/// [`render_with_into`].
pub fn render_lit_into<O: Occlusion>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    occlusion: &O,
    progress: Option<&(dyn Fn(f32) + Sync)>,
    frame: &mut Frame,
) -> Result<(), RasterError> {
    if scene.environment.is_none() && scene.area_lights.is_empty() {
        return render_with_into(scene, camera, options, occlusion, progress, frame);
    }
    options.validate()?;
    camera.validate()?;
    scene.validate()?;
    if scene.environment.is_none() {
        let area = AreaLighting::new(scene, camera, options.area, occlusion)?;
        return render_with_into(scene, camera, options, &area, progress, frame);
    }
    let lit = EnvironmentLighting::new(scene, camera, options.environment, occlusion)?;
    if scene.area_lights.is_empty() {
        return render_with_into(scene, camera, options, &lit, progress, frame);
    }
    let area = AreaLighting::new(scene, camera, options.area, &lit)?;
    render_with_into(scene, camera, options, &area, progress, frame)
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
        return render_lit_into(scene, camera, options, &occlusion, None, frame);
    }
    render_lit_into(scene, camera, options, &NoOcclusion, None, frame)
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
    // The renderer's internals take the providers as a trait object: they are asked once per light per
    // 64 samples (or per textured sample), not per lane, so the indirect call costs nothing measurable,
    // while a generic `O` would compile the whole shading stage once per provider type for every model.
    let occlusion: &dyn Occlusion = occlusion;
    let prep = Prepared::new(scene, camera, options, occlusion)?;
    let n = options.width as usize * options.height as usize;
    frame.width = options.width;
    frame.height = options.height;
    frame.tonemap = options.tonemap;
    frame.exposure = options.exposure;
    // Every element of an output is overwritten by its band, so the old contents need neither clearing
    // nor, when a buffer is too small, copying into a larger one (a fresh zeroed allocation maps its
    // pages lazily). A buffer that is not an output is emptied, its allocation kept for a later render.
    fn fit<T: bytemuck::Zeroable + Clone>(buf: &mut Vec<T>, n: usize, wanted: bool) {
        if !wanted {
            buf.clear();
        } else if buf.capacity() < n {
            *buf = bytemuck::zeroed_vec(n);
        } else {
            buf.resize(n, T::zeroed());
        }
    }
    let o = options.outputs;
    fit(&mut frame.hdr, n, o.contains(Outputs::HDR));
    fit(&mut frame.depth, n, o.contains(Outputs::DEPTH));
    fit(&mut frame.normal, n, o.contains(Outputs::NORMAL));
    fit(&mut frame.triangle_id, n, o.contains(Outputs::TRIANGLE_ID));
    fit(&mut frame.rgb8, 3 * n, o.contains(Outputs::RGB8));
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
