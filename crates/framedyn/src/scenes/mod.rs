//! Scenes: a whole simulation — manifold, body, potential, initial state,
//! method, time span and output — described in TOML or JSON, validated with
//! messages that name the field, the value, what is allowed and the line and
//! column, and run through one type-erased [`Simulation`] that streams its
//! records to a [`RecordSink`]. The command-line tool `framedyn` and the
//! Python module are thin layers over this module.
//!
//! ```
//! use framedyn::scenes::{Scene, MemorySink};
//! use std::sync::atomic::AtomicBool;
//!
//! let scene = Scene::from_toml_str(r#"
//!     [manifold]
//!     kind = "S2"
//!     radius = 1.0
//!     [body]
//!     kind = "gyroscope"
//!     inertia = 0.2
//!     [initial]
//!     r = 0.5
//!     phi = 0.0
//!     r_dot = -1.0
//!     spin = 0.05
//!     [method]
//!     name = "rk4"
//!     h = 0.01
//!     [time]
//!     t_end = 1.0
//!     [output]
//!     every = 10
//!     quantities = ["position", "energy"]
//! "#)?;
//! let mut sim = scene.build()?;
//! let mut sink = MemorySink::default();
//! let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
//! assert_eq!(summary.steps, 100);
//! assert_eq!(sink.rows.len(), 11);
//! assert!(summary.energy_drift < 1e-8);
//! # Ok::<(), framedyn::scenes::SceneError>(())
//! ```
//!
//! # Scene files
//!
//! Tables (every one rejects unknown fields): `[manifold]` (`kind` = `S2`,
//! `H2`, `T2`, `S3`; `radius`, or `L`/`R` for the torus), `[body]` (`kind` =
//! `point`, `gyroscope`, `affine`, `incompressible`, `weyl`, `dilatation`;
//! `mass`, `inertia` or `J`, `signature` = `riemannian`/`lorentz`),
//! `[potential]` (see [`PotentialKind`]), `[initial]` (see [`InitialSpec`]:
//! the paper's coordinates `r, phi` / `theta, phi` / `r1, r2, r3` and their
//! `_dot` rates, or `position`/`velocity` arrays in the embedding; `alpha`,
//! `omega`, `spin`, `orientation`, `frame`, `rho`, `rho_dot` for the body),
//! `[method]` (`name` from [`METHOD_NAMES`]; `h` for fixed steps, or `rtol`,
//! `atol` with `dopri5`; `max_steps`; `newton_tol`, `newton_max_iter` with
//! `implicit_midpoint`), `[time]` (`t0`, `t_end`), `[output]`
//! (`every`, `times` or `samples`; `quantities`; `format` = `csv`/`npz`;
//! `path`), `[[events]]` (see [`EventSpec`]). The embedded examples
//! ([`EXAMPLES`]) cover every manifold × body and every potential family.
//!
//! # Methods
//!
//! | `name` | method | models |
//! |---|---|---|
//! | `lie_euler`, `heun`, `kutta3`, `rk4`, `butcher6` | RKMK of order 1, 2, 3, 4, 6 ([`Rkmk`]) | all |
//! | `dopri5` | RKMK Dormand–Prince 5(4): fixed `h`, or adaptive with `rtol`/`atol` (the tolerance bounds the local error per step; the global error can exceed it by the flow's amplification, 14–117× on the S² and T² gyroscope references) | all |
//! | `dop853` | RKMK Dormand–Prince 8(5,3) (Hairer's DOP853): fixed `h`, or adaptive with `rtol`/`atol` — global error ≤ 8.1 × tol on every reference trajectory (`tests/suite/integrators_dop853.rs`); use it when tol should bound the final error | all |
//! | `strang`, `yoshida4`, `suzuki4`, `blanes_moan4`, `yoshida6`, `blanes_moan6`, `blanes_moan_rkn4`, `blanes_moan_rkn6` | symplectic splittings with exact free flows ([`Splitting`]): bounded energy error, momentum maps to round-off | points and gyroscopes on S², H² (both signatures), S³ |
//! | `implicit_midpoint` | the symmetric implicit Lie midpoint rule ([`ImplicitMidpoint`]), Newton options `newton_tol` (default 1e-14), `newton_max_iter` (30) | all |
//!
//! A method a model does not support is refused by [`Scene::validate`]
//! (`framedyn validate`) with an error naming `method.name`, the value and
//! the methods allowed for that manifold × body ([`Scene::allowed_methods`]).
//! The coordinate baselines ([`baseline`](crate::method::baseline)) are not
//! scene methods (their state is the chart, not the bundle): use them from
//! Rust.
//!
//! # Events
//!
//! Each `[[events]]` entry is a built-in event function `g` of the record:
//! `kind = "plane"` (`normal·x − offset`, embedding position: Poincaré
//! sections), `"distance"` (`|x − point| − distance`, Euclidean in the
//! embedding: pole passages), `"column"` (`column − value` for any record
//! column: the paper's coordinates, `energy`, …), with `direction` =
//! `rising`/`falling`/`either` and `terminal`. Crossings are located by
//! Brent's method on the method's own continuous extension — a sub-step of
//! the method from the start of the step (fixed steps), or the dense output
//! of adaptive `dopri5` — so the time is as accurate as the trajectory
//! (round-off on exact flows; tested on a geodesic to 1e-10 in
//! `tests/suite/scenes.rs`). They arrive at [`RecordSink::event`]
//! ([`MemorySink::events`]; the CLI writes `STEM.events.csv`); a terminal
//! event ends the run with [`SceneStop::Event`] at the event's state. Rust
//! and Python users add their own functions with [`Simulation::add_event`].
//!
//! # Columns and units
//!
//! Units are those of the scene: `L` (length: radii, positions), `T` (time),
//! `M` (mass); angles in radians. In column order:
//!
//! | group | columns | unit |
//! |---|---|---|
//! | (always) | `t` | T |
//! | `position` | `x0 … x{E−1}`: embedding position (ℝ³; ℝ⁴ for S³; H² in Minkowski ℝ^{2,1}) | L |
//! | `velocity` | `v0 …`: embedding velocity | L/T |
//! | `frame` | `e1_0 … eN_{E−1}`: body frame vectors, embedding components (not for points) | 1 |
//! | `coordinates` | the paper's chart coordinates `r, phi` (S², H²), `theta, phi` (T²), `r1, r2, r3` (S³) and their rates `*_dot` (NaN where the chart is singular, e.g. at a pole); gyroscope on a surface: `alpha` (angle of `e₁` from the paper's frame `E_r`); affine bodies: `stretch_1 …` (singular values of `ρ`) | L or rad; L/T or rad/T; rad; 1 |
//! | `momenta` | gyroscope `spin` (2-D) or `spin_1..3` (S³, body components); affine bodies `k_AB` (hypermomentum `ρJρ̇ᵀ`) | M L²/T |
//! | `energy` | `energy`: `T + V` | M L²/T² |
//! | `momentum_map` | `p_phi` (rotations about the ambient z axis; S², H², T²) or `J_ab` (the rotation in the `(a, b)` plane of ℝ⁴; S³) | M L²/T |
//! | `defect` | `defect`: distance of the state from its constraints | 1 |

mod engine;
pub mod error;
mod examples;
mod locate;
pub mod potential;
pub mod spec;

pub use error::{Location, RunError, SceneError};
pub use examples::{example, EXAMPLES, DEFAULT_SCENE};
pub use potential::{Potential2, Potential3, SeparableSeries, Series, UserFunctions, UserGradientFn, UserPotential, UserPotentialFn};
pub use spec::*;

use std::fmt;
use std::io;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use nalgebra::{SMatrix, SVector};

use crate::body::{Affine, Dilatation, Gyroscope, Incompressible, Point, Signature, Weyl};
use crate::bundle::FrameBundle;
use crate::dynamics::affine::{AffineBodyModel, BodyState, Unconstrained};
use crate::dynamics::constrained::{Conformal, Isochoric, PureDilatation};
use crate::dynamics::point::{bundle_element_at, tangent_components};
use crate::dynamics::{Gyroscope2Model, Gyroscope2State, Gyroscope3Model, PointModel, PointState, System};
use crate::lie::{LieGroup, So2, So3};
use crate::manifold::{Hyperbolic2, Sphere2, Sphere3, Torus2};
use crate::method::{ImplicitMidpoint, Rkmk, Splitting};
use crate::potential::{
    Central, Centre, CosineFamily, Elastic, InvariantPotential, Kepler, NeoHookean, Oscillator, Separable,
    StVenantKirchhoff, TorusAngle,
};
use crate::solve::SolveError;
use engine::{DynEngine, MethodChoice, Plan, Sampling, Sel, Stepping};

