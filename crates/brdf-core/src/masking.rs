//! Shadowing–masking terms `G(l, v)` (dimensionless, in [0, 1]) for microfacet BRDFs
//! (Torrance & Sparrow 1967; Cook & Torrance 1982; Walter et al. 2007; Heitz 2014).
//!
//! - V-groove (Torrance & Sparrow 1967; Cook & Torrance 1982):
//!   `G = min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h))` (`v·h = l·h` for reflection).
//! - Smith, height-correlated (the default; Heitz 2014 "Understanding the masking-shadowing
//!   function", pbrt-v4): `G = 1/(1 + Λ(l) + Λ(v))`.
//! - Smith, separable (Walter et al. 2007; Mitsuba 3): `G = G1(l) G1(v)`, `G1 = 1/(1 + Λ)`.
//!   Always ≤ the height-correlated form.
//! - Kelemen & Szirmay-Kalos 2001: `G/((n·l)(n·v)) = 1/(l·h)²`, i.e. `G = (n·l)(n·v)/(v·h)²` (≤ 1).
//! - None: `G = 1`.
//!
//! Λ comes from the distribution: GGX and Beckmann have their own; the others map to Beckmann
//! (see [`crate::microfacet`]). V-groove and Kelemen ignore the distribution.
//!
//! Hot paths want `G/(4 (n·l)(n·v))` (the "visibility"), see [`Masking::visibility`]: for GGX with the
//! height-correlated Smith term it costs two square roots and one division
//! ([`crate::microfacet::ggx::visibility_height_correlated`]); for the Beckmann family two rational
//! G1s and one division ([`crate::microfacet::beckmann::visibility_height_correlated_lanes`]).

use glam::Vec3A;

use crate::BrdfError;
use crate::frame::ShadingFrame;
use crate::microfacet::{Distribution, Mixture, beckmann, ggx};
use crate::simd::{Lane, V3};
use crate::vector::halfway;

/// Registry names of the masking terms.
pub const MASKING_NAMES: [&str; 5] = ["smith", "smith_separable", "v_groove", "kelemen", "none"];

/// V-groove (Cook–Torrance / Torrance–Sparrow) `G = min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h))`.
/// 0 when any of the cosines is ≤ 0 (light or viewer below the surface, or `v·h ≤ 0`).
#[inline]
pub fn v_groove(nl: f32, nv: f32, nh: f32, vh: f32) -> f32 {
    v_groove_lanes(nl, nv, nh, vh)
}

/// [`v_groove`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn v_groove_lanes<F: Lane>(nl: F, nv: F, nh: F, vh: F) -> F {
    let zero = F::splat(0.0);
    let g = (F::splat(2.0) * nh * nl.min(nv) / vh).min(F::splat(1.0));
    F::select(nl.gt(zero) & nv.gt(zero) & nh.gt(zero) & vh.gt(zero), g, zero)
}

/// Kelemen & Szirmay-Kalos `G = (n·l)(n·v)/(v·h)²` (so that `G/((n·l)(n·v)) = 1/(l·h)²`).
/// Never exceeds 1 (since `(v·h)² = (1 + l·v)/2 ≥ (n·l)(n·v)`). 0 when any cosine ≤ 0.
#[inline]
pub fn kelemen(nl: f32, nv: f32, vh: f32) -> f32 {
    kelemen_lanes(nl, nv, vh)
}

/// [`kelemen`] on lanes (the one place its formula is written).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn kelemen_lanes<F: Lane>(nl: F, nv: F, vh: F) -> F {
    let zero = F::splat(0.0);
    let g = (nl * nv / (vh * vh)).min(F::splat(1.0));
    F::select(nl.gt(zero) & nv.gt(zero) & vh.gt(zero), g, zero)
}

/// Height-correlated Smith `G = 1/(1 + Λ(l) + Λ(v))` from the two Λ values (0 if either is +∞).
#[inline]
pub fn smith_height_correlated(lambda_l: f32, lambda_v: f32) -> f32 {
    smith_height_correlated_lanes(lambda_l, lambda_v)
}

/// [`smith_height_correlated`] on lanes.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn smith_height_correlated_lanes<F: Lane>(lambda_l: F, lambda_v: F) -> F {
    F::splat(1.0) / (F::splat(1.0) + lambda_l + lambda_v)
}

