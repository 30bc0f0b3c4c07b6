//! The thread pool every large batch runs on, and the helper that runs a batch on it.
//!
//! The pool belongs to the bindings (not rayon's global pool) so that `brdfpy.set_num_threads(n)` can
//! replace it at any time; tests use that to show that results are bit-identical at 1, 2 and 4 threads.
//! Batches are split into fixed chunks of [`CHUNK`] elements and every output element depends only on
//! its own inputs, so the split, and hence the result, does not depend on the thread count.
//!
//! The pool lock is only ever taken while attached to the interpreter (holding the GIL) and never held
//! across `py.detach`, so a `fork()` (which Python performs while attached) cannot happen while another
//! thread holds it; [`_reset_after_fork`] then drops the parent's pool in the child, whose worker threads
//! do not exist there.

use std::sync::{Arc, Mutex, MutexGuard};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rayon::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::errors::invalid;

/// Elements per parallel task (inputs and output of a chunk stay in the L2 cache).
pub const CHUNK: usize = 8 * 1024;
/// Batches shorter than this run on the calling thread with the GIL held: releasing the GIL and waking
/// the pool cost more than they save (blake3-py's `GIL_MINSIZE` idea).
pub const DETACH_MIN: usize = 4 * 1024;
/// The largest thread count `set_num_threads` accepts.
pub const MAX_THREADS: usize = 1024;

static POOL: Mutex<Option<Arc<ThreadPool>>> = Mutex::new(None);

fn lock() -> MutexGuard<'static, Option<Arc<ThreadPool>>> {
    // A poisoned lock only means a panic elsewhere while it was held; the Option inside is still valid.
    POOL.lock().unwrap_or_else(|e| e.into_inner())
}

fn build(n: Option<usize>) -> PyResult<Arc<ThreadPool>> {
    let mut b = ThreadPoolBuilder::new().thread_name(|i| format!("brdfpy-{i}"));
    if let Some(n) = n {
        b = b.num_threads(n);
    }
    b.build().map(Arc::new).map_err(|e| PyRuntimeError::new_err(format!("cannot start threads: {e}")))
}

/// The current pool, created on first use with rayon's default size (`RAYON_NUM_THREADS` or the number of
/// logical CPUs).
pub fn pool() -> PyResult<Arc<ThreadPool>> {
    let mut g = lock();
    if let Some(p) = g.as_ref() {
        return Ok(Arc::clone(p));
    }
    let p = build(None)?;
    *g = Some(Arc::clone(&p));
    Ok(p)
}

/// Use `n` worker threads for large batches from now on; `None` restores the default (the number of
/// logical CPUs, or `RAYON_NUM_THREADS` when set). Results do not depend on the thread count.
#[pyfunction]
#[pyo3(signature = (n, /))]
pub fn set_num_threads(n: Option<i64>) -> PyResult<()> {
    let n = match n {
        None => None,
        Some(k) if k >= 1 && k <= MAX_THREADS as i64 => Some(k as usize),
        Some(k) => {
            return Err(invalid(format!("n: expected an integer in [1, {MAX_THREADS}] or None, got {k}")));
        }
    };
    let p = build(n)?;
    *lock() = Some(p);
    Ok(())
}

/// The number of worker threads large batches run on.
#[pyfunction]
pub fn get_num_threads() -> PyResult<usize> {
    Ok(pool()?.current_num_threads())
}

/// Forget the pool inherited through `fork()`: its threads exist only in the parent. Registered with
/// `os.register_at_fork(after_in_child=...)` by the Python package.
#[pyfunction]
pub fn _reset_after_fork() {
    if let Some(p) = lock().take() {
        // Dropping would ask worker threads that do not exist in this process to stop; leak it instead.
        std::mem::forget(p);
    }
}

/// A problem found in an input element while a batch runs (reported for the lowest such element).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RowError {
    /// Index of the offending element (row of an `(N, 3)` array, flat index of a scalar array).
    pub row: usize,
    /// The argument it belongs to.
    pub name: &'static str,
    /// What is wrong with it, ending in the word before the element's number ("row", "index").
    pub problem: &'static str,
}

impl RowError {
    /// A non-finite value in row `row` of the `(N, 3)` argument `name`.
    pub fn non_finite_row(name: &'static str, row: usize) -> Self {
        Self {
            row,
            name,
            problem: "contains a non-finite value (NaN or inf, or beyond the float32 range) at row",
        }
    }

    /// A non-finite value at flat index `i` of the argument `name`.
    pub fn non_finite_index(name: &'static str, i: usize) -> Self {
        Self {
            row: i,
            name,
            problem: "contains a non-finite value (NaN or inf, or beyond the float32 range) at index",
        }
    }

    /// The Python exception (`BrdfError`, a `ValueError`) naming the argument and the element.
    pub fn into_py(self) -> PyErr {
        invalid(format!("{}: {} {}", self.name, self.problem, self.row))
    }
}

/// Fill `out` by `body(offset, chunk)` over consecutive chunks of at most [`CHUNK`] elements: inline for
/// small batches, else with the GIL released and the chunks spread over the pool. Checking inputs inside
/// `body` keeps the check in the cache-resident chunk instead of a separate pass over memory. A chunk's
/// `Err` stops nothing (other chunks may be running) but the error of the lowest element is raised, so
/// the message does not depend on the thread count either.
pub fn fill<T: Send>(
    py: Python<'_>,
    out: &mut [T],
    body: impl Fn(usize, &mut [T]) -> Result<(), RowError> + Send + Sync,
) -> PyResult<()> {
    let result = if out.len() < DETACH_MIN {
        out.chunks_mut(CHUNK).enumerate().try_for_each(|(c, chunk)| body(c * CHUNK, chunk))
    } else {
        let pool = pool()?;
        py.detach(|| {
            pool.install(|| {
                out.par_chunks_mut(CHUNK)
                    .enumerate()
                    .filter_map(|(c, chunk)| body(c * CHUNK, chunk).err())
                    .min_by_key(|e| e.row)
                    .map_or(Ok(()), Err)
            })
        })
    };
    result.map_err(RowError::into_py)
}

/// Run `f` on the pool with the GIL released (for core functions that split their own work with rayon,
/// such as the BRDF checks); inline when `len` is small.
pub fn run<T: Send>(py: Python<'_>, len: usize, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    if len < DETACH_MIN {
        return Ok(f());
    }
    let pool = pool()?;
    Ok(py.detach(|| pool.install(f)))
}
