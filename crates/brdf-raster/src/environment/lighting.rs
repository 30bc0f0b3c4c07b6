//! [`EnvironmentLighting`]: the renderer's [`Occlusion`] hooks with the environment's reflected radiance
//! added as each sample's `indirect` term, in the fast or the Monte Carlo mode, wrapping the render's
//! own obscurance and shadow providers.
//!
//! ## Fast mode per sample
//! With `ρ(μ)` the material's directional albedo under a uniform white sky at `μ = n·v` (tabulated at
//! [`ALBEDO_COS`] and interpolated, [`brdf_core::views::albedo::Over::Light`]), `p_k(v)` the share of lobe
//! `k` in the material's sampler ([`brdf_core::sampling::Sampler::lobe_weights`], its estimated albedo)
//! and `L̄_k` the mean radiance that lobe sees ([`super::fast`]: `E(n)/π` for a cosine lobe, the
//! environment prefiltered at the lobe's roughness about its axis for a glossy one):
//!
//! ```text
//! L_o(v) ≈ w(p) · ρ(μ) ∘ Σ_k p_k(v) L̄_k
//! ```
//!
//! exact for a uniform environment (every `L̄_k` is then the radiance), with the obscurance `w(p)` of
//! the render (1 without `ao`) standing in for visibility. The roughness of a lobe: `α = √(α_x α_y)` for
//! GGX, Beckmann and Ward; `α = √(2/(m + 2))` for a Blinn–Phong-like half-vector power `m` (Walter et al.
//! 2007, §5.2), likewise for Ashikhmin–Shirley with `m = √(n_u n_v)`; `α = √(2/(4n + 2))` for a Phong
//! lobe `cosⁿ` about the mirror direction (whose angle is twice the half vector's); 0.35 for a measured
//! table's lobe (an assumption: a table has no roughness).
//!
//! ## Monte Carlo mode per sample
//! [`super::monte_carlo::estimate`]; the obscurance is not applied (visibility is traced).

use std::sync::{Arc, Mutex};

use brdf_core::sampling::{Sampler, Technique};
use brdf_core::views::albedo::{Over, VIEW_QUADRATURE, hemispherical};
use brdf_core::views::direction;
use brdf_core::{Model, ShadingFrame};
use glam::{Vec3, Vec3A};

use super::monte_carlo::{MonteCarloPoint, estimate};
use super::{Environment, EnvironmentMode};
use crate::RasterError;
use crate::bvh::Bvh;
use crate::camera::Camera;
use crate::render::{Occlusion, ShadePoint};
use crate::scene::Scene;
use crate::shadows::shadow_offset;
use crate::tiles::NO_TRI;

/// View cosines of the directional-albedo table (linear in between; held below the first).
pub const ALBEDO_COS: [f32; 16] = {
    let mut c = [0.0f32; 16];
    let mut k = 0;
    while k < 16 {
        c[k] = if k == 15 { 1.0 } else { 0.02 + 0.98 * k as f32 / 15.0 };
        k += 1;
    }
    c
};

/// How one lobe of a material sees the environment in the fast mode.
#[derive(Debug, Clone, Copy, PartialEq)]
enum LobeView {
    /// The cosine-weighted mean radiance `E(n)/π`.
    Diffuse,
    /// Prefiltered at roughness `alpha` about the mirror direction of `v`.
    Mirror { alpha: f32 },
    /// Prefiltered at roughness `alpha` about `normalize(c ∘ v)` in the local frame (Lafortune, Phong).
    Axis { c: [f32; 3], alpha: f32 },
}

fn lobe_view(t: &Technique) -> LobeView {
    let blinn = |m: f32| (2.0 / (m.max(0.0) + 2.0)).sqrt();
    match t {
        Technique::Cosine | Technique::UniformHemisphere => LobeView::Diffuse,
        Technique::CosineLobe { c, exponent } => {
            LobeView::Axis { c: *c, alpha: (2.0 / (4.0 * exponent.max(0.0) + 2.0)).sqrt() }
        }
        Technique::HalfVectorPower { exponent } => LobeView::Mirror { alpha: blinn(*exponent) },
        Technique::GgxVisible { alpha_x, alpha_y }
        | Technique::BeckmannVisible { alpha_x, alpha_y }
        | Technique::WardHalfVector { alpha_x, alpha_y } => {
            LobeView::Mirror { alpha: (alpha_x * alpha_y).abs().sqrt() }
        }
        Technique::AshikhminShirley { nu, nv } => LobeView::Mirror { alpha: blinn((nu * nv).abs().sqrt()) },
        Technique::Tabulated(_) => LobeView::Mirror { alpha: 0.35 },
    }
}

