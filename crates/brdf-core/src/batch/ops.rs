//! The batch forms of the standalone functions: vectors, microfacet terms, Fresnel and tone mapping over
//! [`Arg`]s of any broadcastable shapes, with the checks and conventions of the Python API
//! (`brdfpy.vectors`, `.microfacet`, `.fresnel`, `.tonemap`). Each returns a [`Map`] (or an enum of
//! them): the caller allocates the output from its shape and runs it ([`Map::run`]).
//!
//! Directions are normalised here (they need not be unit length); a zero-length direction gives 0.

// The return types spell out the inputs and the per-element signature: that is the API.
#![allow(clippy::type_complexity)]

use glam::{Vec3, Vec3A};

use super::{Arg, Batch, Check, Map};
use crate::BrdfError;
use crate::frame::ShadingFrame;
use crate::fresnel as fr;
use crate::masking::Masking;
use crate::microfacet::{Distribution, Mixture};
use crate::tonemap::{self as tm, Operator};
use crate::vector::{
    halfway as core_halfway, normalize_or_zero, reflect as core_reflect, refract as core_refract,
};

/// One input of numbers, as a tuple (the form [`Batch::new`] takes).
pub type Numbers<'a> = (Arg<'a, f32>,);
/// Two inputs of vectors.
pub type Vectors2<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>);

/// `w/|w|` for any finite `w`: a very long one (|w|² past the float32 range, |w| > 1.8e19) is shrunk by
/// 2⁻¹⁰⁰ first, exactly, so that its direction is kept rather than lost to an overflow; a zero-length
/// (or non-finite) one gives 0.
#[inline(always)]
fn unit(w: Vec3) -> Vec3A {
    let a = Vec3A::from(w);
    if a.length_squared() == f32::INFINITY && a.is_finite() {
        return normalize_or_zero(a * SHRINK);
    }
    normalize_or_zero(a)
}

/// 2⁻¹⁰⁰: scales the largest float32 to 2.7e8, whose square is far from overflowing.
const SHRINK: f32 = f32::from_bits((127 - 100) << 23);

/// The longest `w` [`reflect`] takes, `f32::MAX / 4` (8.5e37): `r = 2(n̂·w)n̂ − w` computes `2(n̂·w)`,
/// up to `2|w|`, on the way, and `r` keeps the length of `w`.
pub const MAX_REFLECT_LENGTH: f32 = f32::MAX / 4.0;

fn reflect_ok(w: Vec3) -> bool {
    // In float64: |w|² of a finite float32 vector cannot overflow there. NaN and ±inf fail the test.
    w.as_dvec3().length_squared() <= (MAX_REFLECT_LENGTH as f64) * (MAX_REFLECT_LENGTH as f64)
}

const REFLECT_PROBLEM: &str = "must hold finite vectors of length at most 8.5e37 (f32::MAX / 4: \
                               the mirror direction keeps the length of w and would overflow float32 beyond it)";

// ------------------------------------------------------------------------------------------- vectors

/// Mirror `w` about the normal: `r = 2(n̂·w)n̂ − w` with `n̂ = n/|n|`; `w` keeps its length (at most
/// [`MAX_REFLECT_LENGTH`]: a longer one is refused, naming `w`, rather than giving ∞), `n` may have any
/// finite length, a zero-length `n` gives 0. Output: vectors.
pub fn reflect<'a>(
    w: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
) -> Result<Map<Vectors2<'a>, impl Fn((Vec3, Vec3)) -> Vec3 + Sync + Copy>, BrdfError> {
    let w = w.check(Check::Valid { ok: reflect_ok, problem: REFLECT_PROBLEM });
    Ok(Batch::new((w, n))?.map(|(w, n): (Vec3, Vec3)| {
        let n = unit(n);
        if n == Vec3A::ZERO { Vec3::ZERO } else { core_reflect(w.into(), n).into() }
    }))
}

