//! Rebuilding the rasterizer's objects from their stored fields, for pickling (`brdfpy.distributed` sends
//! meshes, lights and images to other processes).
//!
//! Why not through the ordinary constructors: they normalise what they are given (mesh normals, light
//! directions), and normalising a vector that is already unit length in float32 can move its last bit,
//! so a pickled scene would render a slightly different image. These functions take the stored values
//! exactly as the getters return them, check them as strictly as the constructors do (a pickle is input
//! like any other), and build the object with those bits. The Python wrappers' `__reduce__` call them.

use std::sync::Arc;

use brdf_core::lights::Light;
use brdf_core::tonemap::Operator;
use brdf_raster::{Frame, Mesh};
use glam::Vec3;
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::errors::{invalid, to_py};
use crate::raster::{RasterFrame, RasterLight, RasterMesh, raster_err};

/// Largest distance from 1 of the length of a stored unit direction: what normalising in float32 leaves
/// (a few ulp); anything farther is not a stored direction and is refused rather than silently kept.
const UNIT_TOLERANCE: f32 = 1e-5;

fn rows(name: &str, a: &PyReadonlyArray2<'_, f32>) -> PyResult<Vec<Vec3>> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(invalid(format!("{name}: expected shape (N, 3), got ({}, {})", shape[0], shape[1])));
    }
    let s =
        a.as_slice().map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous array")))?;
    Ok(s.chunks_exact(3).map(Vec3::from_slice).collect())
}

fn is_unit(d: Vec3) -> bool {
    d.is_finite() && (d.length() - 1.0).abs() <= UNIT_TOLERANCE
}

/// A mesh with exactly these positions, faces, unit normals and colours (`RasterMesh`'s getters): checked
/// like `RasterMesh(...)` (shapes, indices, finite values), but the normals are kept bit for bit instead
/// of being normalised again.
#[pyfunction]
#[pyo3(signature = (vertices, faces, normals, colors=None))]
pub fn _mesh_from_parts(
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
    normals: PyReadonlyArray2<'_, f32>,
    colors: Option<PyReadonlyArray2<'_, f32>>,
) -> PyResult<RasterMesh> {
    let positions = rows("vertices", &vertices)?;
    if faces.shape()[1] != 3 {
        return Err(invalid(format!("faces: expected shape (F, 3), got {:?}", faces.shape())));
    }
    let fs = faces.as_slice().map_err(|_| PyTypeError::new_err("faces: expected a C-contiguous array"))?;
    let indices: Vec<[u32; 3]> = fs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let stored = rows("normals", &normals)?;
    // Unit, or zero (a vertex no face with an area uses has no normal).
    if let Some(i) = stored.iter().position(|&n| !(is_unit(n) || n == Vec3::ZERO)) {
        return Err(invalid(format!("normals: row {i} is neither a unit vector nor zero: {}", stored[i])));
    }
    // Mesh::new checks positions, faces and the normals' count; then the stored normals replace the
    // re-normalised ones.
    let mut mesh = Mesh::new(positions, indices, Some(stored.clone())).map_err(raster_err)?;
    mesh.normals = stored;
    if let Some(c) = colors {
        mesh = mesh.with_colors(rows("colors", &c)?).map_err(raster_err)?;
    }
    Ok(RasterMesh { inner: Arc::new(mesh) })
}

/// `light` with its direction replaced by `direction`, the stored unit direction of the light pickled
/// (`fields()["direction"]`); for directional and spot lights (a point light has none).
#[pyfunction]
pub fn _light_with_direction(light: PyRef<'_, RasterLight>, direction: [f32; 3]) -> PyResult<RasterLight> {
    let d = Vec3::from_array(direction);
    if !is_unit(d) {
        return Err(invalid(format!("direction: expected a stored unit vector, got {d}")));
    }
    let inner = match light.inner {
        Light::Directional { color, .. } => Light::Directional { direction: d, color },
        Light::Spot { position, intensity, inner_angle, outer_angle, attenuation, .. } => {
            Light::Spot { position, direction: d, intensity, inner_angle, outer_angle, attenuation }
        }
        Light::Point { .. } => return Err(invalid("direction: a point light has no direction")),
    };
    Ok(RasterLight { inner })
}

/// What `_frame_from_state` takes: `(width, height, hdr, depth, normal, triangle_id, rgb8, tonemap,
/// white, exposure)`, buffers as flat arrays (empty when the render did not write them).
type FrameState<'py> = (
    u32,
    u32,
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<f32>>,
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<u8>>,
    &'static str,
    Option<f32>,
    f32,
);

/// Every field of a frame (see [`FrameState`]), copied into flat NumPy arrays.
#[pyfunction]
pub fn _frame_state<'py>(py: Python<'py>, frame: PyRef<'py, RasterFrame>) -> FrameState<'py> {
    let f = &frame.inner;
    let white = match f.tonemap {
        Operator::ReinhardExtended { white } => Some(white),
        _ => None,
    };
    (
        f.width,
        f.height,
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&f.hdr)),
        PyArray1::from_slice(py, &f.depth),
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&f.normal)),
        PyArray1::from_slice(py, &f.triangle_id),
        PyArray1::from_slice(py, &f.rgb8),
        f.tonemap.name(),
        white,
        f.exposure,
    )
}

fn buffer<T: Copy + bytemuck::Pod + numpy::Element>(
    name: &str,
    a: &PyReadonlyArray1<'_, T>,
    expected: usize,
) -> PyResult<Vec<T>> {
    let s = a.as_slice().map_err(|_| PyTypeError::new_err(format!("{name}: expected a contiguous array")))?;
    if !s.is_empty() && s.len() != expected {
        return Err(invalid(format!("{name}: expected 0 or {expected} values, got {}", s.len())));
    }
    Ok(s.to_vec())
}

/// A frame with exactly the fields of `_frame_state` (sizes and lengths checked).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn _frame_from_state(
    width: u32,
    height: u32,
    hdr: PyReadonlyArray1<'_, f32>,
    depth: PyReadonlyArray1<'_, f32>,
    normal: PyReadonlyArray1<'_, f32>,
    triangle_id: PyReadonlyArray1<'_, u32>,
    rgb8: PyReadonlyArray1<'_, u8>,
    tonemap: &str,
    white: Option<f32>,
    exposure: f32,
) -> PyResult<RasterFrame> {
    let n =
        (width as usize).checked_mul(height as usize).ok_or_else(|| invalid("width, height: too large"))?;
    if !exposure.is_finite() {
        return Err(invalid(format!("exposure: must be finite, got {exposure}")));
    }
    let hdr: Vec<f32> = buffer("hdr", &hdr, 3 * n)?;
    let normal: Vec<f32> = buffer("normal", &normal, 3 * n)?;
    let frame = Frame {
        width,
        height,
        hdr: bytemuck::cast_slice::<f32, Vec3>(&hdr).to_vec(),
        depth: buffer("depth", &depth, n)?,
        normal: bytemuck::cast_slice::<f32, Vec3>(&normal).to_vec(),
        triangle_id: buffer("triangle_id", &triangle_id, n)?,
        tonemap: Operator::from_name(tonemap, white).map_err(to_py)?,
        exposure,
        rgb8: buffer("rgb8", &rgb8, 3 * n)?,
    };
    Ok(RasterFrame::from_frame(frame))
}
