//! Pearson's χ² goodness-of-fit test of a sampler against the density it claims, in the style of
//! Mitsuba 3's `mi.chi2` (Jakob et al., `ChiSquareTest`; the test itself: K. Pearson 1900; the
//! pooling rule for small expected counts: W. G. Cochran 1954, "Some Methods for Strengthening the
//! Common χ² Tests").
//!
//! 1. Draw `N` samples and count the valid ones (`pdf > 0`) in the cells of a grid over the sphere of
//!    directions ([`Chi2Grid`]): the observed counts `Oᵢ`.
//! 2. Integrate the claimed density over every cell by Gauss–Legendre quadrature: the expected
//!    counts `Eᵢ = N ∫_cell p dω`.
//! 3. Sort the cells by `Eᵢ`; cells with `Eᵢ ≥ 5` each add `(Oᵢ − Eᵢ)²/Eᵢ` to the statistic, the others
//!    are pooled (in increasing `Eᵢ`) into groups of `ΣE ≥ 5` that add one term each. The degrees of
//!    freedom are the number of terms minus 1, and the p-value is the χ² tail probability
//!    `Q(dof/2, χ²/2)` (regularised upper incomplete gamma function).
//!
//! A p-value is the probability that a correct sampler gives a statistic at least this large: a
//! correct sampler passes a test at significance α with probability 1 − α (p is uniform on [0, 1]
//! for it), a sampler whose density is off by more than the statistical noise of `N` samples fails.
//! Samples in a cell whose expected count is exactly 0 fail the test outright.
//!
//! ## The grid
//! The upper hemisphere around the normal, in `y = 1 − cos θ` (computed from the tangent-plane
//! components, so it is accurate near the pole) and `φ` (from the tangent), each graded toward the
//! peak of the lobe under test (default: the mirror direction of `v`): with cell edges at uniform
//! `s, t ∈ [0, 1]` on either side of the peak (so that the peak is a cell edge),
//!
//! ```text
//! y = g(s; y_peak, zoom),   φ = φ_peak − π + 2π g(t; ½, zoom),
//! g(s; c, k) = c − c ((c − s)/c)ᵏ for s < c,   c + (1 − c)((s − c)/(1 − c))ᵏ for s ≥ c,
//! ```
//!
//! so `zoom = 1` is Mitsuba's grid, uniform in `cos θ` and `φ` (equal solid angle per cell), and
//! `zoom = k > 1` packs cells toward the peak (the `k`-th power of the distance), which resolves lobes
//! down to roughness ~1e-3. The horizon is a cell boundary, so a density's jump there never falls
//! inside a cell; directions at or below the horizon go to one extra cell whose expected count is 0.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3, Vec3A};

use super::Sampler;
use super::batch::{PdfBatch, SampleBatch};
use crate::frame::ShadingFrame;
use crate::properties::gauss_legendre;
use crate::{BrdfError, Model};

/// Expected count below which cells are pooled (Cochran's rule of thumb; Mitsuba's threshold).
pub const POOL_THRESHOLD: f64 = 5.0;

/// One axis of the grid: `n` cells over `x ∈ [0, 1]` with edges at `x = g(s)`, `s` uniform on each
/// side of the peak `c` (`n_lo` cells below it, the rest above), so that `c` is a cell edge and the
/// warp is a polynomial within every cell (Gauss–Legendre then integrates its Jacobian exactly).
#[derive(Debug, Clone, Copy)]
struct Axis {
    c: f64,
    k: f64,
    n: usize,
    n_lo: usize,
}

impl Axis {
    fn new(c: f64, k: f64, n: usize) -> Self {
        let c = c.clamp(0.0, 1.0);
        let mut n_lo = (c * n as f64).round() as usize;
        if n >= 2 {
            // Both sides of an interior peak get at least one cell.
            if c > 0.0 {
                n_lo = n_lo.max(1);
            }
            if c < 1.0 {
                n_lo = n_lo.min(n - 1);
            }
        }
        Self { c, k, n, n_lo: n_lo.min(n) }
    }

    /// `s` of the cell coordinate `σ ∈ [0, n]`, and `ds/dσ`.
    fn s_of(&self, sigma: f64) -> (f64, f64) {
        let (c, n_lo, n_hi) = (self.c, self.n_lo as f64, (self.n - self.n_lo) as f64);
        if sigma < n_lo || n_hi == 0.0 {
            (c * sigma / n_lo, c / n_lo)
        } else {
            (c + (1.0 - c) * (sigma - n_lo) / n_hi, (1.0 - c) / n_hi)
        }
    }

