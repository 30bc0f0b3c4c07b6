//! Microfacet distributions of normals `D(h)` [1/sr] and their Smith `Λ`, one file per distribution,
//! plus the [`Distribution`] enum the models compose and a weighted [`Mixture`] of lobes
//! (Walter et al. 2007).
//!
//! Every `D` is normalised so that the projected microfacet area is the macro-surface area:
//! `∫_Ω D(h) (n·h) dω_h = 1` (Walter et al. 2007 eq. 4; the integration tests check it by quadrature for each
//! distribution at several roughnesses). `D` is evaluated on a unit half vector in the *local* frame
//! (z = normal, x = tangent; see [`crate::frame`]); isotropic distributions also take `cos θ_h = n·h`
//! directly so isotropic models need no frame.
//!
//! Roughness floor: every α is clamped to ≥ [`ALPHA_MIN`] = 1e−4 (pbrt-v4
//! `TrowbridgeReitzDistribution`). Below it the lobe is narrower than f32 can resolve around
//! cos θ = 1, the peak `1/(πα²)` heads for overflow, and `tan²θ/α²` becomes 0/0 at the peak; a
//! near-mirror is better rendered as a mirror.
//!
//! Smith `Λ`: exact for GGX ([`ggx::lambda`]) and Beckmann ([`beckmann::lambda`], the erf form to
//! float32 precision through a fitted rational G1). The other
//! distributions have no closed-form Λ of their own; [`Distribution::lambda`] maps them to the
//! Beckmann Λ of an equivalent roughness (Walter et al. 2007 §5.2): Blinn–Phong and Ashikhmin–Shirley
//! exponents by `α = √(2/(m+2))`, the Gaussian by `α = m` (both are Gaussians in the slope for
//! small angles), Ward exactly (it *is* anisotropic Beckmann).

pub mod ashikhmin_shirley;
pub mod beckmann;
pub mod blinn_phong;
pub mod gaussian;
pub mod ggx;
pub mod half;
pub mod ward;

use glam::Vec3A;

pub use gaussian::Gaussian;
pub use half::HalfVector;

use crate::BrdfError;
use crate::frame::ShadingFrame;
use crate::simd::{Lane, V3};

/// Smallest roughness α used anywhere (pbrt-v4's floor; see the module docs).
pub const ALPHA_MIN: f32 = 1e-4;

/// Largest roughness α accepted by name ([`Distribution::from_name`]): RMS slopes of 10⁴ are facets
/// within 0.006° of vertical, far past any surface (α = 1 is already very rough); above it the
/// slope arithmetic (`α² tan²θ`) leaves float32.
pub const ALPHA_MAX: f32 = 1e4;

/// Registry names of the distributions, in documentation order.
pub const DISTRIBUTION_NAMES: [&str; 6] =
    ["beckmann", "ggx", "gaussian", "blinn_phong", "ward", "ashikhmin_shirley"];

/// One microfacet distribution with its parameters (floors applied by the constructors).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Distribution {
    /// [`beckmann::d_aniso`] (isotropic when `alpha_x == alpha_y`).
    Beckmann {
        /// RMS slope along the tangent.
        alpha_x: f32,
        /// RMS slope along the bitangent.
        alpha_y: f32,
    },
    /// [`ggx::d_aniso`] (isotropic when `alpha_x == alpha_y`).
    Ggx {
        /// Roughness along the tangent.
        alpha_x: f32,
        /// Roughness along the bitangent.
        alpha_y: f32,
    },
    /// [`Gaussian`] in the half-angle (isotropic).
    Gaussian(Gaussian),
    /// [`blinn_phong::d`] (isotropic).
    BlinnPhong {
        /// Exponent m ≥ 0.
        exponent: f32,
    },
    /// [`ward::d`] (normalised Ward = anisotropic Beckmann).
    Ward {
        /// RMS slope along the tangent.
        alpha_x: f32,
        /// RMS slope along the bitangent.
        alpha_y: f32,
    },
    /// [`ashikhmin_shirley::d`] (microfacet-normalised).
    AshikhminShirley {
        /// Exponent along the tangent.
        nu: f32,
        /// Exponent along the bitangent.
        nv: f32,
    },
}

fn floor_alpha(a: f32) -> f32 {
    if a.is_nan() { ALPHA_MIN } else { a.max(ALPHA_MIN) }
}

fn clamp_exponent(e: f32) -> f32 {
    if e.is_nan() { 0.0 } else { e.clamp(0.0, blinn_phong::EXPONENT_MAX) }
}

