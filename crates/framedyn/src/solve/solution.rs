//! The result of a solve: sampled states, recorded invariants, events, dense
//! output, statistics and the reason the run stopped.

use super::event::EventRecord;
use super::SolveError;
use crate::lie::LieGroup;
use crate::method::{DensePoly, MethodInfo, StepCost};

/// Why the run stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// `t_end` was reached.
    Finished,
    /// A terminal event fired; the last state is the event state.
    Event {
        /// Index of the event in the options.
        index: usize,
    },
    /// The run failed (the error is also returned in a [`Failure`](super::Failure)).
    Failed(SolveError),
    /// The cancel flag of the run's [`Control`](super::Control) was raised;
    /// everything up to the state reached is kept.
    Cancelled,
}

/// Work statistics of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps (error test failed, or the `dexp⁻¹` radius guard asked
    /// for a smaller step).
    pub rejected: usize,
    /// Of the rejected steps, those abandoned by the `dexp⁻¹` radius guard
    /// (their partial work is counted in the other fields).
    pub rejected_radius: usize,
    /// Automatic first steps taken again with a larger step because their
    /// error was far below the tolerance (not rejections; see
    /// [`Adaptive`](super::Adaptive), "First step"). Their work is counted in
    /// the other fields.
    pub first_step_probes: usize,
    /// Evaluations of the vector field (steps, first-step selection).
    pub rhs_evals: usize,
    /// Group exponentials in steps and dense-output samples.
    pub exps: usize,
    /// Lie brackets (truncated `dexp⁻¹` series, commutator forms).
    pub brackets: usize,
    /// Closed-form `dexp⁻¹` evaluations.
    pub dexp_inv: usize,
    /// Dense-output evaluations (saved samples and event location).
    pub dense_evals: usize,
    /// Event-function evaluations.
    pub event_evals: usize,
    /// Energy evaluations of the projection ([`Projection::Energy`](super::Projection)).
    pub energy_evals: usize,
    /// Accepted steps projected onto the initial energy (including those
    /// already on it to round-off).
    pub projections: usize,
    /// Accepted steps whose projection was skipped (energy or gradient not
    /// finite, gradient zero, or no Newton step reduced the residual; see
    /// [`projection`](super::projection)).
    pub projections_skipped: usize,
    /// Smallest accepted `|h|` (∞ before the first step).
    pub h_min: f64,
    /// Largest accepted `|h|` (0 before the first step).
    pub h_max: f64,
}

impl Default for Stats {
    fn default() -> Self {
        Stats {
            accepted: 0,
            rejected: 0,
            rejected_radius: 0,
            first_step_probes: 0,
            rhs_evals: 0,
            exps: 0,
            brackets: 0,
            dexp_inv: 0,
            dense_evals: 0,
            event_evals: 0,
            energy_evals: 0,
            projections: 0,
            projections_skipped: 0,
            h_min: f64::INFINITY,
            h_max: 0.0,
        }
    }
}

impl Stats {
    /// Adds the work of one step (accepted or not).
    pub fn add_cost(&mut self, c: &StepCost) {
        self.rhs_evals += c.rhs as usize;
        self.exps += c.exps as usize;
        self.brackets += c.brackets as usize;
        self.dexp_inv += c.dexp_inv as usize;
    }

    /// Records an accepted step of size `h`.
    pub fn accept(&mut self, h: f64) {
        self.accepted += 1;
        self.h_min = self.h_min.min(h.abs());
        self.h_max = self.h_max.max(h.abs());
    }
}

/// The dense output of one step: `y(t) = y₀·exp(θ((t − t₀)/h))`, renormalised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseSegment<G: LieGroup> {
    /// Start of the step.
    pub t0: f64,
    /// Step size (signed).
    pub h: f64,
    /// State at `t0`.
    pub y0: G,
    /// The algebra polynomial `θ(σ)`.
    pub poly: DensePoly<G::Algebra>,
}

