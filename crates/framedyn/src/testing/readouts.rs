//! The read-outs of the reference problems: the ambient *observable* (the
//! same numbers whatever the formulation, so that a coordinate solver can be
//! compared with the group form) and the conserved momentum maps.
//!
//! Layouts of the observables: a gyroscope on a surface — position (3),
//! velocity (3), body frame (3 × 2, column-major), spin `s` (1); on S³ —
//! position (4), velocity (4), body frame (4 × 3), spin (3); an affine body —
//! position, velocity, body frame, `ρ̇` (2 × 2, column-major); a point —
//! position, velocity. The S³ spin and `ρ̇` are components in the parallel
//! frame `q`, not ambient vectors: the same in every formulation that
//! carries `q` from the same initial frame, but they turn with `q` along a
//! gauge direction ([`System::gauge`]), where the ambient `q·π` and `ė` do
//! not.

use nalgebra::Matrix3;

use crate::bundle::FrameBundle;
use crate::dynamics::affine::AffineBodyModel;
use crate::dynamics::affine::{BodyState, InternalConstraint};
use crate::dynamics::gyroscope2::Z_ROTATION;
use crate::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use crate::potential::Potential;

/// Position, velocity, body frame and spin of a gyroscope on a surface.
pub fn gyroscope2_observable<B: FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &Gyroscope2Model<B, P>,
    y: &<Gyroscope2Model<B, P> as System>::State,
) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.push(m.spin(y));
    v
}

/// `p_φ` of a gyroscope on a surface ([`Gyroscope2Model::p_phi`]).
pub fn gyroscope2_p_phi<B: FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &Gyroscope2Model<B, P>,
    y: &<Gyroscope2Model<B, P> as System>::State,
) -> f64 {
    m.p_phi(y)
}

/// Position, velocity, body frame and spin of a gyroscope on a 3-manifold.
pub fn gyroscope3_observable<B: FrameBundle<3, 4>, P: Potential<3, 4>>(
    m: &Gyroscope3Model<B, P>,
    y: &<Gyroscope3Model<B, P> as System>::State,
) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.extend(m.spin(y).iter());
    v
}

/// Position, velocity, body frame and `ρ̇` of an affine body (any internal
/// constraint, any dimension).
pub fn affine_observable<B, V, C, const N: usize, const E: usize>(m: &AffineBodyModel<B, V, C, N, E>, y: &BodyState<B, C, N, E>) -> Vec<f64>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.extend(m.rho_dot(y).iter());
    v
}

/// `p_φ` of an affine body ([`AffineBodyModel::p_phi`]: rotations in the
/// plane of the ambient axes 0 and 1).
pub fn affine_p_phi<B, V, C, const N: usize, const E: usize>(m: &AffineBodyModel<B, V, C, N, E>, y: &BodyState<B, C, N, E>) -> f64
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    m.p_phi(y)
}

/// Position and velocity of a point on a surface.
pub fn point_observable<B: FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &PointModel<B, P, 2, 3>,
    y: &<PointModel<B, P, 2, 3> as System>::State,
) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v
}

/// `p_φ` of a point on a surface: the momentum map of the rotations about
/// the ambient z axis ([`Z_ROTATION`]).
pub fn point_p_phi<B: FrameBundle<2, 3>, P: Potential<2, 3>>(m: &PointModel<B, P, 2, 3>, y: &<PointModel<B, P, 2, 3> as System>::State) -> f64 {
    point_momentum(m, y, &Z_ROTATION)
}

/// [`PointModel::momentum_map`] of a generator known to be skew (the
/// constants of this module), without the error path.
fn point_momentum<B: FrameBundle<2, 3>, P: Potential<2, 3>>(m: &PointModel<B, P, 2, 3>, y: &<PointModel<B, P, 2, 3> as System>::State, a: &Matrix3<f64>) -> f64 {
    m.momentum_map(y, a).expect("Z_ROTATION generates isometries of ℝ³ and ℝ^{2,1}")
}
