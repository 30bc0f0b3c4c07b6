//! Lights from Python: `RasterLight` (directional, point, spot) over brdf-core's `Light`, and
//! `RasterAreaLight` (sphere, rectangle) over brdf-raster's `AreaLight`.

use brdf_core::lights::{Attenuation, Light};
use brdf_raster::area_light::AreaLight;
use glam::Vec3;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::{color3, finite3, raster_err};
use crate::errors::{invalid, to_py};

/// What arrives from a light at a point: `(l toward the light, irradiance, distance)`.
type IncidentTuple = ([f32; 3], [f32; 3], f32);

/// A light source (brdf-core `Light`); build through the static constructors.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterLight {
    pub(crate) inner: Light,
}

/// `None` / "none", "inverse_square", or `(c1, c2, c3)` of `1/(c1 + c2 d + c3 d²)`.
fn attenuation(x: &Bound<'_, PyAny>) -> PyResult<Attenuation> {
    if x.is_none() {
        return Ok(Attenuation::None);
    }
    if let Ok(s) = x.extract::<String>() {
        return match s.to_ascii_lowercase().as_str() {
            "none" => Ok(Attenuation::None),
            "inverse_square" => Ok(Attenuation::InverseSquare),
            _ => Err(invalid(format!(
                "attenuation: expected 'none', 'inverse_square' or (c1, c2, c3), got {s:?}"
            ))),
        };
    }
    match x.extract::<[f32; 3]>() {
        Ok([c1, c2, c3]) => Ok(Attenuation::Polynomial { c1, c2, c3 }),
        Err(_) => Err(PyTypeError::new_err(
            "attenuation: expected 'none', 'inverse_square' or three numbers (c1, c2, c3)",
        )),
    }
}

fn attenuation_to_py<'py>(py: Python<'py>, a: Attenuation) -> PyResult<Bound<'py, PyAny>> {
    Ok(match a {
        Attenuation::None => "none".into_pyobject(py)?.into_any(),
        Attenuation::InverseSquare => "inverse_square".into_pyobject(py)?.into_any(),
        Attenuation::Polynomial { c1, c2, c3 } => (c1, c2, c3).into_pyobject(py)?.into_any(),
    })
}

#[pymethods]
impl RasterLight {
    /// Directional light travelling along `direction` with irradiance `color`.
    #[staticmethod]
    fn directional(direction: [f32; 3], color: [f32; 3]) -> PyResult<Self> {
        let l = Light::directional(finite3("direction", direction)?, color3("color", color)?);
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// Point light at `position` with radiant intensity `intensity`.
    #[staticmethod]
    fn point(position: [f32; 3], intensity: [f32; 3], attenuation: &Bound<'_, PyAny>) -> PyResult<Self> {
        let a = self::attenuation(attenuation)?;
        let l = Light::point(finite3("position", position)?, color3("intensity", intensity)?, a);
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// Spot light; angles are half-angles in radians.
    #[staticmethod]
    fn spot(
        position: [f32; 3],
        direction: [f32; 3],
        intensity: [f32; 3],
        inner_angle: f32,
        outer_angle: f32,
        attenuation: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let a = self::attenuation(attenuation)?;
        let l = Light::spot(
            finite3("position", position)?,
            finite3("direction", direction)?,
            color3("intensity", intensity)?,
            inner_angle,
            outer_angle,
            a,
        );
        Ok(Self { inner: l.map_err(to_py)? })
    }

    /// The light's fields as a dict (`kind` plus the constructor's arguments; angles in radians).
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match self.inner {
            Light::Directional { direction, color } => {
                d.set_item("kind", "directional")?;
                d.set_item("direction", direction.to_array())?;
                d.set_item("color", color.to_array())?;
            }
            Light::Point { position, intensity, attenuation } => {
                d.set_item("kind", "point")?;
                d.set_item("position", position.to_array())?;
                d.set_item("intensity", intensity.to_array())?;
                d.set_item("attenuation", attenuation_to_py(py, attenuation)?)?;
            }
            Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation } => {
                d.set_item("kind", "spot")?;
                d.set_item("position", position.to_array())?;
                d.set_item("direction", direction.to_array())?;
                d.set_item("intensity", intensity.to_array())?;
                d.set_item("inner_angle", inner_angle)?;
                d.set_item("outer_angle", outer_angle)?;
                d.set_item("attenuation", attenuation_to_py(py, attenuation)?)?;
            }
        }
        Ok(d)
    }

