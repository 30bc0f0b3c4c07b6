//! Batch evaluation over slices of `Vec3` (the layout of a C-contiguous NumPy `(N, 3)` float32 array).
//!
//! Every input is either one vector (broadcast) or `n` vectors. Work is split into fixed chunks that
//! rayon runs on the pool's threads; every output element depends only on its own inputs, so the
//! result is bit-identical for any number of threads.

use glam::Vec3;
use rayon::prelude::*;

use crate::models::{Bxdf, Model, ModelVisitor, eval_model, shade_model};
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

    #[inline(always)]
    fn geometry(&self, i: usize) -> Option<Geometry> {
        Geometry::new(self.l.get(i), self.v.get(i), self.n.get(i), self.t.map(|t| t.get(i)))
    }
}

/// Run `body(offset, chunk)` over `out` in fixed chunks, in parallel when large enough.
pub fn for_each_chunk<T: Send>(out: &mut [T], body: impl Fn(usize, &mut [T]) + Sync) {
    if out.len() < PARALLEL_THRESHOLD {
        body(0, out);
    } else {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, chunk)| body(c * CHUNK, chunk));
    }
}

fn run<M: Bxdf>(m: &M, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3]) {
    for_each_chunk(out, |offset, chunk| {
        for (k, o) in chunk.iter_mut().enumerate() {
            *o = match dirs.geometry(offset + k) {
                None => Vec3::ZERO,
                Some(g) => match q {
                    Quantity::Brdf => eval_model(m, &g),
                    Quantity::Shade => shade_model(m, &g),
                },
            };
        }
    });
}

struct Run<'a, 'b> {
    dirs: &'a Directions<'b>,
    q: Quantity,
    out: &'a mut [Vec3],
}

impl ModelVisitor for Run<'_, '_> {
    type Output = ();
    fn visit<M: Bxdf>(self, m: &M) {
        run(m, self.dirs, self.q, self.out);
    }
}

/// Evaluate `model` for every element: `out[i] = f_r(l[i], v[i], n[i])` or the shade value.
///
/// Zero-length or non-finite directions give 0. `out.len()` must be the batch length.
pub fn evaluate(model: &Model, dirs: &Directions<'_>, q: Quantity, out: &mut [Vec3]) {
    model.visit(Run { dirs, q, out });
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
