//! Batches: one skeleton for every function that runs over arrays of inputs, in Rust and in Python.
//!
//! A batch function takes named inputs ([`Arg`]): a slice of elements (numbers `f32`, vectors `Vec3`,
//! …) and its shape without the item axis, i.e. a C-contiguous NumPy array of shape `(..., 3)` for
//! vectors or `(...)` for numbers. The rules, the same for every function and every caller:
//!
//! - **Broadcasting** ([`broadcast`]): the leading shapes combine by NumPy's rule (aligned at the
//!   right, each size equal or 1); the output has the broadcast shape followed by the output's item
//!   axis. A `(3,)` vector has leading shape `()`, so single vectors in give a single result out.
//!   An input with no element is refused (`is empty`), as is a shape that does not broadcast, and a
//!   broadcast shape of more than [`MAX_BATCH_LEN`] (2³²) elements; the messages name the argument and
//!   show the shapes.
//! - **Checks** ([`Check`]): every input element is checked before it is used, by default for
//!   NaN/±∞ (the Python package refuses a float64 value beyond the float32 range when it converts
//!   it, naming it, instead of letting it arrive as ∞); a function may ask for more
//!   (cosines in `[-1, 1]`) or nothing (tone mapping takes any float). The error names the first
//!   argument, in argument order, holding a bad element, and that argument's lowest bad index in its
//!   own shape. Inputs as large as the output are checked chunk by chunk while the chunk is in the
//!   cache; the others (broadcast ones, smaller) once before the run.
//! - **Chunks and threads** ([`for_each_chunk`]): below [`PARALLEL_THRESHOLD`] elements the batch runs
//!   on the calling thread; above, in chunks of [`CHUNK`] elements on the current rayon pool. Every
//!   output element depends only on its own inputs and the chunk boundaries do not depend on the
//!   thread count, so the output — and the error reported — is bit-identical for any thread count.
//! - **Output**: the caller allocates it once, from [`Batch::shape`] (`Vec` in Rust, a NumPy array in
//!   the Python binding) and hands it over as a slice, or a tuple of slices for several outputs
//!   ([`Outputs`]); nothing else is allocated per element.
//!
//! Two drivers share these rules: [`Batch::map`] (any per-element function, scalar code) and
//! [`evaluate_checked`] (reflectance models, eight samples at a time through the model's lane form).
//! [`ops`] holds the batch forms of the standalone functions (vectors, microfacet terms, Fresnel, tone
//! mapping) that the Python binding exposes. A function is written as
//!
//! ```
//! use brdf_core::batch::{Arg, Batch};
//! use glam::Vec3;
//! let w = [Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.6, 0.0, 0.8)];
//! let n = Vec3::Z;
//! // Inputs: (2,) rows and one vector. Broadcast, then one output of the batch's length.
//! let b = Batch::new((Arg::rows("w", &w)?, Arg::one("n", &n)))?;
//! let mut cos = vec![0.0f32; b.len()];
//! b.map(|(w, n): (Vec3, Vec3)| w.dot(n)).run(&mut cos[..])?;
//! assert_eq!(cos, [0.8, 0.8]);
//! # Ok::<(), brdf_core::BrdfError>(())
//! ```

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::BrdfError;
use crate::simd::{Lane, LaneKernel, V3};

mod eval;
pub mod ops;
mod shape;

pub use eval::{Directions, Quantity, evaluate, evaluate_bxdf, evaluate_checked, evaluate_vec};
use shape::{Layout, Odometer};
pub use shape::{MAX_BATCH_LEN, MAX_DIMS, Shape, ShapeOf, broadcast};

/// Below this many elements a batch runs on the calling thread (spawning costs more than it saves);
/// the Python binding also keeps the GIL below it.
pub const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Elements per parallel task (inputs and output of a chunk stay in the L2 cache).
pub const CHUNK: usize = 8 * 1024;

/// `true` when a batch of `len` elements runs in parallel chunks ([`for_each_chunk`]).
#[inline]
pub fn runs_in_parallel(len: usize) -> bool {
    len >= PARALLEL_THRESHOLD
}

