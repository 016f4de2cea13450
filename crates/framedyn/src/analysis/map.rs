//! Chaos-indicator maps over initial conditions: SALI, MEGNO (with the
//! finite-time maximal exponent MEGNO reports) and/or GALI_k of every member
//! of an ensemble [`Table`] on one base scene, in parallel, returned as
//! columns.
//!
//! The members are those of [`run_ensemble`](crate::scenes::run_ensemble):
//! the base scene with row `i` of the table applied (dotted scene fields,
//! e.g. `initial.position.0`, `body.J.0.1`, `method.h`). Each indicator of
//! a member is computed exactly as [`Scene::sali`], [`Scene::megno`] and
//! [`Scene::gali`] compute it for that scene alone, with the steps (fixed `method.h` or
//! error-controlled `method.rtol`/`atol`), span and `method.max_steps` of
//! the member's own scene, so the columns equal the single calls bit for
//! bit. A member
//! whose scene is invalid or whose run fails gets NaN in the columns of the
//! failed indicator and its [`MemberStatus`] and message; the other members
//! are not affected. Cancellation stops running members within a step and
//! skips the members not started (status [`MemberStatus::Cancelled`]).
//!
//! ```
//! use framedyn::analysis::{chaos_map, ChaosMapOptions};
//! use framedyn::scenes::{example, MemberStatus, Table};
//! use std::sync::atomic::AtomicBool;
//!
//! let mut base = example("s2-point-kepler")?;
//! base.time.t_end = 2.0;
//! let table = Table::new([("initial.r", vec![0.5, 0.6, 0.7])])?;
//! let map = chaos_map(&base, &table, &ChaosMapOptions::default(), &AtomicBool::new(false))?;
//! assert_eq!(map.sali.len(), 3);
//! assert!(map.status.iter().all(|s| *s == MemberStatus::Finished));
//! assert!(map.megno_mean.iter().all(|y| y.is_finite()));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::{AnalysisError, Linearisation};
use crate::scenes::{workers, EnsembleOptions, FieldPath, MemberStatus, Scene, SceneAnalysisError, Table, Workers};

/// Settings of [`chaos_map`]. The steps and span of each member are those of
/// its scene (`method.h` or `method.rtol`/`atol`, `time.t0`, `time.t_end`,
/// which the table may set).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChaosMapOptions {
    /// Compute SALI ([`super::sali()`]).
    pub sali: bool,
    /// Compute MEGNO and the finite-time maximal exponent ([`super::megno()`]).
    pub megno: bool,
    /// Compute GALI_k with this `k` ([`super::gali()`]; `None`: not).
    pub gali: Option<usize>,
    /// GALI's threshold, `1e-300 ≤ threshold < 1`: a member's GALI run stops
    /// when it falls below.
    pub gali_threshold: f64,
    /// GALI modulo the gauge directions ([`GaliOptions::quotient`](super::GaliOptions::quotient)).
    pub gali_quotient: bool,
    /// SALI's threshold, `0 < threshold < 1`: a member's SALI run stops when
    /// it falls below.
    pub threshold: f64,
    /// Seed of the random initial tangent vectors (the same for every
    /// member, as a single call with this seed).
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
    /// Worker threads (`None`: rayon's global pool, one per core); see
    /// [`EnsembleOptions::threads`].
    pub threads: Option<usize>,
    /// Allow more threads than cores.
    pub oversubscribe: bool,
}

impl Default for ChaosMapOptions {
    /// SALI and MEGNO (no GALI; GALI's threshold 1e-12, modulo the gauge
    /// directions), threshold 1e-8, seed 1, the default linearisation, one
    /// thread per core.
    fn default() -> Self {
        ChaosMapOptions { sali: true, megno: true, gali: None, gali_threshold: 1e-12, gali_quotient: true, threshold: 1e-8, seed: 1, linearisation: Linearisation::default(), threads: None, oversubscribe: false }
    }
}

impl ChaosMapOptions {
    /// Checks the options once for the whole map: an error names the field
    /// and its allowed range.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        if !(self.sali || self.megno || self.gali.is_some()) {
            return Err(AnalysisError::invalid("indicators", "none", "at least one of sali, megno and gali"));
        }
        if let Some(k) = self.gali {
            if k < 2 {
                return Err(AnalysisError::invalid("k", k, "≥ 2 (and at most the phase space's dimension, or the state group's without the quotient)"));
            }
            if !(self.gali_threshold >= 1e-300 && self.gali_threshold < 1.0) {
                return Err(AnalysisError::invalid("gali_threshold", self.gali_threshold, "≥ 1e-300 and < 1"));
            }
        }
        if !(self.threshold > 0.0 && self.threshold < 1.0) {
            return Err(AnalysisError::invalid("threshold", self.threshold, "between 0 and 1 (exclusive)"));
        }
        self.linearisation.validate()?;
        if let Some(n) = self.threads {
            if n == 0 || n > EnsembleOptions::MAX_THREADS {
                return Err(AnalysisError::invalid("threads", n, format!("between 1 and {}", EnsembleOptions::MAX_THREADS)));
            }
        }
        Ok(())
    }
}

