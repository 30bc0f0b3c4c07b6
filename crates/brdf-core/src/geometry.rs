//! The geometry of one evaluation: unit `l`, `v`, `n` (all pointing away from the surface), an optional
//! tangent, and the cosines every model needs.

use glam::{Vec3, Vec3A};

use crate::frame::ShadingFrame;
use crate::vector::{halfway, normalize_or_zero, reflect};

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
    #[inline]
    pub fn new(l: Vec3, v: Vec3, n: Vec3, tangent: Option<Vec3>) -> Option<Self> {
        let l = normalize_or_zero(l.into());
        let v = normalize_or_zero(v.into());
        let n = normalize_or_zero(n.into());
        if l == Vec3A::ZERO || v == Vec3A::ZERO || n == Vec3A::ZERO {
            return None;
        }
        let tangent = tangent.map(|t| normalize_or_zero(t.into())).filter(|t| *t != Vec3A::ZERO);
        Some(Self { l, v, n, tangent, nl: n.dot(l), nv: n.dot(v) })
    }

    /// Build from vectors the caller guarantees to be unit length (hot loops of the rasterizer).
    #[inline]
    pub fn from_unit(l: Vec3A, v: Vec3A, n: Vec3A) -> Self {
        Self { l, v, n, tangent: None, nl: n.dot(l), nv: n.dot(v) }
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
