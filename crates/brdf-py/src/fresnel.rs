//! `brdfpy.fresnel`: Fresnel reflectance over arrays of cosines of any shape. Thin loops over
//! `brdf_core::fresnel` (exact dielectric with s/p, exact conductor with complex IOR, Schlick, F0 ↔ IOR,
//! the metal table, Cook & Torrance's colour shift). Scalar-or-RGB parameters arrive as 1 or 3 values
//! (validated by the Python wrapper and again here); with 3 the output gains a trailing axis of 3.

use brdf_core::fresnel as fr;
use glam::Vec3;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::map_flat;
use crate::errors::invalid;

type Out<'py> = PyResult<Bound<'py, PyArrayDyn<f32>>>;
/// `(R_s, R_p)`.
type Pair<'py> = (Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>);

const COS_PROBLEM: &str = "must hold finite cosines in [-1, 1]; bad value at index";

/// Cosines may carry float32 rounding just past ±1 (e.g. a dot product of unit vectors).
fn cos_ok(c: f32) -> bool {
    c.is_finite() && c.abs() <= 1.0 + 1e-4
}

/// 1 or 3 values each satisfying `ok`, as a `Vec3` (gray broadcast) and whether it was RGB.
fn channels(name: &str, xs: &[f32], ok: impl Fn(f32) -> bool, want: &str) -> PyResult<(Vec3, bool)> {
    let v = match xs {
        [x] => Vec3::splat(*x),
        [r, g, b] => Vec3::new(*r, *g, *b),
        _ => {
            return Err(invalid(format!(
                "{name}: expected a number or 3 numbers (RGB), got {} numbers",
                xs.len()
            )));
        }
    };
    if let Some(x) = xs.iter().find(|x| !ok(**x)) {
        return Err(invalid(format!("{name}: must be {want}, got {x}")));
    }
    Ok((v, xs.len() == 3))
}

fn eta_ok(x: f32) -> bool {
    x.is_finite() && x > 0.0
}

/// Unpolarised exact dielectric reflectance `(R_s + R_p)/2`; `cos_i < 0` means from inside; TIR → 1.
#[pyfunction]
pub fn dielectric<'py>(py: Python<'py>, cos_i: PyReadonlyArrayDyn<'py, f32>, eta: Vec<f32>) -> Out<'py> {
    let (eta, rgb) = channels("eta", &eta, eta_ok, "finite and > 0")?;
    map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, rgb, move |c| {
        if rgb { fr::dielectric_rgb(c, eta) } else { Vec3::splat(fr::dielectric(c, eta.x)) }
    })
}

/// `(R_s, R_p)` of the exact dielectric Fresnel equations (scalar η).
#[pyfunction]
pub fn dielectric_sp<'py>(
    py: Python<'py>,
    cos_i: PyReadonlyArrayDyn<'py, f32>,
    eta: f32,
) -> PyResult<Pair<'py>> {
    if !eta_ok(eta) {
        return Err(invalid(format!("eta: must be finite and > 0, got {eta}")));
    }
    let rs = map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, false, |c| {
        Vec3::splat(fr::dielectric_sp(c, eta).0)
    })?;
    let rp = map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, false, |c| {
        Vec3::splat(fr::dielectric_sp(c, eta).1)
    })?;
    Ok((rs, rp))
}

/// Exact conductor reflectance for the complex index `η − iκ` (seed 001).
#[pyfunction]
pub fn conductor<'py>(
    py: Python<'py>,
    cos_i: PyReadonlyArrayDyn<'py, f32>,
    eta: Vec<f32>,
    k: Vec<f32>,
) -> Out<'py> {
    let (eta, rgb_e) = channels("eta", &eta, eta_ok, "finite and > 0")?;
    let (k, rgb_k) = channels("k", &k, |x| x.is_finite() && x >= 0.0, "finite and >= 0")?;
    let rgb = rgb_e || rgb_k;
    map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, rgb, move |c| {
        if rgb { fr::conductor(c, eta, k) } else { Vec3::splat(fr::conductor_scalar(c, eta.x, k.x)) }
    })
}

/// Schlick's approximation `F0 + (1 − F0)(1 − |cos_i|)^5`.
#[pyfunction]
pub fn schlick<'py>(py: Python<'py>, cos_i: PyReadonlyArrayDyn<'py, f32>, f0: Vec<f32>) -> Out<'py> {
    let (f0, rgb) = channels("f0", &f0, |x| (0.0..=1.0).contains(&x), "in [0, 1]")?;
    map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, rgb, move |c| {
        if rgb { fr::schlick(c, f0) } else { Vec3::splat(fr::schlick_scalar(c, f0.x)) }
    })
}

