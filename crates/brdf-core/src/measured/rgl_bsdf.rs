//! The RGL material database's `.bsdf` files (J. Dupuy, W. Jakob, "An Adaptive Parameterization for
//! Efficient Material Acquisition and Rendering", ACM TOG 37(6), SIGGRAPH Asia 2018), read and
//! evaluated as Mitsuba 3's `measured` plugin does (`src/bsdfs/measured.cpp`, with the warps of
//! `include/mitsuba/core/distr_2d.h`), and written back.
//!
//! ## The file
//! A [`TensorFile`] with the fields (shapes in C order):
//! - `description` (`u8`, the material's name), `jacobian` (`u8[1]`: whether the values must be
//!   multiplied by the Jacobian term below);
//! - `theta_i` (`f32[n_t]`), `phi_i` (`f32[n_p]`) \[radians\]: the incident directions at which the
//!   material was measured (ascending). `n_p ≤ 2` marks an isotropic material; an anisotropic one with
//!   `phi_i` spanning `2π / r` uses `r`-fold symmetry (`r = 2`: mirror in the `x`–`z` plane, `r = 4`:
//!   both planes);
//! - `ndf` (`f32[h, w]`) and `sigma` (`f32[h, w]`): the microfacet distribution and the projected area
//!   over the unit square of `(u_θ, u_φ)` (bilinear);
//! - `vndf` and `luminance` (`f32[n_p, n_t, h, w]`): the visible-normal distribution (the adaptive
//!   parameterisation) and the luminance, as densities over the square, per incident direction;
//! - `rgb` (`f32[n_p, n_t, 3, h', w']`): the values on the *sample* square — the unit square after
//!   warping by the inverse of the VNDF — per incident direction and channel. A spectral file has
//!   `spectra` and `wavelengths` instead (not supported here: it needs a spectral pipeline).
//!
//! ## Evaluation (faithful to Mitsuba's `Measured::eval`)
//! With `ω_i = v` (Mitsuba's `si.wi`) and `ω_o = l` in the local frame (`z = n`, `x` = tangent), both
//! above the surface: fold `ω_i, ω_o` by the symmetry; `m = normalize(ω_i + ω_o)`; `θ`, `φ` of `ω_i`
//! and `m` (`φ_m − φ_i` for an isotropic file); `u_θ = sqrt(θ / (π/2))`, `u_φ = (φ + π) / 2π`
//! (wrapped into `[0, 1)`); the sample `s = VNDF⁻¹(u_m | φ_i, θ_i)` — the inverse of the continuous
//! marginal/conditional warp of the bilinear VNDF, linearly interpolated in `(φ_i, θ_i)`;
//! `value_c = rgb(s | φ_i, θ_i, c)` bilinearly, and with `jacobian` set, `value ·= ndf(u_m) / (4 σ(u_i))`.
//! Mitsuba's value is `f_r · cos θ_o` (the RGL reference code `powitacq` documents `eval` as
//! "f_r * cos"); [`RglBsdf::eval`] returns `f_r = value / cos θ_o` [1/sr], negative channels clamped
//! to 0 (the RGB files approximate spectra and can dip below zero out of gamut).
//!
//! The warps are computed in `f32` from CDFs accumulated in `f64`, as Mitsuba does.

use std::f32::consts::{FRAC_PI_2, PI};

use glam::{Vec3, Vec3A};

use super::tensor::{DType, TensorField, TensorFile};
use super::{Tabulated, check_dims, directions_from_half_diff};
use crate::{BrdfError, Geometry, Model};

fn bad(problem: String) -> BrdfError {
    BrdfError::InvalidInput { name: "bsdf", problem }
}

/// Mitsuba's `Marginal2D<Float, D, Continuous = true>`: a bilinear density on `[0, 1]²` over a
/// `w × h` grid, one slice per combination of `D` parameters (interpolated linearly), with the
/// conditional (`x` given `y`) and marginal (`y`) CDFs of the piecewise-bilinear density.
#[derive(Debug, Clone, PartialEq)]
struct Warp {
    w: usize,
    h: usize,
    params: Vec<Vec<f32>>,
    strides: Vec<usize>,
    data: Vec<f32>,
    cond: Vec<f32>,
    marg: Vec<f32>,
}

