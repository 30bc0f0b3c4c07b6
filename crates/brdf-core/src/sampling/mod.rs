//! Importance sampling: every model can draw directions `l` in proportion to (roughly) its reflected
//! radiance `f·cos θ_l` and report the density it draws them with, so that a Monte Carlo integrator
//! can estimate `∫ f(l, v) cos θ_l L(l) dω_l` as the mean of `weight · L(l)`. This completes the
//! method set of pbrt-v4's BxDFs (Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed.,
//! §9.1): value (`eval`), `sample` and `pdf`.
//!
//! ```text
//! sample(v, n, u) → (l, weight = f(l, v)·cos θ_l / p(l), p(l))      pdf(l, v, n) → p(l)  [1/sr]
//! ```
//!
//! Conventions are those of evaluation: directions point away from the surface, in world space, with
//! an optional tangent that fixes the frame of anisotropic models; `p` is a density over solid angle;
//! physical models sample and weigh only `n·v > 0`, `n·l > 0`. See [`mixture`] for how lobes are
//! combined, what a failed sample looks like (`pdf = weight = 0`, never NaN) and the exact relation
//! `weight = shade/pdf`.
//!
//! ## Where each technique lives (one file each)
//! | file | technique | models |
//! |---|---|---|
//! | [`cosine`] | cosine-weighted hemisphere (Malley; Shirley–Chiu concentric map); uniform hemisphere | Lambert, Oren–Nayar, every `kd` term; toon |
//! | [`cosine_power`] | `cosⁿ` lobes about `C ∘ v`; half vectors `∝ (n·h)ⁿ` | Phong, Strauss, Lafortune; Blinn–Phong |
//! | [`ggx`] | GGX visible normals (Heitz 2018), (an)isotropic | Cook–Torrance `ggx` |
//! | [`beckmann`] | Beckmann visible normals (Heitz & d'Eon 2014, Jakob 2014) | Cook–Torrance `beckmann`, `gaussian` |
//! | [`ward`] | Ward's Gaussian half vectors (Ward 1992, Walter 2005) | Ward |
//! | [`ashikhmin_shirley`] | Ashikhmin & Shirley 2000's half vectors | Ashikhmin–Shirley |
//! | [`tabulated`] | per-view tabulated distribution + defensive cosine | measured tables |
//! | [`mixture`] | lobe selection by estimated albedo; the [`Sampler`] | all |
//! | [`distribution`] | piecewise-constant 1-D/2-D distributions (pbrt-v4 §A.4) | tables, environment maps |
//! | [`rng`] | counter-based uniform numbers keyed by (seed, row) | batches |
//! | [`batch`] | slices in, slices out, eight lanes at a time | the Python binding |
//! | [`chi2`] | Pearson's χ² test of a sampler against its pdf | tests, `brdfpy.checks.chi2` |
//!
//! Every technique is written once over [`Lane`] (one sample = `f32`, eight = a SIMD register, same
//! bits); per-lane iterations (Beckmann's inversion) and table look-ups run each lane on its own
//! values, so a lane's result never depends on its neighbours.
//!
//! ## Use
//! ```
//! use brdf_core::Model;
//! use glam::Vec3;
//! let m = Model::build("cook_torrance", &[]).unwrap();
//! let sampler = m.sampler().unwrap(); // once per material
//! let (v, n) = (Vec3::new(0.3, 0.0, 1.0), Vec3::Z);
//! let s = m.sample_with(&sampler, v, n, None, [0.3, 0.6, 0.1]);
//! assert!(s.pdf > 0.0);
//! // weight = shade/pdf, bit for bit:
//! let g = brdf_core::Geometry::new(s.l, v, n, None).unwrap();
//! assert_eq!(s.weight, m.shade(&g) / sampler.pdf(s.l, v, n, None));
//! ```
//! On lanes, [`Model::sample_lanes`] draws eight at once; a renderer draws `u` from its own sampler or
//! from [`rng`].

