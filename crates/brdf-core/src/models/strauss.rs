//! Strauss's lighting model for animators (P. S. Strauss, "A Realistic Lighting Model for Computer
//! Animators", IEEE Computer Graphics and Applications 10(6), 56–64, 1990).
//!
//! Per colour channel, for a light of unit colour (`c_r = c_i (Q_d + Q_s + Q_a)`), with `C` the surface
//! colour (`base_color`: the diffuse colour, and for metals the highlight's colour too, so it is not a
//! diffuse reflectance `kd`):
//!
//! ```text
//! x_i = θ_i/(π/2), x_r = θ_r/(π/2)                      normalised angles of l and v to n
//! r_d = (1 − s³)(1 − t),  d = 1 − m s,  r_n = (1 − t) − r_d
//! Q_d = (n·l) d r_d C                                   diffuse
//! j   = F(x_i) G(x_i) G(x_r),   r_j = min(1, r_n + (r_n + k_j) j)
//! Q_s = max(r·v, 0)^{3/(1−s)} r_j C_s,  C_s = 1 + m (1 − F(x_i)) (C − 1)   specular
//! Q_a = r_d C                                           ambient ([`Strauss::ambient`])
//! F(x) = [1/(x−k_f)² − 1/k_f²] / [1/(1−k_f)² − 1/k_f²]
//! G(x) = [1/(1−k_s)² − 1/(x−k_s)²] / [1/(1−k_s)² − 1/k_s²]
//! ```
//! with Strauss's constants `k_f = 1.12`, `k_s = 1.01`, `k_j = 0.1`, registered as `k_fresnel`,
//! `k_shadow` and `k_offspecular` (Strauss's `k_s` is a shadow constant, not a specular reflectance;
//! some texts call it `k_g`; `k_j` sets the off-specular rise of the reflectivity toward grazing).
//!
//! Slips in a widely copied GLSL fragment program of the model, fixed against Strauss 1990:
//! - `f = F((θ_i + θ_r)/2)`: Strauss uses `F(θ_i)` (incidence angle) in both `j` and `C_s`. Default
//!   `fresnel_angle = "incidence"`; `"mean"` reproduces the shader (which makes the highlight factor
//!   symmetric in l and v; the model is still not reciprocal).
//! - `pow(-dot(H, V), …)` with `V` pointing *to* the eye: the sign is Strauss's convention of both
//!   vectors pointing *toward* the surface; in ours the specular base is `r·v` with
//!   `r = 2(n·l)n − l`, clamped at 0 (a negative base to a real power is NaN in GLSL).
//! - `3/(1.0001 − s)`: a guard against s = 1. We use Strauss's `3/(1 − s)` with s capped at 0.9999
//!   (exponent ≤ 30000) so the exponent is exact for every s < 0.9999.
//! - `Q_a` is used but never computed, and `pi` is mistyped 3.1415936 (unused). `Q_a` is exposed as
//!   [`Strauss::ambient`] for the illumination model; the opacity `1 − t` as [`Strauss::opacity`].
//! - The shader clamps `Q_d`, `Q_s` to [0, 1]; for parameters in their ranges both already are
//!   (r_j ≤ 1, C_s ∈ [C, 1]), so no clamp is applied.
//!
//! **Kind:** physical-ish. Its parameters are normalised and its output bounded, but it is an
//! empirical *shading formula* (Q_s carries no `n·l`, F uses the incidence angle only), not a
//! reciprocal BRDF, so it is registered as a classic model: `shade` is the formula above and `f`
//! is `shade/(n·l)`. Light or viewer at or below the horizon gives 0.

use std::f32::consts::FRAC_2_PI;

use glam::Vec3;

use crate::BrdfError;
use crate::models::phong::{mirror_deficit, pow_one_minus};
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// Largest smoothness used in the exponent `3/(1 − s)` (see the module docs).
pub const SMOOTHNESS_MAX: f32 = 0.9999;

/// Which angle Strauss's Fresnel-like factor reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StraussFresnelAngle {
    /// `F(x_i)`, Strauss 1990.
    Incidence,
    /// `F((x_i + x_r)/2)`, a common GLSL shader's form.
    Mean,
}

