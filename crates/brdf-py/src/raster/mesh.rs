//! Meshes from Python: `RasterMesh`, the OBJ/PLY loaders, the procedural and built-in meshes.

use std::sync::Arc;

use brdf_raster::Mesh;
use brdf_raster::normals::Weighting;
use glam::Vec3;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{mat4_from_rows, raster_err, rows3, vec3_array};
use crate::errors::invalid;

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
    /// or `None` (angle-weighted vertex normals), `colors` float32 (V, 3) linear RGB or `None`, `uvs`
    /// float32 (V, 2) texture coordinates (glTF's: `(0, 0)` the top-left of the image, `v` down) or
    /// `None`, `tangents` float32 (V, 4) `(t, w)` (glTF's TANGENT) or `None`.
    #[new]
    #[pyo3(signature = (vertices, faces, normals=None, colors=None, uvs=None, tangents=None))]
    fn new(
        vertices: PyReadonlyArray2<'_, f32>,
        faces: PyReadonlyArray2<'_, u32>,
        normals: Option<PyReadonlyArray2<'_, f32>>,
        colors: Option<PyReadonlyArray2<'_, f32>>,
        uvs: Option<PyReadonlyArray2<'_, f32>>,
        tangents: Option<PyReadonlyArray2<'_, f32>>,
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
        let rows = |name: &str, a: &PyReadonlyArray2<'_, f32>, width: usize| -> PyResult<Vec<f32>> {
            let shape = a.shape();
            if shape[1] != width {
                return Err(invalid(format!(
                    "{name}: expected shape (V, {width}), got ({}, {})",
                    shape[0], shape[1]
                )));
            }
            if shape[0] != nv {
                return Err(invalid(format!("{name}: {} rows for {nv} vertices", shape[0])));
            }
            let s = a
                .as_slice()
                .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous array")))?;
            Ok(s.to_vec())
        };
        if let Some(u) = uvs {
            let u = rows("uvs", &u, 2)?;
            mesh = mesh
                .with_uvs(u.chunks_exact(2).map(glam::Vec2::from_slice).collect())
                .map_err(|e| invalid(format!("uvs: {e}")))?;
        }
        if let Some(t) = tangents {
            let t = rows("tangents", &t, 4)?;
            mesh = mesh
                .with_tangents(t.chunks_exact(4).map(glam::Vec4::from_slice).collect())
                .map_err(|e| invalid(format!("tangents: {e}")))?;
        }
        Ok(Self::wrap(mesh))
    }

    /// Texture coordinates, float32 (V, 2), or `None` (a copy).
    #[getter]
    fn uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.inner
            .uvs
            .as_deref()
            .map(|u| {
                PyArray1::from_slice(py, bytemuck::cast_slice::<glam::Vec2, f32>(u)).reshape([u.len(), 2])
            })
            .transpose()
    }

    /// Tangents `(t, w)`, float32 (V, 4), or `None` (a copy).
    #[getter]
    fn tangents<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        self.inner
            .tangents
            .as_deref()
            .map(|t| {
                PyArray1::from_slice(py, bytemuck::cast_slice::<glam::Vec4, f32>(t)).reshape([t.len(), 4])
            })
            .transpose()
    }

    /// A copy with MikkTSpace tangents (`brdf_raster::texture::tangents`), unless it has tangents.
    fn with_generated_tangents(&self, py: Python<'_>) -> PyResult<Self> {
        if self.inner.tangents.is_some() {
            return Ok(Self { inner: Arc::clone(&self.inner) });
        }
        let mesh = (*self.inner).clone();
        let mesh = py.detach(|| mesh.with_generated_tangents()).map_err(raster_err)?;
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

    /// Recompute the vertex normals in place with `weighting` ("angle", "area" or "equal"; Theoharis et
    /// al. 2008, eqs. 12.31–12.33).
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

/// Normal of a polygon given by its vertices in order (Theoharis et al. 2008, ch. 12): `method` is
/// "newell" (Newell's method, unnormalised: twice the area vector), "cross" (cross product of the first two
/// edges
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
    if !n.is_finite() {
        // The normal is unnormalised (its length is twice an area): coordinates near 1e19 and beyond
        // square past the float32 range.
        return Err(invalid(
            "points: the unnormalised normal overflows float32 (its length grows as the square of the \
             coordinates); scale the polygon down",
        ));
    }
    Ok(n.to_array())
}

/// Names of the meshes embedded in the library.
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
