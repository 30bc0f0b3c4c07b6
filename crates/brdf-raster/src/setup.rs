//! Triangle setup: viewport transform, snapping to fixed point, integer edge functions with the
//! top-left fill rule, back-face culling, and the attribute plane equations used for perspective-correct
//! interpolation.
//!
//! ## Viewport and sampling (the canonical scene's)
//! NDC x = −1…1 maps to columns 0…W and NDC y = +1 to the **top** row (row 0); sample `(c, r)` is the
//! pixel centre `(c + ½, r + ½)`. Screen coordinates are y-down.
//!
//! ## Fixed point
//! Vertices are snapped to 1/256 pixel (8 sub-pixel bits, as llvmpipe's `FIXED_ORDER 8`):
//! `X = round(x_screen · 256)`. With the guard band of [`crate::clip`], `|X|, |Y| < 2^29`, so the edge
//! function `E(P) = dx·(P_y − a_y) − dy·(P_x − a_x)` (differences < 2^30, products < 2^60) is exact in
//! `i64`. Coverage therefore depends only on the snapped integers: two triangles sharing an edge see
//! exactly the same integers and can neither both cover nor both miss a sample on it.
//!
//! ## Orientation and culling
//! A triangle counter-clockwise in NDC (y up) — front-facing — has a **negative** signed area
//! `A = (X1−X0)(Y2−Y0) − (X2−X0)(Y1−Y0)` in y-down screen coordinates. `A = 0` (degenerate or edge-on,
//! decided exactly in integers) is skipped. Back faces (`A > 0`) are culled on request; otherwise
//! every triangle is brought to `A > 0` by swapping two vertices, so that inside ⇔ all three edge
//! functions ≥ 0 (llvmpipe normalises orientation the same way).
//!
//! ## Fill rule: top-left, in the y-down image
//! A sample exactly on an edge belongs to the triangle when that edge is a **top** edge (horizontal,
//! the triangle below it: `dy = 0, dx > 0`) or a **left** edge (the triangle to its right: `dy < 0`),
//! the Direct3D 10 rule, stated for our y-down image (row 0 at the top, as NumPy and PNG have it). It is
//! applied as a −1 bias on the other edges (`E ≥ 0` becomes `E > 0`), as Giesen and llvmpipe do. Since
//! the shared edge of two triangles of equal orientation has opposite `(dx, dy)` in each, exactly one of
//! them owns the samples on it: every sample is covered exactly once (watertight). OpenGL leaves the
//! tie rule to the implementation and counts window rows from the bottom; an implementation applying
//! "top-left" in its y-up window coordinates resolves exact ties on horizontal edges the other way
//! round. Only samples lying exactly on an edge can differ, which real meshes almost never produce
//! (the benchmark's comparison with llvmpipe allows a few dozen silhouette pixels for all reasons together).
//!
//! ## Depth and attributes
//! Window depth `z_window = (z_ndc + 1)/2` is affine in screen space: a plane
//! `z(c, r) = z0 + (c−c0)·dzdx + (r−r0)·dzdy` over sample coordinates, anchored at the first sample
//! `(c0, r0)` of the bounding box, fitted in f64 through the snapped vertices.
//!
//! The other attributes are not interpolated from screen-space planes: the shading pass intersects the
//! sample's view ray with the original (unclipped, unsnapped) world-space triangle and uses the
//! barycentrics of the hit (see `render/interpolate.rs`). That is exactly perspective-correct interpolation —
//! the
//! `b_i/w` over `1/w` of GL's `smooth` qualifier, which is the ray–plane intersection written in
//! screen space — but computed in f64 from the real vertices, so triangles seen almost edge-on
//! (the silhouette of a sphere) keep accurate normals where screen-space planes through snapped
//! vertices are ill-conditioned. (GL implementations likewise fit attribute planes to the float
//! positions, not the snapped ones; llvmpipe's `lp_setup_tri.c`.) Clipped pieces need no extra
//! bookkeeping: they refer to their original face.

use glam::Vec4;

/// Sub-pixel precision in bits.
pub const SUBPIXEL_BITS: u32 = 8;
/// One pixel in fixed point.
pub const SUBPIXEL_ONE: i64 = 1 << SUBPIXEL_BITS;
const HALF: i64 = SUBPIXEL_ONE / 2;

/// The sample grid being rasterized (the image, times the supersampling factor).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Viewport {
    /// Samples per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

