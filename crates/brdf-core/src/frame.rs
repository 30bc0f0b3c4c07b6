//! Orthonormal shading frames: world directions to the local frame where z is the normal (pbrt-v4 `Frame`).

use glam::Vec3A;

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
    #[inline]
    pub fn from_normal(n: Vec3A) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let t = Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let bt = Vec3A::new(b, sign + n.y * n.y * a, -n.y);
        Self { t, b: bt, n }
    }

    /// Frame from a unit normal and a tangent hint: the tangent is Gram-Schmidt orthogonalised
    /// against `n`. Falls back to [`ShadingFrame::from_normal`] when the hint is (nearly) parallel to `n`
    /// or not finite.
    #[inline]
    pub fn from_normal_tangent(n: Vec3A, tangent: Vec3A) -> Self {
        let t = tangent - n * n.dot(tangent);
        let len2 = t.length_squared();
        if !(len2 > 1e-12) || !len2.is_finite() {
            return Self::from_normal(n);
        }
        let t = t / len2.sqrt();
        Self { t, b: n.cross(t), n }
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
