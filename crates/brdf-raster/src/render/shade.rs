//! Shading: each band's visible samples, triangle by triangle in submission order, with the
//! material's model dispatched once per chunk.
//!
//! Where the reflectance model is evaluated depends on the shading mode — per sample (Phong,
//! quadratic), per vertex (Gouraud) or per face centroid (flat) — and always eight points at a time
//! in brdf-core's lane code (the lane queues below, [`Prepared::vertex_terms`] and
//! [`Prepared::flat_terms`]). Obscurance and shadows, when the render has them, are asked for at every
//! **sample** whatever the mode ([`OccQueue`]): flat and Gouraud keep, per face or vertex, the
//! ambient part `A = t∘k_a∘I_a` and each light's part `D_j = t∘E_j∘shade_j` apart (`t` the vertex
//! colour, 1 without), and a sample combines them with its own `w` and `δ_j`:
//! `L = emission + w·A + Σ_j δ_j·D_j + t∘indirect`. The shadow rays of up to 64 neighbouring samples
//! are traced together ([`Occlusion::visibility_each`]).

use brdf_core::illumination::{SurfacePoint, Terms, radiance, radiance_lanes};
use brdf_core::lights::Incident;
use brdf_core::models::{Bxdf, ModelVisitor};
use brdf_core::simd::{Lane, LaneKernel, V3, run_widest};
use brdf_core::vector::normalize_or_zero;
use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::interpolate::BaryPlanes;
use super::vertex::{InstanceData, Prepared, WorldVertex};
use super::{Occlusion, ShadePoint};
use crate::framebuffer::Span;
use crate::shading::{ShadingMode, face_normal, linear_normal, quadratic_normal};
use crate::shadows::geometric_incident;
use crate::tiles::{Chunk, LOCAL_BITS, NO_TRI};

mod textured;

/// Terms with no emission and no ambient part: what one light alone contributes.
const NO_TERMS: Terms = Terms { emission: Vec3::ZERO, ambient: Vec3::ZERO, ambient_light: Vec3::ZERO };

/// A point where the reflectance model is evaluated once for a whole face or vertex (flat, Gouraud).
#[derive(Clone, Copy)]
struct ModelPoint {
    p: Vec3,
    /// Unit normal.
    n: Vec3,
    /// Vertex colour, if the mesh has them.
    tint: Option<Vec3>,
}

