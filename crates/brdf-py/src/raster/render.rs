//! Frames and rendering from Python: `RasterFrame` (with the spare frame a render draws into) and
//! `render_scene`.

use std::sync::{Arc, Mutex};

use brdf_core::tonemap::Operator;
use brdf_raster::ambient::resolve as resolve_ambient;
use brdf_raster::ao::AoOptions;
use brdf_raster::area_lighting::AreaSampling;
use brdf_raster::environment::EnvironmentMode;
use brdf_raster::occlusion::OcclusionCache;
use brdf_raster::render::{MAX_IMAGE_SIDE, MAX_PIXELS, NoOcclusion, Outputs, RenderOptions, render_lit_into};
use brdf_raster::tiles::NO_TRI;
use brdf_raster::{Frame, Material, Scene, ShadingMode};
use glam::Vec3;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use super::texture::{InstanceTextureArgs, material_textures};
use super::{
    RasterAreaLight, RasterCamera, RasterEnvironment, RasterLight, RasterMesh, color3, mat4_from_rows,
    raster_err,
};
use crate::errors::{invalid, to_py};
use crate::models::Model;
use crate::threads::pool;

/// A rendered frame: HDR colour, depth, normal and triangle-id buffers (row 0 at the top).
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterFrame {
    pub(crate) inner: Frame,
}

/// The buffers of the last frame Python dropped, drawn into by the next render.
///
/// Why: a script that renders in a loop (`img = scene.render(...)`) would otherwise hand ~66 MB per
/// 1080p frame back to the system and map it again for the next one; the kernel zeroes every fresh
/// page, which cost as much as a fifth of a frame's time and serialised the threads. One frame is kept,
/// and only up to [`SPARE_FRAME_LIMIT`] bytes, so the memory held after images are gone is bounded.
static SPARE_FRAME: Mutex<Option<Frame>> = Mutex::new(None);

/// Largest frame, in bytes of buffers, kept for reuse (a 4K frame is about 265 MB).
const SPARE_FRAME_LIMIT: usize = 320 << 20;

impl Drop for RasterFrame {
    fn drop(&mut self) {
        let frame = std::mem::take(&mut self.inner);
        if frame.heap_bytes() <= SPARE_FRAME_LIMIT {
            // The replaced spare (if any) is freed here, outside no lock that matters.
            let old = SPARE_FRAME.lock().unwrap_or_else(|e| e.into_inner()).replace(frame);
            drop(old);
        }
    }
}

/// The BVH and per-vertex obscurance of the last scene rendered with obscurance or shadows, reused by
/// the next render while the scene's geometry (meshes, transforms) and the options are unchanged
/// (`brdf_raster::occlusion::OcclusionCache`). It holds the last such scene's meshes until then.
static OCCLUSION_CACHE: Mutex<OcclusionCache> = Mutex::new(OcclusionCache::new());

/// `(hits, misses)` of the occlusion cache of renders (for tests and benchmarks).
#[pyfunction]
pub fn occlusion_cache_info() -> (u64, u64) {
    OCCLUSION_CACHE.lock().unwrap_or_else(|e| e.into_inner()).stats()
}

/// A frame to render into: the spare one if there is one, else an empty one (`render_into` sizes it).
fn take_spare_frame() -> Frame {
    SPARE_FRAME.lock().unwrap_or_else(|e| e.into_inner()).take().unwrap_or_default()
}

fn operator(name: &str, white: Option<f32>) -> PyResult<Operator> {
    if !Operator::NAMES.contains(&name.to_ascii_lowercase().as_str()) {
        return Err(invalid(format!(
            "tonemap: expected one of {}, got {name:?}",
            Operator::NAMES.join(", ")
        )));
    }
    Operator::from_name(name, white).map_err(to_py)
}

impl RasterFrame {
    /// Wrap a frame made elsewhere (the lit-sphere view draws one without the rasterizer).
    pub(crate) fn from_frame(inner: Frame) -> Self {
        Self { inner }
    }

    /// An error unless the frame holds `output` (the render asked for it).
    fn require(&self, output: Outputs, name: &str) -> PyResult<()> {
        let have = self.inner.outputs();
        if have.contains(output) {
            return Ok(());
        }
        Err(invalid(format!(
            "{name}: not rendered (this image holds {}); render with outputs including '{name}'",
            have.names().join(", ")
        )))
    }
}