impl<G: LieGroup> DenseSegment<G> {
    /// The interpolated state at `t` (meaningful for `t` in the step; the
    /// polynomial is evaluated as is outside it).
    pub fn eval(&self, t: f64) -> G {
        let sigma = (t - self.t0) / self.h;
        self.y0.compose(&G::exp(&self.poly.theta(sigma))).renormalize()
    }

    /// End of the step.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }

    /// True if `t` lies in the closed step interval.
    pub fn contains(&self, t: f64) -> bool {
        let (a, b) = if self.h > 0.0 { (self.t0, self.t1()) } else { (self.t1(), self.t0) };
        a <= t && t <= b
    }
}

/// Values of one recorded invariant at the saved times.
#[derive(Debug, Clone, PartialEq)]
pub struct InvariantSeries {
    /// Name (`"energy"`, `"defect"` or the observer's name).
    pub name: String,
    /// One value per saved time.
    pub values: Vec<f64>,
}

impl InvariantSeries {
    /// `maxₖ |vₖ − v₀|`: the largest drift from the first value (NaN if any
    /// value is NaN).
    pub fn drift(&self) -> f64 {
        let Some(&v0) = self.values.first() else { return 0.0 };
        let mut worst: f64 = 0.0;
        for &v in &self.values {
            let d = (v - v0).abs();
            if d.is_nan() {
                return f64::NAN;
            }
            worst = worst.max(d);
        }
        worst
    }

    /// `maxₖ |vₖ|` (NaN if any value is NaN).
    pub fn max_abs(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for &v in &self.values {
            if v.is_nan() {
                return f64::NAN;
            }
            worst = worst.max(v.abs());
        }
        worst
    }
}

/// The result of [`solve`](super::solve).
#[derive(Debug, Clone)]
pub struct Solution<G: LieGroup> {
    pub(crate) t: Vec<f64>,
    pub(crate) y: Vec<G>,
    pub(crate) invariants: Vec<InvariantSeries>,
    pub(crate) events: Vec<EventRecord<G>>,
    pub(crate) dense: Option<Vec<DenseSegment<G>>>,
    pub(crate) stats: Stats,
    pub(crate) stop: StopReason,
    pub(crate) method: MethodInfo,
    pub(crate) t_last: f64,
    pub(crate) y_last: G,
}

impl<G: LieGroup> Solution<G> {
    /// The saved times (in the order of integration).
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// The saved states, one per time.
    pub fn states(&self) -> &[G] {
        &self.y
    }

    /// The last state reached (the final state, the state at a terminal
    /// event, or the last good state before a failure) and its time, whether
    /// or not it was saved.
    pub fn last(&self) -> (f64, &G) {
        (self.t_last, &self.y_last)
    }

    /// The recorded invariants (energy, defect, observers), aligned with
    /// [`times`](Self::times).
    pub fn invariants(&self) -> &[InvariantSeries] {
        &self.invariants
    }

    /// The recorded invariant called `name`.
    pub fn invariant(&self, name: &str) -> Option<&InvariantSeries> {
        self.invariants.iter().find(|s| s.name == name)
    }

    /// The events found, in the order of integration.
    pub fn events(&self) -> &[EventRecord<G>] {
        &self.events
    }

    /// The dense output, one segment per accepted step (if it was requested).
    pub fn dense(&self) -> Option<&[DenseSegment<G>]> {
        self.dense.as_deref()
    }

    /// The state at `t` from the dense output; `None` without dense output or
    /// outside the integrated interval.
    pub fn sample(&self, t: f64) -> Option<G> {
        let segs = self.dense.as_ref()?;
        let first = segs.first()?;
        let forward = first.h > 0.0;
        // Segments are ordered in the direction of integration.
        let idx = segs.partition_point(|s| if forward { s.t1() < t } else { s.t1() > t });
        let seg = segs.get(idx)?;
        let within_run = if forward { t <= self.t_last } else { t >= self.t_last };
        if seg.contains(t) && within_run {
            Some(seg.eval(t))
        } else {
            None
        }
    }

    /// Work statistics.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Why the run stopped.
    pub fn stop_reason(&self) -> &StopReason {
        &self.stop
    }

    /// The method's static properties.
    pub fn method(&self) -> &MethodInfo {
        &self.method
    }
}
