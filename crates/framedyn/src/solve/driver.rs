//! The one stepping loop of framedyn.
//!
//! [`drive`] advances a state from `t₀` towards `t_end` with a [`Method`]:
//! fixed steps on an exact grid or error-controlled steps
//! ([`StepSize`]), sampling ([`Save`]), event location ([`EventSet`]),
//! cancellation and progress ([`Control`]), and typed failures that keep
//! the last good state. It stores nothing: every saved state, accepted step
//! and located event goes to a [`Sink`] as it happens, so a run of any length
//! uses constant memory. [`solve`](super::solve) is `drive` with a sink that
//! collects a [`Solution`](super::Solution); the scene engine
//! ([`scenes`](crate::scenes)) is `drive` with a sink that writes records;
//! the Python module and the CLI run scenes. There is no other loop.
//!
//! # Within a step
//!
//! States between the ends of an accepted step — at sample times of
//! [`Save::At`] and at event crossings — come from the method's own
//! continuous extension: the step's dense output when the run computes one
//! (adaptive runs that sample or locate events; any run with
//! [`Options::dense`](super::Options::dense)), else a sub-step of the method
//! from the start of the step, which has the method's full order. The grid
//! of a run does not depend on what it samples.
//!
//! # Events
//!
//! After each accepted step every event function `g` is evaluated at the new
//! state and its sign compared with the last non-zero sign seen. A change is
//! a crossing, located by Brent's method on the continuous extension; an
//! exact zero at the end of a step is a crossing at that time (and is not
//! reported again from the next step). A zero at `t₀` is not a crossing; the
//! first non-zero sign after it is taken as the reference. Two sign changes
//! within one step cancel and are not seen (bound the step to resolve
//! closely spaced zeros). Crossings of a step are reported in time order; a
//! terminal one stops the run at its time and state.
//!
//! # What a stop leaves
//!
//! The state reached (`t_end`, a terminal event, the last good state before a
//! failure, or the state when the run was cancelled) is always given to the
//! sink, unless it was just saved at that time or the run sampled
//! [`Save::At`] and finished: then only the requested times are saved.

use std::sync::atomic::{AtomicBool, Ordering};

use super::event::{brent_dyn, Direction, Event, EventRecord};
use super::projection::{project_energy, Projection};
use super::{adaptive, fault_error, Adaptive, DenseSegment, Save, SolveError, Stats, StepSize, StopReason};
use crate::dynamics::System;
use crate::lie::{AlgebraVector, LieGroup};
use crate::method::{Alg, GroupNumerics, Method, MethodError, MethodInfo, NonFiniteSource, StepFault, StepOutput, StepRequest};

/// Accepted steps between two polls of [`Control`] (cancel flag, progress).
pub const POLL_EVERY: usize = 256;

/// The step-size, sampling and event settings of a run (the part of
/// [`Options`](super::Options) the loop reads).
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Fixed or adaptive steps.
    pub step: StepSize,
    /// Which states are saved.
    pub save: Save,
    /// Compute the dense output of every step and give it to
    /// [`Sink::step`].
    pub dense: bool,
    /// Limit on the number of accepted steps.
    pub max_steps: usize,
    /// Absolute time tolerance of event location (0: round-off).
    pub event_xtol: f64,
    /// What each accepted step is projected back onto (default none; see
    /// [`projection`](super::projection)).
    pub projection: Projection,
}

/// Where a run's results go, as they happen.
pub trait Sink<G: LieGroup> {
    /// What a sink can fail with (`std::convert::Infallible` for one that
    /// cannot).
    type Error;
    /// A saved state.
    fn save(&mut self, t: f64, y: &G) -> Result<(), Self::Error>;
    /// An accepted step, after its saved states and events (its dense
    /// output when [`Settings::dense`] is set).
    fn step(&mut self, segment: &StepSegment<'_, G>) -> Result<(), Self::Error> {
        let _ = segment;
        Ok(())
    }
    /// A located event crossing.
    fn event(&mut self, record: &EventRecord<G>) -> Result<(), Self::Error> {
        let _ = record;
        Ok(())
    }
}

/// An accepted step, as given to [`Sink::step`].
#[derive(Debug, Clone, Copy)]
pub struct StepSegment<'a, G: LieGroup> {
    /// Start of the step.
    pub t0: f64,
    /// End of the step (before any terminal event inside it).
    pub t1: f64,
    /// The step size the method took: `t1 − t0` up to round-off, exactly
    /// the `h` of [`Method::step`] (so that the step can be repeated, e.g.
    /// from perturbed states).
    pub h: f64,
    /// The state at `t0`.
    pub y0: &'a G,
    /// The state at `t1`.
    pub y1: &'a G,
    /// The dense output of the step, if computed.
    pub dense: Option<&'a DenseSegment<G>>,
}

