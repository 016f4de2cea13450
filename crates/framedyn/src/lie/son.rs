//! SO(n) for general `n`: the fibre of the infinitesimal gyroscope in `n`
//! dimensions. (SO(2), SO(3) and SO(4) also have dedicated closed-form types;
//! this one works for every `n` with the matrix functions of `lie/matrix/`,
//! which [`Gl`](super::Gl) uses too.)

use nalgebra::{DMatrix, SMatrix};

use super::matrix::{
    commutator, det, dexp_inv_matrix, dexp_matrix, expm, logm, orthogonality_defect, polar_factor, skew_index,
    skew_part, Basis,
};
use super::LieGroup;
use crate::{Error, Result};

type Mat<const N: usize> = SMatrix<f64, N, N>;

/// Largest orthogonality defect `max(max|RᵀR − I|, |det R − 1|)` accepted by
/// [`SoN::new`].
pub const SO_TOLERANCE: f64 = 1e-10;

/// The rotation group SO(n) = {R : RᵀR = I, det R = 1} for any `n`.
///
/// - **Algebra** so(n): skew matrices, stored as `SMatrix<f64, N, N>`;
///   `DOF = n(n−1)/2`. Coordinates: `c_ij`, `i < j` in the lexicographic order
///   (0,1), (0,2), …, (0,n−1), (1,2), …, (n−2,n−1), of the basis
///   `E_ij − E_ji`, i.e. `ω = Σ_{i<j} c_ij (E_ij − E_ji)`, `c_ij = ω_ij`.
///   (For n = 3 this is `(ω₀₁, ω₀₂, ω₁₂) = (−ω_z, ω_y, −ω_x)` in terms of the
///   usual hat map; the closed-form `So3` type uses the hat map.) Functions
///   taking an algebra element use its skew part `(ω − ωᵀ)/2`.
/// - `exp`: Padé scaling and squaring (`r_m(ω)` is orthogonal in exact
///   arithmetic since `q_m(ω) = p_m(ω)ᵀ`), then one polar (Björck–Bowie)
///   step removing the round-off drift of the squarings: orthogonal to a few
///   ε for any `ω`.
/// - `log`: principal logarithm (all rotation angles in [0, π)), from the
///   matrix logarithm of [`Gl`](super::Gl) projected onto so(n) (which drops
///   the part of the round-off that leaves SO(n), amplified by θ/sin θ);
///   [`Error::LogUndefined`] if some angle is π, or within 8ε of it (the f64
///   `exp(πJ)` included). Measured on correctly rounded rotations by
///   π − δ, δ down to 1e-6: ≤ 2.6ε (SO(2), SO(3)); for SO(4) with two angles
///   near π the error follows the condition number `φ/(2 sin(φ/2))`,
///   `φ = θ₁ + θ₂ → 2π`, of dexp⁻¹ (≤ 0.26ε times it).
/// - `dexp`: exact scaling and doubling with orthogonal `exp(ω/2^k)`;
///   `dexp⁻¹`: Bernoulli series for `2‖ω‖_F ≤ 1`, else an exact solve in the
///   `n(n−1)/2`-dimensional basis, valid while no two rotation angles
///   `θ_i + θ_j` reach 2π (in particular for every `ω` in the domain of `log`).
/// - `renormalize`: the polar factor (nearest orthogonal matrix in the
///   Frobenius norm): Newton–Schulz/Björck–Bowie steps `R ← R − R(RᵀR − I)/2`
///   from near-orthogonal input (one step, two products, after a
///   composition), scaled Newton `R ← (γR + R⁻ᵀ/γ)/2` from far away, SVD with
///   the orientation fixed for `det ≤ 0` (Å. Björck, C. Bowie, SIAM J.
///   Numer. Anal. 8 (1971) 358–364; N. J. Higham, *Functions of Matrices*,
///   §8.6, §8.9). `constraint_defect = max(max|RᵀR − I|, |det R − 1|)`.
///
/// Matrix representation: `R` itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoN<const N: usize> {
    r: Mat<N>,
}

const fn so_name(n: usize) -> &'static str {
    match n {
        1 => "SO(1)",
        2 => "SO(2)",
        3 => "SO(3)",
        4 => "SO(4)",
        5 => "SO(5)",
        6 => "SO(6)",
        7 => "SO(7)",
        8 => "SO(8)",
        _ => "SO(n)",
    }
}

