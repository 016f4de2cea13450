//! Solving initial-value problems on Lie groups: a [`Problem`] is solved by a
//! [`Method`] with [`Options`] into a [`Solution`] (the separation of
//! DifferentialEquations.jl and diffsol).
//!
//! ```no_run
//! # use framedyn::solve::{solve, Options, Problem, Save};
//! # use framedyn::method::Rkmk;
//! # fn demo<S: framedyn::dynamics::System>(system: S, y0: S::State)
//! # where S::State: framedyn::method::GroupNumerics {
//! let problem = Problem::new(system, y0, (0.0, 10.0)).unwrap();
//! let sol = solve(&problem, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-10)
//!     .save(Save::At(vec![1.0, 2.0, 5.0]))
//!     .record_energy())
//!     .unwrap();
//! # }
//! ```
//!
//! The method only advances one step; the one stepping loop of the crate,
//! [`driver::drive`], owns step-size control ([`Adaptive`]), output
//! sampling ([`Save`], dense output), [`event`]s, cancellation, statistics
//! and failures, and streams what it produces to a [`Sink`]. [`solve`] is
//! the driver with a sink that keeps a [`Solution`] (with the recorded
//! invariants); the scene engine of [`scenes`](crate::scenes), the CLI and
//! the Python module run the same driver with sinks that write records.
//! Every failure is a typed [`SolveError`] carrying `t` and `h`, returned in
//! a [`Failure`] together with the solution computed so far. [`Stepper`]
//! advances a state one step at a time for interactive use.

pub(crate) mod adaptive;
pub mod driver;
mod error;
pub mod event;
mod options;
mod problem;
pub mod projection;
mod solution;
mod stepper;

pub use driver::{drive, fixed_step_count, Control, DriveError, EventSet, Outcome, Settings, Sink, StepSegment, POLL_EVERY};
pub use error::{Failure, SolveError};
pub use event::{Direction, Event, EventRecord};
pub use options::{Adaptive, Controller, ObserverFn, Options, Save, StepSize, Tol, DEFAULT_MAX_STEPS, RTOL_MIN};
pub use problem::{state_is_finite, Problem};
pub use projection::Projection;
pub use solution::{DenseSegment, InvariantSeries, Solution, StopReason, Stats};
pub use stepper::Stepper;

use crate::dynamics::System;
use crate::method::{GroupNumerics, Method, StepFault};

/// The [`SolveError`] of a step fault in the step from `t` with size `h`.
pub(crate) fn fault_error(f: StepFault, t: f64, h: f64) -> SolveError {
    match f {
        StepFault::NonFinite { source, t_eval } => SolveError::NonFinite { what: source, t_eval, t, h },
        StepFault::DexpRadius { radius, limit, .. } => SolveError::DexpRadius { t, h, radius, limit },
        StepFault::NoConvergence { iterations, residual, t_eval } => {
            SolveError::NoConvergence { t, h, t_eval, iterations, residual }
        }
        StepFault::OutsideChart { reason, t_eval } => SolveError::OutsideChart { t, h, t_eval, reason },
        StepFault::Unsupported { method, reason } => SolveError::InvalidOptions { reason: format!("{method} cannot integrate this system: {reason}") },
    }
}

/// Solves `problem` with `method`: [`driver::drive`] with a sink that keeps
/// the saved states, the recorded invariants, the events and the dense
/// output in a [`Solution`].
///
/// Returns the [`Solution`], or a [`Failure`] holding the error and the
/// solution up to the last good state. Options are validated first
/// ([`SolveError::InvalidParameter`], [`SolveError::InvalidOptions`]), and
/// so is the method's fitness for the system ([`Method::check`]).
pub fn solve<S, M>(
    problem: &Problem<S>,
    method: &M,
    options: &Options<S::State>,
) -> Result<Solution<S::State>, Failure<S::State>>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    solve_with(problem, driver::erase(method), options)
}

