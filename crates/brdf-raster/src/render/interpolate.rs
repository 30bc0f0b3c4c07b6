//! Interpolation: perspective-correct barycentrics of a sample in a triangle, from the view ray of
//! the sample (affine planes per triangle).

use glam::{DVec3, Mat4, Vec3};

use crate::setup::Viewport;

/// Perspective-correct barycentrics of one triangle as three affine functions of the sample
/// position, `D`, `U`, `V` (value at the anchor sample and change per column and per row, f64):
/// `u = U/D`, `v = V/D`, `b = (1 − u − v, u, v)`.
///
/// They are the Möller–Trumbore quantities of the sample's view ray against the world-space triangle,
/// `D = e1·(d × e2)`, `U = (o − p0)·(d × e2)`, `V = d·((o − p0) × e1)`: with a perspective camera the
/// origin `o` is the eye (fixed) and the direction `d` is affine in the sample position; with an
/// orthographic one `d` is fixed and `o` affine. Either way D, U and V are affine, so three exact
/// evaluations at the anchor and its two neighbours give their planes, and each sample costs six
/// multiply-adds and a division instead of a full intersection.
pub(super) struct BaryPlanes {
    c0: i32,
    r0: i32,
    /// (value at anchor, per column, per row) of D, U, V.
    d: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
}

impl BaryPlanes {
    pub(super) fn new(rays: &Rays, p: [Vec3; 3], c0: i32, r0: i32) -> Self {
        let p0 = p[0].as_dvec3();
        let (e1, e2) = (p[1].as_dvec3() - p0, p[2].as_dvec3() - p0);
        let (o, d) = rays.ray(c0, r0);
        let t = o - p0;
        let plane = |at: f64, per_c: f64, per_r: f64| [at, per_c, per_r];
        if rays.perspective {
            // o fixed: D = d·(e2×e1), U = d·(e2×t), V = d·(t×e1), linear in d.
            let (a, b, c) = (e2.cross(e1), e2.cross(t), t.cross(e1));
            let (dc, dr) = (rays.d_c, rays.d_r);
            Self {
                c0,
                r0,
                d: plane(d.dot(a), dc.dot(a), dr.dot(a)),
                u: plane(d.dot(b), dc.dot(b), dr.dot(b)),
                v: plane(d.dot(c), dc.dot(c), dr.dot(c)),
            }
        } else {
            // d fixed: D = e1·(d×e2) constant, U = t·(d×e2), V = t·(e1×d), linear in o.
            let (pv, qv) = (d.cross(e2), e1.cross(d));
            let (oc, or) = (rays.o_c, rays.o_r);
            Self {
                c0,
                r0,
                d: plane(e1.dot(pv), 0.0, 0.0),
                u: plane(t.dot(pv), oc.dot(pv), or.dot(pv)),
                v: plane(t.dot(qv), oc.dot(qv), or.dot(qv)),
            }
        }
    }

    /// Barycentrics at sample `(c, r)`; the centroid if the ray is parallel to the triangle's plane.
    /// Slightly outside [0, 1] for samples the snapped triangle covers beyond the exact one, as GL
    /// extrapolates too.
    #[inline(always)]
    pub(super) fn at(&self, c: i32, r: i32) -> Vec3 {
        let (dc, dr) = (f64::from(c - self.c0), f64::from(r - self.r0));
        let d = self.d[0] + dc * self.d[1] + dr * self.d[2];
        if d == 0.0 || !d.is_finite() {
            return Vec3::splat(1.0 / 3.0);
        }
        let inv = 1.0 / d;
        let u = (self.u[0] + dc * self.u[1] + dr * self.u[2]) * inv;
        let v = (self.v[0] + dc * self.v[1] + dr * self.v[2]) * inv;
        Vec3::new((1.0 - u - v) as f32, u as f32, v as f32)
    }

    /// [`BaryPlanes::at`] of the eight samples `(c0 + k, r)`, `k = 0..8`, as three rows of eight
    /// (`b.x`, `b.y`, `b.z`): the same operations in the same order, so the same bits, but written
    /// without a branch so that the compiler evaluates the eight samples in vector registers.
    #[inline(always)]
    pub(super) fn at_row_of_8(&self, c0: i32, r: i32) -> [[f32; 8]; 3] {
        let dr = f64::from(r - self.r0);
        let mut b = [[0.0f32; 8]; 3];
        let [b0, b1, b2] = &mut b;
        for (k, ((b0, b1), b2)) in b0.iter_mut().zip(b1.iter_mut()).zip(b2.iter_mut()).enumerate() {
            let dc = f64::from(c0 + k as i32 - self.c0);
            let d = self.d[0] + dc * self.d[1] + dr * self.d[2];
            let inv = 1.0 / d;
            let u = (self.u[0] + dc * self.u[1] + dr * self.u[2]) * inv;
            let v = (self.v[0] + dc * self.v[1] + dr * self.v[2]) * inv;
            let ok = d != 0.0 && d.is_finite();
            *b0 = if ok { (1.0 - u - v) as f32 } else { 1.0 / 3.0 };
            *b1 = if ok { u as f32 } else { 1.0 / 3.0 };
            *b2 = if ok { v as f32 } else { 1.0 / 3.0 };
        }
        b
    }

