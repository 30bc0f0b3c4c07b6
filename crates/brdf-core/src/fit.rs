//! Fitting a registry model's parameters to measured BRDF samples ([`fit_model`]), as Ngan, Durand &
//! Matusik ("Experimental Analysis of BRDF Models", EGSR 2005) fit analytic models to the MERL data.
//!
//! ## What is fitted
//! Every continuous parameter of the model (scalars and RGB colours, each channel of a colour on its
//! own) is free unless it is fixed ([`FitOptions::fixed`]), kept inside its registry range
//! ([`crate::params`]) by projection after every step (so every trial model is one `Model::build`
//! accepts). Parameters that do not change the model under the given choices (the conductor's `eta` when
//! the Fresnel term is Schlick's, a second lobe of weight 0) are held at their defaults and reported as
//! inactive: a parameter counts as inactive when moving it to two other values of its range, at the
//! defaults and the fixed choices and flags, changes no sample's value by more than 1e-5 of the largest
//! one (fixed numbers are left out of the probe, so that fixing a roughness does not switch on a second
//! lobe whose default roughness then differs). A
//! parameter named in [`FitOptions::start`] is always free (name `weight2` and `roughness2` there to fit a
//! two-lobe mixture). Discrete choices (`distribution`, `fresnel`, ...) are fixed, or searched: every
//! combination of [`FitOptions::choices`] is fitted and the lowest cost kept.
//!
//! ## Where it starts
//! From the given start values (the defaults for the others), and from [`FitOptions::multistart`] more
//! points of a deterministic Latin hypercube over the ranges of the parameters not given a start (M. D.
//! McKay, R. J. Beckman, W. J. Conover, Technometrics 21(2), 1979): uniform, quadratic toward 0 for ranges
//! `[0, hi]` (roughness-like), logarithmic for ranges reaching 20 and more (exponents). Each start runs
//! [`MULTISTART_ITERATIONS`] iterations on a subsample of at most [`MULTISTART_SAMPLES`] samples; the
//! best then runs to convergence on all of them.
//!
//! ## What is minimised: [`Loss`]
//! Measured BRDFs span orders of magnitude between the specular peak and the diffuse floor; a plain
//! squared error fits the few samples near the peak and ignores the rest. With `c = n·l` (the cosine
//! factor of the rendering equation), `f` the model and `d` the data, the residual of sample `i`,
//! channel `k` is (times `√w_i` with [`FitOptions::weights`]):
//! - [`Loss::Log`] (the default): `ln(1 + c f) − ln(1 + c d)`, the logarithmic metric of Löw, Kronander,
//!   Ynnerman & Unger ("BRDF Models for Accurate and Efficient Rendering of Glossy Surfaces", ACM ToG
//!   31(1), 2012, their E2), which they found to give the best renderings: relative near the peak,
//!   absolute in the dark tail, so zeros and noise there do not dominate;
//! - [`Loss::CubeRoot`]: `(c f)^⅓ − (c d)^⅓`, the cube-root metric that A. Forés, J. Ferwerda & J. Gu
//!   ("Toward a Perceptually Based Metric for BRDF Modeling", Color and Imaging Conference 2012) found
//!   closest to perceived differences;
//! - [`Loss::CosineRelative`]: `c (f − d)/(d + ε)` with `ε = 0.01·mean(d)`: the cosine-weighted error of
//!   Ngan et al. (2005) made relative to the data;
//! - [`Loss::Linear`]: `f − d`.
//!
//! Samples with `l` or `v` at or below the horizon are dropped (every physical model is 0 there).
//!
//! ## The solver and what it reports
//! Levenberg–Marquardt (K. Levenberg 1944; D. W. Marquardt 1963) with an analytic Jacobian where one is written (Lambert,
//! Cook–Torrance with GGX, Smith and Schlick) and central differences otherwise (the columns computed in
//! parallel; every model evaluation is the batch evaluator's, in parallel over samples). Standard
//! errors are `√diag((JᵀJ)⁻¹ σ²)` with `σ² = 2·cost/(m − k)` at the solution (m residuals, k free values;
//! the Gauss–Newton approximation of the covariance, e.g. Press et al., *Numerical Recipes*, 3rd ed.,
//! §15.5), over the values not at a bound; NaN where not estimable. That assumes every residual has the
//! same spread; [`FitReport::stderr_robust`] holds the sandwich estimate, which does not.

mod analytic;
mod lm;
mod table;

use glam::Vec3;
use rayon::prelude::*;

pub use table::{Strategy, TableSampling, aniso_table_samples, table_samples};

use crate::batch::{Directions, Quantity, evaluate};
use crate::params::{Input, ModelSpec, ParamKind, ParamSpec, Params, Value};
use crate::{BrdfError, Geometry, Model};