impl Warp {
    /// `data` is `slices × h × w`, C order; `normalize` scales each slice to integrate to 1 (then
    /// every slice must have a positive integral), `sampling` builds the CDFs.
    fn new(
        what: &str,
        data: &[f32],
        (h, w): (usize, usize),
        params: Vec<Vec<f32>>,
        normalize: bool,
        sampling: bool,
    ) -> Result<Self, BrdfError> {
        let mut strides = vec![0; params.len()];
        let mut slices = 1;
        for d in (0..params.len()).rev() {
            strides[d] = if params[d].len() > 1 { slices } else { 0 };
            slices *= params[d].len();
        }
        let n_data = w * h;
        debug_assert_eq!(data.len(), slices * n_data);
        let (sx, sy) = (0.5 / (w - 1) as f64, 0.5 / (h - 1) as f64);
        let mut out = Vec::with_capacity(data.len());
        let (mut cond, mut marg) = (Vec::new(), Vec::new());
        if sampling {
            cond.reserve(slices * h * (w - 1));
            marg.reserve(slices * (h - 1));
        }
        for s in 0..slices {
            let d = &data[s * n_data..(s + 1) * n_data];
            let mut norm = 1.0f64;
            if sampling {
                let mut row_sum = vec![0f64; h];
                let c0 = cond.len();
                for y in 0..h {
                    let mut acc = 0f64;
                    for x in 0..w - 1 {
                        acc += sx * (f64::from(d[y * w + x]) + f64::from(d[y * w + x + 1]));
                        cond.push(acc as f32);
                    }
                    row_sum[y] = acc;
                }
                let m0 = marg.len();
                let mut acc = 0f64;
                for y in 0..h - 1 {
                    acc += sy * (row_sum[y] + row_sum[y + 1]);
                    marg.push(acc as f32);
                }
                if normalize {
                    if !(acc > 0.0) {
                        return Err(bad(format!(
                            "{what}: slice {s} integrates to 0, it cannot be a density"
                        )));
                    }
                    norm = 1.0 / acc;
                    let n32 = norm as f32;
                    cond[c0..].iter_mut().for_each(|x| *x *= n32);
                    marg[m0..].iter_mut().for_each(|x| *x *= n32);
                }
            }
            let n32 = norm as f32;
            out.extend(d.iter().map(|&x| x * n32));
        }
        Ok(Self { w, h, params, strides, data: out, cond, marg })
    }

    /// Mitsuba's `interpolate_weights`: the slice offset of the lower corner and `(w0, w1)` per
    /// parameter (`find_interval`, weights clamped to `[0, 1]`).
    fn weights(&self, x: &[f32]) -> (usize, [[f32; 2]; 3]) {
        let mut ws = [[1.0, 0.0]; 3];
        let mut offset = 0;
        for (d, values) in self.params.iter().enumerate() {
            if values.len() == 1 {
                continue;
            }
            let i = values[1..values.len() - 1].partition_point(|&p| p < x[d]);
            let (p0, p1) = (values[i], values[i + 1]);
            let w1 = ((x[d] - p0) / (p1 - p0)).clamp(0.0, 1.0);
            ws[d] = [1.0 - w1, w1];
            offset += self.strides[d] * i;
        }
        (offset, ws)
    }

    /// Mitsuba's `lookup`: element `index` (within a slice of `size`) of `arr`, interpolated over the
    /// parameter corners from slice offset `slice`.
    fn lookup(&self, arr: &[f32], size: usize, index: usize, (slice, ws): &(usize, [[f32; 2]; 3])) -> f32 {
        let d = self.params.len();
        let mut acc = 0.0f32;
        for corner in 0..(1usize << d) {
            let mut w = 1.0;
            let mut s = *slice;
            for (k, (wk, &stride)) in ws.iter().zip(&self.strides).enumerate() {
                let bit = (corner >> k) & 1;
                w *= wk[bit];
                s += bit * stride;
            }
            if w != 0.0 {
                acc += w * arr[s * size + index];
            }
        }
        acc
    }

    /// Cell and fractions of `pos` (clipped to `[0, 1]²`).
    fn cell(&self, pos: [f32; 2]) -> ([usize; 2], [f32; 2]) {
        let px = pos[0].clamp(0.0, 1.0) * (self.w - 1) as f32;
        let py = pos[1].clamp(0.0, 1.0) * (self.h - 1) as f32;
        let (ix, iy) = ((px as usize).min(self.w - 2), (py as usize).min(self.h - 2));
        ([ix, iy], [px - ix as f32, py - iy as f32])
    }

    /// Mitsuba's `Marginal2D::eval`: the bilinear value at `pos` for parameters `x`.
    fn eval(&self, pos: [f32; 2], x: &[f32]) -> f32 {
        let pw = self.weights(x);
        let ([ix, iy], [fx, fy]) = self.cell(pos);
        let (n, i) = (self.w * self.h, iy * self.w + ix);
        let v00 = self.lookup(&self.data, n, i, &pw);
        let v10 = self.lookup(&self.data, n, i + 1, &pw);
        let v01 = self.lookup(&self.data, n, i + self.w, &pw);
        let v11 = self.lookup(&self.data, n, i + self.w + 1, &pw);
        lerp(lerp(v00, v10, fx), lerp(v01, v11, fx), fy)
    }

