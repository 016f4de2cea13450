//! The micromaterial inertia `J` of an affine body, and the small-matrix
//! helpers of the equations (inverse, `tr(AB)`).

use nalgebra::{DMatrix, SVector};

use super::Mat;
use crate::body::check_inertia;
use crate::lie::matrix::Lu;
use crate::{Error, Result};

/// The micromaterial inertia `J` (symmetric positive definite) with the data
/// the equations need: `J⁻¹` and the principal axes and moments
/// (`J = V diag(j) Vᵀ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia<const N: usize> {
    pub(super) j: Mat<N>,
    pub(super) j_inv: Mat<N>,
    axes: Mat<N>,
    moments: SVector<f64, N>,
}

impl<const N: usize> Inertia<N> {
    /// Validates `j` ([`check_inertia`]: finite, symmetric, positive definite;
    /// errors name the field `"J"`) and precomputes `J⁻¹` and the principal
    /// axes.
    pub fn new(j: &Mat<N>) -> Result<Self> {
        let j = check_inertia(j)?;
        let j_inv = inverse(&j).ok_or(Error::Constraint {
            field: "J",
            constraint: "J invertible",
            defect: f64::INFINITY,
            tolerance: 0.0,
        })?;
        let eig = DMatrix::from_column_slice(N, N, j.as_slice()).symmetric_eigen();
        let axes = Mat::<N>::from_column_slice(eig.eigenvectors.as_slice());
        let moments = SVector::<f64, N>::from_column_slice(eig.eigenvalues.as_slice());
        Ok(Self { j, j_inv: (j_inv + j_inv.transpose()) * 0.5, axes, moments })
    }
    /// `J`.
    pub fn matrix(&self) -> &Mat<N> {
        &self.j
    }
    /// `J⁻¹`.
    pub fn inverse(&self) -> &Mat<N> {
        &self.j_inv
    }
    /// Principal axes `V` (orthogonal, columns), `J = V diag(j) Vᵀ`.
    pub fn axes(&self) -> &Mat<N> {
        &self.axes
    }
    /// Principal moments `j` (eigenvalues of `J`).
    pub fn moments(&self) -> &SVector<f64, N> {
        &self.moments
    }
    /// The skew `ω` with `Jω + ωJ = c` for skew `c` (the inertia operator of
    /// a rotating body, inverted in the principal axes:
    /// `ω̃_ij = c̃_ij/(j_i + j_j)`).
    pub fn solve_rotational(&self, c: &Mat<N>) -> Mat<N> {
        let ct = self.axes.transpose() * c * self.axes;
        let w = Mat::<N>::from_fn(|i, k| if i == k { 0.0 } else { ct[(i, k)] / (self.moments[i] + self.moments[k]) });
        self.axes * w * self.axes.transpose()
    }
}

/// `m⁻¹` (closed form for n ≤ 3, LU otherwise); `None` when `m` is singular
/// or not finite.
pub fn inverse<const N: usize>(m: &Mat<N>) -> Option<Mat<N>> {
    let mut out = Mat::<N>::zeros();
    match N {
        1 => {
            let d = m[(0, 0)];
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            out[(0, 0)] = 1.0 / d;
        }
        2 => {
            let d = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            let r = 1.0 / d;
            out[(0, 0)] = m[(1, 1)] * r;
            out[(0, 1)] = -m[(0, 1)] * r;
            out[(1, 0)] = -m[(1, 0)] * r;
            out[(1, 1)] = m[(0, 0)] * r;
        }
        3 => {
            let c = |i: usize, k: usize| {
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                m[(i1, k1)] * m[(i2, k2)] - m[(i1, k2)] * m[(i2, k1)]
            };
            let (c00, c01, c02) = (c(0, 0), c(0, 1), c(0, 2));
            let d = m[(0, 0)] * c00 + m[(0, 1)] * c01 + m[(0, 2)] * c02;
            if d == 0.0 || !d.is_finite() {
                return None;
            }
            let r = 1.0 / d;
            for i in 0..3 {
                for k in 0..3 {
                    out[(k, i)] = c(i, k) * r;
                }
            }
        }
        _ => return Lu::new(m).map(|lu| lu.inverse()),
    }
    if out.iter().all(|x| x.is_finite()) {
        Some(out)
    } else {
        None
    }
}

/// `tr(A·B)` without forming the product.
#[inline]
pub fn trace_of_product<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> f64 {
    a.component_mul(&b.transpose()).sum()
}