/// The method names accepted in `[method] name`: the RKMK family (any
/// model), the splittings of [`SPLITTING_NAMES`] (points and gyroscopes on
/// S², H², S³ only: they need exact free flows) and `implicit_midpoint` (any
/// model; Newton options `newton_tol`, `newton_max_iter`).
/// [`Scene::allowed_methods`] lists those of a manifold × body.
pub const METHOD_NAMES: &[&str] = &[
    "lie_euler",
    "heun",
    "kutta3",
    "rk4",
    "dopri5",
    "dop853",
    "butcher6",
    "strang",
    "yoshida4",
    "suzuki4",
    "blanes_moan4",
    "yoshida6",
    "blanes_moan6",
    "blanes_moan_rkn4",
    "blanes_moan_rkn6",
    "implicit_midpoint",
];

/// The symplectic splittings (exact free flows: points and gyroscopes on S²,
/// H² — both signatures — and S³; see [`Splitting`]).
pub const SPLITTING_NAMES: &[&str] =
    &["strang", "yoshida4", "suzuki4", "blanes_moan4", "yoshida6", "blanes_moan6", "blanes_moan_rkn4", "blanes_moan_rkn6"];

/// Default limit on accepted steps of a scene run.
pub const DEFAULT_SCENE_MAX_STEPS: u64 = 1_000_000_000;

/// One output column: its name and unit (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Column {
    /// Name, e.g. `"x0"` or `"energy"`.
    pub name: String,
    /// Unit in terms of `L`, `T`, `M` (`"1"`: dimensionless).
    pub unit: &'static str,
}

/// Where a run streams its records.
pub trait RecordSink {
    /// Called once before the first record with the column descriptions.
    fn columns(&mut self, columns: &[Column]) -> io::Result<()>;
    /// One record: one value per column.
    fn record(&mut self, row: &[f64]) -> io::Result<()>;
    /// A located event (default: ignored).
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        let _ = hit;
        Ok(())
    }
}

/// An event function of a record: `g(t, row)`, `row` holding every column
/// of [`Simulation::event_columns`] (all quantities) at time `t`.
pub type EventFn = Arc<dyn Fn(f64, &[f64]) -> f64 + Send + Sync>;

/// An event of a run: the crossings of `g = 0` in `direction` are located
/// on the method's own continuous extension (a sub-step of the method from
/// the start of the step, or the dense output of `dopri5`) by Brent's method
/// to round-off in time, reported to the sink, and a `terminal` one stops the
/// run at the first. Two crossings within one step cancel and are missed
/// (limit `h`); a zero at `t₀` is not reported.
#[derive(Clone)]
pub struct SceneEvent {
    /// Name in the output.
    pub name: String,
    /// The event function.
    pub g: EventFn,
    /// Which crossings are reported.
    pub direction: EventDirection,
    /// Stop at the first reported crossing.
    pub terminal: bool,
}

impl fmt::Debug for SceneEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SceneEvent").field("name", &self.name).field("direction", &self.direction).field("terminal", &self.terminal).finish_non_exhaustive()
    }
}

/// A located event.
#[derive(Debug, Clone, PartialEq)]
pub struct EventHit {
    /// Index of the event (scene events first, then [`Simulation::add_event`] ones).
    pub index: usize,
    /// Its name.
    pub name: String,
    /// The located time.
    pub t: f64,
    /// The record at `t` (the run's columns, [`Simulation::columns`]).
    pub row: Vec<f64>,
    /// True if `g` was rising through zero.
    pub rising: bool,
    /// True if the event stopped the run.
    pub terminal: bool,
}

/// A sink that keeps everything in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MemorySink {
    /// The columns.
    pub columns: Vec<Column>,
    /// The records.
    pub rows: Vec<Vec<f64>>,
    /// The located events.
    pub events: Vec<EventHit>,
}

impl MemorySink {
    /// The values of the column `name`, if present.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }
}

impl RecordSink for MemorySink {
    fn columns(&mut self, columns: &[Column]) -> io::Result<()> {
        self.columns = columns.to_vec();
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        self.rows.push(row.to_vec());
        Ok(())
    }
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }
}

/// A sink that keeps every record in one row-major buffer (`rows × columns`
/// values): one growing allocation instead of [`MemorySink`]'s one per
/// record, and the layout numpy takes without a copy (the Python module
/// returns it as `Solution.data`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlatSink {
    /// The columns.
    pub columns: Vec<Column>,
    /// The records, row-major: record `i` is `data[i·ncols .. (i+1)·ncols]`.
    pub data: Vec<f64>,
    /// The number of records.
    pub rows: usize,
    /// The located events.
    pub events: Vec<EventHit>,
}

impl FlatSink {
    /// Record `i`.
    pub fn row(&self, i: usize) -> &[f64] {
        let n = self.columns.len();
        &self.data[i * n..(i + 1) * n]
    }

    /// The values of the column `name`, if present.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.data.iter().skip(j).step_by(self.columns.len()).copied().collect())
    }
}

impl RecordSink for FlatSink {
    fn columns(&mut self, columns: &[Column]) -> io::Result<()> {
        self.columns = columns.to_vec();
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        self.data.extend_from_slice(row);
        self.rows += 1;
        Ok(())
    }
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }
}

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
    fn new(method: &'static str, t0: f64) -> Self {
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

/// Text a scene was read from (for locating errors).
#[derive(Debug, Clone, PartialEq)]
enum Source {
    Toml(Arc<str>),
    Json(Arc<str>),
}

/// A scene: the whole description of a simulation (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A short name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// What the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// `[manifold]`.
    pub manifold: ManifoldSpec,
    /// `[body]`.
    pub body: BodySpec,
    /// `[potential]` (default none).
    #[serde(default)]
    pub potential: PotentialSpec,
    /// `[initial]`.
    pub initial: InitialSpec,
    /// `[method]` (default RK4 with `h = (t_end − t₀)/1000`).
    #[serde(default)]
    pub method: MethodSpec,
    /// `[time]`.
    pub time: TimeSpec,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSpec,
    /// `[[events]]`: crossings located and reported during the run (see
    /// [`EventSpec`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<EventSpec>,
    #[serde(skip)]
    source: Option<Source>,
}

impl Scene {
    /// A scene from its parts, with no potential, the default method and
    /// output (fill in the public fields to change them).
    pub fn new(manifold: ManifoldSpec, body: BodySpec, initial: InitialSpec, time: TimeSpec) -> Scene {
        Scene {
            name: None,
            description: None,
            manifold,
            body,
            potential: PotentialSpec::default(),
            initial,
            method: MethodSpec::default(),
            time,
            output: OutputSpec::default(),
            events: Vec::new(),
            source: None,
        }
    }

