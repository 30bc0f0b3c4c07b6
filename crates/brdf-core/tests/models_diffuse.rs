//! The diffuse, course-style ("classic") and Phong-family models: limits, closed forms recomputed in
//! f64, band boundaries, and the canonical benchmark's shading formula (bench/SCENE.md).

use std::f64::consts::PI;

use brdf_core::models::blinn_phong::{
    blinn_exponent_from_phong, normalization_exact, normalization_rtr, phong_exponent_from_blinn,
};
use brdf_core::models::oren_nayar::{oren_nayar_a, oren_nayar_b};
use brdf_core::params::Input;
use brdf_core::properties::{Quadrature, SplitMix64, directional_albedo};
use brdf_core::tonemap::{Operator, encode_srgb8};
use brdf_core::{Geometry, Model};
use glam::{DVec3, Vec3, Vec3A};

fn model(name: &str, params: &[(&str, Input)]) -> Model {
    let inputs: Vec<(String, Input)> = params.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    Model::build(name, &inputs).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn num(x: f64) -> Input {
    Input::Number(x)
}

fn text(s: &str) -> Input {
    Input::Text(s.into())
}

fn flag(b: bool) -> Input {
    Input::Bool(b)
}

fn geom(l: Vec3, v: Vec3, n: Vec3) -> Geometry {
    Geometry::new(l, v, n, None).expect("non-degenerate directions")
}

/// A direction at polar angle `theta` and azimuth `phi` about +z.
fn dir(theta: f64, phi: f64) -> Vec3 {
    Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32)
}

/// Random (l, v) pairs in the upper hemisphere of +z, by polar angle and azimuth.
fn random_pairs(count: usize, seed: u64) -> Vec<((f64, f64), (f64, f64))> {
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let mut angle = || (rng.next_f64() * 1.55, rng.next_f64() * 2.0 * PI);
            (angle(), angle())
        })
        .collect()
}

fn close(a: Vec3, b: DVec3, rel: f64) -> bool {
    (a.as_dvec3() - b).abs().max_element() <= rel * b.abs().max_element().max(1e-3)
}

// ---------------------------------------------------------------- Oren-Nayar

#[test]
fn oren_nayar_with_zero_roughness_is_lambert_in_every_variant() {
    let albedo = Input::Numbers(vec![0.9, 0.5, 0.2]);
    let lambert = model("lambert", &[("kd", albedo.clone())]);
    let variants = [
        model("oren_nayar", &[("kd", albedo.clone()), ("sigma", num(0.0))]),
        model("oren_nayar", &[("kd", albedo.clone()), ("sigma", num(0.0)), ("variant", text("compensated"))]),
        model("oren_nayar_full", &[("kd", albedo.clone()), ("sigma", num(0.0))]),
        model("oren_nayar_full", &[("kd", albedo), ("sigma", num(0.0)), ("interreflection", flag(false))]),
    ];
    for ((ti, pi), (tr, pr)) in random_pairs(2000, 1) {
        let g = geom(dir(ti, pi), dir(tr, pr), Vec3::Z);
        let expected = lambert.eval(&g);
        for m in &variants {
            assert!((m.eval(&g) - expected).abs().max_element() < 1e-7, "{m:?} at {g:?}");
        }
    }
}

/// Seed 000's GLSL for the qualitative model, with its acos / sin / tan, in f64.
fn oren_nayar_reference(rho: f64, sigma: f64, c: f64, l: (f64, f64), v: (f64, f64)) -> f64 {
    let (theta_i, theta_r) = (l.0, v.0);
    let (alpha, beta) = (theta_i.max(theta_r), theta_i.min(theta_r));
    let s2 = sigma * sigma;
    let a = 1.0 - 0.5 * s2 / (s2 + c);
    let b = 0.45 * s2 / (s2 + 0.09);
    let g = (v.1 - l.1).cos().max(0.0);
    rho / PI * (a + b * g * alpha.sin() * beta.tan())
}

