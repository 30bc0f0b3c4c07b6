//! Ray packets: up to `F::LANES` rays (eight with AVX2) that share the dominant axis `kz` traverse the
//! tree together, one ray per SIMD lane, so that coherent rays — the shadow rays of neighbouring pixels
//! toward one light, the obscurance rays of one point — share every node fetch and box test, and each
//! triangle is tested against all of them in one go.
//!
//! **Same answers as one ray at a time.** Each lane does exactly the IEEE operations of the single-ray
//! queries ([`RayLanes::boxes`], `triangles4`) in the same order — the near and far planes read by the
//! sign of `1/d` per lane, the watertight test's coordinates permuted by the shared `kz` (a
//! compile-time constant), the f64 re-evaluation of edge functions that are exactly 0 — so a lane's
//! triangle test gives the bits of the single-ray test. Any-hit is then the same boolean (it only asks
//! whether some triangle passes its test, and box tests are conservative: a box never rejects a ray its
//! triangles would accept). Closest-hit distances are the same minimum (order does not change a
//! minimum, and nodes are only pruned beyond the best distance so far, with the same margin).

use brdf_core::simd::{Lane, LaneKernel, run_widest};

use super::node::{BOX_MARGIN, LEAF, Node4, RayConst, Tri4, leaf_packets};
use super::query::Stack;
use super::{Bvh, Ray};

/// Most lanes of a packet (a multiple of every lane type's count).
const MAX_LANES: usize = 16;
/// Rays sorted into packets together.
const BLOCK: usize = 64;

// No closures in the traversal: a closure is compiled on its own, outside the AVX2 function
// `run_widest` compiles the kernel in, and its SIMD operations would become function calls (8× slower,
// measured). Helpers are `#[inline(always)]` methods instead.

/// Rays of one packet: their constants per lane (see [`RayConst`]), all with the same `kz`.
struct Packet<F: Lane> {
    o: [F; 3],
    inv: [F; 3],
    /// `1/d < 0` per axis and lane.
    neg: [F::Mask; 3],
    sx: F,
    sy: F,
    sz: F,
    t_min: F,
    /// The segment's end per lane.
    t_max: F,
    /// Lanes holding a ray (the others repeat the last ray and are ignored).
    live: F::Mask,
}

#[inline(always)]
fn any<F: Lane>(m: F::Mask) -> bool {
    !F::mask_all(!m)
}

impl<F: Lane> Packet<F> {
    /// The packet of `rays` (1 to `F::LANES` of them, all with the same `kz`).
    #[inline(always)]
    fn new(rays: &[RayConst]) -> Self {
        let n = rays.len();
        let r = |i: usize| &rays[i.min(n - 1)];
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let half = F::splat(0.5);
        Self {
            o: [0, 1, 2].map(|a| F::from_fn(|i| r(i).o[a])),
            inv: [0, 1, 2].map(|a| F::from_fn(|i| r(i).inv[a])),
            neg: [0, 1, 2].map(|a| F::from_fn(|i| flag(r(i).neg[a])).gt(half)),
            sx: F::from_fn(|i| r(i).sx),
            sy: F::from_fn(|i| r(i).sy),
            sz: F::from_fn(|i| r(i).sz),
            t_min: F::from_fn(|i| r(i).t_min),
            t_max: F::from_fn(|i| r(i).t_max),
            live: F::from_fn(|i| flag(i < n)).gt(half),
        }
    }

    /// Entry and exit distances of the lanes' rays through child `c`'s slab along axis `a`, the planes
    /// read by the sign of `1/d` (as [`super::node::RayLanes`] does).
    #[inline(always)]
    fn slab(&self, n: &Node4, c: usize, a: usize) -> (F, F) {
        let lo = (F::splat(n.planes[0][a][c]) - self.o[a]) * self.inv[a];
        let hi = (F::splat(n.planes[1][a][c]) - self.o[a]) * self.inv[a];
        (F::select(self.neg[a], hi, lo), F::select(self.neg[a], lo, hi))
    }

