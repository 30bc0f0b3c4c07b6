//! Scene files from Python: glTF 2.0 (`brdf_raster::io::gltf_scene`) and OBJ with its MTL materials
//! (`brdf_raster::io::obj_mtl`), decoded in Rust with the GIL released and handed over as plain
//! dicts of `RasterMesh`es, NumPy arrays, numbers, strings and `bytes` (the encoded images).
//! `brdfpy.load_scene` (`python/brdfpy/assets.py`) turns them into a `Scene`, materials, lights and
//! cameras. Every error of the readers names the file and the element (`meshes[0].primitives[1]...`,
//! `newmtl red: Kd: ...`) and becomes `BrdfError`.

use std::sync::Arc;

use brdf_raster::io::gltf_scene::{
    AlphaMode, GltfLightKind, GltfMaterial, GltfProjection, GltfScene, TextureRef, Wrap,
};
use brdf_raster::io::obj_mtl::{ObjMaterial, ObjScene};
use brdf_raster::{Mesh, RasterError};
use glam::{Mat4, Vec2, Vec3, Vec4};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use super::mesh::RasterMesh;
use super::{raster_err, rows_of, vec3_array};

fn mesh_of(m: Mesh) -> RasterMesh {
    RasterMesh { inner: Arc::new(m) }
}

/// A 4×4 matrix as a float64 NumPy array, row-major (column vectors: `p_world = M @ p`).
fn mat4<'py>(py: Python<'py>, m: Mat4) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = rows_of(m);
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().map(|&x| f64::from(x))).collect();
    PyArray1::from_vec(py, flat).reshape([4, 4])
}

fn vec2_array<'py>(py: Python<'py>, v: &[Vec2]) -> PyResult<Bound<'py, PyArray2<f32>>> {
    PyArray1::from_slice(py, bytemuck::cast_slice::<Vec2, f32>(v)).reshape([v.len(), 2])
}

fn vec4_array<'py>(py: Python<'py>, v: &[Vec4]) -> PyResult<Bound<'py, PyArray2<f32>>> {
    PyArray1::from_slice(py, bytemuck::cast_slice::<Vec4, f32>(v)).reshape([v.len(), 4])
}

fn texture_ref<'py>(py: Python<'py>, t: &TextureRef) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("texture", t.texture)?;
    d.set_item("tex_coord", t.tex_coord)?;
    d.set_item("scale", t.scale)?;
    Ok(d)
}

fn gltf_material<'py>(py: Python<'py>, m: &GltfMaterial) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &m.name)?;
    d.set_item("base_color", m.base_color.to_array())?;
    d.set_item("metallic", m.metallic)?;
    d.set_item("roughness", m.roughness)?;
    d.set_item("emissive", m.emissive.to_array())?;
    let mode = match m.alpha_mode {
        AlphaMode::Opaque => "OPAQUE",
        AlphaMode::Mask => "MASK",
        AlphaMode::Blend => "BLEND",
    };
    d.set_item("alpha_mode", mode)?;
    d.set_item("alpha_cutoff", m.alpha_cutoff)?;
    d.set_item("double_sided", m.double_sided)?;
    let textures = PyDict::new(py);
    let slots = [
        ("baseColorTexture", &m.base_color_texture),
        ("metallicRoughnessTexture", &m.metallic_roughness_texture),
        ("normalTexture", &m.normal_texture),
        ("occlusionTexture", &m.occlusion_texture),
        ("emissiveTexture", &m.emissive_texture),
    ];
    for (slot, t) in slots {
        if let Some(t) = t {
            textures.set_item(slot, texture_ref(py, t)?)?;
        }
    }
    d.set_item("textures", textures)?;
    Ok(d)
}

fn wrap_name(w: Wrap) -> &'static str {
    match w {
        Wrap::Clamp => "CLAMP_TO_EDGE",
        Wrap::Mirror => "MIRRORED_REPEAT",
        Wrap::Repeat => "REPEAT",
    }
}

