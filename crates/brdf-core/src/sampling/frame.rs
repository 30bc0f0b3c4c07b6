//! The shading frame on lanes: [`crate::ShadingFrame`] operation for operation, so that a sampler
//! works in exactly the frame in which an anisotropic model evaluates (its tangent is the model's
//! tangent, bit for bit).

use super::neg;
use crate::simd::{Lane, V3};

/// An orthonormal basis `{t, b, n}` per lane; local coordinates are `(w·t, w·b, w·n)`.
#[derive(Debug, Clone, Copy)]
pub struct LaneFrame<F: Lane> {
    /// Tangent (local x).
    pub t: V3<F>,
    /// Bitangent (local y) = n × t.
    pub b: V3<F>,
    /// Unit normal (local z).
    pub n: V3<F>,
}

/// `a × b` as glam computes it (each component `a_i b_j − a_j b_i`).
#[inline(always)]
pub fn cross<F: Lane>(a: V3<F>, b: V3<F>) -> V3<F> {
    V3 { x: a.y * b.z - a.z * b.y, y: a.z * b.x - a.x * b.z, z: a.x * b.y - a.y * b.x }
}

impl<F: Lane> LaneFrame<F> {
    /// [`crate::ShadingFrame::from_normal`] (Duff et al. 2017) per lane, `n` unit.
    #[inline(always)]
    pub fn from_normal(n: V3<F>) -> Self {
        // sign = copysign(1, n.z): −1 also for n.z = −0 (1/−0 = −∞), as `f32::copysign` has it.
        let one = F::splat(1.0);
        let sign = F::select((one / n.z).lt(F::splat(0.0)), F::splat(-1.0), one);
        let a = F::splat(-1.0) / (sign + n.z);
        let b = n.x * n.y * a;
        let t = V3 { x: one + sign * n.x * n.x * a, y: sign * b, z: neg(sign) * n.x };
        let bt = V3 { x: b, y: sign + n.y * n.y * a, z: neg(n.y) };
        Self { t, b: bt, n }
    }

    /// [`crate::ShadingFrame::from_normal_tangent`] per lane where `tangent_ok`, else
    /// [`LaneFrame::from_normal`]; `n` and `tangent` unit (as [`crate::Geometry::frame`] gets them).
    #[inline(always)]
    pub fn new(n: V3<F>, tangent: Option<V3<F>>, tangent_ok: F::Mask) -> Self {
        let plain = Self::from_normal(n);
        let Some(tangent) = tangent else { return plain };
        let t = tangent - n.scale(n.dot(tangent));
        let len2 = t.dot(t);
        let ok = tangent_ok & len2.gt(F::splat(1e-12)) & len2.is_finite();
        let t = t / len2.sqrt();
        let b = cross(n, t);
        Self { t: V3::select(ok, t, plain.t), b: V3::select(ok, b, plain.b), n }
    }

    /// World direction → local coordinates (z along the normal).
    #[inline(always)]
    pub fn to_local(&self, w: V3<F>) -> V3<F> {
        V3 { x: w.dot(self.t), y: w.dot(self.b), z: w.dot(self.n) }
    }

    /// Local coordinates → world direction (`t·x + b·y + n·z`, summed in that order).
    #[inline(always)]
    pub fn from_local(&self, w: V3<F>) -> V3<F> {
        self.t.scale(w.x) + self.b.scale(w.y) + self.n.scale(w.z)
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec3, Vec3A};

    use super::*;
    use crate::ShadingFrame;
    use crate::simd::F32x8;

    fn bits(v: Vec3A) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    #[test]
    fn lane_frames_equal_the_shading_frame_bit_for_bit() {
        let mut normals: Vec<Vec3A> = (0..61)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f32 + 0.5) / 61.0;
                let s = (1.0 - z * z).sqrt();
                let p = k as f32 * 2.399_963;
                Vec3A::new(s * p.cos(), s * p.sin(), z).normalize()
            })
            .collect();
        normals.extend([
            Vec3A::Z,
            -Vec3A::Z,
            Vec3A::X,
            Vec3A::new(0.6, 0.8, -0.0),
            Vec3A::new(0.6, 0.8, 0.0),
        ]);
        let tangents = [Vec3A::X, Vec3A::new(0.3, -0.9, 0.2).normalize(), Vec3A::Z];
        for chunk in normals.chunks(8) {
            let at = |i: usize| chunk[i.min(chunk.len() - 1)];
            let n = V3::<F32x8> {
                x: F32x8::from_fn(|i| at(i).x),
                y: F32x8::from_fn(|i| at(i).y),
                z: F32x8::from_fn(|i| at(i).z),
            };
            let plain = LaneFrame::from_normal(n);
            for (i, &nn) in chunk.iter().enumerate() {
                let f = ShadingFrame::from_normal(nn);
                assert_eq!(bits(Vec3A::from(plain.t.lane(i))), bits(f.t), "n = {nn}");
                assert_eq!(bits(Vec3A::from(plain.b.lane(i))), bits(f.b), "n = {nn}");
            }
            for &t in &tangents {
                let lf = LaneFrame::new(n, Some(V3::splat(Vec3::from(t))), F32x8::mask_splat(true));
                for (i, &nn) in chunk.iter().enumerate() {
                    let f = ShadingFrame::from_normal_tangent(nn, t);
                    assert_eq!(bits(Vec3A::from(lf.t.lane(i))), bits(f.t), "n = {nn}, t = {t}");
                    assert_eq!(bits(Vec3A::from(lf.b.lane(i))), bits(f.b), "n = {nn}, t = {t}");
                    let w = Vec3A::new(0.2, -0.5, 0.7).normalize();
                    let local = lf.to_local(V3::splat(Vec3::from(w))).lane(i);
                    assert_eq!(bits(local.into()), bits(f.to_local(w)));
                }
            }
        }
    }
}