impl Distribution {
    /// Isotropic Beckmann of RMS slope α.
    pub fn beckmann(alpha: f32) -> Self {
        Self::beckmann_aniso(alpha, alpha)
    }
    /// Anisotropic Beckmann.
    pub fn beckmann_aniso(alpha_x: f32, alpha_y: f32) -> Self {
        Distribution::Beckmann { alpha_x: floor_alpha(alpha_x), alpha_y: floor_alpha(alpha_y) }
    }
    /// Isotropic GGX of roughness α.
    pub fn ggx(alpha: f32) -> Self {
        Self::ggx_aniso(alpha, alpha)
    }
    /// Anisotropic GGX.
    pub fn ggx_aniso(alpha_x: f32, alpha_y: f32) -> Self {
        Distribution::Ggx { alpha_x: floor_alpha(alpha_x), alpha_y: floor_alpha(alpha_y) }
    }
    /// Gaussian of RMS slope angle m \[rad\] (normalisation computed here, once).
    pub fn gaussian(m: f32) -> Self {
        Distribution::Gaussian(Gaussian::new(floor_alpha(m)))
    }
    /// Normalised Blinn–Phong of exponent m.
    pub fn blinn_phong(exponent: f32) -> Self {
        Distribution::BlinnPhong { exponent: clamp_exponent(exponent) }
    }
    /// Normalised anisotropic Ward.
    pub fn ward(alpha_x: f32, alpha_y: f32) -> Self {
        Distribution::Ward { alpha_x: floor_alpha(alpha_x), alpha_y: floor_alpha(alpha_y) }
    }
    /// Microfacet-normalised Ashikhmin–Shirley with exponents nu (tangent), nv (bitangent).
    pub fn ashikhmin_shirley(nu: f32, nv: f32) -> Self {
        Distribution::AshikhminShirley { nu: clamp_exponent(nu), nv: clamp_exponent(nv) }
    }

    /// The isotropic distribution of the same family with roughness `alpha`, exactly what
    /// [`Distribution::from_roughness`] gives for this family's name (GGX, Beckmann, Gaussian,
    /// Blinn–Phong; `alpha` floored at [`ALPHA_MIN`]); `None` for the anisotropic families and an
    /// `alpha` that is not finite and ≥ 0.
    #[inline]
    pub fn with_roughness(&self, alpha: f32) -> Option<Self> {
        if !(alpha.is_finite() && alpha >= 0.0) {
            return None;
        }
        let a = alpha.max(ALPHA_MIN);
        match self {
            Self::Ggx { .. } => Some(Self::ggx(a)),
            Self::Beckmann { .. } => Some(Self::beckmann(a)),
            Self::Gaussian(_) => Some(Self::gaussian(a)),
            Self::BlinnPhong { .. } => Some(Self::blinn_phong(blinn_phong::exponent_from_alpha(a))),
            _ => None,
        }
    }

    /// Build by name from a roughness, as `brdfpy.microfacet.distribution(name, h, n, alpha,
    /// alpha_y=…)` does: `alpha` (and `alpha_y`, bitangent direction, default `alpha`) is the RMS
    /// slope / roughness α > 0 of `beckmann`, `ggx`, `ward`, the RMS slope angle m \[rad\] of
    /// `gaussian`, and is mapped to the Blinn–Phong exponent `2/α² − 2` for `blinn_phong`
    /// (Walter et al. 2007 §5.2). For `ashikhmin_shirley` they are the exponents nu, nv ≥ 0 (that
    /// distribution has no roughness). Errors name the argument: α ≤ 0 or non-finite, `alpha_y` on
    /// an isotropic distribution, an unknown name. For the native parameters use the constructors
    /// ([`Distribution::blinn_phong`] takes the exponent).
    pub fn from_name(name: &str, alpha: f32, alpha_y: Option<f32>) -> Result<Self, BrdfError> {
        let key = name.to_ascii_lowercase();
        let exponents = key == "ashikhmin_shirley";
        let check = |arg: &str, x: f32| {
            if !x.is_finite() || x < 0.0 || (x == 0.0 && !exponents) || (x > ALPHA_MAX && !exponents) {
                let want = if exponents { ">= 0".to_string() } else { format!("in (0, {ALPHA_MAX}]") };
                Err(BrdfError::param(arg, format!("must be finite and {want}, got {x}")))
            } else {
                Ok(x)
            }
        };
        let a = check("alpha", alpha)?;
        let ay = match alpha_y {
            Some(y) => check("alpha_y", y)?,
            None => a,
        };
        let isotropic_only = |d: Self| {
            if ay == a {
                Ok(d)
            } else {
                Err(BrdfError::param(
                    "alpha_y",
                    format!("distribution {name:?} is isotropic; alpha_y must be omitted or equal alpha"),
                ))
            }
        };
        match key.as_str() {
            "beckmann" => Ok(Self::beckmann_aniso(a, ay)),
            "ggx" | "trowbridge_reitz" => Ok(Self::ggx_aniso(a, ay)),
            "ward" => Ok(Self::ward(a, ay)),
            "ashikhmin_shirley" => Ok(Self::ashikhmin_shirley(a, ay)),
            "gaussian" => isotropic_only(Self::gaussian(a)),
            "blinn_phong" => isotropic_only(Self::blinn_phong(blinn_phong::exponent_from_alpha(a))),
            _ => Err(BrdfError::param(
                "distribution",
                format!("expected one of {}, got {name:?}", DISTRIBUTION_NAMES.join(", ")),
            )),
        }
    }

