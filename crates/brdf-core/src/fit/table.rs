//! Samples drawn from a [`Tabulated`] table for a fit ([`super::fit_model`] fits samples, not tables):
//! `count` pairs of directions by a stated strategy, each with the table's interpolated value.
//!
//! - [`Strategy::Cosine`] (the default): `l` and `v` independent, each cosine-distributed over the
//!   hemisphere cut at `θ < max_theta` (drawn exactly: `sin²θ` uniform on `[0, sin²θ_max]`, `φ` uniform),
//!   the distribution of directions that light a surface (Ngan, Durand & Matusik 2005 fit MERL data with
//!   the same grazing cut-off, 80°, where the measurements are least reliable).
//! - [`Strategy::HalfDiff`]: uniform in the table's own index coordinates `(√(θ_h/(π/2)), θ_d/(π/2),
//!   φ_d/π)`, i.e. as densely near the specular peak as the MERL grid (Matusik et al. 2003), keeping the
//!   pairs with both directions within the cut-off: better for sharp lobes, which cosine-distributed
//!   pairs hit rarely.
//!
//! Both are deterministic in `seed` (SplitMix64, Steele, Lea & Flood 2014).
//!
//! An [`AnisotropicTabulated`] table is sampled by the same strategies ([`aniso_table_samples`]), in
//! its own frame: normal `+z`, tangent `+x`. The half/difference strategy's random turn about the
//! normal is then a uniform `φ_h`, so the pairs cover every orientation of the lobe.

use std::f32::consts::{FRAC_PI_2, PI};

use glam::Vec3;

use super::Sample;
use crate::BrdfError;
use crate::Geometry;
use crate::measured::{AnisotropicTabulated, Tabulated, directions_from_half_diff};

/// How [`table_samples`] draws directions (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// `l`, `v` each cosine-distributed below the cut-off.
    Cosine,
    /// Uniform in the table's index coordinates, below the cut-off.
    HalfDiff,
}

impl Strategy {
    /// The strategy of a name (`"cosine"`, `"half_diff"`); an error naming `strategy` otherwise.
    pub fn from_name(name: &str) -> Result<Self, BrdfError> {
        match name {
            "cosine" => Ok(Self::Cosine),
            "half_diff" => Ok(Self::HalfDiff),
            _ => Err(BrdfError::InvalidInput {
                name: "strategy",
                problem: format!("expected \"cosine\" or \"half_diff\", got {name:?}"),
            }),
        }
    }
}

/// What [`table_samples`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableSampling {
    /// Number of samples, 16 to 10⁷.
    pub count: usize,
    /// Seed of the generator.
    pub seed: u64,
    /// Grazing cut-off \[degrees\] for both directions, in (0, 90].
    pub max_theta_deg: f32,
    /// How directions are drawn.
    pub strategy: Strategy,
}

impl Default for TableSampling {
    fn default() -> Self {
        Self { count: 20_000, seed: 0, max_theta_deg: 80.0, strategy: Strategy::Cosine }
    }
}

/// SplitMix64 (G. L. Steele, D. Lea, C. H. Flood, "Fast Splittable Pseudorandom Number Generators",
/// OOPSLA 2014): a small deterministic generator.
pub(crate) struct SplitMix(pub u64);

impl SplitMix {
    /// A uniform number in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A cosine-distributed direction about `+z` with `θ < θ_max` (`s2max = sin²θ_max`).
fn cosine_dir(rng: &mut SplitMix, s2max: f64) -> Vec3 {
    let s2 = rng.next_f64() * s2max;
    let phi = std::f64::consts::TAU * rng.next_f64();
    let s = s2.sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, (1.0 - s2).sqrt() as f32)
}

/// `count` samples of `table` (normal `+z`) by `how` (see the module docs).
pub fn table_samples(table: &Tabulated, how: &TableSampling) -> Result<Vec<Sample>, BrdfError> {
    draw(how, None, |g| table.eval(g))
}

/// `count` samples of an anisotropic `table` by `how` (see the module docs), with normal `+z` and the
/// table's tangent `+x` (pass it to the fit: [`super::FitOptions::tangents`]).
pub fn aniso_table_samples(
    table: &AnisotropicTabulated,
    how: &TableSampling,
) -> Result<Vec<Sample>, BrdfError> {
    draw(how, Some(Vec3::X), |g| table.eval(g))
}

fn draw(
    how: &TableSampling,
    tangent: Option<Vec3>,
    value: impl Fn(&Geometry) -> Vec3,
) -> Result<Vec<Sample>, BrdfError> {
    if !(16..=10_000_000).contains(&how.count) {
        return Err(BrdfError::InvalidInput {
            name: "samples",
            problem: format!("must be in [16, 10000000], got {}", how.count),
        });
    }
    let t = how.max_theta_deg;
    if !(t.is_finite() && t > 0.0 && t <= 90.0) {
        return Err(BrdfError::InvalidInput {
            name: "max_theta",
            problem: format!("must be in (0, 90] degrees, got {t}"),
        });
    }
    let cos_max = t.to_radians().cos();
    let s2max = f64::from(t.to_radians().sin()).powi(2);
    let mut rng = SplitMix(how.seed ^ 0x5DEE_CE66_D1CE_4E5B);
    let mut out = Vec::with_capacity(how.count);
    let mut tries = 0usize;
    while out.len() < how.count {
        tries += 1;
        if tries > 1000 * how.count {
            return Err(BrdfError::InvalidInput {
                name: "max_theta",
                problem: format!("{t} degrees leaves too few pairs of directions to draw from"),
            });
        }
        let (l, v) = match how.strategy {
            Strategy::Cosine => (cosine_dir(&mut rng, s2max), cosine_dir(&mut rng, s2max)),
            Strategy::HalfDiff => {
                let uh = rng.next_f64() as f32;
                let th = uh * uh * FRAC_PI_2;
                let td = rng.next_f64() as f32 * FRAC_PI_2;
                let pd = rng.next_f64() as f32 * PI;
                // Turn the pair about the normal by a random azimuth (isotropy: the value is the same).
                let (l, v) = directions_from_half_diff(th, td, pd);
                let a = std::f32::consts::TAU * rng.next_f64() as f32;
                let rot = glam::Quat::from_rotation_z(a);
                (rot * Vec3::from(l), rot * Vec3::from(v))
            }
        };
        if l.z <= cos_max || v.z <= cos_max {
            continue;
        }
        let Some(g) = Geometry::new(l, v, Vec3::Z, tangent) else { continue };
        out.push(Sample { l, v, n: Vec3::Z, f: value(&g) });
    }
    Ok(out)
}
