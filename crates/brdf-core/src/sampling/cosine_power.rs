//! Cosine-power lobes: directions distributed as `cosⁿ α` about an axis, `p = (n+1)/(2π) cosⁿ α`
//! (Phong 1975's lobe sampled as in Lafortune & Willems 1994, "Using the modified Phong reflectance
//! model for physically based rendering", KU Leuven CW 197; pbrt-v4 §9.3 for the density).
//!
//! Two ways to use the same polar distribution:
//! - [`lobe_sample`] / [`lobe_pdf`]: `l` itself about the axis `a = normalize(C ∘ v)` of a
//!   generalised cosine lobe `(l · (C ∘ v))ⁿ` (Lafortune, Foo, Torrance & Greenberg 1997, "Non-linear
//!   approximation of reflectance functions"). `C = (−1, −1, 1)` is the mirror direction of `v`, i.e.
//!   the Phong lobe `(r·v)ⁿ` (and Strauss's and the course Phong's highlight).
//! - [`half_sample`] / [`half_pdf`]: the half vector `h` about the normal with density
//!   `(n+1)/(2π) (n·h)ⁿ`, then `l = 2(v·h)h − v`, so `p(l) = p(h)/(4 v·h)` (the reflection
//!   Jacobian; Walter et al. 2007 eq. 14). With exponent `m` this matches the normalised Blinn–Phong
//!   lobe `(n·h)^m`; with `m + 1` it is exact microfacet sampling `D(h)(n·h)` of the Blinn–Phong `D`.
//!
//! Both evaluate `cosⁿ` as `exp(n·ln(1 − d))` from the deficit `d = 1 − cos` computed from
//! differences (`|a − l|²/2`, `|h⊥|²/(1 + h_z)`), and sample `1 − cos α = −expm1(ln(1 − u)/(n+1))`, so
//! exponents up to 10⁶ keep their lobe shape in float32 (`cos α` itself rounds to 1 there).

use std::f32::consts::{FRAC_1_PI, TAU};

use super::frame::LaneFrame;
use super::neg;
use crate::simd::{Lane, V3};

/// `(1 − d)ⁿ` for `d < 1` (0 for `d ≥ 1`, i.e. a cosine ≤ 0) [dimensionless].
#[inline(always)]
pub(crate) fn pow_deficit<F: Lane>(d: F, n: f32) -> F {
    let p = (F::splat(n) * neg(d).ln_1p()).exp();
    F::select(d.lt(F::splat(1.0)), p, F::splat(0.0))
}

/// Polar angle of a `cosⁿ` lobe from `u ∈ [0, 1)`: `(cos α, sin α)` with
/// `1 − cos α = −expm1(ln(1 − u)/(n + 1))`.
#[inline(always)]
pub(crate) fn polar<F: Lane>(u: F, n: f32) -> (F, F) {
    let one = F::splat(1.0);
    let d = neg(((one - u).ln() / F::splat(n + 1.0)).map(f32::exp_m1));
    let d = d.clamp(0.0, 1.0);
    (one - d, (d * (F::splat(2.0) - d)).max(F::splat(0.0)).sqrt())
}

/// `(sin α cos φ, sin α sin φ, cos α)` with `φ = 2π u`.
#[inline(always)]
fn spherical<F: Lane>(cos: F, sin: F, u: F) -> V3<F> {
    let (s, c) = (F::splat(TAU) * u).sin_cos();
    V3 { x: sin * c, y: sin * s, z: cos }
}

/// The lobe axis `normalize(C ∘ v)` and `|C ∘ v|` for the local view direction `v`; the axis is the
/// normal where `C ∘ v = 0` (the lobe is then 0 everywhere and has scale 0).
#[inline(always)]
pub fn lobe_axis<F: Lane>(c: [f32; 3], v: V3<F>) -> (V3<F>, F) {
    let cv = V3 { x: F::splat(c[0]) * v.x, y: F::splat(c[1]) * v.y, z: F::splat(c[2]) * v.z };
    let len2 = cv.dot(cv);
    let ok = len2.gt(F::splat(0.0)) & len2.is_finite();
    let len = len2.sqrt();
    let z = V3 { x: F::splat(0.0), y: F::splat(0.0), z: F::splat(1.0) };
    (V3::select(ok, cv / len, z), F::select(ok, len, F::splat(0.0)))
}

