//! Matrix norms: the 1-norm (it selects the Padé degree and the scaling of
//! the exponential and the logarithm), the largest absolute entry (error
//! measures and convergence tests) and the Frobenius norm (it bounds
//! `‖ad_A‖` in `dexp` and measures the defect of the polar iteration).

use super::Mat;

/// Matrix 1-norm (largest absolute column sum).
pub fn norm1<const N: usize>(m: &Mat<N>) -> f64 {
    (0..N)
        .map(|j| (0..N).map(|i| m[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Largest absolute entry.
pub fn amax<const N: usize>(m: &Mat<N>) -> f64 {
    m.iter().fold(0.0, |a, x| a.max(x.abs()))
}

/// Frobenius norm.
#[inline]
pub(super) fn fro<const N: usize>(m: &Mat<N>) -> f64 {
    m.norm()
}