/// The indicators of every member, one column per quantity (index: the
/// table's member). A column of an indicator not asked for, or of a member
/// whose indicator failed, holds NaN (steps: 0).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChaosMap {
    /// SALI at the end of the run ([`SaliEstimate::sali`](super::SaliEstimate::sali)).
    pub sali: Vec<f64>,
    /// The smallest SALI of the run.
    pub sali_min: Vec<f64>,
    /// The time SALI fell below the threshold, NaN if it did not.
    pub chaotic_at: Vec<f64>,
    /// Steps of SALI's run (it stops at the threshold).
    pub sali_steps: Vec<u64>,
    /// MEGNO `Y` at the end ([`MegnoEstimate::megno`](super::MegnoEstimate::megno)).
    pub megno: Vec<f64>,
    /// Its mean `⟨Y⟩` at the end: → 2 regular, ≈ `λ₁t/2` chaotic.
    pub megno_mean: Vec<f64>,
    /// The slope of `⟨Y⟩` over the second half of the run (≈ `λ₁/2` chaotic).
    pub megno_slope: Vec<f64>,
    /// The finite-time maximal exponent of MEGNO's tangent vector.
    pub lyapunov: Vec<f64>,
    /// Steps of MEGNO's run.
    pub megno_steps: Vec<u64>,
    /// `log₁₀ GALI_k` at the end of the run ([`GaliEstimate::log10`](super::GaliEstimate::log10)).
    pub gali_log10: Vec<f64>,
    /// The time GALI_k fell below its threshold, NaN if it did not.
    pub gali_below_at: Vec<f64>,
    /// Steps of GALI's run (it stops at the threshold).
    pub gali_steps: Vec<u64>,
    /// How each member ended: [`MemberStatus::Finished`],
    /// [`MemberStatus::Invalid`] (its scene cannot be analysed),
    /// [`MemberStatus::Failed`] (an indicator's run failed) or
    /// [`MemberStatus::Cancelled`].
    pub status: Vec<MemberStatus>,
    /// Why a member was invalid, failed or was cancelled (`member i: …`).
    pub errors: Vec<Option<String>>,
}

impl ChaosMap {
    /// The number of members.
    pub fn len(&self) -> usize {
        self.status.len()
    }

    /// True if there are no members.
    pub fn is_empty(&self) -> bool {
        self.status.is_empty()
    }
}

/// One member's values, in the order of the columns.
struct Row {
    sali: [f64; 3],
    sali_steps: u64,
    megno: [f64; 4],
    megno_steps: u64,
    gali: [f64; 2],
    gali_steps: u64,
    status: MemberStatus,
    error: Option<String>,
}

impl Row {
    fn empty(status: MemberStatus, error: Option<String>) -> Row {
        Row { sali: [f64::NAN; 3], sali_steps: 0, megno: [f64::NAN; 4], megno_steps: 0, gali: [f64::NAN; 2], gali_steps: 0, status, error }
    }

    /// Records the failure of indicator `what`; the first failure decides
    /// the status and the message. True if it ends the member: an invalid
    /// scene or a cancellation (a failed run does not keep the next
    /// indicator from running).
    fn fail(&mut self, i: usize, what: &str, e: &SceneAnalysisError) -> bool {
        if self.error.is_none() {
            self.status = classify(e);
            self.error = Some(format!("member {i}: {what}: {e}"));
        }
        matches!(e, SceneAnalysisError::Scene(_) | SceneAnalysisError::Analysis(AnalysisError::Cancelled { .. }))
    }
}

/// What an indicator's error makes of the member: invalid (its scene, or
/// an option its scene makes out of range), cancelled or failed.
fn classify(e: &SceneAnalysisError) -> MemberStatus {
    match e {
        SceneAnalysisError::Scene(_) | SceneAnalysisError::Analysis(AnalysisError::InvalidParameter { .. }) => MemberStatus::Invalid,
        SceneAnalysisError::Analysis(AnalysisError::Cancelled { .. }) => MemberStatus::Cancelled,
        SceneAnalysisError::Analysis(_) => MemberStatus::Failed,
    }
}

