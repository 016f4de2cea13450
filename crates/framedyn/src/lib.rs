//! # framedyn
//!
//! Structured particles — infinitesimal gyroscopes and infinitesimal
//! affinely-rigid bodies — moving on curved manifolds (S², H², T², S³), after
//! J. J. Sławianowski et al. (the paper in `shared/seed`, equation labels such
//! as (a52) refer to it).
//!
//! Layout:
//! - [`analysis`]: tangent dynamics on the group, Lyapunov spectra (issue 21);
//! - [`lie`]: the Lie groups of the configuration spaces and their exponential
//!   maps, with closed forms where they exist and series where they do not;
//! - [`manifold`]: the [`Manifold`](manifold::Manifold) trait and the four
//!   manifolds in the paper's coordinates and frames;
//! - [`bundle`]: the orthonormal frame bundle of each manifold in a global,
//!   chart-free representation, with the horizontal lift (parallel transport);
//! - [`body`]: the bodies (point, gyroscope, affine and constrained affine)
//!   and their parameters;
//! - [`dynamics`]: equations of motion in the frame-bundle form, as
//!   left-trivialised vector fields on Lie groups;
//! - [`coords`]: the paper's own coordinate ("E-gauge") formulation — chart
//!   Lagrangians from (a52)/(a74) with Euler–Lagrange equations by automatic
//!   differentiation — an independent cross-check of the frame-bundle form and
//!   the baseline that shows where coordinates fail (poles);
//! - [`method`], [`solve`]: Lie-group integrators (the RKMK family, an
//!   adaptive embedded pair, dense output, events) and the problem → method →
//!   solution driver;
//! - [`potential`]: potentials `V(x, e)` written once, generic over dual
//!   numbers, so forces and torques come by automatic differentiation;
//! - [`testing`]: the reference problems of the benches, the measurement
//!   examples and the tests, each defined once with its parameters.
#![deny(missing_docs)]
#![deny(unsafe_code)]

pub mod analysis;
pub mod body;
pub mod bundle;
pub mod coords;
pub mod dynamics;
pub mod error;
pub mod lie;
pub mod manifold;
pub mod method;
pub mod potential;
pub mod scenes;
pub mod solve;
pub mod testing;

/// Internals checked by the core's tests (`tests/suite/internals/`); not
/// public API.
#[doc(hidden)]
#[path = "internals.rs"]
pub mod __internals;

pub use error::{Error, Result};

/// The README's Rust code blocks, run as doctests (never compiled otherwise).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

/// The guide's (`docs/guide.md`) Rust code blocks, run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/guide.md")]
pub struct GuideDoctests;