    /// Build an isotropic distribution by name from one roughness α ≥ 0 (0 is raised to
    /// [`ALPHA_MIN`]), with the meaning of [`Distribution::from_name`]; `ashikhmin_shirley` gets the
    /// exponent `2/α² − 2` like `blinn_phong`. This is what the Cook–Torrance model's single
    /// `roughness` means for each choice.
    pub fn from_roughness(name: &str, alpha: f32) -> Result<Self, BrdfError> {
        if !(alpha.is_finite() && alpha >= 0.0) {
            return Err(BrdfError::param("roughness", format!("must be finite and >= 0, got {alpha}")));
        }
        match name.to_ascii_lowercase().as_str() {
            "ashikhmin_shirley" => {
                let e = blinn_phong::exponent_from_alpha(alpha);
                Ok(Self::ashikhmin_shirley(e, e))
            }
            _ => Self::from_name(name, alpha.max(ALPHA_MIN), None),
        }
    }

    /// Registry name.
    pub fn name(&self) -> &'static str {
        match self {
            Distribution::Beckmann { .. } => "beckmann",
            Distribution::Ggx { .. } => "ggx",
            Distribution::Gaussian(_) => "gaussian",
            Distribution::BlinnPhong { .. } => "blinn_phong",
            Distribution::Ward { .. } => "ward",
            Distribution::AshikhminShirley { .. } => "ashikhmin_shirley",
        }
    }

    /// `true` when `D` depends on θ_h only.
    pub fn is_isotropic(&self) -> bool {
        match *self {
            Distribution::Beckmann { alpha_x, alpha_y }
            | Distribution::Ggx { alpha_x, alpha_y }
            | Distribution::Ward { alpha_x, alpha_y } => alpha_x == alpha_y,
            Distribution::AshikhminShirley { nu, nv } => nu == nv,
            Distribution::Gaussian(_) | Distribution::BlinnPhong { .. } => true,
        }
    }

    /// `D(h)` [1/sr] for a unit half vector in the local frame (z = normal, x = tangent).
    #[inline]
    pub fn d(&self, h: Vec3A) -> f32 {
        self.d_lanes(V3::from(h))
    }

    /// [`Distribution::d`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_lanes<F: Lane>(&self, h: V3<F>) -> F {
        match *self {
            Distribution::Beckmann { alpha_x, alpha_y } | Distribution::Ward { alpha_x, alpha_y } => {
                beckmann::d_aniso_lanes(h, alpha_x, alpha_y)
            }
            Distribution::Ggx { alpha_x, alpha_y } => ggx::d_aniso_lanes(h, alpha_x, alpha_y),
            Distribution::Gaussian(g) => g.d_lanes(h.z),
            Distribution::BlinnPhong { exponent } => blinn_phong::d_lanes(h.z, exponent),
            Distribution::AshikhminShirley { nu, nv } => ashikhmin_shirley::d_lanes(h, nu, nv),
        }
    }

    /// `D` [1/sr] from `cos_h` = n·h alone, for isotropic models that never build a frame. For an
    /// anisotropic distribution this is its value with h in the tangent–normal plane (φ_h = 0, i.e.
    /// `alpha_x` / `nu`): build a frame and call [`Distribution::d`] instead.
    #[inline]
    pub fn d_cos(&self, cos_h: f32) -> f32 {
        self.d_cos_lanes(cos_h)
    }

    /// [`Distribution::d_cos`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_cos_lanes<F: Lane>(&self, cos_h: F) -> F {
        match *self {
            Distribution::Beckmann { alpha_x, .. } | Distribution::Ward { alpha_x, .. } => {
                beckmann::d_lanes(cos_h, alpha_x)
            }
            Distribution::Ggx { alpha_x, .. } => ggx::d_lanes(cos_h, alpha_x),
            Distribution::Gaussian(g) => g.d_lanes(cos_h),
            Distribution::BlinnPhong { exponent } => blinn_phong::d_lanes(cos_h, exponent),
            Distribution::AshikhminShirley { nu, .. } => blinn_phong::d_lanes(cos_h, nu),
        }
    }

    /// `D` [1/sr] from the un-normalised half vector `h̃ = l + v` (isotropic models; anisotropic
    /// distributions at φ_h = 0 as in [`Distribution::d_cos`]). The same function as `d_cos(n·h)`,
    /// written so that it keeps its precision where `l` and `v` are nearly opposite
    /// ([`crate::microfacet::half`]).
    #[inline]
    pub fn d_half(&self, h: &HalfVector<f32>) -> f32 {
        self.d_half_lanes(h)
    }

    /// [`Distribution::d_half`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_half_lanes<F: Lane>(&self, h: &HalfVector<F>) -> F {
        match *self {
            Distribution::Beckmann { alpha_x, .. } | Distribution::Ward { alpha_x, .. } => {
                beckmann::d_half_lanes(h, alpha_x)
            }
            Distribution::Ggx { alpha_x, .. } => ggx::d_half_lanes(h, alpha_x),
            Distribution::Gaussian(g) => g.d_half_lanes(h),
            Distribution::BlinnPhong { exponent } => blinn_phong::d_half_lanes(h, exponent),
            Distribution::AshikhminShirley { nu, .. } => blinn_phong::d_half_lanes(h, nu),
        }
    }

    /// `D` [1/sr] for world-space unit `h` and normal `n`, with an optional tangent (an arbitrary
    /// frame is built from `n` without one). Convenience for batch/Python evaluation.
    pub fn d_world(&self, h: Vec3A, n: Vec3A, tangent: Option<Vec3A>) -> f32 {
        let frame = match tangent {
            Some(t) => ShadingFrame::from_normal_tangent(n, t),
            None => ShadingFrame::from_normal(n),
        };
        self.d(frame.to_local(h))
    }

    /// Beckmann roughness (αx, αy) whose Smith Λ this distribution uses (see the module docs).
    pub fn beckmann_equivalent(&self) -> (f32, f32) {
        match *self {
            Distribution::Beckmann { alpha_x, alpha_y }
            | Distribution::Ward { alpha_x, alpha_y }
            | Distribution::Ggx { alpha_x, alpha_y } => (alpha_x, alpha_y),
            Distribution::Gaussian(g) => (g.m, g.m),
            Distribution::BlinnPhong { exponent } => {
                let a = blinn_phong::alpha_from_exponent(exponent);
                (a, a)
            }
            Distribution::AshikhminShirley { nu, nv } => {
                (blinn_phong::alpha_from_exponent(nu), blinn_phong::alpha_from_exponent(nv))
            }
        }
    }

    /// Smith `Λ(w)` for a unit local direction: GGX's own, Beckmann's exact, others mapped to
    /// Beckmann (module docs). +∞ below the horizon.
    #[inline]
    pub fn lambda(&self, w: Vec3A) -> f32 {
        self.lambda_lanes(V3::from(w))
    }

    /// [`Distribution::lambda`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lambda_lanes<F: Lane>(&self, w: V3<F>) -> F {
        match *self {
            Distribution::Ggx { alpha_x, alpha_y } => ggx::lambda_aniso_lanes(w, alpha_x, alpha_y),
            _ => {
                let (ax, ay) = self.beckmann_equivalent();
                beckmann::lambda_aniso_lanes(w, ax, ay)
            }
        }
    }

    /// Smith `Λ` from `cos θ` alone (isotropic; anisotropic ones at φ = 0, as [`Distribution::d_cos`]).
    #[inline]
    pub fn lambda_cos(&self, cos_theta: f32) -> f32 {
        self.lambda_cos_lanes(cos_theta)
    }

    /// [`Distribution::lambda_cos`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lambda_cos_lanes<F: Lane>(&self, cos_theta: F) -> F {
        match *self {
            Distribution::Ggx { alpha_x, .. } => ggx::lambda_lanes(cos_theta, alpha_x),
            _ => beckmann::lambda_lanes(cos_theta, self.beckmann_equivalent().0),
        }
    }

    /// Smith masking of one direction `G1 = 1/(1 + Λ(w))`, local frame.
    #[inline]
    pub fn g1(&self, w: Vec3A) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }
}

