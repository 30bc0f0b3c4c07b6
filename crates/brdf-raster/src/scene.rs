//! What is rendered: mesh instances with materials and transforms, lights, ambient light, background.

use std::sync::Arc;

use brdf_core::Model;
use brdf_core::lights::Light;
use glam::{Mat3, Mat4, Vec3};

use crate::texture::MaterialTextures;
use crate::{Mesh, RasterError};

/// A surface's appearance in the Phong illumination model (Phong 1975; Theoharis et al. 2008, ch. 12):
/// `L = emission + k_a ∘ I_a + Σ_j E_j ∘ shade(model; l_j, v, n)`, see
/// [`brdf_core::illumination`]. Any registered reflectance model can be the material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The reflectance model whose `shade` is evaluated for every light.
    pub model: Model,
    /// Ambient reflectance `k_a` (linear RGB), multiplied by the scene's ambient light `I_a`.
    pub ambient: Vec3,
    /// Emitted radiance `I_e` (linear RGB), added unlit (times the emission map, if any).
    pub emission: Vec3,
    /// Parameters of `model` read from textures, normal, occlusion and emission maps
    /// ([`crate::texture::binding`]); `None` for a material without textures. `model` is then the
    /// model at the textures' means, used where no texture coordinates are (and by environment and
    /// area lighting, which see the material's model as a whole).
    pub textures: Option<Arc<MaterialTextures>>,
}

impl Material {
    /// A material with no ambient reflectance and no emission.
    pub fn new(model: Model) -> Self {
        Self { model, ambient: Vec3::ZERO, emission: Vec3::ZERO, textures: None }
    }

    /// Read parameters (and maps) from textures; `textures` must be over this material's model.
    ///
    /// Errors: the textures' parameters belong to another model.
    pub fn with_textures(mut self, textures: MaterialTextures) -> Result<Self, RasterError> {
        let (a, b) = (textures.params().model(), self.model.spec().name);
        if a != b {
            return Err(RasterError::arg(
                "textures",
                format!("are bound to {a}'s parameters, the material is {b}"),
            ));
        }
        self.textures = Some(Arc::new(textures));
        Ok(self)
    }

    /// Set the ambient reflectance `k_a`.
    pub fn with_ambient(mut self, ambient: Vec3) -> Self {
        self.ambient = ambient;
        self
    }

    /// Set the emission `I_e`.
    pub fn with_emission(mut self, emission: Vec3) -> Self {
        self.emission = emission;
        self
    }

    fn validate(&self) -> Result<(), RasterError> {
        for (name, c) in [("ambient", self.ambient), ("emission", self.emission)] {
            if !c.is_finite() || c.min_element() < 0.0 {
                return Err(RasterError::arg(name, format!("must be finite and ≥ 0, got {c}")));
            }
        }
        Ok(())
    }
}

/// One mesh placed in the world with a material. Meshes are shared (`Arc`) between instances.
#[derive(Debug, Clone)]
pub struct Instance {
    /// The mesh (object space).
    pub mesh: Arc<Mesh>,
    /// Its material.
    pub material: Material,
    /// Object → world transform, affine (last row `0 0 0 1`; checked by [`Scene::validate`]). Normals are
    /// transformed by the inverse transpose of its upper 3×3; a mirroring transform (negative
    /// determinant) keeps the counter-clockwise side as the front.
    pub transform: Mat4,
}

impl Instance {
    /// The normal matrix: inverse transpose of the transform's upper 3×3.
    pub fn normal_matrix(&self) -> Mat3 {
        Mat3::from_mat4(self.transform).inverse().transpose()
    }

    /// Whether the transform mirrors (determinant of the upper 3×3 < 0).
    pub fn mirrors(&self) -> bool {
        Mat3::from_mat4(self.transform).determinant() < 0.0
    }
}

/// A scene: instances, lights, the ambient light `I_a` and the background colour.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Mesh instances, drawn in this order (ties in depth keep the earlier one).
    pub instances: Vec<Instance>,
    /// Light sources.
    pub lights: Vec<Light>,
    /// Area lights (sphere, rectangle), sampled by Monte Carlo ([`crate::area_lighting`]).
    pub area_lights: Vec<crate::area_light::AreaLight>,
    /// Ambient light `I_a` (linear RGB).
    pub ambient_light: Vec3,
    /// Radiance of samples no triangle covers (linear RGB), unless there is an environment.
    pub background: Vec3,
    /// Light arriving from every direction, also shown where no triangle is (replacing `background`);
    /// see [`crate::environment`] and [`crate::render::RenderOptions::environment`].
    pub environment: Option<crate::environment::Environment>,
}

impl Default for Scene {
    fn default() -> Self {
        Self::new()
    }
}

impl Scene {
    /// An empty scene with white ambient light `I_a = 1` and a black background.
    pub fn new() -> Self {
        Self {
            instances: Vec::new(),
            lights: Vec::new(),
            area_lights: Vec::new(),
            ambient_light: Vec3::ONE,
            background: Vec3::ZERO,
            environment: None,
        }
    }

    /// Add a mesh instance; returns its index.
    pub fn add(&mut self, mesh: Arc<Mesh>, material: Material, transform: Mat4) -> usize {
        self.instances.push(Instance { mesh, material, transform });
        self.instances.len() - 1
    }

    /// Add a light; returns its index (the index [`crate::render::Occlusion::visibility`] receives).
    pub fn add_light(&mut self, light: Light) -> usize {
        self.lights.push(light);
        self.lights.len() - 1
    }

