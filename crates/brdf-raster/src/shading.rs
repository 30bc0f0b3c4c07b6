//! The four shading algorithms of Theoharis et al. 2008 ("Illumination Algorithms based on the Phong Model"
//! and
//! "Quadratic Interpolation of Vertex Normals"), and the normal interpolation each one uses.
//!
//! | mode | evaluated where | interpolated across the triangle |
//! |---|---|---|
//! | [`ShadingMode::Flat`] (constant) | once per triangle: centroid, face normal | nothing — one colour |
//! | [`ShadingMode::Gouraud`] | at the three vertices (vertex normals) | the colours (perspective-correct) |
//! | [`ShadingMode::Phong`] | every sample | position and vertex normal, normal re-normalised |
//! | [`ShadingMode::QuadraticNormals`] | every sample | position; normal from the quadratic field of
//! [`quadratic_normal`] |
//!
//! The seed interpolates "bi-linearly along the edges and the scanline" in screen space. We interpolate
//! with the perspective-correct barycentrics of the sample instead: on an affine (orthographic) view
//! they are the same thing, and under perspective they are what the surface actually carries (GL's
//! `smooth`, and what the canonical scene uses). Flat shading follows the seed's constant shading in
//! evaluating the illumination model once per polygon with the polygon normal (cross product of two
//! edges), but keeps the true light and view directions at the centroid instead of the seed's
//! simplification `l = v = +z`, so the same lights drive every mode.
//!
//! The mode only says where the **reflectance model** is evaluated. Obscurance and shadows (when a
//! render has them) are asked for at every sample, with the sample's own position, in every mode: a
//! flat face or a Gouraud triangle keeps its ambient part and each light's part apart, and each sample
//! weights them by its own obscurance `w` and visibilities `δ_j` (see `render::shade`). Evaluating
//! shadows once per face or vertex instead gives blocky squares and saw-tooth shadow edges.

use glam::Vec3;

use crate::RasterError;

/// How a triangle is shaded (Theoharis et al. 2008, ch. 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadingMode {
    /// Constant shading: one illumination per triangle (centroid, face normal).
    Flat,
    /// Gouraud shading: illumination at the vertices, colours interpolated.
    Gouraud,
    /// Phong shading: normals interpolated and re-normalised, illumination per sample.
    #[default]
    Phong,
    /// Quadratic normal interpolation (van Overveld & Wyvill 1997), illumination per sample.
    QuadraticNormals,
}

impl ShadingMode {
    /// Every mode, in seed order.
    pub const ALL: [ShadingMode; 4] =
        [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong, ShadingMode::QuadraticNormals];

    /// The mode's name: "flat", "gouraud", "phong", "quadratic".
    pub fn name(self) -> &'static str {
        match self {
            ShadingMode::Flat => "flat",
            ShadingMode::Gouraud => "gouraud",
            ShadingMode::Phong => "phong",
            ShadingMode::QuadraticNormals => "quadratic",
        }
    }

    /// Parse a name of [`ShadingMode::name`] (also "constant" for flat).
    pub fn from_name(name: &str) -> Result<Self, RasterError> {
        match name {
            "flat" | "constant" => Ok(ShadingMode::Flat),
            "gouraud" => Ok(ShadingMode::Gouraud),
            "phong" => Ok(ShadingMode::Phong),
            "quadratic" | "quadratic_normals" => Ok(ShadingMode::QuadraticNormals),
            _ => Err(RasterError::arg(
                "shading",
                format!("unknown shading mode {name:?}; expected one of flat, gouraud, phong, quadratic"),
            )),
        }
    }
}

