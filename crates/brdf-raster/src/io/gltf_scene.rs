//! glTF 2.0 scenes (`.gltf` with `.bin` files or data URIs, and binary `.glb`), read with the `gltf`
//! crate (JSON, GLB container, validation) and decoded here (buffers, accessors, node hierarchy).
//!
//! What is read (Khronos, *glTF 2.0 Specification*, 2021):
//! - the default scene (else the first) and its node tree; every node's matrix or TRS is composed
//!   parent × child into a world matrix ([`GltfPrimitive::transform`], column vectors);
//! - every mesh primitive of mode TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN (strips and fans are
//!   turned into triangles with the specification's vertex order), with its indices (or none),
//!   POSITION, NORMAL, TANGENT, TEXCOORD_0 and COLOR_0 (alpha dropped; unsigned normalised integers
//!   mapped to [0, 1]); POINTS and LINES primitives are skipped and listed in
//!   [`GltfScene::skipped`];
//! - metallic-roughness materials ([`GltfMaterial`]) with their factors and texture references,
//!   alpha mode and cutoff, double-sidedness, `KHR_materials_emissive_strength`;
//! - textures (image and sampler: wrap modes, filters) and images as their **encoded bytes** with
//!   their MIME type ([`GltfImage`]): decoding is left to the caller (the Python package uses Pillow);
//! - cameras (perspective and orthographic) and `KHR_lights_punctual` lights, placed by their nodes.
//!
//! Every failure is a [`RasterError::File`] naming the file and the element as a JSON path
//! (`meshes[0].primitives[1].attributes.POSITION: ...`): malformed JSON or GLB, a failed validation
//! (such as an index to nothing, or an unsupported entry of `extensionsRequired`), missing or short
//! buffers, accessors reaching past their buffer views or views past their buffers, component
//! types the specification does not allow for an attribute, sparse accessors (not supported), a
//! node cycle, an index past the vertices. The accessors are decoded here, after their byte ranges
//! have been checked with overflow-checked arithmetic, so no allocation is sized by a count the
//! file's length does not back.

use std::path::{Path, PathBuf};

use base64::Engine as _;
use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use crate::mesh::MAX_ELEMENTS;
use crate::{Mesh, RasterError};

/// Deepest node nesting followed (a bound on recursion for hostile files; real scenes nest a few
/// levels).
pub const MAX_NODE_DEPTH: usize = 256;

/// A glTF scene, decoded.
#[derive(Debug, Clone)]
pub struct GltfScene {
    /// One entry per (node, mesh primitive) drawn.
    pub primitives: Vec<GltfPrimitive>,
    /// The document's materials, in order (primitives refer to them by index).
    pub materials: Vec<GltfMaterial>,
    /// The document's textures, in order.
    pub textures: Vec<GltfTexture>,
    /// The document's images, in order, encoded.
    pub images: Vec<GltfImage>,
    /// Cameras placed by the nodes that use them, in node order.
    pub cameras: Vec<GltfCamera>,
    /// `KHR_lights_punctual` lights placed by their nodes.
    pub lights: Vec<GltfLight>,
    /// What was read but not drawn, one line each (e.g. a primitive of points).
    pub skipped: Vec<String>,
}

/// One mesh primitive as a node draws it.
#[derive(Debug, Clone)]
pub struct GltfPrimitive {
    /// The geometry in the mesh's own space, with the file's texture coordinates, colours and
    /// tangents when it has them.
    pub mesh: Mesh,
    /// Object → world (column vectors), the product of the node's ancestors' transforms and its own.
    pub transform: Mat4,
    /// Index into [`GltfScene::materials`]; `None`: the specification's default material.
    pub material: Option<usize>,
    /// `"node name/mesh name/primitive index"` for messages.
    pub name: String,
}

/// glTF's alpha modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AlphaMode {
    /// Alpha ignored.
    Opaque,
    /// Fragments with alpha below the cutoff are discarded.
    Mask,
    /// Alpha blending (over operator).
    Blend,
}

