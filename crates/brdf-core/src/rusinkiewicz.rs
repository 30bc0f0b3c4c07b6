//! Rusinkiewicz's half/difference coordinates `(θ_h, θ_d, φ_d)` of a pair of directions: the one
//! place they are computed, shared by the measured-BRDF look-up ([`crate::measured`]) and the
//! θ_h/θ_d image slice ([`crate::views`]).
//!
//! An isotropic BRDF depends on three angles. Rusinkiewicz (1998, "A New Change of Variables for
//! Efficient BRDF Representation") writes a pair `(l, v)` as the half vector `h = normalize(l + v)`,
//! with polar angle `θ_h` from `n`, and the difference vector `d`, which is `l` expressed in a frame
//! where `h` is the pole: `θ_d` is the angle between `l` and `h`, `φ_d` its azimuth around `h`. The
//! specular peak lies along `θ_h = 0` and Fresnel varies with `θ_d`, which is why measured tables
//! (Matusik et al. 2003) and Disney's BRDF Explorer image slice (Burley 2012, "Physically-Based
//! Shading at Disney", §3) use these angles. Helmholtz reciprocity (swapping `l` and `v` maps
//! `d → −d`, i.e. `φ_d → φ_d + π`) makes an isotropic BRDF `π`-periodic in `φ_d`.

use std::f32::consts::PI;

use glam::Vec3A;

use crate::frame::LaneFrame;
use crate::microfacet::HalfVector;
use crate::simd::{Lane, V3};

/// Rusinkiewicz's half/difference angles `(θ_h, θ_d, φ_d)` \[radians\] of a configuration, with `φ_d`
/// folded into `[0, π)` by reciprocity. `None` when `l = −v` (no half vector).
///
/// The difference frame is MERL's: rotate `l` about `n` by `−φ_h`, then about the binormal by `−θ_h`.
/// Equivalently `d = (l·x', l·y', l·h)` with `y' = normalize(n × h)` and `x' = y' × h`. At `θ_h = 0`
/// the azimuth reference is arbitrary (any isotropic BRDF is independent of `φ_d` there).
///
/// The polar angles come from tangent-plane components, not as `acos` of a cosine:
/// `θ_h = atan2(|h̃⊥|, n·h̃)` with the un-normalised `h̃ = l + v` ([`HalfVector`]), and
/// `θ_d = atan2(|l − v|, |l + v|)` (`|l ± v|` = `2 cos θ_d`, `2 sin θ_d` for unit `l`, `v`; `l − v` is
/// `2 sin θ_d` times the difference direction). `acos` of a float32 cosine near 1 is only good to
/// `√(2·2^-24)` ≈ 3.5e-4 rad, and both angles are near 0 exactly where a table matters most: the
/// specular peak (`θ_h` → 0, where the MERL grid's `√θ_h` index spacing turns that into 1.5 cells
/// at 90 nodes) and the retro direction (`θ_d` → 0). A float32 emulation of the `acos` forms was off
/// by 4e-4 rad in both angles, where rounding the inputs to float32 moves them by 2e-7; these forms
/// stay at that floor (1.9e-7 rad), and the look-up of a sharp Cook–Torrance table (roughness 0.05,
/// MERL resolution) near its peak went from 3.2e-4 relative off a float64 look-up to 1.1e-5, where
/// rounding the inputs alone moves it by 9.5e-6 (tests/test_measured.py). Both angles are
/// bit-for-bit symmetric in `l` and `v`.
pub fn half_diff_angles(l: Vec3A, v: Vec3A, n: Vec3A) -> Option<(f32, f32, f32)> {
    let (th, td, pd, ok) = half_diff_angles_lanes::<f32>(l.into(), v.into(), n.into());
    ok.then_some((th, td, pd))
}

