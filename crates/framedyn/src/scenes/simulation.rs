//! [`Simulation`]: a built scene, run to a [`RecordSink`] or stepped. Its
//! engine is one generic type over the models, instantiated once per
//! manifold × body behind the object-safe [`DynEngine`]; every run goes
//! through the crate's one driver ([`solve::drive`](crate::solve::drive))
//! with a sink that turns states into records.

use std::fmt;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::chart::ChartTwin;
use super::error::{RunError, SceneError};
use super::observe::{Observe, Row, Sel};
use super::plan::{Plan, MEASURED};
use super::sink::{Column, EventHit, RecordSink};
use super::spec::Quantity;
use super::summary::{nan_max, GlobalError, Progress, ProjectionCounts, RunFailure, RunSummary, SceneStop};
use crate::lie::LieGroup;
use crate::method::registry::{Built, ChartMethod, Needs};
use crate::method::{Method, StepRequest};
use crate::solve::event::{Direction, Event, EventRecord};
use crate::solve::projection::project_energy;
use crate::solve::{self, Control, DriveError, EventSet, Problem, Projection, Save, Settings, SolveError, Stats, StepSize, StopReason};

/// The object-safe face of an engine.
pub(crate) trait DynEngine: Send {
    fn columns(&self, sel: Sel) -> Vec<Column>;
    fn row(&self, sel: Sel, out: &mut Vec<f64>);
    fn t(&self) -> f64;
    fn energy(&self) -> f64;
    fn defect(&self) -> f64;
    /// Whether a method with these needs can integrate the model.
    fn supports(&self, needs: Needs) -> bool;
    /// One step of `method` of size `h` from the current state, projected
    /// back onto the initial state's energy if `projection` says so.
    fn step(&mut self, method: &Built, h: f64, projection: Projection) -> Result<(), SolveError>;
    /// `n` steps of `method` of size `h` from the current state, through the
    /// driver (cancellable), each projected back onto the initial state's
    /// energy if `projection` says so (through a coordinate method: onto the
    /// chart energy of the state the call starts from).
    fn advance(&mut self, method: &Built, h: f64, n: usize, projection: Projection, cancel: &AtomicBool) -> Result<StopReason, SolveError>;
    fn reset(&mut self);
    /// Runs the plan from the initial state, records to `ctx`.
    fn run(&mut self, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError>;
}

/// The bookkeeping of a run besides the driver: sink, cancel flag,
/// progress, summary.
pub(crate) struct Ctx<'a> {
    pub sink: &'a mut dyn RecordSink,
    pub cancel: &'a AtomicBool,
    pub progress: &'a mut dyn FnMut(&Progress),
    pub summary: RunSummary,
    pub last_progress: Instant,
    /// Columns of the momentum maps in a record.
    pub mm_idx: Vec<usize>,
    /// The compared quantities of every record, kept for a global-error
    /// estimate (`None`: not asked for).
    pub capture: Option<Capture>,
}

/// The time and the compared quantities ([`MEASURED`]) of every record of a
/// run, one flat row after the other (the time first).
pub(crate) struct Capture {
    sel: Sel,
    data: Vec<f64>,
    buf: Vec<f64>,
}

/// A [`RecordSink`] that compares the records of a reference run with the
/// captured ones at the same times ([`GlobalError`]).
struct Compare<'a> {
    captured: &'a [f64],
    width: usize,
    next: usize,
    groups: Vec<Vec<usize>>,
    max: f64,
    last: f64,
}

impl RecordSink for Compare<'_> {
    fn columns(&mut self, columns: &[Column]) -> std::io::Result<()> {
        self.width = columns.len();
        self.groups = measured_groups(columns);
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> std::io::Result<()> {
        // The reference saves exactly at the captured times, in order.
        while self.next * self.width < self.captured.len() {
            let a = &self.captured[self.next * self.width..(self.next + 1) * self.width];
            self.next += 1;
            if a[0] == row[0] {
                let e = state_error(&self.groups, a, row);
                self.max = nan_max(self.max, e);
                self.last = e;
                break;
            }
        }
        Ok(())
    }
}

