//! Measured (tabulated) isotropic BRDFs: a regular grid over Rusinkiewicz's half/difference angles,
//! looked up by trilinear interpolation, with the MERL `.binary` layout as the file format.
//! Anisotropic 4-D tables and the MIT CSAIL `.dat` format are in [`anisotropic`] and [`mit_dat`], the
//! RGL `.bsdf` materials in [`rgl_bsdf`].
//!
//! There are three ways to render from measured data: look the sampled values up with interpolation,
//! fit an analytic model to them ([`crate::fit`]), or project them onto spherical harmonics
//! ([`crate::sh`]). This module is the look-up.
//!
//! ## Parametrisation
//! An isotropic BRDF depends on three angles: Rusinkiewicz's half/difference angles `(θ_h, θ_d, φ_d)`
//! ([`crate::rusinkiewicz`], re-exported here as [`half_diff_angles`] and [`directions_from_half_diff`]).
//! The specular peak lies along `θ_h = 0`, Fresnel varies with `θ_d`, so a coarse grid captures glossy
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

use glam::{Vec3, Vec3A};

use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, Params};
// The half/difference angles live in their own module (shared with the image-slice view); re-exported
// here, where the table's users have always found them.
pub use crate::rusinkiewicz::{directions_from_half_diff, half_diff_angles, half_diff_angles_lanes};
use crate::simd::{Lane, LaneGeometry, V3};
use crate::{BrdfError, Geometry, Model};

pub mod anisotropic;
mod merl;
pub mod mit_dat;
pub mod rgl_bsdf;
pub mod samples;
pub mod tensor;

pub use anisotropic::{AnisotropicTabulated, MeasuredAnisotropic, aniso_angles_lanes};
pub use merl::MERL_SCALE;
pub use rgl_bsdf::{MeasuredRgl, RglBsdf};
pub use samples::{AngleUnit, Coverage, SampleOptions};
pub use tensor::{DType, TensorField, TensorFile};

/// The resolution of the MERL database files: `(n_th, n_td, n_pd) = (90, 90, 180)`.
pub const MERL_RESOLUTION: (usize, usize, usize) = (90, 90, 180);

/// Largest number of nodes along one axis that [`Tabulated::new`] accepts (guards against a corrupt
/// header asking for gigabytes).
pub const MAX_NODES_PER_AXIS: usize = 4096;