    /// Mitsuba's `Marginal2D::invert_continuous` (normalised): the uniform sample that the warp maps to
    /// `pos`, and the density there.
    fn invert(&self, pos: [f32; 2], x: &[f32]) -> ([f32; 2], f32) {
        let pw = self.weights(x);
        let ([ix, iy], [fx, fy]) = self.cell(pos);
        let (w, h) = (self.w, self.h);
        let (n_data, n_cond, n_marg) = (w * h, h * (w - 1), h - 1);
        let i = iy * w + ix;
        let v00 = self.lookup(&self.data, n_data, i, &pw);
        let v10 = self.lookup(&self.data, n_data, i + 1, &pw);
        let v01 = self.lookup(&self.data, n_data, i + w, &pw);
        let v11 = self.lookup(&self.data, n_data, i + w + 1, &pw);
        let (c0, c1) = (lerp(v00, v01, fy), lerp(v10, v11, fy));
        let pdf = lerp(c0, c1, fx);
        let (patch_x, patch_y) = (1.0 / (w - 1) as f32, 1.0 / (h - 1) as f32);
        let mut sx = fx * lerp(c0, c1, 0.5 * fx) * patch_x;
        let oc = iy * (w - 1);
        if ix > 0 {
            let a = self.lookup(&self.cond, n_cond, oc + ix - 1, &pw);
            let b = self.lookup(&self.cond, n_cond, oc + ix - 1 + (w - 1), &pw);
            sx += lerp(a, b, fy);
        }
        let r0 = self.lookup(&self.cond, n_cond, oc + (w - 1) - 1, &pw);
        let r1 = self.lookup(&self.cond, n_cond, oc + 2 * (w - 1) - 1, &pw);
        sx /= lerp(r0, r1, fy);
        let mut sy = fy * lerp(r0, r1, 0.5 * fy) * patch_y;
        if iy > 0 {
            sy += self.lookup(&self.marg, n_marg, iy - 1, &pw);
        }
        ([sx, sy], pdf)
    }
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The arrays of an RGL `.bsdf` file (RGB version), as stored (see the module docs). Grids are
/// `(rows, columns) = (h, w)`: rows along `u_φ`, columns along `u_θ`.
#[derive(Debug, Clone, PartialEq)]
pub struct RglParts {
    /// The material's name.
    pub description: String,
    /// Incident polar angles \[radians\], ascending.
    pub theta_i: Vec<f32>,
    /// Incident azimuths \[radians\], ascending (one or two entries: isotropic).
    pub phi_i: Vec<f32>,
    /// `ndf` grid `(h, w)` and values.
    pub ndf: ((usize, usize), Vec<f32>),
    /// `sigma` grid and values.
    pub sigma: ((usize, usize), Vec<f32>),
    /// `vndf` grid; values `[n_p, n_t, h, w]`.
    pub vndf: ((usize, usize), Vec<f32>),
    /// `luminance` grid (the same as `vndf`'s); values `[n_p, n_t, h, w]`.
    pub luminance: ((usize, usize), Vec<f32>),
    /// `rgb` grid; values `[n_p, n_t, 3, h', w']`.
    pub rgb: ((usize, usize), Vec<f32>),
    /// Multiply by `ndf(u_m) / (4 σ(u_i))`.
    pub jacobian: bool,
}

/// An RGL `.bsdf` material, ready to evaluate (module docs): the arrays and Mitsuba's warps of them.
#[derive(Debug, Clone, PartialEq)]
pub struct RglBsdf {
    parts: RglParts,
    ndf: Warp,
    sigma: Warp,
    vndf: Warp,
    luminance: Warp,
    rgb: Warp,
    isotropic: bool,
    reduction: i32,
}

fn grid_of(name: &str, f: &TensorField, rank: usize) -> Result<Vec<usize>, BrdfError> {
    if f.dtype != DType::F32 || f.shape.len() != rank {
        return Err(bad(format!(
            "field {name:?} must be float32 of rank {rank}, is {:?} of shape {:?}",
            f.dtype, f.shape
        )));
    }
    Ok(f.shape.clone())
}

impl RglBsdf {
    /// Check the arrays (the shapes Mitsuba requires, every grid at least 2 × 2, `theta_i` and
    /// `phi_i` non-empty, finite and strictly ascending, densities finite and ≥ 0, `sigma > 0` when
    /// `jacobian`, `rgb` finite) and build the warps.
    pub fn new(parts: RglParts) -> Result<Self, BrdfError> {
        let (nt, np) = (parts.theta_i.len(), parts.phi_i.len());
        for (name, a) in [("theta_i", &parts.theta_i), ("phi_i", &parts.phi_i)] {
            if a.is_empty() {
                return Err(bad(format!("{name} is empty")));
            }
            if let Some(i) = a.iter().position(|x| !x.is_finite()) {
                return Err(bad(format!("{name}[{i}] is not finite")));
            }
            if let Some(i) = a.windows(2).position(|p| !(p[1] > p[0])) {
                return Err(bad(format!(
                    "{name} must be strictly ascending: {name}[{}] = {} after {}",
                    i + 1,
                    a[i + 1],
                    a[i]
                )));
            }
        }
        if parts.theta_i.iter().any(|&t| !(0.0..=FRAC_PI_2 + 1e-4).contains(&t)) {
            return Err(bad("theta_i must lie in [0, π/2]".to_string()));
        }
        let check = |name: &str, ((h, w), d): &((usize, usize), Vec<f32>), slices: usize, density: bool| {
            if *h < 2 || *w < 2 {
                return Err(bad(format!("{name}: the grid must be at least 2x2, is {h}x{w}")));
            }
            let expected = slices.checked_mul(h * w).filter(|&e| e == d.len());
            if expected.is_none() {
                return Err(bad(format!("{name}: expected {slices} x {h} x {w} values, got {}", d.len())));
            }
            if let Some(i) = d.iter().position(|x| !x.is_finite() || (density && *x < 0.0)) {
                return Err(bad(format!(
                    "{name}: value {i} is {}; values must be finite{}",
                    d[i],
                    if density { " and >= 0" } else { "" }
                )));
            }
            Ok(())
        };
        check("ndf", &parts.ndf, 1, true)?;
        check("sigma", &parts.sigma, 1, true)?;
        check("vndf", &parts.vndf, np * nt, true)?;
        check("luminance", &parts.luminance, np * nt, true)?;
        check("rgb", &parts.rgb, np * nt * 3, false)?;
        if parts.luminance.0 != parts.rgb.0 {
            return Err(bad(format!(
                "luminance and rgb must share their grid, are {:?} and {:?}",
                parts.luminance.0, parts.rgb.0
            )));
        }
        if parts.jacobian && parts.sigma.1.iter().any(|&s| !(s > 0.0)) {
            return Err(bad("sigma must be > 0 when jacobian is set (it divides)".to_string()));
        }
        let isotropic = np <= 2;
        let reduction = if isotropic {
            0
        } else {
            let span = parts.phi_i[np - 1] - parts.phi_i[0];
            (2.0 * PI / span).round() as i32
        };
        let pi = vec![parts.phi_i.clone(), parts.theta_i.clone()];
        let channels = vec![parts.phi_i.clone(), parts.theta_i.clone(), vec![0.0, 1.0, 2.0]];
        Ok(Self {
            ndf: Warp::new("ndf", &parts.ndf.1, parts.ndf.0, vec![], false, false)?,
            sigma: Warp::new("sigma", &parts.sigma.1, parts.sigma.0, vec![], false, false)?,
            vndf: Warp::new("vndf", &parts.vndf.1, parts.vndf.0, pi.clone(), true, true)?,
            luminance: Warp::new("luminance", &parts.luminance.1, parts.luminance.0, pi, true, true)?,
            rgb: Warp::new("rgb", &parts.rgb.1, parts.rgb.0, channels, false, false)?,
            isotropic,
            reduction,
            parts,
        })
    }

