//! Potentials built from user-supplied functions of one variable: central
//! potentials `V(r)` and the separable family `V_r(r) + V_ϱ(ϱ) + V_ε(ε)/ϱ²`
//! of affine bodies ((a128), (b128)).
//!
//! The user writes the one-dimensional functions once, generic over
//! [`Scalar`]; values use them directly, gradients combine their derivatives
//! (one forward-mode dual evaluation each, [`num_dual::first_derivative`])
//! with closed-form derivatives of `r`, `ϱ`, `ε`.
//!
//! ```
//! use framedyn::manifold::Sphere2;
//! use framedyn::potential::{Centre, Potential, Scalar, Separable, SeparableFunctions};
//! use nalgebra::{SMatrix, SVector};
//!
//! /// The elastic potential (a131) in separated form, plus a uniform field.
//! #[derive(Debug)]
//! struct MyModel { kappa: f64, field: f64, radius: f64 }
//!
//! impl SeparableFunctions for MyModel {
//!     fn v_r<D: Scalar>(&self, r: D) -> D { (r * (1.0 / self.radius)).cos() * self.field }
//!     fn v_rho<D: Scalar>(&self, rho: D) -> D { rho * rho * (0.5 * self.kappa) }
//!     fn v_eps<D: Scalar>(&self, eps: D) -> D { (eps * 2.0).cos().recip() * (2.0 * self.kappa) }
//! }
//!
//! let sphere = Sphere2::new(1.0)?;
//! let v = Separable::new(MyModel { kappa: 1.0, field: 0.5, radius: 1.0 }, Centre::sphere2(&sphere));
//! // Undeformed body (orthonormal frame) at the pole: V = 0.5 + 2κ.
//! let x = SVector::from([0.0, 0.0, 1.0]);
//! let e = SMatrix::<f64, 3, 2>::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
//! let grad = v.gradient(&x, &e, &SMatrix::identity());
//! assert!((grad.value - 2.5).abs() < 1e-15);
//! assert!(grad.de.norm() < 1e-15); // the natural state is an equilibrium
//! # Ok::<(), framedyn::Error>(())
//! ```

use nalgebra::{Matrix2, SMatrix, SVector};
use num_dual::{first_derivative, Dual64};
use std::fmt::Debug;

use super::centre::{sqrt0, Centre};
use super::elastic::invariants2;
use super::{green_tensor, Gradient, Potential, Scalar};
use crate::error::positive;
use crate::{Error, Result};

/// A function `V(r)` of one variable, written once for every [`Scalar`].
pub trait RadialFunction: Debug + Send + Sync {
    /// `V(r)`.
    fn v<D: Scalar>(&self, r: D) -> D;
}

/// A central potential `V(r)` (position only), `r` the geodesic distance
/// from a [`Centre`] on S², H² or S³ ([`Centre::distance`]), for any
/// user-supplied [`RadialFunction`].
///
/// `r` is not differentiable at the centre; there the gradient is
/// `V'(0)·0 = 0` (correct for every `V` smooth in `r²`, i.e. with `V'(0) = 0`;
/// otherwise `V` has a conical point there). Non-finite values of `V` are
/// passed through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Central<F, const E: usize> {
    f: F,
    centre: Centre<E>,
}

impl<F: RadialFunction, const E: usize> Central<F, E> {
    /// `V(r) = f(r)` about `centre`.
    pub fn new(f: F, centre: Centre<E>) -> Self {
        Central { f, centre }
    }

    /// The function.
    pub fn function(&self) -> &F {
        &self.f
    }

    /// The centre.
    pub fn centre(&self) -> &Centre<E> {
        &self.centre
    }
}

impl<F: RadialFunction, const N: usize, const E: usize> Potential<N, E> for Central<F, E> {
    fn uses_frame(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _metric: &SMatrix<f64, E, E>) -> D {
        self.f.v(self.centre.distance(x))
    }

    /// `V'(r)·∂r/∂x` with `V'` by one dual evaluation and `∂r/∂x` closed form.
    fn gradient(&self, x: &SVector<f64, E>, _e: &SMatrix<f64, E, N>, _m: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let (r, dr) = self.centre.distance_gradient(x);
        let (value, dv) = first_derivative(|r: Dual64| self.f.v(r), r);
        Gradient { value, dx: dr * dv, de: SMatrix::zeros() }
    }
}