    /// The lanes whose ray meets child `c`'s box before `t_max_m = t_max·BOX_MARGIN`, and their entry
    /// distances: the single-ray box test lane by lane.
    #[inline(always)]
    fn child_box(&self, n: &Node4, c: usize, t_max_m: F) -> (F::Mask, F) {
        let (nx, fx) = self.slab(n, c, 0);
        let (ny, fy) = self.slab(n, c, 1);
        let (nz, fz) = self.slab(n, c, 2);
        let near = nx.max(ny).max(nz).max(self.t_min);
        let far = (fx.min(fy).min(fz) * F::splat(BOX_MARGIN)).min(t_max_m);
        (near.le(far), near)
    }

    /// Vertex `k` of lane `t` of `tri` translated to the rays' origins, its axes rotated to
    /// `(kx, ky, kz)` and sheared (the single-ray test's vertex transform).
    #[inline(always)]
    fn vertex<const KZ: usize>(&self, tri: &Tri4, k: usize, t: usize) -> (F, F, F) {
        let (kx, ky) = ((KZ + 1) % 3, (KZ + 2) % 3);
        let x = F::splat(tri.v[k][kx][t]) - self.o[kx];
        let y = F::splat(tri.v[k][ky][t]) - self.o[ky];
        let z = F::splat(tri.v[k][KZ][t]) - self.o[KZ];
        (x - self.sx * z, y - self.sy * z, z)
    }

    /// The lanes whose ray hits lane `t` of the triangle packet `tri` within `[t_min, t_max]`, and
    /// the hit distances: the single-ray watertight test for one triangle and every ray of the packet.
    #[inline(always)]
    fn hits<const KZ: usize>(&self, tri: &Tri4, t: usize, t_max: F) -> (F::Mask, F) {
        let (ax, ay, az) = self.vertex::<KZ>(tri, 0, t);
        let (bx, by, bz) = self.vertex::<KZ>(tri, 1, t);
        let (cx, cy, cz) = self.vertex::<KZ>(tri, 2, t);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let zero = F::splat(0.0);
        let on_edge = self.live & (u.eq(zero) | v.eq(zero) | w.eq(zero));
        if any::<F>(on_edge) {
            (u, v, w) = edges_f64::<F>(on_edge, [ax, ay, bx, by, cx, cy], (u, v, w));
        }
        let mixed = (u.lt(zero) | v.lt(zero) | w.lt(zero)) & (u.gt(zero) | v.gt(zero) | w.gt(zero));
        let det = u + v + w;
        let ok = self.live & !mixed & !det.eq(zero);
        if !any::<F>(ok) {
            return (ok, zero);
        }
        let t_scaled = u * (self.sz * az) + v * (self.sz * bz) + w * (self.sz * cz);
        let inv_det = F::splat(1.0) / det;
        let tt = t_scaled * inv_det;
        (ok & tt.ge(self.t_min) & tt.le(t_max), tt)
    }
}

/// The exact f64 edge functions in the lanes of `on_edge`, where an f32 one is exactly 0 (as the
/// single-ray test does): rare, so out of line.
#[cold]
#[inline(never)]
fn edges_f64<F: Lane>(on_edge: F::Mask, xy: [F; 6], uvw: (F, F, F)) -> (F, F, F) {
    let lanes =
        |x: F| -> [f32; MAX_LANES] { std::array::from_fn(|i| if i < F::LANES { x.lane(i) } else { 0.0 }) };
    let xy = xy.map(lanes);
    let (mut u, mut v, mut w) = (lanes(uvw.0), lanes(uvw.1), lanes(uvw.2));
    for i in (0..F::LANES).filter(|&i| F::mask_lane(on_edge, i)) {
        let [ax, ay, bx, by, cx, cy] = xy.map(|c| f64::from(c[i]));
        u[i] = (cx * by - cy * bx) as f32;
        v[i] = (ax * cy - ay * cx) as f32;
        w[i] = (bx * ay - by * ax) as f32;
    }
    (F::from_fn(|i| u[i]), F::from_fn(|i| v[i]), F::from_fn(|i| w[i]))
}