/// `|C ∘ v|ⁿ`, the peak value of the lobe `(l · (C ∘ v))ⁿ` (what a mixture weighs it by).
#[inline(always)]
pub fn lobe_scale<F: Lane>(c: [f32; 3], n: f32, v: V3<F>) -> F {
    let (_, len) = lobe_axis(c, v);
    let s = (F::splat(n) * len.ln()).exp();
    F::select(len.gt(F::splat(0.0)), s, F::splat(0.0))
}

/// A local direction distributed as `cosⁿ` about `normalize(C ∘ v)`, from `(u1, u2) ∈ [0, 1)²`.
#[inline(always)]
pub fn lobe_sample<F: Lane>(c: [f32; 3], n: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    let (axis, _) = lobe_axis(c, v);
    let (cos, sin) = polar(u1, n);
    LaneFrame::from_normal(axis).from_local(spherical(cos, sin, u2))
}

/// The density [1/sr] of [`lobe_sample`] at the local direction `l` (unit):
/// `(n+1)/(2π) max(0, a·l)ⁿ`, from the deficit `1 − a·l = |a − l|²/2`.
#[inline(always)]
pub fn lobe_pdf<F: Lane>(c: [f32; 3], n: f32, v: V3<F>, l: V3<F>) -> F {
    let (axis, len) = lobe_axis(c, v);
    let w = axis - l;
    let p = pow_deficit(F::splat(0.5) * w.dot(w), n) * F::splat((n + 1.0) * 0.5 * FRAC_1_PI);
    F::select(len.gt(F::splat(0.0)), p, F::splat(0.0))
}

/// The mirror direction `2(v·h)h − v` of `v` about the unit `h`.
#[inline(always)]
pub(crate) fn reflect<F: Lane>(v: V3<F>, h: V3<F>) -> V3<F> {
    h.scale(F::splat(2.0) * v.dot(h)) - v
}

/// The normalised half vector of unit `l`, `v` and `|l + v|²`; callers treat `|l + v|² ≤ 1e-20`
/// (`l = −v`, no half vector) as density 0.
#[inline(always)]
pub(crate) fn half<F: Lane>(l: V3<F>, v: V3<F>) -> (V3<F>, F) {
    let s = l + v;
    let len2 = s.dot(s);
    (s / len2.sqrt(), len2)
}

/// `1 − h_z` of a unit local half vector above the surface, as `|h⊥|²/(1 + h_z)` (no cancellation).
#[inline(always)]
pub(crate) fn one_minus_z<F: Lane>(h: V3<F>) -> F {
    (h.x * h.x + h.y * h.y) / (F::splat(1.0) + h.z)
}

/// A local direction `l = 2(v·h)h − v` with `h` distributed as `(n+1)/(2π) (n·h)ⁿ`.
#[inline(always)]
pub fn half_sample<F: Lane>(n: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    let (cos, sin) = polar(u1, n);
    reflect(v, spherical(cos, sin, u2))
}

/// The density [1/sr] of [`half_sample`] at the local direction `l`:
/// `(n+1)/(2π) (n·h)ⁿ / (4 v·h)` with `h = normalize(l + v)`; 0 where `h` is at or below the surface
/// or does not exist.
#[inline(always)]
pub fn half_pdf<F: Lane>(n: f32, v: V3<F>, l: V3<F>) -> F {
    let (h, len2) = half(l, v);
    let zero = F::splat(0.0);
    let ok = len2.gt(F::splat(1e-20)) & h.z.gt(zero);
    let ph = pow_deficit(one_minus_z(h), n) * F::splat((n + 1.0) * 0.5 * FRAC_1_PI);
    let vh = v.dot(h);
    F::select(ok & vh.gt(zero), ph / (F::splat(4.0) * vh), zero)
}