#[pymethods]
impl RasterFrame {
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width
    }
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height
    }

    /// 8-bit sRGB, uint8 (H, W, 3): `round(255·srgb(op(c·2^exposure)))`; `None` keeps the frame's own
    /// tone map and exposure (those of the render call).
    #[pyo3(signature = (tonemap=None, exposure=None, white=None))]
    fn rgb8<'py>(
        &self,
        py: Python<'py>,
        tonemap: Option<&str>,
        exposure: Option<f32>,
        white: Option<f32>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let op = match tonemap {
            Some(name) => operator(name, white)?,
            None => self.inner.tonemap,
        };
        let ev = exposure.unwrap_or(self.inner.exposure);
        if !ev.is_finite() {
            return Err(invalid(format!("exposure: must be finite, got {ev}")));
        }
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        // The render encoded the image with the frame's own tone map and exposure (the frame cannot
        // change from Python since): a copy of those bytes.
        let have = self.inner.outputs();
        if have.contains(Outputs::RGB8) && op == self.inner.tonemap && ev == self.inner.exposure {
            return PyArray1::from_slice(py, &self.inner.rgb8).reshape([h, w, 3]);
        }
        if !have.contains(Outputs::HDR) {
            // Another tone map or exposure is an encode of the HDR colours.
            let what =
                if have.contains(Outputs::RGB8) { "rgb with another tone map or exposure" } else { "rgb" };
            return Err(invalid(format!(
                "{what}: needs the 'hdr' output, not rendered (this image holds {}); render with outputs \
                 including 'hdr'",
                have.names().join(", ")
            )));
        }
        let p = pool()?;
        let bytes = py.detach(|| p.install(|| self.inner.to_rgb8_with(op, ev)));
        PyArray1::from_vec(py, bytes).reshape([h, w, 3])
    }

    /// Linear RGB before tone mapping, float32 (H, W, 3).
    fn hdr<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        self.require(Outputs::HDR, "hdr")?;
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&self.inner.hdr)).reshape([h, w, 3])
    }

    /// The HDR colours as a Radiance `.hdr` file (RGBE, `brdf_raster::environment::rgbe`), as bytes.
    fn hdr_file<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        self.require(Outputs::HDR, "hdr")?;
        let (w, h) = (self.inner.width as usize, self.inner.height as usize);
        let bytes = py.detach(|| brdf_raster::environment::rgbe::encode(w, h, &self.inner.hdr));
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// The HDR colours as an OpenEXR file (32-bit float RGB), as bytes.
    fn exr_file<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        self.require(Outputs::HDR, "hdr")?;
        let (w, h) = (self.inner.width as usize, self.inner.height as usize);
        let bytes = py
            .detach(|| brdf_raster::environment::file::encode_exr(w, h, &self.inner.hdr))
            .map_err(raster_err)?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// Window depth in [0, 1] (1 = far / nothing drawn), float32 (H, W).
    fn depth<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        self.require(Outputs::DEPTH, "depth")?;
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, &self.inner.depth).reshape([h, w])
    }

    /// Unit world-space shading normals, float32 (H, W, 3); zero where nothing was drawn.
    fn normal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        self.require(Outputs::NORMAL, "normal")?;
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&self.inner.normal)).reshape([h, w, 3])
    }

    /// Face index over all instances in scene order, int64 (H, W); −1 where nothing was drawn.
    fn triangle_id<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        self.require(Outputs::TRIANGLE_ID, "triangle_id")?;
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        let ids: Vec<i64> =
            self.inner.triangle_id.iter().map(|&t| if t == NO_TRI { -1 } else { i64::from(t) }).collect();
        PyArray1::from_vec(py, ids).reshape([h, w])
    }

    /// Number of pixels some triangle covers (from the triangle ids, else the depth).
    fn covered_pixels(&self) -> PyResult<usize> {
        let have = self.inner.outputs();
        if !have.contains(Outputs::TRIANGLE_ID) && !have.contains(Outputs::DEPTH) {
            return Err(invalid(format!(
                "covered_pixels: needs the 'depth' or 'triangle_id' output (this image holds {})",
                have.names().join(", ")
            )));
        }
        Ok(self.inner.covered_pixels())
    }

    /// The outputs the frame holds, by name ("rgb", "hdr", "depth", "normal", "triangle_id").
    #[getter]
    fn outputs(&self) -> Vec<&'static str> {
        self.inner.outputs().names()
    }
}

/// One instance as the Python `Scene` passes it: mesh, model, row-major 4×4 transform, ambient `k_a`
/// (`None`: the material's white-sky albedo, `brdf_raster::ambient::resolve`), emission.
type InstanceArgs<'py> = (PyRef<'py, RasterMesh>, PyRef<'py, Model>, [f32; 16], Option<[f32; 3]>, [f32; 3]);

