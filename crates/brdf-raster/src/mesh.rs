//! Triangle meshes: positions, per-vertex normals, indices, optional per-vertex colors, validated
//! once; transforms, bounds, face normals, vertex normals by the three weightings of Theoharis et al. 2008,
//! winding checks (signed volume) and a report of degenerate faces and topology.

use glam::{DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::RasterError;
use crate::normals::{self, Weighting};

/// Largest vertex or triangle count accepted (keeps every index in `u32` and memory bounded).
pub const MAX_ELEMENTS: usize = 1 << 28;

/// An indexed triangle mesh. Faces are counter-clockwise seen from the front (outside).
///
/// Invariants (checked by [`Mesh::new`]): at least one vertex and one face, every index < vertex
/// count, every position (and normal, color) finite, `normals.len() == positions.len()`.
/// Degenerate (zero-area) triangles are allowed: [`Mesh::degenerate_faces`] lists them and the
/// renderer skips them.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions (object space).
    pub positions: Vec<Vec3>,
    /// Unit vertex normals (computed when not given).
    pub normals: Vec<Vec3>,
    /// Triangles as vertex-index triples, CCW from the front.
    pub indices: Vec<[u32; 3]>,
    /// Optional per-vertex linear RGB colors that multiply the material's diffuse term.
    pub colors: Option<Vec<Vec3>>,
    /// Optional per-vertex texture coordinates `(u, v)`, glTF's convention: `(0, 0)` is the first
    /// (top-left) texel of the image, `v` grows downward.
    pub uvs: Option<Vec<Vec2>>,
    /// Optional per-vertex tangents `(t, w)`: `t` a unit vector perpendicular to the normal along
    /// increasing `u`, `w = ±1` the handedness, bitangent `b = w·(n × t)` (glTF's TANGENT).
    pub tangents: Option<Vec<Vec4>>,
}

/// An axis-aligned bounding box (`min ≤ max` component-wise for a non-empty set of points).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Smallest coordinates.
    pub min: Vec3,
    /// Largest coordinates.
    pub max: Vec3,
}

impl Aabb {
    /// The box around `points`; `None` when there are none.
    pub fn from_points(points: &[Vec3]) -> Option<Self> {
        let first = *points.first()?;
        let (min, max) = points.iter().fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        Some(Self { min, max })
    }

    /// Centre `(min + max) / 2`.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths `max − min`.
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// Length of the diagonal `|max − min|`.
    pub fn diagonal(&self) -> f32 {
        self.size().length()
    }
}

/// Geometry and topology of a mesh, as [`Mesh::stats`] measures them (the same quantities as the
/// assets' `meshes.json`).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshStats {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of triangles.
    pub triangles: usize,
    /// Triangles of zero area (see [`Mesh::degenerate_faces`]).
    pub degenerate_triangles: usize,
    /// Vertices that no triangle uses.
    pub unreferenced_vertices: usize,
    /// Undirected edges used by exactly one triangle (holes, open borders).
    pub boundary_edges: usize,
    /// Undirected edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges shared by two triangles that traverse it in the same direction (orientation flips).
    pub inconsistent_edges: usize,
    /// Edge-connected parts: triangles sharing a manifold edge (an edge of exactly two
    /// triangles) belong to the same part; a non-manifold edge does not join parts. This is
    /// trimesh's definition, the one `meshes.json` of the test assets uses.
    pub components: usize,
    /// Closed two-manifold: no boundary and no non-manifold edge.
    pub watertight: bool,
    /// Every edge shared by two triangles is traversed in opposite directions.
    pub winding_consistent: bool,
    /// Signed volume `Σ p₀·(p₁×p₂)/6` (f64); > 0 for a closed mesh wound CCW seen from outside.
    pub signed_volume: f64,
    /// Surface area `Σ |(p₁−p₀)×(p₂−p₀)|/2` (f64).
    pub area: f64,
    /// Bounding box of the positions.
    pub bounds: Aabb,
}

