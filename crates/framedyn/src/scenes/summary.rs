//! What a run reports: progress while it runs, and its summary — steps,
//! work, the drift of the energy and of the momentum maps, the constraint
//! defect, why it stopped.

use std::fmt;
use std::time::Duration;

use super::error::RunError;
use crate::solve::SolveError;

/// A progress report during a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Time reached.
    pub t: f64,
    /// Start of the span.
    pub t0: f64,
    /// End of the span.
    pub t_end: f64,
    /// `(t − t₀)/(t_end − t₀)` in `[0, 1]`.
    pub fraction: f64,
    /// Accepted steps so far.
    pub steps: u64,
}

/// Why a run stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneStop {
    /// `t_end` was reached.
    Finished,
    /// The cancel flag was raised; the records up to then are valid.
    Cancelled,
    /// The integration failed; the records up to the last good state are valid.
    Failed(SolveError),
    /// Writing a record failed.
    OutputError(String),
    /// A terminal event (its name) stopped the run; its state is the last record.
    Event(String),
}

impl fmt::Display for SceneStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneStop::Finished => f.write_str("finished"),
            SceneStop::Cancelled => f.write_str("cancelled (interrupted); output holds the part computed so far"),
            SceneStop::Failed(e) => write!(f, "integration failed: {e}; output holds the part up to the last good state"),
            SceneStop::OutputError(e) => write!(f, "output error: {e}"),
            SceneStop::Event(name) => write!(f, "stopped by the terminal event `{name}`"),
        }
    }
}

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// The method's name.
    pub method: &'static str,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (adaptive stepping).
    pub rejected: u64,
    /// Evaluations of the vector field.
    pub rhs_evals: u64,
    /// Records written.
    pub records: u64,
    /// Events located.
    pub events: u64,
    /// Wall-clock time of the run.
    pub wall_time: Duration,
    /// Energy of the first record.
    pub energy_initial: f64,
    /// `max |E − E₀|` over the records (the invariant drift).
    pub energy_drift: f64,
    /// `max |J − J₀|` over the records and the recorded momentum maps
    /// (`p_phi`, or `J_ab` on S³; 0 when none is recorded). Conserved only
    /// when the potential has the symmetry (e.g. central about the pole).
    pub momentum_map_drift: f64,
    /// `max` over the records of the constraint defect.
    pub max_defect: f64,
    /// Time reached.
    pub t_reached: f64,
    /// Why the run stopped.
    pub stop: SceneStop,
}

impl RunSummary {
    pub(crate) fn new(method: &'static str, t0: f64) -> Self {
        RunSummary {
            method,
            steps: 0,
            rejected: 0,
            rhs_evals: 0,
            records: 0,
            events: 0,
            wall_time: Duration::ZERO,
            energy_initial: f64::NAN,
            energy_drift: 0.0,
            momentum_map_drift: 0.0,
            max_defect: 0.0,
            t_reached: t0,
            stop: SceneStop::Finished,
        }
    }

    /// `energy_drift / max(|E₀|, 1e-300)`.
    pub fn relative_energy_drift(&self) -> f64 {
        self.energy_drift / self.energy_initial.abs().max(1e-300)
    }
}

impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "stop:            {}", self.stop)?;
        writeln!(f, "method:          {}", self.method)?;
        writeln!(f, "t reached:       {}", self.t_reached)?;
        writeln!(f, "steps:           {} accepted, {} rejected ({} vector-field evaluations)", self.steps, self.rejected, self.rhs_evals)?;
        writeln!(f, "records:         {}", self.records)?;
        writeln!(f, "events:          {}", self.events)?;
        writeln!(f, "wall time:       {:.3} s", self.wall_time.as_secs_f64())?;
        writeln!(f, "energy:          E0 = {:.12e}, max |E - E0| = {:.3e} (relative {:.3e})", self.energy_initial, self.energy_drift, self.relative_energy_drift())?;
        writeln!(f, "momentum maps:   max |J - J0| = {:.3e}", self.momentum_map_drift)?;
        write!(f, "constraint defect: max {:.3e}", self.max_defect)
    }
}

/// A run that stopped with an error: the error and the summary of the part
/// that was computed and written.
#[derive(Debug)]
pub struct RunFailure {
    /// What went wrong.
    pub error: RunError,
    /// The summary up to the failure.
    pub summary: RunSummary,
}

impl fmt::Display for RunFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.error)
    }
}

impl std::error::Error for RunFailure {}

