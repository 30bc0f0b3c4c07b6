//! Area lights: a sphere and a rectangle (in general a parallelogram) emitting a constant radiance
//! `L_e` \[W/(m²·sr), per RGB channel\] from their surface, giving soft shadows.
//!
//! Unlike the punctual lights of [`brdf_core::lights`], an area light has no single direction: the
//! radiance it reflects toward the viewer is the integral over the solid angle `Ω` it subtends,
//!
//! ```text
//! L_o(v) = ∫_Ω L_e V(p, l) f_r(l, v) cos θ_l dω_l ,
//! ```
//!
//! estimated by [`crate::area_lighting`] with multiple importance sampling between the light's own
//! sampler ([`AreaLight::sample`]) and the material's ([`brdf_core::sampling`]). What this file gives
//! is each light's geometry: drawing a direction toward it with a solid-angle density, the density of
//! a given direction (where the ray hits it, [`AreaLight::hit`]), and the unoccluded vector irradiance
//! ([`AreaLight::irradiance_vector`]).
//!
//! ## Sphere (centre `c`, radius `r`)
//! Seen from `p` at distance `d > r` the sphere fills the cone of half-angle `α`, `sin α = r/d`. Its
//! directions are drawn uniformly in that cone (Shirley, Wang & Zimmerman 1996, "Monte Carlo techniques
//! for direct lighting calculations", ACM TOG 15(1); Pharr, Jakob & Humphreys, *Physically Based
//! Rendering* 4th ed., §6.2.4 "Sphere sampling"): `1 − cos θ = u₀ (1 − cos α)`, `φ = 2π u₁`, with the
//! constant density `p(ω) = 1 / (2π (1 − cos α))`, `1 − cos α = sin²α / (1 + cos α)` computed without
//! cancellation for small lights. Only the outside emits: a point inside the sphere receives nothing.
//! A sphere fully above a surface's horizon gives the irradiance `E = π L_e sin²α cos θ_c` exactly
//! (θ_c the angle between the normal and the direction to the centre), the irradiance of a point light
//! of intensity `I = L_e π r²` at the centre.
//!
//! ## Rectangle (centre `c`, edges `e₀`, `e₁`)
//! The corners are `c ± e₀/2 ± e₁/2`; the emitting side is that of `N = e₀ × e₁` (both sides when
//! two-sided), area `A = |N|`. A point `q` is drawn uniformly on the area and converted to solid angle
//! (Pharr et al. 4th ed., §4.2.3, eq. 4.9): `p(ω) = t² / (A |cos θ_q|)`, `t = |q − p|`, `θ_q` the angle
//! between the light's normal and `−ω`. Lambert's formula for the irradiance of a polygon (Lambert
//! 1760; Baum, Rushmeier & Winget 1989; Arvo 1995, "Applications of irradiance tensors to the
//! simulation of non-Lambertian phenomena", SIGGRAPH) gives the vector irradiance
//! `Φ = L_e/2 Σ_i γ_i û_i` (`γ_i` the angle subtended by edge `i`, `û_i` the unit normal of the plane
//! through `p` and that edge), and `E = Φ·n` on a surface that sees the whole polygon.

use std::f32::consts::PI;

use glam::Vec3;

use crate::RasterError;

/// A light with a surface: a sphere or a parallelogram emitting a constant radiance.
///
/// Build through [`AreaLight::sphere`] and [`AreaLight::rect`], which validate; a light built by hand is
/// checked again by [`AreaLight::validate`] before a render uses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AreaLight {
    /// A sphere emitting `radiance` outward from every point of its surface.
    Sphere {
        /// Centre (world).
        center: Vec3,
        /// Radius, > 0.
        radius: f32,
        /// Emitted radiance per channel \[W/(m²·sr)\].
        radiance: Vec3,
    },
    /// A parallelogram (a rectangle when the edges are perpendicular) with corners
    /// `center ± edge0/2 ± edge1/2`, emitting on the side of `edge0 × edge1` (both sides when `two_sided`).
    Rect {
        /// Centre (world).
        center: Vec3,
        /// First edge vector (its full length).
        edge0: Vec3,
        /// Second edge vector.
        edge1: Vec3,
        /// Emitted radiance per channel \[W/(m²·sr)\].
        radiance: Vec3,
        /// Emits from both sides.
        two_sided: bool,
    },
}

