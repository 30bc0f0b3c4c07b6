//! The one place where core errors become Python exceptions.
//!
//! Every error of brdf-core is a problem with the caller's input (an unknown name, a parameter out of
//! range, arrays that do not broadcast), so it becomes [`BrdfError`], a subclass of `ValueError`: code
//! that catches `ValueError` keeps working, and code that wants only brdfpy's errors can catch those.

use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

pyo3::create_exception!(
    brdfpy,
    BrdfError,
    PyValueError,
    "Invalid input to brdfpy (a ValueError): the message names the argument and the problem."
);

/// Map a core error to [`BrdfError`] with the core's message (which names the argument).
pub fn to_py(e: brdf_core::BrdfError) -> PyErr {
    BrdfError::new_err(e.to_string())
}

/// A `BrdfError` with a message of our own (checks done in the bindings themselves).
pub fn invalid(msg: impl Into<String>) -> PyErr {
    BrdfError::new_err(msg.into())
}