/// A vertex ready for setup: snapped screen position and window depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetupVertex {
    /// Screen x in 1/256 sample units.
    pub x: i64,
    /// Screen y (down) in 1/256 sample units.
    pub y: i64,
    /// Window depth `(z_ndc + 1)/2`.
    pub z: f32,
}

impl Viewport {
    /// Perspective divide and viewport transform of a clip-space position with `w > 0` that lies inside
    /// the guard band (see [`crate::clip`]), snapped to fixed point. Computed in f64 so that the snap
    /// is exact to the rounding of the f32 inputs.
    #[inline]
    pub fn snap(&self, c: Vec4) -> SetupVertex {
        let inv_w = 1.0 / f64::from(c.w);
        let xn = f64::from(c.x) * inv_w;
        let yn = f64::from(c.y) * inv_w;
        let zn = f64::from(c.z) * inv_w;
        let s = SUBPIXEL_ONE as f64;
        let x = round_half_up((xn + 1.0) * (0.5 * f64::from(self.width)) * s);
        let y = round_half_up((1.0 - yn) * (0.5 * f64::from(self.height)) * s);
        SetupVertex { x, y, z: ((zn + 1.0) * 0.5) as f32 }
    }
}

/// `floor(v + ½)` for `|v| < 2^62`, by truncation: the baseline x86-64 target has no rounding
/// instruction, and `f64::round` would be a library call in the hottest loop of the vertex stage.
#[inline(always)]
fn round_half_up(v: f64) -> i64 {
    let w = v + 0.5;
    let t = w as i64;
    if (t as f64) > w { t - 1 } else { t }
}

/// A plane `a(c, r) = a0 + (c − c0)·dx + (r − r0)·dy` over sample coordinates (anchored at the
/// triangle's first bounding-box sample).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Plane {
    /// Value at the anchor sample.
    pub a0: f32,
    /// Change per column.
    pub dx: f32,
    /// Change per row.
    pub dy: f32,
}

impl Plane {
    /// Value at offset `(dc, dr)` samples from the anchor.
    #[inline(always)]
    pub fn at(&self, dc: f32, dr: f32) -> f32 {
        self.a0 + dc * self.dx + dr * self.dy
    }
}

/// What the coverage pass needs of a triangle: its clamped sample bounding box, the three edge
/// functions at the anchor sample with the fill-rule bias applied, their steps, and the depth plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterTri {
    /// First covered-candidate column (anchor column).
    pub min_x: i32,
    /// First row (anchor row).
    pub min_y: i32,
    /// Last column (inclusive).
    pub max_x: i32,
    /// Last row (inclusive).
    pub max_y: i32,
    /// Edge functions at the anchor sample, biased so that "inside" is `≥ 0` for all three.
    pub e: [i64; 3],
    /// `dx` of each edge (fixed point; `|dx| < 2^30`): the edge function changes by `256·dx` per row.
    pub edge_dx: [i32; 3],
    /// `dy` of each edge: the edge function changes by `−256·dy` per column.
    pub edge_dy: [i32; 3],
    /// Window depth plane.
    pub z: Plane,
}

impl RasterTri {
    /// Change of edge function `k` per column, `−256·dy`.
    #[inline(always)]
    pub fn step_x(&self, k: usize) -> i64 {
        -i64::from(self.edge_dy[k]) * SUBPIXEL_ONE
    }

    /// Change of edge function `k` per row, `256·dx`.
    #[inline(always)]
    pub fn step_y(&self, k: usize) -> i64 {
        i64::from(self.edge_dx[k]) * SUBPIXEL_ONE
    }
}

/// What the shading pass needs of a triangle: which mesh face it came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterpTri {
    /// Face index within its instance's mesh.
    pub face: u32,
    /// Instance index in the scene.
    pub instance: u32,
}

/// Face culling choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Culling {
    /// Drop triangles whose front (counter-clockwise side) faces away from the camera.
    pub back: bool,
    /// The instance transform mirrors (det < 0), which reverses the screen winding of its front faces.
    pub mirrored: bool,
}

#[inline]
fn floor_div(a: i64) -> i64 {
    a >> SUBPIXEL_BITS
}

#[inline]
fn ceil_div(a: i64) -> i64 {
    -((-a) >> SUBPIXEL_BITS)
}

