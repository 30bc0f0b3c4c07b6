//! Triangle meshes: positions, per-vertex normals, indices, optional per-vertex colors, validated once.

use glam::Vec3;

use crate::RasterError;

/// Largest vertex or triangle count accepted (keeps every index in `u32` and memory bounded).
pub const MAX_ELEMENTS: usize = 1 << 28;

/// An indexed triangle mesh. Faces are counter-clockwise seen from the front (outside).
///
/// Invariants (checked by [`Mesh::new`]): at least one vertex and one face, every index < vertex
/// count, every position (and normal, color) finite, `normals.len() == positions.len()`.
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
}

impl Mesh {
    /// Validate and build; vertex normals are computed with angle weighting when `normals` is `None`
    /// (see [`crate::normals`]).
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
                n.into_iter().map(|v| v.normalize_or_zero()).collect()
            }
            None => crate::normals::vertex_normals(&positions, &indices, crate::normals::Weighting::Angle),
        };
        Ok(Self { positions, normals, indices, colors: None })
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
}
