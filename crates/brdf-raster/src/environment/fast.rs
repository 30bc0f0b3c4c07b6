//! The fast environment mode: no noise, one look-up per lobe.
//!
//! - **Diffuse lobes** see the irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω`, kept as its order-2 real
//!   spherical-harmonic expansion (nine RGB coefficients; Ramamoorthi & Hanrahan, "An Efficient
//!   Representation for Irradiance Environment Maps", SIGGRAPH 2001: order 2 holds the clamped cosine's
//!   convolution to within a few percent for any lighting) from [`brdf_core::sh`], and reflect
//!   `E(n)/π` (the mean radiance over the cosine lobe).
//! - **Glossy lobes** see the environment prefiltered with a GGX lobe of their roughness `α` around the
//!   lobe's axis, under the `n = v = r` assumption of the split-sum approximation (B. Karis, "Real Shading
//!   in Unreal Engine 4", SIGGRAPH 2013 course notes): [`ALPHAS`] levels, each the `n·l`-weighted mean of
//!   [`PREFILTER_SAMPLES`] GGX-distributed directions (a fixed Hammersley set, so no noise), read from a
//!   box-filtered pyramid of the map at the level whose texels match each sample's solid angle (Colbert
//!   & Křivánek, "GPU-Based Importance Sampling", GPU Gems 3, 2007), and interpolated linearly in `α`.
//!
//! Both are mean radiances; the material's directional albedo scales them ([`super::lighting`]), so a
//! uniform environment is reproduced exactly.

use std::f32::consts::PI;

use brdf_core::ShadingFrame;
use brdf_core::sh;
use glam::{DVec3, Vec3, Vec3A};
use rayon::prelude::*;

use super::{EnvironmentMap, bilinear, direction_to_uv, uv_to_direction};

/// Roughnesses `α` of the prefiltered levels (level 0 is the map itself, the mirror).
pub const ALPHAS: [f32; 9] = [0.0, 0.04, 0.08, 0.14, 0.22, 0.32, 0.45, 0.65, 1.0];
/// GGX samples per prefiltered texel.
pub const PREFILTER_SAMPLES: u32 = 128;
/// Widest map the spherical-harmonic projection reads (a pyramid level; irradiance has no detail).
const SH_WIDTH: usize = 512;
/// Gauss–Legendre nodes in `cos θ` per texel row of the spherical-harmonic projection.
const SH_ROW_NODES: usize = 4;

/// One equirectangular image.
#[derive(Debug, Clone)]
struct Level {
    w: usize,
    h: usize,
    texels: Vec<Vec3>,
}

impl Level {
    #[inline]
    fn at_dir(&self, d: Vec3) -> Vec3 {
        let (u, t) = direction_to_uv(d);
        bilinear(&self.texels, self.w, self.h, u, t)
    }

    /// 2 × 2 box filter (an odd last row or column averaged with itself).
    fn half(&self) -> Level {
        let (w, h) = (self.w.div_ceil(2), self.h.div_ceil(2));
        let texels = (0..w * h)
            .into_par_iter()
            .map(|i| {
                let (x, y) = (2 * (i % w), 2 * (i / w));
                let (x1, y1) = ((x + 1).min(self.w - 1), (y + 1).min(self.h - 1));
                let t = |x: usize, y: usize| self.texels[y * self.w + x];
                (t(x, y) + t(x1, y) + t(x, y1) + t(x1, y1)) * 0.25
            })
            .collect();
        Level { w, h, texels }
    }
}

/// What the fast mode derives from a map once (in the map's own frame).
#[derive(Debug, Clone)]
pub struct FastEnvironment {
    /// Order-2 irradiance coefficients `E_lm` (already convolved with the clamped cosine).
    irradiance: [DVec3; 9],
    /// Prefiltered levels, one per [`ALPHAS`] entry (level 0: the map).
    levels: Vec<Level>,
}

/// The `i`-th of `n` points of the Hammersley set: `(i/n, radical inverse of i in base 2)`.
#[inline]
fn hammersley(i: u32, n: u32) -> (f32, f32) {
    (i as f32 / n as f32, (i.reverse_bits() as f64 / 4_294_967_296.0) as f32)
}