/// A direction drawn toward an area light from a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point toward the light.
    pub l: Vec3,
    /// Distance to the sampled point on the light (a shadow ray stops there).
    pub distance: f32,
    /// Solid-angle density \[1/sr\] of drawing `l`, > 0.
    pub pdf: f32,
}

fn check_finite(name: &'static str, v: Vec3) -> Result<(), RasterError> {
    if !v.is_finite() {
        return Err(RasterError::arg(name, format!("must be finite, got {v}")));
    }
    Ok(())
}

fn check_radiance(r: Vec3) -> Result<(), RasterError> {
    if !r.is_finite() || r.min_element() < 0.0 {
        return Err(RasterError::arg("radiance", format!("must be finite and ≥ 0 per channel, got {r}")));
    }
    Ok(())
}

impl AreaLight {
    /// A sphere light. Refused (naming the argument): a non-finite centre, a radius that is not
    /// finite and > 0 (or whose square overflows), a radiance that is not finite and ≥ 0.
    pub fn sphere(center: Vec3, radius: f32, radiance: Vec3) -> Result<Self, RasterError> {
        check_finite("center", center)?;
        if !(radius > 0.0) || !(radius * radius).is_finite() || !(radius * radius > 0.0) {
            return Err(RasterError::arg(
                "radius",
                format!("must be finite and > 0 (with a finite, non-zero square), got {radius}"),
            ));
        }
        check_radiance(radiance)?;
        Ok(Self::Sphere { center, radius, radiance })
    }

    /// A rectangle (parallelogram) light. Refused (naming the argument): non-finite vectors, a zero
    /// edge, parallel edges or an area that underflows or overflows (a degenerate rectangle), a
    /// radiance that is not finite and ≥ 0.
    pub fn rect(
        center: Vec3,
        edge0: Vec3,
        edge1: Vec3,
        radiance: Vec3,
        two_sided: bool,
    ) -> Result<Self, RasterError> {
        check_finite("center", center)?;
        for (name, e) in [("edge0", edge0), ("edge1", edge1)] {
            check_finite(name, e)?;
            let len = e.length();
            if !(len > 0.0) || !len.is_finite() {
                return Err(RasterError::arg(
                    name,
                    format!("must be a non-zero edge vector with a finite, non-zero float32 length, got {e}"),
                ));
            }
        }
        let area = edge0.cross(edge1).length();
        let scale = edge0.length() * edge1.length();
        if !(area > 1e-6 * scale) || !area.is_finite() || !(area > f32::MIN_POSITIVE) {
            return Err(RasterError::arg(
                "edge0, edge1",
                format!(
                    "span a degenerate rectangle (area |edge0 × edge1| = {area}): the edges must be \
                     non-parallel with a finite, non-zero area, got {edge0} and {edge1}"
                ),
            ));
        }
        check_radiance(radiance)?;
        Ok(Self::Rect { center, edge0, edge1, radiance, two_sided })
    }

    /// Check a light built by hand with the constructors' rules.
    pub fn validate(&self) -> Result<(), RasterError> {
        match *self {
            Self::Sphere { center, radius, radiance } => Self::sphere(center, radius, radiance).map(|_| ()),
            Self::Rect { center, edge0, edge1, radiance, two_sided } => {
                Self::rect(center, edge0, edge1, radiance, two_sided).map(|_| ())
            }
        }
    }

    /// The emitted radiance \[W/(m²·sr)\].
    #[inline]
    pub fn radiance(&self) -> Vec3 {
        match *self {
            Self::Sphere { radiance, .. } | Self::Rect { radiance, .. } => radiance,
        }
    }

