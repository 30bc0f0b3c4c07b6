//! The half vector of a reflection kept un-normalised, for isotropic distributions evaluated without
//! cancellation when `l` and `v` are nearly opposite.
//!
//! With `h̃ = l + v` (so `h = h̃/|h̃|`), an isotropic `D` needs only the angle θ_h between `h` and `n`,
//! and every form of it can be written with three numbers that need no `1 − cos²`:
//!
//! - `n·h̃` (= `|h̃| cos θ_h`),
//! - `|h̃⊥|² = |h̃ − (n·h̃) n|²` (= `|h̃|² sin²θ_h`), the part of `h̃` in the tangent plane,
//! - `|h̃|²`,
//!
//! so that `cos²θ_h = (n·h̃)²/|h̃|²` and `tan²θ_h = |h̃⊥|²/(n·h̃)²`.
//!
//! Why: the textbook route `|h̃|² = 2 + 2 l·v`, `n·h = (n·l + n·v)/|h̃|`, then `1 − (n·h)²` inside
//! `tan²θ_h`, cancels twice. When `l ≈ −v` (both grazing, on opposite sides), `2 + 2 l·v` is the
//! difference of two numbers near 2: with `|h̃| = 0.01` it keeps only ~3 of f32's 7 digits. And at a
//! sharp lobe's peak `1 − (n·h)²` is ~α² of 1, losing another `log₁₀(1/α²)` digits. D is steep there
//! (GGX `∝ 1/(α² + tan²θ)²`): Cook–Torrance at α = 0.05 was off against a float64 reference by up to
//! 160 % for `|h̃|` in 0.01–0.03 and 100× below. Summing `l + v` component by component rounds once
//! per component, relative to the component itself (small where `|h̃|` is); the projection
//! `h̃ − (n·h̃) n` removes at most `|h̃|`, so its rounding is a few ulps of `|h̃|`: small against
//! `|h̃⊥|` unless θ_h is tiny, and there `tan²θ_h ≪ α²` and D hardly depends on it. What remains is
//! the rounding of the unit `l` and `v` themselves (≈ 6e−8 per component), which turns `h` by
//! ≈ 1e−7/|h̃| rad: no float32 implementation can do better from float32 unit vectors (measured: the
//! float64 D of the float32-normalised vectors differs from that of the exact ones by up to 1.4e−4
//! at `|h̃|` = 0.01, α = 0.05, and this form stays within that).

use crate::simd::{Lane, V3};

/// The un-normalised half vector `h̃ = l + v` seen from the normal `n` (see the module docs):
/// `n·h̃`, `|h̃ − (n·h̃) n|²` and `|h̃|²` (unit l, v, n; dimensionless).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfVector<F> {
    /// `n·h̃ = n·l + n·v` (> 0 where h is above the surface).
    pub n_dot: F,
    /// `|h̃⊥|² = |h̃ − (n·h̃) n|² = |h̃|² sin²θ_h`.
    pub perp2: F,
    /// `|h̃|² = 2 + 2 l·v` (0 for `l = −v`, where there is no half vector).
    pub len2: F,
}

impl<F: Lane> HalfVector<F> {
    /// From unit `l`, `v`, `n`: `h̃` summed component by component, then projected on `n` and on
    /// its tangent plane (no cancellation beyond one rounding per component; module docs).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn from_directions(l: V3<F>, v: V3<F>, n: V3<F>) -> Self {
        let s = l + v;
        let n_dot = s.dot(n);
        let p = V3 { x: s.x - n_dot * n.x, y: s.y - n_dot * n.y, z: s.z - n_dot * n.z };
        Self { n_dot, perp2: p.dot(p), len2: s.dot(s) }
    }

    /// From the cosines alone: `n·h̃ = n·l + n·v`, `|h̃|² = 2 + 2 l·v`, `|h̃⊥|² = |h̃|² − (n·h̃)²`
    /// (clamped at 0). Exact in real arithmetic, but it cancels in f32 where `l ≈ −v` or where
    /// `h ≈ n` (module docs): prefer [`HalfVector::from_directions`] when the vectors are at hand.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn from_cosines(nl: F, nv: F, lv: F) -> Self {
        let len2 = F::splat(2.0) + F::splat(2.0) * lv;
        let n_dot = nl + nv;
        let perp2 = (len2 - n_dot * n_dot).max(F::splat(0.0));
        Self { n_dot, perp2, len2 }
    }

    /// Lane `i` as a scalar half vector.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lane(&self, i: usize) -> HalfVector<f32> {
        HalfVector { n_dot: self.n_dot.lane(i), perp2: self.perp2.lane(i), len2: self.len2.lane(i) }
    }

    /// `tan²θ_h = |h̃⊥|²/(n·h̃)²` (+∞ when `h` lies in the tangent plane).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn tan2(&self) -> F {
        self.perp2 / (self.n_dot * self.n_dot)
    }
}