/// What the environment modes need of one instance's material.
#[derive(Debug, Clone)]
struct MaterialData {
    model: Model,
    sampler: Sampler,
    lobes: Vec<LobeView>,
    /// `ρ` at [`ALBEDO_COS`] (fast mode; with the classic scale).
    albedo: Arc<[Vec3; 16]>,
    /// 1 for physical models, 1/π for classic ones (the scale of [`crate::ambient`]).
    scale: f32,
    physical: bool,
}

/// Directional-albedo tables already computed (see [`crate::ambient`]'s cache).
static ALBEDO_CACHE: Mutex<Vec<(Model, Arc<[Vec3; 16]>)>> = Mutex::new(Vec::new());

fn albedo_table(model: &Model, scale: f32) -> Result<Arc<[Vec3; 16]>, RasterError> {
    {
        let cache = ALBEDO_CACHE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, t)) = cache.iter().rev().find(|(m, _)| m == model) {
            return Ok(Arc::clone(t));
        }
    }
    let mut table = [Vec3::ZERO; 16];
    for (t, &c) in table.iter_mut().zip(&ALBEDO_COS) {
        let v = direction(f64::from(c).acos(), 0.0);
        *t = (hemispherical(model, v, Over::Light, &VIEW_QUADRATURE)? * scale).max(Vec3::ZERO);
    }
    let table = Arc::new(table);
    let mut cache = ALBEDO_CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if cache.len() == 16 {
        cache.remove(0);
    }
    cache.push((model.clone(), Arc::clone(&table)));
    Ok(table)
}

#[inline]
fn albedo_at(table: &[Vec3; 16], cos: f32) -> Vec3 {
    let step = ALBEDO_COS[1] - ALBEDO_COS[0];
    let u = ((cos - ALBEDO_COS[0]) / step).clamp(0.0, 15.0);
    let k = (u as usize).min(14);
    let f = u - k as f32;
    table[k] * (1.0 - f) + table[k + 1] * f
}

/// The unit geometric normal of the face a shaded point lies on (`world`: the instances' world-space
/// vertex positions), its shading normal for a vertex or a degenerate face. Offsets visibility rays.
pub(crate) fn geometric_normal(scene: &Scene, world: &[Vec<Vec3>], at: &ShadePoint) -> Vec3 {
    if at.face == NO_TRI {
        return at.n;
    }
    let k = at.instance as usize;
    let w = &world[k];
    let [a, b, c] = scene.instances[k].mesh.indices[at.face as usize].map(|i| w[i as usize]);
    let g = (b - a).cross(c - a).normalize_or_zero();
    if g == Vec3::ZERO { at.n } else { g }
}

/// The key of a shaded point's own stream of random numbers: [`brdf_core::sampling::rng::mix64`] of
/// what identifies it (instance, face, barycentrics), whichever thread shades it.
pub(crate) fn point_key(at: &ShadePoint) -> u64 {
    use brdf_core::sampling::rng::mix64;
    let id = (u64::from(at.instance) << 32) | u64::from(at.face);
    let bary = (u64::from(at.bary.x.to_bits()) << 32) | u64::from(at.bary.y.to_bits());
    mix64(id ^ mix64(bary))
}

/// The world-space vertex positions of every instance (what [`geometric_normal`] reads).
pub(crate) fn world_positions(scene: &Scene) -> Vec<Vec<Vec3>> {
    scene
        .instances
        .iter()
        .map(|i| i.mesh.positions.iter().map(|p| i.transform.transform_point3(*p)).collect())
        .collect()
}

/// The occlusion hooks of a render with an environment: `inner`'s obscurance and shadows, and the
/// environment's reflected radiance as `indirect` (module docs).
pub struct EnvironmentLighting<'a, O> {
    inner: &'a O,
    scene: &'a Scene,
    env: &'a Environment,
    mode: EnvironmentMode,
    eye: Vec3,
    ortho_view: Option<Vec3>,
    backward: Vec3,
    materials: Vec<MaterialData>,
    /// World-space vertex positions per instance (geometric normals of the Monte Carlo mode).
    world: Vec<Vec<Vec3>>,
    bvh: Option<Bvh>,
    eps: f32,
}