    /// Draw a direction from `p` toward the light with `u ∈ [0, 1)²` (module docs); `None` where the
    /// light sends nothing to `p` (inside the sphere, behind a one-sided rectangle, in its plane).
    #[inline]
    pub fn sample(&self, p: Vec3, u: [f32; 2]) -> Option<LightSample> {
        match *self {
            Self::Sphere { center, radius, .. } => {
                let cone = Cone::new(center, radius, p)?;
                let x = u[0] * cone.one_minus_cos; // 1 − cos θ, uniform in [0, 1 − cos α)
                let cos = 1.0 - x;
                let sin = (x * (2.0 - x)).max(0.0).sqrt();
                let phi = 2.0 * PI * u[1];
                let (a, b) = cone.w.any_orthonormal_pair();
                let l = (a * (sin * phi.cos()) + b * (sin * phi.sin()) + cone.w * cos).normalize_or_zero();
                // The near intersection along l: t = d cos θ − √(r² − d² sin²θ).
                let h = (radius * radius - cone.d * cone.d * (sin * sin)).max(0.0).sqrt();
                let distance = (cone.d * cos - h).max(0.0);
                (l != Vec3::ZERO && cone.pdf > 0.0).then_some(LightSample { l, distance, pdf: cone.pdf })
            }
            Self::Rect { center, edge0, edge1, two_sided, .. } => {
                let plane = Plane::new(edge0, edge1);
                if !two_sided && !(plane.n.dot(p - center) > 0.0) {
                    return None;
                }
                let q = center + edge0 * (u[0] - 0.5) + edge1 * (u[1] - 0.5);
                let to = q - p;
                let t2 = to.length_squared();
                let t = t2.sqrt();
                if !(t > 0.0) || !t.is_finite() {
                    return None;
                }
                let l = to / t;
                let cos = l.dot(plane.n).abs();
                let pdf = t2 / (plane.area * cos);
                (cos > 0.0 && pdf.is_finite() && pdf > 0.0).then_some(LightSample { l, distance: t, pdf })
            }
        }
    }

    /// Where the ray from `p` along unit `l` meets the light's emitting side: `(distance, pdf)` with
    /// `pdf` the solid-angle density with which [`AreaLight::sample`] draws `l` from `p`; `None` when
    /// the ray misses (or meets the back of a one-sided rectangle, or starts inside the sphere).
    #[inline]
    pub fn hit(&self, p: Vec3, l: Vec3) -> Option<(f32, f32)> {
        match *self {
            Self::Sphere { center, radius, .. } => {
                let cone = Cone::new(center, radius, p)?;
                let to = center - p;
                let b = to.dot(l);
                if !(b > 0.0) {
                    return None;
                }
                let perp2 = (to - l * b).length_squared();
                let r2 = radius * radius;
                if !(perp2 <= r2) {
                    return None;
                }
                Some(((b - (r2 - perp2).sqrt()).max(0.0), cone.pdf))
            }
            Self::Rect { center, edge0, edge1, two_sided, .. } => {
                let plane = Plane::new(edge0, edge1);
                let denom = l.dot(plane.n);
                // A one-sided light is met from its front: travelling against its normal.
                if denom == 0.0 || (!two_sided && denom > 0.0) {
                    return None;
                }
                let t = (center - p).dot(plane.n) / denom;
                if !(t > 0.0) || !t.is_finite() {
                    return None;
                }
                let dq = p + l * t - center;
                let nn = plane.big_n.length_squared();
                let a = dq.cross(edge1).dot(plane.big_n) / nn;
                let b = edge0.cross(dq).dot(plane.big_n) / nn;
                if !(a.abs() <= 0.5 && b.abs() <= 0.5) {
                    return None;
                }
                let pdf = t * t / (plane.area * denom.abs());
                (pdf.is_finite() && pdf > 0.0).then_some((t, pdf))
            }
        }
    }

    /// The vector irradiance `Φ/L_e` at `p` (geometry only; multiply by the radiance): the irradiance
    /// on a surface with unit normal `n` that sees the whole light above its horizon is
    /// `L_e ∘ (Φ/L_e)·n` (module docs). Zero where the light sends nothing to `p`.
    pub fn irradiance_vector(&self, p: Vec3) -> Vec3 {
        match *self {
            Self::Sphere { center, radius, .. } => {
                let to = center - p;
                let d2 = to.length_squared();
                if !(d2 > radius * radius) {
                    return Vec3::ZERO;
                }
                to.normalize_or_zero() * (PI * radius * radius / d2)
            }
            Self::Rect { center, edge0, edge1, two_sided, .. } => {
                let plane = Plane::new(edge0, edge1);
                let side = plane.n.dot(p - center);
                if side == 0.0 || (!two_sided && side < 0.0) {
                    return Vec3::ZERO;
                }
                let corners = [
                    center - 0.5 * edge0 - 0.5 * edge1,
                    center + 0.5 * edge0 - 0.5 * edge1,
                    center + 0.5 * edge0 + 0.5 * edge1,
                    center - 0.5 * edge0 + 0.5 * edge1,
                ];
                let r = corners.map(|c| (c - p).normalize_or_zero());
                let mut phi = Vec3::ZERO;
                for i in 0..4 {
                    let (a, b) = (r[i], r[(i + 1) % 4]);
                    let gamma = a.dot(b).clamp(-1.0, 1.0).acos();
                    phi += a.cross(b).normalize_or_zero() * gamma;
                }
                // Corners run counter-clockwise about N: Φ points away from the light for a point in
                // front; orient it toward the light (the polygon is convex).
                let phi = 0.5 * phi;
                if phi.dot(center - p) < 0.0 { -phi } else { phi }
            }
        }
    }
}

