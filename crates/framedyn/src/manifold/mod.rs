//! Riemannian manifolds in the paper's coordinates.
//!
//! A [`Manifold`] of dimension `N` embedded in an ambient space of dimension
//! `E` gives, at a point `x` of its chart (the paper's coordinates), the metric,
//! the Christoffel symbols, the Riemann tensor, the paper's orthonormal frame
//! field `E` with its connection coefficients, and the embedding.
//!
//! ## What a manifold provides
//! - **Required**, the [`Manifold`] trait: the chart and its regular part
//!   (`coordinate_names`, `check_chart`); the metric, Christoffel symbols and
//!   Riemann tensor in closed form (`sectional_curvature` has a default); the
//!   frame field and its connection coefficients; the embedding, its inverse
//!   and the projections onto the manifold and its tangent spaces
//!   (`ambient_metric`, `embed`, `embed_tangent`, `chart`, `chart_tangent`,
//!   `point_defect`, `project_point`, `project_tangent`). This is everything
//!   the frame bundles, the dynamics and the integrators use.
//! - **Optional**, the [`GeodesicDistance`] trait: the distance between two
//!   points, used to check results. S², H² and S³ implement it in closed form
//!   next to the manifold; T² by a numerical minimal-geodesic solver in the
//!   [`geodesic`] module (Clairaut quadratures and geodesic shooting). A new
//!   manifold need not implement it.
//!
//! ## Index conventions (used by every implementation)
//! - Christoffel symbols `Γ^i_{jk} = christoffel(x)[i][j][k]`, symmetric in
//!   `j, k`: `∇_{∂_k} ∂_j = Γ^i_{jk} ∂_i`.
//! - Riemann tensor `R^i_{jkl} = riemann(x)[i][j][k][l]` with
//!   `R(∂_k, ∂_l)∂_j = R^i_{jkl} ∂_i` and `R(X,Y) = ∇_X∇_Y − ∇_Y∇_X − ∇_{[X,Y]}`,
//!   i.e. `R^i_{jkl} = ∂_kΓ^i_{jl} − ∂_lΓ^i_{jk} + Γ^i_{mk}Γ^m_{jl} − Γ^i_{ml}Γ^m_{jk}`.
//!   With it the sectional curvature `K(u,v) = g(R(u,v)v, u)/(|u|²|v|² − g(u,v)²)`
//!   is `+1/R²` on the sphere.
//! - Frame field: column `A` of `frame(x)` holds the chart components `E^i_A`
//!   of `E_A`. Its connection coefficients (the paper's `Γ(E)` of (a74)) are
//!   `Γ^A_{BC} = frame_connection(x)[A][B][C]` with `∇_{E_C} E_B = Γ^A_{BC} E_A`;
//!   for an orthonormal frame they are skew in `A, B`.

pub mod distance;
pub mod geodesic;
pub mod hyperbolic2;
pub mod sphere2;
pub mod sphere3;
pub mod spheroid;
pub mod torus2;

#[allow(unused_imports)]
pub use distance::*;
#[allow(unused_imports)]
pub use geodesic::*;
#[allow(unused_imports)]
pub use hyperbolic2::*;
#[allow(unused_imports)]
pub use sphere2::*;
#[allow(unused_imports)]
pub use sphere3::*;
#[allow(unused_imports)]
pub use spheroid::*;
#[allow(unused_imports)]
pub use torus2::*;

use nalgebra::{SMatrix, SVector};
use std::fmt::Debug;

use crate::Result;

/// Rank-3 array `T[a][b][c]` (Christoffel symbols, frame connection coefficients).
pub type Tensor3<const N: usize> = [[[f64; N]; N]; N];
/// Rank-4 array `T[a][b][c][d]` (Riemann tensor).
pub type Tensor4<const N: usize> = [[[[f64; N]; N]; N]; N];