/// Iterations of each start of the multi-start before the best one runs to convergence.
pub const MULTISTART_ITERATIONS: usize = 15;
/// Largest subsample the starts of the multi-start are compared on.
pub const MULTISTART_SAMPLES: usize = 2000;
/// Most combinations of discrete choices [`fit_model`] searches.
pub const MAX_CHOICE_COMBINATIONS: usize = 64;

/// One measurement: directions (pointing away from the surface, any length > 0) and `f_r` [1/sr].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Toward the light.
    pub l: Vec3,
    /// Toward the viewer.
    pub v: Vec3,
    /// Surface normal.
    pub n: Vec3,
    /// Measured `f_r` per RGB channel [1/sr], finite and ≥ 0.
    pub f: Vec3,
}

/// The error a fit minimises (see the module docs for the formulas and sources).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loss {
    /// `ln(1 + c f) − ln(1 + c d)` (Löw et al. 2012); the default.
    Log,
    /// `(c f)^⅓ − (c d)^⅓` (Forés et al. 2012).
    CubeRoot,
    /// `c (f − d)/(d + ε)`.
    CosineRelative,
    /// `f − d`.
    Linear,
}

/// How [`fit_model`] computes the Jacobian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Jacobian {
    /// Analytic where one is written for the model (Lambert; Cook–Torrance GGX, Smith, Schlick), central differences otherwise.
    Auto,
    /// Central differences always.
    FiniteDifference,
}

impl Loss {
    /// The names [`Loss::from_name`] accepts, in the order of the variants.
    pub const NAMES: &'static [&'static str] = &["log", "cube_root", "cosine_relative", "linear"];

    /// The loss of a name; an error naming `loss` and listing the names otherwise.
    pub fn from_name(name: &str) -> Result<Self, BrdfError> {
        match name {
            "log" => Ok(Self::Log),
            "cube_root" => Ok(Self::CubeRoot),
            "cosine_relative" => Ok(Self::CosineRelative),
            "linear" => Ok(Self::Linear),
            _ => Err(BrdfError::InvalidInput {
                name: "loss",
                problem: format!("expected one of {}, got {name:?}", Self::NAMES.join(", ")),
            }),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The residual of model value `f` against data `d` at cosine `c` (`eps`: the relative loss's floor).
    #[inline]
    fn residual(self, f: f64, d: f64, c: f64, eps: f64) -> f64 {
        match self {
            Loss::Log => (c * f).ln_1p() - (c * d).ln_1p(),
            Loss::CubeRoot => (c * f).cbrt() - (c * d).cbrt(),
            Loss::CosineRelative => c * (f - d) / (d + eps),
            Loss::Linear => f - d,
        }
    }

    /// `∂residual/∂f` at model value `f` (the cube root's is taken at `f ≥ 10⁻¹²`, where it is finite).
    #[inline]
    fn derivative(self, f: f64, d: f64, c: f64, eps: f64) -> f64 {
        match self {
            Loss::Log => c / (1.0 + c * f),
            Loss::CubeRoot => c.cbrt() / (3.0 * f.max(1e-12).powf(2.0 / 3.0)),
            Loss::CosineRelative => c / (d + eps),
            Loss::Linear => 1.0,
        }
    }
}

/// What [`fit_model`] fits and how.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// Parameters held at the given values (choices such as `distribution` go here).
    pub fixed: Vec<(String, Input)>,
    /// Starting values of free parameters (scalars and colours only); the others start at their
    /// defaults and at the multi-start points.
    pub start: Vec<(String, Input)>,
    /// The error minimised.
    pub loss: Loss,
    /// A weight ≥ 0 per sample (its residuals are multiplied by `√w`), or `None` for 1.
    pub weights: Option<Vec<f64>>,
    /// A tangent per sample, orienting anisotropic models (and tables), or `None`: the arbitrary
    /// frame of each normal ([`crate::ShadingFrame::from_normal`]; `+x` for the normal `+z`).
    pub tangents: Option<Vec<Vec3>>,
    /// Latin-hypercube starts in addition to the given start (0: only the given start).
    pub multistart: usize,
    /// Discrete choices to search: each combination of the listed values is fitted, the lowest cost kept.
    pub choices: Vec<(String, Vec<String>)>,
    /// Most Levenberg–Marquardt iterations of the final run (each one Jacobian).
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction.
    pub tolerance: f64,
    /// How the Jacobian is computed.
    pub jacobian: Jacobian,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            fixed: Vec::new(),
            start: Vec::new(),
            loss: Loss::Log,
            weights: None,
            tangents: None,
            multistart: 8,
            choices: Vec::new(),
            max_iterations: 100,
            tolerance: 1e-10,
            jacobian: Jacobian::Auto,
        }
    }
}

