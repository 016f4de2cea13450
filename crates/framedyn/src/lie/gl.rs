//! GL⁺(n): orientation-preserving invertible matrices ([`Gl`]).
//!
//! Its `exp`, `log`, `dexp` and `dexp⁻¹` are the fixed-size matrix functions
//! of the crate-internal module `lie::matrix` (directory `lie/matrix/`, one
//! file per function family: LU, exponential, `dexp`/`dexp⁻¹`, real Schur
//! form, square root, logarithm, polar factor), which it shares with
//! [`Sl`](super::Sl), [`SoN`](super::SoN) and [`Co`](super::Co).

use nalgebra::{DMatrix, SMatrix};

use super::matrix::{amax, commutator, det, dexp_inv_matrix, dexp_matrix, expm, logm, nan_matrix, Basis, Lu, Mat};
use super::LieGroup;
use crate::{Error, Result};

/// The identity component GL⁺(n) of the general linear group: real `n×n`
/// matrices with `det > 0` — the fibre of the affinely-rigid body (the
/// configuration `φ` of the body frame `e = E φ`, paper §4).
///
/// - **Algebra** gl(n): all `n×n` matrices (`SMatrix<f64, N, N>`), `DOF = n²`.
///   Coordinates ([`LieGroup::algebra_coords`]) are the entries in
///   **row-major** order `a₀₀, a₀₁, …, a₀,ₙ₋₁, a₁₀, …` (note: the
///   [`AlgebraVector`](super::AlgebraVector) components of an `SMatrix` follow
///   nalgebra's column-major storage instead).
/// - `exp`: scaling and squaring with the \[m/m\] Padé approximant,
///   `m ∈ {3, 5, 7, 9, 13}` chosen by `‖A‖₁` against Higham's θ_m \[H05\].
///   Measured against 256-bit closed forms for `‖A‖` from 1e-12 to 100
///   (tests `exp_accuracy_closed_forms`): relative error ≤ 1.1ε·max(1, ‖A‖_F)
///   for rotation generators, ≤ 1.8ε·max(1, ‖A‖_F) for `P D P⁻¹`, exact for
///   nilpotent `A`, ≤ 7.6ε·‖A‖_F for boosts `[[0, b], [b, 0]]` (the
///   denominator `q₁₃(A)` cancels like `e^{‖A‖}` for positive real
///   eigenvalues, inherent to \[H05\]); `exp` is conditioned like `‖A‖`, so
///   "a few ulp" holds for `‖A‖ ≲ 1`.
/// - `log`: principal branch (all eigenvalues `|Im λ| < π`), inverse scaling
///   and squaring \[AH12\]: a real Schur form (own Francis QR on the stack)
///   gives the spectrum ([`Error::LogUndefined`] for an eigenvalue on, or
///   within 8ε of, the closed negative real axis); square roots by the
///   product Denman–Beavers iteration \[CHKL01\] when every `|arg λ| ≤ 2.9`
///   and `κ₁ ≤ 30` (a few ε there), else by the real Schur method (closed-form
///   2×2 blocks, no cancellation near angle π, backward error independent of
///   κ); `Z = R − I` is carried without cancellation; Padé `log(1 + x)` in
///   partial fractions \[H01\]. [`Error::NoConvergence`] if the Schur form
///   does not converge.
/// - `bracket` = commutator, `Ad_g a = g a g⁻¹`.
/// - `dexp`: exact "scaling and doubling", `φ(ad_A) = ∏_{k=1}^s ½(Ad_{exp(A/2^k)} + 1)·φ(ad_{A/2^s})`
///   from `φ(2z) = φ(z)(e^z + 1)/2`, Taylor series for the last factor
///   (`‖ad_{A/2^s}‖ ≤ 1`); valid for every `a` (dexp is entire); measured
///   ≤ 3ε up to ‖a‖ = 1, ≤ 18ε at ‖a‖ = 4 against the 256-bit block
///   exponential `exp([[A, V], [0, A]])`.
/// - `dexp⁻¹`: the Bernoulli series `Σ_{k≤20} B_k/k! ad_a^k` for
///   `2‖a‖_F ≤ 1` (remainder < 5e-18), else `dexp_a` assembled as an
///   `n²×n²` matrix and solved by Gaussian elimination with partial pivoting
///   (stack storage): no radius restriction, valid wherever `dexp_a` is
///   invertible (no eigenvalue of `ad_a` in `2πiℤ∖{0}`, e.g. all `a` with
///   `|Im λ| < π`); NaN where singular to working precision.
/// - No constraint beyond `det > 0`: [`renormalize`](LieGroup::renormalize)
///   is the identity.
///
/// Matrix representation: the matrix itself.
///
/// References: \[H05\] N. J. Higham, *The scaling and squaring method for
/// the matrix exponential revisited*, SIAM J. Matrix Anal. Appl. 26 (2005)
/// 1179–1193. \[AH12\] A. H. Al-Mohy, N. J. Higham, *Improved inverse
/// scaling and squaring algorithms for the matrix logarithm*, SIAM J. Sci.
/// Comput. 34 (2012) C153–C169. \[CHKL01\] S. H. Cheng, N. J. Higham,
/// C. S. Kenney, A. J. Laub, *Approximating the logarithm of a matrix to
/// specified accuracy*, SIAM J. Matrix Anal. Appl. 22 (2001) 1112–1125.
/// \[H01\] N. J. Higham, *Evaluating Padé approximants of the matrix
/// logarithm*, SIAM J. Matrix Anal. Appl. 22 (2001) 1126–1135. N. J. Higham,
/// *Functions of Matrices*, SIAM 2008 (§6.2 real Schur square root, §8 polar
/// decomposition, §11 logarithm). G. H. Golub, C. F. Van Loan, *Matrix
/// Computations*, 4th ed. 2013 (§7.5 Francis QR). A. Iserles,
/// H. Munthe-Kaas, S. Nørsett, A. Zanna, *Lie-group methods*, Acta Numerica 9
/// (2000) 215–365 (dexp, dexp⁻¹).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gl<const N: usize> {
    m: Mat<N>,
}

