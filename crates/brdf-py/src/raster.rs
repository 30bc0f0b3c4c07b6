//! The rasterizer from Python: meshes, cameras, lights, and one `render_scene` call that builds a
//! `brdf_raster::Scene` under the GIL and renders it with the GIL released, on the bindings' pool.
//!
//! The Python package (`brdfpy/scene.py`, `mesh.py`, `camera.py`, `lights.py`, `image.py`) wraps these
//! classes: it converts array-likes to C-contiguous float32/uint32, converts degrees to radians and
//! keeps the scene itself as plain Python lists, so that a scene is easy to inspect and edit. Every
//! input is checked here again, naming the argument, so that a direct call cannot misbehave either.

use std::sync::{Arc, Mutex};

use brdf_core::lights::{Attenuation, Light};
use brdf_core::tonemap::Operator;
use brdf_raster::ao::AoOptions;
use brdf_raster::normals::Weighting;
use brdf_raster::occlusion::SceneOcclusion;
use brdf_raster::render::{MAX_IMAGE_SIDE, NoOcclusion, RenderOptions, render_with_into};
use brdf_raster::tiles::NO_TRI;
use brdf_raster::{Camera, Frame, Material, Mesh, Projection, RasterError, Scene, ShadingMode};
use glam::{Mat4, Vec3};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{invalid, to_py};
use crate::models::Model;
use crate::threads::pool;

/// A raster error as a Python exception: a file that cannot be parsed, an invalid mesh or argument →
/// `BrdfError` (a `ValueError`) with the core's message, which names the argument or the file.
pub fn raster_err(e: RasterError) -> PyErr {
    match e {
        RasterError::Brdf(b) => to_py(b),
        other => invalid(other.to_string()),
    }
}

/// `(N, 3)` float32 rows as `Vec3`, naming the argument (the Python side has converted the dtype).
fn rows3(name: &str, a: &PyReadonlyArray2<'_, f32>) -> PyResult<Vec<Vec3>> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(invalid(format!("{name}: expected shape (N, 3), got ({}, {})", shape[0], shape[1])));
    }
    let s =
        a.as_slice().map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous array")))?;
    let rows: Vec<Vec3> = s.chunks_exact(3).map(Vec3::from_slice).collect();
    if let Some(i) = rows.iter().position(|r| !r.is_finite()) {
        return Err(invalid(format!("{name}: row {i} is not finite: {}", rows[i])));
    }
    Ok(rows)
}

fn vec3_array<'py>(py: Python<'py>, v: &[Vec3]) -> PyResult<Bound<'py, PyArray2<f32>>> {
    PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(v)).reshape([v.len(), 3])
}

fn finite3(name: &str, v: [f32; 3]) -> PyResult<Vec3> {
    let v = Vec3::from_array(v);
    if !v.is_finite() {
        return Err(invalid(format!("{name}: must be finite, got {v}")));
    }
    Ok(v)
}

fn color3(name: &str, v: [f32; 3]) -> PyResult<Vec3> {
    let v = finite3(name, v)?;
    if v.min_element() < 0.0 {
        return Err(invalid(format!("{name}: must be ≥ 0 in every channel, got {v}")));
    }
    Ok(v)
}

// ---------------------------------------------------------------------------------------------------
// Meshes

/// A triangle mesh (object space): positions, unit vertex normals, CCW faces, optional vertex colours.
/// Immutable from Python's side except for [`RasterMesh::compute_normals`] and
/// [`RasterMesh::flip_winding`]; scenes hold their own reference, taken when the mesh was added.
#[pyclass(module = "brdfpy._brdfpy")]
pub struct RasterMesh {
    pub(crate) inner: Arc<Mesh>,
}

impl RasterMesh {
    fn wrap(m: Mesh) -> Self {
        Self { inner: Arc::new(m) }
    }
}

fn weighting(name: &str) -> PyResult<Weighting> {
    match name.to_ascii_lowercase().as_str() {
        "angle" => Ok(Weighting::Angle),
        "area" => Ok(Weighting::Area),
        "equal" => Ok(Weighting::Equal),
        _ => Err(invalid(format!("weighting: expected 'angle', 'area' or 'equal', got {name:?}"))),
    }
}