/// The face normal by the cross product of two edges, `(p1 − p0) × (p2 − p0)` normalised (Theoharis et al.
/// 2008,
/// ch. 12); zero for a degenerate triangle.
#[inline]
pub fn face_normal(p: [Vec3; 3]) -> Vec3 {
    (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
}

/// The per-edge coefficient of the quadratic normal field: `n_ij = n_i + n_j − β_ij` with
/// `β_ij = 3 ((n_i + n_j)·δ / δ²) δ`, `δ = p_j − p_i` (symmetric in i, j).
///
/// Derivation. Theoharis et al. (*Graphics and Visualization*, 2008, ch. 12) write van Overveld & Wyvill's
/// edge interpolant as
/// `n(s) = n_0 + s·a + s²·b`, `b = 3((n_0 + n_1)·δ/δ²) δ`, `a = n_1 − n_0 − b`; `b` is what makes the
/// normal's average along the edge perpendicular to the edge (`∫₀¹ n(s)·δ ds = 0`), i.e. the
/// reconstructed curve is consistent with the edge being a chord of the surface. Written in the
/// quadratic Bernstein basis, `n(s) = n_0 (1−s)² + n_ij · s(1−s) + n_1 s²` requires exactly
/// `n_ij = n_0 + n_1 − b` (match the `s` and `s²` coefficients). Over the triangle the field is the
/// quadratic `n(b) = Σ_i n_i b_i² + Σ_{i<j} n_ij b_i b_j` in the barycentrics `b`, which reduces to the
/// book's edge interpolant on every edge, so neighbouring triangles agree along shared edges.
#[inline]
pub fn quadratic_edge_coefficient(p_i: Vec3, p_j: Vec3, n_i: Vec3, n_j: Vec3) -> Vec3 {
    let delta = p_j - p_i;
    let d2 = delta.length_squared();
    if !(d2 > 0.0) {
        return n_i + n_j;
    }
    let beta = (3.0 * (n_i + n_j).dot(delta) / d2) * delta;
    n_i + n_j - beta
}

/// The quadratic normal field of van Overveld & Wyvill at barycentrics `b` of a triangle with corner
/// positions `p` and unit vertex normals `n` (see [`quadratic_edge_coefficient`]); not normalised.
/// The per-edge coefficients are evaluated on the fly (three dot products): on dense meshes a triangle
/// covers about one sample, so precomputing them per triangle would cost more than it saves.
#[inline]
pub fn quadratic_normal(p: [Vec3; 3], n: [Vec3; 3], b: Vec3) -> Vec3 {
    let n01 = quadratic_edge_coefficient(p[0], p[1], n[0], n[1]);
    let n12 = quadratic_edge_coefficient(p[1], p[2], n[1], n[2]);
    let n20 = quadratic_edge_coefficient(p[2], p[0], n[2], n[0]);
    n[0] * (b.x * b.x)
        + n[1] * (b.y * b.y)
        + n[2] * (b.z * b.z)
        + n01 * (b.x * b.y)
        + n12 * (b.y * b.z)
        + n20 * (b.z * b.x)
}

/// The linearly interpolated (Phong) normal `Σ b_i n_i`; not normalised.
#[inline]
pub fn linear_normal(n: [Vec3; 3], b: Vec3) -> Vec3 {
    n[0] * b.x + n[1] * b.y + n[2] * b.z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quadratic_field_interpolates_the_vertex_normals_and_the_seed_edge_formula() {
        let p = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.3), Vec3::new(0.5, 1.5, -0.2)];
        let n = [Vec3::new(-0.3, 0.1, 1.0), Vec3::new(0.4, -0.2, 1.0), Vec3::new(0.0, 0.5, 1.0)]
            .map(|v| v.normalize());
        for k in 0..3 {
            let mut b = Vec3::ZERO;
            b[k] = 1.0;
            assert!((quadratic_normal(p, n, b) - n[k]).length() < 1e-6);
        }
        // On edge 0→1 it is the seed's n(s) = n0 + s a + s² b.
        let delta = p[1] - p[0];
        let bb = 3.0 * ((n[0] + n[1]).dot(delta) / delta.length_squared()) * delta;
        let a = n[1] - n[0] - bb;
        for s in [0.1f32, 0.37, 0.5, 0.9] {
            let seed = n[0] + s * a + s * s * bb;
            let ours = quadratic_normal(p, n, Vec3::new(1.0 - s, s, 0.0));
            assert!((seed - ours).length() < 1e-5, "{s}: {seed} vs {ours}");
        }
        // And its mean along the edge is perpendicular to the edge (the condition that defines b).
        let m: f32 = (0..1000)
            .map(|i| {
                quadratic_normal(
                    p,
                    n,
                    Vec3::new(1.0 - (i as f32 + 0.5) / 1000.0, (i as f32 + 0.5) / 1000.0, 0.0),
                )
            })
            .map(|v| v.dot(delta))
            .sum::<f32>()
            / 1000.0;
        assert!(m.abs() < 1e-4, "{m}");
    }

    #[test]
    fn on_a_sphere_the_quadratic_field_is_the_linear_one() {
        // Vertex normals = positions on the unit sphere: (n_i + n_j)·(p_j − p_i) = |p_j|² − |p_i|² = 0.
        let p = [Vec3::new(0.3, 0.4, 0.0), Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.6, 0.0, 0.8)]
            .map(|v| v.normalize());
        let b = Vec3::new(0.2, 0.5, 0.3);
        assert!((quadratic_normal(p, p, b) - linear_normal(p, b)).length() < 1e-6);
    }

    #[test]
    fn the_silhouette_example_gets_varying_normals_where_phong_gives_a_constant() {
        // Seed 004's "silhouette edge problem": equal vertex normals tilted away from a flat face.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = [Vec3::new(0.6, 0.0, 0.8); 3];
        let lin = linear_normal(n, Vec3::splat(1.0 / 3.0)).normalize();
        assert!((lin - n[0]).length() < 1e-6);
        let q = quadratic_normal(p, n, Vec3::splat(1.0 / 3.0)).normalize();
        assert!((q - n[0]).length() > 0.05, "{q}");
    }

    #[test]
    fn mode_names_round_trip() {
        for m in ShadingMode::ALL {
            assert_eq!(ShadingMode::from_name(m.name()).unwrap(), m);
        }
        assert!(ShadingMode::from_name("smooth").unwrap_err().to_string().contains("shading"));
    }
}
