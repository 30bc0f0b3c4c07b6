//! Sampling and densities over batches, on the skeleton of [`crate::batch`]: inputs of any shapes that
//! broadcast (NumPy's rule), checked element by element (directions finite, `u` in `[0, 1)`; the error
//! names the first bad argument and its index), run in fixed chunks on the current rayon pool, eight
//! samples at a time through the lane form of the sampler. Every output element depends only on its
//! own inputs and on its flat index in the output (which keys the random numbers, [`super::rng`]), so
//! the result is the same bits for any chunking, thread count or lane width, and equals
//! [`Model::sample_with`] / [`Sampler::pdf`] element by element. The last, partial group of a chunk is
//! padded by repeating its last element.

use glam::Vec3;

use super::rng;
use super::{Sample, Sampler};
use crate::batch::{Arg, BadIndex, Batch, Check, Shape, ShapeOf, broadcast, for_each_chunk};
use crate::models::{Bxdf, ModelVisitor};
use crate::simd::{F32x8, Lane, LaneKernel};
use crate::{BrdfError, Model};

/// `v`, `n`, the optional tangent and the optional uniform numbers (as `Vec3`s: `u0, u1, u2`).
type SampleArgs<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>, Option<Arg<'a, Vec3>>, Option<Arg<'a, Vec3>>);

fn in_unit_interval(u: Vec3) -> bool {
    (0.0..1.0).contains(&u.x) && (0.0..1.0).contains(&u.y) && (0.0..1.0).contains(&u.z)
}

/// The requirement on `u`.
pub const U_CHECK: Check<Vec3> =
    Check::Valid { ok: in_unit_interval, problem: "must hold numbers in [0, 1) (finite)" };

/// Directions, weights and densities of a batch of samples.
pub type Samples = (Vec<Vec3>, Vec<Vec3>, Vec<f32>);

/// The inputs of a sampling batch, broadcast together (and to `count` samples when asked).
#[derive(Debug, Clone, Copy)]
pub struct SampleBatch<'a> {
    batch: Batch<SampleArgs<'a>>,
    shape: Shape,
    seed: u64,
}

impl<'a> SampleBatch<'a> {
    /// Views `v`, normals `n`, an optional tangent and optional uniform numbers `u` (each `u` element
    /// `[u0, u1, u2]` in `[0, 1)`: `u0` picks the lobe, `u1, u2` the direction), of shapes that
    /// broadcast. Without `u`, element `i` of the output uses [`rng::uniform3`]`(seed, i)`.
    /// With `count`, the output has the broadcast shape of the inputs and `(count,)`; inputs of one
    /// element each give `count` samples of that configuration.
    pub fn new(
        v: Arg<'a, Vec3>,
        n: Arg<'a, Vec3>,
        tangent: Option<Arg<'a, Vec3>>,
        u: Option<Arg<'a, Vec3>>,
        seed: u64,
        count: Option<usize>,
    ) -> Result<Self, BrdfError> {
        let u = u.map(|u| u.check(U_CHECK));
        let batch = Batch::new((v, n, tangent, u))?;
        let Some(c) = count else {
            return Ok(Self { shape: *batch.shape(), batch, seed });
        };
        if c == 0 {
            return Err(BrdfError::InvalidInput { name: "count", problem: "must be >= 1, got 0".into() });
        }
        let rows = Shape::rows(c);
        let shape = broadcast(&[
            ShapeOf { name: "inputs", shape: batch.shape(), item: &[] },
            ShapeOf { name: "count", shape: &rows, item: &[] },
        ])?;
        if shape == *batch.shape() {
            return Ok(Self { shape, batch, seed });
        }
        if batch.len() != 1 {
            return Err(BrdfError::InvalidInput {
                name: "count",
                problem: format!("is {c}, but the inputs broadcast to shape {:?}", batch.shape()),
            });
        }
        // One configuration, `count` samples: every input becomes a broadcast single element.
        let one = |a: &Arg<'a, Vec3>| Arg::one(a.name(), &a.data()[0]);
        let (v, n, t, u) = batch.inputs();
        let batch =
            Batch::new((one(v), one(n), t.as_ref().map(one), u.as_ref().map(|u| one(u).check(U_CHECK))))?;
        Ok(Self { shape, batch, seed })
    }