    /// The arrays.
    pub fn parts(&self) -> &RglParts {
        &self.parts
    }

    /// Whether the material is isotropic (`phi_i` has at most two entries).
    pub fn is_isotropic(&self) -> bool {
        self.isotropic
    }

    /// Read a `.bsdf` file from its bytes ([`TensorFile::read`], then the fields of the module docs).
    /// A spectral file is refused with that reason.
    pub fn read(bytes: &[u8]) -> Result<Self, BrdfError> {
        let tf = TensorFile::read(bytes)?;
        if tf.has_field("wavelengths") || tf.has_field("spectra") {
            return Err(bad(
                "this is a spectral .bsdf file; only the RGB version (field \"rgb\") is supported"
                    .to_string(),
            ));
        }
        let desc = tf.field("description")?;
        if desc.dtype != DType::U8 || desc.shape.len() != 1 {
            return Err(bad("field \"description\" must be uint8 of rank 1".to_string()));
        }
        let jac = tf.field("jacobian")?;
        if jac.dtype != DType::U8 || jac.shape != [1] {
            return Err(bad(format!("field \"jacobian\" must be uint8 of shape [1], is {:?}", jac.shape)));
        }
        let f1 = |name: &str| -> Result<Vec<f32>, BrdfError> {
            let f = tf.field(name)?;
            grid_of(name, f, 1)?;
            f.to_f32()
        };
        let (theta_i, phi_i) = (f1("theta_i")?, f1("phi_i")?);
        let (nt, np) = (theta_i.len(), phi_i.len());
        let g2 = |name: &str| -> Result<((usize, usize), Vec<f32>), BrdfError> {
            let f = tf.field(name)?;
            let s = grid_of(name, f, 2)?;
            Ok(((s[0], s[1]), f.to_f32()?))
        };
        let g4 = |name: &str, rank: usize| -> Result<((usize, usize), Vec<f32>), BrdfError> {
            let f = tf.field(name)?;
            let s = grid_of(name, f, rank)?;
            if s[0] != np || s[1] != nt || (rank == 5 && s[2] != 3) {
                return Err(bad(format!(
                    "field {name:?} has shape {s:?}; expected [{np} (phi_i), {nt} (theta_i){}, h, w]",
                    if rank == 5 { ", 3" } else { "" }
                )));
            }
            Ok(((s[rank - 2], s[rank - 1]), f.to_f32()?))
        };
        Self::new(RglParts {
            description: String::from_utf8_lossy(&desc.bytes).into_owned(),
            theta_i,
            phi_i,
            ndf: g2("ndf")?,
            sigma: g2("sigma")?,
            vndf: g4("vndf", 4)?,
            luminance: g4("luminance", 4)?,
            rgb: g4("rgb", 5)?,
            jacobian: jac.bytes[0] != 0,
        })
    }

    /// The `.bsdf` file of these arrays ([`TensorFile::write`]); [`RglBsdf::read`] reads it back
    /// equal.
    pub fn write(&self) -> Vec<u8> {
        let p = &self.parts;
        let (np, nt) = (p.phi_i.len(), p.theta_i.len());
        let grid = |name: &str, lead: &[usize], ((h, w), d): &((usize, usize), Vec<f32>)| {
            let mut shape = lead.to_vec();
            shape.extend([*h, *w]);
            TensorField::f32(name, shape, d)
        };
        TensorFile {
            fields: vec![
                TensorField::u8("description", vec![p.description.len()], p.description.as_bytes()),
                TensorField::u8("jacobian", vec![1], &[u8::from(p.jacobian)]),
                TensorField::f32("theta_i", vec![nt], &p.theta_i),
                TensorField::f32("phi_i", vec![np], &p.phi_i),
                grid("ndf", &[], &p.ndf),
                grid("sigma", &[], &p.sigma),
                grid("vndf", &[np, nt], &p.vndf),
                grid("luminance", &[np, nt], &p.luminance),
                grid("rgb", &[np, nt, 3], &p.rgb),
            ],
        }
        .write()
    }

