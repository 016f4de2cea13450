//! Projection of each accepted step back onto the energy level of the
//! initial state (\[HLW06\] §IV.4, "standard projection").
//!
//! A Runge–Kutta(–Munthe-Kaas) step conserves no nonlinear first integral,
//! and on flows whose period depends on the energy — Kepler-type orbits with
//! close pericentre passages above all — the energy error of every passage
//! turns into a phase error that grows with time: the global error lands
//! hundreds or thousands of times above the tolerance however good the
//! local error control is (`docs/performance.md`, "Tolerance
//! proportionality"). Projecting the end of every accepted step back onto
//! `E = E₀` removes that mechanism and keeps the method's order (the
//! correction is of the size of the local energy error).
//!
//! **The correction** is the one of least weighted norm in the Lie algebra,
//! `y ↦ y·exp(λ W∇E)`, with `∇E` the gradient of the energy in the
//! left-trivialised algebra coordinates (forward differences, one energy
//! evaluation per coordinate) and `W = diag((1 + sᵢ)²)`, `sᵢ` the reference
//! magnitude of component `i` ([`GroupNumerics::tolerance_scale`]): each
//! component moves in proportion to the scale on which the error norm with
//! `atol = rtol` measures it. `λ` solves `E(y·exp(λW∇E)) = E₀` by at most
//! [`NEWTON_STEPS`] simplified Newton steps with the gradient kept fixed.
//!
//! **When it is skipped**: where the energy or its gradient is not finite,
//! or the gradient vanishes (an equilibrium), or no Newton step reduces
//! `|E − E₀|` while it is still above the round-off of the energy
//! ([`NOISE_ULPS`] ε times the larger of `|E|` and `Σᵢ |∂ᵢE|(1 + sᵢ)`, the
//! change of `E` when every component is rounded — far above `ε|E|` where
//! kinetic and potential energy nearly cancel). The state is then left as
//! the method computed it ([`Stats::projections_skipped`]).
//!
//! **Where it applies**: every accepted step of a run of the
//! [`driver`](super::driver) ([`Settings::projection`](super::Settings),
//! [`Options::project`](super::Options::project), a scene's
//! `[method] project = "energy"`), and every step of the scene engine's
//! stepping API, which projects onto the scene's initial energy
//! ([`Projection::Level`]).
//!
//! **What it does not do**: it is not applied to dense-output samples inside
//! a step (their energy error is one step's local error, not a sum), and it
//! assumes the system is autonomous and conservative — true of every model
//! of the crate, not of every [`System`] a user may write. It does not make
//! a method symplectic: on a long run with a symplectic splitting method,
//! prefer the method without it. On flows that do not amplify energy errors
//! it can cost accuracy as well as time: `docs/performance.md` measures both.
//!
//! \[HLW06\] E. Hairer, C. Lubich, G. Wanner, *Geometric Numerical
//! Integration*, 2nd ed., Springer 2006.

use crate::dynamics::System;
use crate::lie::{AlgebraVector, LieGroup};
use crate::method::{Alg, GroupNumerics};

use super::Stats;

/// Which first integral each accepted step is projected back onto.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Projection {
    /// None: the method's own states (default).
    #[default]
    None,
    /// The energy [`System::energy`] of the state the run starts from (see
    /// the module documentation of [`projection`](self)).
    Energy,
    /// The energy level `E = value`, given (finite). What the scene engine's
    /// stepping API uses, so that steps taken in many calls all return to
    /// the scene's initial energy instead of each call's starting one.
    Level(f64),
}

impl Projection {
    /// The names accepted by the scene format and the Python module.
    pub const NAMES: &'static str = "\"none\" or \"energy\"";

    /// The projection called `name` (`"none"`, `"energy"`), or `None`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "none" => Some(Projection::None),
            "energy" => Some(Projection::Energy),
            _ => None,
        }
    }

    /// The name of the projection (the inverse of [`from_name`](Self::from_name);
    /// `"energy"` for a given level too).
    pub fn name(self) -> &'static str {
        match self {
            Projection::None => "none",
            Projection::Energy | Projection::Level(_) => "energy",
        }
    }

    /// The energy level projected onto: `None` for [`Projection::None`],
    /// `start()` (the energy of the state a run starts from) for
    /// [`Projection::Energy`], the given value for [`Projection::Level`].
    pub fn level(self, start: impl FnOnce() -> f64) -> Option<f64> {
        match self {
            Projection::None => None,
            Projection::Energy => Some(start()),
            Projection::Level(e) => Some(e),
        }
    }
}

