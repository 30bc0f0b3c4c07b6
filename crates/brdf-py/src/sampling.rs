//! Importance sampling from Python: `Model.sample` / `Model.pdf` over NumPy arrays (GIL released, the
//! pool's threads, results independent of the thread count), the counter-based uniform numbers, and the
//! primitives of `brdfpy.checks.chi2` / `pdf_integral`. Thin wrappers over `brdf_core::sampling`.

use brdf_core::batch::{Shape, for_each_chunk};
use brdf_core::sampling::MAX_SAMPLES;
use brdf_core::sampling::batch::{PdfBatch, SampleBatch};
use brdf_core::sampling::chi2::{self, Chi2Grid};
use glam::{Vec3, Vec3A};
use numpy::{
    PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::{outputs, run, vec3, vec3_opt, vec3_view};
use crate::errors::{invalid, to_py};
use crate::models::Model;

/// A C-contiguous float32 array of any shape as a flat slice.
fn flat_view<'a>(name: &str, a: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<&'a [f32]> {
    a.as_slice().map_err(|_| invalid(format!("{name}: expected a C-contiguous float32 array")))
}

/// Draw `(l, weight, pdf)`, float32 arrays of shapes `S + (3,)`, `S + (3,)`, `S`, where `S` is the
/// broadcast shape of `v`, `n` (`tangent`, `u`) without their last axis of 3 (and `(count,)` when given).
/// Without `u`, element `i` (C order) uses the counter-based numbers of `seed` and `i`.
#[pyfunction]
#[pyo3(signature = (model, v, n, u=None, seed=0, tangent=None, count=None))]
#[allow(clippy::type_complexity)]
pub fn model_sample<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    v: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
    u: Option<PyReadonlyArrayDyn<'py, f32>>,
    seed: u64,
    tangent: Option<PyReadonlyArrayDyn<'py, f32>>,
    count: Option<i64>,
) -> PyResult<(Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>)> {
    let count = match count {
        None => None,
        Some(c) if (1..=MAX_SAMPLES).contains(&c) => Some(c as usize),
        Some(c) => return Err(invalid(format!("count: expected an integer in [1, {MAX_SAMPLES}], got {c}"))),
    };
    let batch = SampleBatch::new(
        vec3("v", &v)?,
        vec3("n", &n)?,
        vec3_opt("tangent", &tangent)?,
        vec3_opt("u", &u)?,
        seed,
        count,
    )
    .map_err(to_py)?;
    let m = model.get().core();
    let sampler = m.sampler().map_err(to_py)?;
    outputs::<(Vec3, Vec3, f32)>(py, batch.shape(), |(l, w, p)| batch.run(m, &sampler, l, w, p))
}

/// The density \[1/sr\] with which `Model.sample` draws `l`, float32 of the broadcast shape.
#[pyfunction]
#[pyo3(signature = (model, l, v, n, tangent=None))]
pub fn model_pdf<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    l: PyReadonlyArrayDyn<'py, f32>,
    v: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
    tangent: Option<PyReadonlyArrayDyn<'py, f32>>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let batch = PdfBatch::new(vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, vec3_opt("tangent", &tangent)?)
        .map_err(to_py)?;
    let sampler = model.get().core().sampler().map_err(to_py)?;
    outputs::<f32>(py, batch.shape(), |out| batch.run(&sampler, out))
}

/// The counter-based uniform numbers of `Model.sample`: row `i` of the `(count, 3)` result is what a
/// sample without `u` uses for output element `i` and `seed`.
#[pyfunction]
#[pyo3(signature = (count, seed=0))]
pub fn uniform<'py>(py: Python<'py>, count: i64, seed: u64) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    if !(1..=MAX_SAMPLES).contains(&count) {
        return Err(invalid(format!("count: expected an integer in [1, {MAX_SAMPLES}], got {count}")));
    }
    let key = brdf_core::sampling::rng::key(seed);
    outputs::<Vec3>(py, &Shape::rows(count as usize), |out| {
        for_each_chunk(out, |offset, chunk: &mut [Vec3]| {
            for (k, r) in chunk.iter_mut().enumerate() {
                let row = (offset + k) as u64;
                *r = Vec3::from_array(std::array::from_fn(|d| {
                    brdf_core::sampling::rng::uniform_keyed(key, row, d as u64)
                }));
            }
        });
        Ok(())
    })
}

fn one_vec3(name: &'static str, a: &PyReadonlyArray1<'_, f32>) -> PyResult<Vec3> {
    let s = a.as_slice().map_err(|_| invalid(format!("{name}: expected a contiguous float32 array")))?;
    match s {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(invalid(format!("{name}: expected 3 finite numbers, got {s:?}"))),
    }
}

