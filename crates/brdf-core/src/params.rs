//! Model parameters: a declarative spec per model (name, kind, default, range, unit, doc) so that the
//! factory can validate any input and Python can list every model's parameters.

use std::borrow::Cow;

use glam::Vec3;

use crate::BrdfError;

/// What a parameter holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKind {
    /// One real number.
    Scalar,
    /// A linear RGB triple; a single number is broadcast to gray.
    Color,
    /// One of a fixed set of names.
    Choice(&'static [&'static str]),
    /// true / false.
    Bool,
    /// A flat list of rows of `width` numbers (e.g. Lafortune lobes `[cx, cy, cz, n]`).
    Array {
        /// Numbers per row.
        width: usize,
    },
}

/// A validated parameter value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// See [`ParamKind::Scalar`].
    Scalar(f32),
    /// See [`ParamKind::Color`].
    Color([f32; 3]),
    /// See [`ParamKind::Choice`]; always one of the spec's choices.
    Choice(&'static str),
    /// See [`ParamKind::Bool`].
    Bool(bool),
    /// See [`ParamKind::Array`]; length is a multiple of the width.
    Array(Cow<'static, [f32]>),
}

/// A value as a caller gives it, before validation against a [`ParamSpec`].
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A number.
    Number(f64),
    /// A sequence of numbers (a color, or a flattened array).
    Numbers(Vec<f64>),
    /// A name.
    Text(String),
    /// A flag.
    Bool(bool),
}

/// One parameter of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamSpec {
    /// Name as used by the factory and Python keywords.
    pub name: &'static str,
    /// What it holds.
    pub kind: ParamKind,
    /// Value used when the caller gives none.
    pub default: Value,
    /// Inclusive lower bound of every number (ignored for choices and flags).
    pub min: f32,
    /// Inclusive upper bound of every number.
    pub max: f32,
    /// Unit or meaning of the numbers ("1", "radians", "reflectance", ...).
    pub unit: &'static str,
    /// One-line description.
    pub doc: &'static str,
    /// A different default when another parameter has a given value (see [`DerivedDefault`]).
    pub derived_default: Option<DerivedDefault>,
}

/// A default that depends on another (choice) parameter: when the caller does not give this parameter
/// and the choice `when` is not `unless`, the default is `value`. E.g. Cook–Torrance's diffuse `kd` is
/// a plastic's by default but 0 once a metal preset is chosen (a metal has no diffuse term); a `kd`
/// the caller gives is always kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerivedDefault {
    /// The choice parameter this default depends on.
    pub when: &'static str,
    /// The value of `when` that keeps the ordinary default.
    pub unless: &'static str,
    /// The default otherwise.
    pub value: DerivedValue,
}

/// The value of a [`DerivedDefault`] (numbers only: a plain `Copy` type, so specs stay `const`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DerivedValue {
    /// See [`Value::Scalar`].
    Scalar(f32),
    /// See [`Value::Color`].
    Color([f32; 3]),
}

impl From<DerivedValue> for Value {
    fn from(v: DerivedValue) -> Self {
        match v {
            DerivedValue::Scalar(x) => Value::Scalar(x),
            DerivedValue::Color(c) => Value::Color(c),
        }
    }
}

