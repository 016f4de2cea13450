//! Potentials given only as `f64` closures (e.g. from Python), with
//! gradients by extrapolated finite differences.
//!
//! **Prefer a trait implementation.** A potential written once generic over
//! [`Scalar`] gets exact derivatives by dual numbers at the cost of a few
//! evaluations; a closure of `f64` can only be differenced. Both below are
//! `V = a·z/R` on the unit sphere:
//!
//! ```
//! use framedyn::potential::{FnPotential, Potential, Scalar};
//! use nalgebra::{SMatrix, SVector};
//!
//! // Preferred: exact gradient by forward-mode AD, ~3 evaluations.
//! #[derive(Debug)]
//! struct Tilt { a: f64 }
//! impl Potential<2, 3> for Tilt {
//!     fn uses_frame(&self) -> bool { false }
//!     fn value<D: Scalar>(&self, x: &SVector<D, 3>, _e: &SMatrix<D, 3, 2>, _g: &SMatrix<f64, 3, 3>) -> D {
//!         x[2] * self.a
//!     }
//! }
//!
//! // Fallback: an f64 closure, gradient by Ridders-extrapolated central
//! // differences, 20 evaluations per coordinate and ~1e-12 relative error.
//! let a = 0.5;
//! let closure = FnPotential::<_, 2, 3>::new(
//!     move |x: &SVector<f64, 3>, _e: &SMatrix<f64, 3, 2>, _g: &SMatrix<f64, 3, 3>| a * x[2],
//!     false, // uses_frame
//!     1.0,   // length scale over which V varies (here R)
//! )?;
//!
//! let (x, e, g) = (SVector::from([0.0, 0.6, 0.8]), SMatrix::zeros(), SMatrix::identity());
//! let exact = Tilt { a }.gradient(&x, &e, &g);
//! let approx = closure.gradient(&x, &e, &g);
//! assert_eq!(exact.value, approx.value);
//! assert!((exact.dx - approx.dx).norm() < 1e-12);
//! # Ok::<(), framedyn::Error>(())
//! ```

use nalgebra::{SMatrix, SVector};
use std::fmt;

use super::{Gradient, Potential, Scalar};
use crate::error::positive;
use crate::Result;

/// Levels of the Ridders tableau (steps `h₀ … h₀/1.4⁹`).
const LEVELS: usize = 10;
/// Step ratio between levels.
const CON: f64 = 1.4;
/// First step, relative to the length scale.
const FIRST_STEP: f64 = 0.1;

/// A potential `V(x, e)` given as an `f64` closure `f(x, e, metric)`, with
/// the gradient by Ridders' extrapolation of central differences (Numerical
/// Recipes `dfridr`: steps `h₀ = 0.1·ℓ` divided by 1.4 per level, 10
/// levels, the estimate with the smallest error estimate).
///
/// **Slower and less accurate than the dual-number path** (see the
/// [module documentation](self)): 20 evaluations per coordinate (`E`, plus
/// `E·N` when `uses_frame`), and ~1e-12 relative error instead of
/// round-off (measured ≤ 1e-12 on the Bertrand and elastic potentials),
/// worse near singularities of `V` closer than `h₀`.
///
/// **Requirements on the closure.** Steps are taken in the ambient space, off
/// the manifold (and off the tangent space for `e`) by up to `h₀`: the
/// closure must be defined and smooth there — write it through ambient
/// expressions (e.g. `z/|x|` rather than `acos(z/R)`, which is NaN just
/// above the pole).
///
/// **Steps.** `h₀ = 0.1·ℓ` (`ℓ` the `length_scale` of
/// [`FnPotential::new`]) for the position; for the frame
/// `h₀ = 0.1·det G/((tr G)^{N−1}‖e‖_F)` with `G = eᵀge`: a lower bound of
/// `λ_min(G)/‖e‖_F`, below which a step cannot bring the frame near a
/// degenerate one (`det G = 0`, where deformation potentials are singular);
/// `ℓ` if `G` is not positive definite.
///
/// **Dual numbers.** [`Potential::value`] with first-order dual numbers
/// (what [`autodiff_gradient`](super::autodiff_gradient) and sums
/// differentiated as a whole use) returns the first-order expansion
/// `V + ∂V·(δx, δe)` with the difference gradient, so first derivatives are
/// those of [`Potential::gradient`]; with second-order dual numbers it
/// returns NaN (second derivatives are not available).
pub struct FnPotential<F, const N: usize, const E: usize> {
    f: F,
    uses_frame: bool,
    length: f64,
}

impl<F, const N: usize, const E: usize> fmt::Debug for FnPotential<F, N, E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FnPotential")
            .field("uses_frame", &self.uses_frame)
            .field("length_scale", &self.length)
            .finish_non_exhaustive()
    }
}

