//! The fuzz targets: each takes raw bytes, runs one reader (or mesh validation) on them, and checks
//! the error contract on what comes back.
//!
//! The contract, for every target: the call returns (no panic, no abort, no hang); an error has a
//! message that names its source and says something (`<memory>: ...`, `mesh: ...`, `merl: ...`);
//! a success holds only finite positions and normals, indices in range, and survives the queries a
//! user would make next (bounds, area, face normals, a transform). A broken contract is returned as
//! [`Violation`] so that the driver records the input like a panic.

use brdf_core::measured::{AnisotropicTabulated, Tabulated};
use brdf_raster::environment;
use brdf_raster::io::{self, MeshFormat};
use brdf_raster::{Mesh, RasterError};
use glam::{Mat4, Vec3};

/// A broken contract: what was wrong with the outcome of a call that did return.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation(pub String);

/// How a call that returned ended: accepted, or refused with a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// The input was read (or the mesh built).
    Ok,
    /// The input was refused with a clear error.
    Refused,
}

/// The things this crate fuzzes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    /// `brdf_raster::io::load_obj_bytes`: Wavefront OBJ text.
    Obj,
    /// `brdf_raster::io::load_ply_bytes`: Stanford PLY, ASCII or binary.
    Ply,
    /// `brdf_raster::io::load_stl_bytes`: STL, ASCII or binary.
    Stl,
    /// `brdf_core::measured::Tabulated::read_merl`: a MERL `.binary` table.
    Merl,
    /// `brdf_core::measured::AnisotropicTabulated::read_mit`: a MIT CSAIL anisotropic `.dat` table.
    MitDat,
    /// `brdf_raster::Mesh::new` (+ colors, transform, normals, statistics) on arbitrary arrays.
    Mesh,
    /// `brdf_raster::io::load_gltf_bytes`: glTF 2.0 JSON (data URIs) or GLB.
    Gltf,
    /// `brdf_raster::environment::file::load_bytes` on a `.hdr` (Radiance RGBE) environment map.
    Hdr,
    /// `brdf_raster::environment::file::load_bytes` on a `.exr` (OpenEXR) environment map.
    Exr,
}

impl Target {
    /// Every target, in the order the driver runs them.
    pub const ALL: [Target; 9] = [
        Target::Obj,
        Target::Ply,
        Target::Stl,
        Target::Merl,
        Target::MitDat,
        Target::Mesh,
        Target::Gltf,
        Target::Hdr,
        Target::Exr,
    ];

    /// The target's name on the command line and its corpus folder.
    pub fn name(self) -> &'static str {
        match self {
            Target::Obj => "obj",
            Target::Ply => "ply",
            Target::Stl => "stl",
            Target::Merl => "merl",
            Target::MitDat => "mit_dat",
            Target::Mesh => "mesh",
            Target::Gltf => "gltf",
            Target::Hdr => "hdr",
            Target::Exr => "exr",
        }
    }

    /// The target called `name` (see [`Target::name`]).
    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Run the target once on `data`.
    pub fn run(self, data: &[u8]) -> Result<Outcome, Violation> {
        match self {
            Target::Obj => mesh_file(data, MeshFormat::Obj),
            Target::Ply => mesh_file(data, MeshFormat::Ply),
            Target::Stl => mesh_file(data, MeshFormat::Stl),
            Target::Merl => merl(data),
            Target::MitDat => mit_dat(data),
            Target::Mesh => mesh_arrays(data),
            Target::Gltf => gltf(data),
            Target::Hdr => environment(data, "<memory>.hdr"),
            Target::Exr => environment(data, "<memory>.exr"),
        }
    }
}

fn violation<T>(what: impl Into<String>) -> Result<T, Violation> {
    Err(Violation(what.into()))
}

