//! `framedyn._framedyn.Scene`: a validated scene description
//! ([`framedyn::scenes::Scene`]) read from TOML or JSON.

use framedyn::scenes::{example, Scene, EXAMPLES};
use pyo3::prelude::*;

use crate::errors::{err, scene_err, Kind};

/// A scene: manifold, body, potential, initial state, method, time span and
/// output, read from TOML or JSON (see the Python class `framedyn.Scene`).
#[pyclass(name = "Scene", module = "framedyn._framedyn", frozen)]
#[derive(Clone)]
pub struct PyScene {
    /// The parsed scene.
    pub inner: Scene,
}

#[pymethods]
impl PyScene {
    /// Parses a TOML scene; errors name the field, value, allowed range,
    /// line and column.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str) -> PyResult<Self> {
        Scene::from_toml_str(text).map(|inner| PyScene { inner }).map_err(|e| scene_err(py, &e))
    }

    /// Parses a JSON scene (same fields as TOML).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        Scene::from_json_str(text).map(|inner| PyScene { inner }).map_err(|e| scene_err(py, &e))
    }

    /// The embedded example scene `name`.
    #[staticmethod]
    fn example(py: Python<'_>, name: &str) -> PyResult<Self> {
        example(name).map(|inner| PyScene { inner }).map_err(|e| scene_err(py, &e))
    }

    /// The names of the embedded example scenes.
    #[staticmethod]
    fn example_names() -> Vec<&'static str> {
        EXAMPLES.iter().map(|(n, _)| *n).collect()
    }

    /// The scene as TOML.
    fn to_toml(&self) -> String {
        self.inner.to_toml_string()
    }

    /// The scene as JSON.
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        serde_json::to_string(&self.inner).map_err(|e| err(py, Kind::Invalid, format!("cannot serialise the scene as JSON: {e}")))
    }

    /// Checks everything a run checks, without running.
    fn validate(&self, py: Python<'_>) -> PyResult<()> {
        self.inner.validate().map_err(|e| scene_err(py, &e))
    }

    /// `(name, unit)` of each output column, in order.
    fn columns(&self, py: Python<'_>) -> PyResult<Vec<(String, &'static str)>> {
        let sim = self.inner.build().map_err(|e| scene_err(py, &e))?;
        Ok(sim.columns().iter().map(|c| (c.name.clone(), c.unit)).collect())
    }

    /// Equal when the descriptions are (whatever text they were read from).
    fn __eq__(&self, other: &Self) -> bool {
        serde_json::to_value(&self.inner).ok() == serde_json::to_value(&other.inner).ok()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(name={:?}, manifold={:?}, body={:?})",
            self.inner.name.clone().unwrap_or_default(),
            self.inner.manifold.kind,
            self.inner.body.kind
        )
    }
}
