//! What the integrators need to know about a group beyond [`LieGroup`]: a
//! bound on the spectral radius of `ad_a` (the `dexp⁻¹` radius guard) and
//! the reference magnitudes that give relative tolerances their meaning.

use nalgebra::SMatrix;

use crate::dynamics::affine::{Additive, MatrixAlgebra};
use crate::lie::{AlgebraVector, Co, Gl, LieGroup, Product, Rn, Sl, So12, So2, So3, So4, SoN, Su2};

/// Numerical data of a state group used by the integrators.
///
/// Implemented for every group of [`crate::lie`], for the additive momentum
/// spaces [`Additive`] of the affine bodies, and for direct products.
/// (Proposed for [`LieGroup`] itself, with these as defaults.)
pub trait GroupNumerics: LieGroup {
    /// An upper bound of the spectral radius `ρ(ad_a)` of `ad_a = [a, ·]`.
    ///
    /// The Bernoulli series of `dexp⁻¹_a` converges for `ρ(ad_a) < 2π`, and
    /// the closed forms of `dexp⁻¹` are singular where `ad_a` has an
    /// eigenvalue `±2πi`; the integrators compare this bound with their radius
    /// guard. Abelian groups return 0.
    fn ad_radius(a: &Self::Algebra) -> f64;

    /// `ad_radius(a) ≤ limit`, decided cheaply where possible (the radius
    /// guard runs once per stage): groups whose bound is a norm compare
    /// squares instead of taking the square root. Agrees with
    /// `ad_radius(a) <= limit` up to rounding at the boundary (the guard
    /// evaluates [`GroupNumerics::ad_radius`] itself only when this fails,
    /// to report the bound). The default evaluates `ad_radius`.
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        Self::ad_radius(a) <= limit
    }

    /// Reference magnitude of each stored algebra component at the state
    /// `self`, against which relative tolerances are measured.
    ///
    /// A local error `e ∈ 𝔤` is left-trivialised: the computed state is
    /// `y·exp(e)` with `y` the exact one. For an additive factor ℝᵏ
    /// (momenta, velocities, angle coordinates) `e` is the absolute error of the
    /// coordinates, and the reference magnitude is `|yᵢ|`, the size of the
    /// coordinate itself. For every other factor (rotation, Lorentz, linear
    /// groups) `e` is already a relative error of the group element —
    /// `‖y·exp(e) − y‖ ≤ ‖y‖·‖e‖(1 + O(‖e‖))` in any submultiplicative norm of
    /// the defining representation, and `|e|` is the rotation angle on SO(n)
    /// — so the reference magnitude is 1.
    fn tolerance_scale(&self) -> Self::Algebra;

    /// True if every stored number of the element is finite (a cheap test,
    /// run after every step: an overflow in `exp` or in the product is a
    /// failure, not a state).
    fn is_finite(&self) -> bool;
}

#[inline]
fn all_finite<'a>(v: impl IntoIterator<Item = &'a f64>) -> bool {
    v.into_iter().all(|x| x.is_finite())
}

/// The algebra element with every stored component equal to 1.
#[inline]
pub fn ones<A: AlgebraVector>() -> A {
    let mut a = A::zero();
    for i in 0..A::LEN {
        a.set(i, 1.0);
    }
    a
}

impl GroupNumerics for So2 {
    /// 0: SO(2) is abelian.
    #[inline]
    fn ad_radius(_a: &Self::Algebra) -> f64 {
        0.0
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.cos().is_finite() && self.sin().is_finite()
    }
}

impl GroupNumerics for So3 {
    /// `|ω|`: `ad_ω = hat(ω)` has eigenvalues `0, ±i|ω|`.
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        a.norm()
    }
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        a.norm_squared() <= limit * limit
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

impl GroupNumerics for Su2 {
    /// `|k|`: the bracket is the cross product, as on SO(3).
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        a.norm()
    }
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        a.norm_squared() <= limit * limit
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.quaternion().iter())
    }
}

impl GroupNumerics for So12 {
    /// `√|s|`, `s = ω² − b₁² − b₂²` the Casimir: `ad_X` is equivalent to the
    /// defining representation, eigenvalues `0, ±√(−s)`.
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        (a[2] * a[2] - a[0] * a[0] - a[1] * a[1]).abs().sqrt()
    }
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        (a[2] * a[2] - a[0] * a[0] - a[1] * a[1]).abs() <= limit * limit
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

impl GroupNumerics for So4 {
    /// `max(|ω + β|, |ω − β|)`: the eigenvalues of `ad_X` are `0, ±2i|a|,
    /// ±2i|b|` with `a = (ω + β)/2`, `b = (ω − β)/2` (see [`So4`]).
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        let (mut p, mut m) = (0.0f64, 0.0f64);
        for i in 0..3 {
            p += (a[3 + i] + a[i]).powi(2);
            m += (a[3 + i] - a[i]).powi(2);
        }
        p.max(m).sqrt()
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

/// Frobenius norm of the skew part `(a − aᵀ)/2`.
fn skew_frobenius<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    ((a - a.transpose()) * 0.5).norm()
}

