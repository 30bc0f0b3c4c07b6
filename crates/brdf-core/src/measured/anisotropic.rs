//! Measured anisotropic BRDFs: a 4-D table over `(θ_in, θ_out, φ_diff, φ_in)` in the local frame
//! (tangent `t`, bitangent `b = n × t`, normal `n`), looked up by multilinear interpolation with the
//! azimuths wrapping around. The file format is the MIT CSAIL `.dat` ([`super::mit_dat`]).
//!
//! ## Parametrisation (the layout of the MIT CSAIL data)
//! The data of A. Ngan, F. Durand, W. Matusik, "Experimental Analysis of BRDF Models" (EGSR 2005), as
//! the BRDF Explorer (B. Burley, Disney, 2012: `BRDFMeasuredAniso.cpp`, `measuredAniso.func`) reads
//! them: "in" is the light `l`, "out" the viewer `v`.
//! - `θ_in`, `θ_out` ∈ `[0, π/2]`: polar angles of `l` and `v` from `n`;
//! - `φ_in` ∈ `[0, 2π)`: `atan2(−l·b, −l·t)`, the azimuth of `−l` (the direction the incident light
//!   travels in), i.e. the azimuth of `l` plus π;
//! - `φ_diff` = `φ_out − φ_in` with `φ_out = atan2(−v·b, −v·t)`, in `[0, 2π)` (the two π cancel: it is
//!   the azimuth of `v` minus that of `l`); in `[0, π)` for a "half" table (below).
//!
//! The signs are the Explorer's (its shader is the only published reader of these files): a file then
//! shows the same orientation in both programs, and rotating the tangent by π (which leaves every
//! BRDF with the usual two-fold symmetry unchanged) is the only difference from measuring `φ_in` as
//! the azimuth of `l` itself.
//!
//! Every axis has uniform *bins*: bin `i` of `n` covers `[i, i+1) · range/n`, and its value belongs
//! to the bin centre `(i + ½) · range/n`. The look-up interpolates multilinearly between bin centres;
//! along `θ` a value beyond the first or last centre is held, along `φ_in` (and `φ_diff` of a full
//! table) the last bin's neighbour is the first.
//!
//! ## Half tables
//! With `half_data` the file stores `φ_diff` ∈ `[0, π)` only. The other half follows from Helmholtz
//! reciprocity: exchanging `l` and `v` maps `(θ_in, θ_out, φ_diff, φ_in)` to
//! `(θ_out, θ_in, 2π − φ_diff, φ_in + φ_diff)`, so a configuration with `φ_diff ≥ π` is looked up at
//! its exchanged coordinates. Along `φ_diff` a half table holds its values beyond the first and last
//! bin centres (the neighbours across 0 and π are other cells, not a wrap).
//!
//! ## Cells without data
//! The files mark unmeasured bins with negative values. A cell is *without data* when any of its
//! channels is negative there (the Explorer shows such a bin black); it holds 0, and the look-up
//! interpolates that 0 like any value: continuous, and what the Explorer shows at the bin centre.
//! Renormalising the weights of the corners with data instead would jump to a neighbour's value at a
//! hole's centre. [`AnisotropicTabulated::valid`] is the mask (a fit can weight samples by it).
//!
//! Values are RGB, as stored (see [`super::mit_dat`] for the scale).

use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::sync::Arc;

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::{MAX_NODES, MAX_NODES_PER_AXIS};
use crate::frame::LaneFrame;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};
use crate::{BrdfError, Geometry, Model};

/// The names of the four axes, in the order of the dims (and of the file).
pub const AXES: [&str; 4] = ["theta_in", "theta_out", "phi_diff", "phi_in"];

