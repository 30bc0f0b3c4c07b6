//! Ward's half-vector sampler (G. J. Ward 1992, "Measuring and Modeling Anisotropic Reflection",
//! SIGGRAPH, §4; with the density and weight of B. Walter 2005, "Notes on the Ward BRDF", Cornell
//! PCG-05-06, eqs. 6–9): the slopes of `h` are drawn from Ward's elliptical Gaussian
//! `P₂₂(s) = exp(−(s_x²/αx² + s_y²/αy²))/(π αx αy)`, which in Walter's polar form is
//!
//! ```text
//! φ_h = atan(αy/αx · tan 2πu₂),   tan²θ_h = −ln u₁ / (cos²φ_h/αx² + sin²φ_h/αy²).
//! ```
//!
//! Here the same Gaussian is drawn in Cartesian slope coordinates (Box–Muller: `r = √(−ln(1 − u₁))`,
//! `s = r (αx cos 2πu₂, αy sin 2πu₂)`), which needs no quadrant bookkeeping and is the same
//! distribution. Since `dω_h = cos³θ_h d²s`, the density of `h` is `P₂₂/cos³θ_h = D(h) cos θ_h` with
//! the Beckmann `D` that Ward's Gaussian is (Walter 2005), and reflecting `v` gives
//! `p(l) = D(h) cos θ_h / (4 v·h)` — Walter's corrected density (Ward 1992's printed weight was off).
//! This is also plain microfacet sampling `D(h) cos θ_h` of the Beckmann distribution (Walter et
//! al. 2007 eq. 28–29).

use std::f32::consts::TAU;

use super::beckmann::d;
use super::cosine_power::{half, reflect};
use super::neg;
use crate::microfacet::ALPHA_MIN;
use crate::simd::{Lane, V3};

/// A half vector with density `D(h) cos θ_h` (Beckmann `D`), from `(u1, u2) ∈ [0, 1)²`.
#[inline(always)]
pub fn sample_normal<F: Lane>(alpha_x: f32, alpha_y: f32, u1: F, u2: F) -> V3<F> {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let r = neg((F::splat(1.0) - u1).ln()).max(F::splat(0.0)).sqrt();
    let (s, c) = (F::splat(TAU) * u2).sin_cos();
    let m = V3 { x: neg(F::splat(ax) * r * c), y: neg(F::splat(ay) * r * s), z: F::splat(1.0) };
    m / m.dot(m).sqrt()
}

/// A local direction `l`: `v` reflected about [`sample_normal`].
#[inline(always)]
pub fn sample<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    reflect(v, sample_normal(alpha_x, alpha_y, u1, u2))
}

/// The density [1/sr] of [`sample`] at the local direction `l`: `D(h) cos θ_h / (4 v·h)`,
/// `h = normalize(l + v)`; 0 where `h` does not exist, is not above the surface or faces away from `v`.
#[inline(always)]
pub fn pdf<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, l: V3<F>) -> F {
    let (h, len2) = half(l, v);
    let zero = F::splat(0.0);
    let vh = v.dot(h);
    let ok = len2.gt(F::splat(1e-20)) & h.z.gt(zero) & vh.gt(zero);
    F::select(ok, d(alpha_x, alpha_y, h) * h.z / (F::splat(4.0) * vh), zero)
}
