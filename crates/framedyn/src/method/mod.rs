//! One-step methods on Lie groups: a method only advances one step; the
//! driver in [`solve`](crate::solve) owns step-size control, output, events
//! and failure handling.
//!
//! Problem: `ẏ = y·f(t, y)` on a Lie group ([`System`]). Every method here
//! writes the solution near `y₀` as `y(t₀ + τ) = y₀·exp(θ(τ))`, for which
//! `θ̇ = dexp⁻¹_{−θ} f(t₀ + τ, y₀·exp(θ))`, `θ(0) = 0` (the conventions of
//! [`lie`](crate::lie)). Each step starts again from `θ = 0` at the new point
//! ("rebasing"), so `θ` stays of size `h·|f|`.
//!
//! - [`Rkmk`]: the Runge–Kutta–Munthe-Kaas engine, one generic implementation
//!   driven by the Butcher [`tableau`]s (Lie–Euler, Heun, Kutta 3, RK4 in its
//!   two-commutator form, DOPRI5 with its embedded pair and dense output,
//!   Butcher's order 6, DOP853 with its combined estimate and order-7 dense
//!   output);
//! - [`GroupNumerics`]: the `ad` spectral-radius bound and tolerance scale
//!   each state group provides;
//! - [`trees`]: rooted trees and order conditions for checking tableaux.
//!
//! - [`Splitting`]: symplectic splitting with exact free flows for the
//!   systems that are [`Splittable`](crate::dynamics::Splittable) (gyroscopes and points on S², H², S³);
//! - [`ImplicitMidpoint`]: the symmetric implicit Lie midpoint rule for any
//!   system (Newton with an LU);
//! - [`baseline`]: classical RK4 / DOPRI5 on the paper's chart equations;
//! - [`registry`]: every method by name — display name, family, order,
//!   stepping, what it needs and its constructor — the one list that scenes,
//!   the command line, the Python module and the docs read.
//!
//! # Which method
//!
//! | method | order | cost per step | use it for |
//! |---|---|---|---|
//! | [`Rkmk::lie_euler`] | 1 | 1 RHS, 1 exp | tests, teaching |
//! | [`Rkmk::heun`] | 2 | 2 RHS, 2 exp | cheap low accuracy |
//! | [`Rkmk::kutta3`] | 3 | 3 RHS, 3 exp, 2 brackets | — |
//! | [`Rkmk::rk4`] | 4 | 4 RHS, 4 exp, 2 brackets | fixed-step accuracy on any system |
//! | [`Rkmk::dopri5`] | 5 (4) | 6 RHS (FSAL), 6–7 exp, `ad²` series | adaptive, dense output, events; any system, short to medium times (tolerance per step: the final error can exceed it by the flow's amplification) |
//! | [`Rkmk::dop853`] | 8 (5, 3) | 12 RHS (FSAL; 3 more for dense output), `ad⁶` series | adaptive, with the error closest to tol (within 12 × tol where the flow does not amplify errors strongly: `docs/performance.md`, "Tolerance proportionality"), dense output of order 7, events |
//! | [`Rkmk::butcher6`] | 6 | 7 RHS, 7 exp, `ad⁴` series | high-accuracy references |
//! | [`Splitting::strang`] | 2 | 1 kick (1 force), 2 drifts | long runs at loose accuracy: energy bounded, momentum maps exact |
//! | [`Splitting::yoshida4`] / [`Splitting::suzuki4`] | 4 | 3 / 5 kicks, 4 / 6 drifts | long runs (Suzuki: 10–130× smaller error than Yoshida at equal h) |
//! | [`Splitting::blanes_moan4`] | 4 | 6 kicks, 7 drifts | **long runs on S², H², S³**: 160–1200× smaller error than Yoshida 4 at equal h |
//! | [`Splitting::yoshida6`] / [`Splitting::blanes_moan6`] | 6 | 7 / 10 kicks, 8 / 11 drifts | long runs at tight accuracy (Blanes–Moan 50–450× more accurate at equal h) |
//! | [`Splitting::blanes_moan_rkn4`] / [`Splitting::blanes_moan_rkn6`] | 4 / 6 | 7 / 12 kicks, 6 / 11 drifts | **the fastest on S², H², symmetric S³ at 1e-6 … 1e-10** (Runge–Kutta–Nyström: ≈ 14× more accurate than Blanes–Moan 6 at equal h on the S² reference, `docs/performance.md`) |
//! | [`ImplicitMidpoint`] | 2 | Newton: `dim 𝔤` RHS for the Jacobian + 1 RHS and 1 exp per iteration (≈ 3–6), one LU | long runs where no exact free flow exists (T², affine bodies): symmetric, energy bounded |
//! | [`baseline::CoordinateRk`] | 4 / 5 (4) | 4 / 6 `q̈` evaluations (autodiff + dense LU, allocates) | comparison only: fails at chart poles |
//!
//! A *drift* costs 1 exponential for a point, 3 for the n = 2 gyroscope, 5
//! for the n = 3 symmetric top (and 25 small rotations for an anisotropic
//! one, composed to sixth order); a *kick* is one evaluation of the forces.
//! The RKMK methods keep the group constraint to round-off and their energy
//! error shrinks like `h^p` but drifts over long times; the splittings and
//! the implicit midpoint rule are symmetric and keep the energy error
//! bounded (measured in `tests/suite/splitting.rs`, `implicit.rs`). The
//! costs in this table are counts from the implementations ([`StepCost`]
//! reports them per step); the error ratios are those printed by
//! `cargo test --test methods orders_on -- --nocapture` (gyroscopes and point
//! on S², H², S³). A classical Runge–Kutta method in
//! coordinates is also [`Rkmk`] on the additive group [`Rn`](crate::lie::Rn)
//! (brackets vanish, `exp` is the identity).

