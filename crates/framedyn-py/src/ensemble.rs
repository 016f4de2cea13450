//! Columnar ensembles: a base scene and a table of dotted-field columns
//! (1-D float arrays) in, stacked arrays out — `framedyn::scenes::run_ensemble`
//! with conversion and error mapping only. No Python object is made per
//! member except the exception a member's user potential raised.

use std::sync::{Arc, Mutex};

use framedyn::scenes::{run_ensemble, Ensemble, EnsembleOptions, Keep, MemberStatus, Table};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{err, guard, internal, scene_err, Kind};
use crate::interrupt::interruptible;
use crate::run::{check_user, lock, user_functions, ErrorSlot};
use crate::scene::PyScene;

/// Runs the ensemble `table` (`names[k]` → `columns[k]`, equal lengths) on
/// `scene` in parallel with the GIL released and returns the columnar
/// result as a dict of arrays (see `python/framedyn/_ensemble.py`).
/// `keep`: `"all"`, `"final"` or `"samples"` (with `samples = k`). With a
/// user potential the members run one after another (each call needs the
/// GIL, so threads would only contend for it). Ctrl-C stops running
/// members within a few hundred steps and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scene, names, columns, keep = "all", samples = None, threads = None, user_potential = None, user_gradient = None, oversubscribe = false))]
#[allow(clippy::too_many_arguments)]
pub fn run_table<'py>(
    py: Python<'py>,
    scene: PyRef<'py, PyScene>,
    names: Vec<String>,
    columns: Vec<PyReadonlyArray1<'py, f64>>,
    keep: &str,
    samples: Option<u64>,
    threads: Option<usize>,
    user_potential: Option<Py<PyAny>>,
    user_gradient: Option<Py<PyAny>>,
    oversubscribe: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let keep = match (keep, samples) {
        ("all", None) => Keep::All,
        ("final", None) => Keep::Final,
        ("samples", Some(k)) => Keep::Samples(k),
        (other, s) => {
            return Err(err(py, Kind::Invalid, format!("invalid `keep` = {other:?} (samples = {s:?}): allowed: 'all', 'final', or 'samples' with samples = k ≥ 2")))
        }
    };
    let table = table(py, names, &columns)?;
    let user = check_user(py, user_potential, user_gradient)?;
    let n = table.len();
    // One error slot per member, only when a user potential can raise.
    let slots: Vec<ErrorSlot> = if user.is_some() { (0..n).map(|_| Arc::new(Mutex::new(None))).collect() } else { Vec::new() };
    let opts = EnsembleOptions { keep, threads: if user.is_some() { Some(1) } else { threads }, oversubscribe };
    let base = scene.inner.clone();
    let factory = user.as_ref().map(|u| {
        let slots = &slots;
        move |i: usize| user_functions(u, &slots[i])
    });
    let (result, interrupt) = interruptible(py, |cancel| {
        let f = factory.as_ref().map(|f| f as &(dyn Fn(usize) -> framedyn::scenes::UserFunctions + Sync));
        run_ensemble(&base, &table, &opts, f, cancel, &|_| {})
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    let out = match result {
        Err(panic) => return Err(internal(py, panic)),
        Ok(Err(e)) => return Err(scene_err(py, &e)),
        Ok(Ok(out)) => out,
    };
    let exceptions: Vec<Option<Py<PyAny>>> = if slots.is_empty() { (0..n).map(|_| None).collect() } else { slots.iter().map(|s| lock(s).take().map(|e| e.into_value(py).into_any())).collect() };
    to_py(py, out, exceptions)
}

/// The ensemble table `names[k]` → `columns[k]`, validated once by
/// [`Table::new`] (also the member table of `chaos_map`).
pub fn table(py: Python<'_>, names: Vec<String>, columns: &[PyReadonlyArray1<'_, f64>]) -> PyResult<Table> {
    if names.len() != columns.len() {
        return Err(err(py, Kind::Invalid, format!("table: {} names for {} columns", names.len(), columns.len())));
    }
    let mut cols: Vec<(String, Vec<f64>)> = Vec::with_capacity(names.len());
    for (name, c) in names.into_iter().zip(columns) {
        // numpy refuses views of unaligned memory (e.g. arrays unpickled
        // from a byte buffer) with a panic: report it as bad input instead.
        let values = guard(|| c.as_array().to_vec())
            .map_err(|_| err(py, Kind::Invalid, format!("table column `{name}`: an unaligned array; pass numpy.require(a, float, 'CA')")))?;
        cols.push((name, values));
    }
    Table::new(cols).map_err(|e| scene_err(py, &e))
}

