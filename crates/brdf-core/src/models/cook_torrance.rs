//! Cook–Torrance microfacet BRDF `f = kd/π + ks · D(h) G(l, v) F(v·h) / (4 (n·l)(n·v))`
//! (R. L. Cook, K. E. Torrance, "A Reflectance Model for Computer Graphics", ACM ToG 1(1), 1982;
//! B. Walter, S. R. Marschner, H. Li, K. E. Torrance, "Microfacet Models for Refraction through Rough
//! Surfaces", EGSR 2007, eq. 20).
//!
//! Composes one [`Mixture`] of distributions, one [`Masking`] and one [`Fresnel`]; each term's
//! formula lives in its own module. The denominator is 4 with a normalised D (Walter et al. 2007; some
//! textbooks print `DGF/(π (n·l)(n·v))`): the π form belongs with Cook and Torrance's un-normalised D
//! and makes an energy-conserving D 4/π too bright. With
//! F = 1 and V-groove G the Beckmann directional albedo is 1.000 at m = 0.1 (normal view) and drops
//! with m (lost multiple scattering); the tests recompute those numbers.
//!
//! Hot path (isotropic, the benchmarked GGX/Smith/Schlick case): no frame and no normalised half
//! vector. `h̃ = l + v` is kept un-normalised as `n·h̃`, `|h̃ − (n·h̃)n|²` and `|h̃|²`
//! ([`HalfVector`]); D is written in those (GGX: `α²|h̃|⁴/(π(α²(n·h̃)² + |h̃⊥|²)²)`), `v·h = |h̃|/2`,
//! then the GGX visibility `G/(4 n·l n·v)` in closed form and Schlick with four multiplications: one
//! square root for h, two for the visibility, no `powf`, no trigonometry.
//!
//! Why not `|h̃| = √(2 + 2 l·v)` and `n·h = (n·l + n·v)/|h̃|` from the cosines (the earlier form,
//! still behind [`CookTorrance::specular`]): for light and viewer nearly opposite (both grazing,
//! `|h̃| < 0.25`) `2 + 2 l·v` cancels, and near a sharp lobe's peak so does `1 − (n·h)²`; against a
//! float64 reference that form was off at α = 0.05 by up to 22 % for `|h̃|` in 0.03–0.1,
//! 160 % in 0.01–0.03 and 100× below (see [`crate::microfacet::half`]). The vector form costs
//! ~15 more flops per sample.

use glam::Vec3;

use crate::BrdfError;
use crate::fresnel::{self, Fresnel};
use crate::masking::{MASKING_NAMES, Masking};
use crate::microfacet::{Distribution, HalfVector, Mixture};
use crate::models::{Bxdf, ModelKind};
use crate::params::{DerivedDefault, DerivedValue, ModelSpec, ParamKind, ParamSpec, Params, Value};
use crate::simd::{Lane, LaneGeometry, V3};

/// Distributions the Cook–Torrance model accepts (isotropic ones).
pub const CT_DISTRIBUTIONS: &[&str] = &["ggx", "beckmann", "gaussian", "blinn_phong"];
/// Fresnel choices of the Cook–Torrance model.
pub const CT_FRESNELS: &[&str] = &["schlick", "dielectric", "conductor", "color_shift", "none"];
/// Metal presets: "none" or a symbol of [`fresnel::METAL_F0`].
pub const CT_METALS: &[&str] = &["none", "ti", "cr", "fe", "ni", "pt", "cu", "pd", "zn", "au", "al", "ag"];
const CT_MASKINGS: &[&str] = &MASKING_NAMES;

