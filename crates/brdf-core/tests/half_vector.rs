//! The un-normalised half vector (`microfacet::half`) as a specification: every isotropic `D` written
//! in it is the same function as `D(n·h)`, and it stays accurate where light and viewer are nearly
//! opposite and grazing, which the cosine form (`2 + 2 l·v`, `1 − (n·h)²`) cannot.

use std::f64::consts::TAU;

use brdf_core::Geometry;
use brdf_core::microfacet::{Distribution, HalfVector, ggx};
use brdf_core::simd::V3;
use glam::{DVec3, Vec3};

/// A deterministic stream of numbers in [0, 1) (SplitMix64), so the tests need no RNG crate.
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A unit vector at polar angle `theta` and azimuth `phi` around the unit `n`.
fn around(n: DVec3, theta: f64, phi: f64) -> DVec3 {
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let t = helper.cross(n).normalize();
    let b = n.cross(t);
    (t * phi.cos() + b * phi.sin()) * theta.sin() + n * theta.cos()
}

fn to_f32(w: DVec3) -> Vec3 {
    Vec3::new(w.x as f32, w.y as f32, w.z as f32)
}

fn half_from(g: &Geometry) -> HalfVector<f32> {
    HalfVector::from_directions(V3::from(g.l), V3::from(g.v), V3::from(g.n))
}

/// GGX `D` in float64 for the float32 inputs as given (normalised in float64).
fn ggx_reference(l: Vec3, v: Vec3, n: Vec3, alpha: f64) -> f64 {
    let (l, v, n) = (l.as_dvec3().normalize(), v.as_dvec3().normalize(), n.as_dvec3().normalize());
    let h = (l + v).normalize();
    let c2 = n.dot(h).powi(2);
    let tan2 = (1.0 - c2) / c2;
    alpha * alpha / (std::f64::consts::PI * c2 * c2 * (alpha * alpha + tan2).powi(2))
}

#[test]
fn every_distribution_in_half_vector_form_is_its_cosine_form() {
    let dists = [
        Distribution::ggx(0.08),
        Distribution::ggx(0.5),
        Distribution::beckmann(0.1),
        Distribution::beckmann(0.6),
        Distribution::ward(0.2, 0.2),
        Distribution::gaussian(0.15),
        Distribution::blinn_phong(300.0),
        Distribution::blinn_phong(0.0),
        Distribution::ashikhmin_shirley(40.0, 40.0),
    ];
    let mut s = Stream(7);
    let mut compared = 0;
    for _ in 0..4000 {
        let n = around(DVec3::Z, s.next() * 1.5, s.next() * TAU);
        let l = around(n, s.next() * 1.5, s.next() * TAU);
        let v = around(n, s.next() * 1.5, s.next() * TAU);
        let g = Geometry::new(to_f32(l), to_f32(v), to_f32(n), None).unwrap();
        let h = half_from(&g);
        let nh = (g.l + g.v).normalize().dot(g.n);
        // Away from l ≈ −v and from the peak, where the cosine form is itself accurate.
        if h.len2 < 0.5 || nh > 0.999 {
            continue;
        }
        compared += 1;
        for d in &dists {
            let (a, b) = (d.d_half(&h), d.d_cos(nh));
            assert!((a - b).abs() <= 2e-4 * b.abs() + 1e-30, "{d:?}: d_half {a} vs d_cos {b} at n.h = {nh}");
        }
    }
    assert!(compared > 1000, "only {compared} configurations compared");
    // Below the surface: 0, as D(n·h ≤ 0).
    let below = HalfVector { n_dot: -0.1f32, perp2: 0.5, len2: 0.51 };
    for d in &dists {
        assert_eq!(d.d_half(&below), 0.0, "{d:?}");
    }
}

#[test]
fn ggx_stays_accurate_for_nearly_opposite_grazing_directions() {
    // l + v = 2a·h with h within 3α of the normal (the lobe) and |l + v| = 2a in [0.01, 0.25]: both
    // directions lie near the tangent plane, on opposite sides. The reference is float64 on the same
    // float32 inputs; what float32 cannot avoid is the rounding of the unit l and v (~6e-8 per
    // component), which turns h by ~1e-7/|l + v| rad: at most ~1e-4 in D here (α ≥ 0.05).
    let mut s = Stream(11);
    for alpha in [0.05f64, 0.1, 0.3] {
        let (mut worst_half, mut worst_cos) = (0.0f64, 0.0f64);
        for _ in 0..3000 {
            let n = around(DVec3::Z, s.next() * 1.5, s.next() * TAU);
            let h = around(n, s.next().sqrt() * 3.0 * alpha, s.next() * TAU);
            let a = 0.5 * (0.01f64.ln() + s.next() * (0.25f64 / 0.01).ln()).exp();
            // u ⊥ h, tilted out of the tangent plane just enough to keep l and v above it.
            let u0 = h.cross(n).normalize();
            let w = h.cross(u0);
            let b = (1.0 - a * a).sqrt();
            let lim = a * n.dot(h) / b;
            let c = ((2.0 * s.next() - 1.0) * 0.9 * lim / w.dot(n)).clamp(-1.0, 1.0);
            let u = u0 * (1.0 - c * c).sqrt() + w * c;
            let (l, v) = (to_f32(h * a + u * b), to_f32(h * a - u * b));
            let g = Geometry::new(l, v, to_f32(n), None).unwrap();
            if !(g.nl > 0.0 && g.nv > 0.0) {
                continue;
            }
            let want = ggx_reference(l, v, to_f32(n), alpha);
            let rel = |x: f32| (f64::from(x) - want).abs() / want;
            worst_half = worst_half.max(rel(ggx::d_half(&half_from(&g), alpha as f32)));
            let from_cos = HalfVector::from_cosines(g.nl, g.nv, g.l.dot(g.v));
            worst_cos = worst_cos.max(rel(ggx::d_half(&from_cos, alpha as f32)));
        }
        assert!(worst_half < 2e-4, "alpha {alpha}: worst relative error {worst_half:.2e}");
        // The same samples through the cosine form: what the half-vector form is for.
        assert!(worst_cos > 10.0 * worst_half, "alpha {alpha}: cosine form {worst_cos:.2e}");
    }
}