    /// `f_r(l, v)` [1/sr] (module docs); 0 unless both directions are above the surface. The tangent
    /// of `g` orients an anisotropic material.
    pub fn eval(&self, g: &Geometry) -> Vec3 {
        let frame = g.frame();
        let (wi, wo) = (frame.to_local(g.v), frame.to_local(g.l));
        self.eval_local(wi, wo)
    }

    /// [`RglBsdf::eval`] on local directions (`z` = normal): `ω_i` is Mitsuba's `si.wi` (the viewer),
    /// `ω_o` the light; unit vectors.
    pub fn eval_local(&self, mut wi: Vec3A, mut wo: Vec3A) -> Vec3 {
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return Vec3::ZERO;
        }
        if self.reduction >= 2 {
            // Mitsuba's `mulsign_neg(a, s)`: `a · (−1 if s ≥ 0 else 1)`.
            let sy = wi.y;
            let sx = if self.reduction == 4 { wi.x } else { sy };
            let neg = |a: f32, s: f32| if s.is_sign_negative() { a } else { -a };
            wi.x = neg(wi.x, sx);
            wi.y = neg(wi.y, sy);
            wo.x = neg(wo.x, sx);
            wo.y = neg(wo.y, sy);
        }
        let m = (wi + wo).normalize_or_zero();
        if m == Vec3A::ZERO {
            return Vec3::ZERO;
        }
        let (theta_i, phi_i) = (elevation(wi), wi.y.atan2(wi.x));
        let (theta_m, phi_m) = (elevation(m), m.y.atan2(m.x));
        let u_wi = [theta2u(theta_i), phi2u(phi_i)];
        let mut u_m = [theta2u(theta_m), phi2u(if self.isotropic { phi_m - phi_i } else { phi_m })];
        u_m[1] -= u_m[1].floor();
        let params = [phi_i, theta_i];
        let (sample, _) = self.vndf.invert(u_m, &params);
        let mut spec = [0.0f32; 3];
        for (c, s) in spec.iter_mut().enumerate() {
            *s = self.rgb.eval(sample, &[phi_i, theta_i, c as f32]);
        }
        let mut value = Vec3::from(spec);
        if self.parts.jacobian {
            value *= self.ndf.eval(u_m, &[]) / (4.0 * self.sigma.eval(u_wi, &[]));
        }
        let f = (value / wo.z).max(Vec3::ZERO);
        if f.is_finite() { f } else { Vec3::ZERO }
    }

    /// The density of Mitsuba's importance sampling at `(ω_i = v, ω_o = l)` (its `Measured::pdf`):
    /// `vndf(u_m) · luminance(s) / (max(2π² u_θ sin θ_m, 10⁻⁶) · 4 ω_i·m)` [1/sr].
    pub fn pdf(&self, g: &Geometry) -> f32 {
        let frame = g.frame();
        let (mut wi, mut wo) = (frame.to_local(g.v), frame.to_local(g.l));
        if !(wi.z > 0.0 && wo.z > 0.0) {
            return 0.0;
        }
        if self.reduction >= 2 {
            let sy = wi.y;
            let sx = if self.reduction == 4 { wi.x } else { sy };
            let neg = |a: f32, s: f32| if s.is_sign_negative() { a } else { -a };
            wi.x = neg(wi.x, sx);
            wi.y = neg(wi.y, sy);
            wo.x = neg(wo.x, sx);
            wo.y = neg(wo.y, sy);
        }
        let m = (wi + wo).normalize_or_zero();
        let (theta_i, phi_i) = (elevation(wi), wi.y.atan2(wi.x));
        let (theta_m, phi_m) = (elevation(m), m.y.atan2(m.x));
        let mut u_m = [theta2u(theta_m), phi2u(if self.isotropic { phi_m - phi_i } else { phi_m })];
        u_m[1] -= u_m[1].floor();
        let params = [phi_i, theta_i];
        let (sample, vndf_pdf) = self.vndf.invert(u_m, &params);
        let lum = self.luminance.eval(sample, &params);
        let sin_m = (1.0 - m.z * m.z).max(0.0).sqrt();
        let jac = (2.0 * PI * PI * u_m[0] * sin_m).max(1e-6) * 4.0 * wi.dot(m);
        let p = vndf_pdf * lum / jac;
        if p.is_finite() { p.max(0.0) } else { 0.0 }
    }

