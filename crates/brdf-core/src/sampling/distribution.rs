//! Piecewise-constant distributions on `[0, 1)` and `[0, 1)²` (pbrt-v4 §A.4.1 `PiecewiseConstant1D`,
//! §A.4.2 `PiecewiseConstant2D`): tabulate a non-negative function on a regular grid, sample it by
//! inverting its CDF, and report the density of any point. The measured-BRDF sampler
//! ([`super::tabulated`]) uses them per view-angle slice, and an environment map's luminance (times
//! `sin θ` for an equirectangular image) is sampled with a [`Distribution2D`] the same way.
//!
//! Densities are with respect to the unit interval / unit square: a cell of value `f_i` has density
//! `f_i / ∫f` where `∫f = Σ f_i / n` (cells of zero value are never sampled). A function that is 0
//! everywhere gives the uniform distribution (density 1), so a sampler built on it still covers its
//! domain. Sums are accumulated in `f64`; the results are deterministic.

use crate::BrdfError;
use crate::simd::Lane;

/// A piecewise-constant density on `[0, 1)` with `n` equal cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution1D {
    func: Vec<f32>,
    /// `cdf[i] = Σ_{j<i} f_j / Σ f`, `cdf[n] = 1`.
    cdf: Vec<f32>,
    /// `Σ f_i / n` (0: uniform).
    integral: f64,
}

impl Distribution1D {
    /// From cell values `func` (non-empty, finite, ≥ 0; the error names `name`).
    pub fn new(name: &'static str, func: &[f32]) -> Result<Self, BrdfError> {
        if func.is_empty() {
            return Err(BrdfError::InvalidInput { name, problem: "is empty".into() });
        }
        if let Some(i) = func.iter().position(|f| !(f.is_finite() && *f >= 0.0)) {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("values must be finite and >= 0; entry {i} is {}", func[i]),
            });
        }
        let n = func.len();
        let total: f64 = func.iter().map(|&f| f64::from(f)).sum();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut acc = 0.0f64;
        for &f in func {
            cdf.push(if total > 0.0 { (acc / total) as f32 } else { (cdf.len() as f64 / n as f64) as f32 });
            acc += f64::from(f);
        }
        cdf.push(1.0);
        Ok(Self { func: func.to_vec(), cdf, integral: total / n as f64 })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Always `false` (a distribution has at least one cell).
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// `∫₀¹ f = Σ f_i / n` of the tabulated function.
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// The cell values.
    pub fn func(&self) -> &[f32] {
        &self.func
    }

    /// Density [1 per unit length] of cell `i`.
    #[inline]
    fn density(&self, i: usize) -> f32 {
        if self.integral > 0.0 { (f64::from(self.func[i]) / self.integral) as f32 } else { 1.0 }
    }

    /// A point `x ∈ [0, 1)` from `u ∈ [0, 1)`, with its density and cell: the cell is the last `i` with
    /// `cdf[i] ≤ u` (so cells of value 0 are skipped), `x` is linear in `u` within it.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let n = self.func.len();
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        let i = self.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(n - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let du = if width > 0.0 { ((u - self.cdf[i]) / width).clamp(0.0, 1.0) } else { 0.0 };
        // (i + du)/n may round into the next cell (du → 1): step down to the largest x of cell i, so
        // that `pdf(x)` is the density of the cell that was sampled.
        let mut x = ((i as f32 + du) / n as f32).min(1.0 - f32::EPSILON / 2.0);
        while self.cell(x) > i && x > 0.0 {
            x = f32::from_bits(x.to_bits() - 1);
        }
        (x, self.density(i), i)
    }

    /// Density of the point `x` (clamped into `[0, 1)`).
    #[inline]
    pub fn pdf(&self, x: f32) -> f32 {
        self.density(self.cell(x))
    }

    /// The cell holding `x` (clamped into `[0, 1)`; NaN → 0).
    #[inline]
    pub fn cell(&self, x: f32) -> usize {
        let n = self.func.len();
        let c = x * n as f32;
        if c >= 0.0 { (c as usize).min(n - 1) } else { 0 }
    }
}

