//! The internal constraint of an affine body: which fibre group its internal
//! configuration `ρ` lives in, how the hypermomentum is projected, and the free
//! affine body ([`Unconstrained`]). The three constrained bodies of §4 are in
//! [`constrained`](super::constrained).

use std::fmt::Debug;

use super::{inverse, Additive, Inertia, Mat};
use crate::body::Affine;
use crate::lie::{Gl, LieGroup};
use crate::Result;

/// What [`InternalConstraint::kinematics`] returns: the internal configuration
/// and velocity recovered from the fibre element and the (projected)
/// hypermomentum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics<F: LieGroup, const N: usize> {
    /// `ρ`, components of the body frame in the parallel frame (`e = qρ`).
    pub rho: Mat<N>,
    /// `ρ̇`.
    pub rho_dot: Mat<N>,
    /// `Ω̂ = ρ⁻¹ρ̇` as an element of the fibre's algebra (`ρ̇ = ρ·Ω̂`).
    pub xi: F::Algebra,
}

/// The internal configuration space of an affine body: GL⁺(N) for the free
/// affine body ([`Unconstrained`]) or one of the subgroups of §4
/// ([`Isochoric`](super::constrained::Isochoric) for SL(N),
/// [`Conformal`](super::constrained::Conformal) for CO⁺(N),
/// [`PureDilatation`](super::constrained::PureDilatation) for ℝ⁺).
///
/// A constrained body moves with `Ω̂ = ρ⁻¹ρ̇` in a subalgebra `𝔥` (closed under
/// transposition). By d'Alembert's principle the reaction torque `N_R`
/// does no work on admissible motions, `tr(N_R Y) = 0` for all `Y ∈ 𝔥`, so
/// the equations of motion are the projection of the balance law (c59) onto
/// `𝔥` — exactly as the paper prescribes (traceless part for incompressible
/// bodies, (b61) + (b63) for Weyl bodies, (b63) for pure dilatations):
///
/// ```text
/// d/dt P(K) = P(ρ̇Jρ̇ᵀ + N),     P the orthogonal projection onto 𝔥,
/// ```
///
/// and `Ω̂ ∈ 𝔥` is recovered from `P(K)` by solving `P(ρJΩ̂ᵀρᵀ) = P(K)`.
/// Because `𝔥` is closed under transposition, `P(K) − P(K)ᵀ` is the spin of the
/// unconstrained formula, so the translational equation is unchanged.
pub trait InternalConstraint<const N: usize>: Clone + Debug + Send + Sync + 'static {
    /// The body parameter type ([`Affine`], [`Incompressible`](crate::body::Incompressible), …).
    type Body;
    /// The group the internal configuration `ρ` is stored in.
    type Fibre: LieGroup;
    /// The additive group of the projected hypermomentum `P(K)`.
    type Momentum: LieGroup;
    /// Name of the constraint, e.g. `"GL+(n)"`.
    const NAME: &'static str;
    /// The tangency condition on `ρ̇`, in words (for error messages).
    const TANGENCY: &'static str;
    /// The configuration constraint on `ρ`, in words (for error messages).
    const CONFIGURATION: &'static str;

    /// Mass and inertia of the body.
    fn body_parameters(body: &Self::Body) -> (f64, Mat<N>);
    /// The matrix `ρ` of a fibre element.
    fn rho(&self, f: &Self::Fibre) -> Mat<N>;
    /// The fibre element of a matrix `ρ` that satisfies the configuration
    /// constraint to [`STATE_TOLERANCE`](super::STATE_TOLERANCE) (relative); typed errors name the
    /// field `"rho"`. `det ρ > 0` and finiteness are checked by the caller.
    fn fibre(&self, rho: &Mat<N>) -> Result<Self::Fibre>;
    /// `P(K)` of a hypermomentum matrix, as a momentum.
    fn momentum(&self, k: &Mat<N>) -> Self::Momentum;
    /// The matrix `P(K)` of a momentum.
    fn momentum_matrix(&self, m: &Self::Momentum) -> Mat<N>;
    /// `P(A)` in the momentum algebra (the time derivative of the momentum
    /// when `A = ρ̇Jρ̇ᵀ + N`).
    fn project(&self, a: &Mat<N>) -> <Self::Momentum as LieGroup>::Algebra;
    /// `ρ`, `ρ̇` and `Ω̂` from the fibre element and `P(K)` (the hot path).
    fn kinematics(&self, f: &Self::Fibre, k: &Mat<N>, inertia: &Inertia<N>) -> Kinematics<Self::Fibre, N>;
    /// The derivative of [`kinematics`](Self::kinematics) when the fibre
    /// element moves to `f·exp(s·df)` and the hypermomentum matrix by `dk`:
    /// `(δρ, δρ̇, δΩ̂)` in the fields of a [`Kinematics`] (the exact
    /// derivative of the vector field,
    /// [`System::tangent_field`](crate::dynamics::System::tangent_field)).
    /// `kin` is `kinematics(f, k, inertia)`, which the caller has.
    fn kinematics_derivative(&self, f: &Self::Fibre, k: &Mat<N>, inertia: &Inertia<N>, kin: &Kinematics<Self::Fibre, N>, df: &<Self::Fibre as LieGroup>::Algebra, dk: &Mat<N>) -> Kinematics<Self::Fibre, N>;
    /// The matrix of a momentum direction: `d/ds momentum_matrix(m·exp(s·dm))`,
    /// linear in `dm` (the momentum groups are additive).
    fn momentum_direction(&self, dm: &<Self::Momentum as LieGroup>::Algebra) -> Mat<N>;
    /// Largest entry of the component of `Ω̂ = ρ⁻¹ρ̇` outside the fibre's
    /// algebra (0 for an admissible velocity).
    fn velocity_defect(&self, omega: &Mat<N>) -> f64;
    /// The fibre part of a gauge direction ([`System::gauge`](crate::dynamics::System::gauge)):
    /// the left-trivialised velocity `ρ⁻¹(−w)ρ` of `ρ ↦ kᵀρ`, `k = exp(τw)`,
    /// `w` skew, when the fibre is closed under rotations from the left
    /// (GL⁺, SL, CO⁺); `None` when it is not (pure dilatation: the body
    /// frame is the parallel frame up to scale, so turning `q` turns the
    /// body and there is no gauge freedom).
    fn frame_gauge(&self, f: &Self::Fibre, w: &Mat<N>) -> Option<<Self::Fibre as LieGroup>::Algebra>;
}

