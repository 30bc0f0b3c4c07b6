//! PLY (Stanford polygon file) reading through `ply-rs-bw`: ASCII, binary little- and big-endian,
//! any scalar type, extra properties and elements ignored.
//!
//! What is read: element `vertex` (`x y z`, optional `nx ny nz`, optional `red green blue`) and
//! element `face` (list property `vertex_indices` or `vertex_index`). Polygons with more than 3
//! vertices are split into a fan `(v₀, v_k, v_{k+1})`, exact for convex polygons; faces with fewer
//! than 3 vertices are skipped. Other elements (edges, tristrips, materials...) are read past.
//!
//! Robustness: the header's element counts are checked against the bytes that follow it before
//! any payload is read (so a header that declares 10¹⁸ vertices fails at once, without allocating),
//! every face index is checked against the vertex count, and all values must be finite.

use glam::Vec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{ElementDef, Encoding, Header, Property, PropertyAccess, PropertyType, ScalarType};

use super::Loaded;
use crate::mesh::MAX_ELEMENTS;

/// Names under which vertex colors are found, per channel.
const COLOR_NAMES: [[&str; 3]; 3] =
    [["red", "r", "diffuse_red"], ["green", "g", "diffuse_green"], ["blue", "b", "diffuse_blue"]];

/// One vertex as read: position, normal, color (raw values, f64), which were present.
struct PlyVertex {
    values: [f64; 9],
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self { values: [0.0; 9] }
    }

    fn set_property(&mut self, name: &str, property: Property) {
        if let Some(slot) = vertex_slot(name) {
            if let Some(v) = scalar(&property) {
                self.values[slot] = v;
            }
        }
    }
}

/// Slot of a vertex property in `PlyVertex::values`: 0–2 position, 3–5 normal, 6–8 color.
fn vertex_slot(name: &str) -> Option<usize> {
    match name {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        "nx" => Some(3),
        "ny" => Some(4),
        "nz" => Some(5),
        _ => COLOR_NAMES.iter().position(|names| names.contains(&name)).map(|c| 6 + c),
    }
}

/// One face as read: its index list, kept as the parser produced it (no copy).
struct PlyFace {
    indices: Option<Property>,
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        Self { indices: None }
    }

    fn set_property(&mut self, name: &str, property: Property) {
        if name == "vertex_indices" || name == "vertex_index" {
            self.indices = Some(property);
        }
    }
}

/// Any other element: read and dropped.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Ignored
    }
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// The index list of a face as i64 values (lists of floats are refused).
fn index_list(p: &Property) -> Result<Vec<i64>, String> {
    Ok(match p {
        Property::ListChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i64::from(i)).collect(),
        _ => return Err("face vertex indices must be a list of integers".into()),
    })
}

fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The fewest payload bytes one instance of `element` can take: the scalars and list lengths in
/// binary (lists may be empty), two characters per value in ASCII (a digit and a separator).
fn min_element_bytes(element: &ElementDef, encoding: Encoding) -> u64 {
    element
        .properties
        .values()
        .map(|p| match (&p.data_type, encoding) {
            (_, Encoding::Ascii) => 2,
            (PropertyType::Scalar(t), _) => scalar_size(t),
            (PropertyType::List(count, _), _) => scalar_size(count),
        })
        .sum()
}

/// Refuse headers whose element counts cannot fit in the `remaining` payload bytes, before any
/// allocation; also refuse property-less elements with huge counts (they would read no bytes).
fn check_counts(header: &Header, remaining: u64) -> Result<(), String> {
    let mut needed: u64 = 0;
    for element in header.elements.values() {
        let count = element.count as u64;
        let per = min_element_bytes(element, header.encoding);
        // A property-less element still takes a line in ASCII; in binary bound it by the size.
        let bytes = count.checked_mul(per.max(1)).ok_or_else(|| too_big(element, remaining))?;
        needed = needed.saturating_add(bytes);
        // The last ASCII value may end the file without a separator.
        if needed > remaining.saturating_add(1) {
            return Err(too_big(element, remaining));
        }
    }
    Ok(())
}

fn too_big(element: &ElementDef, remaining: u64) -> String {
    format!(
        "the header declares {} '{}' elements, more than the {remaining} bytes after the header can hold \
         (truncated or corrupt file)",
        element.count, element.name
    )
}

