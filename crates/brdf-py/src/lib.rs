//! Python bindings of brdf-core and brdf-raster: convert, validate, release the GIL, map errors.

use pyo3::prelude::*;

mod arrays;
mod errors;
mod models;

/// The compiled module `brdfpy._brdfpy`; the public API is re-exported by `brdfpy/__init__.py`.
#[pymodule]
mod _brdfpy {
    use pyo3::prelude::*;

    #[pymodule_export]
    use super::models::{Model, model_names};

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("__version__", env!("CARGO_PKG_VERSION"))
    }
}
