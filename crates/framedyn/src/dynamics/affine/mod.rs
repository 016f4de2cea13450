//! Infinitesimal affinely-rigid bodies on a frame bundle (paper §4 (a52),
//! (a59), (d59), (c59); SPEC §3.2, §7), and — through the
//! [`InternalConstraint`] parameter — the constrained affine bodies of §4
//! (see [`constrained`]).
//!
//! # Variables
//!
//! The body frame is `e = q·ρ`: `q = (q₁ … q_N)` is the orthonormal frame of
//! the bundle element `g` ([`FrameBundle`]), **parallel-transported** along
//! the path, and `ρ` (a matrix with `det ρ > 0`) holds the components of the
//! body vectors `e_A = q_a ρ^a_A` in it. The state is
//!
//! ```text
//! y = ((g, ρ), (u, K))  ∈  (G × F) × (ℝᴺ × 𝔨)         (BodyState)
//! ```
//!
//! - `g ∈ G` the bundle element (position `x` and parallel frame `q`),
//! - `ρ ∈ F` the internal configuration: GL⁺(N) ([`Gl`]) for the affine body,
//!   SL(N), CO⁺(N) or ℝ⁺ for the constrained ones,
//! - `u ∈ ℝᴺ` the velocity in the parallel frame, `ẋ = Σ u_a q_a`,
//! - `K` the **kinematical hypermomentum** (affine spin) of the paper,
//!   `K^{ab} = e^a_K (De^b_L/Dt) J^{KL}` (before (b59)), in the parallel frame:
//!   `K = ρ J ρ̇ᵀ`. For a constrained body only its projection onto the
//!   constraint algebra is carried ([`InternalConstraint::project`]), so every
//!   model carries exactly its own degrees of freedom.
//!
//! # Equations of motion (derived from (a52))
//!
//! Kinetic energy. `q` is parallel, `Dq_a/Dt = 0`, hence `De/Dt = q ρ̇`
//! ([`AffineBodyModel::frame_rate`]) and, `q` being orthonormal, (a52) becomes
//!
//! ```text
//! T = (m/2)|u|² + ½ tr(ρ̇ J ρ̇ᵀ)                                (SPEC §3.2)
//! ```
//!
//! the drive terms `φ⁻¹Γφ` of the paper's coordinate form (a74) are absent.
//!
//! Translation, (a59): `m DV^a/Dt = ½ S^k_l R^l_k{}^a{}_j V^j + F^a`. In the
//! parallel frame `DV/Dt = q u̇`, and for the manifolds here (two-dimensional
//! or of constant curvature) the Riemann tensor in an orthonormal frame is
//! `R̂_{lkaj} = K(δ_la δ_kj − δ_lj δ_ka)`, `K` the sectional curvature
//! ([`FrameBundle::curvature_at`]). Contracting with the skew spin `S` gives
//! `½ S_{kl} K(δ_la δ_kj − δ_lj δ_ka) u_j = ½K(Sᵀu − Su)_a = −K(Su)_a`:
//!
//! ```text
//! m u̇ = −K S u + F̂,      S = K − Kᵀ = ρJρ̇ᵀ − ρ̇Jρᵀ,      ġ = g·lift(u)
//! ```
//!
//! (SPEC §7 "spin–curvature force", checked there against the full
//! equations). The geometric force `−K S u` is orthogonal to `u` (S skew): it
//! does no work. `F̂_a = −H_a V` is the horizontal force
//! ([`horizontal_force`]).
//!
//! Internal motion, (d59): `e^a_K (D²e^b_L/Dt²) J^{KL} = N^{ab}` with
//! `N^{ab} = −e^a_K ∂V/∂e^b_K`. With `D²e/Dt² = q ρ̈` and `∂V/∂ρ = qᵀ∂V/∂e`
//! ([`internal_gradient`]) this is
//!
//! ```text
//! ρ J ρ̈ᵀ = N = −ρ (∂V/∂ρ)ᵀ,     i.e.   ρ̈ J = −∂V/∂ρ
//! ```
//!
//! (free motion: `ρ̈ = 0`, `ρ(t) = ρ₀ + t ρ̇₀`: the body frame moves linearly
//! relative to the parallel frame). Differentiating `K = ρJρ̇ᵀ` gives the
//! balance law (c59) that is integrated here:
//!
//! ```text
//! K̇ = ρ̇ J ρ̇ᵀ + N,          ρ̇ = Kᵀ ρ⁻ᵀ J⁻¹,          ρ̇ = ρ·Ω̂,  Ω̂ = ρ⁻¹ρ̇
//! ```
//!
//! `Ω̂` is the left-trivialised velocity the Lie-group integrator consumes.
//!
//! Checked (`tests/suite/dynamics_affine.rs`) against the independent
//! coordinate form [`coords::Affine2`](crate::coords::Affine2) (Euler–Lagrange
//! equations of (a52) with (a74) by automatic differentiation): the ambient
//! accelerations agree to 8e-13 relative on S², H², T² with every force
//! active, and the energy, `p_φ`, `p_α`, `p_β` equal the coordinate form's
//! energy and two-polar canonical momenta to 1e-14.
//!
//! # Why the hypermomentum `K` is the internal variable
//!
//! - Its skew part is the spin: `Ṡ = N − Nᵀ` (b61). `ρ̇Jρ̇ᵀ` is symmetrised
//!   before use, so for torque-free or spatially isotropic potentials
//!   (`N` symmetric) **any** Runge–Kutta or RKMK method conserves `S` to
//!   round-off, and with it the spin–curvature force and the spin part of the
//!   momentum maps. Measured on S² with an anisotropic `J`, an elastic and a
//!   position potential, RKMK4, `h = 0.01`: spin drift 2e-16 with `K`, 1e-10
//!   with the conjugate momentum `P = ρ̇J` and with `Ω̂`; `p_φ` error 4e-11
//!   (`K`), 3e-10 (`P`), 6e-11 (`Ω̂`); energy error 2.9e-10, 3.9e-10, 4.3e-10.
//! - It is the variable of the paper's balance laws (b59), (c59), and the
//!   constrained bodies of §4 are literally its projections (traceless part for
//!   SL, trace and skew part for CO⁺, trace for ℝ⁺): one set of equations for
//!   all four models.
//! - It is additive (a vector space), so it needs no exponential; `Ω̂` would
//!   carry the inertial term `−Ω̂²` even in free motion.
//!
//! # Conserved quantities and diagnostics
//!
//! Energy `T + V`; spin `S` (constant when `N` is symmetric, e.g. for potentials
//! of the Green tensor); the co-moving hypermomentum `Σ̂ = Jρ̇ᵀρ` and the
//! vorticity `Σ̂ − Σ̂ᵀ` (the Noether charge of material rotations `ρ → ρR`,
//! conserved when `J ∝ I` and `V(ρR) = V(ρ)`); the Noether charge of any
//! ambient isometry ([`AffineBodyModel::noether_charge`], `p_φ` for rotations
//! about the symmetry axis). In two dimensions `p_α = S¹²`, `p_β = −(Σ̂ − Σ̂ᵀ)₁₂`
//! are the paper's spin and vorticity momenta of the two-polar decomposition
//! `φ = L(α) D R(β)⁻¹` (§5).
//!
//! # Collapse
//!
//! GL⁺(N) is not complete under free motion: `det(ρ₀ + tρ̇₀)` vanishes at
//! `t* = −1/λ` for the real negative eigenvalues `λ` of `Ω̂` (the body
//! flattens and would turn inside out), and `‖Ω̂‖` grows like `1/(t* − t)`.
//! The exponential map of the integrator cannot cross `det ρ = 0`. The model
//! reports the approach: [`AffineBodyModel::free_collapse_time`] predicts
//! `t*`; [`AffineBodyModel::deformation_rate`] `= ‖Ω̂‖` is the step-size
//! limit (an integrator keeping `h‖Ω̂‖ ≪ 1` approaches `t*` geometrically);
//! [`AffineBodyModel::check_state`] fails with a typed [`Error::Constraint`]
//! (field `"rho"`) once `max(σ_max(ρ), 1)/σ_min(ρ) > 1e12`
//! ([`COLLAPSE_TOLERANCE`]), with [`Error::NotFinite`] for a state the
//! exponential has overflowed, and the vector field of an exactly singular
//! `ρ` is non-finite. What no model can do is recognise the finite but wrong
//! state a fixed step *across* `t*` may produce (measured: `det ρ` jumps from
//! 7e-3 to 1e6): that step had `h‖Ω̂‖ ≈ 1`, which the integrator must refuse.
//!
//! [`FrameBundle`]: crate::bundle::FrameBundle
//! [`Gl`]: crate::lie::Gl
//! [`FrameBundle::curvature_at`]: crate::bundle::FrameBundle::curvature_at
//! [`horizontal_force`]: super::horizontal_force
//! [`internal_gradient`]: super::internal_gradient
//! [`Error::Constraint`]: crate::Error::Constraint
//! [`Error::NotFinite`]: crate::Error::NotFinite

// The additive group of the hypermomentum (`Additive`, `MatrixAlgebra`).
mod additive;
// The incompressible, Weyl and purely dilatational bodies.
pub mod constrained;
// The internal-constraint framework and the free affine body (`Unconstrained`).
mod constraint;
// Deformation, defects and collapse.
mod diagnostics;
// The inertia `J` and the small-matrix helpers.
pub(crate) mod inertia;
// State, model, kinematics, forces, energies and the equations of motion.
mod model;
// Hypermomentum, spin, vorticity and the Noether charges.
mod momenta;

use nalgebra::SMatrix;

pub use additive::{Additive, MatrixAlgebra};
pub use constraint::{InternalConstraint, Kinematics, Unconstrained};
pub use diagnostics::COLLAPSE_TOLERANCE;
pub(crate) use diagnostics::{check_regular, conformality_defect, linear_collapse_time};
pub use inertia::Inertia;
pub(crate) use inertia::{inverse, trace_of_product};
pub use model::{AffineBodyModel, AffineModel, BodyState, BodyVelocity, STATE_TOLERANCE};

type Mat<const N: usize> = SMatrix<f64, N, N>;
