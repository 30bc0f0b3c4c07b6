//! Measured (tabulated) isotropic BRDFs: a regular grid over Rusinkiewicz's half/difference angles,
//! looked up by trilinear interpolation, with the MERL `.binary` layout as the file format.
//!
//! Seed 003 ("Rendering from Measured BRDF") lists the ways to render from measured data: look the
//! sampled values up with interpolation, fit an analytic model to them ([`crate::fit`]), or project
//! them onto spherical harmonics ([`crate::sh`]). This module is the look-up.
//!
//! ## Parametrisation
//! An isotropic BRDF depends on three angles. Rusinkiewicz (1998, "A New Change of Variables for
//! Efficient BRDF Representation") writes a pair `(l, v)` as the half vector `h = normalize(l + v)`,
//! with polar angle `θ_h` from `n`, and the difference vector `d`, which is `l` expressed in a frame
//! where `h` is the pole: `θ_d` is the angle between `l` and `h`, `φ_d` its azimuth around `h`. The
//! specular peak lies along `θ_h = 0`, Fresnel varies with `θ_d`, so a coarse grid captures glossy
//! materials far better than one over `(θ_l, φ_l, θ_v, φ_v)`.
//!
//! The grid is the MERL layout (Matusik, Pfister, Brand, McMillan 2003, "A Data-Driven Reflectance
//! Model"; their `BRDFRead.cpp`):
//! - `θ_h`: `n_th` nodes at `θ_h(i) = (i / n_th)² · π/2` — the square-root mapping puts more samples
//!   near the specular peak;
//! - `θ_d`: `n_td` nodes at `θ_d(j) = j / n_td · π/2`;
//! - `φ_d`: `n_pd` nodes at `φ_d(k) = k / n_pd · π` over `[0, π)`. Helmholtz reciprocity (swapping `l`
//!   and `v` maps `d → −d`, i.e. `φ_d → φ_d + π`) makes the function `π`-periodic in `φ_d`, so the
//!   half range holds everything and interpolation wraps around.
//!
//! MERL reads a sample by truncating each index (nearest lower node). Here the look-up is trilinear
//! in the index coordinates (`sqrt` space for `θ_h`), which is continuous and second-order accurate
//! for smooth BRDFs (the tests measure the rate); outside the last `θ_h`/`θ_d` node the value is
//! held constant.
//!
//! Values are RGB `f_r` in 1/sr. Nodes where `l` or `v` is below the horizon hold 0 (MERL stores a
//! negative "no data" marker there; [`Tabulated::read_merl`] maps negative values to 0).

use std::f32::consts::{FRAC_PI_2, PI};
use std::io::{Read, Write};

use glam::{Vec3, Vec3A};

use crate::microfacet::HalfVector;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, Params};
use crate::{BrdfError, Geometry, Model};

/// MERL's channel scale factors (`BRDFRead.cpp`: `RED_SCALE = 1.0/1500`, `GREEN_SCALE = 1.15/1500`,
/// `BLUE_SCALE = 1.66/1500`): the file stores `f_r / scale` per channel.
pub const MERL_SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

/// The resolution of the MERL database files: `(n_th, n_td, n_pd) = (90, 90, 180)`.
pub const MERL_RESOLUTION: (usize, usize, usize) = (90, 90, 180);

/// Largest number of nodes along one axis that [`Tabulated::new`] accepts (guards against a corrupt
/// header asking for gigabytes).
pub const MAX_NODES_PER_AXIS: usize = 4096;

