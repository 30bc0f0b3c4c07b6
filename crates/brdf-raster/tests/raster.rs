//! Behaviour of the rasterizer: watertight fill rule, clipping, off-screen triangles, the shading
//! algorithms of seed 004 against hand computation, determinism across thread counts, bad input.

use std::sync::Arc;

use brdf_core::lights::{Attenuation, Light};
use brdf_core::{Input, Model};
use brdf_raster::render::MAX_PIXELS;
use brdf_raster::scene::{canonical_camera, canonical_scene};
use brdf_raster::{
    Camera, Frame, Material, Mesh, Outputs, RenderOptions, Scene, ShadingMode, coverage_counts, render,
};
use glam::{DVec3, Mat4, Vec3};

/// A small deterministic generator (SplitMix64) so the "random" cases are reproducible.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn lambert() -> Model {
    Model::build("lambert", &[]).unwrap()
}

fn scene_of(mesh: Mesh, transform: Mat4) -> Scene {
    let mut scene = Scene::new();
    scene.add(Arc::new(mesh), Material::new(lambert()), transform);
    scene
}

/// A `n × n` grid of quads over `[-s, s]²` in the z = 0 plane, interior vertices jittered, each quad
/// split along a random diagonal: many shared edges and vertices.
fn grid(n: usize, s: f64, rng: &mut Rng) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (mut x, mut y) = (-s + 2.0 * s * i as f64 / n as f64, -s + 2.0 * s * j as f64 / n as f64);
            if i > 0 && i < n && j > 0 && j < n {
                let h = 0.3 * 2.0 * s / n as f64;
                x += rng.range(-h, h);
                y += rng.range(-h, h);
            }
            positions.push(Vec3::new(x as f32, y as f32, 0.0));
        }
    }
    let mut indices = Vec::new();
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if rng.next() < 0.5 {
                indices.extend([[a, b, c], [a, c, d]]);
            } else {
                indices.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    Mesh::new(positions, indices, None).unwrap()
}

fn no_cull(w: u32, h: u32) -> RenderOptions {
    RenderOptions { cull_back_faces: false, ..RenderOptions::new(w, h) }
}

fn assert_all_once(counts: &[u32], what: &str) {
    let over = counts.iter().filter(|&&c| c > 1).count();
    let holes = counts.iter().filter(|&&c| c == 0).count();
    assert!(over == 0 && holes == 0, "{what}: {over} samples covered twice or more, {holes} not covered");
}

#[test]
fn a_jittered_grid_covers_every_pixel_exactly_once_under_random_views() {
    let mut rng = Rng(7);
    for case in 0..12 {
        let mesh = grid(32, 16.0, &mut rng);
        // Random rotation about z and tilt, so the grid (far larger than the view) covers the image.
        let rot = Mat4::from_rotation_z(rng.range(0.0, 6.3) as f32)
            * Mat4::from_rotation_x(rng.range(-0.25, 0.25) as f32)
            * Mat4::from_rotation_y(rng.range(-0.25, 0.25) as f32);
        let scene = scene_of(mesh, rot);
        let camera = if case % 3 == 0 {
            Camera::orthographic(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 3.0, 0.1, 100.0).unwrap()
        } else {
            let eye = Vec3::new(
                rng.range(-0.5, 0.5) as f32,
                rng.range(-0.5, 0.5) as f32,
                rng.range(1.0, 3.0) as f32,
            );
            Camera::perspective(eye, Vec3::ZERO, Vec3::Y, 1.0, 0.05, 100.0).unwrap()
        };
        let (w, h) = (97 + 13 * case, 61 + 7 * case);
        let mut options = no_cull(w, h);
        options.samples_per_pixel = if case % 4 == 1 { 4 } else { 1 };
        let counts = coverage_counts(&scene, &camera, &options).unwrap();
        assert_all_once(&counts, &format!("grid case {case}"));
        // The depth-tested render draws every pixel too, from a triangle of the mesh.
        let frame = render(&scene, &camera, &options).unwrap();
        assert_eq!(frame.covered_pixels(), (w * h) as usize, "case {case}");
    }
}