impl<'a, O: Occlusion> EnvironmentLighting<'a, O> {
    /// Prepare the environment lighting of `scene` (whose `environment` must be set) for `camera`:
    /// per-material samplers and albedo tables, the prefiltered environment (fast mode, once per map) or
    /// the sampling distribution and a BVH of the scene (Monte Carlo mode).
    pub fn new(
        scene: &'a Scene,
        camera: &Camera,
        mode: EnvironmentMode,
        inner: &'a O,
    ) -> Result<Self, RasterError> {
        mode.validate()?;
        let env = scene
            .environment
            .as_ref()
            .ok_or_else(|| RasterError::arg("environment", "the scene has no environment"))?;
        env.validate()?;
        let mut materials = Vec::with_capacity(scene.instances.len());
        for inst in &scene.instances {
            let model = inst.material.model.clone();
            let spec = model.spec();
            // A model without a sampler of its own (a classic formula that refuses) is sampled by
            // the cosine: any density that covers the hemisphere keeps the estimate unbiased.
            let sampler = model.sampler().unwrap_or_else(|_| Sampler::new().with(Technique::Cosine, 1.0));
            let lobes = sampler.lobes().iter().map(|l| lobe_view(&l.technique)).collect();
            let scale = if spec.physical { 1.0 } else { std::f32::consts::FRAC_1_PI };
            let albedo = match mode {
                EnvironmentMode::Fast => albedo_table(&model, scale)?,
                EnvironmentMode::MonteCarlo { .. } => Arc::new([Vec3::ZERO; 16]),
            };
            materials.push(MaterialData { model, sampler, lobes, albedo, scale, physical: spec.physical });
        }
        let (world, bvh, eps) = match mode {
            EnvironmentMode::Fast => {
                let _ = env.map.fast();
                (Vec::new(), None, 0.0)
            }
            EnvironmentMode::MonteCarlo { .. } => {
                let _ = env.map.sampling();
                let parts: Vec<(&crate::Mesh, glam::Mat4)> =
                    scene.instances.iter().map(|i| (&*i.mesh, i.transform)).collect();
                let bvh = Bvh::from_instances(&parts)?;
                let eps = shadow_offset(&bvh);
                let world = world_positions(scene);
                (world, Some(bvh), eps)
            }
        };
        Ok(Self {
            inner,
            scene,
            env,
            mode,
            eye: camera.eye,
            ortho_view: camera.is_orthographic().then(|| camera.backward()),
            backward: camera.backward(),
            materials,
            world,
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

    /// The fast mode's reflected radiance (module docs), before the obscurance.
    fn fast(&self, m: &MaterialData, at: &ShadePoint) -> Vec3 {
        let n = at.n;
        let v = self.view(at.p);
        let mu = n.dot(v);
        if m.physical && !(mu > 0.0) {
            return Vec3::ZERO;
        }
        let fast = self.env.map.fast();
        let frame = ShadingFrame::from_normal(Vec3A::from(n));
        let v_local: Vec3 = frame.to_local(Vec3A::from(v)).into();
        let (w, total) = m.sampler.lobe_weights(v_local);
        let mut mean = Vec3::ZERO;
        for (lobe, wk) in m.lobes.iter().zip(w) {
            if !(wk > 0.0) {
                continue;
            }
            let l = match *lobe {
                LobeView::Diffuse => fast.irradiance(self.env.to_map(n)) * std::f32::consts::FRAC_1_PI,
                LobeView::Mirror { alpha } => {
                    let r = (2.0 * mu) * n - v;
                    fast.glossy(self.env.to_map(r.normalize_or_zero()), alpha)
                }
                LobeView::Axis { c, alpha } => {
                    let a = Vec3::from(c) * v_local;
                    let axis: Vec3 = frame.from_local(Vec3A::from(a.normalize_or_zero())).into();
                    fast.glossy(self.env.to_map(axis), alpha)
                }
            };
            mean += l * (wk / total);
        }
        albedo_at(&m.albedo, mu) * mean * self.env.intensity
    }

    /// The Monte Carlo mode's estimate at the point.
    fn monte_carlo(&self, m: &MaterialData, at: &ShadePoint, samples: u32, seed: u64) -> Vec3 {
        let n_geom = geometric_normal(self.scene, &self.world, at);
        let point = MonteCarloPoint { p: at.p, n: at.n, n_geom, v: self.view(at.p), key: point_key(at) };
        estimate(&m.model, &m.sampler, m.scale, self.env, self.bvh.as_ref(), self.eps, &point, samples, seed)
    }
}

impl<O: Occlusion> Occlusion for EnvironmentLighting<'_, O> {
    fn obscurance(&self, at: &ShadePoint) -> f32 {
        self.inner.obscurance(at)
    }

    fn visibility(&self, at: &ShadePoint, light: usize, incident: &brdf_core::lights::Incident) -> f32 {
        self.inner.visibility(at, light, incident)
    }

    fn visibility_each(
        &self,
        at: &[ShadePoint],
        light: usize,
        incident: &[brdf_core::lights::Incident],
        out: &mut [f32],
    ) {
        self.inner.visibility_each(at, light, incident, out);
    }

    fn indirect(&self, at: &ShadePoint, w: f32) -> Vec3 {
        let base = self.inner.indirect(at, w);
        let Some(m) = self.materials.get(at.instance as usize) else { return base };
        let env = match self.mode {
            EnvironmentMode::Fast => self.fast(m, at) * w,
            EnvironmentMode::MonteCarlo { samples, seed } => self.monte_carlo(m, at, samples, seed),
        };
        base + env
    }
}