/// Simplified Newton steps per projection. With a forward-difference
/// gradient accurate to about 1e-7 relative, each step reduces the energy
/// residual by about that factor, so two reach round-off.
pub const NEWTON_STEPS: usize = 3;

/// A residual that no Newton step reduces is round-off, not a skipped
/// projection, while it is below this many ε of the larger of `|E|` and
/// `Σᵢ |∂ᵢE|(1 + sᵢ)` (the change of `E` when every component is rounded):
/// an energy evaluation of an affine body (kinematics, elastic potential)
/// rounds to 5 – 15 ulp of `E`.
pub const NOISE_ULPS: f64 = 64.0;

/// Forward-difference step of the gradient, relative to `1 + sᵢ`.
const GRADIENT_STEP: f64 = 1e-7;

/// The state `y` projected onto the energy level `E = e0` (or `y` itself
/// where the projection is skipped; see the [module documentation](self)):
/// what a run with [`Projection::Energy`] does after every accepted step,
/// for use on its own (e.g. to put a perturbed initial state back on a
/// level). Counts energy evaluations, projections and skips in `stats`.
///
/// Cost: one energy evaluation per algebra coordinate for the gradient,
/// and one group exponential and energy evaluation per Newton step —
/// 0.47 – 0.80 × one DOP853 step of the same model on the surfaces and
/// 1.29 × on the S³ gyroscope (15 coordinates), measured by
/// `FRAMEDYN_RATIOS_ONLY=1 FRAMEDYN_RATIOS_FILTER=project_energy cargo bench
/// -p framedyn-tests --bench step_cost`. The gradient is taken afresh at
/// every step: a direction kept from an earlier step would move the state
/// off the least-norm direction by the angle the state has turned since.
pub fn project_energy<S>(sys: &S, y: &S::State, e0: f64, stats: &mut Stats) -> S::State
where
    S: System,
    S::State: GroupNumerics,
{
    let d = <Alg<S> as AlgebraVector>::LEN;
    let e = sys.energy(y);
    stats.energy_evals += 1;
    let mut r = e - e0;
    // Round-off of one energy evaluation: a residual below it is no error.
    let floor = 4.0 * f64::EPSILON * e0.abs().max(e.abs());
    if !r.is_finite() || !e0.is_finite() {
        stats.projections_skipped += 1;
        return *y;
    }
    if r.abs() <= floor {
        stats.projections += 1;
        return *y;
    }
    let scale = y.tolerance_scale();
    let mut direction = <Alg<S> as AlgebraVector>::zero();
    let mut slope = 0.0;
    // Round-off of the energy itself: each component of the state is stored
    // to ε·(1 + sᵢ), which moves E by up to |∂ᵢE|·ε·(1 + sᵢ); where kinetic
    // and potential energy nearly cancel this is far above ε·|E|.
    let mut noise = 0.0;
    for j in 0..d {
        let unit = 1.0 + scale.get(j).abs();
        let h = GRADIENT_STEP * unit;
        let mut v = <Alg<S> as AlgebraVector>::zero();
        v.set(j, h);
        let g = (sys.energy(&y.compose(&S::State::exp(&v)).renormalize()) - e) / h;
        let w = unit * unit;
        direction.set(j, w * g);
        slope += w * g * g;
        noise += (g * unit).abs();
    }
    let noise = NOISE_ULPS * f64::EPSILON * e0.abs().max(e.abs()).max(noise);
    stats.energy_evals += d;
    if !(slope.is_finite() && slope > 0.0) {
        stats.projections_skipped += 1;
        return *y;
    }
    let mut best = *y;
    let mut moved = false;
    for _ in 0..NEWTON_STEPS {
        let lambda = -r / slope;
        let mut v = <Alg<S> as AlgebraVector>::zero();
        for j in 0..d {
            v.set(j, lambda * direction.get(j));
        }
        let candidate = best.compose(&S::State::exp(&v)).renormalize();
        let r_new = sys.energy(&candidate) - e0;
        stats.energy_evals += 1;
        // Also stops on a NaN residual.
        if r_new.abs().partial_cmp(&r.abs()) != Some(std::cmp::Ordering::Less) {
            break;
        }
        best = candidate;
        r = r_new;
        moved = true;
        if r.abs() <= floor {
            break;
        }
    }
    if moved || r.abs() <= noise {
        stats.projections += 1;
    } else {
        stats.projections_skipped += 1;
    }
    best
}
