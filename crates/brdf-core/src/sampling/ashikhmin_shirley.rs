//! Ashikhmin & Shirley's half-vector sampler (M. Ashikhmin, P. Shirley 2000, "An Anisotropic Phong
//! BRDF Model", JGT 5(2), eqs. 9–10): with `u₁` split into the four quadrants of the tangent plane,
//!
//! ```text
//! φ_h = atan(√((nu + 1)/(nv + 1)) · tan(π ξ/2))   in the first quadrant (ξ ∈ [0, 1)), mirrored into
//!       the others;                                cos θ_h = (1 − u₂)^{1/(nu cos²φ_h + nv sin²φ_h + 1)},
//! ```
//!
//! whose density is exactly their `p_h(h) = √((nu+1)(nv+1))/(2π) · (n·h)^{nu cos²φ_h + nv sin²φ_h}`
//! ([`crate::microfacet::ashikhmin_shirley::pdf_h`]); reflecting `v` gives `p(l) = p_h/(4 v·h)`.
//! Raising both exponents by one samples `D(h) cos θ_h` of the microfacet-normalised AS distribution.
//! Powers and `1 − cos θ_h` are evaluated from deficits as in [`super::cosine_power`], so exponents
//! up to 10⁶ keep their shape.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, PI, TAU};

use super::cosine_power::{half, one_minus_z, reflect};
use super::neg;
use crate::simd::{Lane, V3};

/// `nu cos²φ + nv sin²φ` from the tangent-plane components of a unit `h`; `(nu + nv)/2` at the pole.
#[inline(always)]
fn exponent<F: Lane>(nu: f32, nv: f32, h: V3<F>) -> F {
    let s2 = h.x * h.x + h.y * h.y;
    let e = (F::splat(nu) * h.x * h.x + F::splat(nv) * h.y * h.y) / s2;
    F::select(s2.gt(F::splat(0.0)), e, F::splat(0.5 * (nu + nv)))
}

/// A half vector with density `p_h` (module docs), from `(u1, u2) ∈ [0, 1)²`.
#[inline(always)]
pub fn sample_normal<F: Lane>(nu: f32, nv: f32, u1: F, u2: F) -> V3<F> {
    let (nu, nv) = (nu.max(0.0), nv.max(0.0));
    let one = F::splat(1.0);
    // Quadrant q = ⌊4 u₁⌋ and ξ ∈ [0, 1) within it.
    let x4 = F::splat(4.0) * u1;
    let q = x4.floor().clamp(0.0, 3.0);
    let xi = x4 - q;
    let phi1 = (F::splat(((nu + 1.0) / (nv + 1.0)).sqrt()) * (F::splat(FRAC_PI_2) * xi).tan()).atan();
    // φ = φ₁, π − φ₁, π + φ₁, 2π − φ₁ in quadrants 0–3.
    let (q1, q2, q3) = (q.eq(one), q.eq(F::splat(2.0)), q.eq(F::splat(3.0)));
    let phi = F::select(
        q1,
        F::splat(PI) - phi1,
        F::select(q2, F::splat(PI) + phi1, F::select(q3, F::splat(TAU) - phi1, phi1)),
    );
    let (s, c) = phi.sin_cos();
    let e = F::splat(nu) * c * c + F::splat(nv) * s * s;
    // 1 − cos θ = −expm1(ln(1 − u₂)/(e + 1)).
    let d = neg(((one - u2).ln() / (e + one)).map(f32::exp_m1)).clamp(0.0, 1.0);
    let sin_t = (d * (F::splat(2.0) - d)).max(F::splat(0.0)).sqrt();
    V3 { x: sin_t * c, y: sin_t * s, z: one - d }
}

/// A local direction `l`: `v` reflected about [`sample_normal`].
#[inline(always)]
pub fn sample<F: Lane>(nu: f32, nv: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    reflect(v, sample_normal(nu, nv, u1, u2))
}

/// `p_h(h)` [1/sr] for a unit local `h` with `h_z > 0`.
#[inline(always)]
pub fn pdf_h<F: Lane>(nu: f32, nv: f32, h: V3<F>) -> F {
    let (nu, nv) = (nu.max(0.0), nv.max(0.0));
    let c = ((nu + 1.0) * (nv + 1.0)).sqrt() * 0.5 * FRAC_1_PI;
    let d = one_minus_z(h);
    // (1 − d)^e with a per-lane exponent: exp(e ln(1 − d)).
    let p = (exponent(nu, nv, h) * neg(d).ln_1p()).exp();
    F::splat(c) * F::select(d.lt(F::splat(1.0)), p, F::splat(0.0))
}

/// The density [1/sr] of [`sample`] at the local direction `l`: `p_h(h)/(4 v·h)`,
/// `h = normalize(l + v)`; 0 where `h` does not exist, is not above the surface or faces away from `v`.
#[inline(always)]
pub fn pdf<F: Lane>(nu: f32, nv: f32, v: V3<F>, l: V3<F>) -> F {
    let (h, len2) = half(l, v);
    let zero = F::splat(0.0);
    let vh = v.dot(h);
    let ok = len2.gt(F::splat(1e-20)) & h.z.gt(zero) & vh.gt(zero);
    F::select(ok, pdf_h(nu, nv, h) / (F::splat(4.0) * vh), zero)
}
