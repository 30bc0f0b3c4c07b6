//! The directional albedo as a curve over the incidence angle: `E(θ_i) = ∫_{H²} f_r(l, v) cos θ_o dω_v`,
//! the fraction of the light arriving from `l` that is reflected (BRDF Explorer's albedo plot).
//!
//! The quadrature is brdf-core's graded Gauss–Legendre product rule ([`crate::properties`]), graded
//! toward the polar angle of `l` and toward its azimuth and the mirror azimuth, with every node of one
//! incidence evaluated in one lane batch. [`VIEW_QUADRATURE`] is coarser than the checks' default (4 × 4
//! points per panel, panels down to 1e-3 rad, about 1.4·10⁴ evaluations per angle) because a view
//! redraws interactively: it integrates white Lambert to 1e-6 and lobes down to ~2e-3 rad wide
//! (the tests compare it with the checks' finer rule).

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::{check_angle, eval_rows};
use crate::batch::Quantity;
use crate::properties::{Quadrature, hemisphere_rule};
use crate::{BrdfError, Model};

/// The quadrature of the views (see the module docs).
pub const VIEW_QUADRATURE: Quadrature = Quadrature { theta_order: 4, phi_order: 4, min_panel: 1e-3 };

/// Which direction the integral runs over; the other one is fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Over {
    /// `∫ f_r(l, v) cos θ_v dω_v` with `l` fixed: `E(θ_i)`, what the albedo curve plots.
    Viewer,
    /// `∫ f_r(l, v) cos θ_l dω_l` with `v` fixed: `ρ(v)`, the reflectance seen from `v` under a uniform
    /// white sky (equal to `E` for reciprocal models; what the lit sphere's sky term uses).
    Light,
}

/// The integral of `f_r` × cosine over the hemisphere, per channel, with `fixed` (a local direction,
/// z = normal, tangent `+x`; normalised) held and the other direction integrated ([`Over`]).
pub fn hemispherical(model: &Model, fixed: Vec3, over: Over, q: &Quadrature) -> Result<Vec3, BrdfError> {
    let fixed: Vec3 = crate::vector::normalize_or_zero(Vec3A::from(fixed)).into();
    if fixed == Vec3::ZERO {
        return Err(BrdfError::InvalidInput {
            name: "direction",
            problem: "must be a finite, non-zero vector".into(),
        });
    }
    let nodes = hemisphere_rule(fixed.into(), q)?;
    let dirs: Vec<Vec3> = nodes.iter().map(|(w, _)| Vec3::from(*w)).collect();
    let f = match over {
        Over::Viewer => eval_rows(model, &[fixed], &dirs, &[Vec3::Z], &[Vec3::X], Quantity::Brdf),
        Over::Light => eval_rows(model, &dirs, &[fixed], &[Vec3::Z], &[Vec3::X], Quantity::Brdf),
    };
    // In node order, in f64: the same bits for any thread count.
    let sum = f
        .iter()
        .zip(&nodes)
        .fold(glam::DVec3::ZERO, |acc, (f, (w, wt))| acc + f.as_dvec3() * (f64::from(w.z) * wt));
    Ok(sum.as_vec3())
}

/// `E(θ_i)` per channel at each incidence angle `θ_i` \[rad, in `[0, π/2]`\], with `l` in the x–z plane
/// (azimuth along the tangent): `l = (sin θ_i, 0, cos θ_i)`. The angles run in parallel; each result is
/// deterministic.
pub fn albedo_curve(model: &Model, theta_i: &[f64], q: &Quadrature) -> Result<Vec<Vec3>, BrdfError> {
    for &t in theta_i {
        check_angle("theta_i", t, 0.0, std::f64::consts::FRAC_PI_2)?;
    }
    q.validate()?;
    theta_i.par_iter().map(|&t| hemispherical(model, super::direction(t, 0.0), Over::Viewer, q)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Lambert;
    use crate::properties::directional_albedo;

    #[test]
    fn white_lambert_reflects_everything_at_every_incidence() {
        let m = Model::from(Lambert::new(Vec3::ONE));
        let t: Vec<f64> = (0..=18).map(|k| f64::from(k) * 5f64.to_radians()).collect();
        for e in albedo_curve(&m, &t, &VIEW_QUADRATURE).unwrap() {
            assert!((e - Vec3::ONE).abs().max_element() < 2e-6, "{e}");
        }
        assert!(albedo_curve(&m, &[1.6], &VIEW_QUADRATURE).unwrap_err().to_string().contains("theta_i"));
    }

    #[test]
    fn the_view_rule_agrees_with_the_checks_fine_rule_on_every_physical_model() {
        // E(θ) over the viewer equals ρ(v) over the light for a reciprocal model; the checks' finer rule
        // (8 × 8 points, panels to 1e-4 rad) is the reference for the coarse view rule.
        for spec in crate::MODEL_SPECS.iter().filter(|s| s.physical) {
            let m = Model::build(spec.name, &[]).unwrap();
            for deg in [0.0f64, 30.0, 60.0, 85.0] {
                let t = deg.to_radians();
                let e = albedo_curve(&m, &[t], &VIEW_QUADRATURE).unwrap()[0];
                let r = directional_albedo(&m, t.cos() as f32, &Quadrature::default()).unwrap();
                let err = (e - r).abs().max_element() / r.max_element().max(1e-3);
                assert!(err < 1e-3, "{} at {deg}°: view {e}, checks {r}", spec.name);
            }
        }
    }
}
