//! Potentials `V(x, e)` of a structured particle.
//!
//! A potential sees the body's position `x` and its frame vectors `e = (e₁ … e_N)`
//! as components in the flat ambient space of the manifold's embedding (ℝ³ for
//! S² and T², Minkowski ℝ^{2,1} for H², ℝ⁴ for S³), together with the ambient
//! metric (to form invariants such as the Green tensor `G_AB = ⟨e_A, e_B⟩`).
//! It is written **once**, generic over the scalar type `D: Scalar` (plain
//! `f64` or a dual number), and its gradient — hence the forces
//! `F̂_A = −H_A V` and torques `N̂^A_B = −E^A_B V` of the paper (§4, after
//! (a53)) — comes by forward-mode automatic differentiation ([`num_dual`]).
//! Users never hand-code gradients; built-in potentials may override
//! [`Potential::gradient`] with a closed form for speed (tested against the
//! automatic one).
//!
//! ```
//! use framedyn::potential::{Potential, Scalar};
//! use nalgebra::{SMatrix, SVector};
//!
//! /// V = a·z/R on the sphere of radius R (the paper's a·cos(r/R)).
//! #[derive(Debug)]
//! struct Tilt { a: f64, radius: f64 }
//!
//! impl Potential<2, 3> for Tilt {
//!     fn uses_frame(&self) -> bool { false }
//!     fn value<D: Scalar>(&self, x: &SVector<D, 3>, _e: &SMatrix<D, 3, 2>, _g: &SMatrix<f64, 3, 3>) -> D {
//!         x[2] * (self.a / self.radius)
//!     }
//! }
//!
//! let v = Tilt { a: 0.5, radius: 1.0 };
//! let grad = v.gradient(&SVector::from([0.0, 0.6, 0.8]), &SMatrix::zeros(), &SMatrix::identity());
//! assert!((grad.value - 0.4).abs() < 1e-15);
//! assert_eq!(grad.dx, SVector::from([0.0, 0.0, 0.5]));
//! ```

pub mod bertrand;
pub mod centre;
pub mod combinators;
pub mod elastic;
pub mod integrable;
pub mod invariants;
pub mod separable;
pub mod user;

pub use bertrand::*;
pub use centre::*;
pub use combinators::*;
pub use elastic::*;
pub use integrable::*;
pub use invariants::*;
pub use separable::*;
pub use user::*;

use nalgebra::{SMatrix, SVector};
use nalgebra::Const;
use num_dual::{Dual64, DualNum, DualSVec64, DualVec};
use std::fmt::Debug;

/// The scalar types a potential is evaluated with: `f64` and the dual numbers
/// used for its derivatives. Write potentials generic over `D: Scalar`, with
/// constants as `f64` (`x * 2.0`, `D::from(2.0)`) and functions as methods
/// (`x.sin()`, `x.sqrt()`, `x.powi(2)`).
pub trait Scalar: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// Value and first derivatives of a potential at one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gradient<const N: usize, const E: usize> {
    /// `V(x, e)`.
    pub value: f64,
    /// `∂V/∂x^i` (ambient components of the position).
    pub dx: SVector<f64, E>,
    /// `∂V/∂e^i_A` (column `A`: ambient components of `e_A`); zero when the
    /// potential does not use the frame.
    pub de: SMatrix<f64, E, N>,
}

/// A potential energy `V(x, e)` of a body with `N` frame vectors in an
/// `E`-dimensional ambient space. See the [module documentation](self).
pub trait Potential<const N: usize, const E: usize>: Debug + Send + Sync {
    /// Whether `V` depends on the body frame `e` (`false`: `V = V(x)`, which
    /// also suits structureless points and halves the cost of its gradient).
    fn uses_frame(&self) -> bool;

    /// `V(x, e)`; `metric` is the ambient metric (identity, or
    /// `diag(1, 1, −1)` for H²).
    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, metric: &SMatrix<f64, E, E>) -> D;

    /// Whether [`value`](Self::value) has exact second derivatives at dual
    /// arguments (default `true`: a potential written over [`Scalar`]). The
    /// `f64`-only user potentials ([`FnPotential`], [`GradFnPotential`]) have
    /// none; models in them have no exact [`tangent_field`](crate::dynamics::System::tangent_field).
    fn second_derivatives(&self) -> bool {
        true
    }

    /// Value and gradient; by default by forward-mode automatic differentiation
    /// ([`autodiff_gradient`]).
    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, metric: &SMatrix<f64, E, E>) -> Gradient<N, E>
    where
        Self: Sized,
    {
        autodiff_gradient(self, x, e, metric)
    }
}