/// The column indices of each compared vector: the position, the velocity,
/// each body-frame vector (`e1_*`, `e2_*`, …) and the momenta.
fn measured_groups(columns: &[Column]) -> Vec<Vec<usize>> {
    let of = |q: Quantity| columns.iter().enumerate().filter(|(_, c)| c.group == Some(q)).map(|(j, _)| j).collect::<Vec<_>>();
    let mut out = vec![of(Quantity::Position), of(Quantity::Velocity)];
    let frame = of(Quantity::Frame);
    let vector = |j: usize| columns[j].name.split('_').next().unwrap_or("").to_string();
    let mut names: Vec<String> = frame.iter().map(|&j| vector(j)).collect();
    names.dedup();
    for n in names {
        out.push(frame.iter().copied().filter(|&j| vector(j) == n).collect());
    }
    out.push(of(Quantity::Momenta));
    out.retain(|g| !g.is_empty());
    out
}

/// `max over groups of ‖a − b‖₂/(1 + ‖b‖₂)`.
fn state_error(groups: &[Vec<usize>], a: &[f64], b: &[f64]) -> f64 {
    let mut worst = 0.0;
    for g in groups {
        let d = g.iter().map(|&j| (a[j] - b[j]).powi(2)).sum::<f64>().sqrt();
        let n = g.iter().map(|&j| b[j].powi(2)).sum::<f64>().sqrt();
        worst = nan_max(worst, d / (1.0 + n));
    }
    worst
}

/// The engine of one model: the problem and the current state of the
/// stepping API.
pub(crate) struct Engine<S: Observe> {
    problem: Problem<S>,
    /// The model's chart equations, for the coordinate methods.
    chart: Option<Box<dyn ChartTwin<S>>>,
    t: f64,
    y: S::State,
}

/// An engine for `system` from `y0` over `span`, with the model's chart
/// equations if it has them.
pub(crate) fn boxed<S: Observe>(system: S, y0: S::State, span: (f64, f64), chart: Option<Box<dyn ChartTwin<S>>>) -> Result<Box<dyn DynEngine>, SolveError> {
    let problem = Problem::new(system, y0, span)?;
    Ok(Box::new(Engine { t: span.0, y: *problem.y0(), problem, chart }))
}

/// The sink of a scene run: states become records (the selected columns)
/// for the [`RecordSink`], and the summary notes energy, momentum maps and
/// defect of every record.
pub(crate) struct Records<'a, S: Observe> {
    sys: &'a S,
    sel: Sel,
    sink: &'a mut dyn RecordSink,
    summary: &'a mut RunSummary,
    mm_idx: &'a [usize],
    events: &'a [Event<[f64]>],
    buf: Vec<f64>,
    /// The momentum maps of the current and of the first record.
    mm: Vec<f64>,
    mm0: Vec<f64>,
    /// For a sink that keeps only the last record ([`RecordSink::last_only`]):
    /// the last saved state, recorded by [`Records::finish`].
    last: Option<Option<(f64, S::State)>>,
    capture: Option<&'a mut Capture>,
}

impl<'a, S: Observe> Records<'a, S> {
    fn new(
        sys: &'a S,
        sel: Sel,
        sink: &'a mut dyn RecordSink,
        summary: &'a mut RunSummary,
        mm_idx: &'a [usize],
        events: &'a [Event<[f64]>],
        capture: Option<&'a mut Capture>,
    ) -> Self {
        let last = sink.last_only().then_some(None);
        // Room for the widest record (an affine body on S³ has 59 columns):
        // no reallocation while the first record is built.
        let (buf, mm, mm0) = (Vec::with_capacity(64), Vec::with_capacity(mm_idx.len()), Vec::with_capacity(mm_idx.len()));
        Records { sys, sel, sink, summary, mm_idx, events, buf, mm, mm0, last, capture }
    }

