//! The geometry of one evaluation: unit `l`, `v`, `n` (all pointing away from the surface), an optional
//! tangent, and the cosines every model needs.
//!
//! The formula exists once, over lanes ([`LaneGeometry::new`]); the one-sample [`Geometry::new`] is that
//! code with `F = f32` (the same IEEE operations in the same order, so the same bits as any lane of a
//! batch).

use glam::{Vec3, Vec3A};

use crate::frame::ShadingFrame;
use crate::simd::{Lane, V3};
use crate::vector::{halfway, reflect};

/// One (light, view, normal[, tangent]) configuration, normalised once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Unit direction toward the light.
    pub l: Vec3A,
    /// Unit direction toward the viewer.
    pub v: Vec3A,
    /// Unit surface normal.
    pub n: Vec3A,
    /// Unit tangent hint for anisotropic models (`None`: an arbitrary frame is built from `n`).
    pub tangent: Option<Vec3A>,
    /// cos θ_l = n·l (may be negative).
    pub nl: f32,
    /// cos θ_v = n·v (may be negative).
    pub nv: f32,
}

impl Geometry {
    /// Normalise the inputs. `None` when `l`, `v` or `n` has zero length or is not finite: the caller
    /// returns black for such a sample. A degenerate tangent is dropped (an arbitrary frame is used).
    /// [`LaneGeometry::new`] with one lane.
    #[inline]
    pub fn new(l: Vec3, v: Vec3, n: Vec3, tangent: Option<Vec3>) -> Option<Self> {
        let (g, ok) =
            LaneGeometry::<f32>::new(V3::splat(l), V3::splat(v), V3::splat(n), tangent.map(V3::splat));
        ok.then(|| g.lane(0))
    }

    /// Build from vectors the caller guarantees to be unit length (hot loops of the rasterizer);
    /// [`LaneGeometry::from_unit`] with one lane.
    #[inline]
    pub fn from_unit(l: Vec3A, v: Vec3A, n: Vec3A) -> Self {
        LaneGeometry::<f32>::from_unit(l.into(), v.into(), n.into()).lane(0)
    }

    /// `true` when both the light and the viewer are strictly above the surface.
    #[inline]
    pub fn both_above(&self) -> bool {
        self.nl > 0.0 && self.nv > 0.0
    }

    /// Half vector `normalize(l + v)`, `None` when `l = −v`.
    #[inline]
    pub fn h(&self) -> Option<Vec3A> {
        halfway(self.l, self.v)
    }

    /// Mirror direction of the light, `r = 2(n·l)n − l`.
    #[inline]
    pub fn r(&self) -> Vec3A {
        reflect(self.l, self.n)
    }

    /// The shading frame (tangent from the hint, else arbitrary).
    #[inline]
    pub fn frame(&self) -> ShadingFrame {
        match self.tangent {
            Some(t) => ShadingFrame::from_normal_tangent(self.n, t),
            None => ShadingFrame::from_normal(self.n),
        }
    }

    /// The same configuration with light and viewer exchanged (for reciprocity checks).
    #[inline]
    pub fn swapped(&self) -> Self {
        Self { l: self.v, v: self.l, nl: self.nv, nv: self.nl, ..*self }
    }
}

/// [`Geometry`] for `F::LANES` samples: unit `l`, `v`, `n`, the optional tangent and the cosines.
#[derive(Debug, Clone, Copy)]
pub struct LaneGeometry<F: Lane> {
    /// Unit direction toward the light.
    pub l: V3<F>,
    /// Unit direction toward the viewer.
    pub v: V3<F>,
    /// Unit surface normal.
    pub n: V3<F>,
    /// Unit tangent hint, where given; lanes where it had zero length have `tangent_ok` false.
    pub tangent: Option<V3<F>>,
    /// Lanes whose tangent is usable.
    pub tangent_ok: F::Mask,
    /// cos θ_l = n·l.
    pub nl: F,
    /// cos θ_v = n·v.
    pub nv: F,
}

impl<F: Lane> LaneGeometry<F> {
    /// Normalise the inputs (each divided by its length, [`V3::normalize_or_zero`]). The mask is false
    /// in the lanes where `l`, `v` or `n` has zero length or is not finite ([`Geometry::new`] returns
    /// `None` there); a zero-length tangent only clears `tangent_ok`.
    #[inline(always)]
    pub fn new(l: V3<F>, v: V3<F>, n: V3<F>, tangent: Option<V3<F>>) -> (Self, F::Mask) {
        Self::from_normalized(
            l.normalize_or_zero(),
            v.normalize_or_zero(),
            n.normalize_or_zero(),
            tangent.map(V3::normalize_or_zero),
        )
    }

    /// [`LaneGeometry::new`] from inputs already normalised by [`V3::normalize_or_zero`] (each with
    /// its mask), so that a caller may normalise an input shared by many batches once: the same
    /// operations on the same values, the same bits.
    #[inline(always)]
    pub fn from_normalized(
        (l, ok_l): (V3<F>, F::Mask),
        (v, ok_v): (V3<F>, F::Mask),
        (n, ok_n): (V3<F>, F::Mask),
        tangent: Option<(V3<F>, F::Mask)>,
    ) -> (Self, F::Mask) {
        let (tangent, tangent_ok) = match tangent {
            Some((t, ok)) => (Some(t), ok),
            None => (None, F::mask_splat(false)),
        };
        let g = Self { l, v, n, tangent, tangent_ok, nl: n.dot(l), nv: n.dot(v) };
        (g, ok_l & ok_v & ok_n)
    }