/// The message must name where it comes from and then say something.
fn check_message(message: &str, prefix: &str) -> Result<Outcome, Violation> {
    match message.strip_prefix(prefix) {
        Some(rest) if rest.trim().len() >= 3 => Ok(Outcome::Refused),
        _ => violation(format!("unclear message (expected '{prefix}<problem>'): {message:?}")),
    }
}

fn mesh_file(data: &[u8], format: MeshFormat) -> Result<Outcome, Violation> {
    match io::load_mesh_bytes(data, format) {
        Ok(mesh) => check_mesh(&mesh),
        Err(e @ RasterError::File { .. }) => check_message(&e.to_string(), "<memory>: "),
        Err(e) => violation(format!("a reader returned a non-file error: {e}")),
    }
}

/// A scene read holds only valid meshes with finite transforms, materials and lights.
fn gltf(data: &[u8]) -> Result<Outcome, Violation> {
    let scene = match io::load_gltf_bytes(data) {
        Ok(scene) => scene,
        Err(e @ RasterError::File { .. }) => return check_message(&e.to_string(), "<memory>: "),
        Err(e) => return violation(format!("the glTF reader returned a non-file error: {e}")),
    };
    for (i, p) in scene.primitives.iter().enumerate() {
        check_mesh(&p.mesh).map_err(|Violation(v)| Violation(format!("primitive {i}: {v}")))?;
        if !p.transform.is_finite() {
            return violation(format!("primitive {i}: transform {} is not finite", p.transform));
        }
        if p.material.is_some_and(|m| m >= scene.materials.len()) {
            return violation(format!(
                "primitive {i}: material {:?} of {}",
                p.material,
                scene.materials.len()
            ));
        }
    }
    // The specification bounds every factor; a reader passes on only what a material can use.
    for (i, m) in scene.materials.iter().enumerate() {
        let unit = |x: f32| (0.0..=1.0).contains(&x);
        let colour = |c: f32, finite: bool| finite && c >= 0.0;
        let valid = m.base_color.to_array().into_iter().all(unit)
            && unit(m.metallic)
            && unit(m.roughness)
            && colour(m.emissive.min_element(), m.emissive.is_finite())
            && m.alpha_cutoff.is_finite();
        if !valid {
            return violation(format!("material {i} has factors out of range: {m:?}"));
        }
    }
    for (i, l) in scene.lights.iter().enumerate() {
        if !(l.intensity.is_finite() && l.position.is_finite() && l.direction.is_finite()) {
            return violation(format!("light {i} is not finite: {l:?}"));
        }
    }
    Ok(Outcome::Ok)
}

/// A map read is non-empty, finite and non-negative everywhere a renderer looks it up.
fn environment(data: &[u8], name: &str) -> Result<Outcome, Violation> {
    let env = match environment::file::load_bytes(name, data) {
        Ok(env) => env,
        Err(e @ RasterError::File { .. }) => return check_message(&e.to_string(), &format!("{name}: ")),
        Err(e) => return violation(format!("the environment reader returned a non-file error: {e}")),
    };
    let (w, h) = env.map.size();
    if w == 0 || h == 0 || env.map.texels().len() != w * h {
        return violation(format!("a {w}x{h} map holds {} texels", env.map.texels().len()));
    }
    if let Some(i) = env.map.texels().iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
        return violation(format!("texel {i} is {} (must be finite and >= 0)", env.map.texels()[i]));
    }
    for (u, t) in [(0.0, 0.0), (0.5, 0.5), (1.0, 1.0), (-3.0, 7.5), (0.999_999, 1e-7)] {
        let c = env.map.lookup(u, t);
        if !c.is_finite() || c.min_element() < 0.0 {
            return violation(format!("lookup({u}, {t}) is {c}"));
        }
    }
    Ok(Outcome::Ok)
}

