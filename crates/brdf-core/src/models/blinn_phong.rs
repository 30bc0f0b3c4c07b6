//! Normalised Blinn-Phong BRDF `f_r = kd/π + ks·N(m)·(n·h)^m` (Blinn 1977; T. Akenine-Möller, E. Haines,
//! N. Hoffman, *Real-Time Rendering*, 3rd ed., 2008, §7.6; F. Giesen, "The Blinn-Phong Normalization
//! Zoo", 2009), and the Blinn ↔ Phong exponent relation.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use crate::BrdfError;
use crate::models::classic::MAX_SHININESS;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// Which normalisation factor `N(m)` multiplies `(n·h)^m`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlinnPhongNormalization {
    /// `(m + 8)/(8π)` — Real-Time Rendering's factor ([`normalization_rtr`]).
    Rtr,
    /// `(m + 2)(m + 4)/(8π (2^(−m/2) + m))` — Giesen's exact factor ([`normalization_exact`]).
    Exact,
}

/// The Real-Time-Rendering normalisation of Blinn-Phong, `N(m) = (m + 8)/(8π)` [1/sr]
/// (Akenine-Möller, Haines, Hoffman, *Real-Time Rendering*, 3rd ed., §7.6).
///
/// It approximates [`normalization_exact`] and is **slightly too large** at low and moderate
/// exponents: the directional albedo at normal incidence of `N(m)(n·h)^m` is
/// `(m+8)(2^(−m/2)+m)/((m+2)(m+4))`, i.e. 1.024 at m = 1, 1.075 at m = 10, 1.018 at m = 100, → 1 for
/// m → ∞ — so a white "rtr" lobe reflects up to 7.5 % more than it receives.
#[inline]
pub fn normalization_rtr(m: f32) -> f32 {
    (m + 8.0) / (8.0 * PI)
}

/// The exact Blinn-Phong BRDF normalisation `N(m) = (m+2)(m+4) / (8π (2^(−m/2) + m))` [1/sr]
/// (F. Giesen 2009, "The Blinn-Phong normalization zoo"; TF Graphics `blinn_phong.py`).
///
/// With it the directional albedo of `N(m)(n·h)^m` at normal incidence (`v = n`) is exactly 1: there
/// `θ_h = θ_l/2`, and `∫ cos^m(θ/2) cos θ dω = 8π(2^(−m/2)+m)/((m+2)(m+4))`. At other view directions
/// the albedo is below 1 (the lobe widens and is clipped by the horizon), so the BRDF conserves energy
/// for `kd + ks ≤ 1`.
#[inline]
pub fn normalization_exact(m: f32) -> f32 {
    (m + 2.0) * (m + 4.0) / (8.0 * PI * ((-0.5 * m).exp2() + m))
}

/// Blinn exponent equivalent to a Phong exponent: `m_blinn = 4 · γ_phong`, the usual rule
/// `(r·v)^γ ≈ (n·h)^(4γ)`.
///
/// Why 4: when `l`, `v` and `n` are coplanar, the angle between `r` and `v` is exactly twice the angle
/// between `n` and `h`. For a small half-angle `x`,
/// `cos^γ(2x) = exp(γ ln cos 2x) ≈ exp(−2γx²)` and `cos^m(x) ≈ exp(−m x²/2)`; the two Gaussians agree
/// when `m = 4γ`. The relation is exact in the limit of small angles in the plane of incidence; out of
/// that plane the Blinn highlight is elongated (the angle between `n` and `h` grows more slowly than
/// half the angle between `r` and `v`), which is the well-known shape difference, not captured by any
/// exponent.
#[inline]
pub fn blinn_exponent_from_phong(phong_exponent: f32) -> f32 {
    4.0 * phong_exponent
}

/// Phong exponent equivalent to a Blinn exponent: `γ_phong = m_blinn / 4`, the inverse of
/// [`blinn_exponent_from_phong`].
#[inline]
pub fn phong_exponent_from_blinn(blinn_exponent: f32) -> f32 {
    0.25 * blinn_exponent
}

