//! The course formulas of seeds 000 and 004, exactly as written: Lambert `C·max(n·l, 0)`, Phong
//! `kd·max(n·l, 0) + ks·clamp(v·r)^γ` and Blinn-Phong `kd·max(n·l, 0) + ks·max(n·h, 0)^s`.
//!
//! These are *classic* models ([`ModelKind::Classic`]): [`Bxdf::shade`] is the course formula — the
//! value a shader multiplies by the light colour — with no `1/π`, no normalisation and no energy
//! conservation, so a student's numbers (and the canonical benchmark render of bench/SCENE.md) come out
//! exactly. [`Bxdf::f`] is that value divided by `n·l` ([`classic_f`]). For the physical forms see
//! [`crate::models::Lambert`], [`crate::models::Phong`] and [`crate::models::BlinnPhong`].

use glam::Vec3;

use crate::models::phong::{mirror_deficit, pow_one_minus};
use crate::models::{Bxdf, ModelKind, classic_f};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};
use crate::{BrdfError, Geometry};

/// Largest accepted specular exponent: beyond it `x^s` underflows f32 for every `x` not within an ulp
/// of 1, so the highlight is a single-ulp delta.
pub const MAX_SHININESS: f32 = 10_000.0;

const KD: ParamSpec = ParamSpec::color(
    "kd",
    [0.8, 0.3, 0.2],
    0.0,
    1.0,
    "reflectance",
    "diffuse colour (multiplies max(n.l, 0))",
);
const KS: ParamSpec = ParamSpec::color("ks", [0.5, 0.5, 0.5], 0.0, 1.0, "reflectance", "specular colour");
const SHININESS: ParamSpec = ParamSpec::scalar(
    "shininess",
    32.0,
    0.0,
    MAX_SHININESS,
    "1",
    "specular exponent (larger = smaller highlight)",
);

/// Course Lambert: `shade = C · max(n·l, 0)` (seed 000, "Lambert": `f = C * max(dot(L, N), 0.0)`).
///
/// `C` is a colour, not a reflectance divided by π: the value is what seed 000's shader returns. Its
/// `f` is `C` for `n·l > 0`, i.e. π times [`crate::models::Lambert`] of albedo `C`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LambertClassic {
    /// Surface colour `C` (linear RGB).
    pub color: Vec3,
}

impl LambertClassic {
    /// Course Lambert of colour `color`.
    pub fn new(color: Vec3) -> Self {
        Self { color }
    }
}

impl Bxdf for LambertClassic {
    const SPEC: ModelSpec = ModelSpec {
        name: "lambert_classic",
        summary: "course Lambert, shade = color * max(n.l, 0) (no 1/pi)",
        source: "seed 000 (Lambert, GLSL); seed 004 eq. 12.21",
        physical: false,
        anisotropic: false,
        params: &[ParamSpec::color("color", [0.8, 0.8, 0.8], 0.0, 1.0, "reflectance", "surface colour C")],
    };
    const KIND: ModelKind = ModelKind::Classic;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("color")))
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        classic_f(self.shade(g), g)
    }

    #[inline]
    fn shade(&self, g: &Geometry) -> Vec3 {
        self.color * g.nl.max(0.0)
    }
}

