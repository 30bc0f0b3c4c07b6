//! A bounding volume hierarchy over world-space triangles, built with a binned surface-area heuristic,
//! and exact closest-hit / any-hit ray queries (the ray caster behind obscurance and shadows).
//!
//! ## Why our own, and not a crate
//! The two maintained crates were looked at on crates.io: `bvh` 0.13 (nalgebra types, a generic
//! shape trait, Möller–Trumbore style tests, MSRV 1.90 above the workspace's 1.85) and `obvhs` 0.4 (fast
//! PLOC/CWBVH builders on glam, but `unsafe` traversal, a radix-sort dependency and no watertight
//! triangle test). What this crate needs is small and specific: a deterministic build, a watertight
//! triangle test, a documented tie rule so queries equal brute force exactly, `t_min`/`t_max` ray
//! segments and no `unsafe` (the workspace denies it). That fits in this one file, which keeps the
//! behaviour under our control and under test (`tests/bvh.rs` compares against brute force).
//!
//! ## Build (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies")
//! Top-down: each node bins its primitives' centroids into [`BINS`] bins along each axis, evaluates
//! the SAH cost `C_trav + (A_L·P(N_L) + A_R·P(N_R))/A` at the bin boundaries of all three axes and
//! splits at the cheapest, where `P(N) = ⌈N/4⌉` counts the four-triangle packets a leaf of `N` is
//! tested in (see Layout); it stops at a leaf when that is not cheaper than testing all of them
//! (`P(N)`) and there are at most [`MAX_LEAF`] triangles. Subtrees above [`PARALLEL_THRESHOLD`] triangles are built in
//! parallel with `rayon::join` on disjoint halves of the primitive array; the split decisions depend on
//! the data only, so the tree is **the same whatever the number of threads**. Below depth
//! [`SAH_DEPTH_LIMIT`] a node falls back to an object-median split, which bounds the depth (and the
//! traversal stack) on pathological input.
//!
//! ## Layout
//! The binary SAH tree is collapsed into a 4-wide tree (Wald, Benthin & Boulos 2008, "Getting rid of
//! packets"; the layout of Embree's BVH4): each node holds its up to four children's boxes in SoA form
//! (one `Vec4` per bound and axis) and four 32-bit child codes (an interior node index, or a leaf's
//! first triangle packet and packet count), 128 bytes per node. A traversal step tests four boxes with
//! a dozen SIMD operations, reading each axis's near and far plane by the sign of the ray direction
//! (no min/max per slab), and the tree is about half as deep. Leaf triangles are stored in packets
//! of four in SoA form (Embree's `Triangle4`), so one watertight test checks four triangles at once.
//! Closest-hit visits children nearest first and skips entries farther than the best hit so far;
//! any-hit visits them in any order and tests leaves as soon as their box is hit. The query loops
//! are compiled once per dominant ray axis (a const generic), so the watertight test's axis rotation
//! costs nothing per triangle.
//!
//! ## Queries
//! A ray is `origin + t·dir` for `t ∈ [max(t_min, 0), t_max]`; `dir` need not be unit (t is then in
//! units of `|dir|`); a non-finite origin or direction, a zero direction or an empty segment
//! (`t_max < max(t_min, 0)`, or NaN) hits nothing. Triangles are two-sided. The triangle test is the watertight one of Woop, Benthin
//! & Wald 2013 ("Watertight ray/triangle intersection", JCGT 2(1)): a ray through a shared edge or
//! vertex of a closed mesh hits at least one of the triangles that share it, never slips between.
//! Box tests are conservative: the far distance of a box, and the `t_max` it is tested against,
//! are enlarged by the factor `1 + 2⁻¹⁶` — far more than the few-ulp rounding of the slab test
//! (pbrt-v4 §6.8.2 uses `1 + 2γ₃`) and of the triangle test's `t` — so a box never rejects a ray that
//! its triangle test would accept, and a triangle hit at exactly the best `t` so far is still reached
//! (which the tie rule below needs). It costs a negligible amount of pruning.
//!
//! **Ties.** The closest hit is the smallest `t`; among hits at exactly the same `t` (a ray through a
//! shared edge), the one with the smallest original triangle id. So the answer does not depend on the
//! traversal order and equals a brute-force loop using [`intersect_triangle`] with the same rule.
//!
//! **Batches.** [`Bvh::closest_hits`] and [`Bvh::any_hits`] answer each ray exactly as the single-ray
//! queries do; large batches are traced in the Morton order of the rays' origin cells (a stable,
//! parallel counting sort) and each block of sorted rays is copied together before it is traced, so
//! that consecutive rays share cached nodes and no query waits for its own ray to arrive from memory.