/// Error figures of one RGB channel at the solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelError {
    /// Root-mean-square of the residuals (of the loss, weights included).
    pub rms: f64,
    /// Largest absolute residual.
    pub max: f64,
    /// `√(Σ (f − d)² / Σ d²)` over the samples (no loss, no weights): the relative L2 error of the values.
    pub relative_l2: f64,
}

/// The outcome of [`fit_model`].
#[derive(Debug, Clone, PartialEq)]
pub struct FitReport {
    /// The fitted model (fixed and inactive parameters as given or at their defaults).
    pub model: Model,
    /// The discrete choices of the best combination when [`FitOptions::choices`] was searched.
    pub choices: Vec<(String, String)>,
    /// The fitted values of the free parameters, in registry order (3 numbers for a colour).
    pub values: Vec<(String, Vec<f64>)>,
    /// Their standard errors `√diag((JᵀJ)⁻¹ σ²)` (same layout; NaN where not estimable: at a bound, or a
    /// singular `JᵀJ`): right when every residual has the same spread.
    pub stderr: Vec<(String, Vec<f64>)>,
    /// The sandwich (heteroscedasticity-consistent) standard errors `√diag(A⁻¹ (Σ r² J Jᵀ) A⁻¹ m/(m−k))`,
    /// `A = JᵀJ` (P. J. Huber, 5th Berkeley Symposium 1967; H. White, Econometrica 48(4), 1980, with
    /// MacKinnon & White's m/(m−k)): right also when the spread varies, e.g. multiplicative noise under the
    /// log loss.
    pub stderr_robust: Vec<(String, Vec<f64>)>,
    /// Free values that ended on a bound of their range: `name` or `name[channel]`, and the bound.
    pub at_bound: Vec<(String, f64)>,
    /// Continuous parameters held at their defaults because they do not change the model.
    pub inactive: Vec<String>,
    /// The loss minimised.
    pub loss: Loss,
    /// `½ Σ r²` at the solution.
    pub cost: f64,
    /// Per RGB channel error figures.
    pub channels: [ChannelError; 3],
    /// RMS of `ln(f + ε) − ln(d + ε)` with `ε = 0.01·mean(d)` (the figure of earlier versions).
    pub rms_log_error: f64,
    /// That `ε` [1/sr].
    pub epsilon: f64,
    /// Iterations of the final run.
    pub iterations: usize,
    /// `true` when a stopping rule other than the iteration limit ended the final run.
    pub converged: bool,
    /// Why it stopped, in words.
    pub message: String,
    /// Samples used (those with both directions above the surface).
    pub samples_used: usize,
    /// Starts tried (the given one and the multi-start points).
    pub starts: usize,
    /// The cost of every combination of choices tried (empty without a search).
    pub tried: Vec<(Vec<(String, String)>, f64)>,
    /// `"analytic"` or `"finite_difference"`: how the Jacobian was computed.
    pub jacobian: &'static str,
}

/// One free parameter: its name, whether a colour, its bounds and whether the caller gave its start.
#[derive(Debug, Clone)]
struct Free {
    name: &'static str,
    color: bool,
    lo: f64,
    hi: f64,
    started: bool,
}

impl Free {
    fn width(&self) -> usize {
        if self.color { 3 } else { 1 }
    }
}

/// The samples of a fit, as the batch evaluator reads them, with their targets.
#[derive(Clone)]
struct Data {
    ls: Vec<Vec3>,
    vs: Vec<Vec3>,
    ns: Vec<Vec3>,
    /// Tangents, one per sample, or empty (no tangent: the frame of each normal).
    ts: Vec<Vec3>,
    d: Vec<Vec3>,
    cos: Vec<f64>,
    sqrt_w: Vec<f64>,
}

impl Data {
    fn len(&self) -> usize {
        self.ls.len()
    }

    /// Every `stride`-th sample.
    fn every(&self, stride: usize) -> Data {
        let pick = |v: &Vec<Vec3>| v.iter().step_by(stride).copied().collect::<Vec<_>>();
        Data {
            ls: pick(&self.ls),
            vs: pick(&self.vs),
            ns: pick(&self.ns),
            ts: pick(&self.ts),
            d: pick(&self.d),
            cos: self.cos.iter().step_by(stride).copied().collect(),
            sqrt_w: self.sqrt_w.iter().step_by(stride).copied().collect(),
        }
    }