/// Unit half vector `h = normalize(l̂ + v̂)`; 0 where `l̂ = −v̂` or an input has zero length.
pub fn halfway<'a>(
    l: Arg<'a, Vec3>,
    v: Arg<'a, Vec3>,
) -> Result<Map<Vectors2<'a>, impl Fn((Vec3, Vec3)) -> Vec3 + Sync + Copy>, BrdfError> {
    Ok(Batch::new((l, v))?.map(|(l, v): (Vec3, Vec3)| {
        let (l, v) = (unit(l), unit(v));
        if l == Vec3A::ZERO || v == Vec3A::ZERO {
            Vec3::ZERO
        } else {
            core_halfway(l, v).map_or(Vec3::ZERO, Vec3::from)
        }
    }))
}

/// Refracted direction by Snell's law (`eta = η_t/η_i` in [`ETA_RANGE`]): `(t, ok)`, with `ok` false and
/// `t = 0` on total internal reflection, below the surface (`ŵ·n̂ < 0`) or for a zero-length input.
pub fn refract<'a>(
    w: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
    eta: Arg<'a, f32>,
) -> Result<
    Map<
        (Arg<'a, Vec3>, Arg<'a, Vec3>, Arg<'a, f32>),
        impl Fn((Vec3, Vec3, f32)) -> (Vec3, bool) + Sync + Copy,
    >,
    BrdfError,
> {
    let eta = eta.check(Check::Valid { ok: eta_ok, problem: ETA_PROBLEM });
    Ok(Batch::new((w, n, eta))?.map(|(w, n, eta): (Vec3, Vec3, f32)| {
        let (w, n) = (unit(w), unit(n));
        let t = if w == Vec3A::ZERO || n == Vec3A::ZERO || w.dot(n) < 0.0 {
            None
        } else {
            core_refract(w, n, eta)
        };
        t.map_or((Vec3::ZERO, false), |t| (t.into(), true))
    }))
}

// ------------------------------------------------------------------------------------ microfacet terms

/// A (mixture of) distribution(s) from lobes `(weight, name, alpha, alpha_y)`.
pub fn mixture(lobes: &[(f32, &str, f32, Option<f32>)]) -> Result<Mixture, BrdfError> {
    if lobes.is_empty() {
        return Err(BrdfError::InvalidInput {
            name: "lobes",
            problem: "expected at least one (weight, name, alpha) lobe".into(),
        });
    }
    let built = lobes
        .iter()
        .map(|&(w, name, a, ay)| Ok((w, Distribution::from_name(name, a, ay)?)))
        .collect::<Result<Vec<_>, BrdfError>>()?;
    Mixture::new(&built)
}

/// The local frame at a sample: from the normal and, when given and usable, the tangent.
#[inline]
fn frame(n: Vec3A, t: Option<Vec3A>) -> ShadingFrame {
    match t {
        Some(t) => ShadingFrame::from_normal_tangent(n, t),
        None => ShadingFrame::from_normal(n),
    }
}

/// A tangent hint that is neither zero nor along `n` (else an arbitrary frame is used).
#[inline]
fn usable_tangent(t: Option<Vec3>, n: Vec3A) -> Option<Vec3A> {
    t.map(unit).filter(|t| *t != Vec3A::ZERO && t.cross(n).length_squared() > 1e-12)
}

/// Inputs of a microfacet term of one direction: the direction, the normal, the optional tangent.
pub type Direction<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>, Option<Arg<'a, Vec3>>);

/// `D(h)` [1/sr] of `d` for half vectors `h` around normals `n`; 0 for `h` below the surface or a
/// zero-length input. Output: numbers.
pub fn distribution<'a>(
    d: &'a Mixture,
    h: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
    tangent: Option<Arg<'a, Vec3>>,
) -> Result<Map<Direction<'a>, impl Fn((Vec3, Vec3, Option<Vec3>)) -> f32 + Sync + Copy + 'a>, BrdfError> {
    Ok(Batch::new((h, n, tangent))?.map(move |(h, n, t): (Vec3, Vec3, Option<Vec3>)| {
        let (h, n) = (unit(h), unit(n));
        if h == Vec3A::ZERO || n == Vec3A::ZERO {
            return 0.0;
        }
        let local = frame(n, usable_tangent(t, n)).to_local(h);
        if local.z > 0.0 { d.d(local) } else { 0.0 }
    }))
}

