//! Node layout and the triangle test: 4-wide nodes with SoA child boxes and child codes, triangle
//! packets of four, the per-ray constants of the slab test and the watertight four-lane triangle test.

use glam::{Vec3, Vec4};

use super::MAX_LEAF;
use super::Ray;
use crate::mesh::MAX_ELEMENTS;

/// Conservative enlargement of box far distances and of the `t_max` they are tested against (see the
/// module docs): `1 + 2⁻¹⁶`, against rounding errors of a few ulps (2⁻²³ each).
pub(super) const BOX_MARGIN: f32 = 1.0 + 1.0 / 65536.0;

/// Per-ray constants of the slab test and of the watertight triangle test, each splatted over four
/// lanes (one lane per box or triangle).
#[derive(Clone, Copy)]
pub(super) struct RayLanes {
    /// Origin, one splat per axis.
    pub(super) o: [Vec4; 3],
    /// `1/d` per axis; 1/0 and 1/subnormal become ±`f32::MAX` instead of ±∞, so `(plane − o)·inv` is
    /// never 0·∞ = NaN (a ray lying in a box face plane keeps that axis unconstrained, as it should).
    pub(super) inv: [Vec4; 3],
    /// `1/d < 0` per axis: the box plane a ray meets first along that axis is then the max plane.
    pub(super) neg: [bool; 3],
    /// `kz`, the axis of the largest |d| component; `(kx, ky, kz)` is the cyclic rotation of
    /// `(x, y, z)` ending in it. (The paper also swaps `kx`, `ky` when `d_kz < 0` to keep the winding;
    /// for a two-sided test that only negates all three edge functions and the determinant exactly,
    /// which changes no result.)
    pub(super) kz: usize,
    /// Shear constants `Sx = d_kx/d_kz`, `Sy = d_ky/d_kz`, `Sz = 1/d_kz`.
    pub(super) sx: Vec4,
    pub(super) sy: Vec4,
    pub(super) sz: Vec4,
    /// `max(t_min, 0)`.
    pub(super) t_min: Vec4,
}

/// The per-ray constants of [`RayLanes`], one float each (what a ray packet gathers per lane).
#[derive(Clone, Copy, Default)]
pub(super) struct RayConst {
    pub(super) o: [f32; 3],
    pub(super) inv: [f32; 3],
    pub(super) neg: [bool; 3],
    pub(super) kz: usize,
    pub(super) sx: f32,
    pub(super) sy: f32,
    pub(super) sz: f32,
    pub(super) t_min: f32,
    pub(super) t_max: f32,
}

impl RayConst {
    /// The constants of `ray`, or `None` when it can hit nothing: a non-finite origin or direction, a
    /// zero direction, or an empty (or NaN) segment `t_max < max(t_min, 0)`.
    #[inline]
    pub(super) fn new(ray: &Ray) -> Option<Self> {
        let (o, d) = (ray.origin, ray.dir);
        let t_min = ray.t_min.max(0.0);
        if !(o.is_finite() && d.is_finite() && d != Vec3::ZERO && ray.t_max >= t_min) {
            return None;
        }
        let inv_of = |x: f32| {
            let r = 1.0 / x;
            if r.is_finite() { r } else { f32::MAX.copysign(x) }
        };
        let inv = [inv_of(d.x), inv_of(d.y), inv_of(d.z)];
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        let da = d.to_array();
        Some(Self {
            o: o.to_array(),
            inv,
            neg: inv.map(|x| x < 0.0),
            kz,
            sx: da[kx] / da[kz],
            sy: da[ky] / da[kz],
            sz: 1.0 / da[kz],
            t_min,
            t_max: ray.t_max,
        })
    }
}

impl RayLanes {
    /// The constants of `ray`, or `None` when it can hit nothing (see [`RayConst::new`]).
    #[inline]
    pub(super) fn new(ray: &Ray) -> Option<Self> {
        let c = RayConst::new(ray)?;
        Some(Self {
            o: c.o.map(Vec4::splat),
            inv: c.inv.map(Vec4::splat),
            neg: c.neg,
            kz: c.kz,
            sx: Vec4::splat(c.sx),
            sy: Vec4::splat(c.sy),
            sz: Vec4::splat(c.sz),
            t_min: Vec4::splat(c.t_min),
        })
    }

