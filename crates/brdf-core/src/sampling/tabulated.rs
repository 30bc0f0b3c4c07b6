//! A sampler for tabulated (measured) isotropic BRDFs ([`crate::measured::Tabulated`]): for each of
//! [`SLICES`] view angles, the reflected radiance `f·cos θ_l` is tabulated over half vectors and
//! sampled with a [`Distribution2D`] (pbrt-v4 §A.4.2; the idea of tabulating a per-view warp of a
//! measured BRDF is Matusik et al. 2003's, "Efficient Isotropic BRDF Measurement", §6).
//!
//! ## The grid
//! Half vectors are parametrised like the MERL table itself: `θ_h = (π/2) y²` (the square-root
//! spacing puts rows near the specular peak) and `φ_h = 2π x` measured from the azimuth of `v`, with
//! `(x, y) ∈ [0, 1)²` on [`PHI_CELLS`] × [`THETA_CELLS`] cells — except in the first row
//! (`y < y₀ = 1/THETA_CELLS`), where `1 − cos θ_h` is linear in `y` (equal area), so that the density
//! stays bounded at the pole (with `θ_h ∝ y²` all the way a constant cell density becomes
//! `∝ θ_h^{−3/2}` in solid angle there). A cell's value is, at its centre,
//!
//! ```text
//! mean_rgb f(l, v) · cos θ_l · |dω_l/dx dy|,   l = 2(v·h)h − v,   |dω_l/dx dy| = 4 (v·h) · 2π · |d cos θ_h/dy|,
//! ```
//!
//! so the distribution is proportional to `f·cos` over the hemisphere of `l`, up to the
//! piecewise-constant approximation. The density of a direction is the cell's density divided by
//! that Jacobian at the direction itself (exact, not the cell centre's), so `sample` and `pdf` agree
//! exactly; the approximation only costs variance. The view angle picks the nearest slice
//! (`θ_v` in [`SLICES`] equal steps), the same in `sample` and `pdf`.
//!
//! A table is sampled together with a cosine lobe ([`DEFENSIVE`] of the samples, chosen by the
//! mixture in [`super::Sampler`]), so that every direction where the interpolated table is non-zero
//! but a coarse cell held 0 still has a positive density (defensive importance sampling, Hesterberg
//! 1995, "Weighted average importance sampling and defensive mixture distributions").
//!
//! The slices are built on first use ([`SamplerCache`]), in parallel, deterministically:
//! 32 × 64 × 128 look-ups, a few tens of milliseconds for a MERL table.

use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::sync::{Arc, OnceLock};

use glam::Vec3A;
use rayon::prelude::*;

use super::distribution::Distribution2D;
use crate::measured::Tabulated;
use crate::simd::{Lane, V3};
use crate::{BrdfError, Geometry};

/// View-angle slices.
pub const SLICES: usize = 32;
/// Cells in `y` (`θ_h = (π/2) y²`).
pub const THETA_CELLS: usize = 64;
/// Cells in `x` (`φ_h = 2π x` from the azimuth of `v`).
pub const PHI_CELLS: usize = 128;
/// Fraction of a measured model's samples drawn from the cosine lobe.
pub const DEFENSIVE: f32 = 0.1;

/// The tabulated distributions of one table.
#[derive(Debug, Clone, PartialEq)]
pub struct TabulatedSampler {
    slices: Vec<Distribution2D>,
}

/// The unit vector along `v`'s azimuth in the tangent plane (`x` where `v` is the normal).
#[inline]
fn azimuth_axis(v: Vec3A) -> (f32, f32) {
    let s = (v.x * v.x + v.y * v.y).sqrt();
    if s > 0.0 { (v.x / s, v.y / s) } else { (1.0, 0.0) }
}

/// The first row's edge `y₀` and `1 − cos θ_h` there (`θ_h = (π/2) y₀²`).
#[inline]
fn first_row() -> (f32, f32) {
    let y0 = 1.0 / THETA_CELLS as f32;
    let half = 0.5 * FRAC_PI_2 * y0 * y0;
    (y0, 2.0 * half.sin() * half.sin())
}

/// `(cos θ_h, sin θ_h, |d cos θ_h/dy|)` at `y` (module docs).
#[inline]
fn polar(y: f32) -> (f32, f32, f32) {
    let (y0, d0) = first_row();
    if y < y0 {
        let d = d0 * y / y0;
        (1.0 - d, (d * (2.0 - d)).max(0.0).sqrt(), d0 / y0)
    } else {
        let (s, c) = (FRAC_PI_2 * y * y).sin_cos();
        (c, s, s * PI * y)
    }
}

/// The inverse of [`polar`] for a unit half vector above the surface (`1 − cos θ_h = d`, `sin θ_h`).
#[inline]
fn y_of(d: f32, sin: f32, cos: f32) -> f32 {
    let (y0, d0) = first_row();
    if d < d0 { (y0 * d / d0).min(y0) } else { (sin.atan2(cos) / FRAC_PI_2).sqrt().max(y0) }
}

