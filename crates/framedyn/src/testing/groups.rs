//! Hand-written systems on bare Lie groups, independent of the library's
//! models: the free rigid body and the heavy top on SO(3) × ℝ³ (with the
//! closed-form motion of the free symmetric top, SPEC §4), and a point on H²
//! written directly in the SO⁺(1,2) frame bundle. Their vector fields are
//! curved and non-linear — the generator direction turns — so an RKMK
//! method's order and its dexp⁻¹ truncation show (SPEC §4).

use nalgebra::{Vector2, Vector3};

use super::Reference;
use crate::dynamics::System;
use crate::lie::{LieGroup, Product, ProductAlgebra, Rn, So12, So3};

/// Attitude `R` and body angular momentum `Π` of a rigid body.
pub type RigidBodyState = Product<So3, Rn<3>>;

/// The free rigid body `Ṙ = R ω̂`, `Π̇ = Π × ω`, `ω = I⁻¹Π` (Euler's
/// equations in the body frame), on SO(3) × ℝ³. Energy `½ Π·ω`.
#[derive(Debug, Clone)]
pub struct RigidBody {
    /// The principal moments of inertia `(I₁, I₂, I₃)`.
    pub inertia: Vector3<f64>,
}

impl System for RigidBody {
    type State = RigidBodyState;
    fn vector_field(&self, _t: f64, y: &RigidBodyState) -> ProductAlgebra<Vector3<f64>, Vector3<f64>> {
        let pi = y.1 .0;
        let w = pi.component_div(&self.inertia);
        ProductAlgebra(w, pi.cross(&w))
    }
    fn energy(&self, y: &RigidBodyState) -> f64 {
        0.5 * y.1 .0.dot(&y.1 .0.component_div(&self.inertia))
    }
    fn defect(&self, y: &RigidBodyState) -> f64 {
        y.0.constraint_defect()
    }
}

/// The heavy top: `Π̇ = Π × ω + mgl Γ × χ`, `Γ = Rᵀe₃` the vertical in the
/// body, `χ` the unit vector to the centre of mass; energy
/// `½Π·ω + mgl Γ·χ`.
#[derive(Debug, Clone)]
pub struct HeavyTop {
    /// The principal moments of inertia about the fixed point.
    pub inertia: Vector3<f64>,
    /// `m g l`: mass × gravity × distance of the centre of mass.
    pub mgl: f64,
    /// The unit vector from the fixed point to the centre of mass, in the body.
    pub chi: Vector3<f64>,
}

impl HeavyTop {
    fn gamma(y: &RigidBodyState) -> Vector3<f64> {
        y.0.matrix().row(2).transpose()
    }
}

impl System for HeavyTop {
    type State = RigidBodyState;
    fn vector_field(&self, _t: f64, y: &RigidBodyState) -> ProductAlgebra<Vector3<f64>, Vector3<f64>> {
        let pi = y.1 .0;
        let w = pi.component_div(&self.inertia);
        ProductAlgebra(w, pi.cross(&w) + Self::gamma(y).cross(&self.chi) * self.mgl)
    }
    fn energy(&self, y: &RigidBodyState) -> f64 {
        0.5 * y.1 .0.dot(&y.1 .0.component_div(&self.inertia)) + self.mgl * Self::gamma(y).dot(&self.chi)
    }
    fn defect(&self, y: &RigidBodyState) -> f64 {
        y.0.constraint_defect()
    }
}

/// The attitude matrix (column-major) and `Π` of a rigid body.
pub fn rigid_body_observable<S: System<State = RigidBodyState>>(_m: &S, y: &RigidBodyState) -> Vec<f64> {
    let mut v: Vec<f64> = y.0.matrix().iter().copied().collect();
    v.extend(y.1 .0.iter());
    v
}

/// The vertical component of the spatial angular momentum, `(RΠ)·e₃ = Π·Γ`:
/// the momentum map of the rotations about the vertical, conserved by the
/// free rigid body and by the heavy top.
pub fn vertical_angular_momentum<S: System<State = RigidBodyState>>(_m: &S, y: &RigidBodyState) -> f64 {
    y.0.matrix().row(2).transpose().dot(&y.1 .0)
}

