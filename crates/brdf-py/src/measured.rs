//! Measured BRDFs (`brdf_core::measured`, `brdf_core::fit`) and spherical harmonics (`brdf_core::sh`):
//! the tabulated BRDF as a Python object, the parameter fit, and the SH basis, quadrature, projection and
//! reconstruction on float64 arrays. The Python modules `brdfpy.measured` and `brdfpy.sh` wrap these.

use std::sync::Arc;

use brdf_core::batch::{Batch, Directions, Quantity, evaluate_bxdf};
use brdf_core::fit::{self, FitOptions, Jacobian, Loss, Sample, Strategy, TableSampling};
use brdf_core::measured::samples::read_samples_csv;
use brdf_core::measured::{
    AngleUnit, AnisotropicTabulated as CoreAniso, Coverage, Measured, MeasuredAnisotropic, MeasuredRgl,
    RglBsdf as CoreRgl, SampleOptions, Tabulated as CoreTabulated,
};
use brdf_core::sh;
use glam::{DVec3, Vec3};
use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::arrays::{outputs, run, vec3};
use crate::errors::{invalid, to_py};
use crate::models::{Model, to_inputs};

/// An isotropic BRDF tabulated over Rusinkiewicz's (θ_h, θ_d, φ_d) on the MERL grid, looked up by
/// trilinear interpolation.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct Tabulated {
    /// Shared (not copied) with the models made by `as_model` (a MERL table is 17.5 MB).
    inner: Measured,
}

impl Tabulated {
    /// The table as a model (shares the table).
    pub fn measured(&self) -> &Measured {
        &self.inner
    }

    fn wrap(t: CoreTabulated) -> Self {
        Self { inner: Measured(Arc::new(t)) }
    }
}

#[pymethods]
impl Tabulated {
    /// From a float32 C-contiguous array of shape `(n_theta_h, n_theta_d, n_phi_d, 3)`, values f_r [1/sr].
    #[new]
    fn new(py: Python<'_>, table: PyReadonlyArrayDyn<'_, f32>) -> PyResult<Self> {
        let shape = table.shape().to_vec();
        if shape.len() != 4 || shape[3] != 3 {
            return Err(invalid(format!(
                "table: expected shape (n_theta_h, n_theta_d, n_phi_d, 3), got {:?}",
                shape
            )));
        }
        let flat = table
            .as_slice()
            .map_err(|_| PyTypeError::new_err("table: expected a C-contiguous float32 array"))?;
        let data: Vec<Vec3> = bytemuck::cast_slice::<f32, Vec3>(flat).to_vec();
        let dims = (shape[0], shape[1], shape[2]);
        let inner = run(py, data.len(), || CoreTabulated::new(dims, data))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// Tabulate `model` at the nodes of a `(n_theta_h, n_theta_d, n_phi_d)` grid.
    #[staticmethod]
    fn from_model(
        py: Python<'_>,
        model: PyRef<'_, Model>,
        resolution: (usize, usize, usize),
    ) -> PyResult<Self> {
        let m = model.core().clone();
        let work = resolution.0.saturating_mul(resolution.1).saturating_mul(resolution.2);
        let inner = run(py, work, || CoreTabulated::from_model(&m, resolution))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// Parse the bytes of a MERL `.binary` file.
    #[staticmethod]
    fn from_merl_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let inner = run(py, data.len(), || CoreTabulated::read_merl(data))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// The table in the MERL `.binary` layout.
    fn to_merl_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let mut out = Vec::new();
        self.inner.0.write_merl(&mut out).map_err(to_py)?;
        Ok(PyBytes::new(py, &out))
    }

    /// A table from scattered samples (`brdf_core::measured::Tabulated::from_samples`): float32 `(..., 3)`
    /// arrays that broadcast; returns the table and its coverage as a dict.
    #[staticmethod]
    #[pyo3(signature = (l, v, n, values, resolution, mirror, min_weight))]
    fn from_samples<'py>(
        py: Python<'py>,
        l: PyReadonlyArrayDyn<'py, f32>,
        v: PyReadonlyArrayDyn<'py, f32>,
        n: PyReadonlyArrayDyn<'py, f32>,
        values: PyReadonlyArrayDyn<'py, f32>,
        resolution: (usize, usize, usize),
        mirror: bool,
        min_weight: f32,
    ) -> PyResult<(Self, Bound<'py, PyDict>)> {
        let b = Batch::new((vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, vec3("values", &values)?))
            .map_err(to_py)?;
        let rows = b.map(|s: (Vec3, Vec3, Vec3, Vec3)| s).to_vec().map_err(to_py)?;
        let samples: Vec<Sample> = rows.into_iter().map(|(l, v, n, f)| Sample { l, v, n, f }).collect();
        let options = SampleOptions { resolution, mirror, min_weight };
        let work = samples
            .len()
            .saturating_add(resolution.0.saturating_mul(resolution.1).saturating_mul(resolution.2));
        let (t, cov) = run(py, work, || CoreTabulated::from_samples(&samples, &options))?.map_err(to_py)?;
        Ok((Self::wrap(t), coverage_dict(py, &cov)?))
    }