/// [`solve`] with the method as [`driver::erase`] leaves it (one instance
/// per system in builds with debug assertions).
fn solve_with<S, M>(problem: &Problem<S>, method: &M, options: &Options<S::State>) -> Result<Solution<S::State>, Failure<S::State>>
where
    S: System,
    S::State: GroupNumerics,
    M: driver::StepMethod<S> + ?Sized,
{
    let sys = problem.system();
    let mut names: Vec<String> = Vec::new();
    if options.energy {
        names.push("energy".into());
    }
    if options.defect {
        names.push("defect".into());
    }
    names.extend(options.observers.iter().map(|o| o.0.clone()));
    let info = method.info();
    let mut sink = Collect {
        sys,
        opts: options,
        sol: Solution {
            t: Vec::new(),
            y: Vec::new(),
            invariants: names.into_iter().map(|name| InvariantSeries { name, values: Vec::new() }).collect(),
            events: Vec::new(),
            dense: if options.settings.dense { Some(Vec::new()) } else { None },
            stats: Stats::default(),
            stop: StopReason::Finished,
            method: info,
            t_last: problem.t0(),
            y_last: *problem.y0(),
        },
    };
    if let StepSize::Fixed(h) = &options.settings.step {
        if let (Ok(n), Save::Steps | Save::Every(_)) = (driver::fixed_step_count(problem.t0(), problem.t_end(), *h), &options.settings.save) {
            sink.reserve(n.min(options.settings.max_steps));
        }
    }
    let mut events: &[Event<S::State>] = &options.events;
    let out = driver::drive_with(sys, method, problem.t0(), problem.y0(), problem.t_end(), &options.settings, &mut events, &mut sink, &mut Control::default());
    let mut sol = sink.sol;
    sol.stats = out.stats;
    sol.t_last = out.t;
    sol.y_last = out.y;
    match out.stop {
        Ok(reason) => {
            sol.stop = reason;
            Ok(sol)
        }
        Err(DriveError::Solve(error)) => {
            sol.stop = StopReason::Failed(error.clone());
            Err(Failure { error, solution: Box::new(sol) })
        }
        Err(DriveError::Sink(never)) => match never {},
    }
}

/// The sink of [`solve`]: everything in memory.
struct Collect<'a, S: System> {
    sys: &'a S,
    opts: &'a Options<S::State>,
    sol: Solution<S::State>,
}

impl<S: System> Collect<'_, S> {
    fn reserve(&mut self, steps: usize) {
        let every = match self.opts.settings.save {
            Save::Every(k) => k.max(1) as usize,
            _ => 1,
        };
        let points = steps / every + 2;
        self.sol.t.reserve(points);
        self.sol.y.reserve(points);
        for s in &mut self.sol.invariants {
            s.values.reserve(points);
        }
        if let Some(d) = &mut self.sol.dense {
            d.reserve(steps);
        }
    }
}

impl<S: System> Sink<S::State> for Collect<'_, S> {
    type Error = std::convert::Infallible;

    fn save(&mut self, t: f64, y: &S::State) -> Result<(), Self::Error> {
        self.sol.t.push(t);
        self.sol.y.push(*y);
        let mut k = 0;
        if self.opts.energy {
            self.sol.invariants[k].values.push(self.sys.energy(y));
            k += 1;
        }
        if self.opts.defect {
            self.sol.invariants[k].values.push(self.sys.defect(y));
            k += 1;
        }
        for (name_k, (_, q)) in self.opts.observers.iter().enumerate() {
            self.sol.invariants[k + name_k].values.push(q(t, y));
        }
        Ok(())
    }

    fn step(&mut self, segment: &StepSegment<'_, S::State>) -> Result<(), Self::Error> {
        if let (Some(d), Some(seg)) = (&mut self.sol.dense, segment.dense) {
            d.push(*seg);
        }
        Ok(())
    }

    fn event(&mut self, record: &EventRecord<S::State>) -> Result<(), Self::Error> {
        self.sol.events.push(record.clone());
        Ok(())
    }
}

/// The element `a ∈ 𝔤` with every component `v` or the given components.
pub(crate) fn tol_vector<A: crate::lie::AlgebraVector>(tol: &Tol) -> A {
    let mut a = A::zero();
    for i in 0..A::LEN {
        a.set(
            i,
            match tol {
                Tol::Scalar(v) => *v,
                Tol::PerComponent(v) => v.get(i).copied().unwrap_or(f64::NAN),
            },
        );
    }
    a
}
