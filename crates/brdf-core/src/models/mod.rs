//! One type per reflectance model, all with the same small method set ([`Bxdf`]), and [`Model`], the
//! enum that the registry, the batch evaluator and the rasterizer dispatch on.
//!
//! Each model writes its formula once, [`Bxdf::formula`], generic over [`Lane`]: the scalar `f` and
//! `shade` are that code with `F = f32`, the batch evaluator and the rasterizer run it eight lanes at a
//! time, and both give the same bits (tests in `lane_tests.rs`).
//!
//! Two kinds of model live here (SPEC "Conventions"):
//! - **physical** BRDFs: the formula is the BRDF value `f_r` in 1/sr. It is only called with both `l`
//!   and `v` strictly above the surface; [`Model::eval`] returns 0 otherwise, and [`Model::shade`] is
//!   `f_r · max(n·l, 0)`.
//! - **classic** models (the textbook shading formulas: Lambert, Phong and Blinn-Phong as written in
//!   illumination-model chapters, toon shading, Strauss): the formula is what [`Bxdf::shade`] returns,
//!   exactly as written (it clamps what it clamps, for any `l` and `v`), and `f` is that value divided
//!   by `n·l` (0 where `n·l ≤ 0`), see [`classic_f`].
//!
//! **Parameter names.** One concept has one name in every model: `kd` is the diffuse reflectance
//! (colour), `ks` the specular reflectance or scale, `roughness` a microfacet α, `shininess` a Phong or
//! Blinn exponent, `f0`, `ior`, `eta`, `k` the Fresnel inputs. Names that papers or other libraries use
//! for the same things (`albedo`, `rho_d`, `rd`, `diffuse_color`, ...) are refused with a message that
//! names ours ([`RENAMED_PARAMS`]).

use glam::Vec3;

use crate::params::{Input, ModelSpec, Params, Value};
use crate::simd::{Lane, LaneGeometry, V3};
use crate::{BrdfError, Geometry};

pub mod ashikhmin_shirley;
pub mod blinn_phong;
pub mod classic;
pub mod cook_torrance;
pub mod lafortune;
pub mod lambert;
pub mod oren_nayar;
pub mod phong;
pub mod strauss;
pub mod toon;
pub mod ward;

#[cfg(test)]
mod lane_tests;

pub use ashikhmin_shirley::AshikhminShirley;
pub use blinn_phong::BlinnPhong;
pub use classic::{BlinnPhongClassic, LambertClassic, PhongClassic};
pub use cook_torrance::CookTorrance;
pub use lafortune::Lafortune;
pub use lambert::Lambert;
pub use oren_nayar::{OrenNayar, OrenNayarFull};
pub use phong::Phong;
pub use strauss::Strauss;
pub use toon::Toon;
pub use ward::Ward;

/// Physical BRDF or course formula (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// `f` is a BRDF in 1/sr; reciprocity and energy checks apply.
    Physical,
    /// `shade` is a textbook shading formula offered exactly as written.
    Classic,
}

/// The method set every model has (pbrt-v4's BxDF interface: value, and sampling through
/// [`Bxdf::sampler`]).
///
/// A model writes its formula once, [`Bxdf::formula`], generic over [`Lane`]; the scalar and lane
/// forms of `f` and `shade` derive from it with the conventions of the model's [`ModelKind`], so the
/// scalar path is the lane code with `F = f32` (the same bits as any lane of a batch) and no model can
/// forget one of them. The four derived methods are not meant to be overridden.
pub trait Bxdf: Sized + Send + Sync {
    /// Name, parameters and citation.
    const SPEC: ModelSpec;
    /// Physical BRDF or course formula.
    const KIND: ModelKind;

    /// Build from validated parameters (see [`Params::resolve`]).
    fn from_params(p: &Params) -> Result<Self, BrdfError>;