impl TabulatedSampler {
    /// Tabulate `table` (module docs).
    pub fn new(table: &Tabulated) -> Result<Self, BrdfError> {
        let slices = (0..SLICES)
            .into_par_iter()
            .map(|k| {
                let tv = (k as f32 + 0.5) / SLICES as f32 * FRAC_PI_2;
                let v = Vec3A::new(tv.sin(), 0.0, tv.cos());
                let mut func = Vec::with_capacity(THETA_CELLS * PHI_CELLS);
                for i in 0..THETA_CELLS {
                    let (ch, sh, jy) = polar((i as f32 + 0.5) / THETA_CELLS as f32);
                    for j in 0..PHI_CELLS {
                        let (sp, cp) = ((j as f32 + 0.5) / PHI_CELLS as f32 * TAU).sin_cos();
                        let h = Vec3A::new(sh * cp, sh * sp, ch);
                        let vh = v.dot(h);
                        let l = 2.0 * vh * h - v;
                        let value = if vh > 0.0 && l.z > 0.0 {
                            let f = table.eval(&Geometry::from_unit(l, v, Vec3A::Z));
                            (f.x + f.y + f.z) / 3.0 * l.z * 4.0 * vh * TAU * jy
                        } else {
                            0.0
                        };
                        func.push(if value.is_finite() { value.max(0.0) } else { 0.0 });
                    }
                }
                Distribution2D::new("table", &func, PHI_CELLS, THETA_CELLS)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { slices })
    }

    #[inline]
    fn slice(&self, v: Vec3A) -> &Distribution2D {
        let theta = (v.x * v.x + v.y * v.y).sqrt().atan2(v.z);
        let k = (theta / FRAC_PI_2 * SLICES as f32) as usize;
        &self.slices[k.min(SLICES - 1)]
    }

    /// A local direction for the local view `v` (`v_z > 0`), from `(u1, u2) ∈ [0, 1)²`.
    pub fn sample_one(&self, v: Vec3A, u1: f32, u2: f32) -> Vec3A {
        let ([x, y], _) = self.slice(v).sample(u1, u2);
        let (ch, sh, _) = polar(y);
        let (sp, cp) = (TAU * x).sin_cos();
        let (ex, ey) = azimuth_axis(v);
        let (hx, hy) = (sh * cp, sh * sp);
        let h = Vec3A::new(hx * ex - hy * ey, hx * ey + hy * ex, ch);
        2.0 * v.dot(h) * h - v
    }

    /// The density [1/sr] of [`TabulatedSampler::sample_one`] at the local direction `l` (unit);
    /// 0 where the half vector does not exist or is not above the surface (capped at 1e30, which only
    /// `v·h → 0` approaches).
    pub fn pdf_one(&self, v: Vec3A, l: Vec3A) -> f32 {
        let s = l + v;
        let len2 = s.length_squared();
        if !(len2 > 1e-20) {
            return 0.0;
        }
        let h = s / len2.sqrt();
        let vh = v.dot(h);
        if !(h.z > 0.0 && vh > 0.0) {
            return 0.0;
        }
        let (ex, ey) = azimuth_axis(v);
        let (hx, hy) = (h.x * ex + h.y * ey, h.y * ex - h.x * ey);
        let sh = (hx * hx + hy * hy).sqrt();
        let y = y_of((hx * hx + hy * hy) / (1.0 + h.z), sh, h.z);
        let mut x = hy.atan2(hx) / TAU;
        if x < 0.0 {
            x += 1.0;
        }
        let p = self.slice(v).pdf([x, y]);
        let den = 4.0 * vh * TAU * polar(y).2;
        if p == 0.0 { 0.0 } else { (p / den).min(1e30) }
    }

    /// [`TabulatedSampler::sample_one`] on lanes (lane by lane: same bits).
    #[inline]
    pub fn sample<F: Lane>(&self, v: V3<F>, u1: F, u2: F) -> V3<F> {
        V3::from_fn(|i| {
            let vi = Vec3A::new(v.x.lane(i), v.y.lane(i), v.z.lane(i));
            self.sample_one(vi, u1.lane(i), u2.lane(i)).into()
        })
    }

    /// [`TabulatedSampler::pdf_one`] on lanes.
    #[inline]
    pub fn pdf<F: Lane>(&self, v: V3<F>, l: V3<F>) -> F {
        F::from_fn(|i| {
            let at = |w: &V3<F>| Vec3A::new(w.x.lane(i), w.y.lane(i), w.z.lane(i));
            self.pdf_one(at(&v), at(&l))
        })
    }
}

/// The lazily built [`TabulatedSampler`] of a table, shared by clones. It is derived data: two caches
/// always compare equal, so a table's equality is its values'.
#[derive(Default, Clone)]
pub struct SamplerCache(OnceLock<Result<Arc<TabulatedSampler>, BrdfError>>);

impl SamplerCache {
    /// The sampler of `table`, built on the first call.
    pub fn get_or_build(&self, table: &Tabulated) -> Result<Arc<TabulatedSampler>, BrdfError> {
        self.0.get_or_init(|| TabulatedSampler::new(table).map(Arc::new)).clone()
    }
}

impl PartialEq for SamplerCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for SamplerCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.get().is_some() { "SamplerCache(built)" } else { "SamplerCache(empty)" })
    }
}
