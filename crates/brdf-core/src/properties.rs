//! BRDF properties as checks a user can run on any [`Model`] (Pharr, Jakob, Humphreys, *Physically Based
//! Rendering*, 4th ed., §4.3.1):
//! positivity, Helmholtz reciprocity, energy conservation through the directional albedo, and the
//! normalisation of a microfacet distribution.
//!
//! Everything here is deterministic: random directions come from a seeded [`SplitMix64`], and the
//! quadrature sums its parallel partial results in a fixed order, so results are the same bits for any
//! number of threads.
//!
//! ## The quadrature ([`Quadrature`])
//! Hemispherical integrals `∫ g(ω) dω = ∫₀^{2π} ∫₀^{π/2} g(θ, φ) sin θ dθ dφ` are computed with a
//! tensor product of composite Gauss–Legendre rules in θ and in φ whose panels shrink geometrically
//! (halving) toward the places where a lobe can be sharp:
//! - in θ toward the polar angle of the peak (for a directional albedo: `θ_v`, which is the polar
//!   angle of both the mirror and the retro-reflection direction), down to panels of width
//!   [`Quadrature::min_panel`];
//! - in φ toward the azimuth of the mirror direction `φ_v + π` and of the retro direction `φ_v`, with
//!   panel breaks at `φ_v ± π/2` (where Oren-Nayar's `max(0, cos Δφ)` has its kink).
//!
//! Panel edges therefore sit on every kink the registered models have in the interior of the domain
//! (`θ_l = θ_v`, `Δφ = ±π/2`), and a lobe of angular width `w` is covered by panels no wider than it,
//! down to `w ≈ 2·min_panel`. With the defaults (8 × 8 points per panel, `min_panel = 1e-4` rad, at
//! most 224 × 448 ≈ 10⁵ evaluations per direction) the errors measured by tests/properties.rs are:
//! - white Lambert: `|ρ − 1| < 1e-6` at every view angle;
//! - normalised Phong / exact-normalised Blinn-Phong lobes of exponent ≤ 1000 against their closed
//!   forms (`ks` at normal incidence, `cos θ_v` for an unclipped Phong lobe at θ_v = 60°): < 1e-5;
//! - exponent 10⁴: ~1e-4, limited by evaluating `x^γ` in f32 (as the models do), not by the quadrature
//!   — doubling the order and refining panels to 1e-6 rad moves the result by < 1e-5;
//! - Oren-Nayar, Phong, Blinn-Phong at moderate exponents: unchanged to < 2e-6 by that refinement;
//! - `∫ D cos` of Beckmann α ≥ 0.05 and of a GGX with (αx, αy) = (0.02, 0.6): 1 to < 1e-4.
//!
//! Partial sums are accumulated in f64.
//!
//! ```
//! use brdf_core::Model;
//! use brdf_core::properties::{Quadrature, directional_albedo, reciprocity_error};
//! let m = Model::build("oren_nayar", &[]).unwrap();
//! let rho = directional_albedo(&m, 0.5, &Quadrature::default()).unwrap();
//! assert!(rho.max_element() < 1.0);
//! assert!(reciprocity_error(&m, 1000, 0) < 1e-5);
//! ```

use glam::{DVec3, Vec3, Vec3A};
use rayon::prelude::*;

use crate::frame::ShadingFrame;
use crate::{BrdfError, Geometry, Model};

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// SplitMix64 (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number generators"; the seeder of
/// `xoshiro`): a 64-bit state advanced by the golden-ratio increment and mixed by two xor-shift-multiply
/// rounds. Tiny, fast, and identical on every platform, which is all the checks need.
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// Generator with the given seed (any value, including 0).
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// Next 64 uniformly distributed bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Uniform direction on the unit sphere from two uniform numbers in `[0, 1)`.
#[inline]
fn uniform_sphere(u1: f64, u2: f64) -> Vec3A {
    let z = 1.0 - 2.0 * u1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u2;
    Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)
}

/// Uniform direction on the upper hemisphere (local z > 0) from two uniform numbers in `[0, 1)`.
#[inline]
fn uniform_hemisphere(u1: f64, u2: f64) -> Vec3A {
    let z = 1.0 - u1; // in (0, 1]
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u2;
    Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)
}

