//! `Model`: a registry model as a Python object with batch `eval` and `shade`; the registry's specs as
//! Python dicts.

use brdf_core::batch::{Directions, Quantity, evaluate_checked};
use brdf_core::{Input, ModelSpec, ParamKind, ParamSpec, Params, Value};
use numpy::PyArrayDyn;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};

use crate::arrays::{f32_array, fill, given_array, new_array, read, vec3, vec3_opt};
use crate::errors::{invalid, to_py};
use glam::Vec3;

/// Names of every registered model, in registry order.
#[pyfunction]
pub fn model_names() -> Vec<&'static str> {
    brdf_core::MODEL_SPECS.iter().map(|s| s.name).collect()
}

/// An `f32` as the Python float with the same shortest decimal form (0.3f32 → 0.3, not 0.30000001192…),
/// so that defaults and resolved parameters read back as they were written — unless that decimal falls
/// outside the parameter's range `[lo, hi]` (e.g. a bound of π/2 in f32, whose shortest decimal is above
/// it in f64): then the exact value, so that every value we report is accepted back.
fn py_float(x: f32, lo: f32, hi: f32) -> f64 {
    let exact = f64::from(x);
    match format!("{x}").parse::<f64>() {
        Ok(short) if short >= f64::from(lo) && short <= f64::from(hi) => short,
        _ => exact,
    }
}

fn value_to_py<'py>(py: Python<'py>, p: Option<&ParamSpec>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    let (lo, hi) = p.map_or((f32::MIN, f32::MAX), |p| (p.min, p.max));
    let kind = p.map_or(ParamKind::Scalar, |p| p.kind);
    let py_float = |x: f32| py_float(x, lo, hi);
    Ok(match v {
        Value::Scalar(x) => py_float(*x).into_pyobject(py)?.into_any(),
        Value::Color(c) => PyTuple::new(py, c.iter().map(|&x| py_float(x)))?.into_any(),
        Value::Choice(c) => PyString::new(py, c).into_any(),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Array(a) => {
            let width = match kind {
                ParamKind::Array { width } if width > 0 => width,
                _ => a.len().max(1),
            };
            let rows: Vec<Vec<f64>> =
                a.chunks(width).map(|r| r.iter().map(|&x| py_float(x)).collect()).collect();
            PyList::new(py, rows)?.into_any()
        }
    })
}

fn kind_name(kind: ParamKind) -> &'static str {
    match kind {
        ParamKind::Scalar => "scalar",
        ParamKind::Color => "color",
        ParamKind::Choice(_) => "choice",
        ParamKind::Bool => "bool",
        ParamKind::Array { .. } => "array",
    }
}

fn param_to_py<'py>(py: Python<'py>, p: &ParamSpec) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", p.name)?;
    d.set_item("kind", kind_name(p.kind))?;
    d.set_item("default", value_to_py(py, Some(p), &p.default)?)?;
    let numeric = matches!(p.kind, ParamKind::Scalar | ParamKind::Color | ParamKind::Array { .. });
    // Bounds are reported so that they pass the range check themselves (it compares in f64).
    d.set_item("min", numeric.then(|| py_float(p.min, p.min, p.max)))?;
    d.set_item("max", numeric.then(|| py_float(p.max, p.min, p.max)))?;
    d.set_item("unit", p.unit)?;
    d.set_item("doc", p.doc)?;
    match p.kind {
        ParamKind::Choice(c) => d.set_item("choices", PyTuple::new(py, c)?)?,
        _ => d.set_item("choices", py.None())?,
    }
    if let ParamKind::Array { width } = p.kind {
        d.set_item("width", width)?;
    }
    Ok(d)
}

fn spec_to_py<'py>(py: Python<'py>, s: &ModelSpec) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", s.name)?;
    d.set_item("summary", s.summary)?;
    d.set_item("source", s.source)?;
    d.set_item("physical", s.physical)?;
    d.set_item("anisotropic", s.anisotropic)?;
    let params = s.params.iter().map(|p| param_to_py(py, p)).collect::<PyResult<Vec<_>>>()?;
    d.set_item("params", PyList::new(py, params)?)?;
    Ok(d)
}

/// Everything the registry knows about model `name`: name, summary, source, physical, anisotropic and
/// params (a list of dicts: name, kind, default, min, max, unit, doc, choices).
#[pyfunction]
pub fn model_spec<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    match brdf_core::models::spec(name) {
        Some(s) => spec_to_py(py, s),
        None => Err(to_py(brdf_core::BrdfError::UnknownModel {
            name: name.to_string(),
            known: model_names().join(", "),
        })),
    }
}