fn merl(data: &[u8]) -> Result<Outcome, Violation> {
    match Tabulated::read_merl(data) {
        Ok(table) => {
            let (a, b, c) = table.dims();
            if table.data().len() != a * b * c {
                return violation(format!("{}x{}x{} table holds {} values", a, b, c, table.data().len()));
            }
            if let Some(i) = table.data().iter().position(|v| !v.is_finite() || v.min_element() < 0.0) {
                return violation(format!(
                    "table value {i} is {} (must be finite and >= 0)",
                    table.data()[i]
                ));
            }
            // A look-up anywhere, including outside the grid, is finite.
            for (th, td, pd) in [(0.0, 0.0, 0.0), (1.5, 1.5, 3.1), (-1.0, 9.0, -7.0), (0.3, 1e30, -1e30)] {
                if !table.lookup(th, td, pd).is_finite() {
                    return violation(format!("lookup({th}, {td}, {pd}) is not finite"));
                }
            }
            let mut out = Vec::new();
            if let Err(e) = table.write_merl(&mut out) {
                return violation(format!("a table read cannot be written back: {e}"));
            }
            Ok(Outcome::Ok)
        }
        Err(e) => check_message(&e.to_string(), "merl: "),
    }
}

/// A table read holds finite values ≥ 0 (0 where there are no data), looks up finite values anywhere,
/// and writes back to the same bytes when the file marked its holes with −1 (what the writer does).
fn mit_dat(data: &[u8]) -> Result<Outcome, Violation> {
    match AnisotropicTabulated::read_mit(data, 1.0) {
        Ok(table) => {
            let d = table.dims();
            let cells: usize = d.iter().product();
            if table.data().len() != cells || table.valid().len() != cells {
                return violation(format!("{d:?} table holds {} values", table.data().len()));
            }
            if let Some(i) = table.data().iter().position(|v| !v.is_finite() || v.min_element() < 0.0) {
                return violation(format!(
                    "table value {i} is {} (must be finite and >= 0)",
                    table.data()[i]
                ));
            }
            for a in [
                [0.0, 0.0, 0.0, 0.0],
                [1.5, 1.5, 3.1, 6.2],
                [-1.0, 9.0, -7.0, 1e30],
                [0.3, 1e30, -1e30, -0.0],
            ] {
                let f = table.lookup(a[0], a[1], a[2], a[3]);
                if !f.is_finite() || f.min_element() < 0.0 {
                    return violation(format!("lookup({a:?}) is {f}"));
                }
            }
            let out = match table.write_mit(1.0) {
                Ok(out) => out,
                Err(e) => return violation(format!("a table read cannot be written back: {e}")),
            };
            match AnisotropicTabulated::read_mit(&out, 1.0) {
                Ok(back) if back == table => Ok(Outcome::Ok),
                Ok(_) => violation("the table written back reads differently"),
                Err(e) => violation(format!("the table written back is refused: {e}")),
            }
        }
        Err(e) => check_message(&e.to_string(), "data: "),
    }
}

/// A validated mesh holds what [`Mesh::new`] promises, and the queries on it return finite values.
fn check_mesh(mesh: &Mesh) -> Result<Outcome, Violation> {
    let nv = mesh.positions.len();
    if nv == 0 || mesh.indices.is_empty() {
        return violation("an empty mesh was accepted");
    }
    if mesh.normals.len() != nv {
        return violation(format!("{} normals for {nv} vertices", mesh.normals.len()));
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return violation(format!("position {i} is {}", mesh.positions[i]));
    }
    if let Some(i) = mesh.normals.iter().position(|n| !n.is_finite()) {
        return violation(format!("normal {i} is {}", mesh.normals[i]));
    }
    if let Some(f) = mesh.indices.iter().position(|t| t.iter().any(|&i| i as usize >= nv)) {
        return violation(format!("face {f} is {:?} with {nv} vertices", mesh.indices[f]));
    }
    if let Some(colors) = &mesh.colors {
        if colors.len() != nv || colors.iter().any(|c| !c.is_finite()) {
            return violation("colors are not one finite color per vertex");
        }
    }
    let bounds = mesh.bounds();
    if !bounds.min.is_finite() || !bounds.max.is_finite() {
        return violation(format!("bounds {bounds:?} are not finite"));
    }
    // Area and volume may overflow f64 only for coordinates near f32::MAX squared: they stay finite.
    if !mesh.area().is_finite() || !mesh.signed_volume().is_finite() {
        return violation(format!("area {} or volume {} not finite", mesh.area(), mesh.signed_volume()));
    }
    if let Some(f) = mesh.face_normals().iter().position(|n| !n.is_finite()) {
        return violation(format!("face normal {f} is not finite"));
    }
    let _ = mesh.degenerate_faces();
    let _ = mesh.stats();
    let _ = mesh.bounding_sphere();
    Ok(Outcome::Ok)
}

