//! The crate's error type: every fallible public function returns [`Result`].
//!
//! Errors name the offending field, its value and the allowed range, so that a
//! message can be shown to a user as is (the CLI and the Python module do).

use thiserror::Error;

/// Everything that can go wrong in `framedyn`.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// A scalar parameter lies outside its allowed range (or is not finite).
    #[error("invalid {field} = {}: must be {allowed}", Num(*value))]
    InvalidParameter {
        /// Name of the parameter, e.g. `"R"` or `"L"`.
        field: &'static str,
        /// The value that was given.
        value: f64,
        /// The allowed range, in words, e.g. `"finite and > 0"`.
        allowed: &'static str,
    },
    /// An array argument contains NaN or an infinity.
    #[error("{field} contains a non-finite value")]
    NotFinite {
        /// Name of the argument.
        field: &'static str,
    },
    /// A point or frame does not satisfy a constraint (not on the manifold,
    /// frame not orthonormal, determinant not positive, ...).
    #[error("{field} violates its constraint: {constraint} (defect {defect:e}, tolerance {tolerance:e})")]
    Constraint {
        /// Name of the argument.
        field: &'static str,
        /// The constraint in words, e.g. `"|x| = R"`.
        constraint: &'static str,
        /// Measured defect.
        defect: f64,
        /// Largest defect accepted.
        tolerance: f64,
    },
    /// A chart (the paper's coordinates) is not defined at this point, e.g. the
    /// polar coordinates of S² at a pole.
    #[error("coordinates of {manifold} are singular or undefined here: {reason}")]
    OutsideChart {
        /// Manifold name.
        manifold: &'static str,
        /// Why, in words.
        reason: &'static str,
    },
    /// The group logarithm is not defined (or not unique) at this element.
    #[error("log of {group} is undefined here: {reason}")]
    LogUndefined {
        /// Group name.
        group: &'static str,
        /// Why, in words.
        reason: &'static str,
    },
    /// An iterative algorithm did not converge.
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NoConvergence {
        /// What was being computed.
        what: &'static str,
        /// Iterations spent.
        iterations: usize,
        /// Last residual.
        residual: f64,
    },
}

/// A number as an error message shows it: Rust's shortest round-trip text
/// where that is short, scientific notation where it is not (`{}` writes
/// `1e-300` as a 0 followed by 300 digits).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&v.abs()) {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}

/// `text` (a value as written into an error message), with a long decimal
/// number rewritten in scientific notation (see [`Num`]); other text as is.
pub(crate) fn tidy_value(text: String) -> String {
    if text.len() > 20 {
        if let Ok(v) = text.parse::<f64>() {
            if v.is_finite() {
                return Num(v).to_string();
            }
        }
    }
    text
}

/// `Result` with the crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Checks that `value` is finite and strictly positive.
pub fn positive(field: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter { field, value, allowed: "finite and > 0" })
    }
}

/// Checks that every entry of `values` is finite.
pub fn finite<'a, I: IntoIterator<Item = &'a f64>>(field: &'static str, values: I) -> Result<()> {
    if values.into_iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::NotFinite { field })
    }
}
