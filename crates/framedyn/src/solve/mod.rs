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
//! The method only advances one step; the driver here owns step-size control
//! ([`Adaptive`]), output sampling ([`Save`], dense output), recorded
//! invariants, [`event`]s, statistics and failures. Every failure is a typed
//! [`SolveError`] carrying `t` and `h`, returned in a [`Failure`] together
//! with the solution computed so far. [`Stepper`] advances a state step by
//! step for interactive use.

mod adaptive;
mod error;
pub mod event;
mod options;
mod problem;
mod solution;
mod stepper;

pub use error::{Failure, SolveError};
pub use event::{Direction, Event, EventRecord};
pub use options::{Adaptive, Controller, ObserverFn, Options, Save, StepSize, Tol, DEFAULT_MAX_STEPS};
pub use problem::{state_is_finite, Problem};
pub use solution::{DenseSegment, InvariantSeries, Solution, StopReason, Stats};
pub use stepper::Stepper;

use crate::dynamics::System;
use crate::method::{Alg, GroupNumerics, Method, MethodInfo, NonFiniteSource, StepFault, StepOutput, StepRequest};

/// The [`SolveError`] of a step fault in the step from `t` with size `h`.
pub(crate) fn fault_error(f: StepFault, t: f64, h: f64) -> SolveError {
    match f {
        StepFault::NonFinite { source, t_eval } => SolveError::NonFinite { what: source, t_eval, t, h },
        StepFault::DexpRadius { radius, limit, .. } => SolveError::DexpRadius { t, h, radius, limit },
        StepFault::NoConvergence { iterations, residual, t_eval } => {
            SolveError::NoConvergence { t, h, t_eval, iterations, residual }
        }
        StepFault::OutsideChart { reason, t_eval } => SolveError::OutsideChart { t, h, t_eval, reason },
    }
}

/// Per-event state during a run.
#[derive(Debug, Clone, Copy)]
struct EventState {
    /// `g` at the current point.
    g: f64,
    /// Sign of the last non-zero value (0 at a zero: the next sign change
    /// from there is not a crossing).
    sign: i8,
}

fn sign_of(v: f64) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// Solves `problem` with `method`.
///
/// Returns the [`Solution`], or a [`Failure`] holding the error and the
/// solution up to the last good state. Options are validated first
/// ([`SolveError::InvalidParameter`], [`SolveError::InvalidOptions`]).
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
    let mut run = Run::new(problem, method, options);
    let result = run.go();
    run.finish(result)
}

struct Run<'a, S: System, M> {
    sys: &'a S,
    method: &'a M,
    opts: &'a Options<S::State>,
    info: MethodInfo,
    t0: f64,
    t_end: f64,
    dir: f64,
    at: Vec<f64>,
    at_idx: usize,
    ev: Vec<EventState>,
    need_dense: bool,
    t: f64,
    y: S::State,
    sol: Solution<S::State>,
}

