//! Lobe selection for sums and mixtures, and the [`Sampler`] every model's sampling goes through.
//!
//! A model is a sum of lobes (`kd/π + ks·spec`, two microfacet lobes, Lafortune's lobes); its sampler
//! lists one [`Technique`] per lobe with a weight, the lobe's *estimated albedo* `wᵢ(v)`. A sample
//! picks lobe `i` with probability `wᵢ/Σw` (the first random number), draws a direction from its
//! technique (the other two), and reports the density of the whole mixture,
//!
//! ```text
//! p(l) = Σᵢ wᵢ(v) pᵢ(l) / Σᵢ wᵢ(v),      weight = f(l, v) cos θ_l / p(l),
//! ```
//!
//! which is Veach's one-sample model with the balance heuristic (Veach 1997, "Robust Monte Carlo
//! Methods for Light Transport Simulation", §9.2.4; pbrt-v3's `BSDF::Sample_f` over matching BxDFs):
//! unbiased whenever `p > 0` wherever `f cos > 0`, and close to `f cos` when the weights are close to
//! the lobes' albedos. The weights are estimates (documented per model): a lobe's constant part, times
//! the mean over RGB of a tint times a Fresnel term at `n·v` where the model has one (floored at 1 % of
//! the tint so a lobe with `F(1) = 0` keeps some samples), times a view-dependent scale of the
//! technique (Lafortune's `|C ∘ v|ⁿ`). Where every weight is 0 the lobes are chosen with equal
//! probability, so a sampler always covers its lobes.
//!
//! Directions are drawn in the shading frame of `n` (and the tangent, exactly the frame anisotropic
//! models evaluate in), and the weight is `shade(l, v)/p(l)` computed from the returned `l` exactly as
//! [`crate::Model::shade`] and [`Sampler::pdf`] compute them: `weight` equals
//! `shade(l, v, n)/pdf(l, v, n)` bit for bit. `shade = f·max(n·l, 0)` for physical models; for a classic
//! model its course formula, whose integral over the hemisphere is what
//! [`crate::properties::directional_albedo`] reports.
//!
//! **Failures.** Where `v` is zero, non-finite or not above the surface (`n·v ≤ 0`), and where the
//! drawn direction is not above the surface (a glossy lobe near grazing, a reflected half vector
//! facing away), the sample has `pdf = 0` and `weight = 0` — never NaN. `l` is the zero vector in the
//! first case and the drawn (unit) direction in the second. Such samples carry the part of the
//! sampler's probability that the hemisphere's density does not: `∫ p dω = 1 − P(failure)`.

use std::sync::Arc;

use glam::Vec3;

use super::frame::LaneFrame;
use super::{ashikhmin_shirley, beckmann, cosine, cosine_power, ggx, tabulated::TabulatedSampler, ward};
use crate::BrdfError;
use crate::fresnel::Fresnel;
use crate::microfacet::Distribution;
use crate::models::{Bxdf, shade_model_lanes};
use crate::simd::{Lane, LaneGeometry, V3};

/// Most lobes a [`Sampler`] holds (weights live on the stack).
pub const MAX_LOBES: usize = 16;

