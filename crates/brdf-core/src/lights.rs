//! Analytic light sources of real-time local illumination (Akenine-Möller et al., *Real-Time
//! Rendering* 4th ed., §5.2): directional, point and spot lights, with the distance attenuation of the
//! Phong illumination model `f(d) = 1/(c1 + c2 d + c3 d²)` (Foley, van Dam, Feiner & Hughes, *Computer
//! Graphics: Principles and Practice* 2nd ed., §16.1).
//!
//! A light answers one question, [`Light::incident`]: at a surface point `p`, from which unit direction
//! `l` (pointing **toward** the light, the convention of the reflectance models) does light arrive, and with
//! which irradiance
//! `E` on a surface facing the light (the `E` of `L_o = f_r · E · max(n·l, 0)`)? The renderer then adds
//! `E · shade(l, v, n)` (see [`crate::illumination`]).
//!
//! Units: a directional light's `color` is an irradiance [W/m²] (per RGB channel); a point or spot
//! light's `intensity` is a radiant intensity [W/sr], divided by the attenuation denominator (which has
//! units of m² for the inverse-square law). With the polynomial the result is Foley et al.'s
//! `f(d) · I_i` exactly (a unitless convention). Each is what the light emits: the Python lights take a
//! colour and an intensity on every kind (glTF's `KHR_lights_punctual` convention) and store their
//! product here.

use glam::Vec3;

use crate::BrdfError;
use crate::simd::{Lane, V3};

/// How a point or spot light's intensity falls off with the distance `d` to the surface point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Attenuation {
    /// No falloff: `E = I` at any distance (a "light at infinity" used at a finite place).
    None,
    /// The physical inverse-square law `E = I / d²` (radiometry: intensity over distance squared).
    InverseSquare,
    /// The Phong model's distance factor `E = I / (c1 + c2·d + c3·d²)` (Foley et al. 2nd ed.,
    /// §16.1). Coefficients are ≥ 0 and not all zero. Foley et al. clamp the factor to ≤ 1; it is
    /// not clamped here (the form of most course texts), so `c1 < 1` brightens nearby points.
    Polynomial {
        /// Constant term.
        c1: f32,
        /// Linear term [1/m].
        c2: f32,
        /// Quadratic term [1/m²].
        c3: f32,
    },
}

impl Attenuation {
    /// The factor multiplying the intensity at distance `d ≥ 0`: 1, `1/d²` or `1/(c1 + c2 d + c3 d²)`,
    /// per lane. `+∞`-free: a zero denominator (the light exactly at the point) gives 0, see
    /// [`Light::incident`].
    #[inline(always)]
    pub fn factor<F: Lane>(&self, d: F) -> F {
        let denom = match *self {
            Attenuation::None => return F::splat(1.0),
            Attenuation::InverseSquare => d * d,
            Attenuation::Polynomial { c1, c2, c3 } => F::splat(c1) + d * (F::splat(c2) + d * F::splat(c3)),
        };
        let zero = F::splat(0.0);
        F::select(denom.gt(zero), F::splat(1.0) / denom, zero)
    }