    /// The model's formula on `F::LANES` samples, the one place it is written: the BRDF value `f_r`
    /// [1/sr] per RGB channel for physical models (called only for lanes where both `l` and `v` are
    /// above the surface, [`eval_model_lanes`]), the textbook shading value (what a renderer multiplies
    /// by the light's colour; any `l`, `v`) for classic ones. Only the lanes in `active` matter: the
    /// others may hold any geometry and their result is discarded.
    ///
    /// Write it with `#[cfg_attr(debug_assertions, inline)]` and
    /// `#[cfg_attr(not(debug_assertions), inline(always))]`, and without closures (see [`crate::simd`]).
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F>;

    /// How to importance-sample the model ([`crate::sampling`]): its lobes, each drawn by one
    /// technique and weighted by an estimate of its albedo. With it every model has pbrt-v4's BxDF
    /// method set: value ([`Bxdf::f`]), sample and pdf ([`crate::Model::sample`],
    /// [`crate::Model::pdf`]). The default refuses, naming the model.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        Err(BrdfError::InvalidInput {
            name: "model",
            problem: format!("{} has no importance sampler", Self::SPEC.name),
        })
    }

    /// Set the parameter in slot `slot` of [`Bxdf::SPEC`]`.params` to `value` (validated against that
    /// spec) in place, with every term the model derives from it recomputed, so that the model equals
    /// [`Bxdf::from_params`] of its parameters with that value; `false` when this model cannot and
    /// must be rebuilt by `from_params` (the default, for every parameter). A renderer that reads
    /// parameters from textures changes them at every pixel: a model overrides this for the
    /// parameters that are cheap to change (Cook–Torrance's `kd`, `ks`, `roughness`, `f0`).
    #[inline]
    fn set_param(&mut self, _slot: usize, _value: &Value) -> bool {
        false
    }

    /// The BRDF value `f_r(l, v)` per RGB channel [1/sr], without the cosine: [`Bxdf::f_lanes`] with
    /// one lane.
    ///
    /// Physical models are called only when `g.both_above()`.
    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        self.f_lanes(&LaneGeometry::from(g), true).into()
    }

    /// What a renderer multiplies by the light's color (irradiance at normal incidence):
    /// `f_r · max(n·l, 0)` for physical models, the textbook formula for classic ones;
    /// [`Bxdf::shade_lanes`] with one lane.
    #[inline]
    fn shade(&self, g: &Geometry) -> Vec3 {
        self.shade_lanes(&LaneGeometry::from(g), true).into()
    }

    /// [`Bxdf::f`] on `F::LANES` samples at once (the batch evaluator uses eight, see
    /// [`crate::simd`]): the formula for physical models, the formula divided by `n·l` (0 where
    /// `n·l ≤ 0`) for classic ones ([`classic_f`]).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn f_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        let value = self.formula(g, active);
        match Self::KIND {
            ModelKind::Physical => value,
            ModelKind::Classic => classic_f_lanes(value, g.nl),
        }
    }

    /// [`Bxdf::shade`] on `F::LANES` samples at once: `f_r · max(n·l, 0)` for physical models, the
    /// formula itself for classic ones.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn shade_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        let value = self.formula(g, active);
        match Self::KIND {
            ModelKind::Physical => value.scale(g.nl.max(F::splat(0.0))),
            ModelKind::Classic => value,
        }
    }
}

/// `f` of a classic model: its textbook formula divided by `n·l`, 0 where `n·l ≤ 0`.
#[inline]
pub fn classic_f(shade: Vec3, g: &Geometry) -> Vec3 {
    classic_f_lanes(V3::<f32>::splat(shade), g.nl).into()
}

/// [`classic_f`] on lanes: `shade / nl` where `nl > 0`, else 0.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn classic_f_lanes<F: Lane>(shade: V3<F>, nl: F) -> V3<F> {
    let zero = F::splat(0.0);
    V3::select(nl.gt(zero), shade / nl, V3::splat(Vec3::ZERO))
}

