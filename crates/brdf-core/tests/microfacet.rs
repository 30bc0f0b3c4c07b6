//! Microfacet distributions and masking terms as specifications: every D is normalised
//! (∫ D cos θ_h dω_h = 1, by quadrature), Smith Λ satisfies the visible-projected-area identity,
//! G1 has the right limits, and the mapped/approximate forms stay close to the exact ones.

use std::f64::consts::{FRAC_PI_2, PI};

use brdf_core::masking::{self, Masking};
use brdf_core::microfacet::{
    Distribution, Mixture, ashikhmin_shirley, beckmann, blinn_phong, gaussian, ggx, ward,
};
use glam::Vec3A;

fn dir(theta: f64, phi: f64) -> Vec3A {
    Vec3A::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32)
}

/// ∫_hemisphere g(w) dω by the midpoint rule in (t, φ) with θ = (π/2) t² (dense near the pole, where
/// narrow lobes live): dω = sinθ dθ dφ, dθ = π t dt.
fn hemisphere_integral(n_t: usize, n_phi: usize, g: impl Fn(Vec3A) -> f64) -> f64 {
    let mut sum = 0.0;
    for i in 0..n_t {
        let t = (i as f64 + 0.5) / n_t as f64;
        let theta = FRAC_PI_2 * t * t;
        let w_theta = theta.sin() * PI * t / n_t as f64;
        for j in 0..n_phi {
            let phi = 2.0 * PI * (j as f64 + 0.5) / n_phi as f64;
            sum += g(dir(theta, phi)) * w_theta * (2.0 * PI / n_phi as f64);
        }
    }
    sum
}

fn projected_area(d: &Distribution) -> f64 {
    let n_phi = if d.is_isotropic() { 4 } else { 256 };
    hemisphere_integral(3000, n_phi, |h| f64::from(d.d(h)) * f64::from(h.z))
}

#[test]
fn every_distribution_is_normalised_at_several_roughnesses() {
    let mut cases = Vec::new();
    for a in [0.05f32, 0.2, 0.5, 1.0] {
        cases.push(Distribution::beckmann(a));
        cases.push(Distribution::ggx(a));
        cases.push(Distribution::gaussian(a));
    }
    for m in [0.0f32, 1.0, 10.0, 100.0, 1000.0] {
        cases.push(Distribution::blinn_phong(m));
    }
    cases.extend([
        Distribution::beckmann_aniso(0.1, 0.4),
        Distribution::ggx_aniso(0.1, 0.5),
        Distribution::ggx_aniso(0.8, 0.05),
        Distribution::ward(0.15, 0.3),
        Distribution::ward(0.5, 0.08),
        Distribution::ashikhmin_shirley(100.0, 10.0),
        Distribution::ashikhmin_shirley(1000.0, 50.0),
        Distribution::ashikhmin_shirley(5.0, 5.0),
    ]);
    for d in cases {
        let area = projected_area(&d);
        assert!((area - 1.0).abs() < 2e-3, "{d:?}: ∫ D cos = {area}");
    }
}

#[test]
fn a_weighted_mixture_of_normalised_lobes_is_normalised() {
    let m = Mixture::new(&[(3.0, Distribution::beckmann(0.1)), (7.0, Distribution::ggx(0.6))]).unwrap();
    let w: Vec<f32> = m.lobes().iter().map(|(w, _)| *w).collect();
    assert!((w[0] - 0.3).abs() < 1e-6 && (w[1] - 0.7).abs() < 1e-6);
    let area = hemisphere_integral(3000, 4, |h| f64::from(m.d(h)) * f64::from(h.z));
    assert!((area - 1.0).abs() < 2e-3, "{area}");
    assert!(Mixture::new(&[]).is_err());
    assert!(Mixture::new(&[(0.0, Distribution::ggx(0.1))]).is_err());
    assert!(Mixture::new(&[(-1.0, Distribution::ggx(0.1)), (2.0, Distribution::ggx(0.2))]).is_err());
}

#[test]
fn seed_001_ward_formula_is_the_slope_density_not_a_normalised_d() {
    let (ax, ay) = (0.2f32, 0.4f32);
    // ∫ P22 d(slope) = ∫ P22 / cos³θ dω = 1 ...
    let slope_total =
        hemisphere_integral(3000, 256, |h| f64::from(ward::slope_pdf(h, ax, ay)) / f64::from(h.z).powi(3));
    assert!((slope_total - 1.0).abs() < 2e-3, "{slope_total}");
    // ... so it is not normalised as a D, while D = P22/cos⁴ is.
    let as_d = hemisphere_integral(3000, 256, |h| f64::from(ward::slope_pdf(h, ax, ay)) * f64::from(h.z));
    assert!(as_d < 0.95, "{as_d}");
    let h = dir(0.3, 0.7);
    assert!(
        (ward::d(h, ax, ay) - ward::slope_pdf(h, ax, ay) / h.z.powi(4)).abs() < 1e-4 * ward::d(h, ax, ay)
    );
}