impl Bvh {
    /// Any-hit for the rays of one packet: the lanes whose ray hits something.
    #[inline(always)]
    fn any_hit_packet<F: Lane, const KZ: usize>(&self, p: &Packet<F>) -> F::Mask {
        let t_max_m = p.t_max * F::splat(BOX_MARGIN);
        let mut hit = F::mask_splat(false);
        let mut stack = Stack::new(0u32);
        while let Some(code) = stack.pop() {
            let alive = p.live & !hit;
            if !any::<F>(alive) {
                break;
            }
            let node = &self.wide[code as usize];
            for c in 0..4 {
                // An unused lane holds the empty box: no ray enters it.
                if node.planes[0][0][c] == f32::INFINITY {
                    continue;
                }
                let (enter, _) = p.child_box(node, c, t_max_m);
                let enter = enter & alive & !hit;
                if !any::<F>(enter) {
                    continue;
                }
                let child = node.child[c];
                if child & LEAF == 0 {
                    stack.push(child);
                    continue;
                }
                for k in leaf_packets(child) {
                    let ids = &self.ids[k];
                    for t in 0..4 {
                        // A leaf's last packet repeats its last triangle in the unused lanes.
                        if t > 0 && ids[t] == ids[t - 1] {
                            break;
                        }
                        let (h, _) = p.hits::<KZ>(&self.packets[k], t, p.t_max);
                        hit = hit | (h & enter);
                    }
                }
                if F::mask_all(hit | !p.live) {
                    return hit;
                }
            }
        }
        hit
    }

    /// Closest-hit distances for the rays of one packet: per lane the smallest `t` of a hit, or
    /// `f32::INFINITY` where there is none.
    #[inline(always)]
    fn closest_t_packet<F: Lane, const KZ: usize>(&self, p: &Packet<F>) -> F {
        let mut best = p.t_max;
        let mut found = F::mask_splat(false);
        // Entries: (node code, smallest entry distance over the lanes entering it).
        let mut stack = Stack::new((0u32, f32::NEG_INFINITY));
        while let Some((code, dist)) = stack.pop() {
            // Every live lane's best is below the node's entry: nothing in it can be closer.
            let best_max = (0..F::LANES)
                .filter(|&i| F::mask_lane(p.live, i))
                .map(|i| best.lane(i))
                .fold(f32::NEG_INFINITY, f32::max);
            if dist > best_max * BOX_MARGIN {
                continue;
            }
            let node = &self.wide[code as usize];
            let t_max_m = best * F::splat(BOX_MARGIN);
            let mut kids = [(0f32, 0u32); 4];
            let mut n_kids = 0;
            for c in 0..4 {
                if node.planes[0][0][c] == f32::INFINITY {
                    continue;
                }
                let (enter, near) = p.child_box(node, c, t_max_m);
                let enter = enter & p.live;
                if !any::<F>(enter) {
                    continue;
                }
                let child = node.child[c];
                if child & LEAF == 0 {
                    let d = (0..F::LANES)
                        .filter(|&i| F::mask_lane(enter, i))
                        .map(|i| near.lane(i))
                        .fold(f32::INFINITY, f32::min);
                    kids[n_kids] = (d, child);
                    n_kids += 1;
                    continue;
                }
                for k in leaf_packets(child) {
                    let ids = &self.ids[k];
                    for t in 0..4 {
                        if t > 0 && ids[t] == ids[t - 1] {
                            break;
                        }
                        let (h, tt) = p.hits::<KZ>(&self.packets[k], t, best);
                        let h = h & enter;
                        best = F::select(h, tt, best);
                        found = found | h;
                    }
                }
            }
            // Push the nearest last, so it is popped first.
            kids[..n_kids].sort_by(|a, b| b.0.total_cmp(&a.0));
            for &(d, child) in &kids[..n_kids] {
                stack.push((child, d));
            }
        }
        F::select(found, best, F::splat(f32::INFINITY))
    }
}