    /// `f_r` of `model` at every sample (the batch evaluator: parallel over samples, same bits).
    fn eval(&self, model: &Model) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.len()];
        // The slices all have the batch length, so this cannot fail.
        let ts = (!self.ts.is_empty()).then_some(self.ts.as_slice());
        if let Ok((dirs, _)) = Directions::new(&self.ls, &self.vs, &self.ns, ts) {
            evaluate(model, &dirs, Quantity::Brdf, &mut out);
        }
        out
    }
}

struct Problem<'a> {
    name: &'a str,
    base: Vec<(String, Input)>,
    free: Vec<Free>,
    data: Data,
    loss: Loss,
    eps: f64,
    analytic: Option<analytic::Analytic>,
}

impl Problem<'_> {
    fn inputs(&self, p: &[f64]) -> Vec<(String, Input)> {
        let mut inputs = self.base.clone();
        let mut at = 0;
        for f in &self.free {
            inputs.push((
                f.name.to_string(),
                if f.color { Input::Numbers(p[at..at + 3].to_vec()) } else { Input::Number(p[at]) },
            ));
            at += f.width();
        }
        inputs
    }

    fn bounds(&self) -> Vec<(f64, f64)> {
        self.free.iter().flat_map(|f| std::iter::repeat_n((f.lo, f.hi), f.width())).collect()
    }

    /// Residuals at `p`, or `None` when the model refuses the combination of values.
    fn residuals(&self, p: &[f64]) -> Option<Vec<f64>> {
        let m = Model::build(self.name, &self.inputs(p)).ok()?;
        let f = self.data.eval(&m);
        let mut r = Vec::with_capacity(3 * f.len());
        for (i, fi) in f.iter().enumerate() {
            let (d, c, w) = (self.data.d[i], self.data.cos[i], self.data.sqrt_w[i]);
            for k in 0..3 {
                let fm = f64::from(fi[k]).max(0.0);
                r.push(w * self.loss.residual(fm, f64::from(d[k]), c, self.eps));
            }
        }
        r.iter().all(|x| x.is_finite()).then_some(r)
    }

    /// The Jacobian's columns at `p`: analytic when the problem has one, else central differences.
    fn jacobian(&self, p: &[f64]) -> Vec<Vec<f64>> {
        let m = 3 * self.data.len();
        let fd = || lm::jacobian(&|q: &[f64]| self.residuals(q), p, &self.bounds(), m);
        let Some(a) = self.analytic else { return fd() };
        let Ok(model) = Model::build(self.name, &self.inputs(p)) else { return fd() };
        let k = p.len();
        let f = self.data.eval(&model);
        let jf = a.model_jacobian(&model, &self.free, p, &self.data);
        let mut cols = vec![vec![0.0; m]; k];
        for (i, fi) in f.iter().enumerate() {
            let (d, c, w) = (self.data.d[i], self.data.cos[i], self.data.sqrt_w[i]);
            for ch in 0..3 {
                let s = w * self.loss.derivative(f64::from(fi[ch]).max(0.0), f64::from(d[ch]), c, self.eps);
                let row = &jf[(3 * i + ch) * k..(3 * i + ch + 1) * k];
                for (col, x) in cols.iter_mut().zip(row) {
                    col[3 * i + ch] = s * x;
                }
            }
        }
        cols
    }
}

/// `x` at the fraction `u ∈ [0, 1]` of the range `[lo, hi]` for the multi-start and the activity probe:
/// logarithmic for ranges reaching 20 (exponents), quadratic toward 0 for `[0, hi]` (roughness-like),
/// uniform otherwise.
fn map_unit(lo: f64, hi: f64, u: f64) -> f64 {
    let a = lo.max(1.0);
    if lo >= 0.0 && hi >= 20.0 && hi > a {
        (a.ln() + u * (hi.ln() - a.ln())).exp().clamp(lo, hi)
    } else if lo == 0.0 {
        hi * u * u
    } else {
        lo + (hi - lo) * u
    }
}

fn spec_of(name: &str) -> Result<&'static ModelSpec, BrdfError> {
    crate::models::spec(name).ok_or_else(|| {
        // Let the registry produce its usual message listing the known names.
        Model::build(name, &[]).err().unwrap_or_else(|| BrdfError::param("model", "unknown model"))
    })
}

/// The spec of parameter `pname` of `spec`, or the registry's error (naming the model's parameters)
/// under the argument `arg`.
fn param_of(
    spec: &'static ModelSpec,
    arg: &'static str,
    pname: &str,
    input: &Input,
) -> Result<&'static ParamSpec, BrdfError> {
    let wrap = |e: BrdfError| BrdfError::InvalidInput { name: arg, problem: e.to_string() };
    let Some(ps) = spec.params.iter().find(|p| p.name == pname) else {
        return Err(wrap(
            Model::build(spec.name, &[(pname.to_string(), input.clone())])
                .err()
                .unwrap_or_else(|| BrdfError::param(pname, "unknown parameter")),
        ));
    };
    ps.validate(input).map_err(wrap)?;
    Ok(ps)
}

