//! Direct products of Lie groups, e.g. frame bundle × fibre group × momentum
//! space for the integrators. Zero-cost: every operation is the pair of the
//! component operations, nothing is allocated in `exp`, `compose`, `Ad`,
//! `dexp`, `dexp⁻¹`.

use std::ops::{Add, Mul, Neg, Sub};

use nalgebra::DMatrix;

use super::{AlgebraVector, LieGroup};
use crate::Result;

/// The direct product `A × B`: pairs `(a, b)` with `(a, b)(a', b') = (aa', bb')`.
///
/// Every group operation acts componentwise; the algebra is
/// [`ProductAlgebra`]`<A::Algebra, B::Algebra>` with `[(x, y), (x', y')] =
/// ([x, x'], [y, y'])`, so `exp`, `log`, `Ad`, `dexp`, `dexp⁻¹` are the
/// component maps (with the components' closed forms). Coordinates: those of
/// `A` followed by those of `B` (`DOF = A::DOF + B::DOF`). Matrix
/// representation: block diagonal `diag(A, B)`. `constraint_defect` is the
/// larger of the two; `renormalize` renormalises both; `log` fails with the
/// first component's error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Product<A, B>(pub A, pub B);

/// Algebra of [`Product`]: a pair, stored components `x` then `y`
/// (`LEN = X::LEN + Y::LEN`), vector-space operations componentwise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProductAlgebra<X, Y>(pub X, pub Y);

impl<X: AlgebraVector, Y: AlgebraVector> Add for ProductAlgebra<X, Y> {
    type Output = Self;
    #[inline]
    fn add(self, rhs: Self) -> Self {
        ProductAlgebra(self.0 + rhs.0, self.1 + rhs.1)
    }
}

impl<X: AlgebraVector, Y: AlgebraVector> Sub for ProductAlgebra<X, Y> {
    type Output = Self;
    #[inline]
    fn sub(self, rhs: Self) -> Self {
        ProductAlgebra(self.0 - rhs.0, self.1 - rhs.1)
    }
}

impl<X: AlgebraVector, Y: AlgebraVector> Neg for ProductAlgebra<X, Y> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        ProductAlgebra(-self.0, -self.1)
    }
}

impl<X: AlgebraVector, Y: AlgebraVector> Mul<f64> for ProductAlgebra<X, Y> {
    type Output = Self;
    #[inline]
    fn mul(self, s: f64) -> Self {
        ProductAlgebra(self.0 * s, self.1 * s)
    }
}

impl<X: AlgebraVector, Y: AlgebraVector> AlgebraVector for ProductAlgebra<X, Y> {
    const LEN: usize = X::LEN + Y::LEN;
    #[inline]
    fn zero() -> Self {
        ProductAlgebra(X::zero(), Y::zero())
    }
    #[inline]
    fn get(&self, i: usize) -> f64 {
        if i < X::LEN {
            self.0.get(i)
        } else {
            self.1.get(i - X::LEN)
        }
    }
    #[inline]
    fn set(&mut self, i: usize, v: f64) {
        if i < X::LEN {
            self.0.set(i, v)
        } else {
            self.1.set(i - X::LEN, v)
        }
    }
    #[inline]
    fn norm(&self) -> f64 {
        self.0.norm().hypot(self.1.norm())
    }
    #[inline]
    fn amax(&self) -> f64 {
        self.0.amax().max(self.1.amax())
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.0.is_finite() && self.1.is_finite()
    }
}

/// `diag(a, b)`.
fn block_diag(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let (ra, ca) = a.shape();
    let (rb, cb) = b.shape();
    let mut m = DMatrix::zeros(ra + rb, ca + cb);
    m.view_mut((0, 0), (ra, ca)).copy_from(a);
    m.view_mut((ra, ca), (rb, cb)).copy_from(b);
    m
}

impl<A: LieGroup, B: LieGroup> LieGroup for Product<A, B> {
    type Algebra = ProductAlgebra<A::Algebra, B::Algebra>;
    const DOF: usize = A::DOF + B::DOF;
    const NAME: &'static str = "direct product";

    #[inline]
    fn identity() -> Self {
        Product(A::identity(), B::identity())
    }
    #[inline(always)]
    fn compose(&self, rhs: &Self) -> Self {
        Product(self.0.compose(&rhs.0), self.1.compose(&rhs.1))
    }
    #[inline]
    fn inverse(&self) -> Self {
        Product(self.0.inverse(), self.1.inverse())
    }
    #[inline(always)]
    fn exp(a: &Self::Algebra) -> Self {
        Product(A::exp(&a.0), B::exp(&a.1))
    }
    fn log(&self) -> Result<Self::Algebra> {
        Ok(ProductAlgebra(self.0.log()?, self.1.log()?))
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(self.0.adjoint(&a.0), self.1.adjoint(&a.1))
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(A::bracket(&a.0, &b.0), B::bracket(&a.1, &b.1))
    }
    #[inline]
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(A::dexp(&a.0, &v.0), B::dexp(&a.1, &v.1))
    }
    #[inline]
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(A::dexp_inv(&a.0, &v.0), B::dexp_inv(&a.1, &v.1))
    }
    /// `A`'s coordinates `c[..A::DOF]`, then `B`'s.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        let k = A::DOF.min(c.len());
        ProductAlgebra(A::algebra_from_coords(&c[..k]), B::algebra_from_coords(&c[k..]))
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        let mut c = A::algebra_coords(&a.0);
        c.extend(B::algebra_coords(&a.1));
        c
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        block_diag(&self.0.to_matrix(), &self.1.to_matrix())
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        block_diag(&A::algebra_to_matrix(&a.0), &B::algebra_to_matrix(&a.1))
    }
    /// The larger component defect (NaN if either is NaN).
    fn constraint_defect(&self) -> f64 {
        let (x, y) = (self.0.constraint_defect(), self.1.constraint_defect());
        if x.is_nan() || y.is_nan() {
            f64::NAN
        } else {
            x.max(y)
        }
    }
    #[inline]
    fn renormalize(&self) -> Self {
        Product(self.0.renormalize(), self.1.renormalize())
    }
}
