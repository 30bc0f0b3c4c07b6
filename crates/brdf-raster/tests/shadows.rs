//! Shadows fall where geometry says: a unit square at height 1 over the plane y = 0 blocks exactly the
//! points whose segment toward the light crosses it (directional straight down, slanted, point and spot
//! lights), lit surfaces do not shadow themselves (no acne), and eq. 12.75 combines the terms as
//! documented.

mod ray_support;

use brdf_core::lights::{Attenuation, Light};
use brdf_raster::bvh::Bvh;
use brdf_raster::shadows::{diffuse_irradiance, light_visibility, obscurance_illumination, shadow_offset};
use glam::Vec3;
use ray_support::{Rng, grid_y0, sphere};

const H: f32 = 1.0;

/// The plane y = 0 over [-5, 5]² and the square |x|, |z| ≤ 1 at y = H.
fn scene() -> Bvh {
    let (mut p, mut f) = grid_y0(5.0, 10);
    let base = p.len() as u32;
    p.extend([
        Vec3::new(-1.0, H, -1.0),
        Vec3::new(-1.0, H, 1.0),
        Vec3::new(1.0, H, 1.0),
        Vec3::new(1.0, H, -1.0),
    ]);
    f.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
    Bvh::build(&p, &f).unwrap()
}

/// Plane points on a grid, leaving out those within `margin` of where the analytic shadow edge is
/// (`edge_distance(p)` ≈ 0 there), so the test never depends on rounding at the boundary.
fn plane_points(edge_distance: impl Fn(Vec3) -> f32, margin: f32) -> Vec<Vec3> {
    let mut out = Vec::new();
    for i in 0..=60 {
        for j in 0..=60 {
            let p = Vec3::new(-3.0 + 0.1 * i as f32, 0.0, -3.0 + 0.1 * j as f32);
            if edge_distance(p) > margin {
                out.push(p);
            }
        }
    }
    out
}

/// Distance (in the max norm) of `q` in the square's plane from the square's border.
fn border_distance(q: Vec3) -> f32 {
    let inside = 1.0 - q.x.abs().max(q.z.abs());
    inside.abs()
}

fn in_square(q: Vec3) -> bool {
    q.x.abs() < 1.0 && q.z.abs() < 1.0
}

fn check(bvh: &Bvh, light: &Light, crossing: impl Fn(Vec3) -> Option<Vec3>) {
    let pts = plane_points(|p| crossing(p).map_or(1.0, border_distance), 0.02);
    let (mut lit, mut dark) = (0, 0);
    for p in pts {
        let want_shadow = crossing(p).is_some_and(in_square);
        let delta = light_visibility(bvh, p, Vec3::Y, light);
        assert_eq!(delta, if want_shadow { 0.0 } else { 1.0 }, "at {p}");
        if want_shadow { dark += 1 } else { lit += 1 }
    }
    assert!(lit > 100 && dark > 100, "both outcomes covered: {lit} lit, {dark} dark");
}

#[test]
fn a_directional_light_from_straight_above_shadows_exactly_the_points_under_the_square() {
    let bvh = scene();
    let light = Light::directional(-Vec3::Y, Vec3::ONE).unwrap();
    check(&bvh, &light, |p| Some(p + Vec3::Y * H));
}

#[test]
fn a_slanted_directional_light_shifts_the_shadow_by_height_times_the_slope() {
    let bvh = scene();
    // Travels +x while descending: the shadow moves by +0.5·H in x.
    let light = Light::directional(Vec3::new(0.5, -1.0, 0.0), Vec3::ONE).unwrap();
    check(&bvh, &light, |p| Some(p + Vec3::new(-0.5, 1.0, 0.0) * H));
}

#[test]
fn a_point_light_casts_the_central_projection_of_the_square() {
    let bvh = scene();
    let lp = Vec3::new(0.3, 3.0, -0.2);
    let light = Light::point(lp, Vec3::splat(10.0), Attenuation::InverseSquare).unwrap();
    // The segment p → light crosses y = H at the fraction H / lp.y of the way.
    check(&bvh, &light, |p| Some(p + (lp - p) * (H / lp.y)));
    // A spot light at the same place has the same δ (its cone only shapes the irradiance).
    let spot = Light::spot(lp, -Vec3::Y, Vec3::ONE, 0.1, 0.2, Attenuation::InverseSquare).unwrap();
    check(&bvh, &spot, |p| Some(p + (lp - p) * (H / lp.y)));
}