#[test]
fn qualitative_oren_nayar_equals_the_course_formula_with_angles() {
    // The implementation uses max(0, s)/max(n·l, n·v) instead of acos, sin and tan.
    for (variant, c) in [("qualitative", 0.33), ("compensated", 0.57)] {
        for sigma in [0.2, 0.6, 1.5] {
            let m =
                model("oren_nayar", &[("kd", num(0.7)), ("sigma", num(sigma)), ("variant", text(variant))]);
            for (l, v) in random_pairs(500, 2) {
                let got = m.eval(&geom(dir(l.0, l.1), dir(v.0, v.1), Vec3::Z));
                let expected = oren_nayar_reference(0.7, sigma, c, l, v);
                assert!(
                    close(got, DVec3::splat(expected), 2e-4),
                    "{variant} σ={sigma} {l:?} {v:?}: {got} vs {expected}"
                );
            }
        }
    }
}

/// The full model of Oren & Nayar 1994 (notes (b4)) with explicit angles and azimuths, in f64.
fn oren_nayar_full_reference(
    rho: f64,
    sigma: f64,
    interreflection: bool,
    l: (f64, f64),
    v: (f64, f64),
) -> f64 {
    let (alpha, beta) = (l.0.max(v.0), l.0.min(v.0));
    let cos_dphi = (v.1 - l.1).cos();
    let s2 = sigma * sigma;
    let c1 = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let k = s2 / (s2 + 0.09);
    let c2 = if cos_dphi >= 0.0 {
        0.45 * k * alpha.sin()
    } else {
        0.45 * k * (alpha.sin() - (2.0 * beta / PI).powi(3))
    };
    let c3 = 0.125 * k * (4.0 * alpha * beta / (PI * PI)).powi(2);
    let l1 = rho / PI
        * (c1 + cos_dphi * c2 * beta.tan() + (1.0 - cos_dphi.abs()) * c3 * ((alpha + beta) / 2.0).tan());
    let l2 = 0.17 * rho * rho / PI * s2 / (s2 + 0.13) * (1.0 - cos_dphi * (2.0 * beta / PI).powi(2));
    l1 + if interreflection { l2 } else { 0.0 }
}

#[test]
fn full_oren_nayar_equals_the_published_formula_with_explicit_azimuths() {
    for sigma in [0.1, 0.5, 1.2, 1.57] {
        for interreflection in [true, false] {
            let m = model(
                "oren_nayar_full",
                &[("kd", num(0.8)), ("sigma", num(sigma)), ("interreflection", flag(interreflection))],
            );
            for (l, v) in random_pairs(500, 3) {
                let got = m.eval(&geom(dir(l.0, l.1), dir(v.0, v.1), Vec3::Z));
                let expected = oren_nayar_full_reference(0.8, sigma, interreflection, l, v);
                assert!(
                    close(got, DVec3::splat(expected), 5e-4),
                    "σ={sigma} {l:?} {v:?}: {got} vs {expected}"
                );
            }
        }
    }
}

#[test]
fn the_interreflection_term_scales_with_albedo_squared() {
    // L2 ∝ ρ² (paper), not ρ (seed 004's slip): at normal view only C1 and L2 remain.
    let l2 = |rho: f64| {
        let on = |ir| {
            model("oren_nayar_full", &[("kd", num(rho)), ("sigma", num(0.5)), ("interreflection", flag(ir))])
        };
        let g = geom(dir(0.7, 0.0), Vec3::Z, Vec3::Z);
        f64::from(on(true).eval(&g).x - on(false).eval(&g).x)
    };
    let (full, half) = (l2(1.0), l2(0.5));
    assert!((half / full - 0.25).abs() < 1e-4, "{half} / {full}");
    let s2 = 0.25;
    assert!((full - 0.17 / PI * s2 / (s2 + 0.13)).abs() < 1e-6, "{full}");
}

