//! NumPy ↔ brdf-core batches: zero-copy views of the inputs as [`Arg`]s, one allocation per output, and the
//! one way a batch runs (GIL released and on the pool when large). The rules — broadcasting, checks,
//! chunking, the messages — are `brdf_core::batch`'s, so Rust and Python users see the same ones.
//!
//! The Python wrapper (`brdfpy/_arrays.py`) has already converted array-likes to C-contiguous float32;
//! the layout is checked again here so that a direct call into `_brdfpy` cannot misbehave either.

use brdf_core::batch::{Arg, Shape, ShapeOf, check_out_shape, runs_in_parallel};
use glam::Vec3;
use numpy::{PyArrayDyn, PyArrayMethods, PyReadonlyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyTuple;

use crate::errors::{invalid, to_py};

/// A float32 array of any shape `(..., 3)` as directions (or colours) with its leading shape.
pub fn vec3<'a>(name: &'static str, a: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<Arg<'a, Vec3>> {
    let shape = a.shape();
    if shape.last() != Some(&3) {
        return Err(invalid(format!(
            "{name}: expected an array of shape (..., 3) (3-vectors along the last axis), got {}",
            tuple(shape)
        )));
    }
    let s = a
        .as_slice()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float32 array")))?;
    Arg::new(name, bytemuck::cast_slice(s), &shape[..shape.len() - 1]).map_err(to_py)
}

/// `x` as a float32 C-contiguous aligned NumPy array: `x` itself when it is one already (no copy and
/// no Python-level call: the fixed cost of a small batch), else what `brdfpy._arrays.as_vectors`
/// makes of it (dtype and layout converted once; its errors name `name`). Shapes are checked by the
/// core ([`vec3`]).
pub fn f32_array<'py>(name: &'static str, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    if let Ok(a) = x.cast::<PyArrayDyn<f32>>() {
        if a.is_c_contiguous() && a.is_aligned() {
            return Ok(a.clone());
        }
    }
    static AS_VECTORS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let convert = AS_VECTORS.import(x.py(), "brdfpy._arrays", "as_vectors")?;
    Ok(convert.call1((name, x))?.cast_into::<PyArrayDyn<f32>>()?)
}

/// A read-only view of an input array (refused, naming it, while Rust code elsewhere writes to it).
pub fn read<'py>(
    name: &'static str,
    a: &Bound<'py, PyArrayDyn<f32>>,
) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    a.try_readonly().map_err(|_| invalid(format!("{name}: the array is being written elsewhere")))
}

/// An optional [`vec3`].
pub fn vec3_opt<'a>(
    name: &'static str,
    a: &'a Option<PyReadonlyArrayDyn<'_, f32>>,
) -> PyResult<Option<Arg<'a, Vec3>>> {
    a.as_ref().map(|a| vec3(name, a)).transpose()
}

/// A float32 array of any shape as numbers.
pub fn scalars<'a>(name: &'static str, a: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<Arg<'a, f32>> {
    let s = a
        .as_slice()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float32 array")))?;
    Arg::new(name, s, a.shape()).map_err(to_py)
}