    /// `x` at the cell coordinate `σ`, and `dx/dσ`.
    fn at(&self, sigma: f64) -> (f64, f64) {
        let (s, ds) = self.s_of(sigma);
        let (x, dx) = warp(s, self.c, self.k);
        (x, dx * ds)
    }

    /// The cell holding `x`.
    fn cell(&self, x: f64) -> usize {
        let s = unwarp(x.clamp(0.0, 1.0), self.c, self.k);
        let (c, n_lo, n_hi) = (self.c, self.n_lo as f64, (self.n - self.n_lo) as f64);
        let sigma = if s < c && n_lo > 0.0 { s / c * n_lo } else { n_lo + (s - c) / (1.0 - c) * n_hi };
        (sigma.max(0.0) as usize).min(self.n - 1)
    }
}

/// `g(s; c, k)` of the module docs and its derivative.
#[inline]
fn warp(s: f64, c: f64, k: f64) -> (f64, f64) {
    if s < c {
        let r = (c - s) / c;
        (c - c * r.powf(k), k * r.powf(k - 1.0))
    } else if c < 1.0 {
        let r = (s - c) / (1.0 - c);
        (c + (1.0 - c) * r.powf(k), k * r.powf(k - 1.0))
    } else {
        (1.0, 0.0)
    }
}

/// The inverse of [`warp`].
#[inline]
fn unwarp(x: f64, c: f64, k: f64) -> f64 {
    if x < c {
        c - c * ((c - x) / c).powf(1.0 / k)
    } else if c < 1.0 {
        c + (1.0 - c) * ((x - c) / (1.0 - c)).clamp(0.0, 1.0).powf(1.0 / k)
    } else {
        1.0
    }
}

/// `1 − cos θ` of a unit local direction, from its tangent-plane part (no cancellation near the pole).
#[inline]
fn deficit(w: DVec3) -> f64 {
    let s2 = w.x * w.x + w.y * w.y;
    if w.z > 0.0 { s2 / (1.0 + w.z) } else { 1.0 - w.z }
}

/// The cells of a χ² test (module docs): `rows × cols` over the upper hemisphere, graded toward a peak,
/// plus one cell for everything at or below the horizon (the last index).
#[derive(Debug, Clone)]
pub struct Chi2Grid {
    frame: ShadingFrame,
    phi_peak: f64,
    rows: usize,
    cols: usize,
    /// `y = 1 − cos θ`.
    y: Axis,
    /// `(φ − φ_peak + π)/2π`.
    phi: Axis,
}

impl Chi2Grid {
    /// The grid around normal `n` (with `tangent`, the frame of evaluation), graded toward `peak` (a
    /// world direction; one at or below the horizon grades toward the horizon at its azimuth).
    /// `rows, cols ≥ 1`, `zoom ≥ 1`.
    pub fn new(
        n: Vec3,
        tangent: Option<Vec3>,
        peak: Vec3,
        rows: usize,
        cols: usize,
        zoom: f64,
    ) -> Result<Self, BrdfError> {
        let bad = |name: &'static str, problem: String| Err(BrdfError::InvalidInput { name, problem });
        if !(1..=4096).contains(&rows) {
            return bad("n_theta", format!("must be in [1, 4096], got {rows}"));
        }
        if !(1..=8192).contains(&cols) {
            return bad("n_phi", format!("must be in [1, 8192], got {cols}"));
        }
        if !(zoom.is_finite() && (1.0..=16.0).contains(&zoom)) {
            return bad("zoom", format!("must be in [1, 16], got {zoom}"));
        }
        let n = crate::vector::normalize_or_zero(n.into());
        if n == Vec3A::ZERO {
            return bad("n", "must be a finite, non-zero vector".into());
        }
        let frame = match tangent.map(|t| crate::vector::normalize_or_zero(t.into())) {
            Some(t) if t != Vec3A::ZERO => ShadingFrame::from_normal_tangent(n, t),
            _ => ShadingFrame::from_normal(n),
        };
        let p = crate::vector::normalize_or_zero(peak.into());
        if p == Vec3A::ZERO {
            return bad("peak", "must be a finite, non-zero vector".into());
        }
        let pl = frame.to_local(p).as_dvec3();
        Ok(Self {
            frame,
            phi_peak: pl.y.atan2(pl.x),
            rows,
            cols,
            y: Axis::new(deficit(pl).min(1.0), zoom, rows),
            phi: Axis::new(0.5, zoom, cols),
        })
    }