    /// From unit vectors (no normalisation, no tangent): the cosines only.
    #[inline(always)]
    pub fn from_unit(l: V3<F>, v: V3<F>, n: V3<F>) -> Self {
        Self { l, v, n, tangent: None, tangent_ok: F::mask_splat(false), nl: n.dot(l), nv: n.dot(v) }
    }

    /// Lanes where both the light and the viewer are strictly above the surface
    /// ([`Geometry::both_above`]).
    #[inline(always)]
    pub fn both_above(&self) -> F::Mask {
        let zero = F::splat(0.0);
        self.nl.gt(zero) & self.nv.gt(zero)
    }

    /// Lane `i` as a scalar [`Geometry`] (the tangent dropped where `tangent_ok` is false).
    #[inline]
    pub fn lane(&self, i: usize) -> Geometry {
        let a = |w: &V3<F>| Vec3A::new(w.x.lane(i), w.y.lane(i), w.z.lane(i));
        let tangent = self.tangent.as_ref().filter(|_| F::mask_lane(self.tangent_ok, i)).map(a);
        Geometry {
            l: a(&self.l),
            v: a(&self.v),
            n: a(&self.n),
            tangent,
            nl: self.nl.lane(i),
            nv: self.nv.lane(i),
        }
    }
}

impl From<&Geometry> for LaneGeometry<f32> {
    #[inline(always)]
    fn from(g: &Geometry) -> Self {
        Self {
            l: g.l.into(),
            v: g.v.into(),
            n: g.n.into(),
            tangent: g.tangent.map(Into::into),
            tangent_ok: g.tangent.is_some(),
            nl: g.nl,
            nv: g.nv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::F32x8;
    use crate::vector::normalize_or_zero;

    /// The operations of the one-sample code before it became the lane code with one lane (glam's
    /// `Vec3A` normalisation and dot products): the same bits, so nothing downstream moved.
    fn reference(l: Vec3, v: Vec3, n: Vec3, t: Option<Vec3>) -> Option<Geometry> {
        let (l, v, n) =
            (normalize_or_zero(l.into()), normalize_or_zero(v.into()), normalize_or_zero(n.into()));
        if l == Vec3A::ZERO || v == Vec3A::ZERO || n == Vec3A::ZERO {
            return None;
        }
        let tangent = t.map(|t| normalize_or_zero(t.into())).filter(|t| *t != Vec3A::ZERO);
        Some(Geometry { l, v, n, tangent, nl: n.dot(l), nv: n.dot(v) })
    }

    fn bits(g: &Geometry) -> Vec<u32> {
        let mut b: Vec<u32> = [g.l, g.v, g.n].iter().flat_map(|w| w.to_array().map(f32::to_bits)).collect();
        b.extend(g.tangent.map_or([u32::MAX; 3], |t| t.to_array().map(f32::to_bits)));
        b.extend([g.nl.to_bits(), g.nv.to_bits()]);
        b
    }

    #[test]
    fn lane_geometry_equals_one_sample_geometry_and_glam_bit_for_bit() {
        let mut rows = Vec::new();
        for k in 0..64u32 {
            let f = |j: u32| ((k * 7 + j * 13) as f32 * 0.618).sin() * 2.0;
            rows.push(Vec3::new(f(0), f(1), f(2)));
        }
        rows.extend([
            Vec3::ZERO,
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(1e30, 1e30, 0.0),
            Vec3::splat(1e-30),
            Vec3::new(0.0, f32::INFINITY, 0.0),
        ]);
        for base in 0..rows.len() {
            let at = |off: usize, i: usize| rows[(base + off + 3 * i) % rows.len()];
            let pick = |off: usize| V3::<F32x8>::from_fn(|i| at(off, i));
            let (l, v, n, t) = (pick(0), pick(1), pick(2), pick(5));
            let (g, ok) = LaneGeometry::new(l, v, n, Some(t));
            for i in 0..8 {
                let (li, vi, ni, ti) = (at(0, i), at(1, i), at(2, i), at(5, i));
                let one = Geometry::new(li, vi, ni, Some(ti));
                let want = reference(li, vi, ni, Some(ti));
                assert_eq!(F32x8::mask_lane(ok, i), want.is_some());
                assert_eq!(one.map(|g| bits(&g)), want.map(|g| bits(&g)));
                if let Some(w) = want {
                    assert_eq!(bits(&g.lane(i)), bits(&w));
                }
            }
        }
        let (l, v, n) = (Vec3A::new(0.6, 0.0, 0.8), Vec3A::new(0.0, 0.6, 0.8), Vec3A::Z);
        let g = Geometry::from_unit(l, v, n);
        assert_eq!((g.nl.to_bits(), g.nv.to_bits()), (n.dot(l).to_bits(), n.dot(v).to_bits()));
        assert_eq!((g.l, g.v, g.n, g.tangent), (l, v, n, None));
    }
}