impl<const N: usize> GroupNumerics for SoN<N> {
    /// For the skew part `ω` with rotation angles `θ_k` (`‖ω‖_F² = 2 Σ θ_k²`):
    /// 0 for n ≤ 2 (abelian), `θ = ‖ω‖_F/√2` for n = 3 (`ad_ω` has eigenvalues
    /// `0, ±iθ`), and `2 max θ_k ≤ √2·‖ω‖_F` for n ≥ 4 (eigenvalues `±i(θ_j ± θ_k)`).
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        match N {
            0..=2 => 0.0,
            3 => skew_frobenius(a) * std::f64::consts::FRAC_1_SQRT_2,
            _ => std::f64::consts::SQRT_2 * skew_frobenius(a),
        }
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

impl<const N: usize> GroupNumerics for Co<N> {
    /// That of [`SoN`] for the skew part: the dilatation `κI` is central.
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        SoN::<N>::ad_radius(&((a - a.transpose()) * 0.5))
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.ln_lambda().is_finite() && all_finite(self.rotation().matrix().iter())
    }
}

/// `ρ(ad_a)` for gl(n): the trace part is central and the eigenvalues of
/// `ad_a` are the differences `λᵢ − λⱼ` of those of `a₀ = a − (tr a/n) I`.
/// For n = 2 exactly `2√|det a₀|` (`a₀` has eigenvalues `±√(−det a₀)`); for
/// n ≥ 3 the bound `2‖a₀‖_F` (`|λ| ≤ ‖a₀‖₂ ≤ ‖a₀‖_F`), tight for normal `a₀`
/// and conservative for far-from-normal ones (nilpotent `a` has `ρ = 0`).
fn gl_ad_radius<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    let mean = a.trace() / N as f64;
    let a0 = a - SMatrix::<f64, N, N>::identity() * mean;
    if N == 2 {
        let det = a0[(0, 0)] * a0[(1, 1)] - a0[(0, 1)] * a0[(1, 0)];
        2.0 * det.abs().sqrt()
    } else {
        2.0 * a0.norm()
    }
}

impl<const N: usize> GroupNumerics for Gl<N> {
    /// See [`Gl`]'s algebra: exact for n = 2, `2‖a₀‖_F` for n ≥ 3, with
    /// `a₀` the traceless part (the trace part is central).
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        gl_ad_radius(a)
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

impl<const N: usize> GroupNumerics for Sl<N> {
    /// As for [`Gl`]: exact for n = 2, `2‖a₀‖_F` for n ≥ 3.
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        gl_ad_radius(a)
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        ones()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.matrix().iter())
    }
}

impl<const K: usize> GroupNumerics for Rn<K> {
    /// 0: ℝᵏ is abelian (`dexp⁻¹` is the identity).
    #[inline]
    fn ad_radius(_a: &Self::Algebra) -> f64 {
        0.0
    }
    /// `|yᵢ|`: the coordinates themselves.
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        self.0.abs()
    }
    #[inline]
    fn is_finite(&self) -> bool {
        all_finite(self.0.iter())
    }
}

impl<G: MatrixAlgebra> GroupNumerics for Additive<G> {
    /// 0: a vector space under addition.
    #[inline]
    fn ad_radius(_a: &Self::Algebra) -> f64 {
        0.0
    }
    /// `|aᵢ|`: the stored components themselves (like [`Rn`]).
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        let mut s = self.0;
        for i in 0..<Self::Algebra as AlgebraVector>::LEN {
            s.set(i, self.0.get(i).abs());
        }
        s
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.0.is_finite()
    }
}

impl<A: GroupNumerics, B: GroupNumerics> GroupNumerics for Product<A, B> {
    /// The larger of the two factors' bounds (`ad` is block diagonal);
    /// NaN if either is NaN (`f64::max` would drop it, and a non-finite
    /// argument must fail the radius guard, not pass as radius 0).
    #[inline]
    fn ad_radius(a: &Self::Algebra) -> f64 {
        let (x, y) = (A::ad_radius(&a.0), B::ad_radius(&a.1));
        if x.is_nan() || y.is_nan() {
            f64::NAN
        } else {
            x.max(y)
        }
    }
    #[inline]
    fn within_radius(a: &Self::Algebra, limit: f64) -> bool {
        A::within_radius(&a.0, limit) && B::within_radius(&a.1, limit)
    }
    #[inline]
    fn tolerance_scale(&self) -> Self::Algebra {
        crate::lie::ProductAlgebra(self.0.tolerance_scale(), self.1.tolerance_scale())
    }
    #[inline]
    fn is_finite(&self) -> bool {
        self.0.is_finite() && self.1.is_finite()
    }
}