impl Prepared<'_> {
    /// Values stored per face (flat) or vertex (Gouraud): the radiance itself (1) when the render has
    /// no occlusion, else the ambient part and one part per light (`1 + lights`).
    pub(super) fn terms_len(&self) -> usize {
        if self.occluded { 1 + self.scene.lights.len() } else { 1 }
    }

    /// The stored values (see [`Prepared::terms_len`]) at `points` into `out`, `F::LANES` points at
    /// a time. Without occlusion, the radiance with the same bits as [`Prepared::illuminate`] at the
    /// point (the lane code gives the bits of the one-point code).
    #[inline(always)]
    fn model_terms<M: Bxdf, F: Lane>(&self, m: &M, terms: &Terms, points: &[ModelPoint], out: &mut [Vec3]) {
        let t = self.terms_len();
        let lights = &self.scene.lights;
        let unlit = Terms { emission: Vec3::ZERO, ..*terms };
        for (group, out) in points.chunks(F::LANES).zip(out.chunks_mut(F::LANES * t)) {
            let count = group.len();
            let at = |i: usize| group[i.min(count - 1)];
            let p = V3::<F>::from_fn(|i| at(i).p);
            let n = V3::<F>::from_fn(|i| at(i).n);
            let v = self.view_lanes(p);
            let active = lanes_below::<F>(count);
            let tinted = group[0].tint.is_some();
            if !self.occluded {
                let c = radiance_lanes(m, if tinted { &unlit } else { terms }, lights, p, n, v, active);
                for (i, o) in out.iter_mut().enumerate() {
                    // `illuminate`: `+ indirect` (zero here) changes no bit.
                    *o = match group[i].tint {
                        None => c.lane(i),
                        Some(tint) => terms.emission + tint * c.lane(i),
                    };
                }
                continue;
            }
            let ambient = terms.ambient * terms.ambient_light;
            for (i, g) in group.iter().enumerate() {
                out[i * t] = g.tint.map_or(ambient, |tint| tint * ambient);
            }
            for j in 0..lights.len() {
                let d = radiance_lanes(m, &NO_TERMS, &lights[j..=j], p, n, v, active);
                for (i, g) in group.iter().enumerate() {
                    out[i * t + 1 + j] = g.tint.map_or(d.lane(i), |tint| tint * d.lane(i));
                }
            }
        }
    }

    /// Gouraud: the stored values (see [`Prepared::terms_len`]) at every vertex with its vertex
    /// normal, in parallel.
    pub(super) fn vertex_terms(&self) -> Vec<Vec3> {
        struct Job<'b> {
            prep: &'b Prepared<'b>,
            k: usize,
            out: &'b mut [Vec3],
        }
        impl ModelVisitor for Job<'_> {
            type Output = ();
            fn visit<M: Bxdf>(self, m: &M) {
                let prep = self.prep;
                let data = &prep.instances[self.k];
                let mesh = &prep.scene.instances[self.k].mesh;
                let world = &prep.world[data.vertex_base..data.vertex_base + mesh.positions.len()];
                let colors = mesh.colors.as_deref();
                const PER_JOB: usize = 1024;
                let t = prep.terms_len();
                self.out.par_chunks_mut(PER_JOB * t).enumerate().for_each(|(c, out)| {
                    let first = c * PER_JOB;
                    let points: Vec<ModelPoint> = world[first..first + out.len() / t]
                        .iter()
                        .enumerate()
                        .map(|(i, w)| ModelPoint { p: w.p, n: w.n, tint: colors.map(|col| col[first + i]) })
                        .collect();
                    prep.model_terms_dyn(m, &data.terms, &points, out);
                });
            }
        }
        let t = self.terms_len();
        let mut out: Vec<Vec3> = bytemuck::zeroed_vec(self.world.len() * t);
        for (k, inst) in self.scene.instances.iter().enumerate() {
            let base = self.instances[k].vertex_base;
            let out = &mut out[base * t..(base + inst.mesh.positions.len()) * t];
            inst.material.model.visit(Job { prep: self, k, out });
        }
        out
    }

    /// Flat: the stored values (see [`Prepared::terms_len`]) of every set-up triangle of `chunk`, at
    /// its face's centroid with the face normal (a clipped face's pieces share them).
    pub(super) fn flat_terms(&self, chunk: &Chunk) -> Vec<Vec3> {
        struct Job<'b> {
            prep: &'b Prepared<'b>,
            chunk: &'b Chunk,
        }
        impl ModelVisitor for Job<'_> {
            type Output = Vec<Vec3>;
            fn visit<M: Bxdf>(self, m: &M) -> Vec<Vec3> {
                let prep = self.prep;
                let k = self.chunk.instance as usize;
                let data = &prep.instances[k];
                let mesh = &prep.scene.instances[k].mesh;
                let world = &prep.world[data.vertex_base..];
                let colors = mesh.colors.as_deref();
                let points: Vec<ModelPoint> = self
                    .chunk
                    .interp
                    .iter()
                    .map(|it| {
                        let idx = mesh.indices[it.face as usize];
                        let p = idx.map(|j| world[j as usize].p);
                        let n = face_normal(p);
                        ModelPoint {
                            p: (p[0] + p[1] + p[2]) / 3.0,
                            n: if data.mirrored { -n } else { n },
                            tint: colors.map(|c| {
                                (c[idx[0] as usize] + c[idx[1] as usize] + c[idx[2] as usize]) / 3.0
                            }),
                        }
                    })
                    .collect();
                let mut out = vec![Vec3::ZERO; points.len() * prep.terms_len()];
                prep.model_terms_dyn(m, &data.terms, &points, &mut out);
                out
            }
        }
        let k = chunk.instance as usize;
        self.scene.instances[k].material.model.visit(Job { prep: self, chunk })
    }

    /// [`Prepared::model_terms`] with the lane type chosen at run time.
    #[inline(always)]
    fn model_terms_dyn<M: Bxdf>(&self, m: &M, terms: &Terms, points: &[ModelPoint], out: &mut [Vec3]) {
        struct K<'c, M> {
            prep: &'c Prepared<'c>,
            m: &'c M,
            terms: &'c Terms,
            points: &'c [ModelPoint],
            out: &'c mut [Vec3],
        }
        impl<M: Bxdf> LaneKernel for K<'_, M> {
            #[inline(always)]
            fn run<F: Lane>(self) {
                self.prep.model_terms::<M, F>(self.m, self.terms, self.points, self.out);
            }
        }
        run_widest(K { prep: self, m, terms, points, out });
    }

    /// The unit view direction at `F::LANES` points, as [`Prepared::illuminate`] computes it at one.
    #[inline(always)]
    fn view_lanes<F: Lane>(&self, p: V3<F>) -> V3<F> {
        match self.ortho_view {
            Some(v) => V3::splat(v.into()),
            None => {
                let (v, ok) = (V3::splat(self.eye.into()) - p).normalize_or_zero();
                V3::select(ok, v, V3::splat(self.backward.into()))
            }
        }
    }

    /// The unit view direction at a point (as [`Prepared::view_lanes`]).
    #[inline(always)]
    fn view(&self, p: Vec3) -> Vec3A {
        match self.ortho_view {
            Some(v) => v,
            // Divided by the length (not times its reciprocal), as `view_lanes` does.
            None => {
                let v = normalize_or_zero(self.eye - Vec3A::from(p));
                if v == Vec3A::ZERO { self.backward } else { v }
            }
        }
    }

    /// The illumination model at a point with obscurance `w`, visibilities `vis(j)`, extra radiance
    /// `indirect`, and the mesh's vertex colour (if any) tinting everything but the emission.
    #[inline(always)]
    fn illuminate<M: Bxdf>(
        &self,
        m: &M,
        terms: &Terms,
        at: &ShadePoint,
        tint: Option<Vec3>,
        w: f32,
        vis: impl FnMut(usize, &Incident) -> f32,
        indirect: Vec3,
    ) -> Vec3 {
        let sp = SurfacePoint { p: at.p, n: at.n.into(), v: self.view(at.p), tangent: None };
        match tint {
            None => radiance(m, terms, &self.scene.lights, &sp, w, vis) + indirect,
            Some(t) => {
                let unlit = Terms { emission: Vec3::ZERO, ..*terms };
                terms.emission + t * (radiance(m, &unlit, &self.scene.lights, &sp, w, vis) + indirect)
            }
        }
    }

    /// The radiance behind sample `(column, row)` where no triangle is: the scene's environment seen
    /// along the sample's view ray, else its background colour.
    #[inline]
    fn background_at(&self, column: usize, row: i32) -> Vec3 {
        match &self.scene.environment {
            None => self.scene.background,
            Some(env) => {
                let (_, d) = self.rays.ray(column as i32, row);
                env.radiance(d.as_vec3().normalize_or_zero())
            }
        }
    }

    /// Shade a band (`ws` samples wide, first sample row `row0`) from its visibility buffer `tri`.
    /// The background is written where no triangle is, everywhere or, with `within` (one sample per
    /// pixel), only inside each row's covered span: the caller reads nothing else of `hdr`.
    ///
    /// Shading runs triangle by triangle in submission order — each triangle's visible samples are found
    /// by scanning its bounding box for its id — rather than sample by sample: a triangle's vertex data
    /// is then fetched once and in mesh order (cache-friendly), per-triangle terms (ray set-up,
    /// quadratic coefficients) are computed once, and a chunk (one instance) dispatches its material's
    /// model once.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shade(
        &self,
        band: usize,
        row0: i32,
        ws: usize,
        tri: &[u32],
        hdr: &mut [Vec3],
        mut normal: Option<&mut [Vec3]>,
        mut face: Option<&mut [u32]>,
        occlusion: &dyn Occlusion,
        within: Option<&[Span]>,
    ) {
        let bg = |i: usize| self.background_at(i % ws, row0 + (i / ws) as i32);
        match within {
            Some(spans) if normal.is_none() && face.is_none() => {
                for (y, span) in spans.iter().enumerate() {
                    let row = y * ws;
                    let range = row + span.start as usize..row + span.end as usize;
                    for (i, (h, &t)) in hdr[range.clone()].iter_mut().zip(&tri[range.clone()]).enumerate() {
                        if t == NO_TRI {
                            *h = bg(range.start + i);
                        }
                    }
                }
            }
            _ => {
                for (i, &t) in tri.iter().enumerate() {
                    if t == NO_TRI {
                        hdr[i] = bg(i);
                        if let Some(n) = normal.as_deref_mut() {
                            n[i] = Vec3::ZERO;
                        }
                        if let Some(f) = face.as_deref_mut() {
                            f[i] = NO_TRI;
                        }
                    }
                }
            }
        }
        let rows = (tri.len() / ws) as i32;
        for (ci, chunk) in self.chunks.iter().enumerate() {
            let list = chunk.band(band);
            if list.is_empty() {
                continue;
            }
            let k = chunk.instance as usize;
            let job = ShadeChunk {
                prep: self,
                k,
                base: (ci as u32) << LOCAL_BITS,
                chunk,
                list,
                tri,
                hdr: &mut *hdr,
                normal: normal.as_deref_mut(),
                face: face.as_deref_mut(),
                row0,
                rows,
                ws,
                occlusion,
            };
            self.scene.instances[k].material.model.visit(job);
        }
    }
}