    /// `(n_theta_h, n_theta_d, n_phi_d)`.
    #[getter]
    fn shape(&self) -> (usize, usize, usize) {
        self.inner.0.dims()
    }

    /// A float32 copy of the values, shape `(n_theta_h, n_theta_d, n_phi_d, 3)`.
    #[getter]
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let (a, b, c) = self.inner.0.dims();
        let flat: &[f32] = bytemuck::cast_slice(self.inner.0.data());
        PyArray1::from_slice(py, flat).reshape(vec![a, b, c, 3])
    }

    /// Batch look-up: float32 C-contiguous `(..., 3)` arrays whose leading shapes broadcast; returns the
    /// broadcast shape followed by 3, `f_r` [1/sr].
    fn _eval<'py>(
        &self,
        py: Python<'py>,
        l: PyReadonlyArrayDyn<'py, f32>,
        v: PyReadonlyArrayDyn<'py, f32>,
        n: PyReadonlyArrayDyn<'py, f32>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let dirs =
            Directions::from_args(vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, None).map_err(to_py)?;
        outputs::<Vec3>(py, dirs.shape(), |out| evaluate_bxdf(&self.inner, &dirs, Quantity::Brdf, out))
    }

    fn __repr__(&self) -> String {
        let (a, b, c) = self.inner.0.dims();
        format!("brdfpy.measured.Tabulated(shape=({a}, {b}, {c}))")
    }
}

/// An anisotropic BRDF tabulated over (θ_in, θ_out, φ_diff, φ_in) in the tangent frame
/// (`brdf_core::measured::AnisotropicTabulated`), looked up by multilinear interpolation.
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct AnisotropicTabulated {
    /// Shared (not copied) with the models made by `as_model`.
    inner: MeasuredAnisotropic,
}

impl AnisotropicTabulated {
    /// The table as a model (shares the table).
    pub fn measured(&self) -> &MeasuredAnisotropic {
        &self.inner
    }

    fn wrap(t: CoreAniso) -> Self {
        Self { inner: MeasuredAnisotropic(Arc::new(t)) }
    }
}

/// `scale` for the `.dat` reader and writer, checked here so that the message names it.
fn mit_scale(scale: f64) -> PyResult<f32> {
    let s = scale as f32;
    if !(s.is_finite() && s > 0.0) {
        return Err(invalid(format!("scale: must be finite and > 0, got {scale}")));
    }
    Ok(s)
}

