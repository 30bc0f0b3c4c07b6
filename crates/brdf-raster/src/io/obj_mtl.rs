//! Wavefront OBJ files with their MTL materials: one mesh per material used (`usemtl`), the
//! materials of the `mtllib` files (parsed by `tobj`'s MTL reader) and their texture references.
//!
//! The MTL format (Wavefront Technologies, *Advanced Visualizer Manual*, "MTL material format",
//! 1995) gives each `newmtl` the colours `Ka` (ambient), `Kd` (diffuse), `Ks` (specular), `Ke`
//! (emissive), the exponent `Ns` of the highlight `Ks (n·h)^Ns` (illumination model 2), the dissolve
//! `d` (opacity; `Tr = 1 − d` in some exporters), the illumination model `illum`, and texture maps
//! (`map_Kd`, `map_Ks`, `map_Ns`, `map_d`, `map_Bump`/`bump`, and `norm` and the `Pr`/`Pm`
//! roughness/metalness of the PBR extension that several exporters write). How these become
//! reflectance models is the caller's choice (the Python package documents its mapping); this
//! module reads and checks them:
//!
//! - the OBJ text is checked as by [`super::load_mesh`] (face indices, UTF-8, non-finite
//!   positions), then given to tobj with its `usemtl` and `mtllib` lines;
//! - `mtllib` files are read relative to the OBJ file's folder; one that does not exist is not an
//!   error (OBJ files often travel without theirs): it is listed in [`ObjScene::skipped`] and the
//!   faces that use its materials get the default material (`None`), as do faces after a `usemtl`
//!   naming no known material (also listed);
//! - an MTL file that cannot be parsed, or a colour or scalar that is not finite or is negative,
//!   is an error naming the MTL file and the material;
//! - texture statements keep their options (`-bm` bump multiplier, `-clamp`, `-o`/`-s` offsets and
//!   scales); the file name is resolved relative to the MTL file's folder but not opened.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::{Loaded, obj};
use crate::{Mesh, RasterError};

/// An OBJ file with its materials.
#[derive(Debug, Clone)]
pub struct ObjScene {
    /// One mesh per material used, in order of first use.
    pub parts: Vec<ObjPart>,
    /// The materials of the `mtllib` files, in file order.
    pub materials: Vec<ObjMaterial>,
    /// What was read but not used, one line each (a missing MTL file, an unknown `usemtl` name).
    pub skipped: Vec<String>,
}

/// The faces of an OBJ file that use one material.
#[derive(Debug, Clone)]
pub struct ObjPart {
    /// Their mesh (vertices renumbered as [`super::load_mesh`] does).
    pub mesh: Mesh,
    /// Index into [`ObjScene::materials`]; `None`: no (known) material.
    pub material: Option<usize>,
    /// The material's name, or `"default"`.
    pub name: String,
}

/// A texture statement of an MTL material.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjTexture {
    /// The statement: `map_Kd`, `map_Ks`, `map_Ns`, `map_d`, `map_Ka`, `map_Ke`, `map_Bump` (also
    /// for `bump`) or `norm`.
    pub slot: String,
    /// The file name as written (options removed).
    pub file: String,
    /// The file resolved against the MTL file's folder (not opened here).
    pub path: PathBuf,
    /// `-bm`: the bump multiplier (1 unless given).
    pub bump_multiplier: f32,
    /// `-clamp on`: clamp the texture coordinates to [0, 1] (else repeat).
    pub clamp: bool,
    /// `-o u v w`: texture-coordinate offset (0 unless given).
    pub offset: [f32; 3],
    /// `-s u v w`: texture-coordinate scale (1 unless given).
    pub scale: [f32; 3],
}

/// One `newmtl` of an MTL file; `None` where the statement is absent.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjMaterial {
    /// `newmtl` name.
    pub name: String,
    /// The MTL file it came from.
    pub file: String,
    /// `Ka`, ambient reflectance (linear RGB).
    pub ambient: Option<Vec3>,
    /// `Kd`, diffuse reflectance.
    pub diffuse: Option<Vec3>,
    /// `Ks`, specular reflectance.
    pub specular: Option<Vec3>,
    /// `Ke`, emitted colour.
    pub emissive: Option<Vec3>,
    /// `Ns`, the specular exponent of `(n·h)^Ns`.
    pub shininess: Option<f32>,
    /// `d` (or `1 − Tr`), opacity in [0, 1].
    pub dissolve: Option<f32>,
    /// `illum`, the illumination model number.
    pub illum: Option<u8>,
    /// `Pr`, roughness in [0, 1] (PBR extension of the format).
    pub roughness: Option<f32>,
    /// `Pm`, metalness in [0, 1] (PBR extension of the format).
    pub metallic: Option<f32>,
    /// Texture statements.
    pub textures: Vec<ObjTexture>,
}