/// Course Phong: `shade = kd·max(n·l, 0) + ks·clamp(v·r, 0, 1)^γ` with `r = 2(n·l)n − l` (seed 000
/// "Phong", `pow(clamp(dot(V, r), 0.0, 1.0), gamma)`; seed 004 eq. 12.23; seed 003 "Phong illumination
/// model").
///
/// **Gating.** With `specular_gate = true` (default) the specular term is 0 when `n·l ≤ 0`: a light
/// behind the surface cannot reach it, yet for a grazing viewer `v·r` can still be positive (`r` then
/// lies just below the horizon), which lights a highlight on the dark side. OpenGL's fixed-function
/// lighting, seed 004's `max(0, ·)` discussion and [`BlinnPhongClassic`] (bench/SCENE.md) all gate; set
/// `specular_gate = false` for seed 000's GLSL literally, which does not.
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
        summary: "course Phong, shade = kd*max(n.l,0) + ks*clamp(v.r,0,1)^shininess (specular gated on n.l>0)",
        source: "seed 000 (Phong, GLSL); seed 003; seed 004 eq. 12.23; Phong 1975",
        physical: false,
        anisotropic: false,
        params: &[
            KD,
            KS,
            SHININESS,
            ParamSpec::flag(
                "specular_gate",
                true,
                "zero the specular term when n.l <= 0 (false: seed 000's GLSL, which does not gate)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Classic;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self {
            kd: p.color("kd"),
            ks: p.color("ks"),
            shininess: p.scalar("shininess"),
            specular_gate: p.flag("specular_gate"),
        })
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        classic_f(self.shade(g), g)
    }

    #[inline]
    fn shade(&self, g: &Geometry) -> Vec3 {
        let diffuse = self.kd * g.nl.max(0.0);
        if self.specular_gate && g.nl <= 0.0 {
            return diffuse;
        }
        // clamp(v·r, 0, 1)^γ from the deficit d = 1 − v·r, symmetric in l and v: `2(n·l)(n·v) − l·v`
        // rounds v·r ≈ 1 to float32, γ·2^-24 relative and more at the highlight (phong::mirror_deficit).
        diffuse + self.ks * pow_one_minus(mirror_deficit(g), self.shininess)
    }
}

/// Course Blinn-Phong, exactly bench/SCENE.md's "exact shading formula" (seed 000 "Blinn"; seed 003;
/// seed 004 eq. 12.25; Blinn 1977):
///
/// ```text
/// shade = kd · max(n·l, 0) + (ks · max(n·h, 0)^s  if n·l > 0, else 0),   h = normalize(l + v)
/// ```
///
/// The canonical benchmark render sums `E_k · shade` over its lights and adds `a·kd` ambient. When
/// `l = −v` the half vector does not exist and the specular term is 0. `max(n·h, 0)^0 = 1`.
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
        summary: "course Blinn-Phong, shade = kd*max(n.l,0) + (ks*max(n.h,0)^shininess if n.l>0 else 0)",
        source: "bench/SCENE.md; seed 000 (Blinn); seed 003; seed 004 eq. 12.25; Blinn 1977",
        physical: false,
        anisotropic: false,
        params: &[KD, KS, SHININESS],
    };
    const KIND: ModelKind = ModelKind::Classic;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self { kd: p.color("kd"), ks: p.color("ks"), shininess: p.scalar("shininess") })
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        classic_f(self.shade(g), g)
    }

    #[inline]
    fn shade(&self, g: &Geometry) -> Vec3 {
        self.shade_generic::<f32>(&g.into(), true).into()
    }

    #[inline(always)]
    fn shade_lanes<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        self.shade_generic(g, active)
    }
}

impl BlinnPhongClassic {
    /// The formula once, for one sample or eight (the rasterizer's hot path). `h` as
    /// [`crate::vector::halfway`]: none (no specular) when `|l + v|² ≤ 1e-20`.
    #[inline(always)]
    fn shade_generic<F: Lane>(&self, g: &LaneGeometry<F>, active: F::Mask) -> V3<F> {
        let zero = F::splat(0.0);
        let diffuse = V3::splat(self.kd).scale(g.nl.max(zero));
        let s = g.l + g.v;
        let len2 = s.dot(s);
        let specular = active & g.nl.gt(zero) & len2.gt(F::splat(1e-20));
        let nh = g.n.dot(s / len2.sqrt()).max(zero);
        // `powf` has no lane form: run it on the lanes that keep it only.
        let s = self.shininess;
        let p = F::from_fn(|i| if F::mask_lane(specular, i) { nh.lane(i).powf(s) } else { 0.0 });
        V3::select(specular, diffuse + V3::splat(self.ks).scale(p), diffuse)
    }
}