#[pymethods]
impl AnisotropicTabulated {
    /// From float32 C-contiguous values of shape `(n_theta_in, n_theta_out, n_phi_diff, n_phi_in, 3)` and
    /// an optional bool mask of shape `(n_theta_in, n_theta_out, n_phi_diff, n_phi_in)` of the cells that
    /// have data.
    #[new]
    #[pyo3(signature = (values, valid=None, half_data=false))]
    fn new(
        py: Python<'_>,
        values: PyReadonlyArrayDyn<'_, f32>,
        valid: Option<PyReadonlyArrayDyn<'_, bool>>,
        half_data: bool,
    ) -> PyResult<Self> {
        let shape = values.shape().to_vec();
        if shape.len() != 5 || shape[4] != 3 {
            return Err(invalid(format!(
                "values: expected shape (n_theta_in, n_theta_out, n_phi_diff, n_phi_in, 3), got {shape:?}"
            )));
        }
        let flat = values
            .as_slice()
            .map_err(|_| PyTypeError::new_err("values: expected a C-contiguous float32 array"))?;
        let dims = [shape[0], shape[1], shape[2], shape[3]];
        let mask = match &valid {
            Some(m) => {
                if m.shape() != &shape[..4] {
                    return Err(invalid(format!(
                        "valid: expected shape {:?} (one flag per cell), got {:?}",
                        &shape[..4],
                        m.shape()
                    )));
                }
                Some(
                    m.as_slice()
                        .map_err(|_| PyTypeError::new_err("valid: expected a C-contiguous bool array"))?
                        .to_vec(),
                )
            }
            None => None,
        };
        let data: Vec<Vec3> = bytemuck::cast_slice::<f32, Vec3>(flat).to_vec();
        let inner = run(py, data.len(), || CoreAniso::new(dims, half_data, data, mask))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// Tabulate `model` at the bin centres of `dims = (n_theta_in, n_theta_out, n_phi_diff, n_phi_in)`.
    #[staticmethod]
    #[pyo3(signature = (model, dims, half_data=false))]
    fn from_model(
        py: Python<'_>,
        model: PyRef<'_, Model>,
        dims: (usize, usize, usize, usize),
        half_data: bool,
    ) -> PyResult<Self> {
        let m = model.core().clone();
        let d = [dims.0, dims.1, dims.2, dims.3];
        let work = d.iter().fold(1usize, |a, &x| a.saturating_mul(x));
        let inner = run(py, work, || CoreAniso::from_model(&m, d, half_data))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// Parse the bytes of a MIT CSAIL `.dat` file, values multiplied by `scale`.
    #[staticmethod]
    #[pyo3(signature = (data, scale=1.0))]
    fn from_mit_bytes(py: Python<'_>, data: &[u8], scale: f64) -> PyResult<Self> {
        let s = mit_scale(scale)?;
        let inner = run(py, data.len(), || CoreAniso::read_mit(data, s))?.map_err(to_py)?;
        Ok(Self::wrap(inner))
    }

    /// The table as a MIT CSAIL `.dat` file, values divided by `scale`.
    #[pyo3(signature = (scale=1.0))]
    fn to_mit_bytes<'py>(&self, py: Python<'py>, scale: f64) -> PyResult<Bound<'py, PyBytes>> {
        let out = self.inner.0.write_mit(mit_scale(scale)?).map_err(to_py)?;
        Ok(PyBytes::new(py, &out))
    }

    /// `(n_theta_in, n_theta_out, n_phi_diff, n_phi_in)`.
    #[getter]
    fn dims(&self) -> (usize, usize, usize, usize) {
        let d = self.inner.0.dims();
        (d[0], d[1], d[2], d[3])
    }

    /// Whether phi_diff covers [0, π) (reciprocity gives the rest).
    #[getter]
    fn half_data(&self) -> bool {
        self.inner.0.half_data()
    }

    /// The fraction of the cells that have data.
    #[getter]
    fn coverage(&self) -> f64 {
        self.inner.0.coverage()
    }

    /// A float32 copy of the values, shape `dims + (3,)` (0 in cells without data).
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let d = self.inner.0.dims();
        let flat: &[f32] = bytemuck::cast_slice(self.inner.0.data());
        PyArray1::from_slice(py, flat).reshape(vec![d[0], d[1], d[2], d[3], 3])
    }

    /// A bool copy of the mask of the cells that have data, shape `dims`.
    #[getter]
    fn valid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<bool>>> {
        let d = self.inner.0.dims();
        PyArray1::from_slice(py, self.inner.0.valid()).reshape(vec![d[0], d[1], d[2], d[3]])
    }

    /// Batch look-up: float32 C-contiguous `(..., 3)` arrays whose leading shapes broadcast; the table's
    /// frame is (tangent, n × tangent, n), the tangent arbitrary when not given.
    #[pyo3(signature = (l, v, n, tangent=None))]
    fn _eval<'py>(
        &self,
        py: Python<'py>,
        l: PyReadonlyArrayDyn<'py, f32>,
        v: PyReadonlyArrayDyn<'py, f32>,
        n: PyReadonlyArrayDyn<'py, f32>,
        tangent: Option<PyReadonlyArrayDyn<'py, f32>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let t = crate::arrays::vec3_opt("tangent", &tangent)?;
        let dirs = Directions::from_args(vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, t).map_err(to_py)?;
        outputs::<Vec3>(py, dirs.shape(), |out| evaluate_bxdf(&self.inner, &dirs, Quantity::Brdf, out))
    }

    fn __repr__(&self) -> String {
        let d = self.inner.0.dims();
        format!(
            "brdfpy.measured.AnisotropicTabulated(dims=({}, {}, {}, {}), half_data={}, coverage={:.3})",
            d[0],
            d[1],
            d[2],
            d[3],
            if self.inner.0.half_data() { "True" } else { "False" },
            self.inner.0.coverage()
        )
    }
}

