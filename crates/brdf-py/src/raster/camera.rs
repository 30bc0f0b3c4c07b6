//! Cameras from Python: `RasterCamera` (look-at, perspective or orthographic).

use brdf_raster::{Camera, Projection};
use pyo3::prelude::*;

use super::{finite3, raster_err, rows_of};

/// A look-at camera (OpenGL conventions; angles in radians here, degrees in the Python wrapper).
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterCamera {
    pub(crate) inner: Camera,
}

#[pymethods]
impl RasterCamera {
    /// Perspective camera, vertical field of view `fovy` in radians.
    #[staticmethod]
    fn perspective(
        eye: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
        fovy: f32,
        near: f32,
        far: f32,
    ) -> PyResult<Self> {
        let c = Camera::perspective(
            finite3("eye", eye)?,
            finite3("target", target)?,
            finite3("up", up)?,
            fovy,
            near,
            far,
        );
        Ok(Self { inner: c.map_err(raster_err)? })
    }

    /// Orthographic camera whose view volume is `height` world units tall.
    #[staticmethod]
    fn orthographic(
        eye: [f32; 3],
        target: [f32; 3],
        up: [f32; 3],
        height: f32,
        near: f32,
        far: f32,
    ) -> PyResult<Self> {
        let c = Camera::orthographic(
            finite3("eye", eye)?,
            finite3("target", target)?,
            finite3("up", up)?,
            height,
            near,
            far,
        );
        Ok(Self { inner: c.map_err(raster_err)? })
    }

    #[getter]
    fn eye(&self) -> [f32; 3] {
        self.inner.eye.to_array()
    }
    #[getter]
    fn target(&self) -> [f32; 3] {
        self.inner.target.to_array()
    }
    #[getter]
    fn up(&self) -> [f32; 3] {
        self.inner.up.to_array()
    }
    #[getter]
    fn near(&self) -> f32 {
        self.inner.near
    }
    #[getter]
    fn far(&self) -> f32 {
        self.inner.far
    }
    /// "perspective" or "orthographic".
    #[getter]
    fn kind(&self) -> &'static str {
        if self.inner.is_orthographic() { "orthographic" } else { "perspective" }
    }
    /// Vertical field of view in radians (perspective) or view-volume height (orthographic).
    #[getter]
    fn extent(&self) -> f32 {
        match self.inner.projection {
            Projection::Perspective { fovy } => fovy,
            Projection::Orthographic { height } => height,
        }
    }

    /// The view matrix `V` (4×4 row-major, world → camera).
    fn view_matrix(&self) -> [[f32; 4]; 4] {
        rows_of(self.inner.view())
    }

    /// The projection matrix `P` for an image of aspect ratio `width / height` (OpenGL clip space).
    fn projection_matrix(&self, aspect: f32) -> PyResult<[[f32; 4]; 4]> {
        Ok(rows_of(self.inner.checked_projection(aspect).map_err(raster_err)?))
    }
}