/// Check the shape of an output array a caller provides (`out=`): it must be the batch's `shape`
/// followed by the item axis `item` exactly (no broadcasting into it, no reshaping), so that the result
/// is where the caller will read it. The error names the argument and shows both shapes.
pub fn check_out_shape(
    name: &'static str,
    shape: &Shape,
    item: &[usize],
    got: &[usize],
) -> Result<(), BrdfError> {
    let want = shape.with_item(item);
    if want == got {
        return Ok(());
    }
    Err(BrdfError::InvalidInput {
        name,
        problem: format!(
            "expected shape {} (the broadcast shape of the inputs{}), got {}",
            shape::tuple(&want, &[]),
            match item {
                [] => String::new(),
                _ => format!(
                    " followed by {}",
                    item.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ")
                ),
            },
            shape::tuple(got, &[])
        ),
    })
}

/// An element type of batch inputs: its item shape (for messages and output allocation) and its
/// finiteness test.
pub trait Element: Copy + Send + Sync + std::fmt::Debug + 'static {
    /// The item axis: `[3]` for vectors, `[]` for numbers.
    const ITEM: &'static [usize];
    /// `true` when every component is finite.
    fn is_finite(self) -> bool;
    /// The lowest index of an element that is not finite (vectorised where the type allows).
    #[inline]
    fn first_non_finite(xs: &[Self]) -> Option<usize> {
        xs.iter().position(|x| !x.is_finite())
    }
    /// The value as Python prints it (`0.5`, `nan`, `[0.0, 1.0, inf]`), for messages.
    fn show(self) -> String;
}

/// A number as Python prints it.
fn show_float(x: f64) -> String {
    match x {
        x if x.is_nan() => "nan".into(),
        f64::INFINITY => "inf".into(),
        f64::NEG_INFINITY => "-inf".into(),
        x => format!("{x:?}"),
    }
}

impl Element for f32 {
    const ITEM: &'static [usize] = &[];
    fn show(self) -> String {
        // Through the shortest decimal of the f32 (0.1f32 shows as 0.1, not 0.10000000149011612).
        show_float(format!("{self}").parse().unwrap_or(f64::from(self)))
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn first_non_finite(xs: &[Self]) -> Option<usize> {
        if all_finite(xs) { None } else { xs.iter().position(|x| !x.is_finite()) }
    }
}

impl Element for Vec3 {
    const ITEM: &'static [usize] = &[3];
    fn show(self) -> String {
        format!("[{}, {}, {}]", self.x.show(), self.y.show(), self.z.show())
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        Vec3::is_finite(self)
    }
    #[inline]
    fn first_non_finite(xs: &[Self]) -> Option<usize> {
        if all_finite(bytemuck::cast_slice(xs)) { None } else { xs.iter().position(|x| !x.is_finite()) }
    }
}

impl Element for f64 {
    const ITEM: &'static [usize] = &[];
    fn show(self) -> String {
        show_float(self)
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

impl Element for DVec3 {
    const ITEM: &'static [usize] = &[3];
    fn show(self) -> String {
        format!("[{}, {}, {}]", self.x.show(), self.y.show(), self.z.show())
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        DVec3::is_finite(self)
    }
}

/// What every element of an input must satisfy.
#[derive(Debug, Clone, Copy)]
pub enum Check<T> {
    /// Finite (the default): no NaN, no ±∞.
    Finite,
    /// Anything (e.g. tone mapping, which maps NaN to 0 itself).
    Any,
    /// `ok(x)`; `problem` says what is required, e.g. "must hold finite cosines in [-1, 1]".
    Valid {
        /// The test of one element.
        ok: fn(T) -> bool,
        /// The requirement, as the message states it.
        problem: &'static str,
    },
}

const NON_FINITE: &str = "contains a non-finite value (NaN or inf, or beyond the float32 range)";

impl<T: Element> Check<T> {
    fn first_bad(&self, xs: &[T]) -> Option<usize> {
        match self {
            Check::Finite => T::first_non_finite(xs),
            Check::Any => None,
            Check::Valid { ok, .. } => {
                // Branch-free scan first (the common all-good case), then the position.
                if xs.iter().fold(true, |a, &x| a & ok(x)) { None } else { xs.iter().position(|&x| !ok(x)) }
            }
        }
    }
}

/// One named input of a batch: elements in C order and their shape without the item axis. Checked for
/// non-finite values unless [`Arg::check`] says otherwise.
#[derive(Debug, Clone, Copy)]
pub struct Arg<'a, T> {
    name: &'static str,
    data: &'a [T],
    shape: Shape,
    check: Check<T>,
    layout: Layout,
}

impl<'a, T: Element> Arg<'a, T> {
    /// `data` (C order) with leading shape `shape`; refused when the sizes disagree, when there is no
    /// element, or beyond [`MAX_DIMS`] dimensions.
    pub fn new(name: &'static str, data: &'a [T], shape: &[usize]) -> Result<Self, BrdfError> {
        let item = |s: &[usize]| shape::tuple(s, T::ITEM);
        let s = Shape::new(shape).ok_or_else(|| BrdfError::InvalidInput {
            name,
            problem: format!(
                "has {} dimensions; at most {MAX_DIMS} are supported",
                shape.len() + T::ITEM.len()
            ),
        })?;
        if s.is_empty() || data.is_empty() {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("is empty (shape {})", item(shape)),
            });
        }
        if s.len() != data.len() {
            return Err(BrdfError::InvalidInput {
                name,
                problem: format!("has {} elements, but shape {} holds {}", data.len(), item(shape), s.len()),
            });
        }
        Ok(Self { name, data, shape: s, check: Check::Finite, layout: Layout::Full })
    }

