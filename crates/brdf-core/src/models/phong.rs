//! Energy-normalised ("modified") Phong BRDF: `f_r = kd/π + ks·(γ+2)/(2π)·max(r·v, 0)^γ`
//! (seeds 002 "Normalization", 003 "Phong reflection model"; Lewis 1994; Lafortune & Willems 1994).

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use crate::models::classic::MAX_SHININESS;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::{BrdfError, Geometry};

/// Physical Phong BRDF [1/sr]:
///
/// ```text
/// f_r(l, v) = kd/π + ks · (γ + 2)/(2π) · max(r·v, 0)^γ,    r = 2(n·l)n − l
/// ```
///
/// The factor `(γ+2)/(2π)` makes the specular lobe's directional albedo exactly `ks` when the lobe is
/// not cut by the horizon — at normal incidence, and nearly so whenever the mirror direction is far from
/// grazing: `∫ cos^γ α · cos θ_l dω = 2π cos θ_v/(γ+2)` for an unclipped lobe (Lewis 1994, "Making
/// shaders more physically plausible"). The albedo is therefore `≤ kd + ks`, equal at normal incidence;
/// energy is conserved when `kd + ks ≤ 1` per channel, which is the caller's choice (not enforced, as in
/// Lafortune & Willems 1994). `r·v = 2(n·l)(n·v) − l·v` is symmetric in `l` and `v`, so the BRDF is
/// reciprocal — unlike the course formula ([`crate::models::PhongClassic`]), whose `shade` has no
/// `n·l` factor on the specular term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    /// Diffuse reflectance `kd` (the diffuse albedo).
    kd: Vec3,
    /// Specular reflectance `ks` (the lobe's albedo at normal incidence).
    ks: Vec3,
    /// Phong exponent γ ≥ 0.
    shininess: f32,
    /// `kd/π`, precomputed.
    diffuse: Vec3,
    /// `ks (γ+2)/(2π)`, precomputed.
    specular: Vec3,
}

impl Phong {
    /// Normalised Phong with diffuse `kd`, specular `ks` and exponent `shininess`.
    pub fn new(kd: Vec3, ks: Vec3, shininess: f32) -> Self {
        Self { kd, ks, shininess, diffuse: kd * FRAC_1_PI, specular: ks * ((shininess + 2.0) / (2.0 * PI)) }
    }

    /// Diffuse reflectance `kd` (the diffuse albedo).
    #[inline]
    pub fn kd(&self) -> Vec3 {
        self.kd
    }

    /// Specular reflectance `ks` (the lobe's albedo at normal incidence).
    #[inline]
    pub fn ks(&self) -> Vec3 {
        self.ks
    }

    /// Phong exponent γ ≥ 0.
    #[inline]
    pub fn shininess(&self) -> f32 {
        self.shininess
    }
}

impl Bxdf for Phong {
    const SPEC: ModelSpec = ModelSpec {
        name: "phong",
        summary: "energy-normalised Phong, f_r = kd/pi + ks*(shininess+2)/(2pi)*max(r.v,0)^shininess",
        source: "seeds 002, 003; Lewis 1994; Lafortune & Willems 1994",
        physical: true,
        anisotropic: false,
        params: &[
            ParamSpec::color("kd", [0.5, 0.5, 0.5], 0.0, 1.0, "reflectance", "diffuse albedo"),
            ParamSpec::color(
                "ks",
                [0.5, 0.5, 0.5],
                0.0,
                1.0,
                "reflectance",
                "specular albedo at normal incidence (kd + ks <= 1 conserves energy)",
            ),
            ParamSpec::scalar("shininess", 32.0, 0.0, MAX_SHININESS, "1", "Phong exponent gamma"),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd"), p.color("ks"), p.scalar("shininess")))
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        // r·v = 2(n·l)(n·v) − l·v: bit-for-bit symmetric in l and v.
        let rv = 2.0 * g.nl * g.nv - g.l.dot(g.v);
        if rv <= 0.0 {
            return self.diffuse;
        }
        self.diffuse + self.specular * rv.min(1.0).powf(self.shininess)
    }
}
