//! `lyapunov`, `sali`, `megno`, `section` and `chaos_map` (issue 21): the
//! analyses of a scene, with the GIL released and Ctrl-C honoured; results
//! as numpy arrays.

use framedyn::analysis::{chaos_map as map_core, AnalysisError, ChaosMapOptions, Linearisation};
use framedyn::scenes::{EventSpec, MemberStatus, SceneAnalysisError};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{err, internal, scene_err, solve_err, Kind};
use crate::interrupt::interruptible;
use crate::scene::PyScene;

fn analysis_err(py: Python<'_>, e: &SceneAnalysisError) -> PyErr {
    match e {
        SceneAnalysisError::Scene(s) => scene_err(py, s),
        SceneAnalysisError::Analysis(AnalysisError::Solve(s)) => solve_err(py, s),
        SceneAnalysisError::Analysis(a @ AnalysisError::InvalidParameter { .. }) => err(py, Kind::Invalid, a.to_string()),
        SceneAnalysisError::Analysis(a) => err(py, Kind::Integration, a.to_string()),
    }
}

/// Runs `work` interruptibly; maps a panic, a Ctrl-C and the work's error.
fn run_interruptibly<T: Send>(py: Python<'_>, work: impl FnOnce(&std::sync::atomic::AtomicBool) -> Result<T, SceneAnalysisError> + Send) -> PyResult<T> {
    let (result, interrupt) = interruptible(py, work);
    if let Some(e) = interrupt {
        return Err(e);
    }
    match result {
        Err(panic) => Err(internal(py, panic)),
        Ok(Err(e)) => Err(analysis_err(py, &e)),
        Ok(Ok(v)) => Ok(v),
    }
}

/// Rows of equal length as a 2-D array.
fn matrix<'py>(py: Python<'py>, rows: &[Vec<f64>], width: usize) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat).reshape([rows.len(), width])?.into_any())
}

/// The Lyapunov exponents of a scene (see `framedyn.lyapunov`): a dict of
/// arrays.
#[pyfunction]
#[pyo3(signature = (scene, exponents, every, transient, batches, seed, eps, fourth_order, two_trajectory, quotient, differenced=false))]
#[allow(clippy::too_many_arguments)]
pub fn lyapunov<'py>(
    py: Python<'py>,
    scene: &PyScene,
    exponents: Option<usize>,
    every: usize,
    transient: f64,
    batches: usize,
    seed: u64,
    eps: Option<f64>,
    fourth_order: bool,
    two_trajectory: bool,
    quotient: bool,
    differenced: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.inner.clone();
    let (dof, e, two) = run_interruptibly(py, move |cancel| {
        let mut opts = scene.lyapunov_options()?;
        let dof = scene.state_dimension()?;
        opts.exponents = match exponents {
            Some(k) => k,
            None if quotient => scene.phase_space_dimension()?,
            None => dof,
        };
        opts.quotient = quotient;
        opts.renormalise_every = every;
        opts.transient = transient;
        opts.batches = batches;
        opts.seed = seed;
        opts.linearisation = Linearisation::chosen(fourth_order, eps, differenced);
        let e = scene.lyapunov(&opts, cancel)?;
        let two = if two_trajectory {
            let mut o = scene.two_trajectory_options()?;
            o.renormalise_every = every;
            o.transient = transient;
            o.batches = batches;
            o.seed = seed;
            Some(scene.two_trajectory(&o, cancel)?)
        } else {
            None
        };
        Ok((dof, e, two))
    })?;
    let d = PyDict::new(py);
    let k = e.exponents.len();
    d.set_item("exponents", PyArray1::from_slice(py, &e.exponents))?;
    d.set_item("stderr", PyArray1::from_slice(py, &e.stderr))?;
    d.set_item("spread", PyArray1::from_slice(py, &e.spread))?;
    d.set_item("times", PyArray1::from_slice(py, &e.times))?;
    d.set_item("running", matrix(py, &e.running, k)?)?;
    d.set_item("steps", e.steps)?;
    d.set_item("steps_per_step", e.steps_per_step)?;
    d.set_item("exact_tangents", e.linearisation.exact)?;
    d.set_item("state_dimension", dof)?;
    d.set_item("dimension", e.dimension)?;
    match two {
        Some(t) => {
            let td = PyDict::new(py);
            td.set_item("exponent", t.exponent)?;
            td.set_item("stderr", t.stderr)?;
            td.set_item("spread", t.spread)?;
            td.set_item("times", PyArray1::from_slice(py, &t.times))?;
            td.set_item("running", PyArray1::from_slice(py, &t.running))?;
            d.set_item("two_trajectory", td)?;
        }
        None => d.set_item("two_trajectory", py.None())?,
    }
    Ok(d)
}

