//! The Monte Carlo environment mode: an unbiased estimate of the reflected radiance
//!
//! ```text
//! L_o(v) = ∫_{H²} L(l) V(p, l) f_r(l, v) cos θ_l dω_l
//! ```
//!
//! with `V` the visibility by the scene's BVH, by multiple importance sampling (E. Veach, L. Guibas,
//! "Optimally Combining Sampling Techniques for Monte Carlo Rendering", SIGGRAPH 1995; power heuristic,
//! β = 2) of two strategies, one sample of each per iteration:
//! - the material's own sampler (`Model::sampler`, the importance sampling of [`brdf_core::sampling`]),
//!   `weight = f·cos/p_b`;
//! - the environment's: texels drawn in proportion to luminance × `sin θ` by a piecewise-constant 2-D
//!   distribution ([`brdf_core::sampling::Distribution2D`], Pharr, Jakob & Humphreys, *Physically Based
//!   Rendering*, 4th ed., §12.5), with the solid-angle density `p_e(ω) = p(u, t) / (2π² sin θ)`.
//!
//! Random numbers are counter-based ([`brdf_core::sampling::rng`]), keyed by the seed and by the shaded
//! point itself (instance, face and barycentrics), so every sample gets the same numbers whichever thread
//! shades it: the image has the same bits at any thread count.

use std::f32::consts::PI;

use brdf_core::sampling::{Distribution2D, Sampler, rng};
use brdf_core::{Geometry, Model};
use glam::Vec3;

use super::{Environment, EnvironmentMap, direction_to_uv, uv_to_direction};
use crate::bvh::Bvh;
use crate::shadows::shadow_ray;

/// The environment's luminance distribution over its texels.
#[derive(Debug, Clone)]
pub struct EnvironmentSampler {
    dist: Distribution2D,
    /// Whether any texel has light (otherwise environment samples are skipped).
    lit: bool,
}

/// Rec. 709 luminance of linear RGB.
#[inline]
fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

impl EnvironmentSampler {
    /// The distribution of `map`: luminance × `sin θ` of each texel (so that texels are drawn by the
    /// power they deliver; a tiny floor keeps every lit direction reachable).
    pub fn new(map: &EnvironmentMap) -> Self {
        let (w, h) = map.size();
        let mut func = Vec::with_capacity(w * h);
        for (i, t) in map.texels().iter().enumerate() {
            let st = (((i / w) as f32 + 0.5) / h as f32 * PI).sin();
            let y = luminance(*t).max(t.max_element() * 1e-3);
            func.push(y * st);
        }
        let lit = func.iter().any(|&f| f > 0.0);
        let dist = Distribution2D::new("image", &func, w, h).expect("texels are finite and ≥ 0");
        Self { dist, lit }
    }

    /// A map-frame direction from `(u0, u1)` and its solid-angle density \[1/sr\] (0: none).
    #[inline]
    pub fn sample(&self, u0: f32, u1: f32) -> (Vec3, f32) {
        if !self.lit {
            return (Vec3::Y, 0.0);
        }
        let ([u, t], p) = self.dist.sample(u0, u1);
        let st = (t * PI).sin();
        if !(st > 0.0) {
            return (Vec3::Y, 0.0);
        }
        (uv_to_direction(u, t), p / (2.0 * PI * PI * st))
    }

    /// The solid-angle density of drawing the map-frame unit direction `d` \[1/sr\].
    #[inline]
    pub fn pdf(&self, d: Vec3) -> f32 {
        if !self.lit {
            return 0.0;
        }
        let (u, t) = direction_to_uv(d);
        let st = (t * PI).sin();
        if !(st > 0.0) {
            return 0.0;
        }
        self.dist.pdf([u, t]) / (2.0 * PI * PI * st)
    }
}