/// A random configuration: random unit normal and tangent, `l` and `v` uniform over the hemisphere.
fn random_geometry(rng: &mut SplitMix64) -> Option<Geometry> {
    let n = uniform_sphere(rng.next_f64(), rng.next_f64());
    let frame = ShadingFrame::from_normal(n);
    let (s, c) = (TAU * rng.next_f64()).sin_cos();
    let tangent = frame.t * c as f32 + frame.b * s as f32;
    let l = frame.from_local(uniform_hemisphere(rng.next_f64(), rng.next_f64()));
    let v = frame.from_local(uniform_hemisphere(rng.next_f64(), rng.next_f64()));
    Geometry::new(l.into(), v.into(), n.into(), Some(tangent.into()))
}

/// Positivity check: the smallest channel of `f_r(l, v)` over `samples` random configurations
/// (random normal and tangent; `l`, `v` uniform over the upper hemisphere; seeded by `seed`).
///
/// A BRDF must be ≥ 0 everywhere, so a correct model returns a value
/// ≥ 0. Returns NaN as soon as the model returns a non-finite value, so that such a model fails any
/// `>= 0` test. `samples = 0` returns `+∞` (the minimum over nothing).
pub fn positivity(model: &Model, samples: usize, seed: u64) -> f32 {
    let mut rng = SplitMix64::new(seed);
    let mut min = f32::INFINITY;
    for _ in 0..samples {
        let Some(g) = random_geometry(&mut rng) else { continue };
        let f = model.eval(&g);
        if !f.is_finite() {
            return f32::NAN;
        }
        min = min.min(f.min_element());
    }
    min
}

/// Values of `f_r` below this [1/sr] are compared absolutely in [`reciprocity_error`]: relative
/// differences between two values that are both ~0 measure rounding, not reciprocity.
pub const RECIPROCITY_FLOOR: f32 = 1e-6;

/// Helmholtz reciprocity check: `max |f(l, v) − f(v, l)| / max(|f(l, v)|, |f(v, l)|, 1e-6)` over every
/// channel of `samples` random configurations (as in [`positivity`]; seeded by `seed`).
///
/// Physical BRDFs satisfy `f(l, v) = f(v, l)` (Helmholtz reciprocity), so a correct model returns a
/// few f32 ulps (≲ 1e-6 for most models; lobes `x^γ` amplify a rounding difference in `x` by γ).
/// Textbook formulas (classic models) are not reciprocal. Returns NaN if the model returns a
/// non-finite value; 0 for `samples = 0`.
pub fn reciprocity_error(model: &Model, samples: usize, seed: u64) -> f32 {
    let mut rng = SplitMix64::new(seed);
    let mut worst = 0.0f32;
    for _ in 0..samples {
        let Some(g) = random_geometry(&mut rng) else { continue };
        let (a, b) = (model.eval(&g), model.eval(&g.swapped()));
        if !a.is_finite() || !b.is_finite() {
            return f32::NAN;
        }
        let diff = (a - b).abs();
        let scale = a.abs().max(b.abs()).max(Vec3::splat(RECIPROCITY_FLOOR));
        worst = worst.max((diff / scale).max_element());
    }
    worst
}

/// Settings of the graded Gauss–Legendre product quadrature (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadrature {
    /// Gauss–Legendre points per θ panel (1 ..= 64).
    pub theta_order: usize,
    /// Gauss–Legendre points per φ panel (1 ..= 64).
    pub phi_order: usize,
    /// Width \[rad\] of the smallest panels next to a peak (1e-9 ..= 0.1): lobes down to about twice
    /// this width are resolved.
    pub min_panel: f64,
}

impl Default for Quadrature {
    /// 8 × 8 points per panel, panels down to 1e-4 rad.
    fn default() -> Self {
        Self { theta_order: 8, phi_order: 8, min_panel: 1e-4 }
    }
}

