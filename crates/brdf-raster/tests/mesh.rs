//! Meshes, normals and procedural shapes, as specifications of behaviour: the canonical icosphere
//! of SCENE.md, CCW-outward winding of every generator, seed 004's polygon-normal example and the
//! three vertex-normal weightings, transforms and validation.

use std::f64::consts::PI;

use brdf_raster::mesh::Mesh;
use brdf_raster::normals::{
    Weighting, corner_average_normal, corner_normal, newell_normal, polygon_vertex_normals, triangle_normal,
    vertex_normals,
};
use brdf_raster::procedural::{cube, icosphere, open_box, plane, torus};
use glam::{DVec3, Mat4, Vec3};

fn assert_close(a: Vec3, b: Vec3, tol: f32, what: &str) {
    assert!(
        (a - b).abs().max_element() <= tol,
        "{what}: {a} vs {b} (difference {})",
        (a - b).abs().max_element()
    );
}

fn centroid(mesh: &Mesh, f: usize) -> Vec3 {
    let [a, b, c] = mesh.triangle(f);
    (a + b + c) / 3.0
}

/// Every face's unit normal points away from `inside(centroid)` (a point on the inner side).
fn assert_faces_point_away(mesh: &Mesh, inside: impl Fn(Vec3) -> Vec3, what: &str) {
    for f in 0..mesh.triangle_count() {
        let c = centroid(mesh, f);
        let outward = c - inside(c);
        let n = mesh.face_normal(f);
        assert!(n.dot(outward) > 0.0, "{what}: face {f} at {c} has normal {n}, not away from {}", inside(c));
    }
}

// ---------------------------------------------------------------- icosphere (SCENE.md)

#[test]
fn icosphere_has_20_4l_triangles_and_10_4l_plus_2_vertices() {
    for level in 0..=5u32 {
        let m = icosphere(level).unwrap();
        let four_l = 4usize.pow(level);
        assert_eq!(m.triangle_count(), 20 * four_l, "level {level}");
        assert_eq!(m.vertex_count(), 10 * four_l + 2, "level {level}");
    }
}

#[test]
fn icosphere_above_the_level_limit_is_refused() {
    assert!(icosphere(brdf_raster::procedural::MAX_ICOSPHERE_LEVEL + 1).is_err());
}

#[test]
fn icosphere_level_0_is_a_regular_icosahedron_on_the_unit_sphere() {
    let m = icosphere(0).unwrap();
    for p in &m.positions {
        assert!((p.length() - 1.0).abs() < 1e-6);
    }
    // All 30 edges have the same length: 4/sqrt(10 + 2 sqrt 5) for the unit circumradius.
    let expected = 4.0 / (10.0 + 2.0 * 5.0f64.sqrt()).sqrt();
    let stats = m.stats();
    assert!(stats.watertight && stats.winding_consistent);
    for tri in &m.indices {
        for k in 0..3 {
            let e = m.positions[tri[k] as usize].distance(m.positions[tri[(k + 1) % 3] as usize]);
            assert!((f64::from(e) - expected).abs() < 1e-6, "edge length {e}, expected {expected}");
        }
    }
}

/// Recompute level L+1 from level L exactly as SCENE.md words it, independently of the library:
/// midpoints of the sorted unique edge keys appended in order, 4 children per face in order.
fn assert_is_scene_subdivision(parent: &Mesh, child: &Mesh) {
    let nv = parent.vertex_count();
    let mut edges: Vec<(u32, u32)> = parent
        .indices
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort();
    edges.dedup();
    assert_eq!(child.vertex_count(), nv + edges.len());
    assert_eq!(&child.positions[..nv], &parent.positions[..], "old vertices keep their indices");
    for (k, &(a, b)) in edges.iter().enumerate() {
        let mid = ((parent.positions[a as usize].as_dvec3() + parent.positions[b as usize].as_dvec3()) * 0.5)
            .normalize()
            .as_vec3();
        assert_close(
            child.positions[nv + k],
            mid,
            2e-7,
            &format!("vertex {} = midpoint of edge ({a}, {b})", nv + k),
        );
    }
    let vertex_of = |a: u32, b: u32| nv as u32 + edges.binary_search(&(a.min(b), a.max(b))).unwrap() as u32;
    for (f, &[a, b, c]) in parent.indices.iter().enumerate() {
        let (ab, bc, ca) = (vertex_of(a, b), vertex_of(b, c), vertex_of(c, a));
        assert_eq!(
            &child.indices[4 * f..4 * f + 4],
            &[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]],
            "children of face {f}"
        );
    }
}