/// Cook–Torrance: Lambertian diffuse plus a microfacet specular lobe.
#[derive(Debug, Clone, PartialEq)]
pub struct CookTorrance {
    /// Diffuse reflectance kd (the diffuse term is `kd/π`).
    pub kd: Vec3,
    /// Specular scale ks (multiplies D·G·F/(4 n·l n·v)).
    pub ks: Vec3,
    /// Microfacet distribution (one lobe, or a weighted mixture).
    pub distribution: Mixture,
    /// Shadowing–masking term.
    pub masking: Masking,
    /// Fresnel term, evaluated at `v·h`.
    pub fresnel: Fresnel,
    /// A metal preset gave the Fresnel term ([`Bxdf::from_params`] with `metal`), so the `f0`
    /// parameter does not drive it.
    pub metal_preset: bool,
}

impl CookTorrance {
    /// Compose a Cook–Torrance BRDF from its terms.
    pub fn new(
        kd: Vec3,
        ks: Vec3,
        distribution: impl Into<Mixture>,
        masking: Masking,
        fresnel: Fresnel,
    ) -> Self {
        Self { kd, ks, distribution: distribution.into(), masking, fresnel, metal_preset: false }
    }

    /// The specular part `D G F/(4 (n·l)(n·v))` [1/sr] from the cosines and `l·v`; 0 unless both
    /// cosines are positive and `l ≠ −v`. The half vector comes from [`HalfVector::from_cosines`],
    /// which loses precision for nearly opposite `l`, `v`: with the vectors at hand use
    /// [`CookTorrance::specular_half`] and [`HalfVector::from_directions`] (what [`Bxdf::f`] does).
    #[inline]
    pub fn specular(&self, nl: f32, nv: f32, lv: f32) -> Vec3 {
        self.specular_half(nl, nv, &HalfVector::from_cosines(nl, nv, lv))
    }

    /// [`CookTorrance::specular`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn specular_lanes<F: Lane>(&self, nl: F, nv: F, lv: F) -> V3<F> {
        self.specular_half_lanes(nl, nv, &HalfVector::from_cosines(nl, nv, lv))
    }

    /// The specular part `D G F/(4 (n·l)(n·v))` [1/sr] from the cosines and the un-normalised half
    /// vector `h̃ = l + v`; 0 unless both cosines are positive and `|h̃|² > 1e−12` (`l ≠ −v`; below
    /// that `h` is float32 rounding noise of unit vectors).
    #[inline]
    pub fn specular_half(&self, nl: f32, nv: f32, h: &HalfVector<f32>) -> Vec3 {
        self.specular_half_lanes(nl, nv, h).into()
    }

    /// [`CookTorrance::specular_half`] on lanes (the one place its formula is written; see
    /// [`crate::simd`]).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn specular_half_lanes<F: Lane>(&self, nl: F, nv: F, h: &HalfVector<F>) -> V3<F> {
        let zero = F::splat(0.0);
        let len = h.len2.sqrt(); // |l + v|
        let nh = (h.n_dot / len).min(F::splat(1.0));
        let vh = F::splat(0.5) * len; // v·h = l·h = |l + v|/2
        let d = self.distribution.d_half_lanes(h);
        let vis = self.masking.visibility_lanes(nl, nv, nh, vh, &self.distribution);
        let lobe = self.fresnel.eval_lanes(vh).scale(d * vis);
        // 0 below the horizon, for l = −v, and where D = 0 (whatever G and F give there).
        let ok = nl.gt(zero) & nv.gt(zero) & h.len2.gt(F::splat(1e-12)) & !d.eq(zero);
        V3::select(ok, lobe, V3::splat(Vec3::ZERO))
    }

    /// The whole BRDF on lanes; [`Bxdf::f`] is this with `F = f32`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn f_generic<F: Lane>(&self, g: &LaneGeometry<F>) -> V3<F> {
        let h = HalfVector::from_directions(g.l, g.v, g.n);
        V3::splat(self.kd * std::f32::consts::FRAC_1_PI)
            + V3::splat(self.ks) * self.specular_half_lanes(g.nl, g.nv, &h)
    }
}