impl Quadrature {
    /// Check the settings, naming the offending field.
    pub fn validate(&self) -> Result<(), BrdfError> {
        for (name, order) in [("theta_order", self.theta_order), ("phi_order", self.phi_order)] {
            if !(1..=64).contains(&order) {
                return Err(BrdfError::param(name, format!("must be in [1, 64], got {order}")));
            }
        }
        if !(self.min_panel >= 1e-9 && self.min_panel <= 0.1) {
            return Err(BrdfError::param(
                "min_panel",
                format!("must be in [1e-9, 0.1], got {}", self.min_panel),
            ));
        }
        Ok(())
    }
}

/// A 1-D quadrature rule: `(node, weight)` pairs.
type Rule = Vec<(f64, f64)>;

/// Gauss–Legendre nodes and weights on `[−1, 1]` (Newton iteration on `P_n`, f64; nodes accurate to
/// about 1e-15).
pub(crate) fn gauss_legendre(n: usize) -> Rule {
    let mut rule = vec![(0.0, 0.0); n];
    for i in 0..n.div_ceil(2) {
        // Tricomi's initial guess for the i-th largest root.
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_{n−1}(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let (pn, pn1) = if n == 1 { (x, 1.0) } else { (p1, p0) };
            dp = n as f64 * (x * pn - pn1) / (x * x - 1.0);
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        if n == 1 {
            x = 0.0;
            dp = 1.0;
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        rule[i] = (-x, w);
        rule[n - 1 - i] = (x, w);
    }
    rule
}

/// Panel edges on `[a, b]`, halving toward the ends flagged in `toward = (a_end, b_end)`, down to
/// `min_panel`; an interval graded toward neither end is split into two equal panels.
fn graded_edges(a: f64, b: f64, toward: (bool, bool), min_panel: f64, edges: &mut Vec<f64>) {
    let len = b - a;
    if !(len > 0.0) {
        return;
    }
    match toward {
        (false, false) => edges.extend([a, a + 0.5 * len]),
        (false, true) => {
            edges.push(a);
            let mut d = 0.5 * len;
            while d >= min_panel {
                edges.push(b - d);
                d *= 0.5;
            }
        }
        (true, false) => {
            edges.push(a);
            let mut steps = Vec::new();
            let mut d = 0.5 * len;
            while d >= min_panel {
                steps.push(d);
                d *= 0.5;
            }
            // Ascending: a + smallest, …, a + len/2.
            edges.extend(steps.iter().rev().map(|s| a + s));
        }
        (true, true) => {
            let mid = a + 0.5 * len;
            graded_edges(a, mid, (true, false), min_panel, edges);
            graded_edges(mid, b, (false, true), min_panel, edges);
        }
    }
}

/// A 1-D composite rule: `(node, weight)` over the panels between consecutive `edges` (and `end`).
fn composite_rule(mut edges: Vec<f64>, end: f64, gl: &[(f64, f64)]) -> Rule {
    edges.push(end);
    let mut rule = Vec::with_capacity(edges.len() * gl.len());
    for w in edges.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !(b > a) {
            continue;
        }
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        rule.extend(gl.iter().map(|&(x, wt)| (mid + half * x, half * wt)));
    }
    rule
}

/// Where the integrand may be sharp.
#[derive(Debug, Clone, Copy)]
struct Features {
    /// Polar angle toward which θ panels are graded.
    theta: f64,
    /// Azimuth of the first of four quarter points `φ0 + kπ/2`.
    phi0: f64,
    /// Which quarter points φ panels are graded toward (the others are plain panel breaks).
    graded: [bool; 4],
}

/// The θ and φ rules of a product quadrature for `features`.
fn product_rule(features: Features, q: &Quadrature) -> (Rule, Rule) {
    let (m, tp) = (q.min_panel, features.theta.clamp(0.0, FRAC_PI_2));
    let mut theta_edges = Vec::new();
    if tp <= m {
        graded_edges(0.0, FRAC_PI_2, (true, false), m, &mut theta_edges);
    } else if tp >= FRAC_PI_2 - m {
        graded_edges(0.0, FRAC_PI_2, (false, true), m, &mut theta_edges);
    } else {
        graded_edges(0.0, tp, (false, true), m, &mut theta_edges);
        graded_edges(tp, FRAC_PI_2, (true, false), m, &mut theta_edges);
    }
    let mut phi_edges = Vec::new();
    for k in 0..4 {
        let a = features.phi0 + k as f64 * FRAC_PI_2;
        let toward = (features.graded[k], features.graded[(k + 1) % 4]);
        graded_edges(a, a + FRAC_PI_2, toward, m, &mut phi_edges);
    }
    let theta = composite_rule(theta_edges, FRAC_PI_2, &gauss_legendre(q.theta_order));
    let phi = composite_rule(phi_edges, features.phi0 + TAU, &gauss_legendre(q.phi_order));
    (theta, phi)
}

/// `∫_{H²} g(ω) dω` with the product rule for `features`; `g` receives a local unit direction
/// (z = normal). The θ rows run in parallel; their sums are added in θ order, so the result does not
/// depend on the thread count.
fn integrate(features: Features, q: &Quadrature, g: impl Fn(Vec3A) -> DVec3 + Sync) -> DVec3 {
    let (theta, phi) = product_rule(features, q);
    // Azimuth cosines and sines once, not per θ row.
    let phi: Vec<(f64, f64, f64)> = phi.iter().map(|&(p, w)| (p.cos(), p.sin(), w)).collect();
    let rows: Vec<DVec3> = theta
        .par_iter()
        .map(|&(t, wt)| {
            let (st, ct) = t.sin_cos();
            let mut row = DVec3::ZERO;
            for &(cp, sp, wp) in &phi {
                let w = Vec3A::new((st * cp) as f32, (st * sp) as f32, ct as f32);
                row += g(w) * wp;
            }
            row * (wt * st)
        })
        .collect();
    rows.iter().fold(DVec3::ZERO, |acc, r| acc + *r)
}

/// `∫_{H²} g(ω) dω` over the upper hemisphere (local frame, z = normal) by the graded quadrature of
/// the module docs. With `peak = Some(p)` the panels are graded toward the polar angle of `p` and
/// toward its azimuth and the opposite one; with `None` toward the pole and toward the four tangent
/// axes (the shape of an (an)isotropic microfacet distribution).
pub fn hemisphere_integral(
    g: impl Fn(Vec3A) -> f64 + Sync,
    peak: Option<Vec3A>,
    q: &Quadrature,
) -> Result<f64, BrdfError> {
    q.validate()?;
    let features = match peak {
        Some(p) => {
            let p = crate::vector::normalize_or_zero(p);
            let theta = f64::from(p.z.clamp(-1.0, 1.0)).acos();
            Features { theta, phi0: f64::from(p.y).atan2(f64::from(p.x)), graded: [true, false, true, false] }
        }
        None => Features { theta: 0.0, phi0: 0.0, graded: [true; 4] },
    };
    Ok(integrate(features, q, |w| DVec3::splat(g(w))).x)
}

/// The nodes of the graded product rule as `(direction, weight)` pairs, `Σ wₖ g(ωₖ) ≈ ∫_{H²} g(ω) dω`
/// (the `sin θ` of the measure is in the weights), graded toward the polar angle of `peak` and toward
/// its azimuth and the opposite one, as [`hemisphere_integral`] with `Some(peak)` (local frame,
/// z = normal). For callers that evaluate a model over every node in one batch (brdf-core `views`).
pub fn hemisphere_rule(peak: Vec3A, q: &Quadrature) -> Result<Vec<(Vec3A, f64)>, BrdfError> {
    q.validate()?;
    let p = crate::vector::normalize_or_zero(peak);
    let features = Features {
        theta: f64::from(p.z.clamp(-1.0, 1.0)).acos(),
        phi0: f64::from(p.y).atan2(f64::from(p.x)),
        graded: [true, false, true, false],
    };
    let (theta, phi) = product_rule(features, q);
    let phi: Vec<(f64, f64, f64)> = phi.iter().map(|&(p, w)| (p.cos(), p.sin(), w)).collect();
    let mut nodes = Vec::with_capacity(theta.len() * phi.len());
    for &(t, wt) in &theta {
        let (st, ct) = t.sin_cos();
        for &(cp, sp, wp) in &phi {
            nodes.push((Vec3A::new((st * cp) as f32, (st * sp) as f32, ct as f32), wp * wt * st));
        }
    }
    Ok(nodes)
}

/// Normalisation of a microfacet distribution: `∫_{H²} D(h) (n·h) dω_h`, which is 1 for a normalised
/// `D` (projected microfacet area = macro-surface area; Walter et al. 2007 eq. 4).
///
/// `d` receives the local microfacet normal `h` (z = normal, x = tangent) and returns `D(h)` [1/sr].
/// The quadrature is graded toward the pole and the tangent axes (see [`hemisphere_integral`]).
pub fn microfacet_normalization(d: impl Fn(Vec3A) -> f32 + Sync, q: &Quadrature) -> Result<f64, BrdfError> {
    hemisphere_integral(|h| f64::from(d(h)) * f64::from(h.z), None, q)
}

/// Directional albedo `ρ(v) = ∫_{H²} f_r(l, v) cos θ_l dω_l` per channel, for the view direction `v`
/// given in the local frame (z = normal, x = tangent; normalised here).
///
/// This is the fraction of the energy arriving from `v` that is reflected (by reciprocity, also the
/// reflectance under uniform illumination seen from `v`): energy conservation requires `ρ(v) ≤ 1` for
/// every `v`. For a classic model it is `∫ shade dω`, the textbook formula's
/// response to a uniform white sky. See the module docs for the quadrature and its accuracy.
pub fn directional_albedo_at(model: &Model, v: Vec3, q: &Quadrature) -> Result<Vec3, BrdfError> {
    q.validate()?;
    let v = crate::vector::normalize_or_zero(v.into());
    if v == Vec3A::ZERO {
        return Err(BrdfError::InvalidInput {
            name: "v",
            problem: "must be a finite, non-zero vector".into(),
        });
    }
    let features = Features {
        theta: f64::from(v.z.clamp(-1.0, 1.0)).acos(),
        // Mirror azimuth φ_v + π (graded), φ_v + 3π/2 (break), φ_v (retro, graded), φ_v + π/2 (break).
        phi0: f64::from(v.y).atan2(f64::from(v.x)) + PI,
        graded: [true, false, true, false],
    };
    let sum = integrate(features, q, |l| {
        let mut g = Geometry::from_unit(l, v, Vec3A::Z);
        g.tangent = Some(Vec3A::X);
        model.eval(&g).as_dvec3() * f64::from(l.z)
    });
    Ok(sum.as_vec3())
}

/// [`directional_albedo_at`] for the view direction at polar cosine `cos_theta_v` in the x–z plane
/// (azimuth 0, along the tangent): `v = (sin θ_v, 0, cos θ_v)`. `cos_theta_v` must lie in `[0, 1]`.
pub fn directional_albedo(model: &Model, cos_theta_v: f32, q: &Quadrature) -> Result<Vec3, BrdfError> {
    if !(0.0..=1.0).contains(&cos_theta_v) {
        return Err(BrdfError::InvalidInput {
            name: "cos_theta_v",
            problem: format!("must be in [0, 1], got {cos_theta_v}"),
        });
    }
    let sin = (1.0 - cos_theta_v * cos_theta_v).max(0.0).sqrt();
    directional_albedo_at(model, Vec3::new(sin, 0.0, cos_theta_v), q)
}

/// [`directional_albedo`] for several view cosines (in parallel; each result is deterministic).
pub fn directional_albedos(
    model: &Model,
    cos_theta_v: &[f32],
    q: &Quadrature,
) -> Result<Vec<Vec3>, BrdfError> {
    cos_theta_v.par_iter().map(|&c| directional_albedo(model, c, q)).collect()
}

/// Random configurations used by [`check`].
pub const CHECK_SAMPLES: usize = 10_000;
/// View cosines at which [`check`] computes the directional albedo.
pub const CHECK_COS_THETA_V: [f32; 6] = [1.0, 0.9, 0.7, 0.5, 0.3, 0.1];
/// [`check`]'s tolerance on reciprocity (relative) and on `ρ ≤ 1` (absolute): well above the
/// quadrature error and f32 rounding, well below any modelling error worth reporting.
pub const CHECK_TOLERANCE: f32 = 1e-4;

/// What [`check`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    /// Registry name of the model.
    pub model: &'static str,
    /// Whether the model claims to be a physical BRDF (the three verdicts apply to those).
    pub physical: bool,
    /// [`positivity`] over [`CHECK_SAMPLES`] configurations (seed 0).
    pub min_value: f32,
    /// [`reciprocity_error`] over [`CHECK_SAMPLES`] configurations (seed 0).
    pub reciprocity_error: f32,
    /// The view cosines of [`CheckReport::albedo`] ([`CHECK_COS_THETA_V`]).
    pub cos_theta_v: Vec<f32>,
    /// [`directional_albedo`] at each view cosine (default [`Quadrature`]).
    pub albedo: Vec<Vec3>,
    /// Largest channel of all albedos.
    pub max_albedo: f32,
    /// `min_value ≥ 0`.
    pub positive: bool,
    /// `reciprocity_error ≤ CHECK_TOLERANCE`.
    pub reciprocal: bool,
    /// `max_albedo ≤ 1 + CHECK_TOLERANCE`.
    pub energy_conserving: bool,
}

