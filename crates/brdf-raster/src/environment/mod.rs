//! Environment lighting: a scene lit by the radiance arriving from every direction, given as an
//! equirectangular (latitude–longitude) image, and shown as the background.
//!
//! ## The map
//! World space is y-up. A direction `d` is first turned by the environment's rotation (about `+y`, by
//! `−rotation`), then mapped to the image by
//!
//! ```text
//! θ = acos(d_y) ∈ [0, π]  (0 = zenith, image row 0),   φ = atan2(d_x, −d_z) ∈ (−π, π]
//! u = ½ + φ / 2π ∈ [0, 1)   (column; u = ½ looks along −z),   t = θ / π ∈ [0, 1]   (row)
//! d = (sin θ sin φ, cos θ, −sin θ cos φ)
//! ```
//!
//! so that a camera looking along `−z` (the default) sees the middle of the image ahead, `+x` to its
//! right. Radiance is linear RGB \[W/(m²·sr) or any consistent unit\], looked up bilinearly (wrapping in
//! `u`, clamped in `t`) and multiplied by the environment's `intensity`.
//!
//! ## Modes ([`EnvironmentMode`])
//! - [`EnvironmentMode::Fast`] ([`fast`]): no noise, for interactive use: the diffuse lobes of a
//!   material from the order-2 spherical-harmonic irradiance (Ramamoorthi & Hanrahan 2001), the glossy
//!   ones from the environment prefiltered by roughness (the split-sum approximation of Karis 2013),
//!   both scaled by the material's own directional albedo.
//! - [`EnvironmentMode::MonteCarlo`] ([`monte_carlo`]): an unbiased estimate of
//!   `L_o(v) = ∫ L(l) V(l) f_r(l, v) cos θ_l dω_l` with multiple importance sampling (Veach & Guibas
//!   1995, power heuristic) between the material's sampler and the environment's luminance.

pub mod fast;
pub mod file;
pub mod lighting;
pub mod monte_carlo;
pub mod rgbe;

use std::f32::consts::PI;
use std::sync::{Arc, OnceLock};

use glam::Vec3;

use crate::RasterError;

/// Largest accepted environment image side, in pixels.
pub const MAX_ENVIRONMENT_SIDE: usize = 16384;

/// How an environment lights a render.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EnvironmentMode {
    /// Spherical-harmonic irradiance and a prefiltered environment: no noise ([`fast`]).
    #[default]
    Fast,
    /// Monte Carlo with MIS and ray-cast visibility ([`monte_carlo`]).
    MonteCarlo {
        /// Samples per shaded point and strategy (each takes one BRDF and one environment sample), ≥ 1.
        samples: u32,
        /// Seed of the counter-based random numbers: the same image for the same seed, at any thread
        /// count.
        seed: u64,
    },
}

impl EnvironmentMode {
    /// Parse `"fast"` or `"monte_carlo"` (with `samples` and `seed`).
    pub fn from_name(name: &str, samples: u32, seed: u64) -> Result<Self, RasterError> {
        match name {
            "fast" => Ok(Self::Fast),
            "monte_carlo" | "mc" => {
                let m = Self::MonteCarlo { samples, seed };
                m.validate()?;
                Ok(m)
            }
            _ => Err(RasterError::arg(
                "env_mode",
                format!("unknown environment mode {name:?}; expected \"fast\" or \"monte_carlo\""),
            )),
        }
    }

    /// Check the sample count.
    pub fn validate(&self) -> Result<(), RasterError> {
        match *self {
            Self::MonteCarlo { samples, .. } if !(1..=1 << 20).contains(&samples) => {
                Err(RasterError::arg("env_samples", format!("must be in 1..=1048576, got {samples}")))
            }
            _ => Ok(()),
        }
    }
}

/// The pixels of an equirectangular map and what is derived from them once (prefiltered levels,
/// sampling distribution), shared by every rotation and intensity of it.
#[derive(Debug)]
pub struct EnvironmentMap {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
    fast: OnceLock<fast::FastEnvironment>,
    sampling: OnceLock<monte_carlo::EnvironmentSampler>,
}

