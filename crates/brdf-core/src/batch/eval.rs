//! Reflectance models over batches of directions, eight samples at a time.
//!
//! Inside a chunk ([`super::for_each_chunk`]), samples go eight at a time through the model's lane form
//! ([`Bxdf::f_lanes`], [`crate::simd`]): the rows are transposed into eight-lane registers,
//! normalised, evaluated and transposed back. The last, partial group is padded by repeating its last
//! row, so every sample takes the same path. On x86-64 CPUs with AVX2 (detected at run time) the lanes
//! are one AVX register, otherwise `wide`'s `f32x8`; both perform the same IEEE operations (no fused
//! multiply-add), so the bits do not depend on the CPU either, and they equal
//! [`Model::eval`]/[`Model::shade`] on each sample. [`evaluate_checked`] checks the inputs with the
//! rules of the module ([`super`]): inputs as large as the batch on the rows already loaded into lanes
//! (no second pass over memory), broadcast ones once before the run.

use glam::Vec3;

use super::{Arg, BadIndex, Batch, Shape, for_each_chunk};
use crate::models::{Bxdf, Model, ModelVisitor, eval_model_lanes, shade_model_lanes};
use crate::simd::{F32x8, Lane, LaneGeometry, LaneKernel, V3};
use crate::{BrdfError, Geometry};

/// Which quantity a batch computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// `f_r` [1/sr] ([`Model::eval`]).
    Brdf,
    /// What a renderer multiplies by the light color ([`Model::shade`]).
    Shade,
}

/// `l`, `v`, `n` and the optional tangent.
type Dirs<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>, Arg<'a, Vec3>, Option<Arg<'a, Vec3>>);

/// The directions of one batch: light, view and normal, and an optional tangent, broadcast together.
#[derive(Debug, Clone, Copy)]
pub struct Directions<'a> {
    batch: Batch<Dirs<'a>>,
}

impl<'a> Directions<'a> {
    /// Rows of directions (each slice of length 1, broadcast, or of the batch length); returns the
    /// batch length too.
    pub fn new(
        l: &'a [Vec3],
        v: &'a [Vec3],
        n: &'a [Vec3],
        t: Option<&'a [Vec3]>,
    ) -> Result<(Self, usize), BrdfError> {
        let t = t.map(|t| Arg::rows("tangent", t)).transpose()?;
        let d = Self::from_args(Arg::rows("l", l)?, Arg::rows("v", v)?, Arg::rows("n", n)?, t)?;
        let len = d.len();
        Ok((d, len))
    }

    /// Directions of any shapes that broadcast together (e.g. a `(90, 360)` grid of `l` with one `v`
    /// and one `n`).
    pub fn from_args(
        l: Arg<'a, Vec3>,
        v: Arg<'a, Vec3>,
        n: Arg<'a, Vec3>,
        t: Option<Arg<'a, Vec3>>,
    ) -> Result<Self, BrdfError> {
        Ok(Self { batch: Batch::new((l, v, n, t))? })
    }

    /// The broadcast shape (the output is this shape of RGB values).
    pub fn shape(&self) -> &Shape {
        self.batch.shape()
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.batch.len()
    }

    /// Never `true`: empty inputs are refused.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The scalar geometry of sample `i` (what [`evaluate`] computes, one sample at a time).
    #[inline]
    pub fn geometry(&self, i: usize) -> Option<Geometry> {
        let (l, v, n, t) = self.batch.inputs();
        Geometry::new(l.at(i), v.at(i), n.at(i), t.map(|t| t.at(i)))
    }
}

/// Evaluate `model` for every sample: `out[i] = f_r(l[i], v[i], n[i])` or the shade value.
///
/// Zero-length or non-finite directions give 0 (no check; see [`evaluate_checked`]).
///
/// # Panics
/// If `out.len()` is not the batch length.
pub fn evaluate(model: &Model, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3]) {
    assert_eq!(out.len(), dirs.len(), "evaluate: out must have one element per sample");
    model.visit(Run { dirs, q, out, bad: None });
}

/// [`evaluate`], refusing non-finite input (see the module docs of [`super`]): the error names the
/// first argument in the order l, v, n, tangent holding a NaN or an infinity, with its lowest index;
/// `out` is then fully written but meaningless. Also refuses an `out` of the wrong length. The result
/// does not depend on the thread count.
pub fn evaluate_checked(
    model: &Model,
    dirs: &Directions<'_>,
    q: Quantity,
    out: &mut [Vec3],
) -> Result<(), BrdfError> {
    struct Checked<'a, 'b> {
        dirs: &'a Directions<'b>,
        q: Quantity,
        out: &'a mut [Vec3],
    }
    impl ModelVisitor for Checked<'_, '_> {
        type Output = Result<(), BrdfError>;
        fn visit<M: Bxdf>(self, m: &M) -> Self::Output {
            evaluate_bxdf(m, self.dirs, self.q, self.out)
        }
    }
    model.visit(Checked { dirs, q, out })
}