/// Member `i` of `table` on `base` (`scene`: a scratch copy of `base` that
/// every member overwrites in the same fields, so it is base + row `i`).
fn member(scene: &mut Scene, columns: &[(FieldPath, &[f64])], i: usize, opts: &ChaosMapOptions, cancel: &AtomicBool) -> Row {
    if cancel.load(Ordering::Relaxed) {
        return Row::empty(MemberStatus::Cancelled, Some(format!("member {i}: cancelled before it started")));
    }
    for (path, values) in columns {
        if let Err(e) = path.apply(scene, values[i]) {
            return Row::empty(MemberStatus::Invalid, Some(format!("{e} (table column `{path}`, member {i})")));
        }
    }
    let mut row = Row::empty(MemberStatus::Finished, None);
    if opts.sali {
        let r = scene.sali_options().map_err(SceneAnalysisError::from).and_then(|mut o| {
            o.threshold = opts.threshold;
            o.seed = opts.seed;
            o.linearisation = opts.linearisation;
            scene.sali(&o, cancel)
        });
        match r {
            Ok(e) => {
                row.sali = [e.sali, e.min, e.chaotic_at.unwrap_or(f64::NAN)];
                row.sali_steps = e.steps as u64;
            }
            Err(e) => {
                if row.fail(i, "sali", &e) {
                    return row;
                }
            }
        }
    }
    if opts.megno {
        let r = scene.megno_options().map_err(SceneAnalysisError::from).and_then(|mut o| {
            o.seed = opts.seed;
            o.linearisation = opts.linearisation;
            scene.megno(&o, cancel)
        });
        match r {
            Ok(e) => {
                row.megno = [e.megno, e.mean, e.slope, e.lyapunov];
                row.megno_steps = e.steps as u64;
            }
            Err(e) => {
                if row.fail(i, "megno", &e) {
                    return row;
                }
            }
        }
    }
    if let Some(k) = opts.gali {
        let r = scene.gali_options(k).map_err(SceneAnalysisError::from).and_then(|mut o| {
            o.threshold = opts.gali_threshold;
            o.quotient = opts.gali_quotient;
            o.seed = opts.seed;
            o.linearisation = opts.linearisation;
            scene.gali(&o, cancel)
        });
        match r {
            Ok(e) => {
                row.gali = [e.log10, e.below_at.unwrap_or(f64::NAN)];
                row.gali_steps = e.steps as u64;
            }
            Err(e) => {
                row.fail(i, "gali", &e);
            }
        }
    }
    row
}

/// SALI, MEGNO and/or GALI_k of every member of `table` on `base`, in parallel (see
/// the [module documentation](self)). Fails only for bad options
/// ([`ChaosMapOptions::validate`]); everything about a member is in its
/// row of the columns, its status and its message.
pub fn chaos_map(base: &Scene, table: &Table, opts: &ChaosMapOptions, cancel: &AtomicBool) -> Result<ChaosMap, AnalysisError> {
    opts.validate()?;
    let n = table.len();
    let columns: Vec<(FieldPath, &[f64])> = table
        .names()
        .map(|name| Ok((FieldPath::parse(name).map_err(|e| AnalysisError::invalid("table", e, "a table of scene fields"))?, table.column(name).unwrap_or(&[]))))
        .collect::<Result<_, AnalysisError>>()?;
    let one = |scene: &mut Scene, i: usize| member(scene, &columns, i, opts, cancel);
    let workers = workers(opts.threads, n, opts.oversubscribe)
        .map_err(|e| AnalysisError::invalid("threads", opts.threads.unwrap_or(0), format!("a count the machine can start ({e})")))?;
    let parallel = || (0..n).into_par_iter().map_init(|| base.clone(), one).collect();
    let rows: Vec<Row> = match workers {
        Workers::Serial => {
            let mut scene = base.clone();
            (0..n).map(|i| one(&mut scene, i)).collect()
        }
        Workers::Pool(pool) => pool.install(parallel),
        Workers::Global => parallel(),
    };
    let mut map = ChaosMap::default();
    for r in rows {
        map.sali.push(r.sali[0]);
        map.sali_min.push(r.sali[1]);
        map.chaotic_at.push(r.sali[2]);
        map.sali_steps.push(r.sali_steps);
        map.megno.push(r.megno[0]);
        map.megno_mean.push(r.megno[1]);
        map.megno_slope.push(r.megno[2]);
        map.lyapunov.push(r.megno[3]);
        map.megno_steps.push(r.megno_steps);
        map.gali_log10.push(r.gali[0]);
        map.gali_below_at.push(r.gali[1]);
        map.gali_steps.push(r.gali_steps);
        map.status.push(r.status);
        map.errors.push(r.error);
    }
    Ok(map)
}
