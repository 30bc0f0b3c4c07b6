//! Lafortune's generalised cosine lobes (E. Lafortune, S.-C. Foo, K. Torrance, D. Greenberg,
//! "Non-Linear Approximation of Reflectance Functions", SIGGRAPH 1997), and Schlick's
//! rational power (C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer
//! Graphics Forum 13(3), 1994).
//!
//! In the local frame (x = tangent, y = bitangent, z = normal), with `ρd` = `kd`, `ρs` = `ks`:
//!
//! ```text
//! f = ρd/π + ρs · Σᵢ max(0, Cx,i lx vx + Cy,i ly vy + Cz,i lz vz)^{nᵢ}
//! ```
//! `lᵀ M v` with a symmetric diagonal M, hence reciprocal. Cx = Cy = −1, Cz = 1 is Phong's `(r·v)ⁿ`;
//! Cx = Cy makes a lobe isotropic (then `Cz (l·v) + (Cx − Cz)(l⊥·v⊥)`, with `w⊥ = w − (n·w)n` the
//! tangent-plane part, needs no frame, and the model builds none when every lobe is isotropic);
//! Cx ≠ Cy is anisotropic; Cz < −Cx gives off-specular peaks; all C > 0 retro-reflection. The lobe
//! magnitude lives in the C's (`|C|ⁿ`): a Phong lobe of unit albedo at normal incidence has
//! `|C| = ((n+2)/(2π))^{1/n}`. Energy conservation is the caller's
//! choice of C, n, ρ (as in Lafortune 1997).

use glam::Vec3;

use crate::BrdfError;
use crate::frame::LaneFrame;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// Schlick's rational approximation of a power, `Sⁿ ≈ S/(n − nS + S)` for S ∈ [0, 1], n ≥ 0
/// (Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering"): exact at
/// S = 0 and S = 1, one division instead of `powf`, a slightly wider highlight than the true power.
/// S is clamped to [0, 1] (outside it the denominator can vanish).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn schlick_power<F: Lane>(s: F, n: f32) -> F {
    let s = s.clamp(0.0, 1.0);
    let n = F::splat(n);
    let den = n - n * s + s;
    F::select(den.gt(F::splat(0.0)), s / den, F::splat(1.0))
}

/// One generalised cosine lobe `max(0, Cx lx vx + Cy ly vy + Cz lz vz)^n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LafortuneLobe {
    /// Coefficient along the tangent.
    pub cx: f32,
    /// Coefficient along the bitangent.
    pub cy: f32,
    /// Coefficient along the normal.
    pub cz: f32,
    /// Exponent n ≥ 0.
    pub n: f32,
}

/// How a lobe's power is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LobePower {
    /// `powf`.
    Exact,
    /// [`schlick_power`] (base clamped to [0, 1]).
    Schlick,
}

/// Lafortune's compound cosine-lobe model.
#[derive(Debug, Clone, PartialEq)]
pub struct Lafortune {
    /// Diffuse reflectance ρd.
    pub kd: Vec3,
    /// Specular scale ρs.
    pub ks: Vec3,
    /// The lobes.
    pub lobes: Vec<LafortuneLobe>,
    /// Power evaluation.
    pub power: LobePower,
    isotropic: bool,
}

impl Lafortune {
    /// Model from its lobes; errors on no lobes or a negative/non-finite exponent or coefficient.
    pub fn new(kd: Vec3, ks: Vec3, lobes: Vec<LafortuneLobe>, power: LobePower) -> Result<Self, BrdfError> {
        if lobes.is_empty() {
            return Err(BrdfError::param("lobes", "needs at least one lobe [cx, cy, cz, n]"));
        }
        for (i, l) in lobes.iter().enumerate() {
            if ![l.cx, l.cy, l.cz, l.n].iter().all(|x| x.is_finite()) || l.n < 0.0 {
                return Err(BrdfError::param(
                    "lobes",
                    format!("row {i}: coefficients must be finite and the exponent n >= 0, got {l:?}"),
                ));
            }
        }
        let isotropic = lobes.iter().all(|l| l.cx == l.cy);
        Ok(Self { kd, ks, lobes, power, isotropic })
    }

    /// `max(0, s)ⁿ` with the model's power (0 where `s ≤ 0` or NaN).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn power_of<F: Lane>(&self, s: F, n: f32) -> F {
        let p = match self.power {
            LobePower::Exact => s.max(F::splat(0.0)).powf_uniform(n),
            LobePower::Schlick => schlick_power(s, n),
        };
        F::select(s.gt(F::splat(0.0)), p, F::splat(0.0))
    }
}

