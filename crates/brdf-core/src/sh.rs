//! Real spherical harmonics: basis, projection by an exact quadrature, reconstruction (R. Ramamoorthi,
//! P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps", SIGGRAPH 2001; P.-P.
//! Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008): filtering and illumination–BRDF
//! integration as products of coefficients.
//!
//! ## Convention
//! Orthonormal real harmonics, `∫_{S²} Y_i Y_j dω = δ_ij`, **without** the Condon–Shortley phase
//! `(−1)^m`, as in Ramamoorthi & Hanrahan (2001, "An Efficient Representation for Irradiance
//! Environment Maps"), whose table gives `Y_{1,−1} = 0.488603·y`, `Y_{1,0} = 0.488603·z`,
//! `Y_{1,1} = 0.488603·x`. (Sloan's "Stupid Spherical Harmonics Tricks" includes the phase, which
//! flips the sign of the odd-`m` functions; a coefficient vector converts by negating those.)
//!
//! `Y_{l,0} = P̄_l^0(cos θ)`, `Y_{l,m} = √2 P̄_l^m(cos θ) cos(mφ)`, `Y_{l,−m} = √2 P̄_l^m(cos θ) sin(mφ)`
//! for `m > 0`, with `P̄_l^m = sqrt((2l+1)/(4π) · (l−m)!/(l+m)!) P_l^m` computed by the normalised
//! three-term recurrence (stable to high order, no factorials). Coefficient `(l, m)` is at index
//! `l(l+1) + m`; order `L` has `(L+1)²` coefficients. Directions are in the frame of the caller (for
//! BRDF lobes, the surface frame with `n = +z`).
//!
//! ## Quadrature
//! [`Quadrature`] is a Gauss–Legendre rule in `μ = cos θ` on each hemisphere separately (`[−1, 0]` and
//! `[0, 1]`) times a uniform rule in `φ`. With `n` nodes per hemisphere and `n_φ` azimuths it integrates
//! exactly every `P(μ)·trig(φ)` with `P` of degree ≤ `2n − 1` on each hemisphere and frequencies
//! `< n_φ`: products of harmonics of order ≤ `L` when `n ≥ L + 1`, `n_φ ≥ 2L + 1`, and also functions
//! that are such polynomials on each hemisphere separately with a kink at the horizon — the clamped
//! cosine, and every `f_r · max(n·l, 0)` lobe, is zero below the surface.

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use crate::BrdfError;

/// Highest supported order `L` (`(L+1)²` = 10 201 coefficients).
pub const MAX_ORDER: usize = 100;

/// Number of coefficients of order `L`: `(L+1)²`.
pub const fn num_coeffs(order: usize) -> usize {
    (order + 1) * (order + 1)
}

/// Index of coefficient `(l, m)`, `|m| ≤ l`: `l(l+1) + m`.
pub const fn index(l: usize, m: isize) -> usize {
    ((l * (l + 1)) as isize + m) as usize
}

fn check_order(order: usize) -> Result<(), BrdfError> {
    if order > MAX_ORDER {
        return Err(BrdfError::InvalidInput {
            name: "order",
            problem: format!("must be in [0, {MAX_ORDER}], got {order}"),
        });
    }
    Ok(())
}

