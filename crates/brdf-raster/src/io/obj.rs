//! Wavefront OBJ reading through `tobj`.
//!
//! What is read: `v x y z [w | r g b]` positions (and vertex colors), `vn` normals, `vt u v` texture
//! coordinates (kept as `(u, 1 − v)`: [`crate::Mesh::uvs`] has glTF's top-left origin), `f` faces with
//! `v`, `v/vt`, `v//vn` or `v/vt/vn` corners, 1-based or negative (relative) indices. Polygons are
//! split into a fan `(v₀, v_k, v_{k+1})`, exact for convex polygons. Faces with 1 or 2 corners
//! and `l` (line) and `p` (point) elements are ignored, as are groups, objects and smoothing groups.
//! [`super::load_mesh`] ignores materials (`mtllib` files are never opened);
//! [`super::obj_mtl::load_obj_scene`] reads them (`usemtl`, `mtllib`, through tobj's MTL parser).
//!
//! Vertex order: tobj welds each distinct (position, normal) pair into one vertex, numbered in
//! order of first use by a face, so vertices no face uses are dropped and a position used with
//! two different normals becomes two vertices. Face order is kept. File normals are used only
//! when every face corner has one; otherwise the normals are computed.
//!
//! Robustness: before tobj sees the text, every line is checked here (UTF-8, the face index
//! ranges, zero indices, relative indices reaching before the first vertex), which both gives
//! messages with line numbers and keeps tobj away from inputs on which its index arithmetic
//! could overflow.

use glam::{Vec2, Vec3};

use super::Loaded;
use crate::mesh::MAX_ELEMENTS;

/// Parse a whole OBJ file held in memory.
pub(super) fn parse(bytes: &[u8]) -> Result<Loaded, String> {
    let text = utf8(bytes)?;
    let (filtered, skipped) = filter_and_check(text, false)?;

    let mut reader = filtered.as_bytes();
    let (models, _materials) =
        tobj::load_obj_buf(&mut reader, &options(), |_| Err(tobj::LoadError::OpenFileFailed))
            .map_err(|e| format!("bad OBJ file: {e}"))?;
    // The filtered text has no `o`/`g`/`usemtl` lines, so tobj returns a single model; merging
    // several would still be correct.
    collect(&models.iter().collect::<Vec<_>>(), &skipped)
}

/// The text of an OBJ (or MTL) file, or why it is not UTF-8.
pub(super) fn utf8(bytes: &[u8]) -> Result<&str, String> {
    std::str::from_utf8(bytes).map_err(|e| {
        format!(
            "not a text (UTF-8) file: invalid byte at offset {} — is it really an OBJ file?",
            e.valid_up_to()
        )
    })
}

/// tobj's options: one index per corner, polygons triangulated, points and lines dropped.
pub(super) fn options() -> tobj::LoadOptions {
    // `..Default::default()` stays: the `merging`/`reordering` features (which another crate in a
    // build could enable) add fields to `LoadOptions`.
    #[allow(clippy::needless_update)]
    tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    }
}

