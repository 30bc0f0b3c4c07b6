//! The rasterizer from Python: meshes, cameras, lights, and one `render_scene` call that builds a
//! `brdf_raster::Scene` under the GIL and renders it with the GIL released, on the bindings' pool.
//!
//! The Python package (`brdfpy/scene.py`, `mesh.py`, `camera.py`, `lights.py`, `image.py`) wraps these
//! classes: it converts array-likes to C-contiguous float32/uint32, converts degrees to radians and
//! keeps the scene itself as plain Python lists, so that a scene is easy to inspect and edit. Every
//! input is checked here again, naming the argument, so that a direct call cannot misbehave either.
//!
//! Files: `mesh.rs` (meshes, loaders, procedural and built-in meshes), `camera.rs`, `lights.rs`,
//! `environment.rs` (environment maps), `render.rs` (frames and `render_scene`), `assets.rs` (glTF
//! scenes and OBJ files with their MTL materials).

mod assets;
mod camera;
mod environment;
mod lights;
mod mesh;
mod render;
mod texture;

use glam::{Mat4, Vec3};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use brdf_raster::RasterError;

use crate::errors::{invalid, to_py};

pub use assets::{load_gltf, load_gltf_bytes, load_obj_scene};
pub use camera::RasterCamera;
pub use environment::RasterEnvironment;
pub use lights::{RasterAreaLight, RasterLight};
pub use mesh::{
    RasterMesh, builtin_mesh, builtin_mesh_names, cube, icosphere, load_mesh, load_mesh_bytes, open_box,
    plane, polygon_normal, torus,
};
pub use render::{RasterFrame, occlusion_cache_info, raster_limits, render_scene};
pub use texture::RasterTexture;

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

pub(super) fn mat4_from_rows(name: &str, a: [f32; 16]) -> PyResult<Mat4> {
    if a.iter().any(|x| !x.is_finite()) {
        return Err(invalid(format!("{name}: must be finite")));
    }
    // Python gives row-major (the printed matrix, column vectors: p' = M @ p); glam is column-major.
    Ok(Mat4::from_cols_array(&a).transpose())
}

pub(super) fn rows_of(m: Mat4) -> [[f32; 4]; 4] {
    m.transpose().to_cols_array_2d()
}
