//! [`SceneOcclusion`]: obscurance and shadows for the renderer, through its [`Occlusion`] hooks.
//!
//! Built once per render from the scene: one [`Bvh`] over every instance's world-space triangles (the
//! same `transform_point3` / `project_point3` as the renderer's vertex stage), and, for per-vertex
//! obscurance, `w` at every world-space vertex of every instance with its world normal (the normal
//! matrix, as the renderer does) — shading points then interpolate it with their perspective-correct
//! barycentrics (obscurance is "usually pre-calculated and stored as vertex data"). Per-pixel obscurance
//! instead estimates `w` at each shading point, keyed by a hash of the point so the result does not
//! depend on threads or on the order bands are shaded in.
//!
//! Shadow rays start from the shaded triangle's geometric normal (see [`crate::shadows`]); at a vertex
//! (Gouraud shading) the vertex normal stands in for it.
//!
//! With [`AoOptions::combined`], the lights' diffuse irradiance also feeds the ambient term, as in eq.
//! 12.75: `I = [k_a I_a + k_d I_d(p)]·w(p) + direct`. The renderer adds `k_d ∘ I_d(p) · w(p)` through
//! [`Occlusion::indirect`]; `k_d` is the material's ambient reflectance `k_a` — the reflectance the
//! material offers to indirect light (for the course's Lambertian materials `k_a` and `k_d` are the
//! same colour, and any model's direct term is still its own `shade`).

use std::sync::Arc;

use brdf_core::lights::Incident;
use glam::{Mat3, Vec3, Vec4};
use rayon::prelude::*;

use crate::Mesh;
use crate::RasterError;
use crate::ao::{AoOptions, Obscurance, Sampler};
use crate::bvh::{Bvh, Ray};
use crate::render::{Occlusion, ShadePoint};
use crate::scene::Scene;
use crate::shadows::{diffuse_irradiance, shadow_offset, shadow_ray, visibility};
use crate::tiles::NO_TRI;

/// Obscurance and/or shadows of a scene, ready to answer the renderer's [`Occlusion`] queries: the
/// scene, and what was prepared from its geometry ([`OcclusionData`], shared, reusable by later
/// renders of the same geometry through an [`OcclusionCache`]).
pub struct SceneOcclusion<'a> {
    scene: &'a Scene,
    data: Arc<OcclusionData>,
}

/// What obscurance and shadows prepare from a scene's geometry: the BVH over its world-space
/// triangles, the world-space vertices and the per-vertex obscurance. It depends on the instances'
/// meshes and transforms, the obscurance options and any stored obscurance — not on lights, materials
/// or the camera — so a render in a loop (a turntable, an interactive viewer) can reuse it.
#[derive(Debug)]
pub struct OcclusionData {
    bvh: Bvh,
    ao: Option<AoOptions>,
    /// The per-point estimator (pattern, offset) when obscurance is on.
    sampler: Option<Sampler>,
    shadows: bool,
    /// World-space positions of each instance's vertices.
    world: Vec<Vec<Vec3>>,
    /// Per-vertex `w` of each instance (empty for an instance whose obscurance is per pixel or off).
    vertex_w: Vec<Vec<f32>>,
    shadow_eps: f32,
}

impl<'a> SceneOcclusion<'a> {
    /// Prepare obscurance (`ao`, validated here) and/or shadows (`shadows`) for `scene`.
    /// Per-vertex obscurance is computed here, in parallel.
    pub fn new(scene: &'a Scene, ao: Option<AoOptions>, shadows: bool) -> Result<Self, RasterError> {
        Self::with_stored(scene, ao, shadows, vec![None; scene.instances.len()])
    }

    /// The occlusion of `scene` from data prepared earlier for the same geometry (see
    /// [`OcclusionCache`]). Errors when `data` was made for a scene with other instances or vertex
    /// counts.
    pub fn from_data(scene: &'a Scene, data: Arc<OcclusionData>) -> Result<Self, RasterError> {
        let fits = data.world.len() == scene.instances.len()
            && data.world.iter().zip(&scene.instances).all(|(w, i)| w.len() == i.mesh.positions.len());
        if !fits {
            return Err(RasterError::arg(
                "occlusion",
                "prepared for another scene (instances or vertices differ)",
            ));
        }
        Ok(Self { scene, data })
    }