/// Largest number of nodes of a table, 2²⁶ (46 times a MERL table; 768 MB of RGB float32): 4096³ per-axis
/// maxima would be 800 GB.
pub const MAX_NODES: usize = 1 << 26;

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
    let nodes = n_th * n_td * n_pd;
    if nodes > MAX_NODES {
        return Err(BrdfError::InvalidInput {
            name: "table",
            problem: format!(
                "{n_th}x{n_td}x{n_pd} = {nodes} nodes exceed the limit of {MAX_NODES} ({} MB of RGB float32)",
                (MAX_NODES * 12) >> 20
            ),
        });
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
        source: "S. Rusinkiewicz, A New Change of Variables for Efficient BRDF Representation, EGWR (1998); W. Matusik, H. Pfister, M. Brand, L. McMillan, A Data-Driven Reflectance Model, SIGGRAPH (2003)",
        physical: true,
        anisotropic: false,
        params: &[],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// The table's tabulated distribution ([`crate::sampling::tabulated`]) for `1 − DEFENSIVE` of the
    /// samples, cosine-weighted for the rest; the distribution is built on first use and shared.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::tabulated::DEFENSIVE;
        use crate::sampling::{Sampler, Technique};
        let t = self.0.sampler.get_or_build(&self.0)?;
        Ok(Sampler::new().with(Technique::Tabulated(t), 1.0 - DEFENSIVE).with(Technique::Cosine, DEFENSIVE))
    }

    /// Not buildable from parameters: a measured model is built from its table
    /// (`Model::from(Measured(Arc::new(table)))`).
    fn from_params(_: &Params) -> Result<Self, BrdfError> {
        Err(BrdfError::InvalidInput {
            name: "name",
            problem: "\"measured\" is built from a table (brdfpy.measured.Tabulated.as_model()), not by name"
                .to_string(),
        })
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        self.0.eval_lanes(g)
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
    /// Its importance sampler, built on first use (derived data: not part of equality).
    sampler: crate::sampling::tabulated::SamplerCache,
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
        Ok(Self { n_th, n_td, n_pd, data, sampler: Default::default() })
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

    /// The value at node `(i, j, k)`.
    #[cfg(test)]
    fn at(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.data[(i * self.n_td + j) * self.n_pd + k]
    }

    /// Trilinear look-up at half/difference angles \[radians\]; `φ_d` may be any real (it is reduced
    /// modulo π), `θ_h`, `θ_d` are clamped to the grid.
    pub fn lookup(&self, theta_h: f32, theta_d: f32, phi_d: f32) -> Vec3 {
        self.lookup_lanes(theta_h, theta_d, phi_d.rem_euclid(PI)).into()
    }

    /// [`Tabulated::lookup`] on lanes, the one place it is written, for `φ_d` in `[0, π)` (as
    /// [`half_diff_angles`] gives it): the eight corners of each lane's cell are gathered from the
    /// table. NaN angles clamp to node 0 through `max`; every index stays inside the table whatever
    /// the lanes hold.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lookup_lanes<F: Lane>(&self, theta_h: F, theta_d: F, phi_d: F) -> V3<F> {
        let (zero, one) = (F::splat(0.0), F::splat(1.0));
        let (n_th, n_td, n_pd) = (self.n_th as f32, self.n_td as f32, self.n_pd as f32);
        // Index coordinates.
        let uh = ((theta_h.max(zero) / F::splat(FRAC_PI_2)).sqrt() * F::splat(n_th)).clamp(0.0, n_th - 1.0);
        let ud = (theta_d.max(zero) / F::splat(FRAC_PI_2) * F::splat(n_td)).clamp(0.0, n_td - 1.0);
        let up = (phi_d / F::splat(PI) * F::splat(n_pd)).clamp(0.0, n_pd);
        // Lower nodes (`min` also maps NaN to the last cell: no lane indexes outside the table).
        let i0 = uh.floor().min(F::splat(n_th - 2.0));
        let j0 = ud.floor().min(F::splat(n_td - 2.0));
        let k0 = up.floor().min(F::splat(n_pd - 1.0));
        let (fh, fd, fp) = (uh - i0, ud - j0, (up - k0).clamp(0.0, 1.0));
        let (mut row, mut k0s, mut k1s) = ([0usize; 8], [0usize; 8], [0usize; 8]);
        for i in 0..F::LANES {
            let k = k0.lane(i) as usize;
            row[i] = (i0.lane(i) as usize * self.n_td + j0.lane(i) as usize) * self.n_pd;
            k0s[i] = k;
            k1s[i] = (k + 1) % self.n_pd;
        }
        let mut acc = V3::splat(Vec3::ZERO);
        for (di, wi) in [(0, one - fh), (1, fh)] {
            for (dj, wj) in [(0, one - fd), (1, fd)] {
                let off = (di * self.n_td + dj) * self.n_pd;
                let a = V3::from_fn(|i| self.data[row[i] + off + k0s[i]]);
                let b = V3::from_fn(|i| self.data[row[i] + off + k1s[i]]);
                acc = acc + (a.scale(one - fp) + b.scale(fp)).scale(wi * wj);
            }
        }
        acc
    }

    /// `f_r(l, v)` [1/sr] by trilinear interpolation; 0 unless both `l` and `v` are above the
    /// surface (like every physical model) or when `l = −v`.
    pub fn eval(&self, g: &Geometry) -> Vec3 {
        self.eval_lanes(&LaneGeometry::from(g)).into()
    }

    /// [`Tabulated::eval`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn eval_lanes<F: Lane>(&self, g: &LaneGeometry<F>) -> V3<F> {
        let (th, td, pd, ok) = half_diff_angles_lanes(g.l, g.v, g.n);
        V3::select(ok & g.both_above(), self.lookup_lanes(th, td, pd), V3::splat(Vec3::ZERO))
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
        let m = Model::build("lambert", &[("kd".into(), Input::Number(0.6))]).unwrap();
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
}