/// Fit the plane through `(x_k, y_k, a_k)` (pixel units, relative to the anchor) in f64.
#[inline]
fn fit(px: [f64; 3], py: [f64; 3], a: [f64; 3], inv_area: f64) -> Plane {
    let (dx1, dy1, dx2, dy2) = (px[1] - px[0], py[1] - py[0], px[2] - px[0], py[2] - py[0]);
    let (da1, da2) = (a[1] - a[0], a[2] - a[0]);
    let dadx = (da1 * dy2 - da2 * dy1) * inv_area;
    let dady = (da2 * dx1 - da1 * dx2) * inv_area;
    // px, py are relative to the anchor, so the anchor value is a0 − x0·dadx − y0·dady.
    Plane { a0: (a[0] - px[0] * dadx - py[0] * dady) as f32, dx: dadx as f32, dy: dady as f32 }
}

/// Set up one triangle for a viewport. `None` when it is degenerate (zero integer area), culled, or
/// covers no sample centre of the viewport.
#[inline]
pub fn setup_triangle(
    v: [SetupVertex; 3],
    viewport: Viewport,
    culling: Culling,
    face: u32,
    instance: u32,
) -> Option<(RasterTri, InterpTri)> {
    let [mut v0, mut v1, mut v2] = v;
    let area = (v1.x - v0.x) * (v2.y - v0.y) - (v2.x - v0.x) * (v1.y - v0.y);
    if area == 0 {
        return None;
    }
    let front = (area < 0) != culling.mirrored;
    if culling.back && !front {
        return None;
    }
    if area < 0 {
        std::mem::swap(&mut v1, &mut v2);
    }
    let _ = &mut v0;
    let area = area.abs();

    // Sample bounding box: centres 256·c + 128 within [min, max], clamped to the viewport.
    let min_x = ceil_div(v0.x.min(v1.x).min(v2.x) - HALF).max(0);
    let max_x = floor_div(v0.x.max(v1.x).max(v2.x) - HALF).min(i64::from(viewport.width) - 1);
    let min_y = ceil_div(v0.y.min(v1.y).min(v2.y) - HALF).max(0);
    let max_y = floor_div(v0.y.max(v1.y).max(v2.y) - HALF).min(i64::from(viewport.height) - 1);
    if min_x > max_x || min_y > max_y {
        return None;
    }

    let (px, py) = (min_x * SUBPIXEL_ONE + HALF, min_y * SUBPIXEL_ONE + HALF);
    let vs = [v0, v1, v2];
    let mut e = [0i64; 3];
    let mut edge_dx = [0i32; 3];
    let mut edge_dy = [0i32; 3];
    for k in 0..3 {
        // Edge k is opposite vertex k: from vertex k+1 to vertex k+2.
        let (a, b) = (vs[(k + 1) % 3], vs[(k + 2) % 3]);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let top_left = dy < 0 || (dy == 0 && dx > 0);
        e[k] = dx * (py - a.y) - dy * (px - a.x) - i64::from(!top_left);
        edge_dx[k] = dx as i32;
        edge_dy[k] = dy as i32;
    }

    // Small triangles (most of a dense mesh) often have sample centres in their bounding box but cover
    // none of them: find out now, so they cost no memory and no time in binning and rasterization.
    let (cols, rows) = (max_x - min_x + 1, max_y - min_y + 1);
    if cols * rows <= 4 {
        let covers = |c: i64, r: i64| {
            (0..3).all(|k| {
                e[k] - c * i64::from(edge_dy[k]) * SUBPIXEL_ONE + r * i64::from(edge_dx[k]) * SUBPIXEL_ONE
                    >= 0
            })
        };
        if !(0..rows).any(|r| (0..cols).any(|c| covers(c, r))) {
            return None;
        }
    }

    // Depth plane in f64, positions in pixels relative to the anchor sample centre.
    let s = SUBPIXEL_ONE as f64;
    let pxs = vs.map(|v| (v.x - px) as f64 / s);
    let pys = vs.map(|v| (v.y - py) as f64 / s);
    let inv_area = (s * s) / area as f64;
    let z = fit(pxs, pys, vs.map(|v| f64::from(v.z)), inv_area);

    let (x0, y0) = (min_x as i32, min_y as i32);
    Some((
        RasterTri { min_x: x0, min_y: y0, max_x: max_x as i32, max_y: max_y as i32, e, edge_dx, edge_dy, z },
        InterpTri { face, instance },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sv(x: f64, y: f64) -> SetupVertex {
        SetupVertex { x: (x * 256.0) as i64, y: (y * 256.0) as i64, z: 0.5 }
    }

    fn covered(t: &RasterTri) -> Vec<(i32, i32)> {
        let mut out = vec![];
        for r in t.min_y..=t.max_y {
            for c in t.min_x..=t.max_x {
                let (dc, dr) = (i64::from(c - t.min_x), i64::from(r - t.min_y));
                if (0..3).all(|k| t.e[k] + dc * t.step_x(k) + dr * t.step_y(k) >= 0) {
                    out.push((c, r));
                }
            }
        }
        out
    }

    const VP: Viewport = Viewport { width: 16, height: 16 };
    const NO_CULL: Culling = Culling { back: false, mirrored: false };

    #[test]
    fn snapping_rounds_half_up_to_the_nearest_256th() {
        for (v, r) in
            [(0.49, 0), (0.5, 1), (-0.5, 0), (-0.51, -1), (2.5, 3), (-2.5, -2), (1e9 + 0.25, 1_000_000_000)]
        {
            assert_eq!(round_half_up(v), r, "{v}");
        }
    }

    #[test]
    fn a_square_split_along_either_diagonal_covers_each_pixel_once() {
        // Corners on pixel centres, so many samples lie exactly on edges: the fill rule decides them.
        for (a, b, c, d) in [((0.5, 0.5), (5.5, 0.5), (5.5, 5.5), (0.5, 5.5))] {
            for diag in 0..2 {
                let tris = if diag == 0 { [[a, b, c], [a, c, d]] } else { [[a, b, d], [b, c, d]] };
                let mut count = [[0u8; 16]; 16];
                for t in tris {
                    let vs = [0, 1, 2].map(|k| sv(t[k].0, t[k].1));
                    let (rt, _) = setup_triangle(vs, VP, NO_CULL, 0, 0).unwrap();
                    for (x, y) in covered(&rt) {
                        count[y as usize][x as usize] += 1;
                    }
                }
                let total: u32 = count.iter().flatten().map(|&c| u32::from(c)).sum();
                assert!(count.iter().flatten().all(|&c| c <= 1), "overlap, diagonal {diag}");
                // The square [0.5, 5.5]² holds the centres 0.5..=5.5: top-left keeps the left column and
                // top row, drops the right column and bottom row → 5 × 5.
                assert_eq!(total, 25, "diagonal {diag}");
                assert_eq!(count[0][0], 1);
                assert_eq!(count[5][5], 0);
            }
        }
    }

    #[test]
    fn front_faces_have_negative_screen_area_and_back_faces_are_culled() {
        // NDC (−0.5, −0.5), (0.5, −0.5), (0, 0.5) is counter-clockwise seen from +z: a front face.
        let vp = Viewport { width: 8, height: 8 };
        let ccw =
            [Vec4::new(-0.5, -0.5, 0.0, 1.0), Vec4::new(0.5, -0.5, 0.0, 1.0), Vec4::new(0.0, 0.5, 0.0, 1.0)];
        let vs = ccw.map(|c| vp.snap(c));
        let cull = Culling { back: true, mirrored: false };
        assert!(setup_triangle(vs, vp, cull, 0, 0).is_some());
        assert!(setup_triangle([vs[0], vs[2], vs[1]], vp, cull, 0, 0).is_none());
        assert!(
            setup_triangle([vs[0], vs[2], vs[1]], vp, Culling { back: true, mirrored: true }, 0, 0).is_some()
        );
        assert!(setup_triangle([vs[0], vs[0], vs[1]], vp, NO_CULL, 0, 0).is_none());
    }

    #[test]
    fn the_depth_plane_reproduces_the_vertex_depths() {
        let mut vs = [sv(1.0, 1.0), sv(13.0, 2.0), sv(4.0, 14.0)];
        for (k, v) in vs.iter_mut().enumerate() {
            v.z = 0.1 + 0.3 * k as f32;
        }
        let (rt, it) = setup_triangle(vs, VP, NO_CULL, 7, 3).unwrap();
        assert_eq!((it.face, it.instance), (7, 3));
        for (k, (x, y)) in [(1.0f32, 1.0f32), (13.0, 2.0), (4.0, 14.0)].into_iter().enumerate() {
            let z = rt.z.at(x - 0.5 - rt.min_x as f32, y - 0.5 - rt.min_y as f32);
            assert!((z - vs[k].z).abs() < 1e-5, "{k}: {z}");
        }
    }
}
