//! Running scenes: one run, a parallel batch (rayon) and the stepping object,
//! always with the GIL released. Records arrive as one row-major `f64`
//! buffer that becomes a numpy array without a copy.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use framedyn::scenes::{
    EventDirection, EventFn, FlatSink, Progress, RunError, RunSummary, Scene, SceneError, SceneEvent, SceneStop, Simulation,
    UserFunctions, UserGradientFn, UserPotentialFn,
};
use numpy::{AllowTypeChange, PyArray1, PyArrayLikeDyn, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::errors::{err, guard, internal, run_err, scene_err, solve_err, Kind};
use crate::interrupt::interruptible;
use crate::scene::PyScene;

/// The first Python exception raised by a user potential (later calls
/// return NaN at once, so the run stops at the next step).
pub(crate) type ErrorSlot = Arc<Mutex<Option<PyErr>>>;

pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Builds `scene` with the user potential, if any.
fn build_scene(scene: &Scene, user: Option<&UserFunctions>) -> Result<Simulation, SceneError> {
    match user {
        None => scene.build(),
        Some(u) => scene.build_with_user(u.clone()),
    }
}

/// The number `N` of frame vectors in `e` (`N·E` numbers, `E = x.len()`).
fn frame_rows(x: &[f64], e: &[f64]) -> usize {
    if x.is_empty() {
        0
    } else {
        e.len() / x.len()
    }
}

/// `x` and `e` as numpy arrays: `x` of shape `(E,)`, `e` the body frame
/// vectors as rows, shape `(N, E)`.
fn position_and_frame<'py>(py: Python<'py>, x: &[f64], e: &[f64]) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyAny>)> {
    let xa = PyArray1::from_slice(py, x);
    let ea = PyArray1::from_slice(py, e).reshape([frame_rows(x, e), x.len()])?;
    Ok((xa, ea.into_any()))
}

