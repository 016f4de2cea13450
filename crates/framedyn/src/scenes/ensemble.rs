//! Ensembles: one base scene and a [`Table`] of `N` members (columns named
//! by dotted scene fields, [`FieldPath`]), run in parallel into one columnar
//! [`Ensemble`] — the typed API under Python's `solve_batch(scene, table)`
//! and the CLI's `sweep`.
//!
//! The table is validated once (names, equal lengths, finite values); each
//! member is the base scene with its row applied, run exactly as
//! [`Scene::build`] and [`Simulation::run`] would run it alone (the same
//! model, plan and driver, so a member's records equal those of the single
//! run bit for bit). Each worker thread builds one simulation in full and
//! then rebuilds only its model and initial state for each further member
//! (and its plan if the table sets `method.*` or `time.*`): the columns and
//! events, which depend on no numeric field, are not made again, and no
//! scene is cloned per member. A member that cannot be built or whose integration fails is
//! reported on that member only ([`MemberStatus`], with its message and,
//! for a failed run, the records up to the failure); the others are not
//! affected.
//!
//! ```
//! use framedyn::scenes::{example, run_ensemble, EnsembleOptions, Keep, MemberStatus, Table, DEFAULT_SCENE};
//! use std::sync::atomic::AtomicBool;
//!
//! let base = example(DEFAULT_SCENE)?;
//! let table = Table::new([("initial.r", vec![0.5, 0.6, 0.7]), ("initial.spin", vec![0.0, 0.02, 0.04])])?;
//! let opts = EnsembleOptions { keep: Keep::Final, ..Default::default() };
//! let out = run_ensemble(&base, &table, &opts, None, &AtomicBool::new(false), &|_| {})?;
//! assert_eq!(out.len(), 3);
//! assert!(out.members.iter().all(|m| m.status == MemberStatus::Finished));
//! assert_eq!(out.records(1).len(), out.columns.len()); // one record: the final state
//! # Ok::<(), framedyn::scenes::SceneError>(())
//! ```

use std::io;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;

use rayon::prelude::*;

use super::error::{RunError, SceneError};
use super::fields::FieldPath;
use super::potential::UserFunctions;
use super::scene::Scene;
use super::sink::{Column, EventHit, RecordSink};
use super::simulation::Simulation;
use super::summary::{RunSummary, SceneStop};

/// The members of an ensemble: named columns of equal length `N`, each a
/// numeric scene field by dotted path.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    len: usize,
    columns: Vec<(FieldPath, Vec<f64>)>,
}

impl Table {
    /// A table from `(path, values)` columns. Fails, naming the column, for
    /// no columns, zero members, an unknown or repeated path, unequal
    /// lengths, or a non-finite value (naming the first such member).
    pub fn new<S: AsRef<str>>(columns: impl IntoIterator<Item = (S, Vec<f64>)>) -> Result<Table, SceneError> {
        let mut out: Vec<(FieldPath, Vec<f64>)> = Vec::new();
        for (name, values) in columns {
            let name = name.as_ref();
            let path = FieldPath::parse(name)?;
            if out.iter().any(|(p, _)| p.as_str() == name) {
                return Err(SceneError::invalid(format!("table column `{name}`"), "(repeated)", "each column may appear once"));
            }
            if let Some((first, v)) = out.first() {
                if values.len() != v.len() {
                    return Err(SceneError::invalid(
                        format!("table column `{name}`"),
                        format!("{} members", values.len()),
                        format!("every column must have the length of `{first}` ({} members)", v.len()),
                    ));
                }
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(SceneError::invalid(format!("table column `{name}`, member {i}"), values[i], "must be a finite number"));
            }
            out.push((path, values));
        }
        let len = match out.first() {
            None => return Err(SceneError::invalid("table", "(no columns)", "at least one column (a dotted scene field such as `initial.r`)")),
            Some((_, v)) => v.len(),
        };
        if len == 0 {
            return Err(SceneError::invalid("table", "(0 members)", "at least one member (columns of length ≥ 1)"));
        }
        Ok(Table { len, columns: out })
    }