/// [`evaluate_checked`] for a model type known at compile time (e.g. [`crate::measured::Measured`]).
pub fn evaluate_bxdf<M: Bxdf>(
    m: &M,
    dirs: &Directions<'_>,
    q: Quantity,
    out: &mut [Vec3],
) -> Result<(), BrdfError> {
    let b = &dirs.batch;
    b.check_out(Some(out.len()))?;
    b.check_broadcast_inputs()?;
    let bad = BadIndex::new();
    run(m, dirs, q, out, Some(&bad));
    b.report(&bad)
}

/// Allocate and evaluate: convenience over [`evaluate_checked`].
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
    evaluate_checked(model, &dirs, q, &mut out)?;
    Ok(out)
}

struct Run<'a, 'b> {
    dirs: &'a Directions<'b>,
    q: Quantity,
    out: &'a mut [Vec3],
    bad: Option<&'a BadIndex>,
}

impl ModelVisitor for Run<'_, '_> {
    type Output = ();
    fn visit<M: Bxdf>(self, m: &M) {
        run(m, self.dirs, self.q, self.out, self.bad);
    }
}

fn run<M: Bxdf>(m: &M, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3], bad: Option<&BadIndex>) {
    for_each_chunk(out, |offset, chunk: &mut [Vec3]| run_chunk(m, dirs, q, offset, chunk, bad));
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
    bad: Option<&BadIndex>,
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
    bad: Option<&'a BadIndex>,
}

impl<M: Bxdf> LaneKernel for ChunkKernel<'_, '_, M> {
    /// Evaluate `out[k]` for element `offset + k`, `F::LANES` samples at a time.
    #[inline(always)]
    fn run<F: Lane>(self) {
        let Self { m, dirs, q, offset, out, bad } = self;
        let (l, v, n, t) = dirs.batch.inputs();
        let (mut ol, mut ov, mut on) = (l.odometer(offset), v.odometer(offset), n.odometer(offset));
        let mut ot = t.and_then(|t| t.odometer(offset));
        // An input of one row (a fixed normal or viewer, broadcast) is normalised once here rather than
        // in every group: a square root and three divisions per group saved, same bits.
        let (ul, uv, un) = (normalized_once::<F>(l), normalized_once::<F>(v), normalized_once::<F>(n));
        let ut = t.as_ref().and_then(normalized_once::<F>);
        for (k, group) in out.chunks_mut(F::LANES).enumerate() {
            let (start, count) = (offset + k * F::LANES, group.len());
            let (gl, gv, gn) = (
                l.lanes::<F>(start, count, &mut ol),
                v.lanes::<F>(start, count, &mut ov),
                n.lanes::<F>(start, count, &mut on),
            );
            let gt = t.map(|t| t.lanes::<F>(start, count, &mut ot));
            if let Some(bad) = bad {
                // Inputs as large as the batch, on the values already loaded (padding repeats the last
                // row, so a bad lane is a real row); broadcast inputs were checked before the run.
                let loaded = [Some((l, gl)), Some((v, gv)), Some((n, gn)), t.as_ref().zip(gt)];
                for (arg, (a, x)) in loaded.into_iter().enumerate().filter_map(|(k, x)| Some((k, x?))) {
                    if !matches!(a.layout, super::Layout::Full) {
                        continue;
                    }
                    let finite = x.is_finite();
                    if !F::mask_all(finite) {
                        let j = (0..count).find(|&j| !F::mask_lane(finite, j)).unwrap_or(0);
                        debug_assert!(!a.at(start + j).is_finite());
                        bad.record(arg, start + j);
                    }
                }
            }
            let (g, valid) = LaneGeometry::from_normalized(
                normalized(ul, gl),
                normalized(uv, gv),
                normalized(un, gn),
                gt.map(|x| normalized(ut, x)),
            );
            let value = match q {
                Quantity::Brdf => eval_model_lanes(m, &g, valid),
                Quantity::Shade => shade_model_lanes(m, &g, valid),
            };
            if count == F::LANES {
                F::store_rows(value, group);
            } else {
                for (j, o) in group.iter_mut().enumerate() {
                    *o = value.lane(j);
                }
            }
        }
    }
}

/// An input of one row, normalised ([`V3::normalize_or_zero`]) in every lane; `None` for the others.
/// (Functions, not closures: a closure is not inlined into the AVX2 kernel with its target features.)
#[inline(always)]
fn normalized_once<F: Lane>(a: &Arg<'_, Vec3>) -> Option<(V3<F>, F::Mask)> {
    if matches!(a.layout, super::Layout::Single) {
        Some(a.lanes::<F>(0, 1, &mut None).normalize_or_zero())
    } else {
        None
    }
}

