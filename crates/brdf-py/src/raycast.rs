//! Ray queries and ambient obscurance from Python, over `brdf_raster::bvh` and `brdf_raster::ao`.
//!
//! - [`RayCaster`]: a BVH over one or more meshes (each placed by a 4×4 transform), answering
//!   closest-hit and any-hit queries for NumPy batches of rays, and obscurance `w` at arbitrary points
//!   against everything in it.
//! - [`mesh_obscurance`]: per-vertex `w` of a mesh against itself (`Mesh.compute_obscurance`; renders
//!   use stored values through `SceneOcclusion::with_stored`, see `raster/render.rs`).
//!
//! Every call checks its arguments (naming them), then runs with the GIL released on the bindings'
//! pool (`threads.rs`). Each ray and each point is answered independently (rays by the BVH alone,
//! points with a sample pattern keyed by their index), so results are bit-identical at any thread
//! count.

use std::sync::Arc;
use std::time::Instant;

use brdf_raster::Mesh;
use brdf_raster::ao::{AoOptions, MAX_SAMPLES, Obscurance};
use brdf_raster::bvh::{Bvh, Ray};
use glam::Mat4;
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{at, broadcast_rows, vec3_view};
use crate::errors::invalid;
use crate::raster::{RasterMesh, raster_err};
use crate::threads::pool;

/// Obscurance options from the Python arguments, validated by the core (errors name `tau`, `d_max`
/// or `samples`).
fn ao_options(tau: f64, d_max: f64, samples: i64, seed: u64) -> PyResult<AoOptions> {
    if samples < 1 || samples > i64::from(MAX_SAMPLES) {
        return Err(invalid(format!("samples: must lie in [1, {MAX_SAMPLES}], got {samples}")));
    }
    // f64 → f32 turns values beyond the f32 range into ±inf, which the core refuses by name.
    let opts = AoOptions {
        tau: tau as f32,
        d_max: d_max as f32,
        samples: samples as u32,
        seed,
        per_pixel: false,
        combined: false,
    };
    opts.validate().map_err(raster_err)?;
    Ok(opts)
}

/// Per-vertex obscurance `w` (Zhukov, Iones & Kronin 1998; Theoharis et al. 2008 eq. 12.72, μ
/// normalised to `d_max`: see `brdf_raster::ao`) of `mesh` against itself, in the mesh's own
/// coordinates: float32 `(V,)` in [0, 1]. Vertex `i` uses the sample pattern keyed by `(seed, i)`.
#[pyfunction]
#[pyo3(signature = (mesh, tau, d_max, samples, seed))]
pub fn mesh_obscurance<'py>(
    py: Python<'py>,
    mesh: PyRef<'py, RasterMesh>,
    tau: f64,
    d_max: f64,
    samples: i64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let opts = ao_options(tau, d_max, samples, seed)?;
    let m: Arc<Mesh> = Arc::clone(&mesh.inner);
    let pool = pool()?;
    let w = py.detach(|| pool.install(|| brdf_raster::ao::mesh_obscurance(&m, &opts))).map_err(raster_err)?;
    Ok(PyArray1::from_vec(py, w))
}

/// A BVH over the triangles of one or more meshes (world space), built once, queried many times.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RayCaster {
    bvh: Bvh,
    build_seconds: f64,
}

/// A row-major 4×4 matrix from Python (column vectors, `p' = M @ p`) as glam's column-major `Mat4`.
fn mat4(k: usize, a: [f32; 16]) -> PyResult<Mat4> {
    if a.iter().any(|x| !x.is_finite()) {
        return Err(invalid(format!("transform: part {k} has a non-finite entry")));
    }
    Ok(Mat4::from_cols_array(&a).transpose())
}