/// Obscurance options as the Python wrapper passes them: `(tau, d_max, samples, seed, per_pixel,
/// combined)` (see `brdf_raster::ao::AoOptions`).
type AoArgs = (f32, f32, u32, u64, bool, bool);

fn check_size(name: &'static str, v: i64) -> PyResult<u32> {
    if v < 1 || v > i64::from(MAX_IMAGE_SIDE) {
        return Err(invalid(format!("{name}: must be an integer in 1..={MAX_IMAGE_SIDE} pixels, got {v}")));
    }
    Ok(v as u32)
}

/// Render a scene. `instances`: list of `(RasterMesh, Model, transform[16] row-major, ambient[3] or
/// None, emission[3])`; `ambient_light`: `I_a`, or `None` for none (see `brdf_raster::ambient::resolve`); `lights`: list of `RasterLight`; `area_lights`: list of `RasterAreaLight`, estimated with `area_samples` iterations and `area_seed` (`brdf_raster::area_lighting`); returns a [`RasterFrame`]. The scene is built under
/// the GIL, then rendered with the GIL released on the bindings' thread pool. `progress(fraction)` is
/// called (with the GIL, from worker threads, one call at a time, increasing fractions) as bands of
/// rows finish; an exception it raises is re-raised after the render. `vertex_obscurance`: one entry
/// per instance, its mesh's stored per-vertex `w` (float32 `(V,)`) or `None`; with `ao` on, instances
/// that have one use it instead of an estimate (`SceneOcclusion::with_stored`). `textures`: one entry
/// per instance, `None` or its texture bindings (`texture::InstanceTextureArgs`: bound parameters,
/// normal, occlusion and emission maps), the model being the one at the textures' means.
#[pyfunction]
#[pyo3(signature = (instances, lights, ambient_light, background, camera, width, height, shading="phong",
    cull_back_faces=true, samples=1, tonemap="clamp", exposure=0.0, white=None, ao=None, shadows=false,
    progress=None, vertex_obscurance=None, outputs=None, environment=None, env_mode="fast", env_samples=64,
    env_seed=0, area_lights=None, area_samples=16, area_seed=0, textures=None))]
