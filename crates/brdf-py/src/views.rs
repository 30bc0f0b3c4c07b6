//! `brdfpy.views`: the BRDF Explorer views of `brdf_core::views` as NumPy arrays (and the lit sphere
//! as a frame for `brdfpy.Image`). Angles arrive in radians (the Python wrapper converts the degrees
//! users give); the core checks them and quotes degrees in its errors. Every call runs on the
//! bindings' pool with the GIL released, so `brdfpy.set_num_threads` applies and other Python threads
//! run meanwhile.

use brdf_core::properties::Quadrature;
use brdf_core::tonemap::Operator;
use brdf_core::views::{self, Incidence, albedo, lobe, polar, slice, sphere};
use brdf_raster::Frame;
use brdf_raster::tiles::NO_TRI;
use glam::Vec3;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::run;
use crate::errors::{invalid, to_py};
use crate::models::Model;
use crate::raster::RasterFrame;

fn vec3s<'py>(py: Python<'py>, v: &[Vec3]) -> PyResult<Bound<'py, PyArray2<f32>>> {
    PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(v)).reshape([v.len(), 3])
}

fn count(name: &str, n: i64) -> PyResult<usize> {
    usize::try_from(n).map_err(|_| invalid(format!("{name}: expected a count >= 0, got {n}")))
}

/// The polar slice: signed `θ_o` [rad] (n,), values (n, 3).
type PolarArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f32>>);

/// The θ_h/θ_d image: values (n_d, n_h, 3), valid (n_d, n_h).
type SliceArrays<'py> = (Bound<'py, PyArray3<f32>>, Bound<'py, PyArray2<bool>>);

/// Polar slice: `(theta_o [rad, signed], values (n, 3))` for incidence `(theta_i, phi)` [rad].
#[pyfunction]
#[pyo3(signature = (model, theta_i, phi, n, cosine))]
pub fn view_polar<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    theta_i: f64,
    phi: f64,
    n: i64,
    cosine: bool,
) -> PyResult<PolarArrays<'py>> {
    let inc = Incidence::new(theta_i, phi).map_err(to_py)?;
    let (m, n) = (model.get().core(), count("n", n)?);
    let p = run(py, usize::MAX, || polar::polar(m, inc, n, cosine))?.map_err(to_py)?;
    Ok((PyArray1::from_vec(py, p.theta_o), vec3s(py, &p.values)?))
}

/// The lobe mesh pieces as a tuple: vertices (V, 3), faces (F, 3) uint32, directions (V, 3), values
/// (V, 3), radius (V,).
type LobeArrays<'py> = (
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray2<u32>>,
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray1<f32>>,
);

/// 3D lobe for incidence `(theta_i, phi)` [rad]: see [`LobeArrays`]. `radius` is `"f"` or `"f_cos"`,
/// `channel` one of `"luminance"`, `"r"`, `"g"`, `"b"`.
#[pyfunction]
#[pyo3(signature = (model, theta_i, phi, n_theta, n_phi, radius, channel))]
pub fn view_lobe<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    theta_i: f64,
    phi: f64,
    n_theta: i64,
    n_phi: i64,
    radius: &str,
    channel: &str,
) -> PyResult<LobeArrays<'py>> {
    let inc = Incidence::new(theta_i, phi).map_err(to_py)?;
    let radius = match radius {
        "f" => lobe::Radius::Brdf,
        "f_cos" => lobe::Radius::BrdfCos,
        other => return Err(invalid(format!("radius: expected \"f\" or \"f_cos\", got {other:?}"))),
    };
    let channel = match channel {
        "luminance" => lobe::Channel::Luminance,
        "r" => lobe::Channel::Red,
        "g" => lobe::Channel::Green,
        "b" => lobe::Channel::Blue,
        other => {
            return Err(invalid(format!(
                "channel: expected \"luminance\", \"r\", \"g\" or \"b\", got {other:?}"
            )));
        }
    };
    let (m, nt, np) = (model.get().core(), count("n_theta", n_theta)?, count("n_phi", n_phi)?);
    let l = run(py, usize::MAX, || lobe::lobe(m, inc, nt, np, radius, channel))?.map_err(to_py)?;
    let faces: &[u32] = bytemuck::cast_slice(&l.faces);
    Ok((
        vec3s(py, &l.vertices)?,
        PyArray1::from_slice(py, faces).reshape([l.faces.len(), 3])?,
        vec3s(py, &l.directions)?,
        vec3s(py, &l.values)?,
        PyArray1::from_vec(py, l.radius),
    ))
}