/// Cook & Torrance's colour shift: every channel between its F0 and 1 along the exact curve of `f0_ref`.
#[pyfunction]
#[pyo3(signature = (cos_i, f0, f0_ref=None))]
pub fn color_shift<'py>(
    py: Python<'py>,
    cos_i: PyReadonlyArrayDyn<'py, f32>,
    f0: Vec<f32>,
    f0_ref: Option<f32>,
) -> Out<'py> {
    let (f0, _) = channels("f0", &f0, |x| (0.0..=1.0).contains(&x), "in [0, 1]")?;
    let f0_ref = match f0_ref {
        None => fr::color_shift_reference(f0),
        Some(r) if (0.0..=1.0).contains(&r) => r,
        Some(r) => return Err(invalid(format!("f0_ref: must be in [0, 1], got {r}"))),
    };
    map_flat(py, "cos_i", &cos_i, COS_PROBLEM, cos_ok, true, move |c| fr::color_shift(c, f0, f0_ref))
}

/// `F0 = ((η − 1)/(η + 1))²` element-wise.
#[pyfunction]
pub fn f0_from_ior<'py>(py: Python<'py>, eta: PyReadonlyArrayDyn<'py, f32>) -> Out<'py> {
    map_flat(py, "eta", &eta, "must be finite and > 0; bad value at index", eta_ok, false, |e| {
        Vec3::splat(fr::f0_from_ior(e))
    })
}

/// `η = (1 + √F0)/(1 − √F0)` element-wise (`F0 = 1` gives +inf).
#[pyfunction]
pub fn ior_from_f0<'py>(py: Python<'py>, f0: PyReadonlyArrayDyn<'py, f32>) -> Out<'py> {
    map_flat(
        py,
        "f0",
        &f0,
        "must lie in [0, 1); bad value at index",
        |x| (0.0..1.0).contains(&x),
        false,
        |x| Vec3::splat(fr::ior_from_f0(x)),
    )
}

/// Linear-RGB F0 of a metal by symbol ("au") or English name ("gold"), verbatim from seed 001's table.
#[pyfunction]
pub fn metal_f0(name: &str) -> PyResult<[f32; 3]> {
    fr::metal_f0(name).map(|c| c.to_array()).ok_or_else(|| {
        let known: Vec<&str> = fr::METAL_F0.iter().map(|(s, _)| *s).collect();
        invalid(format!("name: unknown metal {name:?}; known: {}", known.join(", ")))
    })
}

/// Symbols of the metals in the F0 table, in table order.
#[pyfunction]
pub fn metal_names() -> Vec<&'static str> {
    fr::METAL_F0.iter().map(|(s, _)| *s).collect()
}

/// `(r, t, R, T)` of [`split`].
type Split<'py> = (
    Bound<'py, numpy::PyArray2<f32>>,
    Bound<'py, numpy::PyArray2<f32>>,
    Bound<'py, numpy::PyArray1<f32>>,
    Bound<'py, numpy::PyArray1<f32>>,
);

/// Light meeting a smooth dielectric interface: reflected and refracted directions and the reflected and
/// transmitted power fractions `R` (exact Fresnel) and `T = 1 − R` (seed 001; seed 003). `w` points toward
/// where the light comes from, `n` is the outside normal (both normalised here), `eta = η_inside/η_outside`;
/// `w` on the inside flips the normal and inverts η. Total internal reflection: `R = 1`, `T = 0`, `t = 0`.
#[pyfunction]
pub fn split<'py>(
    py: Python<'py>,
    w: numpy::PyReadonlyArray2<'py, f32>,
    n: numpy::PyReadonlyArray2<'py, f32>,
    eta: f32,
) -> PyResult<Split<'py>> {
    use crate::arrays::{at, broadcast_len, check_vec3, vec3_view};
    use numpy::PyArrayMethods;
    if !eta_ok(eta) {
        return Err(invalid(format!("eta: must be finite and > 0, got {eta}")));
    }
    let (ws, ns) = (vec3_view("w", &w)?, vec3_view("n", &n)?);
    let len = broadcast_len(&[("w", ws.len()), ("n", ns.len())])?;
    check_vec3("w", ws, 0).map_err(crate::threads::RowError::into_py)?;
    check_vec3("n", ns, 0).map_err(crate::threads::RowError::into_py)?;
    // Four outputs per sample: one pass on the calling thread (GIL released), the vectors handed to
    // NumPy without copying.
    let mut r = vec![0.0f32; 3 * len];
    let mut t = vec![0.0f32; 3 * len];
    let mut rr = vec![0.0f32; len];
    let mut tt = vec![0.0f32; len];
    py.detach(|| {
        for i in 0..len {
            let wi = brdf_core::vector::normalize_or_zero(at(ws, i).into());
            let ni = brdf_core::vector::normalize_or_zero(at(ns, i).into());
            if wi == glam::Vec3A::ZERO || ni == glam::Vec3A::ZERO {
                continue;
            }
            let s = fr::split(wi, ni, eta);
            r[3 * i..3 * i + 3].copy_from_slice(&s.reflected.to_array());
            if let Some(d) = s.refracted {
                t[3 * i..3 * i + 3].copy_from_slice(&d.to_array());
            }
            rr[i] = s.reflectance;
            tt[i] = s.transmittance;
        }
    });
    let r = numpy::PyArray1::from_vec(py, r).reshape([len, 3])?;
    let t = numpy::PyArray1::from_vec(py, t).reshape([len, 3])?;
    Ok((r, t, numpy::PyArray1::from_vec(py, rr), numpy::PyArray1::from_vec(py, tt)))
}