impl ParamSpec {
    /// A scalar parameter in `[min, max]`.
    pub const fn scalar(
        name: &'static str,
        default: f32,
        min: f32,
        max: f32,
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            kind: ParamKind::Scalar,
            default: Value::Scalar(default),
            min,
            max,
            unit,
            doc,
            derived_default: None,
        }
    }

    /// An RGB parameter with every channel in `[min, max]`.
    pub const fn color(
        name: &'static str,
        default: [f32; 3],
        min: f32,
        max: f32,
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            kind: ParamKind::Color,
            default: Value::Color(default),
            min,
            max,
            unit,
            doc,
            derived_default: None,
        }
    }

    /// A choice among `choices`, defaulting to `default` (which must be one of them).
    pub const fn choice(
        name: &'static str,
        choices: &'static [&'static str],
        default: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            kind: ParamKind::Choice(choices),
            default: Value::Choice(default),
            min: 0.0,
            max: 0.0,
            unit: "",
            doc,
            derived_default: None,
        }
    }

    /// A flag.
    pub const fn flag(name: &'static str, default: bool, doc: &'static str) -> Self {
        Self {
            name,
            kind: ParamKind::Bool,
            default: Value::Bool(default),
            min: 0.0,
            max: 0.0,
            unit: "",
            doc,
            derived_default: None,
        }
    }

    /// A flat array of rows of `width` numbers, each in `[min, max]`.
    pub const fn array(
        name: &'static str,
        width: usize,
        default: &'static [f32],
        min: f32,
        max: f32,
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            kind: ParamKind::Array { width },
            default: Value::Array(Cow::Borrowed(default)),
            min,
            max,
            unit,
            doc,
            derived_default: None,
        }
    }

    fn check_number(&self, x: f64) -> Result<f32, BrdfError> {
        if !x.is_finite() {
            return Err(BrdfError::param(self.name, format!("must be finite, got {x}")));
        }
        let (lo, hi) = (f64::from(self.min), f64::from(self.max));
        if x < lo || x > hi {
            return Err(BrdfError::param(
                self.name,
                format!("must be in [{lo}, {hi}] ({}), got {x}", self.unit),
            ));
        }
        Ok(x as f32)
    }

    /// Validate a caller's input against this spec.
    pub fn validate(&self, input: &Input) -> Result<Value, BrdfError> {
        let wrong = |what: &str| BrdfError::param(self.name, format!("expected {what}, got {input:?}"));
        match (self.kind, input) {
            (ParamKind::Scalar, Input::Number(x)) => Ok(Value::Scalar(self.check_number(*x)?)),
            (ParamKind::Scalar, Input::Numbers(xs)) if xs.len() == 1 => {
                Ok(Value::Scalar(self.check_number(xs[0])?))
            }
            (ParamKind::Scalar, _) => Err(wrong("a number")),
            (ParamKind::Color, Input::Number(x)) => {
                let c = self.check_number(*x)?;
                Ok(Value::Color([c; 3]))
            }
            (ParamKind::Color, Input::Numbers(xs)) if xs.len() == 3 || xs.len() == 1 => {
                let c: Vec<f32> = xs.iter().map(|&x| self.check_number(x)).collect::<Result<_, _>>()?;
                Ok(Value::Color(if c.len() == 1 { [c[0]; 3] } else { [c[0], c[1], c[2]] }))
            }
            (ParamKind::Color, _) => Err(wrong("a number or 3 numbers (linear RGB)")),
            (ParamKind::Choice(choices), Input::Text(s)) => {
                let key = s.to_ascii_lowercase();
                choices.iter().find(|c| **c == key).map(|c| Value::Choice(c)).ok_or_else(|| {
                    BrdfError::param(self.name, format!("expected one of {}, got {s:?}", choices.join(", ")))
                })
            }
            (ParamKind::Choice(choices), _) => Err(wrong(&format!("one of {}", choices.join(", ")))),
            (ParamKind::Bool, Input::Bool(b)) => Ok(Value::Bool(*b)),
            (ParamKind::Bool, _) => Err(wrong("true or false")),
            (ParamKind::Array { width }, Input::Numbers(xs)) => {
                if xs.is_empty() || xs.len() % width != 0 {
                    return Err(BrdfError::param(
                        self.name,
                        format!(
                            "expected a non-empty list of rows of {width} numbers, got {} numbers",
                            xs.len()
                        ),
                    ));
                }
                let v: Vec<f32> = xs.iter().map(|&x| self.check_number(x)).collect::<Result<_, _>>()?;
                Ok(Value::Array(Cow::Owned(v)))
            }
            (ParamKind::Array { width }, _) => Err(wrong(&format!("rows of {width} numbers"))),
        }
    }
}

/// Everything the registry knows about a model.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSpec {
    /// Registry name (`brdfpy.model(name)`).
    pub name: &'static str,
    /// One-line summary with the formula.
    pub summary: &'static str,
    /// Where the formula comes from (paper or book, with section or equation where it helps).
    pub source: &'static str,
    /// `true` for BRDFs in 1/sr that should be reciprocal and energy-conserving; `false` for the
    /// classic (textbook) shading formulas, offered exactly as written.
    pub physical: bool,
    /// `true` when the model is anisotropic and reads the tangent.
    pub anisotropic: bool,
    /// The parameters, in documentation order.
    pub params: &'static [ParamSpec],
}

/// Validated parameters of one model: every spec'd parameter has a value.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    model: &'static str,
    values: Vec<(&'static str, Value)>,
}

