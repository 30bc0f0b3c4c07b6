//! Face and vertex normals (seed 004, "Normals"): cross product, Newell's method, vertex normals
//! weighted equally, by area or by angle.

use glam::Vec3;

/// How face normals are weighted when averaged into a vertex normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Weighting {
    /// Every incident face counts once.
    Equal,
    /// Faces weighted by their area.
    Area,
    /// Faces weighted by the corner angle at the vertex (Thürmer & Wüthrich 1998).
    Angle,
}

/// Unit vertex normals of an indexed mesh by the given weighting; isolated vertices get zero.
pub fn vertex_normals(positions: &[Vec3], indices: &[[u32; 3]], weighting: Weighting) -> Vec<Vec3> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    for tri in indices {
        let p = tri.map(|i| positions[i as usize]);
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let unit = cross.normalize_or_zero();
        for k in 0..3 {
            let w = match weighting {
                Weighting::Equal => unit,
                Weighting::Area => cross * 0.5,
                Weighting::Angle => {
                    let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
                    let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
                    unit * e1.dot(e2).clamp(-1.0, 1.0).acos()
                }
            };
            acc[tri[k] as usize] += w;
        }
    }
    acc.into_iter().map(|n| n.normalize_or_zero()).collect()
}