#[pymethods]
impl RasterMesh {
    /// A handle to the same data, copied on the first in-place change of either (`Arc::make_mut`): what a
    /// scene takes when a mesh is added, so later edits of the mesh do not reach the scene.
    fn __copy__(&self) -> Self {
        Self { inner: Arc::clone(&self.inner) }
    }

    /// Validate and build: `vertices` float32 (V, 3), `faces` uint32 (F, 3), `normals` float32 (V, 3)
    /// or `None` (angle-weighted vertex normals), `colors` float32 (V, 3) linear RGB or `None`.
    #[new]
    #[pyo3(signature = (vertices, faces, normals=None, colors=None))]
    fn new(
        vertices: PyReadonlyArray2<'_, f32>,
        faces: PyReadonlyArray2<'_, u32>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        colors: Option<PyReadonlyArray2<'_, f32>>,
    ) -> PyResult<Self> {
        let positions = rows3("vertices", &vertices)?;
        if positions.is_empty() {
            return Err(invalid("vertices: is empty (a mesh needs at least 3 vertices)"));
        }
        let fshape = faces.shape();
        if fshape[1] != 3 {
            return Err(invalid(format!("faces: expected shape (F, 3), got ({}, {})", fshape[0], fshape[1])));
        }
        if fshape[0] == 0 {
            return Err(invalid("faces: is empty (a mesh needs at least one triangle)"));
        }
        let fs =
            faces.as_slice().map_err(|_| PyTypeError::new_err("faces: expected a C-contiguous array"))?;
        let indices: Vec<[u32; 3]> = fs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let nv = positions.len();
        if let Some(f) = indices.iter().position(|t| t.iter().any(|&i| i as usize >= nv)) {
            return Err(invalid(format!(
                "faces: face {f} {:?} indexes past the {nv} vertices (valid indices are 0..{})",
                indices[f],
                nv - 1
            )));
        }
        let normals = match normals {
            Some(n) => {
                let n = rows3("normals", &n)?;
                if n.len() != nv {
                    return Err(invalid(format!("normals: {} rows for {nv} vertices", n.len())));
                }
                Some(n)
            }
            None => None,
        };
        let mut mesh = Mesh::new(positions, indices, normals).map_err(raster_err)?;
        if let Some(c) = colors {
            let c = rows3("colors", &c)?;
            if c.len() != nv {
                return Err(invalid(format!("colors: {} rows for {nv} vertices", c.len())));
            }
            mesh = mesh.with_colors(c).map_err(raster_err)?;
        }
        Ok(Self::wrap(mesh))
    }

