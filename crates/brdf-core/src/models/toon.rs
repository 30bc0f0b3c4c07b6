//! Toon (cel) shading: a three-band diffuse term and a two-level specular term, the hard-shading
//! idea of A. Lake, C. Marshall, M. Harris, M. Blackstein, "Stylized Rendering Techniques for Scalable
//! Real-Time 3D Animation", NPAR 2000, with the bands and the highlight as explicit thresholds.

use glam::Vec3;

use crate::BrdfError;
use crate::microfacet::HalfVector;
use crate::models::phong::mirror_deficit;
use crate::models::{Bxdf, ModelKind};
use crate::params::{ModelSpec, ParamSpec, Params};
use crate::simd::{Lane, LaneGeometry, V3};

/// What the toon specular thresholds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ToonSpecularMode {
    /// `v·r` with `r = 2(n·l)n − l` (a Phong highlight).
    Phong,
    /// `n·h` with `h = normalize(l + v)` (a Blinn highlight).
    Blinn,
}

/// Toon shading, a classic model whose `shade` is a banded diffuse term plus a thresholded highlight:
///
/// ```text
/// diffuse  = dark_scale · kd   if n·l < dark_threshold
///          = kd_mid            if n·l < diffuse_threshold
///          = kd                otherwise
/// specular = ks                if x ≥ specular_threshold, else 0
///            x = v·r (specular_mode = "phong") or n·h ("blinn")
/// ```
///
/// Bands are half-open (`<` selects the lower band), so a value exactly on a threshold
/// takes the upper band. The diffuse bands apply for any `n·l`, including light from behind (which gets
/// the dark band), exactly as written. The specular term is zeroed for `n·l ≤ 0` when `specular_gate`
/// is true (default), for the reason given at [`crate::models::PhongClassic`]; `specular_gate = false`
/// does not gate. With `l = −v` there is no half vector and the Blinn specular is 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Toon {
    /// Diffuse reflectance `kd` of the lit band (`n·l ≥ diffuse_threshold`).
    pub kd: Vec3,
    /// Mid-band colour (`dark_threshold ≤ n·l < diffuse_threshold`).
    pub kd_mid: Vec3,
    /// Lower edge of the lit band.
    pub diffuse_threshold: f32,
    /// Lower edge of the mid band.
    pub dark_threshold: f32,
    /// Dark band = `dark_scale · kd`.
    pub dark_scale: f32,
    /// Highlight colour `ks`.
    pub ks: Vec3,
    /// Highlight threshold `t_S` on `v·r` or `n·h`.
    pub specular_threshold: f32,
    /// Which cosine is thresholded.
    pub specular_mode: ToonSpecularMode,
    /// Zero the specular term when `n·l ≤ 0`.
    pub specular_gate: bool,
}

impl Toon {
    /// The diffuse band colour for a given `n·l`.
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn diffuse_band<F: Lane>(&self, nl: F) -> V3<F> {
        let mid_or_lit =
            V3::select(nl.lt(F::splat(self.diffuse_threshold)), V3::splat(self.kd_mid), V3::splat(self.kd));
        V3::select(nl.lt(F::splat(self.dark_threshold)), V3::splat(self.dark_scale * self.kd), mid_or_lit)
    }

    /// The specular level for the geometry (Phong or Blinn highlight).
    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn specular_level<F: Lane>(&self, g: &LaneGeometry<F>) -> V3<F> {
        let edge = F::splat(1.0 - self.specular_threshold);
        let lit = match self.specular_mode {
            // v·r ≥ t as d ≤ 1 − t with the mirror deficit d = 1 − v·r (phong::mirror_deficit), not
            // `2(n·l)(n·v) − l·v ≥ t`: that rounds v·r ≈ 1 to a few 2^-24 absolute, which moved the
            // highlight's edge by up to 5.7e-5 rad at t = 0.9999 (1.8e-6 at t = 0.9) in a float32
            // emulation, where rounding the float32 inputs moves it by 1.2e-7 (the deficit: 1.3e-6 at
            // t = 0.9999, most of it t's own float32 rounding; 1.7e-7 at t = 0.9). 1 − t is exact in
            // float32 for t ≥ 0.5.
            ToonSpecularMode::Phong => mirror_deficit(g).le(edge),
            // n·h ≥ t as 1 − n·h ≤ 1 − t with 1 − n·h = |h̃⊥|²/(|h̃|(|h̃| + n·h̃)) from the un-normalised
            // h̃ = l + v (microfacet::HalfVector), not `n·normalize(l + v) ≥ t`: that rounds n·h ≈ 1 to
            // a few 2^-24 absolute, which moved the highlight's edge by up to 1.2e-5 rad at t = 0.9999
            // (2.7e-7 at t = 0.9, 1.3e-4 at t = 0.999999) in a float32 emulation; this form moves it
            // by 5.7e-8 (4.5e-8, 1.1e-7), what rounding the float32 inputs alone does (5.7e-8, 3.9e-8,
            // 1.1e-7). l = −v has no half vector (h̃ = 0): unlit.
            ToonSpecularMode::Blinn => {
                let h = HalfVector::from_directions(g.l, g.v, g.n);
                let len = h.len2.sqrt();
                // 1 − cos θ_h = sin²θ_h/(1 + cos θ_h) cancels nothing where h is above the surface;
                // below it (a threshold < 0) 1 − n·h ≥ 1 has nothing to lose either.
                let above = h.perp2 / (len * (len + h.n_dot));
                let below = F::splat(1.0) - h.n_dot / len;
                let deficit = F::select(h.n_dot.gt(F::splat(0.0)), above, below);
                h.len2.gt(F::splat(1e-20)) & deficit.le(edge)
            }
        };
        let gated = F::mask_splat(self.specular_gate) & g.nl.le(F::splat(0.0));
        V3::select(lit & !gated, V3::splat(self.ks), V3::splat(Vec3::ZERO))
    }
}