/// [`half_diff_angles`] on lanes, the one place it is written: `(θ_h, θ_d, φ_d, ok)`, `ok` false where
/// `l = −v` (the angles of those lanes are meaningless).
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn half_diff_angles_lanes<F: Lane>(l: V3<F>, v: V3<F>, n: V3<F>) -> (F, F, F, F::Mask) {
    let one = F::splat(1.0);
    // h as `vector::halfway` (none where |l + v|² ≤ 1e−20).
    let s = l + v;
    let len2 = s.dot(s);
    let h = s / len2.sqrt();
    let half = HalfVector::from_directions(l, v, n);
    let theta_h = half.perp2.sqrt().atan2(half.n_dot);
    let w = l - v;
    let theta_d = w.dot(w).sqrt().atan2(half.len2.sqrt());
    let axis = n.cross(h);
    let axis2 = axis.dot(axis);
    // glam's normalize: times the reciprocal of the length.
    let y =
        V3::select(axis2.gt(F::splat(1e-12)), axis.scale(one / axis2.sqrt()), LaneFrame::from_normal(h).b);
    let x = y.cross(h);
    // The azimuth of l − v = 2 sin θ_d (cos φ_d x' + sin φ_d y') rather than of l: the same angle, but
    // l·x' and l·y' are ~sin θ_d from components ~1, so near the retro direction (θ_d → 0) they keep
    // the rounding of those products, 2^-24/sin θ_d rad of φ_d (a float32 emulation: 3.5× the input
    // floor, median, at θ_d < 1e-3); l − v is exact there (close floats) and small, and stays at the
    // floor. A table hardly depends on φ_d at θ_d → 0, so this is for the angle's own sake.
    let (dx, dy) = (w.dot(x), w.dot(y));
    let pi = F::splat(PI);
    let phi_d = dy.atan2(dx);
    let phi_d = F::select(phi_d.lt(F::splat(0.0)), phi_d + pi, phi_d);
    let phi_d = F::select(phi_d.ge(pi), phi_d - pi, phi_d);
    (theta_h, theta_d, phi_d, len2.gt(F::splat(1e-20)))
}

/// The directions `(l, v)` for half/difference angles, with `n = +z` and `φ_h = 0` (the inverse of
/// [`half_diff_angles`]; MERL's `half_diff_coords_to_std_coords`).
pub fn directions_from_half_diff(theta_h: f32, theta_d: f32, phi_d: f32) -> (Vec3A, Vec3A) {
    directions_from_half_diff_sin_cos(theta_h.sin_cos(), theta_d.sin_cos(), phi_d.sin_cos())
}