#[test]
fn a_grid_with_edges_through_sample_centres_covers_each_pixel_once() {
    // Vertices exactly on pixel centres, 4 px apart, both diagonal directions: every shared edge
    // (horizontal, vertical, diagonal) passes through sample centres, so only the fill rule decides
    // who owns them.
    let (w, h) = (64u32, 64u32);
    let px = 2.0 / 64.0;
    let centre = |i: i32| -1.0 + (4.0 * i as f32 + 0.5) * px;
    let n = 20;
    let positions: Vec<Vec3> =
        (0..=n).flat_map(|j| (0..=n).map(move |i| Vec3::new(centre(i - 2), -centre(j - 2), 0.0))).collect();
    let at = |i: i32, j: i32| (j * (n + 1) + i) as u32;
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                indices.extend([[a, c, b], [a, d, c]]);
            } else {
                indices.extend([[a, d, b], [b, d, c]]);
            }
        }
    }
    let scene = scene_of(Mesh::new(positions, indices, None).unwrap(), Mat4::IDENTITY);
    let camera = Camera::orthographic(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 2.0, 0.5, 2.0).unwrap();
    for spp in [1, 4] {
        let options = RenderOptions { samples_per_pixel: spp, ..no_cull(w, h) };
        assert_all_once(
            &coverage_counts(&scene, &camera, &options).unwrap(),
            &format!("aligned grid, {spp} spp"),
        );
    }
}

#[test]
fn a_triangle_fan_around_a_random_centre_covers_the_window_exactly_once() {
    // piglit's overdraw fan: perimeter vertices at random non-uniform angular steps on a circle that
    // encloses the window, so most vertices lie off screen.
    let mut rng = Rng(11);
    for case in 0..8 {
        let centre = Vec3::new(rng.range(-0.8, 0.8) as f32, rng.range(-0.8, 0.8) as f32, 0.0);
        let radius = if case % 2 == 0 { 3.0 } else { 5000.0 }; // the second far beyond the guard band
        let mut positions = vec![centre];
        let mut angle = 0.0f64;
        while angle < std::f64::consts::TAU {
            positions.push(centre + radius * Vec3::new(angle.cos() as f32, angle.sin() as f32, 0.0));
            angle += rng.range(0.01, 0.4);
        }
        let n = positions.len() as u32 - 1;
        let indices: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
        let scene = scene_of(Mesh::new(positions, indices, None).unwrap(), Mat4::IDENTITY);
        let camera =
            Camera::orthographic(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 2.0, 0.5, 2.0).unwrap();
        let counts = coverage_counts(&scene, &camera, &no_cull(128, 128)).unwrap();
        assert_all_once(&counts, &format!("fan case {case}"));
    }
}

#[test]
fn triangles_crossing_the_near_plane_are_clipped_not_dropped() {
    // A floor y = −1 from behind the camera (z = +10) to z = −50, as two triangles; the camera at the
    // origin looks down −z, so both triangles cross the near plane.
    let positions = vec![
        Vec3::new(-50.0, -1.0, 10.0),
        Vec3::new(50.0, -1.0, 10.0),
        Vec3::new(50.0, -1.0, -50.0),
        Vec3::new(-50.0, -1.0, -50.0),
    ];
    let mesh = Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3]], None).unwrap();
    let scene = scene_of(mesh, Mat4::IDENTITY);
    let (w, h) = (160u32, 120u32);
    let camera =
        Camera::perspective(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), Vec3::Y, 1.0, 0.1, 1000.0).unwrap();
    let counts = coverage_counts(&scene, &camera, &no_cull(w, h)).unwrap();
    assert!(counts.iter().all(|&c| c <= 1));
    // Analytic expectation: the ray through a pixel centre meets the floor at view depth in (near, 50).
    let t = (0.5f64).tan();
    let mut mismatched = 0;
    for r in 0..h {
        for c in 0..w {
            let xn = 2.0 * (f64::from(c) + 0.5) / f64::from(w) - 1.0;
            let yn = 1.0 - 2.0 * (f64::from(r) + 0.5) / f64::from(h);
            let d = DVec3::new(xn * t * f64::from(w) / f64::from(h), yn * t, -1.0);
            let hit = d.y < 0.0 && {
                let s = -1.0 / d.y;
                let p = s * d;
                s > 0.1 && p.z > -50.0 && p.x.abs() < 50.0
            };
            if hit != (counts[(r * w + c) as usize] == 1) {
                mismatched += 1;
            }
        }
    }
    // Only samples within a hair of the far edge of the floor (at the horizon) may disagree.
    assert!(mismatched <= w as usize / 4, "{mismatched} pixels disagree with the analytic floor");
    // The bottom rows — made only of the clipped parts near the camera — are fully covered.
    assert!(counts[((h - 1) * w) as usize..].iter().all(|&c| c == 1));
}