impl EnvironmentMap {
    /// A map from `width × height` linear RGB texels, row-major, row 0 at the zenith. Refused (naming
    /// `image`): an empty or too large size, a length that does not match, a non-finite or negative
    /// texel.
    pub fn new(width: usize, height: usize, texels: Vec<Vec3>) -> Result<Self, RasterError> {
        if width == 0 || height == 0 || width > MAX_ENVIRONMENT_SIDE || height > MAX_ENVIRONMENT_SIDE {
            return Err(RasterError::arg(
                "image",
                format!("must be 1..={MAX_ENVIRONMENT_SIDE} pixels wide and tall, got {width}×{height}"),
            ));
        }
        if texels.len() != width * height {
            return Err(RasterError::arg(
                "image",
                format!("{width}×{height} needs {} texels, got {}", width * height, texels.len()),
            ));
        }
        if let Some(i) = texels.iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
            return Err(RasterError::arg(
                "image",
                format!(
                    "radiance must be finite and ≥ 0; pixel (row {}, column {}) is {}",
                    i / width,
                    i % width,
                    texels[i]
                ),
            ));
        }
        Ok(Self { width, height, texels, fast: OnceLock::new(), sampling: OnceLock::new() })
    }

    /// Width and height in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The texels, row-major from the zenith.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Bilinear look-up at image coordinates `(u, t) ∈ [0, 1]²` (wrapping in `u`, clamped in `t`).
    #[inline]
    pub fn lookup(&self, u: f32, t: f32) -> Vec3 {
        bilinear(&self.texels, self.width, self.height, u, t)
    }

    /// The prefiltered data of the fast mode, computed on first use.
    pub fn fast(&self) -> &fast::FastEnvironment {
        self.fast.get_or_init(|| fast::FastEnvironment::new(self))
    }

    /// The luminance distribution of the Monte Carlo mode, computed on first use.
    pub fn sampling(&self) -> &monte_carlo::EnvironmentSampler {
        self.sampling.get_or_init(|| monte_carlo::EnvironmentSampler::new(self))
    }
}