/// Rusinkiewicz's half/difference angles `(θ_h, θ_d, φ_d)` \[radians\] of a configuration, with `φ_d`
/// folded into `[0, π)` by reciprocity. `None` when `l = −v` (no half vector).
///
/// The difference frame is MERL's: rotate `l` about `n` by `−φ_h`, then about the binormal by `−θ_h`.
/// Equivalently `d = (l·x', l·y', l·h)` with `y' = normalize(n × h)` and `x' = y' × h`. At `θ_h = 0`
/// the azimuth reference is arbitrary (any isotropic BRDF is independent of `φ_d` there).
///
/// The polar angles come from tangent-plane components, not as `acos` of a cosine:
/// `θ_h = atan2(|h̃⊥|, n·h̃)` with the un-normalised `h̃ = l + v` ([`HalfVector`]), and
/// `θ_d = atan2(|l − v|, |l + v|)` (`|l ± v|` = `2 cos θ_d`, `2 sin θ_d` for unit `l`, `v`; `l − v` is
/// `2 sin θ_d` times the difference direction). `acos` of a float32 cosine near 1 is only good to
/// `√(2·2^-24)` ≈ 3.5e-4 rad, and both angles are near 0 exactly where a table matters most: the
/// specular peak (`θ_h` → 0, where the MERL grid's `√θ_h` index spacing turns that into 1.5 cells
/// at 90 nodes) and the retro direction (`θ_d` → 0). A float32 emulation of the `acos` forms was off
/// by 4e-4 rad in both angles, where rounding the inputs to float32 moves them by 2e-7; these forms
/// stay at that floor (1.9e-7 rad), and the look-up of a sharp Cook–Torrance table (roughness 0.05,
/// MERL resolution) near its peak went from 3.2e-4 relative off a float64 look-up to 1.1e-5, where
/// rounding the inputs alone moves it by 9.5e-6 (tests/test_measured.py). Both angles are
/// bit-for-bit symmetric in `l` and `v`.
pub fn half_diff_angles(l: Vec3A, v: Vec3A, n: Vec3A) -> Option<(f32, f32, f32)> {
    let h = crate::vector::halfway(l, v)?;
    let half = HalfVector::<f32>::from_directions(l.into(), v.into(), n.into());
    let theta_h = half.perp2.sqrt().atan2(half.n_dot);
    let theta_d = (l - v).length().atan2(half.len2.sqrt());
    let axis = n.cross(h);
    let y = if axis.length_squared() > 1e-12 {
        axis.normalize()
    } else {
        crate::frame::ShadingFrame::from_normal(h).b
    };
    let x = y.cross(h);
    // The azimuth of l − v = 2 sin θ_d (cos φ_d x' + sin φ_d y') rather than of l: the same angle, but
    // l·x' and l·y' are ~sin θ_d from components ~1, so near the retro direction (θ_d → 0) they keep
    // the rounding of those products, 2^-24/sin θ_d rad of φ_d (a float32 emulation: 3.5× the input
    // floor, median, at θ_d < 1e-3); l − v is exact there (close floats) and small, and stays at the
    // floor. A table hardly depends on φ_d at θ_d → 0, so this is for the angle's own sake.
    let w = l - v;
    let (dx, dy) = (w.dot(x), w.dot(y));
    let mut phi_d = dy.atan2(dx);
    if phi_d < 0.0 {
        phi_d += PI;
    }
    if phi_d >= PI {
        phi_d -= PI;
    }
    Some((theta_h, theta_d, phi_d))
}

/// The directions `(l, v)` for half/difference angles, with `n = +z` and `φ_h = 0` (the inverse of
/// [`half_diff_angles`]; MERL's `half_diff_coords_to_std_coords`).
pub fn directions_from_half_diff(theta_h: f32, theta_d: f32, phi_d: f32) -> (Vec3A, Vec3A) {
    let (sh, ch) = theta_h.sin_cos();
    let (sd, cd) = theta_d.sin_cos();
    let (sp, cp) = phi_d.sin_cos();
    let h = Vec3A::new(sh, 0.0, ch);
    let y = Vec3A::Y;
    let x = Vec3A::new(ch, 0.0, -sh);
    let (dx, dy, dz) = (sd * cp, sd * sp, cd);
    // v is l mirrored about h: in the half frame (−dx, −dy, dz).
    (dx * x + dy * y + dz * h, -dx * x - dy * y + dz * h)
}

/// Every axis needs two nodes to interpolate, and at most [`MAX_NODES_PER_AXIS`].
fn check_dims((n_th, n_td, n_pd): (usize, usize, usize)) -> Result<(), BrdfError> {
    for (name, n) in [("n_theta_h", n_th), ("n_theta_d", n_td), ("n_phi_d", n_pd)] {
        if !(2..=MAX_NODES_PER_AXIS).contains(&n) {
            return Err(BrdfError::InvalidInput {
                name: "table",
                problem: format!("{name} must be in [2, {MAX_NODES_PER_AXIS}], got {n}"),
            });
        }
    }
    Ok(())
}