/// One sampling technique (one file of [`crate::sampling`] each). Each draws a direction in the local
/// frame (z = normal) from two uniform numbers and knows the density [1/sr] of what it draws.
#[derive(Debug, Clone, PartialEq)]
pub enum Technique {
    /// Cosine-weighted hemisphere ([`cosine`]).
    Cosine,
    /// Uniform hemisphere ([`cosine::sample_uniform`]).
    UniformHemisphere,
    /// `cosⁿ` about `normalize(C ∘ v)` ([`cosine_power::lobe_sample`]); `C = (−1, −1, 1)` is Phong's
    /// mirror lobe ([`Technique::phong`]).
    CosineLobe {
        /// Lafortune's `(Cx, Cy, Cz)`.
        c: [f32; 3],
        /// Exponent n ≥ 0.
        exponent: f32,
    },
    /// Half vector `∝ (n·h)ⁿ`, reflected ([`cosine_power::half_sample`]).
    HalfVectorPower {
        /// Exponent n ≥ 0.
        exponent: f32,
    },
    /// GGX visible normals, reflected ([`ggx`]).
    GgxVisible {
        /// Roughness along the tangent.
        alpha_x: f32,
        /// Roughness along the bitangent.
        alpha_y: f32,
    },
    /// Beckmann visible normals, reflected ([`beckmann`]).
    BeckmannVisible {
        /// RMS slope along the tangent.
        alpha_x: f32,
        /// RMS slope along the bitangent.
        alpha_y: f32,
    },
    /// Ward's Gaussian half vectors, reflected ([`ward`]).
    WardHalfVector {
        /// RMS slope along the tangent.
        alpha_x: f32,
        /// RMS slope along the bitangent.
        alpha_y: f32,
    },
    /// Ashikhmin–Shirley half vectors, reflected ([`ashikhmin_shirley`]).
    AshikhminShirley {
        /// Exponent along the tangent.
        nu: f32,
        /// Exponent along the bitangent.
        nv: f32,
    },
    /// A measured table's per-view distribution ([`super::tabulated`]).
    Tabulated(Arc<TabulatedSampler>),
}

impl Technique {
    /// Phong's lobe `(r·v)ⁿ` about the mirror direction of `v`.
    pub fn phong(exponent: f32) -> Self {
        Technique::CosineLobe { c: [-1.0, -1.0, 1.0], exponent }
    }

    /// The technique that samples `D(h) cos θ_h`-like half vectors of a microfacet distribution:
    /// visible normals for GGX and Beckmann (and Ward's `D`, which is Beckmann's; and the Gaussian,
    /// through the Beckmann distribution of the same RMS slope, Walter et al. 2007 §5.2 — not
    /// identical, so only variance differs), `(n·h)^{m+1}` for Blinn–Phong, Ashikhmin–Shirley's
    /// sampler with exponents raised by one for theirs (both then draw exactly `D cos θ_h`).
    pub fn for_distribution(d: &Distribution) -> Self {
        match *d {
            Distribution::Ggx { alpha_x, alpha_y } => Technique::GgxVisible { alpha_x, alpha_y },
            Distribution::Beckmann { alpha_x, alpha_y } | Distribution::Ward { alpha_x, alpha_y } => {
                Technique::BeckmannVisible { alpha_x, alpha_y }
            }
            Distribution::Gaussian(g) => Technique::BeckmannVisible { alpha_x: g.m, alpha_y: g.m },
            Distribution::BlinnPhong { exponent } => Technique::HalfVectorPower { exponent: exponent + 1.0 },
            Distribution::AshikhminShirley { nu, nv } => {
                Technique::AshikhminShirley { nu: nu + 1.0, nv: nv + 1.0 }
            }
        }
    }

    /// A local direction for the local view `v` from `(u1, u2) ∈ [0, 1)²`.
    #[inline(always)]
    pub fn sample<F: Lane>(&self, v: V3<F>, u1: F, u2: F) -> V3<F> {
        match self {
            Technique::Cosine => cosine::sample(u1, u2),
            Technique::UniformHemisphere => cosine::sample_uniform(u1, u2),
            Technique::CosineLobe { c, exponent } => cosine_power::lobe_sample(*c, *exponent, v, u1, u2),
            Technique::HalfVectorPower { exponent } => cosine_power::half_sample(*exponent, v, u1, u2),
            Technique::GgxVisible { alpha_x, alpha_y } => ggx::sample(*alpha_x, *alpha_y, v, u1, u2),
            Technique::BeckmannVisible { alpha_x, alpha_y } => {
                beckmann::sample(*alpha_x, *alpha_y, v, u1, u2)
            }
            Technique::WardHalfVector { alpha_x, alpha_y } => ward::sample(*alpha_x, *alpha_y, v, u1, u2),
            Technique::AshikhminShirley { nu, nv } => ashikhmin_shirley::sample(*nu, *nv, v, u1, u2),
            Technique::Tabulated(t) => t.sample(v, u1, u2),
        }
    }