/// The core model of a data-driven `brdfpy.Model` (`Model(name, _table=table)`): a `Tabulated`
/// (`"measured"`), an `AnisotropicTabulated` (`"measured_anisotropic"`) or an `RglBsdf` (`"rgl_bsdf"`),
/// sharing its data.
pub fn data_model(name: &str, table: &Bound<'_, PyAny>) -> PyResult<brdf_core::Model> {
    let m = if let Ok(t) = table.cast::<Tabulated>() {
        brdf_core::Model::Measured(t.get().measured().clone())
    } else if let Ok(t) = table.cast::<AnisotropicTabulated>() {
        brdf_core::Model::MeasuredAnisotropic(t.get().measured().clone())
    } else if let Ok(r) = table.cast::<RglBsdf>() {
        brdf_core::Model::MeasuredRgl(MeasuredRgl(r.get().inner.clone()))
    } else {
        return Err(PyTypeError::new_err(
            "_table: expected a measured table (Tabulated, AnisotropicTabulated or RglBsdf of brdfpy._brdfpy)",
        ));
    };
    if m.spec().name != name {
        return Err(invalid(format!(
            "_table: a {} table makes Model({:?}, _table=...), not {name:?}",
            m.spec().name,
            m.spec().name
        )));
    }
    Ok(m)
}

/// The names of the data-driven models (built from data, not by name).
pub const DATA_MODELS: [&str; 3] = ["measured", "measured_anisotropic", "rgl_bsdf"];

/// A data-driven model's data as `(name, file bytes)` for pickling (`None` for the others and for
/// `"measured"`, which pickles by its table): the `.dat` and `.bsdf` writers round-trip bit for bit.
pub fn data_source(m: &brdf_core::Model) -> PyResult<Option<(&'static str, Vec<u8>)>> {
    Ok(match m {
        brdf_core::Model::MeasuredAnisotropic(t) => {
            Some(("measured_anisotropic", t.0.write_mit(1.0).map_err(to_py)?))
        }
        brdf_core::Model::MeasuredRgl(r) => Some(("rgl_bsdf", r.0.write())),
        _ => None,
    })
}

/// A [`Coverage`] as a dict of its fields.
fn coverage_dict<'py>(py: Python<'py>, c: &Coverage) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("samples", c.samples)?;
    d.set_item("nodes", c.nodes)?;
    d.set_item("below_horizon", c.below_horizon)?;
    d.set_item("covered", c.covered)?;
    d.set_item("filled", c.filled)?;
    d.set_item("max_fill_distance", c.max_fill_distance)?;
    d.set_item("fraction", c.fraction())?;
    Ok(d)
}

/// The rows of a CSV of `theta_i, phi_i, theta_o, phi_o, R, G, B`
/// (`brdf_core::measured::samples::read_samples_csv`): `(l, v, values)`, float32 `(count, 3)` each,
/// normal +z. `angles` is `"degrees"` or `"radians"`.
#[pyfunction]
pub fn read_samples_csv_bytes<'py>(
    py: Python<'py>,
    data: &[u8],
    angles: &str,
) -> PyResult<SampleColumns<'py>> {
    let unit = AngleUnit::from_name(angles).map_err(to_py)?;
    let s = run(py, data.len(), || read_samples_csv(data, unit))?.map_err(to_py)?;
    let col = |f: fn(&Sample) -> Vec3| -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = s.iter().flat_map(|x| f(x).to_array()).collect();
        PyArray1::from_vec(py, flat).reshape([s.len(), 3])
    };
    Ok((col(|x| x.l)?, col(|x| x.v)?, col(|x| x.f)?))
}

/// An RGL `.bsdf` material (Dupuy & Jakob 2018) evaluated as Mitsuba 3's `measured` plugin does
/// (`brdf_core::measured::RglBsdf`).
#[pyclass(frozen, module = "brdfpy._brdfpy")]
pub struct RglBsdf {
    inner: Arc<CoreRgl>,
}