#[test]
fn oren_nayar_is_finite_and_continuous_at_normal_incidence() {
    let sigma = 0.8f64;
    let qon = model("oren_nayar", &[("kd", num(1.0)), ("sigma", num(sigma))]);
    let full = model("oren_nayar_full", &[("kd", num(1.0)), ("sigma", num(sigma))]);
    let s2 = sigma * sigma;
    let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let l2 = 0.17 * s2 / (s2 + 0.13);
    // β = 0 whenever either direction is the normal: only A (and C1 + L2) remain.
    for (l, v) in [(Vec3::Z, Vec3::Z), (Vec3::Z, dir(1.2, 0.3)), (dir(0.4, 2.0), Vec3::Z)] {
        let g = geom(l, v, Vec3::Z);
        let (q, f) = (qon.eval(&g), full.eval(&g));
        assert!(q.is_finite() && f.is_finite());
        assert!((f64::from(q.x) - a / PI).abs() < 1e-6, "{l} {v}: {q}");
        assert!((f64::from(f.x) - (a + l2) / PI).abs() < 1e-6, "{l} {v}: {f}");
        // And just off the normal, nothing jumps.
        let g2 = geom(l + Vec3::new(1e-4, 2e-4, 0.0), v + Vec3::new(-3e-4, 1e-4, 0.0), Vec3::Z);
        assert!((full.eval(&g2) - f).abs().max_element() < 1e-3, "{l} {v}");
    }
    // A normal that is not +z, with l = n exactly.
    let n = Vec3::new(0.3, -0.5, 0.8);
    let g = geom(n, Vec3::new(0.0, 0.2, 1.0), n);
    assert!(full.eval(&g).is_finite() && qon.eval(&g).is_finite());
}

#[test]
fn full_oren_nayar_stays_positive_up_to_grazing_at_maximum_roughness() {
    let full = model("oren_nayar_full", &[("kd", num(1.0)), ("sigma", num(std::f64::consts::FRAC_PI_2))]);
    for i in 1..120 {
        for j in 1..120 {
            for k in 0..7 {
                let (ti, tr) = (f64::from(i) * 1.5705 / 120.0, f64::from(j) * 1.5705 / 120.0);
                let g = geom(dir(ti, 0.0), dir(tr, f64::from(k) * PI / 6.0), Vec3::Z);
                let f = full.eval(&g);
                assert!(f.is_finite() && f.min_element() > 0.0, "θi={ti} θr={tr} k={k}: {f}");
            }
        }
    }
}

#[test]
fn rough_surfaces_scatter_back_toward_the_light() {
    // Retro-reflection (seed 002 "Retro-Reflection", seed 004): brighter seen from the light than from
    // the mirror direction, unlike Lambert.
    for name in ["oren_nayar", "oren_nayar_full"] {
        let m = model(name, &[("sigma", num(0.6))]);
        let l = dir(1.0, 0.0);
        let back = m.eval(&geom(l, l, Vec3::Z)).x;
        let mirror = m.eval(&geom(l, dir(1.0, PI), Vec3::Z)).x;
        assert!(back > 1.2 * mirror, "{name}: back {back}, mirror {mirror}");
    }
}

#[test]
fn oren_nayar_albedos_match_the_research_notes() {
    // Notes (b4) print these directional albedos (ρ = 1) to 3 decimals; our quadrature recomputes them.
    let q = Quadrature::default();
    let rows: [(f64, f32, [f64; 3]); 3] = [
        (20.0, 1.0, [0.865, 0.912, 0.947]),
        (40.0, 1.0, [0.702, 0.770, 0.836]),
        (90.0, 0.5, [0.688, 0.723, 0.761]),
    ];
    for (sigma_deg, cos_v, printed) in rows {
        let sigma = num(sigma_deg.to_radians().min(std::f64::consts::FRAC_PI_2));
        let models = [
            model("oren_nayar", &[("kd", num(1.0)), ("sigma", sigma.clone())]),
            model(
                "oren_nayar",
                &[("kd", num(1.0)), ("sigma", sigma.clone()), ("variant", text("compensated"))],
            ),
            model("oren_nayar_full", &[("kd", num(1.0)), ("sigma", sigma)]),
        ];
        for (m, p) in models.iter().zip(printed) {
            let rho = f64::from(directional_albedo(m, cos_v, &q).unwrap().x);
            assert!(
                (rho - p).abs() <= 5e-4 + 1e-5,
                "σ = {sigma_deg}°, cos θv = {cos_v}: {rho} vs printed {p}"
            );
        }
    }
}