    /// [`BaryPlanes::at`] and the barycentrics' change per sample column and per sample row, the exact
    /// derivatives of the perspective-correct `b = (1 − u − v, u, v)`: `∂(U/D)/∂c = (U_c − u·D_c)/D`
    /// (and `V`, rows alike). Any attribute `a = Σ b_i a_i` then changes by `Σ (∂b_i/∂c) a_i` per
    /// column — the screen-space derivatives of texture coordinates that pick a mip level (OpenGL 4.6
    /// §8.14.1). Zero derivatives where [`BaryPlanes::at`] falls back to the centroid.
    #[inline(always)]
    pub(super) fn at_with_derivatives(&self, c: i32, r: i32) -> (Vec3, Vec3, Vec3) {
        let (dc, dr) = (f64::from(c - self.c0), f64::from(r - self.r0));
        let d = self.d[0] + dc * self.d[1] + dr * self.d[2];
        if d == 0.0 || !d.is_finite() {
            return (Vec3::splat(1.0 / 3.0), Vec3::ZERO, Vec3::ZERO);
        }
        let inv = 1.0 / d;
        let u = (self.u[0] + dc * self.u[1] + dr * self.u[2]) * inv;
        let v = (self.v[0] + dc * self.v[1] + dr * self.v[2]) * inv;
        let du = [(self.u[1] - u * self.d[1]) * inv, (self.u[2] - u * self.d[2]) * inv];
        let dv = [(self.v[1] - v * self.d[1]) * inv, (self.v[2] - v * self.d[2]) * inv];
        let db = |k: usize| Vec3::new((-du[k] - dv[k]) as f32, du[k] as f32, dv[k] as f32);
        (Vec3::new((1.0 - u - v) as f32, u as f32, v as f32), db(0), db(1))
    }
}

/// The view ray of every sample: origin and direction affine in the sample's NDC `(x_n, y_n)` (the
/// inverse of a perspective or orthographic projection has a `w` row independent of x and y), built
/// from unprojected points in f64. A perspective camera's rays all start at the eye.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rays {
    /// Perspective: every ray starts at the eye (`o_x = o_y = 0`); orthographic: `d` is constant.
    perspective: bool,
    /// Change of origin and direction per sample column and per sample row.
    o_c: DVec3,
    o_r: DVec3,
    d_c: DVec3,
    d_r: DVec3,
    o: DVec3,
    o_x: DVec3,
    o_y: DVec3,
    d: DVec3,
    d_x: DVec3,
    d_y: DVec3,
    sx: f64,
    sy: f64,
}

impl Rays {
    pub(super) fn new(view_proj: &Mat4, viewport: Viewport, eye: Option<Vec3>) -> Self {
        let inv = view_proj.as_dmat4().inverse();
        let un = |x: f64, y: f64, z: f64| inv.project_point3(DVec3::new(x, y, z));
        let (o, f) = (un(0.0, 0.0, -1.0), un(0.0, 0.0, 1.0));
        let (ox, fx) = (un(1.0, 0.0, -1.0), un(1.0, 0.0, 1.0));
        let (oy, fy) = (un(0.0, 1.0, -1.0), un(0.0, 1.0, 1.0));
        let d = f - o;
        let (o, o_x, o_y) = match eye {
            Some(e) => (e.as_dvec3(), DVec3::ZERO, DVec3::ZERO),
            None => (o, ox - o, oy - o),
        };
        let (d_x, d_y) = (fx - ox - d, fy - oy - d);
        let sx = 2.0 / f64::from(viewport.width);
        let sy = 2.0 / f64::from(viewport.height);
        Self {
            perspective: eye.is_some(),
            o_c: o_x * sx,
            o_r: -o_y * sy,
            d_c: d_x * sx,
            d_r: -d_y * sy,
            o,
            o_x,
            o_y,
            d,
            d_x,
            d_y,
            sx,
            sy,
        }
    }

    /// Origin and direction of the ray through the centre of sample `(c, r)`.
    #[inline]
    pub(super) fn ray(&self, c: i32, r: i32) -> (DVec3, DVec3) {
        let xn = (f64::from(c) + 0.5) * self.sx - 1.0;
        let yn = 1.0 - (f64::from(r) + 0.5) * self.sy;
        (self.o + xn * self.o_x + yn * self.o_y, self.d + xn * self.d_x + yn * self.d_y)
    }
}