use glam::{Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use crate::{Mesh, RasterError, mesh::MAX_ELEMENTS};

/// Number of centroid bins per axis for the SAH (16 is the usual knee of quality vs. build time).
pub const BINS: usize = 16;
/// Largest leaf the SAH may choose; larger nodes are always split.
pub const MAX_LEAF: usize = 8;
/// Subtrees with more triangles than this are built in parallel.
pub const PARALLEL_THRESHOLD: usize = 8192;
/// Batches larger than this are traced in Morton order of the ray origins ([`Bvh::any_hits`]).
pub const COHERENT_BATCH: usize = 4096;
/// Cells per axis of the grid whose Morton order sorts large batches (32³ cells, 15-bit keys).
const SORT_GRID: u32 = 32;
/// Number of sort keys.
const SORT_BUCKETS: usize = (SORT_GRID * SORT_GRID * SORT_GRID) as usize;
/// Sorted rays gathered and traced per block.
const GATHER_BLOCK: usize = 512;
/// Rays per chunk of the parallel counting sort.
const SORT_CHUNK: usize = 1 << 16;
/// Depth below which nodes are split at the object median instead of by SAH (bounds the tree depth).
pub const SAH_DEPTH_LIMIT: usize = 48;
/// Cost of one traversal step relative to one triangle test, in the SAH.
const TRAVERSAL_COST: f32 = 1.0;
/// Cost of testing one packet of four triangles, relative to one traversal step, in the SAH.
const PACKET_COST: f32 = 1.0;
const _: () = assert!(TRAVERSAL_COST >= PACKET_COST, "choose_split's shortcut for n ≤ 4 relies on it");

/// SAH cost of a leaf of `n` triangles: one four-wide test per started packet of four (Embree's
/// `Triangle4` cost model), so a leaf of 3 costs as much as a leaf of 4 and the build fills packets.
#[inline]
fn leaf_cost(n: u32) -> f32 {
    n.div_ceil(4) as f32 * PACKET_COST
}
/// Traversal stack entries kept inline; deeper stacks spill to the heap. A wide node pushes at most 4
/// entries after popping one, so a path of depth `D` keeps at most `3D + 1` entries; typical trees need
/// far fewer than 64, and a small array is cheap to set up for every ray.
const STACK: usize = 64;
const _: () = assert!(STACK.is_power_of_two());

/// A LIFO stack with [`STACK`] entries inline and a heap spill beyond (for pathological depths).
///
/// The hot paths only touch the inline array: a push onto a full array first moves its older half to
/// the heap, a pop from an empty array first brings back the newest spilled half, so `len` is always
/// below [`STACK`] between operations and `len & (STACK − 1)` indexes without a bounds check.
struct Stack<T: Copy + Default> {
    inline: [T; STACK],
    len: usize,
    /// Older entries, oldest first.
    spill: Vec<T>,
}

impl<T: Copy + Default> Stack<T> {
    #[inline(always)]
    fn new(first: T) -> Self {
        let mut inline = [T::default(); STACK];
        inline[0] = first;
        Self { inline, len: 1, spill: Vec::new() }
    }
    #[inline(always)]
    fn push(&mut self, x: T) {
        if self.len == STACK {
            self.spill_half();
        }
        self.inline[self.len & (STACK - 1)] = x;
        self.len += 1;
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<T> {
        if self.len == 0 && !self.refill() {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len & (STACK - 1)])
    }
    #[cold]
    #[inline(never)]
    fn spill_half(&mut self) {
        self.spill.extend_from_slice(&self.inline[..STACK / 2]);
        self.inline.copy_within(STACK / 2.., 0);
        self.len = STACK / 2;
    }
    /// Bring back up to half a stack of spilled entries; false when there are none.
    #[cold]
    #[inline(never)]
    fn refill(&mut self) -> bool {
        let k = self.spill.len().min(STACK / 2);
        let from = self.spill.len() - k;
        self.inline[..k].copy_from_slice(&self.spill[from..]);
        self.spill.truncate(from);
        self.len = k;
        k > 0
    }
}
/// Conservative enlargement of box far distances and of the `t_max` they are tested against (see the
/// module docs): `1 + 2⁻¹⁶`, against rounding errors of a few ulps (2⁻²³ each).
const BOX_MARGIN: f32 = 1.0 + 1.0 / 65536.0;

/// A ray segment `origin + t·dir`, `t ∈ [max(t_min, 0), t_max]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Start point (world space).
    pub origin: Vec3,
    /// Direction; need not be unit (then `t` is in units of its length). A zero or non-finite
    /// direction (or origin) hits nothing; components below ~1e-38 in magnitude are treated as 0 by the
    /// box test.
    pub dir: Vec3,
    /// Smallest accepted `t` (negative values act as 0).
    pub t_min: f32,
    /// Largest accepted `t` (may be `f32::INFINITY`).
    pub t_max: f32,
}

impl Ray {
    /// A ray over `[0, ∞)`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir, t_min: 0.0, t_max: f32::INFINITY }
    }

    /// A ray over `[t_min, t_max]`.
    pub fn segment(origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Self {
        Self { origin, dir, t_min, t_max }
    }
}

/// A ray–triangle hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point (`origin + t·dir`).
    pub t: f32,
    /// Index of the triangle in the input the BVH was built from.
    pub triangle: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the third vertex; the first has `1 − u − v`.
    pub v: f32,
}

/// Per-ray constants of the slab test and of the watertight triangle test, each splatted over four
/// lanes (one lane per box or triangle).
#[derive(Clone, Copy)]
struct RayLanes {
    /// Origin, one splat per axis.
    o: [Vec4; 3],
    /// `1/d` per axis; 1/0 and 1/subnormal become ±`f32::MAX` instead of ±∞, so `(plane − o)·inv` is
    /// never 0·∞ = NaN (a ray lying in a box face plane keeps that axis unconstrained, as it should).
    inv: [Vec4; 3],
    /// `1/d < 0` per axis: the box plane a ray meets first along that axis is then the max plane.
    neg: [bool; 3],
    /// `kz`, the axis of the largest |d| component; `(kx, ky, kz)` is the cyclic rotation of
    /// `(x, y, z)` ending in it. (The paper also swaps `kx`, `ky` when `d_kz < 0` to keep the winding;
    /// for a two-sided test that only negates all three edge functions and the determinant exactly,
    /// which changes no result.)
    kz: usize,
    /// Shear constants `Sx = d_kx/d_kz`, `Sy = d_ky/d_kz`, `Sz = 1/d_kz`.
    sx: Vec4,
    sy: Vec4,
    sz: Vec4,
    /// `max(t_min, 0)`.
    t_min: Vec4,
}