/// The free affine body: `ρ ∈ GL⁺(N)` ([`Gl`]), momentum `K ∈ gl(N)`,
/// `ρ̇ = Kᵀρ⁻ᵀJ⁻¹`, `K̇ = ρ̇Jρ̇ᵀ + N` (c59).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Unconstrained;

impl<const N: usize> InternalConstraint<N> for Unconstrained {
    type Body = Affine<N>;
    type Fibre = Gl<N>;
    type Momentum = Additive<Gl<N>>;
    const NAME: &'static str = "GL+(n)";
    const TANGENCY: &'static str = "any ρ̇";
    const CONFIGURATION: &'static str = "det ρ > 0";

    fn body_parameters(body: &Affine<N>) -> (f64, Mat<N>) {
        (body.mass(), *body.inertia())
    }
    #[inline]
    fn rho(&self, f: &Gl<N>) -> Mat<N> {
        *f.matrix()
    }
    fn fibre(&self, rho: &Mat<N>) -> Result<Gl<N>> {
        Ok(Gl::new_unchecked(*rho))
    }
    #[inline]
    fn momentum(&self, k: &Mat<N>) -> Additive<Gl<N>> {
        Additive(*k)
    }
    #[inline]
    fn momentum_matrix(&self, m: &Additive<Gl<N>>) -> Mat<N> {
        m.0
    }
    #[inline]
    fn project(&self, a: &Mat<N>) -> Mat<N> {
        *a
    }
    #[inline]
    fn kinematics(&self, f: &Gl<N>, k: &Mat<N>, inertia: &Inertia<N>) -> Kinematics<Gl<N>, N> {
        let rho = *f.matrix();
        let rho_inv = inverse(&rho).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN));
        // P = ρ̇J = Kᵀρ⁻ᵀ (the conjugate momentum), ρ̇ = P J⁻¹.
        let p = k.transpose() * rho_inv.transpose();
        let rho_dot = p * inertia.j_inv;
        Kinematics { rho, rho_dot, xi: rho_inv * rho_dot }
    }
    /// `δρ = ρX`, `δ(ρ⁻¹) = −Xρ⁻¹`, `δρ̇ = (δKᵀρ⁻ᵀ + Kᵀδ(ρ⁻¹)ᵀ)J⁻¹`,
    /// `δΩ̂ = δ(ρ⁻¹)ρ̇ + ρ⁻¹δρ̇`.
    fn kinematics_derivative(&self, _f: &Gl<N>, k: &Mat<N>, inertia: &Inertia<N>, kin: &Kinematics<Gl<N>, N>, df: &Mat<N>, dk: &Mat<N>) -> Kinematics<Gl<N>, N> {
        let rho_inv = inverse(&kin.rho).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN));
        let d_rho = kin.rho * df;
        let d_inv = -(df * rho_inv);
        let d_rho_dot = (dk.transpose() * rho_inv.transpose() + k.transpose() * d_inv.transpose()) * inertia.j_inv;
        Kinematics { rho: d_rho, rho_dot: d_rho_dot, xi: d_inv * kin.rho_dot + rho_inv * d_rho_dot }
    }
    fn momentum_direction(&self, dm: &Mat<N>) -> Mat<N> {
        *dm
    }
    fn velocity_defect(&self, _omega: &Mat<N>) -> f64 {
        0.0
    }
    fn frame_gauge(&self, f: &Gl<N>, w: &Mat<N>) -> Option<Mat<N>> {
        inverse(f.matrix()).map(|inv| -(inv * w * f.matrix()))
    }
}