/// Check the samples and options, drop samples below the horizon.
fn prepare(
    samples: &[Sample],
    weights: Option<&[f64]>,
    tangents: Option<&[Vec3]>,
) -> Result<Data, BrdfError> {
    if let Some(i) = samples.iter().position(|s| !s.f.is_finite() || s.f.min_element() < 0.0) {
        return Err(BrdfError::InvalidInput {
            name: "values",
            problem: format!("must be finite and >= 0; row {i} is {}", samples[i].f),
        });
    }
    if let Some(w) = weights {
        if w.len() != samples.len() {
            return Err(BrdfError::InvalidInput {
                name: "weights",
                problem: format!("expected one weight per sample ({}), got {}", samples.len(), w.len()),
            });
        }
        if let Some(i) = w.iter().position(|x| !x.is_finite() || *x < 0.0) {
            return Err(BrdfError::InvalidInput {
                name: "weights",
                problem: format!("must be finite and >= 0; weight {i} is {}", w[i]),
            });
        }
    }
    if let Some(t) = tangents {
        if t.len() != samples.len() {
            return Err(BrdfError::InvalidInput {
                name: "tangent",
                problem: format!("expected one tangent per sample ({}), got {}", samples.len(), t.len()),
            });
        }
        if let Some(i) = t.iter().position(|x| !x.is_finite()) {
            return Err(BrdfError::InvalidInput {
                name: "tangent",
                problem: format!("must be finite; row {i} is {}", t[i]),
            });
        }
    }
    let mut data =
        Data { ls: vec![], vs: vec![], ns: vec![], ts: vec![], d: vec![], cos: vec![], sqrt_w: vec![] };
    for (i, s) in samples.iter().enumerate() {
        if let Some(g) = Geometry::new(s.l, s.v, s.n, None).filter(Geometry::both_above) {
            data.ls.push(s.l);
            data.vs.push(s.v);
            data.ns.push(s.n);
            if let Some(t) = tangents {
                data.ts.push(t[i]);
            }
            data.d.push(s.f);
            data.cos.push(f64::from(g.nl));
            data.sqrt_w.push(weights.map_or(1.0, |w| w[i].sqrt()));
        }
    }
    if data.ls.is_empty() {
        return Err(BrdfError::InvalidInput {
            name: "samples",
            problem: "no sample has both l and v above the surface".into(),
        });
    }
    if data.d.iter().all(|d| d.max_element() == 0.0) {
        return Err(BrdfError::InvalidInput {
            name: "values",
            problem: "every value above the surface is 0: there is nothing to fit".into(),
        });
    }
    if data.sqrt_w.iter().all(|w| *w == 0.0) {
        return Err(BrdfError::InvalidInput {
            name: "weights",
            problem: "every sample above the surface has weight 0".into(),
        });
    }
    Ok(data)
}

