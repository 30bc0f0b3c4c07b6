//! Face and vertex normals (Theoharis et al. 2008, ch. 12): the corner cross product, Newell's method, the
//! average of corner normals, and vertex
//! normals weighted equally, by area or by angle (Theoharis et al. 2008 eqs. 12.31–12.33).
//!
//! Conventions: a polygon's vertices are listed counter-clockwise seen from the front, so every
//! face normal here points toward the viewer of a CCW polygon (right-hand rule). Functions that
//! return a *vector* (`triangle_normal`, `corner_normal`, `newell_normal`) do not normalise it:
//! its length carries the area (twice the area for triangles and planar polygons), which is the
//! weight of eq. 12.32. Degenerate input gives the zero vector, never NaN.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// How face normals are weighted when averaged into a vertex normal (Theoharis et al. 2008, ch. 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Weighting {
    /// Every incident face counts once: `n̂ = Σ f̂_i / |Σ f̂_i|` (eq. 12.31, Gouraud 1971).
    Equal,
    /// Faces weighted by their area: `n̂ = Σ f⃗_i / |Σ f⃗_i|` with `|f⃗_i| = 2·area` (eq. 12.32).
    Area,
    /// Faces weighted by the corner angle θ_i at the vertex: `n̂ = Σ θ_i f̂_i / |Σ θ_i f̂_i|`
    /// (eq. 12.33; Thürmer & Wüthrich 1998). Invariant to how a flat region is triangulated,
    /// hence the default of [`crate::Mesh::new`].
    Angle,
}

/// Triangle normal by the cross product of two edges: `(b − a) × (c − a)`, not normalised.
///
/// Its length is twice the triangle's area; it points to the side from which `a, b, c` are seen
/// counter-clockwise. Zero for a degenerate (collinear or repeated-vertex) triangle.
#[inline]
pub fn triangle_normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    (b - a).cross(c - a)
}

/// The normal at polygon corner `v` with neighbours `prev` and `next` (Theoharis et al. 2008, ch. 12): `n⃗ =
/// (v_{i+1} − v_i) × (v_{i−1} − v_i)`, not normalised.
///
/// For a CCW polygon this is the outward normal; its length is `|e₁|·|e₂|·sin θ` for the corner
/// angle θ.
#[inline]
pub fn corner_normal(prev: Vec3, v: Vec3, next: Vec3) -> Vec3 {
    (next - v).cross(prev - v)
}

/// Polygon normal by Martin Newell's method (Theoharis et al. 2008, ch. 12), not normalised:
///
/// `a = Σ (y_i − y_{i⊕1})(z_i + z_{i⊕1})`, `b = Σ (z_i − z_{i⊕1})(x_i + x_{i⊕1})`,
/// `c = Σ (x_i − x_{i⊕1})(y_i + y_{i⊕1})`, ⊕ = addition modulo n.
///
/// `(a, b, c)` is twice the vector area of the polygon: for a planar polygon its length is twice
/// the area, and for a triangle it equals [`triangle_normal`]. It is robust to slight
/// non-planarity and to collinear consecutive vertices, unlike a single corner's cross product.
/// The sums are translation-invariant (the `(y_i − y_{i⊕1})` terms telescope), so they are taken
/// relative to the first vertex and in f64, which keeps precision for polygons far from the
/// origin. Fewer than 3 vertices give zero.
pub fn newell_normal(polygon: &[Vec3]) -> Vec3 {
    if polygon.len() < 3 {
        return Vec3::ZERO;
    }
    let origin = polygon[0].as_dvec3();
    let mut n = DVec3::ZERO;
    let count = polygon.len();
    for i in 0..count {
        let p = polygon[i].as_dvec3() - origin;
        let q = polygon[(i + 1) % count].as_dvec3() - origin;
        n.x += (p.y - q.y) * (p.z + q.z);
        n.y += (p.z - q.z) * (p.x + q.x);
        n.z += (p.x - q.x) * (p.y + q.y);
    }
    n.as_vec3()
}