    /// Notes the record whose momentum maps are in `self.mm`.
    fn note(&mut self, energy: f64, defect: f64) {
        let s = &mut *self.summary;
        if s.records == 0 {
            self.mm0.clone_from(&self.mm);
        }
        for (m, m0) in self.mm.iter().zip(&self.mm0) {
            s.momentum_map_drift = nan_max(s.momentum_map_drift, (m - m0).abs());
        }
        s.note(energy, defect);
    }

    /// Records the last saved state, if the sink keeps only that one.
    fn finish(&mut self) -> Result<(), RunError> {
        if let Some(Some((t, y))) = self.last.take() {
            self.buf.clear();
            self.sys.observe(self.sel, t, &y, &mut Row::values(&mut self.buf));
            self.sink.record(&self.buf)?;
        }
        Ok(())
    }
}

impl<S: Observe> solve::Sink<S::State> for Records<'_, S> {
    type Error = RunError;

    fn save(&mut self, t: f64, y: &S::State) -> Result<(), RunError> {
        self.buf.clear();
        self.mm.clear();
        match &mut self.last {
            None => {
                self.sys.observe(self.sel, t, y, &mut Row::values(&mut self.buf));
                self.sink.record(&self.buf)?;
                self.mm.extend(self.mm_idx.iter().map(|&j| self.buf[j]));
            }
            Some(last) => {
                // The momentum maps only (after the time, the first column
                // of every row); the whole record of the last state at the end.
                *last = Some((t, *y));
                if let Some(sel) = self.sel.only(Quantity::MomentumMap) {
                    self.sys.observe(sel, t, y, &mut Row::values(&mut self.buf));
                    self.mm.extend_from_slice(&self.buf[1..]);
                }
            }
        }
        if let Some(c) = self.capture.as_deref_mut() {
            c.buf.clear();
            self.sys.observe(c.sel, t, y, &mut Row::values(&mut c.buf));
            c.data.extend_from_slice(&c.buf);
        }
        let (energy, defect) = (self.sys.energy(y), self.sys.defect(y));
        self.note(energy, defect);
        Ok(())
    }

    fn event(&mut self, rec: &EventRecord<S::State>) -> Result<(), RunError> {
        let mut row = Vec::new();
        self.sys.observe(self.sel, rec.t, &rec.y, &mut Row::values(&mut row));
        let name = self.events[rec.index].name().to_string();
        self.sink.event(&EventHit { index: rec.index, name, t: rec.t, row, rising: rec.rising, terminal: rec.terminal })?;
        self.summary.events += 1;
        Ok(())
    }
}

/// The scene's events (functions of the full record) as the driver's
/// [`EventSet`] on the model's states: each evaluation observes every
/// quantity into one reused buffer.
pub(crate) struct RecordEvents<'a, S: Observe> {
    sys: &'a S,
    events: &'a [Event<[f64]>],
    full: Vec<f64>,
}

impl<S: Observe> RecordEvents<'_, S> {
    fn observe(&mut self, t: f64, y: &S::State) {
        self.full.clear();
        self.sys.observe(Sel::ALL, t, y, &mut Row::values(&mut self.full));
    }
}

impl<S: Observe> EventSet<S::State> for RecordEvents<'_, S> {
    fn count(&self) -> usize {
        self.events.len()
    }
    fn direction(&self, k: usize) -> Direction {
        self.events[k].direction_of()
    }
    fn terminal(&self, k: usize) -> bool {
        self.events[k].is_terminal()
    }
    fn values(&mut self, t: f64, y: &S::State, out: &mut [f64]) {
        self.observe(t, y);
        for (o, e) in out.iter_mut().zip(self.events) {
            *o = e.value(t, &self.full);
        }
    }
    fn value(&mut self, k: usize, t: f64, y: &S::State) -> f64 {
        self.observe(t, y);
        self.events[k].value(t, &self.full)
    }
}

/// A sink that keeps nothing (the stepping API's `advance`).
struct Discard;