#[test]
fn triangles_far_off_screen_cover_exactly_the_expected_pixels() {
    // Random large triangles with vertices up to 10^4 image widths away (beyond the guard band, so
    // x/y clipping runs) compared with an exact point-in-triangle test at every pixel centre.
    let mut rng = Rng(3);
    let (w, h) = (64u32, 48u32);
    let camera = Camera::orthographic(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 2.0, 0.5, 2.0).unwrap();
    let aspect = f64::from(w) / f64::from(h);
    for case in 0..40 {
        let spread = [2.0, 50.0, 20_000.0][case % 3];
        let p: Vec<DVec3> =
            (0..3).map(|_| DVec3::new(rng.range(-spread, spread), rng.range(-spread, spread), 0.0)).collect();
        let mesh = Mesh::new(p.iter().map(|v| v.as_vec3()).collect(), vec![[0, 1, 2]], None).unwrap();
        let counts = coverage_counts(&scene_of(mesh, Mat4::IDENTITY), &camera, &no_cull(w, h)).unwrap();
        let area = (p[1] - p[0]).cross(p[2] - p[0]).z;
        let mut wrong = 0;
        for r in 0..h {
            for c in 0..w {
                let x = (2.0 * (f64::from(c) + 0.5) / f64::from(w) - 1.0) * aspect;
                let y = 1.0 - 2.0 * (f64::from(r) + 0.5) / f64::from(h);
                let q = DVec3::new(x, y, 0.0);
                let e = |a: DVec3, b: DVec3| (b - a).cross(q - a).z * area.signum();
                let margin = 1e-6 * spread * spread;
                let (e0, e1, e2) = (e(p[0], p[1]), e(p[1], p[2]), e(p[2], p[0]));
                if e0.abs() < margin || e1.abs() < margin || e2.abs() < margin {
                    continue; // on an edge within snapping precision: either answer is right
                }
                let inside = e0 > 0.0 && e1 > 0.0 && e2 > 0.0;
                if inside != (counts[(r * w + c) as usize] == 1) {
                    wrong += 1;
                }
            }
        }
        assert_eq!(wrong, 0, "case {case} (spread {spread})");
    }
}

/// Seed 004's numerical example: the triangle v0 = (2,2,1), v1 = (6,2,1), v2 = (4,5,1) with vertex
/// normals (−1,−1,1), (1,0,0), (0,1,1), light and viewer at infinity on +z, I_e = 2, I_a = 1, I_i = 12,
/// k_a = 0.3, k_d = 0.3, k_s = 0.6, n = 3, read at s = (4,3,1). Rendered orthographically along −z so
/// that the centre pixel's centre is exactly s (which happens to be the centroid).
fn seed_example(mode: ShadingMode, ks: f64) -> f32 {
    let positions = vec![Vec3::new(2.0, 2.0, 1.0), Vec3::new(6.0, 2.0, 1.0), Vec3::new(4.0, 5.0, 1.0)];
    let normals = vec![Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 1.0)];
    let mesh = Mesh::new(positions, vec![[0, 1, 2]], Some(normals)).unwrap();
    let model = Model::build(
        "blinn_phong_classic",
        &[
            ("kd".into(), Input::Number(0.3)),
            ("ks".into(), Input::Number(ks)),
            ("shininess".into(), Input::Number(3.0)),
        ],
    )
    .unwrap();
    let material = Material::new(model).with_ambient(Vec3::splat(0.3)).with_emission(Vec3::splat(2.0));
    let mut scene = Scene::new();
    scene.add(Arc::new(mesh), material, Mat4::IDENTITY);
    scene.add_light(Light::directional(Vec3::NEG_Z, Vec3::splat(12.0)).unwrap());
    let camera =
        Camera::orthographic(Vec3::new(4.0, 3.0, 10.0), Vec3::new(4.0, 3.0, 0.0), Vec3::Y, 8.1, 1.0, 20.0)
            .unwrap();
    let options = RenderOptions { shading: mode, ..RenderOptions::new(81, 81) };
    let frame: Frame = render(&scene, &camera, &options).unwrap();
    let c = frame.hdr_at(40, 40);
    assert!((c.x - c.y).abs() < 1e-6 && (c.y - c.z).abs() < 1e-6, "grey expected, got {c}");
    c.x
}

/// The course formula `I = I_e + I_a k_a + I_i (k_d (n·l) + k_s (n·h)^n)` with l = v = h = +z, with the
/// specular gated on n·l > 0 (the `blinn_phong_classic` convention).
fn course(n: DVec3, ks: f64) -> f64 {
    let nz = n.normalize().z;
    let spec = if nz > 0.0 { ks * nz.max(0.0).powi(3) } else { 0.0 };
    2.0 + 0.3 + 12.0 * (0.3 * nz.max(0.0) + spec)
}