#[test]
fn qualitative_albedo_at_normal_view_is_a() {
    // With v = n, β = 0 and f = ρA/π, so ρ(v) = ρA exactly.
    for sigma in [0.1f64, 0.35, 0.9, 1.5] {
        for (variant, c) in [("qualitative", 0.33), ("compensated", 0.57)] {
            let m =
                model("oren_nayar", &[("kd", num(1.0)), ("sigma", num(sigma)), ("variant", text(variant))]);
            let rho = f64::from(directional_albedo(&m, 1.0, &Quadrature::default()).unwrap().x);
            let a = 1.0 - 0.5 * sigma * sigma / (sigma * sigma + c);
            assert!((rho - a).abs() < 1e-6, "σ={sigma} {variant}: {rho} vs {a}");
            assert!((f64::from(oren_nayar_a(sigma as f32, c as f32)) - a).abs() < 1e-6);
        }
        let b = 0.45 * sigma * sigma / (sigma * sigma + 0.09);
        assert!((f64::from(oren_nayar_b(sigma as f32)) - b).abs() < 1e-6);
    }
}

#[test]
fn physical_models_are_black_below_the_horizon() {
    let below = geom(Vec3::new(0.3, 0.0, -0.5), Vec3::Z, Vec3::Z);
    let behind = geom(Vec3::Z, Vec3::new(0.3, 0.0, -0.5), Vec3::Z);
    for name in ["oren_nayar", "oren_nayar_full", "phong", "blinn_phong"] {
        let m = model(name, &[]);
        assert_eq!(m.eval(&below), Vec3::ZERO, "{name}");
        assert_eq!(m.eval(&behind), Vec3::ZERO, "{name}");
        assert_eq!(m.shade(&below), Vec3::ZERO, "{name}");
    }
}

// ---------------------------------------------------------------- course (classic) formulas

#[test]
fn classic_lambert_is_color_times_clamped_cosine() {
    let c = Vec3::new(0.9, 0.4, 0.1);
    let m = model("lambert_classic", &[("kd", Input::Numbers(vec![0.9, 0.4, 0.1]))]);
    for (l, expected_cos) in [(dir(0.0, 0.0), 1.0f32), (dir(1.0, 0.3), 1.0f32.cos()), (dir(2.0, 0.0), 0.0)] {
        let g = geom(l, Vec3::Z, Vec3::Z);
        assert!((m.shade(&g) - c * expected_cos).abs().max_element() < 1e-6);
        // f_r = shade / (n·l) = C where lit.
        if expected_cos > 0.0 {
            assert!((m.eval(&g) - c).abs().max_element() < 1e-6);
        } else {
            assert_eq!(m.eval(&g), Vec3::ZERO);
        }
    }
}

/// SCENE.md's formula with its two lights at surface point `p` (normal = p), in f64.
fn scene_color(p: DVec3) -> DVec3 {
    let (kd, ks, s, a) = (DVec3::new(0.8, 0.3, 0.2), DVec3::splat(0.5), 32, 0.05);
    let n = p.normalize();
    let v = (DVec3::new(0.0, 0.0, 3.0) - p).normalize();
    let to_point = DVec3::splat(2.0) - p;
    let lights = [(DVec3::ONE.normalize(), 1.0), (to_point.normalize(), 10.0 / to_point.length_squared())];
    let mut c = a * kd;
    for (l, e) in lights {
        let h = (l + v).normalize();
        let nl = n.dot(l);
        let spec = if nl > 0.0 { ks * n.dot(h).max(0.0).powi(s) } else { DVec3::ZERO };
        c += e * (kd * nl.max(0.0) + spec);
    }
    c
}