/// `Σ wᵢ tᵢ` over the lobes of a mixture for the per-lobe term `$term` of `$d`: the first lobe starts
/// the sum (Σ of one lobe is just w·t, with no extra rounding). A macro and a plain loop rather than
/// a closure or an iterator fold: a closure is a function of its own, compiled without the AVX2
/// target feature of the batch kernel, and the lane intrinsics in it would become calls (measured:
/// Beckmann Cook–Torrance 25× slower).
macro_rules! lobe_sum {
    ($mix:expr, |$d:ident| $term:expr) => {{
        // `$term` is expanded once (a debug build gives every expansion its own stack slots).
        let mut sum = F::splat(0.0);
        for (i, (w, $d)) in $mix.lobes().iter().enumerate() {
            let t = F::splat(*w) * $term;
            sum = if i == 0 { t } else { sum + t };
        }
        sum
    }};
}

/// Most lobes a [`Mixture`] holds (fixed so a mixture is `Copy` and never allocates).
pub const MAX_LOBES: usize = 4;

/// A weighted sum of distributions `D(h) = Σ wᵢ Dᵢ(h)` with `Σ wᵢ = 1` (Cook &
/// Torrance 1982 used two Beckmann lobes for some metals). Normalisation is preserved.
///
/// Smith Λ of the mixture is `Σ wᵢ Λᵢ` exactly: Λ is a linear functional of the slope distribution
/// (Heitz 2014 eq. 72), and mixing D's mixes slope distributions with the same weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mixture {
    lobes: [(f32, Distribution); MAX_LOBES],
    len: usize,
}

