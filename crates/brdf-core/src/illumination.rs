//! The Phong illumination model with any reflectance model (Phong 1975; Theoharis et al. 2008, eq. 12.25;
//! with
//! ambient occlusion and light visibility as in Theoharis et al. 2008, eq. 12.75):
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

use crate::lights::{Incident, IncidentLanes, Light};
use crate::models::{Bxdf, Model, ModelVisitor, shade_model_lanes};
use crate::simd::{Lane, LaneGeometry, V3};

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

/// `F::LANES` shading points: positions, unit normals, unit view directions and an optional unit
/// tangent (the lane form of [`SurfacePoint`]).
#[derive(Debug, Clone, Copy)]
pub struct SurfaceLanes<F: Lane> {
    /// Positions `p`.
    pub p: V3<F>,
    /// Unit shading normals `n`.
    pub n: V3<F>,
    /// Unit directions toward the viewer `v`.
    pub v: V3<F>,
    /// Unit tangents for anisotropic models (`None`: an arbitrary frame around `n`).
    pub tangent: Option<V3<F>>,
}

impl From<&SurfacePoint> for SurfaceLanes<f32> {
    #[inline(always)]
    fn from(s: &SurfacePoint) -> Self {
        Self { p: V3::splat(s.p), n: s.n.into(), v: s.v.into(), tangent: s.tangent.map(Into::into) }
    }
}

/// `L = emission + w·k_a∘I_a + Σ_j δ_j E_j ∘ shade(model; l_j, v, n)` (see the module docs), with the
/// model known at compile time so a renderer's per-pixel loop has no dispatch in it.
///
/// `obscurance` is `w(p)`; `visibility(j, &incident)` returns `δ_j` (it is only called for lights
/// that reach `p`, so a shadow ray is cast only when it matters). A light with `δ_j ≤ 0` (or NaN) or
/// `E_j = 0` costs no BRDF evaluation. [`radiance_lanes_with`] with one lane.
#[inline]
pub fn radiance<M: Bxdf>(
    model: &M,
    terms: &Terms,
    lights: &[Light],
    s: &SurfacePoint,
    obscurance: f32,
    mut visibility: impl FnMut(usize, &Incident) -> f32,
) -> Vec3 {
    // Called only where light arrives (`reach` is the one lane), so the `Incident` exists.
    let vis = |j: usize, inc: &IncidentLanes<f32>, _: bool| inc.lane(0).map_or(0.0, |i| visibility(j, &i));
    radiance_lanes_with(model, terms, lights, &SurfaceLanes::from(s), obscurance, true, vis).into()
}

/// [`radiance`] at `F::LANES` points with no occlusion (`w = 1`, every `δ = 1`): unit normals `n`,
/// unit view directions `v`, positions `p`, no tangent. Lanes outside `active` hold anything.
#[inline(always)]
pub fn radiance_lanes<M: Bxdf, F: Lane>(
    model: &M,
    terms: &Terms,
    lights: &[Light],
    p: V3<F>,
    n: V3<F>,
    v: V3<F>,
    active: F::Mask,
) -> V3<F> {
    let s = SurfaceLanes { p, n, v, tangent: None };
    radiance_lanes_with(model, terms, lights, &s, F::splat(1.0), active, |_, _, _| F::splat(1.0))
}