/// Strauss's model (see the module docs for the formula and the fixes to a common shader).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strauss {
    /// Surface colour C (linear RGB): diffuse colour, and highlight colour for metals.
    pub base_color: Vec3,
    /// Smoothness s ∈ [0, 1].
    pub smoothness: f32,
    /// Metalness m ∈ [0, 1].
    pub metalness: f32,
    /// Transparency t ∈ [0, 1].
    pub transparency: f32,
    /// Fresnel constant k_f (> 1).
    pub k_fresnel: f32,
    /// Shadow constant k_s (> 1).
    pub k_shadow: f32,
    /// Off-specular reflectivity offset k_j.
    pub k_offspecular: f32,
    /// Angle F reads.
    pub fresnel_angle: StraussFresnelAngle,
    rd: f32,
    rn: f32,
    d: f32,
    exponent: f32,
    f_den: f32,
    g_den: f32,
}

impl Strauss {
    /// Strauss's model with Strauss's constants `k_f = 1.12`, `k_s = 1.01`, `k_j = 0.1`.
    pub fn new(base_color: Vec3, smoothness: f32, metalness: f32, transparency: f32) -> Self {
        Self::with_constants(
            base_color,
            smoothness,
            metalness,
            transparency,
            1.12,
            1.01,
            0.1,
            StraussFresnelAngle::Incidence,
        )
    }

    /// Full constructor. `k_fresnel`, `k_shadow` must exceed 1 (their poles must lie outside
    /// x ∈ [0, 1]); they are raised to 1.0001 if not.
    #[allow(clippy::too_many_arguments)]
    pub fn with_constants(
        base_color: Vec3,
        smoothness: f32,
        metalness: f32,
        transparency: f32,
        k_fresnel: f32,
        k_shadow: f32,
        k_offspecular: f32,
        fresnel_angle: StraussFresnelAngle,
    ) -> Self {
        let s = smoothness.clamp(0.0, 1.0);
        let t = transparency.clamp(0.0, 1.0);
        let m = metalness.clamp(0.0, 1.0);
        let kf = k_fresnel.max(1.0001);
        let ks = k_shadow.max(1.0001);
        let rd = (1.0 - s * s * s) * (1.0 - t);
        Self {
            base_color,
            smoothness: s,
            metalness: m,
            transparency: t,
            k_fresnel: kf,
            k_shadow: ks,
            k_offspecular,
            fresnel_angle,
            rd,
            rn: (1.0 - t) - rd,
            d: 1.0 - m * s,
            exponent: 3.0 / (1.0 - s.min(SMOOTHNESS_MAX)),
            f_den: 1.0 / ((1.0 - kf) * (1.0 - kf)) - 1.0 / (kf * kf),
            g_den: 1.0 / ((1.0 - ks) * (1.0 - ks)) - 1.0 / (ks * ks),
        }
    }

    /// Strauss's Fresnel-like factor `F(x)`, x = normalised angle ∈ [0, 1]: 0 at x = 0, 1 at x = 1.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn fresnel<F: Lane>(&self, x: F) -> F {
        let kf = self.k_fresnel;
        let d = x - F::splat(kf);
        (F::splat(1.0) / (d * d) - F::splat(1.0 / (kf * kf))) / F::splat(self.f_den)
    }

    /// Strauss's shadow factor `G(x)`: 1 at x = 0, 0 at x = 1.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn shadow<F: Lane>(&self, x: F) -> F {
        let ks = self.k_shadow;
        let d = x - F::splat(ks);
        (F::splat(1.0 / ((1.0 - ks) * (1.0 - ks))) - F::splat(1.0) / (d * d)) / F::splat(self.g_den)
    }

    /// Ambient reflectance `Q_a = r_d C` (multiply by the ambient light colour).
    pub fn ambient(&self) -> Vec3 {
        self.rd * self.base_color
    }

    /// Opacity `1 − t` (a shader writes it to alpha).
    pub fn opacity(&self) -> f32 {
        1.0 - self.transparency
    }
}

/// `|n × w|` = sin of the angle between unit `n` and `w`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn sin_to<F: Lane>(n: V3<F>, w: V3<F>) -> F {
    let c = n.cross(w);
    c.dot(c).sqrt()
}