impl<F, const N: usize, const E: usize> FnPotential<F, N, E>
where
    F: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> f64 + Send + Sync,
{
    /// `V = f(x, e, metric)`. `uses_frame`: whether `f` depends on `e` (if
    /// not, `∂V/∂e` is not computed and is zero). `length_scale`: the length
    /// over which `V` varies in `x` (e.g. the radius `R`). Fails with
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (field
    /// `"length_scale"`) unless it is finite and > 0.
    pub fn new(f: F, uses_frame: bool, length_scale: f64) -> Result<Self> {
        Ok(FnPotential { f, uses_frame, length: positive("length_scale", length_scale)? })
    }

    /// The gradient and an estimate (not a bound) of the largest absolute
    /// error of its components: per component the larger of Ridders'
    /// extrapolation-error estimate and the rounding floor `2ε·max|V|/h`
    /// (over the test suite the actual error stayed below 10× the estimate).
    pub fn gradient_with_error(
        &self,
        x: &SVector<f64, E>,
        e: &SMatrix<f64, E, N>,
        metric: &SMatrix<f64, E, E>,
    ) -> (Gradient<N, E>, f64) {
        let value = (self.f)(x, e, metric);
        let mut worst = 0.0f64;
        let mut dx = SVector::<f64, E>::zeros();
        let h0 = FIRST_STEP * self.length;
        for i in 0..E {
            let (d, err) = ridders(
                |h| {
                    let mut xh = *x;
                    xh[i] += h;
                    (self.f)(&xh, e, metric)
                },
                h0,
            );
            dx[i] = d;
            worst = worst.max(err);
        }
        let mut de = SMatrix::<f64, E, N>::zeros();
        if self.uses_frame {
            // δe changes G = eᵀge by ~2|δe|‖e‖: keep steps below
            // λ_min(G)/‖e‖ ≥ det G/(tr G^{N−1}‖e‖), away from the collapse.
            let gm = e.transpose() * metric * e;
            let s = spd_det(gm) / (gm.trace().powi(N as i32 - 1) * e.norm());
            let h0 = FIRST_STEP * if s > 0.0 && s.is_finite() { s } else { self.length };
            for a in 0..N {
                for i in 0..E {
                    let (d, err) = ridders(
                        |h| {
                            let mut eh = *e;
                            eh[(i, a)] += h;
                            (self.f)(x, &eh, metric)
                        },
                        h0,
                    );
                    de[(i, a)] = d;
                    worst = worst.max(err);
                }
            }
        }
        (Gradient { value, dx, de }, worst)
    }
}

/// Determinant of a symmetric positive semi-definite matrix by Gaussian
/// elimination without pivoting (stable for such matrices); 0 once a pivot
/// is not positive.
fn spd_det<const N: usize>(mut m: SMatrix<f64, N, N>) -> f64 {
    let mut det = 1.0;
    for k in 0..N {
        let p = m[(k, k)];
        if p.is_nan() || p <= 0.0 {
            return 0.0;
        }
        det *= p;
        for i in k + 1..N {
            let f = m[(i, k)] / p;
            for j in k + 1..N {
                m[(i, j)] -= f * m[(k, j)];
            }
        }
    }
    det
}

/// Ridders' extrapolation (`dfridr`, step ratio 1.4) of the central
/// difference `(φ(h) − φ(−h))/2h` → `φ'(0)`; returns the estimate with the
/// smallest error estimate, and that estimate (at least the rounding floor
/// `2ε·max|φ|/h` of the level it comes from). All levels are evaluated:
/// `dfridr`'s early exit (when the error estimate grows) can stop at a
/// coarse level whose two error indicators agree by chance (measured:
/// 2e-6 relative error on a Kepler gradient). Fixed-size tableau, no
/// allocation.
fn ridders(phi: impl Fn(f64) -> f64, h0: f64) -> (f64, f64) {
    const CON2: f64 = CON * CON;
    let mut a = [[0.0f64; LEVELS]; LEVELS];
    let mut h = h0;
    let (p, m) = (phi(h), phi(-h));
    let mut size = p.abs().max(m.abs());
    a[0][0] = (p - m) / (2.0 * h);
    let mut best = a[0][0];
    let mut err = f64::INFINITY;
    let mut floor = f64::EPSILON * size / h;
    for i in 1..LEVELS {
        h /= CON;
        let (p, m) = (phi(h), phi(-h));
        size = size.max(p.abs()).max(m.abs());
        a[0][i] = (p - m) / (2.0 * h);
        let mut fac = CON2;
        for j in 1..=i {
            a[j][i] = (a[j - 1][i] * fac - a[j - 1][i - 1]) / (fac - 1.0);
            fac *= CON2;
            let e = (a[j][i] - a[j - 1][i]).abs().max((a[j][i] - a[j - 1][i - 1]).abs());
            if e <= err {
                err = e;
                best = a[j][i];
                // Rounding of the values, amplified by the differences at
                // step h and the extrapolation (a factor ≈ 2).
                floor = 2.0 * f64::EPSILON * size / h;
            }
        }
    }
    (best, err.max(floor))
}

impl<F, const N: usize, const E: usize> Potential<N, E> for FnPotential<F, N, E>
where
    F: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> f64 + Send + Sync,
{
    fn uses_frame(&self) -> bool {
        self.uses_frame
    }

    /// None: `V` is an `f64` closure.
    fn second_derivatives(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, metric: &SMatrix<f64, E, E>) -> D {
        first_order(x, e, self.uses_frame, |xr, er| (self.f)(xr, er, metric), |xr, er| self.gradient_with_error(xr, er, metric).0)
    }

    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, metric: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        self.gradient_with_error(x, e, metric).0
    }
}