#[test]
fn seed_004_example_matches_hand_computation_in_every_mode() {
    let n = [DVec3::new(-1.0, -1.0, 1.0), DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 1.0)]
        .map(|v| v.normalize());
    let p = [DVec3::new(2.0, 2.0, 1.0), DVec3::new(6.0, 2.0, 1.0), DVec3::new(4.0, 5.0, 1.0)];
    // s = (4, 3) = b·p with b = (1/3, 1/3, 1/3) (solve 2b0+6b1+4b2 = 4, 2b0+2b1+5b2 = 3, Σb = 1).
    let b = [1.0 / 3.0; 3];
    let tol = 1e-4;

    // Constant shading: the polygon normal (0,0,1). The seed's constant shading has no specular term:
    // with k_s = 0 that is 2 + 0.3 + 12·0.3 = 5.9; with the specular it adds 12·0.6.
    let flat_diffuse = f64::from(seed_example(ShadingMode::Flat, 0.0));
    assert!((flat_diffuse - course(DVec3::Z, 0.0)).abs() < tol, "{flat_diffuse}");
    let flat = f64::from(seed_example(ShadingMode::Flat, 0.6));
    assert!((flat - course(DVec3::Z, 0.6)).abs() < tol, "{flat}");

    // Gouraud: the model at the vertices, interpolated.
    let gouraud_expect: f64 = (0..3).map(|k| b[k] * course(n[k], 0.6)).sum();
    let gouraud = f64::from(seed_example(ShadingMode::Gouraud, 0.6));
    assert!((gouraud - gouraud_expect).abs() < tol, "{gouraud} vs {gouraud_expect}");

    // Phong: the interpolated normal, renormalised.
    let n_s = n[0] * b[0] + n[1] * b[1] + n[2] * b[2];
    let phong = f64::from(seed_example(ShadingMode::Phong, 0.6));
    assert!((phong - course(n_s, 0.6)).abs() < tol, "{phong} vs {}", course(n_s, 0.6));

    // Quadratic (van Overveld & Wyvill): n = Σ n_i b_i² + Σ n_ij b_i b_j, n_ij = n_i + n_j − β_ij,
    // β_ij = 3((n_i + n_j)·δ/δ²)δ with δ = p_j − p_i.
    let coef = |i: usize, j: usize| {
        let d = p[j] - p[i];
        n[i] + n[j] - 3.0 * ((n[i] + n[j]).dot(d) / d.length_squared()) * d
    };
    let n_q = n[0] * b[0] * b[0]
        + n[1] * b[1] * b[1]
        + n[2] * b[2] * b[2]
        + coef(0, 1) * b[0] * b[1]
        + coef(1, 2) * b[1] * b[2]
        + coef(2, 0) * b[2] * b[0];
    let quad = f64::from(seed_example(ShadingMode::QuadraticNormals, 0.6));
    assert!((quad - course(n_q, 0.6)).abs() < tol, "{quad} vs {}", course(n_q, 0.6));
    // The example's point: Phong shading sees the highlight that Gouraud misses.
    assert!(phong > gouraud + 1.0);
}

/// A spot light above and in front of the origin, with the course's polynomial attenuation.
fn overhead_spot() -> Light {
    let falloff = Attenuation::Polynomial { c1: 1.0, c2: 0.1, c3: 0.05 };
    Light::spot(Vec3::new(0.0, 3.0, 2.0), Vec3::new(0.0, -1.0, -0.6), Vec3::splat(6.0), 0.3, 0.6, falloff)
        .unwrap()
}

fn assert_same(a: &Frame, b: &Frame, what: &str) {
    assert!(
        a.hdr
            .iter()
            .zip(&b.hdr)
            .all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits)),
        "{what}: hdr"
    );
    assert!(a.depth.iter().zip(&b.depth).all(|(x, y)| x.to_bits() == y.to_bits()), "{what}: depth");
    assert!(
        a.normal
            .iter()
            .zip(&b.normal)
            .all(|(x, y)| x.to_array().map(f32::to_bits) == y.to_array().map(f32::to_bits)),
        "{what}: normal"
    );
    assert_eq!(a.triangle_id, b.triangle_id, "{what}: ids");
}

#[test]
fn output_is_bit_identical_for_1_2_and_4_threads() {
    // Two overlapping, intersecting instances (depth ties and ordering matter) plus the canonical sphere.
    let mut scene = canonical_scene(4).unwrap();
    let sphere = scene.instances[0].mesh.clone();
    let red = Material::new(lambert()).with_ambient(Vec3::splat(0.1));
    scene.add(sphere.clone(), red.clone(), Mat4::from_translation(Vec3::new(0.5, 0.2, 0.1)));
    scene.add(
        sphere,
        red,
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 0.5, 1.0),
            glam::Quat::from_rotation_z(0.4),
            Vec3::new(-0.4, -0.3, -0.5),
        ),
    );
    scene.add_light(overhead_spot());
    let camera = canonical_camera();
    for (mode, spp) in [
        (ShadingMode::Phong, 1),
        (ShadingMode::Gouraud, 4),
        (ShadingMode::QuadraticNormals, 1),
        (ShadingMode::Flat, 9),
    ] {
        let options = RenderOptions { shading: mode, samples_per_pixel: spp, ..RenderOptions::new(203, 157) };
        let frames: Vec<Frame> = [1, 2, 4]
            .iter()
            .map(|&k| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(k)
                    .build()
                    .unwrap()
                    .install(|| render(&scene, &camera, &options).unwrap())
            })
            .collect();
        assert_same(&frames[0], &frames[1], &format!("{mode:?} 1 vs 2"));
        assert_same(&frames[0], &frames[2], &format!("{mode:?} 1 vs 4"));
        assert!(frames[0].covered_pixels() > 1000);
    }
}