/// Fit registry model `name` to `samples` (see the module docs).
///
/// Errors (each naming the argument): unknown model; a parameter in `fixed`, `start` or `choices` the model
/// does not have, or out of its range; a choice or flag in `start`; a parameter both fixed and started or
/// searched; non-finite or negative values or weights; no sample above the surface, all values 0, fewer
/// residuals than free values; nothing left to fit.
pub fn fit_model(name: &str, samples: &[Sample], options: &FitOptions) -> Result<FitReport, BrdfError> {
    let spec = spec_of(name)?;
    for (i, (pname, input)) in options.fixed.iter().enumerate() {
        param_of(spec, "fixed", pname, input)?;
        if options.fixed[..i].iter().any(|(q, _)| q == pname) {
            return Err(BrdfError::InvalidInput {
                name: "fixed",
                problem: format!("{pname:?} appears twice"),
            });
        }
    }
    for (i, (pname, input)) in options.start.iter().enumerate() {
        let ps = param_of(spec, "start", pname, input)?;
        if !matches!(ps.kind, ParamKind::Scalar | ParamKind::Color) {
            return Err(BrdfError::InvalidInput {
                name: "start",
                problem: format!(
                    "{pname:?} is not a number: only scalar and color parameters can be fitted; pass choices \
                     and flags in fixed (or search choices with choices=)"
                ),
            });
        }
        if options.fixed.iter().any(|(f, _)| f == pname) {
            return Err(BrdfError::InvalidInput {
                name: "start",
                problem: format!("{pname:?} is both fixed and free (in start)"),
            });
        }
        if options.start[..i].iter().any(|(q, _)| q == pname) {
            return Err(BrdfError::InvalidInput {
                name: "start",
                problem: format!("{pname:?} appears twice"),
            });
        }
    }
    let mut combos: Vec<Vec<(String, String)>> = vec![vec![]];
    for (cname, values) in &options.choices {
        let bad = |problem: String| BrdfError::InvalidInput { name: "choices", problem };
        let ps = spec
            .params
            .iter()
            .find(|p| p.name == cname.as_str())
            .ok_or_else(|| bad(format!("{name} has no parameter {cname:?}")))?;
        if !matches!(ps.kind, ParamKind::Choice(_)) {
            return Err(bad(format!("{cname:?} is not a discrete choice of {name}")));
        }
        if options.fixed.iter().any(|(f, _)| f == cname) {
            return Err(bad(format!("{cname:?} is both fixed and searched")));
        }
        if values.is_empty() {
            return Err(bad(format!("{cname:?}: give at least one value")));
        }
        for v in values {
            ps.validate(&Input::Text(v.clone())).map_err(|e| bad(e.to_string()))?;
        }
        combos = combos
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((cname.clone(), v.clone()));
                    c
                })
            })
            .collect();
        if combos.len() > MAX_CHOICE_COMBINATIONS {
            return Err(bad(format!("more than {MAX_CHOICE_COMBINATIONS} combinations of choices")));
        }
    }
    let data = prepare(samples, options.weights.as_deref(), options.tangents.as_deref())?;
    let mean = data.d.iter().map(|d| f64::from(d.x + d.y + d.z)).sum::<f64>() / (3 * data.len()) as f64;
    let eps = (0.01 * mean).max(1e-12);

    let mut best: Option<FitReport> = None;
    let mut tried = Vec::new();
    for combo in &combos {
        let mut base = options.fixed.clone();
        base.extend(combo.iter().map(|(k, v)| (k.clone(), Input::Text(v.clone()))));
        let mut rep = fit_one(spec, base, &data, eps, options)?;
        rep.choices = combo.clone();
        tried.push((combo.clone(), rep.cost));
        // The first of equal costs wins (the order of the lists): deterministic.
        if best.as_ref().is_none_or(|b| rep.cost < b.cost) {
            best = Some(rep);
        }
    }
    let mut rep = best.expect("at least one combination");
    if !options.choices.is_empty() {
        rep.tried = tried;
    }
    Ok(rep)
}

/// Whether changing parameter `ps` changes the model at the base point on the probe samples.
fn is_active(spec: &ModelSpec, base: &[(String, Input)], ps: &ParamSpec, probe: &Data, f0: &[Vec3]) -> bool {
    let scale = f0.iter().map(|f| f.max_element()).fold(0.0f32, f32::max);
    let tol = 1e-5 * scale.max(1e-30);
    let (lo, hi) = (f64::from(ps.min), f64::from(ps.max));
    for u in [0.3, 0.7] {
        let x = map_unit(lo, hi, u);
        let mut inputs = base.to_vec();
        inputs.push((ps.name.to_string(), Input::Number(x)));
        let Ok(m) = Model::build(spec.name, &inputs) else { continue };
        let f = probe.eval(&m);
        if f.iter().zip(f0).any(|(a, b)| (*a - *b).abs().max_element() > tol) {
            return true;
        }
    }
    false
}

