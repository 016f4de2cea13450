//! Lie groups of the configuration spaces.
//!
//! Every group implements [`LieGroup`]; its Lie algebra is represented by a
//! fixed-size type implementing [`AlgebraVector`] (a vector of coordinates in
//! a stated basis, or a matrix for the general-`n` matrix groups).
//!
//! ## Conventions (used by every implementation and by the integrators)
//! - `exp` is the group exponential; `log` its principal inverse where defined.
//! - `compose(a, b)` is the product `a·b`; a left-trivialised velocity `ξ`
//!   means `ġ = g·ξ`, a right-trivialised one `ġ = ξ·g`.
//! - `adjoint(g, ξ) = Ad_g ξ = g ξ g⁻¹`, `bracket(a, b) = [a, b] = ad_a b`.
//! - `dexp(a, v) = Σ_{k≥0} ad_a^k v / (k+1)!`, so that
//!   `d/dt exp(a(t)) = dexp(a, ȧ)·exp(a)` (right-trivialised derivative).
//!   `dexp_inv` is its inverse, `Σ_k B_k/k! ad_a^k v` (Bernoulli numbers,
//!   B₁ = −½), convergent for the spectral radius of `ad_a` below 2π.
//!   For `ġ = g·ξ` with `g = g₀ exp(a)` one has `ȧ = dexp_inv(−a, ξ)`.
//!
//! ## Layout
//! - closed forms: [`so2`], [`so3`], [`su2`] (unit quaternions), [`so4`],
//!   [`so12`] (the Lorentz group of H²), with the coefficient functions of
//!   their exponentials in [`special`];
//! - general-`n` matrix groups: [`gl`] (GL⁺(n)), [`sl`] (SL(n)), [`son`]
//!   (SO(n)), [`co`] (CO⁺(n)); each file holds its group only. The matrix
//!   functions they share (LU, exponential, `dexp` and `dexp⁻¹`, real Schur
//!   form, square root, logarithm, polar factor) are in the crate-internal
//!   module `matrix` (directory `lie/matrix/`, one file per function family,
//!   each citing the literature it follows);
//! - [`rn`] (the additive group ℝᵏ), [`product`] (direct products) and
//!   [`tangent`] (the tangent group `G ⋉ 𝔤`: the group over dual numbers,
//!   through which the integrators differentiate their own steps);
//! - this file: the traits and the generic `dexp`/`dexp⁻¹` series.

pub mod co;
pub mod gl;
pub(crate) mod matrix;
pub mod product;
pub mod rn;
pub mod sl;
pub mod so12;
pub mod so2;
pub mod so3;
pub mod so4;
pub mod son;
pub mod special;
pub mod su2;
pub mod tangent;

#[allow(unused_imports)]
pub use co::*;
#[allow(unused_imports)]
pub use gl::*;
#[allow(unused_imports)]
pub use product::*;
pub use rn::Rn;
#[allow(unused_imports)]
pub use sl::*;
#[allow(unused_imports)]
pub use so12::*;
#[allow(unused_imports)]
pub use so2::*;
#[allow(unused_imports)]
pub use so3::*;
#[allow(unused_imports)]
pub use so4::*;
#[allow(unused_imports)]
pub use son::*;
#[allow(unused_imports)]
pub use su2::*;
pub use tangent::{Tangent, TangentAlgebra};

use nalgebra::{DMatrix, SMatrix};
use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

use crate::Result;

/// Coordinates of a Lie-algebra element: a small fixed-size vector space.
pub trait AlgebraVector:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
{
    /// Number of stored components (≥ the algebra's dimension).
    const LEN: usize;
    /// The zero element.
    fn zero() -> Self;
    /// Stored component `i` (`i < LEN`).
    fn get(&self, i: usize) -> f64;
    /// Sets stored component `i` (`i < LEN`).
    fn set(&mut self, i: usize, v: f64);
    /// Euclidean norm of the stored components.
    fn norm(&self) -> f64 {
        (0..Self::LEN).map(|i| self.get(i).powi(2)).sum::<f64>().sqrt()
    }
    /// Largest absolute stored component.
    fn amax(&self) -> f64 {
        (0..Self::LEN).map(|i| self.get(i).abs()).fold(0.0, f64::max)
    }
    /// True if every component is finite.
    fn is_finite(&self) -> bool {
        (0..Self::LEN).all(|i| self.get(i).is_finite())
    }
}

impl<const R: usize, const C: usize> AlgebraVector for SMatrix<f64, R, C> {
    const LEN: usize = R * C;
    #[inline]
    fn zero() -> Self {
        SMatrix::zeros()
    }
    #[inline]
    fn get(&self, i: usize) -> f64 {
        self[i]
    }
    #[inline]
    fn set(&mut self, i: usize, v: f64) {
        self[i] = v
    }
    #[inline]
    fn norm(&self) -> f64 {
        nalgebra::Matrix::norm(self)
    }
}