    /// The prepared data (to keep for later renders of the same geometry).
    pub fn data(&self) -> &Arc<OcclusionData> {
        &self.data
    }

    /// As [`SceneOcclusion::new`], with per-vertex obscurance already computed for some instances
    /// (`stored[k]`: one `w ∈ [0, 1]` per vertex of instance `k`'s mesh, e.g. from
    /// [`crate::ao::mesh_obscurance`] kept with the mesh). Stored values are interpolated for their
    /// instances whatever `ao.per_pixel` says; the other instances follow `ao` (estimated per vertex
    /// here, or per pixel). Without `ao`, stored values are ignored (no obscurance).
    pub fn with_stored(
        scene: &'a Scene,
        ao: Option<AoOptions>,
        shadows: bool,
        stored: Vec<Option<Vec<f32>>>,
    ) -> Result<Self, RasterError> {
        if let Some(o) = &ao {
            o.validate()?;
        }
        scene.validate()?;
        if stored.len() != scene.instances.len() {
            return Err(RasterError::arg(
                "obscurance",
                format!("{} stored arrays for {} instances", stored.len(), scene.instances.len()),
            ));
        }
        for (k, (w, inst)) in stored.iter().zip(&scene.instances).enumerate() {
            let Some(w) = w else { continue };
            let nv = inst.mesh.positions.len();
            if w.len() != nv {
                return Err(RasterError::arg(
                    "obscurance",
                    format!("instance {k} stores {} values for {nv} vertices", w.len()),
                ));
            }
            if let Some(i) = w.iter().position(|x| !(0.0..=1.0).contains(x)) {
                return Err(RasterError::arg(
                    "obscurance",
                    format!("instance {k}, vertex {i}: {} is not in [0, 1]", w[i]),
                ));
            }
        }
        let world: Vec<Vec<Vec3>> = scene
            .instances
            .iter()
            .map(|inst| {
                let m = inst.transform;
                let affine = m.row(3) == Vec4::W;
                inst.mesh
                    .positions
                    .par_iter()
                    .map(|&p| if affine { m.transform_point3(p) } else { m.project_point3(p) })
                    .collect()
            })
            .collect();
        let parts: Vec<(&[Vec3], &[[u32; 3]])> =
            scene.instances.iter().zip(&world).map(|(i, w)| (&w[..], &i.mesh.indices[..])).collect();
        let bvh = Bvh::from_parts(&parts)?;
        let sampler = ao.as_ref().map(|o| Sampler::new(&bvh, o)).transpose()?;
        let mut vertex_w = Vec::with_capacity(scene.instances.len());
        for ((inst, w), st) in scene.instances.iter().zip(&world).zip(stored) {
            vertex_w.push(match (&ao, st) {
                (None, _) => Vec::new(),
                (Some(_), Some(st)) => st,
                (Some(o), None) if o.per_pixel => Vec::new(),
                (Some(o), None) => {
                    let nm: Mat3 = inst.normal_matrix();
                    let normals: Vec<Vec3> =
                        inst.mesh.normals.iter().map(|&n| (nm * n).normalize_or_zero()).collect();
                    Obscurance::new(&bvh, o)?.at_points(w, &normals)?
                }
            });
        }
        let shadow_eps = shadow_offset(&bvh);
        let data = OcclusionData { bvh, ao, sampler, shadows, world, vertex_w, shadow_eps };
        Ok(Self { scene, data: Arc::new(data) })
    }

    /// The BVH over the scene's world-space triangles.
    pub fn bvh(&self) -> &Bvh {
        &self.data.bvh
    }

