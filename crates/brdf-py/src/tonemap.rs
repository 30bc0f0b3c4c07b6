//! `brdfpy.tonemap`: clamp, the HDR operators, exposure, sRGB and 8-bit encoding over arrays of any shape,
//! channel by channel (`brdf_core::batch::ops`, over `brdf_core::tonemap`, which maps NaN and negative
//! values to 0 and `+inf` to the largest float, so these functions accept any float input).

use brdf_core::batch::ops;
use brdf_core::tonemap::{self as tm, Operator};
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::{outputs, scalars};
use crate::errors::to_py;

type In<'py> = PyReadonlyArrayDyn<'py, f32>;
type Out<'py> = PyResult<Bound<'py, PyArrayDyn<f32>>>;

/// `f` per value of `x`, output of the same shape.
fn map<'py>(py: Python<'py>, x: &In<'py>, f: fn(f32) -> f32) -> Out<'py> {
    let m = ops::tonemap(scalars("x", x)?, f).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Clamp to `[0, 1]`; NaN → 0.
#[pyfunction]
pub fn clamp<'py>(py: Python<'py>, x: In<'py>) -> Out<'py> {
    map(py, &x, tm::clamp_f32)
}

/// Reinhard et al. 2002: `x / (1 + x)`.
#[pyfunction]
pub fn reinhard<'py>(py: Python<'py>, x: In<'py>) -> Out<'py> {
    map(py, &x, tm::reinhard_f32)
}

/// Extended Reinhard: `x (1 + x/w²) / (1 + x)`, clamped to 1 (`x = w` maps to 1).
#[pyfunction]
pub fn reinhard_extended<'py>(py: Python<'py>, x: In<'py>, white: f32) -> Out<'py> {
    let m = ops::reinhard_extended(scalars("x", &x)?, white).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Narkowicz's ACES filmic fit.
#[pyfunction]
pub fn aces<'py>(py: Python<'py>, x: In<'py>) -> Out<'py> {
    map(py, &x, tm::aces_f32)
}

/// `x · 2^ev`.
#[pyfunction]
pub fn exposure<'py>(py: Python<'py>, x: In<'py>, ev: f32) -> Out<'py> {
    let m = ops::exposure(scalars("x", &x)?, ev).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// sRGB OETF (IEC 61966-2-1) after clamping to `[0, 1]`.
#[pyfunction]
pub fn srgb_encode<'py>(py: Python<'py>, x: In<'py>) -> Out<'py> {
    map(py, &x, tm::srgb_encode_f32)
}

/// Inverse sRGB OETF after clamping to `[0, 1]`.
#[pyfunction]
pub fn srgb_decode<'py>(py: Python<'py>, x: In<'py>) -> Out<'py> {
    map(py, &x, tm::srgb_decode_f32)
}

/// `floor(255 · srgb_encode(op(x)) + 0.5)` as uint8, per channel.
#[pyfunction]
#[pyo3(signature = (x, operator="clamp", white=None))]
pub fn to_uint8<'py>(
    py: Python<'py>,
    x: In<'py>,
    operator: &str,
    white: Option<f32>,
) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let m = ops::to_uint8(scalars("x", &x)?, operator, white).map_err(to_py)?;
    outputs::<u8>(py, m.shape(), |o| m.run(o))
}

/// Names of the tone-mapping operators `to_uint8` accepts.
#[pyfunction]
pub fn tonemap_operators() -> Vec<&'static str> {
    Operator::NAMES.to_vec()
}