/// Smith `Λ(w)` of `d`, or `G1 = 1/(1 + Λ)` when `g1`, for directions `w` around normals `n`;
/// `Λ = +∞`, `G1 = 0` below the surface; 0 for a zero-length input. Output: numbers.
pub fn smith_lambda<'a>(
    d: &'a Mixture,
    w: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
    tangent: Option<Arg<'a, Vec3>>,
    g1: bool,
) -> Result<Map<Direction<'a>, impl Fn((Vec3, Vec3, Option<Vec3>)) -> f32 + Sync + Copy + 'a>, BrdfError> {
    Ok(Batch::new((w, n, tangent))?.map(move |(w, n, t): (Vec3, Vec3, Option<Vec3>)| {
        let (w, n) = (unit(w), unit(n));
        if w == Vec3A::ZERO || n == Vec3A::ZERO {
            return 0.0;
        }
        let local = frame(n, usable_tangent(t, n)).to_local(w);
        if local.z <= 0.0 {
            return if g1 { 0.0 } else { f32::INFINITY };
        }
        let lambda = d.lambda(local);
        if g1 { 1.0 / (1.0 + lambda) } else { lambda }
    }))
}

/// Inputs of a shadowing-masking term: `l`, `v`, `n`, the optional tangent.
pub type Pair<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>, Arg<'a, Vec3>, Option<Arg<'a, Vec3>>);

/// Shadowing-masking `G(l, v)` (dimensionless) of term `g` for distribution `d`; 0 for a zero-length
/// input. Output: numbers.
pub fn masking<'a>(
    g: Masking,
    d: &'a Mixture,
    l: Arg<'a, Vec3>,
    v: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
    tangent: Option<Arg<'a, Vec3>>,
) -> Result<Map<Pair<'a>, impl Fn((Vec3, Vec3, Vec3, Option<Vec3>)) -> f32 + Sync + Copy + 'a>, BrdfError> {
    Ok(Batch::new((l, v, n, tangent))?.map(move |(l, v, n, t): (Vec3, Vec3, Vec3, Option<Vec3>)| {
        let (l, v, n) = (unit(l), unit(v), unit(n));
        if l == Vec3A::ZERO || v == Vec3A::ZERO || n == Vec3A::ZERO {
            return 0.0;
        }
        g.g_world(l, v, n, usable_tangent(t, n), d)
    }))
}

// ------------------------------------------------------------------------------------------- Fresnel

/// A scalar-or-RGB parameter: one value for every channel, or three.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Channels {
    /// One value (gray): the output has no channel axis.
    Gray(f32),
    /// Three values: the output gains a trailing axis of 3.
    Rgb(Vec3),
}

impl Channels {
    /// 1 or 3 values each satisfying `ok` (`want` says how, e.g. "finite and > 0").
    pub fn new(name: &'static str, xs: &[f32], ok: fn(f32) -> bool, want: &str) -> Result<Self, BrdfError> {
        let c = match xs {
            [x] => Channels::Gray(*x),
            [r, g, b] => Channels::Rgb(Vec3::new(*r, *g, *b)),
            _ => {
                return Err(BrdfError::InvalidInput {
                    name,
                    problem: format!("expected a number or 3 numbers (RGB), got {} numbers", xs.len()),
                });
            }
        };
        match xs.iter().find(|x| !ok(**x)) {
            Some(x) => Err(BrdfError::InvalidInput { name, problem: format!("must be {want}, got {x}") }),
            None => Ok(c),
        }
    }

    /// The three channels (a gray value repeated).
    pub fn rgb(self) -> Vec3 {
        match self {
            Channels::Gray(x) => Vec3::splat(x),
            Channels::Rgb(c) => c,
        }
    }

    fn is_rgb(self) -> bool {
        matches!(self, Channels::Rgb(_))
    }
}

