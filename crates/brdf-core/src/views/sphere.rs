//! The lit sphere: a unit sphere seen orthographically along `−z` (the viewer `v = +z` at every pixel),
//! shaded per sample from its analytic normal by one directional light and a uniform sky.
//!
//! - The light: `π · shade(l, v, n)` for physical models, i.e. irradiance `E = π` at normal incidence,
//!   so that a white Lambert surface facing the light shows its albedo; `shade(l, v, n)` (the course
//!   formula as written, light colour 1) for classic models, which puts both kinds on one scale.
//! - The sky: radiance `ambient` from every direction reflects `ambient · ρ(θ_v)`, with `ρ` the
//!   model's directional albedo over the light ([`super::albedo::Over::Light`]) tabulated at 12 view
//!   cosines (a coarse rule, [`SKY_QUADRATURE`]) and interpolated linearly in `cos θ_v`; for classic
//!   models `ρ/π`, on the scale above.
//! - The tangent field (anisotropic models): `t = a × n` for a fixed axis `a` (default `+y`, vertical
//!   in the image): circles around `a`, as on a part turned on a lathe. Any field on a sphere vanishes
//!   somewhere (the hairy-ball theorem); this one vanishes only at `n = ±a`, which for an axis in the
//!   image plane are two points of the silhouette, where the sphere is seen edge-on. (A field circling
//!   the view axis, `(−y, x, 0)`, vanishes at the centre of the disc, in plain sight.)
//!
//! Pixels are `s × s` samples on a regular grid (box-filtered HDR; the background fills the samples
//! outside the disc).

use glam::{Vec3, Vec3A};

use super::albedo::{Over, hemispherical};
use super::{check_count, direction, eval_rows};
use crate::batch::Quantity;
use crate::properties::Quadrature;
use crate::{BrdfError, Model};

/// View cosines at which the sky term's directional albedo is tabulated (linear in between; held
/// below the first).
pub const SKY_COS: [f32; 12] = {
    let mut c = [0.0f32; 12];
    let mut k = 0;
    while k < 12 {
        // The last is 1 exactly (0.02 + 0.98 rounds above 1 in f32).
        c[k] = if k == 11 { 1.0 } else { 0.02 + 0.98 * k as f32 / 11.0 };
        k += 1;
    }
    c
};

/// Settings of [`lit_sphere`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereOptions {
    /// Image width and height in pixels (the sphere fills the square), `[8, 4096]`.
    pub size: usize,
    /// Direction toward the light in view space (`+x` right, `+y` up, `+z` toward the viewer);
    /// normalised. BRDF Explorer's incidence `(θ_i, φ)` is [`super::direction`]`(θ_i, φ)` here.
    pub light: Vec3,
    /// Radiance of the uniform sky (`≥ 0`; 0 turns it off).
    pub ambient: f32,
    /// Samples per pixel along each axis, `[1, 4]`.
    pub samples: usize,
    /// The axis `a` of the tangent field `t = a × n`; normalised.
    pub tangent_axis: Vec3,
    /// Linear RGB radiance outside the sphere.
    pub background: Vec3,
}

impl Default for SphereOptions {
    /// 512 pixels, light from the upper right in front (`(1, 1, 1)`), sky 0.05, 1 sample, axis `+y`,
    /// black background.
    fn default() -> Self {
        Self {
            size: 512,
            light: Vec3::ONE,
            ambient: 0.05,
            samples: 1,
            tangent_axis: Vec3::Y,
            background: Vec3::ZERO,
        }
    }
}

/// A rendered lit sphere; every buffer is `size × size`, row-major, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereImage {
    /// Width and height in pixels.
    pub size: usize,
    /// Linear RGB radiance (box-filtered over the samples; the background outside).
    pub hdr: Vec<Vec3>,
    /// Unit normal at the pixel centre; zero outside the disc.
    pub normal: Vec<Vec3>,
    /// `(1 − z)/2` of the sphere point at the pixel centre (0 at the front, ½ at the silhouette); 1
    /// outside.
    pub depth: Vec<f32>,
    /// Whether the pixel centre lies on the sphere.
    pub covered: Vec<bool>,
}