/// The one-dimensional functions of a separable affine-body potential
/// `V = V_r(r) + V_ϱ(ϱ) + V_ε(ε)/ϱ²` ((b128)), written once for every
/// [`Scalar`]. See [`Separable`].
pub trait SeparableFunctions: Debug + Send + Sync {
    /// `V_r(r)`: `r` the geodesic distance from the centre (S², H²), or the
    /// angle `ϑ ∈ (−π, π]` on the torus.
    fn v_r<D: Scalar>(&self, r: D) -> D;
    /// `V_ϱ(ϱ)`, `ϱ = √(λ² + μ²) > 0`.
    fn v_rho<D: Scalar>(&self, rho: D) -> D;
    /// `V_ε(ε)`, evaluated at `ε ∈ [0, π/4)` (see [`Separable`] on the sign
    /// of `ε`).
    fn v_eps<D: Scalar>(&self, eps: D) -> D;
}

/// The paper's torus angle `ϑ` of a point of the torus T²(L, R) ⊂ ℝ³,
/// `x = ((L + R cos ϑ) cos φ, (L + R cos ϑ) sin φ, R sin ϑ)`:
/// `ϑ = atan2(z, √(x² + y²) − L) ∈ (−π, π]` (independent of `R`), smooth
/// except across the inner equator `ϑ = ±π` (the branch cut: a function
/// of `ϑ` gives a smooth potential only if it is 2π-periodic).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorusAngle {
    major: f64,
    minor: f64,
}

impl TorusAngle {
    /// The angle `ϑ` on the torus with radii `L > R > 0`. Fails with
    /// [`Error::InvalidParameter`] (field `"R"`: finite and > 0; field `"L"`:
    /// finite and > R).
    pub fn new(major: f64, minor: f64) -> Result<Self> {
        let minor = positive("R", minor)?;
        if !(major.is_finite() && major > minor) {
            return Err(Error::InvalidParameter { field: "L", value: major, allowed: "finite and > R" });
        }
        Ok(TorusAngle { major, minor })
    }

    /// `L`.
    pub fn major_radius(&self) -> f64 {
        self.major
    }

    /// `R`.
    pub fn minor_radius(&self) -> f64 {
        self.minor
    }

    /// `ϑ(x)`.
    pub fn angle<D: Scalar>(&self, x: &SVector<D, 3>) -> D {
        let w = (x[0] * x[0] + x[1] * x[1]).sqrt() - self.major;
        x[2].atan2(w)
    }

    /// `(ϑ, ∂ϑ/∂x)`.
    fn angle_gradient(&self, x: &SVector<f64, 3>) -> (f64, SVector<f64, 3>) {
        let rxy = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let w = rxy - self.major;
        let den = w * w + x[2] * x[2];
        let f = -x[2] / (den * rxy);
        (x[2].atan2(w), SVector::from([f * x[0], f * x[1], w / den]))
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Base {
    Centre(Centre<3>),
    Torus(TorusAngle),
}

/// The separable affine-body potential of the paper ((a122)–(a129), (b128);
/// §5.1 for S², §5.2 for H², §5.3 for T²):
///
/// `V = V_r(r) + V_ϱ(ϱ) + V_ε(ε)/ϱ²`,
///
/// with user-supplied [`SeparableFunctions`], `r` the geodesic distance from
/// a [`Centre`] (S², H²; the paper's `r` for the chart pole) or the torus
/// angle `ϑ` ([`TorusAngle`]), and `(ϱ, ε)` the paper's polar coordinates of
/// the deformation invariants ((a125), [`polar_invariants`](super::polar_invariants)):
/// `ϱ² = λ² + μ² = tr G`, `cos 2ε = 2λμ/ϱ²`. With the rotation angles
/// `φ, α, β` cyclic, the Hamilton–Jacobi equation separates in
/// `(r, ϱ, ε)` (paper (a129)–(c129)). Example: the elastic potential
/// (a131) is `V_ϱ = κϱ²/2`, `V_ε = 2κ/cos 2ε` (see [`Elastic`](super::Elastic)).
///
/// **Sign of `ε`.** Exchanging `λ ↔ μ` is a change of the two-polar gauge,
/// not of the configuration, and maps `ε → −ε`: a potential on the
/// configuration space must have `V_ε` even. `V_ε` is evaluated at the
/// representative `ε ≥ 0`, so any user function defines a potential; it is
/// smooth at `λ = μ` iff `V_ε` extends to a smooth even function (else it
/// has a kink there and the gradient returned at `λ = μ` exactly is the
/// symmetric one, without the `V_ε'(0)` term). Likewise `r` at the centre
/// (`V_r` should be smooth in `r²`).
///
/// **Singular set.** `ϱ = 0` and the collapse `det G = 0` (`ε = π/4`),
/// wherever the user functions are singular, and on the torus the inner
/// equator if `V_r` is not 2π-periodic. Non-finite values are passed through;
/// the gradient is then non-finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Separable<F> {
    f: F,
    base: Base,
}

impl<F: SeparableFunctions> Separable<F> {
    /// On S² or H², `r` measured from `centre`.
    pub fn new(f: F, centre: Centre<3>) -> Self {
        Separable { f, base: Base::Centre(centre) }
    }