#[test]
fn icosphere_levels_follow_the_scene_construction() {
    let meshes: Vec<Mesh> = (0..=3).map(|l| icosphere(l).unwrap()).collect();
    for w in meshes.windows(2) {
        assert_is_scene_subdivision(&w[0], &w[1]);
    }
    // Spelled out for level 1: vertex 12 is the projected midpoint of the smallest edge key.
    let l0 = &meshes[0];
    let first_edge = l0
        .indices
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .min()
        .unwrap();
    let mid = (l0.positions[first_edge.0 as usize] + l0.positions[first_edge.1 as usize]).normalize();
    assert_close(meshes[1].positions[12], mid, 2e-7, "level-1 vertex 12");
}

#[test]
fn icosphere_normals_are_the_unit_positions() {
    let m = icosphere(3).unwrap();
    assert_eq!(m.normals, m.positions);
    for p in &m.positions {
        assert!((p.length() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn icosphere_faces_are_ccw_seen_from_outside() {
    for level in 0..=4 {
        let m = icosphere(level).unwrap();
        assert_faces_point_away(&m, |_| Vec3::ZERO, &format!("icosphere({level})"));
        let stats = m.stats();
        assert!(stats.watertight && stats.winding_consistent && stats.components == 1);
        assert_eq!(stats.degenerate_triangles, 0);
        assert!(stats.signed_volume > 0.0);
    }
    // The volume converges to the ball's 4π/3 from below.
    let v = icosphere(5).unwrap().signed_volume();
    assert!(v < 4.0 * PI / 3.0 && v > 0.998 * 4.0 * PI / 3.0, "volume {v}");
}

// ---------------------------------------------------------------- torus, plane, boxes

#[test]
fn torus_has_2_m_n_triangles_wound_outward_with_exact_normals() {
    let (big_r, r) = (0.7f32, 0.3f32);
    let m = torus(48, 24).unwrap();
    assert_eq!(m.triangle_count(), 2 * 48 * 24);
    assert_eq!(m.vertex_count(), 48 * 24);
    // The inner side of a point is the centre of its tube cross-section (on the ring of radius R).
    let ring = move |p: Vec3| Vec3::new(p.x, p.y, 0.0).normalize() * big_r;
    assert_faces_point_away(&m, ring, "torus");
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert_close(*n, (*p - ring(*p)) / r, 2e-6, "torus normal");
        assert!(((*p - ring(*p)).length() - r).abs() < 1e-6);
    }
    let stats = m.stats();
    assert!(stats.watertight && stats.winding_consistent);
    // Volume 2π²Rr², approached from below by the inscribed polyhedron.
    let exact = 2.0 * PI * PI * f64::from(big_r) * f64::from(r * r);
    assert!(stats.signed_volume > 0.98 * exact && stats.signed_volume < exact, "{}", stats.signed_volume);
    assert!(torus(2, 10).is_err() && torus(10, 2).is_err());
}

#[test]
fn plane_faces_plus_y_and_is_ccw_from_above() {
    let m = plane(2.0, 4).unwrap();
    assert_eq!(m.triangle_count(), 2 * 16);
    assert_eq!(m.vertex_count(), 25);
    for f in 0..m.triangle_count() {
        assert_close(m.face_normal(f), Vec3::Y, 1e-6, "plane face normal");
    }
    assert!(m.normals.iter().all(|&n| n == Vec3::Y));
    assert!((m.area() - 4.0).abs() < 1e-6);
    let b = m.bounds();
    assert_eq!((b.min, b.max), (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0)));
    assert!(plane(0.0, 1).is_err() && plane(f32::NAN, 1).is_err() && plane(1.0, 0).is_err());
}

#[test]
fn cube_is_closed_ccw_outward_with_flat_normals() {
    let m = cube(2.0, 3).unwrap();
    assert_eq!(m.triangle_count(), 6 * 2 * 9);
    assert_faces_point_away(&m, |_| Vec3::ZERO, "cube");
    for f in 0..m.triangle_count() {
        for &i in &m.indices[f] {
            assert_close(m.normals[i as usize], m.face_normal(f), 1e-6, "flat vertex normals");
        }
    }
    assert!((m.signed_volume() - 8.0).abs() < 1e-5);
    assert!((m.area() - 24.0).abs() < 1e-4);
}

#[test]
fn open_box_has_no_top_and_faces_inward() {
    let m = open_box(1.0, 2).unwrap();
    assert_eq!(m.triangle_count(), 5 * 2 * 4);
    for f in 0..m.triangle_count() {
        let c = centroid(&m, f);
        assert!(c.y < 0.5 - 1e-6, "no face on the open top");
        let n = m.face_normal(f);
        assert!(n.dot(-c) > 0.0, "face {f} at {c} must face the inside, normal {n}");
        for &i in &m.indices[f] {
            assert_close(m.normals[i as usize], n, 1e-6, "flat inward normals");
        }
    }
    // Seen from outside the winding is clockwise: the (open) volume is negative.
    assert!(m.signed_volume() < 0.0);
    assert!(!m.stats().watertight);
}

// ---------------------------------------------------------------- seed 004: polygon normals

/// Seed 004 "Numerical Example": the slightly non-planar quad.
fn seed_quad() -> [Vec3; 4] {
    [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.5)]
}

#[test]
fn newell_on_the_seed_quad_matches_the_written_out_sums() {
    let q = seed_quad();
    // Newell's sums written out in f64, independently of the library:
    // a = Σ (y_i − y_i+1)(z_i + z_i+1), b = Σ (z_i − z_i+1)(x_i + x_i+1), c = Σ (x_i − x_i+1)(y_i + y_i+1).
    let p: Vec<DVec3> = q.iter().map(|v| v.as_dvec3()).collect();
    let mut expected = DVec3::ZERO;
    for i in 0..4 {
        let (a, b) = (p[i], p[(i + 1) % 4]);
        expected +=
            DVec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    // By hand: only edges 3→4 and 4→1 leave the z = 0 plane, giving a = 0.5, b = −0.5, and the
    // xy-projection is the unit square, whose doubled area gives c = 2.
    assert_eq!(expected, DVec3::new(0.5, -0.5, 2.0));
    assert_close(newell_normal(&q), expected.as_vec3(), 1e-7, "Newell vector");
    // The doubled vector area is also the sum of a fan's triangle cross products.
    let fan = triangle_normal(q[0], q[1], q[2]) + triangle_normal(q[0], q[2], q[3]);
    assert_close(newell_normal(&q), fan, 1e-6, "Newell = sum over a fan");
}

#[test]
fn corner_normals_of_the_seed_quad_and_their_average() {
    let q = seed_quad();
    let corner = |i: usize| corner_normal(q[(i + 3) % 4], q[i], q[(i + 1) % 4]);
    // n = (v_i+1 − v_i) × (v_i−1 − v_i), each product expanded by hand.
    assert_eq!(corner(0), Vec3::new(0.0, -0.5, 1.0)); // (1,0,0) × (0,1,0.5)
    assert_eq!(corner(1), Vec3::new(0.0, 0.0, 1.0)); // (0,1,0) × (−1,0,0)
    assert_eq!(corner(2), Vec3::new(0.5, 0.0, 1.0)); // (−1,0,0.5) × (0,−1,0)
    // (0,−1,−0.5) × (1,0,−0.5) = ((−1)(−0.5) − (−0.5)(0), (−0.5)(1) − 0·(−0.5), 0·0 − (−1)(1)).
    // The seed prints (0.25, −0.5, 1) here, a slip that also shifts its averaged normal.
    assert_eq!(corner(3), Vec3::new(0.5, -0.5, 1.0));
    let sum: Vec3 = (0..4).map(|i| corner(i).normalize()).sum();
    let avg = corner_average_normal(&q);
    assert_close(avg, sum.normalize(), 1e-6, "average of unit corner normals");
    // The quad maps onto itself (reversed) under the reflection (x, y, z) → (1 − y, 1 − x, z), so
    // any sound polygon normal has n_x = −n_y, as Newell's (0.5, −0.5, 2) does. The seed's
    // averaged normal does not, because of the slip above.
    assert!((avg.x + avg.y).abs() < 1e-6, "symmetry: {avg}");
    // Both methods agree to a few degrees on this nearly planar quad.
    let newell = newell_normal(&q).normalize();
    assert!(avg.dot(newell) > 0.999, "{avg} vs {newell}");
}

#[test]
fn newell_equals_the_cross_product_for_planar_triangles() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rand = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32 * 20.0 - 10.0
    };
    for _ in 0..1000 {
        let t = [
            Vec3::new(rand(), rand(), rand()),
            Vec3::new(rand(), rand(), rand()),
            Vec3::new(rand(), rand(), rand()),
        ];
        let cross = triangle_normal(t[0], t[1], t[2]);
        let newell = newell_normal(&t);
        assert!((cross - newell).length() <= 1e-4 * cross.length().max(1.0), "{cross} vs {newell}");
    }
}