fn unit(name: &'static str, x: Vec3) -> Result<Vec3, BrdfError> {
    let u: Vec3 = crate::vector::normalize_or_zero(Vec3A::from(x)).into();
    if u == Vec3::ZERO {
        return Err(BrdfError::InvalidInput {
            name,
            problem: format!("must be finite and non-zero, got {x}"),
        });
    }
    Ok(u)
}

/// The tangent of the field `a × n` at `n` (zero where `n = ±a`; the model then picks a frame).
#[inline]
pub fn tangent_at(axis: Vec3, n: Vec3) -> Vec3 {
    axis.cross(n)
}

/// The quadrature of the sky term: 3 × 2 points per panel, panels down to 0.01 rad (about 2.5·10³
/// evaluations per view cosine, a sixth of the albedo view's). The sky is a faint fill light that shows
/// the unlit side: this rule integrates white Lambert to 2e-6 (the test below), and a sharp lobe less
/// well, which is invisible at an ambient of a few percent.
pub const SKY_QUADRATURE: Quadrature = Quadrature { theta_order: 3, phi_order: 2, min_panel: 1e-2 };

/// The sky term's `ρ(θ_v)` table at [`SKY_COS`], scaled for the model's kind.
fn sky_table(model: &Model) -> Result<Vec<Vec3>, BrdfError> {
    use rayon::prelude::*;
    let scale = if model.spec().physical { 1.0 } else { std::f32::consts::FRAC_1_PI };
    SKY_COS
        .par_iter()
        .map(|&c| {
            let v = direction(f64::from(c).min(1.0).acos(), 0.0);
            Ok(hemispherical(model, v, Over::Light, &SKY_QUADRATURE)? * scale)
        })
        .collect()
}

/// Linear interpolation of the table at `cos` (held outside `[SKY_COS[0], 1]`).
fn sky_at(table: &[Vec3], cos: f32) -> Vec3 {
    let step = SKY_COS[1] - SKY_COS[0];
    let u = ((cos - SKY_COS[0]) / step).clamp(0.0, (SKY_COS.len() - 1) as f32);
    let k = (u as usize).min(SKY_COS.len() - 2);
    let f = u - k as f32;
    table[k] * (1.0 - f) + table[k + 1] * f
}

