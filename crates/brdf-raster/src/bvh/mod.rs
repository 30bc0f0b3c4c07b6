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

mod batch;
mod build;
mod node;
mod packet;
mod query;

use glam::Vec3;

pub use node::{intersect_triangle, is_degenerate};

use build::Aabb;
use node::{Node4, Tri4};

/// Number of centroid bins per axis for the SAH (16 is the usual knee of quality vs. build time).
pub const BINS: usize = 16;
/// Largest leaf the SAH may choose; larger nodes are always split.
pub const MAX_LEAF: usize = 8;
/// Subtrees with more triangles than this are built in parallel.
pub const PARALLEL_THRESHOLD: usize = 8192;
/// Batches larger than this are traced in Morton order of the ray origins ([`Bvh::any_hits`]).
pub const COHERENT_BATCH: usize = 4096;
/// Depth below which nodes are split at the object median instead of by SAH (bounds the tree depth).
pub const SAH_DEPTH_LIMIT: usize = 48;

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
}

/// SplitMix64 uniforms in [lo, hi), for the unit tests.
#[cfg(test)]
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
}
