//! `brdfpy.microfacet`: microfacet distributions D [1/sr], Smith Λ and G1, and shadowing-masking terms G
//! over arrays of directions of shape `(..., 3)` (`brdf_core::batch::ops`). Every function takes the
//! distribution as a list of lobes `(weight, name, alpha, alpha_y)` (one lobe of weight 1 for a plain
//! distribution; several for a mixture).

use brdf_core::batch::ops;
use brdf_core::masking::Masking;
use brdf_core::microfacet::Mixture;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

use crate::arrays::{outputs, vec3, vec3_opt};
use crate::errors::to_py;

/// One lobe as Python passes it: (weight, distribution name, alpha, alpha_y).
pub type Lobe = (f32, String, f32, Option<f32>);

type Out<'py> = PyResult<Bound<'py, PyArrayDyn<f32>>>;
type In<'py> = PyReadonlyArrayDyn<'py, f32>;

/// The (mixture of) distribution(s) of `lobes`.
pub fn mixture(lobes: &[Lobe]) -> PyResult<Mixture> {
    let l: Vec<(f32, &str, f32, Option<f32>)> =
        lobes.iter().map(|(w, n, a, ay)| (*w, n.as_str(), *a, *ay)).collect();
    ops::mixture(&l).map_err(to_py)
}

/// `D(h)` [1/sr] of a (mixture of) distribution(s), for half vectors `h` around normals `n`.
#[pyfunction]
#[pyo3(signature = (lobes, h, n, tangent=None))]
pub fn distribution<'py>(
    py: Python<'py>,
    lobes: Vec<Lobe>,
    h: In<'py>,
    n: In<'py>,
    tangent: Option<In<'py>>,
) -> Out<'py> {
    let d = mixture(&lobes)?;
    let m = ops::distribution(&d, vec3("h", &h)?, vec3("n", &n)?, vec3_opt("tangent", &tangent)?)
        .map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Smith `Λ(w)` (or `G1 = 1/(1 + Λ)` when `g1`) for directions `w` around normals `n`; `Λ = +inf`, `G1 = 0`
/// below the surface.
#[pyfunction]
#[pyo3(signature = (lobes, w, n, tangent=None, g1=false))]
pub fn smith_lambda<'py>(
    py: Python<'py>,
    lobes: Vec<Lobe>,
    w: In<'py>,
    n: In<'py>,
    tangent: Option<In<'py>>,
    g1: bool,
) -> Out<'py> {
    let d = mixture(&lobes)?;
    let (w, n, t) = (vec3("w", &w)?, vec3("n", &n)?, vec3_opt("tangent", &tangent)?);
    let m = ops::smith_lambda(&d, w, n, t, g1).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Shadowing-masking `G(l, v)` (dimensionless) of the named term for a (mixture of) distribution(s).
#[pyfunction]
#[pyo3(signature = (name, lobes, l, v, n, tangent=None))]
pub fn masking<'py>(
    py: Python<'py>,
    name: &str,
    lobes: Vec<Lobe>,
    l: In<'py>,
    v: In<'py>,
    n: In<'py>,
    tangent: Option<In<'py>>,
) -> Out<'py> {
    let g = Masking::from_name(name).map_err(to_py)?;
    let d = mixture(&lobes)?;
    let (l, v, n, t) = (vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, vec3_opt("tangent", &tangent)?);
    let m = ops::masking(g, &d, l, v, n, t).map_err(to_py)?;
    outputs::<f32>(py, m.shape(), |o| m.run(o))
}

/// Names of the distributions and of the masking terms.
#[pyfunction]
pub fn microfacet_names() -> (Vec<&'static str>, Vec<&'static str>) {
    (brdf_core::microfacet::DISTRIBUTION_NAMES.to_vec(), brdf_core::masking::MASKING_NAMES.to_vec())
}
