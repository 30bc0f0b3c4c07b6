//! Ashikhmin–Shirley anisotropic Phong BRDF (M. Ashikhmin, P. Shirley, "An Anisotropic Phong BRDF
//! Model", Journal of Graphics Tools 5(2), 2000; BRDF Explorer `ashikhman_shirley.brdf`; pbrt-v3
//! `FresnelBlend`), with `Rd` = `kd`, `Rs` = `ks`:
//!
//! ```text
//! f_s = √((nu+1)(nv+1))/(8π) · (n·h)^{nu cos²φ_h + nv sin²φ_h} / ((h·v) max(n·l, n·v)) · F(h·v)
//! f_d = 28 Rd/(23π) · (1 − Rs) · (1 − (1 − n·l/2)⁵) · (1 − (1 − n·v/2)⁵)
//! F(c) = Rs + (1 − Rs)(1 − c)⁵                       (Schlick)
//! ```
//! The specular lobe is AS2000's half-vector density
//! [`crate::microfacet::ashikhmin_shirley::pdf_h`] over `4 (h·v) max(n·l, n·v)`; the diffuse term is
//! coupled to the specular one so that the sum conserves energy (AS2000 §5). Reciprocal: `h·v = h·l`
//! and `max(n·l, n·v)` are symmetric. Isotropic exponents (nu = nv) skip the frame.

use glam::Vec3;

use crate::BrdfError;
use crate::frame::LaneFrame;
use crate::fresnel::schlick_lanes;
use crate::microfacet::ashikhmin_shirley as as_d;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// Ashikhmin–Shirley BRDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AshikhminShirley {
    /// Diffuse reflectance Rd.
    pub kd: Vec3,
    /// Specular reflectance at normal incidence Rs (Schlick F0).
    pub ks: Vec3,
    /// Phong exponent along the tangent.
    pub nu: f32,
    /// Phong exponent along the bitangent.
    pub nv: f32,
    diffuse_scale: Vec3,
}

impl AshikhminShirley {
    /// AS2000 with diffuse `kd`, specular `ks`, exponents `nu` (tangent), `nv` (bitangent) (clamped ≥ 0).
    pub fn new(kd: Vec3, ks: Vec3, nu: f32, nv: f32) -> Self {
        let diffuse_scale = kd * (Vec3::ONE - ks) * (28.0 / (23.0 * std::f32::consts::PI));
        Self { kd, ks, nu: nu.max(0.0), nv: nv.max(0.0), diffuse_scale }
    }
}

impl Bxdf for AshikhminShirley {
    const SPEC: ModelSpec = ModelSpec {
        name: "ashikhmin_shirley",
        summary: "Ashikhmin-Shirley 2000 anisotropic Phong: sqrt((nu+1)(nv+1))/(8pi) (n.h)^e F/((h.v) max(n.l,n.v)) + coupled diffuse 28 kd (1-ks)/(23 pi)(...)",
        source: "M. Ashikhmin, P. Shirley, An Anisotropic Phong BRDF Model, Journal of Graphics Tools 5(2) (2000), eqs. 4 and 5",
        physical: true,
        anisotropic: true,
        params: &[
            ParamSpec::color("kd", [0.5; 3], 0.0, 1.0, "reflectance", "diffuse reflectance Rd"),
            ParamSpec::color(
                "ks",
                [0.05; 3],
                0.0,
                1.0,
                "reflectance",
                "specular reflectance at normal incidence Rs (Schlick's F0)",
            ),
            ParamSpec::scalar("nu", 100.0, 0.0, 1.0e6, "1", "Phong exponent along the tangent"),
            ParamSpec::scalar("nv", 10.0, 0.0, 1.0e6, "1", "Phong exponent along the bitangent"),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted for the diffuse term, AS2000's half-vector sampler for the specular one
    /// ([`crate::sampling::ashikhmin_shirley`]), weighted by `mean(Rd (1 − Rs))` and `mean(F(n·v))`.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let fresnel = crate::fresnel::Fresnel::Schlick { f0: self.ks };
        Ok(Sampler::new().with(Technique::Cosine, mean(self.kd * (Vec3::ONE - self.ks))).with_fresnel(
            Technique::AshikhminShirley { nu: self.nu, nv: self.nv },
            1.0,
            Vec3::ONE,
            fresnel,
        ))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd"), p.color("ks"), p.scalar("nu"), p.scalar("nv")))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        let (zero, one, half) = (F::splat(0.0), F::splat(1.0), F::splat(0.5));
        let (nl, nv) = (g.nl, g.nv);
        let grazing = (one - pow5(one - half * nl)) * (one - pow5(one - half * nv));
        let diffuse = V3::splat(self.diffuse_scale).scale(grazing);
        // h as `vector::halfway`: none where |l + v|² ≤ 1e−20 (diffuse only).
        let s = g.l + g.v;
        let len2 = s.dot(s);
        let h = s / len2.sqrt();
        let vh = g.v.dot(h);
        let h_local = if self.nu == self.nv {
            let nh = g.n.dot(h).min(one);
            V3 { x: (one - nh * nh).max(zero).sqrt(), y: zero, z: nh }
        } else {
            LaneFrame::of(g).to_local(h)
        };
        let lobe = as_d::pdf_h_lanes(h_local, self.nu, self.nv) / (F::splat(4.0) * vh * nl.max(nv));
        let specular = diffuse + schlick_lanes(vh, self.ks).scale(lobe);
        V3::select(len2.gt(F::splat(1e-20)) & vh.gt(zero), specular, diffuse)
    }
}

/// `x⁵` in three multiplications.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn pow5<F: Lane>(x: F) -> F {
    let x2 = x * x;
    x2 * x2 * x
}