/// Check `dims`: every axis at least 1 bin and at most [`MAX_NODES_PER_AXIS`], at most [`MAX_NODES`]
/// cells (an error naming `name`).
pub(crate) fn check_aniso_dims(name: &'static str, dims: [usize; 4]) -> Result<usize, BrdfError> {
    for (axis, &n) in AXES.iter().zip(&dims) {
        if !(1..=MAX_NODES_PER_AXIS).contains(&n) {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("{axis} must have 1 to {MAX_NODES_PER_AXIS} bins, got {n}"),
            });
        }
    }
    // Each factor is at most 4096, so the product of four fits in u64 (and usize on 64-bit targets).
    let cells = dims.iter().fold(1u64, |a, &n| a * n as u64);
    if cells > MAX_NODES as u64 {
        return Err(BrdfError::InvalidInput {
            name,
            problem: format!(
                "{}x{}x{}x{} = {cells} cells exceed the limit of {MAX_NODES} ({} MB of RGB float32)",
                dims[0],
                dims[1],
                dims[2],
                dims[3],
                (MAX_NODES * 12) >> 20
            ),
        });
    }
    Ok(cells as usize)
}

/// An anisotropic BRDF tabulated over `(θ_in, θ_out, φ_diff, φ_in)` (module docs); RGB values.
#[derive(Debug, Clone, PartialEq)]
pub struct AnisotropicTabulated {
    dims: [usize; 4],
    half_data: bool,
    /// `index = i_φin + n_φin·(i_φdiff + n_φdiff·(i_θout + n_θout·i_θin))` (φ_in fastest), as in the
    /// files; 0 where `valid` is false.
    data: Vec<Vec3>,
    valid: Vec<bool>,
}

/// One axis of a look-up: the two bins and the weight of the upper one, per lane.
struct Axis<F: Lane> {
    i0: [usize; 8],
    i1: [usize; 8],
    f: F,
}

/// The bins around `x` on an axis of `n` bins over `[0, range)`: clamped (held beyond the first and
/// last bin centres) or wrapping. NaN coordinates land on bin 0 (`max` picks the number): every index
/// stays inside the table whatever the lanes hold.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn axis<F: Lane>(x: F, range: f32, n: usize, wrap: bool) -> Axis<F> {
    let nf = n as f32;
    let u = x * F::splat(nf / range) - F::splat(0.5);
    let (mut i0, mut i1) = ([0usize; 8], [0usize; 8]);
    let f = if wrap {
        // u in [−0.5, n − 0.5) for x in [0, range); the bin below −0.5.. is the last one.
        let u = u.max(F::splat(-1.0)).min(F::splat(nf));
        let lo = u.floor();
        for k in 0..F::LANES {
            let i = (lo.lane(k) as isize).rem_euclid(n as isize) as usize;
            i0[k] = i;
            i1[k] = (i + 1) % n;
        }
        (u - lo).clamp(0.0, 1.0)
    } else {
        let u = u.max(F::splat(0.0)).min(F::splat(nf - 1.0));
        let lo = u.floor();
        for k in 0..F::LANES {
            let i = (lo.lane(k) as usize).min(n - 1);
            i0[k] = i;
            i1[k] = (i + 1).min(n - 1);
        }
        u - lo
    };
    Axis { i0, i1, f }
}

impl AnisotropicTabulated {
    /// Wrap `data` (`dims = [n_θin, n_θout, n_φdiff, n_φin]` bins, φ_in fastest) with its mask of
    /// cells that have data (`None`: all of them). Values of cells with data must be finite and ≥ 0;
    /// those of cells without are replaced by 0. `half_data`: `φ_diff` covers `[0, π)` (module docs).
    pub fn new(
        dims: [usize; 4],
        half_data: bool,
        mut data: Vec<Vec3>,
        valid: Option<Vec<bool>>,
    ) -> Result<Self, BrdfError> {
        let cells = check_aniso_dims("dims", dims)?;
        if data.len() != cells {
            return Err(BrdfError::InvalidInput {
                name: "values",
                problem: format!(
                    "expected {}x{}x{}x{} = {cells} RGB values, got {}",
                    dims[0],
                    dims[1],
                    dims[2],
                    dims[3],
                    data.len()
                ),
            });
        }
        let valid = valid.unwrap_or_else(|| vec![true; cells]);
        if valid.len() != cells {
            return Err(BrdfError::InvalidInput {
                name: "valid",
                problem: format!("expected one flag per cell ({cells}), got {}", valid.len()),
            });
        }
        for (i, (d, &ok)) in data.iter_mut().zip(&valid).enumerate() {
            if !ok {
                *d = Vec3::ZERO;
            } else if !d.is_finite() || d.min_element() < 0.0 {
                let [a, b, c, e] = Self::unravel(dims, i);
                return Err(BrdfError::InvalidInput {
                    name: "values",
                    problem: format!(
                        "values of cells with data must be finite and >= 0; cell {i} (theta_in {a}, theta_out {b}, phi_diff {c}, phi_in {e}) is {d}"
                    ),
                });
            }
        }
        Ok(Self { dims, half_data, data, valid })
    }

