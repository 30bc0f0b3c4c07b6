//! NumPy ↔ slices: zero-copy views of the inputs, one allocation for the output, and the checks that name
//! the argument. The Python wrapper (`brdfpy/_arrays.py`) has already converted array-likes to C-contiguous
//! float32; everything is checked again here so that a direct call into `_brdfpy` cannot misbehave either.

use glam::Vec3;
use numpy::{PyReadonlyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::errors::invalid;
use crate::threads::RowError;

/// A borrowed `(k, 3)` float32 C-contiguous array (k ≥ 1) viewed as `&[Vec3]`, without copying.
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

/// A borrowed float32 C-contiguous array of any shape as a flat slice (may be empty).
pub fn flat_view<'a>(name: &str, a: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<&'a [f32]> {
    a.as_slice().map_err(|_| PyTypeError::new_err(format!("{name}: expected a C-contiguous float32 array")))
}

/// `true` when every value is finite (brdf-core's vectorised check, AVX2 where the CPU has it).
#[inline]
pub fn all_finite(xs: &[f32]) -> bool {
    brdf_core::batch::all_finite(xs)
}

/// Check that `rows` (starting at element `offset` of argument `name`) hold only finite numbers.
#[inline]
pub fn check_vec3(name: &'static str, rows: &[Vec3], offset: usize) -> Result<(), RowError> {
    if all_finite(bytemuck::cast_slice(rows)) {
        return Ok(());
    }
    let i = rows.iter().position(|r| !r.is_finite()).unwrap_or(0);
    Err(RowError::non_finite_row(name, offset + i))
}

/// Check that `xs` (starting at element `offset` of argument `name`) are finite.
#[inline]
pub fn check_flat(name: &'static str, xs: &[f32], offset: usize) -> Result<(), RowError> {
    if all_finite(xs) {
        return Ok(());
    }
    let i = xs.iter().position(|x| !x.is_finite()).unwrap_or(0);
    Err(RowError::non_finite_index(name, offset + i))
}

/// The part of an input that serves output elements `offset .. offset + len`: the same slice when it has
/// one element (broadcast), else the matching sub-slice. Lengths are checked before any batch runs.
#[inline]
pub fn part<T>(xs: &[T], offset: usize, len: usize) -> &[T] {
    if xs.len() == 1 { xs } else { &xs[offset..offset + len] }
}

/// Element `i` of a length-1 (broadcast) or full-length slice.
#[inline(always)]
pub fn at<T: Copy>(xs: &[T], i: usize) -> T {
    if xs.len() == 1 { xs[0] } else { xs[i] }
}

/// The common length of inputs that are each of length 1 or N (NumPy broadcasting of `(1, …)` and
/// `(N, …)`), naming the first argument that does not fit.
pub fn broadcast_len(inputs: &[(&str, usize)]) -> PyResult<usize> {
    let n = inputs.iter().map(|(_, k)| *k).max().unwrap_or(0);
    for (name, k) in inputs {
        if *k != 1 && *k != n {
            return Err(invalid(format!("{name}: has {k} elements, which does not broadcast against {n}")));
        }
    }
    Ok(n)
}

/// A float32 array of `shape` (plus a trailing 3 when `rgb`) filled by `f` from the flat float32 input `x`
/// element by element, with the GIL released and the pool used for large inputs. Every element of `x`
/// must satisfy `valid` (else an error naming `name` and the index, saying `problem`).
pub fn map_flat<'py>(
    py: Python<'py>,
    name: &'static str,
    x: &PyReadonlyArrayDyn<'py, f32>,
    problem: &'static str,
    valid: impl Fn(f32) -> bool + Send + Sync,
    rgb: bool,
    f: impl Fn(f32) -> glam::Vec3 + Send + Sync,
) -> PyResult<Bound<'py, numpy::PyArrayDyn<f32>>> {
    use numpy::PyArrayMethods;
    let xs = flat_view(name, x)?;
    let mut shape = x.shape().to_vec();
    if rgb {
        shape.push(3);
    }
    let out = numpy::PyArrayDyn::<f32>::zeros(py, shape, false);
    {
        let mut w = out.readwrite();
        let o = w.as_slice_mut().map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        let body = |offset: usize, input: &[f32]| -> Result<(), RowError> {
            if !input.iter().fold(true, |ok, &c| ok & valid(c)) {
                let i = input.iter().position(|&c| !valid(c)).unwrap_or(0);
                return Err(RowError { row: offset + i, name, problem });
            }
            Ok(())
        };
        if rgb {
            let o: &mut [Vec3] = bytemuck::cast_slice_mut(o);
            crate::threads::fill(py, o, |offset, chunk| {
                let input = &xs[offset..offset + chunk.len()];
                body(offset, input)?;
                for (o, &c) in chunk.iter_mut().zip(input) {
                    *o = f(c);
                }
                Ok(())
            })?;
        } else {
            crate::threads::fill(py, o, |offset, chunk| {
                let input = &xs[offset..offset + chunk.len()];
                body(offset, input)?;
                for (o, &c) in chunk.iter_mut().zip(input) {
                    *o = f(c).x;
                }
                Ok(())
            })?;
        }
    }
    Ok(out)
}

/// The skeleton of every batch evaluation over `(k, 3)` direction arrays broadcast to `len` rows: checks
/// the broadcast (`k = 1`) inputs once, allocates the float32 `(len, 3)` output and fills it chunk by chunk
/// through [`crate::threads::fill`] (GIL released for large batches). `body(offset, parts, chunk)` gets
/// each input's part for the chunk (in the order of `inputs`) and checks the non-broadcast rows itself,
/// where they are already in the cache.
pub fn eval_rows<'py>(
    py: Python<'py>,
    inputs: &[(&'static str, &[Vec3])],
    len: usize,
    body: impl Fn(usize, &[&[Vec3]], &mut [Vec3]) -> Result<(), RowError> + Send + Sync,
) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
    use numpy::PyArrayMethods;
    for &(name, rows) in inputs {
        if rows.len() == 1 {
            check_vec3(name, rows, 0).map_err(RowError::into_py)?;
        }
    }
    let out = numpy::PyArray2::<f32>::zeros(py, [len, 3], false);
    {
        let mut w = out.readwrite();
        let slice = w.as_slice_mut().map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        let o: &mut [Vec3] = bytemuck::cast_slice_mut(slice);
        crate::threads::fill(py, o, |offset, chunk| {
            let mut parts = [&[][..]; 4];
            for (p, &(_, rows)) in parts.iter_mut().zip(inputs) {
                *p = part(rows, offset, chunk.len());
            }
            body(offset, &parts[..inputs.len()], chunk)
        })?;
    }
    Ok(out)
}
