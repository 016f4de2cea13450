//! Step-by-step integration for interactive use.

use super::problem::check_state;
use super::{fault_error, SolveError, Stats};
use crate::dynamics::System;
use crate::method::{GroupNumerics, Method, StepRequest};

/// Advances a state one step at a time, owning the system so that its
/// parameters can be changed between steps.
///
/// ```no_run
/// # use framedyn::solve::Stepper;
/// # use framedyn::method::Rkmk;
/// # fn demo<S: framedyn::dynamics::System>(system: S, y0: S::State)
/// # where S::State: framedyn::method::GroupNumerics {
/// let mut st = Stepper::new(system, Rkmk::rk4(), 0.0, y0).unwrap();
/// for _ in 0..100 {
///     st.step(0.01).unwrap();
/// }
/// let (t, y) = (st.t(), *st.state());
/// # let _ = (t, y);
/// # }
/// ```
///
/// A failed step leaves time and state unchanged. No step allocates.
#[derive(Debug, Clone)]
pub struct Stepper<S: System, M> {
    system: S,
    method: M,
    t: f64,
    y: S::State,
    stats: Stats,
}

impl<S, M> Stepper<S, M>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    /// A stepper at `(t0, y0)` (finite time, finite group element).
    pub fn new(system: S, method: M, t0: f64, y0: S::State) -> Result<Self, SolveError> {
        if !t0.is_finite() {
            return Err(SolveError::InvalidParameter { field: "t0", value: t0, allowed: "finite" });
        }
        check_state(&y0)?;
        Ok(Stepper { system, method, t: t0, y: y0, stats: Stats::default() })
    }

    /// One step of size `h` (finite, non-zero; negative steps go backwards).
    pub fn step(&mut self, h: f64) -> Result<(), SolveError> {
        let t1 = self.t + h;
        self.step_to(t1, h)
    }

    fn step_to(&mut self, t1: f64, h: f64) -> Result<(), SolveError> {
        if !(h.is_finite() && h != 0.0) {
            return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "finite and ≠ 0" });
        }
        let out = self
            .method
            .step(&self.system, self.t, &self.y, h, StepRequest::plain())
            .map_err(|f| fault_error(f, self.t, h))?;
        self.stats.add_cost(&out.cost);
        self.stats.accept(h);
        self.t = t1;
        self.y = out.y;
        Ok(())
    }

    /// `n ≥ 1` equal steps over `duration`, with step times
    /// `t + duration·i/n` (no accumulation of rounding in `t`). Stops at the
    /// first failing step (the steps before it stay done).
    pub fn advance(&mut self, duration: f64, n: usize) -> Result<(), SolveError> {
        if n == 0 || !duration.is_finite() || duration == 0.0 {
            return Err(SolveError::InvalidParameter {
                field: "duration",
                value: duration,
                allowed: "finite and ≠ 0, with n ≥ 1 steps",
            });
        }
        let t_start = self.t;
        for i in 0..n {
            let t1 = if i + 1 == n { t_start + duration } else { t_start + duration * ((i + 1) as f64 / n as f64) };
            let h = t1 - self.t;
            self.step_to(t1, h)?;
        }
        Ok(())
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current state.
    pub fn state(&self) -> &S::State {
        &self.y
    }

    /// Replaces time and state (validated like an initial state).
    pub fn set_state(&mut self, t: f64, y: S::State) -> Result<(), SolveError> {
        if !t.is_finite() {
            return Err(SolveError::InvalidParameter { field: "t", value: t, allowed: "finite" });
        }
        check_state(&y)?;
        self.t = t;
        self.y = y;
        Ok(())
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The system, mutably: change its parameters between steps.
    pub fn system_mut(&mut self) -> &mut S {
        &mut self.system
    }

    /// The method.
    pub fn method(&self) -> &M {
        &self.method
    }

    /// Energy of the current state ([`System::energy`]).
    pub fn energy(&self) -> f64 {
        self.system.energy(&self.y)
    }

    /// Constraint defect of the current state ([`System::defect`]).
    pub fn defect(&self) -> f64 {
        self.system.defect(&self.y)
    }

    /// Work statistics so far (`rejected` stays 0).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The system and the current time and state.
    pub fn into_parts(self) -> (S, f64, S::State) {
        (self.system, self.t, self.y)
    }
}