/// tobj's models merged into one mesh's data (vertices renumbered), checked.
pub(super) fn collect(models: &[&tobj::Model], skipped: &Skipped) -> Result<Loaded, String> {
    let mut loaded = Loaded {
        faces_skipped: skipped.short_faces,
        polygons_triangulated: skipped.polygons,
        ..Default::default()
    };
    let mut normals: Vec<Vec3> = Vec::new();
    let mut colors: Vec<Vec3> = Vec::new();
    let mut uvs: Vec<Vec2> = Vec::new();
    let mut all_normals = true;
    let mut all_colors = true;
    let mut all_uvs = true;
    for model in models {
        let mesh = &model.mesh;
        let base = loaded.positions.len();
        let count = mesh.positions.len() / 3;
        if base + count > MAX_ELEMENTS {
            return Err(format!("more than {MAX_ELEMENTS} vertices"));
        }
        loaded.positions.extend(mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        all_normals &= mesh.normals.len() == mesh.positions.len();
        all_colors &= mesh.vertex_color.len() == mesh.positions.len();
        all_uvs &= mesh.texcoords.len() == count * 2;
        // OBJ's vt has its origin at the bottom left; Mesh::uvs (glTF's) at the top left.
        uvs.extend(mesh.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], 1.0 - c[1])));
        normals.extend(mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        colors.extend(mesh.vertex_color.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        for tri in mesh.indices.chunks_exact(3) {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= count) {
                return Err(format!("tobj produced index {bad} for {count} vertices"));
            }
            loaded.indices.push([0, 1, 2].map(|k| (base + tri[k] as usize) as u32));
        }
        if loaded.indices.len() > MAX_ELEMENTS {
            return Err(format!("more than {MAX_ELEMENTS} triangles"));
        }
    }
    if loaded.indices.is_empty() {
        return Err(format!(
            "has no faces: no 'f' line with 3 or more corners ({} skipped with fewer)",
            loaded.faces_skipped
        ));
    }
    if let Some(i) = loaded.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "vertex {i} (in order of first use) has a non-finite position {}",
            loaded.positions[i]
        ));
    }
    loaded.normals = (all_normals && !normals.is_empty()).then_some(normals);
    loaded.colors = (all_colors && !colors.is_empty()).then_some(colors);
    loaded.uvs = (all_uvs && !uvs.is_empty()).then_some(uvs);
    Ok(loaded)
}

/// What the line filter dropped.
#[derive(Default)]
pub(super) struct Skipped {
    pub(super) short_faces: usize,
    pub(super) polygons: usize,
}

/// Keep only `v`, `vt`, `vn` and `f` lines (and `mtllib`, `usemtl` with `materials`), checking every
/// face corner's indices; count the faces with fewer than 3 corners (dropped) and with more than 3
/// (fan-triangulated by tobj).
pub(super) fn filter_and_check(text: &str, materials: bool) -> Result<(String, Skipped), String> {
    // Totals first: a positive index may legally refer to any vertex of the file.
    let mut totals = [0i64; 3];
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => totals[0] += 1,
            Some("vt") => totals[1] += 1,
            Some("vn") => totals[2] += 1,
            _ => {}
        }
    }
    let kinds = ["vertex", "texture coordinate", "normal"];
    let plurals = ["vertices", "texture coordinates", "normals"];
    let mut seen = [0i64; 3];
    let mut out = String::with_capacity(text.len());
    let mut skipped = Skipped::default();
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => seen[0] += 1,
            Some("vt") => seen[1] += 1,
            Some("vn") => seen[2] += 1,
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                for corner in &corners {
                    let parts: Vec<&str> = corner.split('/').collect();
                    if parts.len() > 3 {
                        return Err(format!("line {number}: face corner '{corner}' has more than 3 parts"));
                    }
                    for (k, part) in parts.iter().enumerate() {
                        if part.is_empty() {
                            if k == 0 {
                                return Err(format!(
                                    "line {number}: face corner '{corner}' has no vertex index"
                                ));
                            }
                            continue;
                        }
                        let index: i64 = part.parse().map_err(|_| {
                            format!("line {number}: '{part}' in face corner '{corner}' is not an integer")
                        })?;
                        let valid =
                            if index > 0 { index <= totals[k] } else { index < 0 && -index <= seen[k] };
                        if !valid {
                            return Err(format!(
                                "line {number}: {} index {index} is out of range (the file has {}{})",
                                kinds[k],
                                count(totals[k], kinds[k], plurals[k]),
                                if index < 0 {
                                    format!(", {} before this line", seen[k])
                                } else {
                                    String::new()
                                }
                            ));
                        }
                    }
                }
                if corners.len() < 3 {
                    skipped.short_faces += 1;
                    continue;
                }
                if corners.len() > 3 {
                    skipped.polygons += 1;
                }
            }
            Some("mtllib" | "usemtl") if materials => {}
            _ => continue,
        }
        out.push_str(line);
        out.push('\n');
    }
    Ok((out, skipped))
}

/// `"1 vertex"`, `"3 vertices"`: a count with its noun in the right number.
fn count(n: i64, singular: &str, plural: &str) -> String {
    format!("{n} {}", if n == 1 { singular } else { plural })
}