/// GL⁺(2).
pub type Gl2 = Gl<2>;
/// GL⁺(3).
pub type Gl3 = Gl<3>;

const fn gl_name(n: usize) -> &'static str {
    match n {
        1 => "GL+(1)",
        2 => "GL+(2)",
        3 => "GL+(3)",
        4 => "GL+(4)",
        5 => "GL+(5)",
        6 => "GL+(6)",
        _ => "GL+(n)",
    }
}

impl<const N: usize> Gl<N> {
    /// Validates and wraps `m`: every entry finite ([`Error::NotFinite`],
    /// field `"matrix"`) and `det m > 0` ([`Error::InvalidParameter`], field
    /// `"det(matrix)"`, with the determinant as the value).
    pub fn new(m: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("matrix", m.iter())?;
        let d = det(&m);
        if d > 0.0 && d.is_finite() {
            Ok(Gl { m })
        } else {
            Err(Error::InvalidParameter {
                field: "det(matrix)",
                value: d,
                allowed: "finite and > 0 (orientation-preserving)",
            })
        }
    }

    /// Wraps `m` without checks (the caller guarantees finite entries and
    /// `det m > 0`).
    #[inline]
    pub fn new_unchecked(m: SMatrix<f64, N, N>) -> Self {
        Gl { m }
    }

    /// The matrix.
    #[inline]
    pub fn matrix(&self) -> &SMatrix<f64, N, N> {
        &self.m
    }

    /// The determinant (by LU with partial pivoting).
    pub fn det(&self) -> f64 {
        det(&self.m)
    }
}

impl<const N: usize> LieGroup for Gl<N> {
    type Algebra = SMatrix<f64, N, N>;
    const DOF: usize = N * N;
    const NAME: &'static str = gl_name(N);

    #[inline]
    fn identity() -> Self {
        Gl {
            m: Mat::<N>::identity(),
        }
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Gl { m: self.m * rhs.m }
    }
    fn inverse(&self) -> Self {
        Gl {
            m: Lu::new(&self.m).map_or_else(nan_matrix, |lu| lu.inverse()),
        }
    }
    fn exp(a: &Self::Algebra) -> Self {
        Gl { m: expm(a) }
    }
    fn log(&self) -> Result<Self::Algebra> {
        logm(&self.m, Self::NAME)
    }
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        match Lu::new(&self.m) {
            Some(lu) => self.m * a * lu.inverse(),
            None => nan_matrix(),
        }
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        commutator(a, b)
    }
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_matrix(a, v, false)
    }
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_inv_matrix(a, v, Basis::Full, false)
    }
    /// Row-major entries (`c.len() == N²`; missing entries are 0).
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        Mat::<N>::from_fn(|i, j| c.get(i * N + j).copied().unwrap_or(0.0))
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        (0..N * N).map(|k| a[(k / N, k % N)]).collect()
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(N, N, self.m.as_slice())
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        DMatrix::from_column_slice(N, N, a.as_slice())
    }
    /// 0 on GL⁺(n) (finite, `det > 0`); `1 + |det|/max|mᵢⱼ|ⁿ ≥ 1` if
    /// `det ≤ 0` (the element has left the group, no round-off can do this);
    /// `+∞` for non-finite entries.
    fn constraint_defect(&self) -> f64 {
        if !self.m.iter().all(|x| x.is_finite()) {
            return f64::INFINITY;
        }
        let d = det(&self.m);
        if d > 0.0 {
            0.0
        } else {
            let s = amax(&self.m);
            1.0 + if s > 0.0 { d.abs() / s.powi(N as i32) } else { 0.0 }
        }
    }
    /// The identity map: GL⁺(n) is open in the matrices, there is no
    /// constraint to restore.
    #[inline]
    fn renormalize(&self) -> Self {
        *self
    }
}