    fn validate(&self) -> Result<(), BrdfError> {
        if let Attenuation::Polynomial { c1, c2, c3 } = *self {
            let ok = [c1, c2, c3].iter().all(|c| c.is_finite() && *c >= 0.0);
            if !ok || c1 + c2 + c3 <= 0.0 {
                return Err(BrdfError::param(
                    "attenuation",
                    format!(
                        "polynomial coefficients must be finite, ≥ 0 and not all zero, got \
                         c1={c1}, c2={c2}, c3={c3}"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// What arrives at a surface point from one light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Incident {
    /// Unit direction from the surface point **toward** the light.
    pub l: Vec3,
    /// Irradiance on a surface facing the light, per RGB channel (`E` in `L_o = f_r·E·max(n·l,0)`).
    pub irradiance: Vec3,
    /// Distance to the light (`f32::INFINITY` for a directional light); shadow rays stop there.
    pub distance: f32,
}

/// A light source: directional, point, or spot with an inner and an outer cone.
///
/// Build through [`Light::directional`], [`Light::point`] and [`Light::spot`], which validate; a
/// `Light` built by hand is checked again by [`Light::validate`] before a renderer uses it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Light from one direction everywhere (the sun).
    Directional {
        /// The direction in which the light **travels** (unit); the surface sees it from `−direction`.
        direction: Vec3,
        /// Irradiance on a surface facing the light, per channel.
        color: Vec3,
    },
    /// An infinitesimally small light at a position.
    Point {
        /// Position of the light.
        position: Vec3,
        /// Radiant intensity per channel.
        intensity: Vec3,
        /// Distance falloff.
        attenuation: Attenuation,
    },
    /// A point light restricted to a cone: full intensity inside the inner
    /// angle, none outside the outer angle, and a smooth falloff in between (see [`spot_falloff`]).
    Spot {
        /// Position of the light.
        position: Vec3,
        /// Axis of the cone, the direction the light shines toward (unit).
        direction: Vec3,
        /// Radiant intensity on the axis, per channel.
        intensity: Vec3,
        /// Half-angle of the fully lit cone θ_i (radians), `0 ≤ θ_i ≤ θ_o`.
        inner_angle: f32,
        /// Half-angle beyond which nothing is lit θ_o (radians), `θ_o < π`.
        outer_angle: f32,
        /// Distance falloff.
        attenuation: Attenuation,
    },
}

/// Smooth cone falloff of a spot light: `smoothstep(t)` = `t²(3 − 2t)` of
/// `t = (cos α − cos θ_o) / (cos θ_i − cos θ_o)` clamped to [0, 1], where `α` is the angle between the
/// spot axis and the direction from the light to the point. 1 inside the inner cone, 0 outside the outer
/// one, C¹-continuous in between (Akenine-Möller et al., *Real-Time Rendering* 4th ed., §5.2.2, which
/// lists smoothstep and `t²` as the usual choices). When
/// `θ_i = θ_o` the cone has a hard edge.
#[inline(always)]
pub fn spot_falloff<F: Lane>(cos_alpha: F, cos_inner: f32, cos_outer: f32) -> F {
    let (ci, co) = (F::splat(cos_inner), F::splat(cos_outer));
    let t = ((cos_alpha - co) / (F::splat(cos_inner - cos_outer))).clamp(0.0, 1.0);
    let smooth = t * t * (F::splat(3.0) - F::splat(2.0) * t);
    // cos α ≤ cos θ_o: 0; cos α ≥ cos θ_i: 1 (also when θ_i = θ_o, where `smooth` is 0/0).
    let inside = F::select(cos_alpha.lt(ci), smooth, F::splat(1.0));
    F::select(cos_alpha.gt(co), inside, F::splat(0.0))
}

fn check_color(name: &str, c: Vec3) -> Result<(), BrdfError> {
    if !c.is_finite() || c.min_element() < 0.0 {
        return Err(BrdfError::param(name, format!("must be finite and ≥ 0 per channel, got {c}")));
    }
    Ok(())
}

fn check_unit(name: &str, d: Vec3) -> Result<Vec3, BrdfError> {
    let len = d.length();
    if !(len > 0.0) || !len.is_finite() {
        return Err(BrdfError::param(name, format!("must be a finite non-zero vector, got {d}")));
    }
    Ok(d / len)
}

fn check_point(name: &str, p: Vec3) -> Result<(), BrdfError> {
    if !p.is_finite() {
        return Err(BrdfError::param(name, format!("must be finite, got {p}")));
    }
    Ok(())
}

impl Light {
    /// A directional light travelling along `direction` (normalised here) with irradiance `color`.
    pub fn directional(direction: Vec3, color: Vec3) -> Result<Self, BrdfError> {
        let direction = check_unit("direction", direction)?;
        check_color("color", color)?;
        Ok(Light::Directional { direction, color })
    }

    /// A point light at `position` with radiant intensity `intensity`.
    pub fn point(position: Vec3, intensity: Vec3, attenuation: Attenuation) -> Result<Self, BrdfError> {
        check_point("position", position)?;
        check_color("intensity", intensity)?;
        attenuation.validate()?;
        Ok(Light::Point { position, intensity, attenuation })
    }

    /// A spot light at `position` shining along `direction` (normalised here), full intensity within
    /// `inner_angle` of the axis, falling smoothly to 0 at `outer_angle` (radians,
    /// `0 ≤ inner ≤ outer < π`).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        inner_angle: f32,
        outer_angle: f32,
        attenuation: Attenuation,
    ) -> Result<Self, BrdfError> {
        check_point("position", position)?;
        let direction = check_unit("direction", direction)?;
        check_color("intensity", intensity)?;
        if !(outer_angle > 0.0 && outer_angle < std::f32::consts::PI) {
            return Err(BrdfError::param(
                "outer_angle",
                format!("must lie in (0, π) rad, got {outer_angle}"),
            ));
        }
        if !(inner_angle >= 0.0 && inner_angle <= outer_angle) {
            return Err(BrdfError::param(
                "inner_angle",
                format!("must lie in [0, outer_angle = {outer_angle}] rad, got {inner_angle}"),
            ));
        }
        attenuation.validate()?;
        Ok(Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation })
    }

    /// Check a light built by hand with the rules of the constructors (directions must be unit
    /// length within 1e-3 here, since they are not normalised again).
    pub fn validate(&self) -> Result<(), BrdfError> {
        let unit = |name: &str, d: Vec3| -> Result<(), BrdfError> {
            if !d.is_finite() || (d.length() - 1.0).abs() > 1e-3 {
                return Err(BrdfError::param(name, format!("must be a unit vector, got {d}")));
            }
            Ok(())
        };
        match *self {
            Light::Directional { direction, color } => {
                unit("direction", direction)?;
                check_color("color", color)
            }
            Light::Point { position, intensity, attenuation } => {
                Light::point(position, intensity, attenuation).map(|_| ())
            }
            Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation } => {
                unit("direction", direction)?;
                Light::spot(position, direction, intensity, inner_angle, outer_angle, attenuation).map(|_| ())
            }
        }
    }

    /// The light arriving at surface point `p`: unit direction `l` toward the light, irradiance `E` on
    /// a surface facing it, and the distance to the light.
    ///
    /// - Directional: `l = −direction`, `E = color`, distance `∞`.
    /// - Point: `l = (p_l − p)/d`, `E = I · att(d)` with `d = |p_l − p|`.
    /// - Spot: as a point light, times [`spot_falloff`] of `cos α = (−l)·axis`.
    ///
    /// `None` when nothing arrives: `p` at the light's position (no direction exists), outside the
    /// spot's outer cone, or zero irradiance. [`Light::incident_lanes`] with one lane.
    #[inline]
    pub fn incident(&self, p: Vec3) -> Option<Incident> {
        self.incident_lanes::<f32>(V3::splat(p)).lane(0)
    }

    /// [`Light::incident`] at `F::LANES` points at once: the formula of every light type, written once
    /// over lanes (the one-sample form is this with `F = f32`).
    #[inline(always)]
    pub fn incident_lanes<F: Lane>(&self, p: V3<F>) -> IncidentLanes<F> {
        let zero = F::splat(0.0);
        let black = |e: &V3<F>| e.x.eq(zero) & e.y.eq(zero) & e.z.eq(zero);
        match *self {
            Light::Directional { direction, color } => IncidentLanes {
                l: V3::splat(-direction),
                irradiance: V3::splat(color),
                distance: F::splat(f32::INFINITY),
                arrives: F::mask_splat(color != Vec3::ZERO),
            },
            Light::Point { position, intensity, attenuation } => {
                let (l, d, ok) = toward(position, p);
                let irradiance = V3::splat(intensity).scale(attenuation.factor(d));
                IncidentLanes { l, irradiance, distance: d, arrives: ok & !black(&irradiance) }
            }
            Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation } => {
                let (l, d, ok) = toward(position, p);
                // (−l)·axis as l·(−axis): negation is exact, so the products are the same numbers.
                let cone = spot_falloff(l.dot(V3::splat(-direction)), inner_angle.cos(), outer_angle.cos());
                let irradiance = V3::splat(intensity).scale(cone * attenuation.factor(d));
                let arrives = ok & !cone.eq(zero) & !black(&irradiance);
                IncidentLanes { l, irradiance, distance: d, arrives }
            }
        }
    }
}

/// [`Incident`] at `F::LANES` points at once (see [`Light::incident_lanes`]).
#[derive(Debug, Clone, Copy)]
pub struct IncidentLanes<F: Lane> {
    /// Unit direction toward the light.
    pub l: V3<F>,
    /// Irradiance on a surface facing the light.
    pub irradiance: V3<F>,
    /// Distance to the light (`∞` for a directional light).
    pub distance: F,
    /// Lanes where light arrives ([`Light::incident`] returns `Some`); the other lanes hold anything.
    pub arrives: F::Mask,
}

impl<F: Lane> IncidentLanes<F> {
    /// Lane `i` as an [`Incident`], `None` where nothing arrives.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Option<Incident> {
        F::mask_lane(self.arrives, i).then(|| Incident {
            l: self.l.lane(i),
            irradiance: self.irradiance.lane(i),
            distance: self.distance.lane(i),
        })
    }
}