/// The event functions of a run, in the form the loop evaluates them: all
/// at once at the end of a step, one at a time while a crossing is located.
///
/// Implemented by a slice of [`Event`]s on the states (`&[Event<G>]`); the
/// scene engine implements it for [`Event`]s on the records it writes
/// (`Event<[f64]>`): one event type, one location routine.
pub trait EventSet<G: ?Sized> {
    /// Number of events.
    fn count(&self) -> usize;
    /// Which crossings of event `k` are reported.
    fn direction(&self, k: usize) -> Direction;
    /// Whether event `k` stops the run.
    fn terminal(&self, k: usize) -> bool;
    /// `g_k(t, y)` for every `k`, into `out` (of length [`Self::count`]).
    fn values(&mut self, t: f64, y: &G, out: &mut [f64]);
    /// `g_k(t, y)`.
    fn value(&mut self, k: usize, t: f64, y: &G) -> f64;
}

impl<G: ?Sized> EventSet<G> for &[Event<G>] {
    fn count(&self) -> usize {
        self.len()
    }
    fn direction(&self, k: usize) -> Direction {
        self[k].direction
    }
    fn terminal(&self, k: usize) -> bool {
        self[k].terminal
    }
    fn values(&mut self, t: f64, y: &G, out: &mut [f64]) {
        for (o, e) in out.iter_mut().zip(self.iter()) {
            *o = e.value(t, y);
        }
    }
    fn value(&mut self, k: usize, t: f64, y: &G) -> f64 {
        self[k].value(t, y)
    }
}

/// Cancellation and progress: polled every [`POLL_EVERY`] accepted steps.
#[derive(Default)]
pub struct Control<'a> {
    /// When raised, the run stops with [`StopReason::Cancelled`] at the next
    /// poll, keeping everything computed so far.
    pub cancel: Option<&'a AtomicBool>,
    /// Called at each poll with the time reached and the statistics so far
    /// (and once more when the run stops).
    pub progress: Option<&'a mut dyn FnMut(f64, &Stats)>,
}

impl std::fmt::Debug for Control<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Control").field("cancel", &self.cancel).field("progress", &self.progress.is_some()).finish()
    }
}

/// Why [`drive`] stopped early: an integration failure, or the sink's own
/// error (e.g. a full disk).
#[derive(Debug, Clone, PartialEq)]
pub enum DriveError<E> {
    /// The integration failed.
    Solve(SolveError),
    /// The sink failed.
    Sink(E),
}

impl<E> From<SolveError> for DriveError<E> {
    fn from(e: SolveError) -> Self {
        DriveError::Solve(e)
    }
}

/// What [`drive`] leaves: why it stopped, where, and the work done.
#[derive(Debug, Clone)]
pub struct Outcome<G, E> {
    /// Why the run stopped (an error keeps `t`, `y` at the last good state).
    pub stop: Result<StopReason, DriveError<E>>,
    /// The time reached.
    pub t: f64,
    /// The state reached.
    pub y: G,
    /// Work statistics.
    pub stats: Stats,
}

/// The number of fixed steps of size at most `h` over `[t0, t_end]`:
/// `|t_end − t₀|/h` when that is an integer to 1e-9 relative (so that
/// `h = span/n` given in decimal gives exactly `n` steps), else its ceiling.
/// Fails for `h` not finite and > 0, or more than 9e15 steps.
pub fn fixed_step_count(t0: f64, t_end: f64, h: f64) -> Result<usize, SolveError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "finite and > 0" });
    }
    let ratio = (t_end - t0).abs() / h;
    let near = ratio.round();
    let n = if near >= 1.0 && (ratio - near).abs() <= 1e-9 * near { near } else { ratio.ceil().max(1.0) };
    if n > 9.0e15 {
        return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "at least |t_end − t0|/9e15" });
    }
    Ok(n as usize)
}

/// Checks the settings against the method and the span: a positive step,
/// tolerances and controller ([`Adaptive`]), sample times within the span,
/// `max_steps ≥ 1`, a finite event tolerance.
pub fn validate<G: LieGroup>(settings: &Settings, info: &MethodInfo, t0: f64, t_end: f64) -> Result<(), SolveError> {
    validate_len(settings, info, t0, t_end, <G::Algebra as AlgebraVector>::LEN)
}