/// A batch with a gray (number per element) or an RGB (three per element) output.
#[derive(Debug, Clone, Copy)]
pub enum GrayOrRgb<G, C> {
    /// Output: numbers.
    Gray(G),
    /// Output: RGB vectors (shape `(..., 3)`).
    Rgb(C),
}

/// A Fresnel batch over cosines, gray or RGB.
pub type Fresnel<'a, G, C> = GrayOrRgb<Map<Numbers<'a>, G>, Map<Numbers<'a>, C>>;

/// Cosines may carry float32 rounding just past ±1 (e.g. a dot product of unit vectors).
const COSINES: Check<f32> = Check::Valid {
    ok: |c| c.is_finite() && c.abs() <= 1.0 + 1e-4,
    problem: "must hold finite cosines in [-1, 1]",
};

/// Relative indices of refraction accepted: every physical one with room to spare, and no further, so
/// that `η²`, `1/η` and `η·cos θ` stay normal float32 numbers (at `η = 10⁻⁴⁵` the Fresnel equations
/// were `0/0`).
pub const ETA_RANGE: (f32, f32) = (1e-6, 1e6);

const ETA_PROBLEM: &str = "must be a relative index of refraction in [1e-6, 1e6]";

fn eta_ok(x: f32) -> bool {
    (ETA_RANGE.0..=ETA_RANGE.1).contains(&x)
}

fn unit_interval(x: f32) -> bool {
    (0.0..=1.0).contains(&x)
}

fn cosines(cos_i: Arg<'_, f32>) -> Result<Batch<Numbers<'_>>, BrdfError> {
    Batch::new((cos_i.check(COSINES),))
}

/// Unpolarised exact dielectric reflectance `(R_s + R_p)/2` for relative indices `eta` (1 or 3 values,
/// in [`ETA_RANGE`]); `cos_i < 0` means from inside; total internal reflection gives 1.
pub fn dielectric<'a>(
    cos_i: Arg<'a, f32>,
    eta: &[f32],
) -> Result<Fresnel<'a, impl Fn((f32,)) -> f32 + Sync + Copy, impl Fn((f32,)) -> Vec3 + Sync + Copy>, BrdfError>
{
    let eta = Channels::new("eta", eta, eta_ok, "in [1e-6, 1e6]")?;
    let b = cosines(cos_i)?;
    let e = eta.rgb();
    Ok(match eta {
        Channels::Gray(x) => GrayOrRgb::Gray(b.map(move |(c,): (f32,)| fr::dielectric(c, x))),
        Channels::Rgb(_) => GrayOrRgb::Rgb(b.map(move |(c,): (f32,)| fr::dielectric_rgb(c, e))),
    })
}

/// `(R_s, R_p)` of the exact dielectric Fresnel equations (scalar `eta` in [`ETA_RANGE`]).
pub fn dielectric_sp(
    cos_i: Arg<'_, f32>,
    eta: f32,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> (f32, f32) + Sync + Copy>, BrdfError> {
    if !eta_ok(eta) {
        return Err(BrdfError::InvalidInput { name: "eta", problem: format!("{ETA_PROBLEM}, got {eta}") });
    }
    Ok(cosines(cos_i)?.map(move |(c,): (f32,)| fr::dielectric_sp(c, eta)))
}

/// Exact conductor reflectance for the complex index `η − iκ` (`eta` in [`ETA_RANGE`], `k` in [0, 10⁶]; 1 or 3 values each,
/// RGB when either has 3).
pub fn conductor<'a>(
    cos_i: Arg<'a, f32>,
    eta: &[f32],
    k: &[f32],
) -> Result<Fresnel<'a, impl Fn((f32,)) -> f32 + Sync + Copy, impl Fn((f32,)) -> Vec3 + Sync + Copy>, BrdfError>
{
    let eta = Channels::new("eta", eta, eta_ok, "in [1e-6, 1e6]")?;
    let k = Channels::new("k", k, |x| (0.0..=ETA_RANGE.1).contains(&x), "in [0, 1e6]")?;
    let b = cosines(cos_i)?;
    let (e, kk) = (eta.rgb(), k.rgb());
    Ok(if eta.is_rgb() || k.is_rgb() {
        GrayOrRgb::Rgb(b.map(move |(c,): (f32,)| fr::conductor(c, e, kk)))
    } else {
        GrayOrRgb::Gray(b.map(move |(c,): (f32,)| fr::conductor_scalar(c, e.x, kk.x)))
    })
}