    /// [`SampleBatch::new`] from rows (slices of length 1 or the batch length).
    pub fn rows(
        v: &'a [Vec3],
        n: &'a [Vec3],
        tangent: Option<&'a [Vec3]>,
        u: Option<&'a [[f32; 3]]>,
        seed: u64,
        count: Option<usize>,
    ) -> Result<Self, BrdfError> {
        let t = tangent.map(|t| Arg::rows("tangent", t)).transpose()?;
        let u = u.map(|u| Arg::rows("u", bytemuck::cast_slice(u))).transpose()?;
        Self::new(Arg::rows("v", v)?, Arg::rows("n", n)?, t, u, seed, count)
    }

    /// The output's shape (without the item axes).
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.shape.len()
    }

    /// Never `true`: empty inputs are refused.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Draw every sample with `sampler` (which must be `model`'s) into `l`, `weight`, `pdf`, after
    /// the checks; on a bad input the error names it and the outputs hold anything.
    pub fn run(
        &self,
        model: &Model,
        sampler: &Sampler,
        l: &mut [Vec3],
        weight: &mut [Vec3],
        pdf: &mut [f32],
    ) -> Result<(), BrdfError> {
        let b = &self.batch;
        for (name, k) in [("l", l.len()), ("weight", weight.len()), ("pdf", pdf.len())] {
            if k != self.len() {
                return Err(BrdfError::InvalidInput {
                    name,
                    problem: format!("has {k} elements, expected {} (shape {:?})", self.len(), self.shape),
                });
            }
        }
        b.check_broadcast_inputs()?;
        let bad = BadIndex::new();
        model.visit(SampleVisit { batch: self, sampler, out: (l, weight, pdf), bad: &bad });
        b.report(&bad)
    }

    /// [`SampleBatch::run`] into new vectors.
    pub fn to_vec(&self, model: &Model, sampler: &Sampler) -> Result<Samples, BrdfError> {
        let n = self.len();
        let (mut l, mut w, mut p) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n], vec![0.0f32; n]);
        self.run(model, sampler, &mut l, &mut w, &mut p)?;
        Ok((l, w, p))
    }
}

type Out<'a> = (&'a mut [Vec3], &'a mut [Vec3], &'a mut [f32]);

struct SampleVisit<'a, 'b> {
    batch: &'a SampleBatch<'b>,
    sampler: &'a Sampler,
    out: Out<'a>,
    bad: &'a BadIndex,
}

impl ModelVisitor for SampleVisit<'_, '_> {
    type Output = ();
    fn visit<M: Bxdf>(self, m: &M) {
        let Self { batch, sampler, out, bad } = self;
        for_each_chunk(out, |offset, chunk: Out<'_>| {
            batch.batch.check_chunk(offset, chunk.0.len(), bad);
            let k = SampleKernel { m, sampler, batch, offset, out: chunk };
            #[cfg(target_arch = "x86_64")]
            let Some(k) = crate::simd::dispatch_avx2(k) else { return };
            k.run::<F32x8>();
        });
    }
}

struct SampleKernel<'a, 'b, M> {
    m: &'a M,
    sampler: &'a Sampler,
    batch: &'a SampleBatch<'b>,
    offset: usize,
    out: Out<'a>,
}

impl<M: Bxdf> LaneKernel for SampleKernel<'_, '_, M> {
    /// Samples `offset + k` into `out.*[k]`, `F::LANES` at a time.
    #[inline(always)]
    fn run<F: Lane>(self) {
        let Self { m, sampler, batch, offset, out: (l, weight, pdf) } = self;
        let (v, n, t, u) = batch.batch.inputs();
        let key = rng::key(batch.seed);
        let (mut ov, mut on) = (v.odometer(offset), n.odometer(offset));
        let mut ot = t.and_then(|t| t.odometer(offset));
        let mut ou = u.and_then(|u| u.odometer(offset));
        for k in (0..l.len()).step_by(F::LANES) {
            let count = (l.len() - k).min(F::LANES);
            let start = offset + k;
            let gv = v.lanes::<F>(start, count, &mut ov);
            let gn = n.lanes::<F>(start, count, &mut on);
            let gt = t.map(|t| t.lanes::<F>(start, count, &mut ot));
            let gu: [F; 3] = match u {
                Some(u) => {
                    let x = u.lanes::<F>(start, count, &mut ou);
                    [x.x, x.y, x.z]
                }
                None => std::array::from_fn(|d| {
                    F::from_fn(|j| rng::uniform_keyed(key, (start + j.min(count - 1)) as u64, d as u64))
                }),
            };
            let s: Sample<F> = sampler.sample_lanes(m, gv, gn, gt, gu);
            for j in 0..count {
                l[k + j] = s.l.lane(j);
                weight[k + j] = s.weight.lane(j);
                pdf[k + j] = s.pdf.lane(j);
            }
        }
    }
}

