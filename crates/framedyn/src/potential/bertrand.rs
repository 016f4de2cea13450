//! The Bertrand potentials of S², H² and S³: the only central potentials
//! for which every bounded orbit of a material point is closed (paper §5.1
//! (b88), (c88); §5.2 (a133), (b133)).

use nalgebra::{SMatrix, SVector};

use super::centre::{transverse_sq, Centre};
use super::{Gradient, Potential, Scalar};
use crate::error::positive;
use crate::Result;

/// The curved-space isotropic oscillator, a Bertrand potential (position
/// only; for a point or any body):
/// - S² (paper (b88)) and S³: `V = (κ/2) R² tan²(r/R)`;
/// - H² (paper (a133)): `V = (κ/2) R² tanh²(r/R)`,
///
/// `r` the geodesic distance from the [`Centre`] `c` (default: the pole of
/// the paper's chart, where `r` is the polar coordinate). For `r ≪ R` it is
/// the flat oscillator `κr²/2`.
///
/// **Ambient form.** With `Z = R cos(r/R)` (`R cosh(r/R)`) and
/// `T = R² sin²(r/R)` (`R² sinh²(r/R)`) from [`Centre::axial_transverse`],
/// `V = (κ/2) R² T/Z²` on all three manifolds. This extension off the
/// manifold is homogeneous of degree 0 in `x`, so `∂V/∂x · x = 0` (the
/// gradient has no component along the position vector), and it is smooth
/// wherever `V` is.
///
/// **Singular set.** S², S³: the great circle (great sphere) `r = πR/2`
/// equidistant from `c` and `−c`, where `V = +∞` (a point cannot cross it);
/// `V` is even about `r = πR/2`, so the antipode `−c` is a second minimum.
/// There the value is `+∞` and every gradient component NaN. H²: none;
/// `V < sup V = κR²/2` and motion with energy above it is unbounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator<const E: usize> {
    kappa: f64,
    centre: Centre<E>,
    /// `κR²/2`.
    scale: f64,
}

impl<const E: usize> Oscillator<E> {
    /// The oscillator of strength `kappa` about `centre`. Fails with
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (field
    /// `"kappa"`) unless `kappa` is finite and > 0.
    ///
    /// ```
    /// use framedyn::manifold::Sphere2;
    /// use framedyn::potential::{Centre, Oscillator, Potential};
    /// use nalgebra::{SMatrix, Vector3};
    ///
    /// let s2 = Sphere2::new(1.0)?;
    /// let v = Oscillator::new(2.0, Centre::sphere2(&s2))?;
    /// // V = (κ/2) R² tan²(r/R) (b88); at r = π/4: κ/2.
    /// let x = Vector3::new(0.5f64.sqrt(), 0.0, 0.5f64.sqrt());
    /// let value: f64 = Potential::<2, 3>::value(&v, &x, &SMatrix::zeros(), &SMatrix::identity());
    /// assert!((value - 1.0).abs() < 1e-14);
    /// assert!(Oscillator::new(-1.0, Centre::sphere2(&s2)).is_err());
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(kappa: f64, centre: Centre<E>) -> Result<Self> {
        let kappa = positive("kappa", kappa)?;
        let r = centre.radius();
        Ok(Oscillator { kappa, centre, scale: 0.5 * kappa * r * r })
    }

    /// The strength `κ`.
    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    /// The centre.
    pub fn centre(&self) -> &Centre<E> {
        &self.centre
    }
}

impl<const N: usize, const E: usize> Potential<N, E> for Oscillator<E> {
    fn uses_frame(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _metric: &SMatrix<f64, E, E>) -> D {
        let (z, t) = self.centre.axial_transverse(x);
        t / (z * z) * self.scale
    }

    /// Closed form: `∂V/∂y₀ = −κR² T/Z³`, `∂V/∂y_k = κR² y_k/Z²` in the
    /// rotated coordinates `y = Mx`, pulled back by `Mᵀ`.
    fn gradient(&self, x: &SVector<f64, E>, _e: &SMatrix<f64, E, N>, _m: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let y = self.centre.rotate(x);
        let z = y[0];
        let t = transverse_sq(&y);
        let value = t / (z * z) * self.scale;
        let dx = if value.is_finite() {
            let f = 2.0 * self.scale / (z * z);
            let mut w = y * f;
            w[0] = -f * t / z;
            self.centre.pull_back(&w)
        } else {
            SVector::repeat(f64::NAN)
        };
        Gradient { value, dx, de: SMatrix::zeros() }
    }
}

/// The curved-space Kepler–Coulomb potential, a Bertrand potential
/// (position only; for a point or any body):
/// - S² (paper (c88)) and S³: `V = −(α/R) cot(r/R)`;
/// - H² (paper (b133)): `V = −(α/R) coth(r/R)`,
///
/// `r` the geodesic distance from the [`Centre`] (default: the chart pole).
/// For `r ≪ R` it is the flat `−α/r`, corrected by `+αr/(3R²)` on S² and
/// `−αr/(3R²)` on H².
///
/// **Ambient form.** `V = −(α/R) Z/√T` with `Z`, `T` as for [`Oscillator`]:
/// homogeneous of degree 0 in `x` (`∂V/∂x · x = 0`) and smooth wherever `V`
/// is.
///
/// **Singular set.** The centre, where `V = −∞`; on S² and S³ also the
/// antipode `−c`, where `V = +∞` (the field of the compensating charge that
/// a compact space requires). At both the value is `∓∞` and every gradient
/// component NaN. On H² `V → −α/R` at infinity (the ionisation threshold).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kepler<const E: usize> {
    alpha: f64,
    centre: Centre<E>,
    /// `α/R`.
    scale: f64,
}

impl<const E: usize> Kepler<E> {
    /// The attractive Kepler–Coulomb potential of strength `alpha` about
    /// `centre`. Fails with
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) (field
    /// `"alpha"`) unless `alpha` is finite and > 0. (The repulsive Coulomb
    /// potential is `Scaled::new(-1.0, kepler)`, see
    /// [`Scaled`](super::Scaled).)
    pub fn new(alpha: f64, centre: Centre<E>) -> Result<Self> {
        let alpha = positive("alpha", alpha)?;
        Ok(Kepler { alpha, centre, scale: alpha / centre.radius() })
    }

    /// The strength `α`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The centre.
    pub fn centre(&self) -> &Centre<E> {
        &self.centre
    }
}

impl<const N: usize, const E: usize> Potential<N, E> for Kepler<E> {
    fn uses_frame(&self) -> bool {
        false
    }

    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _metric: &SMatrix<f64, E, E>) -> D {
        let (z, t) = self.centre.axial_transverse(x);
        -(z / t.sqrt()) * self.scale
    }

    /// Closed form: `∂V/∂y₀ = −(α/R)/√T`, `∂V/∂y_k = (α/R) Z y_k/T^{3/2}`,
    /// pulled back by `Mᵀ`.
    fn gradient(&self, x: &SVector<f64, E>, _e: &SMatrix<f64, E, N>, _m: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        let y = self.centre.rotate(x);
        let z = y[0];
        let t = transverse_sq(&y);
        let s = t.sqrt();
        let value = -(z / s) * self.scale;
        let dx = if value.is_finite() {
            let f = self.scale / s;
            let mut w = y * (f * z / t);
            w[0] = -f;
            self.centre.pull_back(&w)
        } else {
            SVector::repeat(f64::NAN)
        };
        Gradient { value, dx, de: SMatrix::zeros() }
    }
}