#[test]
fn ashikhmin_shirley_half_vector_density_integrates_to_one_without_the_cosine() {
    for (nu, nv) in [(100.0f32, 10.0f32), (5.0, 500.0), (20.0, 20.0)] {
        let total = hemisphere_integral(3000, 256, |h| f64::from(ashikhmin_shirley::pdf_h(h, nu, nv)));
        assert!((total - 1.0).abs() < 2e-3, "({nu}, {nv}): {total}");
    }
    // Isotropic AS D is the normalised Blinn-Phong D.
    let h = dir(0.4, 1.0);
    assert!((ashikhmin_shirley::d(h, 30.0, 30.0) - blinn_phong::d(h.z, 30.0)).abs() < 1e-5);
}

#[test]
fn gaussian_constant_approaches_beckmanns_for_small_roughness() {
    for m in [0.01f32, 0.05] {
        let c = gaussian::normalization(m);
        let beck = 1.0 / (std::f32::consts::PI * m * m);
        assert!((c / beck - 1.0).abs() < 0.01, "m {m}: c {c} vs 1/(πm²) {beck}");
    }
    // For rough surfaces the hemisphere cut matters: c is larger than the small-slope value.
    assert!(gaussian::normalization(1.0) > 1.0 / std::f32::consts::PI);
    assert!((gaussian::d(0.9, 0.3) - Distribution::gaussian(0.3).d_cos(0.9)).abs() < 1e-6);
}

#[test]
fn isotropic_fast_path_equals_the_local_frame_evaluation() {
    for d in [
        Distribution::beckmann(0.3),
        Distribution::ggx(0.3),
        Distribution::gaussian(0.3),
        Distribution::blinn_phong(20.0),
        Distribution::ward(0.3, 0.3),
        Distribution::ashikhmin_shirley(20.0, 20.0),
    ] {
        for (theta, phi) in [(0.0, 0.0), (0.3, 1.0), (1.0, 4.0)] {
            let h = dir(theta, phi);
            let (a, b) = (d.d(h), d.d_cos(h.z));
            assert!((a - b).abs() <= 1e-5 * a.max(1.0), "{d:?} θ {theta}: {a} vs {b}");
            let (a, b) = (d.lambda(h), d.lambda_cos(h.z));
            assert!((a - b).abs() <= 1e-5 * a.max(1.0), "{d:?} Λ θ {theta}: {a} vs {b}");
        }
    }
}

#[test]
fn distributions_vanish_below_the_horizon_and_never_give_nan() {
    for d in [
        Distribution::beckmann(0.0),
        Distribution::ggx(0.0),
        Distribution::gaussian(0.0),
        Distribution::blinn_phong(1e30),
        Distribution::ward(0.0, 1.0),
        Distribution::ashikhmin_shirley(0.0, 1e9),
    ] {
        assert_eq!(d.d(Vec3A::new(0.0, 0.6, -0.8)), 0.0, "{d:?}");
        assert_eq!(d.d(Vec3A::X), 0.0, "{d:?}");
        for h in [Vec3A::Z, dir(1e-4, 0.3), dir(0.5, 2.0), dir(FRAC_PI_2 - 1e-4, 1.0)] {
            let v = d.d(h);
            assert!(v.is_finite() && v >= 0.0, "{d:?} at {h}: {v}");
            let g = d.g1(h);
            assert!(g.is_finite() && (0.0..=1.0).contains(&g), "{d:?} G1 at {h}: {g}");
        }
    }
}

/// Smith's visible-area identity (Heitz 2014 eq. 9 with G1 = 1/(1 + Λ)):
/// `∫ D(h) max(0, v·h) dω_h = (1 + Λ(v)) cos θ_v`. It pins Λ to its D.
#[test]
fn smith_lambda_satisfies_the_projected_area_identity() {
    for d in [
        Distribution::ggx(0.3),
        Distribution::ggx(0.8),
        Distribution::beckmann(0.3),
        Distribution::beckmann(0.7),
        Distribution::ggx_aniso(0.2, 0.6),
        Distribution::beckmann_aniso(0.5, 0.15),
    ] {
        for (theta_v, phi_v) in [(0.3f64, 0.0f64), (1.0, 0.5), (1.3, 2.0)] {
            let v = dir(theta_v, phi_v);
            let lhs = hemisphere_integral(1500, 256, |h| f64::from(d.d(h)) * f64::from(v.dot(h).max(0.0)));
            let rhs = (1.0 + f64::from(d.lambda(v))) * theta_v.cos();
            assert!((lhs - rhs).abs() < 2e-3 * rhs.max(0.1), "{d:?} θv {theta_v}: {lhs} vs {rhs}");
        }
    }
}