/// Append the numbers of `x` (a number or a nested sequence of numbers, at most `depth` levels deep) to
/// `out`; `widths` records the length of every innermost sequence so that ragged rows are refused.
fn flatten(x: &Bound<'_, PyAny>, depth: usize, out: &mut Vec<f64>, widths: &mut Vec<usize>) -> Option<()> {
    if x.is_instance_of::<PyString>() || x.is_instance_of::<PyBool>() {
        return None;
    }
    if let Ok(f) = x.extract::<f64>() {
        out.push(f);
        return Some(());
    }
    if depth == 0 {
        return None;
    }
    // NumPy arrays become nested lists first; anything else must be a list or a tuple.
    let seq = if x.hasattr("tolist").unwrap_or(false) && x.hasattr("ndim").unwrap_or(false) {
        x.call_method0("tolist").ok()?
    } else {
        x.clone()
    };
    if let Ok(f) = seq.extract::<f64>() {
        out.push(f); // a 0-d array
        return Some(());
    }
    if !(seq.is_instance_of::<PyList>() || seq.is_instance_of::<PyTuple>()) {
        return None;
    }
    let before = out.len();
    let mut nested = false;
    for item in seq.try_iter().ok()? {
        let item = item.ok()?;
        let is_number = item.extract::<f64>().is_ok() && !item.is_instance_of::<PyBool>();
        if !is_number {
            nested = true;
        }
        flatten(&item, depth - 1, out, widths)?;
    }
    if !nested {
        widths.push(out.len() - before);
    }
    Some(())
}

/// A Python parameter value as a core [`Input`]: bool (or `numpy.bool_`), str, a number, or a (nested)
/// sequence or array of numbers.
fn to_input(name: &str, x: &Bound<'_, PyAny>) -> PyResult<Input> {
    if x.is_instance_of::<PyString>() {
        return Ok(Input::Text(x.extract::<String>()?));
    }
    if let Ok(b) = x.extract::<bool>() {
        return Ok(Input::Bool(b));
    }
    if let Ok(f) = x.extract::<f64>() {
        return Ok(Input::Number(f));
    }
    let (mut out, mut widths) = (Vec::new(), Vec::new());
    match flatten(x, 2, &mut out, &mut widths) {
        Some(()) if widths.windows(2).any(|w| w[0] != w[1]) => {
            Err(invalid(format!("parameter {name:?}: rows of different lengths {widths:?}")))
        }
        Some(()) if out.is_empty() => Err(invalid(format!("parameter {name:?}: is empty"))),
        Some(()) => Ok(Input::Numbers(out)),
        None => Err(PyTypeError::new_err(format!(
            "parameter {name:?}: expected a number, a bool, a string or a sequence of numbers, got {}",
            x.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into())
        ))),
    }
}

/// Keyword parameters from Python, in order, each converted by [`to_input`].
pub(crate) fn to_inputs(d: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, Input)>> {
    let mut out = Vec::new();
    if let Some(d) = d {
        for (k, v) in d.iter() {
            let key: String =
                k.extract().map_err(|_| PyTypeError::new_err("parameter names must be strings"))?;
            let input = to_input(&key, &v)?;
            out.push((key, input));
        }
    }
    Ok(out)
}

/// A reflectance model with fixed, validated parameters (`brdfpy.Model` subclasses it).
#[pyclass(frozen, subclass, module = "brdfpy._brdfpy")]
pub struct Model {
    inner: brdf_core::Model,
    params: Params,
}

impl Model {
    /// The core model (for other binding areas, e.g. the BRDF checks).
    pub fn core(&self) -> &brdf_core::Model {
        &self.inner
    }

    /// The resolved parameters the model was built from (for texture bindings, which rebuild it).
    pub fn core_params(&self) -> &Params {
        &self.params
    }
}

#[pymethods]
impl Model {
    /// Build model `name` from keyword parameters; defaults fill the rest.
    #[new]
    #[pyo3(signature = (name, /, **params))]
    fn new(name: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        // A measured model is built from its table (`Tabulated.as_model()` passes it as `_table`), not
        // from registry parameters.
        if let Some(table) = params.map(|d| d.get_item("_table")).transpose()?.flatten() {
            if params.is_some_and(|d| d.len() > 1) {
                return Err(invalid("_table: only for Model(name, _table=...), with no other parameter"));
            }
            let inner = crate::measured::data_model(name, &table)?;
            let params = Params::resolve(inner.spec(), &[]).map_err(to_py)?;
            return Ok(Self { inner, params });
        }
        if crate::measured::DATA_MODELS.contains(&name) {
            return Err(invalid(format!(
                "name: {name:?} is built from a table (its data): brdfpy.measured.Tabulated, \
                 AnisotropicTabulated or RglBsdf (...).as_model()"
            )));
        }
        let inputs = to_inputs(params)?;
        let inner = brdf_core::Model::build(name, &inputs).map_err(to_py)?;
        let params = Params::resolve(inner.spec(), &inputs).map_err(to_py)?;
        Ok(Self { inner, params })
    }

