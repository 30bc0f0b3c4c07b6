//! [`AreaLighting`]: the light of the scene's area lights ([`crate::area_light`]) added as each shaded
//! sample's `indirect` term, wrapping the render's own obscurance, shadow and environment providers.
//!
//! Per shaded point, for each area light `j` of radiance `L_j`, an unbiased estimate of
//!
//! ```text
//! L_o(v) = ∫_{Ω_j} L_j V(p, l) f_r(l, v) cos θ_l dω_l
//! ```
//!
//! by multiple importance sampling (Veach & Guibas 1995, power heuristic β = 2) of two strategies, one
//! sample of each per iteration, [`AreaSampling::samples`] iterations:
//! - the light's: `l` drawn toward it with the solid-angle density `p_j` ([`crate::area_light::AreaLight::sample`]),
//!   contributing `L_j f_r cos θ_l · w(p_j, p_b) / p_j` where the shadow ray reaches the sampled point;
//! - the material's (`Model::sampler`, [`brdf_core::sampling`]): `l` with density `p_b`, contributing
//!   `L_j · (f_r cos θ_l / p_b) · w(p_b, p_j)` where the ray meets the light ([`crate::area_light::AreaLight::hit`]) and
//!   nothing blocks it before.
//!
//! `w(a, b) = a²/(a² + b²)`, the power heuristic with β = 2 (E. Veach, PhD thesis, Stanford 1997, §9.2). Visibility is traced in a
//! BVH of the scene whatever `RenderOptions::shadows` says (soft shadows are what an area light is
//! for), from the point offset along the face's geometric normal ([`crate::shadows::shadow_ray`]), to
//! `2ε` short of the light. Area lights are not geometry: they cast no shadow themselves and the
//! camera does not see them (an emissive mesh just inside a sphere light, or just behind a rectangle,
//! shows one without shadowing it). Classic (non-physical) models scale `shade` by `1/π`, as the
//! environment does ([`crate::ambient`]), and a model without a sampler of its own is sampled by the
//! cosine.
//!
//! Random numbers are counter-based ([`brdf_core::sampling::rng`]), keyed by the seed, the light and the
//! shaded point itself (instance, face, barycentrics): the image has the same bits at any thread count.

use brdf_core::lights::Incident;
use brdf_core::sampling::{Sampler, Technique, rng};
use brdf_core::{Geometry, Model};
use glam::Vec3;

use crate::RasterError;
use crate::bvh::Bvh;
use crate::camera::Camera;
use crate::environment::lighting::{geometric_normal, point_key, world_positions};
use crate::environment::monte_carlo::power;
use crate::render::{Occlusion, ShadePoint};
use crate::scene::Scene;
use crate::shadows::{shadow_offset, shadow_ray};

/// Samples and seed of the area lights' Monte Carlo estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AreaSampling {
    /// Iterations per shaded point and light (each one light and one material sample), 1..=2^20.
    pub samples: u32,
    /// Seed of the counter-based random numbers: the same image for the same seed, at any thread count.
    pub seed: u64,
}

impl Default for AreaSampling {
    /// 16 iterations, seed 0.
    fn default() -> Self {
        Self { samples: 16, seed: 0 }
    }
}

impl AreaSampling {
    /// Check the sample count (named `area_samples`, as the Python API calls it).
    pub fn validate(&self) -> Result<(), RasterError> {
        if !(1..=1 << 20).contains(&self.samples) {
            return Err(RasterError::arg(
                "area_samples",
                format!("must be in 1..=1048576, got {}", self.samples),
            ));
        }
        Ok(())
    }
}

/// A salt keeping the area lights' streams apart from the environment's for the same seed.
const STREAM: u64 = 0x4152_4541_4C49_4748; // "AREALIGH"

/// What the estimate needs of one instance's material.
#[derive(Debug, Clone)]
struct MaterialData {
    model: Model,
    sampler: Sampler,
    /// 1 for physical models, 1/π for classic ones.
    scale: f32,
}

/// The occlusion hooks of a render with area lights: `inner`'s obscurance, shadows and `indirect`
/// (an environment's), plus the area lights' reflected radiance (module docs).
pub struct AreaLighting<'a, O> {
    inner: &'a O,
    scene: &'a Scene,
    sampling: AreaSampling,
    eye: Vec3,
    ortho_view: Option<Vec3>,
    backward: Vec3,
    materials: Vec<MaterialData>,
    world: Vec<Vec<Vec3>>,
    bvh: Bvh,
    eps: f32,
}

