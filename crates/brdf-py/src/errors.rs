//! The one place where core errors become Python exceptions.

use brdf_core::BrdfError;
use pyo3::PyErr;
use pyo3::exceptions::PyValueError;

/// Map a core error to `ValueError` with the core's message (which names the argument).
pub fn to_py(e: BrdfError) -> PyErr {
    PyValueError::new_err(e.to_string())
}