/// Unit polygon normal as the average of the unit corner normals (Theoharis et al. 2008, ch. 12,
/// method 1): `n̂ = normalize(Σ_i normalize(corner_normal(v_{i−1}, v_i, v_{i+1})))`.
///
/// Normalising each corner normal first gives every corner equal weight. Degenerate corners
/// (collinear edges) contribute nothing; a fully degenerate polygon gives zero.
///
/// A course text's worked example (after Theoharis et al. 2008) (the quad (0,0,0), (1,0,0), (1,1,0),
/// (0,1,0.5)) prints the corner
/// normal at v₄ as (0.25, −0.5, 1); the cross product (0,−1,−0.5) × (1,0,−0.5) is (0.5, −0.5, 1),
/// so the seed's average is off. The correct average, ≈ (0.225, −0.225, 0.948), has n_x = −n_y
/// as the quad's mirror symmetry demands (tests/mesh.rs checks this).
///
/// ```
/// use brdf_raster::normals::{corner_average_normal, newell_normal};
/// use glam::Vec3;
/// let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.5)];
/// assert_eq!(newell_normal(&quad), Vec3::new(0.5, -0.5, 2.0));
/// let n = corner_average_normal(&quad);
/// assert!((n.x + n.y).abs() < 1e-6 && n.dot(newell_normal(&quad).normalize()) > 0.999);
/// ```
pub fn corner_average_normal(polygon: &[Vec3]) -> Vec3 {
    let count = polygon.len();
    if count < 3 {
        return Vec3::ZERO;
    }
    // The result is a unit vector, so the corners are computed on the polygon scaled by a power of two
    // (exact) to unit extent: the cross products of coordinates beyond ~1e19 would overflow, those of
    // coordinates below ~1e-19 underflow to zero.
    let extent = polygon.iter().map(|p| p.abs().max_element()).fold(0.0, f32::max);
    if !(extent > 0.0 && extent.is_finite()) {
        return Vec3::ZERO;
    }
    let scale = 2f32.powi(-(extent.log2().floor() as i32).clamp(-126, 126));
    let mut sum = Vec3::ZERO;
    for i in 0..count {
        let prev = polygon[(i + count - 1) % count] * scale;
        let next = polygon[(i + 1) % count] * scale;
        sum += corner_normal(prev, polygon[i] * scale, next).normalize_or_zero();
    }
    sum.normalize_or_zero()
}

/// Interior angle (radians, in [0, π]) at corner `v` between the edges toward `prev` and `next`:
/// `θ = acos(ê₁·ê₂)` (Theoharis et al. 2008, ch. 12). Zero for a zero-length edge.
///
/// Computed as `atan2(|e₁×e₂|, e₁·e₂)`, which equals the seed's arccos but stays accurate for
/// angles near 0 and π where acos loses half its digits.
#[inline]
pub fn corner_angle(prev: Vec3, v: Vec3, next: Vec3) -> f32 {
    let e1 = next - v;
    let e2 = prev - v;
    if e1.length_squared() == 0.0 || e2.length_squared() == 0.0 {
        return 0.0;
    }
    e1.cross(e2).length().atan2(e1.dot(e2))
}

/// Weighted contribution of one face to one of its vertices: `f̂`, `f⃗` (twice the area) or `θ·f̂`.
#[inline]
fn contribution(face: Vec3, angle: impl FnOnce() -> f32, weighting: Weighting) -> Vec3 {
    match weighting {
        Weighting::Equal => face.normalize_or_zero(),
        Weighting::Area => face,
        Weighting::Angle => face.normalize_or_zero() * angle(),
    }
}