    /// The number of members `N`.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false (a table has at least one member).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The column names, in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.columns.iter().map(|(p, _)| p.as_str())
    }

    /// The values of the column `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns.iter().find(|(p, _)| p.as_str() == name).map(|(_, v)| v.as_slice())
    }

    /// Member `i`: the base scene with row `i` applied (not yet validated).
    /// Errors name the column and the member.
    pub fn member(&self, base: &Scene, i: usize) -> Result<Scene, SceneError> {
        let mut scene = base.clone();
        for (path, values) in &self.columns {
            path.apply(&mut scene, values[i]).map_err(|e| at_member(e, i))?;
        }
        Ok(scene)
    }

    /// The column a build error of member `i` comes from, if a column set
    /// that field.
    fn blame(&self, err: &SceneError) -> Option<&str> {
        let field = err.path()?.replace('[', ".").replace(']', "");
        self.names().find(|n| n.replace('[', ".").replace(']', "") == field)
    }
}

/// `err` with ` (member i)` appended to its field path.
fn at_member(err: SceneError, i: usize) -> SceneError {
    match err {
        SceneError::Invalid { path, value, allowed, location } => SceneError::Invalid { path: format!("{path} (member {i})"), value, allowed, location },
        SceneError::Parse { format, path, message, location } => SceneError::Parse { format, path: format!("{path} (member {i})"), message, location },
        other => other,
    }
}

/// What an ensemble keeps of each member's run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Keep {
    /// Every record the scene's `[output]` asks for.
    #[default]
    All,
    /// `k ≥ 2` equally spaced records including both ends (replaces the
    /// scene's `every`/`times`/`samples`).
    Samples(u64),
    /// The final record only (and the summary).
    Final,
}

/// How an ensemble runs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnsembleOptions {
    /// What to keep of each member.
    pub keep: Keep,
    /// Worker threads (`None`: rayon's global pool, one per core). At most
    /// [`EnsembleOptions::MAX_THREADS`]; never more than the members, nor
    /// more than the machine's cores unless `oversubscribe`
    /// ([`worker_threads`]). With one worker thread the members run on the
    /// calling thread, one after another.
    pub threads: Option<usize>,
    /// Allow more threads than cores (the members are CPU-bound: more
    /// threads than cores only add switching).
    pub oversubscribe: bool,
}

impl EnsembleOptions {
    /// The largest thread count accepted.
    pub const MAX_THREADS: usize = 1024;
}

/// The worker threads actually started for `requested` threads and
/// `members` members: at most one per member, and at most one per core
/// (`std::thread::available_parallelism`) unless `oversubscribe`.
pub fn worker_threads(requested: usize, members: usize, oversubscribe: bool) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let n = requested.min(members.max(1)).min(EnsembleOptions::MAX_THREADS);
    if oversubscribe {
        n.max(1)
    } else {
        n.min(cores).max(1)
    }
}

/// Where the members of an ensemble run (see [`workers`]).
pub(crate) enum Workers {
    /// On the calling thread, one after another (one worker asked for or
    /// possible).
    Serial,
    /// On a pool of their own, of [`worker_threads`] threads.
    Pool(rayon::ThreadPool),
    /// On rayon's global pool (no thread count given).
    Global,
}

/// The workers for `threads` (checked by the caller: `None` or 1 …
/// [`EnsembleOptions::MAX_THREADS`]) and `members` members. An error is a
/// pool the machine cannot start.
pub(crate) fn workers(threads: Option<usize>, members: usize, oversubscribe: bool) -> Result<Workers, rayon::ThreadPoolBuildError> {
    match threads.map(|n| worker_threads(n, members, oversubscribe)) {
        None => Ok(Workers::Global),
        Some(1) => Ok(Workers::Serial),
        Some(t) => rayon::ThreadPoolBuilder::new().num_threads(t).build().map(Workers::Pool),
    }
}

