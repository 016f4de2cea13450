//! Infinitesimal affinely-rigid bodies on a frame bundle (paper §4 (a52),
//! (a59), (d59), (c59); SPEC §3.2, §7), and — through the
//! [`InternalConstraint`] parameter — the constrained affine bodies of §4
//! (see [`constrained`](super::constrained)).
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
//! Kinetic energy. `q` is parallel, `Dq_a/Dt = 0`, hence `De/Dt = q ρ̇` and,
//! `q` being orthonormal, (a52) becomes
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

use std::fmt::Debug;

use nalgebra::{DMatrix, SMatrix, SVector};

use crate::body::{check_inertia, Affine};
use crate::bundle::FrameBundle;
use crate::dynamics::{horizontal_force, internal_gradient, System};
use crate::error::finite;
use crate::lie::gl::matfun::{det, skew_part, traceless_part, Lu};
use crate::lie::{AlgebraVector, Co, Gl, LieGroup, Product, ProductAlgebra, Rn, Sl};
use crate::potential::Potential;
use crate::{Error, Result};

type Mat<const N: usize> = SMatrix<f64, N, N>;

/// Relative tolerance of the state checks ([`AffineBodyModel::state`],
/// [`AffineBodyModel::check_state`]): bundle and fibre group constraints,
/// tangency of `ρ̇`.
pub const STATE_TOLERANCE: f64 = 1e-9;

/// Largest accepted `max(σ_max(ρ), 1)/σ_min(ρ)`: beyond it the body counts as
/// collapsed (flattened, or shrunk below 1e-12 of an orthonormal frame).
pub const COLLAPSE_TOLERANCE: f64 = 1e12;

// ---------------------------------------------------------------------------
// The additive group of a Lie algebra (momentum spaces)
// ---------------------------------------------------------------------------

/// A matrix group whose Lie algebra is a linear space of `N×N` matrices,
/// closed under transposition, with its orthogonal (Frobenius) projection:
/// gl(N) ([`Gl`]), sl(N) ([`Sl`]: traceless part), co(N) ([`Co`]: `(tr a/N)I`
/// plus the skew part). The momentum spaces of the affine bodies.
pub trait MatrixAlgebra: LieGroup {
    /// The orthogonal projection of an `N×N` matrix onto the algebra.
    fn project_algebra(a: &Self::Algebra) -> Self::Algebra;
}

impl<const N: usize> MatrixAlgebra for Gl<N> {
    /// The identity.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        *a
    }
}

impl<const N: usize> MatrixAlgebra for Sl<N> {
    /// `a − (tr a/N)I`.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        traceless_part(a)
    }
}

impl<const N: usize> MatrixAlgebra for Co<N> {
    /// `(tr a/N)I + (a − aᵀ)/2`.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        let mut p = skew_part(a);
        let t = a.trace() / N as f64;
        for i in 0..N {
            p[(i, i)] += t;
        }
        p
    }
}

/// The Lie algebra of the matrix group `G` as an additive group: the space in
/// which the hypermomentum of a (constrained) affine body lives (the dual of
/// the algebra, identified with it by the pairing `⟨A, B⟩ = tr(AᵀB)`).
///
/// `exp` is the identity map, `compose` is addition, all brackets vanish,
/// `dexp = dexp⁻¹ = id`. Coordinates and `DOF` are those of `G`'s algebra
/// (e.g. `n² − 1` for [`Sl`]). Matrix representation: the `(DOF+1)×(DOF+1)`
/// translation matrix of the coordinates. [`constraint_defect`](LieGroup::constraint_defect)
/// is the largest entry of the part of the stored matrix outside the algebra,
/// relative to `1 + max|a_ij|`; [`renormalize`](LieGroup::renormalize)
/// projects onto the algebra ([`MatrixAlgebra::project_algebra`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Additive<G: LieGroup>(pub G::Algebra);

impl<G: MatrixAlgebra> Additive<G> {
    fn coords_matrix(c: &[f64]) -> DMatrix<f64> {
        let k = c.len();
        let mut m = DMatrix::identity(k + 1, k + 1);
        for (i, v) in c.iter().enumerate() {
            m[(i, k)] = *v;
        }
        m
    }
}

impl<G: MatrixAlgebra> LieGroup for Additive<G> {
    type Algebra = G::Algebra;
    const DOF: usize = G::DOF;
    const NAME: &'static str = "additive Lie algebra";