#[test]
fn shading_eight_samples_at_a_time_gives_the_bits_of_shading_one_at_a_time() {
    // Without occlusion the renderer shades Phong / quadratic samples eight at a time; an occlusion
    // provider that is not marked trivial (but answers w = δ = 1) forces the one-sample path.
    struct OneAtATime;
    impl brdf_raster::render::Occlusion for OneAtATime {}
    let build = |name: &str, params: &[(&str, Input)]| {
        let p: Vec<(String, Input)> = params.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
        Model::build(name, &p).unwrap()
    };
    let mut scene = canonical_scene(3).unwrap();
    let sphere = scene.instances[0].mesh.clone();
    let models = [
        build("cook_torrance", &[("roughness", Input::Number(0.08)), ("kd", Input::Number(0.2))]),
        build(
            "cook_torrance",
            &[("metal", Input::Text("au".into())), ("distribution", Input::Text("beckmann".into()))],
        ),
        build("lambert", &[]),
        build("phong_classic", &[]),
        build("oren_nayar", &[]),
        build("ward", &[]),
        build("toon", &[]),
    ];
    for (k, m) in models.into_iter().enumerate() {
        let angle = k as f32 * 0.9;
        let at = Vec3::new(1.3 * angle.cos(), 0.6 * (k as f32 - 3.0) / 3.0, 1.3 * angle.sin() - 1.0);
        let material =
            Material::new(m).with_ambient(Vec3::splat(0.03)).with_emission(Vec3::new(0.0, 0.01, 0.0));
        scene.add(
            sphere.clone(),
            material,
            Mat4::from_scale_rotation_translation(Vec3::splat(0.45), glam::Quat::IDENTITY, at),
        );
    }
    scene.add_light(overhead_spot());
    scene.add_light(
        Light::point(Vec3::new(-2.0, 0.5, 1.0), Vec3::new(2.0, 1.0, 0.5), Attenuation::None).unwrap(),
    );
    let ortho = Camera::orthographic(Vec3::new(0.5, 1.0, 3.0), Vec3::ZERO, Vec3::Y, 2.5, 0.1, 10.0).unwrap();
    for (camera, what) in [(canonical_camera(), "perspective"), (ortho, "orthographic")] {
        for mode in [ShadingMode::Phong, ShadingMode::QuadraticNormals] {
            let options = RenderOptions { shading: mode, ..RenderOptions::new(211, 149) };
            let lanes = render(&scene, &camera, &options).unwrap();
            let one = brdf_raster::render::render_with(&scene, &camera, &options, &OneAtATime, None).unwrap();
            assert_same(&lanes, &one, &format!("{what} {mode:?}"));
            assert!(lanes.covered_pixels() > 5000, "{what}");
        }
    }
}