/// How a member ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemberStatus {
    /// Reached `t_end`.
    Finished,
    /// A terminal event stopped it.
    Event,
    /// Cancelled (the records up to the cancellation are kept), or not
    /// started before the cancellation.
    Cancelled,
    /// The integration failed (the records up to the last good state are
    /// kept, the message says why).
    Failed,
    /// The member's scene is invalid (not run; the message names the field,
    /// the column and the member).
    Invalid,
}

impl MemberStatus {
    /// `"finished"`, `"event"`, `"cancelled"`, `"failed"` or `"invalid"`.
    pub fn name(self) -> &'static str {
        match self {
            MemberStatus::Finished => "finished",
            MemberStatus::Event => "event",
            MemberStatus::Cancelled => "cancelled",
            MemberStatus::Failed => "failed",
            MemberStatus::Invalid => "invalid",
        }
    }

    /// The status code stored in columnar outputs (the order of the variants).
    pub fn code(self) -> u8 {
        self as u8
    }
}

/// One member's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct MemberOutcome {
    /// How it ended.
    pub status: MemberStatus,
    /// The run's summary (`None` for an invalid member).
    pub summary: Option<RunSummary>,
    /// Why it failed or was invalid.
    pub error: Option<String>,
}

/// The columnar result of an ensemble: the records of every member in one
/// row-major buffer, member `i`'s records being rows
/// `offsets[i] .. offsets[i + 1]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ensemble {
    /// The record columns (empty if no member could be built).
    pub columns: Vec<Column>,
    /// `(N, E)` of the `frame` group (see [`super::Simulation::frame_shape`]).
    pub frame_shape: (usize, usize),
    /// All records, row-major.
    pub data: Vec<f64>,
    /// Record offsets, `N + 1` of them.
    pub offsets: Vec<usize>,
    /// The located events of every member, with the member index.
    pub events: Vec<(usize, EventHit)>,
    /// Per member: status, summary, error.
    pub members: Vec<MemberOutcome>,
}

impl Ensemble {
    /// The number of members.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True if there are no members.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// Member `i`'s records, row-major.
    pub fn records(&self, i: usize) -> &[f64] {
        let n = self.columns.len();
        &self.data[self.offsets[i] * n..self.offsets[i + 1] * n]
    }

    /// The common number of records per member, if every member has the
    /// same (the stacked `(N, records, …)` layout), else `None`.
    pub fn uniform_records(&self) -> Option<usize> {
        let first = self.offsets[1] - self.offsets[0];
        self.offsets.windows(2).all(|w| w[1] - w[0] == first).then_some(first)
    }
}

/// A member's sink: all records, or the last one.
struct MemberSink {
    last_only: bool,
    data: Vec<f64>,
    rows: usize,
    events: Vec<EventHit>,
}

impl RecordSink for MemberSink {
    fn columns(&mut self, _columns: &[Column]) -> io::Result<()> {
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        if self.last_only {
            self.data.clear();
            self.rows = 0;
        }
        self.data.extend_from_slice(row);
        self.rows += 1;
        Ok(())
    }
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }
    fn last_only(&self) -> bool {
        self.last_only
    }
}

struct MemberRun {
    data: Vec<f64>,
    rows: usize,
    events: Vec<EventHit>,
    outcome: MemberOutcome,
}

fn invalid(error: String) -> MemberRun {
    MemberRun { data: Vec::new(), rows: 0, events: Vec::new(), outcome: MemberOutcome { status: MemberStatus::Invalid, summary: None, error: Some(error) } }
}

/// The record columns and frame shape of the ensemble, taken from the
/// first member built.
type Layout = (Vec<Column>, (usize, usize));

/// One worker's members: a scratch copy of the base scene that each
/// member's row overwrites in place (every member sets the same fields, so
/// the scratch scene is exactly base + row), and the simulation of the
/// last member built, whose model and initial state are rebuilt for the
/// next member ([`Simulation::rebuild`]) — its plan too if the table sets
/// `method.*` or `time.*` fields — instead of building the whole scene
/// again (columns, events). A member is built from scratch only until the
/// first one succeeds.
struct Worker<'a> {
    table: &'a Table,
    keep: Keep,
    scene: Scene,
    sim: Option<Simulation>,
    replan: bool,
}

