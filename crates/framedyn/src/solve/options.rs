//! Options of a solve: step-size policy, tolerances, output, recorded
//! invariants and events.

use std::fmt;

use super::driver::Settings;
use super::projection::Projection;
use super::event::Event;
use crate::lie::LieGroup;

/// How steps are chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum StepSize {
    /// `n` equal steps of size at most `h` ([`fixed_step_count`](super::fixed_step_count):
    /// `|t_end − t₀|/h` when that is an integer to 1e-9, else its ceiling;
    /// the interval is split exactly, the last step lands on `t_end`). Step
    /// times are computed as `t₀ + (t_end − t₀)·i/n`, without accumulation.
    Fixed(f64),
    /// Error-controlled steps with an embedded pair.
    Adaptive(Adaptive),
}

/// A tolerance: one value for every component, or one per stored algebra
/// component (`AlgebraVector::LEN` values, in the order of
/// [`AlgebraVector::get`](crate::lie::AlgebraVector::get)).
#[derive(Debug, Clone, PartialEq)]
pub enum Tol {
    /// The same value for every component.
    Scalar(f64),
    /// One value per stored component.
    PerComponent(Vec<f64>),
}

impl From<f64> for Tol {
    fn from(v: f64) -> Self {
        Tol::Scalar(v)
    }
}

/// Step-size controller (\[HNW93\] §II.4; PI form after Gustafsson, as in the
/// code DOPRI5).
///
/// With the error norm `err` of a step (accept iff `err ≤ 1`), `k = 1/(q+1)`,
/// `q = min(p, p̂)` the lower order of the pair, and `α = k − 0.75β`:
/// - accepted: `h_new = h·clamp(safety·err^{−α}·err_prev^{β}, fac_min, fac_max)`
///   (`err_prev` the previous accepted error, ≥ 10⁻⁴); after a rejection the
///   factor is capped at 1;
/// - rejected: `h_new = h·max(fac_min, safety·err^{−α})`.
///
/// `β = 0` is the classical (integral, I) controller `h·(safety/err)^{1/(q+1)}`.
///
/// \[HNW93\] E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary
/// Differential Equations I*, 2nd ed., Springer 1993.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Controller {
    /// PI gain `β ∈ [0, 0.2]` (0: I controller).
    pub beta: f64,
    /// Safety factor in `(0, 1]`.
    pub safety: f64,
    /// Smallest step-size factor, in `(0, 1]`.
    pub fac_min: f64,
    /// Largest step-size factor, `≥ 1`.
    pub fac_max: f64,
}

impl Controller {
    /// The I controller: `β = 0`, safety 0.9, factors in `[0.2, 10]`.
    pub const fn integral() -> Self {
        Controller { beta: 0.0, safety: 0.9, fac_min: 0.2, fac_max: 10.0 }
    }

    /// The PI controller of DOPRI5: `β = 0.04`, safety 0.9, factors in `[0.2, 10]`.
    pub const fn pi() -> Self {
        Controller { beta: 0.04, safety: 0.9, fac_min: 0.2, fac_max: 10.0 }
    }
}

impl Default for Controller {
    fn default() -> Self {
        Controller::pi()
    }
}

