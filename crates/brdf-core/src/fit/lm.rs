//! The damped least-squares solver of [`super`]: Levenberg–Marquardt (K. Levenberg 1944; D. W. Marquardt,
//! "An Algorithm for Least-Squares Estimation of Nonlinear Parameters", SIAM J. Appl. Math. 11(2), 1963)
//! with the damping scaled by `diag(JᵀJ)` (Marquardt's form: invariant to each parameter's unit), bounds
//! kept by projection with a fraction-to-the-boundary step (Nocedal & Wright, *Numerical Optimization*,
//! 2nd ed., §16.6), and a central-difference Jacobian computed column by column in parallel.

use rayon::prelude::*;

/// Why a run of [`solve`] stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// An accepted step lowered the cost by less than the tolerance (relative).
    SmallReduction,
    /// The residuals are zero (to 1e-30 in the cost): an exact fit.
    ZeroCost,
    /// No damped step lowers the cost: a minimum (within the bounds) to the solver's resolution.
    NoDescent,
    /// The iteration limit was reached first.
    MaxIterations,
}

impl Stop {
    /// `true` for every reason but [`Stop::MaxIterations`].
    pub fn converged(self) -> bool {
        self != Stop::MaxIterations
    }

    /// The reason in words (the `message` of a fit report).
    pub fn message(self) -> &'static str {
        match self {
            Stop::SmallReduction => {
                "converged: the last accepted step lowered the cost by less than the tolerance"
            }
            Stop::ZeroCost => "converged: the residuals are zero (an exact fit)",
            Stop::NoDescent => {
                "converged: no damped step lowers the cost (a minimum within the parameter ranges)"
            }
            Stop::MaxIterations => "not converged: the iteration limit was reached",
        }
    }
}

/// What [`solve`] returns.
pub struct Outcome {
    /// The parameters at the end.
    pub p: Vec<f64>,
    /// `½ Σ r²` there.
    pub cost: f64,
    /// The residuals there.
    pub r: Vec<f64>,
    /// Iterations run (Jacobians computed).
    pub iterations: usize,
    /// Why it stopped.
    pub stop: Stop,
}

/// `½ Σ r²`.
pub fn cost(r: &[f64]) -> f64 {
    0.5 * r.iter().map(|x| x * x).sum::<f64>()
}

/// The finite-difference step of parameter `x` in `[lo, hi]`: relative to the value, floored by the range
/// so that a parameter at 0 still moves (the models evaluate in float32: too small a step is all noise).
fn fd_step(x: f64, lo: f64, hi: f64) -> f64 {
    1e-3 * x.abs().max(1e-2 * (hi - lo).min(100.0))
}

/// The Jacobian `∂r_i/∂p_j` by central differences (one-sided at a bound), as `k` columns of `m` rows;
/// the columns are computed in parallel (each is independent, so the bits do not depend on the thread
/// count). A column whose evaluation fails (the model refuses the values) is zero.
pub fn jacobian<R>(residuals: &R, p: &[f64], bounds: &[(f64, f64)], m: usize) -> Vec<Vec<f64>>
where
    R: Fn(&[f64]) -> Option<Vec<f64>> + Sync,
{
    (0..p.len())
        .into_par_iter()
        .map(|j| {
            let (lo, hi) = bounds[j];
            let h = fd_step(p[j], lo, hi);
            let (a, b) = ((p[j] - h).max(lo), (p[j] + h).min(hi));
            if b <= a {
                return vec![0.0; m];
            }
            let (mut pa, mut pb) = (p.to_vec(), p.to_vec());
            pa[j] = a;
            pb[j] = b;
            match (residuals(&pa), residuals(&pb)) {
                (Some(ra), Some(rb)) => ra.iter().zip(&rb).map(|(x, y)| (y - x) / (b - a)).collect(),
                _ => vec![0.0; m],
            }
        })
        .collect()
}

/// `JᵀJ` (k×k, row-major) and `Jᵀr` from the columns of `J`; each entry is one sequential dot product
/// (the entries in parallel), so the bits do not depend on the thread count.
pub fn normal_equations(jac: &[Vec<f64>], r: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let k = jac.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let pairs: Vec<(usize, usize)> = (0..k).flat_map(|a| (a..k).map(move |b| (a, b))).collect();
    let vals: Vec<f64> = pairs.par_iter().map(|&(a, b)| dot(&jac[a], &jac[b])).collect();
    let mut jtj = vec![0.0; k * k];
    for (&(a, b), v) in pairs.iter().zip(vals) {
        jtj[a * k + b] = v;
        jtj[b * k + a] = v;
    }
    let jtr = jac.par_iter().map(|c| dot(c, r)).collect();
    (jtj, jtr)
}