/// Bit `k` set where `ids[k] == id` (`ids` holds at most 8; written so that the compiler compares
/// them in one vector instruction).
#[inline(always)]
fn id_matches(ids: &[u32], id: u32) -> u32 {
    let mut m = 0;
    if let Ok(block) = <&[u32; 8]>::try_from(ids) {
        for (k, &t) in block.iter().enumerate() {
            m |= u32::from(t == id) << k;
        }
    } else {
        for (k, &t) in ids.iter().enumerate() {
            m |= u32::from(t == id) << k;
        }
    }
    m
}

/// The first `count` lanes (of `F::LANES`).
#[inline(always)]
fn lanes_below<F: Lane>(count: usize) -> F::Mask {
    if count >= F::LANES {
        F::mask_splat(true)
    } else {
        F::from_fn(|i| if i < count { 1.0 } else { 0.0 }).gt(F::splat(0.5))
    }
}

/// Shade the samples of one chunk's triangles in a band, with the model known at compile time.
struct ShadeChunk<'b> {
    prep: &'b Prepared<'b>,
    k: usize,
    base: u32,
    chunk: &'b Chunk,
    list: &'b [u16],
    tri: &'b [u32],
    hdr: &'b mut [Vec3],
    /// The shading normals and face ids, when they are outputs of the render.
    normal: Option<&'b mut [Vec3]>,
    face: Option<&'b mut [u32]>,
    row0: i32,
    rows: i32,
    ws: usize,
    occlusion: &'b dyn Occlusion,
}

