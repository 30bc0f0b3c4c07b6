//! Ashikhmin–Shirley anisotropic Phong BRDF (M. Ashikhmin, P. Shirley, "An Anisotropic Phong BRDF
//! Model", JGT 5(2), 2000; seeds 001, 002; BRDF Explorer `ashikhman_shirley.brdf`; pbrt-v3
//! `FresnelBlend`):
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

use glam::{Vec3, Vec3A};

use crate::fresnel::schlick;
use crate::microfacet::ashikhmin_shirley as as_d;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::{BrdfError, Geometry};

/// Ashikhmin–Shirley BRDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AshikhminShirley {
    /// Diffuse reflectance Rd.
    pub rd: Vec3,
    /// Specular reflectance at normal incidence Rs (Schlick F0).
    pub rs: Vec3,
    /// Phong exponent along the tangent.
    pub nu: f32,
    /// Phong exponent along the bitangent.
    pub nv: f32,
    diffuse_scale: Vec3,
}

impl AshikhminShirley {
    /// AS2000 with diffuse `rd`, specular `rs`, exponents `nu` (tangent), `nv` (bitangent) (clamped ≥ 0).
    pub fn new(rd: Vec3, rs: Vec3, nu: f32, nv: f32) -> Self {
        let diffuse_scale = rd * (Vec3::ONE - rs) * (28.0 / (23.0 * std::f32::consts::PI));
        Self { rd, rs, nu: nu.max(0.0), nv: nv.max(0.0), diffuse_scale }
    }
}

impl Bxdf for AshikhminShirley {
    const SPEC: ModelSpec = ModelSpec {
        name: "ashikhmin_shirley",
        summary: "Ashikhmin-Shirley 2000 anisotropic Phong: sqrt((nu+1)(nv+1))/(8pi) (n.h)^e F/((h.v) max(n.l,n.v)) + coupled diffuse 28 rd (1-rs)/(23 pi)(...)",
        source: "seeds 001, 002; Ashikhmin & Shirley 2000",
        physical: true,
        anisotropic: true,
        params: &[
            ParamSpec::color("rd", [0.5; 3], 0.0, 1.0, "reflectance", "diffuse reflectance Rd"),
            ParamSpec::color(
                "rs",
                [0.05; 3],
                0.0,
                1.0,
                "reflectance",
                "specular reflectance at normal incidence Rs",
            ),
            ParamSpec::scalar("nu", 100.0, 0.0, 1.0e6, "1", "Phong exponent along the tangent"),
            ParamSpec::scalar("nv", 10.0, 0.0, 1.0e6, "1", "Phong exponent along the bitangent"),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("rd"), p.color("rs"), p.scalar("nu"), p.scalar("nv")))
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        let (nl, nv) = (g.nl, g.nv);
        let pow5 = |x: f32| {
            let x2 = x * x;
            x2 * x2 * x
        };
        let diffuse = self.diffuse_scale * ((1.0 - pow5(1.0 - 0.5 * nl)) * (1.0 - pow5(1.0 - 0.5 * nv)));
        let Some(h) = g.h() else { return diffuse };
        let vh = g.v.dot(h);
        if !(vh > 0.0) {
            return diffuse;
        }
        let h_local = if self.nu == self.nv {
            let nh = g.n.dot(h).min(1.0);
            Vec3A::new((1.0 - nh * nh).max(0.0).sqrt(), 0.0, nh)
        } else {
            g.frame().to_local(h)
        };
        let lobe = as_d::pdf_h(h_local, self.nu, self.nv) / (4.0 * vh * nl.max(nv));
        diffuse + schlick(vh, self.rs) * lobe
    }
}
