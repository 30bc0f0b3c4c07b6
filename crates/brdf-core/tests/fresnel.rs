//! Fresnel terms as specifications: limits, identities between the printed forms, TIR, an
//! independent complex-arithmetic conductor, Schlick's accuracy, the metal table, the colour shift
//! and the reflected/transmitted split.

use brdf_core::fresnel::*;
use glam::{Vec3, Vec3A};

fn f0_of(eta: f64) -> f64 {
    ((eta - 1.0) / (eta + 1.0)).powi(2)
}

#[test]
fn dielectric_at_normal_incidence_is_the_f0_formula_and_at_grazing_is_one() {
    for eta in [1.0f32, 1.2, 1.33, 1.5, 2.4, 0.5] {
        let f = dielectric(1.0, eta);
        assert!((f64::from(f) - f0_of(f64::from(eta))).abs() < 1e-6, "eta {eta}: {f}");
        assert!((f - f0_from_ior(eta)).abs() < 1e-7);
        let (rs, rp) = dielectric_sp(1.0, eta);
        assert!((rs - rp).abs() < 1e-7, "s and p coincide at normal incidence");
        if eta != 1.0 {
            assert_eq!(dielectric(0.0, eta), 1.0, "grazing, eta {eta}");
        }
    }
    assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-7);
}

#[test]
fn s_p_form_equals_cook_torrance_g_form_everywhere_outside_tir() {
    // Notes (b3): F = ½ (g−c)²/(g+c)² [1 + (c(g+c)−1)²/(c(g−c)+1)²], g = √(η²+c²−1).
    for eta in [1.1f32, 1.33, 1.5, 2.4, 0.9] {
        for i in 0..=100 {
            let c = i as f32 / 100.0;
            if eta * eta + c * c - 1.0 < 0.0 {
                continue;
            }
            let a = dielectric(c, eta);
            let b = dielectric_cook_torrance(c, eta);
            assert!((a - b).abs() < 1e-5, "eta {eta} cos {c}: s/p {a} vs CT {b}");
        }
    }
}

#[test]
fn the_common_denominator_typo_would_be_caught() {
    // (c(g+c)+1)² instead of (c(g−c)+1)² is off by up to ~0.016 at η = 1.5 (notes b3).
    let eta = 1.5f64;
    let mut worst = 0.0f64;
    for i in 1..100 {
        let c = i as f64 / 100.0;
        let g = (eta * eta + c * c - 1.0).sqrt();
        let typo =
            0.5 * ((g - c) / (g + c)).powi(2) * (1.0 + ((c * (g + c) - 1.0) / (c * (g + c) + 1.0)).powi(2));
        worst = worst.max((typo - f64::from(dielectric(c as f32, eta as f32))).abs());
    }
    assert!(worst > 0.01, "typo differs by {worst}");
}

#[test]
fn total_internal_reflection_from_inside_beyond_the_critical_angle() {
    let eta = 1.5f32; // glass inside, air outside; light arriving from inside has cos_i < 0
    let sin_c = 1.0 / eta;
    let cos_c = (1.0 - sin_c * sin_c).sqrt();
    assert_eq!(dielectric(-(cos_c - 0.01), eta), 1.0, "beyond the critical angle");
    assert!(dielectric(-(cos_c + 0.01), eta) < 1.0, "inside the critical angle");
    assert_eq!(dielectric_cook_torrance(cos_c - 0.01, 1.0 / eta), 1.0);
    // From inside at normal incidence the reflectance is the same F0.
    assert!((dielectric(-1.0, eta) - dielectric(1.0, eta)).abs() < 1e-7);
    let (rs, rp) = dielectric_sp(-0.1, eta);
    assert_eq!((rs, rp), (1.0, 1.0));
}

#[test]
fn p_polarised_reflectance_vanishes_at_brewsters_angle() {
    let eta = 1.5f32;
    let theta_b = eta.atan();
    let (rs, rp) = dielectric_sp(theta_b.cos(), eta);
    assert!(rp < 1e-6 && rs > 0.1, "rs {rs} rp {rp}");
}

/// Reflectance of a complex index n_t = η − iκ by complex arithmetic (independent of the library's
/// closed form): r_s = (cos_i − n_t cos_t)/(cos_i + n_t cos_t), r_p = (n_t cos_i − cos_t)/(n_t cos_i + cos_t),
/// cos_t = √(1 − sin²_i/n_t²).
fn conductor_reference(cos_i: f64, eta: f64, k: f64) -> f64 {
    #[derive(Clone, Copy)]
    struct C(f64, f64);
    let add = |a: C, b: C| C(a.0 + b.0, a.1 + b.1);
    let sub = |a: C, b: C| C(a.0 - b.0, a.1 - b.1);
    let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let sqrt = |a: C| {
        let r = (a.0 * a.0 + a.1 * a.1).sqrt();
        let re = ((r + a.0) / 2.0).sqrt();
        let im = ((r - a.0) / 2.0).sqrt().copysign(a.1);
        C(re, im)
    };
    let abs2 = |a: C| a.0 * a.0 + a.1 * a.1;
    let n = C(eta, -k);
    let ci = C(cos_i, 0.0);
    let sin2 = C(1.0 - cos_i * cos_i, 0.0);
    let ct = sqrt(sub(C(1.0, 0.0), div(sin2, mul(n, n))));
    let rs = div(sub(ci, mul(n, ct)), add(ci, mul(n, ct)));
    let rp = div(sub(mul(n, ci), ct), add(mul(n, ci), ct));
    0.5 * (abs2(rs) + abs2(rp))
}