    /// The density [1/sr] of [`Technique::sample`] at the local unit direction `l` (meaningful where
    /// `v_z > 0` and `l_z > 0`).
    #[inline(always)]
    pub fn pdf<F: Lane>(&self, v: V3<F>, l: V3<F>) -> F {
        match self {
            Technique::Cosine => cosine::pdf(l),
            Technique::UniformHemisphere => cosine::pdf_uniform(l),
            Technique::CosineLobe { c, exponent } => cosine_power::lobe_pdf(*c, *exponent, v, l),
            Technique::HalfVectorPower { exponent } => cosine_power::half_pdf(*exponent, v, l),
            Technique::GgxVisible { alpha_x, alpha_y } => ggx::pdf(*alpha_x, *alpha_y, v, l),
            Technique::BeckmannVisible { alpha_x, alpha_y } => beckmann::pdf(*alpha_x, *alpha_y, v, l),
            Technique::WardHalfVector { alpha_x, alpha_y } => ward::pdf(*alpha_x, *alpha_y, v, l),
            Technique::AshikhminShirley { nu, nv } => ashikhmin_shirley::pdf(*nu, *nv, v, l),
            Technique::Tabulated(t) => t.pdf(v, l),
        }
    }

    /// The view-dependent factor of the lobe's weight: `|C ∘ v|ⁿ` for a cosine lobe, else 1.
    #[inline(always)]
    fn scale<F: Lane>(&self, v: V3<F>) -> F {
        match self {
            Technique::CosineLobe { c, exponent } => cosine_power::lobe_scale(*c, *exponent, v),
            _ => F::splat(1.0),
        }
    }
}

/// One lobe of a [`Sampler`]: a technique and its estimated albedo (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Lobe {
    /// How directions are drawn.
    pub technique: Technique,
    /// The constant part of the weight (≥ 0).
    pub weight: f32,
    /// A tint and Fresnel term whose mean over RGB at `n·v` multiplies the weight.
    pub fresnel: Option<(Vec3, Fresnel)>,
}

/// The sampling plan of a model: its lobes (module docs). Build it once ([`crate::Model::sampler`])
/// and use it for any number of samples.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Sampler {
    lobes: Vec<Lobe>,
}

/// Samples drawn on lanes: unit direction toward the light, `f·cos/p` per RGB channel, density \[1/sr\].
#[derive(Debug, Clone, Copy)]
pub struct Sample<F: Lane> {
    /// Drawn direction (world space, unit; zero where `v` was unusable).
    pub l: V3<F>,
    /// `shade(l, v)/pdf` per channel (0 where `pdf = 0`).
    pub weight: V3<F>,
    /// Solid-angle density of `l` \[1/sr\] (0 for a failed sample).
    pub pdf: F,
}

/// One sample: what [`Sample`] holds for one lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// Drawn direction (world space, unit; zero where `v` was unusable).
    pub l: Vec3,
    /// `shade(l, v)/pdf` per channel (0 where `pdf = 0`).
    pub weight: Vec3,
    /// Solid-angle density of `l` \[1/sr\] (0 for a failed sample).
    pub pdf: f32,
}

impl<F: Lane> Sample<F> {
    /// Lane `i`.
    #[inline]
    pub fn lane(&self, i: usize) -> BsdfSample {
        BsdfSample { l: self.l.lane(i), weight: self.weight.lane(i), pdf: self.pdf.lane(i) }
    }
}

/// `mean(rgb)`, the channel average a lobe's weight uses.
#[inline]
pub fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Largest `u` used: the largest `f32` below 1.
const ONE_MINUS: f32 = 1.0 - f32::EPSILON / 2.0;

/// The view in the shading frame.
struct Local<F: Lane> {
    frame: LaneFrame<F>,
    v: V3<F>,
    /// `v` and `n` usable and `n·v > 0`.
    valid: F::Mask,
}

impl<F: Lane> Local<F> {
    /// Normalise as [`LaneGeometry::new`] does and build the frame of [`crate::Geometry::frame`].
    #[inline(always)]
    fn new(v: V3<F>, n: V3<F>, tangent: Option<V3<F>>) -> Self {
        let (v, ok_v) = v.normalize_or_zero();
        let (n, ok_n) = n.normalize_or_zero();
        let (tangent, tangent_ok) = match tangent.map(V3::normalize_or_zero) {
            Some((t, ok)) => (Some(t), ok),
            None => (None, F::mask_splat(false)),
        };
        let frame = LaneFrame::new(n, tangent, tangent_ok);
        let vl = frame.to_local(v);
        Self { frame, v: vl, valid: ok_v & ok_n & vl.z.gt(F::splat(0.0)) }
    }
}