    fn unravel(dims: [usize; 4], i: usize) -> [usize; 4] {
        [
            i / (dims[3] * dims[2] * dims[1]),
            (i / (dims[3] * dims[2])) % dims[1],
            (i / dims[3]) % dims[2],
            i % dims[3],
        ]
    }

    /// The flat index of bin `[i_θin, i_θout, i_φdiff, i_φin]`.
    pub fn index(&self, b: [usize; 4]) -> usize {
        let d = self.dims;
        b[3] + d[3] * (b[2] + d[2] * (b[1] + d[1] * b[0]))
    }

    /// `[n_θin, n_θout, n_φdiff, n_φin]`.
    pub fn dims(&self) -> [usize; 4] {
        self.dims
    }

    /// Whether `φ_diff` covers `[0, π)` (reciprocity gives the rest) rather than `[0, 2π)`.
    pub fn half_data(&self) -> bool {
        self.half_data
    }

    /// The values (0 in cells without data), φ_in fastest.
    pub fn data(&self) -> &[Vec3] {
        &self.data
    }

    /// Which cells have data.
    pub fn valid(&self) -> &[bool] {
        &self.valid
    }

    /// The fraction of the cells that have data.
    pub fn coverage(&self) -> f64 {
        self.valid.iter().filter(|&&v| v).count() as f64 / self.valid.len() as f64
    }

    /// The range of `φ_diff`: 2π, or π for a half table.
    fn phi_diff_range(&self) -> f32 {
        if self.half_data { PI } else { TAU }
    }

    /// The angles `(θ_in, θ_out, φ_diff, φ_in)` \[radians\] of the centre of bin `b`.
    pub fn bin_angles(&self, b: [usize; 4]) -> [f32; 4] {
        let c = |i: usize, n: usize, range: f32| (i as f32 + 0.5) * range / n as f32;
        let d = self.dims;
        [
            c(b[0], d[0], FRAC_PI_2),
            c(b[1], d[1], FRAC_PI_2),
            c(b[2], d[2], self.phi_diff_range()),
            c(b[3], d[3], TAU),
        ]
    }

    /// Local unit directions `(l, v)` (`z` = normal, `x` = tangent) of table angles (the inverse of
    /// [`aniso_angles_lanes`]).
    pub fn directions(theta_in: f32, theta_out: f32, phi_diff: f32, phi_in: f32) -> (Vec3A, Vec3A) {
        // φ is the azimuth of −l (module docs): l itself points at φ + π.
        let dir = |t: f32, p: f32| {
            let (sp, cp) = (p + PI).sin_cos();
            Vec3A::new(t.sin() * cp, t.sin() * sp, t.cos())
        };
        (dir(theta_in, phi_in), dir(theta_out, phi_in + phi_diff))
    }