    /// Add an area light; returns its index in [`Scene::area_lights`].
    pub fn add_area_light(&mut self, light: crate::area_light::AreaLight) -> usize {
        self.area_lights.push(light);
        self.area_lights.len() - 1
    }

    /// Total number of faces over all instances.
    pub fn face_count(&self) -> usize {
        self.instances.iter().map(|i| i.mesh.indices.len()).sum()
    }

    /// Check everything a render relies on: finite, affine, invertible transforms, valid materials and
    /// lights,
    /// finite colours, and at most `u32::MAX − 1` faces and vertices in total (ids fit `u32`).
    pub fn validate(&self) -> Result<(), RasterError> {
        for (k, inst) in self.instances.iter().enumerate() {
            let m = inst.transform;
            if !m.is_finite() {
                return Err(RasterError::arg("transform", format!("instance {k}: not finite")));
            }
            if m.row(3) != glam::Vec4::W {
                return Err(RasterError::arg(
                    "transform",
                    format!("instance {k}: must be affine (last row 0 0 0 1), got {}", m.row(3)),
                ));
            }
            let det = Mat3::from_mat4(m).determinant();
            if !(det.abs() > 0.0) || !det.is_finite() {
                return Err(RasterError::arg("transform", format!("instance {k}: singular (det {det})")));
            }
            inst.material.validate()?;
            if let Some(t) = &inst.material.textures {
                if (t.reads_textures() || t.alpha_mask().is_some()) && inst.mesh.uvs.is_none() {
                    return Err(RasterError::arg(
                        "textures",
                        format!(
                            "instance {k}: the material reads textures ({}) but the mesh has no texture \
                             coordinates (uvs)",
                            texture_uses(t)
                        ),
                    ));
                }
                if t.has_normal_map() && inst.mesh.tangents.is_none() {
                    return Err(RasterError::arg(
                        "normal_map",
                        format!(
                            "instance {k}: the mesh has no tangents; give them, or generate them with \
                             Mesh::with_generated_tangents (MikkTSpace)"
                        ),
                    ));
                }
            }
        }
        for (j, light) in self.lights.iter().enumerate() {
            light.validate().map_err(|e| RasterError::arg("lights", format!("light {j}: {e}")))?;
        }
        for (j, light) in self.area_lights.iter().enumerate() {
            light.validate().map_err(|e| RasterError::arg("area_lights", format!("area light {j}: {e}")))?;
        }
        for (name, c) in [("ambient_light", self.ambient_light), ("background", self.background)] {
            if !c.is_finite() || c.min_element() < 0.0 {
                return Err(RasterError::arg(name, format!("must be finite and ≥ 0, got {c}")));
            }
        }
        if let Some(env) = &self.environment {
            env.validate()?;
        }
        let verts: usize = self.instances.iter().map(|i| i.mesh.positions.len()).sum();
        if self.face_count() >= u32::MAX as usize || verts >= u32::MAX as usize {
            return Err(RasterError::arg("scene", "more than 2^32 − 1 faces or vertices in total"));
        }
        Ok(())
    }
}

/// What a material's textures are used for, for messages ("kd, roughness, normal map").
fn texture_uses(t: &MaterialTextures) -> String {
    let mut v: Vec<&str> = t.bound_names();
    if t.has_normal_map() {
        v.push("normal map");
    }
    if t.alpha_mask().is_some() {
        v.push("alpha mask");
    }
    if v.is_empty() { "occlusion or emission maps".into() } else { v.join(", ") }
}

/// The canonical benchmark scene: `icosphere(level)` at the origin
/// with the classic Blinn-Phong material `kd = (0.8, 0.3, 0.2)`, `ks = 0.5`, `s = 32`, ambient
/// `k_a = 0.05·kd` under `I_a = 1`; a directional light travelling along `(−1, −1, −1)` with `E = 1`
/// and a point light at `(2, 2, 2)` with `I = 10` and inverse-square falloff; black background.
pub fn canonical_scene(level: u32) -> Result<Scene, RasterError> {
    use brdf_core::Input;
    use brdf_core::lights::Attenuation;
    let mesh = Arc::new(crate::procedural::icosphere(level)?);
    let kd = Vec3::new(0.8, 0.3, 0.2);
    let model = Model::build(
        "blinn_phong_classic",
        &[
            ("kd".into(), Input::Numbers(vec![0.8, 0.3, 0.2])),
            ("ks".into(), Input::Number(0.5)),
            ("shininess".into(), Input::Number(32.0)),
        ],
    )?;
    let mut scene = Scene::new();
    scene.add(mesh, Material::new(model).with_ambient(0.05 * kd), Mat4::IDENTITY);
    scene.add_light(Light::directional(Vec3::splat(-1.0), Vec3::ONE)?);
    scene.add_light(Light::point(Vec3::splat(2.0), Vec3::splat(10.0), Attenuation::InverseSquare)?);
    Ok(scene)
}

/// The camera of the canonical scene: eye (0, 0, 3), target 0, up +y, 45° vertical field of view,
/// near 0.1, far 100.
pub fn canonical_camera() -> crate::Camera {
    crate::Camera {
        eye: Vec3::new(0.0, 0.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: crate::Projection::Perspective { fovy: std::f32::consts::FRAC_PI_4 },
        near: 0.1,
        far: 100.0,
    }
}