    /// Parses a TOML scene. Errors ([`SceneError::Parse`]) name the field,
    /// the parser's message (value and expected type/variants) and the line
    /// and column.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let de = toml::Deserializer::new(text);
        let mut scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let location = inner.span().map(|s| locate::offset_to_location(text, s.start));
            SceneError::Parse {
                format: "TOML",
                path: if path == "." { String::new() } else { path },
                message: inner.message().trim().to_string(),
                location,
            }
        })?;
        scene.source = Some(Source::Toml(text.into()));
        Ok(scene)
    }

    /// Parses a JSON scene (same fields as TOML). Errors as [`Self::from_toml_str`].
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let mut scene: Scene = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let location = if inner.line() > 0 { Some(Location { line: inner.line(), column: inner.column() }) } else { None };
            let mut message = inner.to_string();
            if let Some(i) = message.find(" at line ") {
                message.truncate(i);
            }
            SceneError::Parse { format: "JSON", path: if path == "." { String::new() } else { path }, message, location }
        })?;
        de.end().map_err(|e| SceneError::Parse {
            format: "JSON",
            path: String::new(),
            message: "trailing characters after the scene".into(),
            location: Some(Location { line: e.line(), column: e.column() }),
        })?;
        scene.source = Some(Source::Json(text.into()));
        Ok(scene)
    }

    /// Parses TOML, or JSON when the text starts with `{`.
    pub fn from_str_auto(text: &str) -> Result<Scene, SceneError> {
        if text.trim_start().starts_with('{') {
            Self::from_json_str(text)
        } else {
            Self::from_toml_str(text)
        }
    }

    /// The scene as TOML.
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# cannot serialise: {e}\n"))
    }

    /// The scene as JSON.
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// The method names available for this scene's manifold × body (a
    /// subset of [`METHOD_NAMES`]): the splittings of [`SPLITTING_NAMES`]
    /// only for points and gyroscopes on S², H², S³.
    pub fn allowed_methods(&self) -> Vec<&'static str> {
        let split = matches!(self.manifold.kind, ManifoldKind::S2 | ManifoldKind::H2 | ManifoldKind::S3)
            && matches!(self.body.kind, BodyKind::Point | BodyKind::Gyroscope);
        METHOD_NAMES.iter().copied().filter(|n| split || !SPLITTING_NAMES.contains(n)).collect()
    }

    /// Checks everything [`Self::build`] checks, without running.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.build().map(|_| ())
    }

    /// Builds the simulation. Errors name the field (`body.mass`,
    /// `initial.r`, `potential.terms[0].kappa`, …), the value and what is
    /// allowed, with the line and column when the scene came from text.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        self.build_inner(None).map_err(|e| self.locate(e))
    }

    /// Builds the simulation with a user potential `f(x, e)` added to the
    /// scene's potential (`x`: embedding position, `e`: the body frame
    /// vectors column-major, for points the reference frame). Its gradient
    /// is taken by extrapolated finite differences
    /// ([`FnPotential`](crate::potential::FnPotential)): slower than the
    /// built-ins.
    pub fn build_with_user_potential(&self, f: UserPotentialFn) -> Result<Simulation, SceneError> {
        self.build_with_user(UserFunctions { value: f, gradient: None })
    }

    /// [`Self::build_with_user_potential`], with the user's own gradient if
    /// [`UserFunctions::gradient`] is given ([`UserGradientFn`]: `∂V/∂x` and
    /// `∂V/∂e` in the same layouts as `x` and `e`) instead of finite
    /// differences: one call of each function per evaluation. The gradient
    /// is trusted as it is.
    pub fn build_with_user(&self, user: UserFunctions) -> Result<Simulation, SceneError> {
        self.build_inner(Some(user)).map_err(|e| self.locate(e))
    }

    /// The output path (default `trajectory.csv`, or `.npz` for `format = "npz"`).
    pub fn output_path(&self) -> String {
        match (&self.output.path, self.output.format) {
            (Some(p), _) => p.clone(),
            (None, Some(Format::Npz)) => "trajectory.npz".into(),
            (None, _) => "trajectory.csv".into(),
        }
    }

    /// The output format: `format`, else from the extension of the path.
    pub fn output_format(&self) -> Format {
        self.output.format.unwrap_or_else(|| {
            if self.output_path().to_ascii_lowercase().ends_with(".npz") {
                Format::Npz
            } else {
                Format::Csv
            }
        })
    }

    fn locate(&self, e: SceneError) -> SceneError {
        match e {
            SceneError::Invalid { path, value, allowed, location: None } => {
                let location = match &self.source {
                    Some(Source::Toml(s)) => locate::toml_path(s, &path),
                    Some(Source::Json(s)) => locate::json_path(s, &path),
                    None => None,
                };
                SceneError::Invalid { path, value, allowed, location }
            }
            other => other,
        }
    }

    fn plan(&self) -> Result<(Plan, MethodChoice), SceneError> {
        let t = &self.time;
        if !t.t0.is_finite() {
            return Err(SceneError::invalid("time.t0", t.t0, "must be finite"));
        }
        if !t.t_end.is_finite() || t.t_end == t.t0 {
            return Err(SceneError::invalid("time.t_end", t.t_end, "must be finite and ≠ t0"));
        }
        let span = t.t_end - t.t0;
        let m = &self.method;
        let method = match m.name.as_str() {
            "lie_euler" => MethodChoice::LieEuler(Rkmk::lie_euler()),
            "heun" => MethodChoice::Heun(Rkmk::heun()),
            "kutta3" => MethodChoice::Kutta3(Rkmk::kutta3()),
            "rk4" => MethodChoice::Rk4(Rkmk::rk4()),
            "dopri5" => MethodChoice::Dopri5(Rkmk::dopri5()),
            "dop853" => MethodChoice::Dop853(Rkmk::dop853()),
            "butcher6" => MethodChoice::Butcher6(Rkmk::butcher6()),
            "strang" => MethodChoice::Split(Splitting::strang(), "Strang splitting"),
            "yoshida4" => MethodChoice::Split(Splitting::yoshida4(), "Yoshida 4 splitting"),
            "suzuki4" => MethodChoice::Split(Splitting::suzuki4(), "Suzuki 4 splitting"),
            "blanes_moan4" => MethodChoice::Split(Splitting::blanes_moan4(), "Blanes-Moan 4 splitting"),
            "yoshida6" => MethodChoice::Split(Splitting::yoshida6(), "Yoshida 6 splitting"),
            "blanes_moan6" => MethodChoice::Split(Splitting::blanes_moan6(), "Blanes-Moan 6 splitting"),
            "blanes_moan_rkn4" => MethodChoice::Split(Splitting::blanes_moan_rkn4(), "Blanes-Moan RKN 4 splitting"),
            "blanes_moan_rkn6" => MethodChoice::Split(Splitting::blanes_moan_rkn6(), "Blanes-Moan RKN 6 splitting"),
            "implicit_midpoint" => {
                let tol = m.newton_tol.unwrap_or(1e-14);
                if !(tol.is_finite() && (1e-16..=1e-2).contains(&tol)) {
                    return Err(SceneError::invalid("method.newton_tol", tol, "must be in [1e-16, 1e-2]"));
                }
                let it = m.newton_max_iter.unwrap_or(30);
                if !(1..=1000).contains(&it) {
                    return Err(SceneError::invalid("method.newton_max_iter", it, "must be in 1 ..= 1000"));
                }
                let im = ImplicitMidpoint::new().with_newton(tol, it).map_err(|e| SceneError::invalid("method.newton_tol", tol, e.to_string()))?;
                MethodChoice::Implicit(im)
            }
            other => {
                return Err(SceneError::invalid(
                    "method.name",
                    format!("\"{other}\""),
                    format!("one of {}", METHOD_NAMES.join(", ")),
                ))
            }
        };
        if m.name != "implicit_midpoint" && (m.newton_tol.is_some() || m.newton_max_iter.is_some()) {
            let f = if m.newton_tol.is_some() { "method.newton_tol" } else { "method.newton_max_iter" };
            return Err(SceneError::invalid(f, "(given)", format!("Newton options are for name = \"implicit_midpoint\", not \"{}\"", m.name)));
        }
        let allowed = self.allowed_methods();
        if !allowed.contains(&m.name.as_str()) {
            return Err(SceneError::invalid(
                "method.name",
                format!("\"{}\"", m.name),
                format!(
                    "not available for a {} on {:?} (splittings need exact free flows: points and gyroscopes on S2, H2, S3); allowed here: {}",
                    kind_body(self.body.kind),
                    self.manifold.kind,
                    allowed.join(", ")
                ),
            ));
        }
        let adaptive = m.rtol.is_some() || m.atol.is_some() || (m.h.is_none() && (m.name == "dopri5" || m.name == "dop853"));
        let stepping = if adaptive {
            if m.h.is_some() {
                return Err(SceneError::invalid("method.h", m.h.unwrap_or(f64::NAN), "give either h (fixed steps) or rtol/atol (adaptive), not both"));
            }
            if m.name != "dopri5" && m.name != "dop853" {
                return Err(SceneError::invalid("method.rtol", m.rtol.or(m.atol).unwrap_or(f64::NAN), "adaptive stepping (rtol/atol) needs name = \"dopri5\" or \"dop853\""));
            }
            let rtol = m.rtol.unwrap_or(1e-8);
            let atol = m.atol.unwrap_or(1e-10);
            if !(rtol.is_finite() && rtol >= 0.0) {
                return Err(SceneError::invalid("method.rtol", rtol, "must be finite and ≥ 0"));
            }
            if !(atol.is_finite() && atol >= 0.0 && atol + rtol > 0.0) {
                return Err(SceneError::invalid("method.atol", atol, "must be finite and ≥ 0, with rtol + atol > 0"));
            }
            Stepping::Adaptive { rtol, atol }
        } else {
            let h = m.h.unwrap_or(span.abs() / 1000.0);
            if !(h.is_finite() && h > 0.0) {
                return Err(SceneError::invalid("method.h", h, "must be finite and > 0"));
            }
            Stepping::Fixed(h)
        };
        let max_steps = m.max_steps.unwrap_or(DEFAULT_SCENE_MAX_STEPS);
        if max_steps == 0 {
            return Err(SceneError::invalid("method.max_steps", 0, "must be ≥ 1"));
        }
        let o = &self.output;
        let given = o.every.is_some() as u8 + o.times.is_some() as u8 + o.samples.is_some() as u8;
        if given > 1 {
            let path = if o.times.is_some() { "output.times" } else { "output.samples" };
            return Err(SceneError::invalid(path, "(given together with another sampling)", "give only one of every, times, samples"));
        }
        let (lo, hi) = (t.t0.min(t.t_end), t.t0.max(t.t_end));
        let sampling = if let Some(ts) = &o.times {
            if ts.is_empty() {
                return Err(SceneError::invalid("output.times", "[]", "must list at least one time"));
            }
            for (i, &x) in ts.iter().enumerate() {
                if !(x >= lo && x <= hi) {
                    return Err(SceneError::invalid(format!("output.times[{i}]"), x, format!("must lie in the time span [{lo}, {hi}]")));
                }
            }
            let mut v = ts.clone();
            v.sort_by(f64::total_cmp);
            if span < 0.0 {
                v.reverse();
            }
            Sampling::Times(v)
        } else if let Some(n) = o.samples {
            if !(2..=100_000_000).contains(&n) {
                return Err(SceneError::invalid("output.samples", n, "must be in 2 ..= 1e8"));
            }
            Sampling::Times((0..n).map(|i| if i + 1 == n { t.t_end } else { t.t0 + span * (i as f64 / (n - 1) as f64) }).collect())
        } else {
            let every = o.every.unwrap_or(1);
            if every == 0 {
                return Err(SceneError::invalid("output.every", 0, "must be ≥ 1"));
            }
            Sampling::Every(every)
        };
        let quantities = o.quantities.clone().unwrap_or_else(|| Quantity::ALL.to_vec());
        if let Some(p) = &o.path {
            if p.is_empty() {
                return Err(SceneError::invalid("output.path", "\"\"", "must be a non-empty path"));
            }
        }
        Ok((Plan { t0: t.t0, t_end: t.t_end, stepping, sampling, max_steps, sel: Sel::new(&quantities), events: Vec::new() }, method))
    }

    fn build_inner(&self, user: Option<UserFunctions>) -> Result<Simulation, SceneError> {
        let (plan, method) = self.plan()?;
        let span = (plan.t0, plan.t_end);
        let ms = &self.manifold;
        let radius = |ms: &ManifoldSpec| -> Result<f64, SceneError> {
            if ms.major.is_some() || ms.minor.is_some() {
                return Err(SceneError::invalid("manifold.L", ms.major.or(ms.minor).unwrap_or(f64::NAN), "L and R are for kind = \"T2\"; use radius"));
            }
            Ok(ms.radius.unwrap_or(1.0))
        };
        let engine: Box<dyn DynEngine> = match ms.kind {
            ManifoldKind::S2 => {
                let m = Sphere2::new(radius(ms)?).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let pot = self.potential2(&Surface::S2(&m), user)?;
                self.build2(m, pot, span, method)?
            }
            ManifoldKind::H2 => {
                let m = Hyperbolic2::new(radius(ms)?).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let pot = self.potential2(&Surface::H2(&m), user)?;
                self.build2(m, pot, span, method)?
            }
            ManifoldKind::T2 => {
                if let Some(r) = ms.radius {
                    return Err(SceneError::invalid("manifold.radius", r, "the torus takes L (major) and R (minor), not radius"));
                }
                let (l, r) = (ms.major.unwrap_or(2.0), ms.minor.unwrap_or(1.0));
                let m = Torus2::new(l, r).map_err(|e| SceneError::from_core("manifold", e))?;
                let pot = self.potential2(&Surface::T2(l, r), user)?;
                self.build2(m, pot, span, method)?
            }
            ManifoldKind::S3 => {
                let m = Sphere3::new(radius(ms)?).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let pot = self.potential3(&self.potential, "potential", &m)?;
                let pot = match user {
                    None => pot,
                    Some(user) => Potential3::Sum(vec![
                        (1.0, pot),
                        (1.0, Potential3::User(UserPotential::new(user, true, m.radius()).map_err(|e| SceneError::from_core("potential", e))?)),
                    ]),
                };
                self.build3(m, pot, span, method)?
            }
        };
        let columns = engine.columns(plan.sel);
        let event_columns = engine.columns(Sel::new(&Quantity::ALL));
        let mut plan = plan;
        for (i, e) in self.events.iter().enumerate() {
            plan.events.push(compile_event(e, i, &event_columns)?);
        }
        Ok(Simulation { engine, plan, columns, event_columns, name: self.name.clone().unwrap_or_default() })
    }

    // -- potentials -------------------------------------------------------------

    fn potential2(&self, s: &Surface<'_>, user: Option<UserFunctions>) -> Result<Potential2, SceneError> {
        let pot = build_potential2(&self.potential, "potential", s)?;
        Ok(match user {
            None => pot,
            Some(user) => {
                let len = match s {
                    Surface::S2(m) => m.radius(),
                    Surface::H2(m) => m.radius(),
                    Surface::T2(_, r) => *r,
                };
                let u = UserPotential::new(user, self.body.kind != BodyKind::Point, len).map_err(|e| SceneError::from_core("potential", e))?;
                Potential2::Sum(vec![(1.0, pot), (1.0, Potential2::User(u))])
            }
        })
    }

    fn potential3(&self, p: &PotentialSpec, path: &str, m: &Sphere3) -> Result<Potential3, SceneError> {
        let core = |field: &str, e| SceneError::from_core(&format!("{path}.{field}"), e);
        let centre = || -> Result<Centre<4>, SceneError> {
            match &p.centre {
                None => Ok(Centre::sphere3(m)),
                Some(c) => Centre::sphere3_at(m, &vec4(c, &format!("{path}.centre"))?).map_err(|e| core("centre", e)),
            }
        };
        check_fields(p, path)?;
        let base = match p.kind {
            PotentialKind::None => Potential3::Free,
            PotentialKind::Oscillator => Potential3::Oscillator(Oscillator::new(req(p.kappa, path, "kappa")?, centre()?).map_err(|e| core("kappa", e))?),
            PotentialKind::Kepler => Potential3::Kepler(Kepler::new(req(p.alpha, path, "alpha")?, centre()?).map_err(|e| core("alpha", e))?),
            PotentialKind::Cosine => Potential3::Cosine(
                CosineFamily::new(p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0), centre()?).map_err(|e| core("alpha_hat", e))?,
            ),
            PotentialKind::Central => Potential3::Central(Central::new(series(&p.v, path, "v")?, centre()?)),
            PotentialKind::NeoHookean => Potential3::NeoHookean(InvariantPotential::new(
                NeoHookean::new(req(p.lambda, path, "lambda")?, req(p.mu, path, "mu")?).map_err(|e| core("lambda", e))?,
            )),
            PotentialKind::StVenantKirchhoff => Potential3::StVenantKirchhoff(InvariantPotential::new(
                StVenantKirchhoff::new(req(p.lambda, path, "lambda")?, req(p.mu, path, "mu")?).map_err(|e| core("lambda", e))?,
            )),
            PotentialKind::Sum => {
                let terms = p.terms.as_ref().ok_or_else(|| SceneError::invalid(format!("{path}.terms"), "(missing)", "kind = \"sum\" needs terms = [...]"))?;
                let mut out = Vec::new();
                for (i, t) in terms.iter().enumerate() {
                    out.push((1.0, self.potential3(t, &format!("{path}.terms[{i}]"), m)?));
                }
                Potential3::Sum(out)
            }
            PotentialKind::Elastic | PotentialKind::Separable => {
                return Err(SceneError::invalid(
                    format!("{path}.kind"),
                    format!("\"{}\"", kind_name(p.kind)),
                    "on S3 allowed: none, oscillator, kepler, cosine, central, neo_hookean, st_venant_kirchhoff, sum (elastic and separable are the 2-D potentials (a131), (b128))",
                ))
            }
        };
        scaled3(p, path, base)
    }

    // -- models -----------------------------------------------------------------

    fn build2<B>(&self, m: B, pot: Potential2, span: (f64, f64), method: MethodChoice) -> Result<Box<dyn DynEngine>, SceneError>
    where
        B: FrameBundle<2, 3> + Clone + Send + 'static,
        PointModel<B, Potential2, 2, 3>: engine::Observe + System<State = PointState<B::Group, 2>>,
        Gyroscope2Model<B, Potential2>: engine::Observe + System<State = Gyroscope2State<B::Group>>,
        AffineBodyModel<B, Potential2, Unconstrained, 2, 3>: engine::Observe + System<State = BodyState<B, Unconstrained, 2, 3>>,
        AffineBodyModel<B, Potential2, Isochoric, 2, 3>: engine::Observe + System<State = BodyState<B, Isochoric, 2, 3>>,
        AffineBodyModel<B, Potential2, Conformal, 2, 3>: engine::Observe + System<State = BodyState<B, Conformal, 2, 3>>,
        AffineBodyModel<B, Potential2, PureDilatation<2>, 2, 3>: engine::Observe + System<State = BodyState<B, PureDilatation<2>, 2, 3>>,
    {
        let init = Init::<B, 2, 3>::new(&m, &self.initial)?;
        let b = &self.body;
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        let core_init = |e: crate::Error| init_error(e);
        match b.kind {
            BodyKind::Point => {
                self.no_internal(&["alpha", "orientation", "spin", "omega", "frame", "rho", "rho_dot"])?;
                let body = Point::new(b.mass).map_err(|e| SceneError::from_core("body.mass", e))?;
                self.no_inertia()?;
                let model = PointModel::new(m.clone(), body, pot).map_err(|e| SceneError::from_core("potential", e))?;
                let y = model.state_from_parts(&init.g, &init.u).map_err(core_init)?;
                engine::boxed(model, y, span, method).map_err(run)
            }
            BodyKind::Gyroscope => {
                self.no_internal(&["orientation", "rho", "rho_dot"])?;
                let mut body = match &b.j {
                    Some(j) => Gyroscope::<2>::new(b.mass, mat::<2>(j, "body.J")?),
                    None => Gyroscope::<2>::isotropic(b.mass, b.inertia.unwrap_or(1.0)),
                }
                .map_err(|e| SceneError::from_core("body", e))?;
                if b.signature == Some(SignatureSpec::Lorentz) {
                    body = body.with_signature(Signature::Lorentz);
                }
                let model = Gyroscope2Model::new(m.clone(), body, pot).map_err(|e| SceneError::from_core("body", e))?;
                let i = &self.initial;
                let spin = match (&i.spin, &i.omega) {
                    (Some(_), Some(_)) => return Err(SceneError::invalid("initial.omega", "(given with spin)", "give spin or omega, not both")),
                    (Some(s), None) => scalar(s, "initial.spin")?,
                    (None, Some(w)) => model.spin_for_angular_velocity(scalar(w, "initial.omega")?),
                    (None, None) => 0.0,
                };
                let y = if let Some(fr) = &i.frame {
                    if i.alpha.is_some() {
                        return Err(SceneError::invalid("initial.alpha", i.alpha.unwrap_or(0.0), "give frame or alpha, not both"));
                    }
                    let e = frame_matrix::<2, 3>(fr)?;
                    model.state(&init.p, &init.v, &e, spin).map_err(core_init)?
                } else {
                    let alpha = i.alpha.unwrap_or(0.0);
                    model.state_from_parts(&init.g, &So2::exp(&nalgebra::Vector1::new(alpha)), &init.u, spin).map_err(core_init)?
                };
                engine::boxed(model, y, span, method).map_err(run)
            }
            _ => self.build_affine::<B, 2, 3>(m, pot, &init, span, method),
        }
    }

    fn build3(&self, m: Sphere3, pot: Potential3, span: (f64, f64), method: MethodChoice) -> Result<Box<dyn DynEngine>, SceneError> {
        let init = Init::<Sphere3, 3, 4>::new(&m, &self.initial)?;
        let b = &self.body;
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        match b.kind {
            BodyKind::Point => {
                self.no_internal(&["alpha", "orientation", "spin", "omega", "frame", "rho", "rho_dot"])?;
                self.no_inertia()?;
                let body = Point::new(b.mass).map_err(|e| SceneError::from_core("body.mass", e))?;
                let model = PointModel::new(m, body, pot).map_err(|e| SceneError::from_core("potential", e))?;
                let y = model.state_from_parts(&init.g, &init.u).map_err(init_error)?;
                engine::boxed(model, y, span, method).map_err(run)
            }
            BodyKind::Gyroscope => {
                self.no_internal(&["alpha", "rho", "rho_dot"])?;
                if b.signature == Some(SignatureSpec::Lorentz) {
                    return Err(SceneError::invalid("body.signature", "\"lorentz\"", "the Lorentz-type gyroscope (a138) is defined on H2 and S2 surfaces; on S3 use riemannian"));
                }
                let body = match &b.j {
                    Some(j) => Gyroscope::<3>::new(b.mass, mat::<3>(j, "body.J")?),
                    None => Gyroscope::<3>::isotropic(b.mass, b.inertia.unwrap_or(1.0)),
                }
                .map_err(|e| SceneError::from_core("body", e))?;
                let model = Gyroscope3Model::new(m, body, pot).map_err(|e| SceneError::from_core("body", e))?;
                let i = &self.initial;
                let spin_e = match (&i.spin, &i.omega) {
                    (Some(_), Some(_)) => return Err(SceneError::invalid("initial.omega", "(given with spin)", "give spin or omega, not both")),
                    (Some(s), None) => vec3(&s.0, "initial.spin")?,
                    (None, Some(w)) => model.spin_for_angular_velocity(&vec3(&w.0, "initial.omega")?),
                    (None, None) => nalgebra::Vector3::zeros(),
                };
                let y = if let Some(fr) = &i.frame {
                    if i.orientation.is_some() {
                        return Err(SceneError::invalid("initial.orientation", "(given with frame)", "give frame or orientation, not both"));
                    }
                    let e = frame_matrix::<3, 4>(fr)?;
                    model.state(&init.p, &init.v, &e, &spin_e).map_err(init_error)?
                } else {
                    let rv = match &i.orientation {
                        Some(o) => vec3(o, "initial.orientation")?,
                        None => nalgebra::Vector3::zeros(),
                    };
                    let rho = So3::exp(&rv);
                    model.state_from_parts(&init.g, &rho, &init.u, &(rho.matrix() * spin_e)).map_err(init_error)?
                };
                engine::boxed(model, y, span, method).map_err(run)
            }
            _ => self.build_affine::<Sphere3, 3, 4>(m, pot, &init, span, method),
        }
    }

    fn build_affine<B, const N: usize, const E: usize>(
        &self,
        m: B,
        pot: <Self as PotFor<N, E>>::Pot,
        init: &Init<B, N, E>,
        span: (f64, f64),
        method: MethodChoice,
    ) -> Result<Box<dyn DynEngine>, SceneError>
    where
        Self: PotFor<N, E>,
        B: FrameBundle<N, E> + Clone + Send + 'static,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Unconstrained, N, E>: engine::Observe + System<State = BodyState<B, Unconstrained, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Isochoric, N, E>: engine::Observe + System<State = BodyState<B, Isochoric, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Conformal, N, E>: engine::Observe + System<State = BodyState<B, Conformal, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, PureDilatation<N>, N, E>: engine::Observe + System<State = BodyState<B, PureDilatation<N>, N, E>>,
    {
        self.no_internal(&["alpha", "orientation", "spin", "omega", "frame"])?;
        let b = &self.body;
        if b.signature.is_some() {
            return Err(SceneError::invalid("body.signature", "(given)", "signature is for gyroscopes only"));
        }
        let j = match &b.j {
            Some(j) => mat::<N>(j, "body.J")?,
            None => {
                let i = b.inertia.unwrap_or(1.0);
                if !(i.is_finite() && i > 0.0) {
                    return Err(SceneError::invalid("body.inertia", i, "must be finite and > 0"));
                }
                SMatrix::<f64, N, N>::identity() * i
            }
        };
        let i = &self.initial;
        let rho = match &i.rho {
            Some(r) => mat::<N>(r, "initial.rho")?,
            None => SMatrix::identity(),
        };
        let rho_dot = match &i.rho_dot {
            Some(r) => mat::<N>(r, "initial.rho_dot")?,
            None => SMatrix::zeros(),
        };
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        let body_err = |e| SceneError::from_core("body", e);
        let model_err = |e| SceneError::from_core("body", e);
        macro_rules! go {
            ($body:ty, $c:ty) => {{
                let body = <$body>::new(b.mass, j).map_err(body_err)?;
                let model = AffineBodyModel::<B, _, $c, N, E>::new(m, body, pot).map_err(model_err)?;
                let y = model.state(&init.g, &rho, &init.u, &rho_dot).map_err(init_error)?;
                engine::boxed(model, y, span, method).map_err(run)
            }};
        }
        match b.kind {
            BodyKind::Affine => go!(Affine<N>, Unconstrained),
            BodyKind::Incompressible => go!(Incompressible<N>, Isochoric),
            BodyKind::Weyl => go!(Weyl<N>, Conformal),
            _ => go!(Dilatation<N>, PureDilatation<N>),
        }
    }

    fn no_internal(&self, fields: &[&str]) -> Result<(), SceneError> {
        let i = &self.initial;
        for f in fields {
            let given = match *f {
                "alpha" => i.alpha.is_some(),
                "orientation" => i.orientation.is_some(),
                "spin" => i.spin.is_some(),
                "omega" => i.omega.is_some(),
                "frame" => i.frame.is_some(),
                "rho" => i.rho.is_some(),
                "rho_dot" => i.rho_dot.is_some(),
                _ => false,
            };
            if given {
                return Err(SceneError::invalid(
                    format!("initial.{f}"),
                    "(given)",
                    format!("not used by a {} on {:?}", kind_body(self.body.kind), self.manifold.kind),
                ));
            }
        }
        Ok(())
    }

    fn no_inertia(&self) -> Result<(), SceneError> {
        if self.body.inertia.is_some() || self.body.j.is_some() || self.body.signature.is_some() {
            return Err(SceneError::invalid("body.inertia", "(given)", "a point has a mass only"));
        }
        Ok(())
    }
}