/// Write `Y_i(dir)` for every `i < (order+1)²` into `out[..(order+1)²]`. `dir` need not be unit; a
/// zero-length or non-finite direction gives all zeros.
///
/// # Panics
/// If `out` is shorter than `(order+1)²` (a caller bug; the public batch functions size it).
pub fn basis_into(dir: DVec3, order: usize, out: &mut [f64]) {
    let out = &mut out[..num_coeffs(order)];
    let len = dir.length();
    if !(len > 0.0 && len.is_finite()) {
        out.fill(0.0);
        return;
    }
    let d = dir / len;
    let z = d.z.clamp(-1.0, 1.0);
    let s = (d.x * d.x + d.y * d.y).sqrt();
    let phi = d.y.atan2(d.x);
    let (s1, c1) = phi.sin_cos();
    // p_mm = P̄_m^m(z), carried from m − 1 to m.
    let mut p_mm = (1.0 / (4.0 * PI)).sqrt();
    let (mut cm, mut sm) = (1.0, 0.0); // cos(mφ), sin(mφ)
    for m in 0..=order {
        if m > 0 {
            let mf = m as f64;
            p_mm *= s * ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (cm, sm) = (cm * c1 - sm * s1, sm * c1 + cm * s1);
        }
        let mut write = |l: usize, p: f64| {
            if m == 0 {
                out[index(l, 0)] = p;
            } else {
                out[index(l, m as isize)] = std::f64::consts::SQRT_2 * p * cm;
                out[index(l, -(m as isize))] = std::f64::consts::SQRT_2 * p * sm;
            }
        };
        write(m, p_mm);
        if m == order {
            break;
        }
        let mf = m as f64;
        let mut p_lm2 = p_mm;
        let mut p_lm1 = z * (2.0 * mf + 3.0).sqrt() * p_mm;
        write(m + 1, p_lm1);
        for l in m + 2..=order {
            let lf = l as f64;
            let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
            let b = (((lf - 1.0) * (lf - 1.0) - mf * mf) / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0)).sqrt();
            let p = a * (z * p_lm1 - b * p_lm2);
            write(l, p);
            (p_lm2, p_lm1) = (p_lm1, p);
        }
    }
}

/// `Y_i(dir)` for every `i < (order+1)²` (see [`basis_into`]).
pub fn basis(dir: DVec3, order: usize) -> Result<Vec<f64>, BrdfError> {
    check_order(order)?;
    let mut out = vec![0.0; num_coeffs(order)];
    basis_into(dir, order, &mut out);
    Ok(out)
}

/// `Y_i(dirs[k])` into row `k` of `out` (`(order+1)²` values per row, C order), rows in parallel on the
/// current rayon pool (each row depends only on its direction, so any thread count gives the same bits).
pub fn basis_rows(dirs: &[DVec3], order: usize, out: &mut [f64]) -> Result<(), BrdfError> {
    check_order(order)?;
    let nc = num_coeffs(order);
    if out.len() != dirs.len() * nc {
        return Err(BrdfError::InvalidInput {
            name: "out",
            problem: format!("has {} values, expected {} rows of {nc}", out.len(), dirs.len()),
        });
    }
    out.par_chunks_mut(nc)
        .zip(dirs.par_iter())
        .with_min_len(1024)
        .for_each(|(row, d)| basis_into(*d, order, row));
    Ok(())
}

/// Gauss–Legendre nodes and weights on `[−1, 1]` (`n` nodes, exact for polynomials of degree
/// ≤ `2n − 1`), by Newton's method on `P_n` from the Tricomi initial guesses.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        let mut t = (PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(t) and P_n'(t) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, t);
            for k in 2..=n {
                let kf = k as f64;
                (p0, p1) = (p1, ((2.0 * kf - 1.0) * t * p1 - (kf - 1.0) * p0) / kf);
            }
            let p = if n == 1 { t } else { p1 };
            let pm1 = if n == 1 { 1.0 } else { p0 };
            dp = nf * (t * p - pm1) / (t * t - 1.0);
            let step = p / dp;
            t -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        x[i] = -t;
        x[n - 1 - i] = t;
        let wi = 2.0 / ((1.0 - t * t) * dp * dp);
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    (x, w)
}

/// Nodes and weights on the unit sphere (see the module docs for what it integrates exactly).
#[derive(Debug, Clone, PartialEq)]
pub struct Quadrature {
    /// Unit directions.
    pub dirs: Vec<DVec3>,
    /// Weights (steradians); they sum to 4π.
    pub weights: Vec<f64>,
}