impl Mixture {
    /// One lobe of weight 1.
    pub fn single(d: Distribution) -> Self {
        let mut lobes = [(0.0, d); MAX_LOBES];
        lobes[0] = (1.0, d);
        Self { lobes, len: 1 }
    }

    /// Lobes with weights ≥ 0 (renormalised to sum to 1; zero-weight lobes are dropped). Errors on an
    /// empty list, more than [`MAX_LOBES`] lobes, a negative or non-finite weight, or a zero sum.
    pub fn new(lobes: &[(f32, Distribution)]) -> Result<Self, BrdfError> {
        if lobes.is_empty() || lobes.len() > MAX_LOBES {
            return Err(BrdfError::param(
                "lobes",
                format!("expected 1 to {MAX_LOBES} lobes, got {}", lobes.len()),
            ));
        }
        if let Some((w, _)) = lobes.iter().find(|(w, _)| !(w.is_finite() && *w >= 0.0)) {
            return Err(BrdfError::param("weights", format!("must be finite and >= 0, got {w}")));
        }
        let sum: f32 = lobes.iter().map(|(w, _)| w).sum();
        if !(sum > 0.0) {
            return Err(BrdfError::param("weights", "must not all be 0"));
        }
        let mut out = Self::single(lobes[0].1);
        out.len = 0;
        for &(w, d) in lobes.iter().filter(|(w, _)| *w > 0.0) {
            out.lobes[out.len] = (w / sum, d);
            out.len += 1;
        }
        Ok(out)
    }

    /// The (weight, distribution) pairs, weights summing to 1.
    pub fn lobes(&self) -> &[(f32, Distribution)] {
        &self.lobes[..self.len]
    }

    /// `true` when every lobe is isotropic.
    pub fn is_isotropic(&self) -> bool {
        self.lobes().iter().all(|(_, d)| d.is_isotropic())
    }

    /// The single distribution when there is exactly one lobe.
    #[inline]
    pub fn as_single(&self) -> Option<&Distribution> {
        (self.len == 1).then(|| &self.lobes[0].1)
    }

    /// `Σ wᵢ Dᵢ(h)` [1/sr], local frame.
    #[inline]
    pub fn d(&self, h: Vec3A) -> f32 {
        self.d_lanes(V3::from(h))
    }