/// Physical, normalised Blinn-Phong BRDF [1/sr]:
///
/// ```text
/// f_r(l, v) = kd/π + ks · N(m) · (n·h)^m,    h = normalize(l + v)
/// ```
///
/// with `N(m)` = [`normalization_exact`] (`normalization = "exact"`, default, Giesen's exact factor) or
/// [`normalization_rtr`] (`"rtr"`, Real-Time Rendering's `(m+8)/(8π)`). Reciprocal (`h` is symmetric in
/// `l` and `v`). The "rtr" factor makes the lobe's albedo exceed `ks` at low and moderate exponents (up to
/// ×1.075 near m = 10; ×1.046 at the default m = 32, where the default `kd + ks = 1` then reflected 1.023
/// of the light at normal incidence), so only "exact" conserves energy for `kd + ks ≤ 1`: it is the
/// default, "rtr" is there to match engines that use it.
///
/// Unlike the microfacet Blinn-Phong distribution `D = (m+2)/(2π)(n·h)^m`, which is
/// normalised over microfacet normals, `N(m)` here normalises the whole BRDF lobe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlinnPhong {
    /// Diffuse reflectance `kd`.
    kd: Vec3,
    /// Specular reflectance `ks`.
    ks: Vec3,
    /// Blinn exponent `m ≥ 0`.
    shininess: f32,
    /// Normalisation factor in use.
    normalization: BlinnPhongNormalization,
    /// `kd/π`, precomputed.
    diffuse: Vec3,
    /// `ks · N(m)`, precomputed.
    specular: Vec3,
}

impl BlinnPhong {
    /// Normalised Blinn-Phong with diffuse `kd`, specular `ks`, exponent `shininess` and the given
    /// normalisation.
    pub fn new(kd: Vec3, ks: Vec3, shininess: f32, normalization: BlinnPhongNormalization) -> Self {
        let factor = match normalization {
            BlinnPhongNormalization::Rtr => normalization_rtr(shininess),
            BlinnPhongNormalization::Exact => normalization_exact(shininess),
        };
        Self { kd, ks, shininess, normalization, diffuse: kd * FRAC_1_PI, specular: ks * factor }
    }

    /// Diffuse reflectance `kd`.
    #[inline]
    pub fn kd(&self) -> Vec3 {
        self.kd
    }

    /// Specular reflectance `ks`.
    #[inline]
    pub fn ks(&self) -> Vec3 {
        self.ks
    }

    /// Blinn exponent `m ≥ 0`.
    #[inline]
    pub fn shininess(&self) -> f32 {
        self.shininess
    }

    /// Normalisation factor in use.
    #[inline]
    pub fn normalization(&self) -> BlinnPhongNormalization {
        self.normalization
    }
}

impl Bxdf for BlinnPhong {
    const SPEC: ModelSpec = ModelSpec {
        name: "blinn_phong",
        summary: "normalised Blinn-Phong, f_r = kd/pi + ks*N(m)*(n.h)^m, N = Giesen's exact factor ('exact') or (m+8)/(8pi) ('rtr')",
        source: "J. F. Blinn, SIGGRAPH (1977); normalisation: T. Akenine-Moller, E. Haines, N. Hoffman, Real-Time Rendering, 3rd ed. (2008), sec. 7.6; F. Giesen, The Blinn-Phong Normalization Zoo (2009)",
        physical: true,
        anisotropic: false,
        params: &[
            ParamSpec::color("kd", [0.5, 0.5, 0.5], 0.0, 1.0, "reflectance", "diffuse albedo"),
            ParamSpec::color("ks", [0.5, 0.5, 0.5], 0.0, 1.0, "reflectance", "specular reflectance"),
            ParamSpec::scalar("shininess", 32.0, 0.0, MAX_SHININESS, "1", "Blinn exponent m"),
            ParamSpec::choice(
                "normalization",
                &["exact", "rtr"],
                "exact",
                "exact: Giesen's (m+2)(m+4)/(8pi(2^(-m/2)+m)), albedo exactly ks head-on; rtr: (m+8)/(8pi) (Real-Time Rendering, up to 7.5 % above energy conservation)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted for `kd`, half vectors `∝ (n·h)^m` for `ks` ([`crate::sampling::cosine_power`]),
    /// chosen in proportion to `kd : ks`.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        Ok(Sampler::new()
            .with(Technique::Cosine, mean(self.kd))
            .with(Technique::HalfVectorPower { exponent: self.shininess }, mean(self.ks)))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        let normalization = match p.choice("normalization") {
            "rtr" => BlinnPhongNormalization::Rtr,
            _ => BlinnPhongNormalization::Exact,
        };
        Ok(Self::new(p.color("kd"), p.color("ks"), p.scalar("shininess"), normalization))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        // Both l and v are above the surface here, so l + v ≠ 0 and n·h > 0; h as in
        // `vector::halfway` (no half vector where |l + v|² ≤ 1e−20: diffuse only).
        let s = g.l + g.v;
        let len2 = s.dot(s);
        let nh = g.n.dot(s / len2.sqrt()).clamp(0.0, 1.0);
        let lobe = V3::splat(self.diffuse) + V3::splat(self.specular).scale(nh.powf_uniform(self.shininess));
        V3::select(len2.gt(F::splat(1e-20)), lobe, V3::splat(self.diffuse))
    }
}
