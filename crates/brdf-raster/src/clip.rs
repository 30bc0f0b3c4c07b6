//! Clipping in homogeneous clip space, before the perspective divide.
//!
//! - The **near plane** `z = −w` (and the far plane `z = w`) is clipped exactly: a triangle crossing it
//!   becomes a convex polygon of up to 4 vertices, fan-triangulated into 1–2 triangles, never dropped.
//!   After near clipping every vertex has `w ≥ near > 0`, so the divide is safe.
//! - **x and y** are handled by a guard band: triangles are rasterized over their bounding box clamped
//!   to the image, which is exact as long as the snapped fixed-point coordinates stay in range. Only a
//!   vertex farther than [`GUARD_BAND_PX`] pixels from the image centre triggers clipping against the
//!   guard-band planes `|x| ≤ g_x·w`, `|y| ≤ g_y·w` (which lie outside the image, so the visible pixels
//!   are unchanged). This keeps `|X|, |Y| < 2^29` in 8-bit sub-pixel units, so every edge-function
//!   product fits an `i64` (see [`crate::setup`]).
//! - A triangle whose three vertices are outside the same frustum plane is rejected.
//!
//! Watertightness: a new vertex is always computed from the segment's inside endpoint toward its
//! outside endpoint, so the two triangles sharing a clipped edge create bit-identical vertices.

use glam::{Vec3, Vec4};

/// Guard band: a vertex may lie this many pixels outside the image centre before x/y clipping is used
/// (2^20 px; with 8 sub-pixel bits coordinates stay below 2^29).
pub const GUARD_BAND_PX: f64 = (1u64 << 20) as f64;

/// Outcode bits of a clip-space vertex.
pub mod code {
    /// `z < −w` (in front of the near plane).
    pub const NEAR: u16 = 1 << 0;
    /// `z > w` (beyond the far plane).
    pub const FAR: u16 = 1 << 1;
    /// `x < −g_x·w` (outside the left guard band).
    pub const GUARD_LEFT: u16 = 1 << 2;
    /// `x > g_x·w`.
    pub const GUARD_RIGHT: u16 = 1 << 3;
    /// `y < −g_y·w`.
    pub const GUARD_BOTTOM: u16 = 1 << 4;
    /// `y > g_y·w`.
    pub const GUARD_TOP: u16 = 1 << 5;
    /// `x < −w` (left of the view frustum).
    pub const LEFT: u16 = 1 << 6;
    /// `x > w`.
    pub const RIGHT: u16 = 1 << 7;
    /// `y < −w`.
    pub const BOTTOM: u16 = 1 << 8;
    /// `y > w`.
    pub const TOP: u16 = 1 << 9;
    /// Planes that force clipping when any vertex is outside them.
    pub const MUST_CLIP: u16 = NEAR | FAR | GUARD_LEFT | GUARD_RIGHT | GUARD_BOTTOM | GUARD_TOP;
    /// Planes for trivial rejection (all three vertices outside one of them).
    pub const REJECT: u16 = NEAR | FAR | LEFT | RIGHT | BOTTOM | TOP;
}

/// Guard-band extents in NDC units for an image of `width × height` samples: `g = GUARD_BAND_PX / (size/2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuardBand {
    /// `g_x`.
    pub gx: f32,
    /// `g_y`.
    pub gy: f32,
}