/// The illumination model at `F::LANES` points: the one formula behind [`radiance`] (one lane) and
/// [`radiance_lanes`]. `obscurance` is `w` per lane; `visibility(j, &incident, reach)` returns `δ_j`
/// per lane and is called only when light `j` reaches at least one lane of `reach` (a subset of
/// `active`). Lanes outside `active` hold anything.
#[inline(always)]
pub fn radiance_lanes_with<M: Bxdf, F: Lane>(
    model: &M,
    terms: &Terms,
    lights: &[Light],
    s: &SurfaceLanes<F>,
    obscurance: F,
    active: F::Mask,
    mut visibility: impl FnMut(usize, &IncidentLanes<F>, F::Mask) -> F,
) -> V3<F> {
    let any = |m: F::Mask| !F::mask_all(!m);
    let ambient = V3::splat(terms.ambient).scale(obscurance) * V3::splat(terms.ambient_light);
    let mut c = V3::splat(terms.emission) + ambient;
    let nv = s.n.dot(s.v);
    let tangent_ok = F::mask_splat(s.tangent.is_some());
    for (j, light) in lights.iter().enumerate() {
        let inc = light.incident_lanes(s.p);
        let reach = active & inc.arrives;
        if !any(reach) {
            continue;
        }
        let delta = visibility(j, &inc, reach);
        let lit = reach & delta.gt(F::splat(0.0));
        if !any(lit) {
            continue;
        }
        let (n, l) = (s.n, inc.l);
        let g = LaneGeometry { l, v: s.v, n, tangent: s.tangent, tangent_ok, nl: n.dot(l), nv };
        let add = c + inc.irradiance.scale(delta) * shade_model_lanes(model, &g, lit);
        c = V3::select(lit, add, c);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-sample formula before it became the lane formula with one lane (scalar `shade_model`
    /// on a `Geometry`), kept to show that the bits did not move.
    fn reference_radiance<M: Bxdf>(
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
            let mut g = crate::Geometry::from_unit(inc.l.into(), s.v, s.n);
            g.tangent = s.tangent;
            c += delta * inc.irradiance * crate::models::shade_model(model, &g);
        }
        c
    }

    #[test]
    fn lane_radiance_equals_scalar_radiance_bit_for_bit_for_every_model_and_light() {
        use crate::lights::Attenuation;
        use crate::simd::{F32x8, LaneKernel, run_widest};
        use crate::vector::normalize_or_zero;

        let lights = [
            Light::directional(Vec3::new(-1.0, -1.0, -1.0), Vec3::ONE).unwrap(),
            Light::directional(Vec3::new(0.0, -1.0, 0.2), Vec3::ZERO).unwrap(), // black: never arrives
            Light::point(Vec3::splat(2.0), Vec3::splat(10.0), Attenuation::InverseSquare).unwrap(),
            Light::point(
                Vec3::new(-1.0, 0.5, 1.0),
                Vec3::new(3.0, 2.0, 1.0),
                Attenuation::Polynomial { c1: 0.5, c2: 0.2, c3: 0.1 },
            )
            .unwrap(),
            // A point light exactly at a sample (below) gives no light there.
            Light::point(Vec3::new(0.25, 0.0, 0.0), Vec3::ONE, Attenuation::None).unwrap(),
            Light::spot(
                Vec3::new(0.0, 2.0, 2.0),
                Vec3::new(0.0, -1.0, -1.0),
                Vec3::splat(8.0),
                0.2,
                0.5,
                Attenuation::InverseSquare,
            )
            .unwrap(),
        ];
        let terms = Terms {
            emission: Vec3::new(0.01, 0.0, 0.02),
            ambient: Vec3::new(0.04, 0.015, 0.01),
            ambient_light: Vec3::splat(1.0),
        };
        let eye = Vec3::new(0.0, 0.0, 3.0);
        // 40 points on and around a unit sphere, every normal direction, some facing away.
        let points: Vec<(Vec3, Vec3A, Vec3A)> = (0..40)
            .map(|i| {
                let t = i as f32 * 0.61;
                let dir = Vec3::new(t.cos() * (0.3 * t).sin(), (0.7 * t).cos(), t.sin() * (0.3 * t).cos());
                let p = if i == 5 { Vec3::new(0.25, 0.0, 0.0) } else { dir * (1.0 + 0.01 * i as f32) };
                let n = normalize_or_zero((dir + Vec3::new(0.1, 0.0, 0.05)).into());
                let v = normalize_or_zero((eye - p).into());
                (p, n, v)
            })
            .collect();

        struct Compare<'a> {
            lights: &'a [Light],
            terms: &'a Terms,
            points: &'a [(Vec3, Vec3A, Vec3A)],
        }
        struct Kernel<'a, M> {
            m: &'a M,
            c: &'a Compare<'a>,
        }
        impl<M: Bxdf> LaneKernel for Kernel<'_, M> {
            #[inline(always)]
            fn run<F: Lane>(self) {
                let c = self.c;
                for group in c.points.chunks(F::LANES) {
                    let k = group.len();
                    let at = |i: usize| group[i.min(k - 1)];
                    let p = V3::<F>::from_fn(|i| at(i).0);
                    let n = V3::<F>::from_fn(|i| at(i).1.into());
                    let v = V3::<F>::from_fn(|i| at(i).2.into());
                    let active = F::from_fn(|i| if i < k { 1.0 } else { 0.0 }).gt(F::splat(0.5));
                    let got = radiance_lanes(self.m, c.terms, c.lights, p, n, v, active);
                    for (i, &(p, n, v)) in group.iter().enumerate() {
                        let s = SurfacePoint { p, n, v, tangent: None };
                        let want = reference_radiance(self.m, c.terms, c.lights, &s, 1.0, |_, _| 1.0);
                        let one = radiance(self.m, c.terms, c.lights, &s, 1.0, |_, _| 1.0);
                        let g = got.lane(i);
                        let bits = |x: Vec3| x.to_array().map(f32::to_bits);
                        let name = M::SPEC.name;
                        assert_eq!(bits(g), bits(want), "{name} at {p}: lanes {g} vs scalar {want}");
                        assert_eq!(bits(one), bits(want), "{name} at {p}: one sample {one} vs {want}");
                        // With a tangent, an obscurance and a partial shadow, one sample at a time.
                        let s = SurfacePoint { tangent: Some(Vec3A::X.cross(n).normalize_or_zero()), ..s };
                        let vis = |j: usize, _: &Incident| [0.5, 0.0, 1.0][j % 3];
                        let want = reference_radiance(self.m, c.terms, c.lights, &s, 0.3, vis);
                        let one = radiance(self.m, c.terms, c.lights, &s, 0.3, vis);
                        assert_eq!(bits(one), bits(want), "{name} at {p} shadowed: {one} vs {want}");
                    }
                }
            }
        }
        impl ModelVisitor for &Compare<'_> {
            type Output = ();
            fn visit<M: Bxdf>(self, m: &M) {
                Kernel { m, c: self }.run::<F32x8>();
                run_widest(Kernel { m, c: self });
                Kernel { m, c: self }.run::<f32>();
            }
        }
        let cmp = Compare { lights: &lights, terms: &terms, points: &points };
        for spec in crate::MODEL_SPECS {
            Model::build(spec.name, &[]).unwrap().visit(&cmp);
        }
        // A rough Cook-Torrance and a sharp metal, where the GGX lobe is steep.
        for alpha in [0.08, 0.6] {
            let params = [("roughness".to_string(), crate::Input::Number(alpha))];
            Model::build("cook_torrance", &params).unwrap().visit(&cmp);
        }
    }
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
        let rho_pi = m.kd / std::f32::consts::PI;
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