/// [`validate`] for a state algebra of `len` components (not generic, so
/// compiled once).
fn validate_len(settings: &Settings, info: &MethodInfo, t0: f64, t_end: f64, len: usize) -> Result<(), SolveError> {
    if settings.max_steps == 0 {
        return Err(SolveError::InvalidOptions { reason: "max_steps must be ≥ 1".into() });
    }
    if !(settings.event_xtol >= 0.0 && settings.event_xtol.is_finite()) {
        return Err(SolveError::InvalidParameter { field: "event_tolerance", value: settings.event_xtol, allowed: "finite and ≥ 0" });
    }
    match &settings.save {
        Save::At(times) => {
            let (lo, hi) = (t0.min(t_end), t0.max(t_end));
            for &ts in times {
                if !(ts >= lo && ts <= hi) {
                    return Err(SolveError::InvalidParameter { field: "save time", value: ts, allowed: "within the time span [t0, t_end]" });
                }
            }
        }
        Save::Every(0) => return Err(SolveError::InvalidOptions { reason: "Save::Every(k) needs k ≥ 1".into() }),
        _ => {}
    }
    match &settings.step {
        StepSize::Fixed(h) => fixed_step_count(t0, t_end, *h).map(|_| ()),
        StepSize::Adaptive(a) => adaptive::validate(a, info, len),
    }
}

/// Runs `method` on `system` from `(t0, y0)` to `t_end` with `settings`,
/// giving results to `sink` (see the [module docs](self)).
///
/// Validates the settings ([`validate`]), the span and the initial state,
/// and asks the method whether it can integrate the system
/// ([`Method::check`]) before the first step; then steps until `t_end`, a
/// terminal event, a failure, or cancellation.
#[allow(clippy::too_many_arguments)]
pub fn drive<S, M, K, Ev>(
    system: &S,
    method: &M,
    t0: f64,
    y0: &S::State,
    t_end: f64,
    settings: &Settings,
    events: &mut Ev,
    sink: &mut K,
    control: &mut Control<'_>,
) -> Outcome<S::State, K::Error>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
    K: Sink<S::State>,
    Ev: EventSet<S::State> + ?Sized,
{
    drive_with(system, erase(method), t0, y0, t_end, settings, events, sink, control)
}

/// A [`Method`] as the loop calls it. `Method` cannot be a trait object (it
/// is `Clone`); this can, so that builds with debug assertions compile the
/// loop once per system rather than once per system and method
/// ([`erase`]).
pub(crate) trait StepMethod<S: System> {
    /// [`Method::info`].
    fn info(&self) -> MethodInfo;
    /// [`Method::check`].
    fn check(&self, system: &S) -> Result<(), MethodError>;
    /// [`Method::step`].
    fn step(&self, system: &S, t: f64, y0: &S::State, h: f64, request: StepRequest<Alg<S>>) -> Result<StepOutput<S::State>, StepFault>;
}

impl<S: System, M: Method<S>> StepMethod<S> for M {
    #[inline]
    fn info(&self) -> MethodInfo {
        Method::info(self)
    }
    #[inline]
    fn check(&self, system: &S) -> Result<(), MethodError> {
        Method::check(self, system)
    }
    #[inline]
    fn step(&self, system: &S, t: f64, y0: &S::State, h: f64, request: StepRequest<Alg<S>>) -> Result<StepOutput<S::State>, StepFault> {
        Method::step(self, system, t, y0, h, request)
    }
}

/// The method as the loop takes it. With debug assertions (the dev and test
/// profiles) a trait object: the loop's functions are then compiled once
/// per system, which keeps the test build small (docs/development.md,
/// "What a fresh build is made of"); the loop makes one indirect call per
/// step, to a function that does a whole step.
#[cfg(debug_assertions)]
#[inline]
pub(crate) fn erase<S: System, M: Method<S>>(method: &M) -> &dyn StepMethod<S> {
    method
}

/// The method as the loop takes it. In optimised builds the method itself,
/// so that its step is inlined into the loop and specialised on the loop's
/// request (docs/development.md, "Profiles").
#[cfg(not(debug_assertions))]
#[inline]
pub(crate) fn erase<S: System, M: Method<S>>(method: &M) -> &M {
    method
}

/// [`drive`] with a method given as [`erase`] leaves it. The event set and
/// the sink reach the loop as trait objects (the sink's error kept aside by
/// [`Stash`]), in every profile: [`Run`] then has one instance per system
/// and method, not one per system, method, sink and event set (the scene
/// engine runs each model with two sinks: its records, and none when it
/// only steps). The price is a few indirect calls per step, small next to
/// a step (docs/development.md, "Profiles").
#[allow(clippy::too_many_arguments)]
pub(crate) fn drive_with<S, M, K, Ev>(
    system: &S,
    method: &M,
    t0: f64,
    y0: &S::State,
    t_end: f64,
    settings: &Settings,
    events: &mut Ev,
    sink: &mut K,
    control: &mut Control<'_>,
) -> Outcome<S::State, K::Error>
where
    S: System,
    S::State: GroupNumerics,
    M: StepMethod<S> + ?Sized,
    K: Sink<S::State> + ?Sized,
    Ev: EventSet<S::State> + ?Sized,
{
    let mut events = Forward(events);
    let mut stash = Stash { sink, error: None };
    let out = run(system, method, t0, y0, t_end, settings, &mut events as &mut dyn EventSet<S::State>, &mut stash as &mut dyn Sink<S::State, Error = Stashed>, control);
    let stop = match out.stop {
        Ok(reason) => Ok(reason),
        Err(DriveError::Solve(e)) => Err(DriveError::Solve(e)),
        Err(DriveError::Sink(Stashed)) => match stash.error.take() {
            Some(e) => Err(DriveError::Sink(e)),
            None => Err(DriveError::Solve(SolveError::InvalidOptions { reason: "internal: a sink failure without its error".into() })),
        },
    };
    Outcome { stop, t: out.t, y: out.y, stats: out.stats }
}

