//! One type per reflectance model, all with the same small method set ([`Bxdf`]), and [`Model`], the
//! enum that the registry, the batch evaluator and the rasterizer dispatch on.
//!
//! Two kinds of model live here (SPEC "Conventions"):
//! - **physical** BRDFs implement [`Bxdf::f`], the BRDF value `f_r` in 1/sr. They are only called with
//!   both `l` and `v` strictly above the surface; [`Model::eval`] returns 0 otherwise, and
//!   [`Model::shade`] is `f_r · max(n·l, 0)`.
//! - **classic** (course-style) models of seeds 000 and 004 implement [`Bxdf::shade`] as the course
//!   formula exactly as written (it clamps what it clamps, for any `l` and `v`), and `f` is that value
//!   divided by `n·l` (0 where `n·l ≤ 0`), see [`classic_f`].

use glam::Vec3;

use crate::params::{Input, ModelSpec, Params};
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
    /// `shade` is a course formula offered exactly as written.
    Classic,
}

/// The method set every model has (pbrt-v4's BxDF interface, reduced to evaluation).
pub trait Bxdf: Sized + Send + Sync {
    /// Name, parameters and citation.
    const SPEC: ModelSpec;
    /// Physical BRDF or course formula.
    const KIND: ModelKind;

    /// Build from validated parameters (see [`Params::resolve`]).
    fn from_params(p: &Params) -> Result<Self, BrdfError>;

    /// The BRDF value `f_r(l, v)` per RGB channel [1/sr], without the cosine.
    ///
    /// Physical models are called only when `g.both_above()`.
    fn f(&self, g: &Geometry) -> Vec3;

    /// What a renderer multiplies by the light's color (irradiance at normal incidence):
    /// `f_r · max(n·l, 0)` for physical models, the course formula for classic ones.
    #[inline]
    fn shade(&self, g: &Geometry) -> Vec3 {
        self.f(g) * g.nl.max(0.0)
    }

    /// [`Bxdf::f`] on `F::LANES` samples at once (the batch evaluator uses eight, see
    /// [`crate::simd`]). Only the lanes in `active` matter: the others may hold any geometry and their
    /// result is discarded. The default runs the scalar `f` on each active lane. A model whose formula
    /// is written generically over [`Lane`] overrides this and implements `f` as this method with
    /// `F = f32`, so that the formula exists once and both paths give the same bits.
    #[inline]
    fn f_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        V3::from_fn(|i| if F::mask_lane(active, i) { self.f(&g.lane(i)) } else { Vec3::ZERO })
    }

    /// [`Bxdf::shade`] on `F::LANES` samples at once; the default runs the scalar `shade` on each
    /// active lane. Models that override [`Bxdf::f_lanes`] and keep the default `shade` override this
    /// with [`physical_shade_lanes`].
    #[inline]
    fn shade_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        V3::from_fn(|i| if F::mask_lane(active, i) { self.shade(&g.lane(i)) } else { Vec3::ZERO })
    }
}

/// The default [`Bxdf::shade`], `f_r · max(n·l, 0)`, on lanes (for models that override
/// [`Bxdf::f_lanes`]).
#[inline(always)]
pub fn physical_shade_lanes<M: Bxdf, F: Lane>(m: &M, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
    m.f_lanes(g, active).scale(g.nl.max(F::splat(0.0)))
}

/// `f` of a classic model: its course formula divided by `n·l`, 0 where `n·l ≤ 0`.
#[inline]
pub fn classic_f(shade: Vec3, g: &Geometry) -> Vec3 {
    if g.nl > 0.0 { shade / g.nl } else { Vec3::ZERO }
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

    #[test]
    fn every_default_lies_in_its_documented_range() {
        for s in MODEL_SPECS {
            for p in s.params {
                p.validate(&match &p.default {
                    crate::params::Value::Scalar(x) => Input::Number(f64::from(*x)),
                    crate::params::Value::Color(c) => {
                        Input::Numbers(c.iter().map(|&x| f64::from(x)).collect())
                    }
                    crate::params::Value::Choice(c) => Input::Text((*c).to_string()),
                    crate::params::Value::Bool(b) => Input::Bool(*b),
                    crate::params::Value::Array(a) => {
                        Input::Numbers(a.iter().map(|&x| f64::from(x)).collect())
                    }
                })
                .unwrap_or_else(|e| panic!("{}.{}: {e}", s.name, p.name));
            }
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_known_ones_listed() {
        let e = Model::build("nope", &[]).unwrap_err().to_string();
        assert!(e.contains("lambert"), "{e}");
        let e = Model::build("lambert", &[("albedoo".into(), Input::Number(0.5))]).unwrap_err().to_string();
        assert!(e.contains("albedoo") && e.contains("albedo"), "{e}");
        let e = Model::build("lambert", &[("albedo".into(), Input::Number(-0.5))]).unwrap_err().to_string();
        assert!(e.contains("albedo") && e.contains("[0, 1]"), "{e}");
    }
}