/// Bilinear look-up in a `w × h` equirectangular image at `(u, t)` (see [`EnvironmentMap::lookup`]).
#[inline]
pub(crate) fn bilinear(texels: &[Vec3], w: usize, h: usize, u: f32, t: f32) -> Vec3 {
    let x = u * w as f32 - 0.5;
    let y = (t * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let xi = (x0 as i64).rem_euclid(w as i64) as usize;
    let x1 = (xi + 1) % w;
    let yi = (y0 as usize).min(h - 1);
    let y1 = (yi + 1).min(h - 1);
    let at = |x: usize, y: usize| texels[y * w + x];
    (at(xi, yi) * (1.0 - fx) + at(x1, yi) * fx) * (1.0 - fy)
        + (at(xi, y1) * (1.0 - fx) + at(x1, y1) * fx) * fy
}

/// Image coordinates `(u, t)` of a unit direction in the map's own frame (module docs).
#[inline]
pub fn direction_to_uv(d: Vec3) -> (f32, f32) {
    let t = d.y.clamp(-1.0, 1.0).acos() / PI;
    let phi = d.x.atan2(-d.z);
    let u = 0.5 + phi / (2.0 * PI);
    (if u >= 1.0 { u - 1.0 } else { u }, t)
}

/// The unit direction (map frame) at image coordinates `(u, t)` (module docs).
#[inline]
pub fn uv_to_direction(u: f32, t: f32) -> Vec3 {
    let (st, ct) = (t * PI).sin_cos();
    let (sp, cp) = ((u - 0.5) * 2.0 * PI).sin_cos();
    Vec3::new(st * sp, ct, -st * cp)
}

/// An environment: a map, turned about `+y` by `rotation` and scaled by `intensity`.
#[derive(Debug, Clone)]
pub struct Environment {
    /// The image (shared by every rotation and intensity of it).
    pub map: Arc<EnvironmentMap>,
    /// Rotation about `+y` \[rad\]: the map's `−z` direction is seen toward `R_y(rotation)·(−z)`.
    pub rotation: f32,
    /// Radiance scale (≥ 0).
    pub intensity: f32,
}

impl Environment {
    /// An environment from an equirectangular image (see [`EnvironmentMap::new`]), unrotated, intensity 1.
    pub fn from_equirect(width: usize, height: usize, texels: Vec<Vec3>) -> Result<Self, RasterError> {
        Ok(Self { map: Arc::new(EnvironmentMap::new(width, height, texels)?), rotation: 0.0, intensity: 1.0 })
    }

    /// An environment from an image array of shape `(height, width, channels)`, row-major, float32
    /// linear RGB (`channels` must be 3): what a NumPy array holds. Refused naming `image`.
    pub fn from_rgb(height: usize, width: usize, channels: usize, data: &[f32]) -> Result<Self, RasterError> {
        if channels != 3 {
            return Err(RasterError::arg(
                "image",
                format!(
                    "must have shape (height, width, 3) of linear RGB, got ({height}, {width}, {channels})"
                ),
            ));
        }
        if data.len() != height * width * 3 {
            return Err(RasterError::arg(
                "image",
                format!(
                    "shape ({height}, {width}, 3) needs {} values, got {}",
                    height * width * 3,
                    data.len()
                ),
            ));
        }
        if width == 0 || height == 0 {
            return Err(RasterError::arg("image", format!("is empty, shape ({height}, {width}, 3)")));
        }
        Self::from_equirect(width, height, data.chunks_exact(3).map(Vec3::from_slice).collect())
    }

    /// The same radiance `radiance` from every direction (linear RGB, finite, ≥ 0): the white furnace.
    pub fn uniform(radiance: Vec3) -> Result<Self, RasterError> {
        if !radiance.is_finite() || radiance.min_element() < 0.0 {
            return Err(RasterError::arg("radiance", format!("must be finite and ≥ 0, got {radiance}")));
        }
        Self::from_equirect(8, 4, vec![radiance; 32])
    }

    /// A procedural sky over a ground, 512 × 256 texels: above the horizon `horizon → zenith` as
    /// `s = sin(elevation)` grows (by `√s`, a sky brightest near the horizon's haze), below it `ground`,
    /// blended over the 3° below the horizon. A studio gradient is the same with grey tones.
    pub fn sky(zenith: Vec3, horizon: Vec3, ground: Vec3) -> Result<Self, RasterError> {
        for (name, c) in [("zenith", zenith), ("horizon", horizon), ("ground", ground)] {
            if !c.is_finite() || c.min_element() < 0.0 {
                return Err(RasterError::arg(name, format!("must be finite and ≥ 0, got {c}")));
            }
        }
        let (w, h) = (512usize, 256usize);
        let blend = 3f32.to_radians().sin();
        let texels = (0..w * h)
            .map(|i| {
                let t = ((i / w) as f32 + 0.5) / h as f32;
                let s = (t * PI).cos(); // sin(elevation)
                if s >= 0.0 {
                    horizon.lerp(zenith, s.sqrt())
                } else {
                    horizon.lerp(ground, (-s / blend).min(1.0))
                }
            })
            .collect();
        Self::from_equirect(w, h, texels)
    }

    /// This environment turned by `rotation` \[rad\] about `+y`.
    pub fn with_rotation(mut self, rotation: f32) -> Result<Self, RasterError> {
        if !rotation.is_finite() {
            return Err(RasterError::arg("rotation", format!("must be finite, got {rotation}")));
        }
        self.rotation = rotation;
        Ok(self)
    }

    /// This environment with its radiance scaled by `intensity` (finite, ≥ 0).
    pub fn with_intensity(mut self, intensity: f32) -> Result<Self, RasterError> {
        if !intensity.is_finite() || intensity < 0.0 {
            return Err(RasterError::arg("intensity", format!("must be finite and ≥ 0, got {intensity}")));
        }
        self.intensity = intensity;
        Ok(self)
    }

    /// Check rotation and intensity (the map was checked when made).
    pub fn validate(&self) -> Result<(), RasterError> {
        self.clone().with_rotation(self.rotation)?.with_intensity(self.intensity)?;
        Ok(())
    }

    /// A world direction in the map's frame: turned by `−rotation` about `+y`.
    #[inline]
    pub fn to_map(&self, d: Vec3) -> Vec3 {
        let (s, c) = self.rotation.sin_cos();
        Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
    }

    /// A map direction in the world: turned by `rotation` about `+y`.
    #[inline]
    pub fn to_world(&self, d: Vec3) -> Vec3 {
        let (s, c) = self.rotation.sin_cos();
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// Radiance arriving from world direction `d` (unit), looked up bilinearly, times the intensity.
    #[inline]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (u, t) = direction_to_uv(self.to_map(d));
        self.map.lookup(u, t) * self.intensity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_and_image_coordinates_are_inverse() {
        for &(u, t) in &[(0.5, 0.5), (0.75, 0.3), (0.1, 0.9), (0.99, 0.01)] {
            let d = uv_to_direction(u, t);
            let (u2, t2) = direction_to_uv(d);
            assert!((u - u2).abs() < 1e-5 && (t - t2).abs() < 1e-5, "{u} {t} → {u2} {t2}");
        }
        assert!((uv_to_direction(0.5, 0.5) - Vec3::NEG_Z).length() < 1e-6);
        assert!((uv_to_direction(0.75, 0.5) - Vec3::X).length() < 1e-6);
        assert!((uv_to_direction(0.3, 0.0) - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn rotation_turns_the_map_about_the_vertical() {
        let mut texels = vec![Vec3::ZERO; 64 * 32];
        // A bright column at u = 0.75: the +x direction of the map.
        for r in 0..32 {
            texels[r * 64 + 48] = Vec3::ONE;
        }
        let env = Environment::from_equirect(64, 32, texels).unwrap();
        assert!(env.radiance(Vec3::X).x > 0.4);
        let turned = env.with_rotation(std::f32::consts::FRAC_PI_2).unwrap();
        // Turned by +90° about +y, the map's +x is seen toward R_y(90°)·x = −z.
        assert!(turned.radiance(Vec3::NEG_Z).x > 0.4 && turned.radiance(Vec3::X).x < 1e-6);
        let d = Vec3::new(0.3, 0.4, -0.5).normalize();
        assert!((turned.to_world(turned.to_map(d)) - d).length() < 1e-6);
    }

    #[test]
    fn bad_images_are_refused_naming_the_argument() {
        let bad = |w, h, t: Vec<Vec3>| Environment::from_equirect(w, h, t).unwrap_err().to_string();
        assert!(bad(0, 4, vec![]).starts_with("image:"));
        assert!(bad(4, 2, vec![Vec3::ONE; 7]).contains("needs 8 texels"));
        let mut t = vec![Vec3::ONE; 8];
        t[5].y = f32::NAN;
        assert!(bad(4, 2, t.clone()).contains("row 1, column 1"));
        t[5].y = -1.0;
        assert!(bad(4, 2, t).contains("≥ 0"));
        assert!(Environment::uniform(Vec3::ONE).unwrap().with_intensity(-1.0).is_err());
        assert!(Environment::uniform(Vec3::splat(f32::INFINITY)).is_err());
        assert!(
            EnvironmentMode::from_name("monte_carlo", 0, 0).unwrap_err().to_string().contains("env_samples")
        );
        assert!(EnvironmentMode::from_name("path", 1, 0).unwrap_err().to_string().contains("env_mode"));
    }

    #[test]
    fn the_uniform_environment_is_the_same_everywhere() {
        let env = Environment::uniform(Vec3::new(0.5, 1.0, 2.0)).unwrap().with_intensity(2.0).unwrap();
        for d in [Vec3::X, Vec3::Y, Vec3::NEG_Y, Vec3::new(0.6, -0.64, 0.48)] {
            assert_eq!(env.radiance(d), Vec3::new(1.0, 2.0, 4.0));
        }
    }
}
