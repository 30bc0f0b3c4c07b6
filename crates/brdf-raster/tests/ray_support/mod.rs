//! Helpers shared by `tests/bvh.rs` and `tests/ao.rs`: a deterministic RNG, the brute-force ray
//! queries the BVH must equal, and a reader for the binary PLY files in `../shared/assets/meshes`.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use brdf_raster::bvh::{Hit, Ray, intersect_triangle, is_degenerate};
use glam::Vec3;

/// SplitMix64: small, fast and reproducible on every platform.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }
    pub fn vec3(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f32::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// Brute force closest hit with the documented tie rule (smallest t, then smallest id).
pub fn brute_closest(tris: &[[Vec3; 3]], ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (i, t) in tris.iter().enumerate() {
        if is_degenerate(t) {
            continue;
        }
        if let Some((th, u, v)) = intersect_triangle(ray, t) {
            let id = i as u32;
            if best.is_none_or(|b| th < b.t || (th == b.t && id < b.triangle)) {
                best = Some(Hit { t: th, triangle: id, u, v });
            }
        }
    }
    best
}

/// Brute force any hit.
pub fn brute_any(tris: &[[Vec3; 3]], ray: &Ray) -> bool {
    tris.iter().any(|t| !is_degenerate(t) && intersect_triangle(ray, t).is_some())
}

/// `../shared/assets/meshes/<name>` relative to the workspace, if present.
pub fn asset(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes").join(name);
    p.exists().then_some(p)
}

/// Read the assets' PLY form: binary little-endian, `x y z` float32 vertices, then faces as
/// `list uchar int` triangles (the README of the assets fixes this layout).
pub fn read_ply(path: &std::path::Path) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let bytes = std::fs::read(path).expect("read ply");
    let end = bytes.windows(11).position(|w| w == b"end_header\n").expect("ply header") + 11;
    let header = std::str::from_utf8(&bytes[..end]).expect("ascii header");
    assert!(header.contains("binary_little_endian"), "{header}");
    let count = |el: &str| -> usize {
        header
            .lines()
            .find_map(|l| l.strip_prefix(&format!("element {el} ")))
            .and_then(|n| n.trim().parse().ok())
            .expect("element count")
    };
    let (nv, nf) = (count("vertex"), count("face"));
    let mut at = end;
    let f32_at = |b: &[u8], i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    let mut positions = Vec::with_capacity(nv);
    for _ in 0..nv {
        positions.push(Vec3::new(f32_at(&bytes, at), f32_at(&bytes, at + 4), f32_at(&bytes, at + 8)));
        at += 12;
    }
    let mut faces = Vec::with_capacity(nf);
    for _ in 0..nf {
        assert_eq!(bytes[at], 3, "only triangles");
        let i = |k: usize| {
            let o = at + 1 + 4 * k;
            i32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]) as u32
        };
        faces.push([i(0), i(1), i(2)]);
        at += 13;
    }
    (positions, faces)
}

/// An octahedron subdivided `level` times and pushed onto the unit sphere: closed, CCW outward,
/// with shared edges (vertex `i` is also its own outward normal).
pub fn sphere(level: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let mut f: Vec<[u32; 3]> =
        vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
    for _ in 0..level {
        let mut mid = HashMap::new();
        let mut next = Vec::new();
        for t in &f {
            let mut m = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                m[k] = *mid.entry((a, b)).or_insert_with(|| {
                    p.push(((p[a as usize] + p[b as usize]) * 0.5).normalize());
                    (p.len() - 1) as u32
                });
            }
            next.extend([[t[0], m[0], m[2]], [m[0], t[1], m[1]], [m[2], m[1], t[2]], [m[0], m[1], m[2]]]);
        }
        f = next;
    }
    (p, f)
}

/// A square grid of `(n+1)²` vertices over `[-half, half]²` in the plane `y = 0`, facing +y.
pub fn grid_y0(half: f32, n: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let s = |k: u32| -half + 2.0 * half * k as f32 / n as f32;
            p.push(Vec3::new(s(i), 0.0, s(j)));
        }
    }
    let mut f = Vec::new();
    let at = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            // CCW seen from +y: (i,j) → (i,j+1) → (i+1,j+1) (x right, z toward the viewer).
            f.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
            f.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    (p, f)
}
