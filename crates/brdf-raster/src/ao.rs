//! Ambient obscurance `w(p)` exactly as Theoharis et al. 2008 define it (eqs. 12.71–12.74; Zhukov, Iones &
//! Kronin
//! 1998, "An ambient light illumination model"; Iones et al. 2003, "Fast, realistic lighting for video
//! games"), estimated by casting rays into a [`Bvh`].
//!
//! ```text
//! d(p, ω) = |c − p|, c the first surface point seen from p in direction ω; +∞ when there is none  (12.71)
//! w(p)    = (1/π) ∫_Ω μ(d(p, ω)) cos θ dω                                                        (12.72)
//! μ(x)    = 1 − e^(−τx)                                                                          (12.74)
//! ```
//!
//! ## Normalising μ to the range `d_max` (the seed's "μ has to be modified to normalize this input range")
//! The seed asks for μ with `μ(0) = 0`, `μ(∞) = 1`, increasing and concave (12.73), and for `w = 1` when
//! the hemisphere is open up to `d_max`, the distance beyond which no surface counts. We map the input
//! range `[0, d_max]` onto `[0, 1]` with `x = d/d_max` and rescale so that μ reaches 1 exactly at `d_max`:
//!
//! ```text
//! μ(d) = (1 − e^(−τ d/d_max)) / (1 − e^(−τ))   for d < d_max,
//! μ(d) = 1                                     for d ≥ d_max ("open": nothing within range),
//! ```
//!
//! which is continuous at `d_max` (the plain `1 − e^(−τ d/d_max)` would jump from `1 − e^(−τ)` to 1
//! there), 0 at contact, increasing and concave on `[0, d_max]`. `τ > 0` sets how quickly an occluder's
//! weight rises with its distance: small τ makes μ nearly linear (`d/d_max`), large τ confines the
//! darkening to surfaces very close to `p`. Hence `w ∈ [0, 1]`, 1 for a fully open point, 0 only where
//! surfaces touch (`d = 0` in every direction).
//!
//! ## Estimator
//! With cosine-weighted directions (pdf `cos θ/π`) the integral is the mean of μ:
//! `w ≈ (1/S) Σ_k μ(d(p, ω_k))`. The `S` directions come from the 2D Hammersley set
//! `(k/S, Φ₂(k))` (Φ₂ the base-2 radical inverse), mapped by `(u₁, u₂) ↦ (√u₁ cos 2πu₂, √u₁ sin 2πu₂,
//! √(1−u₁))` into the frame of `n` (Duff et al. 2017), after a Cranley–Patterson rotation (a toroidal
//! shift of all points by one random offset) drawn from a hash of `(seed, point key)`: every point gets
//! its own well-stratified pattern, the result is a pure function of `(seed, key, p, n)` — deterministic
//! and independent of the number of threads — and neighbouring points do not share the same banding.
//!
//! ## Self-intersection offset
//! Rays start at `p + ε·n` with `ε = max(2⁻¹⁶·s, 10⁻⁴·d_max)`, `s` the largest coordinate magnitude of
//! the scene ([`Bvh::coordinate_scale`]): 2⁻¹⁶·s is about 256 float ulps at that magnitude, well above the
//! rounding of interpolated positions and of the hit test, so the surface under `p` is not hit again;
//! 10⁻⁴·d_max keeps it negligible against the distances μ measures. Distances are the hit parameter `t`
//! of a unit direction from the offset origin, so they are short by at most ε.
//!
//! ## Inputs
//! Shading normals are used as given (per-vertex normals on a curved mesh let a few grazing rays start
//! below the true surface; they hit the neighbouring faces at once and count as occluded — the usual
//! behaviour of vertex AO). A zero normal (an isolated vertex) has no hemisphere: its `w` is 1.
//! Non-finite positions or normals are refused. Degenerate triangles are skipped by the BVH.

use std::f32::consts::TAU;

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use crate::bvh::{Bvh, Ray};
use crate::{Mesh, RasterError};

/// Largest sample count per point accepted (beyond it the estimate no longer improves visibly, and a
/// typo like 10⁹ would otherwise run for hours).
pub const MAX_SAMPLES: u32 = 1 << 16;