impl<const N: usize> SoN<N> {
    /// Validates `r`: finite ([`Error::NotFinite`], field `"rotation"`), and
    /// `max(max|RᵀR − I|, |det R − 1|) ≤` [`SO_TOLERANCE`]
    /// ([`Error::Constraint`], field `"rotation"`); the stored matrix is the
    /// polar factor of `r` (exactly orthogonal to round-off).
    pub fn new(r: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("rotation", r.iter())?;
        let defect = so_defect(&r);
        if defect <= SO_TOLERANCE {
            Ok(SoN { r: polar_factor(&r) })
        } else {
            Err(Error::Constraint {
                field: "rotation",
                constraint: "RᵀR = I, det R = 1",
                defect,
                tolerance: SO_TOLERANCE,
            })
        }
    }

    /// The rotation nearest to `m` (its orthogonal polar factor), for any
    /// finite `m` with `det m > 0` ([`Error::NotFinite`] / [`Error::InvalidParameter`]
    /// with field `"det(matrix)"` otherwise).
    pub fn nearest(m: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("matrix", m.iter())?;
        let d = det(&m);
        if d > 0.0 && d.is_finite() {
            Ok(SoN { r: polar_factor(&m) })
        } else {
            Err(Error::InvalidParameter {
                field: "det(matrix)",
                value: d,
                allowed: "finite and > 0",
            })
        }
    }

    /// Wraps `r` without checks (the caller guarantees `r ∈ SO(n)`).
    #[inline]
    pub fn new_unchecked(r: SMatrix<f64, N, N>) -> Self {
        SoN { r }
    }

    /// The rotation matrix.
    #[inline]
    pub fn matrix(&self) -> &SMatrix<f64, N, N> {
        &self.r
    }
}

/// `max(max|RᵀR − I|, |det R − 1|)`.
pub(crate) fn so_defect<const N: usize>(r: &Mat<N>) -> f64 {
    if !r.iter().all(|x| x.is_finite()) {
        return f64::INFINITY;
    }
    let d = det(r);
    let dd = if d.is_finite() { (d - 1.0).abs() } else { f64::INFINITY };
    orthogonality_defect(r).max(dd)
}

/// `exp` on so(n): Padé scaling and squaring of the skew part, then the polar factor.
pub(crate) fn so_exp<const N: usize>(w: &Mat<N>) -> Mat<N> {
    let w = skew_part(w);
    polar_factor(&expm(&w))
}

/// Principal `log` on SO(n), projected onto so(n).
pub(crate) fn so_log<const N: usize>(r: &Mat<N>, group: &'static str) -> Result<Mat<N>> {
    Ok(skew_part(&logm(r, group)?))
}

impl<const N: usize> LieGroup for SoN<N> {
    type Algebra = SMatrix<f64, N, N>;
    const DOF: usize = N * (N - 1) / 2;
    const NAME: &'static str = so_name(N);

    #[inline]
    fn identity() -> Self {
        SoN {
            r: Mat::<N>::identity(),
        }
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        SoN { r: self.r * rhs.r }
    }
    /// The transpose.
    #[inline]
    fn inverse(&self) -> Self {
        SoN { r: self.r.transpose() }
    }
    fn exp(a: &Self::Algebra) -> Self {
        SoN { r: so_exp(a) }
    }
    fn log(&self) -> Result<Self::Algebra> {
        so_log(&self.r, Self::NAME)
    }
    /// `R ω Rᵀ` (skew part).
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        skew_part(&(self.r * skew_part(a) * self.r.transpose()))
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        skew_part(&commutator(a, b))
    }
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        skew_part(&dexp_matrix(&skew_part(a), &skew_part(v), true))
    }
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        skew_part(&dexp_inv_matrix(&skew_part(a), &skew_part(v), Basis::Skew, true))
    }
    /// `ω = Σ_{i<j} c_ij (E_ij − E_ji)` (lexicographic `i < j`; missing
    /// coordinates are 0).
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        let mut w = Mat::<N>::zeros();
        for k in 0..Self::DOF {
            let (i, j) = skew_index::<N>(k);
            let v = c.get(k).copied().unwrap_or(0.0);
            w[(i, j)] = v;
            w[(j, i)] = -v;
        }
        w
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        (0..Self::DOF)
            .map(|k| {
                let (i, j) = skew_index::<N>(k);
                0.5 * (a[(i, j)] - a[(j, i)])
            })
            .collect()
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(N, N, self.r.as_slice())
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let w = skew_part(a);
        DMatrix::from_column_slice(N, N, w.as_slice())
    }
    /// `max(max|RᵀR − I|, |det R − 1|)` (`+∞` for non-finite entries).
    fn constraint_defect(&self) -> f64 {
        so_defect(&self.r)
    }
    /// The orthogonal polar factor (nearest rotation in the Frobenius norm);
    /// from round-off-level drift one Björck–Bowie step (two products).
    fn renormalize(&self) -> Self {
        SoN {
            r: polar_factor(&self.r),
        }
    }
}