#[pymethods]
impl RglBsdf {
    /// Parse the bytes of a `.bsdf` file.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        let inner = run(py, data.len(), || CoreRgl::read(data))?.map_err(to_py)?;
        Ok(Self { inner: Arc::new(inner) })
    }

    /// A file of `model` with identity warps (`RglBsdf::from_model`).
    #[staticmethod]
    fn from_model(
        py: Python<'_>,
        model: PyRef<'_, Model>,
        n_theta_i: usize,
        n_phi_i: usize,
        grid: (usize, usize),
    ) -> PyResult<Self> {
        let m = model.core().clone();
        let work = n_theta_i.saturating_mul(n_phi_i.max(1)).saturating_mul(grid.0).saturating_mul(grid.1);
        let inner = run(py, work, || CoreRgl::from_model(&m, n_theta_i, n_phi_i, grid))?.map_err(to_py)?;
        Ok(Self { inner: Arc::new(inner) })
    }

    /// The `.bsdf` file's bytes.
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.inner.write())
    }

    /// Resample the material onto a 4-D `(θ_in, θ_out, φ_diff, φ_in)` table (`RglBsdf::eval` at the bin
    /// centres, tangent +x).
    fn to_anisotropic(
        &self,
        py: Python<'_>,
        dims: (usize, usize, usize, usize),
    ) -> PyResult<AnisotropicTabulated> {
        let m = brdf_core::Model::MeasuredRgl(MeasuredRgl(self.inner.clone()));
        let d = [dims.0, dims.1, dims.2, dims.3];
        let work = d.iter().fold(1usize, |a, &x| a.saturating_mul(x));
        let t = run(py, work, || CoreAniso::from_model(&m, d, false))?.map_err(to_py)?;
        Ok(AnisotropicTabulated::wrap(t))
    }

    /// Resample an isotropic material onto a half/difference table.
    fn to_tabulated(&self, py: Python<'_>, resolution: (usize, usize, usize)) -> PyResult<Tabulated> {
        let r = self.inner.clone();
        let work = resolution.0.saturating_mul(resolution.1).saturating_mul(resolution.2);
        let t = run(py, work, || r.to_tabulated(resolution))?.map_err(to_py)?;
        Ok(Tabulated::wrap(t))
    }

    /// The material's name.
    #[getter]
    fn description(&self) -> String {
        self.inner.parts().description.clone()
    }

    /// Whether `phi_i` has at most two entries.
    #[getter]
    fn isotropic(&self) -> bool {
        self.inner.is_isotropic()
    }

    /// Whether the values are multiplied by `ndf / (4 sigma)`.
    #[getter]
    fn jacobian(&self) -> bool {
        self.inner.parts().jacobian
    }

    /// The incident polar angles [radians].
    #[getter]
    fn theta_i<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.inner.parts().theta_i)
    }

    /// The incident azimuths [radians].
    #[getter]
    fn phi_i<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.inner.parts().phi_i)
    }

    /// The shape of the `rgb` field: `(n_phi_i, n_theta_i, 3, h, w)`.
    #[getter]
    fn rgb_shape(&self) -> (usize, usize, usize, usize, usize) {
        let p = self.inner.parts();
        (p.phi_i.len(), p.theta_i.len(), 3, p.rgb.0.0, p.rgb.0.1)
    }

    /// Batch evaluation: `f_r` [1/sr] (`quantity="brdf"`) or Mitsuba's sampling density [1/sr]
    /// (`"pdf"`, in the first of the three channels) for float32 `(..., 3)` arrays that broadcast.
    #[pyo3(signature = (l, v, n, tangent=None, quantity="brdf"))]
    fn _eval<'py>(
        &self,
        py: Python<'py>,
        l: PyReadonlyArrayDyn<'py, f32>,
        v: PyReadonlyArrayDyn<'py, f32>,
        n: PyReadonlyArrayDyn<'py, f32>,
        tangent: Option<PyReadonlyArrayDyn<'py, f32>>,
        quantity: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let pdf = match quantity {
            "brdf" => false,
            "pdf" => true,
            _ => return Err(invalid(format!("quantity: expected \"brdf\" or \"pdf\", got {quantity:?}"))),
        };
        let args =
            (vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, crate::arrays::vec3_opt("tangent", &tangent)?);
        for (name, a) in [("l", &args.0), ("v", &args.1), ("n", &args.2)]
            .into_iter()
            .chain(args.3.as_ref().map(|t| ("tangent", t)))
        {
            let flat: &[f32] = bytemuck::cast_slice(a.data());
            if let Some(i) = flat.iter().position(|x| !x.is_finite()) {
                return Err(invalid(format!("{name}: non-finite value in row {}", i / 3)));
            }
        }
        let dirs = Directions::from_args(args.0, args.1, args.2, args.3).map_err(to_py)?;
        let r = self.inner.clone();
        outputs::<Vec3>(py, dirs.shape(), move |out| {
            for (i, o) in out.iter_mut().enumerate() {
                *o = match dirs.geometry(i) {
                    Some(g) if pdf => Vec3::new(r.pdf(&g), 0.0, 0.0),
                    Some(g) => r.eval(&g),
                    None => Vec3::ZERO,
                };
            }
            Ok(())
        })
    }

    fn __repr__(&self) -> String {
        let (np, nt, _, h, w) = self.rgb_shape();
        format!(
            "brdfpy.measured.RglBsdf({:?}, {}, phi_i x theta_i = {np} x {nt}, grid {h} x {w})",
            self.inner.parts().description,
            if self.inner.is_isotropic() { "isotropic" } else { "anisotropic" }
        )
    }
}

