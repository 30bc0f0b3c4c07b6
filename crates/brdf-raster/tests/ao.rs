//! Obscurance (seed 004 eq. 12.71–12.74) against values derived independently: an open plane is fully
//! open, the bottom centre and a corner of an open box match a deterministic quadrature of
//! `(1/π) ∫ μ(d) cos θ dω` with `d` computed analytically from the box's planes, a sphere resting on a
//! plane darkens the plane near the contact, and the estimate is deterministic and validated.

mod ray_support;

use brdf_raster::ao::{AoOptions, MAX_SAMPLES, Obscurance, mesh_obscurance, mu, obscurance_per_vertex};
use brdf_raster::bvh::Bvh;
use glam::Vec3;
use ray_support::{grid_y0, sphere};

/// μ of the module docs, written again here in f64 from its definition (not calling the crate).
fn mu_ref(d: f64, tau: f64, d_max: f64) -> f64 {
    if d >= d_max { 1.0 } else { (1.0 - (-tau * d / d_max).exp()) / (1.0 - (-tau).exp()) }
}

/// The seed's plain `1 − e^(−τ d/d_max)` without the normalisation (to show the tests can tell them apart).
fn mu_unnormalised(d: f64, tau: f64, d_max: f64) -> f64 {
    if d >= d_max { 1.0 } else { 1.0 - (-tau * d / d_max).exp() }
}

/// An open box: the floor `z = 0` over `|x|, |y| ≤ a`, four walls up to `z = h`, no lid. Faces point
/// inward (it does not matter: triangles are two-sided).
fn open_box(a: f32, h: f32) -> Vec<[Vec3; 3]> {
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let quad = |p: [Vec3; 4]| [[p[0], p[1], p[2]], [p[0], p[2], p[3]]];
    let mut t = Vec::new();
    t.extend(quad([v(-a, -a, 0.0), v(a, -a, 0.0), v(a, a, 0.0), v(-a, a, 0.0)]));
    t.extend(quad([v(-a, -a, 0.0), v(-a, a, 0.0), v(-a, a, h), v(-a, -a, h)]));
    t.extend(quad([v(a, -a, 0.0), v(a, -a, h), v(a, a, h), v(a, a, 0.0)]));
    t.extend(quad([v(-a, -a, 0.0), v(-a, -a, h), v(a, -a, h), v(a, -a, 0.0)]));
    t.extend(quad([v(-a, a, 0.0), v(a, a, 0.0), v(a, a, h), v(-a, a, h)]));
    t
}

/// `w` at a floor point `(px, py, 0)` of the open box by a midpoint product rule in (θ, φ):
/// `(1/π) Σ μ(d) cos θ sin θ Δθ Δφ`, with `d` the distance to the first wall plane crossed when the
/// crossing lies below the rim (`z ≤ h`), else ∞ (the ray leaves through the open top).
fn box_floor_obscurance(px: f64, py: f64, a: f64, h: f64, mu: impl Fn(f64) -> f64) -> f64 {
    let (nt, np) = (1500, 1500);
    let (dt, dp) = (std::f64::consts::FRAC_PI_2 / nt as f64, std::f64::consts::TAU / np as f64);
    let mut acc = 0.0;
    for i in 0..nt {
        let theta = (i as f64 + 0.5) * dt;
        let (st, ct) = theta.sin_cos();
        let mut ring = 0.0;
        for j in 0..np {
            let (sp, cp) = ((j as f64 + 0.5) * dp).sin_cos();
            let (wx, wy) = (st * cp, st * sp);
            let tx = if wx > 0.0 { (a - px) / wx } else { (-a - px) / wx };
            let ty = if wy > 0.0 { (a - py) / wy } else { (-a - py) / wy };
            let d = tx.min(ty);
            ring += if d * ct <= h { mu(d) } else { 1.0 };
        }
        acc += ring * ct * st;
    }
    acc * dt * dp / std::f64::consts::PI
}

/// The crate's estimate averaged over `keys` independent rotations of the pattern.
fn estimate(o: &Obscurance, p: Vec3, n: Vec3, keys: u64) -> f64 {
    (0..keys).map(|k| f64::from(o.at(p, n, k))).sum::<f64>() / keys as f64
}

#[test]
fn mu_is_zero_at_contact_one_from_d_max_on_increasing_and_concave() {
    let (tau, d_max) = (2.0, 1.5);
    assert_eq!(mu(0.0, tau, d_max), 0.0);
    assert_eq!(mu(d_max, tau, d_max), 1.0);
    assert_eq!(mu(10.0, tau, d_max), 1.0);
    assert_eq!(mu(f32::INFINITY, tau, d_max), 1.0);
    let xs: Vec<f32> = (0..=150).map(|i| i as f32 * 0.01).collect();
    let ys: Vec<f32> = xs.iter().map(|&x| mu(x, tau, d_max)).collect();
    for k in 1..ys.len() - 1 {
        assert!(ys[k] > ys[k - 1], "increasing at {}", xs[k]);
        assert!(ys[k] - ys[k - 1] >= ys[k + 1] - ys[k] - 1e-6, "concave at {}", xs[k]);
        assert!((f64::from(ys[k]) - mu_ref(f64::from(xs[k]), 2.0, 1.5)).abs() < 1e-6);
    }
    // Continuous at d_max: the value just below the range is close to 1.
    assert!(mu(d_max * 0.9999, tau, d_max) > 0.9995);
}