#[test]
fn the_8_bit_image_encoded_during_the_render_is_the_one_encoded_after_it() {
    use brdf_core::tonemap::Operator;
    let mut scene = canonical_scene(4).unwrap();
    // A background whose mean over 9 or 16 samples is not its own bits: the render copies one encoded
    // background pixel outside the covered span of each row, which must be the resolved value's.
    scene.background = Vec3::new(0.1, 0.7, 0.33);
    let camera = canonical_camera();
    let mut reused = Frame::default();
    for (op, ev, spp) in [
        (Operator::Clamp, 0.0, 1),
        (Operator::Reinhard, 1.5, 4),
        (Operator::Aces, -0.5, 1),
        (Operator::ReinhardExtended { white: 3.0 }, 0.0, 9),
        (Operator::Clamp, 0.7, 16),
        (Operator::Aces, 0.0, 9),
    ] {
        let options = RenderOptions {
            tonemap: op,
            exposure: ev,
            samples_per_pixel: spp,
            outputs: brdf_raster::Outputs::ALL,
            ..RenderOptions::new(97, 53)
        };
        let frame = render(&scene, &camera, &options).unwrap();
        assert_eq!(frame.rgb8, frame.to_rgb8(), "{op:?} {ev} {spp}");
        brdf_raster::render::render_into(&scene, &camera, &options, &mut reused).unwrap();
        assert_eq!(reused.rgb8, frame.rgb8, "{op:?}: render_into");
    }
    // A view where the sphere fills whole bands, and one where nothing is drawn (looking away).
    let near = Camera::perspective(Vec3::new(0.0, 0.0, 1.3), Vec3::ZERO, Vec3::Y, 0.8, 0.1, 100.0).unwrap();
    let away =
        Camera::perspective(Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.0, 0.0, 4.0), Vec3::Y, 0.8, 0.1, 100.0)
            .unwrap();
    for spp in [1, 4] {
        let options = RenderOptions {
            samples_per_pixel: spp,
            outputs: brdf_raster::Outputs::ALL,
            ..RenderOptions::new(64, 40)
        };
        let frame = render(&scene, &near, &options).unwrap();
        assert!(frame.covered_pixels() > 64 * 20, "{spp} spp");
        assert_eq!(frame.rgb8, frame.to_rgb8(), "close up, {spp} spp");
        let frame = render(&scene, &away, &options).unwrap();
        assert_eq!(frame.covered_pixels(), 0);
        assert_eq!(frame.rgb8, frame.to_rgb8(), "nothing drawn, {spp} spp");
    }
    // Not asked for: no image kept (and a reused frame drops its old one).
    brdf_raster::render::render_into(&scene, &camera, &RenderOptions::new(97, 53), &mut reused).unwrap();
    assert!(reused.rgb8.is_empty());
    assert!(render(&scene, &camera, &RenderOptions::new(8, 8)).unwrap().rgb8.is_empty());
}

#[test]
fn a_render_writes_exactly_the_outputs_asked_for_with_the_bits_of_a_full_render() {
    let mut scene = canonical_scene(3).unwrap();
    scene.background = Vec3::new(0.02, 0.03, 0.05);
    let camera = canonical_camera();
    // Every subset of the outputs, at 1 and 4 samples per pixel, into one reused frame whose buffers
    // change from render to render.
    let mut reused = Frame::default();
    for spp in [1, 4, 9] {
        let base = RenderOptions { samples_per_pixel: spp, ..RenderOptions::new(83, 61) };
        let full = render(&scene, &camera, &RenderOptions { outputs: Outputs::ALL, ..base }).unwrap();
        assert_eq!(full.outputs(), Outputs::ALL);
        for bits in 1..32u8 {
            let outputs = Outputs::NAMES
                .iter()
                .enumerate()
                .filter(|(k, _)| bits >> k & 1 == 1)
                .fold(Outputs::NONE, |o, (_, (_, x))| o | *x);
            let options = RenderOptions { outputs, ..base };
            brdf_raster::render::render_into(&scene, &camera, &options, &mut reused).unwrap();
            let what = format!("{spp} spp, {:?}", outputs.names());
            assert_eq!(reused.outputs(), outputs, "{what}");
            let expect = Frame {
                hdr: if outputs.contains(Outputs::HDR) { full.hdr.clone() } else { vec![] },
                depth: if outputs.contains(Outputs::DEPTH) { full.depth.clone() } else { vec![] },
                normal: if outputs.contains(Outputs::NORMAL) { full.normal.clone() } else { vec![] },
                triangle_id: if outputs.contains(Outputs::TRIANGLE_ID) {
                    full.triangle_id.clone()
                } else {
                    vec![]
                },
                rgb8: if outputs.contains(Outputs::RGB8) { full.rgb8.clone() } else { vec![] },
                ..full.clone()
            };
            assert_same(&reused, &expect, &what);
            assert_eq!(reused.rgb8, expect.rgb8, "{what}: rgb8");
            if outputs.contains(Outputs::DEPTH) || outputs.contains(Outputs::TRIANGLE_ID) {
                assert_eq!(reused.covered_pixels(), full.covered_pixels(), "{what}: coverage");
            }
            if outputs.contains(Outputs::HDR) || outputs.contains(Outputs::RGB8) {
                assert_eq!(reused.to_rgb8(), full.rgb8, "{what}: to_rgb8");
            }
        }
    }
    // Without supersampling the rows of a band are 16; with it the sample rows stay near 16.
    assert_eq!([1, 2, 3, 4].map(brdf_raster::tiles::band_rows), [16, 8, 5, 4]);
}

#[test]
fn render_into_reuses_a_frame_and_gives_the_same_bits_as_render() {
    let scene = canonical_scene(3).unwrap();
    let camera = canonical_camera();
    let mut frame = render(&scene, &camera, &RenderOptions::new(40, 30)).unwrap();
    for (w, h) in [(64, 48), (64, 48), (17, 90)] {
        let options = RenderOptions::new(w, h);
        brdf_raster::render::render_into(&scene, &camera, &options, &mut frame).unwrap();
        assert_same(&frame, &render(&scene, &camera, &options).unwrap(), &format!("{w}×{h}"));
        assert_eq!((frame.width, frame.height, frame.hdr.len()), (w, h, (w * h) as usize));
    }
}