/// The cone a sphere subtends from an outside point.
struct Cone {
    /// Unit direction to the centre.
    w: Vec3,
    /// Distance to the centre.
    d: f32,
    /// `1 − cos α`, from `sin²α / (1 + cos α)`.
    one_minus_cos: f32,
    /// `1 / (2π (1 − cos α))`.
    pdf: f32,
}

impl Cone {
    #[inline]
    fn new(center: Vec3, radius: f32, p: Vec3) -> Option<Self> {
        let to = center - p;
        let d2 = to.length_squared();
        let r2 = radius * radius;
        if !(d2 > r2) || !d2.is_finite() {
            return None;
        }
        let d = d2.sqrt();
        let sin2 = r2 / d2;
        let cos = (1.0 - sin2).max(0.0).sqrt();
        let one_minus_cos = sin2 / (1.0 + cos);
        let pdf = 1.0 / (2.0 * PI * one_minus_cos);
        (one_minus_cos > 0.0 && pdf.is_finite()).then_some(Self { w: to / d, d, one_minus_cos, pdf })
    }
}

/// A parallelogram's plane.
struct Plane {
    /// `edge0 × edge1`.
    big_n: Vec3,
    /// Its unit vector.
    n: Vec3,
    /// `|edge0 × edge1|`.
    area: f32,
}