// ---------------------------------------------------------------- vertex normal weightings

#[test]
fn vertex_normal_weightings_on_the_seed_quad_split_into_a_fan() {
    let q = seed_quad().to_vec();
    let tris = [[0u32, 1, 2], [0, 2, 3]];
    // Both triangles meet at v1 = origin. By hand:
    // f1 = (1,0,0) × (1,1,0) = (0,0,1); f2 = (1,1,0) × (0,1,0.5) = (0.5,−0.5,1).
    let (f1, f2) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.5, -0.5, 1.0));
    // θ1 = angle((1,0,0), (1,1,0)) = π/4; θ2 = acos((1,1,0)·(0,1,0.5) / (√2 · √1.25)) = acos(1/√2.5).
    let (theta1, theta2) = (std::f32::consts::FRAC_PI_4, (1.0 / 2.5f32.sqrt()).acos());
    let equal = (f1.normalize() + f2.normalize()).normalize();
    let area = (f1 + f2).normalize();
    let angle = (theta1 * f1.normalize() + theta2 * f2.normalize()).normalize();
    let at_v1 = |w| vertex_normals(&q, &tris, w)[0];
    assert_close(at_v1(Weighting::Equal), equal, 1e-6, "eq. 12.31");
    assert_close(at_v1(Weighting::Area), area, 1e-6, "eq. 12.32");
    assert_close(at_v1(Weighting::Angle), angle, 1e-6, "eq. 12.33");
    // They are three different answers here, and the area-weighted one is Newell's normal.
    for (a, b) in [(equal, area), (equal, angle), (area, angle)] {
        assert!((a - b).length() > 0.01, "{a} and {b} should differ");
    }
    assert_close(area, newell_normal(&seed_quad()).normalize(), 1e-6, "area-weighted = Newell");
    // v2 belongs to the first triangle only: its normal is f̂1 whatever the weighting.
    for w in [Weighting::Equal, Weighting::Area, Weighting::Angle] {
        assert_close(vertex_normals(&q, &tris, w)[1], f1, 1e-6, "single face");
    }
    // As one polygon, every vertex gets the Newell normal whatever the weighting.
    for w in [Weighting::Equal, Weighting::Area, Weighting::Angle] {
        for n in polygon_vertex_normals(&q, &[vec![0, 1, 2, 3]], w) {
            assert_close(n, newell_normal(&seed_quad()).normalize(), 1e-6, "polygon vertex normal");
        }
    }
}

