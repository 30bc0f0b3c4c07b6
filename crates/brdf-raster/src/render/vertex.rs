//! The vertex stage (world and clip positions, outcodes, snapped screen positions, in parallel per
//! vertex) and the setup driver: faces in fixed chunks of one instance are rejected, clipped, culled,
//! set up and binned into bands ([`crate::tiles`]), in parallel per chunk.

use brdf_core::illumination::Terms;
use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::interpolate::Rays;
use super::{Occlusion, RenderOptions};
use crate::RasterError;
use crate::camera::Camera;
use crate::clip::{ClipVertex, GuardBand, MAX_POLY, clip_triangle, code};
use crate::scene::Scene;
use crate::setup::{Culling, SetupVertex, Viewport, setup_triangle};
use crate::shading::ShadingMode;
use crate::texture::AlphaMask;
use crate::tiles::{CHUNK_FACES, Chunk, MAX_CHUNKS, band_rows};

/// What triangle setup needs of a vertex (16 bytes, so the setup loop streams through little memory).
#[derive(Debug, Clone, Copy, Default, bytemuck::Zeroable)]
struct ScreenVertex {
    /// Snapped screen position and window depth, valid when `code & MUST_CLIP == 0`.
    x: i32,
    y: i32,
    z: f32,
    code: u16,
}

impl ScreenVertex {
    #[inline]
    fn setup(&self) -> SetupVertex {
        SetupVertex { x: i64::from(self.x), y: i64::from(self.y), z: self.z }
    }
}

/// What shading needs of a vertex: world position and unit world normal.
#[derive(Debug, Clone, Copy, Default, bytemuck::Zeroable)]
pub(super) struct WorldVertex {
    pub(super) p: Vec3,
    pub(super) n: Vec3,
}

/// Per-instance data of the frame.
pub(super) struct InstanceData {
    pub(super) vertex_base: usize,
    pub(super) face_base: u32,
    pub(super) mirrored: bool,
    pub(super) terms: Terms,
    /// The material has textures (the scene checked that a mesh whose material reads them has texture
    /// coordinates): shaded per sample by
    /// `ShadeChunk::run_textured`, whatever the shading mode.
    pub(super) textured: bool,
}

/// Everything the bands need: transformed vertices, binned triangles, per-vertex colours.
pub(super) struct Prepared<'a> {
    pub(super) scene: &'a Scene,
    pub(super) shading: ShadingMode,
    pub(super) viewport: Viewport,
    pub(super) s: usize,
    pub(super) band_samples: u32,
    screen: Vec<ScreenVertex>,
    clip: Vec<Vec4>,
    pub(super) world: Vec<WorldVertex>,
    pub(super) instances: Vec<InstanceData>,
    /// Whether obscurance or shadows are asked for at every sample (the occlusion hooks are not
    /// trivial).
    pub(super) occluded: bool,
    /// Gouraud: what the model gives at every vertex ([`Prepared::terms_len`] values each).
    pub(super) point_terms: Vec<Vec3>,
    pub(super) rays: Rays,
    /// The eye, and `normalize(eye − target)`: the constant view vector of an orthographic camera.
    pub(super) eye: Vec3A,
    pub(super) backward: Vec3A,
    pub(super) ortho_view: Option<Vec3A>,
    pub(super) chunks: Vec<Chunk>,
    /// Per instance: its alpha mask (glTF `MASK`), if any; empty when no instance has one.
    pub(super) masks: Vec<Option<&'a AlphaMask>>,
}

