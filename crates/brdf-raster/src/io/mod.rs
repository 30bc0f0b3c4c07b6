//! Loading meshes from OBJ, PLY and STL files, and the meshes embedded in the crate.
//!
//! Every failure — missing file, unknown extension, malformed or truncated content, index out of
//! range, NaN or infinite coordinates, a header declaring more elements than the file can hold —
//! is a [`RasterError::File`] naming the file and the problem. Nothing here panics on bad input.
//!
//! Common rules for both formats: polygons are split into triangle fans `(v₀, v_k, v_{k+1})`
//! (exact for convex polygons, which is what exporters write), points and lines are ignored,
//! vertex normals stored in the file are used when every vertex has one and computed with angle
//! weighting otherwise (see [`Mesh::new`]), and vertex colors are kept when every vertex has one.
//! The winding is taken as stored: check [`Mesh::signed_volume`] for closed meshes and call
//! [`Mesh::flip_winding`] when it is negative (the Cyberware horse of the test assets is such a
//! mesh).

pub mod gltf_scene;
mod obj;
pub mod obj_mtl;
mod ply;
mod stl;

pub use gltf_scene::{GltfScene, load_gltf, load_gltf_bytes};
pub use obj_mtl::{ObjScene, load_obj_scene};

use std::path::Path;

use glam::Vec3;

use crate::{Mesh, RasterError};

/// Largest mesh file read (16 GiB): beyond any mesh of [`crate::mesh::MAX_ELEMENTS`] triangles
/// in a binary format, and a bound on memory for the text formats.
pub const MAX_FILE_BYTES: u64 = 1 << 34;

/// A file format [`load_mesh_bytes`] can read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (text), read with `tobj`; see the `obj` module notes on vertex order.
    Obj,
    /// Stanford PLY (ASCII or binary, either byte order), read with `ply-rs-bw`.
    Ply,
    /// STL, binary or ASCII; corners welded by position (see the `stl` module notes).
    Stl,
}

impl MeshFormat {
    /// The format for a file name's extension (`.obj`, `.ply`, any case); `None` otherwise.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            "stl" => Some(Self::Stl),
            _ => None,
        }
    }
}

/// What a loader found, before validation into a [`Mesh`].
#[derive(Debug, Default)]
struct Loaded {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<Vec3>>,
    colors: Option<Vec<Vec3>>,
    uvs: Option<Vec<glam::Vec2>>,
    polygons_triangulated: usize,
    faces_skipped: usize,
}

/// A loaded mesh and what the loader did to it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedMesh {
    /// The validated mesh.
    pub mesh: Mesh,
    /// Faces with more than 3 vertices, each split into a triangle fan.
    pub polygons_triangulated: usize,
    /// Faces with fewer than 3 vertices (points, lines), ignored.
    pub faces_skipped: usize,
    /// Whether the vertex normals came from the file (else they were computed).
    pub normals_from_file: bool,
    /// Whether the file had vertex colors.
    pub colors_from_file: bool,
}

/// Load an OBJ, PLY or STL mesh, choosing the format by the extension (`.obj`, `.ply`, `.stl`, any case);
/// a file with another extension is read as PLY when it starts with the PLY magic `ply`.
pub fn load_mesh(path: impl AsRef<Path>) -> Result<Mesh, RasterError> {
    load_mesh_with_info(path).map(|loaded| loaded.mesh)
}

/// [`load_mesh`], also reporting polygons triangulated, faces skipped and where normals and
/// colors came from.
pub fn load_mesh_with_info(path: impl AsRef<Path>) -> Result<LoadedMesh, RasterError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let file_error = |problem: String| RasterError::File { path: name.clone(), problem };
    let bytes = read_regular_file(path)?;
    let format = match MeshFormat::from_path(path) {
        Some(format) => format,
        None if bytes.starts_with(b"ply") => MeshFormat::Ply,
        None => {
            let ext = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
            return Err(file_error(format!(
                "unsupported mesh file type '.{ext}' (expected .obj, .ply or .stl)"
            )));
        }
    };
    load_named(&bytes, format, &name)
}