/// Evaluate `f_r` with the hemisphere convention of the model's kind.
#[inline]
pub fn eval_model<M: Bxdf>(m: &M, g: &Geometry) -> Vec3 {
    match M::KIND {
        ModelKind::Physical if !g.both_above() => Vec3::ZERO,
        _ => m.f(g),
    }
}

/// Evaluate what a renderer multiplies by the light color, with the model kind's convention.
#[inline]
pub fn shade_model<M: Bxdf>(m: &M, g: &Geometry) -> Vec3 {
    match M::KIND {
        ModelKind::Physical if !g.both_above() => Vec3::ZERO,
        _ => m.shade(g),
    }
}

/// [`eval_model`] on lanes: `valid` marks the lanes whose geometry exists (see
/// [`LaneGeometry::new`]); the others, and below-horizon lanes of physical models, give 0.
#[inline(always)]
pub fn eval_model_lanes<M: Bxdf, F: Lane>(m: &M, g: &LaneGeometry<F>, valid: F::Mask) -> V3<F> {
    let active = match M::KIND {
        ModelKind::Physical => valid & g.both_above(),
        ModelKind::Classic => valid,
    };
    V3::select(active, m.f_lanes(g, active), V3::splat(Vec3::ZERO))
}

/// [`shade_model`] on lanes, with the conventions of [`eval_model_lanes`].
#[inline(always)]
pub fn shade_model_lanes<M: Bxdf, F: Lane>(m: &M, g: &LaneGeometry<F>, valid: F::Mask) -> V3<F> {
    let active = match M::KIND {
        ModelKind::Physical => valid & g.both_above(),
        ModelKind::Classic => valid,
    };
    V3::select(active, m.shade_lanes(g, active), V3::splat(Vec3::ZERO))
}

/// A computation generic over the model type, run by [`Model::visit`].
pub trait ModelVisitor {
    /// What the computation returns.
    type Output;
    /// Run on the concrete model.
    fn visit<M: Bxdf>(self, m: &M) -> Self::Output;
}

macro_rules! define_models {
    (
        $($variant:ident($ty:ty)),+ $(,)?
        ; data: $($dvariant:ident($dty:ty)),+ $(,)?
    ) => {
        /// Any model: a registered one (built by name from parameters), or a data-driven one (built
        /// from data, such as a measured table, and not in the registry). Batch loops match once and
        /// then run a loop monomorphised for the model (see [`Model::visit`]).
        #[derive(Debug, Clone, PartialEq)]
        pub enum Model {
            $(
                #[doc = concat!("See [`", stringify!($ty), "`].")]
                $variant($ty),
            )+
            $(
                #[doc = concat!("See [`", stringify!($dty), "`] (data-driven, not in the registry).")]
                $dvariant($dty),
            )+
        }

        /// The specs of every registered model, in registry order.
        pub const MODEL_SPECS: &[&ModelSpec] = &[$(&<$ty as Bxdf>::SPEC),+];

        impl Model {
            /// Build a model by registry name from (name, value) pairs; defaults fill the rest.
            pub fn build(name: &str, inputs: &[(String, Input)]) -> Result<Self, BrdfError> {
                $(
                    if name == <$ty as Bxdf>::SPEC.name {
                        let p = Params::resolve(&<$ty as Bxdf>::SPEC, inputs)?;
                        return Ok(Model::$variant(<$ty as Bxdf>::from_params(&p)?));
                    }
                )+
                Err(BrdfError::UnknownModel {
                    name: name.to_string(),
                    known: MODEL_SPECS.iter().map(|s| s.name).collect::<Vec<_>>().join(", "),
                })
            }

            /// The model's spec.
            pub fn spec(&self) -> &'static ModelSpec {
                match self {
                    $(Model::$variant(_) => &<$ty as Bxdf>::SPEC,)+
                    $(Model::$dvariant(_) => &<$dty as Bxdf>::SPEC,)+
                }
            }

            /// `f_r(l, v)` [1/sr] per channel; 0 below the horizon for physical models.
            #[inline]
            pub fn eval(&self, g: &Geometry) -> Vec3 {
                match self {
                    $(Model::$variant(m) => eval_model(m, g),)+
                    $(Model::$dvariant(m) => eval_model(m, g),)+
                }
            }

            /// What a renderer multiplies by the light color (see [`Bxdf::shade`]).
            #[inline]
            pub fn shade(&self, g: &Geometry) -> Vec3 {
                match self {
                    $(Model::$variant(m) => shade_model(m, g),)+
                    $(Model::$dvariant(m) => shade_model(m, g),)+
                }
            }

            /// Call `visitor` with the concrete model, so that its body is compiled once per model
            /// type and an inner loop over many samples has no dispatch in it.
            #[inline]
            pub fn visit<V: ModelVisitor>(&self, visitor: V) -> V::Output {
                match self {
                    $(Model::$variant(m) => visitor.visit(m),)+
                    $(Model::$dvariant(m) => visitor.visit(m),)+
                }
            }
        }

        $(
            impl From<$ty> for Model {
                fn from(m: $ty) -> Self {
                    Model::$variant(m)
                }
            }
        )+
        $(
            impl From<$dty> for Model {
                fn from(m: $dty) -> Self {
                    Model::$dvariant(m)
                }
            }
        )+

    };
}