/// Parameters of the obscurance estimate (Theoharis et al. 2008 eq. 12.72–12.74).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AoOptions {
    /// τ > 0 of `μ(x) = 1 − e^(−τx)` (dimensionless, since x = d/d_max).
    pub tau: f32,
    /// `d_max` > 0, the range beyond which surfaces do not obscure (world units).
    pub d_max: f32,
    /// Rays per point `S` ≥ 1.
    pub samples: u32,
    /// Seed of the per-point Cranley–Patterson rotations.
    pub seed: u64,
    /// In a render: estimate `w` at every shading point (true) or per vertex, interpolated (false).
    pub per_pixel: bool,
    /// In a render: eq. 12.75's combined mode — the lights' diffuse irradiance `I_d(p)` joins the
    /// ambient term, `[k_a I_a + k_d I_d(p)]·w(p)` (see [`crate::occlusion`]); false: `k_a I_a·w(p)` only.
    pub combined: bool,
}

impl Default for AoOptions {
    /// τ = 2, `d_max` = 1, 64 samples, seed 0, per vertex, ambient only.
    fn default() -> Self {
        Self { tau: 2.0, d_max: 1.0, samples: 64, seed: 0, per_pixel: false, combined: false }
    }
}

impl AoOptions {
    /// Check τ > 0, `d_max` > 0 (both finite) and `1 ≤ samples ≤` [`MAX_SAMPLES`].
    pub fn validate(&self) -> Result<(), RasterError> {
        if !(self.tau > 0.0) || !self.tau.is_finite() {
            return Err(RasterError::arg("tau", format!("must be finite and > 0, got {}", self.tau)));
        }
        if !(self.d_max > 0.0) || !self.d_max.is_finite() {
            return Err(RasterError::arg("d_max", format!("must be finite and > 0, got {}", self.d_max)));
        }
        if self.samples == 0 || self.samples > MAX_SAMPLES {
            return Err(RasterError::arg(
                "samples",
                format!("must lie in [1, {MAX_SAMPLES}], got {}", self.samples),
            ));
        }
        Ok(())
    }
}

/// The normalised obscurance function of the module docs:
/// `μ(d) = (1 − e^(−τ d/d_max)) / (1 − e^(−τ))` for `0 ≤ d < d_max`, 1 for `d ≥ d_max` (and for ∞).
/// Dimensionless, in [0, 1]. Needs τ > 0 and `d_max` > 0 (see [`AoOptions::validate`]); as τ → 0 it
/// tends to `d/d_max`, which is what it gives for τ too small for float32 (τ = 10⁻⁴⁵ was 0/0).
#[inline]
pub fn mu(d: f32, tau: f32, d_max: f32) -> f32 {
    if d >= d_max {
        return 1.0;
    }
    let d = d.max(0.0);
    match Normalisation::new(tau) {
        // exp_m1 keeps precision for small τx, where 1 − e^(−τx) ≈ τx.
        Normalisation::Exponential { .. } => ((-tau * d / d_max).exp_m1() / (-tau).exp_m1()).clamp(0.0, 1.0),
        linear => linear.mu(d, d_max),
    }
}

/// `μ(d)` at a fixed τ, its normalisation computed once.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Normalisation {
    /// `μ = expm1(−τ d/d_max) · inv` with `inv = 1 / expm1(−τ)` (both factors negative).
    Exponential { tau: f32, inv: f32 },
    /// τ below [`Normalisation::LINEAR_BELOW`]: `μ = x (1 − τx/2) / (1 − τ/2)`, `x = d/d_max`, the series of the
    /// exponential form to first order in τ (relative error below τ²/6, i.e. < 2·10⁻⁹ there), which
    /// has no overflow in `1/expm1(−τ)` and no 0/0 as τ → 0.
    Linear { tau: f32 },
}

impl Normalisation {
    /// Where the series takes over: `1/expm1(−τ)` is still exact here, and the series error is far
    /// below float32 rounding.
    const LINEAR_BELOW: f32 = 1e-4;

    pub(crate) fn new(tau: f32) -> Self {
        if tau < Self::LINEAR_BELOW {
            Normalisation::Linear { tau }
        } else {
            Normalisation::Exponential { tau, inv: 1.0 / (-tau).exp_m1() }
        }
    }