#[test]
fn conductor_at_normal_incidence_matches_the_hand_derived_value() {
    // ((η−1)² + κ²)/((η+1)² + κ²) with η = 0.2, κ = 3: (0.64 + 9)/(1.44 + 9) = 9.64/10.44.
    let f = conductor_scalar(1.0, 0.2, 3.0);
    assert!((f64::from(f) - 9.64 / 10.44).abs() < 1e-6, "{f}");
    assert_eq!(conductor_scalar(0.0, 0.2, 3.0), 1.0, "grazing");
}

#[test]
fn conductor_matches_complex_arithmetic_at_every_angle() {
    for (eta, k) in [(0.2f32, 3.0f32), (1.1, 2.0), (0.05, 4.2), (2.5, 0.3), (1.5, 0.0)] {
        for i in 0..=50 {
            let c = i as f32 / 50.0;
            let got = conductor_scalar(c, eta, k);
            let want = conductor_reference(f64::from(c.max(1e-9)), f64::from(eta), f64::from(k));
            assert!((f64::from(got) - want).abs() < 2e-5, "eta {eta} k {k} cos {c}: {got} vs {want}");
        }
    }
}

#[test]
fn conductor_matches_seed_001_a_b_form() {
    // Seed 001 "Unpolarized light": R = ½ ((a−u)²+b²)/((a+u)²+b²) [((a+u−1/u)²+b²)/((a−u+1/u)²+b²) + 1].
    let (n, k) = (0.27f64, 2.8f64);
    for u in [0.1f64, 0.3, 0.5, 0.8, 1.0] {
        let t = n * n - k * k + u * u - 1.0;
        let r = (t * t + 4.0 * n * n * k * k).sqrt();
        let a = ((r + t) / 2.0).sqrt();
        let b2 = (r - t) / 2.0;
        let rs = ((a - u).powi(2) + b2) / ((a + u).powi(2) + b2);
        let ratio = ((a + u - 1.0 / u).powi(2) + b2) / ((a - u + 1.0 / u).powi(2) + b2);
        let want = 0.5 * rs * (ratio + 1.0);
        let got = f64::from(conductor_scalar(u as f32, n as f32, k as f32));
        assert!((got - want).abs() < 2e-5, "u {u}: {got} vs {want}");
    }
}

#[test]
fn conductor_without_extinction_is_the_dielectric() {
    for i in 0..=20 {
        let c = i as f32 / 20.0;
        assert!((conductor_scalar(c, 1.5, 0.0) - dielectric(c, 1.5)).abs() < 1e-5);
    }
}

#[test]
fn conductor_driven_by_f0_reproduces_f0_exactly() {
    let f0 = Vec3::new(0.955, 0.638, 0.538);
    let f = conductor(1.0, Vec3::ONE, conductor_k_from_f0(f0));
    assert!((f - f0).abs().max_element() < 1e-5, "{f}");
    assert!(conductor(1.0, Vec3::ONE, conductor_k_from_f0(Vec3::ONE)).is_finite());
}

#[test]
fn schlick_stays_within_a_few_percent_absolute_of_exact_for_dielectrics() {
    // Schlick's error is largest near grazing (cos θ ≈ 0.1) and for low η: 0.060 at η = 1.33,
    // 0.036 at η = 1.5 (absolute, on the [0, 1] reflectance scale); exact at both ends.
    for (eta, bound_all, bound_78) in [(1.33f32, 0.062, 0.045), (1.5, 0.037, 0.021), (1.7, 0.033, 0.026)] {
        let f0 = f0_from_ior(eta);
        let (mut worst, mut worst_78) = (0.0f32, 0.0f32);
        for i in 0..=1000 {
            let c = i as f32 / 1000.0;
            let e = (schlick_scalar(c, f0) - dielectric(c, eta)).abs();
            worst = worst.max(e);
            if c >= 0.2 {
                worst_78 = worst_78.max(e);
            }
        }
        assert!(worst < bound_all, "eta {eta}: max |Schlick − exact| = {worst}");
        assert!(worst_78 < bound_78, "eta {eta}: max for θ ≤ 78° = {worst_78}");
    }
    assert_eq!(schlick(1.0, Vec3::splat(0.04)), Vec3::splat(0.04));
    assert_eq!(schlick(0.0, Vec3::splat(0.04)), Vec3::ONE);
}