/// Selects the potential type of bodies with `N` frame vectors in `E` dimensions.
pub trait PotFor<const N: usize, const E: usize> {
    /// The potential enum.
    type Pot: crate::potential::Potential<N, E> + Clone + 'static;
}
impl PotFor<2, 3> for Scene {
    type Pot = Potential2;
}
impl PotFor<3, 4> for Scene {
    type Pot = Potential3;
}

fn kind_body(k: BodyKind) -> &'static str {
    match k {
        BodyKind::Point => "point",
        BodyKind::Gyroscope => "gyroscope",
        BodyKind::Affine => "affine body",
        BodyKind::Incompressible => "incompressible body",
        BodyKind::Weyl => "Weyl body",
        BodyKind::Dilatation => "dilatational body",
    }
}

fn kind_name(k: PotentialKind) -> &'static str {
    match k {
        PotentialKind::None => "none",
        PotentialKind::Oscillator => "oscillator",
        PotentialKind::Kepler => "kepler",
        PotentialKind::Cosine => "cosine",
        PotentialKind::Central => "central",
        PotentialKind::Elastic => "elastic",
        PotentialKind::Separable => "separable",
        PotentialKind::NeoHookean => "neo_hookean",
        PotentialKind::StVenantKirchhoff => "st_venant_kirchhoff",
        PotentialKind::Sum => "sum",
    }
}

