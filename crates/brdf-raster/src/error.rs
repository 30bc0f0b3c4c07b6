//! Errors of brdf-raster: invalid meshes, images, files and options, each saying what was wrong.

/// What went wrong when building a mesh, loading a file or rendering.
#[derive(Debug, thiserror::Error)]
pub enum RasterError {
    /// A mesh failed validation (empty, index out of range, non-finite position, ...).
    #[error("mesh: {0}")]
    InvalidMesh(String),
    /// An argument (image size, camera, light, option) is invalid.
    #[error("{name}: {problem}")]
    InvalidArgument {
        /// The argument as the caller knows it.
        name: &'static str,
        /// What is wrong with it.
        problem: String,
    },
    /// A mesh file could not be read or parsed.
    #[error("{path}: {problem}")]
    File {
        /// The file.
        path: String,
        /// What went wrong.
        problem: String,
    },
    /// An error from brdf-core (a material).
    #[error(transparent)]
    Brdf(#[from] brdf_core::BrdfError),
}

impl RasterError {
    /// Shorthand for [`RasterError::InvalidArgument`].
    pub fn arg(name: &'static str, problem: impl Into<String>) -> Self {
        Self::InvalidArgument { name, problem: problem.into() }
    }
}
