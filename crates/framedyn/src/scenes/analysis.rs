//! The analyses of [`crate::analysis`] on a scene: its model, initial state,
//! method and steps (fixed `h`, or error-controlled by `rtol`/`atol`),
//! type-erased like the simulation's engine.

use std::sync::atomic::AtomicBool;

use super::build::Make;
use super::chart::ChartTwin;
use super::error::SceneError;
use super::observe::Observe;
use super::scene::Scene;
use crate::analysis::{gali, lyapunov_spectrum, megno, sali, two_trajectory, AnalysisError, GaliEstimate, GaliOptions, LyapunovEstimate, LyapunovOptions, MegnoEstimate, MegnoOptions, SaliEstimate, SaliOptions, TwoTrajectoryEstimate, TwoTrajectoryOptions};
use crate::lie::LieGroup;
use crate::method::registry::{AnyMethod, Built, Needs};
use crate::solve::{SolveError, StepSize};

/// The object-safe face of a typed model for the analyses.
pub(crate) trait DynAnalysis: Send {
    fn dof(&self) -> usize;
    /// The number of gauge directions at the initial state ([`System::gauge`](crate::dynamics::System::gauge)).
    fn gauge_directions(&self) -> usize;
    fn supports(&self, needs: Needs) -> bool;
    fn lyapunov(&self, method: &AnyMethod, t0: f64, opts: &LyapunovOptions, cancel: &AtomicBool) -> Result<LyapunovEstimate, AnalysisError>;
    fn two_trajectory(&self, method: &AnyMethod, t0: f64, opts: &TwoTrajectoryOptions, cancel: &AtomicBool) -> Result<TwoTrajectoryEstimate, AnalysisError>;
    fn sali(&self, method: &AnyMethod, t0: f64, opts: &SaliOptions, cancel: &AtomicBool) -> Result<SaliEstimate, AnalysisError>;
    fn megno(&self, method: &AnyMethod, t0: f64, opts: &MegnoOptions, cancel: &AtomicBool) -> Result<MegnoEstimate, AnalysisError>;
    fn gali(&self, method: &AnyMethod, t0: f64, opts: &GaliOptions, cancel: &AtomicBool) -> Result<GaliEstimate, AnalysisError>;
}

struct Typed<S: Observe> {
    system: S,
    y0: S::State,
}

impl<S: Observe> DynAnalysis for Typed<S> {
    fn dof(&self) -> usize {
        S::State::DOF
    }
    fn gauge_directions(&self) -> usize {
        crate::dynamics::System::gauge(&self.system, &self.y0).len()
    }
    fn supports(&self, needs: Needs) -> bool {
        match needs {
            Needs::Nothing => true,
            Needs::ExactFreeFlow => self.system.as_splittable().is_some(),
            Needs::Chart => false,
        }
    }
    fn lyapunov(&self, method: &AnyMethod, t0: f64, opts: &LyapunovOptions, cancel: &AtomicBool) -> Result<LyapunovEstimate, AnalysisError> {
        lyapunov_spectrum(&self.system, method, t0, &self.y0, opts, Some(cancel))
    }
    fn two_trajectory(&self, method: &AnyMethod, t0: f64, opts: &TwoTrajectoryOptions, cancel: &AtomicBool) -> Result<TwoTrajectoryEstimate, AnalysisError> {
        two_trajectory(&self.system, method, t0, &self.y0, opts, Some(cancel))
    }
    fn sali(&self, method: &AnyMethod, t0: f64, opts: &SaliOptions, cancel: &AtomicBool) -> Result<SaliEstimate, AnalysisError> {
        sali(&self.system, method, t0, &self.y0, opts, Some(cancel))
    }
    fn megno(&self, method: &AnyMethod, t0: f64, opts: &MegnoOptions, cancel: &AtomicBool) -> Result<MegnoEstimate, AnalysisError> {
        megno(&self.system, method, t0, &self.y0, opts, Some(cancel))
    }
    fn gali(&self, method: &AnyMethod, t0: f64, opts: &GaliOptions, cancel: &AtomicBool) -> Result<GaliEstimate, AnalysisError> {
        gali(&self.system, method, t0, &self.y0, opts, Some(cancel))
    }
}

/// The typed model of a scene for the analyses.
pub(crate) struct Analyses;

impl Make for Analyses {
    type Out = Box<dyn DynAnalysis>;
    fn make<S: Observe>(system: S, y0: S::State, _span: (f64, f64), _chart: Option<Box<dyn ChartTwin<S>>>) -> Result<Self::Out, SolveError> {
        if !crate::solve::state_is_finite(&y0) {
            return Err(SolveError::InvalidInitialState { defect: y0.constraint_defect() });
        }
        Ok(Box::new(Typed { system, y0 }))
    }
}