    /// `data` as rows, shape `(data.len(),)`.
    pub fn rows(name: &'static str, data: &'a [T]) -> Result<Self, BrdfError> {
        Self::new(name, data, &[data.len()])
    }

    /// One element, shape `()`: broadcast to every output element.
    pub fn one(name: &'static str, x: &'a T) -> Self {
        Self {
            name,
            data: std::slice::from_ref(x),
            shape: Shape::SCALAR,
            check: Check::Finite,
            layout: Layout::Single,
        }
    }

    /// The same input with another requirement on its elements.
    pub fn check(self, check: Check<T>) -> Self {
        Self { check, ..self }
    }

    /// The argument's name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// Its shape without the item axis.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// Its elements.
    pub fn data(&self) -> &'a [T] {
        self.data
    }

    /// Element read by output element `i` of the batch it is in.
    #[inline]
    pub(crate) fn at(&self, i: usize) -> T {
        self.data[self.layout.index(i)]
    }

    fn shape_of(&self) -> ShapeOf<'_> {
        ShapeOf { name: self.name, shape: &self.shape, item: T::ITEM }
    }

    /// The error for element `index` (flat) of this input.
    fn bad(&self, index: usize) -> BrdfError {
        let what = match self.check {
            Check::Valid { problem, .. } => problem,
            _ => NON_FINITE,
        };
        let at = match self.shape.ndim() {
            0 => String::new(),
            _ => {
                let idx: Vec<String> = self.shape.unravel(index).iter().map(|i| i.to_string()).collect();
                format!(" at {}[{}]", self.name, idx.join(", "))
            }
        };
        BrdfError::InvalidInput {
            name: self.name,
            problem: format!("{what}{at}: {}", self.data[index].show()),
        }
    }

    /// The walker of a strided input from output element `start` (`None` for the other layouts).
    pub(crate) fn odometer(&self, start: usize) -> Option<Odometer> {
        match &self.layout {
            Layout::Strided(s) => Some(Odometer::new(s, start)),
            _ => None,
        }
    }
}

impl Arg<'_, Vec3> {
    /// Rows `start .. start + count` (`count ≤ F::LANES`) as lanes, padded with the last row; `odo`
    /// walks a strided input (created at the chunk's first element by [`Arg::odometer`]).
    #[inline(always)]
    pub(crate) fn lanes<F: Lane>(&self, start: usize, count: usize, odo: &mut Option<Odometer>) -> V3<F> {
        match (&self.layout, odo) {
            (Layout::Single, _) => V3::splat(self.data[0]),
            (Layout::Full, _) => {
                let rows = &self.data[start..start + count];
                if count == F::LANES { F::load_rows(rows) } else { V3::from_fn(|j| rows[j.min(count - 1)]) }
            }
            (Layout::Strided(_), Some(o)) => {
                let mut buf = [Vec3::ZERO; 8];
                for b in buf.iter_mut().take(count) {
                    *b = self.data[o.next_index()];
                }
                V3::from_fn(|j| buf[j.min(count - 1)])
            }
            (Layout::Strided(_), None) => V3::from_fn(|j| self.at(start + j.min(count - 1))),
        }
    }
}

/// Reads the elements of one input for consecutive output elements.
#[derive(Debug, Clone)]
pub struct Cursor<'a, T> {
    data: &'a [T],
    pos: usize,
    odo: Option<Odometer>,
    single: bool,
}