/// The free asymmetric rigid body of the order tests: inertia (1, 2, 3),
/// `R₀ = exp(0.3, −0.2, 0.5)`, `Π₀ = (1, 0.5, 1.5)` (|Π| ≈ 1.9), T = 4.
pub fn rigid_body() -> Reference<RigidBody> {
    let r0 = So3::exp(&Vector3::new(0.3, -0.2, 0.5));
    Reference {
        name: "rigid_body",
        about: "free rigid body, I = (1, 2, 3), Π₀ = (1, 0.5, 1.5)",
        system: RigidBody { inertia: Vector3::new(1.0, 2.0, 3.0) },
        y0: Product(r0, Rn(Vector3::new(1.0, 0.5, 1.5))),
        t_end: 4.0,
        observable: rigid_body_observable,
        momentum: vertical_angular_momentum,
    }
}

/// The asymmetric heavy top: inertia (1, 1.5, 0.7), mgl = 2, `χ` along
/// (0.1, 0.2, 1), `R₀ = exp(0.4, 0.1, −0.3)`, `Π₀ = (0.3, −1.2, 2)`; chaotic,
/// T = 2.
pub fn heavy_top() -> Reference<HeavyTop> {
    let r0 = So3::exp(&Vector3::new(0.4, 0.1, -0.3));
    Reference {
        name: "heavy_top",
        about: "heavy top, I = (1, 1.5, 0.7), mgl = 2, χ ∥ (0.1, 0.2, 1)",
        system: HeavyTop { inertia: Vector3::new(1.0, 1.5, 0.7), mgl: 2.0, chi: Vector3::new(0.1, 0.2, 1.0).normalize() },
        y0: Product(r0, Rn(Vector3::new(0.3, -1.2, 2.0))),
        t_end: 2.0,
        observable: rigid_body_observable,
        momentum: vertical_angular_momentum,
    }
}

/// A Lagrange top (symmetric, inertia (1, 1, 0.7), centre of mass on the
/// symmetry axis, mgl = 2) from the start of [`heavy_top`]: integrable, so
/// errors grow at most linearly in time (unlike the chaotic asymmetric heavy
/// top, which amplifies them by ~100 over T = 10). T = 10.
pub fn lagrange_top() -> Reference<HeavyTop> {
    let r0 = So3::exp(&Vector3::new(0.4, 0.1, -0.3));
    Reference {
        name: "lagrange_top",
        about: "Lagrange top, I = (1, 1, 0.7), mgl = 2, χ = e₃",
        system: HeavyTop { inertia: Vector3::new(1.0, 1.0, 0.7), mgl: 2.0, chi: Vector3::new(0.0, 0.0, 1.0) },
        y0: Product(r0, Rn(Vector3::new(0.3, -1.2, 2.0))),
        t_end: 10.0,
        observable: rigid_body_observable,
        momentum: vertical_angular_momentum,
    }
}

/// The moment `I₁ = I₂` of [`symmetric_top`].
pub const SYMMETRIC_TOP_I1: f64 = 1.0;
/// The moment `I₃` of [`symmetric_top`].
pub const SYMMETRIC_TOP_I3: f64 = 0.4;

/// The free symmetric top `I = (1, 1, 0.4)` from `R₀ = exp(0.2, −0.5, 0.1)`,
/// `Π₀ = (0.6, 0.2, 1.1)`, T = 12; its exact motion is
/// [`symmetric_top_exact`].
pub fn symmetric_top() -> Reference<RigidBody> {
    let r0 = So3::exp(&Vector3::new(0.2, -0.5, 0.1));
    Reference {
        name: "symmetric_top",
        about: "free symmetric top, I = (1, 1, 0.4), Π₀ = (0.6, 0.2, 1.1)",
        system: RigidBody { inertia: Vector3::new(SYMMETRIC_TOP_I1, SYMMETRIC_TOP_I1, SYMMETRIC_TOP_I3) },
        y0: Product(r0, Rn(Vector3::new(0.6, 0.2, 1.1))),
        t_end: 12.0,
        observable: rigid_body_observable,
        momentum: vertical_angular_momentum,
    }
}