/// `x` normalised, or `pre` where the input was normalised once ([`normalized_once`]).
#[inline(always)]
fn normalized<F: Lane>(pre: Option<(V3<F>, F::Mask)>, x: V3<F>) -> (V3<F>, F::Mask) {
    match pre {
        Some(p) => p,
        None => x.normalize_or_zero(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::PARALLEL_THRESHOLD;
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
        assert!(e.to_string().starts_with("v:"), "{e}");
    }

    /// Every model, eval and shade, on random directions with degenerate rows mixed in, broadcast and
    /// not, with and without tangents, over a length that leaves a partial group of lanes, as rows and
    /// as a strided (partly broadcast) grid: the batch (eight-lane, possibly AVX2) gives exactly the
    /// bits of the scalar `Model::eval`/`shade`.
    #[test]
    fn batch_equals_scalar_evaluation_bit_for_bit_for_every_model() {
        let n = 35 * 29;
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
        let v_row = dirs(29);
        let n_one = Vec3::new(0.1, -0.2, 1.0);
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
        let bits = |x: &[Vec3]| x.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        for m in &models {
            for q in [Quantity::Brdf, Quantity::Shade] {
                for tangent in [None, Some(&t[..])] {
                    // (35, 29) grid of l with a (29,) row of v: v is strided.
                    let grid = |strided: bool| {
                        let l = Arg::new("l", &l, &[35, 29]).unwrap();
                        let v = if strided {
                            Arg::new("v", &v_row, &[29]).unwrap()
                        } else {
                            Arg::new("v", &v, &[35, 29]).unwrap()
                        };
                        let t = tangent.map(|t| Arg::new("tangent", t, &[35, 29]).unwrap());
                        Directions::from_args(l, v, Arg::one("n", &n_one), t).unwrap()
                    };
                    for d in [grid(false), grid(true)] {
                        let mut out = vec![Vec3::ZERO; n];
                        evaluate_checked(m, &d, q, &mut out).unwrap();
                        // The portable lane type gives the same bits (the batch above took the AVX2 lanes
                        // on AVX2 CPUs).
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
                        assert!(bits(&portable) == bits(&out), "{} {q:?}: F32x8 lanes differ", m.spec().name);
                        for (i, o) in out.iter().enumerate() {
                            let want = match d.geometry(i) {
                                None => Vec3::ZERO,
                                Some(g) if q == Quantity::Brdf => m.eval(&g),
                                Some(g) => m.shade(&g),
                            };
                            assert_eq!(
                                bits(&[*o]),
                                bits(&[want]),
                                "{} {q:?} row {i}: {o} vs {want}",
                                m.spec().name
                            );
                        }
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
            evaluate_checked(&m, &d, Quantity::Brdf, &mut vec![Vec3::ZERO; len]).map_err(|e| e.to_string())
        };
        assert_eq!(run(&good, &good, None), Ok(()));
        let mut l = good.clone();
        let mut v = good.clone();
        l[40_000] = Vec3::new(0.0, f32::NAN, 1.0);
        l[n - 1] = Vec3::new(f32::INFINITY, 0.0, 1.0);
        v[7] = Vec3::new(0.0, 0.0, f32::NEG_INFINITY);
        let has = |r: Result<(), String>, what: &[&str]| {
            let e = r.unwrap_err();
            assert!(what.iter().all(|w| e.contains(w)), "{e} lacks {what:?}");
        };
        has(run(&l, &v, None), &["l: ", "at l[40000]", "non-finite"]);
        has(run(&good, &v, None), &["v: ", "at v[7]"]);
        let mut t = good.clone();
        t[n - 1].x = f32::NAN; // in the padded last group
        has(run(&good, &good, Some(&t)), &["tangent: ", &format!("at tangent[{}]", n - 1)]);
        has(run(&good, &[Vec3::splat(f32::NAN)], None), &["v: ", "at v[0]"]);
        // A bad broadcast v after a bad full l: l is reported (argument order).
        has(run(&l, &[Vec3::splat(f32::NAN)], None), &["l: ", "at l[40000]"]);
        // The values of finite rows are those of `evaluate`.
        let (d, _) = Directions::new(&good, &good, &[Vec3::Z], None).unwrap();
        let (mut a, mut b) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
        evaluate(&m, &d, Quantity::Shade, &mut a);
        evaluate_checked(&m, &d, Quantity::Shade, &mut b).unwrap();
        assert_eq!(a, b);
        assert!(evaluate_checked(&m, &d, Quantity::Shade, &mut b[1..]).is_err());
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