#[allow(clippy::too_many_arguments)]
fn run<S, M, K, Ev>(
    system: &S,
    method: &M,
    t0: f64,
    y0: &S::State,
    t_end: f64,
    settings: &Settings,
    events: &mut Ev,
    sink: &mut K,
    control: &mut Control<'_>,
) -> Outcome<S::State, K::Error>
where
    S: System,
    S::State: GroupNumerics,
    M: StepMethod<S> + ?Sized,
    K: Sink<S::State> + ?Sized,
    Ev: EventSet<S::State> + ?Sized,
{
    let info = method.info();
    let mut run = Run {
        sys: system,
        method,
        info,
        set: settings,
        t0,
        t_end,
        dir: if t_end >= t0 { 1.0 } else { -1.0 },
        t: t0,
        y: *y0,
        stats: Stats::default(),
        events,
        ev: Vec::new(),
        gbuf: Vec::new(),
        sink,
        control,
        at: Vec::new(),
        at_idx: 0,
        last_saved: None,
        since_poll: 0,
        e_ref: None,
    };
    let stop = run.go();
    let stop = run.finish(stop);
    Outcome { stop, t: run.t, y: run.y, stats: run.stats }
}

/// The event set of a run, behind a reference that can become a trait object.
struct Forward<'a, Ev: ?Sized>(&'a mut Ev);

impl<G: ?Sized, Ev: EventSet<G> + ?Sized> EventSet<G> for Forward<'_, Ev> {
    fn count(&self) -> usize {
        self.0.count()
    }
    fn direction(&self, k: usize) -> Direction {
        self.0.direction(k)
    }
    fn terminal(&self, k: usize) -> bool {
        self.0.terminal(k)
    }
    fn values(&mut self, t: f64, y: &G, out: &mut [f64]) {
        self.0.values(t, y, out)
    }
    fn value(&mut self, k: usize, t: f64, y: &G) -> f64 {
        self.0.value(k, t, y)
    }
}

/// The marker a [`Stash`] returns in place of its sink's error.
struct Stashed;

/// A sink that keeps its inner sink's error aside and returns [`Stashed`],
/// so that sinks of every error type share one trait object type.
struct Stash<'a, K: ?Sized + Sink<G>, G: LieGroup> {
    sink: &'a mut K,
    error: Option<K::Error>,
}

impl<G: LieGroup, K: ?Sized + Sink<G>> Stash<'_, K, G> {
    fn keep(&mut self, r: Result<(), K::Error>) -> Result<(), Stashed> {
        r.map_err(|e| {
            self.error = Some(e);
            Stashed
        })
    }
}

impl<G: LieGroup, K: ?Sized + Sink<G>> Sink<G> for Stash<'_, K, G> {
    type Error = Stashed;
    fn save(&mut self, t: f64, y: &G) -> Result<(), Stashed> {
        let r = self.sink.save(t, y);
        self.keep(r)
    }
    fn step(&mut self, segment: &StepSegment<'_, G>) -> Result<(), Stashed> {
        let r = self.sink.step(segment);
        self.keep(r)
    }
    fn event(&mut self, record: &EventRecord<G>) -> Result<(), Stashed> {
        let r = self.sink.event(record);
        self.keep(r)
    }
}

/// Per-event state: the last value and the last non-zero sign (0 before the
/// first non-zero value).
#[derive(Debug, Clone, Copy)]
struct EventState {
    g: f64,
    sign: f64,
}

fn sign_of(v: f64) -> f64 {
    if v == 0.0 {
        0.0
    } else {
        v.signum()
    }
}

struct Run<'a, 'c, S: System, M: ?Sized, Ev: ?Sized, K: ?Sized> {
    sys: &'a S,
    method: &'a M,
    info: MethodInfo,
    set: &'a Settings,
    t0: f64,
    t_end: f64,
    dir: f64,
    t: f64,
    y: S::State,
    stats: Stats,
    events: &'a mut Ev,
    ev: Vec<EventState>,
    gbuf: Vec<f64>,
    sink: &'a mut K,
    control: &'a mut Control<'c>,
    at: Vec<f64>,
    at_idx: usize,
    last_saved: Option<f64>,
    since_poll: usize,
    /// The energy every accepted step is projected back onto
    /// ([`Projection::Energy`], [`Projection::Level`]).
    e_ref: Option<f64>,
}