impl<'a, S, M> Run<'a, S, M>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    fn new(problem: &'a Problem<S>, method: &'a M, opts: &'a Options<S::State>) -> Self {
        let info = method.info();
        let (t0, t_end) = (problem.t0(), problem.t_end());
        let mut names: Vec<String> = Vec::new();
        if opts.energy {
            names.push("energy".into());
        }
        if opts.defect {
            names.push("defect".into());
        }
        names.extend(opts.observers.iter().map(|o| o.0.clone()));
        let sol = Solution {
            t: Vec::new(),
            y: Vec::new(),
            invariants: names.into_iter().map(|name| InvariantSeries { name, values: Vec::new() }).collect(),
            events: Vec::new(),
            dense: if opts.dense { Some(Vec::new()) } else { None },
            stats: Stats::default(),
            stop: StopReason::Finished,
            method: info,
            t_last: t0,
            y_last: *problem.y0(),
        };
        Run {
            sys: problem.system(),
            method,
            opts,
            info,
            t0,
            t_end,
            dir: if t_end > t0 { 1.0 } else { -1.0 },
            at: Vec::new(),
            at_idx: 0,
            ev: Vec::new(),
            need_dense: opts.dense || matches!(opts.save, Save::At(_)) || !opts.events.is_empty(),
            t: t0,
            y: *problem.y0(),
            sol,
        }
    }

    fn validate(&mut self) -> Result<(), SolveError> {
        let o = self.opts;
        if o.max_steps == 0 {
            return Err(SolveError::InvalidOptions { reason: "max_steps must be ≥ 1".into() });
        }
        if !(o.event_xtol >= 0.0 && o.event_xtol.is_finite()) {
            return Err(SolveError::InvalidParameter {
                field: "event_tolerance",
                value: o.event_xtol,
                allowed: "finite and ≥ 0",
            });
        }
        if let Save::At(times) = &o.save {
            let (lo, hi) = (self.t0.min(self.t_end), self.t0.max(self.t_end));
            for &ts in times {
                if !(ts >= lo && ts <= hi) {
                    return Err(SolveError::InvalidParameter {
                        field: "save time",
                        value: ts,
                        allowed: "within the time span [t0, t_end]",
                    });
                }
            }
            let mut at = times.clone();
            at.sort_by(f64::total_cmp);
            if self.dir < 0.0 {
                at.reverse();
            }
            self.at = at;
        }
        match &o.step {
            StepSize::Fixed(h) => {
                if !(h.is_finite() && *h > 0.0) {
                    return Err(SolveError::InvalidParameter { field: "h", value: *h, allowed: "finite and > 0" });
                }
            }
            StepSize::Adaptive(a) => adaptive::validate::<S::State>(a, &self.info)?,
        }
        Ok(())
    }

    fn go(&mut self) -> Result<StopReason, SolveError> {
        self.validate()?;
        self.ev = Vec::with_capacity(self.opts.events.len());
        for e in &self.opts.events {
            let g = e.value(self.t0, &self.y);
            self.sol.stats.event_evals += 1;
            if !g.is_finite() {
                return Err(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval: self.t0, t: self.t0, h: 0.0 });
            }
            self.ev.push(EventState { g, sign: sign_of(g) });
        }
        match &self.opts.save {
            Save::Steps | Save::Ends => self.save(self.t0, self.y),
            Save::At(_) => {}
        }
        while self.at_idx < self.at.len() && self.at[self.at_idx] == self.t0 {
            self.save(self.t0, self.y);
            self.at_idx += 1;
        }
        match &self.opts.step {
            StepSize::Fixed(h) => self.run_fixed(*h),
            StepSize::Adaptive(a) => self.run_adaptive(a),
        }
    }

    fn finish(mut self, result: Result<StopReason, SolveError>) -> Result<Solution<S::State>, Failure<S::State>> {
        self.sol.t_last = self.t;
        self.sol.y_last = self.y;
        match result {
            Ok(reason) => {
                if matches!(self.opts.save, Save::Ends) && self.sol.t.last() != Some(&self.t) {
                    self.save(self.t, self.y);
                }
                self.sol.stop = reason;
                Ok(self.sol)
            }
            Err(error) => {
                if self.sol.t.last() != Some(&self.t) {
                    self.save(self.t, self.y);
                }
                self.sol.stop = StopReason::Failed(error.clone());
                Err(Failure { error, solution: Box::new(self.sol) })
            }
        }
    }

    /// Appends a saved point and the recorded invariants there.
    fn save(&mut self, t: f64, y: S::State) {
        self.sol.t.push(t);
        self.sol.y.push(y);
        let mut k = 0;
        if self.opts.energy {
            self.sol.invariants[k].values.push(self.sys.energy(&y));
            k += 1;
        }
        if self.opts.defect {
            self.sol.invariants[k].values.push(self.sys.defect(&y));
            k += 1;
        }
        for (name_k, (_, q)) in self.opts.observers.iter().enumerate() {
            self.sol.invariants[k + name_k].values.push(q(t, &y));
        }
    }

    fn reserve(&mut self, n: usize) {
        let points = match &self.opts.save {
            Save::Steps => n + 1,
            Save::At(v) => v.len(),
            Save::Ends => 2,
        };
        self.sol.t.reserve(points);
        self.sol.y.reserve(points);
        for s in &mut self.sol.invariants {
            s.values.reserve(points);
        }
        if let Some(d) = &mut self.sol.dense {
            d.reserve(n);
        }
    }

    fn run_fixed(&mut self, h_req: f64) -> Result<StopReason, SolveError> {
        let span = self.t_end - self.t0;
        let ratio = span.abs() / h_req;
        let near = ratio.round();
        let n = if near >= 1.0 && (ratio - near).abs() <= 1e-9 * near { near } else { ratio.ceil().max(1.0) };
        if n > 9.0e15 {
            return Err(SolveError::InvalidParameter { field: "h", value: h_req, allowed: "at least |t_end − t0|/9e15" });
        }
        let n = n as usize;
        self.reserve(n.min(self.opts.max_steps));
        let mut f_cache: Option<Alg<S>> = None;
        for i in 0..n {
            let t = self.t;
            let t1 = if i + 1 == n { self.t_end } else { self.t0 + span * ((i + 1) as f64 / n as f64) };
            let h = t1 - t;
            if self.sol.stats.accepted >= self.opts.max_steps {
                return Err(SolveError::MaxSteps { t, h, max_steps: self.opts.max_steps });
            }
            let req = StepRequest { f_start: f_cache.take(), error: false, dense: self.need_dense, f_end: self.need_dense };
            let out = self.method.step(self.sys, t, &self.y, h, req).map_err(|f| fault_error(f, t, h))?;
            self.sol.stats.add_cost(&out.cost);
            f_cache = out.f_end;
            if let Some(index) = self.accept(t1, h, &out)? {
                return Ok(StopReason::Event { index });
            }
        }
        Ok(StopReason::Finished)
    }

    fn run_adaptive(&mut self, a: &Adaptive) -> Result<StopReason, SolveError> {
        adaptive::run(self, a)
    }

    /// Processes an accepted step from `(self.t, self.y)` to `t1` (events,
    /// samples, saving, dense output); returns the index of a terminal event.
    fn accept(&mut self, t1: f64, h: f64, out: &StepOutput<S::State>) -> Result<Option<usize>, SolveError> {
        let t = self.t;
        let seg = out.dense.map(|poly| DenseSegment { t0: t, h, y0: self.y, poly });
        self.sol.stats.accept(h);

        let mut stop: Option<(usize, f64, S::State)> = None;
        if !self.opts.events.is_empty() {
            if let Some(seg) = &seg {
                stop = self.events(t, t1, h, out, seg)?;
            }
        }
        let (t_stop, y_stop) = match &stop {
            Some((_, te, ye)) => (*te, *ye),
            None => (t1, out.y),
        };
        while self.at_idx < self.at.len() && (self.at[self.at_idx] - t_stop) * self.dir <= 0.0 {
            let ts = self.at[self.at_idx];
            let ys = if ts == t_stop {
                y_stop
            } else if let Some(seg) = &seg {
                self.sol.stats.dense_evals += 1;
                self.sol.stats.exps += 1;
                seg.eval(ts)
            } else {
                break;
            };
            self.save(ts, ys);
            self.at_idx += 1;
        }
        if matches!(self.opts.save, Save::Steps) {
            self.save(t_stop, y_stop);
        }
        if let (Some(d), Some(seg)) = (&mut self.sol.dense, seg) {
            d.push(seg);
        }
        self.t = t_stop;
        self.y = y_stop;
        Ok(stop.map(|s| s.0))
    }

    /// Finds the crossings in the step, records them, and returns the
    /// first terminal one.
    fn events(
        &mut self,
        t: f64,
        t1: f64,
        h: f64,
        out: &StepOutput<S::State>,
        seg: &DenseSegment<S::State>,
    ) -> Result<Option<(usize, f64, S::State)>, SolveError> {
        // No allocation unless an event fires.
        let mut hits: Vec<(f64, usize, bool)> = Vec::new();
        let opts: &'a Options<S::State> = self.opts;
        for (k, e) in opts.events.iter().enumerate() {
            let g1 = e.value(t1, &out.y);
            self.sol.stats.event_evals += 1;
            if !g1.is_finite() {
                return Err(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval: t1, t, h });
            }
            let prev = self.ev[k];
            let s1 = sign_of(g1);
            if prev.sign != 0 && s1 != prev.sign {
                let rising = prev.sign < 0;
                let wanted = match e.direction {
                    Direction::Rising => rising,
                    Direction::Falling => !rising,
                    Direction::Either => true,
                };
                if wanted {
                    let t_root = if s1 == 0 {
                        t1
                    } else {
                        let mut bad = false;
                        let mut n_dense = 0;
                        let (tr, _) = event::brent(
                            |tau| {
                                n_dense += 1;
                                let v = e.value(tau, &seg.eval(tau));
                                if !v.is_finite() {
                                    bad = true;
                                }
                                v
                            },
                            t,
                            t1,
                            prev.g,
                            g1,
                            opts.event_xtol,
                        );
                        self.sol.stats.dense_evals += n_dense;
                        self.sol.stats.exps += n_dense;
                        self.sol.stats.event_evals += n_dense;
                        if bad {
                            return Err(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval: tr, t, h });
                        }
                        tr
                    };
                    hits.push((t_root, k, rising));
                }
            }
            self.ev[k] = EventState { g: g1, sign: s1 };
        }
        if hits.is_empty() {
            return Ok(None);
        }
        let dir = self.dir;
        hits.sort_by(|x, y| ((x.0 - t) * dir).total_cmp(&((y.0 - t) * dir)));
        let mut stop = None;
        for (t_root, k, rising) in hits {
            let terminal = self.opts.events[k].terminal;
            let y = if t_root == t1 {
                out.y
            } else {
                self.sol.stats.dense_evals += 1;
                self.sol.stats.exps += 1;
                seg.eval(t_root)
            };
            self.sol.events.push(EventRecord { index: k, t: t_root, y, rising, terminal });
            if terminal {
                stop = Some((k, t_root, y));
                break;
            }
        }
        Ok(stop)
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