/// A [`Tabulated`] BRDF as a [`Model`] (`Model::Measured`), so that a measured material renders,
/// evaluates in batches and goes through the checks like any analytic one. The table is shared, not
/// copied, between clones (a MERL table is 17.5 MB).
#[derive(Debug, Clone, PartialEq)]
pub struct Measured(pub std::sync::Arc<Tabulated>);

impl Bxdf for Measured {
    const SPEC: ModelSpec = ModelSpec {
        name: "measured",
        summary: "tabulated isotropic BRDF on the MERL half/difference grid, trilinear look-up",
        source: "seed 003 (Rendering from Measured BRDF); Rusinkiewicz 1998; Matusik et al. 2003",
        physical: true,
        anisotropic: false,
        params: &[],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Not buildable from parameters: a measured model is built from its table
    /// (`Model::from(Measured(Arc::new(table)))`).
    fn from_params(_: &Params) -> Result<Self, BrdfError> {
        Err(BrdfError::InvalidInput {
            name: "name",
            problem: "\"measured\" is built from a table (brdfpy.measured.Tabulated.as_model()), not by name"
                .to_string(),
        })
    }

    #[inline]
    fn f(&self, g: &Geometry) -> Vec3 {
        self.0.eval(g)
    }
}

impl From<Tabulated> for Model {
    fn from(t: Tabulated) -> Self {
        Model::Measured(Measured(std::sync::Arc::new(t)))
    }
}

/// An isotropic BRDF tabulated on the MERL grid (see the module docs); RGB `f_r` [1/sr].
#[derive(Debug, Clone, PartialEq)]
pub struct Tabulated {
    n_th: usize,
    n_td: usize,
    n_pd: usize,
    /// Row-major `[θ_h][θ_d][φ_d]` (φ_d fastest), as in the MERL files.
    data: Vec<Vec3>,
}

impl Tabulated {
    /// Wrap a table of `n_th × n_td × n_pd` RGB values, row-major `[θ_h][θ_d][φ_d]` (φ_d fastest).
    ///
    /// Every dimension must be at least 2 (interpolation needs two nodes) and at most
    /// [`MAX_NODES_PER_AXIS`]; every value finite and ≥ 0.
    pub fn new(dims: (usize, usize, usize), data: Vec<Vec3>) -> Result<Self, BrdfError> {
        check_dims(dims)?;
        let (n_th, n_td, n_pd) = dims;
        let expected = n_th * n_td * n_pd;
        if data.len() != expected {
            return Err(BrdfError::InvalidInput {
                name: "table",
                problem: format!("expected {n_th}x{n_td}x{n_pd} = {expected} RGB values, got {}", data.len()),
            });
        }
        if let Some(i) = data.iter().position(|c| !c.is_finite() || c.min_element() < 0.0) {
            return Err(BrdfError::InvalidInput {
                name: "table",
                problem: format!(
                    "values must be finite and >= 0; entry {i} (theta_h {}, theta_d {}, phi_d {}) is {}",
                    i / (n_td * n_pd),
                    (i / n_pd) % n_td,
                    i % n_pd,
                    data[i]
                ),
            });
        }
        Ok(Self { n_th, n_td, n_pd, data })
    }

    /// Tabulate `model` on a grid of `dims = (n_th, n_td, n_pd)` nodes: `model.eval` at each node's
    /// `(l, v)` ([`directions_from_half_diff`], `n = +z`). Anisotropic models are refused (the table is
    /// isotropic by construction).
    pub fn from_model(model: &Model, dims: (usize, usize, usize)) -> Result<Self, BrdfError> {
        if model.spec().anisotropic {
            return Err(BrdfError::InvalidInput {
                name: "model",
                problem: format!(
                    "{} is anisotropic; a half/difference table holds isotropic BRDFs only",
                    model.spec().name
                ),
            });
        }
        let (n_th, n_td, n_pd) = dims;
        check_dims(dims)?;
        let mut data = Vec::with_capacity(n_th * n_td * n_pd);
        for i in 0..n_th {
            for j in 0..n_td {
                for k in 0..n_pd {
                    let (th, td, pd) = Self::node_angles_of(dims, i, j, k);
                    let (l, v) = directions_from_half_diff(th, td, pd);
                    let g = Geometry::from_unit(l, v, Vec3A::Z);
                    let f = if g.both_above() { model.eval(&g) } else { Vec3::ZERO };
                    // A classic model's f can be negative nowhere, but guard the table's invariant.
                    data.push(if f.is_finite() { f.max(Vec3::ZERO) } else { Vec3::ZERO });
                }
            }
        }
        Self::new(dims, data)
    }