    /// Resample an isotropic material onto a half/difference table: [`RglBsdf::eval`] at each node's
    /// `(l, v)` (`n = +z`), 0 below the horizon. Anisotropic materials are refused (a
    /// `(θ_h, θ_d, φ_d)` table cannot hold them).
    pub fn to_tabulated(&self, dims: (usize, usize, usize)) -> Result<Tabulated, BrdfError> {
        if !self.isotropic {
            return Err(BrdfError::InvalidInput {
                name: "bsdf",
                problem: "the material is anisotropic; a half/difference table holds isotropic BRDFs only"
                    .to_string(),
            });
        }
        check_dims(dims)?;
        let mut data = Vec::with_capacity(dims.0 * dims.1 * dims.2);
        for i in 0..dims.0 {
            for j in 0..dims.1 {
                for k in 0..dims.2 {
                    let (th, td, pd) = Tabulated::node_angles_of(dims, i, j, k);
                    let (l, v) = directions_from_half_diff(th, td, pd);
                    data.push(self.eval_local(v, l));
                }
            }
        }
        Tabulated::new(dims, data)
    }

    /// An RGL file of `model` with identity warps: uniform `vndf`, `luminance`, `ndf` and `sigma`,
    /// `jacobian` off, so that the sample square *is* the `(u_θm, u_φm)` square and
    /// `rgb[p, t, c, y, x] = f_r · cos θ_o` at `ω_i = (θ_i[t], φ_i[p])`,
    /// `m = (θ = (x/(w−1))² π/2, φ = (2y/(h−1) − 1) π (+ φ_i if isotropic))`, `ω_o = 2(m·ω_i)m − ω_i`
    /// (0 where `ω_o` is below the surface). `θ_i` nodes at `(t/(n_t−1))² · 88°`; an isotropic model
    /// gets one `φ_i = 0`, an anisotropic one `n_p ≥ 3` azimuths over `[−π, π]`.
    ///
    /// Not the adaptive parameterisation of Dupuy & Jakob (that needs the model's VNDF): a file that
    /// Mitsuba reads and that evaluates to the model up to bilinear interpolation on the grid.
    pub fn from_model(
        model: &Model,
        n_theta_i: usize,
        n_phi_i: usize,
        (h, w): (usize, usize),
    ) -> Result<Self, BrdfError> {
        let aniso = model.spec().anisotropic;
        let np = if aniso { n_phi_i } else { 1 };
        if !(2..=256).contains(&n_theta_i) || (aniso && !(3..=256).contains(&n_phi_i)) {
            return Err(BrdfError::InvalidInput {
                name: "resolution",
                problem: format!(
                    "n_theta_i must be in [2, 256] and, for an anisotropic model, n_phi_i in [3, 256]; got {n_theta_i}, {n_phi_i}"
                ),
            });
        }
        if !(2..=1024).contains(&h) || !(2..=1024).contains(&w) {
            return Err(BrdfError::InvalidInput {
                name: "resolution",
                problem: format!("the grid must be in [2, 1024] x [2, 1024], got {h} x {w}"),
            });
        }
        let tmax = 88f32.to_radians();
        let theta_i: Vec<f32> =
            (0..n_theta_i).map(|t| (t as f32 / (n_theta_i - 1) as f32).powi(2) * tmax).collect();
        let phi_i: Vec<f32> = if aniso {
            (0..np).map(|p| (2.0 * p as f32 / (np - 1) as f32 - 1.0) * PI).collect()
        } else {
            vec![0.0]
        };
        let mut rgb = vec![0f32; np * n_theta_i * 3 * h * w];
        for (p, &pi) in phi_i.iter().enumerate() {
            for (t, &ti) in theta_i.iter().enumerate() {
                let wi = Vec3A::new(ti.sin() * pi.cos(), ti.sin() * pi.sin(), ti.cos());
                for y in 0..h {
                    for x in 0..w {
                        let tm = (x as f32 / (w - 1) as f32).powi(2) * FRAC_PI_2;
                        let pm = (2.0 * y as f32 / (h - 1) as f32 - 1.0) * PI + if aniso { 0.0 } else { pi };
                        let m = Vec3A::new(tm.sin() * pm.cos(), tm.sin() * pm.sin(), tm.cos());
                        let wo = (2.0 * m.dot(wi) * m - wi).normalize_or_zero();
                        let f = if wo.z > 0.0 {
                            let g = Geometry::new(wo.into(), wi.into(), Vec3::Z, Some(Vec3::X));
                            g.map_or(Vec3::ZERO, |g| model.eval(&g) * wo.z)
                        } else {
                            Vec3::ZERO
                        };
                        let f = if f.is_finite() { f.max(Vec3::ZERO) } else { Vec3::ZERO };
                        for c in 0..3 {
                            rgb[(((p * n_theta_i + t) * 3 + c) * h + y) * w + x] = f[c];
                        }
                    }
                }
            }
        }
        let ones = |n: usize| vec![1.0f32; n];
        let slices = np * n_theta_i;
        Self::new(RglParts {
            description: format!("{} (brdfpy, identity warps)", model.spec().name),
            theta_i,
            phi_i,
            ndf: ((2, 2), ones(4)),
            sigma: ((2, 2), ones(4)),
            vndf: ((h, w), ones(slices * h * w)),
            luminance: ((h, w), ones(slices * h * w)),
            rgb: ((h, w), rgb),
            jacobian: false,
        })
    }
}

/// An [`RglBsdf`] as a [`Model`] (`Model::MeasuredRgl`): it renders and evaluates in batches like any
/// model (an anisotropic file in the frame of the tangent it is given). Shared between clones.
///
/// Its formula runs [`RglBsdf::eval`] once per lane: the warp inversion searches CDFs and has no
/// lane form, so a batch costs what a loop of single evaluations costs.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredRgl(pub std::sync::Arc<RglBsdf>);

