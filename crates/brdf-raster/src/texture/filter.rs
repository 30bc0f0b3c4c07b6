//! Reading a texture: nearest texel, bilinear interpolation of texel centres, and trilinear
//! mip-mapping with the level of detail of OpenGL 4.6 §8.14.1 (eq. 8.7) from the screen-space
//! derivatives of the texture coordinates.
//!
//! Coordinates follow glTF 2.0 (§3.8.4 "texture coordinates"): `(0, 0)` is the top-left corner of the
//! image and `(1, 1)` its bottom-right corner, `v` grows downward; texel `(i, j)` (column, row, row 0
//! at the top) has its centre at `((i + ½)/W, (j + ½)/H)`.

use glam::{Vec2, Vec4};

use super::Texture;
use super::image::Level;
use super::sampler::{Filter, Wrap};

/// The texel of `level` holding point `uv`: `(⌊u·W⌋, ⌊v·H⌋)`, wrapped.
#[inline(always)]
pub(super) fn nearest(level: &Level, channels: usize, wrap: (Wrap, Wrap), uv: Vec2) -> Vec4 {
    let x = (wrap.0.reduce(f64::from(uv.x)) * f64::from(level.width)).floor() as i64;
    let y = (wrap.1.reduce(f64::from(uv.y)) * f64::from(level.height)).floor() as i64;
    level.texel(channels, wrap.0.index(x, level.width), wrap.1.index(y, level.height))
}

/// Bilinear interpolation of the four texel centres around `uv`: with `x = u·W − ½`, `i = ⌊x⌋`,
/// `α = x − i` (and `y`, `j`, `β` alike), `(1−α)(1−β)·t(i, j) + α(1−β)·t(i+1, j) + (1−α)β·t(i, j+1)
/// + αβ·t(i+1, j+1)`, every index wrapped.
#[inline(always)]
pub(super) fn bilinear(level: &Level, channels: usize, wrap: (Wrap, Wrap), uv: Vec2) -> Vec4 {
    // f64 so that large repeat counts (u = 1000.3) keep their fraction; reduced by whole periods first so
    // that the indices need no division to wrap.
    let x = wrap.0.reduce(f64::from(uv.x)) * f64::from(level.width) - 0.5;
    let y = wrap.1.reduce(f64::from(uv.y)) * f64::from(level.height) - 0.5;
    let (xf, yf) = (x.floor(), y.floor());
    let (a, b) = ((x - xf) as f32, (y - yf) as f32);
    let (i, j) = (xf as i64, yf as i64);
    let (i0, i1) = (wrap.0.index(i, level.width), wrap.0.index(i + 1, level.width));
    let (j0, j1) = (wrap.1.index(j, level.height), wrap.1.index(j + 1, level.height));
    let top = level.texel(channels, i0, j0) * (1.0 - a) + level.texel(channels, i1, j0) * a;
    let bottom = level.texel(channels, i0, j1) * (1.0 - a) + level.texel(channels, i1, j1) * a;
    top * (1.0 - b) + bottom * b
}

/// Level of detail `λ = log2 ρ`, `ρ = max(|∂(uW, vH)/∂x|, |∂(uW, vH)/∂y|)` (OpenGL 4.6 eq. 8.7): the
/// base-level texels one screen step (a sample) covers, along the longer of the two screen axes, in
/// log2. `−∞` when the coordinates do not change.
#[inline(always)]
pub fn level_of_detail(width: u32, height: u32, duv_dx: Vec2, duv_dy: Vec2) -> f32 {
    let size = Vec2::new(width as f32, height as f32);
    let rho2 = (duv_dx * size).length_squared().max((duv_dy * size).length_squared());
    0.5 * rho2.log2()
}

impl Texture {
    /// The filtered value at `uv` (glTF's convention, see the module docs) as linear RGBA, for a sample
    /// whose texture coordinates change by `duv_dx` per sample column and `duv_dy` per sample row.
    /// One channel reads as `(c, c, c, 1)`, three as `(r, g, b, 1)`.
    ///
    /// Nearest and bilinear read the base level; trilinear reads level `λ`
    /// ([`level_of_detail`], clamped to `[0, levels − 1]`): bilinear in levels `⌊λ⌋` and `⌊λ⌋ + 1`,
    /// blended by `λ − ⌊λ⌋`; at `λ ≤ 0` (magnification) the base level, bilinear. Non-finite
    /// coordinates read texel `(0, 0)`.
    #[inline]
    pub fn sample(&self, uv: Vec2, duv_dx: Vec2, duv_dy: Vec2) -> Vec4 {
        let c = self.channels;
        let wrap = (self.sampler.wrap_u, self.sampler.wrap_v);
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        let base = &self.levels[0];
        match self.sampler.filter {
            Filter::Nearest => nearest(base, c, wrap, uv),
            Filter::Bilinear => bilinear(base, c, wrap, uv),
            Filter::Trilinear => {
                let lambda = level_of_detail(base.width, base.height, duv_dx, duv_dy);
                let top = (self.levels.len() - 1) as f32;
                // NaN (infinite derivatives) reads the coarsest level.
                let lambda = if lambda.is_nan() { top } else { lambda.clamp(0.0, top) };
                let d = lambda.floor();
                let (k, t) = (d as usize, lambda - d);
                let a = bilinear(&self.levels[k], c, wrap, uv);
                if t == 0.0 {
                    return a;
                }
                let b = bilinear(&self.levels[k + 1], c, wrap, uv);
                a * (1.0 - t) + b * t
            }
        }
    }
}