/// Most samples drawn in one call (2²⁶, about 2.4 GB of directions, weights and densities): a clean
/// refusal instead of an allocation that fails (a count of 2³² aborted the process).
pub const MAX_SAMPLES: i64 = 1 << 26;

pub mod ashikhmin_shirley;
pub mod batch;
pub mod beckmann;
pub mod chi2;
pub mod cosine;
pub mod cosine_power;
pub mod distribution;
pub mod frame;
pub mod ggx;
pub mod mixture;
pub mod rng;
pub mod tabulated;
pub mod ward;

use glam::Vec3;

pub use distribution::{Distribution1D, Distribution2D};
pub use frame::LaneFrame;
pub use mixture::{BsdfSample, Lobe, MAX_LOBES, Sample, Sampler, Technique, mean};

use crate::models::{Bxdf, ModelVisitor};
use crate::simd::{Lane, V3};
use crate::{BrdfError, Model};

/// `−x` as an exact sign flip on every lane type (`x · −1`). Unary minus is not used in the
/// techniques: `wide`'s `f32x8` negates as `0 − x`, which gives +0 for +0 where `f32` gives −0, and
/// the scalar and lane instantiations of a formula must give the same bits.
#[inline(always)]
pub(crate) fn neg<F: Lane>(x: F) -> F {
    x * F::splat(-1.0)
}

struct SamplerOf;

impl ModelVisitor for SamplerOf {
    type Output = Result<Sampler, BrdfError>;
    fn visit<M: Bxdf>(self, m: &M) -> Self::Output {
        m.sampler()?.check(M::SPEC.name)
    }
}

struct SampleWith<'a, F: Lane> {
    sampler: &'a Sampler,
    v: V3<F>,
    n: V3<F>,
    tangent: Option<V3<F>>,
    u: [F; 3],
}

impl<F: Lane> ModelVisitor for SampleWith<'_, F> {
    type Output = Sample<F>;
    fn visit<M: Bxdf>(self, m: &M) -> Sample<F> {
        self.sampler.sample_lanes(m, self.v, self.n, self.tangent, self.u)
    }
}

impl Model {
    /// The model's sampling plan ([`Bxdf::sampler`]): build it once, then draw with
    /// [`Model::sample_lanes`] / [`Model::sample_with`] and evaluate densities with [`Sampler::pdf`].
    /// Errors for a model that has no sampler.
    pub fn sampler(&self) -> Result<Sampler, BrdfError> {
        self.visit(SamplerOf)
    }

    /// Draw `F::LANES` directions with `sampler` (which must be this model's [`Model::sampler`]); see
    /// [`Sampler::sample_lanes`].
    #[inline]
    pub fn sample_lanes<F: Lane>(
        &self,
        sampler: &Sampler,
        v: V3<F>,
        n: V3<F>,
        tangent: Option<V3<F>>,
        u: [F; 3],
    ) -> Sample<F> {
        self.visit(SampleWith { sampler, v, n, tangent, u })
    }

    /// [`Model::sample_lanes`] for one sample.
    pub fn sample_with(
        &self,
        sampler: &Sampler,
        v: Vec3,
        n: Vec3,
        tangent: Option<Vec3>,
        u: [f32; 3],
    ) -> BsdfSample {
        self.sample_lanes::<f32>(sampler, V3::splat(v), V3::splat(n), tangent.map(V3::splat), u).lane(0)
    }

    /// One sample, building the sampler first (for many samples build it once with
    /// [`Model::sampler`]).
    pub fn sample(
        &self,
        v: Vec3,
        n: Vec3,
        tangent: Option<Vec3>,
        u: [f32; 3],
    ) -> Result<BsdfSample, BrdfError> {
        Ok(self.sample_with(&self.sampler()?, v, n, tangent, u))
    }

    /// The density \[1/sr\] with which [`Model::sample`] draws `l` (building the sampler first).
    pub fn pdf(&self, l: Vec3, v: Vec3, n: Vec3, tangent: Option<Vec3>) -> Result<f32, BrdfError> {
        Ok(self.sampler()?.pdf(l, v, n, tangent))
    }
}

#[cfg(test)]
mod tests;
