//! Why a cycle of a study failed, as a kind the caller can match: the solvers' own errors
//! ([`SolveError`], [`UzawaError`], [`MeshError`]) pass through unchanged, the study's checks
//! (a non-finite solution or estimate, the memory budget, an obstacle without solution) have a
//! variant each, and a layer that knows where the failure happened wraps it in
//! [`StudyError::Context`]. The text a user reads is the `Display` of the kind, with the
//! contexts in front of it, outermost first.

use crate::adaptivity::model::SwapsExceeded;
use crate::linalg::uzawa::UzawaError;
use crate::linalg::SolveError;
use crate::mesh::MeshError;
use crate::models::ModelError;

/// The failure of one cycle (or of the setup before the first one) of a study.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A linear solve failed (factorisation, iteration, a non-finite value).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// A model's solve or an estimator failed.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An Uzawa run of a solver study failed.
    #[error(transparent)]
    Uzawa(#[from] UzawaError),
    /// The mesh cannot be built or refined.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The model marking (Algorithm III.3) did not settle.
    #[error(transparent)]
    Marking(#[from] SwapsExceeded),
    /// The solution or the error estimate of a cycle has a value that is not finite.
    #[error("{0}")]
    NonFinite(String),
    /// The memory budget refuses the cycle (or, predicted, the run).
    #[error("{0}")]
    OverBudget(String),
    /// The contact problem has no solution: an obstacle reaches into the clamped body.
    #[error("{0}")]
    InfeasibleObstacle(String),
    /// Any other failure, as the model or estimator that found it words it.
    #[error("{0}")]
    Failed(String),
    /// `source` with where it happened in front: `"{context}: {source}"`.
    #[error("{context}: {source}")]
    Context {
        context: String,
        #[source]
        source: Box<StudyError>,
    },
}

impl StudyError {
    /// This error with `context` in front (where it happened).
    pub fn context(self, context: impl Into<String>) -> StudyError {
        StudyError::Context {
            context: context.into(),
            source: Box::new(self),
        }
    }

    /// The kind under every context.
    pub fn kind(&self) -> &StudyError {
        match self {
            StudyError::Context { source, .. } => source.kind(),
            other => other,
        }
    }

    /// The failed linear solve behind this error, under the contexts of the study and of the
    /// model, if a solve failed.
    pub fn solve_error(&self) -> Option<&SolveError> {
        match self.kind() {
            StudyError::Solve(e) => Some(e),
            StudyError::Model(m) => match m.kind() {
                ModelError::Solve(e) => Some(e),
                _ => None,
            },
            _ => None,
        }
    }
}

impl From<String> for StudyError {
    fn from(message: String) -> StudyError {
        StudyError::Failed(message)
    }
}

impl From<&str> for StudyError {
    fn from(message: &str) -> StudyError {
        StudyError::Failed(message.to_string())
    }
}