/// The same scene through `blinn_phong_classic` with its defaults (which are SCENE.md's material).
fn scene_color_model(p: Vec3) -> Vec3 {
    let m = model("blinn_phong_classic", &[]);
    let kd = Vec3::new(0.8, 0.3, 0.2);
    let v = Vec3::new(0.0, 0.0, 3.0) - p;
    let to_point = Vec3::splat(2.0) - p;
    let lights = [(Vec3::ONE, 1.0), (to_point, 10.0 / to_point.length_squared())];
    lights.iter().fold(0.05 * kd, |c, &(l, e)| c + e * m.shade(&geom(l, v, p)))
}

#[test]
fn classic_blinn_phong_reproduces_the_benchmark_check_values() {
    // bench/SCENE.md "Check values": linear colour and 8-bit sRGB at three surface points.
    let cases = [
        (Vec3::new(0.0, 0.0, 1.0), [0.810225, 0.311365, 0.211593], 5e-7, [232u8, 151, 127]),
        (
            Vec3::new(0.5, 0.5, std::f32::consts::FRAC_1_SQRT_2),
            [2.1459, 0.8408, 0.5798],
            5e-5,
            [255, 236, 200],
        ),
        (Vec3::new(-0.6, -0.6, 0.529150), [0.04, 0.015, 0.01], 5e-7, [56, 33, 25]),
    ];
    // `half_unit`: half a unit in the last printed decimal.
    for (p, printed, half_unit, srgb8) in cases {
        let reference = scene_color(p.as_dvec3());
        let ours = scene_color_model(p);
        assert!(close(ours, reference, 2e-6), "{p}: model {ours} vs f64 formula {reference}");
        // The f64 formula agrees with SCENE.md to the decimals it prints.
        let printed = DVec3::from_array(printed);
        assert!((reference - printed).abs().max_element() <= half_unit + 1e-9, "{p}: {reference}");
        assert_eq!(encode_srgb8(ours, Operator::Clamp), srgb8, "{p}: {ours}");
    }
}

#[test]
fn classic_blinn_phong_reproduces_seed_004s_numerical_example() {
    // Seed 004, eq. 12.25: n = (0,2,0), l = (1,1,0), v = (0,1,1), I = Ie + Ia ka + Ii (kd n·l + ks (n·h)^n)
    // with Ie = 2, Ia = 1, ka = 0.3, Ii = 12, kd = 0.3, ks = 0.6, n = 3. Recomputed in f64.
    let m = model("blinn_phong_classic", &[("kd", num(0.3)), ("ks", num(0.6)), ("shininess", num(3.0))]);
    let shade = m.shade(&geom(Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0), Vec3::new(0.0, 2.0, 0.0)));
    let nh = (2.0f64 / 3.0).sqrt(); // h = (1, 2, 1)/√6
    let expected = 0.3 / 2f64.sqrt() + 0.6 * nh.powi(3);
    assert!((f64::from(shade.x) - expected).abs() < 1e-6, "{shade} vs {expected}");
    let intensity = 2.0 + 1.0 * 0.3 + 12.0 * f64::from(shade.x);
    assert!((intensity - 8.76).abs() < 0.005, "I = {intensity}");
}

#[test]
fn classic_blinn_phong_has_no_highlight_from_a_light_behind_the_surface() {
    let m = model("blinn_phong_classic", &[("shininess", num(1.0))]);
    // n·l < 0 but n·h > 0: the formula's gate keeps it black.
    let g = geom(Vec3::new(1.0, 0.0, -0.1), Vec3::new(-0.2, 0.0, 1.0), Vec3::Z);
    assert_eq!(m.shade(&g), Vec3::ZERO);
}