/// The surface a 2-D potential lives on.
enum Surface<'a> {
    S2(&'a Sphere2),
    H2(&'a Hyperbolic2),
    T2(f64, f64),
}

fn req(v: Option<f64>, path: &str, field: &str) -> Result<f64, SceneError> {
    v.ok_or_else(|| SceneError::invalid(format!("{path}.{field}"), "(missing)", "required for this kind of potential"))
}

fn series(v: &Option<Series>, path: &str, field: &str) -> Result<Series, SceneError> {
    let s = v.clone().ok_or_else(|| SceneError::invalid(format!("{path}.{field}"), "(missing)", "required: { poly = [...], cos = [[a, w], ...], sec_2x = c }"))?;
    if !s.is_finite() {
        return Err(SceneError::invalid(format!("{path}.{field}"), "(non-finite coefficient)", "coefficients must be finite"));
    }
    Ok(s)
}

/// Rejects parameters that the potential's kind does not use.
fn check_fields(p: &PotentialSpec, path: &str) -> Result<(), SceneError> {
    let used: &[&str] = match p.kind {
        PotentialKind::None => &[],
        PotentialKind::Oscillator => &["kappa", "centre"],
        PotentialKind::Kepler => &["alpha", "centre"],
        PotentialKind::Cosine => &["alpha_hat", "beta_hat", "centre"],
        PotentialKind::Central => &["v", "centre"],
        PotentialKind::Elastic => &["kappa"],
        PotentialKind::Separable => &["v_r", "v_rho", "v_eps", "centre"],
        PotentialKind::NeoHookean | PotentialKind::StVenantKirchhoff => &["lambda", "mu"],
        PotentialKind::Sum => &["terms"],
    };
    let given = [
        ("kappa", p.kappa.is_some()),
        ("alpha", p.alpha.is_some()),
        ("alpha_hat", p.alpha_hat.is_some()),
        ("beta_hat", p.beta_hat.is_some()),
        ("lambda", p.lambda.is_some()),
        ("mu", p.mu.is_some()),
        ("centre", p.centre.is_some()),
        ("v", p.v.is_some()),
        ("v_r", p.v_r.is_some()),
        ("v_rho", p.v_rho.is_some()),
        ("v_eps", p.v_eps.is_some()),
        ("terms", p.terms.is_some()),
    ];
    for (f, g) in given {
        if g && !used.contains(&f) {
            return Err(SceneError::invalid(
                format!("{path}.{f}"),
                "(given)",
                format!("kind = \"{}\" takes only: {}", kind_name(p.kind), if used.is_empty() { "no parameters".to_string() } else { used.join(", ") }),
            ));
        }
    }
    if let Some(s) = p.scale {
        if !s.is_finite() {
            return Err(SceneError::invalid(format!("{path}.scale"), s, "must be finite"));
        }
    }
    Ok(())
}

fn scaled2(p: &PotentialSpec, base: Potential2) -> Potential2 {
    match p.scale {
        Some(s) if s != 1.0 => Potential2::Sum(vec![(s, base)]),
        _ => base,
    }
}

fn scaled3(p: &PotentialSpec, _path: &str, base: Potential3) -> Result<Potential3, SceneError> {
    Ok(match p.scale {
        Some(s) if s != 1.0 => Potential3::Sum(vec![(s, base)]),
        _ => base,
    })
}

fn build_potential2(p: &PotentialSpec, path: &str, s: &Surface<'_>) -> Result<Potential2, SceneError> {
    check_fields(p, path)?;
    let core = |field: &str, e| SceneError::from_core(&format!("{path}.{field}"), e);
    let centre = || -> Result<Centre<3>, SceneError> {
        let cpath = format!("{path}.centre");
        match (s, &p.centre) {
            (Surface::S2(m), None) => Ok(Centre::sphere2(m)),
            (Surface::S2(m), Some(c)) => Centre::sphere2_at(m, &vec3(c, &cpath)?).map_err(|e| core("centre", e)),
            (Surface::H2(m), None) => Ok(Centre::hyperbolic2(m)),
            (Surface::H2(m), Some(c)) => Centre::hyperbolic2_at(m, &vec3(c, &cpath)?).map_err(|e| core("centre", e)),
            (Surface::T2(..), _) => Err(SceneError::invalid(
                format!("{path}.kind"),
                format!("\"{}\"", kind_name(p.kind)),
                "central potentials need a centre on S2, H2 or S3; on T2 allowed: none, elastic, separable (V_r of the torus angle), sum",
            )),
        }
    };
    let base = match p.kind {
        PotentialKind::None => Potential2::Free,
        PotentialKind::Oscillator => Potential2::Oscillator(Oscillator::new(req(p.kappa, path, "kappa")?, centre()?).map_err(|e| core("kappa", e))?),
        PotentialKind::Kepler => Potential2::Kepler(Kepler::new(req(p.alpha, path, "alpha")?, centre()?).map_err(|e| core("alpha", e))?),
        PotentialKind::Cosine => Potential2::Cosine(
            CosineFamily::new(p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0), centre()?).map_err(|e| core("alpha_hat", e))?,
        ),
        PotentialKind::Central => Potential2::Central(Central::new(series(&p.v, path, "v")?, centre()?)),
        PotentialKind::Elastic => Potential2::Elastic(Elastic::new(req(p.kappa, path, "kappa")?).map_err(|e| core("kappa", e))?),
        PotentialKind::Separable => {
            let f = SeparableSeries {
                v_r: p.v_r.as_ref().map(|_| series(&p.v_r, path, "v_r")).transpose()?.unwrap_or_default(),
                v_rho: p.v_rho.as_ref().map(|_| series(&p.v_rho, path, "v_rho")).transpose()?.unwrap_or_default(),
                v_eps: p.v_eps.as_ref().map(|_| series(&p.v_eps, path, "v_eps")).transpose()?.unwrap_or_default(),
            };
            match s {
                Surface::T2(l, r) => {
                    if p.centre.is_some() {
                        return Err(SceneError::invalid(format!("{path}.centre"), "(given)", "on T2 the separable potential uses the torus angle; no centre"));
                    }
                    Potential2::Separable(Separable::torus(f, TorusAngle::new(*l, *r).map_err(|e| core("kind", e))?))
                }
                _ => Potential2::Separable(Separable::new(f, centre()?)),
            }
        }
        PotentialKind::Sum => {
            let terms = p.terms.as_ref().ok_or_else(|| SceneError::invalid(format!("{path}.terms"), "(missing)", "kind = \"sum\" needs terms = [...]"))?;
            let mut out = Vec::new();
            for (i, t) in terms.iter().enumerate() {
                out.push((1.0, build_potential2(t, &format!("{path}.terms[{i}]"), s)?));
            }
            Potential2::Sum(out)
        }
        PotentialKind::NeoHookean | PotentialKind::StVenantKirchhoff => {
            return Err(SceneError::invalid(
                format!("{path}.kind"),
                format!("\"{}\"", kind_name(p.kind)),
                "invariant potentials of the Green tensor are for three-dimensional bodies (S3); on surfaces use elastic or separable",
            ))
        }
    };
    Ok(scaled2(p, base))
}