    /// Number of cells, the below-horizon cell included.
    pub fn cells(&self) -> usize {
        self.rows * self.cols + 1
    }

    /// The cell of a world direction (unit or not; a zero or non-finite one goes to the last cell).
    pub fn cell_of(&self, w: Vec3) -> usize {
        let below = self.rows * self.cols;
        let w = crate::vector::normalize_or_zero(w.into());
        if w == Vec3A::ZERO {
            return below;
        }
        let wl = self.frame.to_local(w).as_dvec3();
        if !(wl.z > 0.0) {
            return below;
        }
        let tau = ((wl.y.atan2(wl.x) - self.phi_peak + PI) / TAU).rem_euclid(1.0);
        self.y.cell(deficit(wl).min(1.0)) * self.cols + self.phi.cell(tau)
    }

    /// Counts per cell of the directions (`cells()` entries).
    pub fn histogram(&self, dirs: impl IntoIterator<Item = Vec3>) -> Vec<f64> {
        let mut h = vec![0.0; self.cells()];
        for w in dirs {
            h[self.cell_of(w)] += 1.0;
        }
        h
    }

    /// Quadrature points (world unit directions) and weights \[sr\] of every hemisphere cell, `ires²`
    /// Gauss–Legendre points per cell, cell by cell in index order.
    pub fn quadrature(&self, ires: usize) -> Result<(Vec<Vec3>, Vec<f64>), BrdfError> {
        if !(1..=16).contains(&ires) {
            return Err(BrdfError::InvalidInput {
                name: "ires",
                problem: format!("must be in [1, 16], got {ires}"),
            });
        }
        let gl = gauss_legendre(ires);
        let mut points = Vec::with_capacity(self.rows * self.cols * ires * ires);
        let mut weights = Vec::with_capacity(points.capacity());
        for i in 0..self.rows {
            for j in 0..self.cols {
                for &(a, wa) in &gl {
                    let (y, dy) = self.y.at(i as f64 + 0.5 + 0.5 * a);
                    let (cos, sin) = (1.0 - y, (y * (2.0 - y)).max(0.0).sqrt());
                    for &(b, wb) in &gl {
                        let (tau, dt) = self.phi.at(j as f64 + 0.5 + 0.5 * b);
                        let phi = self.phi_peak - PI + TAU * tau;
                        let local =
                            Vec3A::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
                        points.push(self.frame.from_local(local).into());
                        weights.push(0.25 * wa * wb * dy * TAU * dt);
                    }
                }
            }
        }
        Ok((points, weights))
    }

    /// Expected counts `N ∫_cell p dω` from the density at the [`Chi2Grid::quadrature`] points (the
    /// below-horizon cell gets 0).
    pub fn expected(&self, pdf: &[f32], weights: &[f64], count: f64) -> Vec<f64> {
        let per = weights.len() / (self.rows * self.cols).max(1);
        let mut e: Vec<f64> = pdf
            .chunks(per.max(1))
            .zip(weights.chunks(per.max(1)))
            .map(|(p, w)| count * p.iter().zip(w).map(|(&p, &w)| f64::from(p) * w).sum::<f64>())
            .collect();
        e.push(0.0);
        e
    }
}

/// The result of a χ² test.
#[derive(Debug, Clone, PartialEq)]
pub struct Chi2Report {
    /// Pearson's statistic.
    pub statistic: f64,
    /// Degrees of freedom (terms − 1).
    pub dof: usize,
    /// `Q(dof/2, statistic/2)`; 0 when the test failed outright (see `problems`).
    pub p_value: f64,
    /// Cells pooled, and the groups they formed.
    pub pooled: (usize, usize),
    /// Observed counts per cell.
    pub observed: Vec<f64>,
    /// Expected counts per cell.
    pub expected: Vec<f64>,
    /// `Σ observed / N`: the fraction of valid samples.
    pub sample_fraction: f64,
    /// `Σ expected / N`: the integral of the density over the hemisphere.
    pub pdf_integral: f64,
    /// Reasons the test failed outright (samples where nothing is expected, too few degrees of freedom,
    /// a density that is negative or integrates above 1.1).
    pub problems: Vec<String>,
}