    /// Bit mask of the four children whose box meets `[t_min, t_max]`, and their entry distances:
    /// the slab test `t = (plane − o)·(1/d)` per axis, lane by lane, reading the near and far plane of
    /// each axis by the sign of `1/d` (the same values as taking min and max of both planes, since
    /// rounding is monotone). It is NaN-free (`1/d` is finite and non-zero, the planes finite or
    /// ±∞), so plain SIMD min/max are exact. `t_max_m` is `t_max·BOX_MARGIN`; the far distance is
    /// enlarged by the same factor (module docs). Unused lanes hold empty boxes (min +∞, max −∞), whose
    /// near distance is +∞ and far −∞ whatever the ray, so they never pass.
    #[inline(always)]
    pub(super) fn boxes(&self, n: &Node4, t_max_m: Vec4) -> (u32, Vec4) {
        let p = &n.planes;
        let slab = |a: usize| {
            let near = (p[usize::from(self.neg[a])][a] - self.o[a]) * self.inv[a];
            let far = (p[usize::from(!self.neg[a])][a] - self.o[a]) * self.inv[a];
            (near, far)
        };
        let ((nx, fx), (ny, fy), (nz, fz)) = (slab(0), slab(1), slab(2));
        let near = nx.max(ny).max(nz).max(self.t_min);
        let far = (fx.min(fy).min(fz) * Vec4::splat(BOX_MARGIN)).min(t_max_m);
        (near.cmple(far).bitmask(), near)
    }
}

/// Four triangles in SoA form, `v[k][axis]` holding vertex `k`'s coordinate along `axis` for the four
/// lanes (144 bytes), so that one watertight test checks four triangles at once. A leaf's last packet
/// repeats its last triangle in the unused lanes: a repeated triangle gives the same answer with the
/// same id, which changes neither any-hit nor closest-hit (ties go to the smaller id).
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub(super) struct Tri4 {
    pub(super) v: [[Vec4; 3]; 3],
}

impl Tri4 {
    /// Pack 1 to 4 triangles (repeating the last one).
    pub(super) fn pack(tris: &[[Vec3; 3]]) -> Self {
        let last = tris.len() - 1;
        let mut a = [[[0f32; 4]; 3]; 3];
        for lane in 0..4 {
            let t = &tris[lane.min(last)];
            for (k, p) in t.iter().enumerate() {
                for axis in 0..3 {
                    a[k][axis][lane] = p[axis];
                }
            }
        }
        Self { v: a.map(|k| k.map(Vec4::from_array)) }
    }
}

/// What one four-lane triangle test found: the lanes in `mask` hit at `t`, with barycentric weights
/// `v·inv_det` (second vertex) and `w·inv_det` (third vertex).
pub(super) struct Hits4 {
    pub(super) mask: u32,
    pub(super) t: Vec4,
    pub(super) inv_det: Vec4,
    pub(super) v: Vec4,
    pub(super) w: Vec4,
}

/// The watertight test (Woop, Benthin & Wald 2013) of four triangles for `t ∈ [t_min, t_max]`, with
/// `KZ` = the ray's `kz` (a compile-time constant so the axis rotation costs nothing).
///
/// Each vertex is translated to the ray origin, its axes rotated to `(kx, ky, kz)` and `(x, y)`
/// sheared so the ray runs along +z through the origin: `(p_kx − Sx·p_kz, p_ky − Sy·p_kz, p_kz)`. The
/// scaled barycentrics are the 2D edge functions `U, V, W`; where one is exactly 0 in f32 the lane is
/// decided in f64, where these products are exact (the paper's fallback). A lane hits when `U, V, W`
/// do not have mixed signs, `det = U + V + W ≠ 0` and `t = (U·Sz·a_z + V·Sz·b_z + W·Sz·c_z)·(1/det)` is
/// in range. Every step is one IEEE operation per lane in a fixed order (no FMA contraction in Rust),
/// so each lane's answer is bit-identical to the same triangle tested in any other lane or alone
/// ([`intersect_triangle`]).
#[inline(always)]
pub(super) fn triangles4<const KZ: usize>(r: &RayLanes, p: &Tri4, t_max: Vec4) -> Hits4 {
    let (kx, ky) = ((KZ + 1) % 3, (KZ + 2) % 3);
    let vert = |k: usize| {
        let x = p.v[k][kx] - r.o[kx];
        let y = p.v[k][ky] - r.o[ky];
        let z = p.v[k][KZ] - r.o[KZ];
        (x - r.sx * z, y - r.sy * z, z)
    };
    let ((ax, ay, az), (bx, by, bz), (cx, cy, cz)) = (vert(0), vert(1), vert(2));
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    let zero = Vec4::ZERO;
    let on_edge = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)).bitmask();
    if on_edge != 0 {
        (u, v, w) = edges_f64(on_edge, [ax, ay, bx, by, cx, cy], (u, v, w));
    }
    let mixed =
        (u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero)) & (u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero));
    let det = u + v + w;
    let mask = !mixed.bitmask() & det.cmpne(zero).bitmask();
    if mask == 0 {
        return Hits4 { mask, t: zero, inv_det: zero, v: zero, w: zero };
    }
    let t_scaled = u * (r.sz * az) + v * (r.sz * bz) + w * (r.sz * cz);
    let inv_det = Vec4::ONE / det;
    let t = t_scaled * inv_det;
    let mask = mask & (t.cmpge(r.t_min) & t.cmple(t_max)).bitmask();
    Hits4 { mask, t, inv_det, v, w }
}

