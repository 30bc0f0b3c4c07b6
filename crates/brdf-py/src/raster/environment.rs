//! Environments from Python: `RasterEnvironment` (an equirectangular radiance map with a rotation and an
//! intensity) and its built-ins. Every rule lives in `brdf_raster::environment`; this only views arrays.

use brdf_raster::environment::Environment;
use glam::Vec3;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use super::{raster_err, rows3, vec3_array};

/// An environment: radiance from every direction, an equirectangular image turned about +y.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
#[derive(Clone)]
pub struct RasterEnvironment {
    pub(crate) inner: Environment,
}

#[pymethods]
impl RasterEnvironment {
    /// From a float32 array of shape (H, W, 3), linear radiance, row 0 at the zenith.
    #[staticmethod]
    fn from_array(py: Python<'_>, image: PyReadonlyArray3<'_, f32>) -> PyResult<Self> {
        let shape = image.shape().to_vec();
        let data = image
            .as_slice()
            .map_err(|_| PyTypeError::new_err("image: expected a C-contiguous float32 array"))?;
        let inner =
            py.detach(|| Environment::from_rgb(shape[0], shape[1], shape[2], data)).map_err(raster_err)?;
        Ok(Self { inner })
    }

    /// From a Radiance `.hdr` or OpenEXR `.exr` file (`brdf_raster::environment::file`).
    #[staticmethod]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let inner = py.detach(|| brdf_raster::environment::file::load(&path)).map_err(raster_err)?;
        Ok(Self { inner })
    }

    /// Radiance `radiance` (linear RGB) from every direction.
    #[staticmethod]
    fn uniform(radiance: [f32; 3]) -> PyResult<Self> {
        Ok(Self { inner: Environment::uniform(Vec3::from(radiance)).map_err(raster_err)? })
    }

    /// The procedural sky over a ground (`brdf_raster::environment::Environment::sky`).
    #[staticmethod]
    fn sky(zenith: [f32; 3], horizon: [f32; 3], ground: [f32; 3]) -> PyResult<Self> {
        let inner = Environment::sky(Vec3::from(zenith), Vec3::from(horizon), Vec3::from(ground))
            .map_err(raster_err)?;
        Ok(Self { inner })
    }

    /// The same map turned by `rotation` [rad] about +y and scaled by `intensity`.
    fn with_(&self, rotation: f32, intensity: f32) -> PyResult<Self> {
        let inner = self
            .inner
            .clone()
            .with_rotation(rotation)
            .and_then(|e| e.with_intensity(intensity))
            .map_err(raster_err)?;
        Ok(Self { inner })
    }

    #[getter]
    fn rotation(&self) -> f32 {
        self.inner.rotation
    }

    #[getter]
    fn intensity(&self) -> f32 {
        self.inner.intensity
    }

    /// (height, width) of the map.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        let (w, h) = self.inner.map.size();
        (h, w)
    }

    /// The map's texels, float32 (H, W, 3) (without rotation or intensity).
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let (w, h) = self.inner.map.size();
        PyArray1::from_slice(py, bytemuck::cast_slice::<Vec3, f32>(self.inner.map.texels()))
            .reshape([h, w, 3])
    }

    /// Radiance arriving from each world direction (N, 3) (normalised here), float32 (N, 3).
    fn radiance<'py>(
        &self,
        py: Python<'py>,
        directions: PyReadonlyArray2<'_, f32>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
        let d = rows3("directions", &directions)?;
        let out: Vec<Vec3> = d.iter().map(|d| self.inner.radiance(d.normalize_or_zero())).collect();
        vec3_array(py, &out)
    }
}