fn gltf_dict<'py>(py: Python<'py>, s: GltfScene) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let prims = PyList::empty(py);
    for p in s.primitives {
        let d = PyDict::new(py);
        d.set_item("uvs", p.mesh.uvs.as_deref().map(|u| vec2_array(py, u)).transpose()?)?;
        d.set_item("tangents", p.mesh.tangents.as_deref().map(|t| vec4_array(py, t)).transpose()?)?;
        d.set_item("colors", p.mesh.colors.as_deref().map(|c| vec3_array(py, c)).transpose()?)?;
        d.set_item("mesh", Py::new(py, mesh_of(p.mesh))?)?;
        d.set_item("transform", mat4(py, p.transform)?)?;
        d.set_item("material", p.material)?;
        d.set_item("name", p.name)?;
        prims.append(d)?;
    }
    out.set_item("primitives", prims)?;
    let mats = PyList::empty(py);
    for m in &s.materials {
        mats.append(gltf_material(py, m)?)?;
    }
    out.set_item("materials", mats)?;
    out.set_item("default_material", gltf_material(py, &GltfMaterial::default_material())?)?;
    let texs = PyList::empty(py);
    for t in &s.textures {
        let d = PyDict::new(py);
        d.set_item("image", t.image)?;
        d.set_item("wrap_s", wrap_name(t.wrap[0]))?;
        d.set_item("wrap_t", wrap_name(t.wrap[1]))?;
        d.set_item("mag_filter", if t.mag_nearest { "NEAREST" } else { "LINEAR" })?;
        d.set_item("mipmaps", t.mipmaps)?;
        texs.append(d)?;
    }
    out.set_item("textures", texs)?;
    let imgs = PyList::empty(py);
    for i in &s.images {
        let d = PyDict::new(py);
        d.set_item("name", &i.name)?;
        d.set_item("mime_type", i.mime_type.as_deref())?;
        d.set_item("data", PyBytes::new(py, &i.bytes))?;
        imgs.append(d)?;
    }
    out.set_item("images", imgs)?;
    let cams = PyList::empty(py);
    for c in &s.cameras {
        let d = PyDict::new(py);
        d.set_item("name", &c.name)?;
        d.set_item("transform", mat4(py, c.transform)?)?;
        match c.projection {
            GltfProjection::Perspective { yfov, aspect, znear, zfar } => {
                d.set_item("type", "perspective")?;
                d.set_item("yfov", yfov)?;
                d.set_item("aspect", aspect)?;
                d.set_item("znear", znear)?;
                d.set_item("zfar", zfar)?;
            }
            GltfProjection::Orthographic { xmag, ymag, znear, zfar } => {
                d.set_item("type", "orthographic")?;
                d.set_item("xmag", xmag)?;
                d.set_item("ymag", ymag)?;
                d.set_item("znear", znear)?;
                d.set_item("zfar", zfar)?;
            }
        }
        cams.append(d)?;
    }
    out.set_item("cameras", cams)?;
    let lights = PyList::empty(py);
    for l in &s.lights {
        let d = PyDict::new(py);
        d.set_item("name", &l.name)?;
        let (kind, cones) = match l.kind {
            GltfLightKind::Directional => ("directional", None),
            GltfLightKind::Point => ("point", None),
            GltfLightKind::Spot { inner, outer } => ("spot", Some((inner, outer))),
        };
        d.set_item("type", kind)?;
        d.set_item("intensity", l.intensity.to_array())?;
        d.set_item("position", l.position.to_array())?;
        d.set_item("direction", l.direction.to_array())?;
        d.set_item("range", l.range)?;
        d.set_item("inner_cone_angle", cones.map(|c| c.0))?;
        d.set_item("outer_cone_angle", cones.map(|c| c.1))?;
        lights.append(d)?;
    }
    out.set_item("lights", lights)?;
    out.set_item("skipped", s.skipped)?;
    Ok(out)
}