#[test]
fn g1_is_one_at_normal_incidence_zero_at_grazing_and_decreasing() {
    for alpha in [0.05f32, 0.3, 1.0] {
        assert!((ggx::g1(1.0, alpha) - 1.0).abs() < 1e-6);
        assert!((beckmann::g1(1.0, alpha) - 1.0).abs() < 1e-6);
        assert_eq!(ggx::g1(0.0, alpha), 0.0);
        assert_eq!(beckmann::g1(0.0, alpha), 0.0);
        assert!(ggx::g1(1e-4, alpha) < 0.01 && beckmann::g1(1e-4, alpha) < 0.01);
        let (mut pg, mut pb) = (1.0f32, 1.0f32);
        for i in (1..=100).rev() {
            let c = i as f32 / 100.0;
            let (g, b) = (ggx::g1(c, alpha), beckmann::g1(c, alpha));
            assert!(g <= pg + 1e-6 && b <= pb + 1e-6, "α {alpha} cos {c}");
            (pg, pb) = (g, b);
        }
    }
    // Smooth surfaces do not mask: G1 → 1 as α → 0 away from grazing.
    assert!(ggx::g1(0.2, 1e-4) > 0.9999 && beckmann::g1(0.2, 1e-4) > 0.9999);
    // Seed 001's printed GGX G1: 2/(1 + √(1 + α² tan²θ)).
    let (c, a) = (0.4f32, 0.5f32);
    let tan2 = (1.0 - c * c) / (c * c);
    assert!((ggx::g1(c, a) - 2.0 / (1.0 + (1.0 + a * a * tan2).sqrt())).abs() < 1e-6);
}

#[test]
fn height_correlated_smith_is_never_below_separable() {
    // Notes (b5): α = 1, n·l = n·v = 0.3 → separable 0.213, height-correlated 0.300 (recomputed).
    let hc = masking::smith_ggx(0.3, 0.3, 1.0);
    let sep = masking::smith_ggx_separable(0.3, 0.3, 1.0);
    let l = ggx::lambda(0.3, 1.0);
    assert!((hc - 1.0 / (1.0 + 2.0 * l)).abs() < 1e-6 && (sep - 1.0 / (1.0 + l).powi(2)).abs() < 1e-6);
    assert!((hc - 0.300).abs() < 5e-4 && (sep - 0.213).abs() < 5e-4, "{hc} {sep}");
    for a in [0.1f32, 0.5, 1.0] {
        for (nl, nv) in [(0.2f32, 0.9f32), (0.5, 0.5), (0.05, 0.3)] {
            assert!(masking::smith_ggx(nl, nv, a) >= masking::smith_ggx_separable(nl, nv, a));
            assert!(masking::smith_beckmann(nl, nv, a) >= masking::smith_beckmann_separable(nl, nv, a));
        }
    }
}

#[test]
fn ggx_visibility_forms_equal_g_over_four_cosines() {
    for a in [0.05f32, 0.3, 1.0] {
        for (nl, nv) in [(0.2f32, 0.9f32), (0.7, 0.4), (1.0, 1.0)] {
            let v = ggx::visibility_height_correlated(nl, nv, a);
            assert!((v - masking::smith_ggx(nl, nv, a) / (4.0 * nl * nv)).abs() < 1e-5 * v.max(1.0));
            let v = ggx::visibility_separable(nl, nv, a);
            assert!(
                (v - masking::smith_ggx_separable(nl, nv, a) / (4.0 * nl * nv)).abs() < 1e-5 * v.max(1.0)
            );
        }
    }
}

#[test]
fn erf_matches_reference_values() {
    // erf(0.5), erf(1), erf(2) to 10 digits (Abramowitz & Stegun table 7.1).
    for (x, want) in
        [(0.5f32, 0.520_499_877_8f64), (1.0, 0.842_700_792_9), (2.0, 0.995_322_265_0), (0.0, 0.0)]
    {
        assert!((f64::from(beckmann::erf(x)) - want).abs() < 3e-7, "erf({x})");
        assert!((f64::from(beckmann::erf(-x)) + want).abs() < 3e-7, "erf(-{x})");
    }
}

