//! Loading OBJ and PLY files: the real meshes of the test assets against `meshes.json`, OBJ and PLY
//! agreement, polygons, normals and colors from files, and the error contract on malformed,
//! truncated and corrupted input (an error, never a panic).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use brdf_raster::RasterError;
use brdf_raster::io::{
    BUILTIN_MESHES, MeshFormat, builtin_mesh, load_mesh, load_mesh_bytes, load_mesh_with_info,
    load_obj_bytes, load_ply_bytes,
};
use brdf_raster::mesh::Mesh;
use glam::Vec3;

/// Repository copies of the CC0 meshes (`tests/data/` at the repository root).
fn repo_data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(name)
}

/// The shared asset folder, when present (`BRDFPY_ASSETS`, or `../shared` beside the work tree).
fn shared_assets() -> Option<PathBuf> {
    let candidates = [
        std::env::var_os("BRDFPY_ASSETS").map(PathBuf::from),
        Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes")),
    ];
    candidates.into_iter().flatten().find(|p| p.join("meshes.json").is_file())
}

/// A deterministic xorshift generator (no dev-dependency needed).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

// ---------------------------------------------------------------- a minimal JSON reader

/// Just enough JSON for `meshes.json` (objects, arrays, numbers, strings, booleans).
#[derive(Debug, Clone)]
enum Json {
    Num(f64),
    Str(String),
    Bool(bool),
    Arr(Vec<Json>),
    Obj(BTreeMap<String, Json>),
    Null,
}

impl Json {
    fn parse(text: &str) -> Json {
        let bytes = text.as_bytes();
        let mut at = 0;
        Self::value(bytes, &mut at)
    }
    fn skip(b: &[u8], at: &mut usize) {
        while *at < b.len() && b[*at].is_ascii_whitespace() {
            *at += 1;
        }
    }
    fn value(b: &[u8], at: &mut usize) -> Json {
        Self::skip(b, at);
        match b[*at] {
            b'{' => {
                *at += 1;
                let mut map = BTreeMap::new();
                loop {
                    Self::skip(b, at);
                    if b[*at] == b'}' {
                        *at += 1;
                        return Json::Obj(map);
                    }
                    let Json::Str(key) = Self::value(b, at) else { panic!("object key at {at}") };
                    Self::skip(b, at);
                    assert_eq!(b[*at], b':');
                    *at += 1;
                    map.insert(key, Self::value(b, at));
                    Self::skip(b, at);
                    if b[*at] == b',' {
                        *at += 1;
                    }
                }
            }
            b'[' => {
                *at += 1;
                let mut items = Vec::new();
                loop {
                    Self::skip(b, at);
                    if b[*at] == b']' {
                        *at += 1;
                        return Json::Arr(items);
                    }
                    items.push(Self::value(b, at));
                    Self::skip(b, at);
                    if b[*at] == b',' {
                        *at += 1;
                    }
                }
            }
            b'"' => {
                let start = *at + 1;
                *at = start + b[start..].iter().position(|&c| c == b'"').unwrap();
                let s = String::from_utf8(b[start..*at].to_vec()).unwrap();
                *at += 1;
                Json::Str(s)
            }
            b't' => {
                *at += 4;
                Json::Bool(true)
            }
            b'f' => {
                *at += 5;
                Json::Bool(false)
            }
            b'n' => {
                *at += 4;
                Json::Null
            }
            _ => {
                let start = *at;
                while *at < b.len()
                    && (b[*at] == b'-'
                        || b[*at] == b'.'
                        || b[*at] == b'e'
                        || b[*at] == b'E'
                        || b[*at] == b'+'
                        || b[*at].is_ascii_digit())
                {
                    *at += 1;
                }
                Json::Num(std::str::from_utf8(&b[start..*at]).unwrap().parse().unwrap())
            }
        }
    }
    fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Obj(m) => m.get(key),
            _ => None,
        }
    }
    fn num(&self, key: &str) -> f64 {
        match self.get(key) {
            Some(Json::Num(n)) => *n,
            other => panic!("{key}: expected a number, got {other:?}"),
        }
    }
    fn flag(&self, key: &str) -> bool {
        matches!(self.get(key), Some(Json::Bool(true)))
    }
    fn vec3(&self, key: &str) -> Vec3 {
        match self.get(key) {
            Some(Json::Arr(a)) => Vec3::from_array(std::array::from_fn(|i| match a[i] {
                Json::Num(n) => n as f32,
                _ => panic!("{key}[{i}]"),
            })),
            other => panic!("{key}: expected an array, got {other:?}"),
        }
    }
}