#[test]
fn classic_phong_is_the_course_formula_and_its_gate_is_optional() {
    let (kd, ks, gamma) = (Vec3::new(0.8, 0.3, 0.2), 0.5f64, 32.0f64);
    let m = model("phong_classic", &[]);
    let (l, v) = (dir(0.5, 0.0), dir(0.45, PI + 0.03));
    let g = geom(l, v, Vec3::Z);
    // r = 2(n·l)n − l; shade = kd (n·l) + ks clamp(v·r)^γ, in f64.
    let (ld, vd) = (l.as_dvec3(), v.as_dvec3());
    let r = 2.0 * ld.z * DVec3::Z - ld;
    let expected = kd.as_dvec3() * ld.z + DVec3::splat(ks * vd.dot(r).clamp(0.0, 1.0).powf(gamma));
    assert!(close(m.shade(&g), expected, 1e-5), "{} vs {expected}", m.shade(&g));

    // Light just behind the surface, viewer at grazing on the mirror side: v·r > 0.
    let behind = geom(Vec3::new(-1.0, 0.0, -0.05), Vec3::new(1.0, 0.0, 0.02), Vec3::Z);
    assert_eq!(m.shade(&behind), Vec3::ZERO, "gated: no highlight on the dark side");
    let literal = model("phong_classic", &[("specular_gate", flag(false))]);
    assert!(literal.shade(&behind).min_element() > 0.1, "seed 000's GLSL does not gate");
}

#[test]
fn toon_diffuse_has_three_bands_with_half_open_edges() {
    let m = model(
        "toon",
        &[
            ("kd", Input::Numbers(vec![0.8, 0.3, 0.2])),
            ("kd_mid", Input::Numbers(vec![0.4, 0.2, 0.1])),
            ("diffuse_threshold", num(0.5)),
            ("dark_threshold", num(0.07)),
            ("dark_scale", num(0.002)),
            ("ks", num(0.0)),
        ],
    );
    let (lit, mid, dark) =
        (Vec3::new(0.8, 0.3, 0.2), Vec3::new(0.4, 0.2, 0.1), 0.002 * Vec3::new(0.8, 0.3, 0.2));
    // Unit vectors with an exact n·l, so the edges themselves are tested.
    let shade_at = |nl: f32| {
        let l = Vec3A::new((1.0 - nl * nl).sqrt(), 0.0, nl);
        m.shade(&Geometry::from_unit(l, Vec3A::Z, Vec3A::Z))
    };
    let eps = 1e-4;
    for (nl, expected) in
        [(1.0, lit), (0.5, lit), (0.5 - eps, mid), (0.07, mid), (0.07 - eps, dark), (0.0, dark), (-0.8, dark)]
    {
        assert_eq!(shade_at(nl), expected, "n·l = {nl}");
    }
}

#[test]
fn toon_specular_thresholds_v_dot_r_or_n_dot_h() {
    let base = [
        ("kd", num(0.0)),
        ("kd_mid", num(0.0)),
        ("dark_scale", num(0.0)),
        ("ks", Input::Numbers(vec![1.0, 0.9, 0.8])),
        ("specular_threshold", num(0.9)),
    ];
    let white = Vec3::new(1.0, 0.9, 0.8);
    let l = dir(0.6, 0.0);
    // Phong mode: v·r = cos(angle between v and the mirror direction r = dir(0.6, π)).
    let phong = model("toon", &base);
    let on_edge = |angle: f64| geom(l, dir(0.6 + angle, PI), Vec3::Z);
    assert_eq!(phong.shade(&on_edge(0.0)), white);
    assert_eq!(phong.shade(&on_edge(0.9f64.acos() - 1e-3)), white);
    assert_eq!(phong.shade(&on_edge(0.9f64.acos() + 1e-3)), Vec3::ZERO);
    // Blinn mode: n·h = cos(half the angle between l and v) for coplanar, opposite directions.
    let mut blinn_params = base.to_vec();
    blinn_params.push(("specular_mode", text("blinn")));
    let blinn = model("toon", &blinn_params);
    let half = 0.9f64.acos(); // n·h = 0.9 when θ_h = half
    // l and v in the same azimuthal half-plane at polar angles θh ± 0.3: h is at polar angle θh.
    let at = |theta_h: f64| geom(dir(theta_h + 0.3, 0.0), dir(theta_h - 0.3, 0.0), Vec3::Z);
    assert_eq!(blinn.shade(&at(half - 1e-3)), white);
    assert_eq!(blinn.shade(&at(half + 1e-3)), Vec3::ZERO);
}

// ---------------------------------------------------------------- physical Phong family

