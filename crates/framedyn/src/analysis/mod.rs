//! Integrability, measured: tangent dynamics on the group, Lyapunov spectra
//! and the two-trajectory estimate (paper's integrability questions, §4–§6).
//!
//! # Tangent vectors
//!
//! A perturbation of a state `y` is left-trivialised, as the vector fields
//! are (`ẏ = y·f`): `δy = y·ξ` with `ξ` in the Lie algebra, stored as its
//! `DOF` coordinates in the group's basis ([`LieGroup::algebra_coords`](crate::lie::LieGroup::algebra_coords)).
//! A tangent vector is therefore never off the tangent space, and nothing is
//! singular at a chart pole.
//!
//! # The tangent map is that of the one-step map
//!
//! The tangent flow is integrated by the *same* method as the trajectory: it
//! is the derivative of the method's one-step map `Φ_h`, in the left
//! trivialisation,
//! `ξ₁ = d/ds log(Φ_h(y₀)⁻¹·Φ_h(y₀·exp(sξ₀)))|_{s=0}`, and the tangent over
//! many steps is the chain rule of these ([`TangentFlow`]). This is the
//! discrete variational equation of the method (for a splitting, a
//! symplectic map, so its spectrum pairs exactly), and it converges to the
//! exact tangent flow at the method's order.
//!
//! **Exact tangent maps.** Where the system has the exact derivative of its
//! vector field ([`System::tangent_field`](crate::dynamics::System::tangent_field):
//! every model of the crate — point, gyroscopes, the four affine bodies — on
//! every manifold, in potentials written over dual numbers) and the method is a Lie-group
//! Runge–Kutta method or the implicit midpoint rule
//! ([`Method::tangent_step`](crate::method::Method::tangent_step)), the
//! method steps the tangent lift [`Linearised`](crate::dynamics::Linearised)
//! on the tangent group [`Tangent`](crate::lie::Tangent) — the group over
//! dual numbers — and so returns the exact derivative of its own one-step
//! map, to round-off: one step of the lift per column (about twice a plain
//! step's work). The derivative of the vector field is in closed form (the
//! bundles' [`lift_derivative`](crate::bundle::FrameBundle::lift_derivative),
//! [`curvature_derivative`](crate::bundle::FrameBundle::curvature_derivative),
//! [`frame_velocity_derivative`](crate::bundle::FrameBundle::frame_velocity_derivative)),
//! with the potential's second derivatives by nested automatic
//! differentiation ([`gradient_derivative`](crate::potential::gradient_derivative)).
//!
//! **Differenced tangent maps.** Elsewhere — the splittings (their exact
//! free flows are not lifted), potentials given as `f64` closures (no
//! second derivatives), systems without a `tangent_field` — and on request
//! ([`Linearisation::differenced`]), the derivative is a central difference
//! of `Φ_h` along each tangent column, with step `ε` in the algebra
//! ([`Linearisation`]): second order by default (`2` steps per column,
//! truncation `O(ε²)·h`, round-off `O(u/ε)`, about `1e-10` relative at the
//! default `ε = 1e-5`), fourth order on request (`4` steps per column,
//! `1e-12`). Over ~10⁷ steps this per-step error becomes visible
//! (docs/integrability.md, the leveling of GALI₂ on `V = r²/2`). Each
//! estimate reports which was used (its `linearisation`, resolved); a run
//! that asks for no tangents never enters this module.
//!
//! # Steps: fixed or error-controlled
//!
//! Every analysis steps its trajectory through the solver's driver
//! ([`crate::solve::drive`]), so it takes the steps a run of the same
//! settings takes ([`StepSize`](crate::solve::StepSize)): equal fixed steps
//! (the last landing on the end), or steps chosen by the controller from
//! the trajectory's error estimate alone, the tangent columns following at
//! each accepted step's size. Holding `h` fixed in the derivative is what
//! makes it a step of the variational equation: the controller's `h`
//! depends on the state too, but a perturbed state advanced by another `h`
//! would be compared at another time. The tangent flow then converges to
//! the exact one in proportion to the tolerance (`tangent_flow`'s test:
//! 0.07–0.56 × tol for DOP853 and DOPRI5 through the pole of S²). A
//! close passage (a Kepler pericentre, a pole) is where this pays: the
//! steps shrink there only.
//!
//! # Lyapunov exponents
//!
//! [`lyapunov_spectrum`]: Benettin's discrete-QR method (Benettin, Galgani,
//! Giorgilli, Strelcyn 1980): `k` tangent columns from a seeded random
//! orthonormal frame, re-orthonormalised by modified Gram–Schmidt every
//! `renormalise_every` steps, the exponents the time averages of
//! `log |R_ii|`. Diagnostics: the running estimates at every
//! re-orthonormalisation, their spread over the second half of the run, and
//! a standard error by batch means. [`two_trajectory`]: the maximal exponent
//! from the separation of two nearby trajectories, renormalised to `d₀`
//! (Benettin, Galgani, Strelcyn 1976) — independent of the tangent code.
//! [`sali()`]: the Smaller Alignment Index (Skokos 2001), a fast chaos
//! indicator from two tangent vectors. [`gali()`]: the Generalised Alignment
//! Index of `k` vectors (Skokos, Bountis & Antonopoulos 2007): an
//! exponential fall on a chaotic orbit, a power law or none on a regular
//! one. [`megno()`]: the Mean Exponential Growth factor of Nearby Orbits
//! (Cincotta & Simó 2000) from one tangent vector.
//! [`chaos_map`]: SALI and MEGNO of every member of an ensemble table, in
//! parallel, as columns (maps over initial conditions).
//!
//! The metric on tangent vectors is the Euclidean one of the algebra
//! coordinates; exponents do not depend on it. The states of the frame-bundle
//! form carry the parallel frame, one gauge direction more than the phase
//! space (a rotation of `q` undone by `ρ` and the velocity components): it
//! contributes one exponent 0, so a Hamiltonian model's `DOF` exponents
//! still pair, `λᵢ + λ_{DOF+1−i} = 0`, and sum to 0.

mod error;
pub mod gali;
pub mod lyapunov;
pub mod map;
pub mod megno;
pub mod sali;
pub mod tangent;
mod walk;

pub use error::AnalysisError;
pub use gali::{gali, GaliEstimate, GaliOptions};
pub use lyapunov::{lyapunov_spectrum, two_trajectory, LyapunovEstimate, LyapunovOptions, TwoTrajectoryEstimate, TwoTrajectoryOptions};
pub use map::{chaos_map, ChaosMap, ChaosMapOptions};
pub use megno::{megno, MegnoEstimate, MegnoOptions};
pub use sali::{sali, SaliEstimate, SaliOptions};
pub use tangent::{flow_derivative, tangent_flow, Difference, Linearisation, TangentFlow};
pub use walk::MAX_STEPS;

use crate::method::GroupNumerics;

/// Checks the start of an analysis: `t0` finite, `y0` a finite state.
fn check_start<G: GroupNumerics>(t0: f64, y0: &G) -> Result<(), AnalysisError> {
    if !t0.is_finite() {
        return Err(AnalysisError::invalid("t0", t0, "finite"));
    }
    if !crate::solve::state_is_finite(y0) {
        return Err(AnalysisError::Solve(crate::solve::SolveError::InvalidInitialState { defect: y0.constraint_defect() }));
    }
    Ok(())
}