    #[inline]
    fn identity() -> Self {
        Additive(G::Algebra::zero())
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Additive(self.0 + rhs.0)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Additive(-self.0)
    }
    #[inline]
    fn exp(a: &Self::Algebra) -> Self {
        Additive(*a)
    }
    fn log(&self) -> Result<Self::Algebra> {
        Ok(self.0)
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        *a
    }
    #[inline]
    fn bracket(_a: &Self::Algebra, _b: &Self::Algebra) -> Self::Algebra {
        G::Algebra::zero()
    }
    #[inline]
    fn dexp(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    #[inline]
    fn dexp_inv(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        G::algebra_from_coords(c)
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        G::algebra_coords(a)
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        Self::coords_matrix(&G::algebra_coords(&self.0))
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let mut m = Self::coords_matrix(&G::algebra_coords(a));
        for i in 0..m.nrows() {
            m[(i, i)] = 0.0;
        }
        m
    }
    /// `max|a − P(a)| / (1 + max|a|)` (`+∞` if not finite).
    fn constraint_defect(&self) -> f64 {
        if !self.0.is_finite() {
            return f64::INFINITY;
        }
        (self.0 - G::project_algebra(&self.0)).amax() / (1.0 + self.0.amax())
    }
    #[inline]
    fn renormalize(&self) -> Self {
        Additive(G::project_algebra(&self.0))
    }
}

// ---------------------------------------------------------------------------
// Inertia
// ---------------------------------------------------------------------------

/// The micromaterial inertia `J` (symmetric positive definite) with the data
/// the equations need: `J⁻¹` and the principal axes and moments
/// (`J = V diag(j) Vᵀ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia<const N: usize> {
    j: Mat<N>,
    j_inv: Mat<N>,
    axes: Mat<N>,
    moments: SVector<f64, N>,
}

impl<const N: usize> Inertia<N> {
    /// Validates `j` ([`check_inertia`]: finite, symmetric, positive definite;
    /// errors name the field `"J"`) and precomputes `J⁻¹` and the principal
    /// axes.
    pub fn new(j: &Mat<N>) -> Result<Self> {
        let j = check_inertia(j)?;
        let j_inv = inverse(&j).ok_or(Error::Constraint {
            field: "J",
            constraint: "J invertible",
            defect: f64::INFINITY,
            tolerance: 0.0,
        })?;
        let eig = DMatrix::from_column_slice(N, N, j.as_slice()).symmetric_eigen();
        let axes = Mat::<N>::from_column_slice(eig.eigenvectors.as_slice());
        let moments = SVector::<f64, N>::from_column_slice(eig.eigenvalues.as_slice());
        Ok(Self { j, j_inv: (j_inv + j_inv.transpose()) * 0.5, axes, moments })
    }
    /// `J`.
    pub fn matrix(&self) -> &Mat<N> {
        &self.j
    }
    /// `J⁻¹`.
    pub fn inverse(&self) -> &Mat<N> {
        &self.j_inv
    }
    /// Principal axes `V` (orthogonal, columns), `J = V diag(j) Vᵀ`.
    pub fn axes(&self) -> &Mat<N> {
        &self.axes
    }
    /// Principal moments `j` (eigenvalues of `J`).
    pub fn moments(&self) -> &SVector<f64, N> {
        &self.moments
    }
    /// The skew `ω` with `Jω + ωJ = c` for skew `c` (the inertia operator of
    /// a rotating body, inverted in the principal axes:
    /// `ω̃_ij = c̃_ij/(j_i + j_j)`).
    pub fn solve_rotational(&self, c: &Mat<N>) -> Mat<N> {
        let ct = self.axes.transpose() * c * self.axes;
        let w = Mat::<N>::from_fn(|i, k| if i == k { 0.0 } else { ct[(i, k)] / (self.moments[i] + self.moments[k]) });
        self.axes * w * self.axes.transpose()
    }
}

/// `m⁻¹` (closed form for n ≤ 3, LU otherwise); `None` when `m` is singular
/// or not finite.
pub(crate) fn inverse<const N: usize>(m: &Mat<N>) -> Option<Mat<N>> {
    let mut out = Mat::<N>::zeros();
    match N {
        1 => {
            let d = m[(0, 0)];
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            out[(0, 0)] = 1.0 / d;
        }
        2 => {
            let d = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            let r = 1.0 / d;
            out[(0, 0)] = m[(1, 1)] * r;
            out[(0, 1)] = -m[(0, 1)] * r;
            out[(1, 0)] = -m[(1, 0)] * r;
            out[(1, 1)] = m[(0, 0)] * r;
        }
        3 => {
            let c = |i: usize, k: usize| {
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                m[(i1, k1)] * m[(i2, k2)] - m[(i1, k2)] * m[(i2, k1)]
            };
            let (c00, c01, c02) = (c(0, 0), c(0, 1), c(0, 2));
            let d = m[(0, 0)] * c00 + m[(0, 1)] * c01 + m[(0, 2)] * c02;
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            let r = 1.0 / d;
            for i in 0..3 {
                for k in 0..3 {
                    out[(k, i)] = c(i, k) * r;
                }
            }
        }
        _ => return Lu::new(m).map(|lu| lu.inverse()),
    }
    if out.iter().all(|x| x.is_finite()) {
        Some(out)
    } else {
        None
    }
}

/// `tr(A·B)` without forming the product.
#[inline]
pub(crate) fn trace_of_product<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> f64 {
    a.component_mul(&b.transpose()).sum()
}

// ---------------------------------------------------------------------------
// The internal constraint: which fibre the body lives in
// ---------------------------------------------------------------------------

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
    /// constraint to [`STATE_TOLERANCE`] (relative); typed errors name the
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
    /// Largest entry of the component of `Ω̂ = ρ⁻¹ρ̇` outside the fibre's
    /// algebra (0 for an admissible velocity).
    fn velocity_defect(&self, omega: &Mat<N>) -> f64;
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
    fn velocity_defect(&self, _omega: &Mat<N>) -> f64 {
        0.0
    }
}