// -- arrays ------------------------------------------------------------------

fn vec_n<const K: usize>(v: &[f64], path: &str) -> Result<SVector<f64, K>, SceneError> {
    if v.len() != K {
        return Err(SceneError::invalid(path, format!("an array of {} numbers", v.len()), format!("must have exactly {K} numbers")));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(SceneError::invalid(format!("{path}[{i}]"), v[i], "must be finite"));
    }
    Ok(SVector::from_column_slice(v))
}

fn vec3(v: &[f64], path: &str) -> Result<nalgebra::Vector3<f64>, SceneError> {
    vec_n::<3>(v, path)
}

fn vec4(v: &[f64], path: &str) -> Result<nalgebra::Vector4<f64>, SceneError> {
    vec_n::<4>(v, path)
}

fn scalar(v: &Numbers, path: &str) -> Result<f64, SceneError> {
    if v.0.len() != 1 {
        return Err(SceneError::invalid(path, format!("an array of {} numbers", v.0.len()), "must be a single number here (2-D gyroscope)"));
    }
    if !v.0[0].is_finite() {
        return Err(SceneError::invalid(path, v.0[0], "must be finite"));
    }
    Ok(v.0[0])
}

/// An `N×N` matrix from rows.
fn mat<const N: usize>(rows: &[Vec<f64>], path: &str) -> Result<SMatrix<f64, N, N>, SceneError> {
    if rows.len() != N || rows.iter().any(|r| r.len() != N) {
        return Err(SceneError::invalid(path, format!("{} rows", rows.len()), format!("must be a {N}×{N} matrix given as {N} rows of {N} numbers")));
    }
    let m = SMatrix::<f64, N, N>::from_fn(|i, j| rows[i][j]);
    if m.iter().any(|x| !x.is_finite()) {
        return Err(SceneError::invalid(path, "(non-finite entry)", "entries must be finite"));
    }
    Ok(m)
}

