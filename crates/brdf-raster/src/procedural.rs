//! Procedural meshes: the canonical benchmark scene's icosphere, a torus, a plane, a cube
//! and an open box. Every mesh is wound counter-clockwise seen from its front side, and its vertex
//! normals are exact (analytic), not averaged.

use glam::{DVec3, Vec3};

use crate::{Mesh, RasterError};

/// Highest icosphere level accepted: level 10 has 20,971,520 triangles (about 0.6 GB with
/// normals); level 11 would need 2.4 GB.
pub const MAX_ICOSPHERE_LEVEL: u32 = 10;

/// Most vertices a grid-based generator ([`torus`], [`plane`], [`cube`], [`open_box`]) builds.
const MAX_GRID_VERTICES: usize = 1 << 26;

/// The unit icosphere of the canonical benchmark scene, subdivided `level` times.
///
/// - Level 0: the regular icosahedron with golden-ratio vertices `(±1, ±φ, 0)`, `(0, ±1, ±φ)`,
///   `(±φ, 0, ±1)`, φ = (1+√5)/2, normalised to radius 1, in the order and with the 20 faces
///   listed in the source (the common "Kahler" order), each CCW seen from outside.
/// - Each level splits face (a, b, c) into (a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca),
///   where `xy` is the midpoint of edge x–y projected onto the unit sphere. The new vertices are
///   appended in ascending order of their edge key (min index, max index); the faces of level
///   L+1 are the 4 children of face 0, then of face 1, and so on.
/// - Counts: `20·4^L` triangles and `10·4^L + 2` vertices.
/// - Positions are computed in f64 and rounded once to f32; the vertex normals are the same
///   f32 unit vectors as the positions.
///
/// Level 8 (1,310,720 triangles) takes well under a second in a release build: edges are found
/// by a counting sort on their smaller index, with no hashing.
///
/// Errors: `level > MAX_ICOSPHERE_LEVEL`.
///
/// ```
/// let sphere = brdf_raster::procedural::icosphere(5)?;
/// assert_eq!((sphere.triangle_count(), sphere.vertex_count()), (20_480, 10_242));
/// assert!(sphere.signed_volume() > 0.0); // CCW seen from outside
/// # Ok::<(), brdf_raster::RasterError>(())
/// ```
pub fn icosphere(level: u32) -> Result<Mesh, RasterError> {
    if level > MAX_ICOSPHERE_LEVEL {
        return Err(RasterError::arg(
            "level",
            format!("icosphere level {level} is above the limit of {MAX_ICOSPHERE_LEVEL}"),
        ));
    }
    let phi = (1.0 + 5.0f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| DVec3::from_array(p).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        (positions, faces) = subdivide(&positions, &faces);
    }
    let positions: Vec<Vec3> = positions.into_iter().map(|p| p.as_vec3()).collect();
    let normals = positions.clone();
    Ok(Mesh { positions, normals, indices: faces, colors: None, uvs: None, tangents: None })
}