impl crate::models::Bxdf for MeasuredRgl {
    const SPEC: crate::params::ModelSpec = crate::params::ModelSpec {
        name: "rgl_bsdf",
        summary: "an RGL .bsdf material (adaptive parameterisation), evaluated as Mitsuba 3's measured plugin",
        source: "J. Dupuy, W. Jakob, An Adaptive Parameterization for Efficient Material Acquisition and Rendering, ACM TOG 37(6), SIGGRAPH Asia (2018)",
        physical: true,
        // An anisotropic file reads the tangent (an isotropic one ignores it).
        anisotropic: true,
        params: &[],
    };
    const KIND: crate::models::ModelKind = crate::models::ModelKind::Physical;

    /// Cosine-weighted directions (Mitsuba's VNDF sampling of the file is not ported).
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    /// Not buildable from parameters: built from its file.
    fn from_params(_: &crate::params::Params) -> Result<Self, BrdfError> {
        Err(BrdfError::InvalidInput {
            name: "name",
            problem: "\"rgl_bsdf\" is built from a file (brdfpy.measured.RglBsdf.as_model()), not by name"
                .to_string(),
        })
    }

    #[inline]
    fn formula<F: crate::simd::Lane>(
        &self,
        g: &crate::simd::LaneGeometry<F>,
        _active: F::Mask,
    ) -> crate::simd::V3<F> {
        crate::simd::V3::from_fn(|i| self.0.eval(&g.lane(i)))
    }
}

impl From<RglBsdf> for Model {
    fn from(r: RglBsdf) -> Self {
        Model::MeasuredRgl(MeasuredRgl(std::sync::Arc::new(r)))
    }
}

/// Mitsuba's numerically stable polar angle of a unit vector: `2 asin(|d − z| / 2)`.
fn elevation(d: Vec3A) -> f32 {
    let dist = (d.x * d.x + d.y * d.y + (d.z - 1.0) * (d.z - 1.0)).sqrt();
    2.0 * (0.5 * dist).clamp(-1.0, 1.0).asin()
}

fn theta2u(theta: f32) -> f32 {
    (theta * (2.0 / PI)).max(0.0).sqrt()
}