/// Why an analysis of a scene failed: the scene (invalid or unsuitable:
/// exit code 3 of the command line) or the analysis (its options, or a
/// failed step: exit code 4).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneAnalysisError {
    /// The scene is invalid, or its method or step cannot be used.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The analysis failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
}

/// The scene's model, method, `t₀`, steps, span and step limit.
struct Prepared {
    model: Box<dyn DynAnalysis>,
    method: AnyMethod,
    t0: f64,
    step: StepSize,
    duration: f64,
    /// `method.max_steps`, at most [`crate::analysis::MAX_STEPS`].
    max_steps: usize,
}

impl Scene {
    fn prepare_analysis(&self) -> Result<Prepared, SceneError> {
        let plan = self.plan().map_err(|e| self.locate(e))?;
        let model = self.build_engine::<Analyses>(None, &(plan.t0, plan.t_end)).map_err(|e| self.locate(e))?;
        let method = match plan.method {
            Built::Group(m) => m,
            Built::Chart(_) => {
                return Err(self.locate(SceneError::invalid(
                    "method.name",
                    format!("\"{}\"", plan.entry.name),
                    "a Lie-group method: tangent vectors live in the state group's algebra, the coordinate methods have none",
                )))
            }
        };
        if !model.supports(plan.entry.needs) {
            return Err(self.locate(SceneError::invalid("method.name", format!("\"{}\"", plan.entry.name), format!("a method this model can take (it needs {})", plan.entry.needs.describe()))));
        }
        let max_steps = plan.settings.max_steps.min(crate::analysis::MAX_STEPS);
        Ok(Prepared { model, method, t0: plan.t0, step: plan.settings.step.clone(), duration: plan.t_end - plan.t0, max_steps })
    }

    /// The dimension of the scene's state group: the number of Lyapunov
    /// exponents of its full spectrum.
    pub fn state_dimension(&self) -> Result<usize, SceneError> {
        Ok(self.prepare_analysis()?.model.dof())
    }

    /// The dimension of the scene's phase space: the state group's less
    /// the gauge directions of its parallel frame
    /// ([`System::gauge`](crate::dynamics::System::gauge)), in which
    /// [`gali`](Self::gali) measures by default
    /// ([`GaliOptions::quotient`]).
    pub fn phase_space_dimension(&self) -> Result<usize, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.dof() - p.model.gauge_directions())
    }

    /// [`LyapunovOptions`] with the scene's steps (fixed or error-controlled),
    /// time span and `method.max_steps` (the other settings at their defaults: the largest
    /// exponent only).
    pub fn lyapunov_options(&self) -> Result<LyapunovOptions, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(LyapunovOptions { max_steps: p.max_steps, ..LyapunovOptions::with_step(p.step, p.duration) })
    }

    /// [`TwoTrajectoryOptions`] with the scene's steps, time span and `method.max_steps`.
    pub fn two_trajectory_options(&self) -> Result<TwoTrajectoryOptions, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(TwoTrajectoryOptions { max_steps: p.max_steps, ..TwoTrajectoryOptions::with_step(p.step, p.duration) })
    }

    /// The Lyapunov exponents of the scene's trajectory
    /// ([`lyapunov_spectrum`]) with its method from its `t₀`; `opts.step`
    /// and `opts.duration` as given (see [`Scene::lyapunov_options`]). Needs
    /// a Lie-group method (fixed `method.h`, or `rtol`/`atol` with an
    /// embedded pair).
    pub fn lyapunov(&self, opts: &LyapunovOptions, cancel: &AtomicBool) -> Result<LyapunovEstimate, SceneAnalysisError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.lyapunov(&p.method, p.t0, opts, cancel)?)
    }

    /// [`SaliOptions`] with the scene's steps, time span and `method.max_steps`.
    pub fn sali_options(&self) -> Result<SaliOptions, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(SaliOptions { max_steps: p.max_steps, ..SaliOptions::with_step(p.step, p.duration) })
    }

    /// The Smaller Alignment Index of the scene's trajectory ([`sali()`]): a
    /// fast chaos indicator for maps over initial conditions.
    pub fn sali(&self, opts: &SaliOptions, cancel: &AtomicBool) -> Result<SaliEstimate, SceneAnalysisError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.sali(&p.method, p.t0, opts, cancel)?)
    }

    /// [`MegnoOptions`] with the scene's steps, time span and `method.max_steps`.
    pub fn megno_options(&self) -> Result<MegnoOptions, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(MegnoOptions { max_steps: p.max_steps, ..MegnoOptions::with_step(p.step, p.duration) })
    }

    /// MEGNO of the scene's trajectory ([`megno()`]): a fast chaos
    /// indicator from one tangent vector, `⟨Y⟩ → 2` on a quasi-periodic
    /// orbit, growing like `λ₁t/2` on a chaotic one.
    pub fn megno(&self, opts: &MegnoOptions, cancel: &AtomicBool) -> Result<MegnoEstimate, SceneAnalysisError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.megno(&p.method, p.t0, opts, cancel)?)
    }

    /// [`GaliOptions`] with the scene's steps, time span, `method.max_steps` and `k` vectors.
    pub fn gali_options(&self, k: usize) -> Result<GaliOptions, SceneError> {
        let p = self.prepare_analysis()?;
        Ok(GaliOptions { max_steps: p.max_steps, ..GaliOptions::with_step(p.step, p.duration, k) })
    }

    /// The Generalised Alignment Index `GALI_k` of the scene's trajectory
    /// ([`gali()`]).
    pub fn gali(&self, opts: &GaliOptions, cancel: &AtomicBool) -> Result<GaliEstimate, SceneAnalysisError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.gali(&p.method, p.t0, opts, cancel)?)
    }

    /// The two-trajectory estimate of the maximal exponent ([`two_trajectory`]).
    pub fn two_trajectory(&self, opts: &TwoTrajectoryOptions, cancel: &AtomicBool) -> Result<TwoTrajectoryEstimate, SceneAnalysisError> {
        let p = self.prepare_analysis()?;
        Ok(p.model.two_trajectory(&p.method, p.t0, opts, cancel)?)
    }
}

