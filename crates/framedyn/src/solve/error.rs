//! Typed failures of a solve: every error carries where (`t`) and with which
//! step (`h`) it happened, and [`Failure`] returns the solution computed so far.

use thiserror::Error;

use super::Solution;
use crate::lie::LieGroup;
use crate::method::NonFiniteSource;

/// Why a solve (or a [`Stepper`](super::Stepper) step) stopped early.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SolveError {
    /// A scalar input lies outside its allowed range (or is not finite).
    #[error("invalid {field} = {}: must be {allowed}", crate::error::Num(*value))]
    InvalidParameter {
        /// Name of the input, e.g. `"t_end"`.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The options do not fit the method or the problem.
    #[error("invalid options: {reason}")]
    InvalidOptions {
        /// What is wrong, in words.
        reason: String,
    },
    /// The initial state is not a finite element of its group.
    #[error("initial state is not a finite group element (constraint defect {defect})")]
    InvalidInitialState {
        /// [`LieGroup::constraint_defect`] of the state.
        defect: f64,
    },
    /// NaN or ±∞ in the vector field, the state, the step increment or an
    /// event function.
    #[error("non-finite {what} at t = {t_eval} in the step from t = {t} with h = {h:e}")]
    NonFinite {
        /// Where the value appeared.
        what: NonFiniteSource,
        /// Time of the evaluation that produced it.
        t_eval: f64,
        /// Start of the failing step.
        t: f64,
        /// Size of the failing step.
        h: f64,
    },
    /// The step-size controller asked for a step below the minimum.
    #[error("step size collapsed at t = {t}: h = {h:e} is below h_min = {h_min:e}")]
    StepSizeTooSmall {
        /// Time reached.
        t: f64,
        /// The step the controller asked for.
        h: f64,
        /// The effective minimum `max(h_min, 16ε·max(|t|, |t_end|))`.
        h_min: f64,
    },
    /// The maximum number of steps was reached before `t_end`.
    #[error("maximum number of steps ({max_steps}) reached at t = {t} (next h = {h:e})")]
    MaxSteps {
        /// Time reached.
        t: f64,
        /// The next step size.
        h: f64,
        /// The limit.
        max_steps: usize,
    },
    /// A fixed step is too large for the `dexp⁻¹` radius guard.
    #[error(
        "step from t = {t} with h = {h:e}: an algebra argument has ρ(ad θ) ≤ {radius}, above the dexp⁻¹ radius guard {limit}; reduce h"
    )]
    DexpRadius {
        /// Start of the step.
        t: f64,
        /// Its size.
        h: f64,
        /// The bound `ρ(ad_θ)` found.
        radius: f64,
        /// The guard.
        limit: f64,
    },
    /// An implicit step's equations were not solved (Newton did not converge).
    #[error(
        "step from t = {t} with h = {h:e}: Newton did not converge after {iterations} iterations (last update {residual:e}, equations at t = {t_eval}); reduce h"
    )]
    NoConvergence {
        /// Start of the step.
        t: f64,
        /// Its size.
        h: f64,
        /// Time at which the equations were posed.
        t_eval: f64,
        /// Iterations spent.
        iterations: u32,
        /// Last update (max norm).
        residual: f64,
    },
    /// A coordinate method left the region where its chart is regular.
    #[error("step from t = {t} with h = {h:e}: outside the chart at t = {t_eval}: {reason}")]
    OutsideChart {
        /// Start of the step.
        t: f64,
        /// Its size.
        h: f64,
        /// Time of the failing evaluation.
        t_eval: f64,
        /// Why, in words.
        reason: &'static str,
    },
}

impl From<crate::method::MethodError> for SolveError {
    /// A method that cannot be built or cannot integrate the system: an
    /// invalid parameter keeps its field; the rest are invalid options.
    fn from(e: crate::method::MethodError) -> Self {
        match e {
            crate::method::MethodError::InvalidParameter { field, value, allowed } => SolveError::InvalidParameter { field, value, allowed },
            other => SolveError::InvalidOptions { reason: other.to_string() },
        }
    }
}

/// A failed solve: the error and the solution up to the last good state.
#[derive(Debug, Error)]
#[error("{error}")]
pub struct Failure<G: LieGroup> {
    /// What went wrong.
    pub error: SolveError,
    /// The solution computed before the failure: saved points up to the last
    /// accepted step (which is always included), statistics, events, dense
    /// output; its [`stop_reason`](Solution::stop_reason) is
    /// [`StopReason::Failed`](super::StopReason::Failed).
    pub solution: Box<Solution<G>>,
}
