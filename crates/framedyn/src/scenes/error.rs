//! Scene errors: every message names the field (a path such as
//! `potential.terms[1].kappa`), the value, what is allowed and, for scenes
//! read from text, the line and column.

use std::fmt;
use std::io;

use thiserror::Error;

use crate::solve::SolveError;

/// A position in a scene file (1-based line and column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    /// Line, from 1.
    pub line: usize,
    /// Column (characters), from 1.
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}", self.line, self.column)
    }
}

/// ` (line L, column C)` or nothing.
pub(crate) struct At(pub Option<Location>);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(l) => write!(f, " (at {l})"),
            None => Ok(()),
        }
    }
}

/// Why a scene could not be read, validated or built.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The text is not valid TOML/JSON, or a field has the wrong type, is
    /// unknown or missing.
    #[error("{format} error in `{path}`{at}: {message}", at = At(*location))]
    Parse {
        /// `"TOML"` or `"JSON"`.
        format: &'static str,
        /// Path of the field (`""` for the whole document).
        path: String,
        /// The parser's message (names the value and what was expected).
        message: String,
        /// Where.
        location: Option<Location>,
    },
    /// A value is outside its allowed range or does not fit the rest of the scene.
    #[error("invalid `{path}` = {value}: {allowed}{at}", at = At(*location))]
    Invalid {
        /// Path of the field, e.g. `body.mass`.
        path: String,
        /// The value given (as written, or a measured defect).
        value: String,
        /// What is allowed.
        allowed: String,
        /// Where (if the scene came from text).
        location: Option<Location>,
    },
    /// No embedded example of this name.
    #[error("no embedded scene `{name}`; available: {available}")]
    UnknownScene {
        /// The name asked for.
        name: String,
        /// The names available.
        available: String,
    },
}

impl SceneError {
    /// The location, if known.
    pub fn location(&self) -> Option<Location> {
        match self {
            SceneError::Parse { location, .. } | SceneError::Invalid { location, .. } => *location,
            SceneError::UnknownScene { .. } => None,
        }
    }

    /// The field path, if any.
    pub fn path(&self) -> Option<&str> {
        match self {
            SceneError::Parse { path, .. } | SceneError::Invalid { path, .. } => Some(path),
            SceneError::UnknownScene { .. } => None,
        }
    }

    pub(crate) fn invalid(path: impl Into<String>, value: impl fmt::Display, allowed: impl Into<String>) -> Self {
        SceneError::Invalid { path: path.into(), value: crate::error::tidy_value(value.to_string()), allowed: allowed.into(), location: None }
    }

    /// A core-library error raised while building the part of the scene at `path`.
    /// The error with `note` added to what is allowed (the other fields a
    /// relation between fields involves, with their values).
    pub(crate) fn with_note(self, note: &str) -> Self {
        match self {
            SceneError::Invalid { path, value, allowed, location } => SceneError::Invalid { path, value, allowed: format!("{allowed} ({note})"), location },
            other => other,
        }
    }

    pub(crate) fn from_core(path: &str, err: crate::Error) -> Self {
        use crate::Error as E;
        let sub = |field: &str| {
            if path.contains('.') || field.is_empty() || path.ends_with(field) {
                path.to_string()
            } else if field == "I" {
                format!("{path}.inertia")
            } else if field.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                format!("{path}.{field}")
            } else {
                format!("{path} ({field})")
            }
        };
        match err {
            E::InvalidParameter { field, value, allowed } => SceneError::invalid(sub(field), value, format!("must be {allowed}")),
            E::NotFinite { field } => SceneError::invalid(sub(field), "a non-finite number", "must be finite"),
            E::Constraint { field, constraint, defect, tolerance } => SceneError::invalid(
                sub(field),
                format!("(defect {defect:.3e})"),
                format!("must satisfy {constraint} (tolerance {tolerance:e})"),
            ),
            other => SceneError::invalid(path, "(see message)", other.to_string()),
        }
    }
}

/// Why a run stopped early: the integration failed, or the sink could not write.
#[derive(Debug, Error)]
pub enum RunError {
    /// The integration failed (the records up to the last good state were written).
    #[error("integration failed: {0}")]
    Integration(SolveError),
    /// Writing a record failed.
    #[error("output error: {0}")]
    Io(#[from] io::Error),
    /// The scene could not be built.
    #[error(transparent)]
    Scene(#[from] SceneError),
}