    /// Vertex positions, float32 (V, 3) (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        vec3_array(py, &self.inner.positions)
    }

    /// Unit vertex normals, float32 (V, 3) (a copy).
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        vec3_array(py, &self.inner.normals)
    }

    /// Triangles as vertex indices, uint32 (F, 3), counter-clockwise seen from the front (a copy).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let flat: &[u32] = bytemuck::cast_slice(&self.inner.indices);
        PyArray1::from_slice(py, flat).reshape([self.inner.indices.len(), 3])
    }

    /// Per-vertex linear RGB colours, float32 (V, 3), or `None`.
    #[getter]
    fn colors<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.inner.colors.as_deref().map(|c| vec3_array(py, c)).transpose()
    }

    /// Unit face normals by the cross product of two edges, float32 (F, 3); zero for degenerate faces.
    fn face_normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        vec3_array(py, &self.inner.face_normals())
    }

    /// Number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.inner.vertex_count()
    }

    /// Number of triangles.
    #[getter]
    fn n_faces(&self) -> usize {
        self.inner.triangle_count()
    }

    /// Recompute the vertex normals in place with `weighting` ("angle", "area" or "equal"; seed 004).
    fn compute_normals(&mut self, weighting_name: &str) -> PyResult<()> {
        let w = weighting(weighting_name)?;
        Arc::make_mut(&mut self.inner).compute_normals(w);
        Ok(())
    }

    /// Reverse every face's winding and negate the normals, in place.
    fn flip_winding(&mut self) {
        Arc::make_mut(&mut self.inner).flip_winding();
    }

    /// A new mesh with positions transformed by the 4×4 row-major `matrix` (normals by its inverse
    /// transpose).
    fn transformed(&self, matrix: [f32; 16]) -> PyResult<Self> {
        let m = mat4_from_rows("matrix", matrix)?;
        Ok(Self::wrap(self.inner.transformed(&m).map_err(raster_err)?))
    }

    /// `((min_x, min_y, min_z), (max_x, max_y, max_z))`.
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.inner.bounds();
        (b.min.to_array(), b.max.to_array())
    }

    /// `((cx, cy, cz), radius)` of a sphere enclosing every vertex (box centre, farthest vertex).
    fn bounding_sphere(&self) -> ([f32; 3], f32) {
        let (c, r) = self.inner.bounding_sphere();
        (c.to_array(), r)
    }

    /// Topology and geometry summary (see `brdf_raster::mesh::MeshStats`).
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = py.detach(|| self.inner.stats());
        let d = PyDict::new(py);
        d.set_item("vertices", s.vertices)?;
        d.set_item("triangles", s.triangles)?;
        d.set_item("degenerate_triangles", s.degenerate_triangles)?;
        d.set_item("unreferenced_vertices", s.unreferenced_vertices)?;
        d.set_item("boundary_edges", s.boundary_edges)?;
        d.set_item("non_manifold_edges", s.non_manifold_edges)?;
        d.set_item("inconsistent_edges", s.inconsistent_edges)?;
        d.set_item("components", s.components)?;
        d.set_item("watertight", s.watertight)?;
        d.set_item("winding_consistent", s.winding_consistent)?;
        d.set_item("signed_volume", s.signed_volume)?;
        d.set_item("area", s.area)?;
        d.set_item("bounds", (s.bounds.min.to_array(), s.bounds.max.to_array()))?;
        Ok(d)
    }

    fn __len__(&self) -> usize {
        self.inner.triangle_count()
    }
}

/// Load an OBJ or PLY file (format from the extension); malformed files raise `BrdfError` naming the
/// file and the problem.
#[pyfunction]
pub fn load_mesh(py: Python<'_>, path: std::path::PathBuf) -> PyResult<RasterMesh> {
    let m = py.detach(|| brdf_raster::io::load_mesh(&path)).map_err(raster_err)?;
    Ok(RasterMesh::wrap(m))
}

/// Parse OBJ (`format="obj"`) or PLY (`"ply"`) bytes.
#[pyfunction]
pub fn load_mesh_bytes(py: Python<'_>, data: Vec<u8>, format: &str) -> PyResult<RasterMesh> {
    use brdf_raster::io::MeshFormat;
    let f = match format.to_ascii_lowercase().as_str() {
        "obj" => MeshFormat::Obj,
        "ply" => MeshFormat::Ply,
        _ => return Err(invalid(format!("format: expected 'obj' or 'ply', got {format:?}"))),
    };
    let m = py.detach(|| brdf_raster::io::load_mesh_bytes(&data, f)).map_err(raster_err)?;
    Ok(RasterMesh::wrap(m))
}

/// Names of the meshes embedded in the library.
/// Normal of a polygon given by its vertices in order (seed 004 "Normals"): `method` is "newell"
/// (Newell's method, unnormalised: twice the area vector), "cross" (cross product of the first two edges
/// at vertex 0) or "corner_average" (mean of the unit corner normals).
#[pyfunction]
pub fn polygon_normal(points: Vec<[f32; 3]>, method: &str) -> PyResult<[f32; 3]> {
    if points.len() < 3 {
        return Err(invalid(format!("points: a polygon needs at least 3 vertices, got {}", points.len())));
    }
    let pts: Vec<Vec3> = points.iter().map(|p| Vec3::from_array(*p)).collect();
    if let Some(i) = pts.iter().position(|p| !p.is_finite()) {
        return Err(invalid(format!("points: vertex {i} is not finite")));
    }
    let n = match method.to_ascii_lowercase().as_str() {
        "newell" => brdf_raster::normals::newell_normal(&pts),
        "cross" => brdf_raster::normals::triangle_normal(pts[0], pts[1], pts[2]),
        "corner_average" => brdf_raster::normals::corner_average_normal(&pts),
        _ => {
            return Err(invalid(format!(
                "method: expected 'newell', 'cross' or 'corner_average', got {method:?}"
            )));
        }
    };
    Ok(n.to_array())
}