impl FastEnvironment {
    /// Project and prefilter `map` (in parallel; the same values at any thread count).
    pub fn new(map: &EnvironmentMap) -> Self {
        let (w0, h0) = map.size();
        let mut pyramid = vec![Level { w: w0, h: h0, texels: map.texels().to_vec() }];
        while pyramid.last().is_some_and(|l| l.w > 4 || l.h > 2) {
            let next = pyramid.last().map(Level::half).expect("non-empty");
            pyramid.push(next);
        }
        let irradiance = project_irradiance(pyramid.iter().find(|l| l.w <= SH_WIDTH).expect("last is small"));
        let texel_solid_angle = 4.0 * PI / (w0 * h0) as f32;
        let mut levels = vec![pyramid[0].clone()];
        for &alpha in &ALPHAS[1..] {
            // About 2.5 texels per α radian: the lobe is resolved, the level stays small.
            let w = ((16.0 / alpha).ceil() as usize).next_power_of_two().max(32).min(w0);
            let h = h0.min(w.div_ceil(2)).max(1);
            let texels = (0..w * h)
                .into_par_iter()
                .map(|i| {
                    let r =
                        uv_to_direction(((i % w) as f32 + 0.5) / w as f32, ((i / w) as f32 + 0.5) / h as f32);
                    prefilter(&pyramid, r, alpha, texel_solid_angle)
                })
                .collect();
            levels.push(Level { w, h, texels });
        }
        Self { irradiance, levels }
    }

    /// Irradiance `E(n)` \[W/m² for radiance in W/(m²·sr)\] at the unit normal `n` (map frame) from the
    /// order-2 expansion, clamped at 0 (a high-contrast map rings slightly below zero behind its sun).
    #[inline]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        let mut y = [0.0f64; 9];
        sh::basis_into(n.as_dvec3(), 2, &mut y);
        let e: DVec3 = self.irradiance.iter().zip(&y).map(|(c, y)| *c * *y).sum();
        e.as_vec3().max(Vec3::ZERO)
    }

    /// Mean radiance over a GGX lobe of roughness `alpha` about the unit direction `r` (map frame),
    /// interpolated between the two nearest [`ALPHAS`] levels.
    #[inline]
    pub fn glossy(&self, r: Vec3, alpha: f32) -> Vec3 {
        let a = alpha.clamp(0.0, ALPHAS[ALPHAS.len() - 1]);
        let j = ALPHAS.partition_point(|&x| x <= a).clamp(1, ALPHAS.len() - 1);
        let f = (a - ALPHAS[j - 1]) / (ALPHAS[j] - ALPHAS[j - 1]);
        let lo = self.levels[j - 1].at_dir(r);
        if f <= 0.0 {
            return lo;
        }
        lo * (1.0 - f) + self.levels[j].at_dir(r) * f
    }
}

/// `c_lm = ∫ L Y_lm dω` of the map read as piecewise constant over its texels, then convolved with the
/// clamped cosine. Each texel row is integrated in `μ = cos θ` by [`SH_ROW_NODES`] Gauss–Legendre nodes
/// over its band `[cos θ₁, cos θ₀]` (the midpoint alone is not exact for `Y_20 ∝ 3μ² − 1` on a coarse map:
/// a uniform 8 × 4 map then had a 2 % spurious band 2), and each column at its centre azimuth (exact for
/// the frequencies `m ≤ 2` of order 2 on a map at least 8 texels wide, summed over a row).
fn project_irradiance(level: &Level) -> [DVec3; 9] {
    use std::f64::consts::PI as PI64;
    let (w, h) = (level.w, level.h);
    let dphi = 2.0 * PI64 / w as f64;
    let (gx, gw) = sh::gauss_legendre(SH_ROW_NODES);
    let mut dirs = Vec::with_capacity(w * h * SH_ROW_NODES);
    let mut weights = Vec::with_capacity(w * h * SH_ROW_NODES);
    let mut values = Vec::with_capacity(w * h * SH_ROW_NODES);
    for y in 0..h {
        let (mu0, mu1) = ((y as f64 / h as f64 * PI64).cos(), ((y + 1) as f64 / h as f64 * PI64).cos());
        for (xk, wk) in gx.iter().zip(&gw) {
            // [−1, 1] → [μ₁, μ₀].
            let mu = 0.5 * (mu0 + mu1) + 0.5 * (mu0 - mu1) * xk;
            let s = (1.0 - mu * mu).max(0.0).sqrt();
            let wt = 0.5 * (mu0 - mu1) * wk * dphi;
            for x in 0..w {
                let phi = ((x as f64 + 0.5) / w as f64 - 0.5) * 2.0 * PI64;
                dirs.push(DVec3::new(s * phi.sin(), mu, -s * phi.cos()));
                weights.push(wt);
                values.push(level.texels[y * w + x].as_dvec3());
            }
        }
    }
    let quad = sh::Quadrature { dirs, weights };
    let radiance = sh::project_values(&values, &quad, 2).expect("finite values, one per node");
    let e = sh::irradiance(&radiance).expect("order 2");
    std::array::from_fn(|i| e[i])
}