impl<T: Copy> Cursor<'_, T> {
    /// The element of the current output element; then step to the next.
    #[inline(always)]
    pub fn next_item(&mut self) -> T {
        if self.single {
            return self.data[0];
        }
        if let Some(o) = self.odo.as_mut() {
            return self.data[o.next_index()];
        }
        let x = self.data[self.pos];
        self.pos += 1;
        x
    }
}

/// One input slot of a batch: an [`Arg`], or an optional one (`None` gives `None` items).
pub trait Input<'a>: Send + Sync {
    /// What the input gives per output element.
    type Item: Copy;
    /// Its reader.
    type Cursor;
    /// The argument, if present (for broadcasting and checks).
    fn arg(&self) -> Option<&dyn AnyArg>;
    /// Fix the layout for a batch of shape `out`.
    fn resolve(&mut self, out: &Shape);
    /// A reader positioned at output element `start`.
    fn cursor(&self, start: usize) -> Self::Cursor;
    /// The element for the current output element of `c`, then step.
    fn next(c: &mut Self::Cursor) -> Self::Item;
}

/// The type-erased part of an [`Arg`] that broadcasting and checking need.
pub trait AnyArg: Sync {
    /// Name, shape, item.
    fn shape_of(&self) -> ShapeOf<'_>;
    /// `true` when the input has as many elements as the batch (checked chunk by chunk).
    fn full(&self) -> bool;
    /// The lowest bad index among elements `start .. start + len` (the whole input: `0, usize::MAX`).
    fn first_bad(&self, start: usize, len: usize) -> Option<usize>;
    /// The error for bad element `index`.
    fn error(&self, index: usize) -> BrdfError;
}

impl<T: Element> AnyArg for Arg<'_, T> {
    fn shape_of(&self) -> ShapeOf<'_> {
        Arg::shape_of(self)
    }
    fn full(&self) -> bool {
        matches!(self.layout, Layout::Full)
    }
    fn first_bad(&self, start: usize, len: usize) -> Option<usize> {
        let end = start.saturating_add(len).min(self.data.len());
        self.check.first_bad(&self.data[start..end]).map(|i| start + i)
    }
    fn error(&self, index: usize) -> BrdfError {
        self.bad(index)
    }
}

impl<'a, T: Element> Input<'a> for Arg<'a, T> {
    type Item = T;
    type Cursor = Cursor<'a, T>;
    fn arg(&self) -> Option<&dyn AnyArg> {
        Some(self)
    }
    fn resolve(&mut self, out: &Shape) {
        self.layout = Layout::of(&self.shape, out);
    }
    #[inline(always)]
    fn cursor(&self, start: usize) -> Cursor<'a, T> {
        let single = matches!(self.layout, Layout::Single);
        Cursor { data: self.data, pos: start, odo: self.odometer(start), single }
    }
    #[inline(always)]
    fn next(c: &mut Cursor<'a, T>) -> T {
        c.next_item()
    }
}

impl<'a, T: Element> Input<'a> for Option<Arg<'a, T>> {
    type Item = Option<T>;
    type Cursor = Option<Cursor<'a, T>>;
    fn arg(&self) -> Option<&dyn AnyArg> {
        self.as_ref().map(|a| a as &dyn AnyArg)
    }
    fn resolve(&mut self, out: &Shape) {
        if let Some(a) = self {
            a.resolve(out);
        }
    }
    #[inline(always)]
    fn cursor(&self, start: usize) -> Self::Cursor {
        self.as_ref().map(|a| a.cursor(start))
    }
    #[inline(always)]
    fn next(c: &mut Self::Cursor) -> Option<T> {
        c.as_mut().map(Cursor::next_item)
    }
}

/// The inputs of a batch: a tuple of [`Input`]s (up to five).
pub trait Inputs<'a>: Send + Sync {
    /// The tuple of items per output element.
    type Item: Copy;
    /// The tuple of readers.
    type Cursor;
    /// The arguments present, in order.
    fn args(&self) -> Vec<&dyn AnyArg>;
    /// Fix every layout for a batch of shape `out`.
    fn resolve(&mut self, out: &Shape);
    /// Readers positioned at output element `start`.
    fn cursor(&self, start: usize) -> Self::Cursor;
    /// The items of the current output element, then step.
    fn next(c: &mut Self::Cursor) -> Self::Item;
}