    /// Per-vertex obscurance of instance `k` (empty when its obscurance is off or per pixel).
    pub fn vertex_obscurance(&self, k: usize) -> &[f32] {
        self.data.vertex_w.get(k).map_or(&[], |v| &v[..])
    }

    /// World-space geometric normal of the shaded triangle (the shading normal at a vertex).
    fn geometric_normal(&self, at: &ShadePoint) -> Vec3 {
        let k = at.instance as usize;
        if at.face == NO_TRI {
            return at.n;
        }
        let w = &self.data.world[k];
        let [a, b, c] = self.scene.instances[k].mesh.indices[at.face as usize].map(|i| w[i as usize]);
        let n = (b - a).cross(c - a).normalize_or_zero();
        if n == Vec3::ZERO { at.n } else { n }
    }
}

/// What [`OcclusionData`] depends on: each instance's mesh (the handle itself, kept alive here, so a
/// changed mesh — a new `Arc`, which is what editing a shared mesh makes — never compares equal) and
/// transform, the obscurance options, shadows on or off, and the stored obscurance values.
#[derive(Debug, Clone)]
struct CacheKey {
    meshes: Vec<(Arc<Mesh>, [u32; 16])>,
    ao: Option<[u64; 4]>,
    shadows: bool,
    stored: Vec<Option<Vec<u32>>>,
}

impl CacheKey {
    fn new(scene: &Scene, ao: Option<AoOptions>, shadows: bool, stored: &[Option<Vec<f32>>]) -> Self {
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
        Self {
            meshes: scene
                .instances
                .iter()
                .map(|i| (Arc::clone(&i.mesh), i.transform.to_cols_array().map(f32::to_bits)))
                .collect(),
            ao: ao.map(|o| {
                [
                    u64::from(o.tau.to_bits()) << 32 | u64::from(o.d_max.to_bits()),
                    u64::from(o.samples),
                    o.seed,
                    u64::from(o.per_pixel) << 1 | u64::from(o.combined),
                ]
            }),
            shadows,
            stored: stored.iter().map(|w| w.as_deref().map(bits)).collect(),
        }
    }

    fn matches(&self, other: &Self) -> bool {
        self.meshes.len() == other.meshes.len()
            && self.meshes.iter().zip(&other.meshes).all(|(a, b)| Arc::ptr_eq(&a.0, &b.0) && a.1 == b.1)
            && self.ao == other.ao
            && self.shadows == other.shadows
            && self.stored == other.stored
    }
}

/// The [`OcclusionData`] of the last scene asked for, reused while its geometry and options do not
/// change: a render in a loop (turntable, interactive viewer) then builds the BVH and estimates the
/// per-vertex obscurance once, not every frame. The key is the scene's content: each instance's mesh
/// handle (`Arc`, held by the cache, so a mesh that was changed is a different handle) and transform,
/// the obscurance options, shadows on or off, and stored obscurance values; lights, materials and the
/// camera may change freely. The cache holds the last scene's meshes until the next miss or
/// [`OcclusionCache::clear`].
#[derive(Debug, Default)]
pub struct OcclusionCache {
    entry: Option<(CacheKey, Arc<OcclusionData>)>,
    hits: u64,
    misses: u64,
}

impl OcclusionCache {
    /// An empty cache (`const`, so it can be a `static`).
    pub const fn new() -> Self {
        Self { entry: None, hits: 0, misses: 0 }
    }

    /// The occlusion of `scene` (as [`SceneOcclusion::with_stored`]), from the cached data when the
    /// scene's geometry and the options are those of the last call, else prepared afresh and kept.
    pub fn get<'a>(
        &mut self,
        scene: &'a Scene,
        ao: Option<AoOptions>,
        shadows: bool,
        stored: Vec<Option<Vec<f32>>>,
    ) -> Result<SceneOcclusion<'a>, RasterError> {
        let key = CacheKey::new(scene, ao, shadows, &stored);
        if let Some((k, data)) = &self.entry {
            if k.matches(&key) {
                // The scene itself (lights, materials) is checked as a fresh one would be.
                scene.validate()?;
                self.hits += 1;
                return SceneOcclusion::from_data(scene, Arc::clone(data));
            }
        }
        self.entry = None;
        let occ = SceneOcclusion::with_stored(scene, ao, shadows, stored)?;
        self.misses += 1;
        self.entry = Some((key, Arc::clone(occ.data())));
        Ok(occ)
    }

    /// `(hits, misses)` so far.
    pub fn stats(&self) -> (u64, u64) {
        (self.hits, self.misses)
    }

    /// Forget the cached data (and the meshes the key holds).
    pub fn clear(&mut self) {
        self.entry = None;
    }
}

