//! The build: binned SAH over primitive boxes into a binary tree (in parallel above
//! [`PARALLEL_THRESHOLD`]), then the collapse into 4-wide nodes and triangle packets.

use glam::{Mat4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::node::{LEAF, Node4, PACKETS_SHIFT, Tri4, is_degenerate};
use super::{BINS, Bvh, BvhStats, MAX_LEAF, PARALLEL_THRESHOLD, SAH_DEPTH_LIMIT};
use crate::{Mesh, RasterError, mesh::MAX_ELEMENTS};

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
pub(super) struct Aabb {
    pub(super) min: Vec3A,
    pub(super) max: Vec3A,
}

impl Aabb {
    pub(super) const EMPTY: Self =
        Self { min: Vec3A::splat(f32::INFINITY), max: Vec3A::splat(f32::NEG_INFINITY) };
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