impl<G: LieGroup> solve::Sink<G> for Discard {
    type Error = std::convert::Infallible;
    fn save(&mut self, _: f64, _: &G) -> Result<(), Self::Error> {
        Ok(())
    }
}

impl<S: Observe> Engine<S> {
    /// The chart equations, or the error of a coordinate method on a model
    /// without them.
    fn chart(&self, m: &ChartMethod) -> Result<&dyn ChartTwin<S>, SolveError> {
        self.chart.as_deref().ok_or_else(|| SolveError::InvalidOptions {
            reason: format!("{} integrates the paper's chart equations, which this model does not have ({})", m.display(), Needs::Chart.describe()),
        })
    }
}

impl<S: Observe> DynEngine for Engine<S> {
    fn columns(&self, sel: Sel) -> Vec<Column> {
        let mut cols = Vec::new();
        let mut vals = Vec::new();
        self.problem.system().observe(sel, self.t, &self.y, &mut Row::described(&mut cols, &mut vals));
        cols
    }

    fn row(&self, sel: Sel, out: &mut Vec<f64>) {
        out.clear();
        self.problem.system().observe(sel, self.t, &self.y, &mut Row::values(out));
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn energy(&self) -> f64 {
        self.problem.system().energy(&self.y)
    }

    fn defect(&self) -> f64 {
        self.problem.system().defect(&self.y)
    }

    fn supports(&self, needs: Needs) -> bool {
        match needs {
            Needs::Nothing => true,
            Needs::ExactFreeFlow => self.problem.system().as_splittable().is_some(),
            Needs::Chart => self.chart.is_some(),
        }
    }

    fn step(&mut self, method: &Built, h: f64, projection: Projection) -> Result<(), SolveError> {
        if !(h.is_finite() && h != 0.0) {
            return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "finite and ≠ 0" });
        }
        let sys = self.problem.system();
        let y = match method {
            Built::Group(m) => m.step(sys, self.t, &self.y, h, StepRequest::plain()).map_err(|f| solve::fault_error(f, self.t, h))?.y,
            Built::Chart(m) => self.chart(m)?.step(sys, m, self.t, &self.y, h)?,
        };
        self.y = match projection.level(|| sys.energy(self.problem.y0())) {
            Some(e0) => project_energy(sys, &y, e0, &mut Stats::default()),
            None => y,
        };
        self.t += h;
        Ok(())
    }

    fn advance(&mut self, method: &Built, h: f64, n: usize, projection: Projection, cancel: &AtomicBool) -> Result<StopReason, SolveError> {
        if !(h.is_finite() && h != 0.0) {
            return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "finite and ≠ 0" });
        }
        if n == 0 {
            return Ok(StopReason::Finished);
        }
        let m = match method {
            Built::Group(m) => *m,
            Built::Chart(m) => {
                let (stop, t, y) = self.chart(m)?.advance(self.problem.system(), m, self.t, &self.y, h, n, projection, cancel);
                if let Some(y) = y {
                    self.t = t;
                    self.y = y;
                }
                return stop;
            }
        };
        let t_end = self.t + h * n as f64;
        // Back to the scene's initial energy, not to that of this call's start.
        let projection = projection.level(|| self.problem.system().energy(self.problem.y0())).map_or(Projection::None, Projection::Level);
        let settings = Settings { step: StepSize::Fixed(h.abs()), save: Save::Ends, dense: false, max_steps: n, event_xtol: 0.0, projection };
        let mut events: &[Event<S::State>] = &[];
        let mut control = Control { cancel: Some(cancel), progress: None };
        let out = solve::drive(self.problem.system(), &m, self.t, &self.y, t_end, &settings, &mut events, &mut Discard, &mut control);
        self.t = out.t;
        self.y = out.y;
        match out.stop {
            Ok(reason) => Ok(reason),
            Err(DriveError::Solve(e)) => Err(e),
            Err(DriveError::Sink(never)) => match never {},
        }
    }

    fn reset(&mut self) {
        self.t = self.problem.t0();
        self.y = *self.problem.y0();
    }

    fn run(&mut self, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError> {
        self.reset();
        let sys = self.problem.system();
        let (t0, t_end) = (plan.t0, plan.t_end);
        let user_progress = &mut *ctx.progress;
        let mut last = ctx.last_progress;
        // Progress at the driver's polls, at most every 50 ms.
        let mut report = |t: f64, stats: &Stats| {
            let now = Instant::now();
            if now.duration_since(last).as_millis() >= 50 {
                last = now;
                let fraction = ((t - t0) / (t_end - t0)).clamp(0.0, 1.0);
                user_progress(&Progress { t, t0, t_end, fraction, steps: stats.accepted as u64 });
            }
        };
        let mut control = Control { cancel: Some(ctx.cancel), progress: Some(&mut report) };
        let mut records = Records::new(sys, plan.sel, &mut *ctx.sink, &mut ctx.summary, &ctx.mm_idx, &plan.events, ctx.capture.as_mut());
        let mut events = RecordEvents { sys, events: &plan.events, full: Vec::new() };
        let (stop, stats) = match &plan.method {
            Built::Group(m) => {
                let out = solve::drive(sys, m, t0, self.problem.y0(), t_end, &plan.settings, &mut events, &mut records, &mut control);
                self.t = out.t;
                self.y = out.y;
                let stop = match out.stop {
                    Ok(r) => Ok(r),
                    Err(DriveError::Solve(e)) => Err(RunError::Integration(e)),
                    Err(DriveError::Sink(e)) => Err(e),
                };
                (stop, out.stats)
            }
            Built::Chart(m) => {
                let twin = self.chart(m).map_err(RunError::Integration)?;
                let out = twin.run(sys, m, t0, self.problem.y0(), t_end, &plan.settings, &mut records, &mut events, &mut control);
                if let Some(y) = out.y {
                    self.t = out.t;
                    self.y = y;
                }
                (out.stop, out.stats)
            }
        };
        let stop = match (stop, records.finish()) {
            (Ok(_), Err(e)) => Err(e),
            (stop, _) => stop,
        };
        let s = &mut ctx.summary;
        s.steps = stats.accepted as u64;
        s.rejected = stats.rejected as u64;
        s.rhs_evals = stats.rhs_evals as u64;
        if plan.settings.projection != Projection::None {
            s.projection = Some(ProjectionCounts {
                projected: stats.projections as u64,
                skipped: stats.projections_skipped as u64,
                energy_evals: stats.energy_evals as u64,
            });
        }
        s.t_reached = self.t;
        match stop {
            Ok(StopReason::Finished) => Ok(()),
            Ok(StopReason::Cancelled) => {
                s.stop = SceneStop::Cancelled;
                Ok(())
            }
            Ok(StopReason::Event { index }) => {
                s.stop = SceneStop::Event(plan.events[index].name().to_string());
                Ok(())
            }
            Ok(StopReason::Failed(e)) => Err(RunError::Integration(e)),
            Err(e) => Err(e),
        }
    }
}