/// The f64 re-evaluation of the edge functions `(U, V, W)` in the lanes of `lanes` (where one of them
/// is exactly 0 in f32): with 24-bit inputs the f64 products and differences are exact, so the sign
/// decides the edge case correctly, and adjacent triangles agree.
#[cold]
#[inline(never)]
pub(super) fn edges_f64(lanes: u32, xy: [Vec4; 6], uvw: (Vec4, Vec4, Vec4)) -> (Vec4, Vec4, Vec4) {
    let xy = xy.map(|c| c.to_array());
    let (mut u, mut v, mut w) = (uvw.0.to_array(), uvw.1.to_array(), uvw.2.to_array());
    for lane in (0..4).filter(|l| lanes >> l & 1 != 0) {
        let [ax, ay, bx, by, cx, cy] = xy.map(|c| f64::from(c[lane]));
        u[lane] = (cx * by - cy * bx) as f32;
        v[lane] = (ax * cy - ay * cx) as f32;
        w[lane] = (bx * ay - by * ax) as f32;
    }
    (Vec4::from_array(u), Vec4::from_array(v), Vec4::from_array(w))
}

/// Run `triangles4` with the ray's `kz` as the compile-time constant.
#[inline(always)]
pub(super) fn triangles4_any_kz(r: &RayLanes, p: &Tri4, t_max: Vec4) -> Hits4 {
    match r.kz {
        0 => triangles4::<0>(r, p, t_max),
        1 => triangles4::<1>(r, p, t_max),
        _ => triangles4::<2>(r, p, t_max),
    }
}

/// Intersect one ray with one triangle by the watertight test the BVH uses: `(t, u, v)` with `u`, `v`
/// the barycentric weights of `tri[1]`, `tri[2]`, for `t ∈ [max(t_min,0), t_max]`; two-sided.
///
/// This is the brute-force reference for the BVH queries (the same arithmetic in one lane, so
/// results agree exactly).
pub fn intersect_triangle(ray: &Ray, tri: &[Vec3; 3]) -> Option<(f32, f32, f32)> {
    let r = RayLanes::new(ray)?;
    let h = triangles4_any_kz(&r, &Tri4::pack(std::slice::from_ref(tri)), Vec4::splat(ray.t_max));
    (h.mask & 1 != 0).then(|| {
        let (t, inv_det, v, w) = (h.t.x, h.inv_det.x, h.v.x, h.w.x);
        (t, v * inv_det, w * inv_det)
    })
}

/// Whether the BVH skips this triangle: zero area (`|e1 × e2| = 0` in f32) — it has no interior to hit.
pub fn is_degenerate(tri: &[Vec3; 3]) -> bool {
    (tri[1] - tri[0]).cross(tri[2] - tri[0]).length_squared() == 0.0
}

/// Marks a leaf in a child code: bits 28–30 hold the number of packets minus one, bits 0–27 the first
/// packet. Without it the code is the index of a [`Node4`].
pub(super) const LEAF: u32 = 1 << 31;
/// Shift of the packet count in a leaf code.
pub(super) const PACKETS_SHIFT: u32 = 28;
/// Bits of the first packet (or node index) in a child code.
pub(super) const INDEX_MASK: u32 = (1 << PACKETS_SHIFT) - 1;
// A leaf of up to MAX_LEAF triangles must fit in the 8 packets a code can count, and every packet and
// node index (each at most the number of triangles) in 28 bits.
const _: () = assert!(MAX_LEAF <= 32 && MAX_ELEMENTS <= 1 << PACKETS_SHIFT);

/// The packet indices of a leaf code.
#[inline(always)]
pub(super) fn leaf_packets(code: u32) -> std::ops::Range<usize> {
    let first = (code & INDEX_MASK) as usize;
    first..first + ((code >> PACKETS_SHIFT) & 7) as usize + 1
}

