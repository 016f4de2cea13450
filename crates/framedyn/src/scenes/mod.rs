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
//! # Layout
//!
//! [`scene`](Scene) (parse, serialise, build), `spec` (the serde tables),
//! `manifolds` (the one place that knows the manifolds), `plan` (method,
//! time and output → the driver's settings), `initial` (the initial state),
//! `build` (models, generic over the frame bundle), `potential` (the
//! potential families), `events`, `observe` (the columns of a record),
//! `sink`, `summary`, `simulation` (the engine on the driver), `examples`.
//! There is no stepping loop here: every run is [`solve::drive`](crate::solve::drive).
//!
//! # Scene files
//!
//! Tables (every one rejects unknown fields): `[manifold]` (`kind` and its
//! size, see [`ManifoldSpec`]: `S2`, `H2`, `S3` with `radius`, `T2` with
//! `L`/`R`), `[body]` (`kind` = `point`, `gyroscope`, `affine`,
//! `incompressible`, `weyl`, `dilatation`; `mass`, `inertia` or `J`,
//! `signature` = `riemannian`/`lorentz`), `[potential]` (see
//! [`PotentialKind`]), `[initial]` (see [`InitialSpec`]: the manifold's own
//! chart coordinates — `r, phi` / `theta, phi` / `r1, r2, r3` — and their
//! `_dot` rates, or `position`/`velocity` arrays in the embedding; `alpha`,
//! `omega`, `spin`, `orientation`, `frame`, `rho`, `rho_dot` for the body),
//! `[method]` (`name` from the method registry
//! [`METHODS`](crate::method::METHODS); `h` for fixed steps, or `rtol`, `atol`
//! with the adaptive methods; `max_steps`; `newton_tol`, `newton_max_iter`
//! with `implicit_midpoint`), `[time]` (`t0`, `t_end`), `[output]` (`every`,
//! `times` or `samples`; `quantities`; `format` = `csv`/`npz`; `path`),
//! `[quality]` (`energy_drift`, `defect`: the limits the run's summary is
//! judged against, see [`QualitySpec`]), `[[events]]` (see [`EventSpec`]). The embedded examples ([`EXAMPLES`])
//! cover every manifold × body and every potential family.
//!
//! # Methods
//!
//! Every method of the registry ([`registry`](crate::method::registry):
//! name, display name, family, order, stepping, what it needs) is a scene
//! method; `framedyn methods` and `framedyn.methods()` list them, and the
//! guide's table is generated from the same entries. A method a model cannot
//! take (a splitting without exact free flows, a coordinate method without
//! chart equations) is refused by [`Scene::validate`] (`framedyn validate`)
//! with an error naming `method.name`, the value and the methods allowed for
//! that manifold × body ([`Scene::allowed_methods`]).
//!
//! # Events
//!
//! Each `[[events]]` entry is a built-in event function `g` of the record:
//! `kind = "plane"` (`normal·x − offset`, embedding position: Poincaré
//! sections), `"distance"` (`|x − point| − distance`, Euclidean in the
//! embedding: pole passages), `"column"` (`column − value` for any record
//! column: the paper's coordinates, `energy`, …), with `direction` =
//! `rising`/`falling`/`either` and `terminal`. They are the crate's one
//! event type ([`Event`](crate::solve::Event), here on the record) with its
//! one semantics: crossings are located by the driver
//! ([`solve::driver`](crate::solve::driver)) with Brent's method on the
//! method's own continuous extension — a sub-step of the method from the
//! start of the step (fixed steps), or the dense output of an adaptive
//! method — so the time is as accurate as the trajectory (round-off on exact
//! flows; tested on a geodesic to 1e-10 in `tests/suite/scenes.rs`). They
//! arrive at [`RecordSink::event`] ([`MemorySink::events`]; the CLI writes
//! `STEM.events.csv`); a terminal event ends the run with
//! [`SceneStop::Event`] at the event's state. Rust and Python users add
//! their own functions with [`Simulation::add_event`].
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
//! | `frame_rate` | affine bodies: `de1_0 … deN_{E−1}`, the covariant rate `De_a/Dt = q ρ̇` of the body frame vectors (embedding components, the layout of `frame`) | 1/T |
//! | `energy` | `energy`: `T + V` | M L²/T² |
//! | `momentum_map` | `p_phi` (rotations about the ambient z axis; S², H², T²) or `J_ab` (the rotation in the `(a, b)` plane of ℝ⁴; S³) | M L²/T |
//! | `defect` | `defect`: distance of the state from its constraints | 1 |

mod analysis;
mod build;
mod chart;
mod ensemble;
pub mod error;
mod events;
mod examples;
mod fields;
mod initial;
pub(crate) mod locate;
mod manifolds;
mod observe;
mod plan;
pub mod potential;
mod scene;
mod simulation;
mod sink;
pub mod spec;
mod summary;

pub use analysis::{SceneAnalysisError, Section};
pub use error::{Location, RunError, SceneError};
pub use ensemble::{run_ensemble, run_ensemble_blocks, worker_threads, Ensemble, EnsembleOptions, Keep, MemberOutcome, MemberStatus, Table};
pub(crate) use ensemble::{workers, Workers};
pub use examples::{example, DEFAULT_SCENE, EXAMPLES};
pub use fields::FieldPath;
pub use plan::DEFAULT_SCENE_MAX_STEPS;
pub use potential::{AngularSeries, Potential2, Potential3, SeparableSeries, Series, UserFunctions, UserGradientFn, UserPotential, UserPotentialFn};
pub use scene::Scene;
pub use simulation::Simulation;
pub use sink::{Column, EventHit, FlatSink, MemorySink, RecordSink};
pub use spec::*;
pub use summary::{GlobalError, Progress, ProjectionCounts, QualityWarning, RunFailure, RunSummary, SceneStop};

/// An event on the full record of a scene (one value per column of
/// [`Simulation::event_columns`]): the crate's one event type on records.
pub type SceneEvent = crate::solve::Event<[f64]>;

/// The function of a [`SceneEvent`]: `g(t, row)`.
pub type EventFn = std::sync::Arc<crate::solve::event::EventFn<[f64]>>;
