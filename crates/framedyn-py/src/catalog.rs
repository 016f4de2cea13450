//! What the Python package reads from Rust instead of copying: the method
//! registry, the manifolds of a scene with their coordinate names, the
//! fields of `[initial]`, and the one writer of record files.

use framedyn::method::METHODS;
use framedyn::scenes::{Format, InitialSpec, ManifoldKind};
use numpy::{PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{err, Kind};

/// The methods of the registry: one dict per method with `name`,
/// `display`, `family`, `order`, `embedded_order` (or None), `adaptive`,
/// `needs` (`"nothing"`, `"exact_free_flow"`, `"chart"`), `needs_text`,
/// `params` and `summary`.
#[pyfunction]
pub fn methods(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    METHODS
        .iter()
        .map(|m| {
            let d = PyDict::new(py);
            d.set_item("name", m.name)?;
            d.set_item("display", m.display)?;
            d.set_item("family", m.family.label())?;
            d.set_item("order", m.order)?;
            d.set_item("embedded_order", m.embedded_order)?;
            d.set_item("adaptive", m.adaptive)?;
            d.set_item(
                "needs",
                match m.needs {
                    framedyn::method::Needs::Nothing => "nothing",
                    framedyn::method::Needs::ExactFreeFlow => "exact_free_flow",
                    framedyn::method::Needs::Chart => "chart",
                },
            )?;
            d.set_item("needs_text", m.needs.describe())?;
            d.set_item("params", m.params.to_vec())?;
            d.set_item("summary", m.summary)?;
            Ok(d)
        })
        .collect()
}

/// The manifolds a scene can name: `{kind: {"fields": [...], "coordinates":
/// [...]}}` (the chart coordinates as the manifold names them; each also
/// with its rate `*_dot` in `[initial]`).
#[pyfunction]
pub fn manifolds(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for k in ManifoldKind::ALL {
        let d = PyDict::new(py);
        d.set_item("fields", k.fields().to_vec())?;
        d.set_item("coordinates", k.coordinate_names())?;
        out.set_item(k.name(), d)?;
    }
    Ok(out)
}

/// The fixed (non-coordinate) fields of `[initial]`.
#[pyfunction]
pub fn initial_fields() -> Vec<&'static str> {
    InitialSpec::FIELDS.to_vec()
}

/// Writes records as `framedyn run` does (the same writer): `data` of shape
/// `(records, columns)`, the column names and units, `format` `"csv"` or
/// `"npz"`; atomic (temporary file, then rename). Errors: `InvalidInputError`
/// for mismatched shapes or an unknown format, `OutputError` for I/O.
#[pyfunction]
pub fn write_records(py: Python<'_>, path: std::path::PathBuf, format: &str, columns: Vec<String>, units: Vec<String>, data: Bound<'_, PyArray2<f64>>) -> PyResult<()> {
    let format = match format {
        "csv" => Format::Csv,
        "npz" => Format::Npz,
        other => return Err(err(py, Kind::Invalid, format!("invalid `format` = {other:?}: allowed: 'csv', 'npz'"))),
    };
    let array = data.readonly();
    let shape = array.shape().to_vec();
    if shape[1] != columns.len() || units.len() != columns.len() {
        return Err(err(py, Kind::Invalid, format!("data has {} columns, with {} names and {} units", shape[1], columns.len(), units.len())));
    }
    let values: Vec<f64> = array.as_array().iter().copied().collect();
    drop(array);
    py.detach(|| framedyn_cli::output::write_records(&path, format, &columns, &units, &values))
        .map_err(|e| err(py, Kind::Io, format!("cannot write {}: {e}", path.display())))
}
