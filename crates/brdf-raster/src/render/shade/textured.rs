//! Shading of an instance whose material reads textures ([`crate::texture::binding`]): every visible
//! sample, one at a time, with its own model.
//!
//! Per sample: perspective-correct barycentrics and their screen derivatives
//! ([`BaryPlanes::at_with_derivatives`]) give the texture coordinates and their change per sample
//! column and row (the mip level), every distinct texture is sampled once, the bound parameters are
//! written into the model in place where it can ([`Bxdf::set_param`], e.g. Cook–Torrance's `kd`,
//! `roughness`, `f0`), else into their slots of its parameters (resolved when the material was built)
//! and the model rebuilt from them — only when the texels differ from the previous sample's — then the
//! normal map tilts the normal,
//! the occlusion map scales the ambient and indirect terms and the emission map the emission, and
//! [`Prepared::illuminate`] evaluates the model with the sample's own obscurance and light
//! visibilities. The model is evaluated per sample in every shading mode (flat uses the face normal,
//! Gouraud the interpolated vertex normals). Each sample is a pure function of the scene and its
//! position, so the frame is bit-identical for any number of threads.

use brdf_core::illumination::Terms;
use brdf_core::models::Bxdf;
use glam::{Mat3, Vec2, Vec3, Vec4};

use super::{ShadeChunk, ShadePoint, TriangleData, id_matches};
use crate::shading::{ShadingMode, linear_normal, quadratic_normal};
use crate::tiles::NO_TRI;

/// `n' = normalize(T·x + B·y + N·z)` for the tangent-space normal `(x, y, z)`, with `T` the tangent
/// `t` made perpendicular to the unit normal `n` (Gram–Schmidt) and `B = w·(n × T)`; `n` unchanged
/// where the tangent has no component in the surface.
#[inline]
pub(crate) fn perturb(n: Vec3, t: Vec4, local: Vec3) -> Vec3 {
    let tt = (t.truncate() - n * n.dot(t.truncate())).normalize_or_zero();
    if tt == Vec3::ZERO {
        return n;
    }
    let w = if t.w < 0.0 { -1.0 } else { 1.0 };
    let b = n.cross(tt) * w;
    let p = (tt * local.x + b * local.y + n * local.z).normalize_or_zero();
    if p == Vec3::ZERO { n } else { p }
}

