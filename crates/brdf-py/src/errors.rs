//! The one place where core errors become Python exceptions.
//!
//! Every error of brdf-core is a problem with the caller's input (an unknown name, a parameter out of
//! range, arrays that do not broadcast), so it becomes [`BrdfError`], a subclass of `ValueError`: code
//! that catches `ValueError` keeps working, and code that wants only brdfpy's errors can catch those.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBool;

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

/// An integer argument in `[lo, hi]` from any Python object: an `int` or a NumPy integer (anything with
/// `__index__`), not a `bool` and not a float. The errors name `name`: a `TypeError` for another type, a
/// `BrdfError` for a value outside the range, at any size (pyo3's own conversion to a Rust integer
/// raises `OverflowError` beyond 64 bits, naming nothing).
pub fn integer(name: &str, x: &Bound<'_, PyAny>, lo: i64, hi: i64) -> PyResult<i64> {
    let type_name = || x.get_type().name().map_or_else(|_| "?".to_string(), |s| s.to_string());
    let is_bool = x.is_instance_of::<PyBool>() || type_name() == "bool" || type_name() == "bool_";
    let k = if is_bool { None } else { x.call_method0("__index__").ok() };
    let Some(k) = k else {
        let got = if is_bool { "a bool".to_string() } else { type_name() };
        return Err(PyTypeError::new_err(format!("{name}: expected an integer in [{lo}, {hi}], got {got}")));
    };
    match k.extract::<i64>() {
        Ok(k) if (lo..=hi).contains(&k) => Ok(k),
        Ok(k) => Err(invalid(format!("{name}: expected an integer in [{lo}, {hi}], got {k}"))),
        Err(_) => Err(invalid(format!(
            "{name}: expected an integer in [{lo}, {hi}], got one outside the 64-bit range"
        ))),
    }
}