impl Params {
    /// Validate `inputs` against `spec`, filling defaults; unknown names are errors.
    pub fn resolve(spec: &ModelSpec, inputs: &[(String, Input)]) -> Result<Self, BrdfError> {
        for (name, _) in inputs {
            if !spec.params.iter().any(|p| p.name == name) {
                let known = spec.params.iter().map(|p| p.name).collect::<Vec<_>>().join(", ");
                return Err(match crate::models::renamed_param(spec, name) {
                    Some(r) => BrdfError::RenamedParameter {
                        model: spec.name,
                        name: name.clone(),
                        new: r.new,
                        what: r.what,
                        known,
                    },
                    None => BrdfError::UnknownParameter { model: spec.name, name: name.clone(), known },
                });
            }
        }
        let mut values = Vec::with_capacity(spec.params.len());
        for p in spec.params {
            let v = match inputs.iter().rev().find(|(n, _)| n == p.name) {
                Some((_, input)) => p.validate(input)?,
                None => p.default.clone(),
            };
            values.push((p.name, v));
        }
        let mut params = Self { model: spec.name, values };
        params.derive_defaults(spec, inputs);
        Ok(params)
    }

    /// The defaults of `spec`.
    pub fn defaults(spec: &ModelSpec) -> Self {
        let mut params = Self {
            model: spec.name,
            values: spec.params.iter().map(|p| (p.name, p.default.clone())).collect(),
        };
        params.derive_defaults(spec, &[]);
        params
    }

    /// Apply the [`DerivedDefault`]s of the parameters the caller did not give.
    fn derive_defaults(&mut self, spec: &ModelSpec, inputs: &[(String, Input)]) {
        for p in spec.params {
            let Some(d) = &p.derived_default else { continue };
            let given = inputs.iter().any(|(n, _)| n == p.name);
            if !given && self.get(d.when) != &Value::Choice(d.unless) {
                self.set(p.name, d.value.into());
            }
        }
    }

    /// All values in spec order.
    pub fn values(&self) -> &[(&'static str, Value)] {
        &self.values
    }

    fn get(&self, name: &str) -> &Value {
        match self.values.iter().find(|(n, _)| *n == name) {
            Some((_, v)) => v,
            // A model asking for a parameter it did not declare is a bug in that model, caught by its tests.
            None => panic!("model {} reads undeclared parameter {name}", self.model),
        }
    }

    /// A scalar parameter.
    pub fn scalar(&self, name: &str) -> f32 {
        match self.get(name) {
            Value::Scalar(x) => *x,
            other => panic!("parameter {name} of {} is {other:?}, not a scalar", self.model),
        }
    }

    /// A color parameter.
    pub fn color(&self, name: &str) -> Vec3 {
        match self.get(name) {
            Value::Color(c) => Vec3::from_array(*c),
            other => panic!("parameter {name} of {} is {other:?}, not a color", self.model),
        }
    }

    /// A choice parameter.
    pub fn choice(&self, name: &str) -> &'static str {
        match self.get(name) {
            Value::Choice(c) => c,
            other => panic!("parameter {name} of {} is {other:?}, not a choice", self.model),
        }
    }

    /// A flag parameter.
    pub fn flag(&self, name: &str) -> bool {
        match self.get(name) {
            Value::Bool(b) => *b,
            other => panic!("parameter {name} of {} is {other:?}, not a flag", self.model),
        }
    }

    /// An array parameter (flat, row-major).
    pub fn array(&self, name: &str) -> &[f32] {
        match self.get(name) {
            Value::Array(a) => a,
            other => panic!("parameter {name} of {} is {other:?}, not an array", self.model),
        }
    }

    /// The registry name of the model these parameters belong to.
    pub fn model(&self) -> &'static str {
        self.model
    }

    /// The slot of parameter `name` (its index in [`Params::values`], the spec's order), if the
    /// model has it: resolve a name once, then [`Params::set_at`] by slot in a loop.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.values.iter().position(|(n, _)| *n == name)
    }

    /// Replace the value in slot `i` (from [`Params::index_of`]; the caller has validated `value`
    /// against the spec). O(1); out-of-range slots are ignored.
    #[inline]
    pub fn set_at(&mut self, i: usize, value: Value) {
        if let Some(slot) = self.values.get_mut(i) {
            slot.1 = value;
        }
    }

    /// Replace one value (already validated by the caller against the spec).
    pub fn set(&mut self, name: &'static str, value: Value) {
        if let Some(slot) = self.values.iter_mut().find(|(n, _)| *n == name) {
            slot.1 = value;
        }
    }
}