impl RayLanes {
    /// The constants of `ray`, or `None` when it can hit nothing: a non-finite origin or direction, a
    /// zero direction, or an empty (or NaN) segment `t_max < max(t_min, 0)`.
    #[inline]
    fn new(ray: &Ray) -> Option<Self> {
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
        let (da, oa) = (d.to_array(), o.to_array());
        Some(Self {
            o: oa.map(Vec4::splat),
            inv: inv.map(Vec4::splat),
            neg: inv.map(|x| x < 0.0),
            kz,
            sx: Vec4::splat(da[kx] / da[kz]),
            sy: Vec4::splat(da[ky] / da[kz]),
            sz: Vec4::splat(1.0 / da[kz]),
            t_min: Vec4::splat(t_min),
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
    fn boxes(&self, n: &Node4, t_max_m: Vec4) -> (u32, Vec4) {
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
struct Tri4 {
    v: [[Vec4; 3]; 3],
}

impl Tri4 {
    /// Pack 1 to 4 triangles (repeating the last one).
    fn pack(tris: &[[Vec3; 3]]) -> Self {
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
struct Hits4 {
    mask: u32,
    t: Vec4,
    inv_det: Vec4,
    v: Vec4,
    w: Vec4,
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
fn triangles4<const KZ: usize>(r: &RayLanes, p: &Tri4, t_max: Vec4) -> Hits4 {
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
fn edges_f64(lanes: u32, xy: [Vec4; 6], uvw: (Vec4, Vec4, Vec4)) -> (Vec4, Vec4, Vec4) {
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
fn triangles4_any_kz(r: &RayLanes, p: &Tri4, t_max: Vec4) -> Hits4 {
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

/// Shape of a [`Bvh`] (see [`Bvh::stats`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BvhStats {
    /// Entries in the node array (including the unused pad at index 1).
    pub nodes: usize,
    /// Leaf nodes.
    pub leaves: usize,
    /// Largest number of triangles in a leaf.
    pub max_leaf: usize,
    /// Depth of the deepest leaf (root = 1).
    pub max_depth: usize,
    /// SAH cost `Σ_interior C_trav·A(n)/A(root) + Σ_leaves N·A(n)/A(root)`, in triangle tests.
    pub sah_cost: f64,
}

fn half_area(n: &Node) -> f32 {
    let e = (n.max() - n.min()).max(Vec3A::ZERO);
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// A node: its box, then either (leaf, `count > 0`) the first triangle in leaf order and the count, or
/// (interior, `count == 0`) the index of the first of its two adjacent children. Stored as two `Vec4`
/// whose `w` lanes carry `first` and `count` as bit patterns, so a box loads as two aligned vectors.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(32))]
struct Node {
    lo: Vec4,
    hi: Vec4,
}

impl Node {
    #[inline]
    fn new(min: Vec3A, max: Vec3A, first: u32, count: u32) -> Self {
        Self { lo: min.extend(f32::from_bits(first)), hi: max.extend(f32::from_bits(count)) }
    }
    #[inline(always)]
    fn min(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }
    #[inline(always)]
    fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }
    #[inline(always)]
    fn first(&self) -> u32 {
        self.lo.w.to_bits()
    }
    #[inline(always)]
    fn count(&self) -> u32 {
        self.hi.w.to_bits()
    }
}

/// A primitive during the build: its box, and its index in the input in the `w` lane of `lo` (32
/// bytes, so the partitions move less memory).
#[derive(Clone, Copy)]
struct PrimRef {
    lo: Vec4,
    hi: Vec4,
}

impl PrimRef {
    #[inline]
    fn new(min: Vec3A, max: Vec3A, idx: u32) -> Self {
        Self { lo: min.extend(f32::from_bits(idx)), hi: max.extend(0.0) }
    }
    #[inline(always)]
    fn min(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }
    #[inline(always)]
    fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }
    #[inline(always)]
    fn idx(&self) -> u32 {
        self.lo.w.to_bits()
    }
    /// Twice the box centre (the SAH only compares centroids).
    #[inline(always)]
    fn centroid2(&self) -> Vec3A {
        self.min() + self.max()
    }
}

/// A node's box and the box of its primitives' (doubled) centroids.
type Bounds = (Aabb, Aabb);

/// What [`choose_split`] decided.
enum Split {
    Leaf,
    /// Split after `mid` primitives, with the bounds of both halves (gathered while partitioning).
    At {
        mid: usize,
        left: Bounds,
        right: Bounds,
    },
}

#[derive(Debug, Clone, Copy)]
struct Aabb {
    min: Vec3A,
    max: Vec3A,
}

impl Aabb {
    const EMPTY: Self = Self { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };
    #[inline]
    fn grow(&mut self, min: Vec3A, max: Vec3A) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }
    #[inline]
    fn merge(self, o: Self) -> Self {
        Self { min: self.min.min(o.min), max: self.max.max(o.max) }
    }
    /// Half the surface area (the SAH only needs ratios).
    #[inline]
    fn half_area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }
}

/// A subtree under construction: split nodes near the root (built in parallel) over flat chunks.
enum Sub {
    Split {
        bounds: Aabb,
        left: Box<Sub>,
        right: Box<Sub>,
    },
    /// Local node array: index 0 is the subtree root; children indices are local; leaf `first` global.
    Flat(Vec<Node>),
}

/// A BVH over triangles, with exact closest-hit and any-hit queries (see the module docs).
#[derive(Debug, Clone)]
pub struct Bvh {
    /// 4-wide nodes (collapsed from the binary SAH tree), root at 0.
    wide: Vec<Node4>,
    /// Scene box.
    root: Aabb,
    /// Shape of the binary tree it was collapsed from.
    stats: BvhStats,
    /// Leaf triangles in packets of four (see [`Tri4`]), in depth-first leaf order.
    packets: Vec<Tri4>,
    /// Original triangle id of each lane of `packets`.
    ids: Vec<[u32; 4]>,
    /// Triangles in the tree (the input minus degenerate ones).
    triangles: usize,
    input_triangles: usize,
}

impl Bvh {
    /// Build over an indexed triangle list (world space).
    ///
    /// Errors: an index out of range, a non-finite vertex used by a face, more than
    /// [`MAX_ELEMENTS`] triangles, or memory that cannot be reserved. Degenerate (zero-area) triangles
    /// are skipped: they are never hit, and [`Bvh::skipped_triangles`] counts them. Triangle ids in hits
    /// are indices into `indices`.
    pub fn build(positions: &[Vec3], indices: &[[u32; 3]]) -> Result<Self, RasterError> {
        let nv = positions.len();
        if let Some((f, &i)) = indices
            .iter()
            .enumerate()
            .find_map(|(f, t)| t.iter().find(|&&i| i as usize >= nv).map(|i| (f, i)))
        {
            return Err(RasterError::InvalidMesh(format!(
                "face {f} indexes vertex {i}, but there are only {nv} vertices"
            )));
        }
        Self::build_with(indices.len(), |f| indices[f].map(|i| positions[i as usize]))
    }

    /// Build over a triangle soup (world space); triangle ids are indices into `triangles`.
    /// Same errors and skipping as [`Bvh::build`].
    pub fn from_triangles(triangles: &[[Vec3; 3]]) -> Result<Self, RasterError> {
        Self::build_with(triangles.len(), |f| triangles[f])
    }

    /// Build over one mesh (its positions as they are).
    pub fn from_mesh(mesh: &Mesh) -> Result<Self, RasterError> {
        Self::build(&mesh.positions, &mesh.indices)
    }

    /// Build over several meshes, each placed by its model-to-world matrix. Triangle ids run through
    /// the meshes in order: mesh `k`'s triangle `f` has id `f + Σ_{j<k} triangles(j)`.
    pub fn from_instances(instances: &[(&Mesh, Mat4)]) -> Result<Self, RasterError> {
        let total: usize = instances.iter().map(|(m, _)| m.indices.len()).sum();
        let mut starts = Vec::with_capacity(instances.len());
        let mut acc = 0usize;
        for (m, _) in instances {
            starts.push(acc);
            acc += m.indices.len();
        }
        let find = |f: usize| {
            let k = starts.partition_point(|&s| s <= f) - 1;
            (k, f - starts[k])
        };
        Self::build_with(total, |f| {
            let (k, local) = find(f);
            let (m, xf) = &instances[k];
            // Projective transforms divide by w, as the renderer's vertex stage does.
            if xf.row(3) == Vec4::W {
                m.triangle(local).map(|p| xf.transform_point3(p))
            } else {
                m.triangle(local).map(|p| xf.project_point3(p))
            }
        })
    }

    /// Build over several indexed triangle lists already in world space, `(positions, indices)` each.
    /// Triangle ids run through the parts in order, as in [`Bvh::from_instances`].
    pub fn from_parts(parts: &[(&[Vec3], &[[u32; 3]])]) -> Result<Self, RasterError> {
        let mut starts = Vec::with_capacity(parts.len());
        let mut acc = 0usize;
        for (k, (p, ix)) in parts.iter().enumerate() {
            if let Some((f, &i)) = ix
                .iter()
                .enumerate()
                .find_map(|(f, t)| t.iter().find(|&&i| i as usize >= p.len()).map(|i| (f, i)))
            {
                return Err(RasterError::InvalidMesh(format!(
                    "part {k}: face {f} indexes vertex {i}, but there are only {} vertices",
                    p.len()
                )));
            }
            starts.push(acc);
            acc += ix.len();
        }
        Self::build_with(acc, |f| {
            let k = starts.partition_point(|&s| s <= f) - 1;
            let (p, ix) = parts[k];
            ix[f - starts[k]].map(|i| p[i as usize])
        })
    }

    fn build_with(n: usize, tri: impl Fn(usize) -> [Vec3; 3] + Sync) -> Result<Self, RasterError> {
        if n > MAX_ELEMENTS {
            return Err(RasterError::InvalidMesh(format!(
                "{n} triangles exceed the BVH limit of {MAX_ELEMENTS}"
            )));
        }
        // Refuse up front what cannot be allocated, with the size in the message (about 100 bytes
        // per triangle at the peak: refs, leaf-ordered vertices, ids and nodes).
        let too_big = |what: &str| {
            RasterError::InvalidMesh(format!(
                "cannot allocate the BVH {what} for {n} triangles (about {:.1} GiB in all)",
                (n as f64 * 100.0) / (1u64 << 30) as f64
            ))
        };
        if let Some(f) = (0..n).into_par_iter().find_first(|&f| !tri(f).iter().all(|p| p.is_finite())) {
            return Err(RasterError::InvalidMesh(format!("triangle {f} has a non-finite vertex")));
        }
        let mut refs: Vec<PrimRef> = Vec::new();
        refs.try_reserve_exact(n).map_err(|_| too_big("primitive list"))?;
        refs.par_extend((0..n).into_par_iter().filter_map(|f| {
            let t = tri(f);
            if is_degenerate(&t) {
                return None;
            }
            let (a, b, c) = (Vec3A::from(t[0]), Vec3A::from(t[1]), Vec3A::from(t[2]));
            Some(PrimRef::new(a.min(b).min(c), a.max(b).max(c), f as u32))
        }));
        if refs.is_empty() {
            // Nothing to hit: a root with no children.
            return Ok(Self {
                wide: vec![Node4::EMPTY],
                root: Aabb::EMPTY,
                stats: BvhStats::default(),
                packets: Vec::new(),
                ids: Vec::new(),
                triangles: 0,
                input_triangles: n,
            });
        }
        let mut nodes: Vec<Node> = Vec::new();
        nodes.try_reserve_exact(2 * refs.len()).map_err(|_| too_big("node array"))?;
        let root_bounds = bounds_of(&refs);
        let sub = build_sub(&mut refs, 0, 0, root_bounds);
        place(sub, 0, &mut nodes, true);
        let stats = binary_stats(&nodes);
        let root = Aabb { min: nodes[0].min(), max: nodes[0].max() };
        let mut tris: Vec<[Vec3; 3]> = Vec::new();
        tris.try_reserve_exact(refs.len()).map_err(|_| too_big("triangle array"))?;
        tris.par_extend(refs.par_iter().map(|r| tri(r.idx() as usize)));
        let ids: Vec<u32> = refs.iter().map(|r| r.idx()).collect();
        drop(refs);
        // Exactly one packet per started group of four triangles in each leaf.
        let n_packets: usize = nodes.iter().map(|nd| (nd.count() as usize).div_ceil(4)).sum();
        let mut out =
            WideOut { tris: &tris, ids: &ids, wide: Vec::new(), packets: Vec::new(), packet_ids: Vec::new() };
        out.wide.try_reserve_exact(nodes.len() / 2 + 1).map_err(|_| too_big("node array"))?;
        out.packets.try_reserve_exact(n_packets).map_err(|_| too_big("triangle array"))?;
        out.packet_ids.try_reserve_exact(n_packets).map_err(|_| too_big("triangle array"))?;
        collapse(&nodes, 0, &mut out);
        let WideOut { wide, packets, packet_ids, .. } = out;
        let stats = BvhStats { nodes: wide.len(), ..stats };
        Ok(Self { wide, root, stats, packets, ids: packet_ids, triangles: tris.len(), input_triangles: n })
    }

    /// Number of triangles in the input (including skipped ones).
    pub fn input_triangles(&self) -> usize {
        self.input_triangles
    }

    /// Number of triangles in the tree (the input minus degenerate ones).
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// Number of degenerate (zero-area) input triangles that were skipped.
    pub fn skipped_triangles(&self) -> usize {
        self.input_triangles - self.triangles
    }

    /// Number of (4-wide) nodes in the flat array.
    pub fn node_count(&self) -> usize {
        self.wide.len()
    }

    /// The scene box `(min, max)` of all non-degenerate triangles (inverted when there are none).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.root.min.into(), self.root.max.into())
    }

    /// The largest coordinate magnitude in the scene box (0 for an empty tree), the scale that
    /// self-intersection offsets must exceed.
    pub fn coordinate_scale(&self) -> f32 {
        if self.triangles == 0 {
            return 0.0;
        }
        let (lo, hi) = self.bounds();
        lo.abs().max(hi.abs()).max_element()
    }

    /// Shape of the tree: node, leaf and depth counts and the SAH cost (for benchmarks and tuning).
    pub fn stats(&self) -> BvhStats {
        self.stats
    }

    /// The closest hit on the segment, or `None` (ties: see the module docs).
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let r = RayLanes::new(ray)?;
        match r.kz {
            0 => self.closest_hit_k::<0>(&r, ray.t_max),
            1 => self.closest_hit_k::<1>(&r, ray.t_max),
            _ => self.closest_hit_k::<2>(&r, ray.t_max),
        }
    }

    fn closest_hit_k<const KZ: usize>(&self, r: &RayLanes, t_max: f32) -> Option<Hit> {
        let mut best_t = t_max;
        let mut best: Option<Hit> = None;
        // Entries: (child code, entry distance).
        let mut stack = Stack::new((0u32, f32::NEG_INFINITY));
        while let Some((code, dist)) = stack.pop() {
            if dist > best_t * BOX_MARGIN {
                continue;
            }
            if code & LEAF != 0 {
                for k in leaf_packets(code) {
                    let h = triangles4::<KZ>(r, &self.packets[k], Vec4::splat(best_t));
                    let mut bits = h.mask;
                    if bits == 0 {
                        continue;
                    }
                    let (t, inv_det, v, w) =
                        (h.t.to_array(), h.inv_det.to_array(), h.v.to_array(), h.w.to_array());
                    while bits != 0 {
                        let lane = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        let (t, id) = (t[lane], self.ids[k][lane]);
                        // Smallest t; equal t → smallest id (independent of traversal order).
                        if best.is_none_or(|b| t < b.t || (t == b.t && id < b.triangle)) {
                            best_t = t;
                            let (u, v) = (v[lane] * inv_det[lane], w[lane] * inv_det[lane]);
                            best = Some(Hit { t, triangle: id, u, v });
                        }
                    }
                }
                continue;
            }
            let node = &self.wide[code as usize];
            let (mask, near) = r.boxes(node, Vec4::splat(best_t * BOX_MARGIN));
            let near = near.to_array();
            // Push the hit children farthest first, so the nearest is popped next.
            let mut order = [(0f32, 0usize); 4];
            let mut k = 0;
            let mut bits = mask;
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let d = near[lane];
                let mut j = k;
                while j > 0 && order[j - 1].0 < d {
                    order[j] = order[j - 1];
                    j -= 1;
                }
                order[j] = (d, lane);
                k += 1;
            }
            for &(d, lane) in &order[..k] {
                stack.push((node.child[lane], d));
            }
        }
        best
    }

    /// Whether anything is hit on the segment (shadow and visibility rays); stops at the first hit.
    pub fn any_hit(&self, ray: &Ray) -> bool {
        let Some(r) = RayLanes::new(ray) else { return false };
        match r.kz {
            0 => self.any_hit_k::<0>(&r, ray.t_max),
            1 => self.any_hit_k::<1>(&r, ray.t_max),
            _ => self.any_hit_k::<2>(&r, ray.t_max),
        }
    }

    fn any_hit_k<const KZ: usize>(&self, r: &RayLanes, t_max: f32) -> bool {
        let (t_max_v, t_max_m) = (Vec4::splat(t_max), Vec4::splat(t_max * BOX_MARGIN));
        // Any order finds a hit if there is one, so children are visited in lane order, leaves at
        // once (the cheapest chance to stop) and interior nodes through the stack.
        let mut stack = Stack::new(0u32);
        while let Some(code) = stack.pop() {
            let node = &self.wide[code as usize];
            let (mut bits, _) = r.boxes(node, t_max_m);
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let child = node.child[lane];
                if child & LEAF == 0 {
                    stack.push(child);
                } else if leaf_packets(child)
                    .any(|k| triangles4::<KZ>(r, &self.packets[k], t_max_v).mask != 0)
                {
                    return true;
                }
            }
        }
        false
    }

    /// [`Bvh::closest_hit`] for every ray, in parallel; `out[i]` answers `rays[i]` (same result at any
    /// thread count: each ray is independent). Large batches are traced in Morton order of their
    /// origins (see [`Bvh::any_hits`]).
    pub fn closest_hits(&self, rays: &[Ray]) -> Vec<Option<Hit>> {
        self.batch(rays, |r| self.closest_hit(r))
    }

    /// [`Bvh::any_hit`] for every ray, in parallel; `out[i]` answers `rays[i]`.
    ///
    /// Batches of more than [`COHERENT_BATCH`] rays are traced in the Morton order of their origins'
    /// cells on a 32³ grid over the scene (a stable counting sort, linear in the batch and parallel),
    /// so that consecutive rays walk the same nodes while those are in cache — 1.3–1.6× faster on random
    /// surface rays on the 516k-triangle teapot, whose tree exceeds the caches — and the answers are
    /// put back in input order.
    pub fn any_hits(&self, rays: &[Ray]) -> Vec<bool> {
        self.batch(rays, |r| self.any_hit(r))
    }

    fn batch<T: Send + Sync + Copy + Default>(
        &self,
        rays: &[Ray],
        f: impl Fn(&Ray) -> T + Sync + Send,
    ) -> Vec<T> {
        if rays.len() <= COHERENT_BATCH || rays.len() > u32::MAX as usize || self.triangles == 0 {
            return rays.par_iter().with_min_len(256).map(f).collect();
        }
        // The key of a ray: the 15-bit Morton code of its origin's cell on a 32³ grid over the scene
        // box. Rays from one cell start in the same subtrees, which then stay in cache.
        let (lo, hi) = (self.root.min, self.root.max);
        let top = (SORT_GRID - 1) as f32;
        let scale = Vec3A::select((hi - lo).cmpgt(Vec3A::ZERO), Vec3A::splat(top) / (hi - lo), Vec3A::ZERO);
        let key = |r: &Ray| -> usize {
            let q = ((Vec3A::from(r.origin) - lo) * scale).clamp(Vec3A::ZERO, Vec3A::splat(top));
            (spread_bits(q.x as u32) | spread_bits(q.y as u32) << 1 | spread_bits(q.z as u32) << 2) as usize
        };
        // A stable counting sort by key, over fixed chunks of the input in parallel: a ray's rank is
        // the number of rays with a smaller key, plus those with its key in earlier chunks, plus those
        // before it in its chunk. The ranks depend on the input only (not on the thread count).
        let hist: Vec<Vec<u32>> = rays
            .par_chunks(SORT_CHUNK)
            .map(|c| {
                let mut h = vec![0u32; SORT_BUCKETS];
                for r in c {
                    h[key(r)] += 1;
                }
                h
            })
            .collect();
        let mut next = hist;
        let mut at = 0u32;
        for k in 0..SORT_BUCKETS {
            for h in next.iter_mut() {
                (h[k], at) = (at, at + h[k]);
            }
        }
        let mut rank = vec![0u32; rays.len()];
        rank.par_chunks_mut(SORT_CHUNK).zip(rays.par_chunks(SORT_CHUNK)).zip(next.par_iter_mut()).for_each(
            |((rank, chunk), next)| {
                for (p, r) in rank.iter_mut().zip(chunk) {
                    let slot = &mut next[key(r)];
                    *p = *slot;
                    *slot += 1;
                }
            },
        );
        let mut order = vec![0u32; rays.len()];
        for (i, &p) in rank.iter().enumerate() {
            order[p as usize] = i as u32;
        }
        // Each block of sorted rays is first gathered into a local buffer: the gather's loads are
        // independent, so their cache misses overlap, where a query that loads its own ray from a
        // random place waits for it (a quarter of the time on a 1M-ray batch).
        let mut sorted = vec![T::default(); rays.len()];
        sorted.par_chunks_mut(GATHER_BLOCK).zip(order.par_chunks(GATHER_BLOCK)).for_each_init(
            || Vec::with_capacity(GATHER_BLOCK),
            |buf: &mut Vec<Ray>, (out, idx)| {
                buf.clear();
                buf.extend(idx.iter().map(|&i| rays[i as usize]));
                for (o, r) in out.iter_mut().zip(buf.iter()) {
                    *o = f(r);
                }
            },
        );
        rank.par_iter().with_min_len(4096).map(|&p| sorted[p as usize]).collect()
    }
}

/// The 10 low bits of `x` spread to every third bit (Morton encoding).
#[inline]
fn spread_bits(x: u32) -> u64 {
    let mut x = u64::from(x & 0x3ff);
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    x = (x | x << 2) & 0x0924_9249;
    x
}

/// Marks a leaf in a child code: bits 28–30 hold the number of packets minus one, bits 0–27 the first
/// packet. Without it the code is the index of a [`Node4`].
const LEAF: u32 = 1 << 31;
/// Shift of the packet count in a leaf code.
const PACKETS_SHIFT: u32 = 28;
/// Bits of the first packet (or node index) in a child code.
const INDEX_MASK: u32 = (1 << PACKETS_SHIFT) - 1;
// A leaf of up to MAX_LEAF triangles must fit in the 8 packets a code can count, and every packet and
// node index (each at most the number of triangles) in 28 bits.
const _: () = assert!(MAX_LEAF <= 32 && MAX_ELEMENTS <= 1 << PACKETS_SHIFT);

/// The packet indices of a leaf code.
#[inline(always)]
fn leaf_packets(code: u32) -> std::ops::Range<usize> {
    let first = (code & INDEX_MASK) as usize;
    first..first + ((code >> PACKETS_SHIFT) & 7) as usize + 1
}

/// Four children's boxes in SoA layout, `planes[0][axis]` their minima and `planes[1][axis]` their
/// maxima along `axis` (one `Vec4` each), so one node test checks four boxes with a few SIMD
/// operations; and the four child codes (an interior [`Node4`] index, or a [`LEAF`] code). 112 bytes,
/// aligned to 64 so a node spans exactly two cache lines. Unused lanes hold the empty box.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Node4 {
    planes: [[Vec4; 3]; 2],
    child: [u32; 4],
}

impl Node4 {
    const EMPTY: Self = Self { planes: [[Vec4::INFINITY; 3], [Vec4::NEG_INFINITY; 3]], child: [LEAF; 4] };
}

/// Where the collapse writes: 4-wide nodes, triangle packets and their ids.
struct WideOut<'a> {
    /// Triangles in leaf order (as the binary leaves index them) and their original ids.
    tris: &'a [[Vec3; 3]],
    ids: &'a [u32],
    wide: Vec<Node4>,
    packets: Vec<Tri4>,
    packet_ids: Vec<[u32; 4]>,
}

/// Collapse the binary subtree at `i` into 4-wide nodes appended to `out.wide`; returns the index of
/// the wide node made for `i`. Children are opened largest surface area first until there are four
/// (or only leaves), the usual BVH2 → BVH4 collapse (Wald et al. 2008, "Getting rid of packets").
/// Leaves become runs of triangle packets, written in depth-first order.
fn collapse(nodes: &[Node], i: usize, out: &mut WideOut) -> u32 {
    let at = out.wide.len();
    out.wide.push(Node4::EMPTY);
    let mut buf = [0usize; 4];
    let mut len = if nodes[i].count() > 0 {
        buf[0] = i;
        1
    } else {
        let c = nodes[i].first() as usize;
        (buf[0], buf[1]) = (c, c + 1);
        2
    };
    while len < 4 {
        // The interior child with the largest area (ties: the first), opened into its two children.
        let mut pick: Option<(usize, f32)> = None;
        for (j, &k) in buf[..len].iter().enumerate() {
            if nodes[k].count() == 0 {
                let a = half_area(&nodes[k]);
                if pick.is_none_or(|(_, best)| a > best) {
                    pick = Some((j, a));
                }
            }
        }
        let Some((j, _)) = pick else { break };
        let c = nodes[buf[j]].first() as usize;
        buf.copy_within(j + 1..len, j + 2);
        (buf[j], buf[j + 1]) = (c, c + 1);
        len += 1;
    }
    let kids = &buf[..len];
    let mut w = Node4::EMPTY;
    let mut planes = [[[f32::INFINITY; 4]; 3], [[f32::NEG_INFINITY; 4]; 3]];
    for (lane, &k) in kids.iter().enumerate() {
        let (mn, mx) = (nodes[k].min(), nodes[k].max());
        for a in 0..3 {
            planes[0][a][lane] = mn[a];
            planes[1][a][lane] = mx[a];
        }
        let count = nodes[k].count() as usize;
        if count > 0 {
            let first = nodes[k].first() as usize;
            let start = out.packets.len();
            for s in (first..first + count).step_by(4) {
                let e = (s + 4).min(first + count);
                out.packets.push(Tri4::pack(&out.tris[s..e]));
                let ids = &out.ids[s..e];
                out.packet_ids.push(std::array::from_fn(|l| ids[l.min(ids.len() - 1)]));
            }
            let n = (out.packets.len() - start) as u32;
            w.child[lane] = LEAF | (n - 1) << PACKETS_SHIFT | start as u32;
        }
    }
    w.planes = planes.map(|b| b.map(Vec4::from_array));
    for (lane, &k) in kids.iter().enumerate() {
        if nodes[k].count() == 0 {
            w.child[lane] = collapse(nodes, k, out);
        }
    }
    out.wide[at] = w;
    at as u32
}

/// Shape statistics of the binary tree.
fn binary_stats(nodes: &[Node]) -> BvhStats {
    let mut st = BvhStats { nodes: nodes.len(), ..BvhStats::default() };
    let root_area = half_area(&nodes[0]).max(f32::MIN_POSITIVE) as f64;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, depth)) = stack.pop() {
        let nd = &nodes[i];
        let rel = half_area(nd) as f64 / root_area;
        st.max_depth = st.max_depth.max(depth);
        if nd.count() > 0 {
            st.leaves += 1;
            st.max_leaf = st.max_leaf.max(nd.count() as usize);
            st.sah_cost += rel * leaf_cost(nd.count()) as f64;
        } else {
            st.sah_cost += rel * f64::from(TRAVERSAL_COST);
            stack.push((nd.first() as usize, depth + 1));
            stack.push((nd.first() as usize + 1, depth + 1));
        }
    }
    st
}

