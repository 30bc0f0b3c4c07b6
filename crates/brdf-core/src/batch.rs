//! Batch evaluation over slices of `Vec3` (the layout of a C-contiguous NumPy `(N, 3)` float32 array).
//!
//! Every input is either one vector (broadcast) or `n` vectors. Work is split into fixed chunks that
//! rayon runs on the pool's threads; every output element depends only on its own inputs, so the
//! result is bit-identical for any number of threads.
//!
//! Inside a chunk, samples go eight at a time through the model's lane form ([`Bxdf::f_lanes`],
//! [`crate::simd`]): the AoS rows are transposed into eight-lane registers, normalised, evaluated and
//! transposed back. The last, partial group is padded by repeating its last row, so every sample takes
//! the same path. On x86-64 CPUs with AVX2 (detected at run time) the lanes are one AVX register,
//! otherwise `wide`'s `f32x8`; both perform the same IEEE operations (no fused multiply-add), so the
//! bits do not depend on the CPU either, and they equal [`Model::eval`]/[`Model::shade`] on each
//! sample. [`evaluate_checked`] also checks the inputs for NaN/∞ on the rows already loaded.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use crate::models::{Bxdf, Model, ModelVisitor, eval_model_lanes, shade_model_lanes};
use crate::simd::{F32x8, Lane, LaneGeometry, LaneKernel, V3};
use crate::{BrdfError, Geometry};

/// Below this many elements a batch runs on the calling thread (spawning costs more than it saves).
pub const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Elements per parallel task.
pub const CHUNK: usize = 8 * 1024;

/// Which quantity a batch computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// `f_r` [1/sr] ([`Model::eval`]).
    Brdf,
    /// What a renderer multiplies by the light color ([`Model::shade`]).
    Shade,
}

/// A slice that is either one element broadcast to every index, or one element per index.
#[derive(Debug, Clone, Copy)]
pub struct Broadcast<'a, T> {
    data: &'a [T],
}

impl<'a, T: Copy> Broadcast<'a, T> {
    /// Wrap `data` (length 1 or `n`) for a batch of `n`, naming the argument in the error.
    pub fn new(name: &'static str, data: &'a [T], n: usize) -> Result<Self, BrdfError> {
        if data.len() == 1 || data.len() == n {
            Ok(Self { data })
        } else {
            Err(BrdfError::InvalidInput {
                name,
                problem: format!("has {} rows, expected 1 or {n}", data.len()),
            })
        }
    }

    /// Element `i` (element 0 when broadcast).
    #[inline(always)]
    pub fn get(&self, i: usize) -> T {
        if self.data.len() == 1 { self.data[0] } else { self.data[i] }
    }
}

impl Broadcast<'_, Vec3> {
    /// Rows `start .. end` (at most `F::LANES`) as lanes; past `end` the row `end − 1` is repeated
    /// (padding).
    #[inline(always)]
    fn lanes<F: Lane>(&self, start: usize, end: usize) -> V3<F> {
        if self.data.len() == 1 {
            return V3::splat(self.data[0]);
        }
        let rows: &[Vec3] = &self.data[start..end];
        let last = rows.len() - 1;
        if last + 1 == F::LANES {
            F::load_rows(rows)
        } else {
            let at = |j: usize| rows[j.min(last)];
            V3 { x: F::from_fn(|j| at(j).x), y: F::from_fn(|j| at(j).y), z: F::from_fn(|j| at(j).z) }
        }
    }
}

/// The common batch length of several inputs: the largest length, which every other length must
/// equal or be 1 (NumPy broadcasting restricted to `(N, 3)` and `(1, 3)`).
pub fn batch_len(inputs: &[(&'static str, usize)]) -> Result<usize, BrdfError> {
    let n = inputs.iter().map(|(_, len)| *len).max().unwrap_or(0);
    for (name, len) in inputs {
        if *len == 0 {
            return Err(BrdfError::InvalidInput { name, problem: "is empty".into() });
        }
        if *len != 1 && *len != n {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("has {len} rows, which does not broadcast against {n}"),
            });
        }
    }
    Ok(n)
}

