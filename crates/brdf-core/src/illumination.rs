//! The Phong illumination model with any reflectance model (SPEC row 14; seed 004 eq. 12.25 and
//! "The Phong Illumination Model (11)–(12)"; seed 003; with ambient occlusion and light visibility as in
//! seed 004 eq. 12.75):
//!
//! ```text
//! L = emission + w(p) · k_a ∘ I_a + Σ_j δ_j · E_j ∘ shade(l_j, v, n)
//! ```
//!
//! - `emission` `I_e`: light the surface emits itself, added unlit.
//! - `k_a ∘ I_a`: the ambient term, material ambient reflectance times the scene's ambient light
//!   (component-wise), scaled by the obscurance `w(p) ∈ [0, 1]` (1 = unoccluded).
//! - `E_j`: irradiance of light `j` from [`Light::incident`] (the course's `f(d) · I_i`),
//!   `δ_j ∈ [0, 1]` its visibility (1 = no shadow).
//! - `shade(l, v, n)`: the model's [`Bxdf::shade`] — `f_r · max(n·l, 0)` for a physical BRDF, the course
//!   formula (e.g. `k_d (n·l) + k_s (n·h)^n`) for a classic one — so the course's numbers come out
//!   exactly for classic models and `L_o = f_r E cos θ` for physical ones.

use glam::{Vec3, Vec3A};

use crate::Geometry;
use crate::lights::{Incident, Light};
use crate::models::{Bxdf, Model, ModelVisitor, shade_model};

/// The material-side constants of the illumination model (all linear RGB).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terms {
    /// Emitted radiance `I_e`, added whatever the lights.
    pub emission: Vec3,
    /// Ambient reflectance `k_a`.
    pub ambient: Vec3,
    /// Ambient light `I_a` of the scene.
    pub ambient_light: Vec3,
}

/// A shading point: position, unit normal and unit direction toward the viewer (all world space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Position `p`.
    pub p: Vec3,
    /// Unit shading normal `n`.
    pub n: Vec3A,
    /// Unit direction toward the viewer `v`.
    pub v: Vec3A,
    /// Optional unit tangent for anisotropic models (`None`: an arbitrary frame around `n`).
    pub tangent: Option<Vec3A>,
}

/// `L = emission + w·k_a∘I_a + Σ_j δ_j E_j ∘ shade(model; l_j, v, n)` (see the module docs), with the
/// model known at compile time so a renderer's per-pixel loop has no dispatch in it.
///
/// `obscurance` is `w(p)`; `visibility(j, &incident)` returns `δ_j` (it is only called for lights
/// that reach `p`, so a shadow ray is cast only when it matters). A light with `δ_j = 0` or `E_j = 0`
/// costs no BRDF evaluation.
#[inline]
pub fn radiance<M: Bxdf>(
    model: &M,
    terms: &Terms,
    lights: &[Light],
    s: &SurfacePoint,
    obscurance: f32,
    mut visibility: impl FnMut(usize, &Incident) -> f32,
) -> Vec3 {
    let mut c = terms.emission + obscurance * terms.ambient * terms.ambient_light;
    for (j, light) in lights.iter().enumerate() {
        let Some(inc) = light.incident(s.p) else { continue };
        let delta = visibility(j, &inc);
        if delta <= 0.0 {
            continue;
        }
        let g = geometry(inc.l, s);
        c += delta * inc.irradiance * shade_model(model, &g);
    }
    c
}

/// [`radiance`] for a model chosen at run time: one dispatch through [`Model::visit`], then the same
/// code (use [`Model::visit`] around a whole loop of [`radiance`] calls in hot paths).
pub fn radiance_dyn(
    model: &Model,
    terms: &Terms,
    lights: &[Light],
    s: &SurfacePoint,
    obscurance: f32,
    visibility: impl FnMut(usize, &Incident) -> f32,
) -> Vec3 {
    struct Radiance<'a, F> {
        terms: &'a Terms,
        lights: &'a [Light],
        s: &'a SurfacePoint,
        obscurance: f32,
        visibility: F,
    }
    impl<F: FnMut(usize, &Incident) -> f32> ModelVisitor for Radiance<'_, F> {
        type Output = Vec3;
        fn visit<M: Bxdf>(self, m: &M) -> Vec3 {
            radiance(m, self.terms, self.lights, self.s, self.obscurance, self.visibility)
        }
    }
    model.visit(Radiance { terms, lights, s, obscurance, visibility })
}

#[inline]
fn geometry(l: Vec3, s: &SurfacePoint) -> Geometry {
    let mut g = Geometry::from_unit(l.into(), s.v, s.n);
    g.tangent = s.tangent;
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::Attenuation;
    use crate::models::Lambert;

    #[test]
    fn lambert_under_two_lights_sums_their_contributions_plus_ambient_and_emission() {
        let m = Lambert::new(Vec3::new(0.8, 0.5, 0.2));
        let terms = Terms {
            emission: Vec3::new(0.01, 0.02, 0.03),
            ambient: Vec3::splat(0.1),
            ambient_light: Vec3::new(1.0, 0.5, 0.25),
        };
        let lights = [
            Light::directional(Vec3::NEG_Z, Vec3::ONE).unwrap(),
            Light::point(Vec3::new(0.0, 3.0, 4.0), Vec3::splat(25.0), Attenuation::InverseSquare).unwrap(),
        ];
        let s = SurfacePoint { p: Vec3::ZERO, n: Vec3A::Z, v: Vec3A::Z, tangent: None };
        let c = radiance(&m, &terms, &lights, &s, 1.0, |_, _| 1.0);
        // Light 1: E = 1, cos = 1. Light 2: d = 5, E = 1, cos = 4/5.
        let rho_pi = m.albedo / std::f32::consts::PI;
        let expect = terms.emission + terms.ambient * terms.ambient_light + rho_pi * (1.0 + 0.8);
        assert!((c - expect).abs().max_element() < 1e-6, "{c} vs {expect}");
        // Shadowing the point light and halving the ambient occlusion.
        let c2 = radiance(&m, &terms, &lights, &s, 0.5, |j, _| if j == 1 { 0.0 } else { 1.0 });
        let expect2 = terms.emission + 0.5 * terms.ambient * terms.ambient_light + rho_pi;
        assert!((c2 - expect2).abs().max_element() < 1e-6);
        let model: Model = m.into();
        let c3 = radiance_dyn(&model, &terms, &lights, &s, 1.0, |_, _| 1.0);
        assert_eq!(c, c3);
    }

    #[test]
    fn a_light_behind_the_surface_adds_nothing_to_a_physical_model() {
        let m = Lambert::new(Vec3::ONE);
        let terms = Terms { emission: Vec3::ZERO, ambient: Vec3::ZERO, ambient_light: Vec3::ZERO };
        let lights = [Light::directional(Vec3::Z, Vec3::ONE).unwrap()];
        let s = SurfacePoint { p: Vec3::ZERO, n: Vec3A::Z, v: Vec3A::Z, tangent: None };
        assert_eq!(radiance(&m, &terms, &lights, &s, 1.0, |_, _| 1.0), Vec3::ZERO);
    }
}