/// Pearson's statistic with pooling of small cells (module docs): `(χ², dof, pooled cells, groups)`.
pub fn pearson(observed: &[f64], expected: &[f64], threshold: f64) -> (f64, usize, usize, usize) {
    let mut order: Vec<usize> = (0..expected.len().min(observed.len())).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]).then(a.cmp(&b)));
    let (mut stat, mut terms, mut pooled, mut groups) = (0.0, 0usize, 0usize, 0usize);
    let (mut po, mut pe) = (0.0, 0.0);
    for i in order {
        let (o, e) = (observed[i], expected[i]);
        if e >= threshold {
            stat += (o - e) * (o - e) / e;
            terms += 1;
        } else if o != 0.0 || e != 0.0 {
            po += o;
            pe += e;
            pooled += 1;
            if pe >= threshold {
                stat += (po - pe) * (po - pe) / pe;
                terms += 1;
                groups += 1;
                (po, pe) = (0.0, 0.0);
            }
        }
    }
    (stat, terms.saturating_sub(1), pooled, groups)
}

/// `ln Γ(x)` for `x > 0` (Lanczos approximation, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1 − x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, &g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)` (series for `x < a + 1`,
/// Lentz's continued fraction otherwise; Press et al., Numerical Recipes, §6.2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if !(a > 0.0) || x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefix = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * log_prefix.exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (log_prefix.exp() * h).clamp(0.0, 1.0)
    }
}

/// The χ² tail probability `P(X ≥ x)` for `dof` degrees of freedom.
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    if dof == 0 {
        return f64::NAN;
    }
    gamma_q(0.5 * dof as f64, 0.5 * x)
}

/// Compare observed with expected counts of `count` samples (module docs).
pub fn evaluate(observed: Vec<f64>, expected: Vec<f64>, count: f64) -> Chi2Report {
    let mut problems = Vec::new();
    let (statistic, dof, pooled_in, pooled_out) = pearson(&observed, &expected, POOL_THRESHOLD);
    let zero_cells = observed.iter().zip(&expected).filter(|&(&o, &e)| e == 0.0 && o > 0.0).count();
    if zero_cells > 0 {
        problems.push(format!("{zero_cells} cell(s) hold samples where the density integrates to 0"));
    }
    if expected.iter().any(|e| !(*e >= 0.0)) {
        problems.push("the density is negative or not finite somewhere".into());
    }
    let pdf_integral = expected.iter().sum::<f64>() / count;
    if pdf_integral > 1.1 {
        problems.push(format!("the density integrates to {pdf_integral:.4} > 1 over the hemisphere"));
    }
    if dof < 1 {
        problems.push("fewer than two terms: too few samples or cells".into());
    }
    let p_value = if problems.is_empty() { chi2_sf(statistic, dof) } else { 0.0 };
    let sample_fraction = observed.iter().sum::<f64>() / count;
    Chi2Report {
        statistic,
        dof,
        p_value,
        pooled: (pooled_in, pooled_out),
        observed,
        expected,
        sample_fraction,
        pdf_integral,
        problems,
    }
}

/// Settings of [`test_sampler`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chi2Options {
    /// Samples drawn.
    pub samples: usize,
    /// Seed of the random numbers ([`super::rng`]).
    pub seed: u64,
    /// Cells in θ.
    pub rows: usize,
    /// Cells in φ.
    pub cols: usize,
    /// Grading toward the peak (1 = uniform).
    pub zoom: f64,
    /// Gauss–Legendre points per cell and axis.
    pub ires: usize,
}

impl Default for Chi2Options {
    /// 10⁶ samples, 64 × 128 cells, uniform, 6 × 6 points per cell, seed 0.
    fn default() -> Self {
        Self { samples: 1_000_000, seed: 0, rows: 64, cols: 128, zoom: 1.0, ires: 6 }
    }
}