// ---------------------------------------------------------------------------
// The model
// ---------------------------------------------------------------------------

/// The state of an (constrained) affine body on the frame bundle `B`:
/// `((g, ρ), (u, P(K)))` — see the [module documentation](self). Access:
/// `y.0 .0` = `g`, `y.0 .1` = `ρ` (fibre element), `y.1 .0 .0` = `u`,
/// `y.1 .1` = the momentum (`P(K)`, read as a matrix with
/// [`AffineBodyModel::momentum_matrix`]).
pub type BodyState<B, C, const N: usize, const E: usize> = Product<
    Product<<B as FrameBundle<N, E>>::Group, <C as InternalConstraint<N>>::Fibre>,
    Product<Rn<N>, <C as InternalConstraint<N>>::Momentum>,
>;

/// The left-trivialised velocity of a [`BodyState`].
pub type BodyVelocity<B, C, const N: usize, const E: usize> = <BodyState<B, C, N, E> as LieGroup>::Algebra;

/// An infinitesimal affinely-rigid body (or a constrained one, by `C`) of mass
/// `m` and inertia `J` on the frame bundle `B`, in the potential `V`.
///
/// Equations (see the [module documentation](self) for the derivation from
/// (a52), (a59), (d59), (c59)):
///
/// ```text
/// ġ = g·lift(u),   ρ̇ = ρΩ̂,   m u̇ = −K S u + F̂,   d/dt P(K) = P(ρ̇Jρ̇ᵀ + N)
/// ```
///
/// with `K` the sectional curvature at `g`, `S = P(K) − P(K)ᵀ` the spin,
/// `F̂_a = −H_aV`, `N = −ρ(∂V/∂ρ)ᵀ`. Use the aliases [`AffineModel`],
/// [`IncompressibleModel`](super::constrained::IncompressibleModel),
/// [`WeylModel`](super::constrained::WeylModel),
/// [`DilatationModel`](super::constrained::DilatationModel).
#[derive(Debug, Clone)]
pub struct AffineBodyModel<B, V, C, const N: usize, const E: usize> {
    bundle: B,
    potential: V,
    constraint: C,
    mass: f64,
    inv_mass: f64,
    inertia: Inertia<N>,
    metric: SMatrix<f64, E, E>,
    frame_dependent: bool,
}

