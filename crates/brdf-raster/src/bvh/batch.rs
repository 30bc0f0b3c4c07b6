//! Ray batches: many rays answered in parallel, large batches traced in the Morton order of their
//! origins so that consecutive rays share cached nodes.

use glam::Vec3A;
use rayon::prelude::*;

use super::{Bvh, COHERENT_BATCH, Hit, Ray};

/// Cells per axis of the grid whose Morton order sorts large batches (32³ cells, 15-bit keys).
const SORT_GRID: u32 = 32;
/// Number of sort keys.
const SORT_BUCKETS: usize = (SORT_GRID * SORT_GRID * SORT_GRID) as usize;
/// Sorted rays gathered and traced per block.
const GATHER_BLOCK: usize = 512;
/// Rays per chunk of the parallel counting sort.
const SORT_CHUNK: usize = 1 << 16;

impl Bvh {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::uniforms;
    use glam::Vec3;

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
