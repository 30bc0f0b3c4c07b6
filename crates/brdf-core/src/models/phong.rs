//! Energy-normalised ("modified") Phong BRDF: `f_r = kd/π + ks·(γ+2)/(2π)·max(r·v, 0)^γ`
//! (R. R. Lewis, "Making Shaders More Physically Plausible", Computer Graphics Forum 13(2), 1994;
//! E. P. Lafortune, Y. D. Willems, "Using the Modified Phong Reflectance Model for Physically Based
//! Rendering", KU Leuven CW 197, 1994).

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use crate::BrdfError;
use crate::models::classic::MAX_SHININESS;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3, math};

/// Physical Phong BRDF [1/sr]:
///
/// ```text
/// f_r(l, v) = kd/π + ks · (γ + 2)/(2π) · max(r·v, 0)^γ,    r = 2(n·l)n − l
/// ```
///
/// The factor `(γ+2)/(2π)` makes the specular lobe's directional albedo exactly `ks` when the lobe is
/// not cut by the horizon — at normal incidence, and nearly so whenever the mirror direction is far from
/// grazing: `∫ cos^γ α · cos θ_l dω = 2π cos θ_v/(γ+2)` for an unclipped lobe (Lewis 1994, "Making
/// shaders more physically plausible"). The albedo is therefore `≤ kd + ks`, equal at normal incidence;
/// energy is conserved when `kd + ks ≤ 1` per channel, which is the caller's choice (not enforced, as in
/// Lafortune & Willems 1994). `r·v` is symmetric in `l` and `v`, so the BRDF is reciprocal — unlike the
/// textbook formula ([`crate::models::PhongClassic`]), whose `shade` has no `n·l` factor on the specular
/// term. It is evaluated as `(1 − d)^γ` from the deficit `d = 1 − r·v` (`mirror_deficit`,
/// `pow_one_minus` below), not from `r·v` itself: see those for why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phong {
    /// Diffuse reflectance `kd` (the diffuse albedo).
    kd: Vec3,
    /// Specular reflectance `ks` (the lobe's albedo at normal incidence).
    ks: Vec3,
    /// Phong exponent γ ≥ 0.
    shininess: f32,
    /// `kd/π`, precomputed.
    diffuse: Vec3,
    /// `ks (γ+2)/(2π)`, precomputed.
    specular: Vec3,
}

impl Phong {
    /// Normalised Phong with diffuse `kd`, specular `ks` and exponent `shininess`.
    pub fn new(kd: Vec3, ks: Vec3, shininess: f32) -> Self {
        Self { kd, ks, shininess, diffuse: kd * FRAC_1_PI, specular: ks * ((shininess + 2.0) / (2.0 * PI)) }
    }

    /// Diffuse reflectance `kd` (the diffuse albedo).
    #[inline]
    pub fn kd(&self) -> Vec3 {
        self.kd
    }

    /// Specular reflectance `ks` (the lobe's albedo at normal incidence).
    #[inline]
    pub fn ks(&self) -> Vec3 {
        self.ks
    }

    /// Phong exponent γ ≥ 0.
    #[inline]
    pub fn shininess(&self) -> f32 {
        self.shininess
    }
}

impl Bxdf for Phong {
    const SPEC: ModelSpec = ModelSpec {
        name: "phong",
        summary: "energy-normalised Phong, f_r = kd/pi + ks*(shininess+2)/(2pi)*max(r.v,0)^shininess",
        source: "R. R. Lewis, Making Shaders More Physically Plausible, Computer Graphics Forum 13(2) (1994); E. P. Lafortune, Y. D. Willems, Using the Modified Phong Reflectance Model for Physically Based Rendering, KU Leuven CW 197 (1994)",
        physical: true,
        anisotropic: false,
        params: &[
            ParamSpec::color("kd", [0.5, 0.5, 0.5], 0.0, 1.0, "reflectance", "diffuse albedo"),
            ParamSpec::color(
                "ks",
                [0.5, 0.5, 0.5],
                0.0,
                1.0,
                "reflectance",
                "specular albedo at normal incidence (kd + ks <= 1 conserves energy)",
            ),
            ParamSpec::scalar("shininess", 32.0, 0.0, MAX_SHININESS, "1", "Phong exponent gamma"),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted for `kd`, Phong's lobe `(r·v)^γ` about the mirror direction of `v` for `ks`
    /// (Lafortune & Willems 1994; [`crate::sampling::cosine_power`]), chosen in proportion to `kd : ks`.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        Ok(Sampler::new()
            .with(Technique::Cosine, mean(self.kd))
            .with(Technique::phong(self.shininess), mean(self.ks)))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self::new(p.color("kd"), p.color("ks"), p.scalar("shininess")))
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        // max(r·v, 0)^γ from the deficit d = 1 − r·v (bit-for-bit symmetric in l and v), r·v ≤ 0 ⇔ d ≥ 1.
        let d = mirror_deficit(g);
        let lobe = F::select(d.lt(F::splat(1.0)), pow_one_minus(d, self.shininess), F::splat(0.0));
        V3::splat(self.diffuse) + V3::splat(self.specular).scale(lobe)
    }
}