#[test]
fn supersampling_blends_the_silhouette_and_keeps_the_interior() {
    let scene = canonical_scene(5).unwrap();
    let camera = canonical_camera();
    let one = render(&scene, &camera, &RenderOptions::new(160, 120)).unwrap();
    let four =
        render(&scene, &camera, &RenderOptions { samples_per_pixel: 16, ..RenderOptions::new(160, 120) })
            .unwrap();
    // Partial coverage at the silhouette gives values strictly between background and surface.
    let partial = four
        .hdr
        .iter()
        .zip(&one.hdr)
        .filter(|(s, o)| s.x > 0.0 && s.x < 0.5 * o.x.max(0.01) && o.x > 0.0)
        .count()
        + four.hdr.iter().zip(&one.hdr).filter(|(s, o)| o.x == 0.0 && s.x > 0.0).count();
    assert!(partial > 50, "{partial}");
    // The centre pixel: the mean of 16 samples of a smooth field stays within half a level.
    let (a, b) = (one.rgb8_at(80, 60), four.rgb8_at(80, 60));
    assert!((0..3).all(|k| (i32::from(a[k]) - i32::from(b[k])).abs() <= 1), "{a:?} vs {b:?}");
}

#[test]
fn back_faces_are_culled_only_when_asked_and_mirroring_keeps_the_front() {
    let tri = || {
        Mesh::new(
            vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)],
            vec![[0, 1, 2]],
            None,
        )
        .unwrap()
    };
    let camera = Camera::perspective(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 1.0, 0.1, 10.0).unwrap();
    let seen = |transform: Mat4, cull: bool| {
        let options = RenderOptions { cull_back_faces: cull, ..RenderOptions::new(32, 32) };
        render(&scene_of(tri(), transform), &camera, &options).unwrap().covered_pixels()
    };
    assert!(seen(Mat4::IDENTITY, true) > 0);
    let flipped = Mat4::from_rotation_y(std::f32::consts::PI);
    assert_eq!(seen(flipped, true), 0);
    assert!(seen(flipped, false) > 0);
    // A mirror (det < 0) turns the winding around on screen, but the front stays the front.
    assert!(seen(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), true) > 0);
}

#[test]
fn lights_of_every_kind_add_up_and_respect_the_spot_cone() {
    // A large plane facing +z, lit from straight above by a narrow spot: lit inside the cone only.
    let plane = Mesh::new(
        vec![
            Vec3::new(-4.0, -4.0, 0.0),
            Vec3::new(4.0, -4.0, 0.0),
            Vec3::new(4.0, 4.0, 0.0),
            Vec3::new(-4.0, 4.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
        None,
    )
    .unwrap();
    let mut scene = scene_of(plane, Mat4::IDENTITY);
    scene.add_light(
        Light::spot(
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::NEG_Z,
            Vec3::splat(4.0),
            0.2,
            0.3,
            Attenuation::InverseSquare,
        )
        .unwrap(),
    );
    let camera = Camera::orthographic(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 8.0, 0.1, 10.0).unwrap();
    let frame = render(&scene, &camera, &RenderOptions::new(80, 80)).unwrap();
    // Centre: E = 4/2² = 1, Lambert 0.8/π, cos = 1.
    let expect = 0.8 / std::f32::consts::PI;
    assert!((frame.hdr_at(40, 40).x - expect).abs() < 1e-3, "{}", frame.hdr_at(40, 40));
    // Outside tan(0.3)·2 ≈ 0.62 units (6 px) from the centre: dark; inside tan(0.2)·2 ≈ 0.41: lit.
    assert_eq!(frame.hdr_at(40 + 8, 40), Vec3::ZERO);
    assert!(frame.hdr_at(40 + 3, 40).x > 0.8 * expect);
}

#[test]
fn bad_input_is_refused_with_a_clear_error() {
    let scene = canonical_scene(1).unwrap();
    let camera = canonical_camera();
    let err = |o: RenderOptions| render(&scene, &camera, &o).unwrap_err().to_string();
    assert!(err(RenderOptions::new(0, 10)).contains("width"));
    assert!(err(RenderOptions::new(10, 20_000)).contains("height"));
    assert!(
        err(RenderOptions { samples_per_pixel: 2, ..RenderOptions::new(10, 10) })
            .contains("samples_per_pixel")
    );
    // The limit is on pixels, whatever the samples per pixel, and names both sides.
    let big = err(RenderOptions { samples_per_pixel: 16, ..RenderOptions::new(16384, 16384) });
    assert!(big.starts_with("width, height:") && big.contains(&MAX_PIXELS.to_string()), "{big}");
    assert!(err(RenderOptions::new(16384, 4097)).contains("exceeds"));
    for spp in [1, 4, 9, 16] {
        RenderOptions { samples_per_pixel: spp, ..RenderOptions::new(3840, 2160) }.validate().unwrap();
        RenderOptions { samples_per_pixel: spp, ..RenderOptions::new(16384, 4096) }.validate().unwrap();
    }
    assert!(err(RenderOptions { outputs: Outputs::NONE, ..RenderOptions::new(4, 4) }).contains("outputs"));
    assert!(err(RenderOptions { exposure: f32::NAN, ..RenderOptions::new(10, 10) }).contains("exposure"));
    let mut bad = scene.clone();
    bad.instances[0].transform = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
    assert!(render(&bad, &camera, &RenderOptions::new(8, 8)).unwrap_err().to_string().contains("singular"));
    bad.instances[0].transform = Mat4::from_translation(Vec3::new(f32::NAN, 0.0, 0.0));
    assert!(render(&bad, &camera, &RenderOptions::new(8, 8)).is_err());
    bad.instances[0].transform =
        Mat4::from_cols(glam::Vec4::new(1.0, 0.0, 0.0, 0.5), glam::Vec4::Y, glam::Vec4::Z, glam::Vec4::W);
    assert!(render(&bad, &camera, &RenderOptions::new(8, 8)).unwrap_err().to_string().contains("affine"));
    // An empty scene renders the background.
    let empty = Scene { background: Vec3::new(0.1, 0.2, 0.3), ..Scene::new() };
    let frame = render(&empty, &camera, &RenderOptions::new(4, 3)).unwrap();
    assert!(frame.hdr.iter().all(|&c| c == Vec3::new(0.1, 0.2, 0.3)) && frame.covered_pixels() == 0);
    // Degenerate triangles are skipped, not an error.
    let degenerate =
        Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0)], vec![[0, 1, 2]], None).unwrap();
    let frame = render(&scene_of(degenerate, Mat4::IDENTITY), &camera, &RenderOptions::new(8, 8)).unwrap();
    assert_eq!(frame.covered_pixels(), 0);
}