/// A fit's per-parameter numbers as a dict: name → float, or a 3-tuple for a colour.
fn values_dict<'py>(py: Python<'py>, vals: &[(String, Vec<f64>)]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, x) in vals {
        if x.len() == 1 {
            d.set_item(k, x[0])?;
        } else {
            d.set_item(k, (x[0], x[1], x[2]))?;
        }
    }
    Ok(d)
}

/// Fit registry model `name` to samples `(l, v, n, values)` (float32 `(..., 3)` arrays that broadcast)
/// with `brdf_core::fit::fit_model`: every continuous parameter free unless in `fixed`. Returns a dict
/// (see `brdfpy.measured.FitReport`). The GIL is released during the fit.
#[pyfunction]
#[pyo3(signature = (name, l, v, n, values, weights=None, fixed=None, start=None, loss="log", multistart=None, choices=None, max_iterations=None, jacobian="auto", tangent=None))]
#[allow(clippy::too_many_arguments)]
pub fn fit_model<'py>(
    py: Python<'py>,
    name: &str,
    l: PyReadonlyArrayDyn<'py, f32>,
    v: PyReadonlyArrayDyn<'py, f32>,
    n: PyReadonlyArrayDyn<'py, f32>,
    values: PyReadonlyArrayDyn<'py, f32>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
    fixed: Option<&Bound<'py, PyDict>>,
    start: Option<&Bound<'py, PyDict>>,
    loss: &str,
    multistart: Option<&Bound<'py, PyAny>>,
    choices: Option<&Bound<'py, PyDict>>,
    max_iterations: Option<&Bound<'py, PyAny>>,
    jacobian: &str,
    tangent: Option<PyReadonlyArrayDyn<'py, f32>>,
) -> PyResult<Bound<'py, PyDict>> {
    let jacobian = match jacobian {
        "auto" => Jacobian::Auto,
        "finite_difference" => Jacobian::FiniteDifference,
        _ => {
            return Err(invalid(format!(
                "jacobian: expected \"auto\" or \"finite_difference\", got {jacobian:?}"
            )));
        }
    };
    // Any int from Python, checked here (pyo3's usize conversion would raise OverflowError naming nothing).
    let max_iterations = match max_iterations {
        Some(k) => crate::errors::integer("max_iterations", k, 1, 100_000)? as usize,
        None => FitOptions::default().max_iterations,
    };
    let multistart = match multistart {
        Some(k) => crate::errors::integer("multistart", k, 0, 1024)? as usize,
        None => FitOptions::default().multistart,
    };
    let t = crate::arrays::vec3_opt("tangent", &tangent)?;
    let has_t = t.is_some();
    let b = Batch::new((vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, vec3("values", &values)?, t))
        .map_err(to_py)?;
    let rows = b.map(|s: (Vec3, Vec3, Vec3, Vec3, Option<Vec3>)| s).to_vec().map_err(to_py)?;
    let tangents: Option<Vec<Vec3>> = has_t.then(|| rows.iter().map(|r| r.4.unwrap_or(Vec3::ZERO)).collect());
    let samples: Vec<Sample> = rows.into_iter().map(|(l, v, n, f, _)| Sample { l, v, n, f }).collect();
    let weights = match &weights {
        Some(w) => Some(
            w.as_slice()
                .map_err(|_| PyTypeError::new_err("weights: expected a C-contiguous float64 array"))?
                .to_vec(),
        ),
        None => None,
    };
    let mut search = Vec::new();
    if let Some(c) = choices {
        for (k, vals) in c.iter() {
            let key: String =
                k.extract().map_err(|_| PyTypeError::new_err("choices: parameter names must be strings"))?;
            let list: Vec<String> = vals.extract().map_err(|_| {
                PyTypeError::new_err(format!("choices: {key:?} must map to a list of names (str)"))
            })?;
            search.push((key, list));
        }
    }
    let options = FitOptions {
        fixed: to_inputs(fixed)?,
        start: to_inputs(start)?,
        loss: Loss::from_name(loss).map_err(to_py)?,
        weights,
        tangents,
        multistart,
        choices: search,
        max_iterations,
        jacobian,
        ..FitOptions::default()
    };
    let name = name.to_string();
    let res = run(py, usize::MAX, || fit::fit_model(&name, &samples, &options))?.map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("values", values_dict(py, &res.values)?)?;
    d.set_item("stderr", values_dict(py, &res.stderr)?)?;
    d.set_item("stderr_robust", values_dict(py, &res.stderr_robust)?)?;
    d.set_item("at_bound", res.at_bound.clone())?;
    d.set_item("inactive", res.inactive.clone())?;
    let ch = PyDict::new(py);
    for (k, v) in &res.choices {
        ch.set_item(k, v)?;
    }
    d.set_item("choices", ch)?;
    d.set_item("loss", res.loss.name())?;
    d.set_item("cost", res.cost)?;
    let per: Vec<(f64, f64, f64)> = res.channels.iter().map(|c| (c.rms, c.max, c.relative_l2)).collect();
    d.set_item("channels", per)?;
    d.set_item("rms_log_error", res.rms_log_error)?;
    d.set_item("epsilon", res.epsilon)?;
    d.set_item("iterations", res.iterations)?;
    d.set_item("converged", res.converged)?;
    d.set_item("message", res.message.clone())?;
    d.set_item("samples_used", res.samples_used)?;
    d.set_item("starts", res.starts)?;
    let tried: Vec<(Vec<(String, String)>, f64)> = res.tried.clone();
    d.set_item("tried", tried)?;
    d.set_item("jacobian", res.jacobian)?;
    Ok(d)
}