/// Reads the arrays of [`Target::Mesh`] from the fuzzer's bytes, zero-filling past the end so that every
/// input is some mesh: byte 0 the vertex count, byte 1 the face count, byte 2 flags (bit 0: reduce indices
/// modulo one more than the vertex count, so most are in range and the rest exactly one past the end;
/// bit 1: normals; bit 2: colors; bit 3: a transform), then positions (f32 LE ×3 per vertex), indices
/// (u32 LE ×3 per face), normals, colors, the 16 transform entries (column-major).
struct MeshBytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl MeshBytes<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }

    fn word(&mut self) -> [u8; 4] {
        [self.byte(), self.byte(), self.byte(), self.byte()]
    }

    fn vec3s(&mut self, n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|_| {
                let mut v = [0f32; 3];
                for x in &mut v {
                    *x = f32::from_le_bytes(self.word());
                }
                Vec3::from(v)
            })
            .collect()
    }
}

fn mesh_arrays(data: &[u8]) -> Result<Outcome, Violation> {
    let mut b = MeshBytes { data, at: 0 };
    let (nv, nf, flags) = (b.byte() as usize, b.byte() as usize, b.byte());
    let positions = b.vec3s(nv);
    let modulus = nv as u32 + 1;
    let indices: Vec<[u32; 3]> = (0..nf)
        .map(|_| {
            let t =
                [u32::from_le_bytes(b.word()), u32::from_le_bytes(b.word()), u32::from_le_bytes(b.word())];
            if flags & 1 != 0 { t.map(|i| i % modulus) } else { t }
        })
        .collect();
    let normals = (flags & 2 != 0).then(|| b.vec3s(nv));
    let colors = (flags & 4 != 0).then(|| b.vec3s(nv));
    let transform = (flags & 8 != 0).then(|| {
        let mut m = [0f32; 16];
        for x in &mut m {
            *x = f32::from_le_bytes(b.word());
        }
        m
    });
    let mesh = match Mesh::new(positions, indices, normals) {
        Ok(mesh) => mesh,
        Err(e) => return check_message(&e.to_string(), "mesh: "),
    };
    check_mesh(&mesh)?;
    let mesh = match colors {
        Some(colors) => match mesh.clone().with_colors(colors) {
            Ok(colored) => colored,
            Err(e) => return check_message(&e.to_string(), "mesh: "),
        },
        None => mesh,
    };
    check_mesh(&mesh)?;
    let mut flipped = mesh.clone();
    flipped.flip_winding();
    flipped.compute_normals(brdf_raster::normals::Weighting::Area);
    check_mesh(&flipped)?;
    if let Some(m) = transform {
        match mesh.transformed(&Mat4::from_cols_array(&m)) {
            Ok(moved) => {
                check_mesh(&moved)?;
            }
            Err(e) => {
                let message = e.to_string();
                if message.trim().len() < 8 || !message.contains(':') {
                    return violation(format!("unclear message from transformed: {message:?}"));
                }
            }
        }
    }
    Ok(Outcome::Ok)
}
