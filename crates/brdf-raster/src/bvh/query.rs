//! Single-ray queries: closest hit (children nearest first, pruned by the best hit so far) and any
//! hit (stops at the first), over an inline traversal stack.

use glam::Vec4;

use super::node::{BOX_MARGIN, LEAF, RayLanes, leaf_packets, triangles4};
use super::{Bvh, Hit, Ray};

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
pub(super) struct Stack<T: Copy + Default> {
    inline: [T; STACK],
    len: usize,
    /// Older entries, oldest first.
    spill: Vec<T>,
}

impl<T: Copy + Default> Stack<T> {
    #[inline(always)]
    pub(super) fn new(first: T) -> Self {
        let mut inline = [T::default(); STACK];
        inline[0] = first;
        Self { inline, len: 1, spill: Vec::new() }
    }
    #[inline(always)]
    pub(super) fn push(&mut self, x: T) {
        if self.len == STACK {
            self.spill_half();
        }
        self.inline[self.len & (STACK - 1)] = x;
        self.len += 1;
    }
    #[inline(always)]
    pub(super) fn pop(&mut self) -> Option<T> {
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

impl Bvh {
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