/// A query traced packet by packet (a trait, not a closure: see above).
trait Query<F: Lane> {
    type Out: Copy;
    /// The answer for a ray that can hit nothing.
    const DEAD: Self::Out;
    /// The answers for the lanes of one packet whose rays share `kz`.
    fn trace(&self, kz: usize, p: &Packet<F>) -> [Self::Out; MAX_LANES];
}

/// Any-hit: whether each ray hits something.
struct AnyHit<'a>(&'a Bvh);

impl<F: Lane> Query<F> for AnyHit<'_> {
    type Out = bool;
    const DEAD: bool = false;
    #[inline(always)]
    fn trace(&self, kz: usize, p: &Packet<F>) -> [bool; MAX_LANES] {
        let m = match kz {
            0 => self.0.any_hit_packet::<F, 0>(p),
            1 => self.0.any_hit_packet::<F, 1>(p),
            _ => self.0.any_hit_packet::<F, 2>(p),
        };
        let mut out = [false; MAX_LANES];
        for (i, o) in out.iter_mut().enumerate().take(F::LANES) {
            *o = F::mask_lane(m, i);
        }
        out
    }
}

/// Closest-hit distance of each ray (∞ for none).
struct ClosestT<'a>(&'a Bvh);

impl<F: Lane> Query<F> for ClosestT<'_> {
    type Out = f32;
    const DEAD: f32 = f32::INFINITY;
    #[inline(always)]
    fn trace(&self, kz: usize, p: &Packet<F>) -> [f32; MAX_LANES] {
        let t = match kz {
            0 => self.0.closest_t_packet::<F, 0>(p),
            1 => self.0.closest_t_packet::<F, 1>(p),
            _ => self.0.closest_t_packet::<F, 2>(p),
        };
        let mut out = [f32::INFINITY; MAX_LANES];
        for (i, o) in out.iter_mut().enumerate().take(F::LANES) {
            *o = t.lane(i);
        }
        out
    }
}

/// `rays` sorted into packets by `kz` (in input order within each axis, so the packets depend on the
/// input only), each traced by `query`. `out[i]` answers `rays[i]`.
#[inline(always)]
fn by_packets<F: Lane, Q: Query<F>>(query: &Q, rays: &[Ray], out: &mut [Q::Out]) {
    debug_assert!(F::LANES <= MAX_LANES);
    for (rays, out) in rays.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
        // The rays of the block that can hit something, grouped by kz, in input order within a group.
        let mut consts = [RayConst::default(); BLOCK];
        let mut index = [0u8; BLOCK];
        let mut n = 0;
        let all: [Option<RayConst>; BLOCK] = std::array::from_fn(|i| rays.get(i).and_then(RayConst::new));
        for kz in 0..3 {
            for (i, c) in all.iter().enumerate().take(rays.len()) {
                match c {
                    Some(c) if c.kz == kz => {
                        (consts[n], index[n]) = (*c, i as u8);
                        n += 1;
                    }
                    None if kz == 0 => out[i] = Q::DEAD,
                    _ => {}
                }
            }
        }
        let mut start = 0;
        while start < n {
            // A packet: up to F::LANES consecutive rays of one kz.
            let kz = consts[start].kz;
            let mut end = start + 1;
            while end < n && end - start < F::LANES && consts[end].kz == kz {
                end += 1;
            }
            let res = query.trace(kz, &Packet::<F>::new(&consts[start..end]));
            for (j, &i) in index[start..end].iter().enumerate() {
                out[i as usize] = res[j];
            }
            start = end;
        }
    }
}