#[test]
fn normalised_phong_peaks_at_the_mirror_direction_with_its_normalisation() {
    let (kd, ks, gamma) = (0.3f64, 0.6f64, 40.0f64);
    let m = model("phong", &[("kd", num(kd)), ("ks", num(ks)), ("shininess", num(gamma))]);
    let l = dir(0.7, 0.2);
    let peak = m.eval(&geom(l, dir(0.7, 0.2 + PI), Vec3::Z));
    let expected = kd / PI + ks * (gamma + 2.0) / (2.0 * PI);
    assert!((f64::from(peak.x) - expected).abs() < 1e-5 * expected, "{peak} vs {expected}");
    // 0.3 rad off the mirror direction in the plane: cos^γ(0.3).
    let off = m.eval(&geom(l, dir(1.0, 0.2 + PI), Vec3::Z));
    let expected_off = kd / PI + ks * (gamma + 2.0) / (2.0 * PI) * 0.3f64.cos().powf(gamma);
    assert!((f64::from(off.x) - expected_off).abs() < 1e-5, "{off} vs {expected_off}");
}

#[test]
fn blinn_phong_normalisations_are_the_documented_factors() {
    for m in [0.0f64, 1.0, 10.0, 32.0, 1000.0] {
        let rtr = (m + 8.0) / (8.0 * PI);
        let exact = (m + 2.0) * (m + 4.0) / (8.0 * PI * ((-m / 2.0).exp2() + m));
        assert!((f64::from(normalization_rtr(m as f32)) - rtr).abs() < 1e-6 * rtr);
        assert!((f64::from(normalization_exact(m as f32)) - exact).abs() < 1e-6 * exact);
        // Seen through the model, at h = n (l = v = n).
        for (name, factor) in [("rtr", rtr), ("exact", exact)] {
            let bp = model(
                "blinn_phong",
                &[("kd", num(0.0)), ("ks", num(1.0)), ("shininess", num(m)), ("normalization", text(name))],
            );
            let f = f64::from(bp.eval(&geom(Vec3::Z, Vec3::Z, Vec3::Z)).x);
            assert!((f - factor).abs() < 1e-6 * factor, "m={m} {name}: {f} vs {factor}");
        }
    }
    // Both → 1/π at m = 0 (a Lambertian lobe), and rtr ≥ exact everywhere.
    assert!((f64::from(normalization_exact(0.0)) - 1.0 / PI).abs() < 1e-7);
    for m in [1.0f32, 5.0, 10.0, 50.0] {
        assert!(normalization_rtr(m) > normalization_exact(m));
    }
}

#[test]
fn blinn_exponent_four_times_phong_matches_highlights_in_the_plane_of_incidence() {
    assert_eq!(blinn_exponent_from_phong(25.0), 100.0);
    assert_eq!(phong_exponent_from_blinn(blinn_exponent_from_phong(7.5)), 7.5);
    // Coplanar l, v, n: angle(r, v) = 2·angle(n, h) exactly; the lobes agree as the angle → 0.
    let gamma = 50.0f64;
    let m = blinn_exponent_from_phong(gamma as f32) as f64;
    let mut previous = f64::INFINITY;
    for x in [0.2f64, 0.1, 0.05, 0.02] {
        let (phong, blinn) = ((2.0 * x).cos().powf(gamma), x.cos().powf(m));
        let err = (phong / blinn).ln().abs();
        assert!(err < previous, "the match must improve as the angle shrinks");
        previous = err;
    }
    assert!(previous < 1e-3, "{previous}");
}

#[test]
fn phong_family_reflects_its_diffuse_part_alone_far_from_the_highlight() {
    let g = geom(dir(0.3, 0.0), dir(0.3, 0.0), Vec3::Z); // retro direction, far from the mirror
    for name in ["phong", "blinn_phong"] {
        let m = model(name, &[("kd", num(0.4)), ("ks", num(0.6)), ("shininess", num(500.0))]);
        assert!((f64::from(m.eval(&g).x) - 0.4 / PI).abs() < 1e-7, "{name}");
    }
}
