//! SL(n): the incompressible (volume-preserving) affine motions of the
//! constrained affinely-rigid body (paper §4).

use nalgebra::{DMatrix, SMatrix};

use super::matrix::{
    commutator, det, dexp_inv_matrix, dexp_matrix, expm, logm, nan_matrix, norm1, traceless_part, Basis, Lu,
};
use super::LieGroup;
use crate::{Error, Result};

type Mat<const N: usize> = SMatrix<f64, N, N>;

/// Largest `|det − 1|` accepted by [`Sl::new`].
pub const SL_TOLERANCE: f64 = 1e-10;
/// Largest `|tr log g|` (= `|ln det g|`) accepted by [`Sl`]'s `log` before
/// projecting the trace away, for well-conditioned `g`; the tolerance used is
/// `SL_LOG_TRACE_TOLERANCE + 16·n·ε·κ₁(g)`, since the determinant of a stored
/// matrix is only defined to about `κ(g)·ε` (a boost of rapidity 10 has
/// `κ₁ ≈ 5e8` and `|ln det| ≈ 1.5e-8` straight out of `exp`).
pub const SL_LOG_TRACE_TOLERANCE: f64 = 1e-8;

/// The special linear group SL(n) = {g : det g = 1}.
///
/// - **Algebra** sl(n): traceless matrices, stored as `SMatrix<f64, N, N>`;
///   `DOF = n² − 1`. Coordinates (`c.len() = n² − 1`): first the `n − 1`
///   diagonal ones `h_k`, `k = 0..n−2`, of the basis `H_k = E_kk − E_{n−1,n−1}`
///   (so `h_k = a_kk` and `a_{n−1,n−1} = −Σ h_k`), then the off-diagonal
///   entries `a_ij`, `i ≠ j`, in row-major order (basis `E_ij`). For n = 2 this
///   is the standard `(H, E, F)` basis: `a = [[h, e], [f, −h]]` ↔ `(h, e, f)`.
///   Functions taking an algebra element use its traceless part.
/// - `exp`, `log`, `Ad`, `dexp`, `dexp⁻¹` are those of [`Gl`](super::Gl)
///   followed by removal of the round-off trace (`det exp(a) = e^{tr a} = 1`
///   up to round-off).
/// - `log` fails with [`Error::Constraint`] if `|tr log g| = |ln det g|`
///   exceeds [`SL_LOG_TRACE_TOLERANCE`]` + 16nεκ₁(g)` (the element has
///   drifted off SL(n) by more than its determinant's round-off).
/// - `renormalize`: `g · det(g)^{−1/n}` (for `det g > 0`);
///   `constraint_defect = |det g − 1|`.
///
/// Matrix representation: the matrix itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sl<const N: usize> {
    m: Mat<N>,
}

/// SL(2).
pub type Sl2 = Sl<2>;
/// SL(3).
pub type Sl3 = Sl<3>;

const fn sl_name(n: usize) -> &'static str {
    match n {
        1 => "SL(1)",
        2 => "SL(2)",
        3 => "SL(3)",
        4 => "SL(4)",
        5 => "SL(5)",
        6 => "SL(6)",
        _ => "SL(n)",
    }
}

/// `g · det(g)^{−1/n}` for `det g > 0`; `g` unchanged otherwise.
fn sl_normalize<const N: usize>(m: &Mat<N>) -> Mat<N> {
    let d = det(m);
    if d > 0.0 && d.is_finite() {
        m * d.powf(-1.0 / N as f64)
    } else {
        *m
    }
}

impl<const N: usize> Sl<N> {
    /// Validates `m`: finite ([`Error::NotFinite`], field `"matrix"`) and
    /// `|det m − 1| ≤` [`SL_TOLERANCE`] ([`Error::Constraint`], field
    /// `"matrix"`); stores `m · det(m)^{−1/n}`.
    pub fn new(m: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("matrix", m.iter())?;
        let d = det(&m);
        let defect = (d - 1.0).abs();
        if defect <= SL_TOLERANCE {
            Ok(Sl { m: sl_normalize(&m) })
        } else {
            Err(Error::Constraint {
                field: "matrix",
                constraint: "det = 1",
                defect,
                tolerance: SL_TOLERANCE,
            })
        }
    }