    /// `μ(d)` for `0 ≤ d < d_max` (clamped to [0, 1]).
    #[inline]
    pub(crate) fn mu(self, d: f32, d_max: f32) -> f32 {
        let m = match self {
            Normalisation::Exponential { tau, inv } => (-tau * d / d_max).exp_m1() * inv,
            Normalisation::Linear { tau } => {
                let x = d / d_max;
                x * (1.0 - 0.5 * tau * x) / (1.0 - 0.5 * tau)
            }
        };
        m.clamp(0.0, 1.0)
    }
}

/// The scene-independent part of the estimator: options, sample pattern, normalisation and offset.
#[derive(Debug, Clone)]
pub(crate) struct Sampler {
    opts: AoOptions,
    /// Hammersley points `(k/S, Φ₂(k))`.
    pattern: Vec<[f32; 2]>,
    /// μ as a function of `d/d_max`.
    norm: Normalisation,
    offset: f32,
}

impl Sampler {
    /// Validate `opts` and prepare the pattern; the offset follows the scale of `bvh`.
    pub(crate) fn new(bvh: &Bvh, opts: &AoOptions) -> Result<Self, RasterError> {
        opts.validate()?;
        let s = opts.samples;
        let pattern = (0..s).map(|k| [k as f32 / s as f32, radical_inverse_2(k)]).collect();
        let offset = (bvh.coordinate_scale() * (1.0 / 65536.0)).max(1e-4 * opts.d_max);
        Ok(Self { opts: *opts, pattern, norm: Normalisation::new(opts.tau), offset })
    }

    /// `w(p)` against `bvh` (the one the sampler was made for); see [`Obscurance::at`].
    pub(crate) fn at(&self, bvh: &Bvh, p: Vec3, n: Vec3, key: u64) -> f32 {
        let n = Vec3A::from(n);
        let len2 = n.length_squared();
        if !(len2 > 0.0) || !len2.is_finite() || !p.is_finite() {
            return 1.0;
        }
        let n = n / len2.sqrt();
        let (t, b) = orthonormal_basis(n);
        let origin = Vec3A::from(p) + n * self.offset;
        let (r1, r2) = rotation(self.opts.seed, key);
        let d_max = self.opts.d_max;
        let mut sum = 0.0f32;
        for &[u1, u2] in &self.pattern {
            let (u1, u2) = (wrap(u1 + r1), wrap(u2 + r2));
            let r = u1.sqrt();
            let (sin_phi, cos_phi) = (TAU * u2).sin_cos();
            let z = (1.0 - u1).max(0.0).sqrt();
            let dir = t * (r * cos_phi) + b * (r * sin_phi) + n * z;
            let ray = Ray::segment(origin.into(), dir.into(), 0.0, d_max);
            sum += match bvh.closest_hit(&ray) {
                // μ(d) for d < d_max, with the normalisation computed once.
                Some(h) => self.norm.mu(h.t, d_max),
                None => 1.0,
            };
        }
        sum / self.pattern.len() as f32
    }
}

/// A validated obscurance estimator bound to a scene: the BVH, the options, the sample pattern and the
/// ray offset, computed once and shared by every point.
#[derive(Debug, Clone)]
pub struct Obscurance<'a> {
    bvh: &'a Bvh,
    sampler: Sampler,
}

impl<'a> Obscurance<'a> {
    /// Validate `opts` and prepare the estimator over `bvh`.
    pub fn new(bvh: &'a Bvh, opts: &AoOptions) -> Result<Self, RasterError> {
        Ok(Self { bvh, sampler: Sampler::new(bvh, opts)? })
    }

    /// The options in use.
    pub fn options(&self) -> &AoOptions {
        &self.sampler.opts
    }

    /// The self-intersection offset ε along the normal (see the module docs), world units.
    pub fn offset(&self) -> f32 {
        self.sampler.offset
    }

    /// `w(p)` for a point `p` with unit normal `n`, its sample pattern rotated by a hash of
    /// `(seed, key)` (use a vertex index, a pixel index, …). Returns 1 for a zero or non-finite normal.
    pub fn at(&self, p: Vec3, n: Vec3, key: u64) -> f32 {
        self.sampler.at(self.bvh, p, n, key)
    }

