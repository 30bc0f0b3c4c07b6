//! Visible-normal sampling of the (anisotropic) GGX / Trowbridge–Reitz distribution (E. Heitz 2018,
//! "Sampling the GGX Distribution of Visible Normals", JCGT 7(4); pbrt-v4 §9.6.4
//! `TrowbridgeReitzDistribution::Sample_wm`).
//!
//! The view direction is stretched into the configuration of roughness 1, where the visible
//! microfacets seen from `v_h` are the projection of a hemisphere: a uniform point on the disk
//! orthogonal to `v_h`, warped onto the part of the disk the hemisphere shows, lifted onto the
//! hemisphere and un-stretched gives a normal `h` with the density of visible normals
//! `D_v(h) = G1(v) max(0, v·h) D(h) / (n·v)` (Heitz & d'Eon 2014, "Importance Sampling
//! Microfacet-Based BSDFs using the Distribution of Visible Normals", EGSR). Reflecting `v` about
//! `h` gives `l` with `p(l) = D_v(h)/(4 v·h) = G1(v) D(h) / (4 n·v)`. Only `G1(v)` and `D(h)` of the
//! GGX itself enter the density, whatever masking term the model uses.

use std::f32::consts::{FRAC_1_PI, TAU};

use super::cosine_power::{half, reflect};
use super::neg;
use crate::microfacet::ALPHA_MIN;
use crate::simd::{Lane, V3};

/// A visible normal for the local view direction `v` (`v_z > 0`), from `(u1, u2) ∈ [0, 1)²`.
#[inline(always)]
pub fn sample_normal<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    let (ax, ay) = (F::splat(alpha_x.max(ALPHA_MIN)), F::splat(alpha_y.max(ALPHA_MIN)));
    let (zero, one) = (F::splat(0.0), F::splat(1.0));
    // Stretch, and an orthonormal basis (t1, t2, vh) around the stretched view direction.
    let vh = V3 { x: ax * v.x, y: ay * v.y, z: v.z };
    let vh = vh / vh.dot(vh).sqrt();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let has = lensq.gt(zero);
    let inv = one / lensq.sqrt();
    let t1 = V3 { x: F::select(has, neg(vh.y) * inv, one), y: F::select(has, vh.x * inv, zero), z: zero };
    let t2 = super::frame::cross(vh, t1);
    // A uniform point of the unit disk, its second coordinate squeezed onto the visible part.
    let r = u1.sqrt();
    let (s, c) = (F::splat(TAU) * u2).sin_cos();
    let (p1, p2) = (r * c, r * s);
    let w = F::splat(0.5) * (one + vh.z);
    let p2 = (one - w) * (one - p1 * p1).max(zero).sqrt() + w * p2;
    let lift = (one - p1 * p1 - p2 * p2).max(zero).sqrt();
    let nh = t1.scale(p1) + t2.scale(p2) + vh.scale(lift);
    // Un-stretch.
    let ne = V3 { x: ax * nh.x, y: ay * nh.y, z: nh.z.max(zero) };
    ne / ne.dot(ne).sqrt()
}

/// A local direction `l`: `v` reflected about a visible normal ([`sample_normal`]).
#[inline(always)]
pub fn sample<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, u1: F, u2: F) -> V3<F> {
    reflect(v, sample_normal(alpha_x, alpha_y, v, u1, u2))
}

/// GGX `D(h)` [1/sr] for a unit local `h` with `h_z > 0`: `1/(π αx αy (hx²/αx² + hy²/αy² + hz²)²)`.
#[inline(always)]
pub fn d<F: Lane>(alpha_x: f32, alpha_y: f32, h: V3<F>) -> F {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let (x, y) = (h.x / F::splat(ax), h.y / F::splat(ay));
    let t = x * x + y * y + h.z * h.z;
    F::splat(FRAC_1_PI / (ax * ay)) / (t * t)
}

/// Smith `G1(v) = 2/(1 + √(1 + (αx² vx² + αy² vy²)/vz²))` of GGX for a unit local `v` with `v_z > 0`.
#[inline(always)]
pub fn g1<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>) -> F {
    let (ax, ay) = (alpha_x.max(ALPHA_MIN), alpha_y.max(ALPHA_MIN));
    let (x, y) = (F::splat(ax) * v.x, F::splat(ay) * v.y);
    let t2 = (x * x + y * y) / (v.z * v.z);
    F::splat(2.0) / (F::splat(1.0) + (F::splat(1.0) + t2).sqrt())
}

/// The density [1/sr] of [`sample`] at the local direction `l`: `G1(v) D(h)/(4 n·v)`,
/// `h = normalize(l + v)`; 0 where `h` does not exist or is not above the surface.
#[inline(always)]
pub fn pdf<F: Lane>(alpha_x: f32, alpha_y: f32, v: V3<F>, l: V3<F>) -> F {
    let (h, len2) = half(l, v);
    let zero = F::splat(0.0);
    let ok = len2.gt(F::splat(1e-20)) & h.z.gt(zero) & v.dot(h).gt(zero);
    let p = g1(alpha_x, alpha_y, v) * d(alpha_x, alpha_y, h) / (F::splat(4.0) * v.z);
    F::select(ok, p, zero)
}
