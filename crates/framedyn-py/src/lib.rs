//! Python bindings of framedyn: the `framedyn._framedyn` extension module.
//!
//! Thin by design: registration, conversion between Rust values and numpy
//! arrays, and error mapping. Every entry point that computes releases the
//! GIL and catches Rust panics (`errors::guard`); Rust errors arrive as the
//! exception classes of `framedyn._errors`. The Python package
//! `python/framedyn` wraps these names (`Scene`, `solve`, `solve_batch`,
//! `Stepper`) and adds the pure-Python helpers (plotting, Dask ensembles).
#![deny(missing_docs)]

use pyo3::prelude::*;

mod analysis;
mod catalog;
mod ensemble;
mod errors;
mod interrupt;
mod run;
mod scene;

/// The extension module `framedyn._framedyn`.
#[pymodule]
fn _framedyn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // Whether this is a development build (the dev profile keeps debug
    // assertions; release wheels do not): scripts that measure speed read it.
    m.add("_debug_assertions", cfg!(debug_assertions))?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<run::PyStepper>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_batch, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::run_table, m)?)?;
    m.add_function(wrap_pyfunction!(errors::raise_for_test, m)?)?;
    m.add_function(wrap_pyfunction!(cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::lyapunov, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::section, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::sali, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::gali, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::megno, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::chaos_map, m)?)?;
    m.add_function(wrap_pyfunction!(catalog::methods, m)?)?;
    m.add_function(wrap_pyfunction!(catalog::manifolds, m)?)?;
    m.add_function(wrap_pyfunction!(catalog::initial_fields, m)?)?;
    m.add_function(wrap_pyfunction!(catalog::write_records, m)?)?;
    Ok(())
}

/// Runs the `framedyn` command line `argv` (program name first) with the GIL
/// released and returns its exit code: the console script `framedyn`
/// installed by the wheel (`python/framedyn/cli.py`). A Rust panic is
/// reported on stderr with exit code 101 instead of crossing into Python.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<String>) -> i32 {
    match py.detach(|| errors::guard(|| framedyn_cli::main_with_args(argv))) {
        Ok(code) => code,
        Err(message) => {
            eprintln!("framedyn: {message}");
            101
        }
    }
}