/// A located crossing: time, event index, direction, state.
type Hit<G> = (f64, usize, bool, G);

impl<S, M, Ev, K> Run<'_, '_, S, M, Ev, K>
where
    S: System,
    S::State: GroupNumerics,
    M: StepMethod<S> + ?Sized,
    K: Sink<S::State> + ?Sized,
    Ev: EventSet<S::State> + ?Sized,
{
    fn go(&mut self) -> Result<StopReason, DriveError<K::Error>> {
        if !self.t0.is_finite() {
            return Err(SolveError::InvalidParameter { field: "t0", value: self.t0, allowed: "finite" }.into());
        }
        if !self.t_end.is_finite() || self.t_end == self.t0 {
            return Err(SolveError::InvalidParameter { field: "t_end", value: self.t_end, allowed: "finite and ≠ t0" }.into());
        }
        super::problem::check_state(&self.y)?;
        validate::<S::State>(self.set, &self.info, self.t0, self.t_end)?;
        self.method.check(self.sys).map_err(SolveError::from)?;
        self.e_ref = self.set.projection.level(|| self.sys.energy(&self.y));
        if let Some(e0) = self.e_ref.filter(|e| !e.is_finite()) {
            return Err(SolveError::InvalidOptions {
                reason: format!("projection = \"energy\" needs a finite energy level; it is {e0} (the energy at t0, or the level given)"),
            }
            .into());
        }
        if let Save::At(times) = &self.set.save {
            let mut at = times.clone();
            at.sort_by(f64::total_cmp);
            if self.dir < 0.0 {
                at.reverse();
            }
            self.at = at;
        }
        let n_ev = self.events.count();
        if n_ev > 0 {
            self.gbuf = vec![0.0; n_ev];
            self.events.values(self.t0, &self.y, &mut self.gbuf);
            self.stats.event_evals += n_ev;
            if self.gbuf.iter().any(|g| !g.is_finite()) {
                return Err(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval: self.t0, t: self.t0, h: 0.0 }.into());
            }
            self.ev = self.gbuf.iter().map(|&g| EventState { g, sign: sign_of(g) }).collect();
        }
        match &self.set.save {
            Save::Steps | Save::Every(_) | Save::Ends => self.save_state(self.t0, self.y)?,
            Save::At(_) => {}
        }
        while self.at_idx < self.at.len() && self.at[self.at_idx] == self.t0 {
            self.save_state(self.t0, self.y)?;
            self.at_idx += 1;
        }
        match &self.set.step {
            StepSize::Fixed(h) => self.run_fixed(*h),
            StepSize::Adaptive(a) => self.run_adaptive(a),
        }
    }

    /// Gives the state reached to the sink (see the module docs) and calls
    /// the progress hook a last time.
    fn finish(&mut self, stop: Result<StopReason, DriveError<K::Error>>) -> Result<StopReason, DriveError<K::Error>> {
        let keep = match &stop {
            Ok(StopReason::Finished) => !matches!(self.set.save, Save::At(_)),
            Ok(_) => true,
            Err(DriveError::Solve(_)) => true,
            Err(DriveError::Sink(_)) => false,
        };
        let mut stop = stop;
        if keep && self.last_saved != Some(self.t) {
            if let Err(e) = self.sink.save(self.t, &self.y) {
                stop = Err(DriveError::Sink(e));
            } else {
                self.last_saved = Some(self.t);
            }
        }
        if let Some(p) = self.control.progress.as_mut() {
            p(self.t, &self.stats);
        }
        stop
    }

    fn save_state(&mut self, t: f64, y: S::State) -> Result<(), DriveError<K::Error>> {
        if self.last_saved == Some(t) {
            return Ok(());
        }
        self.sink.save(t, &y).map_err(DriveError::Sink)?;
        self.last_saved = Some(t);
        Ok(())
    }

    /// Polls the control every [`POLL_EVERY`] accepted steps; true if the
    /// run is to stop.
    fn poll(&mut self) -> bool {
        self.since_poll += 1;
        if self.since_poll < POLL_EVERY {
            return false;
        }
        self.since_poll = 0;
        if let Some(p) = self.control.progress.as_mut() {
            p(self.t, &self.stats);
        }
        self.control.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    fn run_fixed(&mut self, h_req: f64) -> Result<StopReason, DriveError<K::Error>> {
        let n = fixed_step_count(self.t0, self.t_end, h_req)?;
        let span = self.t_end - self.t0;
        let dense = self.set.dense;
        let mut f_cache: Option<Alg<S>> = None;
        for i in 0..n {
            let t = self.t;
            let t1 = if i + 1 == n { self.t_end } else { self.t0 + span * ((i + 1) as f64 / n as f64) };
            let h = t1 - t;
            if self.stats.accepted >= self.set.max_steps {
                return Err(SolveError::MaxSteps { t, h, max_steps: self.set.max_steps }.into());
            }
            let req = StepRequest { f_start: f_cache.take(), error: false, dense, f_end: dense };
            let out = self.method.step(self.sys, t, &self.y, h, req).map_err(|f| fault_error(f, t, h))?;
            self.stats.add_cost(&out.cost);
            let out = self.projected(out);
            f_cache = out.f_end;
            if let Some(index) = self.accept(t1, h, &out)? {
                return Ok(StopReason::Event { index });
            }
            if self.poll() {
                return Ok(StopReason::Cancelled);
            }
        }
        Ok(StopReason::Finished)
    }

    fn run_adaptive(&mut self, a: &Adaptive) -> Result<StopReason, DriveError<K::Error>> {
        let info = self.info;
        let q = info.order.min(info.embedded_order.unwrap_or(info.order));
        let expo = 1.0 / (q as f64 + 1.0);
        let ctl = a.controller;
        let alpha = expo - 0.75 * ctl.beta;
        let atol = super::tol_vector::<Alg<S>>(&a.atol);
        let rtol = super::tol_vector::<Alg<S>>(&a.rtol);
        let dir = self.dir;
        let span = (self.t_end - self.t0).abs();
        let h_max = a.h_max.min(span);
        let need_dense = self.set.dense || matches!(self.set.save, Save::At(_)) || self.events.count() > 0;

        let f0 = self.sys.vector_field(self.t0, &self.y);
        self.stats.rhs_evals += 1;
        if !f0.is_finite() {
            return Err(SolveError::NonFinite { what: NonFiniteSource::VectorField, t_eval: self.t0, t: self.t0, h: 0.0 }.into());
        }
        let mut h = match a.h0 {
            Some(h0) => h0.min(h_max),
            None => {
                let floor = adaptive::min_step(a.h_min, self.t0, self.t_end);
                adaptive::initial_step(self.sys, &self.info, self.t0, &self.y, dir, &f0, &atol, &rtol, h_max, floor, q, &mut self.stats)?
            }
        } * dir;
        let mut f_cache = Some(f0);
        let mut err_prev: f64 = 1e-4;
        let mut rejected_last = false;
        // The automatic first step is a probe (see `adaptive::FIRST_STEP_PROBES`);
        // a first step the user chose is taken as given.
        let mut probes = if a.h0.is_none() { adaptive::FIRST_STEP_PROBES } else { 0 };
        // Aimed at the error the controller settles at on a smooth problem,
        // `safety^{1/(α−β)}` (DOP853 0.15, DOPRI5 0.44 with the default PI).
        let probe_aim = if alpha > ctl.beta { ctl.safety.powf(1.0 / (alpha - ctl.beta)) } else { adaptive::FIRST_STEP_PROBE_BELOW };
        loop {
            let t = self.t;
            let remaining = self.t_end - t;
            if remaining * dir <= 0.0 {
                return Ok(StopReason::Finished);
            }
            if self.stats.accepted >= self.set.max_steps {
                return Err(SolveError::MaxSteps { t, h, max_steps: self.set.max_steps }.into());
            }
            let h_min = adaptive::min_step(a.h_min, t, self.t_end);
            let mut t1 = t + h;
            if (t1 - self.t_end) * dir >= 0.0 {
                h = remaining;
                t1 = self.t_end;
            } else if h.abs() < h_min {
                return Err(SolveError::StepSizeTooSmall { t, h, h_min }.into());
            }
            // f(t₁, y₁) is free for FSAL methods; otherwise it is left to the
            // next step's first stage, so a rejected step does not pay for it.
            let req = StepRequest { f_start: f_cache, error: true, dense: need_dense, f_end: info.fsal };
            let out = match self.method.step(self.sys, t, &self.y, h, req) {
                Ok(out) => out,
                Err(StepFault::DexpRadius { radius, limit, cost }) => {
                    // Too large for dexp⁻¹: a rejection, not a failure.
                    self.stats.add_cost(&cost);
                    self.stats.rejected += 1;
                    self.stats.rejected_radius += 1;
                    h *= (ctl.safety * limit / radius).clamp(ctl.fac_min, ctl.safety);
                    rejected_last = true;
                    continue;
                }
                Err(fault) => return Err(fault_error(fault, t, h).into()),
            };
            self.stats.add_cost(&out.cost);
            let Some(e) = out.error else {
                return Err(SolveError::InvalidOptions { reason: format!("{} returned no error estimate", info.name) }.into());
            };
            let err = adaptive::error_norm(&e, &self.y.tolerance_scale(), &out.y.tolerance_scale(), &atol, &rtol);
            if err.is_nan() {
                return Err(SolveError::NonFinite { what: NonFiniteSource::Increment, t_eval: t1, t, h }.into());
            }
            if probes > 0 && self.stats.accepted == 0 && t1 != self.t_end && h.abs() < h_max {
                // What the controller's own next step would reach if the error
                // grew like h^{q+1}: a ramp still far below the target is
                // replaced by a probe (`adaptive::FIRST_STEP_PROBE_BELOW`).
                probes -= 1;
                let ramp = err * (ctl.safety * err.powf(-alpha) * err_prev.powf(ctl.beta)).clamp(ctl.fac_min, ctl.fac_max).powf(1.0 / expo);
                let grow = (probe_aim / err).powf(expo).clamp(1.0, ctl.fac_max);
                if ramp < adaptive::FIRST_STEP_PROBE_BELOW && grow > 1.0 {
                    self.stats.first_step_probes += 1;
                    f_cache = Some(out.f_start);
                    h = (h * grow).clamp(-h_max, h_max);
                    continue;
                }
                probes = 0;
            }
            if err <= 1.0 {
                let mut fac = (ctl.safety * err.powf(-alpha) * err_prev.powf(ctl.beta)).clamp(ctl.fac_min, ctl.fac_max);
                if rejected_last {
                    fac = fac.min(1.0);
                }
                if fac.is_nan() {
                    fac = ctl.fac_max;
                }
                err_prev = err.max(1e-4);
                rejected_last = false;
                let out = self.projected(out);
                f_cache = out.f_end;
                if let Some(index) = self.accept(t1, h, &out)? {
                    return Ok(StopReason::Event { index });
                }
                if self.poll() {
                    return Ok(StopReason::Cancelled);
                }
                h = (h * fac).clamp(-h_max, h_max);
            } else {
                self.stats.rejected += 1;
                f_cache = Some(out.f_start);
                h *= (ctl.safety * err.powf(-alpha)).max(ctl.fac_min);
                rejected_last = true;
            }
        }
    }

    /// The accepted step's output with its end projected
    /// ([`Settings::projection`]); `f(t₁, y₁)` of an FSAL method is then
    /// dropped, since it belongs to the unprojected end.
    fn projected(&mut self, mut out: StepOutput<S::State>) -> StepOutput<S::State> {
        if let Some(e0) = self.e_ref {
            out.y = project_energy(self.sys, &out.y, e0, &mut self.stats);
            out.f_end = None;
        }
        out
    }

    /// The state at `tau` inside the step from `(t, y0)`: the dense output
    /// if there is one, else a sub-step of the method.
    fn interpolate(&mut self, tau: f64, t: f64, y0: &S::State, seg: Option<&DenseSegment<S::State>>) -> Result<S::State, SolveError> {
        interpolate(self.sys, self.method, &mut self.stats, tau, t, y0, seg)
    }

    /// Processes an accepted step from `(self.t, self.y)` to `t1`: events,
    /// samples, the sink; returns the index of a terminal event.
    fn accept(&mut self, t1: f64, h: f64, out: &StepOutput<S::State>) -> Result<Option<usize>, DriveError<K::Error>> {
        let (t, y0) = (self.t, self.y);
        let seg = out.dense.map(|poly| DenseSegment { t0: t, h, y0, poly });
        self.stats.accept(h);

        let stop = if self.ev.is_empty() { None } else { self.events_on_step(t, t1, h, &out.y, seg.as_ref())? };
        let (t_stop, y_stop) = match &stop {
            Some((te, _, ye)) => (*te, *ye),
            None => (t1, out.y),
        };
        while self.at_idx < self.at.len() && (self.at[self.at_idx] - t_stop) * self.dir <= 0.0 {
            let ts = self.at[self.at_idx];
            let ys = if ts == t_stop { y_stop } else { self.interpolate(ts, t, &y0, seg.as_ref())? };
            self.save_state(ts, ys)?;
            self.at_idx += 1;
        }
        let every = match self.set.save {
            Save::Steps => Some(1),
            Save::Every(k) => Some(k),
            _ => None,
        };
        if let (Some(k), None) = (every, &stop) {
            if (self.stats.accepted as u64) % k == 0 {
                self.save_state(t1, out.y)?;
            }
        }
        self.sink.step(&StepSegment { t0: t, t1, h, y0: &y0, y1: &out.y, dense: seg.as_ref() }).map_err(DriveError::Sink)?;
        self.t = t_stop;
        self.y = y_stop;
        Ok(stop.map(|s| s.1))
    }

    /// Finds the crossings in the step `t → t1` (ending at `y1`), gives them
    /// to the sink in time order, and returns the first terminal one (time,
    /// index, state).
    fn events_on_step(
        &mut self,
        t: f64,
        t1: f64,
        h: f64,
        y1: &S::State,
        seg: Option<&DenseSegment<S::State>>,
    ) -> Result<Option<(f64, usize, S::State)>, DriveError<K::Error>> {
        let y0 = self.y;
        let nonfinite = |t_eval: f64| SolveError::NonFinite { what: NonFiniteSource::Event, t_eval, t, h };
        let n_ev = self.ev.len();
        self.events.values(t1, y1, &mut self.gbuf);
        self.stats.event_evals += n_ev;
        // No allocation unless an event fires.
        let mut hits: Vec<Hit<S::State>> = Vec::new();
        for k in 0..n_ev {
            let g = self.gbuf[k];
            if !g.is_finite() {
                return Err(nonfinite(t1).into());
            }
            let EventState { g: g0, sign: s0 } = self.ev[k];
            let s1 = sign_of(g);
            self.ev[k].g = g;
            if s0 == 0.0 {
                self.ev[k].sign = s1;
                continue;
            }
            if s1 == s0 {
                continue;
            }
            // A sign change, or a zero at the end of the step.
            self.ev[k].sign = if s1 == 0.0 { -s0 } else { s1 };
            let rising = s0 < 0.0;
            let wanted = match self.events.direction(k) {
                Direction::Either => true,
                Direction::Rising => rising,
                Direction::Falling => !rising,
            };
            if !wanted || g0 == 0.0 {
                // g0 = 0: this zero was reported at the end of the last step.
                continue;
            }
            let (tr, yr) = if s1 == 0.0 {
                (t1, *y1)
            } else {
                let (sys, method, xtol) = (self.sys, self.method, self.set.event_xtol);
                let events = &mut *self.events;
                let stats = &mut self.stats;
                let mut failure: Option<SolveError> = None;
                let (tr, evals) = brent_dyn(
                    &mut |tau| match interpolate(sys, method, stats, tau, t, &y0, seg) {
                        Ok(y) => {
                            let v = events.value(k, tau, &y);
                            if !v.is_finite() && failure.is_none() {
                                failure = Some(nonfinite(tau));
                            }
                            v
                        }
                        Err(e) => {
                            failure.get_or_insert(e);
                            f64::NAN
                        }
                    },
                    t,
                    t1,
                    g0,
                    g,
                    xtol,
                );
                self.stats.event_evals += evals;
                if let Some(e) = failure {
                    return Err(e.into());
                }
                let yr = if tr == t1 { *y1 } else { self.interpolate(tr, t, &y0, seg)? };
                (tr, yr)
            };
            hits.push((tr, k, rising, yr));
        }
        if hits.is_empty() {
            return Ok(None);
        }
        for i in time_order(hits.iter().map(|hit| (hit.0 - t) * self.dir).collect()) {
            let (tr, k, rising, yr) = hits[i];
            let terminal = self.events.terminal(k);
            self.sink.event(&EventRecord { index: k, t: tr, y: yr, rising, terminal }).map_err(DriveError::Sink)?;
            if terminal {
                return Ok(Some((tr, k, yr)));
            }
        }
        Ok(None)
    }
}