/// The rays of a batch: origins and directions `(1 or N, 3)`, `t_min` and `t_max` `(1 or N,)`, broadcast
/// to a common `N`. Errors name the argument and the row: a non-finite origin, a zero or non-finite
/// direction, a NaN bound.
fn rays(
    origins: &PyReadonlyArray2<'_, f32>,
    directions: &PyReadonlyArray2<'_, f32>,
    t_min: &PyReadonlyArray1<'_, f32>,
    t_max: &PyReadonlyArray1<'_, f32>,
) -> PyResult<Vec<Ray>> {
    let o = vec3_view("origins", origins)?;
    let d = vec3_view("directions", directions)?;
    let lo = t_min.as_slice().map_err(|_| invalid("t_min: expected a C-contiguous float32 array"))?;
    let hi = t_max.as_slice().map_err(|_| invalid("t_max: expected a C-contiguous float32 array"))?;
    if lo.is_empty() || hi.is_empty() {
        return Err(invalid("t_min, t_max: must not be empty"));
    }
    let n = broadcast_rows(&[
        ("origins", o.len(), &[3]),
        ("directions", d.len(), &[3]),
        ("t_min", lo.len(), &[]),
        ("t_max", hi.len(), &[]),
    ])?;
    if let Some(i) = o.iter().position(|p| !p.is_finite()) {
        return Err(invalid(format!("origins: row {i} is not finite: {}", o[i])));
    }
    if let Some(i) = d.iter().position(|v| !v.is_finite() || v.length_squared() == 0.0) {
        return Err(invalid(format!("directions: row {i} is zero or not finite: {}", d[i])));
    }
    if let Some(i) = lo.iter().position(|t| t.is_nan() || *t == f32::INFINITY) {
        return Err(invalid(format!("t_min: element {i} must be a number below +inf, got {}", lo[i])));
    }
    if let Some(i) = hi.iter().position(|t| t.is_nan()) {
        return Err(invalid(format!("t_max: element {i} is NaN")));
    }
    let mut out: Vec<Ray> = Vec::new();
    out.try_reserve_exact(n).map_err(|_| invalid(format!("origins: cannot allocate {n} rays")))?;
    out.extend((0..n).map(|i| Ray::segment(at(o, i), at(d, i), at(lo, i), at(hi, i))));
    Ok(out)
}

/// Closest-hit answers as NumPy arrays: `(t, triangle, u, v)`.
type Hits<'py> = (
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<f32>>,
);

