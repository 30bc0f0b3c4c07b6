//! Reflection, refraction and the half vector in brdfpy's convention: every direction points AWAY
//! from the surface point (glam's `reflect`/`refract` take the incident vector instead).

use glam::Vec3A;

/// Mirror direction of `w` about the unit normal `n`: `r = 2(n·w)n − w`.
#[inline]
pub fn reflect(w: Vec3A, n: Vec3A) -> Vec3A {
    2.0 * n.dot(w) * n - w
}

/// Half vector `h = normalize(l + v)`, or `None` when `l = −v` (no half vector exists).
#[inline]
pub fn halfway(l: Vec3A, v: Vec3A) -> Option<Vec3A> {
    let s = l + v;
    let len2 = s.length_squared();
    (len2 > 1e-20).then(|| s / len2.sqrt())
}

/// Refracted direction by Snell's law, `η_i sin θ_i = η_t sin θ_t`, with `eta = η_t / η_i`.
///
/// `w` points away from the surface on the incident side, `n` is the unit normal on that side
/// (`n·w > 0`). The result points away from the surface on the other side. `None` on total internal
/// reflection (`sin² θ_t > 1`) or `eta ≤ 0` (Snell's law; Pharr et al., PBR 4th ed., §9.3).
#[inline]
pub fn refract(w: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    if !(eta > 0.0) {
        return None;
    }
    let cos_i = n.dot(w);
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + (cos_i / eta - cos_t) * n)
}

/// `v / |v|`, or zero for a zero-length or non-finite vector: degenerate input shades to black, never NaN.
#[inline]
pub fn normalize_or_zero(v: Vec3A) -> Vec3A {
    let len2 = v.length_squared();
    if len2 > 0.0 && len2.is_finite() { v / len2.sqrt() } else { Vec3A::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflect_keeps_the_angle_and_the_plane() {
        let n = Vec3A::Z;
        let w = Vec3A::new(0.6, 0.0, 0.8);
        assert!((reflect(w, n) - Vec3A::new(-0.6, 0.0, 0.8)).length() < 1e-6);
    }

    #[test]
    fn refract_obeys_snell_and_detects_tir() {
        let n = Vec3A::Z;
        let w = Vec3A::new(0.6, 0.0, 0.8); // sin θi = 0.6
        let t = refract(w, n, 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-6);
        assert!(t.z < 0.0);
        assert!((t.x.abs() - 0.6 / 1.5).abs() < 1e-6);
        assert!(refract(w, n, 1.0 / 1.5).is_some()); // sin θt = 0.9 < 1
        assert!(refract(Vec3A::new(0.8, 0.0, 0.6), n, 1.0 / 1.5).is_none()); // 1.2 > 1: TIR
    }
}