/// Adaptive stepping with an embedded pair.
///
/// **Error norm.** A step's error estimate is `e = Θ − Θ̂ ∈ 𝔤`, the
/// difference of the algebra increments of the two solutions (left
/// trivialised: `y₀·exp(Θ̂) ≈ y₀·exp(Θ)·exp(−e)`). With the reference
/// magnitudes `sᵢ(y)` of [`GroupNumerics::tolerance_scale`](crate::method::GroupNumerics::tolerance_scale)
/// — `|yᵢ|` for the coordinates of additive factors ℝᵏ (momenta,
/// velocities, angles), 1 for every other factor, where `e` is a relative
/// error of the group element (a rotation angle on SO(n)) — the
/// per-component scale is
/// `scᵢ = atolᵢ + rtolᵢ·max(sᵢ(y₀), sᵢ(y₁))`
/// and `err = maxᵢ |eᵢ|/scᵢ` over the `LEN` stored components. A step is
/// accepted iff `err ≤ 1`, i.e. iff *every* component's local error is
/// within its tolerance. So `atol` is an absolute error in algebra
/// coordinates and `rtol` an error relative to the size of additive
/// coordinates and relative to the group element otherwise. Per-component
/// tolerances ([`Tol::PerComponent`]) follow the stored components of the
/// algebra ([`AlgebraVector::get`](crate::lie::AlgebraVector::get)), e.g. for
/// `SO(3) × ℝ³` the three rotation angles, then the three momenta.
///
/// These are the variables in which a run's error is measured, or bound
/// them: for the models of [`dynamics`](crate::dynamics) the state is
/// `(g, ρ, u, π)` — the frame-bundle element `g`, whose rotation angles move
/// the embedded position by `R·angle` and turn the frame by `angle`, the
/// internal configuration `ρ` (relative, like `g`), the velocity `u` in the
/// frame and the internal momenta `π` (absolute/relative per component) —
/// and the embedded velocity `ẋ = q·u` has error at most `|δu| + |u|·|δq|`,
/// both terms controlled.
///
/// The maximum, not the root-mean-square `√(Σᵢ (eᵢ/scᵢ)²/LEN)` of the codes
/// of \[HNW93\] and SciPy: the mean would let one component's error reach
/// `√LEN` times its tolerance, so that the same `tol` meant a different
/// accuracy for a point on S² (`LEN = 5`) and an affine body (`LEN = 13`).
///
/// **Estimates.** DOPRI5 ([`Rkmk::dopri5`](crate::method::Rkmk::dopri5)):
/// `e = Θ₅ − Θ₄`, the error of the fourth-order solution, while the
/// fifth-order one is propagated (local extrapolation). DOP853
/// ([`Rkmk::dop853`](crate::method::Rkmk::dop853)): Hairer's combined
/// estimate `‖e₅‖²/√(‖e₅‖² + 0.01‖e₃‖²)` of its embedded fifth- and
/// third-order solutions, `O(h⁸)`, with the eighth-order solution propagated
/// (the ratio inside is taken with the weights `1/(1 + max(sᵢ(y₀), sᵢ(y₁)))`
/// in the root-mean-square, which matches the driver's scale when
/// `atol = rtol` are scalars; it only decides how much of `e₅` counts).
///
/// **What the tolerance means.** `err ≤ 1` is a criterion *per step* on the
/// local error, as in the codes DOPRI5/DOP853 \[HNW93\] and SciPy; the
/// global error at `t_end` is the sum of the local errors carried along by
/// the flow, so it grows with the number of steps and with the flow's
/// amplification of perturbations, and no step-size controller bounds it by
/// `tol` alone. What it is on measured problems — proportional to `tol`,
/// within 12 × tol (DOP853) and 35 × tol (DOPRI5) on the measured flows
/// that do not amplify errors strongly, and orders of magnitude above `tol` at sharp
/// Kepler pericentre passages — is in `docs/performance.md` ("Tolerance
/// proportionality"), measured by `scripts/tolerance_proportionality.py`;
/// a scene can ask for an estimate of its global error (`[method]
/// global_error = true`).
///
/// **First step.** Without `h0` the first step is chosen as in \[HNW93\]
/// §II.4 and then used as a probe: while the controller's own next step
/// would still leave the error below 1e-2 (the formula's step is
/// deliberately small, and DOP853's PI controller climbs slowly from it),
/// it is taken again with the step that aims at the error the controller
/// settles at, at most three times
/// ([`Stats::first_step_probes`](super::Stats::first_step_probes)).
/// Accepted as it was, a short run at a loose tolerance spent most of its
/// span ramping up from it, with errors far below `tol` there
/// (`docs/performance.md`, "Tolerance proportionality").
///
/// **Tolerance limits.** `rtol ≥` [`RTOL_MIN`] `= 1e-14` (below it the
/// error estimate is round-off) and `atol > 0`, both finite; an `atol` so
/// small that the first step underflows (a component that is zero at `t₀`
/// is scaled by `atol` alone) is an error naming `atol`.
///
/// **Minimum step.** A step smaller than `max(h_min, 16ε·max(|t|, |t_end|))`
/// (other than a final step that reaches `t_end`) is a
/// [`StepSizeTooSmall`](super::SolveError::StepSizeTooSmall) error, never a
/// silent acceptance.
#[derive(Debug, Clone, PartialEq)]
pub struct Adaptive {
    /// Relative tolerance(s), finite and `≥` [`RTOL_MIN`].
    pub rtol: Tol,
    /// Absolute tolerance(s), finite and `> 0`.
    pub atol: Tol,
    /// First step `|h₀|`, taken as given; `None` selects it as in
    /// \[HNW93\] §II.4 (with an explicit Lie–Euler trial step, and
    /// `|h₀|·ρ(ad f₀)` at most half the radius guard) and probes it (see
    /// "First step" above).
    pub h0: Option<f64>,
    /// Smallest allowed `|h|` (the effective minimum is `max(h_min, 16ε·max(|t|, |t_end|))`).
    pub h_min: f64,
    /// Largest allowed `|h|` (`∞`: the span).
    pub h_max: f64,
    /// The controller.
    pub controller: Controller,
}

impl Adaptive {
    /// Scalar tolerances, automatic first step, `h_min = 0`, `h_max = ∞`,
    /// PI controller.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Adaptive {
            rtol: Tol::Scalar(rtol),
            atol: Tol::Scalar(atol),
            h0: None,
            h_min: 0.0,
            h_max: f64::INFINITY,
            controller: Controller::default(),
        }
    }
}

