//! The textbook illumination formulas, exactly as written: Lambert `kd·max(n·l, 0)`, Phong
//! `kd·max(n·l, 0) + ks·clamp(v·r)^γ` (B. T. Phong, "Illumination for Computer Generated Pictures",
//! CACM 18(6), 1975) and Blinn-Phong `kd·max(n·l, 0) + ks·max(n·h, 0)^s` (J. F. Blinn, "Models of
//! Light Reflection for Computer Synthesized Pictures", SIGGRAPH 1977), in the form of T. Theoharis,
//! G. Papaioannou, N. Platis, N. M. Patrikalakis, *Graphics and Visualization: Principles and
//! Algorithms* (A K Peters, 2008), ch. 12, eqs. 12.21, 12.23 and 12.25.
//!
//! These are *classic* models ([`ModelKind::Classic`]): [`Bxdf::shade`] is the textbook formula — the
//! value a shader multiplies by the light colour — with no `1/π`, no normalisation and no energy
//! conservation, so a student's numbers come out exactly. [`Bxdf::f`] is that value divided by `n·l`
//! ([`classic_f`](crate::models::classic_f)). For the physical forms see [`crate::models::Lambert`], [`crate::models::Phong`]
//! and [`crate::models::BlinnPhong`].

use glam::Vec3;

use crate::BrdfError;
use crate::models::phong::{mirror_deficit, pow_one_minus};
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// Largest accepted specular exponent: beyond it `x^s` underflows f32 for every `x` not within an ulp
/// of 1, so the highlight is a single-ulp delta.
pub const MAX_SHININESS: f32 = 10_000.0;

const KD: ParamSpec = ParamSpec::color(
    "kd",
    [0.8, 0.3, 0.2],
    0.0,
    1.0,
    "reflectance",
    "diffuse reflectance (multiplies max(n.l, 0))",
);
const KS: ParamSpec = ParamSpec::color(
    "ks",
    [0.5, 0.5, 0.5],
    0.0,
    1.0,
    "reflectance",
    "specular reflectance (highlight colour)",
);
const SHININESS: ParamSpec = ParamSpec::scalar(
    "shininess",
    32.0,
    0.0,
    MAX_SHININESS,
    "1",
    "specular exponent (larger = smaller highlight)",
);

/// Textbook Lambert: `shade = kd · max(n·l, 0)` (Theoharis et al. 2008, eq. 12.21; a GLSL shader's
/// `kd * max(dot(L, N), 0.0)`).
///
/// `kd` multiplies the cosine directly, with no `1/π`: its `f` is `kd` for `n·l > 0`, i.e. π times
/// [`crate::models::Lambert`] of the same `kd`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LambertClassic {
    /// Diffuse reflectance `kd` (linear RGB).
    pub kd: Vec3,
}

impl LambertClassic {
    /// Textbook Lambert of diffuse reflectance `kd`.
    pub fn new(kd: Vec3) -> Self {
        Self { kd }
    }
}

impl Bxdf for LambertClassic {
    const SPEC: ModelSpec = ModelSpec {
        name: "lambert_classic",
        summary: "textbook Lambert, shade = kd * max(n.l, 0) (no 1/pi)",
        source: "J. H. Lambert, Photometria (1760); as in Theoharis, Papaioannou, Platis, Patrikalakis, Graphics and Visualization (2008), ch. 12, eq. 12.21",
        physical: false,
        anisotropic: false,
        params: &[ParamSpec::color(
            "kd",
            [0.8, 0.8, 0.8],
            0.0,
            1.0,
            "reflectance",
            "diffuse reflectance (multiplies max(n.l, 0))",
        )],
    };
    const KIND: ModelKind = ModelKind::Classic;

    /// Cosine-weighted ([`crate::sampling::cosine`]): `shade/p = π C` exactly.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd")))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        V3::splat(self.kd).scale(g.nl.max(F::splat(0.0)))
    }
}

/// Textbook Phong: `shade = kd·max(n·l, 0) + ks·clamp(v·r, 0, 1)^γ` with `r = 2(n·l)n − l` (Phong
/// 1975; Theoharis et al. 2008, eq. 12.23; a GLSL shader's `pow(clamp(dot(V, r), 0.0, 1.0), gamma)`).
///
/// **Gating.** With `specular_gate = true` (default) the specular term is 0 when `n·l ≤ 0`: a light
/// behind the surface cannot reach it, yet for a grazing viewer `v·r` can still be positive (`r` then
/// lies just below the horizon), which lights a highlight on the dark side. OpenGL's fixed-function
/// lighting, Theoharis et al.'s `max(0, ·)` discussion and [`BlinnPhongClassic`] all gate; set
/// `specular_gate = false` for the ungated formula as many GLSL shaders write it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhongClassic {
    /// Diffuse colour `kd`.
    pub kd: Vec3,
    /// Specular colour `ks`.
    pub ks: Vec3,
    /// Phong exponent γ.
    pub shininess: f32,
    /// Zero the specular term when `n·l ≤ 0` (see the type docs).
    pub specular_gate: bool,
}

