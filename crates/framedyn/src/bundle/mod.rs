//! The orthonormal frame bundle of each manifold, in a global representation
//! without chart singularities (SPEC §3.2).
//!
//! An element `g` of the bundle is a point `x` of the manifold together with an
//! orthonormal (for H²: Minkowski-orthonormal), positively oriented frame
//! `q = (q_1 … q_N)` of `T_xM`. It is stored as an element of a Lie group
//! [`FrameBundle::Group`] — SO(3) for S² and for the spheroid (through its Gauss
//! map), SO⁺(1,2) for H², SO(4) for S³, the global angles (θ, φ, a) ∈ ℝ³ for T² — so that integrators can move it by
//! exponentials and it never meets a coordinate pole.
//!
//! **Horizontal lift.** A curve whose velocity has components `u` in the
//! frame `q` and whose frame is parallel-transported along it satisfies
//! `ġ = g · ξ` with `ξ = horizontal_lift(g, u)` (left-trivialised).
//! **Vertical generator.** Rotating the frame in place, `q̇ = q·w` with `w`
//! skew, is `ġ = g · vertical(g, w)`.

pub mod hyperbolic2;
pub mod sphere2;
pub mod sphere3;
pub mod spheroid;
pub mod torus2;

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

use crate::lie::LieGroup;
use crate::manifold::Manifold;
use crate::Result;

/// A manifold whose orthonormal frame bundle has a global Lie-group representation.
pub trait FrameBundle<const N: usize, const E: usize>: Manifold<N, E> {
    /// The group that stores bundle elements.
    type Group: LieGroup;

    /// The bundle element at the embedded point `p` with frame vectors given as
    /// the columns of `q` (ambient components). Fails with a typed error when
    /// `p` is not on the manifold, or `q` is not tangent, orthonormal and
    /// positively oriented (tolerance 1e-9).
    fn from_frame(&self, p: &SVector<f64, E>, q: &SMatrix<f64, E, N>) -> Result<Self::Group>;
    /// The bundle element at the chart point `x` whose frame is the paper's
    /// frame field `E(x)` rotated by the orthogonal matrix `u`: `q = E(x)·u`.
    fn from_chart(&self, x: &SVector<f64, N>, u: &SMatrix<f64, N, N>) -> Result<Self::Group>;
    /// The point `x` (ambient coordinates).
    fn position(&self, g: &Self::Group) -> SVector<f64, E>;
    /// The frame vectors `q_a` as columns (ambient coordinates).
    fn frame_vectors(&self, g: &Self::Group) -> SMatrix<f64, E, N>;
    /// The chart point and the matrix `u` with `q = E(x)·u`: the inverse of
    /// [`Self::from_chart`]; fails where the chart is singular.
    fn to_chart(&self, g: &Self::Group) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>)>;
    /// Generator of parallel transport along the velocity with frame
    /// components `u`: `ġ = g·ξ`.
    fn horizontal_lift(&self, g: &Self::Group, u: &SVector<f64, N>) -> <Self::Group as LieGroup>::Algebra;
    /// Generator of the in-place frame rotation `q̇ = q·w` (`w` skew).
    fn vertical(&self, g: &Self::Group, w: &SMatrix<f64, N, N>) -> <Self::Group as LieGroup>::Algebra;
    /// Distance of `g` from the bundle (group constraint and, for T², none).
    fn bundle_defect(&self, g: &Self::Group) -> f64;

    /// Ambient velocities `(ẋ, q̇)` of the point and of the frame vectors when
    /// the bundle element moves by `ġ = g·ξ` (exact, no differencing). For the
    /// horizontal lift of `u` this gives `ẋ = Σ u_a q_a` and `q̇_b = −II(ẋ, q_b)`
    /// (the second fundamental form: normal, as parallel transport requires) —
    /// what the forces `F̂_a = −H_a V` of a frame-dependent potential need.
    fn frame_velocity(
        &self,
        g: &Self::Group,
        xi: &<Self::Group as LieGroup>::Algebra,
    ) -> (SVector<f64, E>, SMatrix<f64, E, N>);

    /// Sectional curvature `K` at the point of `g`. For all manifolds here
    /// (two-dimensional, or of constant curvature) the Riemann tensor in any
    /// orthonormal frame is `R̂_{abcd} = K(δ_ac δ_bd − δ_ad δ_bc)`, so `K` is
    /// all the spin–curvature force of (a59) needs.
    fn curvature_at(&self, g: &Self::Group) -> f64;

    /// `d/ds horizontal_lift(g·exp(sη), u)|_{s=0}` for fixed `u`: how the
    /// lift changes with the bundle element (zero where it does not depend
    /// on it: S², H², S³). With [`frame_velocity`](Self::frame_velocity) at
    /// `η` (the first derivatives of the point and the frame) and the two
    /// methods below, what the exact derivatives of the vector fields need
    /// ([`System::tangent_field`](crate::dynamics::System::tangent_field)).
    fn lift_derivative(&self, g: &Self::Group, u: &SVector<f64, N>, eta: &<Self::Group as LieGroup>::Algebra) -> <Self::Group as LieGroup>::Algebra;

    /// `d/ds curvature_at(g·exp(sη))|_{s=0}` (zero for constant curvature).
    fn curvature_derivative(&self, g: &Self::Group, eta: &<Self::Group as LieGroup>::Algebra) -> f64;

    /// `d/ds frame_velocity(g·exp(sη), ξ)|_{s=0}` for fixed `ξ`: second
    /// derivatives of the point and of the frame vectors.
    fn frame_velocity_derivative(
        &self,
        g: &Self::Group,
        xi: &<Self::Group as LieGroup>::Algebra,
        eta: &<Self::Group as LieGroup>::Algebra,
    ) -> (SVector<f64, E>, SMatrix<f64, E, N>);

    /// True if the horizontal lift and the vertical generator do not depend
    /// on the bundle element and are equivariant,
    /// `Ad_{exp(τ·vertical(w))} horizontal_lift(u) = horizontal_lift(exp(τw)u)`:
    /// a manifold of constant curvature acting on itself (S², H², S³). Then
    /// the free motion has the closed form [`free_translation`] and the
    /// splitting methods apply (see [`dynamics::split`](crate::dynamics::split)).
    /// Default `false` (the curvature of T² varies).
    fn exact_free_flow(&self) -> bool {
        false
    }

    /// `g·exp(θ·vertical(g, ε))`, the rotation of the frame in the
    /// `(q₁, q₂)` plane by `θ` (`ε = [[0, −1], [1, 0]]` in that plane), from
    /// `cos θ` and `sin θ`. The default forms the exponential; S² and H²
    /// rotate two columns of the group matrix instead, so that the
    /// gyroscope's drift shares one `sin_cos` between frame and velocity.
    fn rotate_frame(&self, g: &Self::Group, cos: f64, sin: f64) -> Self::Group {
        let eps = SMatrix::<f64, N, N>::from_fn(|i, j| match (i, j) {
            (1, 0) => 1.0,
            (0, 1) => -1.0,
            _ => 0.0,
        });
        g.compose(&Self::Group::exp(&(self.vertical(g, &eps) * sin.atan2(cos))))
    }
}