#[test]
fn a_point_light_between_the_square_and_the_plane_casts_no_shadow_on_the_plane() {
    let bvh = scene();
    let light = Light::point(Vec3::new(0.0, 0.5, 0.0), Vec3::ONE, Attenuation::None).unwrap();
    for p in plane_points(|_| 1.0, 0.0) {
        assert_eq!(light_visibility(&bvh, p, Vec3::Y, &light), 1.0, "at {p}");
    }
    // The square is two-sided and thin: a point on it sees the light whichever normal it is given
    // (the ray offset goes to the light's side), and a point above the square is in its shadow.
    assert_eq!(light_visibility(&bvh, Vec3::new(0.2, H, 0.1), -Vec3::Y, &light), 1.0);
    assert_eq!(light_visibility(&bvh, Vec3::new(0.2, H, 0.1), Vec3::Y, &light), 1.0);
    assert_eq!(light_visibility(&bvh, Vec3::new(0.2, 2.0, 0.1), Vec3::Y, &light), 0.0);
}

#[test]
fn lit_points_on_a_convex_mesh_do_not_shadow_themselves() {
    // Random points inside the faces of a sphere, each lit by a light on its own side of the face:
    // with a correct offset no shadow ray re-hits the face it starts on (no "shadow acne").
    let (p, f) = sphere(4);
    let bvh = Bvh::build(&p, &f).unwrap();
    let mut rng = Rng(21);
    for k in 0..4000 {
        let t = f[k % f.len()].map(|i| p[i as usize]);
        let (a, b) = (rng.f32(), rng.f32());
        let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
        let q = t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b;
        let ng = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let mut l = rng.unit();
        if l.dot(ng) < 0.05 {
            l = (l + ng * 1.05).normalize();
        }
        let light = Light::directional(-l, Vec3::ONE).unwrap();
        assert_eq!(light_visibility(&bvh, q, ng, &light), 1.0, "acne at {q} toward {l}");
        let point = Light::point(q + l * 3.0, Vec3::ONE, Attenuation::InverseSquare).unwrap();
        assert_eq!(light_visibility(&bvh, q, ng, &point), 1.0, "acne at {q} toward a point light");
        // The opposite side of a closed convex mesh is always in its own shadow.
        let behind = Light::directional(l, Vec3::ONE).unwrap();
        assert_eq!(light_visibility(&bvh, q, ng, &behind), 0.0, "light leak at {q}");
    }
    assert!(shadow_offset(&bvh) > 0.0 && shadow_offset(&bvh) < 1e-3);
}

#[test]
fn diffuse_irradiance_counts_only_visible_lights_and_eq_12_75_combines_as_documented() {
    let bvh = scene();
    let sun = Light::directional(-Vec3::Y, Vec3::new(1.0, 0.5, 0.25)).unwrap();
    let lamp = Light::point(Vec3::new(4.0, 2.0, 0.0), Vec3::splat(8.0), Attenuation::InverseSquare).unwrap();
    let lights = [sun, lamp];
    // Under the square: the sun is blocked, the lamp (off to the side, low) is not.
    let p = Vec3::new(0.5, 0.0, 0.0);
    let to = lamp_position(&lamp) - p;
    let lamp_e = 8.0 / to.length_squared() * (to.normalize().dot(Vec3::Y));
    let id = diffuse_irradiance(Some(&bvh), p, Vec3::Y, Vec3::Y, &lights);
    assert!((id - Vec3::splat(lamp_e)).abs().max_element() < 1e-5, "{id} vs {lamp_e}");
    // Without shadows both count.
    let id_open = diffuse_irradiance(None, p, Vec3::Y, Vec3::Y, &lights);
    assert!((id_open - (Vec3::new(1.0, 0.5, 0.25) + Vec3::splat(lamp_e))).abs().max_element() < 1e-5);
    // Eq. 12.75: [ka Ia + kd Id] w + kd Id.
    let (ka, ia, kd, w) = (Vec3::splat(0.2), Vec3::splat(0.5), Vec3::new(0.8, 0.4, 0.2), 0.6);
    let i = obscurance_illumination(ka, ia, kd, id, w);
    let by_hand = Vec3::new(
        (0.2 * 0.5 + 0.8 * id.x) * 0.6 + 0.8 * id.x,
        (0.2 * 0.5 + 0.4 * id.y) * 0.6 + 0.4 * id.y,
        (0.2 * 0.5 + 0.2 * id.z) * 0.6 + 0.2 * id.z,
    );
    assert!((i - by_hand).abs().max_element() < 1e-6);
    // w = 1 and no lights: plain ambient; w = 0: only the direct term.
    assert_eq!(obscurance_illumination(ka, ia, kd, Vec3::ZERO, 1.0), ka * ia);
    assert_eq!(obscurance_illumination(ka, ia, kd, id, 0.0), kd * id);
}

fn lamp_position(l: &Light) -> Vec3 {
    match *l {
        Light::Point { position, .. } | Light::Spot { position, .. } => position,
        Light::Directional { .. } => unreachable!(),
    }
}