impl ModelVisitor for ShadeChunk<'_> {
    type Output = ();

    fn visit<M: Bxdf>(self, m: &M) {
        struct Kernel<'c, 'b, M> {
            job: ShadeChunk<'b>,
            m: &'c M,
        }
        impl<M: Bxdf> LaneKernel for Kernel<'_, '_, M> {
            #[inline(always)]
            fn run<F: Lane>(self) {
                self.job.run::<M, F>(self.m);
            }
        }
        run_widest(Kernel { job: self, m });
    }
}

impl ShadeChunk<'_> {
    /// Shade the chunk's visible samples: per-sample models without occlusion through a
    /// [`LaneQueue`], samples with occlusion through an [`OccQueue`], flat and Gouraud samples
    /// without occlusion straight from their stored colours.
    #[inline(always)]
    fn run<M: Bxdf, F: Lane>(mut self, m: &M) {
        let prep = self.prep;
        if prep.instances[self.k].textured {
            return self.run_textured(m);
        }
        let data = &prep.instances[self.k];
        let mesh = &prep.scene.instances[self.k].mesh;
        let colors = mesh.colors.as_deref();
        let world = &prep.world[data.vertex_base..];
        let t_len = prep.terms_len();
        let vterms =
            if prep.point_terms.is_empty() { &[][..] } else { &prep.point_terms[data.vertex_base * t_len..] };
        let mut lane_queue = LaneQueue::new();
        let per_face_or_vertex = matches!(prep.shading, ShadingMode::Flat | ShadingMode::Gouraud);
        let queue_terms = if per_face_or_vertex { t_len } else { 0 };
        let mut occ_queue = prep.occluded.then(|| OccQueue::new(queue_terms, prep.scene.lights.len()));
        // Flat shading without occlusion needs per-triangle data only for the normal output.
        let flat_plain = prep.shading == ShadingMode::Flat && !prep.occluded;
        let need_td = !flat_plain || self.normal.is_some();
        // Phong without occlusion, the default: a block's positions and normals eight at a time.
        let phong_plain = prep.shading == ShadingMode::Phong && !prep.occluded;
        let mut sample_terms = vec![Vec3::ZERO; t_len];
        for &local in self.list {
            let id = self.base | u32::from(local);
            let t = &self.chunk.raster[local as usize];
            let (r_first, r_last) = (t.min_y.max(self.row0), t.max_y.min(self.row0 + self.rows - 1));
            let f = self.chunk.interp[local as usize].face;
            let face_id = data.face_base + f;
            // Per-triangle data, fetched when the first visible sample is found (many triangles lose
            // the depth test everywhere and need none of it).
            let mut tri_data: Option<TriangleData> = None;
            let triangle_data =
                || TriangleData::new(prep, data, f, (t.min_x, t.min_y), mesh.indices[f as usize], world);
            let flat = &self.chunk.flat[(local as usize * t_len).min(self.chunk.flat.len())..];
            for r in r_first..=r_last {
                let row = (r - self.row0) as usize * self.ws;
                // The triangle's samples in the visibility buffer, found eight at a time (a compare
                // and a bit mask), visited from left to right.
                let (mut c, c_end) = (t.min_x, t.max_x + 1);
                while c < c_end {
                    let (c_block, block) = (c, (c_end - c).min(8));
                    let from = row + c as usize;
                    let mut hits = id_matches(&self.tri[from..from + block as usize], id);
                    c += block;
                    if phong_plain {
                        if hits == 0 {
                            continue;
                        }
                        let td = tri_data.get_or_insert_with(triangle_data);
                        let attrs = td.phong_row_of_8(c_block, r);
                        while hits != 0 {
                            let k = hits.trailing_zeros() as usize;
                            hits &= hits - 1;
                            let i = row + c_block as usize + k;
                            if let Some(fb) = self.face.as_deref_mut() {
                                fb[i] = face_id;
                            }
                            let tint = colors.map(|col| td.interpolate(col, attrs.b(k)));
                            if lane_queue.push(i as u32, attrs.p(k), attrs.n(k), tint) {
                                let normal = self.normal.as_deref_mut();
                                lane_queue.flush::<M, F>(m, prep, &data.terms, self.hdr, normal);
                            }
                        }
                        continue;
                    }
                    while hits != 0 {
                        let c = c_block + hits.trailing_zeros() as i32;
                        hits &= hits - 1;
                        let i = row + c as usize;
                        if let Some(fb) = self.face.as_deref_mut() {
                            fb[i] = face_id;
                        }
                        if flat_plain && !need_td {
                            self.hdr[i] = flat[0];
                            continue;
                        }
                        let td = tri_data.get_or_insert_with(triangle_data);
                        let at = |b: Vec3, p: Vec3, n: Vec3| ShadePoint {
                            p,
                            n,
                            instance: self.k as u32,
                            face: f,
                            vertex: NO_TRI,
                            bary: b,
                        };
                        match prep.shading {
                            ShadingMode::Flat | ShadingMode::Gouraud => {
                                let gouraud = prep.shading == ShadingMode::Gouraud;
                                if !prep.occluded {
                                    // Flat: the face's colour; Gouraud: the vertex colours interpolated.
                                    let (color, n) = if gouraud {
                                        let b = td.bary.at(c, r);
                                        let cv = td.idx.map(|j| vterms[j as usize]);
                                        (
                                            cv[0] * b.x + cv[1] * b.y + cv[2] * b.z,
                                            linear_normal(td.n, b).normalize_or_zero(),
                                        )
                                    } else {
                                        (flat[0], td.face_normal)
                                    };
                                    self.hdr[i] = color;
                                    if let Some(nb) = self.normal.as_deref_mut() {
                                        nb[i] = n;
                                    }
                                    continue;
                                }
                                let b = td.bary.at(c, r);
                                let pos = td.p[0] * b.x + td.p[1] * b.y + td.p[2] * b.z;
                                let n = if gouraud {
                                    let [a0, a1, a2] = td.idx.map(|j| &vterms[j as usize * t_len..][..t_len]);
                                    for (s, ((x, y), z)) in
                                        sample_terms.iter_mut().zip(a0.iter().zip(a1).zip(a2))
                                    {
                                        *s = *x * b.x + *y * b.y + *z * b.z;
                                    }
                                    linear_normal(td.n, b).normalize_or_zero()
                                } else {
                                    sample_terms.copy_from_slice(&flat[..t_len]);
                                    td.face_normal
                                };
                                let tint = colors.map(|col| td.interpolate(col, b));
                                let q = occ_queue.as_mut().expect("occluded renders have the queue");
                                if q.push(i as u32, at(b, pos, n), tint, &sample_terms) {
                                    q.flush(
                                        m,
                                        prep,
                                        data,
                                        self.occlusion,
                                        self.hdr,
                                        self.normal.as_deref_mut(),
                                    );
                                }
                            }
                            mode => {
                                let b = td.bary.at(c, r);
                                let pos = td.p[0] * b.x + td.p[1] * b.y + td.p[2] * b.z;
                                let n = if mode == ShadingMode::QuadraticNormals {
                                    quadratic_normal(td.p, td.n, b)
                                } else {
                                    linear_normal(td.n, b)
                                };
                                let tint = colors.map(|col| td.interpolate(col, b));
                                match occ_queue.as_mut() {
                                    None => {
                                        // Normalised in the queue, eight at a time.
                                        if lane_queue.push(i as u32, pos, n, tint) {
                                            let normal = self.normal.as_deref_mut();
                                            lane_queue.flush::<M, F>(m, prep, &data.terms, self.hdr, normal);
                                        }
                                    }
                                    Some(q) => {
                                        let point = at(b, pos, n.normalize_or_zero());
                                        if q.push(i as u32, point, tint, &[]) {
                                            q.flush(
                                                m,
                                                prep,
                                                data,
                                                self.occlusion,
                                                self.hdr,
                                                self.normal.as_deref_mut(),
                                            );
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        lane_queue.flush::<M, F>(m, prep, &data.terms, self.hdr, self.normal.as_deref_mut());
        if let Some(q) = occ_queue.as_mut() {
            q.flush(m, prep, data, self.occlusion, self.hdr, self.normal.as_deref_mut());
        }
    }
}

/// Samples without occlusion waiting to be shaded eight at a time: their index in the band and, in
/// structure-of-arrays form, the interpolated world position, (not yet normalised) normal and vertex
/// colour.
struct LaneQueue {
    len: usize,
    tinted: bool,
    index: [u32; LaneQueue::CAPACITY],
    p: [[f32; LaneQueue::CAPACITY]; 3],
    n: [[f32; LaneQueue::CAPACITY]; 3],
    tint: [Vec3; LaneQueue::CAPACITY],
}

impl LaneQueue {
    /// A multiple of every lane count; large enough that flushing is not per sample.
    const CAPACITY: usize = 64;

    #[inline(always)]
    fn new() -> Self {
        Self {
            len: 0,
            tinted: false,
            index: [0; Self::CAPACITY],
            p: [[0.0; Self::CAPACITY]; 3],
            n: [[0.0; Self::CAPACITY]; 3],
            tint: [Vec3::ZERO; Self::CAPACITY],
        }
    }

    /// Add a sample; `true` when the queue is full and must be flushed. A chunk's samples are all
    /// tinted or none (one mesh).
    #[inline(always)]
    fn push(&mut self, index: u32, p: Vec3, n: Vec3, tint: Option<Vec3>) -> bool {
        let k = self.len;
        self.index[k] = index;
        (self.p[0][k], self.p[1][k], self.p[2][k]) = (p.x, p.y, p.z);
        (self.n[0][k], self.n[1][k], self.n[2][k]) = (n.x, n.y, n.z);
        if let Some(t) = tint {
            self.tint[k] = t;
            self.tinted = true;
        }
        self.len += 1;
        self.len == Self::CAPACITY
    }

    /// Normalise the queued normals into `normal`, shade every queued sample into `hdr` and empty the
    /// queue: [`Prepared::illuminate`] without occlusion, on `F::LANES` samples at a time (the last
    /// group padded with copies of its last sample, masked off).
    #[inline(always)]
    fn flush<M: Bxdf, F: Lane>(
        &mut self,
        m: &M,
        prep: &Prepared<'_>,
        terms: &Terms,
        hdr: &mut [Vec3],
        mut normal: Option<&mut [Vec3]>,
    ) {
        if self.len == 0 {
            return;
        }
        // Pad the last group with copies of the last sample, so that every group is a contiguous
        // load (CAPACITY is a multiple of every lane count).
        let padded = self.len.next_multiple_of(F::LANES);
        for k in self.len..padded {
            for a in self.p.iter_mut().chain(self.n.iter_mut()) {
                a[k] = a[self.len - 1];
            }
        }
        let unlit = Terms { emission: Vec3::ZERO, ..*terms };
        let shade_terms = if self.tinted { &unlit } else { terms };
        let mut start = 0;
        while start < self.len {
            let count = F::LANES.min(self.len - start);
            let load = |a: &[f32; Self::CAPACITY]| F::from_fn(|i| a[start + i]);
            let p = V3 { x: load(&self.p[0]), y: load(&self.p[1]), z: load(&self.p[2]) };
            let n = unit_or_zero(V3 { x: load(&self.n[0]), y: load(&self.n[1]), z: load(&self.n[2]) });
            let active = lanes_below::<F>(count);
            let c = radiance_lanes(m, shade_terms, &prep.scene.lights, p, n, prep.view_lanes(p), active);
            // `illuminate` adds `indirect`, zero without occlusion: adding 0 changes no bit (the
            // radiance starts from non-negative terms, so it is never −0).
            for j in 0..count {
                let i = self.index[start + j] as usize;
                hdr[i] =
                    if self.tinted { terms.emission + self.tint[start + j] * c.lane(j) } else { c.lane(j) };
                if let Some(nb) = normal.as_deref_mut() {
                    nb[i] = n.lane(j);
                }
            }
            start += count;
        }
        self.len = 0;
    }
}

/// Samples of a render with obscurance or shadows, waiting to be shaded together: their obscurance is
/// asked per sample, and the shadow rays of all of them per light at once
/// ([`Occlusion::visibility_each`]).
struct OccQueue {
    len: usize,
    /// Values per sample of flat / Gouraud shading ([`Prepared::terms_len`]); 0 for per-sample models.
    t_len: usize,
    index: Vec<u32>,
    at: Vec<ShadePoint>,
    tint: Vec<Option<Vec3>>,
    /// `t_len` values per sample.
    terms: Vec<Vec3>,
    /// Scratch: the points and incident light of the samples a light reaches, and their δ.
    reached: Vec<(usize, ShadePoint, Incident)>,
    delta: Vec<f32>,
    /// δ per light and sample (`lights × CAPACITY`).
    vis: Vec<f32>,
}

impl OccQueue {
    const CAPACITY: usize = 64;

    fn new(t_len: usize, lights: usize) -> Self {
        let c = Self::CAPACITY;
        Self {
            len: 0,
            t_len,
            index: Vec::with_capacity(c),
            at: Vec::with_capacity(c),
            tint: Vec::with_capacity(c),
            terms: Vec::with_capacity(c * t_len),
            reached: Vec::with_capacity(c),
            delta: Vec::with_capacity(c),
            vis: vec![1.0; lights * c],
        }
    }

    /// Add a sample (with its flat / Gouraud values, empty for a per-sample model); `true` when the
    /// queue is full and must be flushed.
    #[inline(always)]
    fn push(&mut self, index: u32, at: ShadePoint, tint: Option<Vec3>, terms: &[Vec3]) -> bool {
        self.index.push(index);
        self.at.push(at);
        self.tint.push(tint);
        self.terms.extend_from_slice(terms);
        self.len += 1;
        self.len == Self::CAPACITY
    }

    /// Shade every queued sample into `hdr` (and its normal into `normal`) and empty the queue.
    #[inline(never)]
    fn flush<M: Bxdf>(
        &mut self,
        m: &M,
        prep: &Prepared<'_>,
        data: &InstanceData,
        occlusion: &dyn Occlusion,
        hdr: &mut [Vec3],
        mut normal: Option<&mut [Vec3]>,
    ) {
        if self.len == 0 {
            return;
        }
        let c = Self::CAPACITY;
        let lights = &prep.scene.lights;
        let model_per_sample = self.t_len == 0;
        // δ of every light at every sample, the shadow rays of one light traced together. A
        // per-sample model asks only where the light arrives (as `radiance` does, with the light's
        // own incident direction); flat and Gouraud samples ask wherever the light is (their model
        // was evaluated elsewhere), along the straight line to it.
        for (j, light) in lights.iter().enumerate() {
            self.reached.clear();
            for (k, at) in self.at.iter().enumerate() {
                let inc =
                    if model_per_sample { light.incident(at.p) } else { geometric_incident(light, at.p) };
                if let Some(inc) = inc {
                    self.reached.push((k, *at, inc));
                }
                self.vis[j * c + k] = 1.0;
            }
            if self.reached.is_empty() {
                continue;
            }
            let points: Vec<ShadePoint> = self.reached.iter().map(|r| r.1).collect();
            let incident: Vec<Incident> = self.reached.iter().map(|r| r.2).collect();
            self.delta.clear();
            self.delta.resize(points.len(), 1.0);
            occlusion.visibility_each(&points, j, &incident, &mut self.delta);
            for (r, &d) in self.reached.iter().zip(&self.delta) {
                self.vis[j * c + r.0] = d;
            }
        }
        for k in 0..self.len {
            let at = &self.at[k];
            let w = occlusion.obscurance(at);
            let indirect = occlusion.indirect(at, w);
            let color = if model_per_sample {
                let vis = |j: usize, _: &Incident| self.vis[j * c + k];
                prep.illuminate(m, &data.terms, at, self.tint[k], w, vis, indirect)
            } else {
                let t = &self.terms[k * self.t_len..(k + 1) * self.t_len];
                let mut sum = data.terms.emission + t[0] * w;
                for (j, d) in t[1..].iter().enumerate() {
                    let delta = self.vis[j * c + k];
                    if delta > 0.0 {
                        sum += *d * delta;
                    }
                }
                sum + self.tint[k].map_or(indirect, |tint| tint * indirect)
            };
            let i = self.index[k] as usize;
            hdr[i] = color;
            if let Some(nb) = normal.as_deref_mut() {
                nb[i] = at.n;
            }
        }
        self.len = 0;
        self.index.clear();
        self.at.clear();
        self.tint.clear();
        self.terms.clear();
    }
}

/// glam's `Vec3::normalize_or_zero` (the one-sample path's) on lanes, operation for operation:
/// `v · (1/|v|)` where that reciprocal is finite and positive, else zero.
#[inline(always)]
fn unit_or_zero<F: Lane>(v: V3<F>) -> V3<F> {
    let rcp = F::splat(1.0) / v.dot(v).sqrt();
    let ok = rcp.is_finite() & rcp.gt(F::splat(0.0));
    V3::select(ok, v.scale(rcp), V3::splat(Vec3::ZERO))
}

/// What shading needs of one mesh face, gathered once per triangle.
/// Barycentrics, positions and normals of eight neighbouring samples of a row, component by component.
struct RowOf8 {
    b: [[f32; 8]; 3],
    p: [[f32; 8]; 3],
    n: [[f32; 8]; 3],
}

impl RowOf8 {
    #[inline(always)]
    fn b(&self, k: usize) -> Vec3 {
        Vec3::new(self.b[0][k], self.b[1][k], self.b[2][k])
    }
    #[inline(always)]
    fn p(&self, k: usize) -> Vec3 {
        Vec3::new(self.p[0][k], self.p[1][k], self.p[2][k])
    }
    #[inline(always)]
    fn n(&self, k: usize) -> Vec3 {
        Vec3::new(self.n[0][k], self.n[1][k], self.n[2][k])
    }
}

struct TriangleData {
    idx: [u32; 3],
    p: [Vec3; 3],
    n: [Vec3; 3],
    bary: BaryPlanes,
    face_normal: Vec3,
}

impl TriangleData {
    #[inline(always)]
    fn new(
        prep: &Prepared<'_>,
        data: &InstanceData,
        _face: u32,
        anchor: (i32, i32),
        idx: [u32; 3],
        world: &[WorldVertex],
    ) -> Self {
        let v = idx.map(|j| world[j as usize]);
        let p = [v[0].p, v[1].p, v[2].p];
        let fnorm = face_normal(p);
        let face_normal = if data.mirrored { -fnorm } else { fnorm };
        let bary = BaryPlanes::new(&prep.rays, p, anchor.0, anchor.1);
        Self { idx, p, n: [v[0].n, v[1].n, v[2].n], bary, face_normal }
    }

    /// The barycentrics, positions and (linear, not normalised) normals of the eight samples
    /// `(c0 + k, r)`: [`BaryPlanes::at`], `Σ b_i p_i` and [`linear_normal`], operation for operation
    /// (the same bits), in rows of eight that the compiler keeps in vector registers.
    #[inline(always)]
    fn phong_row_of_8(&self, c0: i32, r: i32) -> RowOf8 {
        let b = self.bary.at_row_of_8(c0, r);
        let mut p = [[0.0f32; 8]; 3];
        let mut n = [[0.0f32; 8]; 3];
        for j in 0..3 {
            let (p0, p1, p2) = (self.p[0][j], self.p[1][j], self.p[2][j]);
            let (n0, n1, n2) = (self.n[0][j], self.n[1][j], self.n[2][j]);
            for k in 0..8 {
                p[j][k] = p0 * b[0][k] + p1 * b[1][k] + p2 * b[2][k];
                n[j][k] = n0 * b[0][k] + n1 * b[1][k] + n2 * b[2][k];
            }
        }
        RowOf8 { b, p, n }
    }

    /// A per-vertex attribute at barycentrics `b`.
    #[inline(always)]
    fn interpolate(&self, attr: &[Vec3], b: Vec3) -> Vec3 {
        attr[self.idx[0] as usize] * b.x + attr[self.idx[1] as usize] * b.y + attr[self.idx[2] as usize] * b.z
    }
}