// The registry: one line per model. Order is the order `brdfpy.models()` lists them in.
define_models! {
    Lambert(Lambert),
    LambertClassic(LambertClassic),
    OrenNayar(OrenNayar),
    OrenNayarFull(OrenNayarFull),
    Toon(Toon),
    PhongClassic(PhongClassic),
    BlinnPhongClassic(BlinnPhongClassic),
    Phong(Phong),
    BlinnPhong(BlinnPhong),
    CookTorrance(CookTorrance),
    Strauss(Strauss),
    Ward(Ward),
    AshikhminShirley(AshikhminShirley),
    Lafortune(Lafortune);
    // Data-driven models: built from data, not by name (`Model::build` does not know them).
    data: Measured(crate::measured::Measured),
    MeasuredAnisotropic(crate::measured::MeasuredAnisotropic),
    MeasuredRgl(crate::measured::MeasuredRgl),
}

/// A parameter name this library does not use, and the name it uses for the same concept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenamedParam {
    /// The name a user may try (from a paper, another library, or an earlier version of this one).
    pub old: &'static str,
    /// The name of the same concept here.
    pub new: &'static str,
    /// The concept, in words, for the message ("the diffuse reflectance").
    pub what: &'static str,
}

const fn renamed(old: &'static str, new: &'static str, what: &'static str) -> RenamedParam {
    RenamedParam { old, new, what }
}

/// The one alias table: for messages only (an old name is refused, never accepted). An entry applies to
/// a model that has a parameter `new` and none called `old`; the first that applies wins, so e.g.
/// `color` means `kd` for `lambert_classic` and `base_color` for `strauss`, and `ks` means Strauss's
/// `k_shadow` only where there is no specular reflectance `ks`.
pub const RENAMED_PARAMS: &[RenamedParam] = &[
    renamed("albedo", "kd", "the diffuse reflectance"),
    renamed("rho_d", "kd", "the diffuse reflectance"),
    renamed("rd", "kd", "the diffuse reflectance"),
    renamed("diffuse_color", "kd", "the diffuse reflectance"),
    renamed("diffuse", "kd", "the diffuse reflectance"),
    renamed("diffuse_reflectance", "kd", "the diffuse reflectance"),
    renamed("color", "kd", "the diffuse reflectance"),
    renamed("base_color", "kd", "the diffuse reflectance"),
    renamed("rho_s", "ks", "the specular reflectance"),
    renamed("rs", "ks", "the specular reflectance"),
    renamed("specular_color", "ks", "the specular reflectance"),
    renamed("specular", "ks", "the specular reflectance"),
    renamed("specular_reflectance", "ks", "the specular reflectance"),
    renamed("diffuse_mid_color", "kd_mid", "the mid-band diffuse colour"),
    renamed("color", "base_color", "the surface colour"),
    renamed("albedo", "base_color", "the surface colour"),
    renamed("kd", "base_color", "the surface colour"),
    renamed("diffuse_color", "base_color", "the surface colour"),
    renamed("kf", "k_fresnel", "Strauss's Fresnel constant k_f"),
    renamed("ks", "k_shadow", "Strauss's shadow constant k_s"),
    renamed("kg", "k_shadow", "Strauss's shadow constant k_s"),
    renamed("kj", "k_offspecular", "Strauss's off-specular constant k_j"),
    renamed("alpha", "roughness", "the microfacet roughness alpha"),
    renamed("roughness", "sigma", "the roughness (slope-angle deviation sigma, radians)"),
    renamed("exponent", "shininess", "the specular exponent"),
    renamed("specular_exponent", "shininess", "the specular exponent"),
];