/// `V` of an `f64`-only potential at dual-number arguments: the value
/// (`NDERIV = 0`), the first-order expansion `V + ∂V·(δx, δe)` with the
/// gradient `grad` (`NDERIV = 1`: what [`autodiff_gradient`](super::autodiff_gradient)
/// and sums differentiated as a whole use), NaN in every part for second
/// derivatives, which such a potential does not have.
fn first_order<D: Scalar, const N: usize, const E: usize>(
    x: &SVector<D, E>,
    e: &SMatrix<D, E, N>,
    uses_frame: bool,
    value: impl FnOnce(&SVector<f64, E>, &SMatrix<f64, E, N>) -> f64,
    grad: impl FnOnce(&SVector<f64, E>, &SMatrix<f64, E, N>) -> Gradient<N, E>,
) -> D {
    let xr = x.map(|v| v.re());
    let er = e.map(|v| v.re());
    match D::NDERIV {
        0 => D::from(value(&xr, &er)),
        1 => {
            let g = grad(&xr, &er);
            let mut out = D::from(g.value);
            for i in 0..E {
                out += (x[i] - D::from(xr[i])) * g.dx[i];
            }
            if uses_frame {
                for k in 0..E * N {
                    out += (e[k] - D::from(er[k])) * g.de[k];
                }
            }
            out
        }
        _ => {
            // NaN in every part: squares of the inputs have non-zero first
            // and second derivative parts, which NaN then poisons.
            let mut out = D::from(f64::NAN);
            for v in x.iter().chain(e.iter()) {
                out += *v * *v * f64::NAN;
            }
            out
        }
    }
}

/// A potential `V(x, e)` given as an `f64` closure `f(x, e, metric)` together
/// with its gradient `grad(x, e, metric) = (∂V/∂x, ∂V/∂e)` supplied by the
/// user (partial derivatives in the ambient components, column `A` of
/// `∂V/∂e` for `e_A`; the metric is not applied). No differencing: one call
/// of each closure per evaluation, and the gradient is exactly what the user
/// wrote — a wrong one is not detected here (compare it once with
/// [`FnPotential::gradient_with_error`], or watch the energy drift).
///
/// Dual numbers as for [`FnPotential`]: first-order expansions with the
/// supplied gradient, NaN for second derivatives.
pub struct GradFnPotential<F, G, const N: usize, const E: usize> {
    f: F,
    grad: G,
    uses_frame: bool,
}

impl<F, G, const N: usize, const E: usize> fmt::Debug for GradFnPotential<F, G, N, E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GradFnPotential").field("uses_frame", &self.uses_frame).finish_non_exhaustive()
    }
}

impl<F, G, const N: usize, const E: usize> GradFnPotential<F, G, N, E>
where
    F: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> f64 + Send + Sync,
    G: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> (SVector<f64, E>, SMatrix<f64, E, N>) + Send + Sync,
{
    /// `V = f(x, e, metric)` with `(∂V/∂x, ∂V/∂e) = grad(x, e, metric)`.
    /// `uses_frame = false`: `∂V/∂e` is taken as zero whatever `grad`
    /// returns for it.
    pub fn new(f: F, grad: G, uses_frame: bool) -> Self {
        GradFnPotential { f, grad, uses_frame }
    }
}

impl<F, G, const N: usize, const E: usize> Potential<N, E> for GradFnPotential<F, G, N, E>
where
    F: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> f64 + Send + Sync,
    G: Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> (SVector<f64, E>, SMatrix<f64, E, N>) + Send + Sync,
{
    fn uses_frame(&self) -> bool {
        self.uses_frame
    }

    /// None: `V` is an `f64` closure.
    fn second_derivatives(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, metric: &SMatrix<f64, E, E>) -> D {
        first_order(x, e, self.uses_frame, |xr, er| (self.f)(xr, er, metric), |xr, er| self.gradient(xr, er, metric))
    }

    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, metric: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let (dx, de) = (self.grad)(x, e, metric);
        Gradient { value: (self.f)(x, e, metric), dx, de: if self.uses_frame { de } else { SMatrix::zeros() } }
    }
}