    /// Registry name.
    #[getter]
    fn name(&self) -> &'static str {
        self.inner.spec().name
    }

    /// `True` for BRDFs in 1/sr (reciprocal, energy-conserving); `False` for course formulas.
    #[getter]
    fn physical(&self) -> bool {
        self.inner.spec().physical
    }

    /// `True` when the model reads the tangent.
    #[getter]
    fn anisotropic(&self) -> bool {
        self.inner.spec().anisotropic
    }

    /// Every parameter's resolved value (defaults filled in), in documentation order.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let spec = self.inner.spec();
        for (name, v) in self.params.values() {
            let p = spec.params.iter().find(|p| p.name == *name);
            d.set_item(*name, value_to_py(py, p, v)?)?;
        }
        Ok(d)
    }

    /// Batch evaluation: `l`, `v`, `n` (and `tangent`) are float32 C-contiguous arrays of shape
    /// `(..., 3)` whose leading shapes broadcast together. Returns float32 of the broadcast shape
    /// followed by 3: `f_r` [1/sr], or the shade value when `shade` is true; written into `out` when
    /// given (a float32 C-contiguous array of exactly that shape, not overlapping an input), which is
    /// then returned.
    #[pyo3(signature = (l, v, n, tangent=None, shade=false, out=None))]
    fn _eval<'py>(
        &self,
        py: Python<'py>,
        l: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        n: &Bound<'py, PyAny>,
        tangent: Option<&Bound<'py, PyAny>>,
        shade: bool,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let (l, v, n) = (f32_array("l", l)?, f32_array("v", v)?, f32_array("n", n)?);
        let t = tangent.map(|t| f32_array("tangent", t)).transpose()?;
        let (l, v, n) = (read("l", &l)?, read("v", &v)?, read("n", &n)?);
        let t = t.as_ref().map(|t| read("tangent", t)).transpose()?;
        let (l, v, n, t) = (vec3("l", &l)?, vec3("v", &v)?, vec3("n", &n)?, vec3_opt("tangent", &t)?);
        let dirs = Directions::from_args(l, v, n, t).map_err(to_py)?;
        let q = if shade { Quantity::Shade } else { Quantity::Brdf };
        let out = match out {
            Some(o) => given_array::<Vec3>("out", o, dirs.shape())?,
            None => new_array::<Vec3>(py, dirs.shape())?,
        };
        fill::<Vec3>(py, &out, dirs.len(), |o| evaluate_checked(&self.inner, &dirs, q, o))?;
        Ok(out)
    }

    /// The table of a measured model, float32 `(n_theta_h, n_theta_d, n_phi_d, 3)` (for pickling);
    /// `None` for the other models.
    fn _measured_table<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, numpy::PyArrayDyn<f32>>>> {
        use numpy::PyArrayMethods;
        let brdf_core::Model::Measured(m) = &self.inner else { return Ok(None) };
        let (a, b, c) = m.0.dims();
        let flat: &[f32] = bytemuck::cast_slice(m.0.data());
        Ok(Some(numpy::PyArray1::from_slice(py, flat).reshape(vec![a, b, c, 3])?))
    }

    /// A data-driven model's data for pickling, `(name, file bytes)` (`crate::measured::data_source`), or
    /// `None`.
    fn _data_source<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Option<(&'static str, Bound<'py, pyo3::types::PyBytes>)>> {
        Ok(crate::measured::data_source(&self.inner)?.map(|(k, b)| (k, pyo3::types::PyBytes::new(py, &b))))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        if let brdf_core::Model::MeasuredAnisotropic(m) = &self.inner {
            let d = m.0.dims();
            return Ok(format!(
                "brdfpy.measured.AnisotropicTabulated(dims=({}, {}, {}, {})).as_model()",
                d[0], d[1], d[2], d[3]
            ));
        }
        if let brdf_core::Model::MeasuredRgl(m) = &self.inner {
            return Ok(format!("brdfpy.measured.RglBsdf({:?}).as_model()", m.0.parts().description));
        }
        if let brdf_core::Model::Measured(m) = &self.inner {
            let (a, b, c) = m.0.dims();
            return Ok(format!("brdfpy.measured.Tabulated(shape=({a}, {b}, {c})).as_model()"));
        }
        let mut s = format!("brdfpy.model({:?}", self.inner.spec().name);
        let params = self.params(py)?;
        for (k, v) in params.iter() {
            s.push_str(&format!(", {}={}", k.str()?, v.repr()?));
        }
        s.push(')');
        Ok(s)
    }
}
