//! Lafortune's generalised cosine lobes (E. Lafortune, S.-C. Foo, K. Torrance, D. Greenberg,
//! "Non-Linear Approximation of Reflectance Functions", SIGGRAPH 1997; seed 001 "Generalized cosine
//! lobe model", "Compound model"), and Schlick's rational power (Schlick 1994; seed 001).
//!
//! In the local frame (x = tangent, y = bitangent, z = normal; seed 001's b, t, n):
//!
//! ```text
//! f = ρd/π + ρs · Σᵢ max(0, Cx,i lx vx + Cy,i ly vy + Cz,i lz vz)^{nᵢ}
//! ```
//! `lᵀ M v` with a symmetric diagonal M, hence reciprocal. Cx = Cy = −1, Cz = 1 is Phong's `(r·v)ⁿ`;
//! Cx = Cy makes a lobe isotropic (then `Cz (l·v) + (Cx − Cz)(l⊥·v⊥)`, with `w⊥ = w − (n·w)n` the
//! tangent-plane part, needs no frame, and the model builds none when every lobe is isotropic);
//! Cx ≠ Cy is anisotropic; Cz < −Cx gives off-specular peaks; all C > 0 retro-reflection. The lobe
//! magnitude lives in the C's (`|C|ⁿ`): a Phong lobe of unit albedo at normal incidence has
//! `|C| = ((n+2)/(2π))^{1/n}` (seed 001 "Cosine lobe options"). Energy conservation is the caller's
//! choice of C, n, ρ (as in Lafortune 1997).

use glam::{Vec3, Vec3A};

use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::{BrdfError, Geometry};

/// Schlick's rational approximation of a power, `Sⁿ ≈ S/(n − nS + S)` for S ∈ [0, 1], n ≥ 0
/// (Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering"; seed 001): exact at
/// S = 0 and S = 1, one division instead of `powf`, a slightly wider highlight than the true power.
/// S is clamped to [0, 1] (outside it the denominator can vanish).
#[inline]
pub fn schlick_power(s: f32, n: f32) -> f32 {
    let s = s.clamp(0.0, 1.0);
    let den = n - n * s + s;
    if den > 0.0 { s / den } else { 1.0 }
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
    pub rho_d: Vec3,
    /// Specular scale ρs.
    pub rho_s: Vec3,
    /// The lobes.
    pub lobes: Vec<LafortuneLobe>,
    /// Power evaluation.
    pub power: LobePower,
    isotropic: bool,
}

impl Lafortune {
    /// Model from its lobes; errors on no lobes or a negative/non-finite exponent or coefficient.
    pub fn new(
        rho_d: Vec3,
        rho_s: Vec3,
        lobes: Vec<LafortuneLobe>,
        power: LobePower,
    ) -> Result<Self, BrdfError> {
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
        Ok(Self { rho_d, rho_s, lobes, power, isotropic })
    }

    #[inline]
    fn lobe_sum(&self, l: Vec3A, v: Vec3A) -> f32 {
        self.lobes
            .iter()
            .map(|c| {
                let s = c.cx * l.x * v.x + c.cy * l.y * v.y + c.cz * l.z * v.z;
                self.power_of(s, c.n)
            })
            .sum()
    }

    #[inline]
    fn power_of(&self, s: f32, n: f32) -> f32 {
        if !(s > 0.0) {
            return 0.0;
        }
        match self.power {
            LobePower::Exact => s.powf(n),
            LobePower::Schlick => schlick_power(s, n),
        }
    }
}

impl Bxdf for Lafortune {
    const SPEC: ModelSpec = ModelSpec {
        name: "lafortune",
        summary: "Lafortune 1997 cosine lobes, f = rho_d/pi + rho_s sum max(0, Cx lx vx + Cy ly vy + Cz lz vz)^n (local frame)",
        source: "seed 001; Lafortune, Foo, Torrance, Greenberg 1997; Schlick 1994 (rational power)",
        physical: true,
        anisotropic: true,
        params: &[
            ParamSpec::color("rho_d", [0.3; 3], 0.0, 1.0, "reflectance", "diffuse reflectance"),
            ParamSpec::color("rho_s", [1.0; 3], 0.0, 1.0e3, "1", "specular scale"),
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
        Self::new(p.color("rho_d"), p.color("rho_s"), lobes, power)
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        let sum = if self.isotropic {
            // No frame: with w⊥ = w − (n·w)n the tangent-plane part, lx vx + ly vy = l⊥·v⊥ and
            // lz vz = l·v − l⊥·v⊥, so the base is Cz (l·v) + (Cx − Cz)(l⊥·v⊥). Not the cosine form
            // `Cx (l·v − (n·l)(n·v)) + Cz (n·l)(n·v)`: near the normal both products are ≈ 1 and their
            // difference keeps only their rounding (a Cz = 0 lobe came out at up to 116× its value
            // there, float32 input rounding explains 0.19×), and the large term carries the float32
            // n's length error twice. Here the large term l·v does not involve n, and the n-dependent
            // l⊥·v⊥ is small wherever a lobe peaks near the normal: a Phong lobe of n = 500 is now
            // within 1.9e-4 of the float64 oracle (was 4.1e-4). tests/test_lafortune_precision.py.
            let lv = g.l.dot(g.v);
            let tp = (g.l - g.n * g.nl).dot(g.v - g.n * g.nv);
            self.lobes.iter().map(|c| self.power_of(c.cz * lv + (c.cx - c.cz) * tp, c.n)).sum()
        } else {
            let fr = g.frame();
            self.lobe_sum(fr.to_local(g.l), fr.to_local(g.v))
        };
        self.rho_d * std::f32::consts::FRAC_1_PI + self.rho_s * sum
    }
}
