//! The geodesic distance, an optional capability of a manifold: see
//! [`GeodesicDistance`].

use nalgebra::SVector;

use super::Manifold;
use crate::Result;

/// The Riemannian (geodesic) distance between two points of a [`Manifold`].
///
/// Nothing in the dynamics needs it: the integrators, frame bundles and
/// potentials work with the chart, the metric and the embedding only. It is
/// implemented where a distance is wanted to check results (a geodesic
/// against its length, a central potential against its radius), and a new
/// manifold need not provide it.
///
/// # Contract
/// - **Meaning.** `distance(p, q)` is the infimum of the lengths of the
///   piecewise smooth curves on the manifold from `p` to `q`, in the units of
///   the manifold's lengths. On the complete manifolds of this crate it is
///   the length of a minimal geodesic; where several minimal geodesics join
///   the two points (antipodes of a sphere, points of each other's cut locus
///   on the torus) they all have this length, so the distance is well defined
///   and does not depend on which one a solver finds. It is not the length of
///   a particular geodesic (the chart's coordinate line, the first one shot),
///   which may be longer.
/// - **Arguments.** `p` and `q` are embedded points (ambient components, as
///   returned by [`Manifold::embed`]) on the manifold to the tolerance that
///   [`Manifold::chart`] accepts. Every point of the manifold is valid,
///   including those where the chart is singular (a pole).
/// - **Laws.** `d(p, p) = 0`, `d(p, q) ≥ 0` and finite, `d(p, q) = d(q, p)`
///   and `d(p, r) ≤ d(p, q) + d(q, r)`, each to the accuracy that the
///   implementation documents; for nearby points `d ≈ √(g_{ij} dx^i dx^j)`.
/// - **Errors.** A typed error, never a panic or a NaN:
///   [`Error::NotFinite`](crate::Error::NotFinite) or
///   [`Error::Constraint`](crate::Error::Constraint) for a point that is not
///   finite or lies off the manifold (as [`Manifold::chart`] reports it), and
///   [`Error::NoConvergence`](crate::Error::NoConvergence) from a numerical
///   solver that cannot certify its documented accuracy (it returns no
///   doubtful value).
pub trait GeodesicDistance<const N: usize, const E: usize>: Manifold<N, E> {
    /// Geodesic distance between two embedded points (see the
    /// [trait documentation](GeodesicDistance) for the contract).
    fn distance(&self, p: &SVector<f64, E>, q: &SVector<f64, E>) -> Result<f64>;
}