/// `l`, `v`, `n` and the optional tangent of a density batch.
type PdfArgs<'a> = (Arg<'a, Vec3>, Arg<'a, Vec3>, Arg<'a, Vec3>, Option<Arg<'a, Vec3>>);

/// The inputs of a density batch, broadcast together.
#[derive(Debug, Clone, Copy)]
pub struct PdfBatch<'a> {
    batch: Batch<PdfArgs<'a>>,
}

impl<'a> PdfBatch<'a> {
    /// Directions `l`, views `v`, normals `n` and an optional tangent, of shapes that broadcast.
    pub fn new(
        l: Arg<'a, Vec3>,
        v: Arg<'a, Vec3>,
        n: Arg<'a, Vec3>,
        tangent: Option<Arg<'a, Vec3>>,
    ) -> Result<Self, BrdfError> {
        Ok(Self { batch: Batch::new((l, v, n, tangent))? })
    }

    /// [`PdfBatch::new`] from rows.
    pub fn rows(
        l: &'a [Vec3],
        v: &'a [Vec3],
        n: &'a [Vec3],
        tangent: Option<&'a [Vec3]>,
    ) -> Result<Self, BrdfError> {
        let t = tangent.map(|t| Arg::rows("tangent", t)).transpose()?;
        Self::new(Arg::rows("l", l)?, Arg::rows("v", v)?, Arg::rows("n", n)?, t)
    }

    /// The output's shape.
    pub fn shape(&self) -> &Shape {
        self.batch.shape()
    }

    /// The number of densities.
    pub fn len(&self) -> usize {
        self.batch.len()
    }

    /// Never `true`: empty inputs are refused.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every density into `out`, after the checks.
    pub fn run(&self, sampler: &Sampler, out: &mut [f32]) -> Result<(), BrdfError> {
        let b = &self.batch;
        b.check_out(Some(out.len()))?;
        b.check_broadcast_inputs()?;
        let bad = BadIndex::new();
        for_each_chunk(out, |offset, chunk: &mut [f32]| {
            b.check_chunk(offset, chunk.len(), &bad);
            let k = PdfKernel { sampler, batch: self, offset, out: chunk };
            #[cfg(target_arch = "x86_64")]
            let Some(k) = crate::simd::dispatch_avx2(k) else { return };
            k.run::<F32x8>();
        });
        b.report(&bad)
    }

    /// [`PdfBatch::run`] into a new vector.
    pub fn to_vec(&self, sampler: &Sampler) -> Result<Vec<f32>, BrdfError> {
        let mut out = vec![0.0f32; self.len()];
        self.run(sampler, &mut out)?;
        Ok(out)
    }
}

struct PdfKernel<'a, 'b> {
    sampler: &'a Sampler,
    batch: &'a PdfBatch<'b>,
    offset: usize,
    out: &'a mut [f32],
}

impl LaneKernel for PdfKernel<'_, '_> {
    #[inline(always)]
    fn run<F: Lane>(self) {
        let Self { sampler, batch, offset, out } = self;
        let (l, v, n, t) = batch.batch.inputs();
        let (mut ol, mut ov, mut on) = (l.odometer(offset), v.odometer(offset), n.odometer(offset));
        let mut ot = t.and_then(|t| t.odometer(offset));
        for k in (0..out.len()).step_by(F::LANES) {
            let count = (out.len() - k).min(F::LANES);
            let start = offset + k;
            let p = sampler.pdf_lanes(
                l.lanes::<F>(start, count, &mut ol),
                v.lanes::<F>(start, count, &mut ov),
                n.lanes::<F>(start, count, &mut on),
                t.map(|t| t.lanes::<F>(start, count, &mut ot)),
            );
            for j in 0..count {
                out[k + j] = p.lane(j);
            }
        }
    }
}