pub mod baseline;
mod error;
pub mod group;
pub mod implicit;
pub mod registry;
pub mod rkmk;
pub mod splitting;
pub mod tableau;
pub mod trees;

pub use error::MethodError;
pub use group::GroupNumerics;
pub use implicit::ImplicitMidpoint;
pub use registry::{AnyMethod, Family, MethodEntry, MethodParams, Needs, METHODS};
pub use rkmk::{DexpInv, Rkmk};
pub use splitting::Splitting;
pub use tableau::Tableau;

use std::fmt::Debug;

use crate::dynamics::System;
use crate::lie::{AlgebraVector, LieGroup};
use tableau::DENSE_DEGREE;

/// The Lie algebra of the state group of `S`.
pub type Alg<S> = <<S as System>::State as LieGroup>::Algebra;

/// The state after a step and the image of a tangent vector under the
/// step's tangent map ([`Method::tangent_step`]).
pub type TangentStep<S> = Result<(<S as System>::State, Alg<S>), StepFault>;

/// Static properties of a method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodInfo {
    /// The display name (from the [`registry`]).
    pub name: &'static str,
    /// Order `p` of the propagated solution.
    pub order: u32,
    /// Order `p̂` of the error estimate (adaptive stepping), if any: the
    /// estimate is `O(h^{p̂+1})` — the embedded solution's order for a
    /// classical pair, 7 for DOP853's combined 5th/3rd-order estimate.
    pub embedded_order: Option<u32>,
    /// Order `q` of the dense output: its local error is `O(h^{q+1})`.
    pub dense_order: u32,
    /// Number of stages.
    pub stages: usize,
    /// Whether the last stage of a step is the first of the next.
    pub fsal: bool,
    /// The radius guard: largest accepted bound `ρ(ad_θ)` of any algebra
    /// argument `θ` of a step (see [`GroupNumerics::ad_radius`]).
    pub radius_limit: f64,
}

