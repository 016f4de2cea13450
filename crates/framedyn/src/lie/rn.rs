//! The additive group ℝᵏ (translations), used for momenta and for the global
//! angle coordinates of the torus frame bundle.

use nalgebra::{DMatrix, SVector};

use super::LieGroup;
use crate::Result;

/// ℝᵏ under addition. Its algebra is ℝᵏ itself, `exp` is the identity map and
/// all brackets vanish. Matrix representation: the `(k+1)×(k+1)` translation
/// matrix `[[I, x], [0, 1]]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rn<const K: usize>(pub SVector<f64, K>);

impl<const K: usize> LieGroup for Rn<K> {
    type Algebra = SVector<f64, K>;
    const DOF: usize = K;
    const NAME: &'static str = "R^k";

    #[inline]
    fn identity() -> Self {
        Rn(SVector::zeros())
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Rn(self.0 + rhs.0)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Rn(-self.0)
    }
    #[inline]
    fn exp(a: &Self::Algebra) -> Self {
        Rn(*a)
    }
    #[inline]
    fn log(&self) -> Result<Self::Algebra> {
        Ok(self.0)
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        *a
    }
    #[inline]
    fn bracket(_a: &Self::Algebra, _b: &Self::Algebra) -> Self::Algebra {
        SVector::zeros()
    }
    #[inline]
    fn dexp(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    #[inline]
    fn dexp_inv(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        SVector::from_column_slice(c)
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        a.as_slice().to_vec()
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        let mut m = DMatrix::identity(K + 1, K + 1);
        for i in 0..K {
            m[(i, K)] = self.0[i];
        }
        m
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(K + 1, K + 1);
        for i in 0..K {
            m[(i, K)] = a[i];
        }
        m
    }
    fn constraint_defect(&self) -> f64 {
        0.0
    }
    fn renormalize(&self) -> Self {
        *self
    }
}