/// Runs `call` with the GIL; its first error goes into `slot` (later calls
/// return NaN at once, so the run stops at the next step).
fn with_slot(slot: &ErrorSlot, call: impl FnOnce(Python<'_>) -> PyResult<()>) -> bool {
    if lock(slot).is_some() {
        return false;
    }
    Python::attach(|py| match call(py) {
        Ok(()) => true,
        Err(e) => {
            lock(slot).get_or_insert(e);
            false
        }
    })
}

/// `part` of a user gradient's return value as `out.len()` numbers of the
/// shape `shape`, or a `ValueError` naming `user_gradient` and the shape.
fn gradient_part(py: Python<'_>, part: &Bound<'_, PyAny>, shape: &[usize], what: &str, out: &mut [f64]) -> PyResult<()> {
    let bad = |got: String| err(py, Kind::Invalid, format!("user_gradient: {what} has {got}; allowed: an array of shape {shape:?} of finite floats"));
    let a: PyArrayLikeDyn<'_, f64, AllowTypeChange> = part.extract().map_err(|_| bad("no numeric array form".into()))?;
    let a = a.as_array();
    if a.shape() != shape {
        return Err(bad(format!("shape {:?}", a.shape())));
    }
    for (o, v) in out.iter_mut().zip(a.iter()) {
        *o = *v;
    }
    Ok(())
}

/// The user's Python callables, checked: `V(x, e) -> float` and the
/// optional gradient `G(x, e) -> (∂V/∂x, ∂V/∂e)`.
#[derive(Clone)]
pub(crate) struct UserCallables {
    value: Arc<Py<PyAny>>,
    gradient: Option<Arc<Py<PyAny>>>,
}

/// Checks the user potential and gradient (callable; no gradient without a
/// potential).
pub(crate) fn check_user(py: Python<'_>, callable: Option<Py<PyAny>>, gradient: Option<Py<PyAny>>) -> PyResult<Option<UserCallables>> {
    let not_callable = |name: &str, what: &str, c: &Py<PyAny>| -> PyResult<()> {
        if c.bind(py).is_callable() {
            return Ok(());
        }
        let tname = c.bind(py).get_type().name().map(|n| n.to_string()).unwrap_or_default();
        Err(err(py, Kind::Invalid, format!("{name}: a {tname} is not callable; allowed: a callable {what}")))
    };
    let Some(callable) = callable else {
        return match gradient {
            None => Ok(None),
            Some(_) => Err(err(py, Kind::Invalid, "user_gradient given without user_potential: it is the gradient of the user potential V(x, e), which must be given too")),
        };
    };
    not_callable("user_potential", "V(x, e) -> float", &callable)?;
    if let Some(g) = &gradient {
        not_callable("user_gradient", "G(x, e) -> (dV/dx, dV/de)", g)?;
    }
    Ok(Some(UserCallables { value: Arc::new(callable), gradient: gradient.map(Arc::new) }))
}

/// The float a user callable returned, or a `TypeError` naming the
/// callable (`what`) and the type it returned instead.
fn returned_float(py: Python<'_>, out: &Py<PyAny>, what: &str) -> PyResult<f64> {
    out.extract::<f64>(py).map_err(|_| {
        let kind = out.bind(py).get_type().name().map_or_else(|_| "?".to_string(), |n| n.to_string());
        pyo3::exceptions::PyTypeError::new_err(format!("{what} returned a {kind}; it must return a float"))
    })
}

/// The Python callables `V(x, e) -> float` and `G(x, e) -> (∂V/∂x, ∂V/∂e)`
/// (optional) as the core's user potential: `x` the embedding position
/// (shape `(E,)`), `e` the body frame vectors as rows (shape `(N, E)`),
/// `∂V/∂e` in the same shape. Each call takes the GIL; the first exception
/// goes into `slot`.
pub(crate) fn user_functions(user: &UserCallables, slot: &ErrorSlot) -> UserFunctions {
    let (callable, s) = (user.value.clone(), slot.clone());
    let value: UserPotentialFn = Arc::new(move |x: &[f64], e: &[f64]| -> f64 {
        let mut v = f64::NAN;
        with_slot(&s, |py| {
            let (xa, ea) = position_and_frame(py, x, e)?;
            v = returned_float(py, &callable.call1(py, (xa, ea))?, "user_potential(x, e)")?;
            Ok(())
        });
        v
    });
    let s = slot.clone();
    let gradient = user.gradient.clone().map(|g| -> UserGradientFn {
        Arc::new(move |x: &[f64], e: &[f64], dx: &mut [f64], de: &mut [f64]| {
            let ok = with_slot(&s, |py| {
                let (xa, ea) = position_and_frame(py, x, e)?;
                let out = g.call1(py, (xa, ea))?;
                let out = out.bind(py);
                let bad = || err(py, Kind::Invalid, "user_gradient: must return a pair (dV/dx, dV/de)");
                if out.len().ok() != Some(2) {
                    return Err(bad());
                }
                gradient_part(py, &out.get_item(0).map_err(|_| bad())?, &[x.len()], "dV/dx", dx)?;
                gradient_part(py, &out.get_item(1).map_err(|_| bad())?, &[frame_rows(x, e), x.len()], "dV/de", de)
            });
            if !ok {
                dx.fill(f64::NAN);
                de.fill(f64::NAN);
            }
        })
    });
    UserFunctions { value, gradient }
}

/// [`check_user`] and [`user_functions`] with a new error slot.
fn user_potential(py: Python<'_>, callable: Option<Py<PyAny>>, gradient: Option<Py<PyAny>>) -> PyResult<Option<(UserFunctions, ErrorSlot)>> {
    Ok(check_user(py, callable, gradient)?.map(|u| {
        let slot: ErrorSlot = Arc::new(Mutex::new(None));
        (user_functions(&u, &slot), slot)
    }))
}

/// A user event from Python, checked: name, `g(t, state) -> float`,
/// direction, terminal. `state` is a dict of every record column (all
/// quantities) at `t`.
struct PyEvent {
    name: String,
    callable: Arc<Py<PyAny>>,
    direction: EventDirection,
    terminal: bool,
}

/// Checks the user events `(name, callable, direction, terminal)`.
fn check_events(py: Python<'_>, events: Option<Vec<(String, Py<PyAny>, String, bool)>>) -> PyResult<Vec<PyEvent>> {
    let mut out = Vec::new();
    for (i, (name, callable, direction, terminal)) in events.unwrap_or_default().into_iter().enumerate() {
        if !callable.bind(py).is_callable() {
            let tname = callable.bind(py).get_type().name().map(|n| n.to_string()).unwrap_or_default();
            return Err(err(py, Kind::Invalid, format!("invalid `events[{i}]`: a {tname} is not callable; allowed: a callable f(t, state) -> float")));
        }
        let direction = match direction.as_str() {
            "either" => EventDirection::Either,
            "rising" => EventDirection::Rising,
            "falling" => EventDirection::Falling,
            other => return Err(err(py, Kind::Invalid, format!("invalid `events[{i}].direction` = {other:?}: allowed: 'rising', 'falling', 'either'"))),
        };
        if name.is_empty() {
            return Err(err(py, Kind::Invalid, format!("invalid `events[{i}].name` = '': must be non-empty")));
        }
        out.push(PyEvent { name, callable: Arc::new(callable), direction, terminal });
    }
    Ok(out)
}

/// The user events as core events over the full record `names`; each call
/// takes the GIL, and an exception is kept in `slot` (the event value is then
/// NaN, which stops the run with an error).
fn user_events(events: &[PyEvent], names: Vec<String>, slot: &ErrorSlot) -> Vec<SceneEvent> {
    let names = Arc::new(names);
    events
        .iter()
        .map(|e| {
            let (callable, names, slot) = (e.callable.clone(), names.clone(), slot.clone());
            let g: EventFn = Arc::new(move |t: f64, row: &[f64]| -> f64 {
                if lock(&slot).is_some() {
                    return f64::NAN;
                }
                Python::attach(|py| {
                    let result = (|| -> PyResult<f64> {
                        let d = PyDict::new(py);
                        for (n, v) in names.iter().zip(row) {
                            d.set_item(n, *v)?;
                        }
                        returned_float(py, &callable.call1(py, (t, d))?, "the event function f(t, state)")
                    })();
                    match result {
                        Ok(v) => v,
                        Err(e) => {
                            lock(&slot).get_or_insert(e);
                            f64::NAN
                        }
                    }
                })
            });
            let event = SceneEvent::from_arc(e.name.clone(), g).direction(e.direction);
            if e.terminal {
                event.terminal()
            } else {
                event
            }
        })
        .collect()
}

/// What one run produced.
struct RunOutput {
    sink: FlatSink,
    summary: RunSummary,
    error: Option<RunError>,
    frame_shape: (usize, usize),
}

/// Builds and runs `scene` (no GIL needed unless a user potential is called).
fn run_scene(
    scene: &Scene,
    user: Option<&UserFunctions>,
    events: Option<(&[PyEvent], &ErrorSlot)>,
    cancel: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<RunOutput, SceneError> {
    let mut sim = build_scene(scene, user)?;
    if let Some((evs, slot)) = events {
        let names = sim.event_columns().iter().map(|c| c.name.clone()).collect();
        for e in user_events(evs, names, slot) {
            sim.add_event(e);
        }
    }
    if let Some(avail) = crate::errors::available_memory() {
        sim.check_memory(avail)?;
    }
    let mut sink = FlatSink::default();
    let frame_shape = sim.frame_shape();
    Ok(match sim.run(&mut sink, cancel, progress) {
        Ok(summary) => RunOutput { sink, summary, error: None, frame_shape },
        Err(failure) => RunOutput { sink, summary: failure.summary, error: Some(failure.error), frame_shape },
    })
}

fn stop_kind(stop: &SceneStop) -> &'static str {
    match stop {
        SceneStop::Finished => "finished",
        SceneStop::Cancelled => "cancelled",
        SceneStop::Failed(_) => "failed",
        SceneStop::OutputError(_) => "output_error",
        SceneStop::Event(_) => "event",
    }
}

/// The Python form of a run: `{"data": (rows, columns) array, "columns",
/// "units", "summary": {...}}`.
fn to_py<'py>(py: Python<'py>, sink: FlatSink, summary: &RunSummary, frame_shape: (usize, usize)) -> PyResult<Bound<'py, PyDict>> {
    let ncols = sink.columns.len();
    let data = PyArray1::from_vec(py, sink.data).reshape([sink.rows, ncols])?;
    let d = PyDict::new(py);
    d.set_item("data", data)?;
    d.set_item("columns", sink.columns.iter().map(|c| c.name.clone()).collect::<Vec<_>>())?;
    d.set_item("units", sink.columns.iter().map(|c| c.unit).collect::<Vec<_>>())?;
    d.set_item("groups", sink.columns.iter().map(|c| c.group.map(|g| g.name())).collect::<Vec<_>>())?;
    d.set_item("frame_shape", frame_shape)?;
    let ev = PyDict::new(py);
    ev.set_item("name", sink.events.iter().map(|e| e.name.clone()).collect::<Vec<_>>())?;
    ev.set_item("index", sink.events.iter().map(|e| e.index).collect::<Vec<_>>())?;
    ev.set_item("t", PyArray1::from_vec(py, sink.events.iter().map(|e| e.t).collect()))?;
    ev.set_item("rising", sink.events.iter().map(|e| e.rising).collect::<Vec<_>>())?;
    ev.set_item("terminal", sink.events.iter().map(|e| e.terminal).collect::<Vec<_>>())?;
    let rows: Vec<f64> = sink.events.iter().flat_map(|e| e.row.iter().copied()).collect();
    ev.set_item("data", PyArray1::from_vec(py, rows).reshape([sink.events.len(), ncols])?)?;
    d.set_item("events", ev)?;
    let s = PyDict::new(py);
    s.set_item("method", summary.method)?;
    s.set_item("steps", summary.steps)?;
    s.set_item("rejected", summary.rejected)?;
    s.set_item("rhs_evals", summary.rhs_evals)?;
    s.set_item("records", summary.records)?;
    s.set_item("events", summary.events)?;
    s.set_item("wall_time", summary.wall_time.as_secs_f64())?;
    s.set_item("energy_initial", summary.energy_initial)?;
    s.set_item("energy_drift", summary.energy_drift)?;
    s.set_item("relative_energy_drift", summary.relative_energy_drift())?;
    s.set_item("max_defect", summary.max_defect)?;
    s.set_item("t_reached", summary.t_reached)?;
    s.set_item("stop", stop_kind(&summary.stop))?;
    s.set_item("message", summary.stop.to_string())?;
    s.set_item("warnings", summary.warning_texts())?;
    // Only when the scene asked for it ([method] global_error = true).
    if let Some(g) = &summary.global_error {
        s.set_item("global_error", g.max)?;
        s.set_item("global_error_final", g.last)?;
        s.set_item("global_error_rhs_evals", g.rhs_evals)?;
    }
    // Only when the scene asked for it ([method] project = "energy").
    if let Some(p) = &summary.projection {
        s.set_item("projected_steps", p.projected)?;
        s.set_item("projection_skipped", p.skipped)?;
        s.set_item("energy_evals", p.energy_evals)?;
    }
    d.set_item("summary", s)?;
    Ok(d)
}

