//! Coordinate methods in scenes: the registry's classical Runge–Kutta methods
//! on the paper's chart equations ([`ChartMethod`]), run on the same scene,
//! with the same records, events and driver as the Lie-group methods.
//!
//! A model that has chart equations carries a [`ChartTwin`]: the coordinate
//! Lagrangian of the same body on the same manifold with the same potential
//! ([`coords`](crate::coords)). A run converts the initial state to the
//! paper's coordinates ([`paper_from_state`]), integrates the chart
//! equations with the chart method through [`solve::drive`], and converts
//! every saved state back to the model's state ([`state_from_paper`]) for
//! the records, so the columns are those of the group methods. Where the
//! chart is singular — the poles of S², the origin of H²'s polar chart, the
//! antipode of the S³ chart — the run fails with the method's typed
//! [`SolveError::OutsideChart`], keeping the records up to the last good
//! state: the baseline users can chart against the group methods and watch
//! fail. Available for points, gyroscopes and (unconstrained) affine bodies
//! on the manifolds with a chart geometry (S², H², T², S³).

use std::marker::PhantomData;
use std::sync::atomic::AtomicBool;

use super::error::RunError;
use super::observe::Observe;
use super::simulation::{RecordEvents, Records};
use crate::coords::{paper_from_state, state_from_paper, AmbientBody, AmbientMap, Lagrangian};
use crate::method::baseline::{ChartState, ChartSystem};
use crate::method::registry::ChartMethod;
use crate::method::{Method, StepRequest};
use crate::solve::event::{Direction, EventRecord};
use crate::solve::{self, Control, DriveError, EventSet, Projection, Save, Settings, SolveError, StepSize, StopReason};

/// A chart-method run of a model: why it stopped, and the time and model
/// state reached (`None` if the state could not be converted back).
pub(crate) struct ChartOutcome<G> {
    pub stop: Result<StopReason, RunError>,
    pub t: f64,
    pub y: Option<G>,
    pub stats: solve::Stats,
}

/// The chart equations of a model, and how to run a coordinate method on
/// them for the model's records.
pub(crate) trait ChartTwin<S: Observe>: Send {
    /// Runs `method` from `(t0, y0)` to `t_end` with `settings`, recording
    /// through `records` and locating `events`.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        model: &S,
        method: &ChartMethod,
        t0: f64,
        y0: &S::State,
        t_end: f64,
        settings: &Settings,
        records: &mut Records<'_, S>,
        events: &mut RecordEvents<'_, S>,
        control: &mut Control<'_>,
    ) -> ChartOutcome<S::State>;

    /// One step of `method` of size `h` from the model state `y` at `t`
    /// (through the paper's coordinates and back).
    fn step(&self, model: &S, method: &ChartMethod, t: f64, y: &S::State, h: f64) -> Result<S::State, SolveError>;

    /// `n` steps of `method` of size `h` from `(t, y)` through the driver
    /// (cancellable), in the paper's coordinates; the time and model state
    /// reached; each step projected back onto the chart energy of `(t, y)`
    /// if `projection` says so.
    #[allow(clippy::too_many_arguments)]
    fn advance(&self, model: &S, method: &ChartMethod, t: f64, y: &S::State, h: f64, n: usize, projection: Projection, cancel: &AtomicBool) -> (Result<StopReason, SolveError>, f64, Option<S::State>);
}

/// The chart equations of the Lagrangian `L` (`Q` coordinates) for a model
/// with `N` frame vectors in `E` dimensions.
pub(crate) struct ChartRunner<L, const Q: usize, const N: usize, const E: usize> {
    sys: ChartSystem<L, Q>,
    _dims: PhantomData<fn() -> ([(); N], [(); E])>,
}

impl<L, const Q: usize, const N: usize, const E: usize> ChartRunner<L, Q, N, E>
where
    L: Lagrangian<Q> + AmbientMap<Q, N, E> + Send + Sync,
{
    pub(crate) fn new(lagrangian: L) -> Self {
        ChartRunner { sys: ChartSystem::new(lagrangian), _dims: PhantomData }
    }
}

/// A conversion failure as the typed error of an integration outside its chart.
fn chart_error(e: crate::Error, t: f64) -> SolveError {
    match e {
        crate::Error::OutsideChart { reason, .. } => SolveError::OutsideChart { t, h: 0.0, t_eval: t, reason },
        other => SolveError::InvalidOptions { reason: format!("the state at t = {t} has no paper coordinates: {other}") },
    }
}