impl Bxdf for Toon {
    const SPEC: ModelSpec = ModelSpec {
        name: "toon",
        summary: "toon shading: 3-band diffuse on n.l (dark / mid / lit) + thresholded specular on v.r or n.h",
        source: "cel shading after A. Lake, C. Marshall, M. Harris, M. Blackstein, Stylized Rendering Techniques for Scalable Real-Time 3D Animation, NPAR (2000), with explicit band and highlight thresholds",
        physical: false,
        anisotropic: false,
        params: &[
            ParamSpec::color(
                "kd",
                [0.8, 0.3, 0.2],
                0.0,
                1.0,
                "reflectance",
                "diffuse colour of the lit band",
            ),
            ParamSpec::color(
                "kd_mid",
                [0.4, 0.15, 0.1],
                0.0,
                1.0,
                "reflectance",
                "diffuse colour of the mid band (default: half the default kd; set both together)",
            ),
            ParamSpec::scalar(
                "diffuse_threshold",
                0.5,
                -1.0,
                1.0,
                "cosine",
                "n.l at and above which the lit colour kd is used",
            ),
            ParamSpec::scalar(
                "dark_threshold",
                0.07,
                -1.0,
                1.0,
                "cosine",
                "n.l below which the dark band is used",
            ),
            ParamSpec::scalar("dark_scale", 0.002, 0.0, 1.0, "1", "dark band = dark_scale * kd"),
            ParamSpec::color("ks", [1.0, 1.0, 1.0], 0.0, 1.0, "reflectance", "highlight colour"),
            ParamSpec::scalar(
                "specular_threshold",
                0.9,
                -1.0,
                1.0,
                "cosine",
                "v.r (phong) or n.h (blinn) at and above which the highlight is drawn",
            ),
            ParamSpec::choice(
                "specular_mode",
                &["phong", "blinn"],
                "phong",
                "thresholded cosine: v.r or n.h",
            ),
            ParamSpec::flag(
                "specular_gate",
                true,
                "no highlight when n.l <= 0 (false: ungated, as many GLSL shaders write it)",
            ),
        ],
    };
    const KIND: ModelKind = ModelKind::Classic;

    /// Uniform over the hemisphere ([`crate::sampling::cosine::sample_uniform`]): each band's `shade`
    /// is a constant, so `shade/p = 2π·shade` is bounded (cosine weighting would give `π·shade/cos θ`,
    /// of infinite variance); the bands themselves, step functions of `n·l` and `v·r`, are not matched.
    fn sampler(&self) -> Result<crate::sampling::Sampler, BrdfError> {
        use crate::sampling::{Sampler, Technique};
        Ok(Sampler::new().with(Technique::UniformHemisphere, 1.0))
    }

    fn from_params(p: &Params) -> Result<Self, BrdfError> {
        Ok(Self {
            kd: p.color("kd"),
            kd_mid: p.color("kd_mid"),
            diffuse_threshold: p.scalar("diffuse_threshold"),
            dark_threshold: p.scalar("dark_threshold"),
            dark_scale: p.scalar("dark_scale"),
            ks: p.color("ks"),
            specular_threshold: p.scalar("specular_threshold"),
            specular_mode: match p.choice("specular_mode") {
                "blinn" => ToonSpecularMode::Blinn,
                _ => ToonSpecularMode::Phong,
            },
            specular_gate: p.flag("specular_gate"),
        })
    }

