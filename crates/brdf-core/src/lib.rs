//! # brdf-core
//!
//! Reflectance models (BRDFs), Fresnel terms, microfacet distributions and masking terms, lights and
//! tone mapping, on [`glam`]. Usable on its own; the Python package `brdfpy` is a thin layer over it.
//!
//! ## Conventions (one set, everywhere)
//! - Directions point **away** from the surface point: `l` toward the light, `v` toward the viewer,
//!   `n` the unit normal; `h = normalize(l + v)`, `r = 2(n·l)n − l`.
//! - `f_r(l, v)` is the BRDF value in 1/sr, without the cosine ([`Model::eval`]). What a light adds is
//!   `L_o = f_r · E · max(n·l, 0)`; [`Model::shade`] returns `f_r · max(n·l, 0)`, i.e. `L_o` per unit
//!   irradiance `E`. The textbook shading formulas (Lambert, Phong, Blinn-Phong as written, toon,
//!   Strauss) are their own "classic" models whose `shade` is the formula exactly as written.
//! - Colors are linear RGB `Vec3`. Clamping and tone mapping are explicit, separate steps.
//!
//! ```
//! use brdf_core::{Geometry, Model};
//! use glam::Vec3;
//! let m = Model::build("lambert", &[]).unwrap();
//! let g = Geometry::new(Vec3::Z, Vec3::new(0.0, 0.6, 0.8), Vec3::Z, None).unwrap();
//! assert!((m.eval(&g).x - 0.8 / std::f32::consts::PI).abs() < 1e-6);
//! ```

pub mod batch;
pub mod error;
pub mod fit;
pub mod frame;
pub mod fresnel;
pub mod geometry;
pub mod illumination;
pub mod lights;
pub mod masking;
pub mod measured;
pub mod microfacet;
pub mod models;
pub mod params;
pub mod properties;
pub mod rusinkiewicz;
pub mod sampling;
pub mod sh;
pub mod simd;
pub mod tonemap;
pub mod vector;
pub mod views;

pub use error::BrdfError;
pub use frame::ShadingFrame;
pub use geometry::Geometry;
pub use models::{Bxdf, MODEL_SPECS, Model, ModelKind};
pub use params::{DerivedDefault, DerivedValue, Input, ModelSpec, ParamKind, ParamSpec, Params, Value};