impl Quadrature {
    /// `n_mu` Gauss–Legendre nodes in `cos θ` on each hemisphere (`2·n_mu` in all) times `n_phi`
    /// uniform azimuths `φ_k = (k + ½)·2π/n_phi`.
    pub fn new(n_mu: usize, n_phi: usize) -> Result<Self, BrdfError> {
        for (name, n) in [("n_mu", n_mu), ("n_phi", n_phi)] {
            if !(1..=4096).contains(&n) {
                return Err(BrdfError::InvalidInput {
                    name,
                    problem: format!("must be in [1, 4096], got {n}"),
                });
            }
        }
        let (x, w) = gauss_legendre(n_mu);
        let dphi = 2.0 * PI / n_phi as f64;
        let mut dirs = Vec::with_capacity(2 * n_mu * n_phi);
        let mut weights = Vec::with_capacity(2 * n_mu * n_phi);
        for sign in [-1.0, 1.0] {
            for (xi, wi) in x.iter().zip(&w) {
                // [−1, 1] → [0, 1] or [−1, 0]: μ = (x ± 1)/2, weight halves.
                let mu = 0.5 * (xi + sign);
                let s = (1.0 - mu * mu).max(0.0).sqrt();
                for k in 0..n_phi {
                    let phi = (k as f64 + 0.5) * dphi;
                    dirs.push(DVec3::new(s * phi.cos(), s * phi.sin(), mu));
                    weights.push(0.5 * wi * dphi);
                }
            }
        }
        Ok(Self { dirs, weights })
    }

    /// The smallest rule of [`Quadrature::new`] that integrates products of two functions of order
    /// ≤ `order` exactly: `n_mu = order + 1`, `n_phi = 2·order + 1`.
    pub fn for_order(order: usize) -> Result<Self, BrdfError> {
        check_order(order)?;
        Self::new(order + 1, 2 * order + 1)
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.dirs.len()
    }

    /// `true` when the rule has no nodes (only possible for one assembled by hand from its fields).
    pub fn is_empty(&self) -> bool {
        self.dirs.is_empty()
    }
}

/// Project RGB values `values[k] = f(quad.dirs[k])` onto the harmonics of order ≤ `order`:
/// `c_i = Σ_k w_k f(ω_k) Y_i(ω_k)`, exact when `f·Y_i` is within the rule's exactness.
pub fn project_values(values: &[DVec3], quad: &Quadrature, order: usize) -> Result<Vec<DVec3>, BrdfError> {
    check_order(order)?;
    if values.len() != quad.len() {
        return Err(BrdfError::InvalidInput {
            name: "values",
            problem: format!("expected one value per quadrature node ({}), got {}", quad.len(), values.len()),
        });
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(BrdfError::InvalidInput {
            name: "values",
            problem: format!("must be finite; row {i} is {}", values[i]),
        });
    }
    let nc = num_coeffs(order);
    let chunk = 256;
    // Partial sums per fixed chunk of nodes, then added in chunk order: rayon's `reduce` would add
    // them in a tree shaped by how the work was split, whose rounding depends on the thread count.
    let partials: Vec<Vec<DVec3>> = values
        .par_chunks(chunk)
        .enumerate()
        .map(|(ci, vals)| {
            let mut acc = vec![DVec3::ZERO; nc];
            let mut y = vec![0.0; nc];
            for (j, f) in vals.iter().enumerate() {
                let k = ci * chunk + j;
                basis_into(quad.dirs[k], order, &mut y);
                let fw = *f * quad.weights[k];
                for (a, yi) in acc.iter_mut().zip(&y) {
                    *a += fw * *yi;
                }
            }
            acc
        })
        .collect();
    let mut coeffs = vec![DVec3::ZERO; nc];
    for p in &partials {
        for (x, y) in coeffs.iter_mut().zip(p) {
            *x += *y;
        }
    }
    Ok(coeffs)
}

/// Project `f` (called once per node, in parallel) onto the harmonics of order ≤ `order`.
pub fn project(
    f: impl Fn(DVec3) -> DVec3 + Sync,
    quad: &Quadrature,
    order: usize,
) -> Result<Vec<DVec3>, BrdfError> {
    let values: Vec<DVec3> = quad.dirs.par_iter().map(|d| f(*d)).collect();
    project_values(&values, quad, order)
}