#[test]
fn random_triangle_soups_with_extreme_coordinates_render_without_panics_or_nans() {
    // Debug builds check integer overflow, so this also guards the fixed-point range reasoning.
    let mut rng = Rng(99);
    for case in 0..60 {
        let scale = 10f64.powf(rng.range(-3.0, 7.0));
        let n = 1 + (rng.next() * 40.0) as usize;
        let positions: Vec<Vec3> = (0..3 * n)
            .map(|_| {
                Vec3::new(
                    rng.range(-1.0, 1.0) as f32,
                    rng.range(-1.0, 1.0) as f32,
                    rng.range(-1.0, 1.0) as f32,
                ) * scale as f32
            })
            .collect();
        let indices: Vec<[u32; 3]> = (0..n as u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        let normals = positions.iter().map(|p| if p.length() > 0.0 { *p } else { Vec3::Z }).collect();
        let mesh = Mesh::new(positions, indices, Some(normals)).unwrap();
        let mut scene = scene_of(mesh, Mat4::IDENTITY);
        scene.add_light(
            Light::point(Vec3::new(0.3, 0.2, 0.1), Vec3::splat(5.0), Attenuation::InverseSquare).unwrap(),
        );
        let eye =
            Vec3::new(rng.range(-2.0, 2.0) as f32, rng.range(-2.0, 2.0) as f32, rng.range(-2.0, 2.0) as f32);
        let camera = if case % 4 == 3 {
            Camera::orthographic(eye, Vec3::ZERO, Vec3::Y, rng.range(0.01, 100.0) as f32, -10.0, 10.0)
        } else {
            Camera::perspective(eye, Vec3::ZERO, Vec3::Y, rng.range(0.1, 3.0) as f32, 1e-3, 1e6)
        };
        let Ok(camera) = camera else { continue };
        let options = RenderOptions {
            shading: ShadingMode::ALL[case % 4],
            samples_per_pixel: [1, 4, 9][case % 3],
            cull_back_faces: case % 2 == 0,
            ..RenderOptions::new(37 + case as u32, 23 + 2 * case as u32)
        };
        let frame = render(&scene, &camera, &options).unwrap();
        assert!(frame.hdr.iter().all(|c| c.is_finite()), "case {case}: non-finite colour");
        assert!(frame.depth.iter().all(|d| (-1e-6..=1.0).contains(d)), "case {case}: depth out of [0, 1]");
        let counts = coverage_counts(&scene, &camera, &options).unwrap();
        assert!(counts.iter().all(|&c| c as usize <= n), "case {case}");
    }
}
