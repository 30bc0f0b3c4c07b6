//! NumPy ↔ `&[Vec3]`: shape, dtype and finiteness checks that name the argument.

use glam::Vec3;
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A borrowed `(N, 3)` float32 C-contiguous array viewed as `&[Vec3]`.
pub fn vec3_slice<'a>(name: &str, a: &'a PyReadonlyArray2<'_, f32>) -> PyResult<&'a [Vec3]> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(PyValueError::new_err(format!("{name}: expected shape (N, 3) or (3,), got {shape:?}")));
    }
    let s = a
        .as_slice()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float32 array")))?;
    if let Some(i) = s.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{name}: contains a non-finite value (NaN or inf) at row {}",
            i / 3
        )));
    }
    Ok(bytemuck::cast_slice(s))
}