/// The order `L` of a coefficient vector of length `(L+1)²`.
pub fn order_of(len: usize) -> Result<usize, BrdfError> {
    let l = (len as f64).sqrt().round() as usize;
    if l == 0 || l * l != len || l - 1 > MAX_ORDER {
        return Err(BrdfError::InvalidInput {
            name: "coeffs",
            problem: format!("length must be (L+1)^2 for an order L in [0, {MAX_ORDER}], got {len}"),
        });
    }
    Ok(l - 1)
}

/// `Σ_i c_i Y_i(dir)` at each direction (in parallel).
pub fn reconstruct(coeffs: &[DVec3], dirs: &[DVec3]) -> Result<Vec<DVec3>, BrdfError> {
    let order = order_of(coeffs.len())?;
    Ok(dirs
        .par_iter()
        .map_init(
            || vec![0.0; coeffs.len()],
            |y, d| {
                basis_into(*d, order, y);
                coeffs.iter().zip(y.iter()).map(|(c, yi)| *c * *yi).sum()
            },
        )
        .collect())
}

/// Zonal coefficients `Â_l = sqrt(4π/(2l+1))·A_l` of the clamped cosine `max(cos θ, 0) = Σ A_l Y_{l,0}`
/// in closed form (Ramamoorthi & Hanrahan 2001, eq. 9): `Â_0 = π`, `Â_1 = 2π/3`, 0 for odd `l > 1`,
/// `2π (−1)^{l/2−1} / ((l+2)(l−1)) · l! / (2^l ((l/2)!)²)` for even `l ≥ 2`. The convolution of a
/// function with the clamped cosine (irradiance from radiance) multiplies its band-`l` coefficients by
/// `Â_l`.
pub fn clamped_cosine_zonal(l: usize) -> f64 {
    match l {
        0 => PI,
        1 => 2.0 * PI / 3.0,
        _ if l % 2 == 1 => 0.0,
        _ => {
            // l! / (2^l (l/2)!²) = C(l, l/2) / 2^l, built as a product to stay in range; past 2^10
            // terms, its asymptotic series C(2h, h)/4^h = (1 − 1/8h + 1/128h² + 5/1024h³ − …)/√(πh)
            // (exact to < 10⁻¹³ there), so that any l costs O(1) (l = 2^63 looped for ever).
            let h = l / 2;
            let ratio: f64 = if h <= 1024 {
                (1..=h).map(|k| (h + k) as f64 / (4.0 * k as f64)).product()
            } else {
                let x = 1.0 / h as f64;
                (1.0 - x / 8.0 + x * x / 128.0 + 5.0 * x * x * x / 1024.0) / (PI * h as f64).sqrt()
            };
            let sign = if h % 2 == 1 { 1.0 } else { -1.0 };
            2.0 * PI * sign / ((l as f64 + 2.0) * (l as f64 - 1.0)) * ratio
        }
    }
}

/// Convolution with a kernel `k(ω·n)` that is symmetric about an axis (Funk–Hecke theorem):
/// `∫ f(ω) k(ω·n) dω = Σ_lm Â_l c_lm Y_lm(n)` with `Â_l = 2π ∫_{−1}^{1} k(t) P_l(t) dt`, so band `l` is
/// scaled by `kernel[l] = Â_l`. With `kernel[l] = clamped_cosine_zonal(l)` this turns radiance into
/// irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω` (Ramamoorthi & Hanrahan 2001): illumination–BRDF
/// integration done as a product of coefficients.
pub fn convolve_zonal(coeffs: &[DVec3], kernel: &[f64]) -> Result<Vec<DVec3>, BrdfError> {
    let order = order_of(coeffs.len())?;
    if kernel.len() != order + 1 {
        return Err(BrdfError::InvalidInput {
            name: "kernel",
            problem: format!("expected one value per band ({}), got {}", order + 1, kernel.len()),
        });
    }
    if let Some(i) = kernel.iter().position(|k| !k.is_finite()) {
        return Err(BrdfError::InvalidInput { name: "kernel", problem: format!("value {i} is not finite") });
    }
    Ok((0..=order)
        .flat_map(|l| (0..2 * l + 1).map(move |j| (l, l * l + j)))
        .map(|(l, i)| coeffs[i] * kernel[l])
        .collect())
}

