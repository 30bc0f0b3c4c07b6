//! glTF 2.0 scenes from bytes: a hand-written document with a data-URI buffer and a GLB container decode
//! to the triangles, transforms and material the file says; malformed documents are errors naming the
//! JSON element, never panics (the Python tests write files with an independent writer).

use base64::Engine as _;
use brdf_raster::RasterError;
use brdf_raster::io::gltf_scene::AlphaMode;
use brdf_raster::io::load_gltf_bytes;
use glam::{Mat4, Vec3};

/// A quad (4 positions, 6 u16 indices) in one buffer: indices first (12 bytes), then positions (48).
fn buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    for p in [[-1f32, -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]] {
        b.extend(p.iter().flat_map(|x| x.to_le_bytes()));
    }
    b
}

fn document(uri: Option<&str>, extra: &str) -> String {
    let buffer = match uri {
        Some(u) => format!(r#"{{"byteLength": 60, "uri": "{u}"}}"#),
        None => r#"{"byteLength": 60}"#.to_string(),
    };
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [1]}}],
        "nodes": [{{"mesh": 0, "translation": [0, 2, 0]}}, {{"children": [0], "scale": [-1, 1, 1]}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 1}}, "indices": 0, "material": 0}}]}}],
        "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.4, 0.2, 1], "metallicFactor": 0.5,
            "roughnessFactor": 0.4}}, "alphaMode": "MASK"}}],
        "accessors": [{{"bufferView": 0, "componentType": 5123, "count": 6, "type": "SCALAR"}},
                      {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3",
                        "min": [-1, -1, 0], "max": [1, 1, 0]}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 12}},
                        {{"buffer": 0, "byteOffset": 12, "byteLength": 48}}],
        "buffers": [{buffer}]{extra}}}"#
    )
}

fn data_uri_document(extra: &str) -> String {
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(buffer())
    );
    document(Some(&uri), extra)
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while j.len() % 4 != 0 {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

fn problem<T: std::fmt::Debug>(r: Result<T, RasterError>) -> String {
    match r {
        Err(RasterError::File { problem, .. }) => problem,
        other => panic!("expected a file error, got {other:?}"),
    }
}

#[test]
fn a_data_uri_document_and_a_glb_decode_to_the_same_placed_quad_and_material() {
    for bytes in [data_uri_document("").into_bytes(), glb(&document(None, ""), &buffer())] {
        let scene = load_gltf_bytes(&bytes).unwrap();
        let [prim] = &scene.primitives[..] else { panic!("one primitive") };
        assert_eq!(prim.mesh.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(prim.mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
        // parent (mirror in x) × child (up 2)
        let expected = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * Mat4::from_translation(Vec3::Y * 2.0);
        assert_eq!(prim.transform, expected);
        let m = &scene.materials[prim.material.unwrap()];
        assert_eq!(m.alpha_mode, AlphaMode::Mask);
        let (kd, f0, alpha) = m.cook_torrance();
        assert!((kd - Vec3::new(0.4, 0.2, 0.1)).abs().max_element() < 1e-6);
        assert!((f0 - Vec3::new(0.42, 0.22, 0.12)).abs().max_element() < 1e-6);
        assert!((alpha - 0.16).abs() < 1e-6);
    }
}

#[test]
fn malformed_documents_name_the_element() {
    let cases = [
        (data_uri_document("").replace(r#""count": 4"#, r#""count": 40"#), "accessors[1]"),
        (data_uri_document("").replace(r#""componentType": 5126"#, r#""componentType": 5121"#), "POSITION"),
        (data_uri_document("").replace(r#""byteLength": 48"#, r#""byteLength": 4800"#), "bufferViews[1]"),
        (
            data_uri_document(
                r#", "extensionsRequired": ["EXT_unknown"], "extensionsUsed": ["EXT_unknown"]"#,
            ),
            "extensionsRequired",
        ),
        (data_uri_document("").replace(r#""children": [0]"#, r#""children": [0, 1]"#), "nodes[1]"),
        // gltf-json's own validation indexes this accessor unchecked (a panic before the reader's check).
        (data_uri_document("").replace(r#""POSITION": 1"#, r#""POSITION": 7"#), "POSITION: accessor 7"),
        (data_uri_document("").replace(r#""accessors""#, r#""accessorz""#), "POSITION: accessor 1"),
        // Factors outside the schema's ranges (1 − metallic would weight the diffuse lobe negatively).
        (
            data_uri_document("").replace(r#""metallicFactor": 0.5"#, r#""metallicFactor": 4.7"#),
            "materials[0].pbrMetallicRoughness.metallicFactor: 4.7 is outside [0, 1]",
        ),
        (
            data_uri_document("").replace(r#""roughnessFactor": 0.4"#, r#""roughnessFactor": -0.3"#),
            "roughnessFactor: -0.3",
        ),
        (data_uri_document("").replace("0.8, 0.4, 0.2, 1", "0.8, 1e39, 0.2, 1"), "baseColorFactor[1]: inf"),
        (document(Some("quad.bin"), ""), "read from memory"),
        (document(None, ""), "buffers[0]"),
        ("{not json".to_string(), "invalid glTF"),
    ];
    for (text, expected) in cases {
        let p = problem(load_gltf_bytes(text.as_bytes()));
        assert!(p.contains(expected), "{expected}: {p}");
    }
}

#[test]
fn truncated_and_corrupted_glb_never_panics() {
    let full = glb(&document(None, ""), &buffer());
    for cut in 0..full.len() {
        let _ = load_gltf_bytes(&full[..cut]);
    }
    let mut short_header = full.clone();
    short_header[8..12].copy_from_slice(&4u32.to_le_bytes());
    assert!(problem(load_gltf_bytes(&short_header)).contains("GLB"));
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..300 {
        let mut bytes = full.clone();
        for _ in 0..4 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let i = (state as usize) % bytes.len();
            bytes[i] = (state >> 32) as u8;
        }
        let _ = load_gltf_bytes(&bytes);
    }
}