/// Run all checks on `model` with fixed settings (seed 0, [`CHECK_SAMPLES`], [`CHECK_COS_THETA_V`]).
pub fn check(model: &Model) -> CheckReport {
    let min_value = positivity(model, CHECK_SAMPLES, 0);
    let reciprocity = reciprocity_error(model, CHECK_SAMPLES, 0);
    let albedo = directional_albedos(model, &CHECK_COS_THETA_V, &Quadrature::default())
        .unwrap_or_else(|_| vec![Vec3::NAN; CHECK_COS_THETA_V.len()]);
    let max_albedo = albedo
        .iter()
        .fold(f32::NEG_INFINITY, |m, a| if a.is_finite() { m.max(a.max_element()) } else { f32::NAN });
    CheckReport {
        model: model.spec().name,
        physical: model.spec().physical,
        min_value,
        reciprocity_error: reciprocity,
        cos_theta_v: CHECK_COS_THETA_V.to_vec(),
        albedo,
        max_albedo,
        positive: min_value >= 0.0,
        reciprocal: reciprocity <= CHECK_TOLERANCE,
        energy_conserving: max_albedo <= 1.0 + CHECK_TOLERANCE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_2n_minus_1_exactly() {
        for n in [1usize, 2, 3, 8, 16, 64] {
            let rule = gauss_legendre(n);
            let total: f64 = rule.iter().map(|&(_, w)| w).sum();
            assert!((total - 2.0).abs() < 1e-13, "n={n}: Σw = {total}");
            let deg = 2 * n - 1;
            // ∫_{-1}^{1} x^{deg-1} dx for even deg-1.
            let p = (deg - 1) as i32;
            let exact = if p % 2 == 0 { 2.0 / (p + 1) as f64 } else { 0.0 };
            let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(p)).sum();
            assert!((got - exact).abs() < 1e-12, "n={n}: {got} vs {exact}");
        }
    }

    #[test]
    fn graded_panels_cover_the_interval_and_shrink_to_the_minimum() {
        let mut e = Vec::new();
        graded_edges(0.0, 1.0, (true, true), 1e-3, &mut e);
        e.push(1.0);
        assert!(e.windows(2).all(|w| w[1] > w[0]), "{e:?}");
        let widths: Vec<f64> = e.windows(2).map(|w| w[1] - w[0]).collect();
        let smallest = widths.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!((1e-3..2e-3).contains(&smallest), "{smallest}");
        assert!((widths[0] - widths[widths.len() - 1]).abs() < 1e-15);
    }

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // First outputs for seed 1234567 of the reference C implementation (Vigna, splitmix64.c).
        let mut r = SplitMix64::new(1_234_567);
        let got: Vec<u64> = (0..3).map(|_| r.next_u64()).collect();
        assert_eq!(got, [6_457_827_717_110_365_317, 3_203_168_211_198_807_973, 9_817_491_932_198_370_423]);
    }
}