#[test]
fn angle_weighting_is_invariant_to_retriangulation_and_equal_weighting_is_not() {
    // The corner of a unit cube at the origin, with its three faces; the xy face is split into
    // two triangles that both touch the corner, the other two faces are one triangle each.
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::new(1.0, 1.0, 0.0), // splits the xy face
    ];
    // All faces wound so that their normals point into the octant's outside (−x, −y, −z).
    let tris = [[0u32, 4, 1], [0, 2, 4], [0, 1, 3], [0, 3, 2]];
    let corner = Vec3::splat(-1.0).normalize();
    assert_close(vertex_normals(&p, &tris, Weighting::Angle)[0], corner, 1e-6, "angle weighting");
    let equal = vertex_normals(&p, &tris, Weighting::Equal)[0];
    assert!(equal.dot(corner) < 0.99, "equal weighting counts the split face twice: {equal}");
}

#[test]
fn compute_normals_replaces_the_vertex_normals() {
    let mut m = icosphere(3).unwrap();
    for w in [Weighting::Equal, Weighting::Area, Weighting::Angle] {
        m.compute_normals(w);
        for (n, p) in m.normals.iter().zip(&m.positions) {
            assert!(n.dot(*p) > 0.995, "{w:?}: averaged normal {n} close to the sphere's {p}");
            assert!((n.length() - 1.0).abs() < 1e-5);
        }
    }
}

// ---------------------------------------------------------------- Mesh behaviour