/// What the driver asks of a step besides the new state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepRequest<A> {
    /// `f(t₀, y₀)` if already known (first-same-as-last, or a rejected step
    /// retried from the same point); saves one evaluation.
    pub f_start: Option<A>,
    /// Return the embedded error estimate.
    pub error: bool,
    /// Return the dense-output polynomial of the step.
    pub dense: bool,
    /// Return `f(t₀ + h, y₁)` (to be passed as `f_start` of the next step).
    pub f_end: bool,
}

impl<A> StepRequest<A> {
    /// Only the new state.
    pub fn plain() -> Self {
        StepRequest { f_start: None, error: false, dense: false, f_end: false }
    }
}

/// Work done by one step (fixed per method and request, so counting costs
/// nothing in the inner loop).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepCost {
    /// Evaluations of the vector field.
    pub rhs: u32,
    /// Group exponentials.
    pub exps: u32,
    /// Lie brackets (truncated `dexp⁻¹` series and commutator forms).
    pub brackets: u32,
    /// Closed-form `dexp⁻¹` evaluations.
    pub dexp_inv: u32,
}

impl std::ops::AddAssign for StepCost {
    fn add_assign(&mut self, o: Self) {
        self.rhs += o.rhs;
        self.exps += o.exps;
        self.brackets += o.brackets;
        self.dexp_inv += o.dexp_inv;
    }
}

/// The dense output of one step in the algebra coordinate:
/// `θ(σ) = Σ_{m=1}^{degree} coeffs[m−1] σᵐ`, `σ = (t − t₀)/h ∈ [0, 1]`, so that
/// `y(t) ≈ y₀·exp(θ(σ))`; `θ(1)` is the step's increment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DensePoly<A> {
    /// Coefficients of `σ¹ … σ^{DENSE_DEGREE}` (those above `degree` are zero).
    pub coeffs: [A; DENSE_DEGREE],
    /// Degree of the polynomial.
    pub degree: usize,
}

impl<A: AlgebraVector> DensePoly<A> {
    /// `θ(σ)` by Horner's rule.
    #[inline]
    pub fn theta(&self, sigma: f64) -> A {
        let mut s = A::zero();
        for m in (0..self.degree).rev() {
            s = (s + self.coeffs[m]) * sigma;
        }
        s
    }

    /// `dθ/dσ` at `σ`.
    pub fn theta_prime(&self, sigma: f64) -> A {
        let mut s = A::zero();
        for m in (0..self.degree).rev() {
            s = s * sigma + self.coeffs[m] * (m + 1) as f64;
        }
        s
    }
}

/// The result of one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutput<G: LieGroup> {
    /// The new state `y₁ = y₀·exp(Θ)`, renormalised onto the group.
    pub y: G,
    /// The increment `Θ`.
    pub theta: G::Algebra,
    /// `f(t₀, y₀)` (the first stage), for reuse after a rejection.
    pub f_start: G::Algebra,
    /// `f(t₀ + h, y₁)` if requested (or free, for FSAL methods).
    pub f_end: Option<G::Algebra>,
    /// The embedded error estimate `Θ − Θ̂ ∈ 𝔤`, if requested.
    pub error: Option<G::Algebra>,
    /// The dense output of the step, if requested.
    pub dense: Option<DensePoly<G::Algebra>>,
    /// Work done.
    pub cost: StepCost,
}

/// Where a non-finite number appeared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NonFiniteSource {
    /// The vector field `f(t, y)` returned NaN or ±∞.
    VectorField,
    /// The new state (overflow in `exp` or the group product).
    State,
    /// The step increment `Θ` or the error estimate.
    Increment,
    /// An event function.
    Event,
}

impl std::fmt::Display for NonFiniteSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NonFiniteSource::VectorField => "vector field",
            NonFiniteSource::State => "state",
            NonFiniteSource::Increment => "step increment",
            NonFiniteSource::Event => "event function",
        })
    }
}

