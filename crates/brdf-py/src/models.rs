//! `Model`: a registry model as a Python object with batch `eval` and `shade`.

use brdf_core::batch::{Directions, Quantity, evaluate};
use glam::Vec3;
use numpy::{PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::arrays::vec3_slice;
use crate::errors::to_py;

/// Names of every registered model.
#[pyfunction]
pub fn model_names() -> Vec<&'static str> {
    brdf_core::MODEL_SPECS.iter().map(|s| s.name).collect()
}

/// A reflectance model with fixed parameters.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct Model {
    inner: brdf_core::Model,
}

#[pymethods]
impl Model {
    #[new]
    fn new(name: &str) -> PyResult<Self> {
        Ok(Self { inner: brdf_core::Model::build(name, &[]).map_err(to_py)? })
    }

    /// Registry name.
    #[getter]
    fn name(&self) -> &'static str {
        self.inner.spec().name
    }

    /// Batch evaluation; arrays are float32 C-contiguous (N, 3) or (1, 3).
    #[pyo3(signature = (l, v, n, tangent=None, shade=false))]
    fn _eval<'py>(
        &self,
        py: Python<'py>,
        l: PyReadonlyArray2<'py, f32>,
        v: PyReadonlyArray2<'py, f32>,
        n: PyReadonlyArray2<'py, f32>,
        tangent: Option<PyReadonlyArray2<'py, f32>>,
        shade: bool,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let (ls, vs, ns) = (vec3_slice("l", &l)?, vec3_slice("v", &v)?, vec3_slice("n", &n)?);
        let ts = tangent.as_ref().map(|t| vec3_slice("tangent", t)).transpose()?;
        let (dirs, len) = Directions::new(ls, vs, ns, ts).map_err(to_py)?;
        let q = if shade { Quantity::Shade } else { Quantity::Brdf };
        let out = PyArray2::<f32>::zeros(py, [len, 3], false);
        {
            let mut w = out.readwrite();
            let slice =
                w.as_slice_mut().map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
            let o: &mut [Vec3] = bytemuck::cast_slice_mut(slice);
            py.detach(|| evaluate(&self.inner, &dirs, q, o));
        }
        Ok(out)
    }
}