macro_rules! inputs_tuple {
    ($($t:ident $i:tt),+) => {
        impl<'a, $($t: Input<'a>),+> Inputs<'a> for ($($t,)+) {
            type Item = ($($t::Item,)+);
            type Cursor = ($($t::Cursor,)+);
            fn args(&self) -> Vec<&dyn AnyArg> {
                [$(self.$i.arg()),+].into_iter().flatten().collect()
            }
            fn resolve(&mut self, out: &Shape) {
                $(self.$i.resolve(out);)+
            }
            #[inline(always)]
            fn cursor(&self, start: usize) -> Self::Cursor {
                ($(self.$i.cursor(start),)+)
            }
            #[inline(always)]
            fn next(c: &mut Self::Cursor) -> Self::Item {
                ($($t::next(&mut c.$i),)+)
            }
        }
    };
}
inputs_tuple!(A 0);
inputs_tuple!(A 0, B 1);
inputs_tuple!(A 0, B 1, C 2);
inputs_tuple!(A 0, B 1, C 2, D 3);
inputs_tuple!(A 0, B 1, C 2, D 3, E 4);

/// Where a batch writes: a mutable slice, or a tuple of slices of the same length for several outputs
/// (e.g. a direction and a flag). Split into chunks for the threads.
pub trait Outputs: Send + Sized {
    /// What one output element receives.
    type Item;
    /// The number of elements (`None` when the slices of a tuple differ in length).
    fn elements(&self) -> Option<usize>;
    /// Elements `..mid` and `mid..`.
    fn split_at(self, mid: usize) -> (Self, Self);
    /// Write element `i`.
    fn set(&mut self, i: usize, x: Self::Item);
}

impl<T: Send> Outputs for &mut [T] {
    type Item = T;
    #[inline]
    fn elements(&self) -> Option<usize> {
        Some(<[T]>::len(self))
    }
    #[inline]
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
    #[inline(always)]
    fn set(&mut self, i: usize, x: T) {
        self[i] = x;
    }
}

macro_rules! outputs_tuple {
    ($($t:ident $i:tt),+) => {
        impl<$($t: Outputs),+> Outputs for ($($t,)+) {
            type Item = ($($t::Item,)+);
            fn elements(&self) -> Option<usize> {
                let lens = [$(self.$i.elements()),+];
                lens.iter().all(|l| *l == lens[0]).then_some(lens[0]).flatten()
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                let parts = ($(self.$i.split_at(mid),)+);
                (($(parts.$i.0,)+), ($(parts.$i.1,)+))
            }
            #[inline(always)]
            fn set(&mut self, i: usize, x: Self::Item) {
                $(self.$i.set(i, x.$i);)+
            }
        }
    };
}
outputs_tuple!(A 0, B 1);
outputs_tuple!(A 0, B 1, C 2);
outputs_tuple!(A 0, B 1, C 2, D 3);

/// The inputs of one batch, broadcast to a common shape (see the module docs for the rules).
#[derive(Debug, Clone, Copy)]
pub struct Batch<I> {
    inputs: I,
    shape: Shape,
}

impl<'a, I: Inputs<'a>> Batch<I> {
    /// Broadcast `inputs` (a tuple of [`Arg`] / `Option<Arg>`), naming the first that does not fit.
    pub fn new(mut inputs: I) -> Result<Self, BrdfError> {
        let shape = {
            let args = inputs.args();
            let shapes: Vec<ShapeOf<'_>> = args.iter().map(|a| a.shape_of()).collect();
            broadcast(&shapes)?
        };
        inputs.resolve(&shape);
        Ok(Self { inputs, shape })
    }

    /// The broadcast shape (without the output's item axis).
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// The number of output elements.
    pub fn len(&self) -> usize {
        self.shape.len()
    }

    /// Never `true`: empty inputs are refused.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The inputs.
    pub fn inputs(&self) -> &I {
        &self.inputs
    }

    /// The batch with the per-element function `f` (see [`Map::run`]).
    pub fn map<F>(self, f: F) -> Map<I, F> {
        Map { batch: self, f }
    }

    /// Check that `out` has one element per batch element.
    pub(crate) fn check_out(&self, len: Option<usize>) -> Result<(), BrdfError> {
        match len {
            Some(k) if k == self.len() => Ok(()),
            _ => Err(BrdfError::InvalidInput {
                name: "out",
                problem: format!(
                    "has {}, expected {} elements (shape {:?})",
                    len.map_or("slices of different lengths".to_string(), |k| format!("{k} elements")),
                    self.len(),
                    self.shape
                ),
            }),
        }
    }