impl GuardBand {
    /// The guard band of an image of `width × height` samples.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            gx: (GUARD_BAND_PX / (0.5 * width as f64)) as f32,
            gy: (GUARD_BAND_PX / (0.5 * height as f64)) as f32,
        }
    }

    /// The outcode of clip-space position `c` (see [`code`]). NaN coordinates are outside everything.
    #[inline]
    pub fn outcode(&self, c: Vec4) -> u16 {
        let mut k = 0;
        let w = c.w;
        if !(c.z >= -w) {
            k |= code::NEAR;
        }
        if !(c.z <= w) {
            k |= code::FAR;
        }
        if !(c.x >= -self.gx * w) {
            k |= code::GUARD_LEFT;
        }
        if !(c.x <= self.gx * w) {
            k |= code::GUARD_RIGHT;
        }
        if !(c.y >= -self.gy * w) {
            k |= code::GUARD_BOTTOM;
        }
        if !(c.y <= self.gy * w) {
            k |= code::GUARD_TOP;
        }
        if !(c.x >= -w) {
            k |= code::LEFT;
        }
        if !(c.x <= w) {
            k |= code::RIGHT;
        }
        if !(c.y >= -w) {
            k |= code::BOTTOM;
        }
        if !(c.y <= w) {
            k |= code::TOP;
        }
        k
    }

    /// Signed distance of `c` to the plane of outcode bit `plane` (≥ 0 inside).
    #[inline]
    fn distance(&self, plane: u16, c: Vec4) -> f32 {
        match plane {
            code::NEAR => c.z + c.w,
            code::FAR => c.w - c.z,
            code::GUARD_LEFT => c.x + self.gx * c.w,
            code::GUARD_RIGHT => self.gx * c.w - c.x,
            code::GUARD_BOTTOM => c.y + self.gy * c.w,
            _ => self.gy * c.w - c.y,
        }
    }
}

/// A polygon vertex during clipping: clip-space position and barycentric coordinates with respect to
/// the original triangle (so attributes are always interpolated from the original vertices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipVertex {
    /// Clip-space position.
    pub pos: Vec4,
    /// Barycentric coordinates in the original triangle.
    pub bary: Vec3,
}

/// Most vertices a triangle clipped by the six clip planes can have (3 + one per plane).
pub const MAX_POLY: usize = 9;

/// A small fixed-capacity polygon.
#[derive(Debug, Clone, Copy)]
pub struct Polygon {
    /// Vertices, the first `len` valid, in the triangle's winding order.
    pub v: [ClipVertex; MAX_POLY],
    /// Number of vertices.
    pub len: usize,
}

/// Clip the triangle `tri` against every plane in `planes` (a mask of [`code::MUST_CLIP`] bits) by
/// Sutherland–Hodgman. Returns the clipped convex polygon (possibly empty, `len < 3`).
pub fn clip_triangle(tri: [ClipVertex; 3], planes: u16, guard: &GuardBand) -> Polygon {
    let mut poly = Polygon { v: [tri[0]; MAX_POLY], len: 3 };
    poly.v[1] = tri[1];
    poly.v[2] = tri[2];
    for bit in 0..6 {
        let plane = 1u16 << bit;
        if planes & plane == 0 {
            continue;
        }
        let mut out = Polygon { v: [tri[0]; MAX_POLY], len: 0 };
        for i in 0..poly.len {
            let a = poly.v[i];
            let b = poly.v[(i + 1) % poly.len];
            let (da, db) = (guard.distance(plane, a.pos), guard.distance(plane, b.pos));
            let (a_in, b_in) = (da >= 0.0, db >= 0.0);
            if a_in {
                push(&mut out, a);
            }
            if a_in != b_in {
                // Canonical direction inside → outside, so a shared edge clips identically in both
                // triangles (watertightness).
                let (vi, vo, di, dout) = if a_in { (a, b, da, db) } else { (b, a, db, da) };
                let t = di / (di - dout);
                push(
                    &mut out,
                    ClipVertex {
                        pos: vi.pos + (vo.pos - vi.pos) * t,
                        bary: vi.bary + (vo.bary - vi.bary) * t,
                    },
                );
            }
        }
        poly = out;
        if poly.len < 3 {
            poly.len = 0;
            break;
        }
    }
    poly
}