/// The free translation of the bundle element:
/// `g(t) = g₀·exp(t(ξ(u₀) + R))·exp(−tR)`, `R = vertical(g₀, w)`, for the
/// velocity `u(t) = exp(tw)u₀` in the parallel frame (the gyroscope's
/// spin–curvature rotation `w`; `w = 0` for a point: the geodesic flow
/// `g₀ exp(t ξ(u₀))`). Two exponentials. Exact when
/// [`FrameBundle::exact_free_flow`] (derivation in
/// [`dynamics::split`](crate::dynamics::split)); elsewhere it is only the
/// flow of the frozen lift.
pub fn free_translation<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g0: &B::Group,
    u0: &SVector<f64, N>,
    w: &SMatrix<f64, N, N>,
    h: f64,
) -> B::Group {
    let xi = bundle.horizontal_lift(g0, u0);
    let r = bundle.vertical(g0, w);
    g0.compose(&B::Group::exp(&((xi + r) * h))).compose(&B::Group::exp(&(r * (-h))))
}

/// `m` with columns `i`, `j` replaced by `c·mᵢ + s·mⱼ`, `c·mⱼ − s·mᵢ`: the
/// closed-form [`FrameBundle::rotate_frame`] of S² and H².
#[inline]
pub(crate) fn rotate_columns(m: &nalgebra::Matrix3<f64>, i: usize, j: usize, cos: f64, sin: f64) -> nalgebra::Matrix3<f64> {
    let mut out = *m;
    let (a, b): (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) = (m.column(i).into(), m.column(j).into());
    out.set_column(i, &(a * cos + b * sin));
    out.set_column(j, &(b * cos - a * sin));
    out
}