/// A key for the per-pixel sample pattern from what identifies the point (instance, face, vertex and
/// the bits of its position): deterministic, independent of threads and band order.
fn point_key(at: &ShadePoint) -> u64 {
    let mut h = 0xCBF2_9CE4_8422_2325u64;
    for x in [at.instance, at.face, at.vertex, at.p.x.to_bits(), at.p.y.to_bits(), at.p.z.to_bits()] {
        h = (h ^ u64::from(x)).wrapping_mul(0x0000_0100_0000_01B3);
    }
    h
}

impl Occlusion for SceneOcclusion<'_> {
    fn obscurance(&self, at: &ShadePoint) -> f32 {
        let Some(sampler) = &self.data.sampler else { return 1.0 };
        let k = at.instance as usize;
        let w = &self.data.vertex_w[k];
        if w.is_empty() {
            return sampler.at(&self.data.bvh, at.p, at.n, point_key(at));
        }
        if at.vertex != NO_TRI {
            return w[at.vertex as usize];
        }
        let [a, b, c] = self.scene.instances[k].mesh.indices[at.face as usize];
        (at.bary.x * w[a as usize] + at.bary.y * w[b as usize] + at.bary.z * w[c as usize]).clamp(0.0, 1.0)
    }

    fn visibility(&self, at: &ShadePoint, _light: usize, incident: &Incident) -> f32 {
        if !self.data.shadows {
            return 1.0;
        }
        visibility(&self.data.bvh, at.p, self.geometric_normal(at), incident, self.data.shadow_eps)
    }

    /// The shadow rays of all the points traced together, in packets ([`Bvh::any_hit_each`]): the
    /// same rays and answers as [`SceneOcclusion::visibility`] point by point.
    fn visibility_each(&self, at: &[ShadePoint], _light: usize, incident: &[Incident], out: &mut [f32]) {
        if !self.data.shadows {
            out.fill(1.0);
            return;
        }
        const BLOCK: usize = 64;
        for ((at, incident), out) in at.chunks(BLOCK).zip(incident.chunks(BLOCK)).zip(out.chunks_mut(BLOCK)) {
            let rays: [Ray; BLOCK] = std::array::from_fn(|k| match (at.get(k), incident.get(k)) {
                (Some(a), Some(inc)) => {
                    shadow_ray(a.p, self.geometric_normal(a), inc.l, inc.distance, self.data.shadow_eps)
                }
                _ => Ray::segment(Vec3::ZERO, Vec3::X, 0.0, -1.0),
            });
            let n = at.len();
            let mut hit = [false; BLOCK];
            self.data.bvh.any_hit_each(&rays[..n], &mut hit[..n]);
            for k in 0..n {
                // `visibility`: an empty segment (the light within 2ε) counts as blocked.
                out[k] = if rays[k].t_max <= 0.0 || hit[k] { 0.0 } else { 1.0 };
            }
        }
    }

    fn indirect(&self, at: &ShadePoint, w: f32) -> Vec3 {
        let Some(o) = &self.data.ao else { return Vec3::ZERO };
        if !o.combined || w <= 0.0 {
            return Vec3::ZERO;
        }
        let ka = self.scene.instances[at.instance as usize].material.ambient;
        let bvh = self.data.shadows.then_some(&self.data.bvh);
        ka * diffuse_irradiance(bvh, at.p, at.n, self.geometric_normal(at), &self.scene.lights) * w
    }
}