/// Four children's boxes in SoA layout, `planes[0][axis]` their minima and `planes[1][axis]` their
/// maxima along `axis` (one `Vec4` each), so one node test checks four boxes with a few SIMD
/// operations; and the four child codes (an interior [`Node4`] index, or a [`LEAF`] code). 112 bytes,
/// aligned to 64 so a node spans exactly two cache lines. Unused lanes hold the empty box.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(super) struct Node4 {
    pub(super) planes: [[Vec4; 3]; 2],
    pub(super) child: [u32; 4],
}

impl Node4 {
    pub(super) const EMPTY: Self =
        Self { planes: [[Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]], child: [LEAF; 4] };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::uniforms;

    #[test]
    fn each_packet_lane_answers_exactly_as_its_triangle_alone() {
        let mut u = uniforms(17);
        for _ in 0..2000 {
            let tris: Vec<[Vec3; 3]> = (0..4)
                .map(|_| {
                    let c = Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
                    [0; 3].map(|_| c + Vec3::new(u(-0.7, 0.7), u(-0.7, 0.7), u(-0.7, 0.7)))
                })
                .collect();
            let o = Vec3::new(u(-2.0, 2.0), u(-2.0, 2.0), u(-2.0, 2.0));
            let ray =
                Ray::segment(o, -o + Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)), 0.0, u(0.5, 3.0));
            let r = RayLanes::new(&ray).unwrap();
            let h = triangles4_any_kz(&r, &Tri4::pack(&tris), Vec4::splat(ray.t_max));
            for (lane, tri) in tris.iter().enumerate() {
                let packed = (h.mask >> lane & 1 != 0).then(|| {
                    let (t, d, v, w) = (h.t[lane], h.inv_det[lane], h.v[lane], h.w[lane]);
                    (t, v * d, w * d)
                });
                assert_eq!(packed, intersect_triangle(&ray, tri), "lane {lane}");
            }
        }
    }

    /// Möller–Trumbore in f64 (an independent formulation): `(t, u, v)` for a two-sided hit.
    fn reference_f64(ray: &Ray, tri: &[Vec3; 3]) -> Option<(f64, f64, f64)> {
        let [p0, p1, p2] = tri.map(|p| p.as_dvec3());
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let (e1, e2) = (p1 - p0, p2 - p0);
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det == 0.0 {
            return None;
        }
        let tv = o - p0;
        let u = tv.dot(pv) / det;
        let qv = tv.cross(e1);
        let v = d.dot(qv) / det;
        let t = e2.dot(qv) / det;
        (u >= 0.0
            && v >= 0.0
            && u + v <= 1.0
            && t >= f64::from(ray.t_min.max(0.0))
            && t <= f64::from(ray.t_max))
        .then_some((t, u, v))
    }

    #[test]
    fn watertight_test_agrees_with_double_precision_moller_trumbore() {
        let mut u = uniforms(23);
        let (mut hits, mut checked) = (0, 0);
        for _ in 0..20_000 {
            let tri = [0; 3].map(|_| Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)));
            let o = Vec3::new(u(-3.0, 3.0), u(-3.0, 3.0), u(-3.0, 3.0));
            let ray = Ray::new(o, Vec3::new(u(-0.5, 0.5), u(-0.5, 0.5), u(-0.5, 0.5)) - o);
            let want = reference_f64(&ray, &tri);
            // Away from the edges (barycentrics ≥ 1e-4 from 0 and 1) both must agree on hit or miss.
            let clear = want.is_none_or(|(_, a, b)| a.min(b).min(1.0 - a - b) > 1e-4);
            let got = intersect_triangle(&ray, &tri);
            if let (Some((t, a, b)), Some((tw, aw, bw))) = (got, want) {
                assert!((f64::from(t) - tw).abs() <= 1e-5 * tw.max(1.0), "t {t} vs {tw}");
                assert!((f64::from(a) - aw).abs() < 1e-5 && (f64::from(b) - bw).abs() < 1e-5, "uv");
                hits += 1;
            } else if clear && want.is_none() {
                // A miss by a margin: the f32 test must miss too, unless the ray grazes an edge.
                let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
                let grazing = e1.cross(e2).normalize().dot(ray.dir.normalize()).abs() < 1e-3;
                assert!(got.is_none() || grazing, "f32 hit where f64 misses: {ray:?} {tri:?}");
            } else if clear {
                assert!(got.is_some(), "f32 miss where f64 hits clearly: {ray:?} {tri:?}");
            }
            checked += 1;
        }
        assert!(hits > 500 && hits < checked, "{hits} of {checked}");
    }
}