/// A texture reference of a material: texture index and the `TEXCOORD_n` set it reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    /// Index into [`GltfScene::textures`].
    pub texture: usize,
    /// The texture-coordinate set (only set 0 is read).
    pub tex_coord: u32,
    /// Normal map `scale` or occlusion `strength` (1 for the others).
    pub scale: f32,
}

/// A metallic-roughness material (glTF 2.0 §3.9) with its factors and textures.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfMaterial {
    /// Name, or `"material N"`.
    pub name: String,
    /// Linear RGBA base colour factor.
    pub base_color: Vec4,
    /// Metalness factor in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness factor in [0, 1] (the GGX α is its square).
    pub roughness: f32,
    /// Emissive factor (linear RGB) times `KHR_materials_emissive_strength`.
    pub emissive: Vec3,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
    /// MASK's cutoff (default 0.5).
    pub alpha_cutoff: f32,
    /// Whether back faces are drawn (and lit with the flipped normal).
    pub double_sided: bool,
    /// sRGB-encoded base colour (RGB) and alpha (A) texture.
    pub base_color_texture: Option<TextureRef>,
    /// Linear texture: G = roughness, B = metalness (multiplying the factors).
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Linear tangent-space normal map (`scale` multiplies its x and y).
    pub normal_texture: Option<TextureRef>,
    /// Linear occlusion in R (`scale` is the strength).
    pub occlusion_texture: Option<TextureRef>,
    /// sRGB-encoded emissive texture (multiplying the factor).
    pub emissive_texture: Option<TextureRef>,
}

impl GltfMaterial {
    /// The specification's default material (no `material` on a primitive): white, fully metallic,
    /// fully rough.
    pub fn default_material() -> Self {
        Self {
            name: "default".into(),
            base_color: Vec4::ONE,
            metallic: 1.0,
            roughness: 1.0,
            emissive: Vec3::ZERO,
            alpha_mode: AlphaMode::Opaque,
            alpha_cutoff: 0.5,
            double_sided: false,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive_texture: None,
        }
    }

    /// The parameters of brdf-core's `cook_torrance` that are this material's BRDF (glTF 2.0
    /// Appendix B with the simplification of the diffuse mix): GGX distribution with
    /// `α = roughness²`, height-correlated Smith masking, Schlick's Fresnel with
    /// `F0 = mix(0.04, baseColor, metallic)`, specular scale 1, and the diffuse term
    /// `(1 − metallic)·baseColor/π`, i.e. `kd = (1 − metallic)·baseColor`.
    ///
    /// Returns `(kd, f0, alpha)` from the factors (a texture multiplies them per texel).
    pub fn cook_torrance(&self) -> (Vec3, Vec3, f32) {
        let base = self.base_color.truncate();
        let m = self.metallic;
        let kd = base * (1.0 - m);
        let f0 = Vec3::splat(0.04).lerp(base, m);
        (kd, f0, self.roughness * self.roughness)
    }
}

/// glTF sampler wrap modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    /// Clamp to the edge texel.
    Clamp,
    /// Repeat mirrored.
    Mirror,
    /// Repeat.
    Repeat,
}

/// A texture: an image and how it is sampled.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfTexture {
    /// Index into [`GltfScene::images`].
    pub image: usize,
    /// Wrap along u and along v.
    pub wrap: [Wrap; 2],
    /// Magnification filter is nearest (else linear).
    pub mag_nearest: bool,
    /// Minification uses mip-maps (unset or a `*_MIPMAP_*` filter; else no mip-maps).
    pub mipmaps: bool,
}

/// An image, still encoded.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfImage {
    /// Name, its URI, or `"image N"`.
    pub name: String,
    /// `image/png`, `image/jpeg`, or what the file says.
    pub mime_type: Option<String>,
    /// The encoded bytes (PNG, JPEG...).
    pub bytes: Vec<u8>,
}

