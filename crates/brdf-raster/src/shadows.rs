//! Light visibility δ(p, j) by shadow rays, and the combined obscurance illumination of
//! Theoharis et al. 2008 eq. 12.75.
//!
//! ## Why shadow rays and not shadow maps
//! The scene is already in a [`Bvh`] for obscurance, and a shadow ray answers δ exactly at the shaded
//! point for every light type (directional, point, spot) with no resolution, no per-light depth
//! render, no depth bias tuned per scene, no cube maps for point lights and no aliasing at shadow edges;
//! the cost is one any-hit query per light and shaded point, which the BVH answers at millions per second
//! per core. Shadow maps win when the scene changes every frame on a GPU; neither holds here.
//!
//! ## Offset (shadow acne)
//! A shadow ray starts at `p + ε·n_g`, where `n_g` is the **geometric** normal of the shaded triangle
//! flipped to the side the light is on, and ends `ε` short of a point or spot light:
//! `t ∈ [0, d − 2ε]` (a lamp modelled as geometry around the light does not shadow its own light). The
//! geometric normal (not the interpolated shading normal) is what separates the two sides of the
//! triangle the point lies on, so the ray cannot re-hit that triangle. `ε = max(2⁻¹⁶·s, 10⁻⁴·D)` with `s`
//! the largest coordinate magnitude ([`Bvh::coordinate_scale`], ≈256 float ulps there) and `D` the scene
//! box diagonal: above the rounding error of interpolated positions, and far below any feature size that
//! matters for shadows.
//!
//! δ is purely geometric, as in the seed ("1 if the j-th light source is visible from the patch"): a
//! spot light's cone and the attenuation belong to the irradiance `E_j`, not to δ.

use brdf_core::lights::{Incident, Light};
use glam::Vec3;

use crate::bvh::{Bvh, Ray};

/// The shadow-ray offset ε of the module docs for a scene (world units).
pub fn shadow_offset(bvh: &Bvh) -> f32 {
    let (lo, hi) = bvh.bounds();
    let diag = if bvh.triangle_count() > 0 { (hi - lo).length() } else { 0.0 };
    (bvh.coordinate_scale() * (1.0 / 65536.0)).max(1e-4 * diag)
}

/// The shadow ray from `p` toward the light along unit `l`, `distance` away (∞ for a directional
/// light): origin `p + ε·n_g` with `n_g` flipped toward `l`, `t ∈ [0, distance − 2ε]`.
pub fn shadow_ray(p: Vec3, n_geom: Vec3, l: Vec3, distance: f32, eps: f32) -> Ray {
    let n = if n_geom.dot(l) < 0.0 { -n_geom } else { n_geom };
    let n = n.normalize_or_zero();
    let t_max = if distance.is_finite() { (distance - 2.0 * eps).max(0.0) } else { f32::INFINITY };
    Ray::segment(p + n * eps, l, 0.0, t_max)
}

/// δ for light arriving as `incident` (from [`Light::incident`]): 1 when the shadow ray reaches the
/// light, 0 when geometry blocks it.
pub fn visibility(bvh: &Bvh, p: Vec3, n_geom: Vec3, incident: &Incident, eps: f32) -> f32 {
    let ray = shadow_ray(p, n_geom, incident.l, incident.distance, eps);
    if ray.t_max <= 0.0 || bvh.any_hit(&ray) { 0.0 } else { 1.0 }
}

/// δ(p, j) of Theoharis et al. 2008 eq. 12.75 for one light, from its geometry alone: toward `−direction` for
/// a
/// directional light, toward the position for a point or spot light (whatever the cone). 1 when
/// visible, 0 when blocked; 1 for a point light at `p` itself (no segment to block).
pub fn light_visibility(bvh: &Bvh, p: Vec3, n_geom: Vec3, light: &Light) -> f32 {
    let Some(inc) = geometric_incident(light, p) else { return 1.0 };
    visibility(bvh, p, n_geom, &inc, shadow_offset(bvh))
}

/// The direction and distance from `p` to a light from its geometry alone, whatever its cone and
/// colour: toward `−direction` (at infinity) for a directional light, toward the position for a point
/// or spot light; `irradiance` is 1. `None` for a point or spot light at `p` itself. What a shadow ray
/// needs where the light's own [`Light::incident`] may say nothing arrives (outside a spot's cone).
pub fn geometric_incident(light: &Light, p: Vec3) -> Option<Incident> {
    let (l, distance) = match *light {
        Light::Directional { direction, .. } => (-direction.normalize_or_zero(), f32::INFINITY),
        Light::Point { position, .. } | Light::Spot { position, .. } => {
            let to = position - p;
            let d = to.length();
            if !(d > 0.0) {
                return None;
            }
            (to / d, d)
        }
    };
    Some(Incident { l, irradiance: Vec3::ONE, distance })
}

/// `I_d(p) = Σ_j δ(p, j) · E_j · max(l_j·n, 0)` of eq. 12.75: the diffuse irradiance from the lights
/// with shadows (linear RGB). `E_j` is [`Light::incident`]'s irradiance, i.e. the seed's
/// `I_L(j)/d_j²` with the light's own attenuation and spot cone. `n` is the unit shading normal,
/// `n_geom` the geometric one for the ray offset; `bvh = None` means no shadows (δ = 1).
pub fn diffuse_irradiance(bvh: Option<&Bvh>, p: Vec3, n: Vec3, n_geom: Vec3, lights: &[Light]) -> Vec3 {
    let eps = bvh.map_or(0.0, shadow_offset);
    let mut sum = Vec3::ZERO;
    for light in lights {
        let Some(inc) = light.incident(p) else { continue };
        let cos = inc.l.dot(n);
        if cos <= 0.0 {
            continue;
        }
        let delta = bvh.map_or(1.0, |b| visibility(b, p, n_geom, &inc, eps));
        sum += delta * cos * inc.irradiance;
    }
    sum
}

/// The combined illumination of Theoharis et al. 2008 eq. 12.75 for a Lambertian surface:
///
/// ```text
/// I(p) = [k_a ∘ I_a + k_d ∘ I_d(p)] · w(p) + k_d ∘ I_d(p)
/// ```
///
/// with `w` the obscurance and `I_d` from [`diffuse_irradiance`]. The ambient term carries, besides
/// the ambient light, the lights' own contribution scaled by the obscurance (the light that reaches
/// `p` indirectly, after bouncing off its surroundings; Iones et al. 2003). **Form chosen:** the seed
/// prints the last term as `I_d(p)`; we multiply it by `k_d`, because the seed derives the formula
/// "assuming Lambertian surfaces", whose direct diffuse term is `k_d (l·n) I_L/d²` (eq. 12.25) — the
/// printed form would reflect direct light with reflectance 1 whatever the surface colour. With
/// `k_d = 1` the two agree. Linear RGB in, linear RGB out.
pub fn obscurance_illumination(ka: Vec3, ia: Vec3, kd: Vec3, id: Vec3, w: f32) -> Vec3 {
    (ka * ia + kd * id) * w + kd * id
}