/// The free (unconstrained) affinely-rigid body of §4: `ρ ∈ GL⁺(N)`,
/// `n + n²` degrees of freedom.
pub type AffineModel<B, V, const N: usize, const E: usize> = AffineBodyModel<B, V, Unconstrained, N, E>;

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N> + Default,
{
    /// The body `body` (mass and inertia, validated by its constructor) on
    /// the bundle `bundle` in the potential `potential`, with the default
    /// constraint data (for [`PureDilatation`](super::constrained::PureDilatation):
    /// the reference shape `ρ₀ = I`).
    pub fn new(bundle: B, body: C::Body, potential: V) -> Result<Self> {
        Self::with_constraint(bundle, body, potential, C::default())
    }
}

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    /// As [`Self::new`] with explicit constraint data. Fails only if the
    /// body's parameters do not validate (mass finite and > 0, field `"mass"`;
    /// `J` symmetric positive definite, field `"J"`).
    pub fn with_constraint(bundle: B, body: C::Body, potential: V, constraint: C) -> Result<Self> {
        let (mass, j) = C::body_parameters(&body);
        let mass = crate::error::positive("mass", mass)?;
        let inertia = Inertia::new(&j)?;
        let metric = bundle.ambient_metric();
        let frame_dependent = potential.uses_frame();
        Ok(Self { bundle, potential, constraint, mass, inv_mass: 1.0 / mass, inertia, metric, frame_dependent })
    }

    /// The same model with other constraint data of the same kind.
    pub(super) fn replace_constraint(mut self, constraint: C) -> Self {
        self.constraint = constraint;
        self
    }

    /// The frame bundle.
    pub fn bundle(&self) -> &B {
        &self.bundle
    }
    /// The potential.
    pub fn potential(&self) -> &V {
        &self.potential
    }
    /// The constraint data.
    pub fn constraint(&self) -> &C {
        &self.constraint
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// The inertia `J` and its derived data.
    pub fn inertia(&self) -> &Inertia<N> {
        &self.inertia
    }

    // -- states ---------------------------------------------------------------

    /// The state at bundle element `g` with internal configuration `ρ`,
    /// velocity `u` (parallel-frame components) and internal velocity `ρ̇`.
    ///
    /// For a constrained body `ρ̇` is checked and the stored momentum is the
    /// projection `P(ρJρ̇ᵀ)`; `ρ` is stored as the fibre element (e.g. for SL
    /// rescaled to `det ρ = 1` exactly).
    ///
    /// Errors: [`Error::NotFinite`] (fields `"g"`, `"rho"`, `"u"`,
    /// `"rho_dot"`); [`Error::Constraint`] field `"g"` if
    /// [`FrameBundle::bundle_defect`] exceeds [`STATE_TOLERANCE`];
    /// [`Error::InvalidParameter`] field `"det(rho)"` unless `det ρ > 0`;
    /// [`Error::Constraint`] field `"rho"` for a collapsed `ρ` (see
    /// [`COLLAPSE_TOLERANCE`]) or one violating the fibre's configuration
    /// constraint (`det ρ = 1`, `ρ` conformal, `ρ ∝ ρ₀`, relative 1e-9);
    /// [`Error::Constraint`] field `"rho_dot"` unless `ρ⁻¹ρ̇` lies in the
    /// fibre's algebra (relative 1e-9).
    pub fn state(
        &self,
        g: &B::Group,
        rho: &Mat<N>,
        u: &SVector<f64, N>,
        rho_dot: &Mat<N>,
    ) -> Result<BodyState<B, C, N, E>> {
        self.check_bundle_element(g)?;
        finite("rho", rho.iter())?;
        check_regular(rho)?;
        let f = self.constraint.fibre(rho)?;
        finite("u", u.iter())?;
        finite("rho_dot", rho_dot.iter())?;
        let rho_s = self.constraint.rho(&f);
        let omega = inverse(&rho_s).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN)) * rho_dot;
        let scale = omega.amax();
        let defect = if scale > 0.0 { self.constraint.velocity_defect(&omega) / scale } else { 0.0 };
        if defect.is_nan() || defect > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "rho_dot",
                constraint: C::TANGENCY,
                defect,
                tolerance: STATE_TOLERANCE,
            });
        }
        let k = rho_s * self.inertia.j * rho_dot.transpose();
        Ok(Product(Product(*g, f), Product(Rn(*u), self.constraint.momentum(&k))))
    }

    /// The state from the fibre element `f`, the velocity `u` and the
    /// hypermomentum `k = ρJρ̇ᵀ` (projected onto the fibre's algebra; for the
    /// unconstrained body `k` itself). Errors as [`Self::state`] (field
    /// `"momentum"` for a non-finite `k`), and [`Error::Constraint`] field
    /// `"rho"` if the group constraint of `f` is violated.
    pub fn state_from_momentum(
        &self,
        g: &B::Group,
        f: &C::Fibre,
        u: &SVector<f64, N>,
        k: &Mat<N>,
    ) -> Result<BodyState<B, C, N, E>> {
        self.check_bundle_element(g)?;
        let rho = self.constraint.rho(f);
        finite("rho", rho.iter())?;
        check_regular(&rho)?;
        self.check_fibre_group(f)?;
        finite("u", u.iter())?;
        finite("momentum", k.iter())?;
        Ok(Product(Product(*g, *f), Product(Rn(*u), self.constraint.momentum(k))))
    }

    fn check_bundle_element(&self, g: &B::Group) -> Result<()> {
        let p = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        finite("g", p.iter().chain(q.iter()))?;
        let d = self.bundle.bundle_defect(g);
        if d <= STATE_TOLERANCE {
            Ok(())
        } else {
            Err(Error::Constraint {
                field: "g",
                constraint: "valid frame-bundle element (group constraint)",
                defect: d,
                tolerance: STATE_TOLERANCE,
            })
        }
    }

    fn check_fibre_group(&self, f: &C::Fibre) -> Result<()> {
        let d = f.constraint_defect();
        if d <= STATE_TOLERANCE {
            Ok(())
        } else {
            Err(Error::Constraint { field: "rho", constraint: C::CONFIGURATION, defect: d, tolerance: STATE_TOLERANCE })
        }
    }

    /// `Ok` if `y` is a valid state: everything finite, `g` a bundle element
    /// and the fibre element on its group (to [`STATE_TOLERANCE`]), `det ρ > 0`
    /// and `ρ` not collapsed ([`COLLAPSE_TOLERANCE`]). The typed errors are
    /// those of [`Self::state`]; collapse is
    /// `Error::Constraint { field: "rho", .. }` with the measured
    /// `max(σ_max, 1)/σ_min` as the defect.
    pub fn check_state(&self, y: &BodyState<B, C, N, E>) -> Result<()> {
        self.check_bundle_element(&y.0 .0)?;
        let rho = self.constraint.rho(&y.0 .1);
        finite("rho", rho.iter())?;
        check_regular(&rho)?;
        self.check_fibre_group(&y.0 .1)?;
        finite("u", y.1 .0 .0.iter())?;
        finite("momentum", self.constraint.momentum_matrix(&y.1 .1).iter())?;
        Ok(())
    }

    // -- kinematics -------------------------------------------------------------

    /// The projected hypermomentum `P(K)` of the state as a matrix.
    #[inline]
    pub fn momentum_matrix(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.constraint.momentum_matrix(&y.1 .1)
    }
    /// `ρ`, `ρ̇` and `Ω̂ = ρ⁻¹ρ̇` at `y`.
    #[inline]
    pub fn kinematics(&self, y: &BodyState<B, C, N, E>) -> Kinematics<C::Fibre, N> {
        self.constraint.kinematics(&y.0 .1, &self.momentum_matrix(y), &self.inertia)
    }
    /// `ρ`: components of the body frame in the parallel frame, `e = qρ`.
    pub fn rho(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.constraint.rho(&y.0 .1)
    }
    /// `ρ̇`.
    pub fn rho_dot(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.kinematics(y).rho_dot
    }
    /// The position `x` (ambient coordinates).
    pub fn position(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, E> {
        self.bundle.position(&y.0 .0)
    }
    /// The velocity `ẋ = Σ u_a q_a` (ambient coordinates).
    pub fn velocity(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, E> {
        self.bundle.frame_vectors(&y.0 .0) * y.1 .0 .0
    }
    /// The body frame `e = qρ` (columns `e_A`, ambient coordinates).
    pub fn body_frame(&self, y: &BodyState<B, C, N, E>) -> SMatrix<f64, E, N> {
        self.bundle.frame_vectors(&y.0 .0) * self.rho(y)
    }

    // -- forces -------------------------------------------------------------------

    /// `(F̂, ∂V/∂ρ)` at `g` for the internal configuration `rho`.
    #[inline]
    fn forces(&self, g: &B::Group, rho: &Mat<N>) -> (SVector<f64, N>, Mat<N>) {
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let grad = self.potential.gradient(&x, &(q * rho), &self.metric);
        let f = horizontal_force(&self.bundle, g, rho, &grad, self.frame_dependent);
        let v_rho = if self.frame_dependent { internal_gradient(&q, &grad) } else { Mat::<N>::zeros() };
        (f, v_rho)
    }

    /// The horizontal force `F̂_a = −H_aV` (parallel-frame components).
    pub fn horizontal_force(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, N> {
        self.forces(&y.0 .0, &self.rho(y)).0
    }

    /// The internal force (torque) `N = −ρ(∂V/∂ρ)ᵀ` of (d59), parallel-frame
    /// components.
    pub fn torque(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let rho = self.rho(y);
        -(rho * self.forces(&y.0 .0, &rho).1.transpose())
    }

    /// The spin–curvature force of (a59), `½ S^k_l R^l_k{}^a{}_j u^j = −K S u`
    /// (SPEC §7).
    pub fn geometric_force(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, N> {
        -(self.spin(y) * y.1 .0 .0) * self.bundle.curvature_at(&y.0 .0)
    }

    /// The power `u · (−K S u)` of the geometric force: zero (S skew), up to
    /// round-off.
    pub fn geometric_power(&self, y: &BodyState<B, C, N, E>) -> f64 {
        y.1 .0 .0.dot(&self.geometric_force(y))
    }

    // -- invariants -----------------------------------------------------------------

    /// Translational kinetic energy `(m/2)|u|²`.
    pub fn translational_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        0.5 * self.mass * y.1 .0 .0.norm_squared()
    }
    /// Internal kinetic energy `½ tr(ρ̇Jρ̇ᵀ)`.
    pub fn internal_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let rd = self.rho_dot(y);
        0.5 * trace_of_product(&(rd * self.inertia.j), &rd.transpose())
    }
    /// Potential energy `V(x, e)`.
    pub fn potential_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let g = &y.0 .0;
        let e = self.bundle.frame_vectors(g) * self.rho(y);
        self.potential.value(&self.bundle.position(g), &e, &self.metric)
    }

    /// The hypermomentum `K = ρJρ̇ᵀ` (the paper's `K^{ab}`, before (b59)),
    /// parallel-frame components (for a constrained body the full `K`, not its
    /// projection).
    pub fn hypermomentum(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let kin = self.kinematics(y);
        kin.rho * self.inertia.j * kin.rho_dot.transpose()
    }
    /// The spin `S = K − Kᵀ = ρJρ̇ᵀ − ρ̇Jρᵀ` (skew; (b61)), parallel-frame
    /// components. Constant when the torque `N` is symmetric.
    pub fn spin(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let k = self.momentum_matrix(y);
        k - k.transpose()
    }
    /// The co-moving hypermomentum `Σ̂ = Jρ̇ᵀρ = Pᵀρ` (`P = ρ̇J` the conjugate
    /// momentum of `ρ`).
    pub fn comoving_hypermomentum(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let kin = self.kinematics(y);
        self.inertia.j * kin.rho_dot.transpose() * kin.rho
    }
    /// The vorticity `Σ̂ − Σ̂ᵀ`: `tr((Σ̂ − Σ̂ᵀ)A)/2` is the Noether charge of the
    /// material rotations `ρ → ρ exp(εA)` (`A` skew), conserved when `J ∝ I`
    /// and `V(ρR) = V(ρ)` (e.g. `V` a function of the Green tensor's invariants).
    pub fn vorticity(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let s = self.comoving_hypermomentum(y);
        s - s.transpose()
    }

    /// Noether charge of the one-parameter group of ambient isometries
    /// `exp(εA)` (which must map the manifold to itself and leave `V`
    /// invariant for the charge to be conserved):
    ///
    /// ```text
    /// J_A = m⟨ẋ, A x⟩ + Σ_{A,B} J^{AB}⟨De_B/Dt, A e_A⟩ = m⟨qu, Ax⟩ + ½ tr(S W),   W = ⟨q_a, A q_b⟩,
    /// ```
    ///
    /// `⟨·,·⟩` the ambient metric `η` (the internal term reduces to the spin
    /// because `W` is skew). Errors: [`Error::NotFinite`] or
    /// [`Error::Constraint`] (field `"generator"`) unless `ηA` is skew
    /// (relative 1e-12): `A` must generate isometries of the ambient space.
    pub fn noether_charge(&self, y: &BodyState<B, C, N, E>, generator: &SMatrix<f64, E, E>) -> Result<f64> {
        finite("generator", generator.iter())?;
        let ma = self.metric * generator;
        let skew = (ma + ma.transpose()).amax() / ma.amax().max(f64::MIN_POSITIVE);
        if skew > 1e-12 {
            return Err(Error::Constraint {
                field: "generator",
                constraint: "ηA skew (generator of ambient isometries)",
                defect: skew,
                tolerance: 1e-12,
            });
        }
        Ok(self.charge(y, &ma))
    }

    fn charge(&self, y: &BodyState<B, C, N, E>, ma: &SMatrix<f64, E, E>) -> f64 {
        let g = &y.0 .0;
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let u = y.1 .0 .0;
        let w = q.transpose() * ma * q;
        let orbital = self.mass * (q * u).dot(&(ma * x));
        orbital + 0.5 * trace_of_product(&self.spin(y), &w)
    }

    /// `p_φ`: the Noether charge of the rotations in the plane of the ambient
    /// axes 0 and 1 (`A = E₁₀ − E₀₁`) — the rotations about the symmetry
    /// (z) axis of S², H² and T² embedded in ℝ³ / ℝ^{2,1}; on S³ ⊂ ℝ⁴ the
    /// rotations of the (x₀, x₁) plane. Conserved when `V` is invariant under
    /// them. On S²: `p_φ = m (x × ẋ)_z + s·cos ϑ` (`s = S¹²`). See
    /// [`Self::noether_charge`].
    pub fn p_phi(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let mut a = SMatrix::<f64, E, E>::zeros();
        if E >= 2 {
            a[(1, 0)] = 1.0;
            a[(0, 1)] = -1.0;
        }
        self.charge(y, &(self.metric * a))
    }

    // -- deformation ------------------------------------------------------------------

    /// The Green deformation tensor `G_AB = ⟨e_A, e_B⟩ = (ρᵀρ)_AB`.
    pub fn green_tensor(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let rho = self.rho(y);
        rho.transpose() * rho
    }
    /// `det ρ` (> 0 on the state space; the volume ratio of the body frame).
    pub fn det_rho(&self, y: &BodyState<B, C, N, E>) -> f64 {
        det(&self.rho(y))
    }
    /// The principal stretches: singular values of `ρ`, descending (the
    /// paper's `λ, μ` of `φ = L(α) D(λ, μ) R(β)⁻¹` for `N = 2`).
    pub fn stretches(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, N> {
        singular_values(&self.rho(y))
    }
    /// `|det ρ − 1|`: the incompressibility defect.
    pub fn unimodularity_defect(&self, y: &BodyState<B, C, N, E>) -> f64 {
        (self.det_rho(y) - 1.0).abs()
    }
    /// `max|ρᵀρ/λ² − I|` with `λ = (det ρ)^{1/N}`: the conformality (Weyl)
    /// defect; `+∞` unless `det ρ > 0`.
    pub fn conformality_defect(&self, y: &BodyState<B, C, N, E>) -> f64 {
        conformality_defect(&self.rho(y))
    }
    /// The fibre group's constraint defect (0 for GL⁺ with `det > 0`,
    /// `|det − 1|` for SL, the rotation's orthogonality defect for CO⁺).
    pub fn fibre_defect(&self, y: &BodyState<B, C, N, E>) -> f64 {
        y.0 .1.constraint_defect()
    }
    /// `‖Ω̂‖ = ‖ρ⁻¹ρ̇‖` (Frobenius): the inverse time scale of the internal
    /// motion. A step `h` with `h‖Ω̂‖ ≳ 1` cannot resolve it; near a collapse
    /// `‖Ω̂‖` grows like `1/(t* − t)`, so an integrator that keeps `h‖Ω̂‖` small
    /// approaches `t*` geometrically and ends at the typed collapse error of
    /// [`Self::check_state`], whereas a fixed step across `t*` lands on a
    /// finite state that no state check can tell from a valid one.
    pub fn deformation_rate(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let kin = self.kinematics(y);
        match inverse(&kin.rho) {
            Some(inv) => (inv * kin.rho_dot).norm(),
            None => f64::INFINITY,
        }
    }
    /// `max(σ_max(ρ), 1)/σ_min(ρ)`: the collapse measure checked against
    /// [`COLLAPSE_TOLERANCE`] (`+∞` for a singular or non-finite `ρ`).
    pub fn collapse_ratio(&self, y: &BodyState<B, C, N, E>) -> f64 {
        collapse_ratio(&self.rho(y))
    }
}

/// Singular values of `m`, descending (via the SVD; NaN for non-finite `m`).
fn singular_values<const N: usize>(m: &Mat<N>) -> SVector<f64, N> {
    if !m.iter().all(|x| x.is_finite()) {
        return SVector::from_element(f64::NAN);
    }
    let sv = DMatrix::from_column_slice(N, N, m.as_slice()).singular_values();
    let mut v: Vec<f64> = sv.iter().copied().collect();
    v.sort_by(|a, b| b.total_cmp(a));
    SVector::from_column_slice(&v)
}

/// `max(σ_max, 1)/σ_min` (`+∞` if singular or not finite).
pub(crate) fn collapse_ratio<const N: usize>(rho: &Mat<N>) -> f64 {
    let s = singular_values(rho);
    let (smax, smin) = (s[0], s[N - 1]);
    if !(smin > 0.0 && smax.is_finite()) {
        f64::INFINITY
    } else {
        smax.max(1.0) / smin
    }
}

/// `max|ρᵀρ/λ² − I|`, `λ = det(ρ)^{1/N}`.
pub(crate) fn conformality_defect<const N: usize>(rho: &Mat<N>) -> f64 {
    let d = det(rho);
    if !(d > 0.0 && d.is_finite()) {
        return f64::INFINITY;
    }
    let l2 = d.powf(2.0 / N as f64);
    (rho.transpose() * rho / l2 - Mat::<N>::identity()).amax()
}

/// `det ρ > 0` ([`Error::InvalidParameter`], field `"det(rho)"`) and not
/// collapsed ([`Error::Constraint`], field `"rho"`).
pub(crate) fn check_regular<const N: usize>(rho: &Mat<N>) -> Result<()> {
    let d = det(rho);
    if d.is_nan() || d <= 0.0 {
        return Err(Error::InvalidParameter {
            field: "det(rho)",
            value: d,
            allowed: "> 0 (positively oriented body frame)",
        });
    }
    let c = collapse_ratio(rho);
    if c.is_nan() || c > COLLAPSE_TOLERANCE {
        return Err(Error::Constraint {
            field: "rho",
            constraint: "body not collapsed: max(σ_max(ρ), 1)/σ_min(ρ) ≤ 1e12",
            defect: c,
            tolerance: COLLAPSE_TOLERANCE,
        });
    }
    Ok(())
}

/// The smallest `t > 0` with `det(I + tΩ̂) = 0`: `−1/λ` over the real negative
/// eigenvalues `λ` of `Ω̂` (an eigenvalue counts as real when
/// `|Im λ| ≤ 1e-10 |λ|`).
pub(crate) fn linear_collapse_time<const N: usize>(omega: &Mat<N>) -> Option<f64> {
    if !omega.iter().all(|x| x.is_finite()) {
        return None;
    }
    let ev = DMatrix::from_column_slice(N, N, omega.as_slice()).complex_eigenvalues();
    ev.iter()
        .filter(|z| z.re < 0.0 && z.im.abs() <= 1e-10 * z.norm())
        .map(|z| -1.0 / z.re)
        .min_by(|a, b| a.total_cmp(b))
}

impl<B, V, const N: usize, const E: usize> AffineBodyModel<B, V, Unconstrained, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
{
    /// In force-free internal motion (`∂V/∂ρ = 0`) `ρ(t) = ρ + tρ̇` and the
    /// body collapses (`det ρ(t) = 0`) after the time `t* = −1/λ`, `λ` the
    /// most negative real eigenvalue of `Ω̂ = ρ⁻¹ρ̇`; `None` if it never does.
    pub fn free_collapse_time(&self, y: &BodyState<B, Unconstrained, N, E>) -> Option<f64> {
        let kin = self.kinematics(y);
        linear_collapse_time(&kin.xi)
    }
}

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    /// The spin scalar `p_α = S¹²` of a two-dimensional body (the paper's
    /// momentum conjugate to the angle `α` of `φ = L(α)DR(β)⁻¹`, §5; SPEC §7).
    /// For `N ≥ 3` the `(1, 2)` component of the spin; 0 for `N = 1`.
    pub fn p_alpha(&self, y: &BodyState<B, C, N, E>) -> f64 {
        if N >= 2 {
            self.spin(y)[(0, 1)]
        } else {
            0.0
        }
    }
    /// The vorticity scalar `p_β = −(Σ̂ − Σ̂ᵀ)₁₂` of a two-dimensional body
    /// (conjugate to `β` of `φ = L(α)DR(β)⁻¹`, §5; SPEC §7). For `N ≥ 3`
    /// minus the `(1, 2)` component of the vorticity; 0 for `N = 1`.
    pub fn p_beta(&self, y: &BodyState<B, C, N, E>) -> f64 {
        if N >= 2 {
            -self.vorticity(y)[(0, 1)]
        } else {
            0.0
        }
    }
}