/// A camera as placed in the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfCamera {
    /// Camera name, or its node's.
    pub name: String,
    /// Camera → world; the camera looks along its local −z with +y up.
    pub transform: Mat4,
    /// The projection.
    pub projection: GltfProjection,
}

/// A glTF camera projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GltfProjection {
    /// Perspective: vertical field of view in radians, optional aspect ratio, near and optional far.
    Perspective {
        /// Vertical field of view \[rad\].
        yfov: f32,
        /// Width / height, if the file fixes it.
        aspect: Option<f32>,
        /// Near plane distance.
        znear: f32,
        /// Far plane distance (`None`: infinite).
        zfar: Option<f32>,
    },
    /// Orthographic: half extents and planes.
    Orthographic {
        /// Half width.
        xmag: f32,
        /// Half height.
        ymag: f32,
        /// Near plane distance.
        znear: f32,
        /// Far plane distance.
        zfar: f32,
    },
}

/// The kinds of `KHR_lights_punctual`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GltfLightKind {
    /// Infinitely far, travelling along the node's −z; intensity in lux.
    Directional,
    /// At the node's origin; intensity in candela, inverse-square falloff.
    Point,
    /// Point light limited to a cone about −z, angles in radians.
    Spot {
        /// Full intensity within this angle from the axis.
        inner: f32,
        /// No light beyond this angle.
        outer: f32,
    },
}

/// A `KHR_lights_punctual` light as placed in the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfLight {
    /// Name, or `"light N"`.
    pub name: String,
    /// The kind (and cone angles).
    pub kind: GltfLightKind,
    /// Linear RGB colour times intensity.
    pub intensity: Vec3,
    /// World position (point and spot).
    pub position: Vec3,
    /// World direction of travel (directional and spot), unit length.
    pub direction: Vec3,
    /// The file's range (distance beyond which the light is cut off), when given.
    pub range: Option<f32>,
}

/// Load a `.gltf` (with its external `.bin` and image files, or data URIs) or `.glb` file.
pub fn load_gltf(path: impl AsRef<Path>) -> Result<GltfScene, RasterError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = super::read_regular_file(path)?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    decode(&bytes, Some(&base)).map_err(|problem| RasterError::File { path: name, problem })
}

/// Load glTF or GLB bytes held in memory; external files are refused (only the GLB chunk and data
/// URIs can hold buffers and images). Errors name the source as `<memory>`.
pub fn load_gltf_bytes(bytes: &[u8]) -> Result<GltfScene, RasterError> {
    decode(bytes, None).map_err(|problem| RasterError::File { path: "<memory>".into(), problem })
}

