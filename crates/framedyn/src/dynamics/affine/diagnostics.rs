//! Deformation and collapse diagnostics of an affine body: Green tensor,
//! stretches, the constraint defects, the deformation rate and the collapse
//! measure with its tolerance (see "Collapse" in the
//! [module documentation](super)).

use nalgebra::{DMatrix, SVector};

use super::{inverse, AffineBodyModel, BodyState, InternalConstraint, Mat, Unconstrained};
use crate::bundle::FrameBundle;
use crate::lie::matrix::det;
use crate::lie::LieGroup;
use crate::potential::Potential;
use crate::{Error, Result};

/// Largest accepted `max(σ_max(ρ), 1)/σ_min(ρ)`: beyond it the body counts as
/// collapsed (flattened, or shrunk below 1e-12 of an orthonormal frame).
pub const COLLAPSE_TOLERANCE: f64 = 1e12;

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
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