fn bounds_of(refs: &[PrimRef]) -> Bounds {
    let mut b = Aabb::EMPTY;
    let mut cb = Aabb::EMPTY;
    for r in refs {
        b.grow(r.min(), r.max());
        let c = r.centroid2();
        cb.grow(c, c);
    }
    (b, cb)
}

/// Build the subtree over `refs` (global offset `base`), in parallel above the threshold.
/// `bb` are the bounds of `refs` (computed by the parent's partition pass).
fn build_sub(refs: &mut [PrimRef], base: usize, depth: usize, bb: Bounds) -> Sub {
    if refs.len() <= PARALLEL_THRESHOLD {
        let mut nodes = Vec::with_capacity(2 * refs.len());
        nodes.push(Node::default());
        build_seq(refs, base, depth, 0, &mut nodes, bb);
        return Sub::Flat(nodes);
    }
    let Split::At { mid, left: lb, right: rb } = choose_split(refs, &bb, depth) else {
        unreachable!("nodes above MAX_LEAF triangles are always split")
    };
    let (l, r) = refs.split_at_mut(mid);
    let (left, right) =
        rayon::join(|| build_sub(l, base, depth + 1, lb), || build_sub(r, base + mid, depth + 1, rb));
    Sub::Split { bounds: bb.0, left: Box::new(left), right: Box::new(right) }
}