/// The mirror deficit `d = 1 − r·v = ½(|l⊥ + v⊥|² + (n·l − n·v)²)` [dimensionless, in `[0, 2]`], with
/// `r = 2(n·l)n − l` and `w⊥ = w − (n·w)n` the tangent-plane part (in a frame with `n = z`,
/// `r = (−l⊥, n·l)`, so `r − v = (−(l⊥ + v⊥), n·l − n·v)` and `1 − r·v = |r − v|²/2` for unit vectors).
///
/// Why not `r·v = 2(n·l)(n·v) − l·v` (the textbook form) or `(n·l)(n·v) − l⊥·v⊥`: a Phong lobe lives where `r·v`
/// is within `~1/γ` of 1, and a float32 number near 1 is only known to `2^-24` absolute, which `x^γ`
/// turns into a relative error of `γ·2^-24` and more (the cosine form rounds `2(n·l)(n·v) ≈ 2` and
/// `l·v ≈ 1`: 7.0e-3 relative at γ = 10000 near the normal, in a float32 emulation). The
/// direction rounding of float32 inputs costs only `~γ·|r − v|·2^-24`, which vanishes at the peak (the
/// peak is flat). `d` is a sum of squares of differences that are small exactly there, and it is
/// insensitive to the float32 length error of the normalised `l`, `v`, `n` (second order), so its
/// error is `~|r − v|·2^-24`: the float32 input floor (γ = 10000: 6.9e-5 relative, where rounding the
/// inputs alone moves the float64 value by 4.7e-5). Bit-for-bit symmetric in `l` and `v`.
/// tests/test_phong_precision.py bounds it against a float64 oracle.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn mirror_deficit<F: Lane>(g: &LaneGeometry<F>) -> F {
    let s = (g.l - g.n.scale(g.nl)) + (g.v - g.n.scale(g.nv));
    let dn = g.nl - g.nv;
    F::splat(0.5) * (s.dot(s) + dn * dn)
}

/// `clamp(1 − d, 0, 1)^γ` for `d ≥ 0` [dimensionless], never rounding `1 − d` to float32 (that
/// rounding alone costs `γ·2^-25` relative, 3e-4 at γ = 10000). For an integer γ in [1, 2¹⁶] (the
/// default 32) by binary powering of `1 − d` formed in float64 (`simd::math::one_minus_powi`: only
/// the error of `d` is left), else as `exp(γ·ln_1p(−d))`, whose float32 errors are those of `d`, of
/// the product and of `exp`: a few `2^-24` times `1 + |ln result|`. `d ≥ 1` (a cosine at or below 0)
/// gives `0^γ`: 0, or 1 for γ = 0 as `powf` has it.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub(crate) fn pow_one_minus<F: Lane>(d: F, gamma: f32) -> F {
    let p = match math::integer_exponent(gamma) {
        Some(n) => math::one_minus_powi(d, n),
        // −d as d·(−1): the same bits in every lane type (see `simd`).
        None => (F::splat(gamma) * (d * F::splat(-1.0)).ln_1p()).exp(),
    };
    F::select(d.lt(F::splat(1.0)), p, F::splat(if gamma == 0.0 { 1.0 } else { 0.0 }))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::Geometry;

    fn deficit(g: &Geometry) -> f32 {
        mirror_deficit(&LaneGeometry::from(g))
    }

    /// A few unit directions above the surface `n = z`, from the normal (1e-4 rad) to grazing.
    fn directions() -> impl Iterator<Item = Vec3> {
        [1e-4_f32, 3e-3, 0.1, 0.7, 1.3, 1.57].into_iter().flat_map(|theta| {
            [0.3_f32, 2.0, 4.5]
                .into_iter()
                .map(move |phi| Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()))
        })
    }

    #[test]
    fn the_lobe_peaks_at_exactly_its_normalisation_in_the_mirror_direction_for_any_exponent() {
        // v = (−lx, −ly, lz) is l's exact mirror about z in float32 too: the deficit is exactly 0, so the
        // peak is exact even at γ = 10000 (the cosine form 2(n·l)(n·v) − l·v rounds r·v to a few ulps
        // of 1, which the exponent made 6e-4 relative here, in a float32 emulation).
        for gamma in [1.0, 100.0, 10_000.0] {
            let m = Phong::new(Vec3::ZERO, Vec3::ONE, gamma);
            for l in directions() {
                let v = Vec3::new(-l.x, -l.y, l.z);
                let g = Geometry::new(l, v, Vec3::Z, None).unwrap();
                assert_eq!(deficit(&g), 0.0, "l = {l}");
                assert_eq!(m.f(&g), Vec3::splat((gamma + 2.0) / (2.0 * PI)), "l = {l}, gamma = {gamma}");
            }
        }
    }

    #[test]
    fn the_deficit_is_one_minus_the_mirror_cosine_and_bit_symmetric_in_l_and_v() {
        let n = Vec3::new(0.2, -0.3, 0.9).normalize();
        for l in directions() {
            for v in directions() {
                let (l, v) = ((l + 0.3 * n).normalize(), (v - 0.2 * n).normalize());
                let g = Geometry::new(l, v, n, None).unwrap();
                let d = deficit(&g);
                assert_eq!(d.to_bits(), deficit(&g.swapped()).to_bits());
                let rv = (2.0 * f64::from(g.nl) * f64::from(g.nv)) - f64::from(g.l.dot(g.v));
                assert!((f64::from(d) - (1.0 - rv)).abs() < 1e-6, "d = {d}, 1 − r·v = {}", 1.0 - rv);
            }
        }
    }

    #[test]
    fn the_power_of_a_cosine_at_or_below_zero_is_zero_except_for_exponent_zero() {
        assert_eq!(pow_one_minus(1.0f32, 5.0), 0.0);
        assert_eq!(pow_one_minus(1.5f32, 5.0), 0.0);
        assert_eq!(pow_one_minus(1.0f32, 0.0), 1.0);
        assert_eq!(pow_one_minus(0.5f32, 0.0), 1.0);
        assert!((pow_one_minus(0.5f32, 3.0) - 0.125).abs() < 1e-7);
    }
}