impl ShadeChunk<'_> {
    /// Shade the chunk's visible samples through the material's textures (module docs).
    pub(super) fn run_textured<M: Bxdf>(mut self, m: &M) {
        let prep = self.prep;
        let data = &prep.instances[self.k];
        let inst = &prep.scene.instances[self.k];
        let mesh = &inst.mesh;
        let Some(tex) = inst.material.textures.as_deref() else { return };
        let uvs = mesh.uvs.as_deref();
        let colors = mesh.colors.as_deref();
        let tangents = mesh.tangents.as_deref().filter(|_| tex.has_normal_map());
        let world = &prep.world[data.vertex_base..];
        // Tangents are directions in the surface: through the transform's 3×3 part, the handedness
        // flipped by a mirror (as `Mesh::transformed` does).
        let linear = Mat3::from_mat4(inst.transform);
        let handed = if data.mirrored { -1.0 } else { 1.0 };
        let mut params = tex.params().clone();
        let mut texels: Vec<Vec4> = Vec::with_capacity(tex.textures().len());
        let mut last: Vec<Vec4> = Vec::new();
        // The model at the untextured parameters, changed per sample in place while it can be.
        let mut model: Option<M> = M::from_params(&params).ok();
        let (mut fast, mut fresh) = (true, false);
        for &local in self.list {
            let id = self.base | u32::from(local);
            let t = &self.chunk.raster[local as usize];
            let (r_first, r_last) = (t.min_y.max(self.row0), t.max_y.min(self.row0 + self.rows - 1));
            let f = self.chunk.interp[local as usize].face;
            let face_id = data.face_base + f;
            let mut tri_data: Option<(TriangleData, [Vec2; 3], [Vec4; 3])> = None;
            for r in r_first..=r_last {
                let row = (r - self.row0) as usize * self.ws;
                let (mut c, c_end) = (t.min_x, t.max_x + 1);
                while c < c_end {
                    let (c_block, block) = (c, (c_end - c).min(8));
                    let from = row + c as usize;
                    let mut hits = id_matches(&self.tri[from..from + block as usize], id);
                    c += block;
                    while hits != 0 {
                        let c = c_block + hits.trailing_zeros() as i32;
                        hits &= hits - 1;
                        let i = row + c as usize;
                        if let Some(fb) = self.face.as_deref_mut() {
                            fb[i] = face_id;
                        }
                        let (td, uv3, t3) = tri_data.get_or_insert_with(|| {
                            let idx = mesh.indices[f as usize];
                            let td = TriangleData::new(prep, data, f, (t.min_x, t.min_y), idx, world);
                            let uv3 = idx.map(|j| uvs.map_or(Vec2::ZERO, |u| u[j as usize]));
                            let t3 = idx.map(|j| {
                                tangents.map_or(Vec4::ZERO, |ts| {
                                    let t = ts[j as usize];
                                    (linear * t.truncate()).normalize_or_zero().extend(t.w * handed)
                                })
                            });
                            (td, uv3, t3)
                        });
                        let (b, db_dc, db_dr) = td.bary.at_with_derivatives(c, r);
                        let pos = td.p[0] * b.x + td.p[1] * b.y + td.p[2] * b.z;
                        let n = match prep.shading {
                            ShadingMode::Flat => td.face_normal,
                            ShadingMode::QuadraticNormals => {
                                quadratic_normal(td.p, td.n, b).normalize_or_zero()
                            }
                            _ => linear_normal(td.n, b).normalize_or_zero(),
                        };
                        let at2 = |w: Vec3| uv3[0] * w.x + uv3[1] * w.y + uv3[2] * w.z;
                        tex.sample_all(at2(b), at2(db_dc), at2(db_dr), &mut texels);
                        if !fresh || texels != last {
                            // In place where the model can (`Bxdf::set_param`: every bound slot is
                            // overwritten, so nothing of the last sample stays), else rebuilt. Values
                            // are clamped into their ranges; a model refusing a combination anyway
                            // keeps the material's own model there.
                            let in_place = fast
                                && model
                                    .as_mut()
                                    .is_some_and(|mm| tex.each_value(&texels, |k, v| mm.set_param(k, &v)));
                            if !in_place {
                                fast = false;
                                tex.apply(&texels, &mut params);
                                model = M::from_params(&params).ok();
                            }
                            fresh = true;
                            last.clone_from(&texels);
                        }
                        let maps = tex.maps(&texels);
                        let n = match maps.normal {
                            Some(local_n) => {
                                let tw = t3[0] * b.x + t3[1] * b.y + t3[2] * b.z;
                                perturb(n, tw.truncate().extend(t3[0].w), local_n)
                            }
                            None => n,
                        };
                        let terms = Terms {
                            emission: data.terms.emission * maps.emission,
                            ambient: data.terms.ambient * maps.occlusion,
                            ambient_light: data.terms.ambient_light,
                        };
                        let at = ShadePoint {
                            p: pos,
                            n,
                            instance: self.k as u32,
                            face: f,
                            vertex: NO_TRI,
                            bary: b,
                        };
                        let occ = self.occlusion;
                        let w = occ.obscurance(&at);
                        let indirect = occ.indirect(&at, w) * maps.occlusion;
                        let vis = |j: usize, inc: &brdf_core::lights::Incident| occ.visibility(&at, j, inc);
                        let tint = colors.map(|col| td.interpolate(col, b));
                        self.hdr[i] = match &model {
                            Some(mm) => prep.illuminate(mm, &terms, &at, tint, w, vis, indirect),
                            None => prep.illuminate(m, &terms, &at, tint, w, vis, indirect),
                        };
                        if let Some(nb) = self.normal.as_deref_mut() {
                            nb[i] = n;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_normal_texel_keeps_the_normal_and_a_tilted_one_turns_it_toward_the_tangent() {
        let n = Vec3::new(0.0, 0.0, 1.0);
        let t = Vec4::new(1.0, 0.0, 0.3, 1.0); // not perpendicular: made so
        assert_eq!(perturb(n, t, Vec3::Z), n);
        let p = perturb(n, t, Vec3::new(1.0, 0.0, 1.0));
        assert!((p - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6, "{p}");
        // y follows the bitangent w·(n × t): +y for w = 1, −y for w = −1.
        assert!(perturb(n, t, Vec3::new(0.0, 1.0, 1.0)).y > 0.5);
        assert!(perturb(n, t.truncate().extend(-1.0), Vec3::new(0.0, 1.0, 1.0)).y < -0.5);
        assert_eq!(perturb(n, Vec4::ZERO, Vec3::X), n, "no tangent, no tilt");
    }
}