/// Sequential build into `nodes`, writing the subtree root at `at`.
fn build_seq(refs: &mut [PrimRef], base: usize, depth: usize, at: usize, nodes: &mut Vec<Node>, bb: Bounds) {
    let bounds = bb.0;
    match choose_split(refs, &bb, depth) {
        Split::Leaf => {
            nodes[at] = Node::new(bounds.min, bounds.max, base as u32, refs.len() as u32);
        }
        Split::At { mid, left, right } => {
            let c = nodes.len();
            nodes.push(Node::default());
            nodes.push(Node::default());
            nodes[at] = Node::new(bounds.min, bounds.max, c as u32, 0);
            let (l, r) = refs.split_at_mut(mid);
            build_seq(l, base, depth + 1, c, nodes, left);
            build_seq(r, base + mid, depth + 1, c + 1, nodes, right);
        }
    }
}

/// Decide how to split `refs` (with bounds `bb`) and partition them in place.
fn choose_split(refs: &mut [PrimRef], bb: &Bounds, depth: usize) -> Split {
    let (bounds, cbounds) = (&bb.0, &bb.1);
    let n = refs.len();
    // Up to four triangles fit one packet: a leaf costs one packet test (`PACKET_COST`), any split at
    // least the traversal step (`TRAVERSAL_COST` ≥ `PACKET_COST`) plus its children's tests, so the SAH
    // below would always choose the leaf, and so would its fallbacks (n ≤ MAX_LEAF). Deciding it here
    // skips binning the smallest nodes, which are the most numerous.
    if n <= 4 {
        return Split::Leaf;
    }
    let extent = cbounds.max - cbounds.min;
    let axis_of_max = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    // All centroids coincide, or the tree got too deep for SAH: object median along the widest axis.
    let median = |refs: &mut [PrimRef]| {
        if n <= MAX_LEAF {
            return Split::Leaf;
        }
        let mid = n / 2;
        refs.select_nth_unstable_by(mid, |a, b| {
            let (ca, cb) = (a.centroid2()[axis_of_max], b.centroid2()[axis_of_max]);
            ca.total_cmp(&cb).then(a.idx().cmp(&b.idx()))
        });
        Split::At { mid, left: bounds_of(&refs[..mid]), right: bounds_of(&refs[mid..]) }
    };
    if extent.max_element() <= 0.0 || depth >= SAH_DEPTH_LIMIT {
        return median(refs);
    }

    // Bin centroids along all three axes in one pass.
    let scale = Vec3A::select(
        extent.cmpgt(Vec3A::ZERO),
        Vec3A::splat(BINS as f32 * (1.0 - 1e-6)) / extent,
        Vec3A::ZERO,
    );
    // Small nodes get fewer bins: the sweep below costs O(bins) per node whatever its size.
    let nb = if n <= 32 { 8 } else { BINS };
    let scale = scale * (nb as f32 / BINS as f32);
    // Bin index = round-to-nearest of (x − ½), read from the low mantissa bits after adding 1.5·2²³
    // (the sum stays in [2²³, 2²⁴), where floats are the integers): monotone in x and the same
    // arithmetic in binning and partitioning, which is all the SAH needs, and far cheaper than three
    // saturating float → int conversions.
    const MAGIC: f32 = 12_582_912.0;
    let bin_of = |c: Vec3A| -> [usize; 3] {
        let x = ((c - cbounds.min) * scale).min(Vec3A::splat((nb - 1) as f32)) + Vec3A::splat(MAGIC - 0.5);
        let b = x.to_array().map(|v| (v.to_bits() & 0xff) as usize);
        [b[0], b[1], b[2]]
    };
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    let mut counts = [[0u32; BINS]; 3];
    for r in refs.iter() {
        let b = bin_of(r.centroid2());
        for a in 0..3 {
            boxes[a][b[a]].grow(r.min(), r.max());
            counts[a][b[a]] += 1;
        }
    }
    // Sweep: cost of splitting after bin i (left = bins 0..=i).
    let mut best = (f32::INFINITY, 0usize, 0usize);
    for a in 0..3 {
        if extent[a] <= 0.0 {
            continue;
        }
        let mut right_cost = [0f32; BINS];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0u32;
        for i in (1..nb).rev() {
            acc = acc.merge(boxes[a][i]);
            cnt += counts[a][i];
            right_cost[i] = if cnt > 0 { acc.half_area() * leaf_cost(cnt) } else { f32::INFINITY };
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0u32;
        for i in 0..nb - 1 {
            acc = acc.merge(boxes[a][i]);
            cnt += counts[a][i];
            if cnt == 0 || cnt as usize == n {
                continue;
            }
            let cost = acc.half_area() * leaf_cost(cnt) + right_cost[i + 1];
            if cost < best.0 {
                best = (cost, a, i);
            }
        }
    }
    let area = bounds.half_area();
    let split_cost = TRAVERSAL_COST + if area > 0.0 { best.0 / area } else { 0.0 };
    if best.0 == f32::INFINITY {
        // Every centroid fell in one bin on every axis (extremely clustered): median split.
        return median(refs);
    }
    if n <= MAX_LEAF && split_cost >= leaf_cost(n as u32) {
        return Split::Leaf;
    }
    // Partition in place by the chosen bin boundary (same binning arithmetic as above), gathering
    // both halves' bounds on the way (the children need them, and it saves them a pass).
    let (axis, split_bin) = (best.1, best.2);
    let (mut lb, mut lcb, mut rb, mut rcb) = (Aabb::EMPTY, Aabb::EMPTY, Aabb::EMPTY, Aabb::EMPTY);
    let mut i = 0usize;
    let mut j = n;
    while i < j {
        let r = refs[i];
        let c = r.centroid2();
        if bin_of(c)[axis] <= split_bin {
            lb.grow(r.min(), r.max());
            lcb.grow(c, c);
            i += 1;
        } else {
            rb.grow(r.min(), r.max());
            rcb.grow(c, c);
            j -= 1;
            refs.swap(i, j);
        }
    }
    Split::At { mid: i, left: (lb, lcb), right: (rb, rcb) }
}

/// Flatten `sub` into `nodes`, its root written at `at` (pushing a fresh root when `root`).
fn place(sub: Sub, at: usize, nodes: &mut Vec<Node>, root: bool) {
    if root {
        // Root at 0 and an unused pad at 1, so that every sibling pair starts at an even index (and
        // shares a 64-byte cache line when the array is 64-byte aligned).
        nodes.push(Node::default());
        nodes.push(Node::default());
    }
    match sub {
        Sub::Split { bounds, left, right } => {
            let c = nodes.len();
            nodes.push(Node::default());
            nodes.push(Node::default());
            nodes[at] = Node::new(bounds.min, bounds.max, c as u32, 0);
            place(*left, c, nodes, false);
            place(*right, c + 1, nodes, false);
        }
        Sub::Flat(local) => {
            // Local index k ≥ 1 lands at offset + k (local pairs start at 1, global ones at even indices).
            let offset = nodes.len() - 1;
            let fix = |nd: Node| {
                if nd.count() == 0 {
                    Node::new(nd.min(), nd.max(), nd.first() + offset as u32, 0)
                } else {
                    nd
                }
            };
            nodes[at] = fix(local[0]);
            nodes.extend(local[1..].iter().map(|&nd| fix(nd)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_leaf_tree_is_hit_through_its_interior() {
        let tri = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let bvh = Bvh::from_triangles(&[tri]).unwrap();
        let h = bvh.closest_hit(&Ray::new(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z)).unwrap();
        assert_eq!(h.triangle, 0);
        assert!((h.t - 2.0).abs() < 1e-6);
        // Barycentrics reproduce the hit point.
        let p = tri[0] * (1.0 - h.u - h.v) + tri[1] * h.u + tri[2] * h.v;
        assert!(p.distance(Vec3::ZERO) < 1e-6, "{p}");
    }

    /// SplitMix64 uniforms in [lo, hi).
    fn uniforms(seed: u64) -> impl FnMut(f32, f32) -> f32 {
        let mut state = seed;
        move |lo, hi| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            lo + (hi - lo) * ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn stack_keeps_lifo_order_across_spills_and_refills() {
        let mut s = Stack::new(0u32);
        // Up and down twice past several spill boundaries, interleaving pushes and pops.
        let mut model = vec![0u32];
        for round in 0..2u32 {
            for k in 1..=5 * STACK as u32 {
                s.push(k + round * 1000);
                model.push(k + round * 1000);
                if k % 7 == 0 {
                    assert_eq!(s.pop(), model.pop());
                }
            }
            for _ in 0..3 * STACK {
                assert_eq!(s.pop(), model.pop());
            }
        }
        while let Some(x) = model.pop() {
            assert_eq!(s.pop(), Some(x));
        }
        assert_eq!(s.pop(), None);
    }

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

    #[test]
    fn batches_spanning_several_sort_chunks_answer_in_input_order_at_any_thread_count() {
        let mut u = uniforms(29);
        let tris: Vec<[Vec3; 3]> = (0..400)
            .map(|_| {
                let c = Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
                [0; 3].map(|_| c + Vec3::new(u(-0.2, 0.2), u(-0.2, 0.2), u(-0.2, 0.2)))
            })
            .collect();
        let bvh = Bvh::from_triangles(&tris).unwrap();
        let rays: Vec<Ray> = (0..2 * SORT_CHUNK + 123)
            .map(|_| {
                let o = Vec3::new(u(-1.5, 1.5), u(-1.5, 1.5), u(-1.5, 1.5));
                Ray::segment(o, Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)), 0.0, u(0.0, 2.0))
            })
            .collect();
        let want: Vec<Option<Hit>> = rays.iter().map(|r| bvh.closest_hit(r)).collect();
        let hits = want.iter().filter(|h| h.is_some()).count();
        assert!(hits > 1000 && hits < rays.len() - 1000, "{hits}");
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let (closest, any) = pool.install(|| (bvh.closest_hits(&rays), bvh.any_hits(&rays)));
            assert!(closest == want, "closest, {threads} threads");
            assert!(any.iter().zip(&want).all(|(a, w)| *a == w.is_some()), "any, {threads} threads");
        }
    }
}