    #[cfg_attr(debug_assertions, inline)]
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn formula<F: Lane>(&self, g: &LaneGeometry<F>, _active: F::Mask) -> V3<F> {
        self.diffuse_band(g.nl) + self.specular_level(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Geometry;

    use glam::DVec3;

    fn level(toon: &Toon, g: &Geometry) -> Vec3 {
        toon.specular_level(&LaneGeometry::from(g)).into()
    }

    /// Specular only: black diffuse bands, white highlight.
    fn specular_only(specular_mode: ToonSpecularMode, specular_threshold: f32) -> Toon {
        Toon {
            kd: Vec3::ZERO,
            kd_mid: Vec3::ZERO,
            diffuse_threshold: 0.5,
            dark_threshold: 0.07,
            dark_scale: 0.0,
            ks: Vec3::ONE,
            specular_threshold,
            specular_mode,
            specular_gate: true,
        }
    }

    /// At threshold 1, `mode`'s highlight lights every exact mirror pair about n = z and not a direction
    /// 1e-3 rad off it.
    fn lights_exactly_the_mirror_direction(mode: ToonSpecularMode) {
        let toon = specular_only(mode, 1.0);
        for i in 1..200 {
            let theta = 1.5 * i as f32 / 200.0;
            for phi in [0.1_f32, 1.0, 2.5, 4.0] {
                let l = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                let g = Geometry::new(l, Vec3::new(-l.x, -l.y, l.z), Vec3::Z, None).unwrap();
                assert_eq!(level(&toon, &g), Vec3::ONE, "theta = {theta}, phi = {phi}");
                let off = Vec3::new(-l.x, -l.y, l.z + 1e-3).normalize();
                let g = Geometry::new(l, off, Vec3::Z, None).unwrap();
                assert_eq!(level(&toon, &g), Vec3::ZERO, "theta = {theta}, phi = {phi}");
            }
        }
    }

    #[test]
    fn a_phong_highlight_at_threshold_one_lights_exactly_the_mirror_direction() {
        // v = (−lx, −ly, lz) is l's exact mirror about n = z in float32 too, so v·r = 1 and a threshold of
        // 1 must light it at every angle; `2(n·l)(n·v) − l·v` rounds v·r to a few ulps of 1, below it for
        // some of these directions. A direction 1e-3 rad off the mirror stays dark.
        lights_exactly_the_mirror_direction(ToonSpecularMode::Phong);
    }

    #[test]
    fn a_blinn_highlight_at_threshold_one_lights_exactly_the_mirror_direction() {
        // For v = (−lx, −ly, lz) and n = z, h̃ = l + v = (0, 0, 2lz) in float32 too: h = n, n·h = 1. The
        // normalised n·h can round to 1 − 2^-24 (|h̃| = √(4lz²) need not be 2lz); |h̃⊥|² is exactly 0.
        lights_exactly_the_mirror_direction(ToonSpecularMode::Blinn);
    }

    #[test]
    fn a_blinn_highlight_edge_sits_where_n_dot_h_crosses_the_threshold() {
        // Half vectors 2e-6 rad inside or outside the edge θ_h = acos(t), t = 0.9999 (θ_h = 0.014), for l
        // and v all around it, in a tilted frame: built in float64 and rounded to float32, which moves θ_h
        // by ~1e-7 rad (the input floor; a float32 emulation of this form moves the edge by 5.7e-8).
        // `n·normalize(l + v) ≥ t` rounds n·h ≈ 1 to a few 2^-24, i.e. a few 2^-24/sin θ_h ≈ 1e-5 rad
        // of θ_h: it puts some of these on the wrong side.
        let t = 0.9999_f32;
        let toon = specular_only(ToonSpecularMode::Blinn, t);
        let edge = f64::from(t).acos();
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let (tx, ty) = n.any_orthonormal_pair();
        let world = |w: DVec3| (w.x * tx + w.y * ty + w.z * n).as_vec3();
        for i in 0..4000 {
            let k = f64::from(i);
            let inside = i % 2 == 0;
            let theta_h = if inside { edge - 2e-6 } else { edge + 2e-6 };
            let (phi_h, theta_d, phi_d) = (k * 2.399, (k * 0.377) % 1.4, k * 1.3);
            let h = DVec3::new(theta_h.sin() * phi_h.cos(), theta_h.sin() * phi_h.sin(), theta_h.cos());
            let y = DVec3::new(-phi_h.sin(), phi_h.cos(), 0.0);
            let x = y.cross(h);
            let d = theta_d.sin() * (phi_d.cos() * x + phi_d.sin() * y);
            let (l, v) = (world(theta_d.cos() * h + d), world(theta_d.cos() * h - d));
            let g = Geometry::new(l, v, n.as_vec3(), None).unwrap();
            if g.nl <= 0.0 {
                continue;
            }
            let want = if inside { Vec3::ONE } else { Vec3::ZERO };
            assert_eq!(level(&toon, &g), want, "theta_h = edge {:+e}, i = {i}", theta_h - edge);
        }
    }
}
