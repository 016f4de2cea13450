//! The additive group of a Lie algebra: the momentum space in which the
//! (projected) hypermomentum `P(K)` of an affine body lives, and the matrix
//! algebras gl(N), sl(N), co(N) with their orthogonal projections.

use nalgebra::DMatrix;

use super::Mat;
use crate::lie::matrix::{skew_part, traceless_part};
use crate::lie::{AlgebraVector, Co, Gl, LieGroup, Sl};
use crate::Result;

/// A matrix group whose Lie algebra is a linear space of `N×N` matrices,
/// closed under transposition, with its orthogonal (Frobenius) projection:
/// gl(N) ([`Gl`]), sl(N) ([`Sl`]: traceless part), co(N) ([`Co`]: `(tr a/N)I`
/// plus the skew part). The momentum spaces of the affine bodies.
pub trait MatrixAlgebra: LieGroup {
    /// The orthogonal projection of an `N×N` matrix onto the algebra.
    fn project_algebra(a: &Self::Algebra) -> Self::Algebra;
}

impl<const N: usize> MatrixAlgebra for Gl<N> {
    /// The identity.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        *a
    }
}

impl<const N: usize> MatrixAlgebra for Sl<N> {
    /// `a − (tr a/N)I`.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        traceless_part(a)
    }
}

impl<const N: usize> MatrixAlgebra for Co<N> {
    /// `(tr a/N)I + (a − aᵀ)/2`.
    #[inline]
    fn project_algebra(a: &Mat<N>) -> Mat<N> {
        let mut p = skew_part(a);
        let t = a.trace() / N as f64;
        for i in 0..N {
            p[(i, i)] += t;
        }
        p
    }
}

/// The Lie algebra of the matrix group `G` as an additive group: the space in
/// which the hypermomentum of a (constrained) affine body lives (the dual of
/// the algebra, identified with it by the pairing `⟨A, B⟩ = tr(AᵀB)`).
///
/// `exp` is the identity map, `compose` is addition, all brackets vanish,
/// `dexp = dexp⁻¹ = id`. Coordinates and `DOF` are those of `G`'s algebra
/// (e.g. `n² − 1` for [`Sl`]). Matrix representation: the `(DOF+1)×(DOF+1)`
/// translation matrix of the coordinates. [`constraint_defect`](LieGroup::constraint_defect)
/// is the largest entry of the part of the stored matrix outside the algebra,
/// relative to `1 + max|a_ij|`; [`renormalize`](LieGroup::renormalize)
/// projects onto the algebra ([`MatrixAlgebra::project_algebra`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Additive<G: LieGroup>(pub G::Algebra);

impl<G: MatrixAlgebra> Additive<G> {
    fn coords_matrix(c: &[f64]) -> DMatrix<f64> {
        let k = c.len();
        let mut m = DMatrix::identity(k + 1, k + 1);
        for (i, v) in c.iter().enumerate() {
            m[(i, k)] = *v;
        }
        m
    }
}

impl<G: MatrixAlgebra> LieGroup for Additive<G> {
    type Algebra = G::Algebra;
    const DOF: usize = G::DOF;
    const NAME: &'static str = "additive Lie algebra";

    #[inline]
    fn identity() -> Self {
        Additive(G::Algebra::zero())
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Additive(self.0 + rhs.0)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Additive(-self.0)
    }
    #[inline]
    fn exp(a: &Self::Algebra) -> Self {
        Additive(*a)
    }
    fn log(&self) -> Result<Self::Algebra> {
        Ok(self.0)
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        *a
    }
    #[inline]
    fn bracket(_a: &Self::Algebra, _b: &Self::Algebra) -> Self::Algebra {
        G::Algebra::zero()
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
        G::algebra_from_coords(c)
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        G::algebra_coords(a)
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        Self::coords_matrix(&G::algebra_coords(&self.0))
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let mut m = Self::coords_matrix(&G::algebra_coords(a));
        for i in 0..m.nrows() {
            m[(i, i)] = 0.0;
        }
        m
    }
    /// `max|a − P(a)| / (1 + max|a|)` (`+∞` if not finite).
    fn constraint_defect(&self) -> f64 {
        if !self.0.is_finite() {
            return f64::INFINITY;
        }
        (self.0 - G::project_algebra(&self.0)).amax() / (1.0 + self.0.amax())
    }
    #[inline]
    fn renormalize(&self) -> Self {
        Additive(G::project_algebra(&self.0))
    }
}