    /// Check the inputs that are not as large as the batch (broadcast ones), each once. On a bad one,
    /// the full inputs before it are checked too, so that the first bad argument is reported.
    pub(crate) fn check_broadcast_inputs(&self) -> Result<(), BrdfError> {
        let args = self.inputs.args();
        for (k, a) in args.iter().enumerate() {
            if a.full() {
                continue;
            }
            if let Some(i) = a.first_bad(0, usize::MAX) {
                for b in &args[..k] {
                    if let Some(j) = b.first_bad(0, usize::MAX) {
                        return Err(b.error(j));
                    }
                }
                return Err(a.error(i));
            }
        }
        Ok(())
    }

    /// Check the full inputs' elements `start .. start + len`, recording the lowest bad index of each.
    #[inline]
    pub(crate) fn check_chunk(&self, start: usize, len: usize, bad: &BadIndex) {
        for (k, a) in self.inputs.args().iter().enumerate() {
            if a.full() {
                if let Some(i) = a.first_bad(start, len) {
                    bad.record(k, i);
                }
            }
        }
    }

    /// The error for the first argument with a recorded bad element.
    pub(crate) fn report(&self, bad: &BadIndex) -> Result<(), BrdfError> {
        let args = self.inputs.args();
        match bad.first() {
            Some((k, i)) => Err(args[k].error(i)),
            None => Ok(()),
        }
    }
}

/// The lowest bad element index found so far for each argument (written by concurrent chunks).
pub(crate) struct BadIndex([AtomicUsize; 5]);

impl BadIndex {
    pub(crate) fn new() -> Self {
        Self(std::array::from_fn(|_| AtomicUsize::new(usize::MAX)))
    }
    #[inline]
    pub(crate) fn record(&self, arg: usize, index: usize) {
        self.0[arg].fetch_min(index, Ordering::Relaxed);
    }
    fn first(&self) -> Option<(usize, usize)> {
        self.0.iter().enumerate().find_map(|(k, a)| {
            let i = a.load(Ordering::Relaxed);
            (i != usize::MAX).then_some((k, i))
        })
    }
}

/// A batch and the function of one element's inputs that computes its output.
#[derive(Clone, Copy)]
pub struct Map<I, F> {
    batch: Batch<I>,
    f: F,
}

impl<I: std::fmt::Debug, F> std::fmt::Debug for Map<I, F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Map").field("batch", &self.batch).finish_non_exhaustive()
    }
}

impl<'a, I: Inputs<'a>, F> Map<I, F> {
    /// The broadcast shape (without the output's item axis).
    pub fn shape(&self) -> &Shape {
        &self.batch.shape
    }

    /// The number of output elements.
    pub fn len(&self) -> usize {
        self.batch.len()
    }

    /// Never `true`: empty inputs are refused.
    pub fn is_empty(&self) -> bool {
        self.batch.is_empty()
    }

    /// `out[i] = f(inputs at i)` for every element, after the checks (module docs); `out` has
    /// [`Map::len`] elements. On a bad input the error is returned and `out` holds anything.
    pub fn run<O>(&self, out: O) -> Result<(), BrdfError>
    where
        O: Outputs,
        F: Fn(I::Item) -> O::Item + Sync,
    {
        let b = &self.batch;
        b.check_out(out.elements())?;
        b.check_broadcast_inputs()?;
        let bad = BadIndex::new();
        for_each_chunk(out, |offset, mut chunk| {
            let len = chunk.elements().unwrap_or(0);
            b.check_chunk(offset, len, &bad);
            let mut c = b.inputs.cursor(offset);
            for i in 0..len {
                chunk.set(i, (self.f)(I::next(&mut c)));
            }
        });
        b.report(&bad)
    }

    /// [`Map::run`] into a new `Vec`.
    pub fn to_vec<R>(&self) -> Result<Vec<R>, BrdfError>
    where
        R: Send + Copy + Default,
        F: Fn(I::Item) -> R + Sync,
    {
        let mut out = vec![R::default(); self.len()];
        self.run(&mut out[..])?;
        Ok(out)
    }
}