/// The frame matrix (columns `e_A`) from a list of `N` vectors of `E` numbers.
fn frame_matrix<const N: usize, const E: usize>(vs: &[Vec<f64>]) -> Result<SMatrix<f64, E, N>, SceneError> {
    if vs.len() != N || vs.iter().any(|r| r.len() != E) {
        return Err(SceneError::invalid("initial.frame", format!("{} vectors", vs.len()), format!("must list {N} frame vectors of {E} numbers each")));
    }
    let m = SMatrix::<f64, E, N>::from_fn(|i, a| vs[a][i]);
    if m.iter().any(|x| !x.is_finite()) {
        return Err(SceneError::invalid("initial.frame", "(non-finite entry)", "entries must be finite"));
    }
    Ok(m)
}

fn init_error(e: crate::Error) -> SceneError {
    let field = match &e {
        crate::Error::InvalidParameter { field, .. } | crate::Error::NotFinite { field } | crate::Error::Constraint { field, .. } => *field,
        _ => "",
    };
    let path = match field {
        "p" => "initial.position",
        "v" | "u" => "initial.velocity",
        "e" | "q" => "initial.frame",
        "spin" => "initial.spin",
        "rho" | "det(rho)" => "initial.rho",
        "rho_dot" => "initial.rho_dot",
        "alpha" => "initial.alpha",
        _ => "initial",
    };
    SceneError::from_core(path, e)
}

/// The initial point: position, velocity, reference bundle element and
/// velocity components in its frame.
struct Init<B: FrameBundle<N, E>, const N: usize, const E: usize> {
    p: SVector<f64, E>,
    v: SVector<f64, E>,
    g: B::Group,
    u: SVector<f64, N>,
}

impl<B: FrameBundle<N, E>, const N: usize, const E: usize> Init<B, N, E> {
    fn new(b: &B, i: &InitialSpec) -> Result<Self, SceneError> {
        let names = b.coordinate_names();
        let get = |name: &str| -> Option<f64> {
            match name {
                "r" => i.r,
                "phi" => i.phi,
                "theta" => i.theta,
                "r1" => i.r1,
                "r2" => i.r2,
                "r3" => i.r3,
                "r_dot" => i.r_dot,
                "phi_dot" => i.phi_dot,
                "theta_dot" => i.theta_dot,
                "r1_dot" => i.r1_dot,
                "r2_dot" => i.r2_dot,
                "r3_dot" => i.r3_dot,
                _ => None,
            }
        };
        // Coordinates of the other manifolds are errors.
        let all = ["r", "phi", "theta", "r1", "r2", "r3"];
        for c in all {
            let rate = format!("{c}_dot");
            for f in [c, rate.as_str()] {
                let own = names.iter().any(|n| *n == c);
                if get(f).is_some() && !own {
                    return Err(SceneError::invalid(format!("initial.{f}"), get(f).unwrap_or(f64::NAN), format!("not a coordinate of this manifold; its coordinates are {}", names.join(", "))));
                }
            }
        }
        let any_chart = names.iter().any(|n| get(n).is_some() || get(&format!("{n}_dot")).is_some());
        if any_chart && (i.position.is_some() || i.velocity.is_some()) {
            return Err(SceneError::invalid("initial.position", "(given with paper coordinates)", "give either the paper's coordinates or position/velocity, not both"));
        }
        if any_chart {
            let mut x = SVector::<f64, N>::zeros();
            let mut xd = SVector::<f64, N>::zeros();
            for (k, n) in names.iter().enumerate() {
                x[k] = get(n).ok_or_else(|| SceneError::invalid(format!("initial.{n}"), "(missing)", format!("all of {} are needed", names.join(", "))))?;
                xd[k] = get(&format!("{n}_dot")).unwrap_or(0.0);
                if !x[k].is_finite() {
                    return Err(SceneError::invalid(format!("initial.{n}"), x[k], "must be finite"));
                }
                if !xd[k].is_finite() {
                    return Err(SceneError::invalid(format!("initial.{n}_dot"), xd[k], "must be finite"));
                }
            }
            b.check_chart(&x).map_err(|e| SceneError::invalid(format!("initial.{}", names[0]), x[0], format!("{e}; at a chart pole give position/velocity instead")))?;
            let g = b.from_chart(&x, &SMatrix::identity()).map_err(|e| SceneError::from_core(&format!("initial.{}", names[0]), e))?;
            let p = b.embed(&x);
            let v = b.embed_tangent(&x, &xd);
            let u = tangent_components(b, &g, &v, "v").map_err(init_error)?;
            Ok(Init { p, v, g, u })
        } else {
            let p = i.position.as_ref().ok_or_else(|| {
                SceneError::invalid("initial.position", "(missing)", format!("give the paper's coordinates ({}) or position = [...]", names.join(", ")))
            })?;
            let p = vec_n::<E>(p, "initial.position")?;
            let v = match &i.velocity {
                Some(v) => vec_n::<E>(v, "initial.velocity")?,
                None => SVector::zeros(),
            };
            let g = bundle_element_at(b, &p).map_err(init_error)?;
            let u = tangent_components(b, &g, &v, "v").map_err(init_error)?;
            Ok(Init { p, v, g, u })
        }
    }
}

