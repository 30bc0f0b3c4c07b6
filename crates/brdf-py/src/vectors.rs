//! `brdfpy.vectors`: reflect, refract and the half vector over arrays of directions of shape `(..., 3)`,
//! in brdfpy's convention (every direction points away from the surface): `brdf_core::batch::ops`.

use brdf_core::batch::ops;
use glam::Vec3;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::{outputs, scalars, vec3};
use crate::errors::to_py;

type Out<'py> = PyResult<Bound<'py, PyArrayDyn<f32>>>;
/// `(t, ok)` of [`refract`].
type Refracted<'py> = (Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<bool>>);

/// Mirror `w` about the normal: `r = 2(n̂·w)n̂ − w`, with `n̂ = n/|n|`. `w` keeps its length; a
/// zero-length `n` gives 0.
#[pyfunction]
pub fn reflect<'py>(
    py: Python<'py>,
    w: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
) -> Out<'py> {
    let m = ops::reflect(vec3("w", &w)?, vec3("n", &n)?).map_err(to_py)?;
    outputs::<Vec3>(py, m.shape(), |o| m.run(o))
}

/// Unit half vector `h = normalize(l̂ + v̂)`; 0 where `l̂ = −v̂` or an input has zero length.
#[pyfunction]
pub fn halfway<'py>(
    py: Python<'py>,
    l: PyReadonlyArrayDyn<'py, f32>,
    v: PyReadonlyArrayDyn<'py, f32>,
) -> Out<'py> {
    let m = ops::halfway(vec3("l", &l)?, vec3("v", &v)?).map_err(to_py)?;
    outputs::<Vec3>(py, m.shape(), |o| m.run(o))
}

/// Refracted direction by Snell's law (`η_i sin θ_i = η_t sin θ_t`, `eta = η_t/η_i`): `(t, ok)`; `ok`
/// is false (and `t` is 0) on total internal reflection, when `w` is below the surface or an input has
/// zero length. `w`, `n` `(..., 3)` and `eta` `(...)` broadcast together.
#[pyfunction]
pub fn refract<'py>(
    py: Python<'py>,
    w: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
    eta: PyReadonlyArrayDyn<'py, f32>,
) -> PyResult<Refracted<'py>> {
    let m = ops::refract(vec3("w", &w)?, vec3("n", &n)?, scalars("eta", &eta)?).map_err(to_py)?;
    outputs::<(Vec3, bool)>(py, m.shape(), |o| m.run(o))
}
