//! Equations of motion in the singularity-free frame-bundle form (SPEC §3.2).
//!
//! A [`System`] is a vector field on a Lie group of states (frame bundle ×
//! fibre group × velocities/momenta, built with [`Product`](crate::lie::Product)
//! and [`Rn`](crate::lie::Rn)), given left-trivialised: `ẏ = y·f(t, y)`.
//! That is the form every Lie-group integrator consumes.
//!
//! The generalised forces of a potential `V(x, e)` (paper §4, after (a53)) are
//! computed once here, for every manifold:
//! - horizontal force `F̂_a = −H_a V`: the derivative of `V` when the point
//!   moves along `q_a` and the body frame is parallel-transported,
//!   `F̂_a = −(∂_x V·q_a + Σ_b ∂_{e_b}V·δ_a e_b)` with `δ_a e = (δ_a q)·ρ` and
//!   `δ_a q` from [`FrameBundle::frame_velocity`];
//! - internal force `∂V/∂ρ = qᵀ·∂_e V` for the body frame `e = q·ρ`.

use nalgebra::{SMatrix, SVector};

use crate::bundle::FrameBundle;
use crate::lie::LieGroup;
use crate::potential::{Gradient, Potential};

/// A left-trivialised vector field `ẏ = y·f(t, y)` on a Lie group of states,
/// with its conserved energy and the distance of a state from its constraints.
pub trait System: Send + Sync {
    /// The group the states live in.
    type State: LieGroup;
    /// `f(t, y)`.
    fn vector_field(&self, t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra;
    /// Total energy `T + V` (conserved when the potential does not depend on `t`).
    fn energy(&self, y: &Self::State) -> f64;
    /// Distance of `y` from the state manifold (group constraints, frames
    /// orthonormal, …); 0 up to round-off along an exact solution.
    fn defect(&self, y: &Self::State) -> f64;

    /// The gauge directions at `y`: left-trivialised velocities along which
    /// the stored state changes and the physical one does not. The models on
    /// a frame bundle carry the parallel frame `q`, which a point does not
    /// have and a body has only through `e = q·ρ`: turning `q` in place,
    /// `q ↦ q·k` (`k ∈ SO(N)`), with the components stored in it turned back
    /// (`u ↦ kᵀu`, `ρ ↦ kᵀρ`, a spin or hypermomentum `P ↦ kᵀPk`) leaves the
    /// position, velocity, body frame and internal motion unchanged. One
    /// direction per basis element `w` of so(N) ([`skew_basis`]), in its
    /// order: `d/dτ y·exp(τ·ξ_w)` is that rotation with `k = exp(τw)`.
    ///
    /// The equations are equivariant under these rotations, so a step's
    /// tangent map takes gauge directions to gauge directions, and deviation
    /// vectors taken modulo them are those of the physical phase space
    /// (GALI's [`quotient`](crate::analysis::GaliOptions::quotient)).
    /// Empty (the default) when the stored state has no such redundancy: a
    /// system on a bare group, or a body whose frame is the parallel frame up
    /// to scale (pure dilatation).
    fn gauge(&self, _y: &Self::State) -> Vec<<Self::State as LieGroup>::Algebra> {
        Vec::new()
    }

    /// `(f(t, y), Df(t, y)[ξ])`: the vector field and its exact directional
    /// derivative in the left trivialisation,
    /// `Df(t, y)[ξ] = d/ds f(t, y·exp(sξ))|_{s=0}` — in closed form, with the
    /// potential's second derivatives by automatic differentiation
    /// ([`gradient_derivative`](crate::potential::gradient_derivative)).
    /// What the tangent analyses integrate ([`Linearised`]); `None` (the
    /// default) for a system without it, whose tangent maps are then
    /// differenced ([`analysis::tangent`](crate::analysis::tangent)).
    fn tangent_field(&self, _t: f64, _y: &Self::State, _xi: &<Self::State as LieGroup>::Algebra) -> Option<FieldAndDerivative<Self::State>> {
        None
    }
}

/// `(f, Df[ξ])` of [`System::tangent_field`]: two elements of the algebra of `G`.
pub type FieldAndDerivative<G> = (<G as LieGroup>::Algebra, <G as LieGroup>::Algebra);

/// A basis of so(N): for `i < j` (in the order (0,1), (0,2), …, (1,2), …)
/// the matrix `w` with `w_ji = 1`, `w_ij = −1` (for N = 2 the single
/// `ε = [[0, −1], [1, 0]]`, the rotation by +90°).
pub fn skew_basis<const N: usize>() -> Vec<SMatrix<f64, N, N>> {
    let mut out = Vec::with_capacity(N * N.saturating_sub(1) / 2);
    for i in 0..N {
        for j in i + 1..N {
            let mut w = SMatrix::<f64, N, N>::zeros();
            w[(j, i)] = 1.0;
            w[(i, j)] = -1.0;
            out.push(w);
        }
    }
    out
}

/// `−qᵀ·∂_x V`: the position part of the horizontal force, `−q_a·∂_x V` for
/// each frame vector `q_a` (the columns of `q`).
///
/// Summed over the non-zero entries of `∂_x V` only. A potential whose
/// gradient has zero entries known at compile time (a
/// [`Pole`](crate::potential::Pole) centre: `∂_x V ∝ e_z`) then costs only the
/// rows of `q` it reads, and an integrator's stage frame is not computed
/// where nothing reads it. A product `q_{ia}·0` cannot be dropped by the
/// compiler (it is NaN for a non-finite `q_{ia}` and `−0` for a negative
/// one), so the plain product `qᵀ·∂_x V` kept the whole frame alive. The sum
/// starts from `−0`, the additive identity, so that where no entry is zero
/// the result is that of `qᵀ·∂_x V` bit for bit; a skipped zero entry can
/// only change the sign of a zero component. A non-finite frame is still
/// caught: the integrators test every new state.
#[inline(always)]
pub fn position_force<const N: usize, const E: usize>(q: &SMatrix<f64, E, N>, dx: &SVector<f64, E>) -> SVector<f64, N> {
    let mut f = SVector::<f64, N>::zeros();
    for a in 0..N {
        let mut acc = -0.0;
        for i in 0..E {
            if dx[i] != 0.0 {
                acc += q[(i, a)] * dx[i];
            }
        }
        f[a] = -acc;
    }
    f
}

/// The horizontal force `F̂_a = −H_a V` in the parallel frame `q` of `g`, for
/// the body frame `e = q·ρ` and the gradient `grad` of `V` at `(x, e)`.
/// `frame_dependent = false` skips the frame term (potentials `V(x)`).
pub fn horizontal_force<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g: &B::Group,
    rho: &SMatrix<f64, N, N>,
    grad: &Gradient<N, E>,
    frame_dependent: bool,
) -> SVector<f64, N> {
    let q = bundle.frame_vectors(g);
    let mut f = position_force(&q, &grad.dx);
    if frame_dependent {
        for a in 0..N {
            let mut unit = SVector::<f64, N>::zeros();
            unit[a] = 1.0;
            let (_, dq) = bundle.frame_velocity(g, &bundle.horizontal_lift(g, &unit));
            let de = dq * rho;
            f[a] -= grad.de.component_mul(&de).sum();
        }
    }
    f
}