#[pyfunction]
pub fn builtin_mesh_names() -> Vec<&'static str> {
    brdf_raster::io::BUILTIN_MESHES.to_vec()
}

/// An embedded mesh by name (see [`builtin_mesh_names`]).
#[pyfunction]
pub fn builtin_mesh(name: &str) -> PyResult<RasterMesh> {
    Ok(RasterMesh::wrap(brdf_raster::io::builtin_mesh(name).map_err(raster_err)?))
}

/// The unit icosphere of SCENE.md (level L: 20·4^L faces, normals = positions).
#[pyfunction]
pub fn icosphere(py: Python<'_>, level: u32) -> PyResult<RasterMesh> {
    Ok(RasterMesh::wrap(py.detach(|| brdf_raster::procedural::icosphere(level)).map_err(raster_err)?))
}

/// The torus of SCENE.md (R 0.7, r 0.3, axis +z).
#[pyfunction]
pub fn torus(py: Python<'_>, major_segments: u32, minor_segments: u32) -> PyResult<RasterMesh> {
    let m = py.detach(|| brdf_raster::procedural::torus(major_segments, minor_segments));
    Ok(RasterMesh::wrap(m.map_err(raster_err)?))
}

/// A square in y = 0 facing +y.
#[pyfunction]
pub fn plane(size: f32, subdivisions: u32) -> PyResult<RasterMesh> {
    Ok(RasterMesh::wrap(brdf_raster::procedural::plane(size, subdivisions).map_err(raster_err)?))
}

/// A closed cube centred at the origin.
#[pyfunction]
pub fn cube(size: f32, subdivisions: u32) -> PyResult<RasterMesh> {
    Ok(RasterMesh::wrap(brdf_raster::procedural::cube(size, subdivisions).map_err(raster_err)?))
}

/// A box open at the top, faces pointing inward.
#[pyfunction]
pub fn open_box(size: f32, subdivisions: u32) -> PyResult<RasterMesh> {
    Ok(RasterMesh::wrap(brdf_raster::procedural::open_box(size, subdivisions).map_err(raster_err)?))
}

// ---------------------------------------------------------------------------------------------------
// Camera

fn mat4_from_rows(name: &str, a: [f32; 16]) -> PyResult<Mat4> {
    if a.iter().any(|x| !x.is_finite()) {
        return Err(invalid(format!("{name}: must be finite")));
    }
    // Python gives row-major (the printed matrix, column vectors: p' = M @ p); glam is column-major.
    Ok(Mat4::from_cols_array(&a).transpose())
}

fn rows_of(m: Mat4) -> [[f32; 4]; 4] {
    m.transpose().to_cols_array_2d()
}

/// A look-at camera (OpenGL conventions; angles in radians here, degrees in the Python wrapper).
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterCamera {
    pub(crate) inner: Camera,
}

#[pymethods]
impl RasterCamera {
    /// Perspective camera, vertical field of view `fovy` in radians.
    #[staticmethod]
    fn perspective(
        eye: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
        fovy: f32,
        near: f32,
        far: f32,
    ) -> PyResult<Self> {
        let c = Camera::perspective(
            finite3("eye", eye)?,
            finite3("target", target)?,
            finite3("up", up)?,
            fovy,
            near,
            far,
        );
        Ok(Self { inner: c.map_err(raster_err)? })
    }

    /// Orthographic camera whose view volume is `height` world units tall.
    #[staticmethod]
    fn orthographic(
        eye: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
        height: f32,
        near: f32,
        far: f32,
    ) -> PyResult<Self> {
        let c = Camera::orthographic(
            finite3("eye", eye)?,
            finite3("target", target)?,
            finite3("up", up)?,
            height,
            near,
            far,
        );
        Ok(Self { inner: c.map_err(raster_err)? })
    }