fn decode(bytes: &[u8], base: Option<&Path>) -> Result<GltfScene, String> {
    if bytes.starts_with(b"glTF") {
        // The gltf crate subtracts the 12-byte header from the declared length unchecked: refuse a
        // header shorter than itself here (an arithmetic overflow panics in debug builds).
        let declared = bytes.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
        match declared {
            Some(n) if (12..=bytes.len()).contains(&n) => {}
            Some(n) => {
                return Err(format!(
                    "invalid GLB container: its header declares {n} bytes, the file has {}",
                    bytes.len()
                ));
            }
            None => {
                return Err(format!(
                    "invalid GLB container: {} bytes, shorter than its 12-byte header",
                    bytes.len()
                ));
            }
        }
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| describe(&e))?;
    validate(document.as_json())?;
    let mut blob = blob;
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for buffer in document.buffers() {
        let i = buffer.index();
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| format!("buffers[{i}]: refers to the GLB binary chunk, which is absent"))?,
            gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, base).map_err(|e| format!("buffers[{i}]: {e}"))?
            }
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "buffers[{i}]: declares {} bytes but holds {} (truncated)",
                buffer.length(),
                data.len()
            ));
        }
        buffers.push(data);
    }
    for view in document.views() {
        let end = view.offset().checked_add(view.length());
        let len = buffers[view.buffer().index()].len();
        if end.is_none_or(|e| e > len) {
            return Err(format!(
                "bufferViews[{}]: bytes {}..{} reach past the end of buffers[{}] ({len} bytes)",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index()
            ));
        }
    }
    let images = document
        .images()
        .map(|image| {
            let i = image.index();
            let (bytes, mime, uri_name) = match image.source() {
                gltf::image::Source::View { view, mime_type } => {
                    let data = &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()];
                    (data.to_vec(), Some(mime_type.to_owned()), None)
                }
                gltf::image::Source::Uri { uri, mime_type } => {
                    let data = read_uri(uri, base).map_err(|e| format!("images[{i}]: {e}"))?;
                    let mime = mime_type.map(str::to_owned).or_else(|| data_uri_mime(uri));
                    let shown = if uri.starts_with("data:") { None } else { Some(uri.to_owned()) };
                    (data, mime, shown)
                }
            };
            let name = image.name().map(str::to_owned).or(uri_name).unwrap_or_else(|| format!("image {i}"));
            Ok(GltfImage { name, mime_type: mime, bytes })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let textures = document
        .textures()
        .map(|t| {
            let s = t.sampler();
            let wrap = |w: gltf::texture::WrappingMode| match w {
                gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
                gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
                gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
            };
            use gltf::texture::{MagFilter, MinFilter};
            GltfTexture {
                image: t.source().index(),
                wrap: [wrap(s.wrap_s()), wrap(s.wrap_t())],
                mag_nearest: s.mag_filter() == Some(MagFilter::Nearest),
                mipmaps: !matches!(s.min_filter(), Some(MinFilter::Nearest | MinFilter::Linear)),
            }
        })
        .collect();
    let materials = document
        .materials()
        .map(|m| check_factors(&m).map(|()| material(&m)))
        .collect::<Result<Vec<_>, String>>()?;

    let mut scene = GltfScene {
        primitives: Vec::new(),
        materials,
        textures,
        images,
        cameras: Vec::new(),
        lights: Vec::new(),
        skipped: Vec::new(),
    };
    let Some(root) = document.default_scene().or_else(|| document.scenes().next()) else {
        return Err("has no scene to show (no 'scenes')".into());
    };
    let mut path = Vec::new();
    let mut triangles = 0usize;
    for node in root.nodes() {
        visit(&node, Mat4::IDENTITY, &buffers, &mut scene, &mut path, &mut triangles)?;
    }
    if scene.primitives.is_empty() {
        return Err(format!("scenes[{}]: draws no triangles", root.index()));
    }
    Ok(scene)
}

/// A gltf error with the element's JSON path when validation found it.
/// The checks of `gltf::Gltf::from_slice`, preceded by the one it lacks: gltf-json 1.4's validation looks
/// up a primitive's POSITION accessor by index before it checks that the index exists, and panics on a
/// file whose index is out of range (found by `brdf-fuzz run gltf`).
fn validate(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::{Checked, Validate};
    let n = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            if let Some(a) = prim.attributes.get(&Checked::Valid(Semantic::Positions)) {
                if a.value() >= n {
                    return Err(format!(
                        "invalid glTF: meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does \
                         not exist (the file has {n})",
                        a.value()
                    ));
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| errors.push((path(), error)));
    if errors.is_empty() { Ok(()) } else { Err(describe(&gltf::Error::Validation(errors))) }
}

fn describe(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(list) => {
            let items: Vec<String> =
                list.iter().take(8).map(|(path, err)| format!("{path}: {err}")).collect();
            format!("invalid glTF: {}", items.join("; "))
        }
        gltf::Error::Binary(b) => format!("invalid GLB container: {b}"),
        other => format!("invalid glTF: {other}"),
    }
}