/// The `(l, v, values)` columns of drawn samples, each `(count, 3)`.
type SampleColumns<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>);

/// How to draw samples from a table, from Python's arguments (checked, naming them).
fn sampling(
    count: &Bound<'_, PyAny>,
    seed: &Bound<'_, PyAny>,
    max_theta: f64,
    strategy: &str,
) -> PyResult<TableSampling> {
    Ok(TableSampling {
        count: crate::errors::integer("samples", count, 16, 10_000_000)? as usize,
        seed: crate::errors::integer("seed", seed, 0, i64::MAX)? as u64,
        max_theta_deg: max_theta as f32,
        strategy: Strategy::from_name(strategy).map_err(to_py)?,
    })
}

/// The `(l, v, values)` columns of drawn samples.
fn sample_columns<'py>(py: Python<'py>, s: &[Sample]) -> PyResult<SampleColumns<'py>> {
    let col = |f: fn(&Sample) -> Vec3| -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = s.iter().flat_map(|x| f(x).to_array()).collect();
        PyArray1::from_vec(py, flat).reshape([s.len(), 3])
    };
    Ok((col(|x| x.l)?, col(|x| x.v)?, col(|x| x.f)?))
}

/// Samples of a table for a fit (`brdf_core::fit::table_samples`): `(l, v, values)`, float32 `(count, 3)`
/// each, normal +z.
#[pyfunction]
#[pyo3(signature = (table, count, seed, max_theta, strategy))]
pub fn table_samples<'py>(
    py: Python<'py>,
    table: PyRef<'py, Tabulated>,
    count: &Bound<'py, PyAny>,
    seed: &Bound<'py, PyAny>,
    max_theta: f64,
    strategy: &str,
) -> PyResult<SampleColumns<'py>> {
    let how = sampling(count, seed, max_theta, strategy)?;
    let t = table.inner.0.clone();
    let s = run(py, how.count, || fit::table_samples(&t, &how))?.map_err(to_py)?;
    sample_columns(py, &s)
}

/// Samples of an anisotropic table for a fit (`brdf_core::fit::aniso_table_samples`): `(l, v, values)`,
/// float32 `(count, 3)` each, normal +z, tangent +x.
#[pyfunction]
#[pyo3(signature = (table, count, seed, max_theta, strategy))]
pub fn aniso_table_samples<'py>(
    py: Python<'py>,
    table: PyRef<'py, AnisotropicTabulated>,
    count: &Bound<'py, PyAny>,
    seed: &Bound<'py, PyAny>,
    max_theta: f64,
    strategy: &str,
) -> PyResult<SampleColumns<'py>> {
    let how = sampling(count, seed, max_theta, strategy)?;
    let t = table.inner.0.clone();
    let s = run(py, how.count, || fit::aniso_table_samples(&t, &how))?.map_err(to_py)?;
    sample_columns(py, &s)
}