/// The inputs of one batch: light, view and normal directions, optional tangents.
#[derive(Debug, Clone, Copy)]
pub struct Directions<'a> {
    /// Toward the light.
    pub l: Broadcast<'a, Vec3>,
    /// Toward the viewer.
    pub v: Broadcast<'a, Vec3>,
    /// Surface normal.
    pub n: Broadcast<'a, Vec3>,
    /// Tangent for anisotropic models.
    pub t: Option<Broadcast<'a, Vec3>>,
}

impl<'a> Directions<'a> {
    /// Check lengths and wrap; returns the batch length too.
    pub fn new(
        l: &'a [Vec3],
        v: &'a [Vec3],
        n: &'a [Vec3],
        t: Option<&'a [Vec3]>,
    ) -> Result<(Self, usize), BrdfError> {
        let mut lens = vec![("l", l.len()), ("v", v.len()), ("n", n.len())];
        if let Some(t) = t {
            lens.push(("tangent", t.len()));
        }
        let len = batch_len(&lens)?;
        let dirs = Self {
            l: Broadcast::new("l", l, len)?,
            v: Broadcast::new("v", v, len)?,
            n: Broadcast::new("n", n, len)?,
            t: t.map(|t| Broadcast::new("tangent", t, len)).transpose()?,
        };
        Ok((dirs, len))
    }

    /// The scalar geometry of element `i` (what [`evaluate`] computes, one sample at a time).
    #[inline(always)]
    pub fn geometry(&self, i: usize) -> Option<Geometry> {
        Geometry::new(self.l.get(i), self.v.get(i), self.n.get(i), self.t.map(|t| t.get(i)))
    }

    /// The geometry of elements `start .. end` (at most `F::LANES`, padded) and the lanes where it
    /// exists.
    #[inline(always)]
    fn lanes<F: Lane>(&self, start: usize, end: usize, bad: Option<&BadRows>) -> (LaneGeometry<F>, F::Mask) {
        let (l, v, n) = (self.l.lanes(start, end), self.v.lanes(start, end), self.n.lanes(start, end));
        let t = self.t.map(|t| t.lanes(start, end));
        if let Some(bad) = bad {
            let inputs = [(self.l, Some(l)), (self.v, Some(v)), (self.n, Some(n))];
            for (k, (b, x)) in inputs.into_iter().chain(self.t.map(|b| (b, t))).enumerate() {
                let Some(x) = x else { continue };
                let finite = x.is_finite();
                if !F::mask_all(finite) {
                    // Rare: find the lane (padding repeats the last row, so it is a real one).
                    let j = (0..F::LANES).find(|&j| !F::mask_lane(finite, j)).unwrap_or(0);
                    let row = if b.data.len() == 1 { 0 } else { start + j };
                    bad[k].fetch_min(row, Ordering::Relaxed);
                }
            }
        }
        LaneGeometry::new(l, v, n, t)
    }
}

/// The lowest row of each input (l, v, n, tangent) found to hold a non-finite value.
type BadRows = [AtomicUsize; 4];

/// A non-finite input value found by [`evaluate_checked`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NonFinite {
    /// The argument: "l", "v", "n" or "tangent".
    pub name: &'static str,
    /// Its lowest row holding a NaN or an infinity (0 for a broadcast input).
    pub row: usize,
}

/// Run `body(offset, chunk)` over `out` in fixed chunks, in parallel when large enough.
pub fn for_each_chunk<T: Send>(out: &mut [T], body: impl Fn(usize, &mut [T]) + Sync) {
    if out.len() < PARALLEL_THRESHOLD {
        body(0, out);
    } else {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, chunk)| body(c * CHUNK, chunk));
    }
}

fn run<M: Bxdf>(m: &M, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3], bad: Option<&BadRows>) {
    for_each_chunk(out, |offset, chunk| run_chunk(m, dirs, q, offset, chunk, bad));
}

/// One chunk, eight samples at a time: in one AVX register each where the CPU has AVX2 (run-time
/// detection, [`crate::simd`]), else in [`F32x8`] (two SSE registers). Same operations, same bits.
#[inline]
fn run_chunk<M: Bxdf>(
    m: &M,
    dirs: &Directions<'_>,
    q: Quantity,
    offset: usize,
    out: &mut [Vec3],
    bad: Option<&BadRows>,
) {
    let k = ChunkKernel { m, dirs, q, offset, out, bad };
    #[cfg(target_arch = "x86_64")]
    let Some(k) = crate::simd::dispatch_avx2(k) else { return };
    k.run::<F32x8>();
}