    #[getter]
    fn eye(&self) -> [f32; 3] {
        self.inner.eye.to_array()
    }
    #[getter]
    fn target(&self) -> [f32; 3] {
        self.inner.target.to_array()
    }
    #[getter]
    fn up(&self) -> [f32; 3] {
        self.inner.up.to_array()
    }
    #[getter]
    fn near(&self) -> f32 {
        self.inner.near
    }
    #[getter]
    fn far(&self) -> f32 {
        self.inner.far
    }
    /// "perspective" or "orthographic".
    #[getter]
    fn kind(&self) -> &'static str {
        if self.inner.is_orthographic() { "orthographic" } else { "perspective" }
    }
    /// Vertical field of view in radians (perspective) or view-volume height (orthographic).
    #[getter]
    fn extent(&self) -> f32 {
        match self.inner.projection {
            Projection::Perspective { fovy } => fovy,
            Projection::Orthographic { height } => height,
        }
    }

    /// The view matrix `V` (4×4 row-major, world → camera).
    fn view_matrix(&self) -> [[f32; 4]; 4] {
        rows_of(self.inner.view())
    }

    /// The projection matrix `P` for an image of aspect ratio `width / height` (OpenGL clip space).
    fn projection_matrix(&self, aspect: f32) -> PyResult<[[f32; 4]; 4]> {
        if !(aspect > 0.0) || !aspect.is_finite() {
            return Err(invalid(format!("aspect: must be finite and > 0, got {aspect}")));
        }
        Ok(rows_of(self.inner.projection(aspect)))
    }
}

// ---------------------------------------------------------------------------------------------------
// Lights

/// What arrives from a light at a point: `(l toward the light, irradiance, distance)`.
type IncidentTuple = ([f32; 3], [f32; 3], f32);

/// A light source (brdf-core `Light`); build through the static constructors.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterLight {
    pub(crate) inner: Light,
}

/// `None` / "none", "inverse_square", or `(c1, c2, c3)` of `1/(c1 + c2 d + c3 d²)`.
fn attenuation(x: &Bound<'_, PyAny>) -> PyResult<Attenuation> {
    if x.is_none() {
        return Ok(Attenuation::None);
    }
    if let Ok(s) = x.extract::<String>() {
        return match s.to_ascii_lowercase().as_str() {
            "none" => Ok(Attenuation::None),
            "inverse_square" => Ok(Attenuation::InverseSquare),
            _ => Err(invalid(format!(
                "attenuation: expected 'none', 'inverse_square' or (c1, c2, c3), got {s:?}"
            ))),
        };
    }
    match x.extract::<[f32; 3]>() {
        Ok([c1, c2, c3]) => Ok(Attenuation::Polynomial { c1, c2, c3 }),
        Err(_) => Err(PyTypeError::new_err(
            "attenuation: expected 'none', 'inverse_square' or three numbers (c1, c2, c3)",
        )),
    }
}

fn attenuation_to_py<'py>(py: Python<'py>, a: Attenuation) -> PyResult<Bound<'py, PyAny>> {
    Ok(match a {
        Attenuation::None => "none".into_pyobject(py)?.into_any(),
        Attenuation::InverseSquare => "inverse_square".into_pyobject(py)?.into_any(),
        Attenuation::Polynomial { c1, c2, c3 } => (c1, c2, c3).into_pyobject(py)?.into_any(),
    })
}