/// Schlick's approximation `F0 + (1 − F0)(1 − |cos_i|)^5` (`f0` in [0, 1], 1 or 3 values).
pub fn schlick<'a>(
    cos_i: Arg<'a, f32>,
    f0: &[f32],
) -> Result<Fresnel<'a, impl Fn((f32,)) -> f32 + Sync + Copy, impl Fn((f32,)) -> Vec3 + Sync + Copy>, BrdfError>
{
    let f0 = Channels::new("f0", f0, unit_interval, "in [0, 1]")?;
    let b = cosines(cos_i)?;
    let f = f0.rgb();
    Ok(match f0 {
        Channels::Gray(x) => GrayOrRgb::Gray(b.map(move |(c,): (f32,)| fr::schlick_scalar(c, x))),
        Channels::Rgb(_) => GrayOrRgb::Rgb(b.map(move |(c,): (f32,)| fr::schlick(c, f))),
    })
}

/// Cook & Torrance's colour shift (`f0` in [0, 1], 1 or 3 values; `f0_ref` in [0, 1], default the mean
/// of `f0`). Output: RGB.
pub fn color_shift<'a>(
    cos_i: Arg<'a, f32>,
    f0: &[f32],
    f0_ref: Option<f32>,
) -> Result<Map<Numbers<'a>, impl Fn((f32,)) -> Vec3 + Sync + Copy>, BrdfError> {
    let f0 = Channels::new("f0", f0, unit_interval, "in [0, 1]")?.rgb();
    let f0_ref = match f0_ref {
        None => fr::color_shift_reference(f0),
        Some(r) if unit_interval(r) => r,
        Some(r) => {
            return Err(BrdfError::InvalidInput {
                name: "f0_ref",
                problem: format!("must be in [0, 1], got {r}"),
            });
        }
    };
    Ok(cosines(cos_i)?.map(move |(c,): (f32,)| fr::color_shift(c, f0, f0_ref)))
}

/// `F0 = ((η − 1)/(η + 1))²` element-wise (`eta` in [`ETA_RANGE`]).
pub fn f0_from_ior(
    eta: Arg<'_, f32>,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> f32 + Sync + Copy>, BrdfError> {
    let eta = eta.check(Check::Valid { ok: eta_ok, problem: ETA_PROBLEM });
    Ok(Batch::new((eta,))?.map(|(e,): (f32,)| fr::f0_from_ior(e)))
}

/// `η = (1 + √F0)/(1 − √F0)` element-wise (`f0` in [0, 1); `F0 = 1` is refused: it has no finite η).
pub fn ior_from_f0(
    f0: Arg<'_, f32>,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> f32 + Sync + Copy>, BrdfError> {
    let f0 = f0.check(Check::Valid { ok: |x| (0.0..1.0).contains(&x), problem: "must lie in [0, 1)" });
    Ok(Batch::new((f0,))?.map(|(x,): (f32,)| fr::ior_from_f0(x)))
}

/// What a smooth dielectric interface does to light from `w` at normal `n` (both normalised;
/// `eta = η_inside/η_outside` in [`ETA_RANGE`]): `(reflected, refracted, R, T)`, all 0 for a
/// zero-length input, `refracted = 0` on total internal reflection.
pub fn split<'a>(
    w: Arg<'a, Vec3>,
    n: Arg<'a, Vec3>,
    eta: f32,
) -> Result<Map<Vectors2<'a>, impl Fn((Vec3, Vec3)) -> (Vec3, Vec3, f32, f32) + Sync + Copy>, BrdfError> {
    if !eta_ok(eta) {
        return Err(BrdfError::InvalidInput { name: "eta", problem: format!("{ETA_PROBLEM}, got {eta}") });
    }
    Ok(Batch::new((w, n))?.map(move |(w, n): (Vec3, Vec3)| {
        let (w, n) = (unit(w), unit(n));
        if w == Vec3A::ZERO || n == Vec3A::ZERO {
            return (Vec3::ZERO, Vec3::ZERO, 0.0, 0.0);
        }
        let s = fr::split(w, n, eta);
        (s.reflected.into(), s.refracted.map_or(Vec3::ZERO, Vec3::from), s.reflectance, s.transmittance)
    }))
}