#[inline]
fn push(p: &mut Polygon, v: ClipVertex) {
    // Each plane adds at most one vertex to a convex polygon, so MAX_POLY is never exceeded; a
    // degenerate input (NaN) that would is truncated instead of panicking.
    if p.len < MAX_POLY {
        p.v[p.len] = v;
        p.len += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cv(x: f32, y: f32, z: f32, w: f32, k: usize) -> ClipVertex {
        let mut bary = Vec3::ZERO;
        bary[k] = 1.0;
        ClipVertex { pos: Vec4::new(x, y, z, w), bary }
    }

    #[test]
    fn a_triangle_with_one_vertex_behind_the_near_plane_becomes_a_quad() {
        let g = GuardBand::new(100, 100);
        let tri = [cv(0.0, 0.0, 0.5, 1.0, 0), cv(1.0, 0.0, 0.5, 1.0, 1), cv(0.0, 1.0, -3.0, 1.0, 2)];
        let p = clip_triangle(tri, code::NEAR, &g);
        assert_eq!(p.len, 4);
        for v in &p.v[..p.len] {
            assert!(v.pos.z + v.pos.w >= -1e-6, "{v:?}");
            // Barycentrics still reproduce the position.
            let rebuilt = tri[0].pos * v.bary.x + tri[1].pos * v.bary.y + tri[2].pos * v.bary.z;
            assert!((rebuilt - v.pos).abs().max_element() < 1e-6);
        }
    }

    #[test]
    fn two_vertices_behind_leave_a_triangle_and_all_behind_leave_nothing() {
        let g = GuardBand::new(100, 100);
        let tri = [cv(0.0, 0.0, 0.5, 1.0, 0), cv(1.0, 0.0, -2.0, 1.0, 1), cv(0.0, 1.0, -3.0, 1.0, 2)];
        assert_eq!(clip_triangle(tri, code::NEAR, &g).len, 3);
        let gone = [cv(0.0, 0.0, -2.0, 1.0, 0), cv(1.0, 0.0, -2.0, 1.0, 1), cv(0.0, 1.0, -3.0, 1.0, 2)];
        assert_eq!(clip_triangle(gone, code::NEAR, &g).len, 0);
    }

    #[test]
    fn a_shared_edge_is_clipped_to_bit_identical_points_from_both_sides() {
        let g = GuardBand::new(64, 64);
        let a = Vec4::new(0.3, -0.7, 0.9, 1.3);
        let b = Vec4::new(-0.2, 0.4, -5.7, 0.11);
        let c1 = Vec4::new(0.9, 0.8, 0.2, 2.0);
        let c2 = Vec4::new(-0.9, -0.8, 0.1, 1.7);
        let v = |p: Vec4| ClipVertex { pos: p, bary: Vec3::ZERO };
        let p1 = clip_triangle([v(a), v(b), v(c1)], code::NEAR, &g);
        let p2 = clip_triangle([v(b), v(a), v(c2)], code::NEAR, &g);
        let on = |p: &Polygon| {
            p.v[..p.len].iter().map(|v| v.pos).filter(|q| (q.z + q.w).abs() < 1e-6).collect::<Vec<_>>()
        };
        let shared: Vec<Vec4> = on(&p1).into_iter().filter(|q| on(&p2).contains(q)).collect();
        assert_eq!(shared.len(), 1, "{:?} vs {:?}", on(&p1), on(&p2));
    }

    #[test]
    fn outcodes_flag_near_far_frustum_and_guard_band() {
        let g = GuardBand::new(1000, 1000);
        assert_eq!(g.outcode(Vec4::new(0.0, 0.0, 0.0, 1.0)), 0);
        assert_eq!(g.outcode(Vec4::new(0.0, 0.0, -2.0, 1.0)), code::NEAR);
        assert_eq!(g.outcode(Vec4::new(2.0, 0.0, 0.0, 1.0)), code::RIGHT);
        assert_eq!(g.outcode(Vec4::new(0.0, -1e5, 0.0, 1.0)), code::BOTTOM | code::GUARD_BOTTOM);
        assert_eq!(g.outcode(Vec4::new(f32::NAN, 0.0, 0.0, 1.0)) & code::GUARD_LEFT, code::GUARD_LEFT);
    }
}