/// Why a step could not be completed (the driver adds the step's `t`, `h`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepFault {
    /// A non-finite value, first seen at time `t_eval`.
    NonFinite {
        /// What was not finite.
        source: NonFiniteSource,
        /// The time at which it was evaluated.
        t_eval: f64,
    },
    /// An algebra argument exceeded the `dexp⁻¹` radius guard.
    DexpRadius {
        /// The bound `ρ(ad_θ)` found.
        radius: f64,
        /// The guard.
        limit: f64,
        /// Work done before the step was abandoned (an adaptive driver
        /// retries with a smaller step and counts it).
        cost: StepCost,
    },
    /// The nonlinear equations of an implicit step were not solved
    /// ([`ImplicitMidpoint`]): too many iterations, divergence or a singular
    /// Jacobian.
    NoConvergence {
        /// Newton iterations spent.
        iterations: u32,
        /// The last update (max norm) when it stopped.
        residual: f64,
        /// The time at which the equations were posed.
        t_eval: f64,
    },
    /// A coordinate method reached a point where its chart is singular
    /// ([`baseline`]).
    OutsideChart {
        /// Why, in words (from [`Error::OutsideChart`](crate::Error::OutsideChart)
        /// or the mass-matrix check of [`coords`](crate::coords)).
        reason: &'static str,
        /// The time of the failing evaluation.
        t_eval: f64,
    },
    /// The method cannot integrate this system ([`Method::check`] refuses
    /// it; a driver checks before the first step).
    Unsupported {
        /// The method's display name.
        method: &'static str,
        /// What is missing, in words.
        reason: &'static str,
    },
}

/// A one-step method for the systems `S`.
///
/// Implementations must be pure functions of their arguments (no interior
/// state), so that a rejected step can be retried and the same method value
/// can drive several solves.
pub trait Method<S: System>: Clone + Debug {
    /// Static properties.
    fn info(&self) -> MethodInfo;

    /// Whether the method can integrate `system` (default: yes). A method
    /// that needs a structure of the system — exact free flows for the
    /// splittings — refuses the others here; the driver asks before the
    /// first step.
    fn check(&self, system: &S) -> Result<(), MethodError> {
        let _ = system;
        Ok(())
    }

    /// Advances `y₀` at `t` by `h` (which may be negative).
    fn step(
        &self,
        system: &S,
        t: f64,
        y0: &S::State,
        h: f64,
        request: StepRequest<Alg<S>>,
    ) -> Result<StepOutput<S::State>, StepFault>;

    /// The step from `(t, y₀)` of size `h` and the image of the tangent
    /// vector `ξ₀` (algebra, left-trivialised) under the step's exact
    /// tangent map: the same method stepping the tangent lift
    /// [`Linearised`](crate::dynamics::Linearised) on the tangent group
    /// ([`crate::lie::tangent`]). The caller has checked that `system` has a
    /// [`tangent_field`](System::tangent_field) (else the step fails as
    /// non-finite). `None` (the default) for a method without an exact
    /// tangent map (the splittings, whose exact free flows are not lifted):
    /// the analyses then difference its steps.
    fn tangent_step(&self, system: &S, t: f64, y0: &S::State, h: f64, xi0: &Alg<S>) -> Option<TangentStep<S>> {
        let _ = (system, t, y0, h, xi0);
        None
    }
}

/// [`Method::tangent_step`] for a method that integrates any system (the
/// tangent lift included).
pub(crate) fn lifted_step<S, M>(method: &M, system: &S, t: f64, y0: &S::State, h: f64, xi0: &Alg<S>) -> Result<(S::State, Alg<S>), StepFault>
where
    S: System,
    S::State: GroupNumerics,
    M: for<'a> Method<crate::dynamics::Linearised<'a, S>>,
{
    let lifted = crate::dynamics::Linearised::unchecked(system);
    method.step(&lifted, t, &crate::lie::Tangent(*y0, *xi0), h, StepRequest::plain()).map(|o| (o.y.0, o.y.1))
}
