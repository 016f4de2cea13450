//! The reference problems of framedyn, each defined once: the problems the
//! benches (`benches/step_cost.rs`), the measurement examples
//! (`examples/work_precision.rs`, `examples/stability.rs`) and the test
//! suite integrate, with their parameters documented here and checked by
//! `tests/suite/testing.rs` (energy and momentum map conserved by a fine
//! reference integration, initial states equal to the ones built from their
//! documented chart values).
//!
//! A problem is a [`Reference`]: the model, the initial state, the time span
//! `[0, t_end]` and the read-outs — an ambient *observable* (position,
//! velocity, body frame, internal momentum: the same numbers whatever the
//! formulation, [`readouts`]) and a conserved momentum map (the Noether
//! charge of the potential's symmetry). The energy is the model's
//! [`System::energy`].
//!
//! Two families:
//!
//! - **The measured problems**, in the potentials of the paper's families
//!   ([`CosineFamily`](crate::potential::CosineFamily), the elastic
//!   potential (a131)) or a [`UniformField`]: the S² gyroscope of SPEC §5
//!   ([`s2_gyro`]: m = 1, R = 1, I = 0.3, V = 0.5 cos(r/R), chart start
//!   (r, φ, ψ) = (1, 0.3, 0.4), rates (ṙ, φ̇) = (0.3, 0.6), ω = 1, T = 100),
//!   its passage through the pole ([`s2_pole`]), the S² point
//!   ([`s2_point`]), the S² and T² affine bodies ([`s2_affine`],
//!   [`t2_affine`]), the collapsing affine body ([`s2_affine_collapse`]), the
//!   H² gyroscopes ([`h2_gyro`], [`h2_lorentz`]), the T² gyroscope
//!   ([`t2_gyro`]) and the S³ gyroscope ([`s3_gyro`]). Their names are the
//!   CSV keys of `docs/data`.
//! - **The tilted problems** of the integrator tests, in the [`Axial`]
//!   potential (a tilt plus a frame coupling, so that the generator
//!   direction of the flow turns and an RKMK method's missing dexp⁻¹ term
//!   shows, SPEC §4): [`s2_tilted_gyro`], [`s2_tilted_point`],
//!   [`s2_tilted_affine`], [`h2_tilted_gyro`], [`h2_tilted_incompressible`],
//!   [`t2_tilted_gyro`], [`s3_tilted_gyro`], [`s3_tilted_weyl`].
//!
//! And the hand-written systems on bare Lie groups, independent of the
//! library's models ([`groups`]): the free rigid body, the heavy and Lagrange
//! tops, the symmetric top with its closed-form motion, a point on H².
//!
//! One file per manifold: [`sphere2`], [`hyperbolic2`], [`torus2`],
//! [`sphere3`]; the potentials in [`potentials`]. A problem with parameters
//! (`*_with`) validates them and returns [`Result`](crate::Result); a
//! problem without is built from constants and cannot fail.
//!
//! ```
//! use framedyn::dynamics::System;
//! use framedyn::method::{Rkmk, Splitting};
//! use framedyn::solve::{solve, Options};
//! use framedyn::testing::s2_gyro;
//!
//! let r = s2_gyro();
//! assert_eq!((r.name, r.t_end), ("s2_gyro", 100.0));
//! let mut short = r.clone();
//! short.t_end = 1.0;
//! let p = short.problem().unwrap();
//! // RKMK4: energy error O(h⁴).
//! let y = *solve(&p, &Rkmk::rk4(), &Options::fixed(0.01)).unwrap().last().1;
//! assert!((r.system.energy(&y) - r.system.energy(&r.y0)).abs() < 1e-9);
//! // A splitting keeps the momentum map p_φ of the axisymmetric potential to round-off.
//! let y = *solve(&p, &Splitting::strang(), &Options::fixed(0.01)).unwrap().last().1;
//! assert!(((r.momentum)(&r.system, &y) - (r.momentum)(&r.system, &r.y0)).abs() < 1e-12);
//! ```

pub mod bodies;
pub mod groups;
pub mod hyperbolic2;
pub mod potentials;
pub mod readouts;
pub mod sphere2;
pub mod sphere3;
pub mod torus2;

pub use bodies::*;
pub use groups::*;
pub use hyperbolic2::*;
pub use potentials::{Axial, UniformField};
pub use sphere2::*;
pub use sphere3::*;
pub use torus2::*;

use crate::dynamics::System;
use crate::method::GroupNumerics;
use crate::solve::{Problem, SolveError};

/// A reference problem: model, initial state, span and read-outs.
#[derive(Clone)]
pub struct Reference<S: System> {
    /// Short name (the CSV key of the measurements).
    pub name: &'static str,
    /// One-line description: the model, its parameters, the potential.
    pub about: &'static str,
    /// The model.
    pub system: S,
    /// The initial state at `t = 0`.
    pub y0: S::State,
    /// Final time of the measurements (`t₀ = 0`); a test may integrate any
    /// other span.
    pub t_end: f64,
    /// The ambient observable ([`readouts`]).
    pub observable: fn(&S, &S::State) -> Vec<f64>,
    /// A conserved momentum map (the Noether charge of the potential's
    /// symmetry).
    pub momentum: fn(&S, &S::State) -> f64,
}

impl<S: System> Reference<S> {
    /// The model and the initial state.
    pub fn into_parts(self) -> (S, S::State) {
        (self.system, self.y0)
    }
}

impl<S: System + Clone> Reference<S>
where
    S::State: GroupNumerics,
{
    /// The problem over `[0, t_end]`. Fails (typed) only if `t_end` was
    /// changed to 0 or a non-finite value.
    pub fn problem(&self) -> Result<Problem<S>, SolveError> {
        Problem::new(self.system.clone(), self.y0, (0.0, self.t_end))
    }
}

impl<S: System + std::fmt::Debug> std::fmt::Debug for Reference<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reference")
            .field("name", &self.name)
            .field("system", &self.system)
            .field("y0", &self.y0)
            .field("t_end", &self.t_end)
            .finish_non_exhaustive()
    }
}