/// Read a glTF 2.0 file (`.gltf` with its `.bin` and image files or data URIs, or `.glb`): a dict
/// with `primitives` (each `mesh`, `transform` (4, 4) float64 object → world, `material` index or
/// None, `name`, and the file's `uvs` (V, 2), `tangents` (V, 4), `colors` (V, 3) or None),
/// `materials` (metallic-roughness factors, alpha mode, double-sidedness, `textures` by slot),
/// `default_material`, `textures` (image index, wrap modes, filters), `images` (`name`,
/// `mime_type`, encoded `data` bytes), `cameras` (`transform` camera → world, looking along −z;
/// perspective `yfov` [rad], `aspect`, `znear`, `zfar`, or orthographic `xmag`, `ymag`),
/// `lights` (`KHR_lights_punctual`: `type`, `intensity` = colour × intensity [cd or lx],
/// world `position`, unit `direction` of travel, `range`, spot cone half-angles [rad]) and
/// `skipped`. Errors name the file and the element.
#[pyfunction]
pub fn load_gltf<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let s = py.detach(|| brdf_raster::io::load_gltf(&path)).map_err(raster_err)?;
    gltf_dict(py, s)
}

/// [`load_gltf`] from the bytes of a `.glb` or a self-contained `.gltf` (data URIs only).
#[pyfunction]
pub fn load_gltf_bytes<'py>(py: Python<'py>, data: Vec<u8>) -> PyResult<Bound<'py, PyDict>> {
    let s = py.detach(|| brdf_raster::io::load_gltf_bytes(&data)).map_err(raster_err)?;
    gltf_dict(py, s)
}

fn opt3(v: Option<Vec3>) -> Option<[f32; 3]> {
    v.map(|c| c.to_array())
}

fn obj_material<'py>(py: Python<'py>, m: &ObjMaterial) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &m.name)?;
    d.set_item("file", &m.file)?;
    d.set_item("Ka", opt3(m.ambient))?;
    d.set_item("Kd", opt3(m.diffuse))?;
    d.set_item("Ks", opt3(m.specular))?;
    d.set_item("Ke", opt3(m.emissive))?;
    d.set_item("Ns", m.shininess)?;
    d.set_item("d", m.dissolve)?;
    d.set_item("illum", m.illum)?;
    d.set_item("Pr", m.roughness)?;
    d.set_item("Pm", m.metallic)?;
    let textures = PyList::empty(py);
    for t in &m.textures {
        let td = PyDict::new(py);
        td.set_item("slot", &t.slot)?;
        td.set_item("file", &t.file)?;
        td.set_item("path", &t.path)?;
        td.set_item("bump_multiplier", t.bump_multiplier)?;
        td.set_item("clamp", t.clamp)?;
        td.set_item("offset", t.offset)?;
        td.set_item("scale", t.scale)?;
        textures.append(td)?;
    }
    d.set_item("textures", textures)?;
    Ok(d)
}

fn obj_dict<'py>(py: Python<'py>, s: ObjScene) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let parts = PyList::empty(py);
    for p in s.parts {
        let d = PyDict::new(py);
        d.set_item("uvs", p.mesh.uvs.as_deref().map(|u| vec2_array(py, u)).transpose()?)?;
        d.set_item("mesh", Py::new(py, mesh_of(p.mesh))?)?;
        d.set_item("material", p.material)?;
        d.set_item("name", p.name)?;
        parts.append(d)?;
    }
    out.set_item("parts", parts)?;
    let mats = PyList::empty(py);
    for m in &s.materials {
        mats.append(obj_material(py, m)?)?;
    }
    out.set_item("materials", mats)?;
    out.set_item("skipped", s.skipped)?;
    Ok(out)
}

/// Read an OBJ file with the materials of its `mtllib` files: a dict with `parts` (one per material
/// used: `mesh`, `material` index or None, `name`, `uvs` or None), `materials` (`name`, `file`,
/// `Ka`, `Kd`, `Ks`, `Ke`, `Ns`, `d`, `illum`, `Pr`, `Pm`, each None when absent, and `textures`:
/// `slot`, `file`, resolved `path`, `bump_multiplier`, `clamp`, `offset`, `scale`) and `skipped`
/// (a missing MTL file, an unknown `usemtl` name). Errors name the OBJ or MTL file and the element.
#[pyfunction]
pub fn load_obj_scene<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let s = py.detach(|| brdf_raster::io::load_obj_scene(&path)).map_err(|e: RasterError| raster_err(e))?;
    obj_dict(py, s)
}