fn phi2u(phi: f32) -> f32 {
    (phi + PI) * (0.5 / PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Input;

    fn ct() -> Model {
        Model::build(
            "cook_torrance",
            &[
                ("roughness".into(), Input::Number(0.5)),
                ("kd".into(), Input::Numbers(vec![0.5, 0.3, 0.2])),
                ("ks".into(), Input::Number(0.3)),
            ],
        )
        .unwrap()
    }

    #[test]
    fn a_uniform_warp_inverts_to_the_identity() {
        let w = Warp::new("t", &[1.0; 12], (3, 4), vec![], true, true).unwrap();
        for pos in [[0.0, 0.0], [0.3, 0.7], [0.99, 0.01], [1.0, 1.0]] {
            let (s, pdf) = w.invert(pos, &[]);
            assert!((s[0] - pos[0]).abs() < 1e-6 && (s[1] - pos[1]).abs() < 1e-6, "{pos:?} {s:?}");
            assert!((pdf - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn the_warp_inverse_is_the_cdf_of_the_bilinear_density() {
        // Density 1 + x on [0,1]² (w = 2 columns: 1 and 2), normalised by 1.5: F(x) = (x + x²/2) / 1.5.
        let w = Warp::new("t", &[1.0, 2.0, 1.0, 2.0], (2, 2), vec![], true, true).unwrap();
        for x in [0.1f32, 0.5, 0.9] {
            let (s, pdf) = w.invert([x, 0.4], &[]);
            assert!((s[0] - (x + x * x / 2.0) / 1.5).abs() < 1e-6, "{x}: {s:?}");
            assert!((s[1] - 0.4).abs() < 1e-6);
            assert!((pdf - (1.0 + x) / 1.5).abs() < 1e-6);
        }
    }

    #[test]
    fn a_file_of_a_model_evaluates_to_the_model_and_round_trips() {
        let m = ct();
        let rgl = RglBsdf::from_model(&m, 24, 0, (48, 48)).unwrap();
        assert!(rgl.is_isotropic());
        let bytes = rgl.write();
        let back = RglBsdf::read(&bytes).unwrap();
        assert_eq!(back, rgl);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for a in 0..40 {
            for b in 0..40 {
                let (tl, pl) = (a as f32 / 40.0 * 1.2, a as f32 * 0.7);
                let (tv, pv) = (b as f32 / 40.0 * 1.2, b as f32 * 1.3 + 0.2);
                let l = Vec3::new(tl.sin() * pl.cos(), tl.sin() * pl.sin(), tl.cos());
                let v = Vec3::new(tv.sin() * pv.cos(), tv.sin() * pv.sin(), tv.cos());
                let g = Geometry::new(l, v, Vec3::Z, None).unwrap();
                let (x, y) = (back.eval(&g), m.eval(&g));
                num += f64::from((x - y).length_squared());
                den += f64::from(y.length_squared());
            }
        }
        let rel = (num / den).sqrt();
        eprintln!("relative RMS error of an identity-warp RGL file of Cook-Torrance: {rel:.4}");
        assert!(rel < 0.02, "{rel}");
        let t = back.to_tabulated((16, 16, 32)).unwrap();
        let r = Tabulated::from_model(&m, (16, 16, 32)).unwrap();
        let g = Geometry::new(Vec3::new(0.3, 0.1, 1.0), Vec3::new(-0.2, 0.3, 1.0), Vec3::Z, None).unwrap();
        assert!((t.eval(&g) - r.eval(&g)).abs().max_element() < 0.02 * r.eval(&g).max_element());
    }

    #[test]
    fn an_anisotropic_model_keeps_its_orientation() {
        let ward = Model::build(
            "ward",
            &[("alpha_x".into(), Input::Number(0.15)), ("alpha_y".into(), Input::Number(0.5))],
        )
        .unwrap();
        let rgl = RglBsdf::from_model(&ward, 16, 17, (48, 48)).unwrap();
        assert!(!rgl.is_isotropic());
        let back = RglBsdf::read(&rgl.write()).unwrap();
        let l = Vec3::new(0.4, 0.0, 1.0).normalize();
        for (vx, vy) in [(-0.4, 0.05), (0.05, -0.4), (-0.3, -0.2)] {
            let v = Vec3::new(vx, vy, 1.0).normalize();
            let g = Geometry::new(l, v, Vec3::Z, Some(Vec3::X)).unwrap();
            let (x, y) = (back.eval(&g), ward.eval(&g));
            assert!((x - y).abs().max_element() < 0.1 * y.max_element(), "{x} {y}");
        }
        assert!(back.to_tabulated((8, 8, 8)).unwrap_err().to_string().contains("anisotropic"));
    }

    #[test]
    fn the_material_as_a_model_evaluates_as_the_material_in_batches() {
        use crate::batch::{Directions, Quantity, evaluate};
        let ward = Model::build(
            "ward",
            &[("alpha_x".into(), Input::Number(0.2)), ("alpha_y".into(), Input::Number(0.4))],
        )
        .unwrap();
        let rgl = RglBsdf::from_model(&ward, 6, 7, (12, 12)).unwrap();
        let model = Model::from(rgl.clone());
        assert_eq!(model.spec().name, "rgl_bsdf");
        let ls: Vec<Vec3> =
            (0..37).map(|i| Vec3::new((i as f32 * 0.7).sin(), (i as f32).cos(), 1.2)).collect();
        let vs: Vec<Vec3> = (0..37).map(|i| Vec3::new((i as f32 * 1.3).cos(), -0.3, 0.9)).collect();
        let (n, t) = ([Vec3::Z], [Vec3::new(1.0, 0.2, 0.0)]);
        let (dirs, len) = Directions::new(&ls, &vs, &n, Some(&t)).unwrap();
        let mut out = vec![Vec3::ZERO; len];
        evaluate(&model, &dirs, Quantity::Brdf, &mut out);
        for ((&l, &v), &o) in ls.iter().zip(&vs).zip(&out) {
            let g = Geometry::new(l, v, Vec3::Z, Some(t[0])).unwrap();
            assert_eq!(o.to_array().map(f32::to_bits), rgl.eval(&g).to_array().map(f32::to_bits));
        }
    }

    #[test]
    fn corrupt_files_are_refused_with_the_field() {
        let rgl = RglBsdf::from_model(&ct(), 4, 0, (4, 4)).unwrap();
        let mut p = rgl.parts().clone();
        p.vndf.1[3] = f32::NAN;
        assert!(RglBsdf::new(p).unwrap_err().to_string().contains("vndf: value 3"));
        let mut p = rgl.parts().clone();
        p.luminance.1[0] = -1.0;
        assert!(RglBsdf::new(p).unwrap_err().to_string().contains("luminance"));
        let mut p = rgl.parts().clone();
        p.vndf.1.iter_mut().take(16).for_each(|x| *x = 0.0);
        assert!(RglBsdf::new(p).unwrap_err().to_string().contains("integrates to 0"));
        let mut p = rgl.parts().clone();
        p.theta_i[2] = p.theta_i[1];
        assert!(RglBsdf::new(p).unwrap_err().to_string().contains("ascending"));
        let mut p = rgl.parts().clone();
        p.rgb.1.pop();
        assert!(RglBsdf::new(p).unwrap_err().to_string().contains("rgb: expected"));
        let bytes = rgl.write();
        let e = RglBsdf::read(&bytes[..bytes.len() - 4]).unwrap_err().to_string();
        assert!(e.contains("truncated") && e.contains("rgb"), "{e}");
        // Drop the rgb field from the file: the reader names what is missing.
        let mut tf = TensorFile::read(&bytes).unwrap();
        tf.fields.retain(|f| f.name != "rgb");
        assert!(RglBsdf::read(&tf.write()).unwrap_err().to_string().contains("no field \"rgb\""));
        let mut tf = TensorFile::read(&bytes).unwrap();
        tf.fields.push(TensorField::f32("wavelengths", vec![2], &[400.0, 500.0]));
        assert!(RglBsdf::read(&tf.write()).unwrap_err().to_string().contains("spectral"));
    }
}