    /// On the torus, with the angle `ϑ` as the first variable.
    pub fn torus(f: F, angle: TorusAngle) -> Self {
        Separable { f, base: Base::Torus(angle) }
    }

    /// The user functions.
    pub fn functions(&self) -> &F {
        &self.f
    }
}

impl<F: SeparableFunctions> Potential<2, 3> for Separable<F> {
    fn uses_frame(&self) -> bool {
        true
    }

    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, metric: &SMatrix<f64, 3, 3>) -> D {
        let r = match &self.base {
            Base::Centre(c) => c.distance(x),
            Base::Torus(t) => t.angle(x),
        };
        let (tr, det, delta2) = invariants2(&green_tensor(e, metric));
        let eps = sqrt0(delta2).atan2(det.sqrt() * 2.0) * 0.5;
        self.f.v_r(r) + self.f.v_rho(tr.sqrt()) + self.f.v_eps(eps) / tr
    }

    /// Closed form by the chain rule: `∂V/∂x = V_r'·∂r/∂x`,
    /// `∂V/∂e = V_ϱ'·ge/ϱ + V_ε'·∂ε/∂e/ϱ² − 2V_ε·ge/ϱ⁴` with
    /// `∂ε/∂e = ge·[2s(2G − tr G·I)/Δ − Δ·adj G/s]/(Δ² + 4s²)`,
    /// `s = √det G`, `Δ = λ² − μ²` (first term dropped at `Δ = 0`).
    fn gradient(&self, x: &SVector<f64, 3>, e: &SMatrix<f64, 3, 2>, metric: &SMatrix<f64, 3, 3>) -> Gradient<2, 3> {
        let (r, dr) = match &self.base {
            Base::Centre(c) => c.distance_gradient(x),
            Base::Torus(t) => t.angle_gradient(x),
        };
        let g = green_tensor(e, metric);
        let (tr, det, delta2) = invariants2(&g);
        let s = det.sqrt();
        let delta = sqrt0(delta2);
        let eps = delta.atan2(s * 2.0) * 0.5;
        let rho = tr.sqrt();
        let (vr, dvr) = first_derivative(|r: Dual64| self.f.v_r(r), r);
        let (vrho, dvrho) = first_derivative(|p: Dual64| self.f.v_rho(p), rho);
        let (veps, dveps) = first_derivative(|p: Dual64| self.f.v_eps(p), eps);
        let value = vr + vrho + veps / tr;
        // ∂ε/∂e = ge·K, K = [2s(2G − tr I)/Δ − Δ adj(G)/s]/(Δ² + 4s²).
        let mut k = Matrix2::new(g[(1, 1)], -g[(0, 1)], -g[(1, 0)], g[(0, 0)]) * (-delta / s);
        if delta != 0.0 {
            let a = 2.0 * s / delta;
            k += Matrix2::new(g[(0, 0)] - g[(1, 1)], 2.0 * g[(0, 1)], 2.0 * g[(1, 0)], g[(1, 1)] - g[(0, 0)]) * a;
        }
        k /= delta2 + 4.0 * det;
        let ge = metric * e;
        let coef_id = dvrho / rho - 2.0 * veps / (tr * tr);
        let m = k * (dveps / tr) + Matrix2::identity() * coef_id;
        Gradient { value, dx: dr * dvr, de: ge * m }
    }
}
