//! The thread pool every large batch runs on, and the helper that runs a batch on it.
//!
//! The pool belongs to the bindings (not rayon's global pool) so that `brdfpy.set_num_threads(n)` can
//! replace it at any time; tests use that to show that results are bit-identical at 1, 2 and 4 threads.
//! How a batch is split (fixed chunks, independent of the thread count) and when it goes parallel is
//! `brdf_core::batch`'s rule; `arrays::run` releases the GIL exactly then and installs this pool.
//!
//! The pool lock is only ever taken while attached to the interpreter (holding the GIL) and never held
//! across `py.detach`, so a `fork()` (which Python performs while attached) cannot happen while another
//! thread holds it; [`_reset_after_fork`] then drops the parent's pool in the child, whose worker threads
//! do not exist there.

use std::sync::{Arc, Mutex, MutexGuard};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::errors::integer;

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
///
/// `n` is an `int` (or a NumPy integer) in `[1, MAX_THREADS]`, or `None`; a `bool` is refused (`True`
/// is not a thread count), as are integers of any size outside the range (a `ValueError` naming `n`, not
/// the `OverflowError` of a 64-bit conversion).
#[pyfunction]
#[pyo3(signature = (n, /))]
pub fn set_num_threads(n: &Bound<'_, PyAny>) -> PyResult<()> {
    let n = if n.is_none() { None } else { Some(integer("n", n, 1, MAX_THREADS as i64)? as usize) };
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