/// Load an OBJ file and the materials of its `mtllib` files (see the module notes).
pub fn load_obj_scene(path: impl AsRef<Path>) -> Result<ObjScene, RasterError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let file_error = |problem: String| RasterError::File { path: name.clone(), problem };
    let bytes = super::read_regular_file(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    let text = obj::utf8(&bytes).map_err(file_error)?;
    let (filtered, skipped) = obj::filter_and_check(text, true).map_err(file_error)?;

    // tobj calls the loader for each `mtllib` (a `Fn`): what it finds is recorded here.
    let notes: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let failure: RefCell<Option<RasterError>> = RefCell::new(None);
    let files: RefCell<Vec<(String, PathBuf, usize)>> = RefCell::new(Vec::new());
    let loader = |lib: &Path| -> tobj::MTLLoadResult {
        let full = base.join(lib);
        let shown = full.display().to_string();
        let Ok(meta) = std::fs::metadata(&full) else {
            notes
                .borrow_mut()
                .push(format!("mtllib '{}': no such file; its materials are not applied", lib.display()));
            return Ok((Vec::new(), Default::default()));
        };
        let bytes = if meta.is_file() {
            super::read_regular_file(&full)
        } else {
            Err(RasterError::File {
                path: shown.clone(),
                problem: "cannot read the file: not a regular file".into(),
            })
        };
        let parsed = bytes.and_then(|b| {
            obj::utf8(&b).map_err(|p| RasterError::File { path: shown.clone(), problem: p })?;
            tobj::load_mtl_buf(&mut b.as_slice())
                .map_err(|e| RasterError::File { path: shown.clone(), problem: format!("bad MTL file: {e}") })
        });
        match parsed {
            Ok((mats, map)) => {
                files.borrow_mut().push((
                    shown,
                    full.parent().map(Path::to_path_buf).unwrap_or_default(),
                    mats.len(),
                ));
                Ok((mats, map))
            }
            Err(e) => {
                failure.borrow_mut().get_or_insert(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let mut reader = filtered.as_bytes();
    let result = tobj::load_obj_buf(&mut reader, &obj::options(), loader);
    if let Some(e) = failure.into_inner() {
        return Err(e);
    }
    let (models, mats) = result.map_err(|e| file_error(format!("bad OBJ file: {e}")))?;
    let mats = mats.map_err(|e| file_error(format!("bad MTL file: {e}")))?;

    // Which MTL file each material came from (tobj appends them in `mtllib` order).
    let mut origin: Vec<(String, PathBuf)> = Vec::with_capacity(mats.len());
    for (file, dir, n) in files.into_inner() {
        origin.extend(std::iter::repeat_n((file, dir), n));
    }
    let materials = mats
        .iter()
        .zip(&origin)
        .map(|(m, (file, dir))| material(m, file, dir))
        .collect::<Result<Vec<_>, RasterError>>()?;

    let mut skipped_notes = notes.into_inner();
    let known: HashMap<&str, usize> =
        materials.iter().enumerate().map(|(i, m)| (m.name.as_str(), i)).collect();
    let mut unknown: Vec<&str> = Vec::new();
    for line in filtered.lines() {
        if let Some(rest) = line.strip_prefix("usemtl") {
            let n = rest.trim();
            if !n.is_empty() && !known.contains_key(n) && !unknown.contains(&n) {
                unknown.push(n);
            }
        }
    }
    for n in unknown {
        skipped_notes
            .push(format!("usemtl '{n}': no such material in the MTL files; the default material is used"));
    }

    // Group tobj's models (one per object/material run) by material, in order of first use.
    let mut order: Vec<Option<usize>> = Vec::new();
    for m in &models {
        let id = m.mesh.material_id.filter(|&i| i < materials.len());
        if !order.contains(&id) {
            order.push(id);
        }
    }
    let mut parts = Vec::with_capacity(order.len());
    for (k, id) in order.iter().enumerate() {
        let group: Vec<&tobj::Model> =
            models.iter().filter(|m| m.mesh.material_id.filter(|&i| i < materials.len()) == *id).collect();
        // Short faces and polygons are counted once, on the first part.
        let none = obj::Skipped::default();
        let counts = if k == 0 { &skipped } else { &none };
        let Loaded { positions, indices, normals, colors, uvs, .. } = match obj::collect(&group, counts) {
            Ok(l) => l,
            Err(p) if p.starts_with("has no faces") => continue, // a material with only points or lines
            Err(p) => return Err(file_error(p)),
        };
        let part_name = id.map(|i| materials[i].name.clone()).unwrap_or_else(|| "default".into());
        let in_part = |e: RasterError| file_error(format!("material '{part_name}': {e}"));
        let mut mesh = Mesh::new(positions, indices, normals).map_err(in_part)?;
        if let Some(c) = colors {
            mesh = mesh.with_colors(c).map_err(in_part)?;
        }
        if let Some(u) = uvs {
            mesh = mesh.with_uvs(u).map_err(in_part)?;
        }
        parts.push(ObjPart { mesh, material: *id, name: part_name });
    }
    if parts.is_empty() {
        return Err(file_error("has no faces: no 'f' line with 3 or more corners".into()));
    }
    Ok(ObjScene { parts, materials, skipped: skipped_notes })
}

/// One tobj material, checked (finite, non-negative; `d`, `Pr`, `Pm` in [0, 1]).
fn material(m: &tobj::Material, file: &str, dir: &Path) -> Result<ObjMaterial, RasterError> {
    let err = |what: &str, problem: String| RasterError::File {
        path: file.to_owned(),
        problem: format!("newmtl {}: {what}: {problem}", m.name),
    };
    let color = |what: &str, c: Option<[f32; 3]>| -> Result<Option<Vec3>, RasterError> {
        match c.map(Vec3::from_array) {
            Some(v) if !v.is_finite() || v.min_element() < 0.0 => {
                Err(err(what, format!("{v} must be finite and >= 0 in every channel")))
            }
            other => Ok(other),
        }
    };
    let unit = |what: &str, x: Option<f32>| -> Result<Option<f32>, RasterError> {
        match x {
            Some(v) if !(0.0..=1.0).contains(&v) => Err(err(what, format!("{v} is outside [0, 1]"))),
            other => Ok(other),
        }
    };
    let number = |key: &str| -> Result<Option<f32>, RasterError> {
        match m.unknown_param.get(key) {
            None => Ok(None),
            Some(t) => t
                .split_whitespace()
                .next()
                .and_then(|w| w.parse::<f32>().ok())
                .map(Some)
                .ok_or_else(|| err(key, format!("'{t}' is not a number"))),
        }
    };
    let shininess = match m.shininess {
        Some(s) if !(s.is_finite() && s >= 0.0) => {
            return Err(err("Ns", format!("{s} must be finite and >= 0")));
        }
        other => other,
    };
    let dissolve = match (m.dissolve, number("Tr")?) {
        (Some(d), _) => Some(d),
        (None, Some(tr)) => Some(1.0 - tr),
        (None, None) => None,
    };
    let mut textures = Vec::new();
    let slots: [(&str, Option<&String>); 8] = [
        ("map_Kd", m.diffuse_texture.as_ref()),
        ("map_Ks", m.specular_texture.as_ref()),
        ("map_Ns", m.shininess_texture.as_ref()),
        ("map_d", m.dissolve_texture.as_ref()),
        ("map_Ka", m.ambient_texture.as_ref()),
        ("map_Ke", m.unknown_param.get("map_Ke")),
        ("map_Bump", m.normal_texture.as_ref()),
        ("norm", m.unknown_param.get("norm")),
    ];
    for (slot, statement) in slots {
        if let Some(s) = statement {
            textures.push(texture(slot, s, dir).map_err(|p| err(slot, p))?);
        }
    }
    Ok(ObjMaterial {
        name: m.name.clone(),
        file: file.to_owned(),
        ambient: color("Ka", m.ambient)?,
        diffuse: color("Kd", m.diffuse)?,
        specular: color("Ks", m.specular)?,
        emissive: color("Ke", m.emissive)?,
        shininess,
        dissolve: unit(if m.dissolve.is_some() { "d" } else { "Tr" }, dissolve)?,
        illum: m.illumination_model,
        roughness: unit("Pr", number("Pr")?)?,
        metallic: unit("Pm", number("Pm")?)?,
        textures,
    })
}

/// A texture statement's options and file name (MTL format, "Options for texture map statements").
fn texture(slot: &str, statement: &str, dir: &Path) -> Result<ObjTexture, String> {
    let words: Vec<&str> = statement.split_whitespace().collect();
    let mut tex = ObjTexture {
        slot: slot.to_owned(),
        file: String::new(),
        path: PathBuf::new(),
        bump_multiplier: 1.0,
        clamp: false,
        offset: [0.0; 3],
        scale: [1.0; 3],
    };
    let num = |w: Option<&&str>, opt: &str| -> Result<f32, String> {
        w.and_then(|w| w.parse::<f32>().ok())
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("option {opt} expects a finite number"))
    };
    let mut i = 0;
    while i < words.len() && words[i].starts_with('-') && words[i].len() > 1 {
        let opt = words[i];
        match opt {
            "-bm" | "-boost" | "-texres" => {
                let x = num(words.get(i + 1), opt)?;
                if opt == "-bm" {
                    tex.bump_multiplier = x;
                }
                i += 2;
            }
            "-clamp" | "-blendu" | "-blendv" | "-cc" | "-imfchan" | "-type" => {
                let v = words.get(i + 1).ok_or_else(|| format!("option {opt} expects a value"))?;
                if opt == "-clamp" {
                    tex.clamp = v.eq_ignore_ascii_case("on");
                }
                i += 2;
            }
            "-mm" => {
                num(words.get(i + 1), opt)?;
                num(words.get(i + 2), opt)?;
                i += 3;
            }
            "-o" | "-s" | "-t" => {
                let mut v = if opt == "-s" { [1.0; 3] } else { [0.0; 3] };
                v[0] = num(words.get(i + 1), opt)?;
                let mut k = 1;
                while k < 3 && words.get(i + 1 + k).and_then(|w| w.parse::<f32>().ok()).is_some() {
                    v[k] = num(words.get(i + 1 + k), opt)?;
                    k += 1;
                }
                match opt {
                    "-o" => tex.offset = v,
                    "-s" => tex.scale = v,
                    _ => {}
                }
                i += 1 + k;
            }
            _ => return Err(format!("unknown option '{opt}'")),
        }
    }
    if i >= words.len() {
        return Err(format!("'{statement}' names no file"));
    }
    tex.file = words[i..].join(" ");
    tex.path = dir.join(tex.file.replace('\\', "/"));
    Ok(tex)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_parsed_and_the_file_is_what_remains() {
        let t = texture("map_Bump", "-bm 0.5 -s 2 2 -clamp on bricks normal.png", Path::new("/a")).unwrap();
        assert_eq!(t.bump_multiplier, 0.5);
        assert_eq!(t.scale, [2.0, 2.0, 1.0]);
        assert!(t.clamp);
        assert_eq!(t.file, "bricks normal.png");
        assert_eq!(t.path, Path::new("/a/bricks normal.png"));
        assert!(texture("map_Kd", "-bm", Path::new(".")).is_err());
        assert!(texture("map_Kd", "-zz 1 a.png", Path::new(".")).is_err());
    }

    #[test]
    fn materials_split_the_faces_and_a_missing_mtl_is_listed() {
        let dir = std::env::temp_dir().join(format!("brdf-obj-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl red\nKd 0.8 0.1 0.1\nKs 0.2 0.2 0.2\nNs 50\nd 0.9\nKe 0 0 0\nmap_Kd -s 2 2 red.png\n\
             newmtl blue\nKd 0.1 0.1 0.8\nnorm n.png\nPr 0.4\n",
        )
        .unwrap();
        let obj = "mtllib m.mtl\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
                   usemtl red\nf 1 2 3\nusemtl blue\nf 2 4 3\nusemtl nothing\nf 1 2 4\n";
        std::fs::write(dir.join("a.obj"), obj).unwrap();
        let s = load_obj_scene(dir.join("a.obj")).unwrap();
        assert_eq!(s.materials.len(), 2);
        assert_eq!(s.materials[0].diffuse, Some(Vec3::new(0.8, 0.1, 0.1)));
        assert_eq!(s.materials[0].shininess, Some(50.0));
        assert_eq!(s.materials[0].textures[0].scale, [2.0, 2.0, 1.0]);
        assert_eq!(s.materials[1].roughness, Some(0.4));
        assert_eq!(s.materials[1].textures[0].slot, "norm");
        let names: Vec<&str> = s.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["red", "blue", "default"]);
        assert!(s.parts.iter().all(|p| p.mesh.triangle_count() == 1));
        assert_eq!(s.skipped.len(), 2, "{:?}", s.skipped);
        std::fs::write(dir.join("m.mtl"), "newmtl red\nKd nan 0 0\n").unwrap();
        let e = load_obj_scene(dir.join("a.obj")).unwrap_err().to_string();
        assert!(e.contains("m.mtl") && e.contains("newmtl red") && e.contains("Kd"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
