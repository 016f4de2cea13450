//! Sums and multiples of potentials.
//!
//! ```
//! use framedyn::manifold::Sphere2;
//! use framedyn::potential::{Centre, Elastic, Kepler, Potential, Scaled, Sum};
//! use nalgebra::{SMatrix, SVector};
//!
//! let sphere = Sphere2::new(1.0)?;
//! // An elastic body in a repulsive Coulomb field: −1 × Kepler + elastic.
//! let v = Sum::new(Scaled::new(-1.0, Kepler::new(0.3, Centre::sphere2(&sphere))?)?, Elastic::new(2.0)?);
//! let x = SVector::from([0.6, 0.0, 0.8]);
//! let e = SMatrix::<f64, 3, 2>::new(0.8, 0.0, 0.0, 1.0, -0.6, 0.0);
//! let g = v.gradient(&x, &e, &SMatrix::identity());
//! assert!(Potential::<2, 3>::uses_frame(&v));
//! assert!((g.value - (0.3 * 0.8 / 0.6 + 4.0)).abs() < 1e-14);
//! # Ok::<(), framedyn::Error>(())
//! ```

use nalgebra::{SMatrix, SVector};

use super::integrable::finite_param;
use super::{Gradient, Potential, Scalar};
use crate::Result;

/// `V = V₁ + V₂`. Its gradient is the sum of the two gradients (each
/// part's own, closed-form where it has one); it uses the frame if either
/// part does. Nest for more terms: `Sum::new(a, Sum::new(b, c))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sum<P1, P2> {
    first: P1,
    second: P2,
}

impl<P1, P2> Sum<P1, P2> {
    /// `first + second`.
    pub fn new(first: P1, second: P2) -> Self {
        Sum { first, second }
    }

    /// The first term.
    pub fn first(&self) -> &P1 {
        &self.first
    }

    /// The second term.
    pub fn second(&self) -> &P2 {
        &self.second
    }
}

impl<P1: Potential<N, E>, P2: Potential<N, E>, const N: usize, const E: usize> Potential<N, E> for Sum<P1, P2> {
    fn uses_frame(&self) -> bool {
        self.first.uses_frame() || self.second.uses_frame()
    }

    fn second_derivatives(&self) -> bool {
        self.first.second_derivatives() && self.second.second_derivatives()
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, metric: &SMatrix<f64, E, E>) -> D {
        self.first.value(x, e, metric) + self.second.value(x, e, metric)
    }

    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, metric: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let a = self.first.gradient(x, e, metric);
        let b = self.second.gradient(x, e, metric);
        Gradient { value: a.value + b.value, dx: a.dx + b.dx, de: a.de + b.de }
    }
}

/// `V = c·V₀` for a finite constant `c` of either sign (e.g. `−1` turns the
/// attractive [`Kepler`](super::Kepler) potential into the repulsive
/// Coulomb one). Gradient: `c` times that of `V₀`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaled<P> {
    factor: f64,
    inner: P,
}

impl<P> Scaled<P> {
    /// `factor · inner`. Fails with
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (field
    /// `"factor"`) unless `factor` is finite.
    pub fn new(factor: f64, inner: P) -> Result<Self> {
        Ok(Scaled { factor: finite_param("factor", factor)?, inner })
    }

    /// The factor `c`.
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// The scaled potential.
    pub fn inner(&self) -> &P {
        &self.inner
    }
}

impl<P: Potential<N, E>, const N: usize, const E: usize> Potential<N, E> for Scaled<P> {
    fn uses_frame(&self) -> bool {
        self.inner.uses_frame()
    }

    fn second_derivatives(&self) -> bool {
        self.inner.second_derivatives()
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, metric: &SMatrix<f64, E, E>) -> D {
        self.inner.value(x, e, metric) * self.factor
    }

    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, metric: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let g = self.inner.gradient(x, e, metric);
        Gradient { value: g.value * self.factor, dx: g.dx * self.factor, de: g.de * self.factor }
    }
}