#[test]
fn new_rejects_empty_out_of_range_and_non_finite_input() {
    let tri = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    assert!(Mesh::new(vec![], vec![[0, 1, 2]], None).is_err());
    assert!(Mesh::new(tri.clone(), vec![], None).is_err());
    let e = Mesh::new(tri.clone(), vec![[0, 1, 3]], None).unwrap_err().to_string();
    assert!(e.contains("face 0") && e.contains("vertex 3"), "{e}");
    assert!(
        Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)], vec![[0, 1, 2]], None).is_err()
    );
    assert!(Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::splat(f32::INFINITY)], vec![[0, 1, 2]], None).is_err());
    assert!(Mesh::new(tri.clone(), vec![[0, 1, 2]], Some(vec![Vec3::Z; 2])).is_err());
    assert!(Mesh::new(tri.clone(), vec![[0, 1, 2]], Some(vec![Vec3::Z, Vec3::Z, Vec3::NAN])).is_err());
    let m = Mesh::new(tri, vec![[0, 1, 2]], None).unwrap();
    assert!(m.clone().with_colors(vec![Vec3::ONE; 2]).is_err());
    assert!(m.with_colors(vec![Vec3::ONE, Vec3::ONE, Vec3::INFINITY]).is_err());
}

#[test]
fn zero_given_normals_are_replaced_by_computed_ones() {
    let m = Mesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        vec![[0, 1, 2]],
        Some(vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO]),
    )
    .unwrap();
    assert_eq!(m.normals, vec![Vec3::Z; 3]);
}

#[test]
fn degenerate_faces_are_reported_not_rejected() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0];
    let m = Mesh::new(p, vec![[0, 1, 2], [0, 0, 1], [0, 1, 3], [2, 1, 0]], None).unwrap();
    assert_eq!(m.degenerate_faces(), vec![1, 2]);
    assert_eq!(m.face_normal(1), Vec3::ZERO);
    assert_eq!(m.stats().degenerate_triangles, 2);
}

#[test]
fn flip_winding_reverses_orientation_and_normals() {
    let original = icosphere(2).unwrap();
    let mut m = original.clone();
    m.flip_winding();
    assert!((m.signed_volume() + original.signed_volume()).abs() < 1e-9);
    assert_faces_point_away(&m, |c| c * 2.0, "flipped sphere faces inward");
    assert_eq!(m.normals[5], -original.normals[5]);
    m.flip_winding();
    assert_eq!(m, original);
}

#[test]
fn transformed_moves_positions_and_keeps_normals_perpendicular() {
    let m = cube(1.0, 1).unwrap();
    let t = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
        * Mat4::from_rotation_y(0.3)
        * Mat4::from_scale(Vec3::new(2.0, 0.5, 1.0));
    let moved = m.transformed(&t).unwrap();
    for (p, q) in m.positions.iter().zip(&moved.positions) {
        assert_close(*q, t.transform_point3(*p), 1e-6, "position");
    }
    // The cube's vertex normals are face normals, so they must match the moved faces' normals.
    for f in 0..moved.triangle_count() {
        for &i in &moved.indices[f] {
            assert_close(moved.normals[i as usize], moved.face_normal(f), 1e-5, "normal matrix");
        }
    }
    assert!((moved.signed_volume() - 1.0).abs() < 1e-5, "det = 1 here");
}

#[test]
fn a_mirroring_transform_keeps_faces_ccw_outward() {
    let m = icosphere(2).unwrap();
    let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * Mat4::from_translation(Vec3::X);
    let moved = m.transformed(&mirror).unwrap();
    assert!(moved.signed_volume() > 0.0);
    let center = Vec3::new(-1.0, 0.0, 0.0);
    assert_faces_point_away(&moved, |_| center, "mirrored sphere");
    for (p, n) in moved.positions.iter().zip(&moved.normals) {
        assert!(n.dot(*p - center) > 0.99);
    }
}

#[test]
fn transformed_refuses_singular_projective_and_non_finite_matrices() {
    let m = icosphere(0).unwrap();
    assert!(m.transformed(&Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_err());
    assert!(m.transformed(&Mat4::from_cols_array(&[1.0; 16])).is_err());
    let mut nan = Mat4::IDENTITY;
    nan.x_axis.x = f32::NAN;
    assert!(m.transformed(&nan).is_err());
    assert!(m.transformed(&Mat4::from_scale(Vec3::splat(1e30))).is_err(), "overflows to infinity");
}

#[test]
fn bounds_sphere_and_unit_transform() {
    let m = torus(32, 16).unwrap();
    let b = m.bounds();
    assert_close(b.max, Vec3::new(1.0, 1.0, 0.3), 1e-6, "max");
    assert_close(b.min, Vec3::new(-1.0, -1.0, -0.3), 1e-6, "min");
    let fitted = m.transformed(&m.unit_sphere_transform()).unwrap();
    let (c, r) = fitted.bounding_sphere();
    assert!(c.length() < 1e-6 && (r - 1.0).abs() < 1e-6, "{c} {r}");
}
