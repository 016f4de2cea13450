//! Errors of building a method or of asking it to integrate a system it
//! cannot: typed, naming the parameter and the allowed range.

use thiserror::Error;

/// Why a method could not be built, or cannot integrate a system.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MethodError {
    /// A method parameter outside its range.
    #[error("invalid {field} = {}: must be {allowed}", crate::error::Num(*value))]
    InvalidParameter {
        /// The parameter, e.g. `"newton_tol"`.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The method needs a structure the system does not have (e.g. a
    /// splitting on a model without exact free flows).
    #[error("{method} cannot integrate this system: {reason}")]
    Unsupported {
        /// The method's display name.
        method: &'static str,
        /// What is missing, in words.
        reason: &'static str,
    },
    /// No method of the registry has this name.
    #[error("unknown method {name:?}: one of {allowed}")]
    Unknown {
        /// The name asked for.
        name: String,
        /// The registry's names, comma-separated.
        allowed: String,
    },
}