/// Render the lit sphere of `model` (see the module docs).
pub fn lit_sphere(model: &Model, opts: &SphereOptions) -> Result<SphereImage, BrdfError> {
    let size = check_count("size", opts.size, 8, 4096)?;
    let s = check_count("samples", opts.samples, 1, 4)?;
    let light = unit("light", opts.light)?;
    let axis = unit("tangent_axis", opts.tangent_axis)?;
    if !(opts.ambient.is_finite() && opts.ambient >= 0.0) {
        return Err(BrdfError::InvalidInput {
            name: "ambient",
            problem: format!("must be a finite number >= 0, got {}", opts.ambient),
        });
    }
    if !opts.background.is_finite() || opts.background.min_element() < 0.0 {
        return Err(BrdfError::InvalidInput {
            name: "background",
            problem: format!("must be finite and >= 0, got {}", opts.background),
        });
    }
    // Every sample on the disc, in row-major order of the supersampled grid, with its pixel.
    let m = size * s;
    let anisotropic = model.spec().anisotropic;
    let coord = |k: usize, m: usize| ((k as f64 + 0.5) / m as f64 * 2.0 - 1.0) as f32;
    let (mut normals, mut tangents, mut pixel) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..m {
        let cy = -coord(y, m);
        for x in 0..m {
            let cx = coord(x, m);
            let r2 = cx * cx + cy * cy;
            if r2 < 1.0 {
                let n = Vec3::new(cx, cy, (1.0 - r2).sqrt());
                normals.push(n);
                if anisotropic {
                    tangents.push(tangent_at(axis, n));
                }
                pixel.push((y / s) * size + x / s);
            }
        }
    }
    if !anisotropic {
        tangents.push(Vec3::X); // ignored by isotropic models (eval_rows drops it)
    }
    let shade = eval_rows(model, &[light], &[Vec3::Z], &normals, &tangents, Quantity::Shade);
    let scale = if model.spec().physical { std::f32::consts::PI } else { 1.0 };
    let sky = if opts.ambient > 0.0 { Some(sky_table(model)?) } else { None };
    let px = size * size;
    // Box filter: every pixel starts as background in all its samples, and each sample on the disc
    // replaces its share.
    let share = 1.0 / (s * s) as f32;
    let mut hdr = vec![opts.background; px];
    for ((c, n), &p) in shade.iter().zip(&normals).zip(&pixel) {
        let mut c = super::sanitize(*c * scale);
        if let Some(t) = &sky {
            c += opts.ambient * sky_at(t, n.z);
        }
        hdr[p] += (c - opts.background) * share;
    }
    // The pixel-centre buffers (normal, depth, coverage).
    let (mut normal, mut depth, mut covered) = (vec![Vec3::ZERO; px], vec![1.0f32; px], vec![false; px]);
    for y in 0..size {
        let cy = -coord(y, size);
        for x in 0..size {
            let cx = coord(x, size);
            let r2 = cx * cx + cy * cy;
            if r2 < 1.0 {
                let z = (1.0 - r2).sqrt();
                let i = y * size + x;
                normal[i] = Vec3::new(cx, cy, z);
                depth[i] = (1.0 - z) / 2.0;
                covered[i] = true;
            }
        }
    }
    Ok(SphereImage { size, hdr, normal, depth, covered })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Lambert;

    #[test]
    fn a_white_lambert_sphere_shows_its_albedo_times_the_cosine_plus_the_sky() {
        let m = Model::from(Lambert::new(Vec3::splat(0.8)));
        let light = Vec3::new(0.3, 0.5, 1.0).normalize();
        let opts = SphereOptions { size: 64, light, ambient: 0.1, ..Default::default() };
        let img = lit_sphere(&m, &opts).unwrap();
        for i in (0..64 * 64).step_by(37) {
            if !img.covered[i] {
                assert_eq!(img.hdr[i], Vec3::ZERO);
                continue;
            }
            let n = img.normal[i];
            let want = 0.8 * n.dot(light).max(0.0) + 0.1 * 0.8;
            assert!((img.hdr[i].x - want).abs() < 2e-6, "{} vs {want}", img.hdr[i].x);
        }
        assert!(img.covered[32 * 64 + 32] && !img.covered[0]);
    }

    #[test]
    fn the_tangent_field_vanishes_only_on_the_silhouette() {
        // Over the disc the tangent has length sqrt(1 − (a·n)²) = sqrt(1 − n_y²) for a = +y: it is
        // zero only where |n_y| = 1, i.e. at the top and bottom of the silhouette.
        let m = 200;
        let mut smallest = f32::MAX;
        for y in 0..m {
            for x in 0..m {
                let (cx, cy) =
                    ((x as f32 + 0.5) / m as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / m as f32 * 2.0);
                let r2 = cx * cx + cy * cy;
                if r2 < 1.0 {
                    let n = Vec3::new(cx, cy, (1.0 - r2).sqrt());
                    let t = tangent_at(Vec3::Y, n);
                    assert!(t.dot(n).abs() < 1e-6);
                    if n.z > 0.2 {
                        smallest = smallest.min(t.length());
                    }
                }
            }
        }
        assert!(smallest > 0.19, "{smallest}");
    }

    #[test]
    fn bad_options_are_refused_by_name() {
        let m = Model::build("lambert", &[]).unwrap();
        for (opts, name) in [
            (SphereOptions { size: 4, ..Default::default() }, "size"),
            (SphereOptions { samples: 9, ..Default::default() }, "samples"),
            (SphereOptions { light: Vec3::ZERO, ..Default::default() }, "light"),
            (SphereOptions { ambient: f32::NAN, ..Default::default() }, "ambient"),
            (
                SphereOptions { tangent_axis: Vec3::splat(f32::INFINITY), ..Default::default() },
                "tangent_axis",
            ),
        ] {
            let e = lit_sphere(&m, &opts).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }
}
