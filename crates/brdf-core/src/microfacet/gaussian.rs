//! The Gaussian distribution in the half-angle, `D(h) = c · exp(−(θ_h/m)²)` (Cook & Torrance
//! 1982; Blinn 1977).
//!
//! θ_h = angle(n, h) in radians, m = RMS slope angle (roughness). Cook & Torrance leave `c` open ("c · …"),
//! and some course texts multiply by an extra `(n·h)`; we follow Cook & Torrance (no extra
//! cosine) and fix `c` so that `∫ D(h) cosθ_h dω_h = 1`:
//!
//! `c(m) = 1 / (2π ∫₀^{π/2} exp(−θ²/m²) cosθ sinθ dθ)`.
//!
//! The integral has no elementary closed form (it is an error function of complex argument), so it
//! is computed once per `m` by composite Simpson quadrature in f64 over `[0, min(π/2, 12m)]` (the
//! integrand is below e^{−144} beyond 12m) with 2048 intervals: relative error < 1e−9, far below
//! f32. For small m, `c → 1/(π m²)`: the Gaussian and Beckmann distributions agree for small slopes.

use crate::microfacet::{ALPHA_MIN, HalfVector};
use crate::simd::Lane;

/// Normalisation constant `c(m)` [1/sr] of the Gaussian distribution (see the module docs).
/// `m` is clamped to ≥ [`ALPHA_MIN`].
pub fn normalization(m: f32) -> f32 {
    let m = f64::from(m.max(ALPHA_MIN));
    let upper = (12.0 * m).min(std::f64::consts::FRAC_PI_2);
    const N: usize = 2048; // even
    let h = upper / N as f64;
    let f = |t: f64| (-(t / m) * (t / m)).exp() * t.cos() * t.sin();
    let mut sum = f(0.0) + f(upper);
    for i in 1..N {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * f(i as f64 * h);
    }
    let integral = sum * h / 3.0;
    (1.0 / (2.0 * std::f64::consts::PI * integral)) as f32
}

/// Gaussian `D` [1/sr] at `cos_h` = n·h given the precomputed constant `c` = [`normalization`]`(m)`:
/// `c · exp(−(acos(cos_h)/m)²)`; 0 for `cos_h ≤ 0`.
#[inline]
pub fn d_with_normalization(cos_h: f32, m: f32, c: f32) -> f32 {
    d_with_normalization_lanes(cos_h, m, c)
}

/// [`d_with_normalization`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_with_normalization_lanes<F: Lane>(cos_h: F, m: f32, c: f32) -> F {
    let theta = cos_h.min(F::splat(1.0)).acos();
    F::select(cos_h.gt(F::splat(0.0)), of_angle(theta, m, c), F::splat(0.0))
}

/// `c · exp(−(θ/m)²)`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn of_angle<F: Lane>(theta: F, m: f32, c: f32) -> F {
    let t = theta / F::splat(m.max(ALPHA_MIN));
    F::splat(c) * (t * t).exp_neg_normal()
}

/// Gaussian `D` [1/sr] from the un-normalised half vector `h̃ = l + v` ([`HalfVector`]) given
/// `c` = [`normalization`]`(m)`: `c · exp(−(θ_h/m)²)` with `θ_h = atan2(|h̃⊥|, n·h̃)` — the same
/// function as [`d_with_normalization`], but `atan2` keeps full precision near θ_h = 0 where
/// `acos(cos θ_h)` loses half the digits (and see [`crate::microfacet::half`]). 0 for `n·h̃ ≤ 0`.
#[inline]
pub fn d_half_with_normalization(h: &HalfVector<f32>, m: f32, c: f32) -> f32 {
    d_half_with_normalization_lanes(h, m, c)
}

/// [`d_half_with_normalization`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn d_half_with_normalization_lanes<F: Lane>(h: &HalfVector<F>, m: f32, c: f32) -> F {
    let theta = h.perp2.sqrt().atan2(h.n_dot);
    F::select(h.n_dot.gt(F::splat(0.0)), of_angle(theta, m, c), F::splat(0.0))
}

/// Gaussian `D` [1/sr] at `cos_h` for roughness `m` \[rad\]. Computes `c(m)` by quadrature on every
/// call (≈ 2000 exponentials): for many samples build a [`Gaussian`] once instead.
pub fn d(cos_h: f32, m: f32) -> f32 {
    d_with_normalization(cos_h, m, normalization(m))
}

/// A Gaussian distribution with its normalisation constant computed once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gaussian {
    /// RMS slope angle m \[rad\], ≥ [`ALPHA_MIN`].
    pub m: f32,
    /// `c(m)` [1/sr].
    pub c: f32,
}

impl Gaussian {
    /// Gaussian of roughness `m` \[rad\] (clamped to ≥ [`ALPHA_MIN`]: below it the lobe is narrower than
    /// f32 can resolve around cos θ = 1).
    pub fn new(m: f32) -> Self {
        let m = m.max(ALPHA_MIN);
        Self { m, c: normalization(m) }
    }

    /// `D` [1/sr] at `cos_h` = n·h.
    #[inline]
    pub fn d(&self, cos_h: f32) -> f32 {
        d_with_normalization(cos_h, self.m, self.c)
    }

    /// `D` [1/sr] from the un-normalised half vector (see [`d_half_with_normalization`]).
    #[inline]
    pub fn d_half(&self, h: &HalfVector<f32>) -> f32 {
        d_half_with_normalization(h, self.m, self.c)
    }

    /// [`Gaussian::d`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_lanes<F: Lane>(&self, cos_h: F) -> F {
        d_with_normalization_lanes(cos_h, self.m, self.c)
    }

    /// [`Gaussian::d_half`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn d_half_lanes<F: Lane>(&self, h: &HalfVector<F>) -> F {
        d_half_with_normalization_lanes(h, self.m, self.c)
    }
}
