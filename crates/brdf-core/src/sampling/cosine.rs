//! Hemisphere sampling. Cosine-weighted, `p(l) = cos θ_l / π` (Malley's method: a uniform point on the
//! unit disk lifted to the hemisphere; pbrt-v4 §A.5.3 `SampleCosineHemisphere`). The disk point comes
//! from Shirley & Chiu's concentric map (1997, "A Low Distortion Map Between Disk and Square", JGT
//! 2(3)), which keeps stratified `u` stratified. `f·cos/p = π f`: exact importance sampling for
//! Lambert, and the diffuse lobe of every other model (Oren–Nayar, the `kd` terms). Uniform,
//! `p(l) = 1/(2π)` ([`sample_uniform`]; pbrt-v4 §A.5.2): for integrands `f·cos` that do not vanish at
//! the horizon, such as the toon bands (whose `shade` is a constant per band, so `f = shade/cos θ`
//! and cosine-weighted weights `π·shade/cos θ` would have infinite variance).

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4};

use crate::simd::{Lane, V3};

/// A point of the unit disk from `(u1, u2) ∈ [0, 1)²` by the concentric map (area-preserving up to
/// a constant: uniform in, uniform out).
#[inline(always)]
pub fn concentric_disk<F: Lane>(u1: F, u2: F) -> (F, F) {
    let one = F::splat(1.0);
    let (a, b) = (F::splat(2.0) * u1 - one, F::splat(2.0) * u2 - one);
    // |a| > |b|: r = a, φ = π/4 · b/a; else r = b, φ = π/2 − π/4 · a/b. At a = b = 0 both quotients
    // are 0/0: the point is the centre, set explicitly.
    let wide = a.abs().gt(b.abs());
    let r = F::select(wide, a, b);
    let phi =
        F::select(wide, F::splat(FRAC_PI_4) * (b / a), F::splat(FRAC_PI_2) - F::splat(FRAC_PI_4) * (a / b));
    let (s, c) = phi.sin_cos();
    let centre = a.eq(F::splat(0.0)) & b.eq(F::splat(0.0));
    let zero = F::splat(0.0);
    (F::select(centre, zero, r * c), F::select(centre, zero, r * s))
}

/// A local direction (z = normal) with density `cos θ / π` from `(u1, u2) ∈ [0, 1)²`.
#[inline(always)]
pub fn sample<F: Lane>(u1: F, u2: F) -> V3<F> {
    let (x, y) = concentric_disk(u1, u2);
    let z = (F::splat(1.0) - x * x - y * y).max(F::splat(0.0)).sqrt();
    V3 { x, y, z }
}

/// The density `max(cos θ, 0)/π` [1/sr] of [`sample`] at the local direction `l`.
#[inline(always)]
pub fn pdf<F: Lane>(l: V3<F>) -> F {
    l.z.max(F::splat(0.0)) * F::splat(FRAC_1_PI)
}

/// A local direction uniform over the upper hemisphere, `p = 1/(2π)`: `cos θ = 1 − u1`, `φ = 2π u2`.
#[inline(always)]
pub fn sample_uniform<F: Lane>(u1: F, u2: F) -> V3<F> {
    let z = F::splat(1.0) - u1;
    let r = (F::splat(1.0) - z * z).max(F::splat(0.0)).sqrt();
    let (s, c) = (F::splat(std::f32::consts::TAU) * u2).sin_cos();
    V3 { x: r * c, y: r * s, z }
}

/// The density `1/(2π)` [1/sr] of [`sample_uniform`] where `l_z > 0`.
#[inline(always)]
pub fn pdf_uniform<F: Lane>(l: V3<F>) -> F {
    F::select(l.z.gt(F::splat(0.0)), F::splat(0.5 * FRAC_1_PI), F::splat(0.0))
}