/// A piecewise-constant density on `[0, 1)²` with `nu × nv` cells: a marginal distribution over rows
/// (`y`) and one conditional distribution over columns (`x`) per row.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// From `func` in row-major order, `nv` rows of `nu` values (`func[y·nu + x]`).
    pub fn new(name: &'static str, func: &[f32], nu: usize, nv: usize) -> Result<Self, BrdfError> {
        if nu == 0 || nv == 0 || func.len() != nu * nv {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("expected {nv} rows of {nu} values (> 0), got {} values", func.len()),
            });
        }
        let conditional =
            func.chunks_exact(nu).map(|row| Distribution1D::new(name, row)).collect::<Result<Vec<_>, _>>()?;
        let rows: Vec<f32> = conditional.iter().map(|c| c.integral() as f32).collect();
        let marginal = Distribution1D::new(name, &rows)?;
        Ok(Self { conditional, marginal })
    }

    /// `(nu, nv)`: columns, rows.
    pub fn dims(&self) -> (usize, usize) {
        (self.conditional[0].len(), self.conditional.len())
    }

    /// `∫∫ f` over the unit square.
    pub fn integral(&self) -> f64 {
        self.marginal.integral()
    }

    /// A point `(x, y) ∈ [0, 1)²` from `(u0, u1)` (u1 picks the row), and its density.
    #[inline]
    pub fn sample(&self, u0: f32, u1: f32) -> ([f32; 2], f32) {
        let (y, py, row) = self.marginal.sample(u1);
        let (x, px, _) = self.conditional[row].sample(u0);
        ([x, y], px * py)
    }

    /// Density of the point `p` (clamped into the unit square).
    #[inline]
    pub fn pdf(&self, p: [f32; 2]) -> f32 {
        let row = self.marginal.cell(p[1]);
        self.conditional[row].pdf(p[0]) * self.marginal.pdf(p[1])
    }

    /// [`Distribution2D::sample`] on lanes (each lane as one scalar sample: same bits).
    #[inline]
    pub fn sample_lanes<F: Lane>(&self, u0: F, u1: F) -> (F, F, F) {
        let mut out = [[0.0f32; 3]; 16];
        for (i, o) in out.iter_mut().enumerate().take(F::LANES) {
            let ([x, y], p) = self.sample(u0.lane(i), u1.lane(i));
            *o = [x, y, p];
        }
        (F::from_fn(|i| out[i][0]), F::from_fn(|i| out[i][1]), F::from_fn(|i| out[i][2]))
    }

    /// [`Distribution2D::pdf`] on lanes.
    #[inline]
    pub fn pdf_lanes<F: Lane>(&self, x: F, y: F) -> F {
        F::from_fn(|i| self.pdf([x.lane(i), y.lane(i)]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_dimensional_sampling_inverts_the_cdf_and_skips_empty_cells() {
        let d = Distribution1D::new("f", &[1.0, 0.0, 3.0, 0.0]).unwrap();
        assert_eq!(d.integral(), 1.0);
        // Cell 0 holds u in [0, 0.25), cell 2 holds [0.25, 1); cells 1 and 3 are never chosen.
        let (x, p, i) = d.sample(0.125);
        assert_eq!((i, p), (0, 1.0));
        assert!((x - 0.125).abs() < 1e-7);
        let (x, p, i) = d.sample(0.25);
        assert_eq!((i, p), (2, 3.0));
        assert!((x - 0.5).abs() < 1e-7);
        let (x, _, i) = d.sample(1.0 - 2f32.powi(-24));
        assert_eq!(i, 2);
        assert!(x < 0.75 && d.pdf(x) == 3.0);
        assert_eq!(d.pdf(0.3), 0.0);
        let zero = Distribution1D::new("f", &[0.0; 5]).unwrap();
        assert_eq!(zero.sample(0.5).1, 1.0);
        assert!(Distribution1D::new("f", &[]).is_err());
        let e = Distribution1D::new("f", &[1.0, f32::NAN]).unwrap_err().to_string();
        assert!(e.starts_with("f") && e.contains("entry 1"), "{e}");
    }

    #[test]
    fn two_dimensional_density_is_the_normalised_cell_value_and_matches_the_samples() {
        let (nu, nv) = (5, 3);
        let func: Vec<f32> = (0..nu * nv).map(|k| ((k * 7) % 5) as f32).collect();
        let d = Distribution2D::new("env", &func, nu, nv).unwrap();
        let total: f32 = func.iter().sum::<f32>() / (nu * nv) as f32;
        let mut counts = vec![0u32; nu * nv];
        let m = 100_000;
        for k in 0..m {
            let u = super::super::rng::uniform3(3, k);
            let ([x, y], p) = d.sample(u[0], u[1]);
            let cell = (y * nv as f32) as usize * nu + (x * nu as f32) as usize;
            assert!((p - func[cell] / total).abs() < 1e-5 * p, "{p} vs {}", func[cell] / total);
            assert_eq!(p, d.pdf([x, y]));
            counts[cell] += 1;
        }
        for (c, &f) in counts.iter().zip(&func) {
            let expected = f64::from(f / total) / (nu * nv) as f64 * m as f64;
            assert!((f64::from(*c) - expected).abs() <= 5.0 * expected.sqrt() + 1e-9, "{c} vs {expected}");
        }
    }
}