impl Bxdf for Strauss {
    const SPEC: ModelSpec = ModelSpec {
        name: "strauss",
        summary: "Strauss 1990: Qd = (n.l) d rd C, Qs = max(r.v,0)^(3/(1-s)) rj Cs; normalised smoothness/metalness/transparency",
        source: "P. S. Strauss, A Realistic Lighting Model for Computer Animators, IEEE Computer Graphics and Applications 10(6) (1990)",
        physical: false,
        anisotropic: false,
        params: &[
            ParamSpec::color(
                "base_color",
                [0.8, 0.3, 0.2],
                0.0,
                1.0,
                "reflectance",
                "surface colour C: the diffuse colour, and the highlight colour of metals",
            ),
            ParamSpec::scalar("smoothness", 0.5, 0.0, 1.0, "1", "s: 0 dull .. 1 mirror"),
            ParamSpec::scalar("metalness", 0.0, 0.0, 1.0, "1", "m: 0 dielectric .. 1 metal"),
            ParamSpec::scalar("transparency", 0.0, 0.0, 1.0, "1", "t: 0 opaque .. 1 transparent"),
            ParamSpec::scalar("k_fresnel", 1.12, 1.001, 10.0, "1", "Strauss's Fresnel constant k_f"),
            ParamSpec::scalar("k_shadow", 1.01, 1.001, 10.0, "1", "Strauss's shadow constant k_s"),
            ParamSpec::scalar(
                "k_offspecular",
                0.1,
                0.0,
                1.0,
                "1",
                "Strauss's k_j: how much the reflectivity rises toward grazing (off-specular peak)",
            ),
            ParamSpec::choice(
                "fresnel_angle",
                &["incidence", "mean"],
                "incidence",
                "F reads theta_i (Strauss 1990) or (theta_i+theta_r)/2 (a common GLSL shader's form)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Classic;

    /// Cosine-weighted for `Q_d`, Phong's lobe `(r·v)^{3/(1−s)}` for `Q_s` (whose `shade` is exactly
    /// that lobe times `r_j C_s`), weighted by `mean(d r_d C)` and `(r_n + k_j)·2π/(h+1)`.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let spec = (self.rn + self.k_offspecular) * 2.0 * std::f32::consts::PI / (self.exponent + 1.0);
        Ok(Sampler::new()
            .with(Technique::Cosine, mean(self.d * self.rd * self.base_color))
            .with(Technique::phong(self.exponent), spec))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        let angle = match p.choice("fresnel_angle") {
            "mean" => StraussFresnelAngle::Mean,
            _ => StraussFresnelAngle::Incidence,
        };
        Ok(Self::with_constants(
            p.color("base_color"),
            p.scalar("smoothness"),
            p.scalar("metalness"),
            p.scalar("transparency"),
            p.scalar("k_fresnel"),
            p.scalar("k_shadow"),
            p.scalar("k_offspecular"),
            angle,
        ))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let (zero, one) = (F::splat(0.0), F::splat(1.0));
        // θ = atan2(|n×w|, n·w), not acos(n·w): near the normal a float32 cosine ≈ 1 is known only to a
        // few 2^-24, which acos turns into ~2^-24/sin θ of angle (1e-4 rad at θ = 5e-4; r_j came out
        // 180× further from the float64 oracle than input rounding explains); |n×w| keeps sin θ to a
        // few 2^-24 relative. tests/test_phong_precision.py.
        let xi = sin_to(g.n, g.l).atan2(g.nl) * F::splat(FRAC_2_PI);
        let xr = sin_to(g.n, g.v).atan2(g.nv) * F::splat(FRAC_2_PI);
        let f = self.fresnel(match self.fresnel_angle {
            StraussFresnelAngle::Incidence => xi,
            StraussFresnelAngle::Mean => F::splat(0.5) * (xi + xr),
        });
        let j = f * self.shadow(xi) * self.shadow(xr);
        let rn = F::splat(self.rn);
        let rj = (rn + (rn + F::splat(self.k_offspecular)) * j).min(one);
        // max(r·v, 0)^h from the deficit d = 1 − r·v: `r·v` itself near 1 is rounded to float32, which
        // the exponent (up to 30000) amplifies to h·2^-24 relative and more (phong::mirror_deficit).
        let d = mirror_deficit(g);
        let rs = F::select(d.lt(one), pow_one_minus(d, self.exponent) * rj, zero);
        let cs = V3::splat(Vec3::ONE)
            + V3::splat(self.base_color - Vec3::ONE).scale(F::splat(self.metalness) * (one - f));
        let qd = V3::splat(self.base_color).scale(g.nl * F::splat(self.d) * F::splat(self.rd));
        V3::select(g.both_above(), qd + cs.scale(rs), V3::splat(Vec3::ZERO))
    }
}
