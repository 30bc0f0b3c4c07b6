//! Clamping, tone-mapping operators, exposure, the sRGB transfer function and 8-bit quantisation
//! (SPEC row 20; bench/SCENE.md "Output").

use brdf_core::tonemap::{
    Operator, aces, aces_f32, clamp, encode_srgb8, encode_srgb8_slice, exposure, reinhard, reinhard_extended,
    reinhard_extended_f32, reinhard_f32, srgb_decode, srgb_decode_f32, srgb_encode, srgb_encode_f32, to_u8,
};
use glam::Vec3;

/// Inputs no operator may turn into NaN or send outside [0, 1].
const NASTY: [f32; 9] = [0.0, -1.0, -0.0, 1e-30, 0.5, 1.0, 1e30, f32::INFINITY, f32::NAN];

fn operators() -> [Operator; 5] {
    [
        Operator::Clamp,
        Operator::Reinhard,
        Operator::ReinhardExtended { white: 4.0 },
        Operator::ReinhardExtended { white: 0.5 },
        Operator::Aces,
    ]
}

#[test]
fn every_operator_maps_any_input_into_the_unit_interval_without_nan() {
    for op in operators() {
        for x in NASTY {
            let y = op.apply(Vec3::splat(x));
            assert!(y.is_finite() && y.min_element() >= 0.0 && y.max_element() <= 1.0, "{op:?}({x}) = {y}");
        }
        // Negative and NaN count as black.
        assert_eq!(op.apply(Vec3::new(-3.0, f32::NAN, 0.0)), Vec3::ZERO, "{op:?}");
    }
}

#[test]
fn every_operator_is_monotonic() {
    for op in operators() {
        let mut previous = -1.0f32;
        for i in 0..=4000 {
            let y = op.apply(Vec3::splat(i as f32 * 0.005)).x;
            assert!(y >= previous, "{op:?} decreases at {}", i as f32 * 0.005);
            previous = y;
        }
    }
}

#[test]
fn clamp_is_seed_000s_piecewise_function() {
    assert_eq!(clamp(Vec3::new(-0.5, 0.25, 7.0)), Vec3::new(0.0, 0.25, 1.0));
}

#[test]
fn reinhard_halves_one_and_approaches_one() {
    assert_eq!(reinhard_f32(1.0), 0.5);
    assert!((reinhard_f32(3.0) - 0.75).abs() < 1e-7);
    assert_eq!(reinhard_f32(f32::INFINITY), 1.0);
    assert_eq!(reinhard(Vec3::new(0.0, 1.0, 3.0)), Vec3::new(0.0, 0.5, 0.75));
}

#[test]
fn extended_reinhard_maps_the_white_point_to_one_and_tends_to_simple_reinhard() {
    for white in [0.5f32, 1.0, 4.0, 100.0] {
        assert!((reinhard_extended_f32(white, white) - 1.0).abs() < 1e-6, "w = {white}");
        assert_eq!(reinhard_extended_f32(2.0 * white, white), 1.0);
        // Just below white it is just below 1.
        assert!(reinhard_extended_f32(0.99 * white, white) < 1.0);
    }
    // x(1 + x/w²)/(1 + x) at x = 1, w = 2: 1·1.25/2.
    assert!((reinhard_extended_f32(1.0, 2.0) - 0.625).abs() < 1e-7);
    for x in [0.1f32, 1.0, 10.0] {
        assert!((reinhard_extended_f32(x, 1e6) - reinhard_f32(x)).abs() < 1e-6);
    }
    assert_eq!(reinhard_extended(Vec3::splat(4.0), 4.0), Vec3::ONE);
}

#[test]
fn aces_is_narkowiczs_rational_fit() {
    let fit = |x: f64| x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    for x in [0.0f64, 0.01, 0.18, 0.5, 1.0, 2.0, 5.0] {
        let expected = fit(x).min(1.0);
        assert!((f64::from(aces_f32(x as f32)) - expected).abs() < 1e-6, "{x}");
    }
    // It saturates where the fit reaches 1: 0.08x² − 0.56x − 0.14 = 0.
    let x1 = (0.56 + (0.56f64 * 0.56 + 4.0 * 0.08 * 0.14).sqrt()) / (2.0 * 0.08);
    assert!(aces_f32((x1 * 0.999) as f32) < 1.0);
    assert_eq!(aces_f32((x1 * 1.001) as f32), 1.0);
    assert_eq!(aces(Vec3::new(0.0, 100.0, f32::INFINITY)), Vec3::new(0.0, 1.0, 1.0));
}

