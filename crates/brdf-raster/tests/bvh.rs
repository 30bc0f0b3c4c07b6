//! The BVH answers every ray exactly as a brute-force loop over all triangles does: same hit/miss, same
//! triangle id, same t (bit for bit, since both use the same watertight triangle test), on random soups
//! and on real meshes; it is watertight on closed meshes; bad input is refused; results do not depend on
//! the number of threads.

mod ray_support;

use brdf_raster::bvh::{Bvh, Hit, Ray};
use glam::{Mat4, Vec3};
use ray_support::{Rng, asset, brute_any, brute_closest, read_ply, sphere};

/// Compare BVH and brute force on every ray; returns the number of rays that hit.
fn assert_matches_brute_force(tris: &[[Vec3; 3]], bvh: &Bvh, rays: &[Ray]) -> usize {
    let closest = bvh.closest_hits(rays);
    let any = bvh.any_hits(rays);
    let mut hits = 0;
    for (i, r) in rays.iter().enumerate() {
        let want = brute_closest(tris, r);
        assert_eq!(closest[i], want, "ray {i}: {r:?}");
        assert_eq!(bvh.closest_hit(r), want, "single query, ray {i}");
        assert_eq!(any[i], brute_any(tris, r), "any-hit, ray {i}: {r:?}");
        assert_eq!(any[i], want.is_some(), "any-hit agrees with closest-hit, ray {i}");
        hits += usize::from(want.is_some());
    }
    hits
}

fn random_soup(rng: &mut Rng, n: usize, size: f32) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|_| {
            let c = rng.vec3(-1.0, 1.0);
            [c + rng.vec3(-size, size), c + rng.vec3(-size, size), c + rng.vec3(-size, size)]
        })
        .collect()
}

fn random_rays(rng: &mut Rng, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|k| {
            let origin = rng.vec3(-1.5, 1.5);
            // Non-unit directions on purpose: t is in units of |dir|.
            let dir = rng.unit() * rng.range(0.5, 2.0);
            match k % 4 {
                0 => Ray::new(origin, dir),
                1 => Ray::segment(origin, dir, rng.range(0.0, 0.5), rng.range(0.5, 2.0)),
                2 => Ray::segment(origin, dir, 0.0, rng.range(0.0, 0.3)),
                // Axis-aligned directions exercise the 1/0 slab path.
                _ => Ray::new(origin, [Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::X][(k / 4) % 4]),
            }
        })
        .collect()
}

#[test]
fn closest_and_any_hit_equal_brute_force_on_random_soups() {
    let mut rng = Rng(7);
    for (n, size) in [(1, 0.5), (7, 0.3), (300, 0.2), (3000, 0.05)] {
        let tris = random_soup(&mut rng, n, size);
        let bvh = Bvh::from_triangles(&tris).unwrap();
        assert_eq!(bvh.triangle_count(), n);
        let rays = random_rays(&mut rng, 3000);
        let hits = assert_matches_brute_force(&tris, &bvh, &rays);
        // The comparison must cover both outcomes to mean anything.
        assert!(hits > 0 && hits < rays.len(), "n={n}: {hits} hits");
    }
}

#[test]
fn soups_with_clustered_and_coincident_centroids_still_match() {
    // Many triangles sharing one centroid force the median fallback; a thin slab of parallel
    // triangles gives a zero-extent axis.
    let mut rng = Rng(11);
    let mut tris: Vec<[Vec3; 3]> = (0..200)
        .map(|_| {
            let d = rng.vec3(-0.3, 0.3);
            [-d, Vec3::ZERO + Vec3::new(d.y, d.z, d.x), d - Vec3::new(d.y, d.z, d.x)]
        })
        .collect();
    tris.extend((0..200).map(|k| {
        let z = 0.5;
        let x = k as f32 * 0.01 - 1.0;
        [Vec3::new(x, -1.0, z), Vec3::new(x + 0.02, -1.0, z), Vec3::new(x, 1.0, z)]
    }));
    let bvh = Bvh::from_triangles(&tris).unwrap();
    let rays = random_rays(&mut rng, 2000);
    assert!(assert_matches_brute_force(&tris, &bvh, &rays) > 0);
}