fn tuple(shape: &[usize]) -> String {
    match shape {
        [x] => format!("({x},)"),
        _ => format!("({})", shape.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// A borrowed `(k, 3)` float32 C-contiguous array (k ≥ 1) viewed as `&[Vec3]`, without copying (for the
/// row-based APIs of the rasterizer and the ray caster).
pub fn vec3_view<'a>(name: &str, a: &'a PyReadonlyArray2<'_, f32>) -> PyResult<&'a [Vec3]> {
    let shape = a.shape();
    if shape[1] != 3 {
        return Err(invalid(format!(
            "{name}: expected shape (N, 3) or (3,), got ({}, {})",
            shape[0], shape[1]
        )));
    }
    if shape[0] == 0 {
        return Err(invalid(format!("{name}: is empty (shape (0, 3))")));
    }
    let s = a
        .as_slice()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float32 array")))?;
    Ok(bytemuck::cast_slice(s))
}

/// Element `i` of a length-1 (broadcast) or full-length slice.
#[inline(always)]
pub fn at<T: Copy>(xs: &[T], i: usize) -> T {
    if xs.len() == 1 { xs[0] } else { xs[i] }
}

/// The common length of row inputs of lengths 1 or N, by `brdf_core::batch::broadcast` (naming the first
/// that does not fit); `item` is each input's item shape for the message (`&[3]` for vectors).
pub fn broadcast_rows(inputs: &[(&'static str, usize, &'static [usize])]) -> PyResult<usize> {
    let shapes: Vec<Shape> = inputs.iter().map(|&(_, k, _)| Shape::rows(k)).collect();
    let of: Vec<ShapeOf<'_>> =
        inputs.iter().zip(&shapes).map(|(&(name, _, item), shape)| ShapeOf { name, shape, item }).collect();
    brdf_core::batch::broadcast(&of).map(|s| s.len()).map_err(to_py)
}

/// A Rust element type of a batch output and the NumPy array that holds it: `Vec3` in a float32 array
/// with a trailing axis of 3, numbers and flags in arrays of the batch's shape.
pub trait OutElem: Sized + Send + 'static {
    /// The NumPy element type.
    type Np: numpy::Element + Send;
    /// The item axis appended to the batch's shape.
    const ITEM: &'static [usize];
    /// The array's elements as `Self`.
    fn cast(s: &mut [Self::Np]) -> &mut [Self];
}

impl OutElem for f32 {
    type Np = f32;
    const ITEM: &'static [usize] = &[];
    fn cast(s: &mut [f32]) -> &mut [f32] {
        s
    }
}

impl OutElem for Vec3 {
    type Np = f32;
    const ITEM: &'static [usize] = &[3];
    fn cast(s: &mut [f32]) -> &mut [Vec3] {
        bytemuck::cast_slice_mut(s)
    }
}

impl OutElem for u8 {
    type Np = u8;
    const ITEM: &'static [usize] = &[];
    fn cast(s: &mut [u8]) -> &mut [u8] {
        s
    }
}

impl OutElem for bool {
    type Np = bool;
    const ITEM: &'static [usize] = &[];
    fn cast(s: &mut [bool]) -> &mut [bool] {
        s
    }
}

/// Outputs of at least this many bytes are allocated through `numpy.zeros` ([`new_array`]).
pub const LARGE_OUTPUT_BYTES: usize = 4 << 20;

/// A new NumPy array for a batch of `shape` with elements `T`. Allocated zeroed: NumPy takes large blocks
/// from `calloc`, i.e. fresh zero pages, so this costs no pass over memory.
///
/// Outputs of [`LARGE_OUTPUT_BYTES`] or more are made by calling `numpy.zeros`, whose failed allocation is
/// a Python `MemoryError` (with the size in its message) that reaches the caller as it is: the C-API path
/// of smaller ones would turn a failure into a panic. (The core's `MAX_BATCH_LEN` bounds the shapes that
/// get here; the machine's memory, or a `ulimit -v`, may still be smaller.)
pub fn new_array<'py, T: OutElem>(py: Python<'py>, shape: &Shape) -> PyResult<Bound<'py, PyArrayDyn<T::Np>>> {
    let dims = shape.with_item(T::ITEM);
    let bytes = dims.iter().try_fold(std::mem::size_of::<T::Np>(), |a, &d| a.checked_mul(d));
    if bytes.is_some_and(|b| b < LARGE_OUTPUT_BYTES) {
        return Ok(PyArrayDyn::<T::Np>::zeros(py, dims, false));
    }
    static ZEROS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let zeros = ZEROS.import(py, "numpy", "zeros")?;
    let a = zeros.call1((PyTuple::new(py, &dims)?, numpy::dtype::<T::Np>(py)))?;
    Ok(a.cast_into::<PyArrayDyn<T::Np>>()?)
}

/// A caller's array (`out=`) to write a batch of `shape` into: of `T`'s NumPy type, exactly the batch's
/// shape followed by `T`'s item axis (the core's rule, `batch::check_out_shape`), C-contiguous and
/// writeable. Whether it overlaps an input is checked when it is borrowed for writing ([`fill`]).
pub fn given_array<'py, T: OutElem>(
    name: &'static str,
    out: &Bound<'py, PyAny>,
    shape: &Shape,
) -> PyResult<Bound<'py, PyArrayDyn<T::Np>>> {
    let dtype = numpy::dtype::<T::Np>(out.py());
    let Ok(a) = out.cast::<PyArrayDyn<T::Np>>() else {
        let what = match out.cast::<numpy::PyUntypedArray>() {
            Ok(u) => format!("an array of dtype {}", u.dtype()),
            Err(_) => out.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string()),
        };
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a numpy.ndarray of dtype {dtype}, got {what}"
        )));
    };
    check_out_shape(name, shape, T::ITEM, a.shape()).map_err(to_py)?;
    if !a.is_c_contiguous() {
        return Err(invalid(format!("{name}: expected a C-contiguous array (e.g. from numpy.empty)")));
    }
    Ok(a.clone())
}

/// `f()` on the pool with the GIL released when a batch of `len` elements runs in parallel
/// (`brdf_core::batch::runs_in_parallel`), else inline with the GIL held: releasing it and waking the
/// pool cost more than a small batch.
pub fn run<T: Send>(py: Python<'_>, len: usize, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    if !runs_in_parallel(len) {
        return Ok(f());
    }
    let pool = crate::threads::pool()?;
    Ok(py.detach(|| pool.install(f)))
}