/// Separable Smith `G = 1/((1 + Λ(l))(1 + Λ(v)))` from the two Λ values (0 if either is +∞).
#[inline]
pub fn smith_separable(lambda_l: f32, lambda_v: f32) -> f32 {
    smith_separable_lanes(lambda_l, lambda_v)
}

/// [`smith_separable`] on lanes.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn smith_separable_lanes<F: Lane>(lambda_l: F, lambda_v: F) -> F {
    let one = F::splat(1.0);
    one / ((one + lambda_l) * (one + lambda_v))
}

/// Height-correlated Smith G for isotropic GGX of roughness α, from `n·l`, `n·v`.
#[inline]
pub fn smith_ggx(nl: f32, nv: f32, alpha: f32) -> f32 {
    smith_height_correlated(ggx::lambda(nl, alpha), ggx::lambda(nv, alpha))
}

/// Separable Smith G for isotropic GGX: `G1(l) G1(v)`.
#[inline]
pub fn smith_ggx_separable(nl: f32, nv: f32, alpha: f32) -> f32 {
    smith_separable(ggx::lambda(nl, alpha), ggx::lambda(nv, alpha))
}

/// Height-correlated Smith G for isotropic Beckmann (Walter et al. 2007 eq. 25 Λ).
#[inline]
pub fn smith_beckmann(nl: f32, nv: f32, alpha: f32) -> f32 {
    smith_height_correlated(beckmann::lambda(nl, alpha), beckmann::lambda(nv, alpha))
}

/// Separable Smith G for isotropic Beckmann (Walter et al. 2007 eq. 25 Λ).
#[inline]
pub fn smith_beckmann_separable(nl: f32, nv: f32, alpha: f32) -> f32 {
    smith_separable(beckmann::lambda(nl, alpha), beckmann::lambda(nv, alpha))
}

/// Which shadowing–masking term a microfacet model uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Masking {
    /// Height-correlated Smith (default).
    Smith,
    /// Separable Smith.
    SmithSeparable,
    /// Cook–Torrance / Torrance–Sparrow V-groove.
    VGroove,
    /// Kelemen & Szirmay-Kalos.
    Kelemen,
    /// G = 1.
    None,
}

impl Masking {
    /// Parse a registry name ([`MASKING_NAMES`]).
    pub fn from_name(name: &str) -> Result<Self, BrdfError> {
        match name.to_ascii_lowercase().as_str() {
            "smith" => Ok(Masking::Smith),
            "smith_separable" => Ok(Masking::SmithSeparable),
            "v_groove" => Ok(Masking::VGroove),
            "kelemen" => Ok(Masking::Kelemen),
            "none" => Ok(Masking::None),
            _ => Err(BrdfError::param(
                "masking",
                format!("expected one of {}, got {name:?}", MASKING_NAMES.join(", ")),
            )),
        }
    }