/// Solve `a x = b` (k×k, row-major) by Gaussian elimination with partial pivoting; `None` if singular.
pub fn linear_solve(mut a: Vec<f64>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let k = b.len();
    let scale = (0..k).map(|i| a[i * k + i].abs()).fold(0.0, f64::max).max(1e-300);
    for col in 0..k {
        let piv = (col..k).max_by(|&i, &j| a[i * k + col].abs().total_cmp(&a[j * k + col].abs()))?;
        if a[piv * k + col].abs() <= 1e-14 * scale {
            return None;
        }
        if piv != col {
            for c in 0..k {
                a.swap(piv * k + c, col * k + c);
            }
            b.swap(piv, col);
        }
        for row in col + 1..k {
            let f = a[row * k + col] / a[col * k + col];
            for c in col..k {
                a[row * k + c] -= f * a[col * k + c];
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = vec![0.0; k];
    for row in (0..k).rev() {
        let s: f64 = (row + 1..k).map(|c| a[row * k + c] * x[c]).sum();
        x[row] = (b[row] - s) / a[row * k + row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// `p + α·δ` inside `bounds`. A component already at a bound and pushed outward is held (the active
/// set); otherwise the step is shortened so that no component goes more than 90 % of its way to its
/// bound (fraction to the boundary). Clamping the full step instead lets one overshooting step throw e.g.
/// a roughness onto 0, where the lobe vanishes from every sample and the gradient with it. A component
/// pushed outward with less than `1e-6` of its range left goes onto its bound instead of limiting the
/// step: otherwise a value that has crept to within a hair of its bound shrinks every later step to that
/// hair and the solver stops on a small reduction far from the minimum. A component left within `1e-9`
/// of the range from its bound is put on it.
fn bounded_step(p: &[f64], delta: &[f64], bounds: &[(f64, f64)]) -> Vec<f64> {
    // `Some(bound)`: the component goes onto that bound whatever α is.
    let onto: Vec<Option<f64>> = p
        .iter()
        .zip(delta)
        .zip(bounds)
        .map(|((x, dj), &(lo, hi))| {
            let (room, bound) = if *dj < 0.0 { (x - lo, lo) } else { (hi - x, hi) };
            (*dj != 0.0 && room <= 1e-6 * (hi - lo)).then_some(bound)
        })
        .collect();
    let mut alpha: f64 = 1.0;
    for (((x, dj), (lo, hi)), onto) in p.iter().zip(delta).zip(bounds).zip(&onto) {
        let room = if *dj < 0.0 { x - lo } else { hi - x };
        if onto.is_none() && dj.abs() > room {
            alpha = alpha.min(0.9 * room / dj.abs());
        }
    }
    p.iter()
        .zip(delta)
        .zip(bounds)
        .zip(&onto)
        .map(|(((x, dj), &(lo, hi)), onto)| {
            if let Some(b) = onto {
                return *b;
            }
            let y = (x + alpha * dj).clamp(lo, hi);
            let snap = 1e-9 * (hi - lo);
            if y - lo < snap {
                lo
            } else if hi - y < snap {
                hi
            } else {
                y
            }
        })
        .collect()
}

/// Minimise `½ Σ r(p)²` over `p` inside `bounds` from `p0` (which must give residuals `r0`); `jac(p, r)`
/// gives the Jacobian's columns at `p` (see [`jacobian`]).
#[allow(clippy::too_many_arguments)]
pub fn solve<R, J>(
    residuals: &R,
    jac: &J,
    p0: Vec<f64>,
    r0: Vec<f64>,
    bounds: &[(f64, f64)],
    max_iterations: usize,
    tolerance: f64,
) -> Outcome
where
    R: Fn(&[f64]) -> Option<Vec<f64>> + Sync,
    J: Fn(&[f64]) -> Vec<Vec<f64>>,
{
    let (mut p, mut r) = (p0, r0);
    let mut c = cost(&r);
    let k = p.len();
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let stop = loop {
        if c < 1e-30 {
            break Stop::ZeroCost;
        }
        if iterations >= max_iterations {
            break Stop::MaxIterations;
        }
        iterations += 1;
        let columns = jac(&p);
        let (jtj, jtr) = normal_equations(&columns, &r);
        let mut accepted = None;
        while lambda < 1e12 {
            let mut a = jtj.clone();
            for d in 0..k {
                a[d * k + d] += lambda * jtj[d * k + d].max(1e-12);
            }
            let Some(delta) = linear_solve(a, jtr.iter().map(|x| -x).collect()) else {
                lambda *= 10.0;
                continue;
            };
            let trial = bounded_step(&p, &delta, bounds);
            match residuals(&trial) {
                Some(rt) if cost(&rt) < c => {
                    accepted = Some((trial, rt));
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        let Some((trial, rt)) = accepted else { break Stop::NoDescent };
        let ct = cost(&rt);
        let gain = (c - ct) / c.max(1e-300);
        p = trial;
        r = rt;
        c = ct;
        lambda = (lambda / 3.0).max(1e-12);
        if gain < tolerance {
            break Stop::SmallReduction;
        }
    };
    Outcome { p, cost: c, r, iterations, stop }
}