/// The Poincaré section of a scene by an `[[events]]` entry given as JSON
/// (see `framedyn.section`): a dict with `name`, `columns`, `units`, `data`
/// (crossings × columns) and `rising`.
#[pyfunction]
pub fn section<'py>(py: Python<'py>, scene: &PyScene, spec_json: &str) -> PyResult<Bound<'py, PyDict>> {
    let spec: EventSpec = serde_json::from_str(spec_json).map_err(|e| err(py, Kind::Invalid, format!("invalid section: {e}")))?;
    let scene = scene.inner.clone();
    let s = run_interruptibly(py, move |cancel| scene.section(&spec, cancel))?;
    let d = PyDict::new(py);
    let w = s.columns.len();
    d.set_item("name", &s.name)?;
    d.set_item("columns", s.columns.iter().map(|c| c.name.clone()).collect::<Vec<_>>())?;
    d.set_item("units", s.columns.iter().map(|c| c.unit).collect::<Vec<_>>())?;
    d.set_item("data", PyArray1::from_vec(py, s.data).reshape([s.rising.len(), w])?)?;
    d.set_item("rising", PyArray1::from_vec(py, s.rising))?;
    Ok(d)
}

/// The Smaller Alignment Index of a scene (see `framedyn.sali`):
/// `(sali, chaotic_at, min, steps, exact_tangents)`.
#[pyfunction]
#[pyo3(signature = (scene, threshold, seed, eps=None, fourth_order=false, differenced=false))]
pub fn sali(py: Python<'_>, scene: &PyScene, threshold: f64, seed: u64, eps: Option<f64>, fourth_order: bool, differenced: bool) -> PyResult<(f64, Option<f64>, f64, usize, bool)> {
    let scene = scene.inner.clone();
    let e = run_interruptibly(py, move |cancel| {
        let mut opts = scene.sali_options()?;
        opts.threshold = threshold;
        opts.seed = seed;
        opts.linearisation = Linearisation::chosen(fourth_order, eps, differenced);
        scene.sali(&opts, cancel)
    })?;
    Ok((e.sali, e.chaotic_at, e.min, e.steps, e.linearisation.exact))
}

/// MEGNO of a scene (see `framedyn.megno`): a dict of its values and running
/// arrays.
#[pyfunction]
#[pyo3(signature = (scene, seed, eps, fourth_order, differenced=false))]
pub fn megno<'py>(py: Python<'py>, scene: &PyScene, seed: u64, eps: Option<f64>, fourth_order: bool, differenced: bool) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.inner.clone();
    let e = run_interruptibly(py, move |cancel| {
        let mut opts = scene.megno_options()?;
        opts.seed = seed;
        opts.linearisation = Linearisation::chosen(fourth_order, eps, differenced);
        scene.megno(&opts, cancel)
    })?;
    let d = PyDict::new(py);
    d.set_item("megno", e.megno)?;
    d.set_item("mean", e.mean)?;
    d.set_item("slope", e.slope)?;
    d.set_item("lyapunov", e.lyapunov)?;
    d.set_item("times", PyArray1::from_vec(py, e.times))?;
    d.set_item("running_megno", PyArray1::from_vec(py, e.running_megno))?;
    d.set_item("running_mean", PyArray1::from_vec(py, e.running_mean))?;
    d.set_item("steps", e.steps)?;
    d.set_item("steps_per_step", e.steps_per_step)?;
    d.set_item("exact_tangents", e.linearisation.exact)?;
    Ok(d)
}

