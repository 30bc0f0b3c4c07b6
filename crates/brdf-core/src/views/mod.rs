//! The views of a reflectance model that Disney's BRDF Explorer draws (Burley 2012, "Physically-Based
//! Shading at Disney", §3; the `wdas/brdf` program), as data: every function evaluates one model over
//! a grid of directions in one batch ([`crate::batch::evaluate`], eight lanes at a time, on the pool
//! for large grids) and returns plain arrays. Plotting lives elsewhere (Python's `brdfpy.plot`).
//!
//! - [`polar::polar`]: the in-plane slice `f_r(θ_o)` for a fixed incidence, optionally × `cos θ_o`;
//! - [`lobe::lobe`]: the 3D lobe for a fixed incidence as a triangle mesh (radius `f_r` or
//!   `f_r cos θ_o` of one channel or the luminance);
//! - [`slice::half_diff_slice`]: the image over Rusinkiewicz's `(θ_h, θ_d)` at a chosen `φ_d`
//!   ([`crate::rusinkiewicz`]);
//! - [`albedo::albedo_curve`]: the directional albedo `E(θ_i)`;
//! - [`sphere::lit_sphere`]: the lit sphere (a directional light and a uniform sky).
//!
//! ## Frame and angles
//! Everything is in the local frame: `n = +z`, the tangent (for anisotropic models) `+x`. The
//! incidence ([`Incidence`]) is the light direction `l = (sin θ_i cos φ, sin θ_i sin φ, cos θ_i)`
//! with `θ_i ∈ [0, π/2]` from the normal and `φ` the azimuth of the plane of incidence from the
//! tangent. Angles are radians here; errors quote them in degrees too, since users give degrees.
//! Directions are computed in f64 and rounded once to f32.

use glam::Vec3;

use crate::BrdfError;
use crate::Model;
use crate::batch::{Directions, Quantity, evaluate};

pub mod albedo;
pub mod lobe;
pub mod polar;
pub mod slice;
pub mod sphere;

/// Rec. 709 / sRGB luminance weights of linear RGB (ITU-R BT.709, item 3.2): `Y = 0.2126 R +
/// 0.7152 G + 0.0722 B`.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Largest number of samples a view evaluates (a 4096 × 4096 slice): guards against a request for
/// gigabytes.
pub const MAX_SAMPLES: usize = 1 << 24;

/// The unit direction with polar angle `theta` from `+z` and azimuth `phi` from `+x` toward `+y`
/// \[radians\], computed in f64 and rounded once.
#[inline]
pub fn direction(theta: f64, phi: f64) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new((st * cp) as f32, (st * sp) as f32, ct as f32)
}

/// A finite angle `x` \[rad\] in `[lo, hi]`, or an error naming `name` (with degrees, which is what
/// users type).
pub fn check_angle(name: &'static str, x: f64, lo: f64, hi: f64) -> Result<f64, BrdfError> {
    if x.is_finite() && x >= lo && x <= hi {
        return Ok(x);
    }
    // Degrees rounded to 1e-9 so that 95° given in degrees and converted reads back as 95°.
    let deg = |r: f64| (r.to_degrees() * 1e9).round() / 1e9;
    Err(BrdfError::InvalidInput {
        name,
        problem: format!("must be a finite angle in [{}°, {}°], got {}° ({x} rad)", deg(lo), deg(hi), deg(x)),
    })
}

/// A count `x` in `[lo, hi]`, or an error naming `name`.
pub fn check_count(name: &'static str, x: usize, lo: usize, hi: usize) -> Result<usize, BrdfError> {
    if (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(BrdfError::InvalidInput { name, problem: format!("must be in [{lo}, {hi}], got {x}") })
    }
}

/// The incident (light) direction of a view: polar angle `θ_i` from the normal and the azimuth `φ`
/// of the plane of incidence from the tangent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Incidence {
    /// `θ_i` \[rad\], in `[0, π/2]`.
    pub theta_i: f64,
    /// `φ` \[rad\], any finite value.
    pub phi: f64,
}

impl Incidence {
    /// Check `θ_i ∈ [0, π/2]` (the light above the surface, grazing included) and a finite `φ`.
    pub fn new(theta_i: f64, phi: f64) -> Result<Self, BrdfError> {
        check_angle("theta_i", theta_i, 0.0, std::f64::consts::FRAC_PI_2)?;
        if !phi.is_finite() {
            return Err(BrdfError::InvalidInput {
                name: "phi",
                problem: format!("must be a finite angle, got {phi}"),
            });
        }
        Ok(Self { theta_i, phi })
    }

    /// The unit light direction `l`.
    pub fn light(&self) -> Vec3 {
        direction(self.theta_i, self.phi)
    }

    /// The in-plane direction at signed angle `theta_o` from the normal, positive on the mirror side:
    /// `v(θ_o) = (−sin θ_o cos φ, −sin θ_o sin φ, cos θ_o)`, so `v(θ_i)` is the mirror direction of `l`
    /// and `v(−θ_i) = l` (retro-reflection).
    pub fn in_plane(&self, theta_o: f64) -> Vec3 {
        direction(-theta_o, self.phi)
    }
}

/// `f_r` (or the shade value) of `model` for every row, with the tangents `t` (`+x` in the local frame of
/// the views): one batch through the lane evaluator. Isotropic models get no tangent, which saves
/// normalising one per sample (they ignore it).
pub(crate) fn eval_rows(
    model: &Model,
    l: &[Vec3],
    v: &[Vec3],
    n: &[Vec3],
    t: &[Vec3],
    q: Quantity,
) -> Vec<Vec3> {
    let t = model.spec().anisotropic.then_some(t);
    match Directions::new(l, v, n, t) {
        Ok((dirs, len)) => {
            let mut out = vec![Vec3::ZERO; len];
            evaluate(model, &dirs, q, &mut out);
            out
        }
        // The views build their inputs with matching lengths; an empty result is the only other case.
        Err(_) => Vec::new(),
    }
}

/// `x` with NaN/∞/negative values replaced by 0 (a view draws what a model returns; a classic model
/// never returns such values, but a plot must not be poisoned by one).
#[inline]
pub(crate) fn sanitize(x: Vec3) -> Vec3 {
    let f = |c: f32| if c.is_finite() && c > 0.0 { c } else { 0.0 };
    Vec3::new(f(x.x), f(x.y), f(x.z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn a(x: Vec3) -> Vec3A {
        x.into()
    }

    #[test]
    fn incidence_is_checked_and_in_plane_directions_put_the_mirror_at_plus_theta_i() {
        let inc = Incidence::new(0.5, 0.3).unwrap();
        let l = a(inc.light());
        let r = crate::vector::reflect(l, Vec3A::Z);
        assert!((a(inc.in_plane(0.5)) - r).length() < 1e-6);
        assert!((a(inc.in_plane(-0.5)) - l).length() < 1e-6);
        for bad in [-1e-9, 1.6, f64::NAN, f64::INFINITY] {
            let e = Incidence::new(bad, 0.0).unwrap_err().to_string();
            assert!(e.contains("theta_i") && e.contains("[0°, 90°]"), "{e}");
        }
        assert!(Incidence::new(std::f64::consts::FRAC_PI_2, 0.0).is_ok());
        assert!(Incidence::new(0.3, f64::NAN).unwrap_err().to_string().contains("phi"));
    }
}