    /// Tabulate `model` at the bin centres of `dims` (`half_data`: `φ_diff` over `[0, π)` only, which
    /// assumes the model reciprocal): `model.eval` at each centre's `(l, v)` with `n = +z` and
    /// tangent `+x`. Every bin centre is above the horizon, so every cell has data.
    pub fn from_model(model: &Model, dims: [usize; 4], half_data: bool) -> Result<Self, BrdfError> {
        let cells = check_aniso_dims("dims", dims)?;
        let proto = Self { dims, half_data, data: vec![], valid: vec![] };
        let row = dims[1] * dims[2] * dims[3];
        let mut data = vec![Vec3::ZERO; cells];
        data.par_chunks_mut(row).enumerate().for_each(|(i, out)| {
            for (k, o) in out.iter_mut().enumerate() {
                let [_, b, c, e] = Self::unravel(dims, i * row + k);
                let [ti, to, pd, pi] = proto.bin_angles([i, b, c, e]);
                let (l, v) = Self::directions(ti, to, pd, pi);
                let f = Geometry::new(l.into(), v.into(), Vec3::Z, Some(Vec3::X))
                    .filter(Geometry::both_above)
                    .map_or(Vec3::ZERO, |g| model.eval(&g));
                // A physical model is ≥ 0 and finite there; guard the table's invariant anyway.
                *o = if f.is_finite() { f.max(Vec3::ZERO) } else { Vec3::ZERO };
            }
        });
        Self::new(dims, half_data, data, None)
    }

    /// Multilinear look-up at table angles \[radians\] (any real `φ`s: they are reduced modulo 2π;
    /// `θ`s are held beyond the first and last bin centres).
    pub fn lookup(&self, theta_in: f32, theta_out: f32, phi_diff: f32, phi_in: f32) -> Vec3 {
        self.lookup_lanes(theta_in, theta_out, phi_diff.rem_euclid(TAU), phi_in.rem_euclid(TAU)).into()
    }

    /// [`AnisotropicTabulated::lookup`] on lanes, the one place it is written, for `φ`s in `[0, 2π)`:
    /// the 16 corners of each lane's cell are gathered from the table.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn lookup_lanes<F: Lane>(&self, theta_in: F, theta_out: F, phi_diff: F, phi_in: F) -> V3<F> {
        let (mut ti, mut to, mut pd, mut pi) = (theta_in, theta_out, phi_diff, phi_in);
        if self.half_data {
            // Reciprocity (module docs): φ_diff ≥ π is the exchanged configuration's 2π − φ_diff.
            let tau = F::splat(TAU);
            let swap = pd.ge(F::splat(PI));
            let pi2 = pi + pd;
            let pi2 = F::select(pi2.ge(tau), pi2 - tau, pi2);
            (ti, to) = (F::select(swap, theta_out, theta_in), F::select(swap, theta_in, theta_out));
            pd = F::select(swap, tau - pd, pd);
            pi = F::select(swap, pi2, pi);
        }
        let d = self.dims;
        let a = [
            axis(ti, FRAC_PI_2, d[0], false),
            axis(to, FRAC_PI_2, d[1], false),
            axis(pd, self.phi_diff_range(), d[2], !self.half_data),
            axis(pi, TAU, d[3], true),
        ];
        let one = F::splat(1.0);
        let ws =
            [[one - a[0].f, a[0].f], [one - a[1].f, a[1].f], [one - a[2].f, a[2].f], [one - a[3].f, a[3].f]];
        // Per axis and lane, the flat offsets of the lower and upper bins (φ_in fastest).
        let strides = [d[1] * d[2] * d[3], d[2] * d[3], d[3], 1];
        let mut off = [[[0usize; 8]; 2]; 4];
        for (k, x) in a.iter().enumerate() {
            for (b, bins) in [&x.i0, &x.i1].into_iter().enumerate() {
                for (o, &i) in off[k][b].iter_mut().zip(bins).take(F::LANES) {
                    *o = i * strides[k];
                }
            }
        }
        // The 16 corners, θ_in's bit most significant; each weight is ((w0·w1)·w2)·w3.
        let mut acc = V3::splat(Vec3::ZERO);
        let mut idx = [0usize; 8];
        for b0 in 0..2 {
            for b1 in 0..2 {
                let w01 = ws[0][b0] * ws[1][b1];
                for b2 in 0..2 {
                    let w012 = w01 * ws[2][b2];
                    for b3 in 0..2 {
                        let weight = w012 * ws[3][b3];
                        for (lane, slot) in idx.iter_mut().enumerate().take(F::LANES) {
                            *slot = off[0][b0][lane] + off[1][b1][lane] + off[2][b2][lane] + off[3][b3][lane];
                        }
                        acc = acc + V3::from_fn(|lane| self.data[idx[lane]]).scale(weight);
                    }
                }
            }
        }
        acc
    }

    /// `f(l, v)` by multilinear interpolation, in the frame of `g` (its tangent, else the arbitrary
    /// frame of its normal); 0 unless both directions are above the surface.
    pub fn eval(&self, g: &Geometry) -> Vec3 {
        self.eval_lanes(&LaneGeometry::from(g)).into()
    }

    /// [`AnisotropicTabulated::eval`] on lanes.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn eval_lanes<F: Lane>(&self, g: &LaneGeometry<F>) -> V3<F> {
        let frame = LaneFrame::of(g);
        let (ti, to, pd, pi) = aniso_angles_lanes(frame.to_local(g.l), frame.to_local(g.v));
        V3::select(g.both_above(), self.lookup_lanes(ti, to, pd, pi), V3::splat(Vec3::ZERO))
    }
}

