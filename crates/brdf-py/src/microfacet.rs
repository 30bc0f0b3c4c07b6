//! `brdfpy.microfacet`: microfacet distributions D [1/sr], Smith Λ and G1, and shadowing-masking terms G
//! over batches of directions. Thin loops over `brdf_core::microfacet` and `brdf_core::masking`. Every
//! function takes the distribution as a list of lobes `(weight, name, alpha, alpha_y)` (one lobe of
//! weight 1 for a plain distribution; several for a mixture, seed 001 "BRDF – mixture").

use brdf_core::ShadingFrame;
use brdf_core::masking::Masking;
use brdf_core::microfacet::{Distribution, Mixture};
use brdf_core::vector::normalize_or_zero;
use glam::{Vec3, Vec3A};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::arrays::{at, broadcast_len, check_vec3, part, vec3_view};
use crate::errors::{invalid, to_py};
use crate::threads::{RowError, fill};

/// One lobe as Python passes it: (weight, distribution name, alpha, alpha_y).
pub type Lobe = (f32, String, f32, Option<f32>);

pub fn mixture(lobes: &[Lobe]) -> PyResult<Mixture> {
    if lobes.is_empty() {
        return Err(invalid("lobes: expected at least one (weight, name, alpha) lobe"));
    }
    let built = lobes
        .iter()
        .map(|(w, name, a, ay)| Ok((*w, Distribution::from_name(name, *a, *ay).map_err(to_py)?)))
        .collect::<PyResult<Vec<_>>>()?;
    Mixture::new(&built).map_err(to_py)
}

/// The local frame at a sample: from the normal and, when given and not degenerate, the tangent.
#[inline]
fn frame(n: Vec3A, t: Option<Vec3>) -> ShadingFrame {
    match t.map(|t| normalize_or_zero(t.into())) {
        Some(t) if t != Vec3A::ZERO && t.cross(n).length_squared() > 1e-12 => {
            ShadingFrame::from_normal_tangent(n, t)
        }
        _ => ShadingFrame::from_normal(n),
    }
}

/// `out[i] = f(dirs[0][i], …)` (unit-normalised; 0 when any is zero-length) over broadcast `(k, 3)` inputs,
/// plus an optional tangent, into a float32 `(N,)` array.
fn map_dirs<'py>(
    py: Python<'py>,
    dirs: &[(&'static str, &[Vec3])],
    tangent: Option<&[Vec3]>,
    f: impl Fn(&[Vec3A; 3], Option<Vec3>) -> f32 + Send + Sync,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let mut lens: Vec<(&str, usize)> = dirs.iter().map(|(n, s)| (*n, s.len())).collect();
    if let Some(t) = tangent {
        lens.push(("tangent", t.len()));
    }
    let len = broadcast_len(&lens)?;
    let mut all: Vec<(&'static str, &[Vec3])> = dirs.to_vec();
    if let Some(t) = tangent {
        all.push(("tangent", t));
    }
    for (name, s) in &all {
        if s.len() == 1 {
            check_vec3(name, s, 0).map_err(RowError::into_py)?;
        }
    }
    let out = PyArray1::<f32>::zeros(py, [len], false);
    {
        let mut w = out.readwrite();
        let o = w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        fill(py, o, |offset, chunk| {
            let k = chunk.len();
            for (name, s) in &all {
                if s.len() > 1 {
                    check_vec3(name, part(s, offset, k), offset)?;
                }
            }
            for (i, o) in chunk.iter_mut().enumerate() {
                let mut w = [Vec3A::ZERO; 3];
                for (j, (_, s)) in dirs.iter().enumerate() {
                    w[j] = normalize_or_zero(at(s, offset + i).into());
                }
                let degenerate = w[..dirs.len()].contains(&Vec3A::ZERO);
                *o = if degenerate { 0.0 } else { f(&w, tangent.map(|t| at(t, offset + i))) };
            }
            Ok(())
        })?;
    }
    Ok(out)
}

/// `D(h)` [1/sr] of a (mixture of) distribution(s), for half vectors `h` around normals `n`.
#[pyfunction]
#[pyo3(signature = (lobes, h, n, tangent=None))]
pub fn distribution<'py>(
    py: Python<'py>,
    lobes: Vec<Lobe>,
    h: PyReadonlyArray2<'py, f32>,
    n: PyReadonlyArray2<'py, f32>,
    tangent: Option<PyReadonlyArray2<'py, f32>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let d = mixture(&lobes)?;
    let (hs, ns) = (vec3_view("h", &h)?, vec3_view("n", &n)?);
    let ts = tangent.as_ref().map(|t| vec3_view("tangent", t)).transpose()?;
    map_dirs(py, &[("h", hs), ("n", ns)], ts, |w, t| {
        let local = frame(w[1], t).to_local(w[0]);
        if local.z > 0.0 { d.d(local) } else { 0.0 }
    })
}

/// Smith `Λ(w)` (or `G1 = 1/(1 + Λ)` when `g1`) for directions `w` around normals `n`; `Λ = +inf`, `G1 = 0`
/// below the surface.
#[pyfunction]
#[pyo3(signature = (lobes, w, n, tangent=None, g1=false))]
pub fn smith_lambda<'py>(
    py: Python<'py>,
    lobes: Vec<Lobe>,
    w: PyReadonlyArray2<'py, f32>,
    n: PyReadonlyArray2<'py, f32>,
    tangent: Option<PyReadonlyArray2<'py, f32>>,
    g1: bool,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let d = mixture(&lobes)?;
    let (ws, ns) = (vec3_view("w", &w)?, vec3_view("n", &n)?);
    let ts = tangent.as_ref().map(|t| vec3_view("tangent", t)).transpose()?;
    map_dirs(py, &[("w", ws), ("n", ns)], ts, |x, t| {
        let local = frame(x[1], t).to_local(x[0]);
        if local.z <= 0.0 {
            return if g1 { 0.0 } else { f32::INFINITY };
        }
        let lambda = d.lambda(local);
        if g1 { 1.0 / (1.0 + lambda) } else { lambda }
    })
}

/// Shadowing-masking `G(l, v)` (dimensionless) of the named term for a (mixture of) distribution(s).
#[pyfunction]
#[pyo3(signature = (name, lobes, l, v, n, tangent=None))]
pub fn masking<'py>(
    py: Python<'py>,
    name: &str,
    lobes: Vec<Lobe>,
    l: PyReadonlyArray2<'py, f32>,
    v: PyReadonlyArray2<'py, f32>,
    n: PyReadonlyArray2<'py, f32>,
    tangent: Option<PyReadonlyArray2<'py, f32>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let g = Masking::from_name(name).map_err(to_py)?;
    let d = mixture(&lobes)?;
    let (ls, vs, ns) = (vec3_view("l", &l)?, vec3_view("v", &v)?, vec3_view("n", &n)?);
    let ts = tangent.as_ref().map(|t| vec3_view("tangent", t)).transpose()?;
    map_dirs(py, &[("l", ls), ("v", vs), ("n", ns)], ts, |w, t| {
        let tangent = t
            .map(|t| normalize_or_zero(t.into()))
            .filter(|t| *t != Vec3A::ZERO && t.cross(w[2]).length_squared() > 1e-12);
        g.g_world(w[0], w[1], w[2], tangent, &d)
    })
}

/// Names of the distributions and of the masking terms.
#[pyfunction]
pub fn microfacet_names() -> (Vec<&'static str>, Vec<&'static str>) {
    (brdf_core::microfacet::DISTRIBUTION_NAMES.to_vec(), brdf_core::masking::MASKING_NAMES.to_vec())
}