/// One shaded point as the estimator needs it.
#[derive(Debug, Clone, Copy)]
pub struct MonteCarloPoint {
    /// Position (world).
    pub p: Vec3,
    /// Unit shading normal.
    pub n: Vec3,
    /// Unit geometric normal (offsets the visibility rays).
    pub n_geom: Vec3,
    /// Unit direction toward the viewer.
    pub v: Vec3,
    /// The point's own stream of random numbers ([`rng::mix64`] of what identifies it).
    pub key: u64,
}

/// The power heuristic `a² / (a² + b²)` (0 where both are 0).
#[inline]
pub(crate) fn power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

/// The MIS estimate of `L_o(v)` at `at` with `samples` iterations (one BRDF and one environment sample
/// each), `scale` multiplying `f·cos` (1 for physical models, 1/π for classic ones), visibility by
/// `bvh` (offset `eps`; `None`: nothing occludes). Finite and ≥ 0.
#[allow(clippy::too_many_arguments)]
pub fn estimate(
    model: &Model,
    sampler: &Sampler,
    scale: f32,
    env: &Environment,
    bvh: Option<&Bvh>,
    eps: f32,
    at: &MonteCarloPoint,
    samples: u32,
    seed: u64,
) -> Vec3 {
    let envs = env.map.sampling();
    let key = rng::key(seed);
    let visible = |l: Vec3| match bvh {
        None => true,
        Some(b) => !b.any_hit(&shadow_ray(at.p, at.n_geom, l, f32::INFINITY, eps)),
    };
    let mut sum = Vec3::ZERO;
    for s in 0..samples {
        let row = at.key.wrapping_add(u64::from(s).wrapping_mul(2));
        // The material's strategy.
        let u = [0, 1, 2].map(|d| rng::uniform_keyed(key, row, d));
        let bs = model.sample_with(sampler, at.v, at.n, None, u);
        if bs.pdf > 0.0 {
            let li = env.radiance(bs.l);
            if li.max_element() > 0.0 && visible(bs.l) {
                let pe = envs.pdf(env.to_map(bs.l));
                sum += bs.weight * li * power(bs.pdf, pe);
            }
        }
        // The environment's strategy.
        let row_e = row.wrapping_add(1);
        let (d, pe) = envs.sample(rng::uniform_keyed(key, row_e, 0), rng::uniform_keyed(key, row_e, 1));
        if pe > 0.0 {
            let l = env.to_world(d);
            if let Some(g) = Geometry::new(l, at.v, at.n, None) {
                let fc = model.shade(&g);
                if fc.max_element() > 0.0 && visible(l) {
                    let pb = sampler.pdf(l, at.v, at.n, None);
                    sum += fc * env.radiance(l) * (power(pe, pb) / pe);
                }
            }
        }
    }
    let c = sum * (scale / samples as f32);
    if c.is_finite() { c.max(Vec3::ZERO) } else { Vec3::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_environment_density_integrates_to_one_and_follows_the_light() {
        let (w, h) = (64, 32);
        let texels: Vec<Vec3> = (0..w * h)
            .map(|i| if (i % w) > 40 && (i / w) < 12 { Vec3::splat(5.0) } else { Vec3::splat(0.1) })
            .collect();
        let map = EnvironmentMap::new(w, h, texels).unwrap();
        let s = EnvironmentSampler::new(&map);
        // ∫ p_e dω over a fine rule of the sphere.
        let q = brdf_core::sh::Quadrature::new(200, 400).unwrap();
        let total: f64 = q.dirs.iter().zip(&q.weights).map(|(d, w)| f64::from(s.pdf(d.as_vec3())) * w).sum();
        assert!((total - 1.0).abs() < 1e-2, "{total}");
        // Drawn directions land on the bright patch far more often than its area share.
        let bright = (0..4000)
            .filter(|&k| {
                let (d, _) = s.sample(rng::uniform_keyed(7, k, 0), rng::uniform_keyed(7, k, 1));
                let (u, t) = direction_to_uv(d);
                u * 64.0 > 40.0 && t * 32.0 < 12.0
            })
            .count();
        assert!(bright > 3000, "{bright}");
    }
}