/// The factors of material `m` within the ranges of the glTF 2.0 schema (a file outside them is
/// invalid: a metalness of 4.7 would make the diffuse weight 1 − metallic negative).
fn check_factors(m: &gltf::Material<'_>) -> Result<(), String> {
    let at = format!("materials[{}]", m.index().unwrap_or(0));
    let pbr = m.pbr_metallic_roughness();
    let in_unit = |what: &str, x: f32| {
        if (0.0..=1.0).contains(&x) { Ok(()) } else { Err(format!("{at}.{what}: {x} is outside [0, 1]")) }
    };
    for (i, &c) in pbr.base_color_factor().iter().enumerate() {
        in_unit(&format!("pbrMetallicRoughness.baseColorFactor[{i}]"), c)?;
    }
    in_unit("pbrMetallicRoughness.metallicFactor", pbr.metallic_factor())?;
    in_unit("pbrMetallicRoughness.roughnessFactor", pbr.roughness_factor())?;
    for (i, &c) in m.emissive_factor().iter().enumerate() {
        in_unit(&format!("emissiveFactor[{i}]"), c)?;
    }
    if let Some(o) = m.occlusion_texture() {
        in_unit("occlusionTexture.strength", o.strength())?;
    }
    if let Some(n) = m.normal_texture() {
        if !n.scale().is_finite() {
            return Err(format!("{at}.normalTexture.scale: {} is not finite", n.scale()));
        }
    }
    if let Some(s) = m.emissive_strength() {
        if !(s >= 0.0 && s.is_finite()) {
            return Err(format!(
                "{at}.extensions.KHR_materials_emissive_strength: {s} must be finite and >= 0"
            ));
        }
    }
    if let Some(c) = m.alpha_cutoff() {
        if !(c >= 0.0 && c.is_finite()) {
            return Err(format!("{at}.alphaCutoff: {c} must be finite and >= 0"));
        }
    }
    Ok(())
}

fn material(m: &gltf::Material<'_>) -> GltfMaterial {
    let pbr = m.pbr_metallic_roughness();
    let tex = |info: Option<gltf::texture::Info<'_>>| {
        info.map(|i| TextureRef { texture: i.texture().index(), tex_coord: i.tex_coord(), scale: 1.0 })
    };
    GltfMaterial {
        name: m.name().map(str::to_owned).unwrap_or_else(|| format!("material {}", m.index().unwrap_or(0))),
        base_color: Vec4::from_array(pbr.base_color_factor()),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        emissive: Vec3::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask,
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        alpha_cutoff: m.alpha_cutoff().unwrap_or(0.5),
        double_sided: m.double_sided(),
        base_color_texture: tex(pbr.base_color_texture()),
        metallic_roughness_texture: tex(pbr.metallic_roughness_texture()),
        normal_texture: m.normal_texture().map(|n| TextureRef {
            texture: n.texture().index(),
            tex_coord: n.tex_coord(),
            scale: n.scale(),
        }),
        occlusion_texture: m.occlusion_texture().map(|o| TextureRef {
            texture: o.texture().index(),
            tex_coord: o.tex_coord(),
            scale: o.strength(),
        }),
        emissive_texture: tex(m.emissive_texture()),
    }
}