/// The crossings of a Poincaré section: one row per crossing, located on the
/// method's continuous extension by the driver's event machinery
/// ([`crate::solve::event`]), with every column of the scene's record.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// The section's name.
    pub name: String,
    /// The columns of a row (`t` first, then those of
    /// [`Simulation::event_columns`](super::Simulation::event_columns)).
    pub columns: Vec<super::Column>,
    /// The rows, one after the other (`crossings × columns.len()` numbers).
    pub data: Vec<f64>,
    /// Whether each crossing was rising (`g` from − to +).
    pub rising: Vec<bool>,
}

impl Section {
    /// Number of crossings.
    pub fn len(&self) -> usize {
        self.rising.len()
    }
    /// True if there was no crossing.
    pub fn is_empty(&self) -> bool {
        self.rising.is_empty()
    }
    /// The values of column `name` at the crossings.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let w = self.columns.len();
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.data.chunks(w).map(|r| r[j]).collect())
    }
}

/// A sink keeping the crossings of event 0 only (records are not built).
struct Crossings {
    section: Section,
}

impl super::RecordSink for Crossings {
    fn columns(&mut self, _columns: &[super::Column]) -> std::io::Result<()> {
        Ok(())
    }
    fn record(&mut self, _row: &[f64]) -> std::io::Result<()> {
        Ok(())
    }
    fn event(&mut self, hit: &super::EventHit) -> std::io::Result<()> {
        self.section.data.extend_from_slice(&hit.row);
        self.section.rising.push(hit.rising);
        Ok(())
    }
    fn last_only(&self) -> bool {
        true
    }
}

impl Scene {
    /// The Poincaré section of the scene's trajectory by `section` (an
    /// `[[events]]` entry: `plane`, `column` or `distance`, with its
    /// direction; `terminal` is ignored): every crossing over the scene's
    /// span with the whole record (all quantities) at it. The scene's own
    /// events and output settings are not used.
    pub fn section(&self, section: &super::EventSpec, cancel: &AtomicBool) -> Result<Section, SceneAnalysisError> {
        let mut scene = self.clone();
        scene.output.quantities = None;
        scene.output.times = None;
        scene.output.samples = None;
        scene.output.every = None;
        scene.events = vec![super::EventSpec { terminal: false, ..section.clone() }];
        let mut sim = scene.build().map_err(|e| match e {
            SceneError::Invalid { path, value, allowed, location } if path.starts_with("events[0]") => {
                SceneError::Invalid { path: path.replacen("events[0]", "section", 1), value, allowed, location }
            }
            e => e,
        })?;
        let name = sim.events()[0].name().to_string();
        let name = if section.name.is_none() { "section".to_string() } else { name };
        let mut sink = Crossings { section: Section { name, columns: sim.event_columns().to_vec(), data: Vec::new(), rising: Vec::new() } };
        match sim.run(&mut sink, cancel, &mut |_| {}) {
            Ok(summary) => match summary.stop {
                super::SceneStop::Cancelled => Err(AnalysisError::Cancelled { t: summary.t_reached }.into()),
                _ => Ok(sink.section),
            },
            Err(f) => match f.error {
                super::RunError::Integration(e) => Err(AnalysisError::Solve(e).into()),
                other => Err(AnalysisError::invalid("section", other.to_string(), "a run without output errors").into()),
            },
        }
    }
}