// ---------------------------------------------------------------- the real meshes

fn assert_matches_json(mesh: &Mesh, entry: &Json, what: &str, obj: bool) {
    let stats = mesh.stats();
    let unreferenced = entry.num("unreferenced_vertices") as usize;
    // The OBJ reader numbers vertices in order of first use and drops the unused ones.
    let vertices = entry.num("vertices") as usize - if obj { unreferenced } else { 0 };
    assert_eq!(stats.vertices, vertices, "{what}: vertices");
    assert_eq!(stats.triangles, entry.num("triangles") as usize, "{what}: triangles");
    assert_eq!(stats.unreferenced_vertices, if obj { 0 } else { unreferenced }, "{what}: unreferenced");
    assert_eq!(stats.degenerate_triangles, entry.num("degenerate_triangles") as usize, "{what}: degenerate");
    assert_eq!(stats.watertight, entry.flag("watertight"), "{what}: watertight");
    assert_eq!(stats.winding_consistent, entry.flag("winding_consistent"), "{what}: winding");
    assert_eq!(stats.components, entry.num("components") as usize, "{what}: components");
    // meshes.json rounds the box to 6 decimals.
    let tol = 1e-6 + 1e-6 * stats.bounds.diagonal();
    assert!(
        (stats.bounds.min - entry.vec3("bbox_min")).abs().max_element() <= tol,
        "{what}: bbox_min {}",
        stats.bounds.min
    );
    assert!(
        (stats.bounds.max - entry.vec3("bbox_max")).abs().max_element() <= tol,
        "{what}: bbox_max {}",
        stats.bounds.max
    );
    for n in &mesh.normals {
        assert!((n.length() - 1.0).abs() < 1e-4 || *n == Vec3::ZERO);
    }
}