/// A finite-dimensional real Lie group with a faithful matrix representation.
///
/// See the [module documentation](self) for the conventions.
pub trait LieGroup: Copy + Debug + Send + Sync + 'static {
    /// Lie-algebra coordinates.
    type Algebra: AlgebraVector;
    /// Dimension of the group (number of independent algebra coordinates).
    const DOF: usize;
    /// Human-readable name, e.g. `"SO(3)"`.
    const NAME: &'static str;

    /// The neutral element.
    fn identity() -> Self;
    /// The product `self · rhs`.
    fn compose(&self, rhs: &Self) -> Self;
    /// The inverse element.
    fn inverse(&self) -> Self;
    /// The group exponential.
    fn exp(a: &Self::Algebra) -> Self;
    /// The principal logarithm, where it is defined.
    fn log(&self) -> Result<Self::Algebra>;
    /// `Ad_g a = g a g⁻¹`.
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra;
    /// The Lie bracket `[a, b]`.
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra;

    /// `dexp_a(v) = Σ_{k≥0} ad_a^k v/(k+1)!`, in closed form where one exists.
    /// The default sums the series until it stops changing the result.
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_series::<Self>(a, v, 60)
    }
    /// `dexp_a⁻¹(v)`, in closed form where one exists. The default sums the
    /// Bernoulli series (valid while the spectral radius of `ad_a` < 2π).
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_inv_series::<Self>(a, v, BERNOULLI_OVER_FACTORIAL.len() - 1)
    }

    /// The algebra element with coordinates `c` in the group's basis
    /// (`c.len() == DOF`). For matrix algebras the basis is documented on the type.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra;
    /// Coordinates of `a` in the group's basis (`DOF` numbers).
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64>;

    /// The element as a matrix of the defining representation.
    fn to_matrix(&self) -> DMatrix<f64>;
    /// The algebra element as a matrix of the defining representation
    /// (so that `exp` agrees with the matrix exponential of this matrix).
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64>;

    /// Distance of the stored representation from the group manifold
    /// (orthogonality defect, |det − 1|, Minkowski-metric defect, ...).
    fn constraint_defect(&self) -> f64;
    /// The nearest element of the group (removes round-off drift).
    fn renormalize(&self) -> Self;
}

/// `B_k / k!` for k = 0..=20 (B₁ = −½). Odd terms beyond k = 1 vanish.
pub const BERNOULLI_OVER_FACTORIAL: [f64; 21] = [
    1.0,
    -0.5,
    1.0 / 12.0,
    0.0,
    -1.0 / 720.0,
    0.0,
    1.0 / 30240.0,
    0.0,
    -1.0 / 1209600.0,
    0.0,
    1.0 / 47900160.0,
    0.0,
    -691.0 / 1307674368000.0,
    0.0,
    1.0 / 74724249600.0,
    0.0,
    -3617.0 / 10670622842880000.0,
    0.0,
    43867.0 / 5109094217170944000.0,
    0.0,
    -174611.0 / 802857662698291200000.0,
];

/// `Σ_{k=0}^{max_power} ad_a^k v/(k+1)!`: `dexp` truncated after the
/// `ad^{max_power}` term (stops early once the terms underflow).
pub fn dexp_series<G: LieGroup + ?Sized>(
    a: &G::Algebra,
    v: &G::Algebra,
    max_power: usize,
) -> G::Algebra {
    let mut term = *v;
    let mut sum = *v;
    let mut fact = 1.0;
    for k in 1..=max_power {
        term = G::bracket(a, &term);
        fact *= (k + 1) as f64;
        let add = term * (1.0 / fact);
        if add.amax() == 0.0 {
            break;
        }
        sum = sum + add;
    }
    sum
}

/// `Σ_{k=0}^{max_power} B_k/k! ad_a^k v`: `dexp⁻¹` truncated after the
/// `ad^{max_power}` term. An RKMK method of order `q` needs `max_power = q − 2`
/// (Munthe-Kaas 1999); fewer terms lower its order. `max_power` is capped at 20.
pub fn dexp_inv_series<G: LieGroup + ?Sized>(
    a: &G::Algebra,
    v: &G::Algebra,
    max_power: usize,
) -> G::Algebra {
    let mut term = *v;
    let mut sum = *v;
    for (k, &c) in BERNOULLI_OVER_FACTORIAL
        .iter()
        .enumerate()
        .take(max_power.min(BERNOULLI_OVER_FACTORIAL.len() - 1) + 1)
        .skip(1)
    {
        term = G::bracket(a, &term);
        if c != 0.0 {
            sum = sum + term * c;
        }
        if k > 2 && term.amax() == 0.0 {
            break;
        }
    }
    sum
}