impl<B, V, C, const N: usize, const E: usize> System for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    type State = BodyState<B, C, N, E>;

    /// `(ġ, ρ̇, u̇, d P(K)/dt)` left-trivialised:
    /// `(lift(u), Ω̂, (−K S u + F̂)/m, P(sym(ρ̇Jρ̇ᵀ) − ρ(∂V/∂ρ)ᵀ))`.
    #[inline]
    fn vector_field(&self, _t: f64, y: &Self::State) -> BodyVelocity<B, C, N, E> {
        let g = &y.0 .0;
        let u = y.1 .0 .0;
        let k = self.constraint.momentum_matrix(&y.1 .1);
        let kin = self.constraint.kinematics(&y.0 .1, &k, &self.inertia);
        let (f_hat, v_rho) = self.forces(g, &kin.rho);
        let curvature = self.bundle.curvature_at(g);
        let spin = k - k.transpose();
        let u_dot = (f_hat - spin * u * curvature) * self.inv_mass;
        let a = kin.rho_dot * self.inertia.j * kin.rho_dot.transpose();
        let k_dot = (a + a.transpose()) * 0.5 - kin.rho * v_rho.transpose();
        ProductAlgebra(
            ProductAlgebra(self.bundle.horizontal_lift(g, &u), kin.xi),
            ProductAlgebra(u_dot, self.constraint.project(&k_dot)),
        )
    }

    /// `(m/2)|u|² + ½tr(ρ̇Jρ̇ᵀ) + V(x, qρ)`.
    fn energy(&self, y: &Self::State) -> f64 {
        self.translational_energy(y) + self.internal_energy(y) + self.potential_energy(y)
    }

    /// The largest of the bundle defect, the fibre group's defect (≥ 1 for
    /// `det ρ ≤ 0` on GL⁺), the momentum's distance from its subspace; `+∞`
    /// for non-finite entries.
    fn defect(&self, y: &Self::State) -> f64 {
        let parts = [
            self.bundle.bundle_defect(&y.0 .0),
            y.0 .1.constraint_defect(),
            y.1 .1.constraint_defect(),
            if y.1 .0 .0.iter().all(|v| v.is_finite()) { 0.0 } else { f64::INFINITY },
        ];
        if parts.iter().any(|d| d.is_nan()) {
            f64::INFINITY
        } else {
            parts.iter().fold(0.0, |a, &b| a.max(b))
        }
    }
}