impl<'a, O: Occlusion> AreaLighting<'a, O> {
    /// Prepare the area lighting of `scene` for `camera`: per-material samplers and a BVH of the scene.
    pub fn new(
        scene: &'a Scene,
        camera: &Camera,
        sampling: AreaSampling,
        inner: &'a O,
    ) -> Result<Self, RasterError> {
        sampling.validate()?;
        for (j, light) in scene.area_lights.iter().enumerate() {
            light.validate().map_err(|e| RasterError::arg("area_lights", format!("area light {j}: {e}")))?;
        }
        let materials = scene
            .instances
            .iter()
            .map(|inst| {
                let model = inst.material.model.clone();
                let sampler = model.sampler().unwrap_or_else(|_| Sampler::new().with(Technique::Cosine, 1.0));
                let scale = if model.spec().physical { 1.0 } else { std::f32::consts::FRAC_1_PI };
                MaterialData { model, sampler, scale }
            })
            .collect();
        let parts: Vec<(&crate::Mesh, glam::Mat4)> =
            scene.instances.iter().map(|i| (&*i.mesh, i.transform)).collect();
        let bvh = Bvh::from_instances(&parts)?;
        let eps = shadow_offset(&bvh);
        Ok(Self {
            inner,
            scene,
            sampling,
            eye: camera.eye,
            ortho_view: camera.is_orthographic().then(|| camera.backward()),
            backward: camera.backward(),
            materials,
            world: world_positions(scene),
            bvh,
            eps,
        })
    }

    #[inline]
    fn view(&self, p: Vec3) -> Vec3 {
        match self.ortho_view {
            Some(v) => v,
            None => {
                let v = (self.eye - p).normalize_or_zero();
                if v == Vec3::ZERO { self.backward } else { v }
            }
        }
    }

    /// The area lights' reflected radiance at the point (module docs). Finite and ≥ 0.
    fn estimate(&self, m: &MaterialData, at: &ShadePoint) -> Vec3 {
        let n_geom = geometric_normal(self.scene, &self.world, at);
        let v = self.view(at.p);
        let n = at.n;
        let key = rng::mix64(rng::key(self.sampling.seed) ^ STREAM);
        let point = point_key(at);
        let samples = self.sampling.samples;
        let visible = |l: Vec3, distance: f32| {
            let ray = shadow_ray(at.p, n_geom, l, distance, self.eps);
            ray.t_max > 0.0 && !self.bvh.any_hit(&ray)
        };
        let mut total = Vec3::ZERO;
        for (j, light) in self.scene.area_lights.iter().enumerate() {
            let le = light.radiance();
            let mut sum = Vec3::ZERO;
            for s in 0..samples {
                let row = point.wrapping_add((j as u64 * u64::from(samples) + u64::from(s)).wrapping_mul(2));
                // The material's strategy.
                let u = [0, 1, 2].map(|d| rng::uniform_keyed(key, row, d));
                let bs = m.model.sample_with(&m.sampler, v, n, None, u);
                if bs.pdf > 0.0
                    && bs.weight.max_element() > 0.0
                    && let Some((t, pl)) = light.hit(at.p, bs.l)
                    && visible(bs.l, t)
                {
                    sum += bs.weight * power(bs.pdf, pl);
                }
                // The light's strategy.
                let row_l = row.wrapping_add(1);
                let ul = [rng::uniform_keyed(key, row_l, 0), rng::uniform_keyed(key, row_l, 1)];
                if let Some(ls) = light.sample(at.p, ul)
                    && let Some(g) = Geometry::new(ls.l, v, n, None)
                {
                    let fc = m.model.shade(&g);
                    if fc.max_element() > 0.0 && visible(ls.l, ls.distance) {
                        let pb = m.sampler.pdf(ls.l, v, n, None);
                        sum += fc * (power(ls.pdf, pb) / ls.pdf);
                    }
                }
            }
            total += le * sum;
        }
        let c = total * (m.scale / samples as f32);
        if c.is_finite() { c.max(Vec3::ZERO) } else { Vec3::ZERO }
    }
}

impl<O: Occlusion> Occlusion for AreaLighting<'_, O> {
    fn obscurance(&self, at: &ShadePoint) -> f32 {
        self.inner.obscurance(at)
    }

    fn visibility(&self, at: &ShadePoint, light: usize, incident: &Incident) -> f32 {
        self.inner.visibility(at, light, incident)
    }

    fn visibility_each(&self, at: &[ShadePoint], light: usize, incident: &[Incident], out: &mut [f32]) {
        self.inner.visibility_each(at, light, incident, out);
    }

    fn indirect(&self, at: &ShadePoint, w: f32) -> Vec3 {
        let base = self.inner.indirect(at, w);
        match self.materials.get(at.instance as usize) {
            Some(m) => base + self.estimate(m, at),
            None => base,
        }
    }
}