    /// [`Mixture::d`] on lanes (summed as [`Mixture::d_cos_lanes`]).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_lanes<F: Lane>(&self, h: V3<F>) -> F {
        lobe_sum!(self, |d| d.d_lanes(h))
    }

    /// `Σ wᵢ Dᵢ` from `cos θ_h` (see [`Distribution::d_cos`]).
    #[inline]
    pub fn d_cos(&self, cos_h: f32) -> f32 {
        self.d_cos_lanes(cos_h)
    }

    /// [`Mixture::d_cos`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_cos_lanes<F: Lane>(&self, cos_h: F) -> F {
        lobe_sum!(self, |d| d.d_cos_lanes(cos_h))
    }

    /// `Σ wᵢ Dᵢ` from the un-normalised half vector (see [`Distribution::d_half`]).
    #[inline]
    pub fn d_half(&self, h: &HalfVector<f32>) -> f32 {
        self.d_half_lanes(h)
    }

    /// [`Mixture::d_half`] on lanes (summed as [`Mixture::d_cos_lanes`]).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_half_lanes<F: Lane>(&self, h: &HalfVector<F>) -> F {
        lobe_sum!(self, |d| d.d_half_lanes(h))
    }

    /// `Σ wᵢ Λᵢ(w)`, local frame.
    #[inline]
    pub fn lambda(&self, w: Vec3A) -> f32 {
        self.lambda_lanes(V3::from(w))
    }

    /// [`Mixture::lambda`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lambda_lanes<F: Lane>(&self, w: V3<F>) -> F {
        lobe_sum!(self, |d| d.lambda_lanes(w))
    }

    /// `Σ wᵢ Λᵢ` from `cos θ`.
    #[inline]
    pub fn lambda_cos(&self, cos_theta: f32) -> f32 {
        self.lambda_cos_lanes(cos_theta)
    }

    /// [`Mixture::lambda_cos`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lambda_cos_lanes<F: Lane>(&self, cos_theta: F) -> F {
        lobe_sum!(self, |d| d.lambda_cos_lanes(cos_theta))
    }
}

impl From<Distribution> for Mixture {
    fn from(d: Distribution) -> Self {
        Self::single(d)
    }
}

#[cfg(test)]
mod lane_tests {
    use super::*;
    use crate::simd::{F32x8, LaneKernel, run_widest};

    /// The six distributions, anisotropic where they can be, and a mixture.
    fn distributions() -> Vec<Mixture> {
        vec![
            Distribution::ggx_aniso(0.2, 0.5).into(),
            Distribution::beckmann_aniso(0.3, 0.1).into(),
            Distribution::gaussian(0.25).into(),
            Distribution::blinn_phong(50.0).into(),
            Distribution::ward(0.15, 0.4).into(),
            Distribution::ashikhmin_shirley(10.0, 300.0).into(),
            Mixture::new(&[(0.5, Distribution::ggx(0.1)), (0.5, Distribution::beckmann(0.4))]).unwrap(),
        ]
    }

    struct Compare;

    impl LaneKernel for Compare {
        #[cfg_attr(debug_assertions, inline)]
        #[cfg_attr(not(debug_assertions), inline(always))]
        fn run<F: Lane>(self) {
            let dirs: Vec<Vec3A> = (0..101)
                .map(|i| {
                    let t = i as f32 * 0.37;
                    let z = if i % 10 == 0 { -0.2 } else { (t * 0.71).cos().abs() };
                    Vec3A::new(t.sin(), (t * 1.3).cos(), z).normalize()
                })
                .collect();
            for m in distributions() {
                for c in dirs.chunks_exact(F::LANES) {
                    let w = V3 {
                        x: F::from_fn(|i| c[i].x),
                        y: F::from_fn(|i| c[i].y),
                        z: F::from_fn(|i| c[i].z),
                    };
                    let (d, l, lc, dc) =
                        (m.d_lanes(w), m.lambda_lanes(w), m.lambda_cos_lanes(w.z), m.d_cos_lanes(w.z));
                    for (i, h) in c.iter().enumerate() {
                        let same = |a: f32, b: f32| a.to_bits() == b.to_bits();
                        assert!(same(d.lane(i), m.d(*h)), "{m:?} D({h})");
                        assert!(same(l.lane(i), m.lambda(*h)), "{m:?} Lambda({h})");
                        assert!(same(lc.lane(i), m.lambda_cos(h.z)), "{m:?} Lambda_cos({h})");
                        assert!(same(dc.lane(i), m.d_cos(h.z)), "{m:?} D_cos({h})");
                    }
                }
            }
        }
    }

    #[test]
    fn every_distribution_and_lambda_gives_the_scalar_bits_in_every_lane_type() {
        Compare.run::<F32x8>();
        run_widest(Compare);
    }
}