/// Exact motion of the free symmetric top `I = (i1, i1, i3)` from `y0`:
/// `Π(t) = exp(−λt ê₃)Π₀`, `R(t) = R₀ exp(tΠ₀/i1) exp(λt e₃)`,
/// `λ = Π₃(1/i3 − 1/i1)` (SPEC §4).
pub fn symmetric_top_exact(i1: f64, i3: f64, y0: &RigidBodyState, t: f64) -> RigidBodyState {
    let pi0 = y0.1 .0;
    let lam = pi0[2] * (1.0 / i3 - 1.0 / i1);
    let e3 = Vector3::new(0.0, 0.0, 1.0);
    let pi = So3::exp(&(e3 * (-lam * t))).act(&pi0);
    let r = y0.0.compose(&So3::exp(&(pi0 * (t / i1)))).compose(&So3::exp(&(e3 * (lam * t))));
    Product(r, Rn(pi))
}

/// Frame bundle of H² (`Λ = [q₁ | q₂ | x] ∈ SO⁺(1,2)`) × the velocity in
/// the parallel frame.
pub type HyperbolicOscillatorState = Product<So12, Rn<2>>;

/// A point on the hyperbolic plane H² (R = 1, m = 1) in the potential
/// `V = κ(cosh r − 1)`, in the frame-bundle form: `Λ = [q₁ | q₂ | x]`
/// moves by the horizontal lift `Λ̇ = Λ h(u)` (algebra coordinates
/// `(u₁, u₂, 0)`), and the velocity in the parallel frame obeys
/// `u̇_a = −κ Λ₃ₐ`. Energy `½|u|² + κ(Λ₃₃ − 1)`.
#[derive(Debug, Clone)]
pub struct HyperbolicOscillator {
    /// The stiffness `κ`.
    pub kappa: f64,
}

impl System for HyperbolicOscillator {
    type State = HyperbolicOscillatorState;
    fn vector_field(&self, _t: f64, y: &HyperbolicOscillatorState) -> ProductAlgebra<Vector3<f64>, Vector2<f64>> {
        let l = y.0.matrix();
        let u = y.1 .0;
        ProductAlgebra(Vector3::new(u[0], u[1], 0.0), Vector2::new(-self.kappa * l[(2, 0)], -self.kappa * l[(2, 1)]))
    }
    fn energy(&self, y: &HyperbolicOscillatorState) -> f64 {
        0.5 * y.1 .0.norm_squared() + self.kappa * (y.0.matrix()[(2, 2)] - 1.0)
    }
    fn defect(&self, y: &HyperbolicOscillatorState) -> f64 {
        y.0.constraint_defect()
    }
}

/// The frame `Λ` (column-major) and the velocity components `u`.
pub fn hyperbolic_oscillator_observable(_m: &HyperbolicOscillator, y: &HyperbolicOscillatorState) -> Vec<f64> {
    let mut v: Vec<f64> = y.0.matrix().iter().copied().collect();
    v.extend(y.1 .0.iter());
    v
}

/// The angular momentum about the origin, `x₀ẋ₁ − x₁ẋ₀` with `x = Λe₃` and
/// `ẋ = Λ(u₁, u₂, 0)`: the momentum map of the rotations about the
/// hyperboloid's axis, a symmetry of `V`.
pub fn hyperbolic_oscillator_angular_momentum(_m: &HyperbolicOscillator, y: &HyperbolicOscillatorState) -> f64 {
    let l = y.0.matrix();
    let u = y.1 .0;
    let x = l.column(2);
    let xd = l.column(0) * u[0] + l.column(1) * u[1];
    x[0] * xd[1] - x[1] * xd[0]
}

/// The oscillator on H² of the tests: κ = 1, starting off the origin at
/// `Λ₀ = kak(0.3, 0.8, −0.2)` with `u₀ = (0.4, 0.9)` (a bounded orbit),
/// T = 4.
pub fn hyperbolic_oscillator() -> Reference<HyperbolicOscillator> {
    Reference {
        name: "h2_oscillator",
        about: "point on H² in V = κ(cosh r − 1), κ = 1, frame-bundle form",
        system: HyperbolicOscillator { kappa: 1.0 },
        y0: Product(So12::from_kak(0.3, 0.8, -0.2), Rn(Vector2::new(0.4, 0.9))),
        t_end: 4.0,
        observable: hyperbolic_oscillator_observable,
        momentum: hyperbolic_oscillator_angular_momentum,
    }
}