/// The model state of a chart state.
fn to_model<S, L, const Q: usize, const N: usize, const E: usize>(lag: &L, model: &S, t: f64, y: &ChartState<Q>) -> Result<S::State, SolveError>
where
    S: AmbientBody<N, E>,
    L: AmbientMap<Q, N, E>,
{
    state_from_paper(lag, model, &y.0 .0, &y.1 .0).map_err(|e| chart_error(e, t))
}

/// The model's sink, fed chart states.
struct ChartSink<'a, 'r, S: Observe, L, const Q: usize, const N: usize, const E: usize> {
    lag: &'a L,
    model: &'a S,
    inner: &'a mut Records<'r, S>,
}

impl<S, L, const Q: usize, const N: usize, const E: usize> solve::Sink<ChartState<Q>> for ChartSink<'_, '_, S, L, Q, N, E>
where
    S: Observe + AmbientBody<N, E>,
    L: AmbientMap<Q, N, E>,
{
    type Error = RunError;

    fn save(&mut self, t: f64, y: &ChartState<Q>) -> Result<(), RunError> {
        let ys = to_model::<S, L, Q, N, E>(self.lag, self.model, t, y).map_err(RunError::Integration)?;
        solve::Sink::save(self.inner, t, &ys)
    }

    fn event(&mut self, rec: &EventRecord<ChartState<Q>>) -> Result<(), RunError> {
        let ys = to_model::<S, L, Q, N, E>(self.lag, self.model, rec.t, &rec.y).map_err(RunError::Integration)?;
        solve::Sink::event(self.inner, &EventRecord { index: rec.index, t: rec.t, y: ys, rising: rec.rising, terminal: rec.terminal })
    }
}

/// The model's events, evaluated on chart states (NaN where a state has no
/// model state, which the driver reports as a non-finite event value).
struct ChartEvents<'a, 'r, S: Observe, L, const Q: usize, const N: usize, const E: usize> {
    lag: &'a L,
    model: &'a S,
    inner: &'a mut RecordEvents<'r, S>,
}

impl<S, L, const Q: usize, const N: usize, const E: usize> EventSet<ChartState<Q>> for ChartEvents<'_, '_, S, L, Q, N, E>
where
    S: Observe + AmbientBody<N, E>,
    L: AmbientMap<Q, N, E>,
{
    fn count(&self) -> usize {
        self.inner.count()
    }
    fn direction(&self, k: usize) -> Direction {
        self.inner.direction(k)
    }
    fn terminal(&self, k: usize) -> bool {
        self.inner.terminal(k)
    }
    fn values(&mut self, t: f64, y: &ChartState<Q>, out: &mut [f64]) {
        match to_model::<S, L, Q, N, E>(self.lag, self.model, t, y) {
            Ok(ys) => self.inner.values(t, &ys, out),
            Err(_) => out.fill(f64::NAN),
        }
    }
    fn value(&mut self, k: usize, t: f64, y: &ChartState<Q>) -> f64 {
        match to_model::<S, L, Q, N, E>(self.lag, self.model, t, y) {
            Ok(ys) => self.inner.value(k, t, &ys),
            Err(_) => f64::NAN,
        }
    }
}

