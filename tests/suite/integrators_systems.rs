//! Test systems for the integrator suite: curved, non-linear vector fields
//! whose generator direction turns (a constant generator would be integrated
//! exactly by every RKMK method and prove nothing).

use framedyn::dynamics::System;
use framedyn::lie::{Gl, LieGroup, Product, ProductAlgebra, Rn, So12, So3};
use nalgebra::{Matrix2, Vector2, Vector3};

/// Attitude and body angular momentum of a rigid body.
pub type Body = Product<So3, Rn<3>>;

/// The free rigid body `Ṙ = R ω̂`, `Π̇ = Π × ω`, `ω = I⁻¹Π` (Euler's equations
/// in the body frame), on SO(3) × ℝ³.
#[derive(Debug, Clone)]
pub struct RigidBody {
    pub inertia: Vector3<f64>,
}

impl System for RigidBody {
    type State = Body;
    fn vector_field(&self, _t: f64, y: &Body) -> ProductAlgebra<Vector3<f64>, Vector3<f64>> {
        let pi = y.1 .0;
        let w = pi.component_div(&self.inertia);
        ProductAlgebra(w, pi.cross(&w))
    }
    fn energy(&self, y: &Body) -> f64 {
        0.5 * y.1 .0.dot(&y.1 .0.component_div(&self.inertia))
    }
    fn defect(&self, y: &Body) -> f64 {
        y.0.constraint_defect()
    }
}

/// The heavy top: `Π̇ = Π × ω + mgl Γ × χ`, `Γ = Rᵀe₃` the vertical in the body,
/// `χ` the unit vector to the centre of mass; energy `½Π·ω + mgl Γ·χ`.
#[derive(Debug, Clone)]
pub struct HeavyTop {
    pub inertia: Vector3<f64>,
    pub mgl: f64,
    pub chi: Vector3<f64>,
}

impl HeavyTop {
    fn gamma(y: &Body) -> Vector3<f64> {
        y.0.matrix().row(2).transpose()
    }
}

impl System for HeavyTop {
    type State = Body;
    fn vector_field(&self, _t: f64, y: &Body) -> ProductAlgebra<Vector3<f64>, Vector3<f64>> {
        let pi = y.1 .0;
        let w = pi.component_div(&self.inertia);
        ProductAlgebra(w, pi.cross(&w) + Self::gamma(y).cross(&self.chi) * self.mgl)
    }
    fn energy(&self, y: &Body) -> f64 {
        0.5 * y.1 .0.dot(&y.1 .0.component_div(&self.inertia)) + self.mgl * Self::gamma(y).dot(&self.chi)
    }
    fn defect(&self, y: &Body) -> f64 {
        y.0.constraint_defect()
    }
}

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

/// A point on the hyperbolic plane H² (R = 1) in the potential
/// `V = κ(cosh r − 1)`, in the frame-bundle form: `Λ = [q₁ | q₂ | x] ∈ SO⁺(1,2)`
/// moves by the horizontal lift `Λ̇ = Λ h(u)` (algebra coordinates
/// `(u₁, u₂, 0)`), and the velocity in the parallel frame obeys
/// `u̇_a = −κ Λ₃ₐ`. Energy `½|u|² + κ(Λ₃₃ − 1)`.
#[derive(Debug, Clone)]
pub struct HyperbolicOscillator {
    pub kappa: f64,
}

/// Frame bundle of H² × velocity.
pub type HypState = Product<So12, Rn<2>>;

impl System for HyperbolicOscillator {
    type State = HypState;
    fn vector_field(&self, _t: f64, y: &HypState) -> ProductAlgebra<Vector3<f64>, Vector2<f64>> {
        let l = y.0.matrix();
        let u = y.1 .0;
        ProductAlgebra(Vector3::new(u[0], u[1], 0.0), Vector2::new(-self.kappa * l[(2, 0)], -self.kappa * l[(2, 1)]))
    }
    fn energy(&self, y: &HypState) -> f64 {
        0.5 * y.1 .0.norm_squared() + self.kappa * (y.0.matrix()[(2, 2)] - 1.0)
    }
    fn defect(&self, y: &HypState) -> f64 {
        y.0.constraint_defect()
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

/// The rigid body of the order tests: inertia (1, 2, 3), |Π| ≈ 1.9.
pub fn rigid_body() -> (RigidBody, Body) {
    let r0 = So3::exp(&Vector3::new(0.3, -0.2, 0.5));
    (RigidBody { inertia: Vector3::new(1.0, 2.0, 3.0) }, Product(r0, Rn(Vector3::new(1.0, 0.5, 1.5))))
}

/// The heavy top of the tests.
pub fn heavy_top() -> (HeavyTop, Body) {
    let r0 = So3::exp(&Vector3::new(0.4, 0.1, -0.3));
    (
        HeavyTop { inertia: Vector3::new(1.0, 1.5, 0.7), mgl: 2.0, chi: Vector3::new(0.1, 0.2, 1.0).normalize() },
        Product(r0, Rn(Vector3::new(0.3, -1.2, 2.0))),
    )
}

/// A Lagrange top (symmetric, centre of mass on the symmetry axis):
/// integrable, so errors grow at most linearly in time (unlike the chaotic
/// asymmetric heavy top, which amplifies them by ~100 over T = 10).
pub fn lagrange_top() -> (HeavyTop, Body) {
    let r0 = So3::exp(&Vector3::new(0.4, 0.1, -0.3));
    (
        HeavyTop { inertia: Vector3::new(1.0, 1.0, 0.7), mgl: 2.0, chi: Vector3::new(0.0, 0.0, 1.0) },
        Product(r0, Rn(Vector3::new(0.3, -1.2, 2.0))),
    )
}

/// The GL⁺(2) flow of the tests.
pub fn gl_flow() -> (GlFlow, Gl<2>) {
    (GlFlow { eps: 0.3 }, Gl::new(Matrix2::new(1.3, 0.4, -0.2, 0.9)).expect("det > 0"))
}

/// The H² oscillator of the tests (starts off the origin, bounded orbit).
pub fn hyperbolic() -> (HyperbolicOscillator, HypState) {
    (HyperbolicOscillator { kappa: 1.0 }, Product(So12::from_kak(0.3, 0.8, -0.2), Rn(Vector2::new(0.4, 0.9))))
}

/// Exact solution of the free symmetric top `I = (i1, i1, i3)`:
/// `Π(t) = exp(−λt ê₃)Π₀`, `R(t) = R₀ exp(tΠ₀/i1) exp(λt e₃)`,
/// `λ = Π₃(1/i3 − 1/i1)` (SPEC §4).
pub fn symmetric_top_exact(i1: f64, i3: f64, y0: &Body, t: f64) -> Body {
    let pi0 = y0.1 .0;
    let lam = pi0[2] * (1.0 / i3 - 1.0 / i1);
    let e3 = Vector3::new(0.0, 0.0, 1.0);
    let pi = So3::exp(&(e3 * (-lam * t))).act(&pi0);
    let r = y0.0.compose(&So3::exp(&(pi0 * (t / i1)))).compose(&So3::exp(&(e3 * (lam * t))));
    Product(r, Rn(pi))
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