#[pymethods]
impl RasterLight {
    /// Directional light travelling along `direction` with irradiance `color`.
    #[staticmethod]
    fn directional(direction: [f32; 3], color: [f32; 3]) -> PyResult<Self> {
        let l = Light::directional(finite3("direction", direction)?, color3("color", color)?);
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// Point light at `position` with radiant intensity `intensity`.
    #[staticmethod]
    fn point(position: [f32; 3], intensity: [f32; 3], attenuation: &Bound<'_, PyAny>) -> PyResult<Self> {
        let a = self::attenuation(attenuation)?;
        let l = Light::point(finite3("position", position)?, color3("intensity", intensity)?, a);
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// Spot light; angles are half-angles in radians.
    #[staticmethod]
    fn spot(
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        inner_angle: f32,
        outer_angle: f32,
        attenuation: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let a = self::attenuation(attenuation)?;
        let l = Light::spot(
            finite3("position", position)?,
            finite3("direction", direction)?,
            color3("intensity", intensity)?,
            inner_angle,
            outer_angle,
            a,
        );
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// The light's fields as a dict (`kind` plus the constructor's arguments; angles in radians).
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match self.inner {
            Light::Directional { direction, color } => {
                d.set_item("kind", "directional")?;
                d.set_item("direction", direction.to_array())?;
                d.set_item("color", color.to_array())?;
            }
            Light::Point { position, intensity, attenuation } => {
                d.set_item("kind", "point")?;
                d.set_item("position", position.to_array())?;
                d.set_item("intensity", intensity.to_array())?;
                d.set_item("attenuation", attenuation_to_py(py, attenuation)?)?;
            }
            Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation } => {
                d.set_item("kind", "spot")?;
                d.set_item("position", position.to_array())?;
                d.set_item("direction", direction.to_array())?;
                d.set_item("intensity", intensity.to_array())?;
                d.set_item("inner_angle", inner_angle)?;
                d.set_item("outer_angle", outer_angle)?;
                d.set_item("attenuation", attenuation_to_py(py, attenuation)?)?;
            }
        }
        Ok(d)
    }

    /// `(l, irradiance, distance)` arriving at point `p`, or `None` (outside a spot's cone, at the light).
    fn incident(&self, p: [f32; 3]) -> PyResult<Option<IncidentTuple>> {
        let p = finite3("p", p)?;
        Ok(self.inner.incident(p).map(|i| (i.l.to_array(), i.irradiance.to_array(), i.distance)))
    }
}

// ---------------------------------------------------------------------------------------------------
// Frames and rendering

/// A rendered frame: HDR colour, depth, normal and triangle-id buffers (row 0 at the top).
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterFrame {
    inner: Frame,
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
        if !self.inner.rgb8.is_empty() && op == self.inner.tonemap && ev == self.inner.exposure {
            return PyArray1::from_slice(py, &self.inner.rgb8).reshape([h, w, 3]);
        }
        let p = pool()?;
        let bytes = py.detach(|| p.install(|| self.inner.to_rgb8_with(op, ev)));
        PyArray1::from_vec(py, bytes).reshape([h, w, 3])
    }

    /// Linear RGB before tone mapping, float32 (H, W, 3).
    fn hdr<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&self.inner.hdr)).reshape([h, w, 3])
    }

    /// Window depth in [0, 1] (1 = far / nothing drawn), float32 (H, W).
    fn depth<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, &self.inner.depth).reshape([h, w])
    }

    /// Unit world-space shading normals, float32 (H, W, 3); zero where nothing was drawn.
    fn normal<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&self.inner.normal)).reshape([h, w, 3])
    }

    /// Face index over all instances in scene order, int64 (H, W); −1 where nothing was drawn.
    fn triangle_id<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let (h, w) = (self.inner.height as usize, self.inner.width as usize);
        let ids: Vec<i64> =
            self.inner.triangle_id.iter().map(|&t| if t == NO_TRI { -1 } else { i64::from(t) }).collect();
        PyArray1::from_vec(py, ids).reshape([h, w])
    }

    /// Number of pixels some triangle covers.
    fn covered_pixels(&self) -> usize {
        self.inner.covered_pixels()
    }
}

/// One instance as the Python `Scene` passes it: mesh, model, row-major 4×4 transform, ambient `k_a`,
/// emission.
type InstanceArgs<'py> = (PyRef<'py, RasterMesh>, PyRef<'py, Model>, [f32; 16], [f32; 3], [f32; 3]);