    fn node_angles_of(dims: (usize, usize, usize), i: usize, j: usize, k: usize) -> (f32, f32, f32) {
        let u = i as f32 / dims.0 as f32;
        (u * u * FRAC_PI_2, j as f32 / dims.1 as f32 * FRAC_PI_2, k as f32 / dims.2 as f32 * PI)
    }

    /// The angles `(θ_h, θ_d, φ_d)` \[radians\] of node `(i, j, k)`.
    pub fn node_angles(&self, i: usize, j: usize, k: usize) -> (f32, f32, f32) {
        Self::node_angles_of(self.dims(), i, j, k)
    }

    /// `(n_th, n_td, n_pd)`.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.n_th, self.n_td, self.n_pd)
    }

    /// The values, row-major `[θ_h][θ_d][φ_d]`.
    pub fn data(&self) -> &[Vec3] {
        &self.data
    }

    #[inline]
    fn at(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.data[(i * self.n_td + j) * self.n_pd + k]
    }

    /// Trilinear look-up at half/difference angles \[radians\]; `φ_d` may be any real (it is reduced
    /// modulo π), `θ_h`, `θ_d` are clamped to the grid.
    pub fn lookup(&self, theta_h: f32, theta_d: f32, phi_d: f32) -> Vec3 {
        // Index coordinates; NaN inputs clamp to node 0 through `max`.
        let uh =
            ((theta_h.max(0.0) / FRAC_PI_2).sqrt() * self.n_th as f32).clamp(0.0, (self.n_th - 1) as f32);
        let ud = (theta_d.max(0.0) / FRAC_PI_2 * self.n_td as f32).clamp(0.0, (self.n_td - 1) as f32);
        let up = (phi_d.rem_euclid(PI) / PI * self.n_pd as f32).clamp(0.0, self.n_pd as f32);
        let (i0, j0) = ((uh as usize).min(self.n_th - 2), (ud as usize).min(self.n_td - 2));
        let k0 = (up as usize).min(self.n_pd - 1);
        let (fh, fd, fp) = (uh - i0 as f32, ud - j0 as f32, (up - k0 as f32).clamp(0.0, 1.0));
        let k1 = (k0 + 1) % self.n_pd;
        let mut acc = Vec3::ZERO;
        for (di, wi) in [(0, 1.0 - fh), (1, fh)] {
            for (dj, wj) in [(0, 1.0 - fd), (1, fd)] {
                let a = self.at(i0 + di, j0 + dj, k0);
                let b = self.at(i0 + di, j0 + dj, k1);
                acc += wi * wj * (a * (1.0 - fp) + b * fp);
            }
        }
        acc
    }

    /// `f_r(l, v)` [1/sr] by trilinear interpolation; 0 unless both `l` and `v` are above the
    /// surface (like every physical model) or when `l = −v`.
    pub fn eval(&self, g: &Geometry) -> Vec3 {
        if !g.both_above() {
            return Vec3::ZERO;
        }
        match half_diff_angles(g.l, g.v, g.n) {
            Some((th, td, pd)) => self.lookup(th, td, pd),
            None => Vec3::ZERO,
        }
    }