/// GALI_k of a scene (see `framedyn.gali`): a dict of its values and
/// running arrays (`k = None`: the dimension of the space the vectors live
/// in, the phase space's with `quotient`, else the state group's).
#[pyfunction]
#[pyo3(signature = (scene, k, threshold, seed, eps, fourth_order, quotient, differenced=false))]
#[allow(clippy::too_many_arguments)]
pub fn gali<'py>(py: Python<'py>, scene: &PyScene, k: Option<usize>, threshold: f64, seed: u64, eps: Option<f64>, fourth_order: bool, quotient: bool, differenced: bool) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.inner.clone();
    let (k, e) = run_interruptibly(py, move |cancel| {
        let k = match k {
            Some(k) => k,
            None if quotient => scene.phase_space_dimension()?,
            None => scene.state_dimension()?,
        };
        let mut opts = scene.gali_options(k)?;
        opts.threshold = threshold;
        opts.seed = seed;
        opts.linearisation = Linearisation::chosen(fourth_order, eps, differenced);
        opts.quotient = quotient;
        Ok((k, scene.gali(&opts, cancel)?))
    })?;
    let d = PyDict::new(py);
    d.set_item("k", k)?;
    d.set_item("gali", e.gali)?;
    d.set_item("log10", e.log10)?;
    d.set_item("below_at", e.below_at)?;
    d.set_item("times", PyArray1::from_vec(py, e.times))?;
    d.set_item("running_log10", PyArray1::from_vec(py, e.running_log10))?;
    d.set_item("steps", e.steps)?;
    d.set_item("steps_per_step", e.steps_per_step)?;
    d.set_item("dimension", e.dimension)?;
    d.set_item("exact_tangents", e.linearisation.exact)?;
    Ok(d)
}

/// SALI, MEGNO and/or GALI_k of every member of the ensemble table `names[k]` →
/// `columns[k]` on `scene` (see `framedyn.chaos_map`), in parallel with
/// the GIL released: a dict of `(N,)` arrays, one per quantity, with the
/// members' status codes and messages. Ctrl-C stops the running members
/// and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scene, names, columns, sali, megno, gali, threshold, gali_threshold, gali_quotient, seed, eps, fourth_order, threads, oversubscribe, differenced=false))]
#[allow(clippy::too_many_arguments)]
pub fn chaos_map<'py>(
    py: Python<'py>,
    scene: &PyScene,
    names: Vec<String>,
    columns: Vec<PyReadonlyArray1<'py, f64>>,
    sali: bool,
    megno: bool,
    gali: Option<usize>,
    threshold: f64,
    gali_threshold: f64,
    gali_quotient: bool,
    seed: u64,
    eps: Option<f64>,
    fourth_order: bool,
    threads: Option<usize>,
    oversubscribe: bool,
    differenced: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let table = crate::ensemble::table(py, names, &columns)?;
    let linearisation = Linearisation::chosen(fourth_order, eps, differenced);
    let opts = ChaosMapOptions { sali, megno, gali, threshold, gali_threshold, gali_quotient, seed, linearisation, threads, oversubscribe };
    let base = scene.inner.clone();
    let m = run_interruptibly(py, move |cancel| Ok(map_core(&base, &table, &opts, cancel)?))?;
    let d = PyDict::new(py);
    for (name, v) in [
        ("sali", m.sali),
        ("sali_min", m.sali_min),
        ("chaotic_at", m.chaotic_at),
        ("megno", m.megno),
        ("megno_mean", m.megno_mean),
        ("megno_slope", m.megno_slope),
        ("lyapunov", m.lyapunov),
        ("gali_log10", m.gali_log10),
        ("gali_below_at", m.gali_below_at),
    ] {
        d.set_item(name, PyArray1::from_vec(py, v))?;
    }
    d.set_item("sali_steps", PyArray1::from_vec(py, m.sali_steps))?;
    d.set_item("megno_steps", PyArray1::from_vec(py, m.megno_steps))?;
    d.set_item("gali_steps", PyArray1::from_vec(py, m.gali_steps))?;
    d.set_item("status", PyArray1::from_vec(py, m.status.iter().map(|s| s.code()).collect()))?;
    let names = [MemberStatus::Finished, MemberStatus::Event, MemberStatus::Cancelled, MemberStatus::Failed, MemberStatus::Invalid];
    d.set_item("status_names", names.iter().map(|s| s.name()).collect::<Vec<_>>())?;
    d.set_item("errors", m.errors)?;
    Ok(d)
}
