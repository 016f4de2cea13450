//! The tangent group `TG = G ⋉ 𝔤` of a Lie group: the group over dual
//! numbers, whose integrators compute exact derivatives.
//!
//! An element `(g, ξ)` stands for `g·(1 + εξ)` with `ε² = 0`: a point `g`
//! of `G` with a left-trivialised tangent vector `δg = g·ξ`. An algebra
//! element `(a, b)` stands for `a + εb`. Every group operation is the
//! operation of `G` applied to dual numbers, the `ε` part of which is its
//! derivative (forward-mode automatic differentiation through the group):
//!
//! ```text
//! (g₁, ξ₁)(g₂, ξ₂) = (g₁g₂, Ad_{g₂⁻¹}ξ₁ + ξ₂)      (g, ξ)⁻¹ = (g⁻¹, −Ad_g ξ)
//! exp(a, b) = (exp a, dexp_{−a} b)                 log(g, ξ) = (log g, dexp⁻¹_{−a} ξ)
//! Ad_{(g,ξ)}(a, b) = (Ad_g a, Ad_g(b + [ξ, a]))   [(a₁, b₁), (a₂, b₂)] = ([a₁, a₂], [a₁, b₂] + [b₁, a₂])
//! ```
//!
//! So a Lie-group method applied to the tangent lift of a vector field
//! ([`Linearised`](crate::dynamics::Linearised): `ẏ = y·f(y)` with
//! `ξ̇ = Df(y)[ξ] + [ξ, f(y)]`) returns, in the second component, the exact
//! derivative of its own one-step map along `ξ₀` — the discrete variational
//! equation, without a finite difference. The first component is the plain
//! step (the same operations of `G` in the same order).
//!
//! Matrix representation: `g·(1 + εξ) ↦ [[g, gξ], [0, g]]` (`ε ↦ [[0, 1], [0, 0]]`).

use nalgebra::DMatrix;

use super::{dexp_series, AlgebraVector, LieGroup, Product, ProductAlgebra};
use crate::method::GroupNumerics;
use crate::Result;

/// The tangent group of `G`: `(g, ξ)`, the point `g` with the tangent vector
/// `g·ξ` (see the [module documentation](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangent<G: LieGroup>(pub G, pub G::Algebra);

/// Algebra of [`Tangent`]: `(a, b)` for `a + εb`, stored as the vector
/// space `𝔤 × 𝔤` of [`ProductAlgebra`] (components `a` then `b`); the
/// bracket is the tangent group's, not the product's.
pub type TangentAlgebra<A> = ProductAlgebra<A, A>;

/// Terms of the `dexp` series summed for the derivative part of
/// [`Tangent`]'s `dexp` and `dexp⁻¹` (the series stops earlier once its
/// terms underflow; `ad^60/61!` is below round-off for `ρ(ad) < 20`).
const DEXP_TERMS: usize = 60;

impl<G: LieGroup> LieGroup for Tangent<G> {
    type Algebra = TangentAlgebra<G::Algebra>;
    const DOF: usize = 2 * G::DOF;
    const NAME: &'static str = "tangent group";

    #[inline]
    fn identity() -> Self {
        Tangent(G::identity(), G::Algebra::zero())
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Tangent(self.0.compose(&rhs.0), rhs.0.inverse().adjoint(&self.1) + rhs.1)
    }
    #[inline]
    fn inverse(&self) -> Self {
        Tangent(self.0.inverse(), -self.0.adjoint(&self.1))
    }
    #[inline]
    fn exp(a: &Self::Algebra) -> Self {
        Tangent(G::exp(&a.0), G::dexp(&(-a.0), &a.1))
    }
    fn log(&self) -> Result<Self::Algebra> {
        let a = self.0.log()?;
        Ok(ProductAlgebra(a, G::dexp_inv(&(-a), &self.1)))
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(self.0.adjoint(&a.0), self.0.adjoint(&(a.1 + G::bracket(&self.1, &a.0))))
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        ProductAlgebra(G::bracket(&a.0, &b.0), G::bracket(&a.0, &b.1) + G::bracket(&a.1, &b.0))
    }
    /// `G`'s `dexp_a v` (its closed form), and its derivative
    /// `dexp_a w + (D_a dexp_a v)[b]` from the series of the tangent algebra.
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let series = dexp_series::<Self>(a, v, DEXP_TERMS);
        ProductAlgebra(G::dexp(&a.0, &v.0), series.1)
    }
    /// `u = dexp⁻¹_a v` by `G`'s closed form; its derivative `u'` from
    /// `v + εw = dexp_{a+εb}(u + εu')`: `u' = dexp⁻¹_a(w − (D_a dexp_a u)[b])`.
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let u = G::dexp_inv(&a.0, &v.0);
        let d = dexp_series::<Self>(a, &ProductAlgebra(u, G::Algebra::zero()), DEXP_TERMS).1;
        ProductAlgebra(u, G::dexp_inv(&a.0, &(v.1 - d)))
    }
    /// `G`'s coordinates of `a`, then those of `b`: those of `G × G`.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        Product::<G, G>::algebra_from_coords(c)
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        Product::<G, G>::algebra_coords(a)
    }
    /// `[[g, gξ], [0, g]]`.
    fn to_matrix(&self) -> DMatrix<f64> {
        let g = self.0.to_matrix();
        let gx = &g * G::algebra_to_matrix(&self.1);
        dual_block(&g, &gx)
    }
    /// `[[a, b], [0, a]]`.
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        dual_block(&G::algebra_to_matrix(&a.0), &G::algebra_to_matrix(&a.1))
    }
    /// `G`'s defect of `g` (the tangent part is an algebra element by
    /// construction); NaN if `ξ` is not finite.
    fn constraint_defect(&self) -> f64 {
        if self.1.is_finite() {
            self.0.constraint_defect()
        } else {
            f64::NAN
        }
    }
    /// `g` renormalised, `ξ` kept: the projection moves `g` by round-off,
    /// and `ξ` is tangent by construction.
    #[inline]
    fn renormalize(&self) -> Self {
        Tangent(self.0.renormalize(), self.1)
    }
}

/// `[[x, y], [0, x]]`.
fn dual_block(x: &DMatrix<f64>, y: &DMatrix<f64>) -> DMatrix<f64> {
    let (r, c) = x.shape();
    let mut m = DMatrix::zeros(2 * r, 2 * c);
    m.view_mut((0, 0), (r, c)).copy_from(x);
    m.view_mut((r, c), (r, c)).copy_from(x);
    m.view_mut((0, c), (r, c)).copy_from(y);
    m
}

impl<G: GroupNumerics> GroupNumerics for Tangent<G> {
    /// `G`'s bound for `a`: `ad_{(a, b)}` is block triangular with `ad_a` on
    /// the diagonal, so it has the spectrum of `ad_a`.
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        G::ad_radius(&a.0)
    }
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        G::within_radius(&a.0, limit)
    }
    /// `G`'s scale for both parts (a tangent vector is measured in the
    /// units of the state's algebra coordinates).
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        let s = self.0.tolerance_scale();
        ProductAlgebra(s, s)
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.0.is_finite() && self.1.is_finite()
    }
}