    /// Read a MERL `.binary` file: three little-endian `int32` dimensions `(n_th, n_td, n_pd)`, then
    /// `n_th·n_td·n_pd` little-endian `f64` per channel, red block, green block, blue block, each value
    /// `f_r / MERL_SCALE[c]`. Negative values (MERL's marker for unmeasured configurations) become 0.
    pub fn read_merl(mut r: impl Read) -> Result<Self, BrdfError> {
        let bad = |problem: String| BrdfError::InvalidInput { name: "merl", problem };
        let mut header = [0u8; 12];
        r.read_exact(&mut header).map_err(|e| bad(format!("cannot read the 12-byte header: {e}")))?;
        let mut dims = [0usize; 3];
        for (c, d) in dims.iter_mut().enumerate() {
            let x =
                i32::from_le_bytes([header[4 * c], header[4 * c + 1], header[4 * c + 2], header[4 * c + 3]]);
            if !(2..=MAX_NODES_PER_AXIS as i32).contains(&x) {
                return Err(bad(format!(
                    "dimension {c} in the header is {x}, expected 2..={MAX_NODES_PER_AXIS}"
                )));
            }
            *d = x as usize;
        }
        let count = dims[0] * dims[1] * dims[2];
        let mut bytes = vec![0u8; 3 * count * 8];
        r.read_exact(&mut bytes).map_err(|e| {
            bad(format!(
                "expected {} bytes of data for {}x{}x{} samples x 3 channels: {e}",
                bytes.len(),
                dims[0],
                dims[1],
                dims[2]
            ))
        })?;
        let mut extra = [0u8; 1];
        if r.read(&mut extra).map_err(|e| bad(e.to_string()))? != 0 {
            return Err(bad("trailing bytes after the data".to_string()));
        }
        let mut data = vec![Vec3::ZERO; count];
        for c in 0..3 {
            for (i, out) in data.iter_mut().enumerate() {
                let o = (c * count + i) * 8;
                let mut b = [0u8; 8];
                b.copy_from_slice(&bytes[o..o + 8]);
                let x = f64::from_le_bytes(b);
                if !x.is_finite() {
                    return Err(bad(format!("value {i} of channel {c} is not finite ({x})")));
                }
                out[c] = (x * MERL_SCALE[c]).max(0.0) as f32;
            }
        }
        Self::new((dims[0], dims[1], dims[2]), data)
    }