/// One 1→4 midpoint subdivision step with the canonical scene's vertex and face order (see [`icosphere`]).
fn subdivide(positions: &[DVec3], faces: &[[u32; 3]]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let nv = positions.len();
    // Counting sort of the undirected edges by their smaller endpoint: bucket `a` holds the larger
    // endpoints `b > a` of the edges (a, b). Sorting and de-duplicating each small bucket puts the
    // edges in ascending order of the key (a, b), which is the canonical scene's order for new vertices.
    let mut start = vec![0u32; nv + 1];
    for tri in faces {
        for k in 0..3 {
            start[tri[k].min(tri[(k + 1) % 3]) as usize + 1] += 1;
        }
    }
    for i in 0..nv {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut larger = vec![0u32; faces.len() * 3];
    for tri in faces {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let slot = &mut fill[a.min(b) as usize];
            larger[*slot as usize] = a.max(b);
            *slot += 1;
        }
    }
    // Compact each bucket to its sorted unique entries; `end[a]` marks the end of bucket a, and
    // the rank of an edge (its position in the compacted list) numbers its midpoint vertex.
    let mut end = vec![0u32; nv];
    let mut unique = 0u32;
    let mut compact_start = vec![0u32; nv];
    for a in 0..nv {
        let (lo, hi) = (start[a] as usize, start[a + 1] as usize);
        larger[lo..hi].sort_unstable();
        compact_start[a] = unique;
        let mut last = None;
        // Compacting in place is safe: `unique ≤ lo + i` since bucket a starts at `lo ≥ unique`.
        for i in lo..hi {
            let b = larger[i];
            if last != Some(b) {
                larger[unique as usize] = b;
                unique += 1;
                last = Some(b);
            }
        }
        end[a] = unique;
    }
    let mut new_positions = Vec::with_capacity(nv + unique as usize);
    new_positions.extend_from_slice(positions);
    for a in 0..nv {
        for &b in &larger[compact_start[a] as usize..end[a] as usize] {
            new_positions.push(((positions[a] + positions[b as usize]) * 0.5).normalize());
        }
    }
    let midpoint = |a: u32, b: u32| -> u32 {
        let (lo, hi) = (a.min(b), a.max(b));
        let range = compact_start[lo as usize] as usize..end[lo as usize] as usize;
        // Buckets hold about 3 entries: a linear scan beats a binary search.
        let rank = range.clone().find(|&i| larger[i] == hi).unwrap_or(range.start);
        nv as u32 + rank as u32
    };
    let mut new_faces = Vec::with_capacity(faces.len() * 4);
    for &[a, b, c] in faces {
        let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
        new_faces.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    (new_positions, new_faces)
}

/// Major radius of [`torus`].
pub const TORUS_MAJOR_RADIUS: f32 = 0.7;
/// Minor (tube) radius of [`torus`].
pub const TORUS_MINOR_RADIUS: f32 = 0.3;

/// The benchmark torus: major radius R = 0.7, minor radius r = 0.3, axis +z, centred at the
/// origin, with `major_segments` (M) around the axis and `minor_segments` (m) around the tube.
///
/// Vertex `i·m + j` (i < M, j < m) sits at `u = 2πi/M`, `v = 2πj/m`:
/// `p = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`, with the exact unit normal
/// `n = (cos v cos u, cos v sin u, sin v)`. Each grid cell (i, j) gives the triangles
/// `(p_ij, p_i+1,j, p_i+1,j+1)` and `(p_ij, p_i+1,j+1, p_i,j+1)` (indices wrap), which are
/// counter-clockwise seen from outside because `∂p/∂u × ∂p/∂v` points along `+n`.
/// Counts: `M·m` vertices, `2·M·m` triangles.
///
/// Errors: fewer than 3 segments either way, or more than 2^26 vertices.
pub fn torus(major_segments: u32, minor_segments: u32) -> Result<Mesh, RasterError> {
    if major_segments < 3 {
        return Err(RasterError::arg("major_segments", format!("must be at least 3, got {major_segments}")));
    }
    if minor_segments < 3 {
        return Err(RasterError::arg("minor_segments", format!("must be at least 3, got {minor_segments}")));
    }
    let (mm, m) = (major_segments as usize, minor_segments as usize);
    check_grid_size("major_segments × minor_segments", mm.checked_mul(m))?;
    let (big_r, small_r) = (f64::from(TORUS_MAJOR_RADIUS), f64::from(TORUS_MINOR_RADIUS));
    let mut positions = Vec::with_capacity(mm * m);
    let mut normals = Vec::with_capacity(mm * m);
    for i in 0..mm {
        let u = std::f64::consts::TAU * i as f64 / mm as f64;
        let (su, cu) = u.sin_cos();
        for j in 0..m {
            let v = std::f64::consts::TAU * j as f64 / m as f64;
            let (sv, cv) = v.sin_cos();
            let ring = big_r + small_r * cv;
            positions.push(DVec3::new(ring * cu, ring * su, small_r * sv).as_vec3());
            normals.push(DVec3::new(cv * cu, cv * su, sv).as_vec3());
        }
    }
    let mut indices = Vec::with_capacity(2 * mm * m);
    for i in 0..mm {
        let i1 = (i + 1) % mm;
        for j in 0..m {
            let j1 = (j + 1) % m;
            let at = |a: usize, b: usize| (a * m + b) as u32;
            let (p00, p10, p11, p01) = (at(i, j), at(i1, j), at(i1, j1), at(i, j1));
            indices.push([p00, p10, p11]);
            indices.push([p00, p11, p01]);
        }
    }
    Mesh::new(positions, indices, Some(normals))
}

/// A square in the plane y = 0, facing **+y** (a floor under objects in the +y-up world), centred at the
/// origin, `size` on a side, split into `subdivisions × subdivisions`
/// cells of two triangles. Vertex `j·(s+1) + i` sits at `x = −size/2 + i·size/s`,
/// `z = +size/2 − j·size/s`; all normals are +y; faces are CCW seen from above.
/// Rotate it with [`Mesh::transformed`] for another orientation.
///
/// Errors: `size` not finite and positive, `subdivisions` = 0, or more than 2^26 vertices.
pub fn plane(size: f32, subdivisions: u32) -> Result<Mesh, RasterError> {
    check_size(size)?;
    let mut builder = GridBuilder::default();
    let h = size / 2.0;
    builder.square(Vec3::new(-h, 0.0, h), Vec3::X * size, Vec3::NEG_Z * size, subdivisions)?;
    builder.build()
}

/// A closed axis-aligned cube centred at the origin, `size` on a side, each of its 6 faces split
/// into `subdivisions × subdivisions` cells. Faces do not share vertices, so every vertex normal
/// is its face's exact outward normal (flat shading at the edges); CCW seen from outside.
/// Face order: +x, −x, +y, −y, +z, −z.
///
/// Errors: as [`plane`].
pub fn cube(size: f32, subdivisions: u32) -> Result<Mesh, RasterError> {
    box_faces(size, subdivisions, true)
}

/// A box open at the top, for ambient-occlusion tests: the cube of [`cube`] without its +y face,
/// turned **inside out** (faces CCW seen from inside, normals pointing inward), so that with
/// back-face culling a camera looking in from above sees the floor and the four walls, and every
/// point inside is partly occluded by its neighbours. Face order: +x, −x, −y, +z, −z walls.
///
/// Errors: as [`plane`].
pub fn open_box(size: f32, subdivisions: u32) -> Result<Mesh, RasterError> {
    box_faces(size, subdivisions, false)
}

fn box_faces(size: f32, subdivisions: u32, closed_outward: bool) -> Result<Mesh, RasterError> {
    check_size(size)?;
    let h = size / 2.0;
    let mut builder = GridBuilder::default();
    // Each face: (outward normal, u axis, v axis) with u × v = outward normal.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    for (normal, u, v) in faces {
        if !closed_outward && normal == Vec3::Y {
            continue; // the open top
        }
        // Inward faces swap u and v, which reverses the winding and the normal.
        let (u, v) = if closed_outward { (u, v) } else { (v, u) };
        let corner = (normal - u - v) * h;
        builder.square(corner, u * size, v * size, subdivisions)?;
    }
    builder.build()
}

