//! Lambertian diffuse reflection, physical form `f_r = kd/π` (J. H. Lambert, *Photometria*, 1760; the
//! BRDF form as in Pharr, Jakob, Humphreys, *Physically Based Rendering*, 4th ed., 2023, §9.2).

use glam::Vec3;

use crate::BrdfError;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params, Value};
use crate::simd::{Lane, LaneGeometry, V3};

/// Ideal diffuse reflector: `f_r = kd/π` [1/sr]; its directional albedo is exactly `kd`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lambert {
    /// Diffuse reflectance `kd` ∈ [0, 1] per channel (the albedo).
    pub kd: Vec3,
}

impl Lambert {
    /// Lambertian reflector of diffuse reflectance `kd`.
    pub fn new(kd: Vec3) -> Self {
        Self { kd }
    }
}

impl Bxdf for Lambert {
    const SPEC: ModelSpec = ModelSpec {
        name: "lambert",
        summary: "Lambertian diffuse, f_r = kd/pi",
        source: "J. H. Lambert, Photometria (1760); BRDF form: Pharr, Jakob, Humphreys, Physically Based Rendering, 4th ed. (2023), sec. 9.2",
        physical: true,
        anisotropic: false,
        params: &[ParamSpec::color(
            "kd",
            [0.8, 0.8, 0.8],
            0.0,
            1.0,
            "reflectance",
            "diffuse reflectance (the albedo)",
        )],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted ([`crate::sampling::cosine`]): `f·cos/p = albedo` exactly.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd")))
    }

    #[inline]
    fn set_param(&mut self, slot: usize, value: &Value) -> bool {
        match (slot, value) {
            (0, Value::Color(c)) => {
                self.kd = Vec3::from_array(*c);
                true
            }
            _ => false,
        }
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, _g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        V3::splat(self.kd * std::f32::consts::FRAC_1_PI)
    }
}