#[test]
fn every_shared_asset_mesh_loads_with_the_counts_of_meshes_json() {
    let Some(dir) = shared_assets() else {
        eprintln!("skipped: shared/assets/meshes not found (set BRDFPY_ASSETS to run this test)");
        return;
    };
    let json = Json::parse(&std::fs::read_to_string(dir.join("meshes.json")).unwrap());
    let Json::Obj(entries) = &json else { panic!("meshes.json is not an object") };
    let mut loaded = 0;
    for (name, entry) in entries {
        let Some(Json::Obj(files)) = entry.get("files") else { continue };
        for file in files.keys() {
            let path = dir.join(file);
            let is_obj = file.ends_with(".obj");
            if !(is_obj || file.ends_with(".ply")) {
                continue;
            }
            let mesh = load_mesh(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
            assert_matches_json(&mesh, entry, file, is_obj);
            let volume = mesh.signed_volume();
            if entry.flag("watertight") {
                if name == "cyberware_horse" {
                    assert!(volume < 0.0, "the horse is documented as wound inward, volume {volume}");
                } else {
                    assert!(volume > 0.0, "{file}: closed and CCW outward, volume {volume}");
                }
            }
            loaded += 1;
        }
    }
    assert!(loaded >= 10, "only {loaded} files loaded");
}

#[test]
fn the_horse_is_wound_inward_and_flip_winding_fixes_it() {
    let Some(dir) = shared_assets() else {
        eprintln!("skipped: shared/assets/meshes not found");
        return;
    };
    let mut horse = load_mesh(dir.join("cyberware_horse.ply")).unwrap();
    let inward = horse.signed_volume();
    assert!(inward < 0.0);
    // Computed vertex normals follow the winding, so they point inside too: on average they point
    // toward the centre rather than away from it.
    let c = horse.bounds().center();
    let outwardness = |m: &Mesh| m.positions.iter().zip(&m.normals).map(|(p, n)| n.dot(*p - c)).sum::<f32>();
    assert!(outwardness(&horse) < 0.0);
    horse.flip_winding();
    assert!((horse.signed_volume() + inward).abs() < 1e-12);
    assert!(outwardness(&horse) > 0.0);
}

#[test]
fn repository_copies_load_and_obj_agrees_with_ply() {
    for name in ["garland_cow", "hoppe_fandisk"] {
        let ply = load_mesh(repo_data(&format!("{name}.ply"))).unwrap();
        let obj = load_mesh(repo_data(&format!("{name}.obj"))).unwrap();
        assert_eq!(ply.triangle_count(), obj.triangle_count(), "{name}");
        assert_eq!(ply.vertex_count(), obj.vertex_count(), "{name}: no unused vertices in these");
        let stats = ply.stats();
        assert!(
            stats.watertight
                && stats.winding_consistent
                && stats.components == 1
                && stats.signed_volume > 0.0
        );
        // Same faces in the same order with the same corner positions (the OBJ text has 6
        // decimals, hence the tolerance), and so the same computed normals per corner.
        let tol = 1e-6 * ply.bounds().diagonal().max(1.0);
        for f in 0..ply.triangle_count() {
            let (a, b) = (ply.triangle(f), obj.triangle(f));
            for k in 0..3 {
                assert!((a[k] - b[k]).abs().max_element() <= tol, "{name} face {f}: {} vs {}", a[k], b[k]);
                let (na, nb) =
                    (ply.normals[ply.indices[f][k] as usize], obj.normals[obj.indices[f][k] as usize]);
                assert!(na.dot(nb) > 0.9999, "{name} face {f} normal {na} vs {nb}");
            }
        }
        assert!((ply.signed_volume() - obj.signed_volume()).abs() < 1e-5 * ply.signed_volume().abs());
    }
}

#[test]
fn builtin_meshes_need_no_files() {
    assert_eq!(BUILTIN_MESHES, &["cow", "fandisk"]);
    let cow = builtin_mesh("cow").unwrap();
    assert_eq!((cow.vertex_count(), cow.triangle_count()), (2904, 5804));
    assert!(cow.signed_volume() > 0.0);
    let fandisk = builtin_mesh("fandisk").unwrap();
    assert_eq!((fandisk.vertex_count(), fandisk.triangle_count()), (6475, 12946));
    assert_eq!(
        cow,
        load_mesh(repo_data("garland_cow.ply")).unwrap(),
        "the embedded file is the repository's copy"
    );
    let e = builtin_mesh("teapot").unwrap_err().to_string();
    assert!(e.contains("teapot") && e.contains("cow"), "{e}");
}

// ---------------------------------------------------------------- formats and features

/// The cow written as ASCII PLY and as big-endian binary PLY (with an extra property and an extra
/// element), both of which must load to the same mesh as the little-endian original.
fn rewrite_ply(mesh: &Mesh, ascii: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let format = if ascii { "ascii" } else { "binary_big_endian" };
    out.extend_from_slice(
        format!(
            "ply\nformat {format} 1.0\ncomment rewritten by tests/io.rs\nelement vertex {}\n\
             property double x\nproperty double y\nproperty double z\nproperty float confidence\n\
             element face {}\nproperty list uchar uint vertex_indices\nelement edge 1\n\
             property int vertex1\nproperty int vertex2\nend_header\n",
            mesh.vertex_count(),
            mesh.triangle_count()
        )
        .as_bytes(),
    );
    for p in &mesh.positions {
        if ascii {
            out.extend_from_slice(format!("{} {} {} 0.5\n", p.x, p.y, p.z).as_bytes());
        } else {
            for c in p.to_array() {
                out.extend_from_slice(&f64::from(c).to_be_bytes());
            }
            out.extend_from_slice(&0.5f32.to_be_bytes());
        }
    }
    for t in &mesh.indices {
        if ascii {
            out.extend_from_slice(format!("3 {} {} {}\n", t[0], t[1], t[2]).as_bytes());
        } else {
            out.push(3);
            for i in t {
                out.extend_from_slice(&i.to_be_bytes());
            }
        }
    }
    if ascii {
        out.extend_from_slice(b"0 1\n");
    } else {
        out.extend_from_slice(&0i32.to_be_bytes());
        out.extend_from_slice(&1i32.to_be_bytes());
    }
    out
}

#[test]
fn ascii_and_big_endian_ply_load_like_little_endian() {
    let cow = load_mesh(repo_data("garland_cow.ply")).unwrap();
    for ascii in [true, false] {
        let again = load_ply_bytes(&rewrite_ply(&cow, ascii)).unwrap();
        assert_eq!(
            again.positions, cow.positions,
            "ascii = {ascii}: f32 → text/f64 → f32 round-trips exactly"
        );
        assert_eq!(again.indices, cow.indices);
    }
}

#[test]
fn polygons_become_fans_and_points_and_lines_are_ignored() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
                f 1 2 3 4\nf 2 5 3\nl 1 2 3\np 4\nf 1 2\nf 3\no other\ng group\nusemtl missing\ns 1\n";
    let mesh = load_obj_bytes(obj).unwrap();
    // The quad (1,2,3,4) becomes (1,2,3), (1,3,4); then (2,5,3). OBJ vertices are numbered in
    // order of first use, which here is file order.
    assert_eq!(mesh.indices, vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
    assert_eq!(mesh.vertex_count(), 5);

    let ply =
        b"ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
                element face 3\nproperty list uchar int vertex_index\nend_header\n\
                0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n5 0 1 2 4 3\n2 0 1\n3 1 0 3\n";
    let mesh = load_ply_bytes(ply).unwrap();
    assert_eq!(mesh.indices, vec![[0, 1, 2], [0, 2, 4], [0, 4, 3], [1, 0, 3]]);
}

#[test]
fn normals_and_colors_from_the_file_are_used() {
    // Normals deliberately unlike the geometric +z, and not unit length.
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 2 0\nvn 1 0 0\nf 1//1 2//1 3//2\n";
    let mesh = load_obj_bytes(obj).unwrap();
    assert_eq!(mesh.normals, vec![Vec3::Y, Vec3::Y, Vec3::X]);

    let ply =
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                property float nx\nproperty float ny\nproperty float nz\n\
                property uchar red\nproperty uchar green\nproperty uchar blue\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 0 0 -3 255 0 128\n1 0 0 0 1 0 0 0 0\n0 1 0 1 0 0 10 20 30\n3 0 1 2\n";
    let mesh = load_ply_bytes(ply).unwrap();
    assert_eq!(mesh.normals, vec![Vec3::NEG_Z, Vec3::Y, Vec3::X]);
    let colors = mesh.colors.as_ref().unwrap();
    // 8-bit colors are sRGB-encoded: decode with the sRGB EOTF (IEC 61966-2-1).
    let decode = |v: f32| {
        let c = v / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    assert_eq!(colors[0].x, 1.0);
    assert_eq!(colors[1], Vec3::ZERO);
    for (got, byte) in [(colors[0].z, 128.0), (colors[2].x, 10.0), (colors[2].y, 20.0), (colors[2].z, 30.0)] {
        assert!((got - decode(byte)).abs() < 1e-6, "{got} vs {}", decode(byte));
    }
    // Without normals in the file they are computed (+z here).
    let plain = load_obj_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(plain.normals, vec![Vec3::Z; 3]);
    assert!(plain.colors.is_none());
}

#[test]
fn relative_obj_indices_resolve_backwards() {
    let mesh = load_obj_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n").unwrap();
    assert_eq!(mesh.indices, vec![[0, 1, 2]]);
}

// ---------------------------------------------------------------- the error contract

fn file_problem(result: Result<Mesh, RasterError>) -> String {
    match result {
        Err(RasterError::File { problem, .. }) => problem,
        Err(other) => panic!("expected a File error, got {other:?}"),
        Ok(m) => panic!("expected an error, got a mesh of {} faces", m.triangle_count()),
    }
}

#[test]
fn bad_obj_files_give_clear_errors() {
    let cases: &[(&[u8], &str)] = &[
        (b"", "has no faces"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "vertex index 4 is out of range (the file has 3 vertices)"),
        (b"v 0 0 0\nf 1 2 3\n", "(the file has 1 vertex)"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//1 3//1\nvn 0 0 1\n", "the file has 1 normal)"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/3 2/1 3/1\n", "has 2 texture coordinates)"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "vertex index -4"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "texture coordinate index 1"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//9 2//1 3//1\nvn 0 0 1\n", "normal index 9"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "not an integer"),
        (b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"),
        (b"v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"),
        (b"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "position"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\xff\xfe", "UTF-8"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n", "more than 3 parts"),
    ];
    for (text, expected) in cases {
        let problem = file_problem(load_obj_bytes(text));
        assert!(
            problem.contains(expected),
            "{:?}: '{problem}' should mention '{expected}'",
            String::from_utf8_lossy(text)
        );
    }
    // Index-out-of-range messages carry the line number.
    let problem = file_problem(load_obj_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"));
    assert!(problem.starts_with("line 4:"), "{problem}");
}

#[test]
fn bad_ply_files_give_clear_errors() {
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                  element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let with = |body: &str| format!("{header}{body}").into_bytes();
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (b"".to_vec(), "header"),
        (b"solid stl\n".to_vec(), "header"),
        (b"ply\nformat ascii 1.0\nelement vertex 3\n".to_vec(), "header"),
        (with("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "indexes vertex 3"),
        (with("0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n"), "indexes vertex -1"),
        (with("0 0 0\n1 0 0\n0 1 0\n"), "face"),
        (with("0 0 0\n1 0 0\n"), "vertex"),
        (with("0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n"), "vertex"),
        (with("0 0 1e39\n1 0 0\n0 1 0\n3 0 1 2\n"), "non-finite"),
        (
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n0 0\n1 0\n0 1\n".to_vec(),
            "no 'z'",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                .to_vec(),
            "no 'face' element",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_vec(),
            "integers",
        ),
    ];
    for (bytes, expected) in cases {
        let problem = file_problem(load_ply_bytes(&bytes));
        assert!(
            problem.contains(expected),
            "{:?}: '{problem}' should mention '{expected}'",
            String::from_utf8_lossy(&bytes)
        );
    }
}

#[test]
fn huge_declared_counts_fail_before_allocating() {
    for (count, encoding) in [
        ("1000000000000", "binary_little_endian"),
        ("18446744073709551615", "binary_little_endian"),
        ("4000000000", "ascii"),
        ("268435457", "binary_big_endian"),
    ] {
        let bytes = format!(
            "ply\nformat {encoding} 1.0\nelement vertex {count}\nproperty float x\nproperty float y\nproperty float z\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n"
        );
        let start = std::time::Instant::now();
        let problem = file_problem(load_ply_bytes(bytes.as_bytes()));
        assert!(problem.contains("bytes") || problem.contains("header"), "{problem}");
        assert!(start.elapsed().as_secs_f32() < 1.0, "must fail at once");
    }
    // An element without properties would read no bytes per instance: bounded by the file size too.
    let bytes = b"ply\nformat binary_little_endian 1.0\nelement junk 1000000000000\nelement vertex 0\nproperty float x\n\
                  property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
    assert!(file_problem(load_ply_bytes(bytes)).contains("junk"));
    // A binary face list with a huge length fails at the end of the data, not by allocating.
    let mut bytes =
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                      property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
            .to_vec();
    bytes.extend(std::iter::repeat_n(0u8, 36));
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    bytes.extend_from_slice(&[0; 12]);
    file_problem(load_ply_bytes(&bytes));
}

#[test]
fn load_mesh_reports_missing_files_and_unknown_types() {
    let problem = file_problem(load_mesh("/definitely/not/here.ply"));
    assert!(problem.contains("cannot read"), "{problem}");
    let dir = std::env::temp_dir().join(format!("brdf-raster-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let off = dir.join("model.off");
    std::fs::write(&off, b"OFF\n3 1 0\n").unwrap();
    let problem = file_problem(load_mesh(&off));
    assert!(problem.contains(".off") && problem.contains(".obj, .ply or .stl"), "{problem}");
    // A PLY file under another name is recognised by its magic; extensions are case-blind.
    let odd = dir.join("cow.mesh");
    std::fs::copy(repo_data("garland_cow.ply"), &odd).unwrap();
    assert_eq!(load_mesh(&odd).unwrap().triangle_count(), 5804);
    let upper = dir.join("COW.OBJ");
    std::fs::copy(repo_data("garland_cow.obj"), &upper).unwrap();
    assert_eq!(load_mesh(&upper).unwrap().triangle_count(), 5804);
    assert_eq!(MeshFormat::from_path(Path::new("a.Ply")), Some(MeshFormat::Ply));
    let problem = file_problem(load_mesh(&dir));
    assert!(problem.contains("cannot read"), "a directory: {problem}");
    #[cfg(unix)]
    {
        let problem = file_problem(load_mesh("/dev/zero"));
        assert!(problem.contains("not a regular file"), "a device that never ends: {problem}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn load_mesh_with_info_says_what_it_did() {
    let info = load_mesh_with_info(repo_data("garland_cow.obj")).unwrap();
    assert_eq!((info.polygons_triangulated, info.faces_skipped), (0, 0));
    assert!(!info.normals_from_file && !info.colors_from_file);
}

// ---------------------------------------------------------------- fuzzing: never panic

/// Truncate at many offsets and flip random bytes; every result must be a mesh or an error.
fn fuzz(bytes: &[u8], format: MeshFormat, seed: u64, rounds: usize) -> (usize, usize) {
    let mut rng = Rng(seed);
    let (mut ok, mut err) = (0, 0);
    let mut tally = |r: Result<Mesh, RasterError>| match r {
        Ok(m) => {
            assert!(m.positions.iter().all(|p| p.is_finite()));
            assert!(m.indices.iter().flatten().all(|&i| (i as usize) < m.vertex_count()));
            ok += 1;
        }
        Err(_) => err += 1,
    };
    for _ in 0..rounds {
        let cut = rng.below(bytes.len());
        tally(load_mesh_bytes(&bytes[..cut], format));
        let mut corrupted = bytes.to_vec();
        for _ in 0..1 + rng.below(8) {
            let at = rng.below(corrupted.len());
            corrupted[at] ^= 1 << rng.below(8);
        }
        tally(load_mesh_bytes(&corrupted, format));
        // Corruptions concentrated in the header, where the parser decides how much to read.
        let mut corrupted = bytes.to_vec();
        let at = rng.below(bytes.len().min(400));
        corrupted[at] = rng.next() as u8;
        tally(load_mesh_bytes(&corrupted, format));
    }
    (ok, err)
}

#[test]
fn truncated_and_corrupted_files_never_panic() {
    let cow_ply = std::fs::read(repo_data("garland_cow.ply")).unwrap();
    let cow_obj = std::fs::read(repo_data("garland_cow.obj")).unwrap();
    let cow = load_ply_bytes(&cow_ply).unwrap();
    let ascii = rewrite_ply(&cow, true);
    let big_endian = rewrite_ply(&cow, false);
    let (_, err) = fuzz(&cow_ply, MeshFormat::Ply, 1, 150);
    assert!(err > 0);
    fuzz(&ascii, MeshFormat::Ply, 2, 100);
    fuzz(&big_endian, MeshFormat::Ply, 3, 100);
    fuzz(&cow_obj, MeshFormat::Obj, 4, 100);
    // A binary PLY cut anywhere inside its payload is incomplete: always an error.
    let header_end = cow_ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let mut rng = Rng(5);
    for _ in 0..100 {
        let cut = header_end + rng.below(cow_ply.len() - header_end);
        file_problem(load_ply_bytes(&cow_ply[..cut]));
    }
}