/// The table angles `(θ_in, θ_out, φ_diff, φ_in)` of local directions (`z` = normal, `x` = tangent;
/// module docs): `θ = atan2(|w_⊥|, w_z)` (accurate near the normal, where `acos` of a float32 cosine
/// is not), `φ_in = atan2(−l_y, −l_x)` and `φ_diff = atan2(−v_y, −v_x) − φ_in`, both in `[0, 2π)`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
pub fn aniso_angles_lanes<F: Lane>(l: V3<F>, v: V3<F>) -> (F, F, F, F) {
    // −x as x·(−1): the same bits in every lane type (DEVELOPERS.md).
    let minus = F::splat(-1.0);
    let phi_in = wrap_tau((l.y * minus).atan2(l.x * minus));
    let phi_out = wrap_tau((v.y * minus).atan2(v.x * minus));
    (polar(l), polar(v), wrap_tau(phi_out - phi_in), phi_in)
}

/// The polar angle of a local unit vector, `atan2(|w_⊥|, w_z)`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn polar<F: Lane>(w: V3<F>) -> F {
    (w.x * w.x + w.y * w.y).sqrt().atan2(w.z)
}

/// An angle in `(−2π, 4π)` (a difference of two in `[0, 2π)`, or an `atan2`) moved into `[0, 2π)`.
#[cfg_attr(debug_assertions, inline)]
#[cfg_attr(not(debug_assertions), inline(always))]
fn wrap_tau<F: Lane>(p: F) -> F {
    let tau = F::splat(TAU);
    let p = F::select(p.lt(F::splat(0.0)), p + tau, p);
    F::select(p.ge(tau), p - tau, p)
}

/// An [`AnisotropicTabulated`] table as a [`Model`] (`Model::MeasuredAnisotropic`): it renders and
/// evaluates in batches like any model, in the frame of the tangent it is given. Shared, not copied,
/// between clones.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredAnisotropic(pub Arc<AnisotropicTabulated>);

impl Bxdf for MeasuredAnisotropic {
    const SPEC: ModelSpec = ModelSpec {
        name: "measured_anisotropic",
        summary: "tabulated anisotropic BRDF over (θ_in, θ_out, φ_diff, φ_in) in the tangent frame, multilinear look-up",
        source: "A. Ngan, F. Durand, W. Matusik, Experimental Analysis of BRDF Models, EGSR (2005) (the MIT CSAIL data); B. Burley, BRDF Explorer, Disney (2012) (the file layout)",
        physical: true,
        anisotropic: true,
        params: &[],
    };
    const KIND: ModelKind = ModelKind::Physical;