/// θ_h/θ_d image at `phi_d` [rad]: `(values (n_d, n_h, 3), valid (n_d, n_h))`, row `i` at θ_d cell `i`.
#[pyfunction]
#[pyo3(signature = (model, phi_d, n_h, n_d))]
pub fn view_half_diff_slice<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    phi_d: f64,
    n_h: i64,
    n_d: i64,
) -> PyResult<SliceArrays<'py>> {
    let (m, nh, nd) = (model.get().core(), count("n_theta_h", n_h)?, count("n_theta_d", n_d)?);
    let s = run(py, usize::MAX, || slice::half_diff_slice(m, phi_d, nh, nd))?.map_err(to_py)?;
    let values =
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(&s.values)).reshape([nd, nh, 3])?;
    let valid = PyArray1::from_vec(py, s.valid).reshape([nd, nh])?;
    Ok((values, valid))
}

/// `E(θ_i)` per channel, (K, 3), at the angles `theta_i` [rad] (a flat float64 array).
#[pyfunction]
#[pyo3(signature = (model, theta_i, theta_order=4, phi_order=4, min_panel=1e-3))]
pub fn view_albedo<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    theta_i: PyReadonlyArrayDyn<'py, f64>,
    theta_order: i64,
    phi_order: i64,
    min_panel: f64,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let t = theta_i.as_slice().map_err(|_| invalid("theta_i: expected a C-contiguous float64 array"))?;
    if t.is_empty() {
        return Err(invalid("theta_i: is empty"));
    }
    let q = Quadrature {
        theta_order: count("theta_order", theta_order)?,
        phi_order: count("phi_order", phi_order)?,
        min_panel,
    };
    let m = model.get().core();
    let e = run(py, usize::MAX, || albedo::albedo_curve(m, t, &q))?.map_err(to_py)?;
    vec3s(py, &e)
}

/// The lit sphere as a frame: `size` pixels, light direction (view space), sky radiance, samples per
/// axis, tangent-field axis, background (linear RGB), and the frame's tone map (name, exposure in stops,
/// white point for `reinhard_extended`; `None`: the sphere's largest value, at least 1).
#[pyfunction]
#[pyo3(signature = (model, size, light, ambient, samples, tangent_axis, background, tonemap, exposure, white=None))]
pub fn view_lit_sphere(
    py: Python<'_>,
    model: &Bound<'_, Model>,
    size: i64,
    light: [f32; 3],
    ambient: f32,
    samples: i64,
    tangent_axis: [f32; 3],
    background: [f32; 3],
    tonemap: &str,
    exposure: f32,
    white: Option<f32>,
) -> PyResult<RasterFrame> {
    if !Operator::NAMES.contains(&tonemap.to_ascii_lowercase().as_str()) {
        return Err(invalid(format!(
            "tonemap: expected one of {}, got {tonemap:?}",
            Operator::NAMES.join(", ")
        )));
    }
    if !exposure.is_finite() {
        return Err(invalid(format!("exposure: must be finite, got {exposure}")));
    }
    let opts = sphere::SphereOptions {
        size: count("size", size)?,
        light: Vec3::from(light),
        ambient,
        samples: count("samples", samples)?,
        tangent_axis: Vec3::from(tangent_axis),
        background: Vec3::from(background),
    };
    let m = model.get().core();
    let img = run(py, usize::MAX, || sphere::lit_sphere(m, &opts))?.map_err(to_py)?;
    // The automatic white point: the brightest channel on the sphere (the peak of a highlight maps to
    // white, the rest keeps its gradient), never below 1 (a sphere within [0, 1] is shown unchanged:
    // the extended operator with white 1 is the identity there).
    let white = match white {
        Some(w) => w,
        None => img
            .hdr
            .iter()
            .zip(&img.covered)
            .filter(|(_, c)| **c)
            .fold(1.0f32, |w, (c, _)| w.max(c.max_element() * exposure.exp2())),
    };
    let op = Operator::from_name(tonemap, Some(white)).map_err(to_py)?;
    let size = img.size as u32;
    let frame = Frame {
        width: size,
        height: size,
        triangle_id: img.covered.iter().map(|&c| if c { 0 } else { NO_TRI }).collect(),
        hdr: img.hdr,
        depth: img.depth,
        normal: img.normal,
        tonemap: op,
        exposure,
        rgb8: Vec::new(),
    };
    Ok(RasterFrame::from_frame(frame))
}

/// The cell-centre angles [rad] of an axis of `n` cells over `[0, π/2]` (the slice's θ_h and θ_d).
#[pyfunction]
pub fn view_cell_angles<'py>(py: Python<'py>, n: i64) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let n = count("n", n)?;
    Ok(PyArray1::from_vec(py, slice::cell_angles(n.min(views::MAX_SAMPLES))))
}

/// `(theta_order, phi_order, min_panel)` of the views' albedo quadrature.
#[pyfunction]
pub fn view_quadrature() -> (usize, usize, f64) {
    let q = albedo::VIEW_QUADRATURE;
    (q.theta_order, q.phi_order, q.min_panel)
}