fn fit_one(
    spec: &'static ModelSpec,
    base: Vec<(String, Input)>,
    data: &Data,
    eps: f64,
    options: &FitOptions,
) -> Result<FitReport, BrdfError> {
    let name = spec.name;
    // The fixed values together must build (one message naming `fixed`).
    Model::build(name, &base)
        .map_err(|e| BrdfError::InvalidInput { name: "fixed", problem: e.to_string() })?;
    // Activity is probed at the defaults with the fixed choices and flags only: a fixed number (say a
    // roughness) must not switch on a term (a second lobe whose default roughness now differs).
    let structural: Vec<(String, Input)> =
        base.iter().filter(|(_, i)| matches!(i, Input::Text(_) | Input::Bool(_))).cloned().collect();
    let probe_model = Model::build(name, &structural)?;
    let probe = data.every(data.len().div_ceil(64).max(1));
    let f_base = probe.eval(&probe_model);
    let mut free = Vec::new();
    let mut inactive = Vec::new();
    for ps in spec.params {
        if !matches!(ps.kind, ParamKind::Scalar | ParamKind::Color) || base.iter().any(|(n, _)| n == ps.name)
        {
            continue;
        }
        let started = options.start.iter().any(|(n, _)| n == ps.name);
        if started || is_active(spec, &structural, ps, &probe, &f_base) {
            free.push(Free {
                name: ps.name,
                color: ps.kind == ParamKind::Color,
                lo: f64::from(ps.min),
                hi: f64::from(ps.max),
                started,
            });
        } else {
            inactive.push(ps.name.to_string());
        }
    }
    if free.is_empty() {
        return Err(BrdfError::InvalidInput {
            name: "fixed",
            problem: format!(
                "every continuous parameter of {name} is fixed or has no effect: nothing to fit"
            ),
        });
    }
    let k: usize = free.iter().map(Free::width).sum();
    if 3 * data.len() < k {
        return Err(BrdfError::InvalidInput {
            name: "samples",
            problem: format!(
                "{} samples above the surface give {} residuals, fewer than the {k} free values",
                data.len(),
                3 * data.len()
            ),
        });
    }
    // The given start, the defaults (with the fixed values' derived defaults) for the rest.
    let mut start_inputs = base.clone();
    start_inputs.extend(options.start.iter().cloned());
    let params = Params::resolve(spec, &start_inputs)?;
    let mut p0 = Vec::with_capacity(k);
    for f in &free {
        match params.values().iter().find(|(n, _)| *n == f.name).map(|(_, v)| v) {
            Some(Value::Scalar(x)) => p0.push(f64::from(*x)),
            Some(Value::Color(c)) => p0.extend(c.iter().map(|&x| f64::from(x))),
            _ => unreachable!("free parameters are scalars and colours"),
        }
    }
    let analytic = match options.jacobian {
        Jacobian::Auto => {
            Model::build(name, &start_inputs).ok().and_then(|m| analytic::Analytic::for_problem(&m, &free))
        }
        Jacobian::FiniteDifference => None,
    };
    let problem = Problem { name, base, free, data: data.clone(), loss: options.loss, eps, analytic };
    let bounds = problem.bounds();

    // Latin-hypercube starts over the parameters without a given start.
    let mut candidates = vec![p0.clone()];
    if options.multistart > 0 && problem.free.iter().any(|f| !f.started) {
        let s = options.multistart;
        let mut rng = table::SplitMix(0x0F17_5EED);
        let mut points = vec![p0.clone(); s];
        let mut at = 0;
        for f in &problem.free {
            if !f.started {
                let mut perm: Vec<usize> = (0..s).collect();
                for i in (1..s).rev() {
                    perm.swap(i, (rng.next_f64() * (i + 1) as f64) as usize % (i + 1));
                }
                for (pt, cell) in points.iter_mut().zip(&perm) {
                    let u = (*cell as f64 + 0.25 + 0.5 * rng.next_f64()) / s as f64;
                    let x = map_unit(f.lo, f.hi, u);
                    for c in 0..f.width() {
                        pt[at + c] = x;
                    }
                }
            }
            at += f.width();
        }
        candidates.extend(points);
    }
    let starts = candidates.len();
    let mut p_best = p0;
    if starts > 1 {
        let sub = Problem {
            name,
            base: problem.base.clone(),
            free: problem.free.clone(),
            data: data.every(data.len().div_ceil(MULTISTART_SAMPLES).max(1)),
            loss: options.loss,
            eps,
            analytic: problem.analytic,
        };
        let res = |p: &[f64]| sub.residuals(p);
        let jac = |p: &[f64]| sub.jacobian(p);
        let runs: Vec<Option<(f64, Vec<f64>)>> = candidates
            .par_iter()
            .map(|c| {
                let r0 = sub.residuals(c)?;
                let o =
                    lm::solve(&res, &jac, c.clone(), r0, &bounds, MULTISTART_ITERATIONS, options.tolerance);
                Some((o.cost, o.p))
            })
            .collect();
        let mut best_cost = f64::INFINITY;
        for (c, p) in runs.into_iter().flatten() {
            if c < best_cost {
                best_cost = c;
                p_best = p;
            }
        }
    }
    let r0 = problem.residuals(&p_best).ok_or_else(|| BrdfError::InvalidInput {
        name: "start",
        problem: "the model gives non-finite values at the starting point".into(),
    })?;
    let res = |p: &[f64]| problem.residuals(p);
    let jac = |p: &[f64]| problem.jacobian(p);
    let out = lm::solve(&res, &jac, p_best, r0, &bounds, options.max_iterations, options.tolerance);
    report(&problem, out, inactive, starts)
}