/// One run's result for Python: the result dict, or the exception to raise
/// (an `IntegrationError` carries the partial result as `partial`; an
/// exception raised by a user potential is re-raised as it is, with the
/// partial result attached when possible).
fn finish<'py>(py: Python<'py>, out: Result<Result<RunOutput, SceneError>, String>, slot: Option<&ErrorSlot>) -> PyResult<Bound<'py, PyDict>> {
    let out = match out {
        Err(panic) => return Err(internal(py, panic)),
        Ok(Err(e)) => return Err(scene_err(py, &e)),
        Ok(Ok(out)) => out,
    };
    let user_error = slot.and_then(|s| lock(s).take());
    let result = to_py(py, out.sink, &out.summary, out.frame_shape)?;
    match (out.error, user_error) {
        (None, None) => Ok(result),
        (error, Some(user)) => {
            // The user's own exception explains the failure better than the
            // non-finite value it left behind.
            let value = user.value(py);
            let _ = value.setattr("partial", &result);
            if let Some(e) = error {
                let _ = value.setattr("framedyn_error", e.to_string());
            }
            Err(user)
        }
        (Some(error), None) => {
            let e = run_err(py, &error);
            e.value(py).setattr("partial", &result)?;
            Err(e)
        }
    }
}

/// Runs one scene with the GIL released: `{"data", "columns", "units",
/// "summary"}`. Ctrl-C (SIGINT) is noticed within about 50 ms: the run stops
/// and `KeyboardInterrupt` is raised.
#[pyfunction]
#[pyo3(signature = (scene, user_potential = None, events = None, user_gradient = None))]
pub fn run<'py>(
    py: Python<'py>,
    scene: PyRef<'py, PyScene>,
    user_potential: Option<Py<PyAny>>,
    events: Option<Vec<(String, Py<PyAny>, String, bool)>>,
    user_gradient: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let user = self::user_potential(py, user_potential, user_gradient)?;
    let events = check_events(py, events)?;
    let (f, slot) = match user {
        Some((f, s)) => (Some(f), Some(s)),
        None if !events.is_empty() => (None, Some(Arc::new(Mutex::new(None)))),
        None => (None, None),
    };
    let scene = scene.inner.clone();
    let cancel = AtomicBool::new(false);
    let mut interrupt: Option<PyErr> = None;
    let out = py.detach(|| {
        guard(|| {
            let mut progress = |_: &Progress| {
                if interrupt.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        interrupt = Some(e);
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
            };
            let ev = slot.as_ref().filter(|_| !events.is_empty()).map(|s| (events.as_slice(), s));
            run_scene(&scene, f.as_ref(), ev, &cancel, &mut progress)
        })
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    finish(py, out, slot.as_ref())
}

/// Runs many scenes in parallel (rayon, GIL released) and returns, per
/// scene in order, the result dict or the exception it failed with (not
/// raised: the Python wrapper decides). `threads`: size of the thread pool
/// (default: rayon's global pool, one thread per core). With a user
/// potential every scene has its own error state (an exception is reported
/// on the member that raised it only) and the scenes run one after another:
/// each call of the potential holds the GIL, so threads would only contend
/// for it.
#[pyfunction]
#[pyo3(signature = (scenes, user_potential = None, threads = None, user_gradient = None, oversubscribe = false))]
pub fn run_batch<'py>(
    py: Python<'py>,
    scenes: Vec<PyRef<'py, PyScene>>,
    user_potential: Option<Py<PyAny>>,
    threads: Option<usize>,
    user_gradient: Option<Py<PyAny>>,
    oversubscribe: bool,
) -> PyResult<Vec<Py<PyAny>>> {
    if threads == Some(0) {
        return Err(err(py, Kind::Invalid, "threads = 0: must be ≥ 1 (or None for one per core)"));
    }
    let user = check_user(py, user_potential, user_gradient)?;
    let scenes: Vec<Scene> = scenes.iter().map(|s| s.inner.clone()).collect();
    let slots: Vec<ErrorSlot> = scenes.iter().map(|_| Arc::new(Mutex::new(None))).collect();
    // With a user potential the scenes run one after another on the
    // interruptible call's worker thread (no pool: see `interruptible`).
    let pool = match threads {
        Some(_) if user.is_some() => None,
        Some(n) => Some(
            // Never more workers than members, nor than cores unless asked.
            rayon::ThreadPoolBuilder::new()
                .num_threads(framedyn::scenes::worker_threads(n, scenes.len(), oversubscribe))
                .build()
                .map_err(|e| err(py, Kind::Internal, format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let (outs, interrupt) = interruptible(py, |cancel| {
        let one = |(s, slot): (&Scene, &ErrorSlot)| {
            let f = user.as_ref().map(|u| user_functions(u, slot));
            guard(|| run_scene(s, f.as_ref(), None, cancel, &mut |_| {}))
        };
        let work = || scenes.par_iter().zip(slots.par_iter()).map(one).collect::<Vec<Result<Result<RunOutput, SceneError>, String>>>();
        match &pool {
            _ if user.is_some() => scenes.iter().zip(&slots).map(one).collect(),
            Some(p) => p.install(work),
            None => work(),
        }
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    let outs = outs.map_err(|panic| internal(py, panic))?;
    outs.into_iter()
        .zip(&slots)
        .map(|(o, slot)| match finish(py, o, user.as_ref().map(|_| slot)) {
            Ok(d) => Ok(d.into_any().unbind()),
            Err(e) => Ok(e.into_value(py).into_any()),
        })
        .collect()
}

/// A built scene advanced step by step (the stepping API): `step(h)`,
/// `advance(h, n)`, the current record as an array, `reset()`.
#[pyclass(name = "Stepper", module = "framedyn._framedyn", frozen)]
pub struct PyStepper {
    sim: Mutex<Simulation>,
    columns: Vec<(String, &'static str)>,
    slot: Option<ErrorSlot>,
}

impl PyStepper {
    fn with<T: Send>(&self, py: Python<'_>, f: impl FnOnce(&mut Simulation) -> Result<T, framedyn::solve::SolveError> + Send) -> PyResult<T> {
        let out = py.detach(|| guard(|| f(&mut lock(&self.sim))));
        let user_error = self.slot.as_ref().and_then(|s| lock(s).take());
        match out {
            Err(panic) => Err(internal(py, panic)),
            Ok(Ok(v)) => Ok(v),
            Ok(Err(e)) => match user_error {
                Some(u) => Err(u),
                None => Err(solve_err(py, &e)),
            },
        }
    }
}

#[pymethods]
impl PyStepper {
    /// Builds `scene` (with an optional Python user potential `V(x, e)` and
    /// its optional gradient `G(x, e)`) at its initial state.
    #[new]
    #[pyo3(signature = (scene, user_potential = None, user_gradient = None))]
    fn new(py: Python<'_>, scene: PyRef<'_, PyScene>, user_potential: Option<Py<PyAny>>, user_gradient: Option<Py<PyAny>>) -> PyResult<Self> {
        let user = self::user_potential(py, user_potential, user_gradient)?;
        let scene = scene.inner.clone();
        let (f, slot) = match user {
            Some((f, s)) => (Some(f), Some(s)),
            None => (None, None),
        };
        let built = py.detach(|| guard(|| build_scene(&scene, f.as_ref())));
        let sim = match built {
            Err(panic) => return Err(internal(py, panic)),
            Ok(Err(e)) => {
                if let Some(u) = slot.as_ref().and_then(|s| lock(s).take()) {
                    return Err(u);
                }
                return Err(scene_err(py, &e));
            }
            Ok(Ok(sim)) => sim,
        };
        let columns = sim.columns().iter().map(|c| (c.name.clone(), c.unit)).collect();
        Ok(PyStepper { sim: Mutex::new(sim), columns, slot })
    }

    /// One step of size `h` (finite, non-zero; negative goes backwards).
    fn step(&self, py: Python<'_>, h: f64) -> PyResult<()> {
        self.with(py, |s| s.step(h))
    }

    /// `n` steps of size `h`; stops at the first failure (the steps before
    /// it stay done).
    ///
    /// Ctrl-C is noticed between chunks of at most 4096 steps
    /// (`KeyboardInterrupt`; the chunks before it stay done).
    fn advance(&self, py: Python<'_>, h: f64, n: usize) -> PyResult<()> {
        const CHUNK: usize = 4096;
        let mut left = n;
        while left > 0 {
            let k = left.min(CHUNK);
            self.with(py, |s| s.advance(h, k))?;
            left -= k;
            py.check_signals()?;
        }
        Ok(())
    }

    /// Current time.
    #[getter]
    fn t(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |s| Ok(s.t()))
    }

    /// Energy of the current state.
    #[getter]
    fn energy(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |s| Ok(s.energy()))
    }

    /// Constraint defect of the current state.
    #[getter]
    fn defect(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |s| Ok(s.defect()))
    }

    /// `max |E − E₀|` over the states at the start and end of every
    /// `step`/`advance` call since construction or `reset()` (`E₀`: the
    /// energy before the first call); 0 before any call.
    #[getter]
    fn energy_drift(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |s| Ok(s.stepping_summary().map_or(0.0, |r| r.energy_drift)))
    }

    /// The largest constraint defect over the same states.
    #[getter]
    fn max_defect(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |s| Ok(s.stepping_summary().map_or(0.0, |r| r.max_defect)))
    }

    /// The quality check of those against the scene's `[quality]` limits
    /// (energy drift, defect, non-finite values): empty while sound.
    #[getter]
    fn warnings(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        self.with(py, |s| Ok(s.stepping_summary().map_or_else(Vec::new, |r| r.warning_texts())))
    }

    /// The scene's time span `(t0, t_end)`.
    #[getter]
    fn span(&self, py: Python<'_>) -> PyResult<(f64, f64)> {
        self.with(py, |s| Ok(s.span()))
    }

    /// The method's name.
    #[getter]
    fn method(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.with(py, |s| Ok(s.method_name()))
    }

    /// `(name, unit)` of each entry of `row()`.
    #[getter]
    fn columns(&self) -> Vec<(String, &'static str)> {
        self.columns.clone()
    }

    /// The current state as one record (the scene's output columns).
    fn row<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let row = self.with(py, |s| Ok(s.row()))?;
        Ok(PyArray1::from_vec(py, row))
    }

    /// Back to the initial state.
    fn reset(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |s| {
            s.reset();
            Ok(())
        })
    }
}