/// Test the directions `draw` produces for `model` against the density `claimed` reports, at view
/// `v`, normal `n`, optional tangent, with the grid graded toward `peak` (default: the mirror
/// direction of `v`). A correct sampler is tested with `draw` = `claimed` = `model.sampler()`.
#[allow(clippy::too_many_arguments)]
pub fn test_sampler(
    model: &Model,
    draw: &Sampler,
    claimed: &Sampler,
    v: Vec3,
    n: Vec3,
    tangent: Option<Vec3>,
    peak: Option<Vec3>,
    o: &Chi2Options,
) -> Result<Chi2Report, BrdfError> {
    let vn = crate::vector::normalize_or_zero(v.into());
    let nn = crate::vector::normalize_or_zero(n.into());
    let peak = peak.unwrap_or_else(|| crate::vector::reflect(vn, nn).into());
    let grid = Chi2Grid::new(n, tangent, peak, o.rows, o.cols, o.zoom)?;
    let (vs, ns, t) = ([v], [n], tangent.map(|t| [t]));
    let batch = SampleBatch::rows(&vs, &ns, t.as_ref().map(|t| &t[..]), None, o.seed, Some(o.samples))?;
    let (l, _, p) = batch.to_vec(model, draw)?;
    let observed = grid.histogram(l.iter().zip(&p).filter(|(_, p)| **p > 0.0).map(|(l, _)| *l));
    let (points, weights) = grid.quadrature(o.ires)?;
    let pdf = PdfBatch::rows(&points, &vs, &ns, t.as_ref().map(|t| &t[..]))?.to_vec(claimed)?;
    let expected = grid.expected(&pdf, &weights, o.samples as f64);
    Ok(evaluate(observed, expected, o.samples as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chi2_tail_matches_known_values() {
        // Reference values of the χ² survival function (e.g. NIST/SEMATECH e-Handbook table 1.3.6.7.4,
        // and for large dof the Wilson–Hilferty approximation to 1e-3).
        assert!((chi2_sf(3.841_458_82, 1) - 0.05).abs() < 1e-8);
        assert!((chi2_sf(9.210_340_37, 2) - 0.01).abs() < 1e-8);
        assert!((chi2_sf(18.307_038, 10) - 0.05).abs() < 1e-7);
        assert!((chi2_sf(124.342_113, 100) - 0.05).abs() < 1e-6);
        assert!((chi2_sf(0.0, 5) - 1.0).abs() < 1e-15);
        // dof = 8000 at the mean: the median is ≈ k(1 − 2/(9k))³ = k − 0.67, and the density there
        // ≈ 1/√(4πk), so P(X ≥ k) ≈ 0.5 − 0.67/√(4πk) = 0.4979.
        let p = chi2_sf(8000.0, 8000);
        assert!((p - 0.4979).abs() < 2e-4, "{p}");
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13 && (ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-13);
    }

    #[test]
    fn warp_and_unwarp_are_inverse_and_the_cells_cover_the_hemisphere() {
        for &(c, k) in &[(0.0, 1.0), (0.3, 3.0), (1.0, 4.0), (0.5, 2.0)] {
            for i in 0..=20 {
                let s = f64::from(i) / 20.0;
                let (x, _) = warp(s, c, k);
                assert!((unwarp(x, c, k) - s).abs() < 1e-9, "c={c} k={k} s={s}");
            }
        }
        let grid = Chi2Grid::new(Vec3::Z, None, Vec3::new(0.5, 0.2, 0.3), 16, 32, 3.0).unwrap();
        let (points, weights) = grid.quadrature(4).unwrap();
        // Σ weights = 2π (the hemisphere), and every point lies in the cell it was generated for.
        assert!((weights.iter().sum::<f64>() - TAU).abs() < 1e-9);
        for (k, p) in points.iter().enumerate() {
            assert_eq!(grid.cell_of(*p), k / 16);
        }
        assert_eq!(grid.cell_of(-Vec3::Z), grid.cells() - 1);
    }

    #[test]
    fn pooling_keeps_every_count_and_merges_small_cells() {
        let o = [10.0, 1.0, 0.0, 2.0, 3.0, 0.0];
        let e = [10.0, 1.0, 1.0, 2.0, 3.0, 0.0];
        let (stat, dof, pooled, groups) = pearson(&o, &e, 5.0);
        // 1 + 1 + 2 pool to E = 4 (< 5), + 3 → E = 7: one group (O = 6); the 10 stands alone.
        assert_eq!((pooled, groups, dof), (4, 1, 1));
        assert!((stat - 1.0 / 7.0).abs() < 1e-12, "{stat}");
    }
}