impl Bxdf for CookTorrance {
    const SPEC: ModelSpec = ModelSpec {
        name: "cook_torrance",
        summary: "Cook-Torrance microfacet BRDF, f = kd/pi + ks*D*G*F/(4 (n.l)(n.v)) with a choice of D, G and F",
        source: "R. L. Cook, K. E. Torrance, A Reflectance Model for Computer Graphics, ACM ToG 1(1) (1982); B. Walter et al., Microfacet Models for Refraction through Rough Surfaces, EGSR (2007), eq. 20; E. Heitz, Understanding the Masking-Shadowing Function, JCGT 3(2) (2014)",
        physical: true,
        anisotropic: false,
        params: &[
            // A red plastic by default (f0 = 0.04); a metal preset has no diffuse term unless kd is given.
            ParamSpec {
                name: "kd",
                kind: ParamKind::Color,
                default: Value::Color([0.5, 0.12, 0.08]),
                min: 0.0,
                max: 1.0,
                unit: "reflectance",
                doc: "diffuse reflectance (kd/pi); default a red plastic, 0 with a metal preset unless given",
                derived_default: Some(DerivedDefault {
                    when: "metal",
                    unless: "none",
                    value: DerivedValue::Color([0.0; 3]),
                }),
            },
            ParamSpec::color("ks", [1.0; 3], 0.0, 1.0, "1", "specular scale"),
            ParamSpec::choice("distribution", CT_DISTRIBUTIONS, "ggx", "microfacet distribution D"),
            ParamSpec::scalar(
                "roughness",
                0.3,
                0.0,
                2.0,
                "alpha",
                "alpha of GGX/Beckmann, m [rad] of the Gaussian, exponent 2/alpha^2-2 of Blinn-Phong; floored at 1e-4",
            ),
            ParamSpec::choice(
                "masking",
                CT_MASKINGS,
                "smith",
                "shadowing-masking G (smith = height-correlated)",
            ),
            ParamSpec::choice("fresnel", CT_FRESNELS, "schlick", "Fresnel term F at v.h"),
            ParamSpec::color(
                "f0",
                [0.04; 3],
                0.0,
                1.0,
                "reflectance",
                "normal-incidence reflectance (schlick, color_shift)",
            ),
            ParamSpec::scalar(
                "ior",
                1.5,
                0.01,
                10.0,
                "1",
                "relative index eta_inside/eta_outside (dielectric)",
            ),
            ParamSpec::color("eta", [1.5; 3], 0.01, 10.0, "1", "real part of the complex index (conductor)"),
            ParamSpec::color("k", [0.0; 3], 0.0, 20.0, "1", "extinction coefficient kappa (conductor)"),
            ParamSpec::choice(
                "metal",
                CT_METALS,
                "none",
                "metal F0 preset (N. Hoffman, Physics and Math of Shading, SIGGRAPH 2010 course); overrides f0, ior, eta and k",
            ),
            ParamSpec::scalar("roughness2", 0.3, 0.0, 2.0, "alpha", "roughness of the second lobe"),
            ParamSpec::scalar(
                "weight2",
                0.0,
                0.0,
                1.0,
                "1",
                "weight of the second lobe: D = (1-w) D1 + w D2",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted for `kd`; for each lobe of the distribution its visible normals (GGX, Beckmann,
    /// Gaussian via Beckmann) or `D cos θ_h` (Blinn–Phong), [`crate::sampling::Technique::for_distribution`],
    /// weighted by the lobe's weight times `mean(ks ∘ F(n·v))`.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique, mean};
        let mut s = Sampler::new().with(Technique::Cosine, mean(self.kd));
        for (w, d) in self.distribution.lobes() {
            s = s.with_fresnel(Technique::for_distribution(d), *w, self.ks, self.fresnel);
        }
        Ok(s)
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        let name = p.choice("distribution");
        let d1 = Distribution::from_roughness(name, p.scalar("roughness"))?;
        let w2 = p.scalar("weight2");
        let distribution = if w2 > 0.0 {
            let d2 = Distribution::from_roughness(name, p.scalar("roughness2"))?;
            Mixture::new(&[(1.0 - w2, d1), (w2, d2)])?
        } else {
            Mixture::single(d1)
        };
        let masking = Masking::from_name(p.choice("masking"))?;
        // A metal preset gives an F0 colour; every Fresnel choice is then driven by it.
        let metal = match p.choice("metal") {
            "none" => None,
            m => Some(
                fresnel::metal_f0_clamped(m)
                    .ok_or_else(|| BrdfError::param("metal", format!("unknown metal {m:?}")))?,
            ),
        };
        let f0 = metal.unwrap_or_else(|| p.color("f0"));
        let fresnel = match p.choice("fresnel") {
            "none" => Fresnel::None,
            "schlick" => Fresnel::Schlick { f0 },
            "dielectric" => Fresnel::Dielectric {
                eta: match metal {
                    // Cook & Torrance 1982: an index per channel from F0.
                    Some(f0) => {
                        let f0 = f0.min(Vec3::splat(0.9999));
                        Vec3::new(
                            fresnel::ior_from_f0(f0.x),
                            fresnel::ior_from_f0(f0.y),
                            fresnel::ior_from_f0(f0.z),
                        )
                    }
                    None => Vec3::splat(p.scalar("ior")),
                },
            },
            "conductor" => match metal {
                Some(f0) => Fresnel::Conductor { eta: Vec3::ONE, k: fresnel::conductor_k_from_f0(f0) },
                None => Fresnel::Conductor { eta: p.color("eta"), k: p.color("k") },
            },
            "color_shift" => Fresnel::color_shift(f0),
            other => return Err(BrdfError::param("fresnel", format!("unknown Fresnel term {other:?}"))),
        };
        let mut m = Self::new(p.color("kd"), p.color("ks"), distribution, masking, fresnel);
        m.metal_preset = metal.is_some();
        Ok(m)
    }

    /// `kd` (slot 0), `ks` (1), `roughness` (3, with one lobe) and `f0` (6, with Schlick's Fresnel and
    /// no metal preset) in place; the rest by a rebuild.
    #[inline]
    fn set_param(&mut self, slot: usize, value: &Value) -> bool {
        match (slot, value) {
            (0, Value::Color(c)) => self.kd = Vec3::from_array(*c),
            (1, Value::Color(c)) => self.ks = Vec3::from_array(*c),
            (3, Value::Scalar(alpha)) => {
                let [(_, d)] = self.distribution.lobes() else { return false };
                match d.with_roughness(*alpha) {
                    Some(d) => self.distribution = Mixture::single(d),
                    None => return false,
                }
            }
            (6, Value::Color(c)) => match &mut self.fresnel {
                Fresnel::Schlick { f0 } if !self.metal_preset => *f0 = Vec3::from_array(*c),
                _ => return false,
            },
            _ => return false,
        }
        true
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        self.f_generic(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Geometry;
    use crate::simd::{F32x8, LaneKernel, run_widest};

    /// Every D (and a two-lobe mixture) × every G × every F, including an exact conductor with
    /// the gold index Mitsuba uses at RGB.
    fn every_configuration() -> Vec<CookTorrance> {
        let ds: Vec<Mixture> = vec![
            Distribution::ggx(0.3).into(),
            Distribution::ggx(0.05).into(),
            Distribution::beckmann(0.3).into(),
            Distribution::gaussian(0.3).into(),
            Distribution::blinn_phong(crate::microfacet::blinn_phong::exponent_from_alpha(0.3)).into(),
            Distribution::from_roughness("ashikhmin_shirley", 0.2).unwrap().into(),
            Mixture::new(&[(0.7, Distribution::beckmann(0.1)), (0.3, Distribution::beckmann(0.5))]).unwrap(),
        ];
        let gs = [Masking::Smith, Masking::SmithSeparable, Masking::VGroove, Masking::Kelemen, Masking::None];
        let fs = [
            Fresnel::Schlick { f0: Vec3::new(0.04, 0.5, 0.9) },
            Fresnel::Dielectric { eta: Vec3::splat(1.5) },
            Fresnel::Dielectric { eta: Vec3::new(1.3, 1.5, 2.4) },
            Fresnel::Conductor {
                eta: Vec3::new(0.143_036, 0.375_307, 1.442_045),
                k: Vec3::new(3.982_997, 2.385_556, 1.603_359),
            },
            Fresnel::color_shift(Vec3::new(0.95, 0.64, 0.54)),
            Fresnel::None,
        ];
        let mut out = Vec::new();
        for d in &ds {
            for g in gs {
                for f in fs {
                    out.push(CookTorrance::new(Vec3::new(0.2, 0.1, 0.05), Vec3::ONE, *d, g, f));
                }
            }
        }
        out
    }

    /// Random directions with degenerate rows (zero, below the horizon, l = −v, grazing) mixed in.
    fn rows(n: usize) -> (Vec<Vec3>, Vec<Vec3>, Vec<Vec3>) {
        let mut seed = 0x9e37_79b9_u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let (mut l, mut v, mut nrm) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..n {
            let a = Vec3::new(rnd(), rnd(), rnd().abs() + 0.02);
            let b = match i % 29 {
                3 => -a,
                7 => Vec3::new(a.x, a.y, 1e-4),
                11 => a,
                _ => Vec3::new(rnd(), rnd(), rnd().abs() * 1.2 + 0.01),
            };
            l.push(if i % 31 == 5 { Vec3::ZERO } else { a });
            v.push(if i % 37 == 9 { Vec3::new(0.0, 0.0, -1.0) } else { b });
            nrm.push(Vec3::new(0.1 * rnd(), 0.1 * rnd(), 1.0));
        }
        (l, v, nrm)
    }

    struct Compare<'a>(&'a [CookTorrance], &'a (Vec<Vec3>, Vec<Vec3>, Vec<Vec3>));

    impl LaneKernel for Compare<'_> {
        #[cfg_attr(debug_assertions, inline)]
        #[cfg_attr(not(debug_assertions), inline(always))]
        fn run<F: Lane>(self) {
            let (l, v, n) = self.1;
            for ct in self.0 {
                for start in (0..l.len() - F::LANES).step_by(F::LANES) {
                    let r = start..start + F::LANES;
                    let (g, ok) = LaneGeometry::new(
                        F::load_rows(&l[r.clone()]),
                        F::load_rows(&v[r.clone()]),
                        F::load_rows(&n[r]),
                        None,
                    );
                    let f = ct.f_lanes(&g, ok);
                    for i in 0..F::LANES {
                        let Some(s) = Geometry::new(l[start + i], v[start + i], n[start + i], None) else {
                            continue;
                        };
                        let (got, want) = (f.lane(i), ct.f(&s));
                        assert_eq!(
                            got.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits),
                            "{ct:?} row {}: {got} vs {want} ({} lanes)",
                            start + i,
                            F::LANES
                        );
                    }
                }
            }
        }
    }

    /// batch == scalar for every D, G and F: the eight-lane forms (AVX2 where available, and the
    /// portable one) give the bits of `Bxdf::f` on every sample.
    #[test]
    fn every_term_gives_the_scalar_bits_in_every_lane_type() {
        let cts = every_configuration();
        let data = rows(203);
        Compare(&cts, &data).run::<F32x8>();
        run_widest(Compare(&cts, &data));
    }

    /// No term yields NaN or a negative value on valid or degenerate geometry.
    #[test]
    fn every_configuration_is_finite_and_non_negative() {
        let (l, v, n) = rows(203);
        for ct in every_configuration() {
            for i in 0..l.len() {
                if let Some(g) = Geometry::new(l[i], v[i], n[i], None) {
                    let f = ct.f(&g);
                    assert!(f.is_finite() && f.min_element() >= 0.0, "{ct:?} row {i}: {f}");
                }
            }
        }
    }
}
