//! The family `α̂ cos²(r/R) + β̂ cos(r/R)` compatible with the separation of
//! the S² gyroscope (paper §5.1, after (a109)), and its H² analogue.

use nalgebra::{SMatrix, SVector};

use super::centre::{Axis, Centre};
use super::{Gradient, Potential, Scalar};
use crate::{Error, Result};

/// `Ok(value)` if `value` is finite, else [`Error::InvalidParameter`].
pub(crate) fn finite_param(field: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter { field, value, allowed: "finite" })
    }
}

/// `V = α̂ cos²(r/R) + β̂ cos(r/R)` on S² (and S³), `V = α̂ cosh²(r/R) +
/// β̂ cosh(r/R)` on H² (position only), `r` the geodesic distance from the
/// centre (default: the pole of the paper's chart). `α̂ = 0` gives the
/// potential `β̂ cos(r/R)` of a uniform field (SPEC §5's test problem).
///
/// The paper (§5.1, text after (a109)) derives it as the family for which
/// the Hamilton–Jacobi equation of the S² gyroscope with cyclic `φ, ψ` stays
/// separable in `(r, φ, ψ)`. Its further claims — elementary integrals and
/// total degeneracy — are wrong (SPEC §8, lines 3725–3746): the radial
/// integral is elliptic and the degeneracy is lost (rotation numbers vary
/// with the energy).
///
/// **Ambient form.** `cos(r/R) = ⟨x, c⟩/R²` (S², S³) and `cosh(r/R) =
/// −⟨x, c⟩_η/R²` (H²): linear in `x`, so `V` is a quadratic polynomial in `x`,
/// smooth everywhere, with no singular set.
///
/// **Centre type.** `C` is a [`Centre`] (any point; the default) or a
/// [`Pole`](super::Pole) (the chart's pole fixed at compile time: the same
/// values bit for bit, and cheaper inside an integrator step — see
/// [`Axis`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CosineFamily<const E: usize, C: Axis<E> = Centre<E>> {
    alpha: f64,
    beta: f64,
    centre: C,
    /// `2α̂/R²` and `β̂/R`: `∂V/∂x = (2α̂/R² · y₀ + β̂/R) M₀` with one
    /// multiplication and one addition per evaluation.
    grad_quad: f64,
    grad_lin: f64,
}

impl<const E: usize, C: Axis<E>> CosineFamily<E, C> {
    /// `α̂ cos²(r/R) + β̂ cos(r/R)` about `centre`. Fails with
    /// [`Error::InvalidParameter`] (field `"alpha_hat"` or `"beta_hat"`)
    /// unless both are finite (any sign).
    pub fn new(alpha_hat: f64, beta_hat: f64, centre: C) -> Result<Self> {
        let (alpha, beta) = (finite_param("alpha_hat", alpha_hat)?, finite_param("beta_hat", beta_hat)?);
        let k = centre.centre().inv_radius();
        Ok(CosineFamily { alpha, beta, centre, grad_quad: 2.0 * alpha * k * k, grad_lin: beta * k })
    }

    /// `α̂`.
    pub fn alpha_hat(&self) -> f64 {
        self.alpha
    }

    /// `β̂`.
    pub fn beta_hat(&self) -> f64 {
        self.beta
    }

    /// The centre.
    pub fn centre(&self) -> &Centre<E> {
        self.centre.centre()
    }
}

impl<const N: usize, const E: usize, C: Axis<E>> Potential<N, E> for CosineFamily<E, C> {
    fn uses_frame(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _metric: &SMatrix<f64, E, E>) -> D {
        let c = self.centre.axial(x) * self.centre.centre().inv_radius();
        c * (c * self.alpha + self.beta)
    }

    /// Closed form: `∂V/∂x = (2α̂ cos + β̂)/R · M₀ = (2α̂ Z/R² + β̂/R) M₀`,
    /// `M₀` the axial row, `Z = M₀·x`.
    ///
    /// For `α̂ = 0` (a uniform field, SPEC §5's problem) the gradient
    /// `β̂/R · M₀` does not depend on `x`, and it is computed without reading
    /// `x`: inside an integrator step the position of a stage is then not
    /// computed where only the gradient needs it (the value still reads
    /// `Z`). The same numbers as `(0·Z + β̂/R) M₀` for every finite `x`.
    #[inline(always)]
    fn gradient(&self, x: &SVector<f64, E>, _e: &SMatrix<f64, E, N>, _m: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let z = self.centre.axial_f64(x);
        let c = z * self.centre.centre().inv_radius();
        let value = c * (c * self.alpha + self.beta);
        let dx = if self.grad_quad != 0.0 {
            self.centre.scaled_row(self.grad_quad * z + self.grad_lin)
        } else {
            self.centre.scaled_row(self.grad_lin)
        };
        Gradient { value, dx, de: SMatrix::zeros() }
    }
}
