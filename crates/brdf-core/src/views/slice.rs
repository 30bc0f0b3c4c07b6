//! The image slice over Rusinkiewicz's half/difference angles: `x = θ_h`, `y = θ_d`, at one `φ_d`
//! (Burley 2012 §3: "the image slice" of BRDF Explorer, which shows the specular peak along `θ_h = 0`,
//! Fresnel along `θ_d`, retro-reflection at `θ_d = 0`).

use std::f64::consts::{FRAC_PI_2, PI};

use glam::Vec3;

use super::{MAX_SAMPLES, check_angle, check_count, eval_rows, sanitize};
use crate::batch::Quantity;
use crate::rusinkiewicz::directions_from_half_diff_sin_cos;
use crate::{BrdfError, Model};

/// A θ_h/θ_d image.
#[derive(Debug, Clone, PartialEq)]
pub struct Slice {
    /// Columns: `θ_h` of column `j` is `(j + ½)/n_h · π/2`.
    pub n_h: usize,
    /// Rows: `θ_d` of row `i` is `(i + ½)/n_d · π/2` (row 0 at `θ_d ≈ 0`).
    pub n_d: usize,
    /// `f_r` \[1/sr\] per channel, row-major `[θ_d][θ_h]`.
    pub values: Vec<Vec3>,
    /// Where both `l` and `v` are above the surface (elsewhere physical models give 0 by convention, not
    /// because the material is dark).
    pub valid: Vec<bool>,
}

/// The cell-centre angles `(j + ½)/n · π/2` of an axis of `n` cells over `[0, π/2]`.
pub fn cell_angles(n: usize) -> Vec<f64> {
    (0..n).map(|j| (j as f64 + 0.5) / n as f64 * FRAC_PI_2).collect()
}

/// `f_r` at the half/difference angles of every cell of an `n_h × n_d` grid over `[0, π/2]²`, at
/// `phi_d` \[rad, in `[0, π]`\] (`n = +z`, `φ_h = 0`, tangent `+x`; the directions of
/// [`crate::rusinkiewicz::directions_from_half_diff`]). `n_h`, `n_d` in `[1, 4096]`.
pub fn half_diff_slice(model: &Model, phi_d: f64, n_h: usize, n_d: usize) -> Result<Slice, BrdfError> {
    check_angle("phi_d", phi_d, 0.0, PI)?;
    check_count("n_theta_h", n_h, 1, 4096)?;
    check_count("n_theta_d", n_d, 1, 4096)?;
    debug_assert!(n_h * n_d <= MAX_SAMPLES);
    let sc = |x: f64| {
        let (s, c) = (x as f32).sin_cos();
        (s, c)
    };
    let hs: Vec<(f32, f32)> = cell_angles(n_h).into_iter().map(sc).collect();
    let ds: Vec<(f32, f32)> = cell_angles(n_d).into_iter().map(sc).collect();
    let p = sc(phi_d);
    let (mut l, mut v) = (Vec::with_capacity(n_h * n_d), Vec::with_capacity(n_h * n_d));
    for &d in &ds {
        for &h in &hs {
            let (a, b) = directions_from_half_diff_sin_cos(h, d, p);
            l.push(Vec3::from(a));
            v.push(Vec3::from(b));
        }
    }
    let f = eval_rows(model, &l, &v, &[Vec3::Z], &[Vec3::X], Quantity::Brdf);
    let valid = l.iter().zip(&v).map(|(l, v)| l.z > 0.0 && v.z > 0.0).collect();
    Ok(Slice { n_h, n_d, values: f.into_iter().map(sanitize).collect(), valid })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rusinkiewicz::{directions_from_half_diff, half_diff_angles};
    use crate::{Geometry, Input};

    #[test]
    fn slice_cells_are_the_model_at_their_half_difference_angles() {
        let m = Model::build("cook_torrance", &[("roughness".into(), Input::Number(0.2))]).unwrap();
        let (n_h, n_d, phi_d) = (24, 16, 1.2);
        let s = half_diff_slice(&m, phi_d, n_h, n_d).unwrap();
        let (th, td) = (cell_angles(n_h), cell_angles(n_d));
        for i in (0..n_d).step_by(3) {
            for j in (0..n_h).step_by(5) {
                let (l, v) = directions_from_half_diff(th[j] as f32, td[i] as f32, phi_d as f32);
                let g = Geometry::new(l.into(), v.into(), Vec3::Z, Some(Vec3::X)).unwrap();
                assert_eq!(s.values[i * n_h + j], m.eval(&g));
                assert_eq!(s.valid[i * n_h + j], l.z > 0.0 && v.z > 0.0);
                if s.valid[i * n_h + j] {
                    let (a, b, _) = half_diff_angles(l, v, glam::Vec3A::Z).unwrap();
                    assert!((f64::from(a) - th[j]).abs() < 1e-5 && (f64::from(b) - td[i]).abs() < 1e-5);
                }
            }
        }
        // θ_h + θ_d beyond π/2 puts the light below the horizon at φ_d = 0 (the plane of h).
        let s0 = half_diff_slice(&m, 0.0, 8, 8).unwrap();
        assert!(!s0.valid[7 * 8 + 7] && s0.valid[0]);
        assert!(half_diff_slice(&m, 4.0, 8, 8).unwrap_err().to_string().contains("phi_d"));
        assert!(half_diff_slice(&m, 1.0, 0, 8).unwrap_err().to_string().contains("n_theta_h"));
    }
}