/// Walter et al. 2007 eq. 25 in float64: `G1 = 1/(1 + Λ)`, `Λ = (e^{−a²}/(a√π) − erfc a)/2`, with
/// `erf a = (2/√π) e^{−a²} Σ 2ⁿ a^{2n+1}/(1·3···(2n+1))` (Abramowitz & Stegun 7.1.6: positive terms, no
/// cancellation; 1e−16 absolute for a ≤ 4).
fn beckmann_g1_f64(a: f64) -> f64 {
    let (mut term, mut sum, mut k) = (a, a, 0.0);
    while term > 1e-18 * sum {
        k += 1.0;
        term *= 2.0 * a * a / (2.0 * k + 1.0);
        sum += term;
    }
    let e = (-a * a).exp();
    let erfc = 1.0 - 2.0 / PI.sqrt() * e * sum;
    1.0 / (1.0 + (e / (a * PI.sqrt()) - erfc) / 2.0)
}

/// The rational G1 is the erf form to a few float32 ulps over its whole range, G1 = 1 where the exact
/// value rounds to 1, and Λ(a) follows it (limits included).
#[test]
fn beckmann_g1_is_walters_erf_form_to_float32_precision() {
    let mut worst = 0.0f64;
    for i in 1..=200_000 {
        let a = beckmann::A_ONE * i as f32 / 200_000.0;
        let want = beckmann_g1_f64(f64::from(a));
        let got = 1.0 / (1.0 + f64::from(beckmann::lambda_of_a(a)));
        let (num, den) = beckmann::g1_parts_lanes(a);
        let g1 = f64::from(num / den);
        worst = worst.max((g1 / want - 1.0).abs()).max((got / want - 1.0).abs());
    }
    // scripts/fit_beckmann_g1.py: 3.7e-7 evaluated in float32 (6 ulps of 2^-24); Λ's own division adds one.
    assert!(worst < 5e-7, "max relative error of G1 {worst:e}");
    // Beyond A_ONE the exact G1 is within 2^-25 of 1: float32 has nothing between.
    assert!(1.0 - beckmann_g1_f64(f64::from(beckmann::A_ONE)) < 2f64.powi(-25));
    for a in [beckmann::A_ONE, 5.0, 1e30, f32::INFINITY] {
        assert_eq!(beckmann::lambda_of_a(a), 0.0, "a = {a}");
    }
    for a in [0.0, -1.0, f32::NAN] {
        assert_eq!(beckmann::lambda_of_a(a), f32::INFINITY, "a = {a}");
    }
    // Just above the horizon Λ ≈ 1/(2a√π) − 1/2, saturated at f32::MAX rather than overflowing.
    let a = 1e-3f32;
    let want = 1.0 / beckmann_g1_f64(f64::from(a)) - 1.0;
    assert!((f64::from(beckmann::lambda_of_a(a)) / want - 1.0).abs() < 5e-7);
    assert_eq!(beckmann::lambda_of_a(1e-44), f32::MAX);
}

/// The one-division visibility forms are `G/(4 (n·l)(n·v))` of the Λ forms, and 0 below the horizon.
#[test]
fn beckmann_visibility_forms_equal_g_over_four_cosines() {
    for a in [0.05f32, 0.3, 1.0] {
        for (nl, nv) in [(0.2f32, 0.9f32), (0.7, 0.4), (1.0, 1.0), (1e-3, 0.5)] {
            let v = beckmann::visibility_height_correlated_lanes(nl, nv, a);
            let want = masking::smith_beckmann(nl, nv, a) / (4.0 * nl * nv);
            assert!((v - want).abs() <= 1e-6 * want, "α {a} ({nl}, {nv}): {v} vs {want}");
            let v = beckmann::visibility_separable_lanes(nl, nv, a);
            let want = masking::smith_beckmann_separable(nl, nv, a) / (4.0 * nl * nv);
            assert!((v - want).abs() <= 1e-6 * want, "α {a} ({nl}, {nv}): {v} vs {want}");
        }
        // Both directions so close to the horizon that G1 underflows: 0, not 0/0.
        assert_eq!(beckmann::visibility_height_correlated_lanes(1e-30f32, 1e-30, a), 0.0);
        for (nl, nv) in [(0.0f32, 0.5f32), (0.5, -0.1), (-1.0, -1.0)] {
            assert_eq!(beckmann::visibility_height_correlated_lanes(nl, nv, a), 0.0);
            assert_eq!(beckmann::visibility_separable_lanes(nl, nv, a), 0.0);
        }
    }
}