#[test]
fn exposure_scales_by_powers_of_two() {
    let c = Vec3::new(0.1, 0.2, 0.4);
    assert_eq!(exposure(c, 1.0), 2.0 * c);
    assert_eq!(exposure(c, -2.0), 0.25 * c);
    assert_eq!(exposure(c, 0.0), c);
}

#[test]
fn srgb_encoding_is_scene_mds_oetf() {
    // v = 12.92c for c ≤ 0.0031308, else 1.055c^(1/2.4) − 0.055 (recomputed in f64).
    let oetf = |c: f64| if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    for c in [0.0f64, 0.001, 0.0031308, 0.0031309, 0.01, 0.18, 0.5, 0.9, 1.0] {
        assert!((f64::from(srgb_encode_f32(c as f32)) - oetf(c)).abs() < 2e-6, "{c}");
    }
    // The two branches meet at the threshold (continuity of the standard curve).
    let t = 0.003_130_8f32;
    assert!((srgb_encode_f32(t) - srgb_encode_f32(t + 1e-7)).abs() < 1e-5);
    // Out-of-range input is clamped first.
    let e = srgb_encode(Vec3::new(-1.0, 2.0, f32::NAN));
    assert!((e - Vec3::new(0.0, 1.0, 0.0)).abs().max_element() < 1e-6, "{e}");
    assert_eq!(e, srgb_encode(Vec3::new(0.0, 1.0, 0.0)));
}

#[test]
fn srgb_decoding_inverts_encoding() {
    for i in 0..=1000 {
        let c = i as f32 / 1000.0;
        assert!((srgb_decode_f32(srgb_encode_f32(c)) - c).abs() < 2e-6, "{c}");
    }
    let c = Vec3::new(0.02, 0.3, 0.77);
    assert!((srgb_decode(srgb_encode(c)) - c).abs().max_element() < 2e-6);
    // Mid-grey: encoded 0.5 is linear ≈ 0.214.
    assert!((srgb_decode_f32(0.5) - 0.214_041).abs() < 1e-5);
}

#[test]
fn quantisation_rounds_half_up_after_clamping() {
    assert_eq!(to_u8(0.0), 0);
    assert_eq!(to_u8(1.0), 255);
    assert_eq!(to_u8(-0.2), 0);
    assert_eq!(to_u8(3.0), 255);
    assert_eq!(to_u8(f32::NAN), 0);
    // floor(255v + 0.5): values just either side of a half step.
    assert_eq!(to_u8(100.49 / 255.0), 100);
    assert_eq!(to_u8(100.51 / 255.0), 101);
}

#[test]
fn scene_check_values_encode_to_their_8_bit_pixels() {
    // bench/SCENE.md "Check values": linear colour → 8-bit sRGB after clamping.
    for (linear, srgb8) in [
        ([0.810225, 0.311365, 0.211593], [232u8, 151, 127]),
        ([2.1459, 0.8408, 0.5798], [255, 236, 200]),
        ([0.04, 0.015, 0.01], [56, 33, 25]),
        ([0.0, 0.0, 0.0], [0, 0, 0]),
    ] {
        assert_eq!(encode_srgb8(Vec3::from_array(linear), Operator::Clamp), srgb8, "{linear:?}");
    }
}

#[test]
fn operators_are_found_by_name_and_bad_names_or_white_points_are_refused() {
    for name in Operator::NAMES {
        assert_eq!(Operator::from_name(name, None).unwrap().name(), *name);
    }
    assert_eq!(Operator::from_name("ACES", None).unwrap(), Operator::Aces);
    assert_eq!(
        Operator::from_name("reinhard_extended", Some(2.0)).unwrap(),
        Operator::ReinhardExtended { white: 2.0 }
    );
    let e = Operator::from_name("filmic", None).unwrap_err().to_string();
    assert!(e.contains("operator") && e.contains("reinhard"), "{e}");
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let e = Operator::from_name("reinhard_extended", Some(bad)).unwrap_err().to_string();
        assert!(e.contains("white"), "{e}");
    }
}

#[test]
fn slice_encoding_matches_pixel_encoding_and_checks_lengths() {
    let src: Vec<Vec3> = (0..50_000).map(|i| Vec3::new(i as f32 * 1e-4, (i % 7) as f32 * 0.3, 0.5)).collect();
    let mut dst = vec![[0u8; 3]; src.len()];
    encode_srgb8_slice(&src, Operator::Reinhard, &mut dst).unwrap();
    for (c, px) in src.iter().zip(&dst) {
        assert_eq!(*px, encode_srgb8(*c, Operator::Reinhard));
    }
    let e = encode_srgb8_slice(&src, Operator::Clamp, &mut dst[..10]).unwrap_err().to_string();
    assert!(e.contains("dst"), "{e}");
}