impl Bxdf for PhongClassic {
    const SPEC: ModelSpec = ModelSpec {
        name: "phong_classic",
        summary: "textbook Phong, shade = kd*max(n.l,0) + ks*clamp(v.r,0,1)^shininess (specular gated on n.l>0)",
        source: "B. T. Phong, Illumination for Computer Generated Pictures, CACM 18(6) (1975); as in Theoharis et al., Graphics and Visualization (2008), ch. 12, eq. 12.23",
        physical: false,
        anisotropic: false,
        params: &[
            KD,
            KS,
            SHININESS,
            ParamSpec::flag(
                "specular_gate",
                true,
                "zero the specular term when n.l <= 0 (false: ungated, as many GLSL shaders write it)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Classic;

    /// Cosine-weighted for `kd`, Phong's lobe `(r·v)^γ` ([`crate::sampling::cosine_power`]) for the
    /// highlight, weighted by its integral `mean(ks)·2π/(γ+1)`: the highlight's `shade` is exactly that lobe.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let spec = mean(self.ks) * 2.0 * std::f32::consts::PI / (self.shininess + 1.0);
        Ok(Sampler::new().with(Technique::Cosine, mean(self.kd)).with(Technique::phong(self.shininess), spec))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self {
            kd: p.color("kd"),
            ks: p.color("ks"),
            shininess: p.scalar("shininess"),
            specular_gate: p.flag("specular_gate"),
        })
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let zero = F::splat(0.0);
        let diffuse = V3::splat(self.kd).scale(g.nl.max(zero));
        // clamp(v·r, 0, 1)^γ from the deficit d = 1 − v·r, symmetric in l and v: `2(n·l)(n·v) − l·v`
        // rounds v·r ≈ 1 to float32, γ·2^-24 relative and more at the highlight (phong::mirror_deficit).
        let specular = V3::splat(self.ks).scale(pow_one_minus(mirror_deficit(g), self.shininess));
        let gated = F::mask_splat(self.specular_gate) & g.nl.le(zero);
        V3::select(gated, diffuse, diffuse + specular)
    }
}

/// Textbook Blinn-Phong (Blinn 1977; Theoharis et al. 2008, eq. 12.25), with the specular term gated
/// on `n·l > 0`:
///
/// ```text
/// shade = kd · max(n·l, 0) + (ks · max(n·h, 0)^s  if n·l > 0, else 0),   h = normalize(l + v)
/// ```
///
/// A renderer sums `E_k · shade` over its lights and adds `a·kd` ambient. When `l = −v` the half
/// vector does not exist and the specular term is 0. `max(n·h, 0)^0 = 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlinnPhongClassic {
    /// Diffuse colour `kd`.
    pub kd: Vec3,
    /// Specular colour `ks`.
    pub ks: Vec3,
    /// Blinn exponent `s`.
    pub shininess: f32,
}

impl Bxdf for BlinnPhongClassic {
    const SPEC: ModelSpec = ModelSpec {
        name: "blinn_phong_classic",
        summary: "textbook Blinn-Phong, shade = kd*max(n.l,0) + (ks*max(n.h,0)^shininess if n.l>0 else 0)",
        source: "J. F. Blinn, Models of Light Reflection for Computer Synthesized Pictures, SIGGRAPH (1977); as in Theoharis et al., Graphics and Visualization (2008), ch. 12, eq. 12.25",
        physical: false,
        anisotropic: false,
        params: &[KD, KS, SHININESS],
    };
    const KIND: ModelKind = ModelKind::Classic;

    /// Cosine-weighted for `kd`, half vectors `∝ (n·h)^s` ([`crate::sampling::cosine_power`]) for the
    /// highlight, weighted by `mean(ks)·4π/(s+1)` (the highlight's integral at `n·v ≈ ½`).
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let spec = mean(self.ks) * 4.0 * std::f32::consts::PI / (self.shininess + 1.0);
        Ok(Sampler::new()
            .with(Technique::Cosine, mean(self.kd))
            .with(Technique::HalfVectorPower { exponent: self.shininess }, spec))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self { kd: p.color("kd"), ks: p.color("ks"), shininess: p.scalar("shininess") })
    }

    /// `h` as [`crate::vector::halfway`]: none (no specular) when `|l + v|² ≤ 1e-20`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let zero = F::splat(0.0);
        let diffuse = V3::splat(self.kd).scale(g.nl.max(zero));
        let s = g.l + g.v;
        let len2 = s.dot(s);
        let specular = g.nl.gt(zero) & len2.gt(F::splat(1e-20));
        let nh = g.n.dot(s / len2.sqrt()).max(zero);
        let p = nh.powf_uniform(self.shininess);
        V3::select(specular, diffuse + V3::splat(self.ks).scale(p), diffuse)
    }
}