    /// `w` at many points in parallel; point `i` uses key `i` (deterministic at any thread count).
    /// Errors when the slices differ in length or hold non-finite values.
    pub fn at_points(&self, points: &[Vec3], normals: &[Vec3]) -> Result<Vec<f32>, RasterError> {
        check_points(points, normals)?;
        let mut out: Vec<f32> = Vec::new();
        out.try_reserve_exact(points.len()).map_err(|_| {
            RasterError::arg("points", format!("cannot allocate obscurance for {} points", points.len()))
        })?;
        out.par_extend(
            points
                .par_iter()
                .zip(normals.par_iter())
                .enumerate()
                .map(|(i, (&p, &n))| self.at(p, n, i as u64)),
        );
        Ok(out)
    }
}

/// Per-vertex obscurance `w` of `positions` with unit `normals` against the scene in `bvh` (which may
/// be the same mesh or a whole scene), `S = opts.samples` rays per vertex, vertex `i` keyed by `i`.
/// Parallel and deterministic. Errors: invalid options, length mismatch, non-finite input.
pub fn obscurance_per_vertex(
    bvh: &Bvh,
    positions: &[Vec3],
    normals: &[Vec3],
    opts: &AoOptions,
) -> Result<Vec<f32>, RasterError> {
    Obscurance::new(bvh, opts)?.at_points(positions, normals)
}

/// Per-vertex obscurance of a mesh against itself (builds its BVH; see [`obscurance_per_vertex`]).
pub fn mesh_obscurance(mesh: &Mesh, opts: &AoOptions) -> Result<Vec<f32>, RasterError> {
    opts.validate()?;
    let bvh = Bvh::from_mesh(mesh)?;
    obscurance_per_vertex(&bvh, &mesh.positions, &mesh.normals, opts)
}

fn check_points(points: &[Vec3], normals: &[Vec3]) -> Result<(), RasterError> {
    if points.len() != normals.len() {
        return Err(RasterError::arg(
            "normals",
            format!("{} normals for {} points", normals.len(), points.len()),
        ));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(RasterError::arg("points", format!("point {i} is not finite: {}", points[i])));
    }
    if let Some(i) = normals.iter().position(|n| !n.is_finite()) {
        return Err(RasterError::arg("normals", format!("normal {i} is not finite: {}", normals[i])));
    }
    Ok(())
}

/// Φ₂(k): the bits of `k` mirrored about the binary point (van der Corput), in [0, 1).
#[inline]
fn radical_inverse_2(k: u32) -> f32 {
    // 24 bits are all an f32 in [0,1) can hold exactly.
    (k.reverse_bits() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// `x mod 1` for `x ∈ [0, 2)`.
#[inline]
fn wrap(x: f32) -> f32 {
    if x >= 1.0 { x - 1.0 } else { x }
}

/// The Cranley–Patterson offset of a point: two uniforms in [0, 1) from SplitMix64 of `(seed, key)`.
#[inline]
fn rotation(seed: u64, key: u64) -> (f32, f32) {
    let h = splitmix64(seed ^ splitmix64(key.wrapping_add(0x632B_E59B_D9B4_E019)));
    let to01 = |x: u64| (x >> 40) as f32 * (1.0 / (1u64 << 24) as f32);
    (to01(h), to01(h << 24))
}

#[inline]
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Tangent and bitangent completing unit `n` to a right-handed frame, without branches on the axis
/// (Duff et al. 2017, "Building an orthonormal basis, revisited", JCGT 6(1)).
#[inline]
pub(crate) fn orthonormal_basis(n: Vec3A) -> (Vec3A, Vec3A) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3A::new(b, sign + n.y * n.y * a, -n.y))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radical_inverse_mirrors_the_bits() {
        assert_eq!(radical_inverse_2(0), 0.0);
        assert_eq!(radical_inverse_2(1), 0.5);
        assert_eq!(radical_inverse_2(2), 0.25);
        assert_eq!(radical_inverse_2(3), 0.75);
        assert_eq!(radical_inverse_2(5), 0.625);
    }

    #[test]
    fn basis_is_orthonormal_for_any_normal_including_minus_z() {
        for n in [Vec3A::Z, -Vec3A::Z, Vec3A::X, Vec3A::new(0.3, -0.4, 0.866).normalize()] {
            let (t, b) = orthonormal_basis(n);
            for (x, y) in [(t, b), (t, n), (b, n)] {
                assert!(x.dot(y).abs() < 1e-6);
            }
            assert!((t.length() - 1.0).abs() < 1e-6 && (b.length() - 1.0).abs() < 1e-6);
            assert!((t.cross(b) - n).length() < 1e-5, "right-handed");
        }
    }
}