fn visit(
    node: &gltf::Node<'_>,
    parent: Mat4,
    buffers: &[Vec<u8>],
    scene: &mut GltfScene,
    path: &mut Vec<usize>,
    triangles: &mut usize,
) -> Result<(), String> {
    let i = node.index();
    if path.contains(&i) {
        return Err(format!("nodes[{i}]: is its own ancestor (a cycle in the node hierarchy)"));
    }
    if path.len() >= MAX_NODE_DEPTH {
        return Err(format!("nodes[{i}]: nested deeper than {MAX_NODE_DEPTH} levels"));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    if !local.is_finite() {
        return Err(format!("nodes[{i}]: its transform is not finite"));
    }
    let world = parent * local;
    if !world.is_finite() {
        return Err(format!("nodes[{i}]: its world transform overflows (not finite)"));
    }
    let node_name = node.name().map(str::to_owned).unwrap_or_else(|| format!("node {i}"));
    if let Some(mesh) = node.mesh() {
        for (p, prim) in mesh.primitives().enumerate() {
            let at = format!("meshes[{}].primitives[{p}]", mesh.index());
            let label = format!("{node_name}/{}/{p}", mesh.name().unwrap_or("mesh"));
            match primitive(&prim, buffers, &at)? {
                None => {
                    scene.skipped.push(format!("{at} ({label}): mode {:?} is not triangles", prim.mode()))
                }
                Some(m) => {
                    *triangles += m.triangle_count();
                    if *triangles > MAX_ELEMENTS {
                        return Err(format!("more than {MAX_ELEMENTS} triangles in the scene"));
                    }
                    scene.primitives.push(GltfPrimitive {
                        mesh: m,
                        transform: world,
                        material: prim.material().index(),
                        name: label,
                    });
                }
            }
        }
    }
    if let Some(cam) = node.camera() {
        let projection = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => GltfProjection::Perspective {
                yfov: p.yfov(),
                aspect: p.aspect_ratio(),
                znear: p.znear(),
                zfar: p.zfar(),
            },
            gltf::camera::Projection::Orthographic(o) => GltfProjection::Orthographic {
                xmag: o.xmag(),
                ymag: o.ymag(),
                znear: o.znear(),
                zfar: o.zfar(),
            },
        };
        let name = cam.name().map(str::to_owned).unwrap_or_else(|| node_name.clone());
        scene.cameras.push(GltfCamera { name, transform: world, projection });
    }
    if let Some(light) = node.light() {
        use gltf::khr_lights_punctual::Kind;
        let kind = match light.kind() {
            Kind::Directional => GltfLightKind::Directional,
            Kind::Point => GltfLightKind::Point,
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                GltfLightKind::Spot { inner: inner_cone_angle, outer: outer_cone_angle }
            }
        };
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let (intensity, position) =
            (Vec3::from_array(light.color()) * light.intensity(), world.transform_point3(Vec3::ZERO));
        if !intensity.is_finite() || !position.is_finite() || direction == Vec3::ZERO {
            return Err(format!("nodes[{i}]: its light has a non-finite intensity, position or direction"));
        }
        scene.lights.push(GltfLight {
            name: light.name().map(str::to_owned).unwrap_or_else(|| format!("light {}", light.index())),
            kind,
            intensity,
            position,
            direction,
            range: light.range(),
        });
    }
    path.push(i);
    for child in node.children() {
        visit(&child, world, buffers, scene, path, triangles)?;
    }
    path.pop();
    Ok(())
}