/// `∂V/∂ρ = qᵀ·∂_e V` for the body frame `e = q·ρ` (entry `(c, b)` is
/// `∂V/∂ρ_{cb}`); the internal (vertical) generalised force is its negative.
pub fn internal_gradient<const N: usize, const E: usize>(
    q: &SMatrix<f64, E, N>,
    grad: &Gradient<N, E>,
) -> SMatrix<f64, N, N> {
    q.transpose() * grad.de
}

/// The generalised forces of a potential at a configuration and their
/// derivative along a motion of it ([`force_derivative`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceDerivative<const N: usize> {
    /// The horizontal force `F̂` ([`horizontal_force`]).
    pub force: SVector<f64, N>,
    /// Its derivative.
    pub d_force: SVector<f64, N>,
    /// `∂V/∂ρ = qᵀ·∂_e V` ([`internal_gradient`]; zero for a `V(x)`).
    pub internal: SMatrix<f64, N, N>,
    /// Its derivative.
    pub d_internal: SMatrix<f64, N, N>,
}

/// [`horizontal_force`] and [`internal_gradient`] at `(g, ρ)` (body frame
/// `e = q·ρ`), and their exact derivatives when the bundle element moves
/// along `ġ = g·η` and the body frame's components by `δρ`: the chain rule
/// through the bundle's [`frame_velocity`](FrameBundle::frame_velocity),
/// [`lift_derivative`](FrameBundle::lift_derivative) and
/// [`frame_velocity_derivative`](FrameBundle::frame_velocity_derivative),
/// with the potential's second derivatives by nested automatic
/// differentiation ([`gradient_derivative`](crate::potential::gradient_derivative)).
#[allow(clippy::too_many_arguments)]
pub fn force_derivative<B, P, const N: usize, const E: usize>(
    bundle: &B,
    potential: &P,
    metric: &SMatrix<f64, E, E>,
    g: &B::Group,
    rho: &SMatrix<f64, N, N>,
    eta: &<B::Group as LieGroup>::Algebra,
    drho: &SMatrix<f64, N, N>,
) -> ForceDerivative<N>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    let x = bundle.position(g);
    let q = bundle.frame_vectors(g);
    let (dx, dq) = bundle.frame_velocity(g, eta);
    let frame_dependent = potential.uses_frame();
    let de = if frame_dependent { dq * rho + q * drho } else { SMatrix::zeros() };
    let (grad, dgrad) = crate::potential::gradient_derivative(potential, &x, &(q * rho), metric, &dx, &de);
    let mut force = -(q.transpose() * grad.dx);
    let mut d_force = -(dq.transpose() * grad.dx + q.transpose() * dgrad.dx);
    let (mut internal, mut d_internal) = (SMatrix::zeros(), SMatrix::zeros());
    if frame_dependent {
        for a in 0..N {
            let mut unit = SVector::<f64, N>::zeros();
            unit[a] = 1.0;
            let lift = bundle.horizontal_lift(g, &unit);
            let (_, dq_a) = bundle.frame_velocity(g, &lift);
            let (_, ddq_a) = bundle.frame_velocity_derivative(g, &lift, eta);
            let (_, ddq_a_lift) = bundle.frame_velocity(g, &bundle.lift_derivative(g, &unit, eta));
            let de_a = dq_a * rho;
            let dde_a = (ddq_a + ddq_a_lift) * rho + dq_a * drho;
            force[a] -= grad.de.component_mul(&de_a).sum();
            d_force[a] -= dgrad.de.component_mul(&de_a).sum() + grad.de.component_mul(&dde_a).sum();
        }
        internal = q.transpose() * grad.de;
        d_internal = dq.transpose() * grad.de + q.transpose() * dgrad.de;
    }
    ForceDerivative { force, d_force, internal, d_internal }
}

pub mod affine;
pub use affine::constrained;
pub mod gyroscope;
pub mod gyroscope2;
pub mod gyroscope3;
pub mod linearised;
pub mod point;
pub mod split;

pub use gyroscope2::{Gyroscope2Model, Gyroscope2State};
pub use gyroscope3::{Gyroscope3Model, Gyroscope3State, PaperMomenta};
pub use linearised::Linearised;
pub use point::{PointModel, PointState};
pub use split::{NoSplit, SplitDispatch, Splittable};
