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
    /// What the quality check found ([`RunSummary::judge`] against the
    /// scene's `[quality]` limits); empty when the run is sound.
    pub warnings: Vec<QualityWarning>,
    /// The estimate of the run's global error, when the scene asks for it
    /// (`[method] global_error = true`); `None` otherwise.
    pub global_error: Option<GlobalError>,
    /// What the energy projection did, when the scene asks for it
    /// (`[method] project = "energy"`); `None` otherwise.
    pub projection: Option<ProjectionCounts>,
}

/// What the energy projection of a run did (`[method] project = "energy"`;
/// see [`projection`](crate::solve::projection)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ProjectionCounts {
    /// Accepted steps projected onto the initial energy.
    pub projected: u64,
    /// Accepted steps left as the method computed them (energy or gradient
    /// not finite, gradient zero, or no Newton step reduced the residual).
    pub skipped: u64,
    /// Energy evaluations of the projection (its price, besides one
    /// vector-field evaluation per step that an FSAL method no longer saves).
    pub energy_evals: u64,
}

/// An estimate of a run's global error (`[method] global_error = true`).
///
/// The run is repeated from the same initial state with a hundredth of its
/// tolerances (`rtol` no smaller than 1e-14), or a quarter of its fixed step,
/// and the two are compared at every record. If the error is proportional
/// to the tolerance (as `docs/performance.md`, "Tolerance proportionality",
/// measures for DOP853 and DOPRI5) the reference's own error is about 1 % of
/// the run's (`4⁻ᵖ` for a fixed step of order `p`), so the difference is the
/// run's error to within a few per cent. Measured against fixed-step
/// references on the twelve problems there, [`GlobalError::max`] is within
/// 0.80 – 1.02 × the true maximum and [`GlobalError::last`] within
/// 0.76 – 1.08 × the true final error (`scripts/tolerance_proportionality.py`);
/// with `[method] project = "energy"` (the reference run projects too)
/// within 0.43 – 1.35 × and 0.60 – 1.79 ×, the outliers at tol 1e-12, where
/// the reference's `rtol` is held at 1e-14.
/// It fails when the reference is not ~100 × more accurate than the run:
/// where the error is not proportional to the tolerance, or where the
/// final error happens to be far below the run's typical error.
///
/// The error of a record is `max over quantities of ‖δ‖₂/(1 + ‖ref‖₂)` over
/// the embedded position, the velocity, each body-frame vector and the
/// internal momenta (mixed absolute/relative, like `atol = rtol`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalError {
    /// The largest error of the records.
    pub max: f64,
    /// The error of the last record.
    pub last: f64,
    /// Vector-field evaluations of the reference run (the price of the
    /// estimate, besides the memory of the compared quantities of each
    /// record).
    pub rhs_evals: u64,
}

/// A finding of the quality check of a run's summary.
#[derive(Debug, Clone, PartialEq)]
pub enum QualityWarning {
    /// A record's energy or defect was not finite (`what` names which).
    NonFinite {
        /// `"energy"` or `"constraint defect"`.
        what: &'static str,
    },
    /// The energy drift exceeded `quality.energy_drift`.
    EnergyDrift {
        /// `max |E − E₀| / |E₀|` (absolute when `|E₀| < 1e-12`).
        drift: f64,
        /// The limit.
        limit: f64,
    },
    /// The constraint defect exceeded `quality.defect`.
    Defect {
        /// The largest defect of the records.
        defect: f64,
        /// The limit.
        limit: f64,
    },
    /// The energy projection was skipped on some accepted steps.
    ProjectionSkipped {
        /// How many.
        skipped: u64,
        /// Of how many accepted steps.
        steps: u64,
    },
}

impl fmt::Display for QualityWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QualityWarning::NonFinite { what } => write!(f, "the {what} is not finite in some record: the results are not usable"),
            QualityWarning::EnergyDrift { drift, limit } => {
                write!(f, "the energy drift {drift:.3e} exceeds quality.energy_drift = {limit:.3e} (reduce h or tol, or choose a more accurate method)")
            }
            QualityWarning::Defect { defect, limit } => write!(f, "the constraint defect {defect:.3e} exceeds quality.defect = {limit:.3e}"),
            QualityWarning::ProjectionSkipped { skipped, steps } => write!(
                f,
                "the energy projection was skipped on {skipped} of {steps} steps (energy or its gradient not finite or zero, or no Newton step reduced the residual): the energy is not held there"
            ),
        }
    }
}