/// The χ² test of `brdfpy.checks.chi2`: bins the valid sample directions `l` (`(K, 3)`) of `count`
/// samples, integrates the density `pdf(points) -> (P,)` over the cells, and compares (see
/// `brdf_core::sampling::chi2`). Returns a dict.
#[pyfunction]
#[pyo3(signature = (l, count, pdf, n, peak, tangent=None, n_theta=64, n_phi=128, zoom=1.0, ires=6))]
#[allow(clippy::too_many_arguments)]
pub fn chi2_test<'py>(
    py: Python<'py>,
    l: PyReadonlyArray2<'py, f32>,
    count: i64,
    pdf: &Bound<'py, PyAny>,
    n: PyReadonlyArray1<'py, f32>,
    peak: PyReadonlyArray1<'py, f32>,
    tangent: Option<PyReadonlyArray1<'py, f32>>,
    n_theta: usize,
    n_phi: usize,
    zoom: f64,
    ires: usize,
) -> PyResult<Bound<'py, PyDict>> {
    if count < 1 {
        return Err(invalid(format!("sample_count: expected an integer >= 1, got {count}")));
    }
    let (n, peak) = (one_vec3("n", &n)?, one_vec3("peak", &peak)?);
    let tangent = tangent.as_ref().map(|t| one_vec3("tangent", t)).transpose()?;
    let grid = Chi2Grid::new(n, tangent, peak, n_theta, n_phi, zoom).map_err(to_py)?;
    let dirs: &[Vec3] = if l.shape()[0] == 0 { &[] } else { vec3_view("l", &l)? };
    let (points, weights) = grid.quadrature(ires).map_err(to_py)?;
    let observed = run(py, dirs.len(), || grid.histogram(dirs.iter().copied()))?;
    let flat: &[f32] = bytemuck::cast_slice(&points);
    let arr = PyArray1::from_slice(py, flat).reshape([points.len(), 3])?;
    let values = pdf.call1((arr,))?;
    let values: PyReadonlyArrayDyn<'py, f32> = values
        .extract()
        .map_err(|_| invalid("pdf: must return a float32 array of one density per direction".to_string()))?;
    let vals = flat_view("pdf", &values)?;
    if vals.len() != points.len() {
        return Err(invalid(format!("pdf: returned {} values for {} directions", vals.len(), points.len())));
    }
    let expected = grid.expected(vals, &weights, count as f64);
    let r = chi2::evaluate(observed, expected, count as f64);
    let d = PyDict::new(py);
    d.set_item("statistic", r.statistic)?;
    d.set_item("dof", r.dof)?;
    d.set_item("p_value", r.p_value)?;
    d.set_item("pooled_cells", r.pooled.0)?;
    d.set_item("pooled_groups", r.pooled.1)?;
    d.set_item("sample_fraction", r.sample_fraction)?;
    d.set_item("pdf_integral", r.pdf_integral)?;
    d.set_item("problems", PyList::new(py, &r.problems)?)?;
    d.set_item("observed", PyArray1::from_slice(py, &r.observed))?;
    d.set_item("expected", PyArray1::from_slice(py, &r.expected))?;
    Ok(d)
}

/// `∫_{H²} pdf(l, v) dω_l` at each view cosine (`v = (sin θ_v, 0, cos θ_v)`, `n = z`, tangent `x`), by
/// the graded quadrature of the checks.
#[pyfunction]
#[pyo3(signature = (model, cos_theta_v, theta_order=16, phi_order=16, min_panel=1e-4))]
pub fn pdf_integral<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    cos_theta_v: PyReadonlyArrayDyn<'py, f32>,
    theta_order: i64,
    phi_order: i64,
    min_panel: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let cs = flat_view("cos_theta_v", &cos_theta_v)?;
    if cs.is_empty() {
        return Err(invalid("cos_theta_v: is empty"));
    }
    if let Some(i) = cs.iter().position(|c| !(*c > 0.0 && *c <= 1.0)) {
        return Err(invalid(format!("cos_theta_v: values must lie in (0, 1], got {} at index {i}", cs[i])));
    }
    let q = crate::checks::quadrature(theta_order, phi_order, min_panel)?;
    let sampler = model.get().core().sampler().map_err(to_py)?;
    let out = run(py, usize::MAX, || {
        cs.iter()
            .map(|&c| {
                let v = Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
                let peak = Vec3A::new(-v.x, 0.0, v.z);
                brdf_core::properties::hemisphere_integral(
                    |l| f64::from(sampler.pdf(l.into(), v, Vec3::Z, Some(Vec3::X))),
                    Some(peak),
                    &q,
                )
            })
            .collect::<Result<Vec<f64>, _>>()
    })?
    .map_err(to_py)?;
    Ok(PyArray1::from_vec(py, out))
}