/// A primitive's mesh; `None` for points and lines.
fn primitive(prim: &gltf::Primitive<'_>, buffers: &[Vec<u8>], at: &str) -> Result<Option<Mesh>, String> {
    let mode = prim.mode();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(None);
    }
    let attr = |semantic: Semantic| prim.get(&semantic);
    let pos_acc = attr(Semantic::Positions).ok_or_else(|| format!("{at}: has no POSITION attribute"))?;
    let positions: Vec<Vec3> = read_floats(
        &pos_acc,
        buffers,
        &[Dimensions::Vec3],
        &[DataType::F32],
        &format!("{at}.attributes.POSITION"),
    )?
    .chunks_exact(3)
    .map(|c| Vec3::new(c[0], c[1], c[2]))
    .collect();
    let n = positions.len();
    let same_count = |what: &str, count: usize| {
        if count == n {
            Ok(())
        } else {
            Err(format!("{at}.attributes.{what}: {count} values for {n} positions"))
        }
    };
    let normals = match attr(Semantic::Normals) {
        None => None,
        Some(acc) => {
            let v = read_floats(
                &acc,
                buffers,
                &[Dimensions::Vec3],
                &[DataType::F32],
                &format!("{at}.attributes.NORMAL"),
            )?;
            same_count("NORMAL", v.len() / 3)?;
            Some(v.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect::<Vec<_>>())
        }
    };
    let tangents = match attr(Semantic::Tangents) {
        None => None,
        Some(acc) => {
            let v = read_floats(
                &acc,
                buffers,
                &[Dimensions::Vec4],
                &[DataType::F32],
                &format!("{at}.attributes.TANGENT"),
            )?;
            same_count("TANGENT", v.len() / 4)?;
            // w is ±1 by the specification; a writer's rounding is not worth refusing the file.
            Some(
                v.chunks_exact(4)
                    .map(|c| Vec4::new(c[0], c[1], c[2], if c[3] < 0.0 { -1.0 } else { 1.0 }))
                    .collect::<Vec<_>>(),
            )
        }
    };
    let uvs = match attr(Semantic::TexCoords(0)) {
        None => None,
        Some(acc) => {
            let types = [DataType::F32, DataType::U8, DataType::U16];
            let v = read_floats(
                &acc,
                buffers,
                &[Dimensions::Vec2],
                &types,
                &format!("{at}.attributes.TEXCOORD_0"),
            )?;
            same_count("TEXCOORD_0", v.len() / 2)?;
            Some(v.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect::<Vec<_>>())
        }
    };
    let colors = match attr(Semantic::Colors(0)) {
        None => None,
        Some(acc) => {
            let types = [DataType::F32, DataType::U8, DataType::U16];
            let dims = [Dimensions::Vec3, Dimensions::Vec4];
            let k = if acc.dimensions() == Dimensions::Vec4 { 4 } else { 3 };
            let v = read_floats(&acc, buffers, &dims, &types, &format!("{at}.attributes.COLOR_0"))?;
            same_count("COLOR_0", v.len() / k)?;
            Some(v.chunks_exact(k).map(|c| Vec3::new(c[0], c[1], c[2])).collect::<Vec<_>>())
        }
    };
    let order: Vec<u32> = match prim.indices() {
        Some(acc) => read_indices(&acc, buffers, &format!("{at}.indices"))?,
        None => (0..n as u32).collect(),
    };
    if let Some(bad) = order.iter().position(|&i| i as usize >= n) {
        return Err(format!("{at}.indices: index {} (at {bad}) is past the {n} vertices", order[bad]));
    }
    let indices: Vec<[u32; 3]> = match mode {
        Mode::Triangles => order.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        // §3.7.2.1: strip triangle i is {i, i + (1 + i%2), i + (2 − i%2)}; fan triangle i is
        // {i + 1, i + 2, 0}.
        Mode::TriangleStrip => (0..order.len().saturating_sub(2))
            .map(|i| [order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]])
            .collect(),
        _ => (0..order.len().saturating_sub(2)).map(|i| [order[i + 1], order[i + 2], order[0]]).collect(),
    };
    if indices.is_empty() {
        return Err(format!("{at}: has no triangles ({} indices)", order.len()));
    }
    let mut mesh = Mesh::new(positions, indices, normals).map_err(|e| format!("{at}: {e}"))?;
    if let Some(uvs) = uvs {
        mesh = mesh.with_uvs(uvs).map_err(|e| format!("{at}: {e}"))?;
    }
    if let Some(colors) = colors {
        mesh = mesh.with_colors(colors).map_err(|e| format!("{at}: {e}"))?;
    }
    if let Some(tangents) = tangents {
        mesh = mesh.with_tangents(tangents).map_err(|e| format!("{at}: {e}"))?;
    }
    Ok(Some(mesh))
}

/// The byte range check of an accessor: `(bytes of its view from the accessor's start, stride,
/// element size)`, each element inside the view, the view inside its buffer (checked at load).
fn accessor_bytes<'b>(
    acc: &gltf::Accessor<'_>,
    buffers: &'b [Vec<u8>],
    at: &str,
) -> Result<(&'b [u8], usize, usize), String> {
    if acc.sparse().is_some() {
        return Err(format!("{at}: accessors[{}] is sparse, which is not supported", acc.index()));
    }
    let view = acc.view().ok_or_else(|| {
        format!("{at}: accessors[{}] has no buffer view (all zeros is not supported)", acc.index())
    })?;
    let elem = acc.size();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "{at}: bufferViews[{}] has a stride of {stride} bytes, less than one element ({elem})",
            view.index()
        ));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("{at}: accessors[{}] has count 0", acc.index()));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(acc.offset()));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{at}: accessors[{}] ({count} elements of {elem} bytes, stride {stride}, offset {}) reaches past \
             the end of bufferViews[{}] ({} bytes)",
            acc.index(),
            acc.offset(),
            view.index(),
            view.length()
        ));
    }
    let data = &buffers[view.buffer().index()][view.offset() + acc.offset()..view.offset() + view.length()];
    Ok((data, stride, elem))
}

