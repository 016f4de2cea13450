//! Errors of the analyses.

use crate::solve::SolveError;

/// Why a tangent integration, a Lyapunov estimate or a section failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// An option lies outside its allowed range.
    #[error("invalid {field} = {value}: must be {allowed}")]
    InvalidParameter {
        /// The option, e.g. `"exponents"`.
        field: &'static str,
        /// The value given, as text.
        value: String,
        /// The allowed range, in words.
        allowed: String,
    },
    /// A step of the trajectory or of a perturbed trajectory failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The logarithm of a perturbed state relative to the base state failed,
    /// or a group operation refused its input.
    #[error(transparent)]
    Core(#[from] crate::Error),
    /// Tangent vectors became linearly dependent or non-finite (a
    /// re-orthonormalisation found a column of norm `norm`).
    #[error("tangent column {column} degenerated at t = {t} (norm {norm:e}): re-orthonormalise more often or shorten the step")]
    Degenerate {
        /// The column.
        column: usize,
        /// The time.
        t: f64,
        /// Its norm before normalisation.
        norm: f64,
    },
    /// Stopped by the cancel flag.
    #[error("cancelled at t = {t}")]
    Cancelled {
        /// The time reached.
        t: f64,
    },
}

impl AnalysisError {
    /// An [`AnalysisError::InvalidParameter`].
    pub fn invalid(field: &'static str, value: impl std::fmt::Display, allowed: impl Into<String>) -> Self {
        AnalysisError::InvalidParameter { field, value: crate::error::tidy_value(value.to_string()), allowed: allowed.into() }
    }
}