/// Unit vertex normals of an indexed triangle mesh by the given weighting (Theoharis et al. 2008 eqs.
/// 12.31–12.33); face normals by [`triangle_normal`]. A vertex no face uses, or whose
/// contributions cancel, gets the zero vector. Indices must be in range (a [`crate::Mesh`]
/// guarantees it).
///
/// The corner angles use `θ = atan2(|f⃗|, e₁·e₂)`, as [`corner_angle`] does, sharing the face's
/// `|f⃗| = |e₁×e₂|` between its three corners. Face contributions are computed in parallel in
/// chunks and summed into the vertices in face order on one thread, so the result is the same
/// bits at any thread count.
pub fn vertex_normals(positions: &[Vec3], indices: &[[u32; 3]], weighting: Weighting) -> Vec<Vec3> {
    const CHUNK: usize = 1 << 16;
    let mut acc = vec![Vec3::ZERO; positions.len()];
    let mut contributions: Vec<[Vec3; 3]> = Vec::with_capacity(CHUNK.min(indices.len()));
    for chunk in indices.chunks(CHUNK) {
        chunk
            .par_iter()
            .with_min_len(4096)
            .map(|tri| face_contributions(tri.map(|i| positions[i as usize]), weighting))
            .collect_into_vec(&mut contributions);
        for (tri, c) in chunk.iter().zip(&contributions) {
            for k in 0..3 {
                acc[tri[k] as usize] += c[k];
            }
        }
    }
    acc.into_iter().map(Vec3::normalize_or_zero).collect()
}

/// What face `p` adds to each of its three corners' vertex normals.
#[inline]
fn face_contributions(p: [Vec3; 3], weighting: Weighting) -> [Vec3; 3] {
    let face = triangle_normal(p[0], p[1], p[2]);
    let length = face.length();
    if length == 0.0 || !length.is_finite() {
        return [Vec3::ZERO; 3];
    }
    let unit = face / length;
    match weighting {
        Weighting::Equal => [unit; 3],
        Weighting::Area => [face; 3],
        Weighting::Angle => {
            let (a, b, c) = (p[1] - p[0], p[2] - p[1], p[0] - p[2]);
            // Corner k's edges point to the other two corners; their cross product has length |f⃗|.
            let dots = [-a.dot(c), -a.dot(b), -b.dot(c)];
            dots.map(|d| unit * length.atan2(d))
        }
    }
}

/// Unit vertex normals of a mesh of arbitrary polygons (Theoharis et al. 2008 eqs. 12.31–12.33), each face
/// normal by [`newell_normal`] (twice the area for a planar polygon, so `Area` weighting agrees
/// with [`vertex_normals`] on triangles), each angle the polygon's interior angle at the vertex.
/// Faces with fewer than 3 vertices and indices out of range are skipped.
pub fn polygon_vertex_normals(positions: &[Vec3], faces: &[Vec<u32>], weighting: Weighting) -> Vec<Vec3> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    let mut corners: Vec<Vec3> = Vec::new();
    for face in faces {
        if face.len() < 3 || face.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        corners.clear();
        corners.extend(face.iter().map(|&i| positions[i as usize]));
        let normal = newell_normal(&corners);
        if normal == Vec3::ZERO {
            continue;
        }
        let count = corners.len();
        for k in 0..count {
            let (prev, next) = (corners[(k + count - 1) % count], corners[(k + 1) % count]);
            acc[face[k] as usize] += contribution(normal, || corner_angle(prev, corners[k], next), weighting);
        }
    }
    acc.into_iter().map(Vec3::normalize_or_zero).collect()
}

/// Unit face normals of an indexed triangle mesh (zero for degenerate faces).
pub fn face_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    indices
        .iter()
        .map(|tri| {
            let p = tri.map(|i| positions[i as usize]);
            triangle_normal(p[0], p[1], p[2]).normalize_or_zero()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_angle_of_a_right_angle_is_half_pi() {
        let a = corner_angle(Vec3::Y, Vec3::ZERO, Vec3::X);
        assert!((a - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn degenerate_polygons_give_zero_not_nan() {
        assert_eq!(newell_normal(&[Vec3::ZERO, Vec3::X]), Vec3::ZERO);
        assert_eq!(corner_average_normal(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]), Vec3::ZERO);
        assert_eq!(corner_angle(Vec3::ZERO, Vec3::ZERO, Vec3::X), 0.0);
    }
}
