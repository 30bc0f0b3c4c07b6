//! `brdfpy.checks`: the BRDF properties of SPEC row 19 as functions a user can call on any model
//! (positivity, Helmholtz reciprocity, directional albedo by quadrature, a summary). Thin wrappers over
//! `brdf_core::properties`, which is deterministic for any thread count.

use brdf_core::properties::{self as props, Quadrature};
use numpy::{PyArray2, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{run, scalars};
use crate::errors::{invalid, to_py};
use crate::models::Model;

/// The largest number of random configurations a check accepts (about a minute of work).
pub const MAX_SAMPLES: i64 = 100_000_000;

fn sample_count(samples: i64) -> PyResult<usize> {
    if (1..=MAX_SAMPLES).contains(&samples) {
        Ok(samples as usize)
    } else {
        Err(invalid(format!("samples: expected an integer in [1, {MAX_SAMPLES}], got {samples}")))
    }
}

fn seed(s: i64) -> PyResult<u64> {
    u64::try_from(s).map_err(|_| invalid(format!("seed: expected an integer >= 0, got {s}")))
}

/// Smallest channel of `f_r` over `samples` random configurations (seeded): ≥ 0 for a valid BRDF; NaN if
/// the model returned a non-finite value.
#[pyfunction]
#[pyo3(signature = (model, samples=10_000, seed=0))]
pub fn positivity(py: Python<'_>, model: &Bound<'_, Model>, samples: i64, seed: i64) -> PyResult<f32> {
    let (n, s, m) = (sample_count(samples)?, self::seed(seed)?, model.get().core());
    run(py, n, || props::positivity(m, n, s))
}

/// `max |f(l,v) − f(v,l)| / max(|f(l,v)|, |f(v,l)|, 1e-6)` over `samples` random configurations
/// (seeded).
#[pyfunction]
#[pyo3(signature = (model, samples=10_000, seed=0))]
pub fn reciprocity_error(py: Python<'_>, model: &Bound<'_, Model>, samples: i64, seed: i64) -> PyResult<f32> {
    let (n, s, m) = (sample_count(samples)?, self::seed(seed)?, model.get().core());
    run(py, n, || props::reciprocity_error(m, n, s))
}

/// Directional albedo `ρ(v) = ∫ f_r(l, v) cos θ_l dω_l` per channel at each view cosine, `(K, 3)`.
#[pyfunction]
#[pyo3(signature = (model, cos_theta_v, theta_order=8, phi_order=8, min_panel=1e-4))]
pub fn directional_albedo<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    cos_theta_v: PyReadonlyArrayDyn<'py, f32>,
    theta_order: i64,
    phi_order: i64,
    min_panel: f64,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let cs = scalars("cos_theta_v", &cos_theta_v)?.data();
    if let Some(i) = cs.iter().position(|c| !(*c >= 0.0 && *c <= 1.0)) {
        return Err(invalid(format!("cos_theta_v: values must lie in [0, 1], got {} at index {i}", cs[i])));
    }
    let q = quadrature(theta_order, phi_order, min_panel)?;
    let m = model.get().core();
    // Every albedo costs up to ~10^5 evaluations: always worth releasing the GIL.
    let albedo = run(py, usize::MAX, || props::directional_albedos(m, cs, &q))?.map_err(to_py)?;
    let out = PyArray2::<f32>::zeros(py, [albedo.len(), 3], false);
    {
        let mut w = out.readwrite();
        let o = w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        o.copy_from_slice(bytemuck::cast_slice(&albedo));
    }
    Ok(out)
}

/// Normalisation `∫ D(h) (n·h) dω_h` of a (mixture of) microfacet distribution(s) by quadrature; 1 for a
/// normalised D (Walter et al. 2007 eq. 4).
#[pyfunction]
#[pyo3(signature = (lobes, theta_order=8, phi_order=8, min_panel=1e-4))]
pub fn d_normalization(
    py: Python<'_>,
    lobes: Vec<crate::microfacet::Lobe>,
    theta_order: i64,
    phi_order: i64,
    min_panel: f64,
) -> PyResult<f64> {
    let d = crate::microfacet::mixture(&lobes)?;
    let q = quadrature(theta_order, phi_order, min_panel)?;
    run(py, usize::MAX, || props::microfacet_normalization(|h| d.d(h), &q))?.map_err(to_py)
}

pub(crate) fn quadrature(theta_order: i64, phi_order: i64, min_panel: f64) -> PyResult<Quadrature> {
    let order = |name: &str, k: i64| {
        usize::try_from(k).map_err(|_| invalid(format!("{name}: must be in [1, 64], got {k}")))
    };
    let q = Quadrature {
        theta_order: order("n_theta", theta_order)?,
        phi_order: order("n_phi", phi_order)?,
        min_panel,
    };
    q.validate().map_err(to_py)?;
    Ok(q)
}

/// All checks with fixed settings (seed 0, 10 000 configurations, albedo at six view cosines), as a dict.
#[pyfunction]
pub fn check<'py>(py: Python<'py>, model: &Bound<'py, Model>) -> PyResult<Bound<'py, PyDict>> {
    let m = model.get().core();
    let r = run(py, usize::MAX, || props::check(m))?;
    let d = PyDict::new(py);
    d.set_item("model", r.model)?;
    d.set_item("physical", r.physical)?;
    d.set_item("min_value", r.min_value)?;
    d.set_item("reciprocity_error", r.reciprocity_error)?;
    d.set_item("cos_theta_v", r.cos_theta_v)?;
    d.set_item("albedo", r.albedo.iter().map(|a| a.to_array()).collect::<Vec<_>>())?;
    d.set_item("max_albedo", r.max_albedo)?;
    d.set_item("positive", r.positive)?;
    d.set_item("reciprocal", r.reciprocal)?;
    d.set_item("energy_conserving", r.energy_conserving)?;
    Ok(d)
}