impl Sampler {
    /// No lobes yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a lobe drawn by `technique` with estimated albedo `weight` (negative or non-finite → 0).
    pub fn with(mut self, technique: Technique, weight: f32) -> Self {
        let weight = if weight.is_finite() { weight.max(0.0) } else { 0.0 };
        self.lobes.push(Lobe { technique, weight, fresnel: None });
        self
    }

    /// Add a lobe whose weight is `weight · max(mean(tint ∘ F(n·v)), 0.01 mean(tint))`.
    pub fn with_fresnel(self, technique: Technique, weight: f32, tint: Vec3, fresnel: Fresnel) -> Self {
        let mut s = self.with(technique, weight);
        if let Some(l) = s.lobes.last_mut() {
            l.fresnel = Some((tint, fresnel));
        }
        s
    }

    /// The lobes, in the order they were added.
    pub fn lobes(&self) -> &[Lobe] {
        &self.lobes
    }

    /// Refuse an empty sampler or one with more than [`MAX_LOBES`] lobes (naming `model`).
    pub fn check(self, model: &str) -> Result<Self, BrdfError> {
        if self.lobes.is_empty() || self.lobes.len() > MAX_LOBES {
            return Err(BrdfError::InvalidInput {
                name: "model",
                problem: format!(
                    "{model}: a sampler needs 1 to {MAX_LOBES} lobes, this one has {}",
                    self.lobes.len()
                ),
            });
        }
        Ok(self)
    }

    /// Every lobe's selection weight (its estimated albedo) at the local unit view `v` (z = normal), and
    /// their sum, as [`Sampler::sample`] selects lobes: what a renderer that treats lobes separately
    /// (a prefiltered environment for each) splits a material's reflectance by.
    #[inline]
    pub fn lobe_weights(&self, v: Vec3) -> ([f32; MAX_LOBES], f32) {
        self.weights::<f32>(V3::splat(v))
    }

    /// Every lobe's weight at the local view `v`, and their sum (equal weights where the sum is 0).
    #[inline(always)]
    fn weights<F: Lane>(&self, v: V3<F>) -> ([F; MAX_LOBES], F) {
        let zero = F::splat(0.0);
        let mut w = [zero; MAX_LOBES];
        let mut total = zero;
        for (wi, lobe) in w.iter_mut().zip(&self.lobes) {
            let mut x = F::splat(lobe.weight) * lobe.technique.scale(v);
            if let Some((tint, fresnel)) = &lobe.fresnel {
                let f = fresnel.eval_lanes(v.z) * V3::splat(*tint);
                let m = (f.x + f.y + f.z) / F::splat(3.0);
                x = x * m.max(F::splat(0.01 * mean(*tint)));
            }
            // NaN → 0 and a cap, so that sums stay finite.
            *wi = F::select(x.gt(zero), x.min(F::splat(1e30)), zero);
            total = total + *wi;
        }
        let none = !total.gt(zero);
        if F::mask_all(!none) {
            return (w, total);
        }
        let one = F::splat(1.0);
        for wi in w.iter_mut().take(self.lobes.len()) {
            *wi = F::select(none, one, *wi);
        }
        (w, F::select(none, F::splat(self.lobes.len() as f32), total))
    }

    /// The mixture density at the world direction `l` (normalised here) for the frame and weights of
    /// `local`.
    #[inline(always)]
    fn pdf_local<F: Lane>(&self, local: &Local<F>, w: &[F; MAX_LOBES], total: F, l: V3<F>) -> F {
        let zero = F::splat(0.0);
        let (l, ok) = l.normalize_or_zero();
        let ll = local.frame.to_local(l);
        let mut sum = zero;
        for (lobe, &wi) in self.lobes.iter().zip(w) {
            let p = lobe.technique.pdf(local.v, ll);
            sum = sum + F::select(wi.gt(zero), wi * p, zero);
        }
        let p = sum / total;
        F::select(local.valid & ok & ll.z.gt(zero) & p.is_finite() & p.gt(zero), p, zero)
    }