/// The arguments of [`run_chunk`], as a computation generic over the lane type.
struct ChunkKernel<'a, 'b, M> {
    m: &'a M,
    dirs: &'a Directions<'b>,
    q: Quantity,
    offset: usize,
    out: &'a mut [Vec3],
    /// Where to record non-finite inputs (`None`: no check).
    bad: Option<&'a BadRows>,
}

impl<M: Bxdf> LaneKernel for ChunkKernel<'_, '_, M> {
    /// Evaluate `out[k]` for element `offset + k`, `F::LANES` samples at a time.
    #[inline(always)]
    fn run<F: Lane>(self) {
        let Self { m, dirs, q, offset, out, bad } = self;
        for (k, group) in out.chunks_mut(F::LANES).enumerate() {
            let start = offset + k * F::LANES;
            let (g, valid) = dirs.lanes::<F>(start, start + group.len(), bad);
            let value = match q {
                Quantity::Brdf => eval_model_lanes(m, &g, valid),
                Quantity::Shade => shade_model_lanes(m, &g, valid),
            };
            if group.len() == F::LANES {
                F::store_rows(value, group);
            } else {
                for (j, o) in group.iter_mut().enumerate() {
                    *o = value.lane(j);
                }
            }
        }
    }
}

struct Run<'a, 'b> {
    dirs: &'a Directions<'b>,
    q: Quantity,
    out: &'a mut [Vec3],
    bad: Option<&'a BadRows>,
}

impl ModelVisitor for Run<'_, '_> {
    type Output = ();
    fn visit<M: Bxdf>(self, m: &M) {
        run(m, self.dirs, self.q, self.out, self.bad);
    }
}

/// Evaluate `model` for every element: `out[i] = f_r(l[i], v[i], n[i])` or the shade value.
///
/// Zero-length or non-finite directions give 0. `out.len()` must be the batch length.
pub fn evaluate(model: &Model, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3]) {
    model.visit(Run { dirs, q, out, bad: None });
}

/// [`evaluate`], refusing non-finite input: every component of every input row is checked in the same
/// pass, on the values already loaded into lanes (no second pass over memory). On a NaN or an
/// infinity it returns the first argument in the order l, v, n, tangent that holds one, with its
/// lowest row; `out` is then fully written but meaningless. The result does not depend on the
/// thread count.
pub fn evaluate_checked(
    model: &Model,
    dirs: &Directions<'_>,
    q: Quantity,
    out: &mut [Vec3],
) -> Result<(), NonFinite> {
    let bad: BadRows = std::array::from_fn(|_| AtomicUsize::new(usize::MAX));
    model.visit(Run { dirs, q, out, bad: Some(&bad) });
    for (b, name) in bad.iter().zip(["l", "v", "n", "tangent"]) {
        let row = b.load(Ordering::Relaxed);
        if row != usize::MAX {
            return Err(NonFinite { name, row });
        }
    }
    Ok(())
}

/// Allocate and evaluate: convenience over [`evaluate`].
pub fn evaluate_vec(
    model: &Model,
    l: &[Vec3],
    v: &[Vec3],
    n: &[Vec3],
    t: Option<&[Vec3]>,
    q: Quantity,
) -> Result<Vec<Vec3>, BrdfError> {
    let (dirs, len) = Directions::new(l, v, n, t)?;
    let mut out = vec![Vec3::ZERO; len];
    evaluate(model, &dirs, q, &mut out);
    Ok(out)
}

/// `true` when every value is finite (no NaN, no ±∞): the input check of a batch, one pass over
/// cache-resident data. The exponent-bits test (all ones ⇔ ∞ or NaN) is an integer reduction that
/// vectorises (`f32::is_finite` compiles to a slower per-element class test here), and it runs in the
/// AVX2 build on CPUs that have AVX2.
pub fn all_finite(xs: &[f32]) -> bool {
    struct Check<'a>(&'a [f32], &'a mut bool);
    impl LaneKernel for Check<'_> {
        #[inline(always)]
        fn run<F: Lane>(self) {
            const EXP: u32 = 0x7f80_0000;
            // Bit 31 of `(!x & EXP) − 1` is set exactly when the exponent bits of x are all ones.
            let bad = self.0.iter().fold(0u32, |acc, x| acc | ((!x.to_bits() & EXP).wrapping_sub(1) >> 31));
            *self.1 = bad == 0;
        }
    }
    let mut ok = false;
    let k = Check(xs, &mut ok);
    #[cfg(target_arch = "x86_64")]
    let Some(k) = crate::simd::dispatch_avx2(k) else { return ok };
    k.run::<f32>();
    ok
}

