//! Test systems of the integrator suite that are not reference problems: a
//! non-autonomous flow on GL⁺(2) and the systems of the failure paths
//! (blow-up, NaN, overflow, Dahlquist's test equation). The rigid body, the
//! heavy and Lagrange tops, the symmetric top and the oscillator on H² are
//! the reference problems of `framedyn::testing::groups`, re-exported here.

pub use framedyn::testing::{
    heavy_top, hyperbolic_oscillator, lagrange_top, rigid_body, symmetric_top, symmetric_top_exact, HeavyTop, RigidBody,
    RigidBodyState as Body, SYMMETRIC_TOP_I1, SYMMETRIC_TOP_I3,
};

use framedyn::dynamics::System;
use framedyn::lie::{Gl, LieGroup, Rn};
use nalgebra::Matrix2;

/// A non-autonomous, non-linear flow on GL⁺(2):
/// `ẏ = y·ξ`, `ξ = (1 + ½ sin t) J + ε(½ tr(M) I − M)`, `M = yᵀy`,
/// `J = [[0, −1], [1, 0]]`. `ξ` is traceless, so `det y` is conserved
/// (reported as the "energy"); the symmetric part pulls `yᵀy` towards a
/// multiple of the identity and does not commute with `J`.
#[derive(Debug, Clone)]
pub struct GlFlow {
    pub eps: f64,
}

impl System for GlFlow {
    type State = Gl<2>;
    fn vector_field(&self, t: f64, y: &Gl<2>) -> Matrix2<f64> {
        let m = y.matrix().transpose() * y.matrix();
        let j = Matrix2::new(0.0, -1.0, 1.0, 0.0);
        j * (1.0 + 0.5 * t.sin()) + (Matrix2::identity() * (0.5 * m.trace()) - m) * self.eps
    }
    fn energy(&self, y: &Gl<2>) -> f64 {
        y.det()
    }
    fn defect(&self, y: &Gl<2>) -> f64 {
        y.constraint_defect()
    }
}

/// `ṗ = p²` on ℝ: blows up at `t = 1/p₀`.
#[derive(Debug, Clone)]
pub struct Riccati;

impl System for Riccati {
    type State = Rn<1>;
    fn vector_field(&self, _t: f64, y: &Rn<1>) -> nalgebra::Vector1<f64> {
        nalgebra::Vector1::new(y.0[0] * y.0[0])
    }
    fn energy(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
    fn defect(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
}

/// Wraps a system and returns NaN from the vector field for `t > t_bad`.
#[derive(Debug, Clone)]
pub struct NanAfter<S> {
    pub inner: S,
    pub t_bad: f64,
}

impl<S: System> System for NanAfter<S> {
    type State = S::State;
    fn vector_field(&self, t: f64, y: &S::State) -> <S::State as LieGroup>::Algebra {
        let f = self.inner.vector_field(t, y);
        if t > self.t_bad {
            f * f64::NAN
        } else {
            f
        }
    }
    fn energy(&self, y: &S::State) -> f64 {
        self.inner.energy(y)
    }
    fn defect(&self, y: &S::State) -> f64 {
        self.inner.defect(y)
    }
}

/// The GL⁺(2) flow of the tests.
pub fn gl_flow() -> (GlFlow, Gl<2>) {
    (GlFlow { eps: 0.3 }, Gl::new(Matrix2::new(1.3, 0.4, -0.2, 0.9)).expect("det > 0"))
}

/// `ṗ = 10³⁰⁸` on ℝ: the state overflows after one step from 1.5·10³⁰⁸.
#[derive(Debug, Clone)]
pub struct Overflow;

impl System for Overflow {
    type State = Rn<1>;
    fn vector_field(&self, _t: f64, _y: &Rn<1>) -> nalgebra::Vector1<f64> {
        nalgebra::Vector1::new(1e308)
    }
    fn energy(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
    fn defect(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
}

/// `ẏ = λy` on ℝ (Dahlquist's test equation).
#[derive(Debug, Clone)]
pub struct Linear {
    pub lambda: f64,
}

impl System for Linear {
    type State = Rn<1>;
    fn vector_field(&self, _t: f64, y: &Rn<1>) -> nalgebra::Vector1<f64> {
        y.0 * self.lambda
    }
    fn energy(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
    fn defect(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
}
