//! Lambertian diffuse reflection, physical form `f_r = ρ/π` (seeds 002, 003, 004; Lambert 1760).

use glam::Vec3;

use crate::models::{Bxdf, ModelKind, physical_shade_lanes};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};
use crate::{BrdfError, Geometry};

/// Ideal diffuse reflector: `f_r = ρ/π` [1/sr]; directional albedo is exactly `ρ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lambert {
    /// Diffuse reflectance ρ ∈ [0, 1] per channel.
    pub albedo: Vec3,
}

impl Lambert {
    /// Lambertian reflector of reflectance `albedo`.
    pub fn new(albedo: Vec3) -> Self {
        Self { albedo }
    }
}

impl Bxdf for Lambert {
    const SPEC: ModelSpec = ModelSpec {
        name: "lambert",
        summary: "Lambertian diffuse, f_r = albedo/pi",
        source: "seeds 002, 003, 004; J. H. Lambert, Photometria (1760)",
        physical: true,
        anisotropic: false,
        params: &[ParamSpec::color(
            "albedo",
            [0.8, 0.8, 0.8],
            0.0,
            1.0,
            "reflectance",
            "diffuse reflectance rho",
        )],
    };
    const KIND: ModelKind = ModelKind::Physical;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("albedo")))
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        self.f_lanes(&LaneGeometry::from(g), true).into()
    }

    #[inline(always)]
    fn f_lanes<F: Lane>(&self, _g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        V3::splat(self.albedo * std::f32::consts::FRAC_1_PI)
    }

    #[inline(always)]
    fn shade_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        physical_shade_lanes(self, g, active)
    }
}