#[test]
fn real_mesh_matches_brute_force_for_thousands_of_rays() {
    let Some(path) = asset("garland_cow.ply") else {
        eprintln!("skipped: ../shared/assets/meshes/garland_cow.ply is absent");
        return;
    };
    let (positions, faces) = read_ply(&path);
    let tris: Vec<[Vec3; 3]> = faces.iter().map(|f| f.map(|i| positions[i as usize])).collect();
    let bvh = Bvh::build(&positions, &faces).unwrap();
    assert_eq!(bvh.input_triangles(), faces.len());
    let mut rng = Rng(3);
    let mut rays = Vec::new();
    // From outside toward random points in the box, and from surface points in random directions
    // (the AO pattern: offset a little along the face normal).
    for _ in 0..2000 {
        let target = rng.vec3(-0.5, 0.5) * Vec3::new(1.0, 0.6, 0.33);
        let origin = rng.unit() * 1.5;
        rays.push(Ray::new(origin, target - origin));
    }
    for _ in 0..2000 {
        let f = &tris[(rng.next_u64() % tris.len() as u64) as usize];
        let (a, b) = (rng.f32(), rng.f32());
        let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
        let p = f[0] + (f[1] - f[0]) * a + (f[2] - f[0]) * b;
        let n = (f[1] - f[0]).cross(f[2] - f[0]).normalize();
        let mut d = rng.unit();
        if d.dot(n) < 0.0 {
            d = -d;
        }
        rays.push(Ray::segment(p + n * 1e-4, d, 0.0, rng.range(0.05, 2.0)));
    }
    let hits = assert_matches_brute_force(&tris, &bvh, &rays);
    assert!(hits > 1000 && hits < rays.len(), "{hits}");
}

#[test]
fn rays_through_shared_edges_and_vertices_of_a_closed_mesh_never_slip_through() {
    let (positions, faces) = sphere(4);
    let bvh = Bvh::build(&positions, &faces).unwrap();
    let origin = Vec3::new(0.01, -0.02, 0.015);
    // Aim exactly at every vertex and every edge midpoint (the watertightness cases).
    let mut targets = positions.clone();
    for t in &faces {
        for k in 0..3 {
            targets.push((positions[t[k] as usize] + positions[t[(k + 1) % 3] as usize]) * 0.5);
        }
    }
    for q in targets {
        let r = Ray::new(origin, q - origin);
        assert!(bvh.any_hit(&r), "slipped through at {q}");
        let h = bvh.closest_hit(&r).expect("closest hit");
        assert!((h.t - 1.0).abs() < 1e-3, "t = {} at {q}", h.t);
        assert!(h.u >= 0.0 && h.v >= 0.0 && h.u + h.v <= 1.0 + 1e-6);
    }
}

#[test]
fn coincident_triangles_report_the_smaller_id_whatever_their_order() {
    let tri = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let other = [Vec3::new(5.0, 5.0, 5.0), Vec3::new(6.0, 5.0, 5.0), Vec3::new(5.0, 6.0, 5.0)];
    let ray = Ray::new(Vec3::new(0.1, 0.0, 3.0), -Vec3::Z);
    for (soup, want) in [(vec![other, tri, tri], 1), (vec![tri, other, tri], 0)] {
        let bvh = Bvh::from_triangles(&soup).unwrap();
        assert_eq!(bvh.closest_hit(&ray).map(|h| h.triangle), Some(want));
    }
}

#[test]
fn t_min_and_t_max_bound_the_segment_inclusively() {
    let tri = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let bvh = Bvh::from_triangles(&[tri]).unwrap();
    let o = Vec3::new(0.0, 0.0, 2.0);
    assert!(bvh.any_hit(&Ray::segment(o, -Vec3::Z, 0.0, 2.0)));
    assert!(bvh.any_hit(&Ray::segment(o, -Vec3::Z, 2.0, 3.0)));
    assert!(!bvh.any_hit(&Ray::segment(o, -Vec3::Z, 0.0, 1.999)));
    assert!(!bvh.any_hit(&Ray::segment(o, -Vec3::Z, 2.001, 9.0)));
    // Behind the origin is never hit (negative t_min acts as 0).
    assert!(!bvh.any_hit(&Ray::segment(o, Vec3::Z, -10.0, 10.0)));
    // Both sides are hit.
    assert!(bvh.any_hit(&Ray::new(-o, Vec3::Z)));
}