/// The entry of [`RENAMED_PARAMS`] that explains why `spec` has no parameter `name`, if any.
pub fn renamed_param(spec: &ModelSpec, name: &str) -> Option<&'static RenamedParam> {
    let has = |p: &str| spec.params.iter().any(|q| q.name == p);
    RENAMED_PARAMS.iter().find(|r| r.old == name && has(r.new) && !has(r.old))
}

/// Look up a model's spec by registry name.
pub fn spec(name: &str) -> Option<&'static ModelSpec> {
    MODEL_SPECS.iter().copied().find(|s| s.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_model_builds_from_its_defaults_and_evaluates_finite() {
        let g = Geometry::new(Vec3::new(0.3, 0.2, 1.0), Vec3::new(-0.4, 0.1, 1.0), Vec3::Z, Some(Vec3::X))
            .unwrap();
        for s in MODEL_SPECS {
            let m = Model::build(s.name, &[]).unwrap_or_else(|e| panic!("{}: {e}", s.name));
            assert_eq!(m.spec().name, s.name);
            let (f, c) = (m.eval(&g), m.shade(&g));
            assert!(f.is_finite() && c.is_finite(), "{}: {f} {c}", s.name);
            assert!(f.min_element() >= 0.0 && c.min_element() >= 0.0, "{}: {f} {c}", s.name);
        }
    }

    struct KindOf;
    impl ModelVisitor for KindOf {
        type Output = ModelKind;
        fn visit<M: Bxdf>(self, _: &M) -> ModelKind {
            M::KIND
        }
    }

    #[test]
    fn every_model_is_evaluated_with_the_conventions_its_registry_flag_announces() {
        // `physical` is what users and the checks read; `KIND` is what eval/shade obey. A mismatch would
        // run the BRDF checks on a formula, or give a BRDF the formula conventions.
        for s in MODEL_SPECS {
            let kind = Model::build(s.name, &[]).unwrap().visit(KindOf);
            assert_eq!(kind == ModelKind::Physical, s.physical, "{}", s.name);
        }
    }

    #[test]
    fn strauss_is_classic_because_its_formula_is_not_a_reciprocal_brdf() {
        // Strauss's highlight reads the incidence angle only (F(x_i)) and carries no n·l, so f(l, v) and
        // f(v, l) differ: registered as physical, the reciprocity and energy checks would be run on it.
        let m = Model::build("strauss", &[]).unwrap();
        assert!(!m.spec().physical);
        assert_eq!(m.visit(KindOf), ModelKind::Classic);
        let (l, v) = (Vec3::new(0.95, 0.0, 0.31), Vec3::new(-0.6, 0.0, 0.8));
        let g = Geometry::new(l, v, Vec3::Z, None).unwrap();
        let (a, b) = (m.eval(&g), m.eval(&g.swapped()));
        assert!((a - b).abs().max_element() > 0.05 * a.max_element(), "{a} {b}");
        // And its shade is the formula itself (Q_d + Q_s): with a black surface colour only the white
        // dielectric highlight Q_s = (r·v)^h r_j is left, not divided or multiplied by n·l. At the mirror
        // direction r·v = 1, so shade = r_j ≤ 1 however grazing the light is.
        let black = Model::build("strauss", &[("base_color".into(), Input::Number(0.0))]).unwrap();
        let l = Vec3::new(0.95, 0.0, 0.05).normalize();
        let g = Geometry::new(l, Vec3::new(-l.x, -l.y, l.z), Vec3::Z, None).unwrap();
        let s = black.shade(&g);
        let Model::Strauss(st) = &black else { unreachable!() };
        let x = g.n.cross(g.l).length().atan2(g.nl) * std::f32::consts::FRAC_2_PI;
        let r_n = 1.0 - (1.0 - 0.5f32.powi(3)); // (1 − t) − r_d at s = 0.5, t = 0
        let r_j = (r_n + (r_n + 0.1) * st.fresnel(x) * st.shadow(x) * st.shadow(x)).min(1.0);
        assert!((s - Vec3::splat(r_j)).abs().max_element() < 1e-5 && r_j > 0.2, "{s} vs r_j = {r_j}");
        assert_eq!(black.eval(&g), s / g.nl);
    }

    /// A parameter's default as a caller would give it.
    fn default_input(p: &crate::params::ParamSpec) -> Input {
        match &p.default {
            crate::params::Value::Scalar(x) => Input::Number(f64::from(*x)),
            crate::params::Value::Color(c) => Input::Numbers(c.iter().map(|&x| f64::from(x)).collect()),
            crate::params::Value::Choice(c) => Input::Text((*c).to_string()),
            crate::params::Value::Bool(b) => Input::Bool(*b),
            crate::params::Value::Array(a) => Input::Numbers(a.iter().map(|&x| f64::from(x)).collect()),
        }
    }

    /// What [`Bxdf::set_param`] gives, against a rebuild from the parameters.
    struct SetParamAgrees<'a> {
        params: &'a Params,
        slot: usize,
        value: Value,
    }
    impl ModelVisitor for SetParamAgrees<'_> {
        type Output = Option<bool>;
        fn visit<M: Bxdf>(self, m: &M) -> Option<bool> {
            let mut changed = M::from_params(self.params).ok()?;
            let _ = m;
            if !changed.set_param(self.slot, &self.value) {
                return None;
            }
            let mut p = self.params.clone();
            p.set_at(self.slot, self.value.clone());
            let rebuilt = M::from_params(&p).ok()?;
            let g =
                Geometry::new(Vec3::new(0.3, 0.2, 1.0), Vec3::new(-0.4, 0.1, 1.0), Vec3::Z, None).unwrap();
            Some(changed.f(&g) == rebuilt.f(&g))
        }
    }

    #[test]
    fn set_param_gives_the_model_a_rebuild_with_that_value_gives() {
        let mut checked = 0;
        for s in MODEL_SPECS {
            for metal in ["none", "au"] {
                let inputs: Vec<(String, Input)> = if s.name == "cook_torrance" {
                    vec![("metal".into(), Input::Text(metal.into()))]
                } else {
                    vec![]
                };
                let params = Params::resolve(s, &inputs).unwrap();
                let m = Model::build(s.name, &inputs).unwrap();
                for (slot, p) in s.params.iter().enumerate() {
                    let value = match p.kind {
                        crate::params::ParamKind::Scalar => Value::Scalar(0.5 * (p.min + p.max.min(1.0))),
                        crate::params::ParamKind::Color => {
                            Value::Color([0.3, 0.6, 0.9].map(|x| p.min + x * (p.max.min(1.0) - p.min)))
                        }
                        _ => continue,
                    };
                    if let Some(same) = m.visit(SetParamAgrees { params: &params, slot, value }) {
                        assert!(same, "{}.{} (metal {metal})", s.name, p.name);
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 5, "{checked}");
    }

    #[test]
    fn every_default_lies_in_its_documented_range() {
        for s in MODEL_SPECS {
            for p in s.params {
                p.validate(&default_input(p)).unwrap_or_else(|e| panic!("{}.{}: {e}", s.name, p.name));
            }
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_known_ones_listed() {
        let e = Model::build("nope", &[]).unwrap_err().to_string();
        assert!(e.contains("lambert"), "{e}");
        let e = Model::build("lambert", &[("kdd".into(), Input::Number(0.5))]).unwrap_err().to_string();
        assert!(e.contains("kdd") && e.contains("kd"), "{e}");
        let e = Model::build("lambert", &[("kd".into(), Input::Number(-0.5))]).unwrap_err().to_string();
        assert!(e.contains("kd") && e.contains("[0, 1]"), "{e}");
    }

    fn refusal(model: &str, name: &str) -> String {
        Model::build(model, &[(name.into(), Input::Number(0.5))]).unwrap_err().to_string()
    }

    #[test]
    fn an_old_or_foreign_parameter_name_is_refused_with_the_name_of_the_same_concept_here() {
        assert!(
            refusal("lambert", "albedo")
                .starts_with("lambert has no parameter 'albedo': the diffuse reflectance is 'kd'"),
            "{}",
            refusal("lambert", "albedo")
        );
        for (model, old, new) in [
            ("lambert_classic", "color", "kd"),
            ("oren_nayar", "albedo", "kd"),
            ("oren_nayar_full", "albedo", "kd"),
            ("toon", "diffuse_color", "kd"),
            ("toon", "specular_color", "ks"),
            ("toon", "diffuse_mid_color", "kd_mid"),
            ("ward", "rho_d", "kd"),
            ("ward", "rho_s", "ks"),
            ("ashikhmin_shirley", "rd", "kd"),
            ("ashikhmin_shirley", "rs", "ks"),
            ("lafortune", "rho_d", "kd"),
            ("lafortune", "rho_s", "ks"),
            ("cook_torrance", "albedo", "kd"),
            ("cook_torrance", "alpha", "roughness"),
            ("oren_nayar", "roughness", "sigma"),
            ("strauss", "color", "base_color"),
            ("strauss", "kd", "base_color"),
            ("strauss", "kf", "k_fresnel"),
            ("strauss", "ks", "k_shadow"),
            ("strauss", "kj", "k_offspecular"),
        ] {
            let e = refusal(model, old);
            assert!(e.starts_with(&format!("{model} has no parameter '{old}': ")), "{e}");
            assert!(e.contains(&format!(" is '{new}'")), "{model}.{old}: {e}");
            // The suggestion is a parameter the model has: following it builds the model.
            let p = spec(model).unwrap().params.iter().find(|p| p.name == new).unwrap();
            assert!(Model::build(model, &[(new.into(), default_input(p))]).is_ok(), "{model}.{new}");
        }
        // A name that means nothing gets the plain refusal with the list of parameters.
        let e = refusal("ward", "glossiness");
        assert!(e.contains("no parameter \"glossiness\"") && e.contains("kd, ks, alpha_x"), "{e}");
    }

    #[test]
    fn every_alias_points_to_a_parameter_some_model_has_and_never_shadows_a_real_one() {
        for r in RENAMED_PARAMS {
            let target = MODEL_SPECS.iter().any(|s| s.params.iter().any(|p| p.name == r.new));
            assert!(target, "{} -> {}: no model has {}", r.old, r.new, r.new);
        }
        // A parameter a model has is never answered by the table.
        for s in MODEL_SPECS {
            for p in s.params {
                assert!(renamed_param(s, p.name).is_none(), "{}.{}", s.name, p.name);
            }
        }
    }
}
