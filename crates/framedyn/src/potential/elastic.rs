//! Deformation invariants of a two-dimensional affine body and the elastic
//! potential (a131).
//!
//! The body frame `e = (e₁, e₂)` of an affine body is `e = q·φ` with `q` an
//! orthonormal frame of `T_xM` and `φ ∈ GL⁺(2)`. Its deformation invariants
//! `λ ≥ μ > 0` are the singular values of `φ` (in the paper's two-polar
//! decomposition `φ = L(α) D(λ, μ) R(β)⁻¹`). They are read off the Green
//! tensor `G = eᵀ g e = φᵀφ` ([`green_tensor`]) without an SVD:
//! `λ² + μ² = tr G`, `λ²μ² = det G`, and `λ² − μ² = Δ` with the
//! cancellation-free `Δ² = (tr G)² − 4 det G = (G₁₁ − G₂₂)² + 4G₁₂²`.

use nalgebra::{Matrix2, SMatrix, SVector};

use super::centre::sqrt0;
use super::{green_tensor, Gradient, Potential, Scalar};
use crate::error::positive;
use crate::Result;

/// `(tr G, det G, Δ²)` of a symmetric 2×2 Green tensor, with
/// `Δ² = (G₁₁ − G₂₂)² + 4G₁₂² = (λ² − μ²)²`.
#[inline]
pub(crate) fn invariants2<D: Scalar>(g: &SMatrix<D, 2, 2>) -> (D, D, D) {
    let tr = g[(0, 0)] + g[(1, 1)];
    let det = g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)];
    let d = g[(0, 0)] - g[(1, 1)];
    let off = g[(0, 1)] * 2.0;
    (tr, det, d * d + off * off)
}

/// The deformation invariants `(λ, μ)`, `λ ≥ μ ≥ 0`, of the body frame `e`:
/// the singular values of `φ` in `e = q·φ` (`q` orthonormal), from the Green
/// tensor: `λ² = (tr G + Δ)/2`, `μ = √(det G)/λ` (no cancellation for
/// `μ ≪ λ`). They are not differentiable where `λ = μ` (derivative parts
/// there are those of `λ = μ = √(tr G/2)`); the potentials of this module
/// use only their smooth symmetric functions.
pub fn deformation_invariants<D: Scalar, const E: usize>(e: &SMatrix<D, E, 2>, metric: &SMatrix<f64, E, E>) -> (D, D) {
    let (tr, det, delta2) = invariants2(&green_tensor(e, metric));
    let lambda = ((tr + sqrt0(delta2)) * 0.5).sqrt();
    (lambda, det.sqrt() / lambda)
}

/// The paper's polar coordinates `(ϱ, ε)` in the space of deformation
/// invariants ((a125); §5.1): `x = (λ − μ)/√2 = ϱ sin ε`,
/// `y = (λ + μ)/√2 = ϱ cos ε`, so that
/// - `ϱ² = λ² + μ² = tr G`,
/// - `cos 2ε = 2λμ/ϱ² = 2√(det G)/tr G`, `sin 2ε = (λ² − μ²)/ϱ² = Δ/tr G`,
///
/// computed as `ϱ = √(tr G)`, `ε = ½·atan2(Δ, 2√det G) ∈ [0, π/4)`
/// (`ε → π/4` is the collapse `μ → 0`). The Green tensor's determinant is
/// `det G = ϱ⁴ cos²(2ε)/4`; the determinant `∝ ϱ⁶` of SPEC §8 is that of
/// the paper's configuration-space metric `[G_ij]` (kinetic energy), a
/// different object.
///
/// **Gauge.** The exchange `λ ↔ μ` (with `α, β → α − π/2, β − π/2`) is the
/// same configuration; it maps `ε → −ε`. This function returns the
/// representative `ε ≥ 0`; `ε` is not differentiable at `λ = μ` (`ε = 0`),
/// where its derivative parts are set to zero — the derivative there of
/// every smooth even function of `ε`.
pub fn polar_invariants<D: Scalar, const E: usize>(e: &SMatrix<D, E, 2>, metric: &SMatrix<f64, E, E>) -> (D, D) {
    let (tr, det, delta2) = invariants2(&green_tensor(e, metric));
    (tr.sqrt(), sqrt0(delta2).atan2(det.sqrt() * 2.0) * 0.5)
}

/// The two-dimensional elastic potential of the paper, (a131):
///
/// `V = κ (1/(λμ) + (λ² + μ²)/2) = 2κ/(ϱ² cos 2ε) + κϱ²/2`,
///
/// `λ, μ` the deformation invariants ([`deformation_invariants`]),
/// `(ϱ, ε)` their polar coordinates ([`polar_invariants`]); through the
/// Green tensor `V = κ (1/√(det G) + tr G/2)` (frame only, any `E`: S², H²,
/// T²). The first term prevents the collapse of the body to a segment or a
/// point, the second its unlimited expansion.
///
/// **Natural state.** `V ≥ 2κ` with equality exactly at `λ = μ = 1`
/// (`1/(λμ) + λμ ≥ 2` and `λ² + μ² ≥ 2λμ`): the undeformed body, `φ`
/// orthogonal. There the Hessian in `(λ, μ)` is `κ[[3, 1], [1, 3]]`
/// (eigenvalues `2κ`, `4κ`); in the four entries of `φ` it has eigenvalues
/// `0` (rotation: a gyroscopic zero mode), `2κ` (shear), `2κ`
/// (`λ − μ`), `4κ` (dilatation).
///
/// **Singular set.** Degenerate frames `det G = 0`: the value is `+∞` and
/// every gradient component NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    kappa: f64,
}

impl Elastic {
    /// The elastic potential of stiffness `kappa`. Fails with
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (field
    /// `"kappa"`) unless `kappa` is finite and > 0.
    pub fn new(kappa: f64) -> Result<Self> {
        Ok(Elastic { kappa: positive("kappa", kappa)? })
    }

    /// The stiffness `κ`.
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
}

impl<const E: usize> Potential<2, E> for Elastic {
    fn uses_frame(&self) -> bool {
        true
    }

    fn value<D: Scalar>(&self, _x: &SVector<D, E>, e: &SMatrix<D, E, 2>, metric: &SMatrix<f64, E, E>) -> D {
        let (tr, det, _) = invariants2(&green_tensor(e, metric));
        (det.sqrt().recip() + tr * 0.5) * self.kappa
    }

    /// Closed form: `∂V/∂e = κ g e (I − adj(G)/(det G)^{3/2})` (in `φ`:
    /// `κ(φ − φ^{−T}/det φ)`).
    fn gradient(&self, _x: &SVector<f64, E>, e: &SMatrix<f64, E, 2>, metric: &SMatrix<f64, E, E>) -> Gradient<2, E> {
        let g = green_tensor(e, metric);
        let (tr, det, _) = invariants2(&g);
        let s = det.sqrt();
        let value = (s.recip() + tr * 0.5) * self.kappa;
        let de = if value.is_finite() {
            let f = 1.0 / (det * s);
            let m = Matrix2::new(1.0 - g[(1, 1)] * f, g[(0, 1)] * f, g[(1, 0)] * f, 1.0 - g[(0, 0)] * f);
            metric * e * (m * self.kappa)
        } else {
            SMatrix::repeat(f64::NAN)
        };
        Gradient { value, dx: SVector::zeros(), de }
    }
}