/// Apply `f` element-wise from `input` to `out` (same length), in parallel when large.
pub fn map<I: Copy + Sync, O: Send>(input: &[I], out: &mut [O], f: impl Fn(I) -> O + Sync) {
    for_each_chunk(out, |offset, chunk| {
        for (k, o) in chunk.iter_mut().enumerate() {
            *o = f(input[offset + k]);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::Lambert;

    #[test]
    fn broadcasting_and_degenerate_inputs() {
        let m: Model = Lambert::new(Vec3::splat(0.5)).into();
        let l = [Vec3::Z, Vec3::ZERO, -Vec3::Z];
        let out = evaluate_vec(&m, &l, &[Vec3::Z], &[Vec3::Z], None, Quantity::Brdf).unwrap();
        assert!((out[0].x - 0.5 / std::f32::consts::PI).abs() < 1e-7);
        assert_eq!(out[1], Vec3::ZERO); // zero-length light direction
        assert_eq!(out[2], Vec3::ZERO); // below the horizon
        let e = evaluate_vec(&m, &l, &[Vec3::Z; 2], &[Vec3::Z], None, Quantity::Brdf).unwrap_err();
        assert!(e.to_string().contains("\"v\""), "{e}");
    }

    /// Every model, eval and shade, on random directions with degenerate rows mixed in, broadcast and
    /// not, with and without tangents, over a length that leaves a partial group of lanes: the batch
    /// (eight-lane, possibly AVX2) gives exactly the bits of the scalar `Model::eval`/`shade`.
    #[test]
    fn batch_equals_scalar_evaluation_bit_for_bit_for_every_model() {
        let n = 1000 + 5;
        let mut seed = 0x2545_f491_u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let mut dirs = |k: usize| -> Vec<Vec3> {
            (0..k)
                .map(|i| match i % 97 {
                    13 => Vec3::ZERO,
                    41 => Vec3::new(0.0, 0.0, -1.0),
                    _ => Vec3::new(rnd(), rnd(), rnd().abs() * 1.5 + 0.05),
                })
                .collect()
        };
        let (l, v, t) = (dirs(n), dirs(n), dirs(n));
        let n_one = [Vec3::new(0.1, -0.2, 1.0)];
        let mut models: Vec<Model> =
            crate::MODEL_SPECS.iter().map(|s| Model::build(s.name, &[]).unwrap()).collect();
        for (d, g, f) in [
            ("beckmann", "smith", "dielectric"),
            ("ggx", "smith_separable", "conductor"),
            ("ggx", "v_groove", "schlick"),
            ("blinn_phong", "kelemen", "color_shift"),
        ] {
            let p = |k: &str, x: &str| (k.to_string(), crate::Input::Text(x.into()));
            models.push(
                Model::build("cook_torrance", &[p("distribution", d), p("masking", g), p("fresnel", f)])
                    .unwrap(),
            );
        }
        for m in &models {
            for q in [Quantity::Brdf, Quantity::Shade] {
                for tangent in [None, Some(&t[..])] {
                    let out = evaluate_vec(m, &l, &v, &n_one, tangent, q).unwrap();
                    let (d, _) = Directions::new(&l, &v, &n_one, tangent).unwrap();
                    // The portable lane type gives the same bits (the batch above took the AVX2 lanes on
                    // AVX2 CPUs).
                    struct Portable<'a, 'b>(&'a Directions<'b>, Quantity, &'a mut [Vec3]);
                    impl ModelVisitor for Portable<'_, '_> {
                        type Output = ();
                        fn visit<B: Bxdf>(self, m: &B) {
                            let Portable(dirs, q, out) = self;
                            ChunkKernel { m, dirs, q, offset: 0, out, bad: None }.run::<F32x8>();
                        }
                    }
                    let mut portable = vec![Vec3::ZERO; n];
                    m.visit(Portable(&d, q, &mut portable));
                    let bits = |x: &[Vec3]| {
                        x.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>()
                    };
                    assert!(bits(&portable) == bits(&out), "{} {q:?}: F32x8 lanes differ", m.spec().name);
                    for (i, o) in out.iter().enumerate() {
                        let want = match d.geometry(i) {
                            None => Vec3::ZERO,
                            Some(g) if q == Quantity::Brdf => m.eval(&g),
                            Some(g) => m.shade(&g),
                        };
                        let bits = |x: Vec3| x.to_array().map(f32::to_bits);
                        assert_eq!(bits(*o), bits(want), "{} {q:?} row {i}: {o} vs {want}", m.spec().name);
                    }
                }
            }
        }
    }

    #[test]
    fn evaluate_checked_names_the_first_argument_and_its_lowest_bad_row() {
        let m = Model::build("cook_torrance", &[]).unwrap();
        let n = 3 * PARALLEL_THRESHOLD + 5; // parallel, with a partial last group
        let good = vec![Vec3::new(0.1, 0.2, 1.0); n];
        let run = |l: &[Vec3], v: &[Vec3], t: Option<&[Vec3]>| {
            let (d, len) = Directions::new(l, v, &[Vec3::Z], t).unwrap();
            evaluate_checked(&m, &d, Quantity::Brdf, &mut vec![Vec3::ZERO; len])
        };
        assert_eq!(run(&good, &good, None), Ok(()));
        let mut l = good.clone();
        let mut v = good.clone();
        l[40_000] = Vec3::new(0.0, f32::NAN, 1.0);
        l[n - 1] = Vec3::new(f32::INFINITY, 0.0, 1.0);
        v[7] = Vec3::new(0.0, 0.0, f32::NEG_INFINITY);
        assert_eq!(run(&l, &v, None), Err(NonFinite { name: "l", row: 40_000 }));
        assert_eq!(run(&good, &v, None), Err(NonFinite { name: "v", row: 7 }));
        let mut t = good.clone();
        t[n - 1].x = f32::NAN; // in the padded last group
        assert_eq!(run(&good, &good, Some(&t)), Err(NonFinite { name: "tangent", row: n - 1 }));
        assert_eq!(run(&good, &[Vec3::splat(f32::NAN)], None), Err(NonFinite { name: "v", row: 0 }));
        // The values of finite rows are those of `evaluate`.
        let (d, _) = Directions::new(&good, &good, &[Vec3::Z], None).unwrap();
        let (mut a, mut b) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
        evaluate(&m, &d, Quantity::Shade, &mut a);
        evaluate_checked(&m, &d, Quantity::Shade, &mut b).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn all_finite_rejects_exactly_nan_and_infinities() {
        let mut xs: Vec<f32> = (0..1000).map(|i| (i as f32 * 0.37).sin() * 1e3).collect();
        xs.extend([0.0, -0.0, f32::MAX, f32::MIN, f32::MIN_POSITIVE, 1e-45, -1e-45]);
        assert!(all_finite(&xs) && all_finite(&[]));
        for bad in [f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::from_bits(0x7f80_0001)] {
            for at in [0, 17, xs.len() - 1] {
                let mut ys = xs.clone();
                ys[at] = bad;
                assert!(!all_finite(&ys), "{bad} at {at}");
            }
        }
    }

    #[test]
    fn parallel_result_equals_serial_bit_for_bit() {
        let m: Model = Lambert::new(Vec3::new(0.2, 0.5, 0.9)).into();
        let n = 3 * PARALLEL_THRESHOLD + 17;
        let l: Vec<Vec3> = (0..n).map(|i| Vec3::new((i as f32).sin(), (i as f32 * 0.7).cos(), 1.0)).collect();
        let par = evaluate_vec(&m, &l, &[Vec3::Z], &[Vec3::Z], None, Quantity::Shade).unwrap();
        let (dirs, _) = Directions::new(&l, &[Vec3::Z], &[Vec3::Z], None).unwrap();
        let mut serial = vec![Vec3::ZERO; n];
        for (i, o) in serial.iter_mut().enumerate() {
            *o = m.shade(&dirs.geometry(i).unwrap());
        }
        assert_eq!(par, serial);
    }
}