    /// Registry name.
    pub fn name(self) -> &'static str {
        match self {
            Masking::Smith => "smith",
            Masking::SmithSeparable => "smith_separable",
            Masking::VGroove => "v_groove",
            Masking::Kelemen => "kelemen",
            Masking::None => "none",
        }
    }

    /// `G` for an isotropic distribution from the cosines `n·l`, `n·v`, `n·h`, `v·h`
    /// (anisotropic lobes are taken at φ = 0, see [`Distribution::d_cos`]). 0 below the horizon.
    #[inline]
    pub fn g_cos(self, nl: f32, nv: f32, nh: f32, vh: f32, d: &Mixture) -> f32 {
        self.g_cos_lanes(nl, nv, nh, vh, d)
    }

    /// [`Masking::g_cos`] on lanes (the one place it is written).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn g_cos_lanes<F: Lane>(self, nl: F, nv: F, nh: F, vh: F, d: &Mixture) -> F {
        let zero = F::splat(0.0);
        let g = match self {
            Masking::Smith => smith_height_correlated_lanes(d.lambda_cos_lanes(nl), d.lambda_cos_lanes(nv)),
            Masking::SmithSeparable => smith_separable_lanes(d.lambda_cos_lanes(nl), d.lambda_cos_lanes(nv)),
            Masking::VGroove => v_groove_lanes(nl, nv, nh, vh),
            Masking::Kelemen => kelemen_lanes(nl, nv, vh),
            Masking::None => F::splat(1.0),
        };
        F::select(nl.gt(zero) & nv.gt(zero), g, zero)
    }

    /// `G` for unit local directions `l`, `v` (z = normal) and their half vector `h`; anisotropic
    /// Smith Λ where the distribution is anisotropic.
    #[inline]
    pub fn g_local(self, l: Vec3A, v: Vec3A, h: Vec3A, d: &Mixture) -> f32 {
        self.g_local_lanes(V3::from(l), V3::from(v), V3::from(h), d)
    }

    /// [`Masking::g_local`] on lanes (the one place it is written).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn g_local_lanes<F: Lane>(self, l: V3<F>, v: V3<F>, h: V3<F>, d: &Mixture) -> F {
        let (nl, nv, nh, vh) = (l.z, v.z, h.z, v.dot(h));
        let zero = F::splat(0.0);
        let g = match self {
            Masking::Smith => smith_height_correlated_lanes(d.lambda_lanes(l), d.lambda_lanes(v)),
            Masking::SmithSeparable => smith_separable_lanes(d.lambda_lanes(l), d.lambda_lanes(v)),
            Masking::VGroove => v_groove_lanes(nl, nv, nh, vh),
            Masking::Kelemen => kelemen_lanes(nl, nv, vh),
            Masking::None => F::splat(1.0),
        };
        F::select(nl.gt(zero) & nv.gt(zero), g, zero)
    }

    /// `G` for world-space unit `l`, `v`, `n` and an optional tangent (for batch/Python use).
    /// 0 when `l = −v` (no half vector) or either direction is below the surface.
    pub fn g_world(self, l: Vec3A, v: Vec3A, n: Vec3A, tangent: Option<Vec3A>, d: &Mixture) -> f32 {
        let Some(h) = halfway(l, v) else { return 0.0 };
        let frame = match tangent {
            Some(t) => ShadingFrame::from_normal_tangent(n, t),
            None => ShadingFrame::from_normal(n),
        };
        self.g_local(frame.to_local(l), frame.to_local(v), frame.to_local(h), d)
    }

    /// The visibility `G/(4 (n·l)(n·v))` [dimensionless / cos²] for an isotropic distribution, from
    /// cosines; the closed GGX forms for a single GGX lobe (no tan, no Λ). 0 below the horizon.
    #[inline]
    pub fn visibility(self, nl: f32, nv: f32, nh: f32, vh: f32, d: &Mixture) -> f32 {
        self.visibility_lanes(nl, nv, nh, vh, d)
    }

    /// [`Masking::visibility`] on lanes: for a single lobe the closed Smith forms with one division
    /// (GGX's own; the Beckmann rational G1 for Beckmann and the lobes that borrow its Λ, at their
    /// [`Distribution::beckmann_equivalent`] roughness), else [`Masking::g_cos_lanes`] `/ (4 (n·l)(n·v))`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn visibility_lanes<F: Lane>(self, nl: F, nv: F, nh: F, vh: F, d: &Mixture) -> F {
        // All four forms are 0 below the horizon already.
        match (self, d.as_single()) {
            (Masking::Smith, Some(Distribution::Ggx { alpha_x, .. })) => {
                return ggx::visibility_height_correlated_lanes(nl, nv, *alpha_x);
            }
            (Masking::SmithSeparable, Some(Distribution::Ggx { alpha_x, .. })) => {
                return ggx::visibility_separable_lanes(nl, nv, *alpha_x);
            }
            (Masking::Smith, Some(single)) => {
                return beckmann::visibility_height_correlated_lanes(nl, nv, single.beckmann_equivalent().0);
            }
            (Masking::SmithSeparable, Some(single)) => {
                return beckmann::visibility_separable_lanes(nl, nv, single.beckmann_equivalent().0);
            }
            _ => {}
        }
        let g = self.g_cos_lanes(nl, nv, nh, vh, d);
        let zero = F::splat(0.0);
        F::select(nl.gt(zero) & nv.gt(zero), g / (F::splat(4.0) * nl * nv), zero)
    }
}