/// An accessor's components as f32 (unsigned normalised integers mapped to [0, 1]), checking the
/// element type and component type against what the attribute allows; non-finite values refused.
fn read_floats(
    acc: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    dims: &[Dimensions],
    types: &[DataType],
    at: &str,
) -> Result<Vec<f32>, String> {
    if !dims.contains(&acc.dimensions()) || !types.contains(&acc.data_type()) {
        return Err(format!(
            "{at}: accessors[{}] is {:?} of {:?}; expected {} of {}",
            acc.index(),
            acc.dimensions(),
            acc.data_type(),
            dims.iter().map(|d| format!("{d:?}")).collect::<Vec<_>>().join(" or "),
            types.iter().map(|t| format!("{t:?}")).collect::<Vec<_>>().join(" or ")
        ));
    }
    if acc.data_type() != DataType::F32 && !acc.normalized() {
        return Err(format!("{at}: accessors[{}] holds integers that are not normalized", acc.index()));
    }
    let (data, stride, elem) = accessor_bytes(acc, buffers, at)?;
    let k = acc.dimensions().multiplicity();
    let mut out = Vec::with_capacity(acc.count() * k);
    for e in 0..acc.count() {
        let item = &data[e * stride..e * stride + elem];
        match acc.data_type() {
            DataType::F32 => {
                out.extend(item.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            }
            DataType::U8 => out.extend(item.iter().map(|&b| f32::from(b) / 255.0)),
            _ => out
                .extend(item.chunks_exact(2).map(|b| f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0)),
        }
    }
    if let Some(bad) = out.iter().position(|x| !x.is_finite()) {
        return Err(format!("{at}: accessors[{}] element {} is not finite", acc.index(), bad / k));
    }
    Ok(out)
}

fn read_indices(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>], at: &str) -> Result<Vec<u32>, String> {
    if acc.dimensions() != Dimensions::Scalar
        || !matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "{at}: accessors[{}] is {:?} of {:?}; indices must be Scalar of U8, U16 or U32",
            acc.index(),
            acc.dimensions(),
            acc.data_type()
        ));
    }
    let (data, stride, elem) = accessor_bytes(acc, buffers, at)?;
    Ok((0..acc.count())
        .map(|e| {
            let b = &data[e * stride..e * stride + elem];
            match elem {
                1 => u32::from(b[0]),
                2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            }
        })
        .collect())
}

/// The bytes a buffer or image URI names: a `data:` URI (base64), or a file relative to `base`.
fn read_uri(uri: &str, base: Option<&Path>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or_else(|| "a data URI without ';base64,' is not supported".to_string())?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| format!("its data URI is not valid base64 ({e})"));
    }
    if uri.contains("://") {
        return Err(format!("refers to '{uri}': only relative file names and data URIs are read"));
    }
    let base =
        base.ok_or_else(|| format!("refers to the file '{uri}', but the glTF was read from memory"))?;
    let relative =
        percent_decode(uri).ok_or_else(|| format!("'{uri}' is not a valid percent-encoded URI"))?;
    let path = base.join(relative);
    super::read_regular_file(&path).map_err(|e| match e {
        RasterError::File { problem, .. } => format!("'{}': {problem}", path.display()),
        other => other.to_string(),
    })
}

fn data_uri_mime(uri: &str) -> Option<String> {
    let rest = uri.strip_prefix("data:")?;
    let (mime, _) = rest.split_once(';')?;
    (!mime.is_empty()).then(|| mime.to_owned())
}

/// RFC 3986 percent-decoding of a relative reference into a UTF-8 path; `None` when malformed.
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}