impl Bxdf for Lafortune {
    const SPEC: ModelSpec = ModelSpec {
        name: "lafortune",
        summary: "Lafortune 1997 cosine lobes, f = kd/pi + ks sum max(0, Cx lx vx + Cy ly vy + Cz lz vz)^n (local frame)",
        source: "E. Lafortune, S.-C. Foo, K. Torrance, D. Greenberg, Non-Linear Approximation of Reflectance Functions, SIGGRAPH (1997); rational power: C. Schlick, Computer Graphics Forum 13(3) (1994)",
        physical: true,
        anisotropic: true,
        params: &[
            ParamSpec::color("kd", [0.3; 3], 0.0, 1.0, "reflectance", "diffuse reflectance rho_d"),
            ParamSpec::color("ks", [1.0; 3], 0.0, 1.0e3, "1", "specular scale rho_s (multiplies every lobe)"),
            ParamSpec::array(
                "lobes",
                4,
                &[-1.0, -1.0, 1.0, 20.0],
                -1.0e3,
                1.0e6,
                "1",
                "rows [cx, cy, cz, n]; x = tangent, z = normal; n >= 0",
            ),
            ParamSpec::choice(
                "power",
                &["exact", "schlick"],
                "exact",
                "lobe power: powf, or Schlick's rational S/(n - nS + S)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted for `ρd`; each lobe `(l·(C∘v))ⁿ` by a `cosⁿ` lobe about `C∘v`
    /// ([`crate::sampling::cosine_power`]), weighted by `mean(ρs)·|C∘v|ⁿ·2π/(n+2)`, the lobe's albedo
    /// when the horizon does not cut it. At most 15 lobes.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let mut s = Sampler::new().with(Technique::Cosine, mean(self.kd));
        for c in &self.lobes {
            let t = Technique::CosineLobe { c: [c.cx, c.cy, c.cz], exponent: c.n };
            s = s.with(t, mean(self.ks) * 2.0 * std::f32::consts::PI / (c.n + 2.0));
        }
        Ok(s)
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        let lobes = p
            .array("lobes")
            .chunks_exact(4)
            .map(|r| LafortuneLobe { cx: r[0], cy: r[1], cz: r[2], n: r[3] })
            .collect();
        let power = match p.choice("power") {
            "schlick" => LobePower::Schlick,
            _ => LobePower::Exact,
        };
        Self::new(p.color("kd"), p.color("ks"), lobes, power)
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let mut sum = F::splat(0.0);
        if self.isotropic {
            // No frame: with w⊥ = w − (n·w)n the tangent-plane part, lx vx + ly vy = l⊥·v⊥ and
            // lz vz = l·v − l⊥·v⊥, so the base is Cz (l·v) + (Cx − Cz)(l⊥·v⊥). Not the cosine form
            // `Cx (l·v − (n·l)(n·v)) + Cz (n·l)(n·v)`: near the normal both products are ≈ 1 and their
            // difference keeps only their rounding (a Cz = 0 lobe came out at up to 116× its value
            // there, float32 input rounding explains 0.19×), and the large term carries the float32
            // n's length error twice. Here the large term l·v does not involve n, and the n-dependent
            // l⊥·v⊥ is small wherever a lobe peaks near the normal: a Phong lobe of n = 500 is now
            // within 1.9e-4 of the float64 oracle (was 4.1e-4). tests/test_lafortune_precision.py.
            let lv = g.l.dot(g.v);
            let tp = (g.l - g.n.scale(g.nl)).dot(g.v - g.n.scale(g.nv));
            for c in &self.lobes {
                sum = sum + self.power_of(F::splat(c.cz) * lv + F::splat(c.cx - c.cz) * tp, c.n);
            }
        } else {
            let frame = LaneFrame::of(g);
            let (l, v) = (frame.to_local(g.l), frame.to_local(g.v));
            for c in &self.lobes {
                let s = F::splat(c.cx) * l.x * v.x + F::splat(c.cy) * l.y * v.y + F::splat(c.cz) * l.z * v.z;
                sum = sum + self.power_of(s, c.n);
            }
        }
        V3::splat(self.kd * std::f32::consts::FRAC_1_PI) + V3::splat(self.ks).scale(sum)
    }
}
