//! Why a model could not be solved or evaluated, as a kind the study can match: the linear
//! solvers' errors pass through unchanged, a value that is not finite has its variant, and a
//! model that knows which of its solves failed wraps the error in [`ModelError::Context`]
//! (`"contact: …"`, `"cavitation: …"`). The text a user reads is the `Display`, contexts first.

use crate::linalg::saddle_point::SaddlePointError;
use crate::linalg::uzawa::UzawaError;
use crate::linalg::SolveError;

/// The failure of a model's solve or of an estimator.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A linear solve (or the active-set method around it) failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A saddle point system could not be split off or solved directly.
    #[error(transparent)]
    SaddlePoint(#[from] SaddlePointError),
    /// An Uzawa run failed.
    #[error(transparent)]
    Uzawa(#[from] UzawaError),
    /// A computed field has a value that is not finite.
    #[error("{0}")]
    NonFinite(String),
    /// Any other failure, as the model words it.
    #[error("{0}")]
    Failed(String),
    /// `source` with the part of the model that failed in front: `"{context}: {source}"`.
    #[error("{context}: {source}")]
    Context {
        context: String,
        #[source]
        source: Box<ModelError>,
    },
}

impl ModelError {
    /// This error with `context` in front (which part of the model failed).
    pub fn context(self, context: impl Into<String>) -> ModelError {
        ModelError::Context {
            context: context.into(),
            source: Box::new(self),
        }
    }

    /// The kind under every context.
    pub fn kind(&self) -> &ModelError {
        match self {
            ModelError::Context { source, .. } => source.kind(),
            other => other,
        }
    }
}

impl From<String> for ModelError {
    fn from(message: String) -> ModelError {
        ModelError::Failed(message)
    }
}

impl From<&str> for ModelError {
    fn from(message: &str) -> ModelError {
        ModelError::Failed(message.to_string())
    }
}
