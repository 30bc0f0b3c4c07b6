//! Errors of brdf-core: every constructor and factory validates its input and says what was wrong.

/// What went wrong when building or evaluating a model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BrdfError {
    /// No model of that name is registered.
    #[error("unknown model {name:?}; known models: {known}")]
    UnknownModel {
        /// The name that was asked for.
        name: String,
        /// Comma-separated list of the registered names.
        known: String,
    },
    /// The model has no parameter of that name.
    #[error("model {model:?} has no parameter {name:?}; its parameters: {known}")]
    UnknownParameter {
        /// The model being built.
        model: &'static str,
        /// The unknown parameter.
        name: String,
        /// Comma-separated list of the model's parameters.
        known: String,
    },
    /// The model has no parameter of that name, but has one for the same concept under the name this
    /// library uses everywhere (see [`crate::models::RENAMED_PARAMS`]).
    #[error("{model} has no parameter '{name}': {what} is '{new}' (its parameters: {known})")]
    RenamedParameter {
        /// The model being built.
        model: &'static str,
        /// The name that was given.
        name: String,
        /// The name of the same concept in this model.
        new: &'static str,
        /// The concept, in words ("the diffuse reflectance").
        what: &'static str,
        /// Comma-separated list of the model's parameters.
        known: String,
    },
    /// A parameter value is out of its documented range, non-finite, or of the wrong kind.
    #[error("parameter {name:?}: {problem}")]
    InvalidParameter {
        /// The parameter (or argument) name.
        name: String,
        /// What is wrong with it, in words.
        problem: String,
    },
    /// A batch input has the wrong shape or contents. Shown as `name: problem`, the form of every
    /// argument error of the Python API.
    #[error("{name}: {problem}")]
    InvalidInput {
        /// The argument name as the caller knows it.
        name: &'static str,
        /// What is wrong with it, in words.
        problem: String,
    },
}

impl BrdfError {
    /// Shorthand for [`BrdfError::InvalidParameter`].
    pub fn param(name: impl Into<String>, problem: impl Into<String>) -> Self {
        Self::InvalidParameter { name: name.into(), problem: problem.into() }
    }
}
