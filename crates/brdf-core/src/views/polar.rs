//! The polar plot: `f_r` in the plane of incidence as the viewer sweeps from one horizon to the other.

use std::f64::consts::FRAC_PI_2;

use glam::Vec3;

use super::{Incidence, MAX_SAMPLES, check_count, eval_rows, sanitize};
use crate::batch::Quantity;
use crate::{BrdfError, Model};

/// The in-plane slice of a model for one incidence.
#[derive(Debug, Clone, PartialEq)]
pub struct Polar {
    /// Signed outgoing angles `θ_o` \[rad\], from `−π/2` to `π/2` inclusive, positive on the mirror
    /// side ([`Incidence::in_plane`]).
    pub theta_o: Vec<f64>,
    /// `f_r(l, v(θ_o))` \[1/sr\] per channel, times `cos θ_o` when asked for.
    pub values: Vec<Vec3>,
}

/// `f_r(l, v(θ_o))` at `count` equally spaced signed angles `θ_o ∈ [−π/2, π/2]` in the plane of
/// incidence (BRDF Explorer's polar plot), with the tangent along `+x`. With `cosine`, each value is
/// multiplied by `cos θ_o`: the reflected radiant intensity per unit incident flux, whose integral over
/// the hemisphere is the directional albedo. `count` must be in `[2, 2^24]`.
pub fn polar(model: &Model, inc: Incidence, count: usize, cosine: bool) -> Result<Polar, BrdfError> {
    check_count("n", count, 2, MAX_SAMPLES)?;
    let step = 2.0 * FRAC_PI_2 / (count - 1) as f64;
    let theta_o: Vec<f64> = (0..count).map(|k| -FRAC_PI_2 + step * k as f64).collect();
    let v: Vec<Vec3> = theta_o.iter().map(|&t| inc.in_plane(t)).collect();
    let f = eval_rows(model, &[inc.light()], &v, &[Vec3::Z], &[Vec3::X], Quantity::Brdf);
    let values =
        f.iter().zip(&v).map(|(&f, v)| sanitize(if cosine { f * v.z.max(0.0) } else { f })).collect();
    Ok(Polar { theta_o, values })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Geometry;

    #[test]
    fn polar_values_are_the_model_at_the_in_plane_directions() {
        let m = Model::build("cook_torrance", &[]).unwrap();
        let inc = Incidence::new(0.6, 0.4).unwrap();
        let p = polar(&m, inc, 181, false).unwrap();
        let pc = polar(&m, inc, 181, true).unwrap();
        assert_eq!(p.theta_o.len(), 181);
        assert_eq!((p.theta_o[0], p.theta_o[180]), (-FRAC_PI_2, FRAC_PI_2));
        for (k, &t) in p.theta_o.iter().enumerate().step_by(7) {
            let v = inc.in_plane(t);
            let g = Geometry::new(inc.light(), v, Vec3::Z, Some(Vec3::X)).unwrap();
            assert_eq!(p.values[k], m.eval(&g), "theta_o {t}");
            assert_eq!(pc.values[k], m.eval(&g) * v.z.max(0.0));
        }
        assert!(polar(&m, inc, 1, false).unwrap_err().to_string().starts_with("n:"));
    }
}