/// The `n·l`-weighted mean radiance over GGX(`alpha`) reflections about `r` (module docs).
fn prefilter(pyramid: &[Level], r: Vec3, alpha: f32, texel_solid_angle: f32) -> Vec3 {
    let frame = ShadingFrame::from_normal(Vec3A::from(r));
    let a2 = alpha * alpha;
    let n = PREFILTER_SAMPLES;
    let (mut sum, mut wsum) = (Vec3::ZERO, 0.0f32);
    for i in 0..n {
        let (u1, u2) = hammersley(i, n);
        // GGX normal: tan²θ_h = α² u/(1 − u).
        let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
        let (ct, st) = (cos2.sqrt(), (1.0 - cos2).max(0.0).sqrt());
        let (sp, cp) = (2.0 * PI * u2).sin_cos();
        let h = Vec3::new(st * cp, st * sp, ct);
        // l = reflect(v = z) about h.
        let l = 2.0 * ct * h - Vec3::Z;
        if l.z <= 0.0 {
            continue;
        }
        // p(l) = D(h)·(n·h)/(4 v·h) = D/4 with n = v; D = α²/(π((α² − 1)cos²θ + 1)²).
        let dd = (a2 - 1.0) * cos2 + 1.0;
        let pdf = a2 / (PI * dd * dd) / 4.0;
        let lod = (0.5 * ((1.0 / (n as f32 * pdf)) / texel_solid_angle).log2() + 1.0).max(0.0);
        let level = &pyramid[(lod.round() as usize).min(pyramid.len() - 1)];
        let world = Vec3::from(frame.from_local(Vec3A::from(l)));
        sum += level.at_dir(world) * l.z;
        wsum += l.z;
    }
    if wsum > 0.0 { sum / wsum } else { pyramid[0].at_dir(r) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map_of(w: usize, h: usize, f: impl Fn(Vec3) -> Vec3) -> EnvironmentMap {
        let texels = (0..w * h)
            .map(|i| f(uv_to_direction(((i % w) as f32 + 0.5) / w as f32, ((i / w) as f32 + 0.5) / h as f32)))
            .collect();
        EnvironmentMap::new(w, h, texels).unwrap()
    }

    #[test]
    fn a_uniform_environment_gives_irradiance_pi_and_itself_at_every_roughness() {
        // 8 × 4 is the map of `Environment::uniform`.
        let fast = FastEnvironment::new(&map_of(8, 4, |_| Vec3::new(1.0, 0.5, 0.25)));
        for n in [Vec3::Y, Vec3::NEG_Y, Vec3::new(0.6, 0.0, -0.8)] {
            let e = fast.irradiance(n);
            assert!((e - PI * Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-4, "{e}");
            for a in [0.0, 0.03, 0.3, 1.0] {
                let g = fast.glossy(n, a);
                assert!((g - Vec3::new(1.0, 0.5, 0.25)).abs().max_element() < 1e-5, "{a}: {g}");
            }
        }
    }

    #[test]
    fn the_irradiance_of_a_linear_gradient_sky_is_its_analytic_value() {
        // L(ω) = 1 + 0.8·ω_y: E(n) = π + (2π/3)·0.8·n_y (a band-0 plus band-1 function, held exactly by
        // order 2; the texel-sum rule of a 256 × 128 map is accurate to ~1e-4 relative).
        let fast = FastEnvironment::new(&map_of(256, 128, |d| Vec3::splat(1.0 + 0.8 * d.y)));
        for n in [Vec3::Y, Vec3::NEG_Y, Vec3::X, Vec3::new(0.36, 0.48, -0.8)] {
            let want = PI + 2.0 * PI / 3.0 * 0.8 * n.y;
            let got = fast.irradiance(n);
            assert!((got - Vec3::splat(want)).abs().max_element() < 2e-3 * want, "n {n}: {got} vs {want}");
        }
    }

    #[test]
    fn rough_levels_blur_a_small_bright_patch_and_keep_its_energy_local() {
        let fast = FastEnvironment::new(&map_of(256, 128, |d| {
            if d.dot(Vec3::NEG_Z) > 0.995 { Vec3::splat(100.0) } else { Vec3::ZERO }
        }));
        let sharp = fast.glossy(Vec3::NEG_Z, 0.0).x;
        let blurred = fast.glossy(Vec3::NEG_Z, 0.3).x;
        let off_axis = fast.glossy(Vec3::new(0.5, 0.0, -0.866), 0.3).x;
        assert!(
            sharp > 50.0 && blurred < sharp && blurred > off_axis && off_axis > 0.0,
            "{sharp} {blurred} {off_axis}"
        );
        assert!(fast.glossy(Vec3::Z, 0.3).x < 1e-3);
    }

    #[test]
    fn prefiltering_gives_the_same_bits_at_any_thread_count() {
        let map = map_of(128, 64, |d| Vec3::new(d.x.max(0.0), 1.0 + d.y, (3.0 * d.z).sin().abs()));
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| FastEnvironment::new(&map))
        };
        let (a, b) = (run(1), run(3));
        assert_eq!(a.irradiance, b.irradiance);
        for (x, y) in a.levels.iter().zip(&b.levels) {
            assert_eq!(x.texels, y.texels);
        }
    }
}