impl<'a> Prepared<'a> {
    /// Transform, clip, set up and bin the scene; `occlusion` says whether every sample asks for
    /// obscurance and shadows ([`Occlusion::is_trivial`]).
    pub(super) fn new(
        scene: &'a Scene,
        camera: &'a Camera,
        options: &RenderOptions,
        occlusion: &dyn Occlusion,
    ) -> Result<Self, RasterError> {
        options.validate()?;
        camera.validate()?;
        scene.validate()?;
        let s = options.ssaa_factor();
        let viewport = Viewport { width: options.width * s, height: options.height * s };
        let guard = GuardBand::new(viewport.width, viewport.height);
        let view_proj = camera.view_projection(options.width as f32 / options.height as f32);

        // Vertex stage, written in parallel straight into three arrays.
        let n_vertices: usize = scene.instances.iter().map(|i| i.mesh.positions.len()).sum();
        // Zeroed allocations: the pages are touched first by the parallel writers below.
        let mut screen: Vec<ScreenVertex> = bytemuck::zeroed_vec(n_vertices);
        let mut clip: Vec<Vec4> = bytemuck::zeroed_vec(n_vertices);
        let mut world: Vec<WorldVertex> = bytemuck::zeroed_vec(n_vertices);
        let mut instances = Vec::with_capacity(scene.instances.len());
        let (mut vertex_base, mut face_base) = (0usize, 0u32);
        for inst in &scene.instances {
            let m = inst.transform;
            let nm = inst.normal_matrix();
            let mesh = &inst.mesh;
            let n = mesh.positions.len();
            instances.push(InstanceData {
                vertex_base,
                face_base,
                mirrored: inst.mirrors(),
                textured: inst.material.textures.as_deref().is_some_and(|t| t.shades_textures()),
                terms: Terms {
                    emission: inst.material.emission,
                    ambient: inst.material.ambient,
                    ambient_light: scene.ambient_light,
                },
            });
            let range = vertex_base..vertex_base + n;
            screen[range.clone()]
                .par_iter_mut()
                .zip(clip[range.clone()].par_iter_mut())
                .zip(world[range].par_iter_mut())
                .zip(mesh.positions.par_iter().zip(mesh.normals.par_iter()))
                .with_min_len(4096)
                .for_each(|(((sv, cv), wv), (&p, &n))| {
                    let p = m.transform_point3(p);
                    *wv = WorldVertex { p, n: (nm * n).normalize_or_zero() };
                    *cv = view_proj * p.extend(1.0);
                    let code = guard.outcode(*cv);
                    *sv = ScreenVertex { code, ..ScreenVertex::default() };
                    if code & code::MUST_CLIP == 0 {
                        let snapped = viewport.snap(*cv);
                        (sv.x, sv.y, sv.z) = (snapped.x as i32, snapped.y as i32, snapped.z);
                    }
                });
            vertex_base += n;
            face_base += mesh.indices.len() as u32;
        }

        let mut prep = Prepared {
            scene,
            shading: options.shading,
            viewport,
            s: s as usize,
            band_samples: band_rows(s) * s,
            screen,
            clip,
            world,
            instances,
            occluded: !occlusion.is_trivial(),
            point_terms: Vec::new(),
            rays: Rays::new(&view_proj, viewport, (!camera.is_orthographic()).then_some(camera.eye)),
            eye: camera.eye.into(),
            backward: camera.backward().into(),
            ortho_view: camera.is_orthographic().then(|| camera.backward().into()),
            chunks: Vec::new(),
            masks: Vec::new(),
        };
        let masks: Vec<_> = scene
            .instances
            .iter()
            .map(|i| i.material.textures.as_deref().and_then(|t| t.alpha_mask()))
            .collect();
        if masks.iter().any(Option::is_some) {
            prep.masks = masks;
        }
        if prep.shading == ShadingMode::Gouraud {
            prep.point_terms = prep.vertex_terms();
        }

        // Setup and binning, in chunks of faces of one instance.
        let mut jobs = Vec::new();
        for (k, inst) in scene.instances.iter().enumerate() {
            let n = inst.mesh.indices.len();
            jobs.extend((0..n).step_by(CHUNK_FACES).map(|start| (k, start, (start + CHUNK_FACES).min(n))));
        }
        if jobs.len() > MAX_CHUNKS {
            return Err(RasterError::arg(
                "scene",
                format!("too many faces ({} chunks of {CHUNK_FACES})", jobs.len()),
            ));
        }
        let n_bands = viewport.height.div_ceil(prep.band_samples) as usize;
        let cull = options.cull_back_faces;
        prep.chunks = jobs
            .par_iter()
            .map(|&(k, start, end)| {
                let mut chunk = prep.setup_chunk(k, start, end, cull, &guard);
                if prep.shading == ShadingMode::Flat {
                    chunk.flat = prep.flat_terms(&chunk);
                }
                chunk.bin(prep.band_samples, n_bands);
                chunk
            })
            .collect();
        Ok(prep)
    }

    /// Free the per-frame arrays on the pool's threads: returning tens of megabytes to the system
    /// (munmap) is slow enough to unbalance the threads when one of them does it all.
    pub(super) fn release(self) {
        let Prepared { screen, clip, world, point_terms, chunks, .. } = self;
        rayon::join(
            || chunks.into_par_iter().with_max_len(8).for_each(drop),
            || {
                rayon::join(|| drop(screen), || drop(clip));
                rayon::join(|| drop(world), || drop(point_terms));
            },
        );
    }

    /// Reject, clip, cull and set up faces `start..end` of instance `k`.
    fn setup_chunk(&self, k: usize, start: usize, end: usize, cull: bool, guard: &GuardBand) -> Chunk {
        let inst = &self.instances[k];
        let mesh = &self.scene.instances[k].mesh;
        let culling = Culling { back: cull, mirrored: inst.mirrored };
        let range = inst.vertex_base..inst.vertex_base + mesh.positions.len();
        let (screen, clip) = (&self.screen[range.clone()], &self.clip[range]);
        let mut chunk = Chunk { instance: k as u32, ..Chunk::default() };
        chunk.raster.reserve((end - start) / 2);
        chunk.interp.reserve((end - start) / 2);
        for (f, idx) in mesh.indices[start..end].iter().enumerate() {
            let face = (start + f) as u32;
            let v = idx.map(|i| &screen[i as usize]);
            if v[0].code & v[1].code & v[2].code & code::REJECT != 0 {
                continue;
            }
            let any = v[0].code | v[1].code | v[2].code;
            if any & code::MUST_CLIP == 0 {
                let tri = [v[0].setup(), v[1].setup(), v[2].setup()];
                if let Some((r, i)) = setup_triangle(tri, self.viewport, culling, face, k as u32) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
                continue;
            }
            let tri = [0, 1, 2].map(|j| {
                let mut bary = Vec3::ZERO;
                bary[j] = 1.0;
                ClipVertex { pos: clip[idx[j] as usize], bary }
            });
            let poly = clip_triangle(tri, any & code::MUST_CLIP, guard);
            if poly.len < 3 {
                continue;
            }
            let mut snapped = [SetupVertex { x: 0, y: 0, z: 0.0 }; MAX_POLY];
            for (s, c) in snapped.iter_mut().zip(&poly.v[..poly.len]) {
                *s = self.viewport.snap(c.pos);
            }
            for j in 1..poly.len - 1 {
                let tri = [snapped[0], snapped[j], snapped[j + 1]];
                if let Some((r, i)) = setup_triangle(tri, self.viewport, culling, face, k as u32) {
                    chunk.raster.push(r);
                    chunk.interp.push(i);
                }
            }
        }
        chunk
    }
}