/// A built scene: run it to a sink, or step it.
pub struct Simulation {
    pub(crate) engine: Box<dyn DynEngine>,
    pub(crate) plan: Plan,
    pub(crate) columns: Vec<Column>,
    pub(crate) event_columns: Vec<Column>,
    pub(crate) name: String,
    /// What the stepping API has seen since the last reset (see
    /// [`Simulation::stepping_summary`]).
    pub(crate) stepping: Option<RunSummary>,
}

impl fmt::Debug for Simulation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Simulation").field("name", &self.name).field("columns", &self.columns.len()).finish_non_exhaustive()
    }
}

impl Simulation {
    /// The columns of a record (see the [module docs](super)).
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// `(N, E)`: the number of body frame vectors (0 for a point) and the
    /// dimension of the embedding, the shape of the `frame` group of a
    /// record (vectors in order, each with its `E` components).
    pub fn frame_shape(&self) -> (usize, usize) {
        let count = |q: Quantity| self.event_columns.iter().filter(|c| c.group == Some(q)).count();
        let e = count(Quantity::Position);
        (if e == 0 { 0 } else { count(Quantity::Frame) / e }, e)
    }

    /// The method's display name (the registry's).
    pub fn method_name(&self) -> &'static str {
        self.plan.method.display()
    }

    /// The columns an event function sees: every quantity, whatever
    /// `output.quantities` selects.
    pub fn event_columns(&self) -> &[Column] {
        &self.event_columns
    }

    /// Adds an event on the full record ([`Self::event_columns`]), after
    /// those of the scene's `[[events]]`, to later runs.
    pub fn add_event(&mut self, event: Event<[f64]>) {
        self.plan.events.push(event);
    }

    /// The events of a run.
    pub fn events(&self) -> &[Event<[f64]>] {
        &self.plan.events
    }

    /// The most records a run can write, if known before it: for fixed
    /// steps and for `output.times`/`samples` (with adaptive steps recorded
    /// every k-th step the count depends on the steps taken: `None`).
    pub fn record_bound(&self) -> Option<u64> {
        use crate::solve::fixed_step_count;
        let s = &self.plan.settings;
        let steps = match &s.step {
            StepSize::Fixed(h) => fixed_step_count(self.plan.t0, self.plan.t_end, *h).map_or(s.max_steps, |n| n.min(s.max_steps)) as u64,
            StepSize::Adaptive(_) => match &s.save {
                Save::At(ts) => return Some(ts.len() as u64),
                Save::Ends => return Some(2),
                _ => return None,
            },
        };
        Some(match &s.save {
            Save::Steps => steps.saturating_add(1),
            Save::Every(k) => (steps / (*k).max(1)).saturating_add(2),
            Save::At(ts) => ts.len() as u64,
            Save::Ends => 2,
        })
    }

    /// Refuses, before anything is allocated, a run whose records could
    /// need more than `available` bytes when kept in memory (8 bytes per
    /// value): the error names the settings that decide the record count.
    /// Runs whose record count is not known in advance ([`Self::record_bound`])
    /// pass; their growth fails with an out-of-memory error instead.
    pub fn check_memory(&self, available: u64) -> Result<(), SceneError> {
        let Some(records) = self.record_bound() else { return Ok(()) };
        let bytes = (records as f64) * (self.columns.len() as f64) * 8.0;
        if bytes <= available as f64 {
            return Ok(());
        }
        let (field, value) = match &self.plan.settings.save {
            Save::At(ts) => ("output.samples", ts.len().to_string()),
            Save::Every(k) => ("output.every", k.to_string()),
            _ => ("output.every", "1".to_string()),
        };
        Err(SceneError::invalid(
            field,
            value,
            format!(
                "the run can keep {records} records × {} columns = {:.1} GB in memory, more than the {:.1} GB available; record fewer (output.every, output.samples, quantities) or stream the records to a file with the command line",
                self.columns.len(),
                bytes / 1e9,
                available as f64 / 1e9
            ),
        ))
    }

    /// Runs the scene from its initial state over its time span (the
    /// simulation is reset first and left at the last state reached — with
    /// `[method] global_error = true`, the reference run's state at that
    /// time, see [`GlobalError`]),
    /// streaming records to `sink`; `cancel` is polled every few hundred
    /// steps (a cancelled run stops cleanly with [`SceneStop::Cancelled`]
    /// and the last state recorded); `progress` is called at most every
    /// 50 ms, and once at the end.
    ///
    /// On an integration failure the records up to the last good state have
    /// been written and the error comes with the summary ([`RunFailure`]).
    pub fn run(&mut self, sink: &mut dyn RecordSink, cancel: &AtomicBool, progress: &mut dyn FnMut(&Progress)) -> Result<RunSummary, RunFailure> {
        let started = Instant::now();
        self.stepping = None;
        let mut summary = RunSummary::new(self.method_name(), self.plan.t0);
        if let Err(e) = sink.columns(&self.columns) {
            summary.stop = SceneStop::OutputError(e.to_string());
            return Err(RunFailure { error: RunError::Io(e), summary });
        }
        let mm_idx = self.columns.iter().enumerate().filter(|(_, c)| c.group == Some(Quantity::MomentumMap)).map(|(j, _)| j).collect();
        let capture = self.plan.global_error.then(|| Capture { sel: Sel::new(&MEASURED), data: Vec::new(), buf: Vec::new() });
        let mut ctx = Ctx { sink, cancel, progress, summary, last_progress: started, mm_idx, capture };
        let result = self.engine.run(&self.plan, &mut ctx);
        let (t0, t_end, t) = (self.plan.t0, self.plan.t_end, self.engine.t());
        let fraction = ((t - t0) / (t_end - t0)).clamp(0.0, 1.0);
        (ctx.progress)(&Progress { t, t0, t_end, fraction, steps: ctx.summary.steps });
        let capture = ctx.capture.take();
        let mut summary = ctx.summary;
        summary.t_reached = t;
        if let (Ok(()), Some(capture)) = (&result, capture) {
            if summary.stop != SceneStop::Cancelled && t != t0 {
                summary.global_error = self.estimate_global_error(&capture, t, cancel);
            }
        }
        summary.wall_time = started.elapsed();
        summary.judge(self.plan.quality);
        match result {
            Ok(()) => Ok(summary),
            Err(error) => {
                summary.stop = match &error {
                    RunError::Integration(e) => SceneStop::Failed(e.clone()),
                    RunError::Io(e) => SceneStop::OutputError(e.to_string()),
                    RunError::Scene(e) => SceneStop::OutputError(e.to_string()),
                };
                Err(RunFailure { error, summary })
            }
        }
    }

    /// The global-error estimate of a run whose compared quantities are in
    /// `capture` and which reached `t_reached` ([`GlobalError`]): the
    /// reference run ([`Plan::reference`]) compared at every record. `None`
    /// if the reference run fails or is cancelled. Leaves the simulation at
    /// the reference run's last state.
    fn estimate_global_error(&mut self, capture: &Capture, t_reached: f64, cancel: &AtomicBool) -> Option<GlobalError> {
        let sel = Sel::new(&MEASURED);
        let width = self.engine.columns(sel).len();
        let times: Vec<f64> = capture.data.chunks_exact(width).map(|r| r[0]).collect();
        let plan = self.plan.reference(t_reached, times);
        let mut compare = Compare { captured: &capture.data, width, next: 0, groups: Vec::new(), max: 0.0, last: f64::NAN };
        compare.columns(&self.engine.columns(sel)).ok()?;
        let mut no_progress = |_: &Progress| {};
        let mut ctx = Ctx {
            sink: &mut compare,
            cancel,
            progress: &mut no_progress,
            summary: RunSummary::new(self.method_name(), self.plan.t0),
            last_progress: Instant::now(),
            mm_idx: Vec::new(),
            capture: None,
        };
        let ran = self.engine.run(&plan, &mut ctx);
        let (finished, rhs_evals) = (ctx.summary.stop == SceneStop::Finished, ctx.summary.rhs_evals);
        drop(ctx);
        (ran.is_ok() && finished).then_some(GlobalError { max: compare.max, last: compare.last, rhs_evals })
    }

    /// Advances the current state by one step of size `h` with the scene's
    /// method (stepping API; [`Self::run`] always starts again from the
    /// initial state).
    pub fn step(&mut self, h: f64) -> Result<(), SolveError> {
        self.start_stepping();
        let out = self.engine.step(&self.plan.method, h, self.plan.settings.projection);
        self.note_stepping();
        out
    }

    /// `n` steps of size `h` (the span `n·h` split exactly by the driver);
    /// stops at the first failure, the steps before it done.
    pub fn advance(&mut self, h: f64, n: usize) -> Result<(), SolveError> {
        self.advance_cancellable(h, n, &AtomicBool::new(false)).map(|_| ())
    }

    /// [`Self::advance`], stopping cleanly within a few hundred steps after
    /// `cancel` is raised ([`StopReason::Cancelled`], the state reached kept).
    pub fn advance_cancellable(&mut self, h: f64, n: usize, cancel: &AtomicBool) -> Result<StopReason, SolveError> {
        self.start_stepping();
        let out = self.engine.advance(&self.plan.method, h, n, self.plan.settings.projection, cancel);
        self.note_stepping();
        out
    }

    /// Starts the stepping record with the current state, unless it runs:
    /// a call starts where the previous one ended, already noted.
    fn start_stepping(&mut self) {
        if self.stepping.is_none() {
            self.note_stepping();
        }
    }

    /// Notes the current state in the stepping record (the first note
    /// starts it) and judges the record.
    fn note_stepping(&mut self) {
        let (energy, defect, t) = (self.engine.energy(), self.engine.defect(), self.engine.t());
        let s = self.stepping.get_or_insert_with(|| RunSummary::new(self.plan.method.display(), t));
        s.note(energy, defect);
        s.t_reached = t;
        s.judge(self.plan.quality);
    }

    /// What the stepping API ([`Self::step`], [`Self::advance`]) has seen
    /// since the simulation was built or [`reset`](Self::reset): the
    /// energy drift and largest defect over the states at the start and end
    /// of every call (not at every step inside an `advance`), and the
    /// quality check of those against the scene's `[quality]` limits
    /// ([`RunSummary::warnings`]). `None` before the first call.
    pub fn stepping_summary(&self) -> Option<&RunSummary> {
        self.stepping.as_ref()
    }

    /// Current time of the stepping API.
    pub fn t(&self) -> f64 {
        self.engine.t()
    }

    /// The current state as one record (values in the order of [`Self::columns`]).
    pub fn row(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.columns.len());
        self.engine.row(self.plan.sel, &mut out);
        out
    }

    /// The value of column `name` in the current state.
    pub fn value(&self, name: &str) -> Option<f64> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.row()[j])
    }

    /// Energy of the current state.
    pub fn energy(&self) -> f64 {
        self.engine.energy()
    }

    /// Constraint defect of the current state.
    pub fn defect(&self) -> f64 {
        self.engine.defect()
    }

    /// Back to the initial state.
    pub fn reset(&mut self) {
        self.engine.reset();
        self.stepping = None;
    }

    /// Rebuilds the model and its initial state from `scene`, a scene that
    /// differs from the one this simulation was built from in numeric
    /// fields only ([`FieldPath`](super::FieldPath)s: the manifold, body and
    /// potential kinds, the method's name, the output's quantities and the
    /// events are the same). The columns and compiled events are kept; the
    /// plan (span, step size, tolerances, output times) is rebuilt only if
    /// `replan`, i.e. if a `method.*` or `time.*` field may differ. The
    /// simulation then runs exactly as `scene.build()` would (the same
    /// model, state and plan, so the same records bit for bit) without
    /// recomputing its columns and events: the per-member path of
    /// [`run_ensemble`](super::run_ensemble). On an error (the same as
    /// [`Scene::build`](super::Scene::build)'s) the simulation is unchanged.
    pub(crate) fn rebuild(&mut self, scene: &super::Scene, user: Option<super::UserFunctions>, replan: bool) -> Result<(), SceneError> {
        let plan = if replan { Some(scene.plan().map_err(|e| scene.locate(e))?) } else { None };
        let engine = scene.planned_engine(user, plan.as_ref().unwrap_or(&self.plan)).map_err(|e| scene.locate(e))?;
        if let Some(mut plan) = plan {
            plan.events = std::mem::take(&mut self.plan.events);
            self.plan = plan;
        }
        self.engine = engine;
        self.stepping = None;
        Ok(())
    }

    /// The time span `(t₀, t_end)`.
    pub fn span(&self) -> (f64, f64) {
        (self.plan.t0, self.plan.t_end)
    }
}