#[test]
fn a_point_on_an_open_plane_is_fully_open() {
    let (p, f) = grid_y0(5.0, 4);
    let bvh = Bvh::build(&p, &f).unwrap();
    for samples in [1, 7, 64, 1000] {
        let opts = AoOptions { tau: 3.0, d_max: 2.0, samples, seed: 5, ..AoOptions::default() };
        let o = Obscurance::new(&bvh, &opts).unwrap();
        for (i, q) in [Vec3::ZERO, Vec3::new(1.3, 0.0, -2.2), Vec3::new(2.5, 0.0, 2.5)].iter().enumerate() {
            assert_eq!(o.at(*q, Vec3::Y, i as u64), 1.0, "samples={samples} at {q}");
        }
    }
}

#[test]
fn bottom_centre_and_corner_of_an_open_box_match_quadrature() {
    let (a, h, tau, d_max) = (1.0f32, 1.0f32, 2.0f32, 1.5f32);
    let bvh = Bvh::from_triangles(&open_box(a, h)).unwrap();
    let opts = AoOptions { tau, d_max, samples: 4096, seed: 17, ..AoOptions::default() };
    let o = Obscurance::new(&bvh, &opts).unwrap();
    let (a64, h64, t64, d64) = (a as f64, h as f64, tau as f64, d_max as f64);
    for (px, py) in [(0.0, 0.0), (-0.8, -0.8), (0.5, -0.2)] {
        let want = box_floor_obscurance(px, py, a64, h64, |d| mu_ref(d, t64, d64));
        let plain = box_floor_obscurance(px, py, a64, h64, |d| mu_unnormalised(d, t64, d64));
        let got = estimate(&o, Vec3::new(px as f32, py as f32, 0.0), Vec3::Z, 4);
        // 16384 stratified rays: the error is far below the tolerance, which is itself far below the
        // gap to the unnormalised μ (so a wrong normalisation cannot pass).
        assert!((got - want).abs() < 2e-3, "({px},{py}): estimate {got}, quadrature {want}");
        assert!((plain - want).abs() > 0.02, "({px},{py}): test has no power ({plain} vs {want})");
        assert!(want > 0.0 && want < 1.0);
    }
}

#[test]
fn the_corner_is_darker_than_the_centre_and_a_taller_box_darker_still() {
    let opts = AoOptions { tau: 2.0, d_max: 1.5, samples: 1024, seed: 1, ..AoOptions::default() };
    let low = Bvh::from_triangles(&open_box(1.0, 0.5)).unwrap();
    let tall = Bvh::from_triangles(&open_box(1.0, 2.0)).unwrap();
    let w = |bvh: &Bvh, x: f32| Obscurance::new(bvh, &opts).unwrap().at(Vec3::new(x, x, 0.0), Vec3::Z, 0);
    assert!(w(&low, -0.8) < w(&low, 0.0));
    assert!(w(&tall, 0.0) < w(&low, 0.0));
    assert!(w(&tall, -0.8) < w(&low, -0.8));
}