/// Parse a whole PLY file held in memory.
pub(super) fn parse(bytes: &[u8]) -> Result<Loaded, String> {
    let mut reader: &[u8] = bytes;
    let header =
        Parser::<Ignored>::new().read_header(&mut reader).map_err(|e| format!("bad PLY header: {e}"))?;
    check_counts(&header, reader.len() as u64)?;

    let vertex_def = header.elements.get("vertex").ok_or("the PLY file has no 'vertex' element")?;
    for axis in ["x", "y", "z"] {
        match vertex_def.properties.get(axis).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => return Err(format!("vertex property '{axis}' is a list")),
            None => return Err(format!("the 'vertex' element has no '{axis}' property")),
        }
    }
    let face_def =
        header.elements.get("face").ok_or("the PLY file has no 'face' element (a point cloud?)")?;
    if !face_def.properties.contains_key("vertex_indices")
        && !face_def.properties.contains_key("vertex_index")
    {
        return Err("the 'face' element has no 'vertex_indices' (or 'vertex_index') list".into());
    }
    if vertex_def.count > MAX_ELEMENTS || face_def.count > MAX_ELEMENTS {
        return Err(format!(
            "{} vertices and {} faces exceed the limit of {MAX_ELEMENTS}",
            vertex_def.count, face_def.count
        ));
    }
    let has = |name: &str| vertex_def.properties.contains_key(name);
    let has_normals = ["nx", "ny", "nz"].iter().all(|n| has(n));
    let color_names: Option<[&str; 3]> = (|| {
        let mut names = [""; 3];
        for (c, options) in COLOR_NAMES.iter().enumerate() {
            names[c] = *options.iter().find(|n| has(n))?;
        }
        Some(names)
    })();

    // Read the payload element by element, in header order.
    let mut vertices: Vec<PlyVertex> = Vec::new();
    let mut faces: Vec<PlyFace> = Vec::new();
    for (name, def) in &header.elements {
        let context = |e: std::io::Error| format!("reading the '{name}' elements: {e}");
        match name.as_str() {
            "vertex" => {
                vertices =
                    Parser::new().read_payload_for_element(&mut reader, def, &header).map_err(context)?
            }
            "face" => {
                faces = Parser::new().read_payload_for_element(&mut reader, def, &header).map_err(context)?
            }
            _ => {
                Parser::<Ignored>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(context)?;
            }
        }
    }

    let nv = vertices.len();
    let mut positions = Vec::with_capacity(nv);
    for (i, v) in vertices.iter().enumerate() {
        let p = Vec3::new(v.values[0] as f32, v.values[1] as f32, v.values[2] as f32);
        if !p.is_finite() {
            return Err(format!("vertex {i} has a non-finite position {p}"));
        }
        positions.push(p);
    }
    let normals = has_normals.then(|| {
        vertices
            .iter()
            .map(|v| Vec3::new(v.values[3] as f32, v.values[4] as f32, v.values[5] as f32))
            .collect()
    });
    let colors = color_names.map(|names| {
        // 8- and 16-bit integer colors are display-encoded (sRGB) by convention; floats are taken
        // as linear already.
        let decode: [Option<f64>; 3] =
            names.map(|n| match vertex_def.properties.get(n).map(|p| &p.data_type) {
                Some(PropertyType::Scalar(ScalarType::UChar | ScalarType::Char)) => Some(255.0),
                Some(PropertyType::Scalar(ScalarType::UShort | ScalarType::Short)) => Some(65535.0),
                _ => None,
            });
        vertices
            .iter()
            .map(|v| {
                let c: [f32; 3] = std::array::from_fn(|k| match decode[k] {
                    Some(max) => srgb_to_linear((v.values[6 + k] / max).clamp(0.0, 1.0)) as f32,
                    None => v.values[6 + k] as f32,
                });
                Vec3::from_array(c)
            })
            .collect()
    });
    drop(vertices);

    let mut indices = Vec::with_capacity(faces.len());
    let mut skipped = 0usize;
    let mut polygons = 0usize;
    for (f, face) in faces.iter().enumerate() {
        let list = index_list(face.indices.as_ref().ok_or("a face has no index list")?)
            .map_err(|e| format!("face {f}: {e}"))?;
        if let Some(&bad) = list.iter().find(|&&i| i < 0 || i as u64 >= nv as u64) {
            return Err(format!("face {f} indexes vertex {bad}, but there are only {nv} vertices"));
        }
        if list.len() < 3 {
            skipped += 1;
            continue;
        }
        if list.len() > 3 {
            polygons += 1;
        }
        for k in 1..list.len() - 1 {
            indices.push([list[0] as u32, list[k] as u32, list[k + 1] as u32]);
        }
        if indices.len() > MAX_ELEMENTS {
            return Err(format!("more than {MAX_ELEMENTS} triangles after triangulating the polygons"));
        }
    }
    Ok(Loaded {
        positions,
        indices,
        normals,
        colors,
        uvs: None,
        polygons_triangulated: polygons,
        faces_skipped: skipped,
    })
}

/// sRGB EOTF (IEC 61966-2-1): display value in [0, 1] → linear.
fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}