    /// `m · det(m)^{−1/n}` for any finite `m` with `det m > 0`
    /// ([`Error::NotFinite`] / [`Error::InvalidParameter`], field
    /// `"det(matrix)"`, otherwise).
    pub fn normalized(m: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("matrix", m.iter())?;
        let d = det(&m);
        if d > 0.0 && d.is_finite() {
            Ok(Sl { m: sl_normalize(&m) })
        } else {
            Err(Error::InvalidParameter {
                field: "det(matrix)",
                value: d,
                allowed: "finite and > 0",
            })
        }
    }

    /// Wraps `m` without checks (the caller guarantees `det m = 1`).
    #[inline]
    pub fn new_unchecked(m: SMatrix<f64, N, N>) -> Self {
        Sl { m }
    }

    /// The matrix.
    #[inline]
    pub fn matrix(&self) -> &SMatrix<f64, N, N> {
        &self.m
    }

    /// The determinant (1 up to round-off).
    pub fn det(&self) -> f64 {
        det(&self.m)
    }
}

impl<const N: usize> LieGroup for Sl<N> {
    type Algebra = SMatrix<f64, N, N>;
    const DOF: usize = N * N - 1;
    const NAME: &'static str = sl_name(N);

    #[inline]
    fn identity() -> Self {
        Sl {
            m: Mat::<N>::identity(),
        }
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Sl { m: self.m * rhs.m }
    }
    fn inverse(&self) -> Self {
        Sl {
            m: Lu::new(&self.m).map_or_else(nan_matrix, |lu| lu.inverse()),
        }
    }
    fn exp(a: &Self::Algebra) -> Self {
        Sl {
            m: expm(&traceless_part(a)),
        }
    }
    fn log(&self) -> Result<Self::Algebra> {
        let l = logm(&self.m, Self::NAME)?;
        let tr = l.trace();
        let kappa = Lu::new(&self.m).map_or(f64::INFINITY, |lu| norm1(&self.m) * norm1(&lu.inverse()));
        let tolerance = SL_LOG_TRACE_TOLERANCE + 16.0 * N as f64 * f64::EPSILON * kappa;
        if tr.abs().is_nan() || tr.abs() > tolerance {
            return Err(Error::Constraint {
                field: "SL element",
                constraint: "det = 1 (|tr log g| = |ln det g|)",
                defect: tr.abs(),
                tolerance,
            });
        }
        Ok(traceless_part(&l))
    }
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        match Lu::new(&self.m) {
            Some(lu) => traceless_part(&(self.m * a * lu.inverse())),
            None => nan_matrix(),
        }
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        traceless_part(&commutator(a, b))
    }
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        traceless_part(&dexp_matrix(&traceless_part(a), &traceless_part(v), false))
    }
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        traceless_part(&dexp_inv_matrix(
            &traceless_part(a),
            &traceless_part(v),
            Basis::Full,
            false,
        ))
    }
    /// `(h₀, …, h_{n−2}, off-diagonal row-major)`; missing coordinates are 0.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        let at = |k: usize| c.get(k).copied().unwrap_or(0.0);
        let mut a = Mat::<N>::zeros();
        let mut last = 0.0;
        for k in 0..N - 1 {
            a[(k, k)] = at(k);
            last -= at(k);
        }
        a[(N - 1, N - 1)] = last;
        let mut k = N - 1;
        for i in 0..N {
            for j in 0..N {
                if i != j {
                    a[(i, j)] = at(k);
                    k += 1;
                }
            }
        }
        a
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        let a = traceless_part(a);
        let mut c = Vec::with_capacity(N * N - 1);
        c.extend((0..N - 1).map(|k| a[(k, k)]));
        for i in 0..N {
            for j in 0..N {
                if i != j {
                    c.push(a[(i, j)]);
                }
            }
        }
        c
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(N, N, self.m.as_slice())
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let a = traceless_part(a);
        DMatrix::from_column_slice(N, N, a.as_slice())
    }
    /// `|det g − 1|` (`+∞` if not finite).
    fn constraint_defect(&self) -> f64 {
        let d = det(&self.m);
        if d.is_finite() {
            (d - 1.0).abs()
        } else {
            f64::INFINITY
        }
    }
    /// `g · det(g)^{−1/n}` (unchanged if `det g ≤ 0` or not finite).
    fn renormalize(&self) -> Self {
        Sl {
            m: sl_normalize(&self.m),
        }
    }
}
