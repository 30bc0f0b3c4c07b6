//! `brdfpy.fresnel`: Fresnel reflectance over arrays of cosines of any shape (`brdf_core::batch::ops`:
//! exact dielectric with s/p, exact conductor with complex IOR, Schlick, F0 ↔ IOR, the colour shift,
//! the dielectric split) and the metal table. Scalar-or-RGB parameters arrive as 1 or 3 values; with 3
//! the output gains a trailing axis of 3.

use brdf_core::batch::ops::{self, GrayOrRgb};
use brdf_core::fresnel as fr;
use glam::Vec3;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::{OutSet, outputs, scalars, vec3};
use crate::errors::{invalid, to_py};

type Out<'py> = PyResult<Bound<'py, PyArrayDyn<f32>>>;
/// `(R_s, R_p)`.
type Pair<'py> = (Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>);

/// Run a gray-or-RGB Fresnel batch into a new array.
macro_rules! gray_or_rgb {
    ($py:expr, $op:expr) => {
        match $op.map_err(to_py)? {
            GrayOrRgb::Gray(m) => outputs::<f32>($py, m.shape(), |o| m.run(o)),
            GrayOrRgb::Rgb(m) => outputs::<Vec3>($py, m.shape(), |o| m.run(o)),
        }
    };
}

/// Unpolarised exact dielectric reflectance `(R_s + R_p)/2`; `cos_i < 0` means from inside; TIR → 1.
#[pyfunction]
pub fn dielectric<'py>(py: Python<'py>, cos_i: PyReadonlyArrayDyn<'py, f32>, eta: Vec<f32>) -> Out<'py> {
    gray_or_rgb!(py, ops::dielectric(scalars("cos_i", &cos_i)?, &eta))
}

/// `(R_s, R_p)` of the exact dielectric Fresnel equations (scalar η).
#[pyfunction]
pub fn dielectric_sp<'py>(
    py: Python<'py>,
    cos_i: PyReadonlyArrayDyn<'py, f32>,
    eta: f32,
) -> PyResult<Pair<'py>> {
    let m = ops::dielectric_sp(scalars("cos_i", &cos_i)?, eta).map_err(to_py)?;
    outputs::<(f32, f32)>(py, m.shape(), |o| m.run(o))
}

/// Exact conductor reflectance for the complex index `η − iκ`.
#[pyfunction]
pub fn conductor<'py>(
    py: Python<'py>,
    cos_i: PyReadonlyArrayDyn<'py, f32>,
    eta: Vec<f32>,
    k: Vec<f32>,
) -> Out<'py> {
    gray_or_rgb!(py, ops::conductor(scalars("cos_i", &cos_i)?, &eta, &k))
}

/// Schlick's approximation `F0 + (1 − F0)(1 − |cos_i|)^5`.
#[pyfunction]
pub fn schlick<'py>(py: Python<'py>, cos_i: PyReadonlyArrayDyn<'py, f32>, f0: Vec<f32>) -> Out<'py> {
    gray_or_rgb!(py, ops::schlick(scalars("cos_i", &cos_i)?, &f0))
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
    let m = ops::color_shift(scalars("cos_i", &cos_i)?, &f0, f0_ref).map_err(to_py)?;
    outputs::<Vec3>(py, m.shape(), |o| m.run(o))
}

/// `F0 = ((η − 1)/(η + 1))²` element-wise.
#[pyfunction]
pub fn f0_from_ior<'py>(py: Python<'py>, eta: PyReadonlyArrayDyn<'py, f32>) -> Out<'py> {
    let m = ops::f0_from_ior(scalars("eta", &eta)?).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// `η = (1 + √F0)/(1 − √F0)` element-wise.
#[pyfunction]
pub fn ior_from_f0<'py>(py: Python<'py>, f0: PyReadonlyArrayDyn<'py, f32>) -> Out<'py> {
    let m = ops::ior_from_f0(scalars("f0", &f0)?).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Linear-RGB F0 of a metal by symbol ("au") or English name ("gold"), verbatim from the table.
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
type Split<'py> = <(Vec3, Vec3, f32, f32) as OutSet>::Arrays<'py>;

/// Light meeting a smooth dielectric interface: reflected and refracted directions and the reflected and
/// transmitted power fractions `R` (exact Fresnel) and `T = 1 − R`. `w` points toward where the light
/// comes from, `n` is the outside normal (both normalised here, shapes `(..., 3)` that broadcast),
/// `eta = η_inside/η_outside`; `w` on the inside flips the normal and inverts η. Total internal
/// reflection: `R = 1`, `T = 0`, `t = 0`.
#[pyfunction]
pub fn split<'py>(
    py: Python<'py>,
    w: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
    eta: f32,
) -> PyResult<Split<'py>> {
    let m = ops::split(vec3("w", &w)?, vec3("n", &n)?, eta).map_err(to_py)?;
    outputs::<(Vec3, Vec3, f32, f32)>(py, m.shape(), |o| m.run(o))
}