/// The indices of `keys` in increasing order (ties in index order): the
/// order in which a step's crossings are reported, from their distances
/// along the direction of integration. Not generic, so that the sort is
/// compiled once rather than for every system × method the driver runs.
fn time_order(keys: Vec<f64>) -> Vec<usize> {
    let mut order: Vec<usize> = (0..keys.len()).collect();
    order.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
    order
}

/// The state at `tau` in the step from `(t, y0)`: `seg` evaluated, or a
/// sub-step of `method` of size `tau − t`.
fn interpolate<S, M>(
    sys: &S,
    method: &M,
    stats: &mut Stats,
    tau: f64,
    t: f64,
    y0: &S::State,
    seg: Option<&DenseSegment<S::State>>,
) -> Result<S::State, SolveError>
where
    S: System,
    S::State: GroupNumerics,
    M: StepMethod<S> + ?Sized,
{
    if tau == t {
        return Ok(*y0);
    }
    match seg {
        Some(seg) => {
            stats.dense_evals += 1;
            stats.exps += 1;
            Ok(seg.eval(tau))
        }
        None => {
            let out = method.step(sys, t, y0, tau - t, StepRequest::plain()).map_err(|f| fault_error(f, t, tau - t))?;
            stats.add_cost(&out.cost);
            stats.dense_evals += 1;
            Ok(out.y)
        }
    }
}