/// Obscurance options as the Python wrapper passes them: `(tau, d_max, samples, seed, per_pixel,
/// combined)` (see `brdf_raster::ao::AoOptions`).
type AoArgs = (f32, f32, u32, u64, bool, bool);

fn check_size(name: &'static str, v: i64) -> PyResult<u32> {
    if v < 1 || v > i64::from(MAX_IMAGE_SIDE) {
        return Err(invalid(format!("{name}: must be an integer in 1..={MAX_IMAGE_SIDE} pixels, got {v}")));
    }
    Ok(v as u32)
}

/// Render a scene. `instances`: list of `(RasterMesh, Model, transform[16] row-major, ambient[3],
/// emission[3])`; `lights`: list of `RasterLight`; returns a [`RasterFrame`]. The scene is built under
/// the GIL, then rendered with the GIL released on the bindings' thread pool. `progress(fraction)` is
/// called (with the GIL, from worker threads, one call at a time, increasing fractions) as bands of
/// rows finish; an exception it raises is re-raised after the render. `vertex_obscurance`: one entry
/// per instance, its mesh's stored per-vertex `w` (float32 `(V,)`) or `None`; with `ao` on, instances
/// that have one use it instead of an estimate (`SceneOcclusion::with_stored`).
#[pyfunction]
#[pyo3(signature = (instances, lights, ambient_light, background, camera, width, height, shading="phong",
    cull_back_faces=true, samples=1, tonemap="clamp", exposure=0.0, white=None, ao=None, shadows=false,
    progress=None, vertex_obscurance=None))]
pub fn render_scene(
    py: Python<'_>,
    instances: Vec<InstanceArgs<'_>>,
    lights: Vec<PyRef<'_, RasterLight>>,
    ambient_light: [f32; 3],
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
    // `Image.rgb` is what most scripts read: encode it while each band is in the cache.
    options.encode_rgb8 = true;
    options.validate().map_err(raster_err)?;

    let mut scene = Scene::new();
    scene.ambient_light = color3("ambient_light", ambient_light)?;
    scene.background = color3("background", background)?;
    for (k, (mesh, model, transform, ambient, emission)) in instances.iter().enumerate() {
        let m = mat4_from_rows("transform", *transform)?;
        let material = Material::new(model.core().clone())
            .with_ambient(color3("ambient", *ambient)?)
            .with_emission(color3("emission", *emission)?);
        if !(glam::Mat3::from_mat4(m).determinant().abs() > 0.0) {
            return Err(invalid(format!("transform: instance {k} has a singular transform")));
        }
        scene.add(Arc::clone(&mesh.inner), material, m);
    }
    for l in &lights {
        scene.add_light(l.inner);
    }
    scene.validate().map_err(raster_err)?;
    let stored: Option<Vec<Option<Vec<f32>>>> = match (&options.ao, vertex_obscurance) {
        (Some(_), Some(v)) if v.iter().any(Option::is_some) => {
            Some(v.iter().map(|w| w.as_ref().map(|w| w.as_array().iter().copied().collect())).collect())
        }
        _ => None,
    };
    let cam = camera.inner;
    let pool = pool()?;

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
                return render_with_into(&scene, &cam, &options, &NoOcclusion, Some(report), &mut frame);
            }
            // One BVH over the world-space scene; per-vertex obscurance is estimated here, in parallel,
            // except for instances whose mesh brought stored values.
            let occlusion = match stored {
                Some(stored) => SceneOcclusion::with_stored(&scene, options.ao, options.shadows, stored)?,
                None => SceneOcclusion::new(&scene, options.ao, options.shadows)?,
            };
            render_with_into(&scene, &cam, &options, &occlusion, Some(report), &mut frame)
        })
    });
    result.map_err(raster_err)?;
    if let Some(e) = state.into_inner().unwrap_or_else(|e| e.into_inner()).1 {
        return Err(e);
    }
    Ok(RasterFrame { inner: frame })
}

/// The largest accepted image side and sample count, for the Python docs and checks.
#[pyfunction]
pub fn raster_limits() -> (u32, u64) {
    (MAX_IMAGE_SIDE, brdf_raster::render::MAX_SAMPLES)
}
