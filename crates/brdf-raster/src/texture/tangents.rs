//! Per-vertex tangents for normal maps by MikkTSpace (M. S. Mikkelsen, "Simulation of Wrinkled
//! Surfaces Revisited", MSc thesis, University of Copenhagen, 2008), the algorithm glTF 2.0 (§3.7.2.1)
//! prescribes when a mesh has a normal map but no TANGENT attribute, so that normal maps baked by other
//! tools read back as they were baked.
//!
//! The `bevy_mikktspace` crate does the work: a safe Rust port of the reference implementation
//! (byte-identical results on x86), maintained with the Bevy engine; `mikktspace` (gltf-rs) is the
//! older port, with `unsafe` code and no release since 2021.

use glam::{Vec3, Vec4};

use crate::{Mesh, RasterError};

struct Geometry<'a> {
    mesh: &'a Mesh,
    uvs: &'a [glam::Vec2],
    /// Sum of the corner tangents of each vertex, and the handedness of its first corner.
    sum: Vec<Vec3>,
    sign: Vec<f32>,
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.indices[face][vert] as usize].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.indices[face][vert] as usize].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        // MikkTSpace works with v up (OpenGL's texture space); glTF's v grows downward. Flipping v makes
        // the bitangent w·(n × t) point up the image, glTF's +y of a normal texel.
        let uv = self.uvs[self.mesh.indices[face][vert] as usize];
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent(&mut self, ts: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        let Some(ts) = ts else { return };
        let i = self.mesh.indices[face][vert] as usize;
        let [x, y, z, w] = ts.tangent_encoded();
        self.sum[i] += Vec3::new(x, y, z);
        if self.sign[i] == 0.0 {
            self.sign[i] = w;
        }
    }
}

/// MikkTSpace tangents `(t, w)` of every vertex of `mesh` from its positions, normals and texture
/// coordinates (glTF's TANGENT: `t` along increasing `u`, bitangent `w·(n × t)` up the image). A vertex
/// shared by faces (an indexed mesh; MikkTSpace works per face corner) gets the normalised sum of its
/// corners' tangents; a vertex of no face, or whose tangents cancel, gets `(0, 0, 0, 1)` (no frame:
/// the normal map leaves its normal as it is).
///
/// Errors: the mesh has no texture coordinates.
pub fn mikktspace_tangents(mesh: &Mesh) -> Result<Vec<Vec4>, RasterError> {
    let uvs = mesh.uvs.as_deref().ok_or_else(|| {
        RasterError::InvalidMesh("has no texture coordinates (uvs): tangents follow them".into())
    })?;
    let n = mesh.positions.len();
    let mut g = Geometry { mesh, uvs, sum: vec![Vec3::ZERO; n], sign: vec![0.0; n] };
    // The crate's error type has no variants: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut g);
    Ok(g.sum
        .iter()
        .zip(&g.sign)
        .map(|(t, &w)| t.normalize_or_zero().extend(if w == 0.0 { 1.0 } else { w }))
        .collect())
}

impl Mesh {
    /// The mesh with MikkTSpace tangents ([`mikktspace_tangents`]) unless it has tangents already.
    pub fn with_generated_tangents(self) -> Result<Self, RasterError> {
        if self.tangents.is_some() {
            return Ok(self);
        }
        let t = mikktspace_tangents(&self)?;
        self.with_tangents(t)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;

    #[test]
    fn a_plane_mapped_u_along_x_and_v_down_minus_y_gets_tangent_x_and_bitangent_up() {
        // The quad z = 0 facing +z: u grows with x, v (down the image) grows toward −y.
        let p = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let uv = vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)];
        let mesh = Mesh::new(p, vec![[0, 1, 2], [0, 2, 3]], None).unwrap().with_uvs(uv).unwrap();
        let t = mikktspace_tangents(&mesh).unwrap();
        for t in t {
            assert!((t.truncate() - Vec3::X).length() < 1e-5, "{t}");
            // b = w (n × t) = w (z × x) = w·y: up the image is +y here.
            assert_eq!(t.w, 1.0, "{t}");
        }
        let e = mikktspace_tangents(
            &Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]], None).unwrap(),
        );
        assert!(e.unwrap_err().to_string().contains("no texture coordinates"));
    }
}
