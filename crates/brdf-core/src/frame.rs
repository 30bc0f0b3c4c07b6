//! Orthonormal shading frames: world directions to the local frame where z is the normal (pbrt-v4 `Frame`).

use glam::Vec3A;

use crate::geometry::LaneGeometry;
use crate::simd::{Lane, V3};

/// An orthonormal basis `{t, b, n}`; local coordinates are `(w·t, w·b, w·n)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingFrame {
    /// Tangent (local x).
    pub t: Vec3A,
    /// Bitangent (local y) = n × t.
    pub b: Vec3A,
    /// Unit normal (local z).
    pub n: Vec3A,
}

impl ShadingFrame {
    /// Frame from a unit normal alone; the tangent is chosen without branches on the sign of `n.z`
    /// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"), so isotropic models do not care.
    /// [`LaneFrame::from_normal`] with one lane.
    #[inline]
    pub fn from_normal(n: Vec3A) -> Self {
        LaneFrame::<f32>::from_normal(n.into()).into()
    }

    /// Frame from a unit normal and a tangent hint: the tangent is Gram-Schmidt orthogonalised
    /// against `n`. Falls back to [`ShadingFrame::from_normal`] when the hint is (nearly) parallel to `n`
    /// or not finite. [`LaneFrame::from_normal_tangent`] with one lane.
    #[inline]
    pub fn from_normal_tangent(n: Vec3A, tangent: Vec3A) -> Self {
        LaneFrame::<f32>::from_normal_tangent(n.into(), tangent.into(), true).into()
    }

    /// World direction → local coordinates (z along the normal).
    #[inline]
    pub fn to_local(&self, w: Vec3A) -> Vec3A {
        Vec3A::new(w.dot(self.t), w.dot(self.b), w.dot(self.n))
    }

    /// Local coordinates → world direction.
    #[inline]
    pub fn from_local(&self, w: Vec3A) -> Vec3A {
        self.t * w.x + self.b * w.y + self.n * w.z
    }
}

/// [`ShadingFrame`] for `F::LANES` samples: the one place its construction is written (the scalar
/// frame is this with `F = f32`, the same bits).
#[derive(Debug, Clone, Copy)]
pub struct LaneFrame<F: Lane> {
    /// Tangent (local x).
    pub t: V3<F>,
    /// Bitangent (local y) = n × t.
    pub b: V3<F>,
    /// Unit normal (local z).
    pub n: V3<F>,
}

impl<F: Lane> LaneFrame<F> {
    /// [`ShadingFrame::from_normal`] on lanes (Duff et al. 2017).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn from_normal(n: V3<F>) -> Self {
        let one = F::splat(1.0);
        let sign = one.copysign(n.z);
        let a = F::splat(-1.0) / (sign + n.z);
        let b = n.x * n.y * a;
        // −x as x·(−1): the same bits in every lane type (wide's negation is 0 − x, +0 for +0).
        let minus = F::splat(-1.0);
        let t = V3 { x: one + sign * n.x * n.x * a, y: sign * b, z: sign * minus * n.x };
        let bt = V3 { x: b, y: sign + n.y * n.y * a, z: n.y * minus };
        Self { t, b: bt, n }
    }

    /// [`ShadingFrame::from_normal_tangent`] on lanes; `tangent_ok` false (a lane without a usable
    /// hint) falls back to [`LaneFrame::from_normal`] like a degenerate hint does.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn from_normal_tangent(n: V3<F>, tangent: V3<F>, tangent_ok: F::Mask) -> Self {
        let fallback = Self::from_normal(n);
        let t = tangent - n.scale(n.dot(tangent));
        let len2 = t.dot(t);
        let ok = tangent_ok & len2.gt(F::splat(1e-12)) & len2.is_finite();
        let t = t / len2.sqrt();
        let b = n.cross(t);
        Self { t: V3::select(ok, t, fallback.t), b: V3::select(ok, b, fallback.b), n }
    }

    /// The frame of a geometry: from its tangent hint where usable, else from `n` alone
    /// ([`crate::Geometry::frame`]).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn of(g: &LaneGeometry<F>) -> Self {
        match g.tangent {
            Some(t) => Self::from_normal_tangent(g.n, t, g.tangent_ok),
            None => Self::from_normal(g.n),
        }
    }

    /// World direction → local coordinates (z along the normal).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn to_local(&self, w: V3<F>) -> V3<F> {
        V3 { x: w.dot(self.t), y: w.dot(self.b), z: w.dot(self.n) }
    }
}

impl From<LaneFrame<f32>> for ShadingFrame {
    #[inline(always)]
    fn from(f: LaneFrame<f32>) -> Self {
        let a = |w: V3<f32>| Vec3A::new(w.x, w.y, w.z);
        Self { t: a(f.t), b: a(f.b), n: a(f.n) }
    }
}

/// Trigonometry of a local direction `w` (unit, z = normal), as in pbrt-v4's `cos_theta` helpers.
pub mod local {
    use glam::Vec3A;

    /// cos θ = w.z.
    #[inline]
    pub fn cos_theta(w: Vec3A) -> f32 {
        w.z
    }
    /// cos² θ.
    #[inline]
    pub fn cos2_theta(w: Vec3A) -> f32 {
        w.z * w.z
    }
    /// sin² θ = max(0, 1 − cos² θ).
    #[inline]
    pub fn sin2_theta(w: Vec3A) -> f32 {
        (1.0 - w.z * w.z).max(0.0)
    }
    /// tan² θ = sin² θ / cos² θ (infinite at grazing).
    #[inline]
    pub fn tan2_theta(w: Vec3A) -> f32 {
        sin2_theta(w) / cos2_theta(w)
    }
    /// cos φ, with φ measured from the local x axis (1 when sin θ = 0).
    #[inline]
    pub fn cos_phi(w: Vec3A) -> f32 {
        let s = sin2_theta(w).sqrt();
        if s == 0.0 { 1.0 } else { (w.x / s).clamp(-1.0, 1.0) }
    }
    /// sin φ (0 when sin θ = 0).
    #[inline]
    pub fn sin_phi(w: Vec3A) -> f32 {
        let s = sin2_theta(w).sqrt();
        if s == 0.0 { 0.0 } else { (w.y / s).clamp(-1.0, 1.0) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_from_normal_is_orthonormal_for_all_hemispheres() {
        for n in [
            Vec3A::Z,
            -Vec3A::Z,
            Vec3A::X,
            Vec3A::new(0.3, -0.4, 0.866).normalize(),
            Vec3A::new(1e-8, 0.0, -1.0).normalize(),
        ] {
            let f = ShadingFrame::from_normal(n);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!((f.b.length() - 1.0).abs() < 1e-5);
            assert!(f.t.dot(f.n).abs() < 1e-5 && f.b.dot(f.n).abs() < 1e-5 && f.t.dot(f.b).abs() < 1e-5);
            let w = Vec3A::new(0.2, 0.5, -0.7).normalize();
            assert!((f.from_local(f.to_local(w)) - w).length() < 1e-5);
        }
    }

    #[test]
    fn tangent_hint_is_orthogonalised() {
        let n = Vec3A::Z;
        let f = ShadingFrame::from_normal_tangent(n, Vec3A::new(1.0, 0.0, 0.5));
        assert!((f.t - Vec3A::X).length() < 1e-6);
        assert!((f.b - Vec3A::Y).length() < 1e-6);
    }
}