/// The ensemble as a dict of arrays.
fn to_py<'py>(py: Python<'py>, out: Ensemble, exceptions: Vec<Option<Py<PyAny>>>) -> PyResult<Bound<'py, PyDict>> {
    let ncols = out.columns.len();
    let rows = out.offsets.last().copied().unwrap_or(0);
    let d = PyDict::new(py);
    d.set_item("data", PyArray1::from_vec(py, out.data).reshape([rows, ncols])?)?;
    d.set_item("offsets", PyArray1::from_vec(py, out.offsets.iter().map(|&o| o as i64).collect()))?;
    d.set_item("columns", out.columns.iter().map(|c| c.name.clone()).collect::<Vec<_>>())?;
    d.set_item("units", out.columns.iter().map(|c| c.unit).collect::<Vec<_>>())?;
    d.set_item("groups", out.columns.iter().map(|c| c.group.map(|g| g.name())).collect::<Vec<_>>())?;
    d.set_item("frame_shape", out.frame_shape)?;
    d.set_item("status", PyArray1::from_vec(py, out.members.iter().map(|m| m.status.code()).collect()))?;
    let names = [MemberStatus::Finished, MemberStatus::Event, MemberStatus::Cancelled, MemberStatus::Failed, MemberStatus::Invalid];
    d.set_item("status_names", names.iter().map(|s| s.name()).collect::<Vec<_>>())?;
    d.set_item("errors", out.members.iter().map(|m| m.error.clone()).collect::<Vec<_>>())?;
    d.set_item("exceptions", exceptions)?;
    let sum = PyDict::new(py);
    // The summaries' numeric fields as (N,) arrays, NaN for invalid members.
    for (k, name) in framedyn::scenes::RunSummary::NUMBER_NAMES.into_iter().enumerate() {
        let v: Vec<f64> = out.members.iter().map(|m| m.summary.as_ref().map_or(f64::NAN, |s| s.numbers()[k])).collect();
        sum.set_item(name, PyArray1::from_vec(py, v))?;
    }
    // Quality warnings of the members that have any (most have none): their
    // indices and findings, not one Python list per member.
    let warned: Vec<(i64, Vec<String>)> =
        out.members.iter().enumerate().filter_map(|(i, m)| m.summary.as_ref().filter(|s| !s.warnings.is_empty()).map(|s| (i as i64, s.warning_texts()))).collect();
    d.set_item("warned", PyArray1::from_vec(py, warned.iter().map(|(i, _)| *i).collect()))?;
    d.set_item("warned_texts", warned.into_iter().map(|(_, w)| w).collect::<Vec<_>>())?;
    d.set_item("method", out.members.iter().find_map(|m| m.summary.as_ref().map(|s| s.method)))?;
    d.set_item("summary", sum)?;
    let ev = PyDict::new(py);
    ev.set_item("member", PyArray1::from_vec(py, out.events.iter().map(|(i, _)| *i as i64).collect()))?;
    ev.set_item("index", PyArray1::from_vec(py, out.events.iter().map(|(_, e)| e.index as i64).collect()))?;
    ev.set_item("name", out.events.iter().map(|(_, e)| e.name.clone()).collect::<Vec<_>>())?;
    ev.set_item("t", PyArray1::from_vec(py, out.events.iter().map(|(_, e)| e.t).collect()))?;
    ev.set_item("rising", PyArray1::from_vec(py, out.events.iter().map(|(_, e)| e.rising).collect()))?;
    ev.set_item("terminal", PyArray1::from_vec(py, out.events.iter().map(|(_, e)| e.terminal).collect()))?;
    let k = out.events.len();
    let rows: Vec<f64> = out.events.into_iter().flat_map(|(_, e)| e.row).collect();
    ev.set_item("data", PyArray1::from_vec(py, rows).reshape([k, ncols])?)?;
    d.set_item("events", ev)?;
    Ok(d)
}