/// An `N`-dimensional Riemannian manifold with the paper's chart and frame
/// field, embedded in an `E`-dimensional flat ambient space (Euclidean, or
/// Minkowski for H²). See the [module documentation](self) for conventions;
/// the geodesic distance is the optional [`GeodesicDistance`].
pub trait Manifold<const N: usize, const E: usize>: Clone + Debug + Send + Sync {
    /// Name, e.g. `"S2"`.
    const NAME: &'static str;

    /// Names of the chart coordinates as in the paper, e.g. `["r", "phi"]`.
    fn coordinate_names(&self) -> [&'static str; N];
    /// The unit of each chart coordinate: `"L"` (a length, e.g. the
    /// geodesic distance `r`) or `"rad"` (an angle); their rates are per
    /// `T`. Used to label output columns.
    fn coordinate_units(&self) -> [&'static str; N];
    /// `Ok` if `x` lies in the regular part of the chart (where the metric is
    /// non-degenerate and the frame field `E` is defined), else
    /// [`Error::OutsideChart`](crate::Error::OutsideChart).
    fn check_chart(&self, x: &SVector<f64, N>) -> Result<()>;

    /// Metric components `g_{ij}(x)`.
    fn metric(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Christoffel symbols `Γ^i_{jk}(x)` (closed form).
    fn christoffel(&self, x: &SVector<f64, N>) -> Tensor3<N>;
    /// Riemann tensor `R^i_{jkl}(x)` (closed form).
    fn riemann(&self, x: &SVector<f64, N>) -> Tensor4<N>;
    /// Sectional curvature of the plane spanned by chart vectors `u, v` at `x`
    /// (the Gaussian curvature when `N = 2`).
    fn sectional_curvature(
        &self,
        x: &SVector<f64, N>,
        u: &SVector<f64, N>,
        v: &SVector<f64, N>,
    ) -> f64 {
        let g = self.metric(x);
        let r = self.riemann(x);
        // g(R(u,v)v, u) = g_{im} R^i_{jkl} v^j u^k v^l u^m
        let mut num = 0.0;
        for i in 0..N {
            for j in 0..N {
                for k in 0..N {
                    for l in 0..N {
                        let rv = r[i][j][k][l] * v[j] * u[k] * v[l];
                        if rv != 0.0 {
                            for m in 0..N {
                                num += g[(i, m)] * rv * u[m];
                            }
                        }
                    }
                }
            }
        }
        let uu = u.dot(&(g * u));
        let vv = v.dot(&(g * v));
        let uv = u.dot(&(g * v));
        num / (uu * vv - uv * uv)
    }

    /// The paper's orthonormal frame field: column `A` = chart components of `E_A`.
    fn frame(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Connection coefficients `Γ^A_{BC}(x)` of the frame field (closed form).
    fn frame_connection(&self, x: &SVector<f64, N>) -> Tensor3<N>;

    /// The metric of the flat ambient space (identity, or `diag(1, 1, −1)`).
    fn ambient_metric(&self) -> SMatrix<f64, E, E>;
    /// Embedding of the chart point `x`.
    fn embed(&self, x: &SVector<f64, N>) -> SVector<f64, E>;
    /// Push-forward of the chart vector `v` at `x` to the ambient space.
    fn embed_tangent(&self, x: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, E>;
    /// Chart coordinates of the embedded point `p` (which must lie on the
    /// manifold to the tolerance of [`Self::point_defect`] ≤ 1e-9 relative).
    fn chart(&self, p: &SVector<f64, E>) -> Result<SVector<f64, N>>;
    /// Chart components of the ambient tangent vector `w` at the embedded point `p`.
    fn chart_tangent(&self, p: &SVector<f64, E>, w: &SVector<f64, E>) -> Result<SVector<f64, N>>;
    /// Relative distance of `p` from the manifold (0 on it).
    fn point_defect(&self, p: &SVector<f64, E>) -> f64;
    /// The nearest point of the manifold to `p` (removes round-off drift).
    fn project_point(&self, p: &SVector<f64, E>) -> SVector<f64, E>;
    /// The tangential part of the ambient vector `w` at the point `p`.
    fn project_tangent(&self, p: &SVector<f64, E>, w: &SVector<f64, E>) -> SVector<f64, E>;
}