#[test]
fn beckmann_rational_lambda_stays_within_its_stated_error() {
    let mut worst = 0.0f32;
    for a in [0.05f32, 0.2, 0.5, 1.0] {
        for i in 1..=200 {
            let c = i as f32 / 200.0;
            let exact = 1.0 / (1.0 + beckmann::lambda(c, a));
            let approx = 1.0 / (1.0 + beckmann::lambda_rational(c, a));
            worst = worst.max((exact - approx).abs());
        }
    }
    assert!(worst < 4e-3, "max |G1 rational − G1 exact| = {worst}");
}

#[test]
fn v_groove_and_kelemen_limits() {
    // l = v = n: nothing is shadowed.
    assert_eq!(masking::v_groove(1.0, 1.0, 1.0, 1.0), 1.0);
    assert!((masking::kelemen(1.0, 1.0, 1.0) - 1.0).abs() < 1e-7);
    // Grazing light is fully shadowed.
    assert_eq!(masking::v_groove(0.0, 1.0, 0.7, 0.7), 0.0);
    // Kelemen never exceeds 1 over random configurations; its G/(n·l n·v) is 1/(l·h)².
    let mut s = 1u32;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        f64::from(s) / f64::from(u32::MAX)
    };
    let n = Vec3A::Z;
    let dm = Mixture::single(Distribution::ggx(0.3));
    for _ in 0..2000 {
        let l = dir(rnd() * 1.5, rnd() * 2.0 * PI);
        let v = dir(rnd() * 1.5, rnd() * 2.0 * PI);
        let h = (l + v).normalize();
        let (nl, nv, nh, vh) = (l.z, v.z, h.z, v.dot(h));
        let k = masking::kelemen(nl, nv, vh);
        assert!(k <= 1.0 && (k / (nl * nv) - 1.0 / (vh * vh)).abs() < 1e-3 / (vh * vh));
        let vg = masking::v_groove(nl, nv, nh, vh);
        assert!((0.0..=1.0).contains(&vg));
        for m in [Masking::Smith, Masking::SmithSeparable, Masking::VGroove, Masking::Kelemen, Masking::None]
        {
            let (a, b) = (m.g_world(l, v, n, None, &dm), m.g_cos(nl, nv, nh, vh, &dm));
            assert!((a - b).abs() < 1e-5, "{m:?}: {a} vs {b}");
            assert_eq!(Masking::from_name(m.name()).unwrap(), m);
        }
    }
    assert!(Masking::from_name("smithy").is_err());
}

#[test]
fn registry_names_build_each_distribution_with_its_native_parameters() {
    assert_eq!(Distribution::from_name("GGX", 0.2, None).unwrap(), Distribution::ggx(0.2));
    assert_eq!(Distribution::from_name("ward", 0.1, Some(0.3)).unwrap(), Distribution::ward(0.1, 0.3));
    // Blinn-Phong takes a roughness here, mapped to the exponent 2/α² − 2 (Walter et al. 2007).
    let Distribution::BlinnPhong { exponent } = Distribution::from_name("blinn_phong", 0.3, None).unwrap()
    else {
        panic!()
    };
    assert!((exponent - (2.0 / 0.09 - 2.0)).abs() < 1e-3);
    assert_eq!(
        Distribution::from_roughness("blinn_phong", 0.3).unwrap(),
        Distribution::blinn_phong(exponent)
    );
    assert_eq!(
        Distribution::from_name("ashikhmin_shirley", 100.0, Some(10.0)).unwrap(),
        Distribution::ashikhmin_shirley(100.0, 10.0)
    );
    assert!(Distribution::from_name("blinn_phong", 0.3, Some(0.1)).is_err());
    for bad in [-0.1f32, 0.0, f32::NAN, f32::INFINITY] {
        let e = Distribution::from_name("ggx", bad, None).unwrap_err().to_string();
        assert!(e.contains("alpha"), "{e}");
    }
    assert!(Distribution::from_name("ggx", 0.3, Some(-1.0)).unwrap_err().to_string().contains("alpha_y"));
    assert!(Distribution::from_name("phong", 0.1, None).unwrap_err().to_string().contains("phong"));
    // Models may ask for roughness 0: it is floored, not refused.
    assert_eq!(Distribution::from_roughness("ggx", 0.0).unwrap(), Distribution::ggx(1e-4));
    assert!(Distribution::from_roughness("ggx", -1.0).is_err());
    // The floor: α = 0 is raised to 1e-4 and stays finite at the peak.
    assert!(Distribution::ggx(0.0).d(Vec3A::Z).is_finite());
}
