//! STL reading, binary and ASCII (the 3D Systems StereoLithography Interface Specification, 1989).
//!
//! Binary: an 80-byte header, a little-endian `u32` triangle count `N`, then `N` records of 50 bytes
//! (facet normal, three vertices, each three `f32`, and a `u16` attribute). ASCII:
//! `solid name`, then `facet normal nx ny nz / outer loop / vertex x y z` ×3 `/ endloop / endfacet`,
//! `endsolid`; several solids in one file are read one after the other.
//!
//! Which is which: a file whose length is exactly `84 + 50·N` for the `N` of its header is binary,
//! even if its header starts with `solid` (some CAD programs write that into binary headers);
//! otherwise a file starting with `solid` is ASCII; anything else is a binary file of the wrong
//! length, refused with both lengths named. The header's `N` is only ever used after it has been
//! checked against the file's length, so no allocation is sized by it.
//!
//! STL stores every triangle's corners separately: corners with bit-identical positions (after
//! `−0 → +0`) are welded into one vertex, numbered in order of first use, so that the mesh has
//! topology (watertightness, signed volume, smooth vertex normals) as trimesh's loader gives it. The
//! facet normals of the file are ignored: the specification makes the counter-clockwise winding seen
//! from outside agree with them, many writers leave them zero, and the winding is what the renderer
//! uses. For a CAD part with sharp creases, flat shading shows the facets as they were exported.

use std::collections::HashMap;

use glam::Vec3;

use super::Loaded;
use crate::mesh::MAX_ELEMENTS;

/// Bytes of the binary header and of one triangle record.
const HEADER: usize = 84;
const RECORD: usize = 50;

/// Parse a whole STL file held in memory.
pub(super) fn parse(bytes: &[u8]) -> Result<Loaded, String> {
    if bytes.len() >= HEADER {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if n.checked_mul(RECORD).and_then(|b| b.checked_add(HEADER)) == Some(bytes.len()) {
            return parse_binary(&bytes[HEADER..], n);
        }
    }
    if starts_with_solid(bytes) {
        return parse_ascii(bytes);
    }
    if bytes.len() < HEADER {
        return Err(format!(
            "not an STL file: {} bytes, shorter than a binary STL header (84 bytes), and no 'solid' line",
            bytes.len()
        ));
    }
    let n = u64::from(u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]));
    Err(format!(
        "binary STL of the wrong length: its header declares {n} triangles ({} bytes), the file has {} bytes \
         (truncated, or not an STL file)",
        HEADER as u64 + RECORD as u64 * n,
        bytes.len()
    ))
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].len() >= 5 && bytes[start..start + 5].eq_ignore_ascii_case(b"solid")
}

fn parse_binary(records: &[u8], n: usize) -> Result<Loaded, String> {
    if n == 0 {
        return Err("has no faces: the binary header declares 0 triangles".into());
    }
    if n > MAX_ELEMENTS {
        return Err(format!("{n} triangles exceed the limit of {MAX_ELEMENTS}"));
    }
    let mut weld = Welder::with_capacity(n);
    for (t, record) in records.chunks_exact(RECORD).enumerate() {
        let mut corners = [0u32; 3];
        for (k, corner) in corners.iter_mut().enumerate() {
            let at = 12 + 12 * k;
            let f = |o: usize| {
                f32::from_le_bytes([
                    record[at + o],
                    record[at + o + 1],
                    record[at + o + 2],
                    record[at + o + 3],
                ])
            };
            let p = Vec3::new(f(0), f(4), f(8));
            if !p.is_finite() {
                return Err(format!("triangle {t}: vertex {k} has a non-finite position {p}"));
            }
            *corner = weld.vertex(p);
        }
        weld.indices.push(corners);
    }
    Ok(weld.finish())
}

fn parse_ascii(bytes: &[u8]) -> Result<Loaded, String> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| format!("ASCII STL with an invalid (non-UTF-8) byte at offset {}", e.valid_up_to()))?;
    // Capacity from the text's own length: a facet takes well over 100 bytes.
    let mut weld = Welder::with_capacity(text.len() / 128);
    let mut corners: Vec<u32> = Vec::with_capacity(3);
    let mut in_facet = false;
    let mut facet_line = 0;
    for (number, line) in text.lines().enumerate() {
        let number = number + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword.to_ascii_lowercase().as_str() {
            "facet" => {
                if in_facet {
                    return Err(format!("line {number}: 'facet' before the 'endfacet' of line {facet_line}"));
                }
                in_facet = true;
                facet_line = number;
                corners.clear();
            }
            "vertex" => {
                if !in_facet {
                    return Err(format!("line {number}: 'vertex' outside a facet"));
                }
                if corners.len() == 3 {
                    return Err(format!(
                        "line {number}: the facet of line {facet_line} has more than 3 vertices"
                    ));
                }
                let mut xyz = [0f32; 3];
                for x in &mut xyz {
                    let word =
                        words.next().ok_or_else(|| format!("line {number}: a vertex needs 3 numbers"))?;
                    *x = word.parse().map_err(|_| format!("line {number}: '{word}' is not a number"))?;
                }
                let p = Vec3::from(xyz);
                if !p.is_finite() {
                    return Err(format!("line {number}: non-finite vertex position {p}"));
                }
                corners.push(weld.vertex(p));
            }
            "endfacet" => {
                if !in_facet {
                    return Err(format!("line {number}: 'endfacet' without a facet"));
                }
                if corners.len() != 3 {
                    return Err(format!(
                        "line {number}: the facet of line {facet_line} has {} vertices (3 expected)",
                        corners.len()
                    ));
                }
                weld.indices.push([corners[0], corners[1], corners[2]]);
                if weld.indices.len() > MAX_ELEMENTS {
                    return Err(format!("more than {MAX_ELEMENTS} triangles"));
                }
                in_facet = false;
            }
            "solid" | "endsolid" | "outer" | "endloop" => {
                if in_facet && keyword.eq_ignore_ascii_case("endsolid") {
                    return Err(format!("line {number}: 'endsolid' inside the facet of line {facet_line}"));
                }
            }
            other => return Err(format!("line {number}: unexpected '{other}' in an ASCII STL file")),
        }
    }
    if in_facet {
        return Err(format!("truncated: the facet of line {facet_line} has no 'endfacet'"));
    }
    if weld.indices.is_empty() {
        return Err("has no faces: no facet in the ASCII STL file".into());
    }
    Ok(weld.finish())
}

/// Corner welding: one vertex per distinct position bit pattern, numbered in order of first use.
struct Welder {
    // std's randomly keyed SipHash: a file crafted so that positions collide cannot make the welding
    // quadratic. The numbering does not depend on the hash (first use), so loads are deterministic.
    ids: HashMap<[u32; 3], u32>,
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

impl Welder {
    fn with_capacity(triangles: usize) -> Self {
        // A closed mesh has about half as many vertices as triangles.
        Self {
            ids: HashMap::with_capacity(triangles / 2 + 3),
            positions: Vec::with_capacity(triangles / 2 + 3),
            indices: Vec::with_capacity(triangles),
        }
    }

    #[inline]
    fn vertex(&mut self, p: Vec3) -> u32 {
        // + 0.0 turns −0 into +0, so that the two zeros weld.
        let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
        let next = self.positions.len() as u32;
        let id = *self.ids.entry(key).or_insert(next);
        if id == next {
            self.positions.push(p + Vec3::ZERO);
        }
        id
    }

    fn finish(self) -> Loaded {
        Loaded { positions: self.positions, indices: self.indices, ..Default::default() }
    }
}