fn report(
    problem: &Problem<'_>,
    out: lm::Outcome,
    inactive: Vec<String>,
    starts: usize,
) -> Result<FitReport, BrdfError> {
    let p = &out.p;
    let model = Model::build(problem.name, &problem.inputs(p))?;
    let bounds = problem.bounds();
    let k = p.len();
    let m = out.r.len();
    // Values on a bound, by name.
    let mut at_bound = Vec::new();
    let mut slot_names = Vec::new();
    for f in &problem.free {
        for c in 0..f.width() {
            slot_names.push(if f.color { format!("{}[{c}]", f.name) } else { f.name.to_string() });
        }
    }
    let on_bound: Vec<Option<f64>> = p
        .iter()
        .zip(&bounds)
        .map(|(&x, &(lo, hi))| {
            let tol = 1e-6 * (hi - lo);
            if x - lo <= tol {
                Some(lo)
            } else if hi - x <= tol {
                Some(hi)
            } else {
                None
            }
        })
        .collect();
    for (n, b) in slot_names.iter().zip(&on_bound) {
        if let Some(b) = b {
            at_bound.push((n.clone(), *b));
        }
    }
    // Standard errors over the values inside their ranges: the Gauss–Newton covariance A⁻¹σ² (A = JᵀJ)
    // and the sandwich A⁻¹ (Σ r² J Jᵀ) A⁻¹ · m/(m − k), which stays right when the residuals' spread
    // varies from sample to sample.
    let mut se = vec![f64::NAN; k];
    let mut se_robust = vec![f64::NAN; k];
    let inside: Vec<usize> = (0..k).filter(|&j| on_bound[j].is_none()).collect();
    if m > k && !inside.is_empty() {
        let jac = problem.jacobian(p);
        let sub: Vec<Vec<f64>> = inside.iter().map(|&j| jac[j].clone()).collect();
        let (jtj, _) = lm::normal_equations(&sub, &out.r);
        let sigma2 = 2.0 * out.cost / (m - k) as f64;
        let n = inside.len();
        let inv: Option<Vec<Vec<f64>>> = (0..n)
            .map(|a| {
                let mut e = vec![0.0; n];
                e[a] = 1.0;
                lm::linear_solve(jtj.clone(), e)
            })
            .collect();
        if let Some(inv) = inv {
            let weighted: Vec<Vec<f64>> =
                sub.iter().map(|c| c.iter().zip(&out.r).map(|(x, r)| x * r).collect()).collect();
            let (meat, _) = lm::normal_equations(&weighted, &out.r);
            let hc1 = m as f64 / (m - k) as f64;
            for (a, &j) in inside.iter().enumerate() {
                se[j] = (inv[a][a].max(0.0) * sigma2).sqrt();
                let mut v = 0.0;
                for b in 0..n {
                    for c in 0..n {
                        v += inv[a][b] * meat[b * n + c] * inv[c][a];
                    }
                }
                se_robust[j] = (v.max(0.0) * hc1).sqrt();
            }
        }
    }
    let mut values = Vec::new();
    let mut stderr = Vec::new();
    let mut stderr_robust = Vec::new();
    let mut at = 0;
    for f in &problem.free {
        values.push((f.name.to_string(), p[at..at + f.width()].to_vec()));
        stderr.push((f.name.to_string(), se[at..at + f.width()].to_vec()));
        stderr_robust.push((f.name.to_string(), se_robust[at..at + f.width()].to_vec()));
        at += f.width();
    }
    // Error figures.
    let data = &problem.data;
    let fm = data.eval(&model);
    let mut channels = [ChannelError { rms: 0.0, max: 0.0, relative_l2: 0.0 }; 3];
    let (mut num, mut den) = ([0.0f64; 3], [0.0f64; 3]);
    let log_eps = problem.eps;
    let mut log_sq = 0.0;
    for (i, f) in fm.iter().enumerate() {
        for c in 0..3 {
            let r = out.r[3 * i + c];
            channels[c].rms += r * r;
            channels[c].max = channels[c].max.max(r.abs());
            let (a, b) = (f64::from(f[c]).max(0.0), f64::from(data.d[i][c]));
            num[c] += (a - b) * (a - b);
            den[c] += b * b;
            let lr = (a + log_eps).ln() - (b + log_eps).ln();
            log_sq += lr * lr;
        }
    }
    let n = fm.len() as f64;
    for ((ch, num), den) in channels.iter_mut().zip(num).zip(den) {
        ch.rms = (ch.rms / n).sqrt();
        ch.relative_l2 = if den > 0.0 { (num / den).sqrt() } else { num.sqrt() };
    }
    Ok(FitReport {
        model,
        choices: Vec::new(),
        values,
        stderr,
        stderr_robust,
        at_bound,
        inactive,
        loss: problem.loss,
        cost: out.cost,
        channels,
        rms_log_error: (log_sq / (3.0 * n)).sqrt(),
        epsilon: log_eps,
        iterations: out.iterations,
        converged: out.stop.converged(),
        message: out.stop.message().to_string(),
        samples_used: fm.len(),
        starts,
        tried: Vec::new(),
        jacobian: if problem.analytic.is_some() { "analytic" } else { "finite_difference" },
    })
}

#[cfg(test)]
mod tests;