fn check_size(size: f32) -> Result<(), RasterError> {
    if !(size > 0.0) || !size.is_finite() {
        return Err(RasterError::arg("size", format!("must be finite and > 0, got {size}")));
    }
    Ok(())
}

fn check_grid_size(name: &'static str, vertices: Option<usize>) -> Result<(), RasterError> {
    match vertices {
        Some(n) if n <= MAX_GRID_VERTICES => Ok(()),
        _ => Err(RasterError::arg(name, format!("would need more than {MAX_GRID_VERTICES} vertices"))),
    }
}

/// Accumulates flat, subdivided parallelograms into one mesh.
#[derive(Default)]
struct GridBuilder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

impl GridBuilder {
    /// Add the parallelogram `origin + a·u + b·v`, a, b ∈ [0, 1], as `n × n` cells; it faces
    /// `u × v` (CCW seen from that side). Vertex `j·(n+1) + i` of the square is at a = i/n, b = j/n.
    fn square(&mut self, origin: Vec3, u: Vec3, v: Vec3, n: u32) -> Result<(), RasterError> {
        if n == 0 {
            return Err(RasterError::arg("subdivisions", "must be at least 1"));
        }
        let n = n as usize;
        let side = n.checked_add(1);
        let count = side.and_then(|s| s.checked_mul(s)).and_then(|c| c.checked_add(self.positions.len()));
        check_grid_size("subdivisions", count)?;
        let normal = u.cross(v).normalize();
        let base = self.positions.len();
        for j in 0..=n {
            for i in 0..=n {
                let (a, b) = (i as f32 / n as f32, j as f32 / n as f32);
                self.positions.push(origin + u * a + v * b);
                self.normals.push(normal);
            }
        }
        let at = |i: usize, j: usize| (base + j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                let (p00, p10, p11, p01) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                self.indices.push([p00, p10, p11]);
                self.indices.push([p00, p11, p01]);
            }
        }
        Ok(())
    }

    fn build(self) -> Result<Mesh, RasterError> {
        Mesh::new(self.positions, self.indices, Some(self.normals))
    }
}