/// Run `body(offset, chunk)` over `out` (one slice or a tuple of slices) in chunks of [`CHUNK`]
/// elements, in parallel on the current rayon pool when there are at least [`PARALLEL_THRESHOLD`]
/// (else once, on the calling thread). The chunk boundaries do not depend on the thread count.
pub fn for_each_chunk<O: Outputs>(out: O, body: impl Fn(usize, O) + Sync) {
    let len = out.elements().unwrap_or(0);
    if !runs_in_parallel(len) {
        body(0, out);
        return;
    }
    let mut chunks = Vec::with_capacity(len.div_ceil(CHUNK));
    let (mut rest, mut offset) = (out, 0);
    while len - offset > CHUNK {
        let (a, b) = rest.split_at(CHUNK);
        chunks.push((offset, a));
        (rest, offset) = (b, offset + CHUNK);
    }
    chunks.push((offset, rest));
    chunks.into_par_iter().for_each(|(offset, chunk)| body(offset, chunk));
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

/// Apply `f` element-wise from `input` to `out` (same length), in parallel when large (no checks: see
/// [`Batch::map`] for checked, broadcasting batches).
pub fn map<I: Copy + Sync, O: Send>(input: &[I], out: &mut [O], f: impl Fn(I) -> O + Sync) {
    for_each_chunk(out, |offset, chunk: &mut [O]| {
        for (k, o) in chunk.iter_mut().enumerate() {
            *o = f(input[offset + k]);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A 2-D grid against a broadcast row and a single vector: each output element reads what NumPy's
    /// broadcasting reads, in parallel and serially alike.
    #[test]
    fn map_broadcasts_like_numpy_at_any_size() {
        for (rows, cols) in [(3, 5), (90, 360), (7, 3 * PARALLEL_THRESHOLD / 7 + 11)] {
            let grid: Vec<Vec3> = (0..rows * cols).map(|i| Vec3::new(i as f32, 1.0, 0.0)).collect();
            let row: Vec<f32> = (0..cols).map(|j| j as f32 * 0.5).collect();
            let col: Vec<f32> = (0..rows).map(|i| i as f32 * 100.0).collect();
            let one = Vec3::new(0.0, 2.0, 0.0);
            let b = Batch::new((
                Arg::new("g", &grid, &[rows, cols]).unwrap(),
                Arg::new("r", &row, &[cols]).unwrap(),
                Arg::new("c", &col, &[rows, 1]).unwrap(),
                Arg::one("one", &one),
            ))
            .unwrap();
            assert_eq!(b.shape().dims(), &[rows, cols]);
            let out =
                b.map(|(g, r, c, o): (Vec3, f32, f32, Vec3)| g.x + g.dot(o) + r + c).to_vec::<f32>().unwrap();
            for i in 0..rows {
                for j in 0..cols {
                    let k = i * cols + j;
                    assert_eq!(out[k], k as f32 + 2.0 + j as f32 * 0.5 + i as f32 * 100.0, "({i}, {j})");
                }
            }
        }
    }

    #[test]
    fn several_outputs_and_an_optional_input() {
        let w: Vec<Vec3> = (0..40_000).map(|i| Vec3::new(i as f32, 0.0, 1.0)).collect();
        let t = Vec3::X;
        for tangent in [None, Some(Arg::one("tangent", &t))] {
            let b = Batch::new((Arg::rows("w", &w).unwrap(), tangent)).unwrap();
            let (mut a, mut flag) = (vec![Vec3::ZERO; w.len()], vec![false; w.len()]);
            b.map(|(w, t): (Vec3, Option<Vec3>)| (w * 2.0, t.is_some()))
                .run((&mut a[..], &mut flag[..]))
                .unwrap();
            assert!(a.iter().zip(&w).all(|(a, w)| *a == *w * 2.0));
            assert!(flag.iter().all(|f| *f == tangent.is_some()));
            let e = b.map(|_: (Vec3, Option<Vec3>)| (Vec3::ZERO, false)).run((&mut a[..], &mut flag[..5]));
            assert!(e.unwrap_err().to_string().contains("out"));
        }
    }

    /// The error names the first argument (in order) holding a bad element and its lowest bad index in
    /// its own shape, whichever chunk or thread finds it; broadcast inputs are checked too.
    #[test]
    fn checks_name_the_first_bad_argument_and_its_lowest_index() {
        let n = 3 * PARALLEL_THRESHOLD + 5;
        let good = vec![Vec3::new(0.1, 0.2, 1.0); n];
        let cos = vec![0.5f32; n];
        let run = |w: &[Vec3], c: &[f32], one: Vec3| {
            let unit = Check::Valid { ok: |c: f32| c.abs() <= 1.0, problem: "must hold cosines in [-1, 1]" };
            let b = Batch::new((
                Arg::rows("w", w).unwrap(),
                Arg::rows("c", c).unwrap().check(unit),
                Arg::one("one", &one),
            ));
            b.and_then(|b| b.map(|(w, c, o): (Vec3, f32, Vec3)| w.x + c + o.x).to_vec::<f32>().map(|_| ()))
                .map_err(|e| e.to_string())
        };
        assert_eq!(run(&good, &cos, Vec3::Z), Ok(()));
        let mut w = good.clone();
        w[40_000].y = f32::NAN;
        w[n - 1].x = f32::INFINITY;
        let e = run(&w, &cos, Vec3::Z).unwrap_err();
        assert!(e.starts_with("w:") && e.contains("non-finite") && e.contains("at w[40000]"), "{e}");
        let mut c = cos.clone();
        c[7] = 1.5;
        c[n - 2] = f32::NAN;
        let e = run(&good, &c, Vec3::Z).unwrap_err();
        assert!(e.starts_with("c:") && e.contains("cosines") && e.contains("at c[7]: 1.5"), "{e}");
        // A bad broadcast input is found before the run, but a bad earlier argument still wins.
        let e = run(&good, &c, Vec3::NAN).unwrap_err();
        assert!(e.starts_with("c:"), "{e}");
        let e = run(&good, &cos, Vec3::NAN).unwrap_err();
        assert!(e.starts_with("one:") && !e.contains(" at "), "{e}");
        // Indices in the input's own shape.
        let grid = vec![Vec3::ONE; 12];
        let mut bad = grid.clone();
        bad[7] = Vec3::new(0.0, f32::NEG_INFINITY, 0.0);
        let b = Batch::new((Arg::new("g", &bad, &[3, 4]).unwrap(), Arg::new("h", &grid[..4], &[4]).unwrap()));
        let e = b.unwrap().map(|(g, h): (Vec3, Vec3)| g + h).to_vec::<Vec3>().unwrap_err().to_string();
        assert!(e.contains("at g[1, 3]"), "{e}");
    }

    /// A caller's output array has exactly the batch shape and the item axis; anything else is refused
    /// by name with both shapes shown.
    #[test]
    fn a_callers_output_must_have_the_batch_shape_and_the_item_axis() {
        let s = Shape::new(&[4, 5]).unwrap();
        assert!(check_out_shape("out", &s, &[3], &[4, 5, 3]).is_ok());
        assert!(check_out_shape("out", &Shape::SCALAR, &[3], &[3]).is_ok());
        assert!(check_out_shape("out", &s, &[], &[4, 5]).is_ok());
        for bad in [&[4, 5][..], &[20, 3], &[1, 5, 3], &[4, 5, 3, 1], &[5, 4, 3]] {
            let e = check_out_shape("out", &s, &[3], bad).unwrap_err().to_string();
            assert!(e.starts_with("out: expected shape (4, 5, 3)") && e.contains("followed by 3"), "{e}");
            assert!(e.ends_with(&format!("got {}", shape::tuple(bad, &[]))), "{e}");
        }
        let e = check_out_shape("out", &Shape::SCALAR, &[3], &[1, 3]).unwrap_err().to_string();
        assert!(e.contains("expected shape (3,)") && e.ends_with("got (1, 3)"), "{e}");
    }

    #[test]
    fn bad_shapes_are_refused_by_name() {
        let xs = [1.0f32; 6];
        assert!(Arg::new("x", &xs[..0], &[0]).unwrap_err().to_string().contains("is empty"));
        assert!(Arg::new("x", &xs, &[4]).unwrap_err().to_string().contains("shape (4,) holds 4"));
        assert!(Arg::new("x", &xs, &[1; 33]).unwrap_err().to_string().contains("at most 32"));
        let e = Batch::new((Arg::rows("a", &xs).unwrap(), Arg::new("b", &xs, &[2, 3]).unwrap())).unwrap_err();
        assert!(e.to_string().starts_with("b:") && e.to_string().contains("(2, 3)"), "{e}");
    }
}