#[test]
fn degenerate_triangles_are_skipped_and_never_hit() {
    let good = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let line = [Vec3::new(-1.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0)];
    let point = [Vec3::ONE; 3];
    let bvh = Bvh::from_triangles(&[line, good, point]).unwrap();
    assert_eq!((bvh.input_triangles(), bvh.triangle_count(), bvh.skipped_triangles()), (3, 1, 2));
    let h = bvh.closest_hit(&Ray::new(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z)).unwrap();
    assert_eq!(h.triangle, 1, "ids stay those of the input");
    // Only degenerate triangles: a valid, empty tree.
    let empty = Bvh::from_triangles(&[line, point]).unwrap();
    assert_eq!(empty.triangle_count(), 0);
    assert!(!empty.any_hit(&Ray::new(Vec3::ZERO, Vec3::X)));
    assert_eq!(empty.closest_hit(&Ray::new(Vec3::ZERO, Vec3::X)), None);
}

#[test]
fn non_finite_vertices_and_bad_indices_are_refused() {
    let bad = [Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y];
    let e = Bvh::from_triangles(&[bad]).unwrap_err().to_string();
    assert!(e.contains("triangle 0") && e.contains("non-finite"), "{e}");
    let e = Bvh::build(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 3]]).unwrap_err().to_string();
    assert!(e.contains("face 0") && e.contains("vertex 3"), "{e}");
}

#[test]
fn instances_place_each_mesh_by_its_matrix_and_number_triangles_in_order() {
    let mesh = brdf_raster::Mesh::new(
        vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)],
        vec![[0, 1, 2]],
        None,
    )
    .unwrap();
    let bvh = Bvh::from_instances(&[
        (&mesh, Mat4::IDENTITY),
        (&mesh, Mat4::from_translation(Vec3::new(0.0, 0.0, -5.0))),
    ])
    .unwrap();
    let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z);
    assert_eq!(bvh.closest_hit(&ray).map(|h| (h.triangle, h.t)), Some((0, 1.0)));
    let below = Ray::segment(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 1.5, f32::INFINITY);
    assert_eq!(bvh.closest_hit(&below).map(|h| (h.triangle, h.t)), Some((1, 6.0)));
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let mut rng = Rng(99);
    // Large enough to take the parallel build path (> PARALLEL_THRESHOLD triangles).
    let tris = random_soup(&mut rng, 40_000, 0.02);
    let rays = random_rays(&mut rng, 20_000);
    let run = |threads: usize| -> (usize, Vec<Option<Hit>>, Vec<bool>) {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let bvh = Bvh::from_triangles(&tris).unwrap();
            (bvh.node_count(), bvh.closest_hits(&rays), bvh.any_hits(&rays))
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
    // And the parallel build is still exact against brute force on a sample of the rays.
    let bvh = Bvh::from_triangles(&tris).unwrap();
    assert_matches_brute_force(&tris, &bvh, &rays[..300]);
}

#[test]
fn large_batches_traced_in_morton_order_answer_each_ray_in_input_order() {
    // Above COHERENT_BATCH rays the batch functions sort the rays internally; every answer must still
    // land at its ray's index and equal the single-ray query (itself checked against brute force).
    let mut rng = Rng(5);
    let tris = random_soup(&mut rng, 500, 0.2);
    let bvh = Bvh::from_triangles(&tris).unwrap();
    let rays = random_rays(&mut rng, brdf_raster::bvh::COHERENT_BATCH * 2 + 17);
    let closest = bvh.closest_hits(&rays);
    let any = bvh.any_hits(&rays);
    for (i, r) in rays.iter().enumerate() {
        assert_eq!(closest[i], bvh.closest_hit(r), "ray {i}");
        assert_eq!(any[i], bvh.any_hit(r), "ray {i}");
    }
    assert_matches_brute_force(&tris, &bvh, &rays[..500]);
}
