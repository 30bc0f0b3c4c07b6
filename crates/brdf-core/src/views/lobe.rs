//! The 3D lobe: for a fixed incidence, every outgoing direction `v` of the hemisphere pushed out to the
//! radius `f_r(l, v)` (or `f_r cos θ_o`), as a triangle mesh the rasterizer can draw or a file can hold.

use std::f64::consts::{FRAC_PI_2, TAU};

use glam::Vec3;

use super::{Incidence, LUMINANCE, MAX_SAMPLES, check_count, direction, eval_rows, sanitize};
use crate::batch::Quantity;
use crate::{BrdfError, Model};

/// What sets a lobe vertex's distance from the origin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Radius {
    /// `f_r(l, v)` \[1/sr\].
    Brdf,
    /// `f_r(l, v) cos θ_o` (the reflected intensity; see [`super::polar::polar`]).
    BrdfCos,
}

/// Which number of the RGB value the radius is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    /// Rec. 709 luminance ([`LUMINANCE`]).
    Luminance,
    /// Red.
    Red,
    /// Green.
    Green,
    /// Blue.
    Blue,
}

impl Channel {
    /// The channel's number of `c`.
    #[inline]
    pub fn of(self, c: Vec3) -> f32 {
        match self {
            Channel::Luminance => LUMINANCE.dot(c),
            Channel::Red => c.x,
            Channel::Green => c.y,
            Channel::Blue => c.z,
        }
    }
}

/// A lobe mesh: vertices, counter-clockwise faces (seen from outside), and per vertex the outgoing
/// direction, the RGB value and the radius.
#[derive(Debug, Clone, PartialEq)]
pub struct Lobe {
    /// `radius · direction`, one per vertex.
    pub vertices: Vec<Vec3>,
    /// Vertex indices, counter-clockwise seen from outside the lobe.
    pub faces: Vec<[u32; 3]>,
    /// The unit outgoing direction `v` of each vertex: the pole `+z` first, then ring by ring from the
    /// normal toward the horizon, each ring by increasing azimuth from `+x`.
    pub directions: Vec<Vec3>,
    /// `f_r(l, v)` (× `cos θ_o` for [`Radius::BrdfCos`]) per channel at each vertex.
    pub values: Vec<Vec3>,
    /// The radius of each vertex: `values` through the [`Channel`].
    pub radius: Vec<f32>,
}

/// The lobe of `model` for incidence `inc` on a grid of `n_theta` rings (polar angles
/// `k/n_theta · π/2`, `k = 1 ..= n_theta`, the last at the horizon) of `n_phi` azimuths each, plus the
/// pole: `1 + n_theta·n_phi` vertices, `n_phi (2 n_theta − 1)` faces. The tangent is `+x`.
/// `n_theta ≥ 1`, `n_phi ≥ 3`.
pub fn lobe(
    model: &Model,
    inc: Incidence,
    n_theta: usize,
    n_phi: usize,
    radius: Radius,
    channel: Channel,
) -> Result<Lobe, BrdfError> {
    check_count("n_theta", n_theta, 1, MAX_SAMPLES)?;
    check_count("n_phi", n_phi, 3, MAX_SAMPLES)?;
    if n_theta * n_phi > MAX_SAMPLES {
        return Err(BrdfError::InvalidInput {
            name: "n_theta",
            problem: format!("n_theta·n_phi = {} exceeds {MAX_SAMPLES}", n_theta * n_phi),
        });
    }
    let mut directions = Vec::with_capacity(1 + n_theta * n_phi);
    directions.push(Vec3::Z);
    for k in 1..=n_theta {
        let theta = k as f64 / n_theta as f64 * FRAC_PI_2;
        for j in 0..n_phi {
            directions.push(direction(theta, j as f64 / n_phi as f64 * TAU));
        }
    }
    let f = eval_rows(model, &[inc.light()], &directions, &[Vec3::Z], &[Vec3::X], Quantity::Brdf);
    let values: Vec<Vec3> = f
        .iter()
        .zip(&directions)
        .map(|(&f, v)| sanitize(if radius == Radius::BrdfCos { f * v.z.max(0.0) } else { f }))
        .collect();
    let radii: Vec<f32> = values.iter().map(|&c| channel.of(c).max(0.0)).collect();
    let vertices = directions.iter().zip(&radii).map(|(&d, &r)| d * r).collect();
    // Ring k (1-based) starts at vertex 1 + (k − 1)·n_phi.
    let at = |k: usize, j: usize| (1 + (k - 1) * n_phi + j % n_phi) as u32;
    let mut faces = Vec::with_capacity(n_phi * (2 * n_theta - 1));
    for j in 0..n_phi {
        faces.push([0, at(1, j), at(1, j + 1)]);
    }
    for k in 1..n_theta {
        for j in 0..n_phi {
            let (a0, a1, b0, b1) = (at(k, j), at(k, j + 1), at(k + 1, j), at(k + 1, j + 1));
            faces.push([a0, b0, b1]);
            faces.push([a0, b1, a1]);
        }
    }
    Ok(Lobe { vertices, faces, directions, values, radius: radii })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobe_of_a_white_lambert_is_a_hemisphere_of_radius_one_over_pi_with_outward_faces() {
        let m = Model::from(crate::models::Lambert::new(Vec3::ONE));
        let inc = Incidence::new(0.3, 0.0).unwrap();
        let lobe = lobe(&m, inc, 8, 16, Radius::Brdf, Channel::Green).unwrap();
        assert_eq!(lobe.vertices.len(), 1 + 8 * 16);
        assert_eq!(lobe.faces.len(), 16 * 15);
        let g = lobe.values[0].y;
        // Every vertex sits at the same radius: the horizon ring too (its cos θ_o is cos(π/2) rounded,
        // 6e-17, so f_r there is its grazing limit), and with the cosine the radius is g cos θ_o.
        assert!((g - 1.0 / std::f32::consts::PI).abs() < 1e-7);
        assert!(lobe.radius.iter().all(|r| (r - g).abs() < 1e-7));
        let cos = super::lobe(&m, inc, 8, 16, Radius::BrdfCos, Channel::Luminance).unwrap();
        for (d, r) in cos.directions.iter().zip(&cos.radius) {
            assert!((r - g * d.z).abs() < 1e-6, "{d} {r}");
        }
        // Faces away from the horizon point outward: the normal by the winding agrees with the
        // direction of the face centre.
        for f in &lobe.faces[..16 * 9] {
            let [p, q, r] = f.map(|i| lobe.vertices[i as usize]);
            let normal = (q - p).cross(r - p);
            assert!(normal.dot(p + q + r) > 0.0, "{f:?}");
        }
        let e = super::lobe(&m, inc, 8, 2, Radius::Brdf, Channel::Red).unwrap_err().to_string();
        assert!(e.contains("n_phi"), "{e}");
    }
}