/// The event function of `[[events]]` entry `i` over the full record.
fn compile_event(e: &EventSpec, i: usize, cols: &[Column]) -> Result<SceneEvent, SceneError> {
    let path = |f: &str| format!("events[{i}].{f}");
    let kind = match e.kind {
        EventKind::Plane => "plane",
        EventKind::Distance => "distance",
        EventKind::Column => "column",
    };
    let used: &[&str] = match e.kind {
        EventKind::Plane => &["normal", "offset"],
        EventKind::Distance => &["point", "distance"],
        EventKind::Column => &["column", "value"],
    };
    for (f, given) in [
        ("normal", e.normal.is_some()),
        ("offset", e.offset.is_some()),
        ("point", e.point.is_some()),
        ("distance", e.distance.is_some()),
        ("column", e.column.is_some()),
        ("value", e.value.is_some()),
    ] {
        if given && !used.contains(&f) {
            return Err(SceneError::invalid(path(f), "(given)", format!("kind = \"{kind}\" takes only: {}", used.join(", "))));
        }
    }
    let xs: Vec<usize> = cols.iter().enumerate().filter(|(_, c)| c.name.len() == 2 && c.name.starts_with('x')).map(|(j, _)| j).collect();
    let dim = xs.len();
    let vector = |v: &Option<Vec<f64>>, f: &str| -> Result<Vec<f64>, SceneError> {
        let v = v.as_ref().ok_or_else(|| SceneError::invalid(path(f), "(missing)", format!("required for kind = \"{kind}\": {dim} embedding components")))?;
        if v.len() != dim {
            return Err(SceneError::invalid(path(f), format!("an array of {} numbers", v.len()), format!("must have exactly {dim} numbers (embedding components)")));
        }
        if let Some(j) = v.iter().position(|x| !x.is_finite()) {
            return Err(SceneError::invalid(format!("{}[{j}]", path(f)), v[j], "must be finite"));
        }
        Ok(v.clone())
    };
    let number = |v: Option<f64>, f: &str, default: Option<f64>| -> Result<f64, SceneError> {
        let x = v.or(default).ok_or_else(|| SceneError::invalid(path(f), "(missing)", format!("required for kind = \"{kind}\"")))?;
        if !x.is_finite() {
            return Err(SceneError::invalid(path(f), x, "must be finite"));
        }
        Ok(x)
    };
    let g: EventFn = match e.kind {
        EventKind::Plane => {
            let n = vector(&e.normal, "normal")?;
            if n.iter().all(|x| *x == 0.0) {
                return Err(SceneError::invalid(path("normal"), "[0, …]", "must be a non-zero vector"));
            }
            let c = number(e.offset, "offset", Some(0.0))?;
            Arc::new(move |_t, row: &[f64]| xs.iter().zip(&n).map(|(&j, a)| a * row[j]).sum::<f64>() - c)
        }
        EventKind::Distance => {
            let p = vector(&e.point, "point")?;
            let d = number(e.distance, "distance", None)?;
            if d < 0.0 {
                return Err(SceneError::invalid(path("distance"), d, "must be ≥ 0"));
            }
            Arc::new(move |_t, row: &[f64]| xs.iter().zip(&p).map(|(&j, a)| (row[j] - a).powi(2)).sum::<f64>().sqrt() - d)
        }
        EventKind::Column => {
            let name = e.column.as_deref().ok_or_else(|| SceneError::invalid(path("column"), "(missing)", "required for kind = \"column\": a record column"))?;
            let j = cols.iter().position(|c| c.name == name).ok_or_else(|| {
                SceneError::invalid(path("column"), format!("\"{name}\""), format!("not a column of this scene; allowed: {}", cols.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")))
            })?;
            let v = number(e.value, "value", None)?;
            Arc::new(move |_t, row: &[f64]| row[j] - v)
        }
    };
    if let Some(n) = &e.name {
        if n.is_empty() || n.contains([',', '\n', '"']) {
            return Err(SceneError::invalid(path("name"), format!("{n:?}"), "must be non-empty, without commas, quotes or newlines"));
        }
    }
    Ok(SceneEvent { name: e.name.clone().unwrap_or_else(|| format!("event{i}")), g, direction: e.direction, terminal: e.terminal })
}

/// A built scene: run it to a sink, or step it.
pub struct Simulation {
    engine: Box<dyn DynEngine>,
    plan: Plan,
    columns: Vec<Column>,
    event_columns: Vec<Column>,
    name: String,
}

impl fmt::Debug for Simulation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Simulation").field("name", &self.name).field("columns", &self.columns.len()).finish_non_exhaustive()
    }
}

impl Simulation {
    /// The columns of a record (see the [module docs](self)).
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// The method's name.
    pub fn method_name(&self) -> &'static str {
        self.engine.method_name()
    }

    /// The columns an event function sees: every quantity, whatever
    /// `output.quantities` selects.
    pub fn event_columns(&self) -> &[Column] {
        &self.event_columns
    }

    /// Adds an event (after those of the scene's `[[events]]`) to later runs.
    pub fn add_event(&mut self, event: SceneEvent) {
        self.plan.events.push(event);
    }

    /// The events of a run.
    pub fn events(&self) -> &[SceneEvent] {
        &self.plan.events
    }

    /// Runs the scene from its initial state over its time span (the
    /// simulation is reset first and left at the last state reached),
    /// streaming records to `sink`; `cancel` is polled every few hundred steps (a
    /// cancelled run stops cleanly with [`SceneStop::Cancelled`] and the last
    /// state recorded); `progress` is called at most every 50 ms.
    ///
    /// On an integration failure the records up to the last good state have
    /// been written and the error comes with the summary ([`RunFailure`]).
    pub fn run(&mut self, sink: &mut dyn RecordSink, cancel: &AtomicBool, progress: &mut dyn FnMut(&Progress)) -> Result<RunSummary, RunFailure> {
        let started = Instant::now();
        let mut summary = RunSummary::new(self.engine.method_name(), self.plan.t0);
        if let Err(e) = sink.columns(&self.columns) {
            summary.stop = SceneStop::OutputError(e.to_string());
            return Err(RunFailure { error: RunError::Io(e), summary });
        }
        let mut ctx = engine::Ctx {
            sink,
            cancel,
            progress,
            summary,
            buf: Vec::with_capacity(self.columns.len()),
            last_recorded_t: None,
            ev_sign: Vec::new(),
            ev_g: Vec::new(),
            full: Vec::new(),
            mm_idx: self.columns.iter().enumerate().filter(|(_, c)| c.name == "p_phi" || c.name.starts_with("J_")).map(|(j, _)| j).collect(),
            mm0: Vec::new(),
            last_progress: started,
        };
        let result = self.engine.run(&self.plan, &mut ctx);
        ctx.progress(&self.plan, self.engine.t(), true);
        let mut summary = ctx.summary;
        summary.t_reached = self.engine.t();
        summary.wall_time = started.elapsed();
        match result {
            Ok(()) => Ok(summary),
            Err(error) => {
                summary.stop = match &error {
                    RunError::Integration(e) => SceneStop::Failed(e.clone()),
                    RunError::Io(e) => SceneStop::OutputError(e.to_string()),
                    RunError::Scene(e) => SceneStop::OutputError(e.to_string()),
                };
                Err(RunFailure { error, summary })
            }
        }
    }

    /// Advances the current state by one step of size `h` with the scene's
    /// method (stepping API; [`Self::run`] always starts again from the
    /// initial state).
    pub fn step(&mut self, h: f64) -> Result<(), SolveError> {
        self.engine.step(h)
    }

    /// `n` steps of size `h`; stops at the first failure.
    pub fn advance(&mut self, h: f64, n: usize) -> Result<(), SolveError> {
        for _ in 0..n {
            self.engine.step(h)?;
        }
        Ok(())
    }

    /// Current time of the stepping API.
    pub fn t(&self) -> f64 {
        self.engine.t()
    }

    /// The current state as one record (values in the order of [`Self::columns`]).
    pub fn row(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.columns.len());
        self.engine.row(self.plan.sel, &mut out);
        out
    }

    /// The value of column `name` in the current state.
    pub fn value(&self, name: &str) -> Option<f64> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.row()[j])
    }

    /// Energy of the current state.
    pub fn energy(&self) -> f64 {
        self.engine.energy()
    }

    /// Constraint defect of the current state.
    pub fn defect(&self) -> f64 {
        self.engine.defect()
    }

    /// Back to the initial state.
    pub fn reset(&mut self) {
        self.engine.reset()
    }

    /// The time span `(t₀, t_end)`.
    pub fn span(&self) -> (f64, f64) {
        (self.plan.t0, self.plan.t_end)
    }
}