impl Mesh {
    /// Validate and build; vertex normals are computed with angle weighting when `normals` is `None`
    /// (see [`crate::normals`]).
    ///
    /// Given normals are normalised; a given normal of zero length (such as `vn 0 0 0` in an OBJ
    /// file) is replaced by the angle-weighted normal of its vertex, so that no shading normal is
    /// zero where the geometry defines one.
    pub fn new(
        positions: Vec<Vec3>,
        indices: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
    ) -> Result<Self, RasterError> {
        if positions.is_empty() {
            return Err(RasterError::InvalidMesh("has no vertices".into()));
        }
        if indices.is_empty() {
            return Err(RasterError::InvalidMesh("has no faces".into()));
        }
        if positions.len() > MAX_ELEMENTS || indices.len() > MAX_ELEMENTS {
            return Err(RasterError::InvalidMesh(format!(
                "{} vertices and {} faces exceed the limit of {MAX_ELEMENTS}",
                positions.len(),
                indices.len()
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(RasterError::InvalidMesh(format!(
                "vertex {i} has a non-finite position {}",
                positions[i]
            )));
        }
        let nv = positions.len();
        for (f, tri) in indices.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= nv) {
                return Err(RasterError::InvalidMesh(format!(
                    "face {f} indexes vertex {i}, but there are only {nv} vertices"
                )));
            }
        }
        let normals = match normals {
            Some(n) => {
                if n.len() != nv {
                    return Err(RasterError::InvalidMesh(format!("{} normals for {nv} vertices", n.len())));
                }
                if let Some(i) = n.iter().position(|v| !v.is_finite()) {
                    return Err(RasterError::InvalidMesh(format!("normal {i} is not finite")));
                }
                let mut n: Vec<Vec3> = n.into_iter().map(|v| v.normalize_or_zero()).collect();
                if n.contains(&Vec3::ZERO) {
                    let computed = normals::vertex_normals(&positions, &indices, Weighting::Angle);
                    for (given, computed) in n.iter_mut().zip(computed) {
                        if *given == Vec3::ZERO {
                            *given = computed;
                        }
                    }
                }
                n
            }
            None => normals::vertex_normals(&positions, &indices, Weighting::Angle),
        };
        Ok(Self { positions, normals, indices, colors: None, uvs: None, tangents: None })
    }

    /// Attach per-vertex texture coordinates (one per vertex, finite).
    pub fn with_uvs(mut self, uvs: Vec<Vec2>) -> Result<Self, RasterError> {
        if uvs.len() != self.positions.len() {
            return Err(RasterError::InvalidMesh(format!(
                "{} texture coordinates for {} vertices",
                uvs.len(),
                self.positions.len()
            )));
        }
        if let Some(i) = uvs.iter().position(|c| !c.is_finite()) {
            return Err(RasterError::InvalidMesh(format!("texture coordinate {i} is not finite")));
        }
        self.uvs = Some(uvs);
        Ok(self)
    }

    /// Attach per-vertex tangents `(t, w)` (one per vertex, finite, `w = ±1`; `t` is normalised, and a
    /// zero `t` is kept as zero: no frame there).
    pub fn with_tangents(mut self, tangents: Vec<Vec4>) -> Result<Self, RasterError> {
        if tangents.len() != self.positions.len() {
            return Err(RasterError::InvalidMesh(format!(
                "{} tangents for {} vertices",
                tangents.len(),
                self.positions.len()
            )));
        }
        if let Some(i) = tangents.iter().position(|t| !t.is_finite() || t.w.abs() != 1.0) {
            return Err(RasterError::InvalidMesh(format!(
                "tangent {i} {} is not finite or its w is not ±1",
                tangents[i]
            )));
        }
        let tangents = tangents.into_iter().map(|t| t.truncate().normalize_or_zero().extend(t.w)).collect();
        self.tangents = Some(tangents);
        Ok(self)
    }

    /// Attach per-vertex colors (one per vertex, finite).
    pub fn with_colors(mut self, colors: Vec<Vec3>) -> Result<Self, RasterError> {
        if colors.len() != self.positions.len() {
            return Err(RasterError::InvalidMesh(format!(
                "{} colors for {} vertices",
                colors.len(),
                self.positions.len()
            )));
        }
        if let Some(i) = colors.iter().position(|c| !c.is_finite()) {
            return Err(RasterError::InvalidMesh(format!("color {i} is not finite")));
        }
        self.colors = Some(colors);
        Ok(self)
    }

    /// The three corner positions of face `f`.
    #[inline]
    pub fn triangle(&self, f: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[f];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    /// Number of vertices.
    #[inline]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    #[inline]
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Axis-aligned bounding box of all positions (unused vertices included).
    pub fn bounds(&self) -> Aabb {
        // A valid mesh has at least one vertex; the fallback only serves a hand-emptied struct.
        Aabb::from_points(&self.positions).unwrap_or(Aabb { min: Vec3::ZERO, max: Vec3::ZERO })
    }

    /// A sphere enclosing the mesh: centre = bounding-box centre, radius = largest distance from
    /// it to a vertex. (Not the minimal sphere; good enough to frame a camera.)
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let center = self.bounds().center();
        let radius = self.positions.iter().map(|p| p.distance(center)).fold(0.0f32, f32::max);
        (center, radius)
    }

    /// The similarity transform (translate, then uniform scale) that moves the bounding sphere of
    /// [`Mesh::bounding_sphere`] to the unit sphere at the origin; identity scale for a mesh that
    /// is a single point. Use it to frame a user's mesh like the canonical scene's icosphere.
    pub fn unit_sphere_transform(&self) -> Mat4 {
        let (center, radius) = self.bounding_sphere();
        let scale = if radius > 0.0 && radius.is_finite() { 1.0 / radius } else { 1.0 };
        Mat4::from_scale(Vec3::splat(scale)) * Mat4::from_translation(-center)
    }

    /// Unit normal of face `f` by the cross product `(p₁−p₀)×(p₂−p₀)` (Theoharis et al. 2008, ch. 12); zero
    /// when the
    /// face is degenerate.
    #[inline]
    pub fn face_normal(&self, f: usize) -> Vec3 {
        let [a, b, c] = self.triangle(f);
        normals::triangle_normal(a, b, c).normalize_or_zero()
    }

    /// Unit normals of all faces (zero for degenerate faces).
    pub fn face_normals(&self) -> Vec<Vec3> {
        normals::face_normals(&self.positions, &self.indices)
    }

    /// Recompute the vertex normals from the faces by `weighting` (Theoharis et al. 2008 eqs. 12.31–12.33),
    /// replacing any normals given or loaded.
    pub fn compute_normals(&mut self, weighting: Weighting) {
        self.normals = normals::vertex_normals(&self.positions, &self.indices, weighting);
    }

    /// Reverse the orientation: swap the last two indices of every face (CW ↔ CCW) and negate the
    /// vertex normals. Use it for meshes wound inward (negative [`Mesh::signed_volume`]), such as
    /// the Cyberware horse of the test assets, which back-face culling would otherwise render
    /// inside out.
    pub fn flip_winding(&mut self) {
        for tri in &mut self.indices {
            tri.swap(1, 2);
        }
        for n in &mut self.normals {
            *n = -*n;
        }
        // The normal turned, the bitangent w·(n × t) stays where the texture has it.
        for t in self.tangents.iter_mut().flatten() {
            t.w = -t.w;
        }
    }

    /// Signed volume `V = Σ_f p₀·(p₁×p₂) / 6` (divergence theorem), accumulated in f64.
    ///
    /// For a closed mesh wound counter-clockwise seen from outside, `V > 0` and equals the
    /// enclosed volume; `V < 0` means the faces are wound inward. For an open mesh the value
    /// depends on the origin and only its sign relative to a known shape is meaningful.
    pub fn signed_volume(&self) -> f64 {
        self.indices
            .iter()
            .map(|&[a, b, c]| {
                let [p0, p1, p2] = [a, b, c].map(|i| self.positions[i as usize].as_dvec3());
                p0.dot(p1.cross(p2))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Surface area `Σ_f |(p₁−p₀)×(p₂−p₀)| / 2`, accumulated in f64.
    pub fn area(&self) -> f64 {
        self.indices.iter().map(|&tri| double_area(&self.positions, tri)).sum::<f64>() / 2.0
    }

    /// Indices of the degenerate faces: those that repeat a vertex index or whose corners are
    /// collinear or coincident, i.e. `(p₁−p₀)×(p₂−p₀) = 0` exactly when evaluated in f64 from the
    /// f32 positions. The rasterizer skips them (they cover no pixel); face normal = zero.
    pub fn degenerate_faces(&self) -> Vec<usize> {
        self.indices
            .iter()
            .enumerate()
            .filter(|&(_, &tri)| is_degenerate(&self.positions, tri))
            .map(|(f, _)| f)
            .collect()
    }

    /// A copy transformed by the affine model matrix `m` (column vectors, `p' = M·[p, 1]`).
    ///
    /// Normals go through the normal matrix `(M₃ₓ₃⁻¹)ᵀ` and are re-normalised, so they stay
    /// perpendicular to the surface under non-uniform scale. When `det M₃ₓ₃ < 0` (a mirror) the
    /// winding of every face is reversed too, so faces stay counter-clockwise seen from the side
    /// the normals point to (a GPU would need `glFrontFace(GL_CW)` instead). Colors and texture
    /// coordinates are kept; tangents go through `M₃ₓ₃`, their handedness flipped by a mirror.
    ///
    /// Errors: `m` is not finite, not affine (last row ≠ 0 0 0 1 within 10⁻⁶; within it the last
    /// row is ignored), singular, or maps a vertex to a non-finite position.
    pub fn transformed(&self, m: &Mat4) -> Result<Mesh, RasterError> {
        if !m.is_finite() {
            return Err(RasterError::arg("transform", "has a non-finite entry"));
        }
        // Same tolerance as glam's own affine assertion in `transform_point3`.
        if !m.row(3).abs_diff_eq(Vec4::W, 1e-6) {
            return Err(RasterError::arg(
                "transform",
                format!("must be affine (last row 0 0 0 1), got {}", m.row(3)),
            ));
        }
        let linear = Mat3::from_mat4(*m);
        let det = linear.determinant();
        if det == 0.0 || !det.is_finite() {
            return Err(RasterError::arg("transform", "is singular (its 3×3 part has determinant 0)"));
        }
        let normal_matrix = linear.inverse().transpose();
        let positions: Vec<Vec3> = self.positions.iter().map(|&p| m.transform_point3(p)).collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(RasterError::arg("transform", format!("maps vertex {i} to a non-finite position")));
        }
        let normals = self.normals.iter().map(|&n| (normal_matrix * n).normalize_or_zero()).collect();
        let mut indices = self.indices.clone();
        if det < 0.0 {
            for tri in &mut indices {
                tri.swap(1, 2);
            }
        }
        // Tangents are directions in the surface: they go through M itself; a mirror swaps the
        // handedness of the (t, b, n) frame.
        let handedness = if det < 0.0 { -1.0 } else { 1.0 };
        let tangents = self.tangents.as_ref().map(|ts| {
            ts.iter().map(|t| (linear * t.truncate()).normalize_or_zero().extend(t.w * handedness)).collect()
        });
        Ok(Mesh { positions, normals, indices, colors: self.colors.clone(), uvs: self.uvs.clone(), tangents })
    }

    /// Measure the mesh: counts, degenerate faces, unreferenced vertices, boundary and
    /// non-manifold edges, winding consistency, edge-connected components, signed volume, area
    /// and bounds. Runs in O(F log F) (one sort of the 3F half-edges); deterministic.
    pub fn stats(&self) -> MeshStats {
        let mut referenced = vec![false; self.positions.len()];
        for tri in &self.indices {
            for &i in tri {
                referenced[i as usize] = true;
            }
        }
        // Half-edges as (undirected key, face, forward?) sorted by key: each run of one key is
        // one undirected edge with the faces that use it.
        let mut half_edges: Vec<(u64, u32, bool)> = Vec::with_capacity(self.indices.len() * 3);
        for (f, tri) in self.indices.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if a != b {
                    let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                    half_edges.push((key, f as u32, a < b));
                }
            }
        }
        half_edges.sort_unstable();
        let mut parent: Vec<u32> = (0..self.indices.len() as u32).collect();
        let (mut boundary, mut non_manifold, mut inconsistent) = (0, 0, 0);
        for run in half_edges.chunk_by(|x, y| x.0 == y.0) {
            match run.len() {
                1 => boundary += 1,
                2 => {
                    if run[0].2 == run[1].2 {
                        inconsistent += 1;
                    }
                }
                _ => non_manifold += 1,
            }
            // Only manifold edges connect parts (as in trimesh, and so in `meshes.json`): scans
            // glued at a non-manifold edge count as separate parts.
            if let [x, y] = run {
                union(&mut parent, x.1, y.1);
            }
        }
        let components = (0..parent.len() as u32).filter(|&f| find(&mut parent, f) == f).count();
        MeshStats {
            vertices: self.positions.len(),
            triangles: self.indices.len(),
            degenerate_triangles: self.degenerate_faces().len(),
            unreferenced_vertices: referenced.iter().filter(|&&r| !r).count(),
            boundary_edges: boundary,
            non_manifold_edges: non_manifold,
            inconsistent_edges: inconsistent,
            components,
            watertight: boundary == 0 && non_manifold == 0,
            winding_consistent: inconsistent == 0,
            signed_volume: self.signed_volume(),
            area: self.area(),
            bounds: self.bounds(),
        }
    }
}

/// `|(p₁−p₀)×(p₂−p₀)|` in f64 (twice the triangle's area).
fn double_area(positions: &[Vec3], [a, b, c]: [u32; 3]) -> f64 {
    let [p0, p1, p2]: [DVec3; 3] = [a, b, c].map(|i| positions[i as usize].as_dvec3());
    (p1 - p0).cross(p2 - p0).length()
}

fn is_degenerate(positions: &[Vec3], tri: [u32; 3]) -> bool {
    tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || double_area(positions, tri) == 0.0
}

/// Union-find root with path halving.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grand = parent[parent[x as usize] as usize];
        parent[x as usize] = grand;
        x = grand;
    }
    x
}

/// Join the sets of `a` and `b` (the smaller root becomes the parent: deterministic).
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi as usize] = lo;
    }
}