/// A float64 C-contiguous `(N, 3)` array viewed as `&[DVec3]` (N may be 0).
fn dvec3_view<'a>(name: &str, a: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [DVec3]> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(invalid(format!("{name}: expected shape (N, 3), got ({}, {})", shape[0], shape[1])));
    }
    let s = a
        .as_slice()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float64 array")))?;
    if let Some(i) = s.iter().position(|x| !x.is_finite()) {
        return Err(invalid(format!("{name}: non-finite value in row {}", i / 3)));
    }
    Ok(bytemuck::cast_slice(s))
}

fn check_order(order: usize) -> PyResult<()> {
    if order > sh::MAX_ORDER {
        return Err(invalid(format!("order: must be in [0, {}], got {order}", sh::MAX_ORDER)));
    }
    Ok(())
}

/// `Y_i(dir)` for every direction (rows) and coefficient `i < (order+1)²` (columns), float64.
#[pyfunction]
pub fn sh_basis<'py>(
    py: Python<'py>,
    dirs: PyReadonlyArray2<'py, f64>,
    order: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    check_order(order)?;
    let ds = dvec3_view("directions", &dirs)?;
    let nc = sh::num_coeffs(order);
    let out = PyArray2::<f64>::zeros(py, [ds.len(), nc], false);
    {
        let mut w = out.readwrite();
        let o = w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        run(py, o.len(), || sh::basis_rows(ds, order, o))?.map_err(to_py)?;
    }
    Ok(out)
}

/// Quadrature directions `(M, 3)` and weights `(M,)`.
type NodesWeights<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// The hemisphere-split Gauss–Legendre × uniform-φ rule: `(directions (M, 3), weights (M,))`.
#[pyfunction]
pub fn sh_quadrature<'py>(py: Python<'py>, n_mu: usize, n_phi: usize) -> PyResult<NodesWeights<'py>> {
    let q = sh::Quadrature::new(n_mu, n_phi).map_err(to_py)?;
    let flat: &[f64] = bytemuck::cast_slice(&q.dirs);
    let dirs = PyArray1::from_slice(py, flat).reshape([q.len(), 3])?;
    Ok((dirs, PyArray1::from_vec(py, q.weights)))
}

/// `c_i = Σ_k w_k f_k Y_i(ω_k)` for RGB values `(M, 3)` at directions `(M, 3)` with weights `(M,)`.
#[pyfunction]
pub fn sh_project<'py>(
    py: Python<'py>,
    values: PyReadonlyArray2<'py, f64>,
    dirs: PyReadonlyArray2<'py, f64>,
    weights: PyReadonlyArray1<'py, f64>,
    order: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    check_order(order)?;
    let vs = dvec3_view("values", &values)?;
    let ds = dvec3_view("directions", &dirs)?;
    let ws =
        weights.as_slice().map_err(|_| PyTypeError::new_err("weights: expected a C-contiguous array"))?;
    if ds.len() != ws.len() || ds.is_empty() {
        return Err(invalid(format!(
            "weights: expected one weight per direction ({}), got {}",
            ds.len(),
            ws.len()
        )));
    }
    if let Some(i) = ws.iter().position(|x| !x.is_finite()) {
        return Err(invalid(format!("weights: non-finite value at index {i}")));
    }
    let q = sh::Quadrature { dirs: ds.to_vec(), weights: ws.to_vec() };
    let work = vs.len().saturating_mul(sh::num_coeffs(order));
    let c = run(py, work, || sh::project_values(vs, &q, order))?.map_err(to_py)?;
    let flat: &[f64] = bytemuck::cast_slice(&c);
    PyArray1::from_slice(py, flat).reshape([c.len(), 3])
}

/// `Σ_i c_i Y_i(ω)` for RGB coefficients `((L+1)², 3)` at directions `(N, 3)`.
#[pyfunction]
pub fn sh_reconstruct<'py>(
    py: Python<'py>,
    coeffs: PyReadonlyArray2<'py, f64>,
    dirs: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let cs = dvec3_view("coeffs", &coeffs)?;
    let ds = dvec3_view("directions", &dirs)?;
    let work = cs.len().saturating_mul(ds.len());
    let r = run(py, work, || sh::reconstruct(cs, ds))?.map_err(to_py)?;
    let flat: &[f64] = bytemuck::cast_slice(&r);
    PyArray1::from_slice(py, flat).reshape([r.len(), 3])
}

/// Ramamoorthi–Hanrahan's `Â_l` of the clamped cosine, in closed form.
#[pyfunction]
pub fn sh_clamped_cosine_zonal(l: usize) -> f64 {
    sh::clamped_cosine_zonal(l)
}

/// The highest supported SH order.
#[pyfunction]
pub fn sh_max_order() -> usize {
    sh::MAX_ORDER
}