// ------------------------------------------------------------------------------------------ tone maps

/// A tone-mapping function of one value over an array of any shape. Any float is accepted (NaN and
/// negative values count as 0, `+∞` as the largest float; see [`crate::tonemap`]).
pub fn tonemap<T>(
    x: Arg<'_, f32>,
    f: impl Fn(f32) -> T + Sync + Copy,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> T + Sync + Copy>, BrdfError> {
    Ok(Batch::new((x.check(Check::Any),))?.map(move |(c,): (f32,)| f(c)))
}

/// Extended Reinhard with white point `white` (finite and > 0).
pub fn reinhard_extended(
    x: Arg<'_, f32>,
    white: f32,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> f32 + Sync + Copy>, BrdfError> {
    if !(white > 0.0 && white.is_finite()) {
        return Err(BrdfError::InvalidInput {
            name: "white",
            problem: format!("must be finite and > 0, got {white}"),
        });
    }
    tonemap(x, move |c| tm::reinhard_extended_f32(c, white))
}

/// `x · 2^ev` (`ev` finite), saturating at `±f32::MAX` (see [`tm::exposure`]).
pub fn exposure(
    x: Arg<'_, f32>,
    ev: f32,
) -> Result<Map<Numbers<'_>, impl Fn((f32,)) -> f32 + Sync + Copy>, BrdfError> {
    if !ev.is_finite() {
        return Err(BrdfError::InvalidInput { name: "ev", problem: format!("must be finite, got {ev}") });
    }
    tonemap(x, move |c| tm::exposure_f32(c, ev))
}

/// `floor(255 · srgb_encode(op(x)) + 0.5)` per value, for the operator named `operator`.
pub fn to_uint8<'a>(
    x: Arg<'a, f32>,
    operator: &str,
    white: Option<f32>,
) -> Result<Map<Numbers<'a>, impl Fn((f32,)) -> u8 + Sync + Copy>, BrdfError> {
    let op = Operator::from_name(operator, white)?;
    tonemap(x, move |c| tm::to_u8(tm::srgb_encode_f32(op.apply(Vec3::splat(c)).x)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vector_functions_broadcast_and_map_degenerate_input_to_zero() {
        let w = [Vec3::new(0.6, 0.0, 0.8), Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0)];
        let n = Vec3::Z * 2.0;
        let r = reflect(Arg::rows("w", &w).unwrap(), Arg::one("n", &n)).unwrap().to_vec::<Vec3>().unwrap();
        assert!((r[0] - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6 && r[1] == Vec3::ZERO);
        let zero = Vec3::ZERO;
        let r = reflect(Arg::rows("w", &w).unwrap(), Arg::one("n", &zero)).unwrap().to_vec::<Vec3>().unwrap();
        assert!(r.iter().all(|r| *r == Vec3::ZERO));
        let eta = [1.5f32];
        let t =
            refract(Arg::rows("w", &w).unwrap(), Arg::one("n", &n), Arg::rows("eta", &eta).unwrap()).unwrap();
        let t = t.to_vec::<(Vec3, bool)>().unwrap();
        assert!(t[0].1 && !t[1].1 && !t[2].1 && t[0].0.z < 0.0);
        let bad = [0.0f32];
        let e =
            refract(Arg::rows("w", &w).unwrap(), Arg::one("n", &n), Arg::rows("eta", &bad).unwrap()).unwrap();
        let e = e.to_vec::<(Vec3, bool)>().unwrap_err().to_string();
        assert!(e.starts_with("eta:") && e.contains("[1e-6, 1e6]"), "{e}");
    }

    /// reflect refuses a w so long that the mirror direction would overflow (naming w, its index and the
    /// limit) and accepts one at the limit; the normalised inputs (n of reflect, l and v of halfway, w and
    /// n of refract) keep their direction at any finite length instead of overflowing to 0 or inf.
    #[test]
    fn vector_functions_refuse_or_survive_huge_magnitudes() {
        let n = Vec3::Z;
        let at_limit = [Vec3::new(0.0, 0.0, MAX_REFLECT_LENGTH)];
        let r =
            reflect(Arg::rows("w", &at_limit).unwrap(), Arg::one("n", &n)).unwrap().to_vec::<Vec3>().unwrap();
        assert_eq!(r[0], at_limit[0]);
        let w = [Vec3::new(0.6, 0.0, 0.8), Vec3::new(3e38, 0.0, 3e38)];
        let e =
            reflect(Arg::rows("w", &w).unwrap(), Arg::one("n", &n)).unwrap().to_vec::<Vec3>().unwrap_err();
        let e = e.to_string();
        assert!(e.starts_with("w: ") && e.contains("at w[1]") && e.contains("8.5e37"), "{e}");
        let huge_n = Vec3::new(0.0, 0.0, 3e38);
        let r = reflect(Arg::rows("w", &w[..1]).unwrap(), Arg::one("n", &huge_n)).unwrap();
        let r = r.to_vec::<Vec3>().unwrap();
        assert!((r[0] - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6, "{r:?}");
        let (l, v) = ([Vec3::new(3e38, 0.0, 3e38)], Vec3::new(0.0, 0.0, 1e30));
        let h = halfway(Arg::rows("l", &l).unwrap(), Arg::one("v", &v)).unwrap().to_vec::<Vec3>().unwrap();
        let want = Vec3::new(1.0, 0.0, 1.0 + 2f32.sqrt()).normalize();
        assert!((h[0] - want).length() < 1e-6, "{h:?}");
        let eta = [1.0f32];
        let t = refract(Arg::rows("w", &l).unwrap(), Arg::one("n", &huge_n), Arg::rows("eta", &eta).unwrap());
        let t = t.unwrap().to_vec::<(Vec3, bool)>().unwrap();
        assert!(t[0].1 && (t[0].0 - Vec3::new(-1.0, 0.0, -1.0).normalize()).length() < 1e-6, "{t:?}");
    }

    #[test]
    fn fresnel_is_gray_or_rgb_by_its_parameter_and_refuses_bad_cosines() {
        let c = [1.0f32, 0.5, -0.2];
        let arg = || Arg::rows("cos_i", &c).unwrap();
        match dielectric(arg(), &[1.5]).unwrap() {
            GrayOrRgb::Gray(m) => {
                let f = m.to_vec::<f32>().unwrap();
                assert!((f[0] - 0.04).abs() < 1e-6);
            }
            GrayOrRgb::Rgb(_) => panic!("one eta gives gray"),
        }
        assert!(matches!(dielectric(arg(), &[1.5, 1.6, 1.7]).unwrap(), GrayOrRgb::Rgb(_)));
        assert!(dielectric(arg(), &[1.5, 1.6]).unwrap_err().to_string().contains("3 numbers"));
        assert!(conductor(arg(), &[1.0], &[-1.0]).unwrap_err().to_string().starts_with("k:"));
        let c2 = [0.5f32, 1.5];
        let GrayOrRgb::Gray(m) = schlick(Arg::rows("cos_i", &c2).unwrap(), &[0.04]).unwrap() else {
            panic!()
        };
        let e = m.to_vec::<f32>().unwrap_err().to_string();
        assert!(e.contains("cosines") && e.contains("cos_i[1]: 1.5"), "{e}");
        // Tone maps take anything.
        let x = [f32::NAN, -1.0, f32::INFINITY];
        let y = tonemap(Arg::rows("x", &x).unwrap(), tm::clamp_f32).unwrap().to_vec::<f32>().unwrap();
        assert_eq!(y, [0.0, 0.0, 1.0]);
    }
}
