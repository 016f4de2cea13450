//! The trajectory of an analysis: stepped by the solver's driver
//! ([`drive`]) with fixed or error-controlled steps, the analysis acting on
//! each accepted step (see the [module documentation](super)).

use std::sync::atomic::{AtomicBool, Ordering};

use super::AnalysisError;
use crate::dynamics::System;
use crate::method::{GroupNumerics, Method};
use crate::solve::{drive, fixed_step_count, Control, DriveError, Event, Projection, Save, Settings, Sink, StepSegment, StepSize, StopReason};

/// The most steps an analysis takes, and the default of its options'
/// `max_steps` (fixed steps are checked against `max_steps` before the run;
/// an error-controlled run that needs more stops with
/// [`SolveError::MaxSteps`](crate::solve::SolveError::MaxSteps)).
pub const MAX_STEPS: usize = 1_000_000_000;

/// An accepted step of the trajectory, as an analysis sees it.
pub(crate) struct Step<'a, G> {
    /// Start and end of the step.
    pub t0: f64,
    pub t1: f64,
    /// The step size the method took (repeat the step with it).
    pub h: f64,
    /// The states at `t0` and `t1`.
    pub y0: &'a G,
    pub y1: &'a G,
    /// The number of this step, from 1.
    pub index: usize,
    /// True for the step that ends the span.
    pub last: bool,
}

/// What an analysis asks for after a step.
pub(crate) enum Next {
    /// The next step.
    Go,
    /// Stop here: the analysis has its answer.
    Stop,
}

/// Where a walk ended.
pub(crate) struct Walked {
    /// The time reached.
    pub t: f64,
    /// Steps taken.
    pub steps: usize,
}

/// Checks the step settings, the `duration` and `max_steps` of an analysis:
/// a fixed step `h` (finite, > 0, at most `max_steps` steps) or
/// error-controlled steps (checked by the driver, like a run's);
/// `1 ≤ max_steps ≤` [`MAX_STEPS`]. Returns the number of fixed steps,
/// `None` for error-controlled ones.
pub(crate) fn plan(step: &StepSize, duration: f64, max_steps: usize) -> Result<Option<usize>, AnalysisError> {
    if !(duration.is_finite() && duration > 0.0) {
        return Err(AnalysisError::invalid("duration", duration, "finite and > 0"));
    }
    if !(1..=MAX_STEPS).contains(&max_steps) {
        return Err(AnalysisError::invalid("max_steps", max_steps, format!("between 1 and {MAX_STEPS:e}")));
    }
    match step {
        StepSize::Fixed(h) => {
            if !(h.is_finite() && *h > 0.0) {
                return Err(AnalysisError::invalid("h", h, "finite and > 0"));
            }
            let n = fixed_step_count(0.0, duration, *h)?;
            if n > max_steps {
                return Err(AnalysisError::invalid("h", h, format!("≥ duration/max_steps = {:e} (at most max_steps = {max_steps} steps)", duration / max_steps as f64)));
            }
            Ok(Some(n))
        }
        StepSize::Adaptive(_) => Ok(None),
    }
}

/// Why the walk's sink stopped the driver.
enum Halt {
    Stop,
    Cancelled(f64),
    Failed(AnalysisError),
}

struct Each<'c, F> {
    each: F,
    cancel: Option<&'c AtomicBool>,
    t_end: f64,
    steps: usize,
    t: f64,
}

impl<G, F> Sink<G> for Each<'_, F>
where
    G: crate::lie::LieGroup,
    F: FnMut(&Step<'_, G>) -> Result<Next, AnalysisError>,
{
    type Error = Halt;
    fn save(&mut self, _t: f64, _y: &G) -> Result<(), Halt> {
        Ok(())
    }
    fn step(&mut self, s: &StepSegment<'_, G>) -> Result<(), Halt> {
        if self.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Err(Halt::Cancelled(s.t0));
        }
        self.steps += 1;
        let step = Step { t0: s.t0, t1: s.t1, h: s.h, y0: s.y0, y1: s.y1, index: self.steps, last: s.t1 == self.t_end };
        let next = (self.each)(&step).map_err(Halt::Failed)?;
        self.t = s.t1;
        match next {
            Next::Go => Ok(()),
            Next::Stop => Err(Halt::Stop),
        }
    }
}