#[test]
fn f0_and_ior_convert_both_ways() {
    for eta in [1.0f32, 1.33, 1.5, 2.0, 3.5] {
        assert!((ior_from_f0(f0_from_ior(eta)) - eta).abs() < 1e-3 * eta);
    }
    assert!((ior_from_f0(0.04) - 1.5).abs() < 1e-5);
    assert_eq!(ior_from_f0(1.0), f32::INFINITY);
    assert_eq!(ior_from_f0(-1.0), 1.0);
    assert_eq!(f0_from_ior(-2.0), 0.0);
}

#[test]
fn metal_table_has_the_eleven_seed_metals_with_lookup_by_symbol_and_name() {
    let symbols: Vec<&str> = METAL_F0.iter().map(|(s, _)| *s).collect();
    assert_eq!(symbols, ["ti", "cr", "fe", "ni", "pt", "cu", "pd", "zn", "au", "al", "ag"]);
    assert_eq!(metal_f0("Au"), metal_f0("gold"));
    assert_eq!(metal_f0("aluminium"), metal_f0("al"));
    assert_eq!(metal_f0("unobtainium"), None);
    let cu = metal_f0("cu").unwrap();
    assert!(cu.x > cu.y && cu.x > cu.z, "copper is red");
    for (name, f0) in METAL_F0 {
        let c = metal_f0_clamped(name).unwrap();
        assert!(c.max_element() <= 1.0 && c.min_element() > 0.3, "{name}: {c}");
        // Metals reflect far more than dielectrics at normal incidence.
        assert!(f0.min_element() > 0.3, "{name}");
    }
    // The documented out-of-gamut entry.
    assert!(metal_f0("au").unwrap().x > 1.0);
}

#[test]
fn color_shift_keeps_f0_at_normal_incidence_and_reaches_one_at_grazing() {
    let f0 = Vec3::new(0.955, 0.638, 0.538);
    let r = color_shift_reference(f0);
    assert!((color_shift(1.0, f0, r) - f0).abs().max_element() < 1e-5);
    assert!((color_shift(0.0, f0, r) - Vec3::ONE).abs().max_element() < 1e-5);
    let mut prev = color_shift(1.0, f0, r);
    for i in (0..100).rev() {
        let f = color_shift(i as f32 / 100.0, f0, r);
        assert!(f.cmpge(prev - Vec3::splat(1e-6)).all(), "monotone toward grazing");
        prev = f;
    }
    // A grey F0 is its own reference: the interpolation is then the exact dielectric curve.
    let g = Vec3::splat(0.04);
    for i in 0..=10 {
        let c = i as f32 / 10.0;
        assert!((color_shift(c, g, 0.04).x - dielectric(c, 1.5)).abs() < 1e-4);
    }
    let fr = Fresnel::color_shift(f0);
    assert!((fr.eval(0.3) - color_shift(0.3, f0, r)).abs().max_element() < 1e-6);
}

#[test]
fn split_conserves_power_and_obeys_snell() {
    let n = Vec3A::Z;
    let w = Vec3A::new(0.6, 0.0, 0.8);
    let s = split(w, n, 1.5);
    assert!((s.reflectance + s.transmittance - 1.0).abs() < 1e-7);
    assert!((s.reflectance - dielectric(0.8, 1.5)).abs() < 1e-7);
    assert!((s.reflected - Vec3A::new(-0.6, 0.0, 0.8)).length() < 1e-6);
    let t = s.refracted.unwrap();
    assert!(t.z < 0.0 && (t.x.abs() * 1.5 - 0.6).abs() < 1e-5, "sin θt = sin θi / η: {t}");

    // From inside the glass (w below the outside normal), beyond the critical angle: TIR.
    let w_in = Vec3A::new(0.8, 0.0, -0.6);
    let s = split(w_in, n, 1.5);
    assert_eq!((s.reflectance, s.transmittance, s.refracted), (1.0, 0.0, None));
    assert!((s.reflected - Vec3A::new(-0.8, 0.0, -0.6)).length() < 1e-6);
    // From inside within the critical angle: light leaves into air, bending away from the normal.
    let w_in = Vec3A::new(0.3, 0.0, -(1.0f32 - 0.09).sqrt());
    let s = split(w_in, n, 1.5);
    let t = s.refracted.unwrap();
    assert!(t.z > 0.0 && (t.x.abs() - 0.45).abs() < 1e-5, "{t}");
    assert!((s.reflectance - dielectric(w_in.z, 1.5)).abs() < 1e-6);
}

#[test]
fn degenerate_arguments_never_give_nan() {
    for c in [-2.0f32, -1.0, 0.0, 1e-30, 1.0, 2.0, f32::NAN] {
        for eta in [0.0f32, -1.0, 1.0, 1.5, f32::INFINITY, f32::NAN] {
            let f = dielectric(c, eta);
            if !c.is_nan() {
                assert!(f.is_finite() && (0.0..=1.0).contains(&f), "cos {c} eta {eta}: {f}");
            }
        }
        if !c.is_nan() {
            assert!(conductor(c, Vec3::ONE, Vec3::ZERO).is_finite());
            assert!(schlick(c, Vec3::splat(0.5)).is_finite());
        }
    }
}