/// Unit direction from `p` to `position`, the distance, and the lanes where they exist (not where the
/// two coincide or the distance overflows).
#[inline(always)]
fn toward<F: Lane>(position: Vec3, p: V3<F>) -> (V3<F>, F, F::Mask) {
    let to = V3::splat(position) - p;
    let d2 = to.dot(to);
    let ok = d2.gt(F::splat(0.0)) & d2.is_finite();
    let d = d2.sqrt();
    (to / d, d, ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }

    #[test]
    fn directional_light_arrives_from_minus_its_travel_direction() {
        let d = Vec3::new(-1.0, -1.0, -1.0);
        let light = Light::directional(d, Vec3::ONE).unwrap();
        let inc = light.incident(Vec3::new(5.0, -3.0, 2.0)).unwrap();
        assert!(close(inc.l, Vec3::splat(1.0 / 3f32.sqrt()), 1e-6));
        assert_eq!(inc.irradiance, Vec3::ONE);
        assert!(inc.distance.is_infinite());
    }

    #[test]
    fn point_light_follows_the_inverse_square_law() {
        // SCENE.md's point light at (2,2,2), I = 10, seen from (0,0,1): d² = 4 + 4 + 1 = 9.
        let light = Light::point(Vec3::splat(2.0), Vec3::splat(10.0), Attenuation::InverseSquare).unwrap();
        let inc = light.incident(Vec3::Z).unwrap();
        assert!(close(inc.irradiance, Vec3::splat(10.0 / 9.0), 1e-6));
        assert!(close(inc.l, Vec3::new(2.0, 2.0, 1.0) / 3.0, 1e-6));
        assert!((inc.distance - 3.0).abs() < 1e-6);
        // Doubling the distance quarters the irradiance.
        let far = light.incident(Vec3::splat(2.0) - 2.0 * Vec3::new(2.0, 2.0, 1.0)).unwrap();
        assert!(close(far.irradiance * 4.0, inc.irradiance, 1e-6));
    }

    #[test]
    fn polynomial_attenuation_is_the_course_distance_factor() {
        let att = Attenuation::Polynomial { c1: 1.0, c2: 0.5, c3: 0.25 };
        let d = 2.0f32;
        assert!((att.factor(d) - 1.0 / (1.0 + 0.5 * d + 0.25 * d * d)).abs() < 1e-7);
        assert_eq!(Attenuation::None.factor(1e6f32), 1.0);
        assert!(
            Light::point(Vec3::ZERO, Vec3::ONE, Attenuation::Polynomial { c1: 0.0, c2: 0.0, c3: 0.0 })
                .is_err()
        );
        assert!(
            Light::point(Vec3::ZERO, Vec3::ONE, Attenuation::Polynomial { c1: -1.0, c2: 0.0, c3: 1.0 })
                .is_err()
        );
    }

    #[test]
    fn spot_light_is_full_inside_zero_outside_and_smooth_between() {
        let (inner, outer) = (0.2f32, 0.4f32);
        let light = Light::spot(Vec3::ZERO, Vec3::NEG_Z, Vec3::ONE, inner, outer, Attenuation::None).unwrap();
        let at_angle = |a: f32| Vec3::new(a.sin(), 0.0, -a.cos()) * 3.0;
        assert_eq!(light.incident(at_angle(0.0)).unwrap().irradiance, Vec3::ONE);
        assert_eq!(light.incident(at_angle(0.19)).unwrap().irradiance, Vec3::ONE);
        assert!(light.incident(at_angle(0.41)).is_none());
        // Monotone decreasing in between, and the midpoint in cos is exactly smoothstep(0.5) = 0.5.
        let mut last = 1.0;
        for k in 1..20 {
            let a = inner + (outer - inner) * k as f32 / 20.0;
            let e = light.incident(at_angle(a)).unwrap().irradiance.x;
            assert!(e < last && e > 0.0, "angle {a}: {e} after {last}");
            last = e;
        }
        let cos_mid = 0.5 * (inner.cos() + outer.cos());
        assert!((spot_falloff(cos_mid, inner.cos(), outer.cos()) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn nothing_arrives_at_the_light_position_and_bad_lights_are_refused() {
        let light = Light::point(Vec3::ONE, Vec3::ONE, Attenuation::InverseSquare).unwrap();
        assert!(light.incident(Vec3::ONE).is_none());
        assert!(Light::directional(Vec3::ZERO, Vec3::ONE).is_err());
        assert!(Light::directional(Vec3::X, Vec3::new(1.0, -1.0, 0.0)).is_err());
        assert!(Light::point(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE, Attenuation::None).is_err());
        assert!(Light::spot(Vec3::ZERO, Vec3::Z, Vec3::ONE, 0.5, 0.4, Attenuation::None).is_err());
        assert!(Light::spot(Vec3::ZERO, Vec3::Z, Vec3::ONE, 0.1, 3.2, Attenuation::None).is_err());
        let hand = Light::Directional { direction: Vec3::new(0.0, 0.0, 2.0), color: Vec3::ONE };
        assert!(hand.validate().is_err());
    }

    /// The one-sample code before `incident` became the lane code with one lane, kept here to show
    /// that the bits did not move (renders and their references stay the same).
    fn reference_incident(light: &Light, p: Vec3) -> Option<Incident> {
        let toward = |position: Vec3| {
            let to = position - p;
            let d2 = to.length_squared();
            (d2 > 0.0 && d2.is_finite()).then(|| (to / d2.sqrt(), d2.sqrt()))
        };
        let factor = |a: Attenuation, d: f32| {
            let denom = match a {
                Attenuation::None => return 1.0,
                Attenuation::InverseSquare => d * d,
                Attenuation::Polynomial { c1, c2, c3 } => c1 + d * (c2 + d * c3),
            };
            if denom > 0.0 { 1.0 / denom } else { 0.0 }
        };
        let falloff = |ca: f32, ci: f32, co: f32| {
            if ca <= co {
                return 0.0;
            }
            if ca >= ci {
                return 1.0;
            }
            let t = ((ca - co) / (ci - co)).clamp(0.0, 1.0);
            t * t * (3.0 - 2.0 * t)
        };
        match *light {
            Light::Directional { direction, color } => (color != Vec3::ZERO).then_some(Incident {
                l: -direction,
                irradiance: color,
                distance: f32::INFINITY,
            }),
            Light::Point { position, intensity, attenuation } => {
                let (l, d) = toward(position)?;
                let irradiance = intensity * factor(attenuation, d);
                (irradiance != Vec3::ZERO).then_some(Incident { l, irradiance, distance: d })
            }
            Light::Spot { position, direction, intensity, inner_angle, outer_angle, attenuation } => {
                let (l, d) = toward(position)?;
                let cone = falloff((-l).dot(direction), inner_angle.cos(), outer_angle.cos());
                if cone == 0.0 {
                    return None;
                }
                let irradiance = intensity * (cone * factor(attenuation, d));
                (irradiance != Vec3::ZERO).then_some(Incident { l, irradiance, distance: d })
            }
        }
    }

    #[test]
    fn one_formula_gives_the_previous_one_sample_bits_and_every_lane_the_same() {
        use crate::simd::{F32x8, V3};
        let lights = [
            Light::directional(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 0.5, 0.2)).unwrap(),
            Light::directional(Vec3::Z, Vec3::ZERO).unwrap(),
            Light::point(Vec3::splat(2.0), Vec3::splat(10.0), Attenuation::InverseSquare).unwrap(),
            Light::point(Vec3::X, Vec3::ONE, Attenuation::Polynomial { c1: 0.5, c2: 0.2, c3: 0.1 }).unwrap(),
            Light::point(Vec3::ZERO, Vec3::ONE, Attenuation::None).unwrap(),
            Light::spot(
                Vec3::new(0.0, 2.0, 2.0),
                Vec3::new(0.0, -1.0, -1.0),
                Vec3::ONE,
                0.2,
                0.5,
                Attenuation::None,
            )
            .unwrap(),
            Light::spot(Vec3::Z * 3.0, Vec3::NEG_Z, Vec3::splat(4.0), 0.3, 0.3, Attenuation::InverseSquare)
                .unwrap(),
        ];
        let points: Vec<Vec3> = (0..203)
            .map(|i| match i {
                0 => Vec3::ZERO, // at the point light
                1 => Vec3::X,    // at the polynomial one
                2 => Vec3::splat(f32::MAX),
                _ => {
                    let t = i as f32 * 0.37;
                    Vec3::new(t.sin() * 2.0, (0.7 * t).cos() * 2.0, (1.3 * t).sin())
                }
            })
            .collect();
        let bits = |i: Option<Incident>| {
            i.map(|i| [i.l, i.irradiance, Vec3::splat(i.distance)].map(|v| v.to_array().map(f32::to_bits)))
        };
        for light in &lights {
            for group in points.chunks(8) {
                let at = |i: usize| group[i.min(group.len() - 1)];
                let lanes = light.incident_lanes(V3::<F32x8>::from_fn(at));
                for (i, &p) in group.iter().enumerate() {
                    let want = bits(reference_incident(light, p));
                    assert_eq!(bits(light.incident(p)), want, "{light:?} at {p}");
                    assert_eq!(bits(lanes.lane(i)), want, "{light:?} at {p}, lane {i}");
                }
            }
        }
    }
}