pub fn render_scene(
    py: Python<'_>,
    instances: Vec<InstanceArgs<'_>>,
    lights: Vec<PyRef<'_, RasterLight>>,
    ambient_light: Option<[f32; 3]>,
    background: [f32; 3],
    camera: PyRef<'_, RasterCamera>,
    width: i64,
    height: i64,
    shading: &str,
    cull_back_faces: bool,
    samples: i64,
    tonemap: &str,
    exposure: f32,
    white: Option<f32>,
    ao: Option<AoArgs>,
    shadows: bool,
    progress: Option<Bound<'_, PyAny>>,
    vertex_obscurance: Option<Vec<Option<PyReadonlyArray1<'_, f32>>>>,
    outputs: Option<Vec<String>>,
    environment: Option<PyRef<'_, RasterEnvironment>>,
    env_mode: &str,
    env_samples: i64,
    env_seed: u64,
    area_lights: Option<Vec<PyRef<'_, RasterAreaLight>>>,
    area_samples: i64,
    area_seed: u64,
    textures: Option<Vec<Option<InstanceTextureArgs<'_>>>>,
) -> PyResult<RasterFrame> {
    let width = check_size("width", width)?;
    let height = check_size("height", height)?;
    if ![1, 4, 9, 16].contains(&samples) {
        return Err(invalid(format!(
            "samples: must be 1, 4, 9 or 16 (an s×s grid per pixel), got {samples}"
        )));
    }
    let mut options = RenderOptions::new(width, height);
    options.shading = ShadingMode::from_name(&shading.to_ascii_lowercase()).map_err(raster_err)?;
    options.cull_back_faces = cull_back_faces;
    options.samples_per_pixel = samples as u32;
    options.tonemap = operator(tonemap, white)?;
    options.exposure = exposure;
    options.ao = ao.map(|(tau, d_max, samples, seed, per_pixel, combined)| AoOptions {
        tau,
        d_max,
        samples,
        seed,
        per_pixel,
        combined,
    });
    options.shadows = shadows;
    // By default what most scripts read: the 8-bit image (encoded while each band is in the cache) and
    // the depth (which also gives the coverage).
    options.outputs = match &outputs {
        None => Outputs::RGB8 | Outputs::DEPTH,
        Some(names) => Outputs::from_names(names.iter().map(String::as_str)).map_err(raster_err)?,
    };
    let env_samples = u32::try_from(env_samples).unwrap_or(0);
    options.environment = EnvironmentMode::from_name(env_mode, env_samples, env_seed).map_err(raster_err)?;
    options.area = AreaSampling { samples: u32::try_from(area_samples).unwrap_or(0), seed: area_seed };
    options.validate().map_err(raster_err)?;

    let mut scene = Scene::new();
    scene.environment = environment.map(|e| e.inner.clone());
    let ambient_light = ambient_light.map(|c| color3("ambient_light", c)).transpose()?;
    scene.ambient_light = ambient_light.unwrap_or(Vec3::ONE);
    scene.background = color3("background", background)?;
    let pool = pool()?;
    for (k, (mesh, model, transform, ambient, emission)) in instances.iter().enumerate() {
        let m = mat4_from_rows("transform", *transform)?;
        let ambient = ambient.map(|c| color3("ambient", c)).transpose()?;
        let core = model.core();
        // The white-sky albedo is a quadrature over the model: without the GIL.
        let (_, ka) = py
            .detach(|| pool.install(|| resolve_ambient(core, ambient, ambient_light)))
            .map_err(raster_err)?;
        let mut material =
            Material::new(core.clone()).with_ambient(ka).with_emission(color3("emission", *emission)?);
        if let Some(Some(t)) = textures.as_ref().and_then(|t| t.get(k)) {
            let mt = material_textures(model.core_params(), t)?;
            material = material.with_textures(mt).map_err(raster_err)?;
        }
        if !(glam::Mat3::from_mat4(m).determinant().abs() > 0.0) {
            return Err(invalid(format!("transform: instance {k} has a singular transform")));
        }
        scene.add(Arc::clone(&mesh.inner), material, m);
    }
    for l in &lights {
        scene.add_light(l.inner);
    }
    for l in area_lights.iter().flatten() {
        scene.add_area_light(l.inner);
    }
    scene.validate().map_err(raster_err)?;
    let stored: Option<Vec<Option<Vec<f32>>>> = match (&options.ao, vertex_obscurance) {
        (Some(_), Some(v)) if v.iter().any(Option::is_some) => {
            Some(v.iter().map(|w| w.as_ref().map(|w| w.as_array().iter().copied().collect())).collect())
        }
        _ => None,
    };
    let cam = camera.inner;

    // Progress: serialised, increasing, and the first Python error kept for after the render.
    let state: Mutex<(f32, Option<PyErr>)> = Mutex::new((0.0, None));
    let cb = progress.map(|p| p.unbind());
    let report = |f: f32| {
        let Some(cb) = cb.as_ref() else { return };
        let mut s = state.lock().unwrap_or_else(|e| e.into_inner());
        if f <= s.0 || s.1.is_some() {
            return;
        }
        s.0 = f;
        Python::attach(|py| {
            if let Err(e) = cb.call1(py, (f,)) {
                s.1 = Some(e);
            }
        });
    };

    let report: &(dyn Fn(f32) + Sync) = &report;
    let mut frame = take_spare_frame();
    let result = py.detach(|| {
        pool.install(|| {
            if options.ao.is_none() && !options.shadows {
                return render_lit_into(&scene, &cam, &options, &NoOcclusion, Some(report), &mut frame);
            }
            // One BVH over the world-space scene; per-vertex obscurance is estimated here, in parallel,
            // except for instances whose mesh brought stored values. Both are kept for the next render
            // of the same geometry (a loop of renders with a moving camera or changing lights).
            let stored = stored.unwrap_or_else(|| vec![None; scene.instances.len()]);
            let occlusion = {
                let mut cache = OCCLUSION_CACHE.lock().unwrap_or_else(|e| e.into_inner());
                cache.get(&scene, options.ao, options.shadows, stored)?
            };
            render_lit_into(&scene, &cam, &options, &occlusion, Some(report), &mut frame)
        })
    });
    result.map_err(raster_err)?;
    if let Some(e) = state.into_inner().unwrap_or_else(|e| e.into_inner()).1 {
        return Err(e);
    }
    Ok(RasterFrame { inner: frame })
}

/// The largest accepted image side and pixel count (`brdf_raster::render::MAX_PIXELS`, whatever the
/// samples per pixel), for the Python docs and checks.
#[pyfunction]
pub fn raster_limits() -> (u32, u64) {
    (MAX_IMAGE_SIDE, MAX_PIXELS)
}