#[test]
fn a_sphere_resting_on_a_plane_darkens_the_plane_near_the_contact() {
    // Unit sphere centred at (0, 1, 0), touching the plane y = 0 at the origin.
    let (sp, sf) = sphere(4);
    let (gp, gf) = grid_y0(4.0, 32);
    let mut positions: Vec<Vec3> = gp.clone();
    let mut faces = gf.clone();
    let base = positions.len() as u32;
    positions.extend(sp.iter().map(|&p| p + Vec3::Y));
    faces.extend(sf.iter().map(|t| t.map(|i| i + base)));
    let bvh = Bvh::build(&positions, &faces).unwrap();
    let opts = AoOptions { tau: 1.0, d_max: 2.0, samples: 256, seed: 3, ..AoOptions::default() };

    // Along the plane, w rises with the distance from the contact point.
    let xs = [0.25f32, 0.5, 1.0, 1.5, 2.0, 3.0];
    let pts: Vec<Vec3> = xs.iter().map(|&x| Vec3::new(x, 0.0, 0.0)).collect();
    let w = obscurance_per_vertex(&bvh, &pts, &vec![Vec3::Y; pts.len()], &opts).unwrap();
    for k in 1..w.len() {
        assert!(w[k] > w[k - 1], "w({}) = {} ≤ w({}) = {}", xs[k], w[k], xs[k - 1], w[k - 1]);
    }
    assert!(w[0] < 0.6, "near the contact the sphere covers much of the sky: {}", w[0]);
    // Beyond d_max of every sphere point the plane is open again.
    let far = obscurance_per_vertex(&bvh, &[Vec3::new(3.9, 0.0, 3.9)], &[Vec3::Y], &opts).unwrap();
    assert_eq!(far[0], 1.0);

    // On the sphere, per vertex: a vertex low on the sphere (facing the plane from close by) is darker
    // than the equator, whose lower half-hemisphere sees the plane farther away, and the top is fully
    // open. (The contact vertex itself is left out: its hemisphere faces straight into the plane at
    // distance 0, where any ray offset steps through the plane.)
    let normals: Vec<Vec3> = sp.clone();
    let spos: Vec<Vec3> = sp.iter().map(|&p| p + Vec3::Y).collect();
    let ws = obscurance_per_vertex(&bvh, &spos, &normals, &opts).unwrap();
    let at = |dir: Vec3| ws[sp.iter().position(|&p| p.distance(dir) < 1e-6).unwrap()];
    assert_eq!(at(Vec3::Y), 1.0);
    let low = at(Vec3::new(1.0, -1.0, 0.0).normalize());
    assert!(low < at(Vec3::X) && at(Vec3::X) < at(Vec3::Y), "{low} {} {}", at(Vec3::X), at(Vec3::Y));
    // The sphere alone is convex: every vertex sees an open hemisphere.
    let (mp, mf) = (sp.clone(), sf.clone());
    let alone = brdf_raster::Mesh::new(mp, mf, Some(sp.clone())).unwrap();
    assert!(mesh_obscurance(&alone, &opts).unwrap().iter().all(|&x| x == 1.0));
}

#[test]
fn obscurance_is_deterministic_and_independent_of_the_thread_count() {
    let (sp, sf) = sphere(3);
    let (gp, gf) = grid_y0(3.0, 24);
    let mut positions = gp.clone();
    let mut faces = gf;
    let base = positions.len() as u32;
    positions.extend(sp.iter().map(|&p| p + Vec3::Y));
    faces.extend(sf.iter().map(|t| t.map(|i| i + base)));
    let normals: Vec<Vec3> = gp.iter().map(|_| Vec3::Y).chain(sp.iter().copied()).collect();
    let bvh = Bvh::build(&positions, &faces).unwrap();
    let opts = AoOptions { tau: 2.0, d_max: 1.5, samples: 32, seed: 9, ..AoOptions::default() };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| obscurance_per_vertex(&bvh, &positions, &normals, &opts).unwrap())
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
    // Another seed rotates the patterns: some values change, none by much.
    let other = obscurance_per_vertex(&bvh, &positions, &normals, &AoOptions { seed: 10, ..opts }).unwrap();
    assert!(one.iter().zip(&other).any(|(a, b)| a != b));
    let mean_diff: f32 = one.iter().zip(&other).map(|(a, b)| (a - b).abs()).sum::<f32>() / one.len() as f32;
    assert!(mean_diff < 0.05, "{mean_diff}");
    assert!(one.iter().all(|&w| (0.0..=1.0).contains(&w)));
}

#[test]
fn invalid_options_and_inputs_are_refused_with_the_argument_named() {
    let bvh = Bvh::from_triangles(&open_box(1.0, 1.0)).unwrap();
    let ok = AoOptions::default();
    let cases = [
        (AoOptions { tau: 0.0, ..ok }, "tau"),
        (AoOptions { tau: -1.0, ..ok }, "tau"),
        (AoOptions { tau: f32::NAN, ..ok }, "tau"),
        (AoOptions { d_max: 0.0, ..ok }, "d_max"),
        (AoOptions { d_max: f32::INFINITY, ..ok }, "d_max"),
        (AoOptions { samples: 0, ..ok }, "samples"),
        (AoOptions { samples: MAX_SAMPLES + 1, ..ok }, "samples"),
    ];
    for (opts, name) in cases {
        let e = Obscurance::new(&bvh, &opts).unwrap_err().to_string();
        assert!(e.starts_with(name), "{e}");
    }
    let p = [Vec3::ZERO, Vec3::X];
    let e = obscurance_per_vertex(&bvh, &p, &[Vec3::Z], &ok).unwrap_err().to_string();
    assert!(e.starts_with("normals"), "{e}");
    let e = obscurance_per_vertex(&bvh, &[Vec3::NAN], &[Vec3::Z], &ok).unwrap_err().to_string();
    assert!(e.starts_with("points") && e.contains("point 0"), "{e}");
    let e = obscurance_per_vertex(&bvh, &[Vec3::ZERO], &[Vec3::new(0.0, f32::NAN, 1.0)], &ok)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("normals"), "{e}");
    // A zero normal (isolated vertex) has no hemisphere: w = 1 by definition.
    assert_eq!(obscurance_per_vertex(&bvh, &[Vec3::ZERO], &[Vec3::ZERO], &ok).unwrap(), vec![1.0]);
}
