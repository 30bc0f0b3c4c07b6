//! `brdfpy.vectors`: reflect, refract and the half vector over batches, in brdfpy's convention (every
//! direction points away from the surface). Thin loops over `brdf_core::vector`.

use brdf_core::vector::{
    halfway as core_halfway, normalize_or_zero, reflect as core_reflect, refract as core_refract,
};
use glam::{Vec3, Vec3A};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyReadonlyArrayDyn};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::arrays::{at, broadcast_len, check_flat, check_vec3, flat_view, part, vec3_view};
use crate::threads::{RowError, fill};

/// `(t, ok)` of [`refract`].
type Refracted<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray1<bool>>);

/// Check the length-1 (broadcast) inputs once; longer ones are checked chunk by chunk.
fn check_broadcast(inputs: &[(&'static str, &[Vec3])]) -> PyResult<()> {
    for (name, s) in inputs {
        if s.len() == 1 {
            check_vec3(name, s, 0).map_err(RowError::into_py)?;
        }
    }
    Ok(())
}

fn check_parts(inputs: &[(&'static str, &[Vec3])], offset: usize) -> Result<(), RowError> {
    for (name, s) in inputs {
        if s.len() > 1 {
            check_vec3(name, s, offset)?;
        }
    }
    Ok(())
}

/// `out[i] = f(a[i], b[i])` with broadcasting, checks and the pool.
fn map2<'py>(
    py: Python<'py>,
    (an, a): (&'static str, &[Vec3]),
    (bn, b): (&'static str, &[Vec3]),
    f: impl Fn(Vec3A, Vec3A) -> Vec3A + Send + Sync,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let len = broadcast_len(&[(an, a.len()), (bn, b.len())])?;
    check_broadcast(&[(an, a), (bn, b)])?;
    let out = PyArray2::<f32>::zeros(py, [len, 3], false);
    {
        let mut w = out.readwrite();
        let o: &mut [Vec3] =
            bytemuck::cast_slice_mut(w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?);
        fill(py, o, |offset, chunk| {
            let k = chunk.len();
            let (pa, pb) = (part(a, offset, k), part(b, offset, k));
            check_parts(&[(an, pa), (bn, pb)], 0).map_err(|e| RowError { row: e.row + offset, ..e })?;
            for (i, o) in chunk.iter_mut().enumerate() {
                *o = f(at(pa, i).into(), at(pb, i).into()).into();
            }
            Ok(())
        })?;
    }
    Ok(out)
}

/// Mirror `w` about the normal: `r = 2(n̂·w)n̂ − w`, with `n̂ = n/|n|` (seed 003). `w` keeps its length;
/// a zero-length `n` gives 0.
#[pyfunction]
pub fn reflect<'py>(
    py: Python<'py>,
    w: PyReadonlyArray2<'py, f32>,
    n: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let (ws, ns) = (vec3_view("w", &w)?, vec3_view("n", &n)?);
    map2(py, ("w", ws), ("n", ns), |w, n| {
        let n = normalize_or_zero(n);
        if n == Vec3A::ZERO { Vec3A::ZERO } else { core_reflect(w, n) }
    })
}

/// Unit half vector `h = normalize(l̂ + v̂)`; 0 where `l̂ = −v̂` or an input has zero length.
#[pyfunction]
pub fn halfway<'py>(
    py: Python<'py>,
    l: PyReadonlyArray2<'py, f32>,
    v: PyReadonlyArray2<'py, f32>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let (ls, vs) = (vec3_view("l", &l)?, vec3_view("v", &v)?);
    map2(py, ("l", ls), ("v", vs), |l, v| {
        let (l, v) = (normalize_or_zero(l), normalize_or_zero(v));
        if l == Vec3A::ZERO || v == Vec3A::ZERO {
            Vec3A::ZERO
        } else {
            core_halfway(l, v).unwrap_or(Vec3A::ZERO)
        }
    })
}

/// Refracted direction by Snell's law (`η_i sin θ_i = η_t sin θ_t`, `eta = η_t/η_i`; seed 001): `w` and
/// `n` are normalised, `w` on the side `n` points to; the result points away on the other side. Returns
/// `(t, ok)`: `ok` is false (and `t` is 0) on total internal reflection, when `w` is below the surface or
/// an input has zero length.
#[pyfunction]
pub fn refract<'py>(
    py: Python<'py>,
    w: PyReadonlyArray2<'py, f32>,
    n: PyReadonlyArray2<'py, f32>,
    eta: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Refracted<'py>> {
    let (ws, ns, es) = (vec3_view("w", &w)?, vec3_view("n", &n)?, flat_view("eta", &eta)?);
    if es.is_empty() {
        return Err(crate::errors::invalid("eta: is empty"));
    }
    if let Some(i) = es.iter().position(|&e| !(e > 0.0) || !e.is_finite()) {
        return Err(crate::errors::invalid(format!(
            "eta: must be finite and > 0, got {} at index {i}",
            es[i]
        )));
    }
    let len = broadcast_len(&[("w", ws.len()), ("n", ns.len()), ("eta", es.len())])?;
    check_broadcast(&[("w", ws), ("n", ns)])?;
    let out = PyArray2::<f32>::zeros(py, [len, 3], false);
    let ok = PyArray1::<bool>::zeros(py, [len], false);
    {
        let mut w = out.readwrite();
        let o: &mut [Vec3] =
            bytemuck::cast_slice_mut(w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?);
        fill(py, o, |offset, chunk| {
            let k = chunk.len();
            let (pw, pn) = (part(ws, offset, k), part(ns, offset, k));
            check_parts(&[("w", pw), ("n", pn)], 0).map_err(|e| RowError { row: e.row + offset, ..e })?;
            let pe = part(es, offset, k);
            check_flat("eta", pe, offset)?;
            for (i, o) in chunk.iter_mut().enumerate() {
                let (w, n) = (normalize_or_zero(at(pw, i).into()), normalize_or_zero(at(pn, i).into()));
                let t = if w == Vec3A::ZERO || n == Vec3A::ZERO || w.dot(n) < 0.0 {
                    None
                } else {
                    core_refract(w, n, at(pe, i))
                };
                *o = t.map_or(Vec3::ZERO, Vec3::from);
            }
            Ok(())
        })?;
        let mut okw = ok.readwrite();
        let oks = okw.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        for (b, t) in oks.iter_mut().zip(o.iter()) {
            *b = *t != Vec3::ZERO;
        }
    }
    Ok((out, ok))
}