impl Plane {
    #[inline]
    fn new(edge0: Vec3, edge1: Vec3) -> Self {
        let big_n = edge0.cross(edge1);
        let area = big_n.length();
        Self { big_n, n: big_n / area, area }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_core::sampling::rng;

    fn u2(k: u64) -> [f32; 2] {
        [rng::uniform_keyed(3, k, 0), rng::uniform_keyed(3, k, 1)]
    }

    fn lights() -> Vec<AreaLight> {
        vec![
            AreaLight::sphere(Vec3::new(0.3, 2.0, -0.2), 0.5, Vec3::ONE).unwrap(),
            AreaLight::sphere(Vec3::new(0.0, 50.0, 0.0), 0.01, Vec3::ONE).unwrap(),
            AreaLight::rect(
                Vec3::new(0.2, 1.5, 0.1),
                Vec3::new(1.0, 0.0, 0.2),
                Vec3::new(0.0, 0.0, 0.7),
                Vec3::ONE,
                false,
            )
            .unwrap(),
            AreaLight::rect(
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::X * 2.0,
                Vec3::new(0.5, 0.0, 1.0),
                Vec3::ONE,
                true,
            )
            .unwrap(),
        ]
    }

    #[test]
    fn a_sampled_direction_hits_the_light_at_its_distance_with_its_density() {
        let p = Vec3::new(0.1, 0.0, 0.05);
        for light in lights() {
            for k in 0..2000 {
                let Some(s) = light.sample(p, u2(k)) else { panic!("{light:?} sends nothing") };
                let (t, pdf) = light.hit(p, s.l).unwrap_or_else(|| panic!("{light:?}: {s:?} misses"));
                assert!((t - s.distance).abs() <= 1e-3 * t.max(1.0), "{light:?}: {t} vs {s:?}");
                assert!((pdf - s.pdf).abs() <= 2e-3 * pdf, "{light:?}: {pdf} vs {s:?}");
            }
        }
    }

    #[test]
    fn the_density_integrates_to_one_over_the_sphere_of_directions() {
        // ∫ pdf(ω) dω over a fine rule of the sphere: 1 (the density is normalised on the light).
        let q = brdf_core::sh::Quadrature::new(600, 1200).unwrap();
        let p = Vec3::new(0.1, 0.0, 0.05);
        for light in &lights()[..1] {
            let total: f64 = q
                .dirs
                .iter()
                .zip(&q.weights)
                .map(|(d, w)| light.hit(p, d.as_vec3().normalize()).map_or(0.0, |h| f64::from(h.1)) * w)
                .sum();
            assert!((total - 1.0).abs() < 2e-2, "{light:?}: {total}");
        }
        let rect = lights()[2];
        let total: f64 = q
            .dirs
            .iter()
            .zip(&q.weights)
            .map(|(d, w)| rect.hit(p, d.as_vec3().normalize()).map_or(0.0, |h| f64::from(h.1)) * w)
            .sum();
        assert!((total - 1.0).abs() < 2e-2, "rect: {total}");
    }

    #[test]
    fn the_estimated_irradiance_is_lamberts() {
        // E(n) = ∫ L cos dω = E[cos / pdf] over the light's own samples, against Φ·n.
        let p = Vec3::new(0.1, 0.0, 0.05);
        let n = Vec3::new(0.1, 1.0, 0.05).normalize();
        for light in lights() {
            let count = 40_000;
            let mut sum = 0.0f64;
            for k in 0..count {
                let s = light.sample(p, u2(k)).unwrap();
                sum += f64::from(s.l.dot(n).max(0.0) / s.pdf);
            }
            let e = sum / count as f64;
            let want = f64::from(light.irradiance_vector(p).dot(n));
            assert!((e - want).abs() < 0.01 * want, "{light:?}: {e} vs Lambert {want}");
        }
        // The sphere: π sin²α facing the centre.
        let s = AreaLight::sphere(Vec3::new(0.0, 3.0, 0.0), 1.0, Vec3::ONE).unwrap();
        let phi = s.irradiance_vector(Vec3::ZERO);
        assert!((phi - Vec3::Y * PI / 9.0).length() < 1e-6, "{phi}");
    }

    #[test]
    fn nothing_arrives_from_behind_or_inside_and_bad_lights_are_refused() {
        let sphere = AreaLight::sphere(Vec3::ZERO, 1.0, Vec3::ONE).unwrap();
        assert!(sphere.sample(Vec3::new(0.2, 0.0, 0.0), [0.5, 0.5]).is_none());
        assert!(sphere.hit(Vec3::new(0.2, 0.0, 0.0), Vec3::X).is_none());
        let down = AreaLight::rect(Vec3::Y, Vec3::X, Vec3::Z, Vec3::ONE, false).unwrap(); // X × Z = −Y
        assert!(down.sample(Vec3::ZERO, [0.5, 0.5]).is_some());
        assert!(down.sample(Vec3::Y * 2.0, [0.5, 0.5]).is_none());
        assert!(down.hit(Vec3::Y * 2.0, Vec3::NEG_Y).is_none());
        assert!(down.hit(Vec3::ZERO, Vec3::Y).is_some());
        assert_eq!(down.irradiance_vector(Vec3::Y * 2.0), Vec3::ZERO);
        let both = AreaLight::rect(Vec3::Y, Vec3::X, Vec3::Z, Vec3::ONE, true).unwrap();
        assert!(both.hit(Vec3::Y * 2.0, Vec3::NEG_Y).is_some());
        let name = |e: RasterError| match e {
            RasterError::InvalidArgument { name, .. } => name,
            other => panic!("{other}"),
        };
        assert_eq!(name(AreaLight::sphere(Vec3::ZERO, 0.0, Vec3::ONE).unwrap_err()), "radius");
        assert_eq!(name(AreaLight::sphere(Vec3::ZERO, -1.0, Vec3::ONE).unwrap_err()), "radius");
        assert_eq!(name(AreaLight::sphere(Vec3::ZERO, f32::NAN, Vec3::ONE).unwrap_err()), "radius");
        assert_eq!(name(AreaLight::sphere(Vec3::NAN, 1.0, Vec3::ONE).unwrap_err()), "center");
        assert_eq!(name(AreaLight::sphere(Vec3::ZERO, 1.0, -Vec3::ONE).unwrap_err()), "radiance");
        assert_eq!(
            name(AreaLight::rect(Vec3::ZERO, Vec3::ZERO, Vec3::Z, Vec3::ONE, false).unwrap_err()),
            "edge0"
        );
        assert_eq!(
            name(AreaLight::rect(Vec3::ZERO, Vec3::X, Vec3::INFINITY, Vec3::ONE, false).unwrap_err()),
            "edge1"
        );
        assert_eq!(
            name(AreaLight::rect(Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::ONE, false).unwrap_err()),
            "edge0, edge1"
        );
    }
}
