//! Potentials of a three-dimensional affine body that depend on its
//! deformation only through the principal invariants of the Green tensor
//! `G = eᵀ g e` ([`green_tensor`]): hyperelastic energies on S³ (§6) or any
//! three-dimensional manifold.
//!
//! With `e = q·φ` (`q` orthonormal) `G = φᵀφ` is the right Cauchy–Green
//! tensor `C` of continuum mechanics, and its principal invariants are
//! `I₁ = tr G = Σλᵢ²`, `I₂ = ½((tr G)² − tr G²) = Σ_{i<j} λᵢ²λⱼ²`,
//! `I₃ = det G = (λ₁λ₂λ₃)²` (`λᵢ` the singular values of `φ`). A function of
//! them is invariant under rotations of the body in space (`φ → Uφ`, `G`
//! fixed) and is isotropic (`φ → φU`).

use nalgebra::{Matrix3, SMatrix, SVector};
use num_dual::gradient;
use std::fmt::Debug;

use super::{green_tensor, Gradient, Potential, Scalar};
use crate::error::positive;
use crate::{Error, Result};

/// The principal invariants `(I₁, I₂, I₃)` of a 3×3 matrix `G`:
/// trace, sum of the principal 2×2 minors, determinant.
pub fn principal_invariants<D: Scalar>(g: &SMatrix<D, 3, 3>) -> (D, D, D) {
    let i1 = g[(0, 0)] + g[(1, 1)] + g[(2, 2)];
    let m01 = g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)];
    let m02 = g[(0, 0)] * g[(2, 2)] - g[(0, 2)] * g[(2, 0)];
    let m12 = g[(1, 1)] * g[(2, 2)] - g[(1, 2)] * g[(2, 1)];
    let i2 = m01 + m02 + m12;
    let i3 = g[(0, 0)] * m12 - g[(0, 1)] * (g[(1, 0)] * g[(2, 2)] - g[(1, 2)] * g[(2, 0)])
        + g[(0, 2)] * (g[(1, 0)] * g[(2, 1)] - g[(1, 1)] * g[(2, 0)]);
    (i1, i2, i3)
}

/// An energy `W(I₁, I₂, I₃)` of the principal invariants of the Green
/// tensor, written once for every [`Scalar`]. See [`InvariantPotential`].
pub trait InvariantFunction: Debug + Send + Sync {
    /// `W(I₁, I₂, I₃)`.
    fn energy<D: Scalar>(&self, i1: D, i2: D, i3: D) -> D;
}

/// `V(x, e) = W(I₁, I₂, I₃)` for a three-dimensional body (`N = 3`, any
/// ambient dimension `E`; on S³ `E = 4`), `W` a user-supplied or built-in
/// [`InvariantFunction`] of the principal invariants of `G = eᵀ g e`
/// ([`principal_invariants`]). Frame only.
///
/// The gradient is closed form by the chain rule,
/// `∂V/∂e = 2 g e (W₁ I + W₂ (I₁ I − G) + W₃ adj G)` with `W_k = ∂W/∂I_k`
/// from one forward-mode evaluation of `W` with three-component dual
/// numbers (about four times cheaper than differentiating `V` through `e`).
/// Where the value is not finite every gradient component is NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InvariantPotential<F> {
    f: F,
}

impl<F: InvariantFunction> InvariantPotential<F> {
    /// `V = W(I₁, I₂, I₃)` with `W = f`.
    pub fn new(f: F) -> Self {
        InvariantPotential { f }
    }

    /// The energy function.
    pub fn function(&self) -> &F {
        &self.f
    }
}

impl<F: InvariantFunction, const E: usize> Potential<3, E> for InvariantPotential<F> {
    fn uses_frame(&self) -> bool {
        true
    }

    fn value<D: Scalar>(&self, _x: &SVector<D, E>, e: &SMatrix<D, E, 3>, metric: &SMatrix<f64, E, E>) -> D {
        let (i1, i2, i3) = principal_invariants(&green_tensor(e, metric));
        self.f.energy(i1, i2, i3)
    }