impl<'a> Worker<'a> {
    fn new(base: &Scene, table: &'a Table, keep: Keep) -> Worker<'a> {
        let mut scene = base.clone();
        if let Keep::Samples(k) = keep {
            scene.output.samples = Some(k);
            scene.output.every = None;
            scene.output.times = None;
        }
        let replan = table.columns.iter().any(|(p, _)| p.is_plan());
        Worker { table, keep, scene, sim: None, replan }
    }

    /// Member `i`'s simulation, ready to run, or the message of why it is invalid.
    fn build(&mut self, i: usize, user: Option<&UserFunctions>) -> Result<&mut Simulation, String> {
        for (path, values) in &self.table.columns {
            path.apply(&mut self.scene, values[i]).map_err(|e| at_member(e, i).to_string())?;
        }
        let built = match self.sim.take() {
            // A failed rebuild leaves the simulation as it was: kept for the next member.
            Some(mut sim) => match sim.rebuild(&self.scene, user.cloned(), self.replan) {
                Ok(()) => Ok(sim),
                Err(e) => {
                    self.sim = Some(sim);
                    Err(e)
                }
            },
            None => match user {
                None => self.scene.build(),
                Some(u) => self.scene.build_with_user(u.clone()),
            },
        };
        match built {
            Ok(sim) => Ok(self.sim.insert(sim)),
            Err(e) => Err(match self.table.blame(&e) {
                Some(col) => format!("{e} (table column `{col}`, member {i})"),
                None => format!("{e} (member {i})"),
            }),
        }
    }

    fn run(&mut self, i: usize, user: Option<&UserFunctions>, cancel: &AtomicBool, layout: &OnceLock<Layout>) -> MemberRun {
        let keep = self.keep;
        let sim = match self.build(i, user) {
            Ok(sim) => sim,
            Err(msg) => return invalid(msg),
        };
        layout.get_or_init(|| (sim.columns().to_vec(), sim.frame_shape()));
        if cancel.load(Ordering::Relaxed) {
            let mut summary = RunSummary::new(sim.method_name(), sim.span().0);
            summary.stop = SceneStop::Cancelled;
            let outcome = MemberOutcome { status: MemberStatus::Cancelled, summary: Some(summary), error: None };
            return MemberRun { data: Vec::new(), rows: 0, events: Vec::new(), outcome };
        }
        let width = sim.columns().len();
        let rows = if keep == Keep::Final { 1 } else { sim.record_bound().map_or(0, |n| n.min(1 << 16) as usize) };
        let mut sink = MemberSink { last_only: keep == Keep::Final, data: Vec::with_capacity(rows * width), rows: 0, events: Vec::new() };
        let (summary, error) = match sim.run(&mut sink, cancel, &mut |_| {}) {
            Ok(s) => (s, None),
            Err(f) => (f.summary, Some(f.error)),
        };
        let status = match (&error, &summary.stop) {
            (Some(_), _) => MemberStatus::Failed,
            (None, SceneStop::Cancelled) => MemberStatus::Cancelled,
            (None, SceneStop::Event(_)) => MemberStatus::Event,
            (None, _) => MemberStatus::Finished,
        };
        let error = error.map(|e: RunError| format!("member {i}: {e}"));
        MemberRun { data: sink.data, rows: sink.rows, events: sink.events, outcome: MemberOutcome { status, summary: Some(summary), error } }
    }
}

/// Runs every member of `table` on `base` in parallel (see the [module
/// docs](crate::scenes)). `user(i)` gives member `i`'s user potential, if the scene
/// uses one (a separate instance per member, so that one member's failure
/// inside it cannot reach another). `cancel` stops running members within a
/// few hundred steps and skips those not started (status
/// [`MemberStatus::Cancelled`]); `done(k)` is called after each finished
/// member with the number finished so far (from the worker threads).
///
/// Fails only for bad options; everything about a member is in its
/// [`MemberOutcome`].
pub fn run_ensemble(
    base: &Scene,
    table: &Table,
    opts: &EnsembleOptions,
    user: Option<&(dyn Fn(usize) -> UserFunctions + Sync)>,
    cancel: &AtomicBool,
    done: &(dyn Fn(usize) + Sync),
) -> Result<Ensemble, SceneError> {
    let mut whole = None;
    run_ensemble_blocks(base, table, opts, user, cancel, done, table.len(), &mut |_, block| {
        whole = Some(block);
        ControlFlow::Continue(())
    })?;
    whole.ok_or_else(|| SceneError::invalid("table", "(0 members)", "at least one member"))
}

/// [`run_ensemble`] in blocks of at most `block` consecutive members, for
/// callers that stream the records instead of keeping them all (the
/// command line's `sweep`): `out(first, ensemble)` receives each block as
/// soon as all its members are done, in order — member `k` of the block
/// is member `first + k` of the table, and messages and event member
/// indices name the table's member. Members of one block run in parallel;
/// the blocks one after another. `out` returning `Break` stops before the
/// next block. Fails only for bad options.
#[allow(clippy::too_many_arguments)]
pub fn run_ensemble_blocks(
    base: &Scene,
    table: &Table,
    opts: &EnsembleOptions,
    user: Option<&(dyn Fn(usize) -> UserFunctions + Sync)>,
    cancel: &AtomicBool,
    done: &(dyn Fn(usize) + Sync),
    block: usize,
    out: &mut dyn FnMut(usize, Ensemble) -> ControlFlow<()>,
) -> Result<(), SceneError> {
    if let Keep::Samples(k) = opts.keep {
        if k < 2 {
            return Err(SceneError::invalid("samples", k, "must be ≥ 2 (both ends of the span)"));
        }
    }
    if block == 0 {
        return Err(SceneError::invalid("block", 0, "must be ≥ 1 member"));
    }
    // One worker thread: the members run on the calling thread, one after
    // another (no pool; a user potential that calls back into an
    // interpreter is called from the thread that ran the ensemble).
    if let Some(n) = opts.threads {
        if n == 0 || n > EnsembleOptions::MAX_THREADS {
            return Err(SceneError::invalid("threads", n, format!("must be between 1 and {}", EnsembleOptions::MAX_THREADS)));
        }
    }
    let workers = workers(opts.threads, table.len(), opts.oversubscribe)
        .map_err(|e| SceneError::invalid("threads", opts.threads.unwrap_or(0), format!("cannot start the threads: {e}")))?;
    let finished = AtomicUsize::new(0);
    let mut own = Worker::new(base, table, opts.keep);
    for first in (0..table.len()).step_by(block) {
        let members = first..(first + block).min(table.len());
        let layout = OnceLock::new();
        let one = |w: &mut Worker, i: usize| {
            let u = user.map(|f| f(i));
            let r = w.run(i, u.as_ref(), cancel, &layout);
            done(finished.fetch_add(1, Ordering::Relaxed) + 1);
            r
        };
        let work = || members.clone().into_par_iter().map_init(|| Worker::new(base, table, opts.keep), one).collect::<Vec<_>>();
        let runs: Vec<MemberRun> = match &workers {
            Workers::Serial => members.clone().map(|i| one(&mut own, i)).collect(),
            Workers::Pool(p) => p.install(work),
            Workers::Global => work(),
        };
        let (columns, frame_shape) = layout.into_inner().unwrap_or_default();
        let total: usize = runs.iter().map(|r| r.data.len()).sum();
        let mut ens = Ensemble { columns, frame_shape, data: Vec::with_capacity(total), offsets: Vec::with_capacity(runs.len() + 1), events: Vec::new(), members: Vec::with_capacity(runs.len()) };
        ens.offsets.push(0);
        for (k, r) in runs.into_iter().enumerate() {
            ens.data.extend_from_slice(&r.data);
            ens.offsets.push(ens.offsets[k] + r.rows);
            ens.events.extend(r.events.into_iter().map(|e| (first + k, e)));
            ens.members.push(r.outcome);
        }
        if out(first, ens).is_break() {
            break;
        }
    }
    Ok(())
}