#[pymethods]
impl RayCaster {
    /// Build over `parts`: a list of `(RasterMesh, transform)` with the transform a row-major 4×4
    /// (16 floats) or `None` for the identity. Triangle ids run through the parts in order. Degenerate
    /// triangles are skipped (never hit). Built with the GIL released, on the pool.
    #[new]
    fn new(py: Python<'_>, parts: Vec<(PyRef<'_, RasterMesh>, Option<[f32; 16]>)>) -> PyResult<Self> {
        if parts.is_empty() {
            return Err(invalid("meshes: need at least one mesh"));
        }
        let mut owned: Vec<(Arc<Mesh>, Mat4)> = Vec::with_capacity(parts.len());
        for (k, (m, xf)) in parts.iter().enumerate() {
            let xf = match xf {
                Some(a) => mat4(k, *a)?,
                None => Mat4::IDENTITY,
            };
            owned.push((Arc::clone(&m.inner), xf));
        }
        let pool = pool()?;
        let (bvh, build_seconds) = py
            .detach(|| {
                pool.install(|| {
                    let refs: Vec<(&Mesh, Mat4)> = owned.iter().map(|(m, x)| (&**m, *x)).collect();
                    let t0 = Instant::now();
                    // A single untransformed mesh: its positions as they are (no matrix product at all).
                    let bvh = if refs.len() == 1 && refs[0].1 == Mat4::IDENTITY {
                        Bvh::from_mesh(refs[0].0)
                    } else {
                        Bvh::from_instances(&refs)
                    };
                    bvh.map(|b| (b, t0.elapsed().as_secs_f64()))
                })
            })
            .map_err(raster_err)?;
        Ok(Self { bvh, build_seconds })
    }

    /// Triangles in the input, including skipped degenerate ones.
    #[getter]
    fn n_triangles(&self) -> usize {
        self.bvh.input_triangles()
    }

    /// Degenerate (zero-area) input triangles that were skipped.
    #[getter]
    fn n_skipped(&self) -> usize {
        self.bvh.skipped_triangles()
    }

    /// Wall-clock seconds the build took.
    #[getter]
    fn build_seconds(&self) -> f64 {
        self.build_seconds
    }

    /// `((min), (max))` of the non-degenerate triangles.
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let (lo, hi) = self.bvh.bounds();
        (lo.to_array(), hi.to_array())
    }

    /// Shape of the tree: nodes, leaves, max_leaf, max_depth, sah_cost.
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.bvh.stats();
        let d = PyDict::new(py);
        d.set_item("nodes", s.nodes)?;
        d.set_item("leaves", s.leaves)?;
        d.set_item("max_leaf", s.max_leaf)?;
        d.set_item("max_depth", s.max_depth)?;
        d.set_item("sah_cost", s.sah_cost)?;
        Ok(d)
    }

    /// Closest hits: `(t, triangle, u, v)` float32, int64, float32, float32 arrays of `N`; a miss has
    /// `t = inf`, `triangle = -1`, `u = v = 0`.
    fn closest_hit<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'py, f32>,
        directions: PyReadonlyArray2<'py, f32>,
        t_min: PyReadonlyArray1<'py, f32>,
        t_max: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<Hits<'py>> {
        let rays = rays(&origins, &directions, &t_min, &t_max)?;
        let pool = pool()?;
        let hits = py.detach(|| pool.install(|| self.bvh.closest_hits(&rays)));
        let n = hits.len();
        let (mut t, mut id, mut u, mut v) =
            (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        for h in &hits {
            match h {
                Some(h) => {
                    t.push(h.t);
                    id.push(i64::from(h.triangle));
                    u.push(h.u);
                    v.push(h.v);
                }
                None => {
                    t.push(f32::INFINITY);
                    id.push(-1);
                    u.push(0.0);
                    v.push(0.0);
                }
            }
        }
        Ok((
            PyArray1::from_vec(py, t),
            PyArray1::from_vec(py, id),
            PyArray1::from_vec(py, u),
            PyArray1::from_vec(py, v),
        ))
    }

    /// Whether each ray hits anything on its segment: bool array of `N`.
    fn any_hit<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'py, f32>,
        directions: PyReadonlyArray2<'py, f32>,
        t_min: PyReadonlyArray1<'py, f32>,
        t_max: PyReadonlyArray1<'py, f32>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let rays = rays(&origins, &directions, &t_min, &t_max)?;
        let pool = pool()?;
        let hits = py.detach(|| pool.install(|| self.bvh.any_hits(&rays)));
        Ok(PyArray1::from_vec(py, hits))
    }

    /// Obscurance `w` at `points` with unit `normals` (both `(N, 3)`) against everything in the BVH,
    /// point `i` keyed by `i`: float32 `(N,)`. A zero normal gives 1.
    #[pyo3(signature = (points, normals, tau, d_max, samples, seed))]
    #[allow(clippy::too_many_arguments)]
    fn obscurance<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f32>,
        normals: PyReadonlyArray2<'py, f32>,
        tau: f64,
        d_max: f64,
        samples: i64,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let opts = ao_options(tau, d_max, samples, seed)?;
        let p = vec3_view("points", &points)?;
        let n = vec3_view("normals", &normals)?;
        let pool = pool()?;
        let w = py
            .detach(|| pool.install(|| Obscurance::new(&self.bvh, &opts)?.at_points(p, n)))
            .map_err(raster_err)?;
        Ok(PyArray1::from_vec(py, w))
    }
}
