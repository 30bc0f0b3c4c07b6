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
    /// A parameter value is out of its documented range, non-finite, or of the wrong kind.
    #[error("parameter {name:?}: {problem}")]
    InvalidParameter {
        /// The parameter (or argument) name.
        name: String,
        /// What is wrong with it, in words.
        problem: String,
    },
    /// A batch input has the wrong length or contents.
    #[error("argument {name:?}: {problem}")]
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