/// The outputs of a batch: one [`OutElem`] or a tuple of them, with the NumPy arrays that hold them and
/// the slices the core's batch writes (`brdf_core::batch::Outputs`).
pub trait OutSet {
    /// The NumPy arrays (one, or a tuple).
    type Arrays<'py>;
    /// Their write guards.
    type Guards<'py>;
    /// The slices into them (one, or a tuple): what the core's batch fills.
    type Slices<'a>: Send;
    /// New arrays for a batch of `shape` ([`new_array`]).
    fn alloc<'py>(py: Python<'py>, shape: &Shape) -> PyResult<Self::Arrays<'py>>;
    /// Borrow every array for writing; refused (naming `out`) when one is not writeable or overlaps an
    /// array borrowed already, i.e. an input of the same call.
    fn borrow<'py>(arrays: &Self::Arrays<'py>) -> PyResult<Self::Guards<'py>>;
    /// The slices of the borrowed arrays.
    fn slices<'a, 'py>(guards: &'a mut Self::Guards<'py>) -> PyResult<Self::Slices<'a>>;
}

fn borrow_one<'py, T: OutElem>(
    a: &Bound<'py, PyArrayDyn<T::Np>>,
) -> PyResult<numpy::PyReadwriteArrayDyn<'py, T::Np>> {
    a.try_readwrite().map_err(|e| {
        invalid(match e {
            numpy::BorrowError::NotWriteable => "out: the array is read-only".to_string(),
            _ => "out: overlaps an input of the same call (pass a separate array)".to_string(),
        })
    })
}

fn slice_of<'a, T: OutElem>(w: &'a mut numpy::PyReadwriteArrayDyn<'_, T::Np>) -> PyResult<&'a mut [T]> {
    let s = w.as_slice_mut().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(T::cast(s))
}

impl<T: OutElem> OutSet for T {
    type Arrays<'py> = Bound<'py, PyArrayDyn<T::Np>>;
    type Guards<'py> = numpy::PyReadwriteArrayDyn<'py, T::Np>;
    type Slices<'a> = &'a mut [T];
    fn alloc<'py>(py: Python<'py>, shape: &Shape) -> PyResult<Self::Arrays<'py>> {
        new_array::<T>(py, shape)
    }
    fn borrow<'py>(a: &Self::Arrays<'py>) -> PyResult<Self::Guards<'py>> {
        borrow_one::<T>(a)
    }
    fn slices<'a, 'py>(g: &'a mut Self::Guards<'py>) -> PyResult<&'a mut [T]> {
        slice_of::<T>(g)
    }
}

macro_rules! out_set_tuple {
    ($($t:ident $i:tt),+) => {
        impl<$($t: OutElem),+> OutSet for ($($t,)+) {
            type Arrays<'py> = ($(Bound<'py, PyArrayDyn<$t::Np>>,)+);
            type Guards<'py> = ($(numpy::PyReadwriteArrayDyn<'py, $t::Np>,)+);
            type Slices<'a> = ($(&'a mut [$t],)+);
            fn alloc<'py>(py: Python<'py>, shape: &Shape) -> PyResult<Self::Arrays<'py>> {
                Ok(($(new_array::<$t>(py, shape)?,)+))
            }
            fn borrow<'py>(a: &Self::Arrays<'py>) -> PyResult<Self::Guards<'py>> {
                Ok(($(borrow_one::<$t>(&a.$i)?,)+))
            }
            fn slices<'a, 'py>(g: &'a mut Self::Guards<'py>) -> PyResult<Self::Slices<'a>> {
                Ok(($(slice_of::<$t>(&mut g.$i)?,)+))
            }
        }
    };
}
out_set_tuple!(A 0, B 1);
out_set_tuple!(A 0, B 1, C 2);
out_set_tuple!(A 0, B 1, C 2, D 3);

/// Fill `arrays` (new or a caller's) with a batch of `len` elements by `fill` (GIL released and on the
/// pool when large, [`run`]) and map the core's error.
pub fn fill<'py, T: OutSet>(
    py: Python<'py>,
    arrays: &T::Arrays<'py>,
    len: usize,
    fill: impl for<'a> FnOnce(T::Slices<'a>) -> Result<(), brdf_core::BrdfError> + Send,
) -> PyResult<()> {
    let mut guards = T::borrow(arrays)?;
    let slices = T::slices(&mut guards)?;
    run(py, len, || fill(slices))?.map_err(to_py)
}

/// The one path of a batch function: allocate the arrays of its outputs `T` (one [`OutElem`] or a tuple)
/// for `shape`, fill them by `fill`, return them. E.g. `outputs::<(Vec3, bool)>(py, m.shape(), |o| m.run(o))`.
pub fn outputs<'py, T: OutSet>(
    py: Python<'py>,
    shape: &Shape,
    fill_with: impl for<'a> FnOnce(T::Slices<'a>) -> Result<(), brdf_core::BrdfError> + Send,
) -> PyResult<T::Arrays<'py>> {
    let arrays = T::alloc(py, shape)?;
    fill::<T>(py, &arrays, shape.len(), fill_with)?;
    Ok(arrays)
}