impl<S, L, const Q: usize, const N: usize, const E: usize> ChartTwin<S> for ChartRunner<L, Q, N, E>
where
    S: Observe + AmbientBody<N, E>,
    L: Lagrangian<Q> + AmbientMap<Q, N, E> + Send + Sync + 'static,
{
    fn run(
        &self,
        model: &S,
        method: &ChartMethod,
        t0: f64,
        y0: &S::State,
        t_end: f64,
        settings: &Settings,
        records: &mut Records<'_, S>,
        events: &mut RecordEvents<'_, S>,
        control: &mut Control<'_>,
    ) -> ChartOutcome<S::State> {
        let lag = self.sys.lagrangian();
        let start = match paper_from_state(lag, model, y0) {
            Ok(p) => ChartSystem::<L, Q>::state(&p.q, &p.qdot),
            Err(e) => {
                return ChartOutcome { stop: Err(RunError::Integration(chart_error(e, t0))), t: t0, y: None, stats: solve::Stats::default() };
            }
        };
        let mut sink = ChartSink::<S, L, Q, N, E> { lag, model, inner: records };
        let mut evs = ChartEvents::<S, L, Q, N, E> { lag, model, inner: events };
        let out = solve::drive(&self.sys, method, t0, &start, t_end, settings, &mut evs, &mut sink, control);
        let y = to_model::<S, L, Q, N, E>(lag, model, out.t, &out.y).ok();
        let stop = match out.stop {
            Ok(r) => Ok(r),
            Err(DriveError::Solve(e)) => Err(RunError::Integration(e)),
            Err(DriveError::Sink(e)) => Err(e),
        };
        ChartOutcome { stop, t: out.t, y, stats: out.stats }
    }

    fn step(&self, model: &S, method: &ChartMethod, t: f64, y: &S::State, h: f64) -> Result<S::State, SolveError> {
        let lag = self.sys.lagrangian();
        let p = paper_from_state(lag, model, y).map_err(|e| chart_error(e, t))?;
        let yc = ChartSystem::<L, Q>::state(&p.q, &p.qdot);
        let out = method.step(&self.sys, t, &yc, h, StepRequest::plain()).map_err(|f| solve::fault_error(f, t, h))?;
        to_model::<S, L, Q, N, E>(lag, model, t + h, &out.y)
    }

    fn advance(&self, model: &S, method: &ChartMethod, t: f64, y: &S::State, h: f64, n: usize, projection: Projection, cancel: &AtomicBool) -> (Result<StopReason, SolveError>, f64, Option<S::State>) {
        let lag = self.sys.lagrangian();
        let start = match paper_from_state(lag, model, y) {
            Ok(p) => ChartSystem::<L, Q>::state(&p.q, &p.qdot),
            Err(e) => return (Err(chart_error(e, t)), t, None),
        };
        let settings = Settings { step: StepSize::Fixed(h.abs()), save: Save::Ends, dense: false, max_steps: n, event_xtol: 0.0, projection };
        let mut none: &[solve::Event<ChartState<Q>>] = &[];
        let mut control = Control { cancel: Some(cancel), progress: None };
        let out = solve::drive(&self.sys, method, t, &start, t + h * n as f64, &settings, &mut none, &mut Discard, &mut control);
        let ym = to_model::<S, L, Q, N, E>(lag, model, out.t, &out.y).ok();
        let stop = match out.stop {
            Ok(r) => Ok(r),
            Err(DriveError::Solve(e)) => Err(e),
            Err(DriveError::Sink(never)) => match never {},
        };
        (stop, out.t, ym)
    }
}

/// A sink that keeps nothing.
struct Discard;

impl<const Q: usize> solve::Sink<ChartState<Q>> for Discard {
    type Error = std::convert::Infallible;
    fn save(&mut self, _: f64, _: &ChartState<Q>) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// The chart geometry of a manifold that has none in [`coords`](crate::coords)
/// (the spheroid): a type without values, so `None::<NoChart>` is the only
/// use and its methods can never run. Coordinate methods are refused there.
#[derive(Debug, Clone, Copy)]
pub(crate) enum NoChart {}

impl<const N: usize, const E: usize> crate::coords::ChartGeometry<N, E> for NoChart {
    const NAME: &'static str = "none";
    fn coordinate_names(&self) -> [&'static str; N] {
        match *self {}
    }
    fn check_chart(&self, _: &nalgebra::SVector<f64, N>) -> crate::Result<()> {
        match *self {}
    }
    fn metric<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> nalgebra::SMatrix<D, N, N> {
        match *self {}
    }
    fn frame<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> nalgebra::SMatrix<D, N, N> {
        match *self {}
    }
    fn coframe<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> nalgebra::SMatrix<D, N, N> {
        match *self {}
    }
    fn frame_connection<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> crate::coords::Connection<D, N> {
        match *self {}
    }
    fn ambient_metric(&self) -> nalgebra::SMatrix<f64, E, E> {
        match *self {}
    }
    fn embed<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> nalgebra::SVector<D, E> {
        match *self {}
    }
    fn embed_jacobian<D: crate::potential::Scalar>(&self, _: &nalgebra::SVector<D, N>) -> nalgebra::SMatrix<D, E, N> {
        match *self {}
    }
    fn chart_point(&self, _: &nalgebra::SVector<f64, E>) -> crate::Result<nalgebra::SVector<f64, N>> {
        match *self {}
    }
}