    /// The solid-angle density \[1/sr\] with which [`Sampler::sample_lanes`] draws the world direction
    /// `l` for view `v`, normal `n` and optional tangent (none of them need be unit). 0 where `l` or
    /// `v` is not above the surface or is degenerate.
    #[inline(always)]
    pub fn pdf_lanes<F: Lane>(&self, l: V3<F>, v: V3<F>, n: V3<F>, tangent: Option<V3<F>>) -> F {
        let local = Local::new(v, n, tangent);
        let (w, total) = self.weights(local.v);
        self.pdf_local(&local, &w, total, l)
    }

    /// Draw `l` for view `v`, normal `n` and optional tangent (none need be unit) from
    /// `u ∈ [0, 1)³` (`u[0]` picks the lobe, `u[1]`, `u[2]` the direction; values outside are clamped),
    /// and weigh it by `m`'s `shade(l, v)/p(l)` (module docs). `m` must be the model the sampler was
    /// built for.
    #[inline(always)]
    pub fn sample_lanes<M: Bxdf, F: Lane>(
        &self,
        m: &M,
        v: V3<F>,
        n: V3<F>,
        tangent: Option<V3<F>>,
        u: [F; 3],
    ) -> Sample<F> {
        let zero = F::splat(0.0);
        let local = Local::new(v, n, tangent);
        let (w, total) = self.weights(local.v);
        let clamp = |x: F| F::select(x.ge(zero), x.min(F::splat(ONE_MINUS)), zero);
        let (u0, u1, u2) = (clamp(u[0]), clamp(u[1]), clamp(u[2]));
        // Lobe i where the cumulative weight first exceeds u0·Σw; rounding leftovers (u0·Σw rounded up
        // to Σw) go to the last lobe of positive weight.
        let x = u0 * total;
        let k = self.lobes.len();
        let mut chosen = [F::mask_splat(false); MAX_LOBES];
        let mut taken = F::mask_splat(false);
        let mut cumulative = zero;
        for i in 0..k {
            cumulative = cumulative + w[i];
            chosen[i] = !taken & w[i].gt(zero) & x.lt(cumulative);
            taken = taken | chosen[i];
        }
        for i in (0..k).rev() {
            let left = !taken & w[i].gt(zero);
            chosen[i] = chosen[i] | left;
            taken = taken | left;
        }
        let mut ll = V3 { x: zero, y: zero, z: F::splat(1.0) };
        for (lobe, &c) in self.lobes.iter().zip(&chosen) {
            let c = c & local.valid;
            if F::mask_all(!c) {
                continue; // no lane drew this lobe: its directions would all be discarded.
            }
            ll = V3::select(c, lobe.technique.sample(local.v, u1, u2), ll);
        }
        let (l, _) = local.frame.from_local(ll).normalize_or_zero();
        let l = V3::select(local.valid, l, V3::splat(Vec3::ZERO));
        let pdf = self.pdf_local(&local, &w, total, l);
        let (g, ok) = LaneGeometry::new(l, v, n, tangent);
        let value = shade_model_lanes(m, &g, ok);
        let weight = value / pdf;
        let good = pdf.gt(zero) & weight.is_finite();
        Sample { l, weight: V3::select(good, weight, V3::splat(Vec3::ZERO)), pdf }
    }

    /// [`Sampler::sample_lanes`] for one sample.
    pub fn sample<M: Bxdf>(&self, m: &M, v: Vec3, n: Vec3, tangent: Option<Vec3>, u: [f32; 3]) -> BsdfSample {
        let s = self.sample_lanes::<M, f32>(m, V3::splat(v), V3::splat(n), tangent.map(V3::splat), u);
        s.lane(0)
    }

    /// [`Sampler::pdf_lanes`] for one direction.
    pub fn pdf(&self, l: Vec3, v: Vec3, n: Vec3, tangent: Option<Vec3>) -> f32 {
        self.pdf_lanes::<f32>(V3::splat(l), V3::splat(v), V3::splat(n), tangent.map(V3::splat))
    }
}