    fn gradient(&self, _x: &SVector<f64, E>, e: &SMatrix<f64, E, 3>, metric: &SMatrix<f64, E, E>) -> Gradient<3, E> {
        let g = green_tensor(e, metric);
        let (i1, i2, i3) = principal_invariants(&g);
        let (value, w) = gradient(|i: SVector<_, 3>| self.f.energy(i[0], i[1], i[2]), &SVector::from([i1, i2, i3]));
        let de = if value.is_finite() {
            let adj = Matrix3::new(
                g[(1, 1)] * g[(2, 2)] - g[(1, 2)] * g[(2, 1)],
                g[(0, 2)] * g[(2, 1)] - g[(0, 1)] * g[(2, 2)],
                g[(0, 1)] * g[(1, 2)] - g[(0, 2)] * g[(1, 1)],
                g[(1, 2)] * g[(2, 0)] - g[(1, 0)] * g[(2, 2)],
                g[(0, 0)] * g[(2, 2)] - g[(0, 2)] * g[(2, 0)],
                g[(0, 2)] * g[(1, 0)] - g[(0, 0)] * g[(1, 2)],
                g[(1, 0)] * g[(2, 1)] - g[(1, 1)] * g[(2, 0)],
                g[(0, 1)] * g[(2, 0)] - g[(0, 0)] * g[(2, 1)],
                g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)],
            );
            let m = Matrix3::identity() * (w[0] + w[1] * i1) - g * w[1] + adj * w[2];
            metric * e * (m * 2.0)
        } else {
            SMatrix::repeat(f64::NAN)
        };
        Gradient { value, dx: SVector::zeros(), de }
    }
}

/// The compressible neo-Hookean energy (J. Bonet, R. D. Wood, *Nonlinear
/// Continuum Mechanics for Finite Element Analysis*, 2nd ed., Cambridge
/// University Press 2008, §6.4.3):
///
/// `W = (μ/2)(I₁ − 3) − μ ln J + (λ/2)(ln J)²`, `J = √I₃ = det φ`,
///
/// with Lamé constants `λ ≥ 0`, `μ > 0` (for `λ < 0` it is unbounded below
/// as `J → 0`). Minimum `W = 0` exactly at `G = I` (the undeformed body); its
/// linearisation there is isotropic linear elasticity,
/// `W ≈ (λ/2)(tr ε)² + μ tr ε²`, `ε = sym(φ − I)`, so in the nine entries of
/// `φ` the Hessian has eigenvalues `0` (×3, rotations), `2μ` (×5, shears)
/// and `3λ + 2μ` (dilatation). `W = +∞` at collapse (`I₃ = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    lambda: f64,
    mu: f64,
}

impl NeoHookean {
    /// Lamé constants `lambda` (finite, ≥ 0) and `mu` (finite, > 0); errors
    /// [`Error::InvalidParameter`] with field `"lambda"` or `"mu"`.
    pub fn new(lambda: f64, mu: f64) -> Result<Self> {
        let mu = positive("mu", mu)?;
        if !(lambda.is_finite() && lambda >= 0.0) {
            return Err(Error::InvalidParameter { field: "lambda", value: lambda, allowed: "finite and ≥ 0" });
        }
        Ok(NeoHookean { lambda, mu })
    }

    /// `λ`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }
}

impl InvariantFunction for NeoHookean {
    fn energy<D: Scalar>(&self, i1: D, _i2: D, i3: D) -> D {
        let ln_j = i3.ln() * 0.5;
        (i1 - 3.0) * (0.5 * self.mu) - ln_j * self.mu + ln_j * ln_j * (0.5 * self.lambda)
    }
}

/// The St Venant–Kirchhoff energy (P. G. Ciarlet, *Mathematical
/// Elasticity* vol. I, North-Holland 1988, ch. 3):
///
/// `W = (λ/2)(tr E)² + μ tr E²`, `E = (G − I)/2` (Green–St Venant strain),
///
/// in invariants `tr E = (I₁ − 3)/2`, `tr E² = (I₁² − 2I₂ − 2I₁ + 3)/4`.
/// Lamé constants `μ > 0`, `3λ + 2μ > 0` (then `W ≥ 0`, with `W = 0` exactly
/// at `G = I`). Same linearisation at `G = I` as [`NeoHookean`]. It does
/// not prevent collapse (`W` is finite at `det G = 0`) and is meant for
/// moderate strains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StVenantKirchhoff {
    lambda: f64,
    mu: f64,
}

impl StVenantKirchhoff {
    /// Lamé constants `mu` (finite, > 0) and `lambda` (finite, > −2μ/3);
    /// errors [`Error::InvalidParameter`] with field `"lambda"` or `"mu"`.
    pub fn new(lambda: f64, mu: f64) -> Result<Self> {
        let mu = positive("mu", mu)?;
        if !(lambda.is_finite() && 3.0 * lambda + 2.0 * mu > 0.0) {
            return Err(Error::InvalidParameter {
                field: "lambda",
                value: lambda,
                allowed: "finite and > −2μ/3 (positive bulk modulus)",
            });
        }
        Ok(StVenantKirchhoff { lambda, mu })
    }

    /// `λ`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }
}

impl InvariantFunction for StVenantKirchhoff {
    fn energy<D: Scalar>(&self, i1: D, i2: D, _i3: D) -> D {
        let tr_e = (i1 - 3.0) * 0.5;
        let tr_e2 = (i1 * i1 - i2 * 2.0 - i1 * 2.0 + 3.0) * 0.25;
        tr_e * tr_e * (0.5 * self.lambda) + tr_e2 * self.mu
    }
}