    /// `(l, irradiance, distance)` arriving at point `p`, or `None` (outside a spot's cone, at the light).
    fn incident(&self, p: [f32; 3]) -> PyResult<Option<IncidentTuple>> {
        let p = finite3("p", p)?;
        Ok(self.inner.incident(p).map(|i| (i.l.to_array(), i.irradiance.to_array(), i.distance)))
    }
}

/// An area light (brdf-raster `AreaLight`: sphere or rectangle, emitting a radiance); build through the
/// static constructors.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RasterAreaLight {
    pub(crate) inner: AreaLight,
}

#[pymethods]
impl RasterAreaLight {
    /// Sphere light at `center` of `radius`, emitting `radiance` [W/(m²·sr)] from its outside.
    #[staticmethod]
    fn sphere(center: [f32; 3], radius: f32, radiance: [f32; 3]) -> PyResult<Self> {
        let l = AreaLight::sphere(Vec3::from_array(center), radius, Vec3::from_array(radiance));
        Ok(Self { inner: l.map_err(raster_err)? })
    }

    /// Rectangle (parallelogram) light with corners `center ± edge0/2 ± edge1/2`, emitting `radiance`
    /// on the side of `edge0 × edge1` (both with `two_sided`).
    #[staticmethod]
    fn rect(
        center: [f32; 3],
        edge0: [f32; 3],
        edge1: [f32; 3],
        radiance: [f32; 3],
        two_sided: bool,
    ) -> PyResult<Self> {
        let [c, e0, e1, r] = [center, edge0, edge1, radiance].map(Vec3::from_array);
        Ok(Self { inner: AreaLight::rect(c, e0, e1, r, two_sided).map_err(raster_err)? })
    }

    /// The light's fields as a dict (`kind` plus the constructor's arguments).
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match self.inner {
            AreaLight::Sphere { center, radius, radiance } => {
                d.set_item("kind", "sphere")?;
                d.set_item("center", center.to_array())?;
                d.set_item("radius", radius)?;
                d.set_item("radiance", radiance.to_array())?;
            }
            AreaLight::Rect { center, edge0, edge1, radiance, two_sided } => {
                d.set_item("kind", "rect")?;
                d.set_item("center", center.to_array())?;
                d.set_item("edge0", edge0.to_array())?;
                d.set_item("edge1", edge1.to_array())?;
                d.set_item("radiance", radiance.to_array())?;
                d.set_item("two_sided", two_sided)?;
            }
        }
        Ok(d)
    }

    /// `(l, irradiance, distance)` at point `p` from the unoccluded vector irradiance `Φ`
    /// (`AreaLight::irradiance_vector`): `l = Φ/|Φ|`, the irradiance `|Φ|·radiance` on a surface facing
    /// `l` that sees the whole light, the distance to the light's centre; `None` where nothing arrives.
    fn incident(&self, p: [f32; 3]) -> PyResult<Option<IncidentTuple>> {
        let p = finite3("p", p)?;
        let phi = self.inner.irradiance_vector(p);
        let len = phi.length();
        if !(len > 0.0) || !len.is_finite() {
            return Ok(None);
        }
        let center = match self.inner {
            AreaLight::Sphere { center, .. } | AreaLight::Rect { center, .. } => center,
        };
        Ok(Some(((phi / len).to_array(), (self.inner.radiance() * len).to_array(), (center - p).length())))
    }
}