/// The bytes of a regular file of at most [`MAX_FILE_BYTES`]; errors name the file.
pub(crate) fn read_regular_file(path: &Path) -> Result<Vec<u8>, RasterError> {
    let file_error = |problem: String| RasterError::File { path: path.display().to_string(), problem };
    // Only regular files: reading a device such as /dev/zero or a FIFO would never end.
    let metadata = std::fs::metadata(path).map_err(|e| file_error(format!("cannot read the file: {e}")))?;
    if !metadata.is_file() {
        return Err(file_error("cannot read the file: not a regular file".into()));
    }
    if metadata.len() > MAX_FILE_BYTES {
        return Err(file_error(format!(
            "the file has {} bytes, more than the limit of {MAX_FILE_BYTES}",
            metadata.len()
        )));
    }
    std::fs::read(path).map_err(|e| file_error(format!("cannot read the file: {e}")))
}

/// Load a mesh from bytes in memory (the contents of a file of the given format).
/// Errors name the source as `<memory>`.
pub fn load_mesh_bytes(bytes: &[u8], format: MeshFormat) -> Result<Mesh, RasterError> {
    load_named(bytes, format, "<memory>").map(|loaded| loaded.mesh)
}

/// Load an OBJ mesh from bytes in memory.
pub fn load_obj_bytes(bytes: &[u8]) -> Result<Mesh, RasterError> {
    load_mesh_bytes(bytes, MeshFormat::Obj)
}

/// Load a PLY mesh from bytes in memory.
pub fn load_ply_bytes(bytes: &[u8]) -> Result<Mesh, RasterError> {
    load_mesh_bytes(bytes, MeshFormat::Ply)
}

/// Load an STL mesh (binary or ASCII) from bytes in memory.
pub fn load_stl_bytes(bytes: &[u8]) -> Result<Mesh, RasterError> {
    load_mesh_bytes(bytes, MeshFormat::Stl)
}

fn load_named(bytes: &[u8], format: MeshFormat, name: &str) -> Result<LoadedMesh, RasterError> {
    let file_error = |problem: String| RasterError::File { path: name.to_owned(), problem };
    let loaded = match format {
        MeshFormat::Obj => obj::parse(bytes),
        MeshFormat::Ply => ply::parse(bytes),
        MeshFormat::Stl => stl::parse(bytes),
    }
    .map_err(file_error)?;
    let Loaded { positions, indices, normals, colors, uvs, polygons_triangulated, faces_skipped } = loaded;
    let normals_from_file = normals.is_some();
    let mut mesh = Mesh::new(positions, indices, normals).map_err(|e| file_error(e.to_string()))?;
    let colors_from_file = colors.is_some();
    if let Some(colors) = colors {
        mesh = mesh.with_colors(colors).map_err(|e| file_error(e.to_string()))?;
    }
    if let Some(uvs) = uvs {
        mesh = mesh.with_uvs(uvs).map_err(|e| file_error(e.to_string()))?;
    }
    Ok(LoadedMesh { mesh, polygons_triangulated, faces_skipped, normals_from_file, colors_from_file })
}

/// Names of the meshes embedded in the crate, for [`builtin_mesh`].
pub const BUILTIN_MESHES: &[&str] = &["cow", "fandisk"];

/// A mesh embedded in the crate, so that a render needs no files:
///
/// - `"cow"`: Garland's QSlim cow (2,904 vertices, 5,804 triangles, closed, CCW outward;
///   bounding box ±0.5 × ±0.306 × ±0.163, x along the body).
/// - `"fandisk"`: Hoppe's fandisk CAD part (6,475 vertices, 12,946 triangles, closed, sharp
///   creases; ±0.46 × ±0.26 × ±0.5).
///
/// Both come from CGAL's data set (Debian `libcgal-demo` 5.5.1-2, `data/meshes/{cow,fandisk}.off`),
/// CC0-1.0; see `crates/brdf-raster/assets/README.md`. Vertex normals are computed with angle
/// weighting (the files have none).
///
/// Errors: an unknown name (the message lists the known ones).
///
/// ```
/// let cow = brdf_raster::io::builtin_mesh("cow")?;
/// assert_eq!(cow.triangle_count(), 5804);
/// # Ok::<(), brdf_raster::RasterError>(())
/// ```
pub fn builtin_mesh(name: &str) -> Result<Mesh, RasterError> {
    let bytes: &[u8] = match name {
        "cow" => include_bytes!("../../assets/garland_cow.ply"),
        "fandisk" => include_bytes!("../../assets/hoppe_fandisk.ply"),
        _ => {
            return Err(RasterError::arg(
                "name",
                format!("no built-in mesh '{name}' (known: {})", BUILTIN_MESHES.join(", ")),
            ));
        }
    };
    load_named(bytes, MeshFormat::Ply, name).map(|loaded| loaded.mesh)
}