impl RunSummary {
    #[doc(hidden)] // public for the internal tests only (`framedyn::__internals`)
    pub fn new(method: &'static str, t0: f64) -> Self {
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
            warnings: Vec::new(),
            global_error: None,
            projection: None,
        }
    }

    /// Judges the run against `(energy_drift, defect)` limits (see
    /// [`QualitySpec`](super::QualitySpec)) and sets [`Self::warnings`]. A run
    /// without records is not judged.
    pub fn judge(&mut self, (energy_limit, defect_limit): (f64, f64)) {
        self.warnings.clear();
        if self.records == 0 {
            return;
        }
        let energy_ok = self.energy_initial.is_finite() && self.energy_drift.is_finite();
        if !energy_ok {
            self.warnings.push(QualityWarning::NonFinite { what: "energy" });
        }
        if !self.max_defect.is_finite() {
            self.warnings.push(QualityWarning::NonFinite { what: "constraint defect" });
        }
        let scale = if self.energy_initial.abs() < 1e-12 { 1.0 } else { self.energy_initial.abs() };
        let drift = self.energy_drift / scale;
        if energy_ok && drift > energy_limit {
            self.warnings.push(QualityWarning::EnergyDrift { drift, limit: energy_limit });
        }
        if self.max_defect.is_finite() && self.max_defect > defect_limit {
            self.warnings.push(QualityWarning::Defect { defect: self.max_defect, limit: defect_limit });
        }
        if let Some(p) = self.projection.filter(|p| p.skipped > 0) {
            self.warnings.push(QualityWarning::ProjectionSkipped { skipped: p.skipped, steps: self.steps });
        }
    }

    /// Notes one state's energy and constraint defect: the first note sets
    /// `E₀`; the drift and the defect keep their maximum, NaN once any value
    /// is NaN.
    pub(crate) fn note(&mut self, energy: f64, defect: f64) {
        if self.records == 0 {
            self.energy_initial = energy;
        }
        self.energy_drift = nan_max(self.energy_drift, (energy - self.energy_initial).abs());
        self.max_defect = nan_max(self.max_defect, defect);
        self.records += 1;
    }

    /// The quality warnings as text (what the command line, the Python
    /// statistics and the sweep's `.npz` show).
    pub fn warning_texts(&self) -> Vec<String> {
        self.warnings.iter().map(|w| w.to_string()).collect()
    }

    /// The names of [`Self::numbers`], in its order.
    pub const NUMBER_NAMES: [&'static str; 14] = [
        "steps",
        "rejected",
        "rhs_evals",
        "records",
        "events",
        "wall_time",
        "energy_initial",
        "energy_drift",
        "relative_energy_drift",
        "momentum_map_drift",
        "max_defect",
        "t_reached",
        "global_error",
        "global_error_final",
    ];

    /// The numeric fields (counts as floats) in the order of
    /// [`Self::NUMBER_NAMES`]: what the Python module's ensemble statistics
    /// and the sweep's `.npz` hold.
    /// `global_error` and `global_error_final` are the estimate's largest
    /// and last-record errors ([`GlobalError`]), NaN when the run did not
    /// ask for one.
    pub fn numbers(&self) -> [f64; 14] {
        [
            self.steps as f64,
            self.rejected as f64,
            self.rhs_evals as f64,
            self.records as f64,
            self.events as f64,
            self.wall_time.as_secs_f64(),
            self.energy_initial,
            self.energy_drift,
            self.relative_energy_drift(),
            self.momentum_map_drift,
            self.max_defect,
            self.t_reached,
            self.global_error.as_ref().map_or(f64::NAN, |g| g.max),
            self.global_error.as_ref().map_or(f64::NAN, |g| g.last),
        ]
    }

    /// `energy_drift / max(|E₀|, 1e-300)`.
    pub fn relative_energy_drift(&self) -> f64 {
        self.energy_drift / self.energy_initial.abs().max(1e-300)
    }
}

/// `max(a, b)`, NaN if either is NaN (a drift that was once undefined
/// stays so).
pub(crate) fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
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
        write!(f, "constraint defect: max {:.3e}", self.max_defect)?;
        if let Some(p) = &self.projection {
            write!(f, "\nprojection:      energy, {} steps projected, {} skipped ({} energy evaluations)", p.projected, p.skipped, p.energy_evals)?;
        }
        if let Some(g) = &self.global_error {
            write!(
                f,
                "\nglobal error:    estimated max {:.2e}, at the end {:.2e} (relative to 1 + |value|; reference run: {} vector-field evaluations)",
                g.max, g.last, g.rhs_evals
            )?;
        }
        if self.warnings.is_empty() {
            write!(f, "\nquality:         ok")
        } else {
            for w in &self.warnings {
                write!(f, "\nquality:         WARNING: {w}")?;
            }
            Ok(())
        }
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
