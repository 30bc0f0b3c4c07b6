//! `brdfpy.tonemap`: clamp, the HDR operators, exposure, sRGB and 8-bit encoding over arrays of any shape,
//! channel by channel. Thin loops over `brdf_core::tonemap`, which maps NaN and negative values to 0 and
//! `+inf` to the largest float (an image with one bad pixel still saves), so these functions accept any
//! float input.

use brdf_core::tonemap::{self as tm, Operator};
use numpy::{PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

use crate::arrays::flat_view;
use crate::errors::{invalid, to_py};
use crate::threads::fill;

/// `out[i] = f(x[i])` over a float32 array of any shape, output of the same shape.
fn map<'py, T: numpy::Element + Copy + Send>(
    py: Python<'py>,
    name: &str,
    x: &PyReadonlyArrayDyn<'py, f32>,
    f: impl Fn(f32) -> T + Send + Sync,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let xs = flat_view(name, x)?;
    let out = PyArrayDyn::<T>::zeros(py, x.shape(), false);
    {
        let mut w = out.readwrite();
        let o = w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        fill(py, o, |offset, chunk| {
            for (k, o) in chunk.iter_mut().enumerate() {
                *o = f(xs[offset + k]);
            }
            Ok(())
        })?;
    }
    Ok(out)
}

/// Clamp to `[0, 1]` (seed 000); NaN → 0.
#[pyfunction]
pub fn clamp<'py>(py: Python<'py>, x: PyReadonlyArrayDyn<'py, f32>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    map(py, "x", &x, tm::clamp_f32)
}

/// Reinhard et al. 2002: `x / (1 + x)`.
#[pyfunction]
pub fn reinhard<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    map(py, "x", &x, tm::reinhard_f32)
}

/// Extended Reinhard: `x (1 + x/w²) / (1 + x)`, clamped to 1 (`x = w` maps to 1).
#[pyfunction]
pub fn reinhard_extended<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
    white: f32,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    if !(white > 0.0 && white.is_finite()) {
        return Err(invalid(format!("white: must be finite and > 0, got {white}")));
    }
    map(py, "x", &x, move |c| tm::reinhard_extended_f32(c, white))
}

/// Narkowicz's ACES filmic fit.
#[pyfunction]
pub fn aces<'py>(py: Python<'py>, x: PyReadonlyArrayDyn<'py, f32>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    map(py, "x", &x, tm::aces_f32)
}

/// `x · 2^ev`.
#[pyfunction]
pub fn exposure<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
    ev: f32,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    if !ev.is_finite() {
        return Err(invalid(format!("ev: must be finite, got {ev}")));
    }
    map(py, "x", &x, move |c| tm::exposure(glam::Vec3::splat(c), ev).x)
}

/// sRGB OETF (IEC 61966-2-1) after clamping to `[0, 1]`.
#[pyfunction]
pub fn srgb_encode<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    map(py, "x", &x, tm::srgb_encode_f32)
}

/// Inverse sRGB OETF after clamping to `[0, 1]`.
#[pyfunction]
pub fn srgb_decode<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    map(py, "x", &x, tm::srgb_decode_f32)
}

/// `floor(255 · srgb_encode(op(x)) + 0.5)` as uint8, per channel.
#[pyfunction]
#[pyo3(signature = (x, operator="clamp", white=None))]
pub fn to_uint8<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f32>,
    operator: &str,
    white: Option<f32>,
) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let op = Operator::from_name(operator, white).map_err(to_py)?;
    map(py, "x", &x, move |c| tm::to_u8(tm::srgb_encode_f32(op.apply(glam::Vec3::splat(c)).x)))
}

/// Names of the tone-mapping operators `to_uint8` accepts.
#[pyfunction]
pub fn tonemap_operators() -> Vec<&'static str> {
    Operator::NAMES.to_vec()
}