/// Value and gradient of `p` by forward-mode automatic differentiation: one
/// evaluation with `E`-component dual numbers for `∂V/∂x`, and one more per
/// frame vector for `∂V/∂e` when [`Potential::uses_frame`] is true.
pub fn autodiff_gradient<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    metric: &SMatrix<f64, E, E>,
) -> Gradient<N, E> {
    let lift_e = || e.map(DualSVec64::<E>::from_re);
    let ed = lift_e();
    let (value, dx) = num_dual::gradient(|xd: SVector<DualSVec64<E>, E>| p.value(&xd, &ed, metric), x);
    let mut de = SMatrix::<f64, E, N>::zeros();
    if p.uses_frame() {
        let xd = x.map(DualSVec64::<E>::from_re);
        for a in 0..N {
            let col: SVector<f64, E> = e.column(a).into_owned();
            let (_, g) = num_dual::gradient(
                |cd: SVector<DualSVec64<E>, E>| {
                    let mut ed = lift_e();
                    ed.set_column(a, &cd);
                    p.value(&xd, &ed, metric)
                },
                &col,
            );
            de.set_column(a, &g);
        }
    }
    Gradient { value, dx, de }
}

/// The gradient of `p` at `(x, e)` and its directional derivative along
/// `(δx, δe)` — the Hessian of `V` applied to `(δx, δe)`, with `value` the
/// derivative `dV[(δx, δe)]` — by nested forward-mode automatic
/// differentiation: the gradient's dual numbers over dual numbers carrying
/// the direction. One evaluation for `∂V/∂x`, one more per frame vector when
/// [`Potential::uses_frame`]. Exact only where [`Potential::second_derivatives`].
pub fn gradient_derivative<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    metric: &SMatrix<f64, E, E>,
    dx: &SVector<f64, E>,
    de: &SMatrix<f64, E, N>,
) -> (Gradient<N, E>, Gradient<N, E>) {
    type Inner<const E: usize> = DualVec<Dual64, Const<E>>;
    let xd = x.zip_map(dx, Dual64::new);
    let ed = e.zip_map(de, Dual64::new);
    let lift_e = || ed.map(Inner::<E>::from_re);
    let e_lifted = lift_e();
    let (value, gx) = num_dual::gradient(|xi: SVector<Inner<E>, E>| p.value(&xi, &e_lifted, metric), &xd);
    let mut g = Gradient { value: value.re, dx: gx.map(|v| v.re), de: SMatrix::zeros() };
    let mut d = Gradient { value: value.eps, dx: gx.map(|v| v.eps), de: SMatrix::zeros() };
    if p.uses_frame() {
        let x_lifted = xd.map(Inner::<E>::from_re);
        for a in 0..N {
            let col: SVector<Dual64, E> = ed.column(a).into_owned();
            let (_, ga) = num_dual::gradient(
                |cd: SVector<Inner<E>, E>| {
                    let mut ei = lift_e();
                    ei.set_column(a, &cd);
                    p.value(&x_lifted, &ei, metric)
                },
                &col,
            );
            g.de.set_column(a, &ga.map(|v| v.re));
            d.de.set_column(a, &ga.map(|v| v.eps));
        }
    }
    (g, d)
}

/// `V = 0`: free (geodesic) motion.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Free;

impl<const N: usize, const E: usize> Potential<N, E> for Free {
    fn uses_frame(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, _x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _metric: &SMatrix<f64, E, E>) -> D {
        D::from(0.0)
    }
    fn gradient(&self, _x: &SVector<f64, E>, _e: &SMatrix<f64, E, N>, _m: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        Gradient { value: 0.0, dx: SVector::zeros(), de: SMatrix::zeros() }
    }
}

/// The Green tensor `G_AB = ⟨e_A, e_B⟩` of the body frame in the ambient
/// metric (the deformation invariants of an affine body are functions of it).
pub fn green_tensor<D: Scalar, const N: usize, const E: usize>(
    e: &SMatrix<D, E, N>,
    metric: &SMatrix<f64, E, E>,
) -> SMatrix<D, N, N> {
    SMatrix::from_fn(|a, b| {
        let mut s = D::from(0.0);
        for i in 0..E {
            for j in 0..E {
                if metric[(i, j)] != 0.0 {
                    s += e[(i, a)] * e[(j, b)] * metric[(i, j)];
                }
            }
        }
        s
    })
}