/// Irradiance coefficients from radiance coefficients: [`convolve_zonal`] with the clamped cosine.
pub fn irradiance(radiance: &[DVec3]) -> Result<Vec<DVec3>, BrdfError> {
    let order = order_of(radiance.len())?;
    let kernel: Vec<f64> = (0..=order).map(clamped_cosine_zonal).collect();
    convolve_zonal(radiance, &kernel)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Geometry, Model};
    use glam::Vec3;

    #[test]
    fn gauss_legendre_integrates_polynomials_to_degree_2n_minus_1() {
        for n in [1, 2, 5, 12, 33] {
            let (x, w) = gauss_legendre(n);
            for deg in 0..2 * n {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                let want = if deg % 2 == 1 { 0.0 } else { 2.0 / (deg as f64 + 1.0) };
                assert!((got - want).abs() < 1e-13, "n {n} deg {deg}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn basis_is_orthonormal_under_the_quadrature() {
        let order = 12;
        let q = Quadrature::for_order(order).unwrap();
        let nc = num_coeffs(order);
        let mut gram = vec![0.0; nc * nc];
        let mut y = vec![0.0; nc];
        for (d, w) in q.dirs.iter().zip(&q.weights) {
            basis_into(*d, order, &mut y);
            for i in 0..nc {
                for j in 0..nc {
                    gram[i * nc + j] += w * y[i] * y[j];
                }
            }
        }
        let worst = (0..nc * nc)
            .map(|k| (gram[k] - if k / nc == k % nc { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "max |G - I| = {worst:e}");
        assert!((q.weights.iter().sum::<f64>() - 4.0 * PI).abs() < 1e-12);
    }

    #[test]
    fn first_bands_match_ramamoorthi_hanrahans_table() {
        let d = DVec3::new(0.3, -0.5, 0.7).normalize();
        let y = basis(d, 2).unwrap();
        let c1 = (3.0 / (4.0 * PI)).sqrt();
        let want = [
            (1.0 / (4.0 * PI)).sqrt(),
            c1 * d.y,
            c1 * d.z,
            c1 * d.x,
            0.5 * (15.0 / PI).sqrt() * d.x * d.y,
            0.5 * (15.0 / PI).sqrt() * d.y * d.z,
            0.25 * (5.0 / PI).sqrt() * (3.0 * d.z * d.z - 1.0),
            0.5 * (15.0 / PI).sqrt() * d.x * d.z,
            0.25 * (15.0 / PI).sqrt() * (d.x * d.x - d.y * d.y),
        ];
        for (i, (a, b)) in y.iter().zip(want).enumerate() {
            assert!((a - b).abs() < 1e-14, "Y[{i}] = {a}, expected {b}");
        }
    }

    /// Legendre polynomial by its recurrence (independent of the basis code).
    fn legendre(l: usize, x: f64) -> f64 {
        let (mut p0, mut p1) = (1.0, x);
        if l == 0 {
            return 1.0;
        }
        for k in 2..=l {
            let k = k as f64;
            (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
        }
        p1
    }

    #[test]
    fn addition_theorem_holds_to_high_order() {
        // Σ_m Y_lm(a) Y_lm(b) = (2l+1)/(4π) P_l(a·b): checks normalisation and the m ≠ 0 terms together.
        let (a, b) = (DVec3::new(0.2, 0.9, -0.3).normalize(), DVec3::new(-0.7, 0.1, 0.6).normalize());
        let order = 60;
        let (ya, yb) = (basis(a, order).unwrap(), basis(b, order).unwrap());
        for l in 0..=order {
            let s: f64 = (-(l as isize)..=l as isize).map(|m| ya[index(l, m)] * yb[index(l, m)]).sum();
            let want = (2.0 * l as f64 + 1.0) / (4.0 * PI) * legendre(l, a.dot(b));
            assert!((s - want).abs() < 1e-11, "l {l}: {s} vs {want}");
        }
    }

    #[test]
    fn clamped_cosine_projects_onto_ramamoorthi_hanrahans_coefficients() {
        // The hemisphere-split rule is exact for max(μ, 0)·P_l(μ): recompute Â_l by projection and compare
        // with the closed form (Â_0 = π, Â_1 = 2π/3, Â_2 = π/4, Â_4 = −π/24, odd l > 1 vanish).
        let order = 10;
        let q = Quadrature::for_order(order).unwrap();
        let c = project(|d| DVec3::splat(d.z.max(0.0)), &q, order).unwrap();
        for l in 0..=order {
            let got = (4.0 * PI / (2.0 * l as f64 + 1.0)).sqrt() * c[index(l, 0)].x;
            assert!(
                (got - clamped_cosine_zonal(l)).abs() < 1e-13,
                "l {l}: {got} vs {}",
                clamped_cosine_zonal(l)
            );
            for m in 1..=l as isize {
                assert!(c[index(l, m)].x.abs() < 1e-13 && c[index(l, -m)].x.abs() < 1e-13);
            }
        }
        assert!((clamped_cosine_zonal(2) - PI / 4.0).abs() < 1e-15);
        assert!((clamped_cosine_zonal(4) + PI / 24.0).abs() < 1e-15);
    }

    /// Relative L2 error on the sphere of the order-`order` projection of `f`, measured on a finer rule.
    fn projection_error(f: &(impl Fn(DVec3) -> DVec3 + Sync), order: usize) -> f64 {
        let fine = Quadrature::new(100, 200).unwrap();
        let c = project(f, &fine, order).unwrap();
        let rec = reconstruct(&c, &fine.dirs).unwrap();
        let (mut num, mut den) = (0.0, 0.0);
        for ((d, w), r) in fine.dirs.iter().zip(&fine.weights).zip(&rec) {
            let v = f(*d);
            num += w * (v - *r).length_squared();
            den += w * v.length_squared();
        }
        (num / den).sqrt()
    }

    #[test]
    fn brdf_lobe_times_cosine_converges_as_the_order_grows() {
        let m = Model::build("cook_torrance", &[("roughness".into(), crate::Input::Number(0.4))]).unwrap();
        let v = Vec3::new(0.5, 0.0, 0.866);
        let f = |d: DVec3| {
            let g = Geometry::new(d.as_vec3(), v, Vec3::Z, None);
            g.map_or(DVec3::ZERO, |g| m.shade(&g).as_dvec3())
        };
        let errs: Vec<f64> = [1, 2, 4, 8, 16].iter().map(|&l| projection_error(&f, l)).collect();
        eprintln!("relative L2 error of f_r cos at L = 1, 2, 4, 8, 16: {errs:?}");
        // Parseval: the projection error can only fall as bands are added. The lobe has a kink at the
        // horizon, so the decay is algebraic, not spectral.
        for w in errs.windows(2) {
            assert!(w[1] < w[0], "{errs:?}");
        }
        // Measured: 0.58, 0.33, 0.098, 0.024, 0.0095.
        assert!(errs[4] < 0.02, "{errs:?}");
    }

    #[test]
    fn irradiance_from_coefficients_equals_the_cosine_weighted_integral() {
        // A band-limited radiance (order 6); E(n) = ∫ L(ω) max(n·ω, 0) dω by a direct quadrature in the
        // frame of n (the hemisphere-split rule about n is exact for this integrand) against the
        // reconstruction of the convolved coefficients. Beyond band 2 the clamped cosine's coefficients are
        // small but not zero, so the comparison uses every band.
        let order = 6;
        let radiance: Vec<DVec3> = (0..num_coeffs(order))
            .map(|i| DVec3::new(((i * 7 % 11) as f64 - 5.0) / 7.0, 0.1 * i as f64, (i as f64).sin()))
            .collect();
        let e = irradiance(&radiance).unwrap();
        let q = Quadrature::for_order(order + 1).unwrap();
        for n in [DVec3::Z, DVec3::new(0.3, -0.8, 0.2).normalize(), -DVec3::X] {
            let frame = crate::ShadingFrame::from_normal(n.as_vec3a());
            let dirs: Vec<DVec3> = q.dirs.iter().map(|d| frame.from_local(d.as_vec3a()).as_dvec3()).collect();
            let l = reconstruct(&radiance, &dirs).unwrap();
            let direct: DVec3 =
                l.iter().zip(&q.dirs).zip(&q.weights).map(|((li, d), w)| *li * (w * d.z.max(0.0))).sum();
            let via_sh = reconstruct(&e, &[n]).unwrap()[0];
            // 1e-5, not 1e-13: the rotated nodes pass through the f32 shading frame.
            assert!((direct - via_sh).abs().max_element() < 1e-5, "n {n}: {direct} vs {via_sh}");
        }
        // A constant radiance 1 gives E = π everywhere.
        let mut one = vec![DVec3::ZERO; 4];
        one[0] = DVec3::splat((4.0 * PI).sqrt());
        let e1 = reconstruct(&irradiance(&one).unwrap(), &[DVec3::new(0.2, 0.5, -0.4)]).unwrap()[0];
        assert!((e1 - DVec3::splat(PI)).abs().max_element() < 1e-12);
        assert!(convolve_zonal(&one, &[1.0]).unwrap_err().to_string().contains("kernel"));
    }

    #[test]
    fn bad_inputs_are_refused() {
        assert!(basis(DVec3::Z, MAX_ORDER + 1).unwrap_err().to_string().contains("order"));
        assert_eq!(basis(DVec3::ZERO, 2).unwrap(), vec![0.0; 9]);
        let q = Quadrature::for_order(2).unwrap();
        let e = project_values(&[DVec3::ONE; 3], &q, 2).unwrap_err().to_string();
        assert!(e.contains("one value per quadrature node"), "{e}");
        let mut vals = vec![DVec3::ONE; q.len()];
        vals[4].y = f64::NAN;
        assert!(project_values(&vals, &q, 2).unwrap_err().to_string().contains("row 4"));
        assert!(reconstruct(&[DVec3::ONE; 5], &[DVec3::Z]).unwrap_err().to_string().contains("(L+1)^2"));
        assert!(Quadrature::new(0, 3).unwrap_err().to_string().contains("n_mu"));
    }

    #[test]
    fn projection_gives_the_same_bits_at_any_thread_count() {
        let q = Quadrature::new(64, 129).unwrap();
        let values: Vec<DVec3> =
            q.dirs.iter().map(|d| DVec3::new(1.0 + d.x * d.y, (3.0 * d.z).sin().abs(), d.x.exp())).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| project_values(&values, &q, 4).unwrap())
        };
        let one = run(1);
        for threads in [2, 3, 8] {
            let other = run(threads);
            assert!(
                one.iter()
                    .zip(&other)
                    .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn the_irradiance_of_a_linear_gradient_sky_is_its_analytic_value() {
        // L(ω) = a + b·(ω·z) ≥ 0 for a ≥ b: E(n) = ∫ L max(n·ω, 0) dω = π a + (2π/3) b (n·z), since
        // ∫ (ω·z) max(n·ω, 0) dω = (2π/3) n·z. Order 2 holds it exactly (a band-1 function).
        let (a, b) = (1.0, 0.6);
        let q = Quadrature::for_order(2).unwrap();
        let coeffs = project(|d| DVec3::splat(a + b * d.z), &q, 2).unwrap();
        let e = irradiance(&coeffs).unwrap();
        for n in [DVec3::Z, -DVec3::Z, DVec3::X, DVec3::new(0.3, -0.5, 0.8).normalize()] {
            let got = reconstruct(&e, &[n]).unwrap()[0];
            let want = PI * a + 2.0 * PI / 3.0 * b * n.z;
            assert!((got - DVec3::splat(want)).abs().max_element() < 1e-12, "n {n}: {got} vs {want}");
        }
    }
}
