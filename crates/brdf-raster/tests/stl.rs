//! STL files: binary and ASCII round trips of a real mesh, welding, format detection, and the error
//! contract on truncated, corrupted and hostile input (an error naming the problem, never a panic or
//! an allocation sized by the header).

use std::path::Path;

use brdf_raster::RasterError;
use brdf_raster::io::{builtin_mesh, load_mesh, load_stl_bytes};
use brdf_raster::mesh::Mesh;

fn binary_stl(mesh: &Mesh, header: &[u8; 80]) -> Vec<u8> {
    let mut out = header.to_vec();
    out.extend_from_slice(&(mesh.triangle_count() as u32).to_le_bytes());
    for f in 0..mesh.triangle_count() {
        let n = mesh.face_normal(f);
        out.extend(n.to_array().iter().flat_map(|x| x.to_le_bytes()));
        for p in mesh.triangle(f) {
            out.extend(p.to_array().iter().flat_map(|x| x.to_le_bytes()));
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

fn ascii_stl(mesh: &Mesh) -> String {
    let mut out = String::from("solid cow\n");
    for f in 0..mesh.triangle_count() {
        let n = mesh.face_normal(f);
        out += &format!("  facet normal {:e} {:e} {:e}\n    outer loop\n", n.x, n.y, n.z);
        for p in mesh.triangle(f) {
            // `{:?}` prints the shortest text that reads back to the same f32.
            out += &format!("      vertex {:?} {:?} {:?}\n", p.x, p.y, p.z);
        }
        out += "    endloop\n  endfacet\n";
    }
    out + "endsolid cow\n"
}

fn problem<T: std::fmt::Debug>(r: Result<T, RasterError>) -> String {
    match r {
        Err(RasterError::File { problem, .. }) => problem,
        other => panic!("expected a file error, got {other:?}"),
    }
}

/// The welded STL mesh has the source's triangles corner for corner and its topology back.
fn assert_same_geometry(source: &Mesh, loaded: &Mesh) {
    assert_eq!(loaded.triangle_count(), source.triangle_count());
    // One vertex per distinct position (the cow has two vertices at the same place: 2903 positions).
    let distinct: std::collections::HashSet<[u32; 3]> =
        source.positions.iter().map(|p| p.to_array().map(f32::to_bits)).collect();
    assert_eq!(loaded.vertex_count(), distinct.len(), "every corner welded to its position's vertex");
    for f in 0..source.triangle_count() {
        assert_eq!(loaded.triangle(f), source.triangle(f), "face {f}");
    }
    let (a, b) = (source.stats(), loaded.stats());
    assert!(b.watertight && b.winding_consistent);
    assert_eq!(a.signed_volume, b.signed_volume);
}

#[test]
fn binary_and_ascii_stl_of_the_cow_give_back_its_triangles_and_topology() {
    let cow = builtin_mesh("cow").unwrap();
    assert_same_geometry(&cow, &load_stl_bytes(&binary_stl(&cow, &[b' '; 80])).unwrap());
    assert_same_geometry(&cow, &load_stl_bytes(ascii_stl(&cow).as_bytes()).unwrap());
}

#[test]
fn a_binary_file_whose_header_starts_with_solid_is_read_as_binary() {
    let cow = builtin_mesh("cow").unwrap();
    let mut header = [b' '; 80];
    header[..12].copy_from_slice(b"solid part 1");
    assert_same_geometry(&cow, &load_stl_bytes(&binary_stl(&cow, &header)).unwrap());
}

#[test]
fn corners_weld_by_position_and_the_two_zeros_are_one() {
    let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n\
                endfacet\nfacet normal 0 0 1\nouter loop\nvertex -0 1 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\n\
                endfacet\nendsolid t\n";
    let m = load_stl_bytes(text.as_bytes()).unwrap();
    assert_eq!(m.vertex_count(), 4);
    assert_eq!(m.indices, vec![[0, 1, 2], [2, 1, 3]]);
}

#[test]
fn load_mesh_reads_stl_by_extension() {
    let dir = std::env::temp_dir().join(format!("brdf-raster-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cow = builtin_mesh("cow").unwrap();
    let path = dir.join("cow.STL");
    std::fs::write(&path, binary_stl(&cow, &[0; 80])).unwrap();
    assert_same_geometry(&cow, &load_mesh(&path).unwrap());
    let err = load_mesh(Path::new(&path).with_extension("stl"));
    assert!(err.is_err());
}

#[test]
fn truncated_and_hostile_binary_files_are_refused_naming_both_lengths() {
    let cow = builtin_mesh("cow").unwrap();
    let full = binary_stl(&cow, &[0; 80]);
    let p = problem(load_stl_bytes(&full[..full.len() - 7]));
    assert!(p.contains("5804 triangles") && p.contains(&format!("{} bytes", full.len() - 7)), "{p}");
    // A header declaring 4 billion triangles over a few bytes: refused before any allocation.
    let mut hostile = vec![0u8; 80];
    hostile.extend_from_slice(&u32::MAX.to_le_bytes());
    hostile.extend_from_slice(&[0; 100]);
    let p = problem(load_stl_bytes(&hostile));
    assert!(p.contains("4294967295 triangles"), "{p}");
    let p = problem(load_stl_bytes(b"\x00\x01short"));
    assert!(p.contains("not an STL file"), "{p}");
    let mut empty = vec![0u8; 84];
    empty[80..84].copy_from_slice(&0u32.to_le_bytes());
    assert!(problem(load_stl_bytes(&empty)).contains("no faces"));
}

#[test]
fn non_finite_positions_are_refused_naming_the_triangle() {
    let cow = builtin_mesh("cow").unwrap();
    let mut bytes = binary_stl(&cow, &[0; 80]);
    let at = 84 + 50 * 17 + 12 + 12 + 4; // triangle 17, vertex 1, y
    bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let p = problem(load_stl_bytes(&bytes));
    assert!(p.contains("triangle 17") && p.contains("vertex 1"), "{p}");
}

#[test]
fn malformed_ascii_is_refused_naming_the_line() {
    let cases: [(&str, &str); 6] = [
        ("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n", "line 7"),
        ("solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n", "truncated"),
        ("solid\nvertex 0 0 0\n", "line 2"),
        ("solid\nfacet\nouter loop\nvertex 0 zero 0\n", "'zero'"),
        ("solid\nfacet\nouter loop\nvertex 0 nan 0\n", "non-finite"),
        ("solid x\nendsolid x\n", "no faces"),
    ];
    for (text, expected) in cases {
        let p = problem(load_stl_bytes(text.as_bytes()));
        assert!(p.contains(expected), "{text:?}: {p}");
    }
}

#[test]
fn random_corruption_of_either_form_is_an_error_or_a_valid_mesh_never_a_panic() {
    let cow = builtin_mesh("cow").unwrap();
    let sources = [binary_stl(&cow, &[0; 80]), ascii_stl(&cow).into_bytes()];
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for source in &sources {
        for _ in 0..200 {
            let mut bytes = source.clone();
            match next() % 3 {
                0 => bytes.truncate((next() as usize) % bytes.len()),
                1 => {
                    for _ in 0..8 {
                        let i = (next() as usize) % bytes.len();
                        bytes[i] = next() as u8;
                    }
                }
                _ => {
                    let i = (next() as usize) % bytes.len();
                    bytes.insert(i, next() as u8);
                }
            }
            if let Ok(m) = load_stl_bytes(&bytes) {
                assert!(m.positions.iter().all(|p| p.is_finite()));
            }
        }
    }
}