/// Steps `method` from `(t0, y0)` over `duration` with `step`, at most
/// `max_steps` steps (checked by [`plan`]), through the driver, calling `each` after every accepted step;
/// `cancel` is looked at before each. Fixed steps are those of a run
/// ([`fixed_step_count`]: equal steps, the last landing on the end); error-
/// controlled steps are chosen by the driver's controller for the
/// trajectory alone.
#[allow(clippy::too_many_arguments)]
pub(crate) fn walk<S, M, F>(system: &S, method: &M, t0: f64, y0: &S::State, step: &StepSize, duration: f64, max_steps: usize, cancel: Option<&AtomicBool>, each: F) -> Result<Walked, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
    F: FnMut(&Step<'_, S::State>) -> Result<Next, AnalysisError>,
{
    let t_end = t0 + duration;
    let settings = Settings { step: step.clone(), save: Save::Ends, dense: false, max_steps, event_xtol: 0.0, projection: Projection::None };
    let mut sink = Each { each, cancel, t_end, steps: 0, t: t0 };
    let mut control = Control::default();
    let mut events: &[Event<S::State>] = &[];
    let out = drive(system, method, t0, y0, t_end, &settings, &mut events, &mut sink, &mut control);
    let walked = Walked { t: sink.t, steps: sink.steps };
    match out.stop {
        Ok(StopReason::Cancelled) => Err(AnalysisError::Cancelled { t: walked.t }),
        Ok(StopReason::Failed(e)) => Err(AnalysisError::Solve(e)),
        Ok(StopReason::Finished | StopReason::Event { .. }) => Ok(walked),
        Err(DriveError::Sink(Halt::Stop)) => Ok(walked),
        Err(DriveError::Sink(Halt::Cancelled(t))) => Err(AnalysisError::Cancelled { t }),
        Err(DriveError::Sink(Halt::Failed(e))) => Err(e),
        Err(DriveError::Solve(e)) => Err(AnalysisError::Solve(e)),
    }
}

/// Running estimates kept along a run, thinned so that at most
/// [`MAX_HISTORY`](super::lyapunov::MAX_HISTORY) rows and the last are
/// kept: every `stride`-th row offered, the stride fixed in advance for a
/// known number of rows ([`History::every`]) or doubled (every other kept
/// row dropped) each time the rows fill up ([`History::growing`]).
pub(crate) struct History<R> {
    stride: usize,
    offered: usize,
    rows: Vec<(f64, R)>,
}

impl<R> History<R> {
    /// Every `stride`-th row.
    pub fn every(stride: usize) -> Self {
        History { stride: stride.max(1), offered: 0, rows: Vec::new() }
    }

    /// Every row until the history is full, then every second, …
    pub fn growing() -> Self {
        Self::every(1)
    }

    /// Offers the row of the `offered`-th call; `last` rows are always kept.
    pub fn offer(&mut self, t: f64, row: impl FnOnce() -> R, last: bool) {
        self.offered += 1;
        if !last && self.offered.is_multiple_of(self.stride) && self.rows.len() >= super::lyapunov::MAX_HISTORY {
            // Keep the rows at multiples of twice the stride.
            let mut i = 0;
            self.rows.retain(|_| {
                i += 1;
                i % 2 == 0
            });
            self.stride *= 2;
        }
        if last || self.offered.is_multiple_of(self.stride) {
            self.rows.push((t, row()));
        }
    }

    /// The rows kept.
    pub fn rows(&self) -> &[(f64, R)] {
        &self.rows
    }

    /// The rows kept, by value.
    pub fn into_rows(self) -> Vec<(f64, R)> {
        self.rows
    }
}