/// [`directions_from_half_diff`] from the `(sin, cos)` pairs of `θ_h`, `θ_d` and `φ_d` (the same
/// operations, so the same bits), for grids that compute each once per row or column.
#[inline]
pub fn directions_from_half_diff_sin_cos(
    (sh, ch): (f32, f32),
    (sd, cd): (f32, f32),
    (sp, cp): (f32, f32),
) -> (Vec3A, Vec3A) {
    let h = Vec3A::new(sh, 0.0, ch);
    let y = Vec3A::Y;
    let x = Vec3A::new(ch, 0.0, -sh);
    let (dx, dy, dz) = (sd * cp, sd * sp, cd);
    // v is l mirrored about h: in the half frame (−dx, −dy, dz).
    (dx * x + dy * y + dz * h, -dx * x - dy * y + dz * h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_diff_angles_invert_directions_from_half_diff() {
        for &(th, td, pd) in &[(0.3, 0.5, 0.2), (0.05, 1.0, 2.9), (0.7, 0.2, 1.4), (0.0, 0.4, 0.0)] {
            let (l, v) = directions_from_half_diff(th, td, pd);
            assert!((l.length() - 1.0).abs() < 1e-6 && (v.length() - 1.0).abs() < 1e-6);
            let (a, b, c) = half_diff_angles(l, v, Vec3A::Z).unwrap();
            assert!((a - th).abs() < 1e-3 && (b - td).abs() < 1e-4, "{th} {td} -> {a} {b}");
            if th > 0.0 {
                assert!((c - pd).abs() < 1e-4, "{pd} -> {c}");
            }
        }
    }

    #[test]
    fn half_and_difference_angles_near_zero_are_accurate_to_the_float32_input_rounding() {
        // The specular peak (θ_h → 0) and the retro direction (θ_d → 0): directions built in float64 at
        // known angles from 1e-7 rad up, rounded to float32. Rounding the inputs moves the angles by
        // ~1e-7 rad (an ulp of a unit vector's components over |l + v| ≥ 0.34); acos of a float32
        // cosine near 1 was off by up to 4e-4 rad (√(2·2^-24) at the angle 0), and φ_d as the azimuth
        // of l rather than of l − v by ~2^-24/sin θ_d (a few times the input floor).
        use glam::DVec3;
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..3000 {
            let k = f64::from(i);
            let theta_h = 1e-7 * 1e6f64.powf((k * 0.618_034) % 1.0);
            let theta_d =
                if i % 2 == 0 { 1e-7 * 1e6f64.powf((k * 0.414_214) % 1.0) } else { (k * 0.377) % 1.4 };
            let (phi_h, phi_d) = (k * 2.399, (k * 1.3) % std::f64::consts::PI);
            let h = DVec3::new(theta_h.sin() * phi_h.cos(), theta_h.sin() * phi_h.sin(), theta_h.cos());
            let y = DVec3::new(-phi_h.sin(), phi_h.cos(), 0.0);
            let d = theta_d.sin() * (phi_d.cos() * y.cross(h) + phi_d.sin() * y);
            let (l, v) = (theta_d.cos() * h + d, theta_d.cos() * h - d);
            if l.z <= 0.0 || v.z <= 0.0 {
                continue;
            }
            let (a, b, c) = half_diff_angles(l.as_vec3a(), v.as_vec3a(), Vec3A::Z).unwrap();
            let (ea, eb) = ((f64::from(a) - theta_h).abs(), (f64::from(b) - theta_d).abs());
            assert!(ea < 4e-7 && eb < 4e-7, "theta_h {theta_h:e} -> {a:e}, theta_d {theta_d:e} -> {b:e}");
            worst = (worst.0.max(ea), worst.1.max(eb), worst.2);
            // φ_d is the azimuth of l − v, of length 2 sin θ_d, in a frame turned with n × h (exact for
            // n = z): rounding the inputs moves it by ~6e-8/sin θ_d. The floor is that, for these
            // float32 inputs: φ_d of them in float64. Below |n × h| = 1e-6 the azimuth reference is
            // arbitrary (a fixed frame around h).
            if theta_h < 2e-6 {
                continue;
            }
            let (l32, v32) = (l.as_vec3().as_dvec3(), v.as_vec3().as_dvec3());
            let h32 = (l32 + v32).normalize();
            let y32 = DVec3::Z.cross(h32).normalize();
            let w32 = l32 - v32;
            let azimuth = |p: f64| {
                let e = (p - phi_d).rem_euclid(std::f64::consts::PI);
                e.min(std::f64::consts::PI - e)
            };
            let floor = azimuth(w32.dot(y32).atan2(w32.dot(y32.cross(h32))));
            let ec = azimuth(f64::from(c));
            let bound = 4.0 * floor + 8.0 * f64::from(f32::EPSILON / 2.0);
            assert!(
                ec <= bound,
                "phi_d {phi_d} -> {c} (floor {floor:e}) at theta_h {theta_h:e}, theta_d {theta_d:e}"
            );
            worst.2 = worst.2.max(ec / bound);
        }
        eprintln!(
            "largest errors near 0: theta_h {:.2e}, theta_d {:.2e} rad; phi_d {:.2} of its bound",
            worst.0, worst.1, worst.2
        );
    }

    #[test]
    fn swapping_light_and_viewer_shifts_phi_d_by_pi() {
        let (l, v) = directions_from_half_diff(0.4, 0.6, 0.5);
        let (_, _, p1) = half_diff_angles(l, v, Vec3A::Z).unwrap();
        let (_, _, p2) = half_diff_angles(v, l, Vec3A::Z).unwrap();
        assert!((p1 - p2).abs() < 1e-5, "{p1} {p2}: folded to [0, pi) both must agree");
    }
}
