//! The momenta of an affine body: hypermomentum, spin, co-moving
//! hypermomentum and vorticity, the Noether charges of ambient isometries and
//! the paper's canonical momenta `p_φ`, `p_α`, `p_β` (see "Conserved
//! quantities and diagnostics" in the [module documentation](super)).

use nalgebra::SMatrix;

use super::{trace_of_product, AffineBodyModel, BodyState, InternalConstraint, Mat};
use crate::bundle::FrameBundle;
use crate::error::finite;
use crate::potential::Potential;
use crate::{Error, Result};

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
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