    /// Write the table in the MERL `.binary` layout (see [`Tabulated::read_merl`]).
    pub fn write_merl(&self, mut w: impl Write) -> Result<(), BrdfError> {
        let io = |e: std::io::Error| BrdfError::InvalidInput { name: "merl", problem: e.to_string() };
        let mut out = Vec::with_capacity(12 + self.data.len() * 24);
        for d in [self.n_th, self.n_td, self.n_pd] {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for c in 0..3 {
            for v in &self.data {
                out.extend_from_slice(&(f64::from(v[c]) / MERL_SCALE[c]).to_le_bytes());
            }
        }
        w.write_all(&out).map_err(io)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Input;

    fn ct() -> Model {
        Model::build(
            "cook_torrance",
            &[
                ("roughness".into(), Input::Number(0.3)),
                ("kd".into(), Input::Numbers(vec![0.5, 0.3, 0.2])),
                ("ks".into(), Input::Number(0.5)),
            ],
        )
        .unwrap()
    }

    #[test]
    fn a_table_as_a_model_evaluates_as_the_table_one_by_one_and_in_batches() {
        use crate::batch::{Directions, Quantity, evaluate};
        let table = Tabulated::from_model(&ct(), (16, 16, 32)).unwrap();
        let model = Model::from(table.clone());
        assert_eq!((model.spec().name, model.spec().physical), ("measured", true));
        let dirs: Vec<Vec3> = hemisphere(64, 89.0).into_iter().map(Vec3::from).collect();
        let (mut ls, mut vs) = (Vec::new(), Vec::new());
        for &l in &dirs {
            for &v in dirs.iter().step_by(7) {
                ls.push(l);
                vs.push(v);
            }
        }
        // Below the horizon too: 0 there, like every physical model.
        ls.push(Vec3::new(0.3, 0.1, -0.5));
        vs.push(Vec3::new(0.0, 0.2, 1.0));
        let n = [Vec3::Z];
        let (batch_dirs, len) = Directions::new(&ls, &vs, &n, None).unwrap();
        let mut out = vec![Vec3::ZERO; len];
        evaluate(&model, &batch_dirs, Quantity::Brdf, &mut out);
        for ((&l, &v), &o) in ls.iter().zip(&vs).zip(&out) {
            let g = Geometry::new(l, v, Vec3::Z, None).unwrap();
            assert_eq!(model.eval(&g), table.eval(&g));
            assert_eq!(o.to_array().map(f32::to_bits), model.eval(&g).to_array().map(f32::to_bits));
        }
        assert_eq!(*out.last().unwrap(), Vec3::ZERO);
        let e = Model::build("measured", &[]).unwrap_err().to_string();
        assert!(e.contains("unknown model"), "{e}");
    }

    /// Deterministic directions over the hemisphere (a Fibonacci spiral), `n = +z`.
    fn hemisphere(count: usize, max_theta_deg: f32) -> Vec<Vec3A> {
        let zmin = max_theta_deg.to_radians().cos();
        (0..count)
            .map(|i| {
                let z = 1.0 - (1.0 - zmin) * (i as f32 + 0.5) / count as f32;
                let phi = i as f32 * 2.399_963;
                let s = (1.0 - z * z).sqrt();
                Vec3A::new(s * phi.cos(), s * phi.sin(), z)
            })
            .collect()
    }

    #[test]
    fn half_diff_angles_invert_directions_from_half_diff() {
        for &(th, td, pd) in &[(0.3, 0.5, 0.2), (0.05, 1.0, 2.9), (0.7, 0.2, 1.4), (0.0, 0.4, 0.0)] {
            let (l, v) = directions_from_half_diff(th, td, pd);
            assert!((l.length() - 1.0).abs() < 1e-6 && (v.length() - 1.0).abs() < 1e-6);
            let (a, b, c) = half_diff_angles(l, v, Vec3A::Z).unwrap();
            assert!((a - th).abs() < 1e-3 && (b - td).abs() < 1e-4, "{th} {td} -> {a} {b}");
            if th > 0.0 {
                assert!((c - pd).abs() < 1e-4, "{pd} -> {c}");
            }
        }
    }

    #[test]
    fn half_and_difference_angles_near_zero_are_accurate_to_the_float32_input_rounding() {
        // The specular peak (θ_h → 0) and the retro direction (θ_d → 0): directions built in float64 at
        // known angles from 1e-7 rad up, rounded to float32. Rounding the inputs moves the angles by
        // ~1e-7 rad (an ulp of a unit vector's components over |l + v| ≥ 0.34); acos of a float32
        // cosine near 1 was off by up to 4e-4 rad (√(2·2^-24) at the angle 0), and φ_d as the azimuth
        // of l rather than of l − v by ~2^-24/sin θ_d (a few times the input floor).
        use glam::DVec3;
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..3000 {
            let k = f64::from(i);
            let theta_h = 1e-7 * 1e6f64.powf((k * 0.618_034) % 1.0);
            let theta_d =
                if i % 2 == 0 { 1e-7 * 1e6f64.powf((k * 0.414_214) % 1.0) } else { (k * 0.377) % 1.4 };
            let (phi_h, phi_d) = (k * 2.399, (k * 1.3) % std::f64::consts::PI);
            let h = DVec3::new(theta_h.sin() * phi_h.cos(), theta_h.sin() * phi_h.sin(), theta_h.cos());
            let y = DVec3::new(-phi_h.sin(), phi_h.cos(), 0.0);
            let d = theta_d.sin() * (phi_d.cos() * y.cross(h) + phi_d.sin() * y);
            let (l, v) = (theta_d.cos() * h + d, theta_d.cos() * h - d);
            if l.z <= 0.0 || v.z <= 0.0 {
                continue;
            }
            let (a, b, c) = half_diff_angles(l.as_vec3a(), v.as_vec3a(), Vec3A::Z).unwrap();
            let (ea, eb) = ((f64::from(a) - theta_h).abs(), (f64::from(b) - theta_d).abs());
            assert!(ea < 4e-7 && eb < 4e-7, "theta_h {theta_h:e} -> {a:e}, theta_d {theta_d:e} -> {b:e}");
            worst = (worst.0.max(ea), worst.1.max(eb), worst.2);
            // φ_d is the azimuth of l − v, of length 2 sin θ_d, in a frame turned with n × h (exact for
            // n = z): rounding the inputs moves it by ~6e-8/sin θ_d. The floor is that, for these
            // float32 inputs: φ_d of them in float64. Below |n × h| = 1e-6 the azimuth reference is
            // arbitrary (a fixed frame around h).
            if theta_h < 2e-6 {
                continue;
            }
            let (l32, v32) = (l.as_vec3().as_dvec3(), v.as_vec3().as_dvec3());
            let h32 = (l32 + v32).normalize();
            let y32 = DVec3::Z.cross(h32).normalize();
            let w32 = l32 - v32;
            let azimuth = |p: f64| {
                let e = (p - phi_d).rem_euclid(std::f64::consts::PI);
                e.min(std::f64::consts::PI - e)
            };
            let floor = azimuth(w32.dot(y32).atan2(w32.dot(y32.cross(h32))));
            let ec = azimuth(f64::from(c));
            let bound = 4.0 * floor + 8.0 * f64::from(f32::EPSILON / 2.0);
            assert!(
                ec <= bound,
                "phi_d {phi_d} -> {c} (floor {floor:e}) at theta_h {theta_h:e}, theta_d {theta_d:e}"
            );
            worst.2 = worst.2.max(ec / bound);
        }
        eprintln!(
            "largest errors near 0: theta_h {:.2e}, theta_d {:.2e} rad; phi_d {:.2} of its bound",
            worst.0, worst.1, worst.2
        );
    }

    #[test]
    fn swapping_light_and_viewer_shifts_phi_d_by_pi() {
        let (l, v) = directions_from_half_diff(0.4, 0.6, 0.5);
        let (_, _, p1) = half_diff_angles(l, v, Vec3A::Z).unwrap();
        let (_, _, p2) = half_diff_angles(v, l, Vec3A::Z).unwrap();
        assert!((p1 - p2).abs() < 1e-5, "{p1} {p2}: folded to [0, pi) both must agree");
    }

    #[test]
    fn lookup_at_a_node_returns_the_node_value() {
        let t = Tabulated::from_model(&ct(), (16, 16, 32)).unwrap();
        for &(i, j, k) in &[(3, 4, 5), (10, 2, 31), (0, 7, 0)] {
            let (th, td, pd) = t.node_angles(i, j, k);
            let got = t.lookup(th, td, pd);
            assert!((got - t.at(i, j, k)).abs().max_element() < 1e-4 * (1.0 + t.at(i, j, k).max_element()));
        }
    }

    /// Relative RMS error of the table against its model over directions up to 70° (away from the
    /// horizon, where the table's last nodes hold 0 for configurations below it).
    fn rel_rms(model: &Model, t: &Tabulated) -> f32 {
        let dirs = hemisphere(200, 70.0);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for (a, &l) in dirs.iter().enumerate() {
            for &v in dirs.iter().skip(a % 7).step_by(7) {
                let g = Geometry::from_unit(l, v, Vec3A::Z);
                let (m, e) = (model.eval(&g), t.eval(&g));
                num += f64::from((m - e).length_squared());
                den += f64::from(m.length_squared());
            }
        }
        (num / den).sqrt() as f32
    }

    #[test]
    fn interpolation_error_shrinks_at_second_order_with_resolution() {
        let m = ct();
        let errs: Vec<f32> = [8usize, 16, 32, 64]
            .iter()
            .map(|&n| rel_rms(&m, &Tabulated::from_model(&m, (n, n, 2 * n)).unwrap()))
            .collect();
        eprintln!("relative RMS error of the table at n = 8, 16, 32, 64: {errs:?}");
        // Trilinear interpolation of a smooth function is O(h²), so halving the
        // spacing should divide the error by about 4. Measured: 7.0e-3, 1.6e-3, 4.2e-4, 1.05e-4
        // (ratios 4.3, 3.8, 4.0); ask for 3.3 at every step.
        for w in errs.windows(2) {
            assert!(w[0] / w[1] > 3.3, "errors {errs:?}");
        }
        assert!(errs[3] < 2e-4, "errors {errs:?}");
    }

    #[test]
    fn lambertian_table_is_exact_above_the_horizon_and_zero_below() {
        let m = Model::build("lambert", &[("albedo".into(), Input::Number(0.6))]).unwrap();
        let t = Tabulated::from_model(&m, (8, 8, 16)).unwrap();
        let g = Geometry::new(Vec3::new(0.2, 0.1, 1.0), Vec3::new(-0.5, 0.3, 1.0), Vec3::Z, None).unwrap();
        assert!((t.eval(&g) - Vec3::splat(0.6 / PI)).abs().max_element() < 1e-6);
        let below = Geometry::new(Vec3::new(0.2, 0.1, -1.0), Vec3::Z, Vec3::Z, None).unwrap();
        assert_eq!(t.eval(&below), Vec3::ZERO);
    }

    #[test]
    fn table_is_reciprocal_by_construction() {
        let t = Tabulated::from_model(&ct(), (16, 16, 32)).unwrap();
        let dirs = hemisphere(40, 80.0);
        for &l in &dirs {
            for &v in dirs.iter().step_by(3) {
                let g = Geometry::from_unit(l, v, Vec3A::Z);
                let (a, b) = (t.eval(&g), t.eval(&g.swapped()));
                assert!((a - b).abs().max_element() <= 1e-4 * (1.0 + a.max_element()), "{a} {b}");
            }
        }
    }

    #[test]
    fn bad_tables_are_refused_with_the_reason() {
        let e = Tabulated::new((1, 4, 4), vec![Vec3::ZERO; 16]).unwrap_err().to_string();
        assert!(e.contains("n_theta_h") && e.contains("got 1"), "{e}");
        let e = Tabulated::new((2, 2, 2), vec![Vec3::ZERO; 7]).unwrap_err().to_string();
        assert!(e.contains("8") && e.contains("got 7"), "{e}");
        let mut d = vec![Vec3::ONE; 8];
        d[5] = Vec3::new(0.0, f32::NAN, 0.0);
        let e = Tabulated::new((2, 2, 2), d).unwrap_err().to_string();
        assert!(e.contains("finite") && e.contains("entry 5"), "{e}");
        let mut d = vec![Vec3::ONE; 8];
        d[2] = Vec3::new(0.0, -1.0, 0.0);
        assert!(Tabulated::new((2, 2, 2), d).is_err());
        let ward = Model::build("ward", &[]).unwrap();
        let e = Tabulated::from_model(&ward, (4, 4, 4)).unwrap_err().to_string();
        assert!(e.contains("anisotropic"), "{e}");
    }

    #[test]
    fn merl_binary_round_trips_and_has_the_documented_layout() {
        let t = Tabulated::from_model(&ct(), (6, 5, 8)).unwrap();
        let mut bytes = Vec::new();
        t.write_merl(&mut bytes).unwrap();
        assert_eq!(bytes.len(), 12 + 6 * 5 * 8 * 3 * 8);
        assert_eq!(&bytes[0..12], &[6, 0, 0, 0, 5, 0, 0, 0, 8, 0, 0, 0]);
        // Green value of node (i, j, k) = (2, 3, 4) sits in the second block at (2*5 + 3)*8 + 4.
        let idx = (2 * 5 + 3) * 8 + 4;
        let o = 12 + (6 * 5 * 8 + idx) * 8;
        let g = f64::from_le_bytes(bytes[o..o + 8].try_into().unwrap());
        assert!((g * 1.15 / 1500.0 - f64::from(t.at(2, 3, 4).y)).abs() < 1e-9);
        let back = Tabulated::read_merl(bytes.as_slice()).unwrap();
        assert_eq!(back.dims(), t.dims());
        for (a, b) in back.data().iter().zip(t.data()) {
            assert!((*a - *b).abs().max_element() <= 1e-7 * a.max_element().max(1.0));
        }
    }

    #[test]
    fn merl_reader_refuses_truncated_or_corrupt_files() {
        let t = Tabulated::from_model(&ct(), (4, 4, 4)).unwrap();
        let mut bytes = Vec::new();
        t.write_merl(&mut bytes).unwrap();
        let e = Tabulated::read_merl(&bytes[..bytes.len() - 3]).unwrap_err().to_string();
        assert!(e.contains("expected") && e.contains("bytes"), "{e}");
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(Tabulated::read_merl(longer.as_slice()).unwrap_err().to_string().contains("trailing"));
        let mut bad = bytes.clone();
        bad[0..4].copy_from_slice(&(-90i32).to_le_bytes());
        assert!(Tabulated::read_merl(bad.as_slice()).unwrap_err().to_string().contains("-90"));
        let mut neg = bytes.clone();
        neg[12..20].copy_from_slice(&(-1.0f64).to_le_bytes());
        assert_eq!(Tabulated::read_merl(neg.as_slice()).unwrap().data()[0].x, 0.0);
    }
}
