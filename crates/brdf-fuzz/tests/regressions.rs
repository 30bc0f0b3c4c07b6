//! Regressions of the hostile-input runs (issue 9) in the Rust crates, where the rules live: each test
//! states the contract that an input once broke (a silent NaN/∞ from finite input, or an allocation
//! sized by a corrupt header).

use brdf_core::measured::Tabulated;
use brdf_core::microfacet::{Distribution, ggx};
use brdf_core::{fresnel, tonemap};
use brdf_raster::Camera;
use brdf_raster::ao;
use glam::{Vec3, Vec3A};

#[test]
fn obscurance_mu_tends_to_its_linear_limit_as_tau_vanishes() {
    for tau in [1e-45f32, 1e-38, 1e-20, 1e-6, 9.9e-5] {
        for d in [0.0f32, 0.25, 0.5, 0.999] {
            let m = ao::mu(d, tau, 1.0);
            assert!(m.is_finite() && (m - d).abs() <= 1e-4, "mu({d}, tau {tau}) = {m}");
        }
    }
    // Across the switch to the series, μ is continuous to float32 precision.
    let (below, above) = (ao::mu(0.3, 0.99e-4, 1.0), ao::mu(0.3, 1.01e-4, 1.0));
    assert!((below - above).abs() < 1e-6, "{below} vs {above}");
}

#[test]
fn exposure_of_a_finite_value_is_finite_and_exact_where_representable() {
    assert_eq!(tonemap::exposure_f32(0.0, 1e38), 0.0);
    assert_eq!(tonemap::exposure_f32(1.0, 1e38), f32::MAX);
    assert_eq!(tonemap::exposure_f32(-1.0, 1e38), -f32::MAX);
    assert_eq!(tonemap::exposure_f32(1.0, -1e38), 0.0);
    assert_eq!(tonemap::exposure_f32(2f32.powi(-100), 200.0), 2f32.powi(100));
    assert_eq!(tonemap::exposure_f32(2f32.powi(100), -200.0), 2f32.powi(-100));
    // The ordinary path is the plain product.
    assert_eq!(tonemap::exposure_f32(0.7, 1.5), 0.7 * 1.5f32.exp2());
    assert_eq!(tonemap::exposure(Vec3::new(1.0, 0.0, 3e38), 1.0), Vec3::new(2.0, 0.0, f32::MAX));
}

#[test]
fn a_merl_header_asking_for_terabytes_is_refused_before_any_allocation() {
    let mut file = Vec::new();
    for d in [4096i32, 4096, 4096] {
        file.extend_from_slice(&d.to_le_bytes());
    }
    let e = Tabulated::read_merl(file.as_slice()).unwrap_err().to_string();
    assert!(e.starts_with("merl: the header asks for 4096x4096x4096"), "{e}");
    // Within the node limit but with the data missing: the size is checked against what is there.
    let mut file = Vec::new();
    for d in [90i32, 90, 180] {
        file.extend_from_slice(&d.to_le_bytes());
    }
    let e = Tabulated::read_merl(file.as_slice()).unwrap_err().to_string();
    assert!(
        e.starts_with("merl: expected 34992000 bytes of data for 90x90x180") && e.ends_with("found 0"),
        "{e}"
    );
}

#[test]
fn a_table_beyond_the_node_limit_is_refused() {
    let e = Tabulated::new((4096, 4096, 4096), Vec::new()).unwrap_err().to_string();
    assert!(e.contains("exceed the limit"), "{e}");
}

#[test]
fn projection_refuses_aspects_that_overflow_and_accepts_every_image_shape() {
    let cam = Camera::perspective(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 0.8, 0.1, 10.0).unwrap();
    for aspect in [1e-45f32, 0.0, -1.0, f32::INFINITY, f32::NAN, 1e9] {
        let e = cam.checked_projection(aspect).unwrap_err().to_string();
        assert!(e.starts_with("aspect: must be a width/height ratio"), "{e}");
    }
    for aspect in [1.0 / 16384.0, 1.0, 16384.0] {
        assert!(cam.checked_projection(aspect).unwrap().is_finite());
    }
}

#[test]
fn ggx_lambda_is_finite_above_the_surface_at_any_angle_and_roughness() {
    for alpha in [1e-4f32, 0.3, 1e4] {
        for cos in [1.0f32, 0.5, 1e-10, 1e-20, 1e-38, 1e-45] {
            let l = ggx::lambda(cos, alpha);
            assert!(l.is_finite() && l >= 0.0, "lambda({cos}, {alpha}) = {l}");
        }
    }
    // Past the switch, Λ = α tanθ / 2 to float32 precision.
    let (cos, alpha) = (1e-20f32, 0.5f32);
    let want = 0.5 * alpha / cos;
    assert!((ggx::lambda(cos, alpha) / want - 1.0).abs() < 1e-6);
    let w = Vec3A::new(1.0, 1.0, 1e-30).normalize();
    let l = ggx::lambda_aniso(w, 1e4, 1e4);
    assert!(l.is_finite() && l > 1e30, "{l}");
    assert_eq!(ggx::lambda(-0.5, 0.3), f32::INFINITY);
}

#[test]
fn distributions_by_name_refuse_roughness_beyond_alpha_max() {
    let e = Distribution::from_name("ggx", 1e9, None).unwrap_err().to_string();
    assert!(e.starts_with("parameter \"alpha\": must be finite and in (0, 10000]"), "{e}");
    assert!(Distribution::from_name("beckmann", 1e4, None).is_ok());
}

#[test]
fn dielectric_fresnel_is_finite_over_the_accepted_index_range() {
    for eta in [1e-6f32, 1e-3, 1.0, 1.5, 1e3, 1e6] {
        for i in 0..=100 {
            let c = -1.0 + 0.02 * i as f32;
            let r = fresnel::dielectric(c, eta);
            assert!(r.is_finite() && (0.0..=1.0).contains(&r), "dielectric({c}, {eta}) = {r}");
        }
    }
}

#[test]
fn clamped_cosine_zonal_is_continuous_across_its_asymptotic_form_and_costs_o1_at_any_band() {
    use brdf_core::sh::clamped_cosine_zonal;
    let (exact, series) = (clamped_cosine_zonal(2048), clamped_cosine_zonal(2050));
    // |Â_l| falls as l^(-5/2) with alternating signs: the series at 2050 continues the product at 2048.
    let want = (2048.0f64 / 2050.0).powf(2.5);
    assert!((series.abs() / exact.abs() - want).abs() < 1e-5, "{exact} vs {series}");
    for l in [1usize << 20, 1 << 40, usize::MAX - 1] {
        let a = clamped_cosine_zonal(l);
        assert!(a.is_finite() && a.abs() < 1e-9, "A({l}) = {a}");
    }
}