impl Bvh {
    /// [`Bvh::any_hit`] for each of `rays` (`out[i]` answers `rays[i]`, the same booleans), traced in
    /// packets of up to eight rays that share the dominant axis. Sequential: call it from parallel
    /// code on coherent groups of rays (the shadow rays of neighbouring samples).
    pub fn any_hit_each(&self, rays: &[Ray], out: &mut [bool]) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        struct K<'a> {
            bvh: &'a Bvh,
            rays: &'a [Ray],
            out: &'a mut [bool],
        }
        impl LaneKernel for K<'_> {
            #[inline(always)]
            fn run<F: Lane>(self) {
                by_packets::<F, _>(&AnyHit(self.bvh), self.rays, self.out);
            }
        }
        if self.triangles == 0 {
            out.fill(false);
            return;
        }
        run_widest(K { bvh: self, rays, out });
    }

    /// The closest-hit distance `t` for each of `rays` (`f32::INFINITY` where [`Bvh::closest_hit`]
    /// finds nothing, else its `t`, the same bits), traced in packets as [`Bvh::any_hit_each`].
    pub fn closest_t_each(&self, rays: &[Ray], out: &mut [f32]) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        struct K<'a> {
            bvh: &'a Bvh,
            rays: &'a [Ray],
            out: &'a mut [f32],
        }
        impl LaneKernel for K<'_> {
            #[inline(always)]
            fn run<F: Lane>(self) {
                by_packets::<F, _>(&ClosestT(self.bvh), self.rays, self.out);
            }
        }
        if self.triangles == 0 {
            out.fill(f32::INFINITY);
            return;
        }
        run_widest(K { bvh: self, rays, out });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::uniforms;
    use glam::Vec3;

    #[test]
    fn packets_answer_exactly_as_one_ray_at_a_time() {
        let mut u = uniforms(31);
        let tris: Vec<[Vec3; 3]> = (0..600)
            .map(|_| {
                let c = Vec3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
                [0; 3].map(|_| c + Vec3::new(u(-0.25, 0.25), u(-0.25, 0.25), u(-0.25, 0.25)))
            })
            .collect();
        let bvh = Bvh::from_triangles(&tris).unwrap();
        // Coherent bundles (one origin region, one target region, like shadow rays to a light),
        // scattered rays, rays through shared vertices (edge cases), dead rays.
        let mut rays = Vec::new();
        for b in 0..60 {
            let o = Vec3::new(u(-1.5, 1.5), u(-1.5, 1.5), u(-1.5, 1.5));
            let to = Vec3::new(u(-3.0, 3.0), u(-3.0, 3.0), u(-3.0, 3.0));
            for _ in 0..13 {
                let jo = o + Vec3::new(u(-0.05, 0.05), u(-0.05, 0.05), u(-0.05, 0.05));
                let d = to - jo;
                let t_max = if b % 3 == 0 { f32::INFINITY } else { u(0.1, 1.0) };
                rays.push(Ray::segment(jo, d, u(-0.1, 0.1), t_max));
            }
            let v = tris[b * 7][b % 3];
            rays.push(Ray::new(o, v - o));
        }
        rays.push(Ray::new(Vec3::ZERO, Vec3::ZERO));
        rays.push(Ray::segment(Vec3::ZERO, Vec3::X, 1.0, 0.5));
        rays.push(Ray::new(Vec3::splat(f32::NAN), Vec3::X));
        let mut any = vec![false; rays.len()];
        let mut t = vec![0f32; rays.len()];
        bvh.any_hit_each(&rays, &mut any);
        bvh.closest_t_each(&rays, &mut t);
        let (mut hits, mut misses) = (0, 0);
        for (i, r) in rays.iter().enumerate() {
            assert_eq!(any[i], bvh.any_hit(r), "any-hit, ray {i}: {r:?}");
            let want = bvh.closest_hit(r).map_or(f32::INFINITY, |h| h.t);
            assert_eq!(t[i].to_bits(), want.to_bits(), "closest t, ray {i}: {r:?}");
            if any[i] { hits += 1 } else { misses += 1 }
        }
        assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
        // And with one ray per packet (the f32 lane type) the same answers.
        let mut one = vec![false; rays.len()];
        by_packets::<f32, _>(&AnyHit(&bvh), &rays, &mut one);
        assert_eq!(one, any);
        let mut one_t = vec![0f32; rays.len()];
        by_packets::<f32, _>(&ClosestT(&bvh), &rays, &mut one_t);
        assert!(one_t.iter().zip(&t).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