    /// Cosine-weighted directions (the table has no sampler of its own).
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::Cosine, 1.0))
    }

    /// Not buildable from parameters: built from its table.
    fn from_params(_: &Params) -> Result<Self, BrdfError> {
        Err(BrdfError::InvalidInput {
            name: "name",
            problem: "\"measured_anisotropic\" is built from a table (brdfpy.measured.AnisotropicTabulated.as_model()), not by name".to_string(),
        })
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        self.0.eval_lanes(g)
    }
}

impl From<AnisotropicTabulated> for Model {
    fn from(t: AnisotropicTabulated) -> Self {
        Model::MeasuredAnisotropic(MeasuredAnisotropic(Arc::new(t)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measured::Tabulated;
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

    fn ward() -> Model {
        Model::build(
            "ward",
            &[
                ("alpha_x".into(), Input::Number(0.25)),
                ("alpha_y".into(), Input::Number(0.5)),
                ("kd".into(), Input::Number(0.2)),
                ("ks".into(), Input::Number(0.3)),
            ],
        )
        .unwrap()
    }

    /// Deterministic local directions over the hemisphere up to `max_deg` (a Fibonacci spiral).
    fn hemisphere(count: usize, max_deg: f32) -> Vec<Vec3> {
        let zmin = max_deg.to_radians().cos();
        (0..count)
            .map(|i| {
                let z = 1.0 - (1.0 - zmin) * (i as f32 + 0.5) / count as f32;
                let phi = i as f32 * 2.399_963 + 0.3;
                let s = (1.0 - z * z).sqrt();
                Vec3::new(s * phi.cos(), s * phi.sin(), z)
            })
            .collect()
    }

    fn pairs() -> Vec<(Vec3, Vec3)> {
        let d = hemisphere(150, 75.0);
        let mut out = Vec::new();
        for (a, &l) in d.iter().enumerate() {
            for &v in d.iter().skip(a % 5).step_by(5) {
                out.push((l, v));
            }
        }
        out
    }

    fn geom(l: Vec3, v: Vec3) -> Geometry {
        Geometry::new(l, v, Vec3::Z, Some(Vec3::X)).unwrap()
    }

    /// Relative RMS error of `f` against `model` over [`pairs`].
    fn rel_rms(model: &Model, f: impl Fn(&Geometry) -> Vec3) -> f64 {
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for (l, v) in pairs() {
            let g = geom(l, v);
            let (m, e) = (model.eval(&g), f(&g));
            num += f64::from((m - e).length_squared());
            den += f64::from(m.length_squared());
        }
        (num / den).sqrt()
    }

    #[test]
    fn angles_invert_directions_and_follow_the_explorer_signs() {
        for &(ti, to, pd, pi) in
            &[(0.3f32, 1.1f32, 0.4f32, 5.9f32), (1.2, 0.2, 4.0, 0.1), (0.7, 0.7, 3.0, 3.3)]
        {
            let (l, v) = AnisotropicTabulated::directions(ti, to, pd, pi);
            let (a, b, c, d) = aniso_angles_lanes::<f32>(l.into(), v.into());
            for (x, y) in [(a, ti), (b, to), (c, pd), (d, pi)] {
                assert!((x - y).abs() < 2e-5, "{x} {y}");
            }
        }
        // The Explorer's φ_in is the azimuth of −l: a light along +x (toward the tangent) has φ_in = π,
        // along +y (the bitangent) 3π/2.
        let v = V3::<f32>::splat(Vec3::Z);
        let (_, _, _, p) = aniso_angles_lanes::<f32>(V3::splat(Vec3::new(1.0, 0.0, 1.0).normalize()), v);
        assert!((p - PI).abs() < 1e-6, "{p}");
        let (_, _, _, p) = aniso_angles_lanes::<f32>(V3::splat(Vec3::new(0.0, 1.0, 1.0).normalize()), v);
        assert!((p - 1.5 * PI).abs() < 1e-6, "{p}");
    }

    #[test]
    fn lookup_at_a_bin_centre_returns_the_bin_and_interpolates_linearly_between() {
        let t = AnisotropicTabulated::from_model(&ward(), [6, 5, 8, 12], false).unwrap();
        for b in [[2, 3, 5, 7], [0, 0, 0, 0], [5, 4, 7, 11]] {
            let [a, c, d, e] = t.bin_angles(b);
            let got = t.lookup(a, c, d, e);
            let want = t.data()[t.index(b)];
            assert!((got - want).abs().max_element() <= 1e-5 * (1.0 + want.max_element()), "{got} {want}");
        }
        // Halfway between the centres of φ_in bins 11 and 0 (the wrap).
        let [a, c, d, _] = t.bin_angles([2, 3, 5, 0]);
        let got = t.lookup(a, c, d, 0.0);
        let want = 0.5 * (t.data()[t.index([2, 3, 5, 11])] + t.data()[t.index([2, 3, 5, 0])]);
        assert!((got - want).abs().max_element() <= 1e-5 * (1.0 + want.max_element()), "{got} {want}");
    }

    #[test]
    fn a_table_of_an_isotropic_model_agrees_with_the_model_and_the_isotropic_table() {
        let m = ct();
        let aniso = AnisotropicTabulated::from_model(&m, [32, 32, 64, 8], false).unwrap();
        let iso = Tabulated::from_model(&m, (32, 32, 64)).unwrap();
        let e_aniso = rel_rms(&m, |g| aniso.eval(g));
        let e_iso = rel_rms(&m, |g| iso.eval(g));
        eprintln!(
            "relative RMS error against Cook-Torrance: 4-D table 32x32x64x8 {e_aniso:.4}, MERL-layout 32x32x64 {e_iso:.4}"
        );
        // Measured: 0.0038 (4-D, 524 k cells) against 0.0022 (the half/difference grid, 65 k cells).
        assert!(e_aniso < 0.005 && e_iso < e_aniso, "{e_aniso} {e_iso}");
    }

    #[test]
    fn a_table_of_an_anisotropic_model_converges_at_second_order() {
        let m = ward();
        let errs: Vec<f64> = [6usize, 12, 24]
            .iter()
            .map(|&n| {
                let t = AnisotropicTabulated::from_model(&m, [n, n, 4 * n, 4 * n], false).unwrap();
                rel_rms(&m, |g| t.eval(g))
            })
            .collect();
        eprintln!("relative RMS error of the 4-D table of Ward (0.25, 0.5) at n = 6, 12, 24: {errs:?}");
        // Measured: 0.071, 0.0175, 0.0045 (ratios 4.0, 3.9).
        for w in errs.windows(2) {
            assert!(w[0] / w[1] > 3.0, "errors {errs:?}");
        }
    }

    #[test]
    fn a_table_of_a_reciprocal_model_is_reciprocal_and_the_half_table_agrees() {
        let m = ward();
        let full = AnisotropicTabulated::from_model(&m, [16, 16, 64, 64], false).unwrap();
        let half = AnisotropicTabulated::from_model(&m, [16, 16, 32, 64], true).unwrap();
        let (mut worst, mut worst_half) = (0.0f32, 0.0f32);
        for (l, v) in pairs() {
            let g = geom(l, v);
            let (a, b) = (full.eval(&g), full.eval(&g.swapped()));
            worst = worst.max((a - b).abs().max_element() / a.max_element().max(1e-3));
            let h = half.eval(&g);
            worst_half = worst_half.max((h - a).abs().max_element() / a.max_element().max(1e-3));
            // A half table reads the same cells for (l, v) and (v, l), up to the rounding of the angles.
            let (x, y) = (half.eval(&g), half.eval(&g.swapped()));
            assert!((x - y).abs().max_element() <= 1e-4 * (1e-2 + x.max_element()), "{x} {y}");
        }
        eprintln!(
            "reciprocity of the full 4-D table of Ward: worst relative difference {worst:.2e}; half against full {worst_half:.3}"
        );
        // Measured: 1.8e-2 (l and v are binned asymmetrically: exchanging them reads other cells) and
        // 0.022 between the half and the full table.
        assert!(worst < 0.03, "{worst}");
        assert!(worst_half < 0.04, "{worst_half}");
    }

    #[test]
    fn cells_without_data_hold_zero_and_are_interpolated_as_zero() {
        let dims = [2, 2, 2, 2];
        let data: Vec<Vec3> = (0..16).map(|i| Vec3::splat(1.0 + i as f32)).collect();
        let mut valid = vec![true; 16];
        valid[0] = false;
        let t = AnisotropicTabulated::new(dims, false, data.clone(), Some(valid)).unwrap();
        assert_eq!(t.data()[0], Vec3::ZERO);
        assert!((t.coverage() - 15.0 / 16.0).abs() < 1e-12);
        // At the centre of bin 0 (no data) about 0; halfway to bin 1 along φ_in half of bin 1.
        let [a, b, c, d] = t.bin_angles([0, 0, 0, 0]);
        assert!(t.lookup(a, b, c, d).max_element() < 1e-4, "{}", t.lookup(a, b, c, d));
        let got = t.lookup(a, b, c, d + PI / 2.0);
        assert!((got - 0.5 * data[1]).abs().max_element() < 1e-4, "{got}");
        let e = AnisotropicTabulated::new(dims, false, vec![Vec3::ONE; 15], None).unwrap_err().to_string();
        assert!(e.starts_with("values") && e.contains("got 15"), "{e}");
        let e = AnisotropicTabulated::new([0, 2, 2, 2], false, vec![], None).unwrap_err().to_string();
        assert!(e.starts_with("dims") && e.contains("theta_in"), "{e}");
        let e =
            AnisotropicTabulated::new([4096, 4096, 4096, 4096], false, vec![], None).unwrap_err().to_string();
        assert!(e.contains("exceed"), "{e}");
        let mut bad = data;
        bad[3].y = f32::NAN;
        let e = AnisotropicTabulated::new(dims, false, bad, None).unwrap_err().to_string();
        assert!(e.contains("cell 3"), "{e}");
    }

    #[test]
    fn the_table_as_a_model_evaluates_as_the_table_one_by_one_and_in_batches() {
        use crate::batch::{Directions, Quantity, evaluate};
        let t = AnisotropicTabulated::from_model(&ward(), [8, 8, 16, 16], false).unwrap();
        let model = Model::from(t.clone());
        assert_eq!(model.spec().name, "measured_anisotropic");
        assert!(model.spec().anisotropic && model.spec().physical);
        let (ls, vs): (Vec<Vec3>, Vec<Vec3>) = pairs().into_iter().take(203).unzip();
        let (n, tan) = ([Vec3::Z], [Vec3::X]);
        let (dirs, len) = Directions::new(&ls, &vs, &n, Some(&tan)).unwrap();
        let mut out = vec![Vec3::ZERO; len];
        evaluate(&model, &dirs, Quantity::Brdf, &mut out);
        for ((&l, &v), &o) in ls.iter().zip(&vs).zip(&out) {
            let g = geom(l, v);
            assert_eq!(o.to_array().map(f32::to_bits), t.eval(&g).to_array().map(f32::to_bits));
            assert_eq!(model.eval(&g), t.eval(&g));
        }
        let below = Geometry::new(Vec3::new(0.3, 0.1, -0.5), Vec3::Z, Vec3::Z, Some(Vec3::X)).unwrap();
        assert_eq!(model.eval(&below), Vec3::ZERO);
        // The tangent turns the table: a frame turned by 90° reads other cells.
        let (l, v) = (Vec3::new(0.5, 0.1, 0.8), Vec3::new(-0.4, 0.2, 0.9));
        let a = t.eval(&geom(l, v));
        let b = t.eval(&Geometry::new(l, v, Vec3::Z, Some(Vec3::Y)).unwrap());
        assert!((a - b).abs().max_element() > 1e-3 * a.max_element(), "{a} {b}");
    }
}