/// Affine bodies have no exact free flow on a curved manifold: the
/// splitting methods refuse them.
impl<B, V, C, const N: usize, const E: usize> crate::dynamics::SplitDispatch for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    type Split = crate::dynamics::NoSplit<BodyState<B, C, N, E>>;
    fn as_splittable(&self) -> Option<&Self::Split> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xorshift(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn check_inverse<const N: usize>(rng: &mut impl FnMut() -> f64) {
        for _ in 0..200 {
            let m = Mat::<N>::identity() + Mat::<N>::from_fn(|_, _| rng()) * (0.6 / N as f64);
            let inv = inverse(&m).expect("invertible");
            let err = (m * inv - Mat::<N>::identity()).amax();
            assert!(err < 1e-14, "N = {N}: |m m⁻¹ − I| = {err:e}");
        }
        let mut singular = Mat::<N>::identity();
        singular[(0, 0)] = 0.0;
        for i in 0..N {
            singular[(0, i)] = 0.0;
        }
        assert!(inverse(&singular).is_none());
        assert!(inverse(&Mat::<N>::from_element(f64::NAN)).is_none());
    }

    /// The closed-form inverses (n ≤ 3) and the LU fallback (n = 4).
    #[test]
    fn inverse_closed_forms() {
        let mut rng = xorshift(0x1234_5678_9abc_def1);
        check_inverse::<1>(&mut rng);
        check_inverse::<2>(&mut rng);
        check_inverse::<3>(&mut rng);
        check_inverse::<4>(&mut rng);
    }

    /// `tr(AB)` and the inverse of the rotational inertia operator
    /// `ω ↦ Jω + ωJ` on skew matrices.
    #[test]
    fn trace_of_product_and_rotational_solve() {
        let mut rng = xorshift(0x0bad_cafe_f00d_1234);
        for _ in 0..100 {
            let a = Mat::<3>::from_fn(|_, _| rng());
            let b = Mat::<3>::from_fn(|_, _| rng());
            assert!((trace_of_product(&a, &b) - (a * b).trace()).abs() < 1e-15);
            let l = Mat::<3>::from_fn(|_, _| rng());
            let inertia = Inertia::new(&(Mat::<3>::identity() * 0.1 + l * l.transpose() * 0.2)).unwrap();
            let c = Mat::<3>::from_fn(|_, _| rng());
            let c = c - c.transpose();
            let w = inertia.solve_rotational(&c);
            let j = inertia.matrix();
            assert!((j * w + w * j - c).amax() < 1e-13, "Jω + ωJ ≠ c");
            assert!((w + w.transpose()).amax() < 1e-14, "ω not skew");
            assert!((inertia.inverse() * j - Mat::<3>::identity()).amax() < 1e-13);
        }
    }

    /// `Inertia::new` rejects what `check_inertia` rejects, with the field `"J"`.
    #[test]
    fn inertia_validation() {
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, -1.0)), Err(Error::Constraint { field: "J", .. })));
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.5, 0.0, 1.0)), Err(Error::Constraint { field: "J", .. })));
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, f64::NAN)), Err(Error::NotFinite { field: "J" })));
    }
}