/// Which states a run saves (besides the state it stops at: see
/// [`driver`](super::driver)).
#[derive(Debug, Clone, PartialEq)]
pub enum Save {
    /// `t₀` and the end of every accepted step.
    Steps,
    /// `t₀`, the end of every `k`-th accepted step (`k ≥ 1`) and the final
    /// state.
    Every(u64),
    /// Exactly the given times (sorted into the direction of integration;
    /// each within the span), from the method's continuous extension over
    /// the step that contains them — independent of the steps taken.
    At(Vec<f64>),
    /// `t₀` and the final time only.
    Ends,
}

/// A recorded scalar `q(t, y)`.
pub type ObserverFn<G> = dyn Fn(f64, &G) -> f64 + Send + Sync;

/// Options of [`solve`](super::solve). Built from [`Options::fixed`] or
/// [`Options::adaptive`] and the builder methods.
pub struct Options<G: LieGroup> {
    pub(crate) settings: Settings,
    pub(crate) energy: bool,
    pub(crate) defect: bool,
    pub(crate) observers: Vec<(String, Box<ObserverFn<G>>)>,
    pub(crate) events: Vec<Event<G>>,
}

impl<G: LieGroup> fmt::Debug for Options<G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Options")
            .field("settings", &self.settings)
            .field("energy", &self.energy)
            .field("defect", &self.defect)
            .field("observers", &self.observers.iter().map(|o| &o.0).collect::<Vec<_>>())
            .field("events", &self.events)
            .finish()
    }
}

/// The smallest relative tolerance, `1e-14` (≈ 45ε): below it the local
/// error estimate of a step is round-off, and the controller would shrink the
/// step until it underflows.
pub const RTOL_MIN: f64 = 1e-14;

/// Default limit on the number of accepted steps.
pub const DEFAULT_MAX_STEPS: usize = 1_000_000;

impl<G: LieGroup> Options<G> {
    fn with_step(step: StepSize) -> Self {
        Options {
            settings: Settings { step, save: Save::Steps, dense: false, max_steps: DEFAULT_MAX_STEPS, event_xtol: 0.0, projection: Projection::None },
            energy: false,
            defect: false,
            observers: Vec::new(),
            events: Vec::new(),
        }
    }

    /// Fixed steps of size at most `h` (see [`StepSize::Fixed`]).
    pub fn fixed(h: f64) -> Self {
        Self::with_step(StepSize::Fixed(h))
    }

    /// Adaptive steps with scalar tolerances (see [`Adaptive`]).
    pub fn adaptive(rtol: f64, atol: f64) -> Self {
        Self::with_step(StepSize::Adaptive(Adaptive::new(rtol, atol)))
    }

    /// Adaptive steps with full control.
    pub fn adaptive_with(adaptive: Adaptive) -> Self {
        Self::with_step(StepSize::Adaptive(adaptive))
    }

    /// Which states to keep (default [`Save::Steps`]).
    pub fn save(mut self, save: Save) -> Self {
        self.settings.save = save;
        self
    }

    /// Keep the dense output of every step (default: no).
    pub fn dense(mut self, dense: bool) -> Self {
        self.settings.dense = dense;
        self
    }

    /// Limit on the number of accepted steps (default [`DEFAULT_MAX_STEPS`]);
    /// reaching it before `t_end` is a [`MaxSteps`](super::SolveError::MaxSteps) error.
    pub fn max_steps(mut self, n: usize) -> Self {
        self.settings.max_steps = n;
        self
    }

    /// Record [`System::energy`](crate::dynamics::System::energy) at the saved times, as `"energy"`.
    pub fn record_energy(mut self) -> Self {
        self.energy = true;
        self
    }

    /// Record [`System::defect`](crate::dynamics::System::defect) at the saved times, as `"defect"`.
    pub fn record_defect(mut self) -> Self {
        self.defect = true;
        self
    }

    /// Record `q(t, y)` at the saved times under `name`.
    pub fn observe(mut self, name: impl Into<String>, q: impl Fn(f64, &G) -> f64 + Send + Sync + 'static) -> Self {
        self.observers.push((name.into(), Box::new(q)));
        self
    }

    /// Add an event.
    pub fn event(mut self, event: Event<G>) -> Self {
        self.events.push(event);
        self
    }

    /// Project the end of every accepted step back onto a first integral
    /// (default [`Projection::None`]; see [`projection`](super::projection)).
    pub fn project(mut self, projection: Projection) -> Self {
        self.settings.projection = projection;
        self
    }

    /// Absolute time tolerance of event location (default 0: to round-off,
    /// `2ε|t|`).
    pub fn event_tolerance(mut self, xtol: f64) -> Self {
        self.settings.event_xtol = xtol;
        self
    }

    /// The step-size policy.
    pub fn step_size(&self) -> &StepSize {
        &self.settings.step
    }

    /// The step-size, sampling and event settings (what the driver reads).
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
}
