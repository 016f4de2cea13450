//! Error mapping: every Rust error becomes an instance of one of the
//! exception classes of `framedyn._errors` (written in Python so that they can
//! inherit from both `FramedynError` and `ValueError` / `RuntimeError`), and
//! no Rust panic crosses into Python.

use std::panic::{catch_unwind, AssertUnwindSafe};

use framedyn::scenes::{RunError, SceneError};
use framedyn::solve::SolveError;
use pyo3::prelude::*;
use pyo3::types::PyType;

/// The kinds of error the bindings raise, one per class of `framedyn._errors`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Invalid input (scene, parameter, array shape, dtype, NaN):
    /// `framedyn.InvalidInputError`, a `ValueError`.
    Invalid,
    /// The integration failed: `framedyn.IntegrationError`, a `RuntimeError`.
    Integration,
    /// Reading or writing a file failed: `framedyn.OutputError`, an `OSError`.
    Io,
    /// A bug (a caught Rust panic): `framedyn.InternalError`, a `RuntimeError`.
    Internal,
}

impl Kind {
    fn class_name(self) -> &'static str {
        match self {
            Kind::Invalid => "InvalidInputError",
            Kind::Integration => "IntegrationError",
            Kind::Io => "OutputError",
            Kind::Internal => "InternalError",
        }
    }
}

/// The Python exception class of `kind`.
fn class<'py>(py: Python<'py>, kind: Kind) -> PyResult<Bound<'py, PyType>> {
    let module = py.import("framedyn._errors")?;
    Ok(module.getattr(kind.class_name())?.cast_into::<PyType>()?)
}

/// A Python exception of `kind` carrying `message` (the Rust error's text).
pub fn err(py: Python<'_>, kind: Kind, message: impl Into<String>) -> PyErr {
    let message = message.into();
    match class(py, kind) {
        Ok(cls) => PyErr::from_type(cls, message),
        Err(e) => e,
    }
}

/// An invalid scene: `InvalidInputError` with the scene's message (field,
/// value, allowed range, line and column).
pub fn scene_err(py: Python<'_>, e: &SceneError) -> PyErr {
    err(py, Kind::Invalid, e.to_string())
}

/// A failed step of the stepping API.
pub fn solve_err(py: Python<'_>, e: &SolveError) -> PyErr {
    match e {
        SolveError::InvalidParameter { .. } | SolveError::InvalidOptions { .. } => err(py, Kind::Invalid, e.to_string()),
        _ => err(py, Kind::Integration, e.to_string()),
    }
}

/// A failed run (without its partial solution; see `run::failure`).
pub fn run_err(py: Python<'_>, e: &RunError) -> PyErr {
    match e {
        RunError::Integration(s) => solve_err(py, s),
        RunError::Io(io) if io.kind() == std::io::ErrorKind::OutOfMemory => pyo3::exceptions::PyMemoryError::new_err(io.to_string()),
        RunError::Io(io) => err(py, Kind::Io, format!("output error: {io}")),
        RunError::Scene(s) => scene_err(py, s),
    }
}

/// Runs `f`, turning a Rust panic into `framedyn.InternalError` (the panic
/// never unwinds into the interpreter). The caller decides whether the GIL
/// is held.
pub fn guard<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        let what = if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "(no message)".to_string()
        };
        format!("internal error (a Rust panic, please report it): {what}")
    })
}

/// The `InternalError` for a caught panic message.
pub fn internal(py: Python<'_>, message: String) -> PyErr {
    err(py, Kind::Internal, message)
}

/// Raises the exception of `kind` with `message` (for the tests of the
/// error mapping).
#[pyfunction]
#[pyo3(name = "_raise_for_test")]
pub fn raise_for_test(py: Python<'_>, kind: &str, message: &str) -> PyResult<()> {
    let k = match kind {
        "invalid" => Kind::Invalid,
        "integration" => Kind::Integration,
        "io" => Kind::Io,
        "internal" => Kind::Internal,
        "panic" => {
            return match py.detach(|| guard(|| -> () { panic!("{}", message.to_string()) })) {
                Ok(()) => Ok(()),
                Err(m) => Err(internal(py, m)),
            }
        }
        other => return Err(err(py, Kind::Invalid, format!("kind: unknown value {other:?}; allowed: invalid, integration, io, internal, panic"))),
    };
    Err(err(py, k, message))
}

/// Memory this process may still use, in bytes: the smaller of the
/// system's `MemAvailable` and the cgroup's remaining limit, when known.
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines().find_map(|l| l.strip_prefix("MemAvailable:").and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok()).map(|kb| kb * 1024))
    });
    let cgroup = (|| {
        let max: u64 = std::fs::read_to_string("/sys/fs/cgroup/memory.max").ok()?.trim().parse().ok()?;
        let cur: u64 = std::fs::read_to_string("/sys/fs/cgroup/memory.current").ok()?.trim().parse().ok()?;
        Some(max.saturating_sub(cur))
    })();
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}
