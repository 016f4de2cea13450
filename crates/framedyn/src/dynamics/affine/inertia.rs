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
pub(crate) fn inverse<const N: usize>(m: &Mat<N>) -> Option<Mat<N>> {
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
pub(crate) fn trace_of_product<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> f64 {
    a.component_mul(&b.transpose()).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xorshift(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn check_inverse<const N: usize>(rng: &mut impl FnMut() -> f64) {
        for _ in 0..200 {
            let m = Mat::<N>::identity() + Mat::<N>::from_fn(|_, _| rng()) * (0.6 / N as f64);
            let inv = inverse(&m).expect("invertible");
            let err = (m * inv - Mat::<N>::identity()).amax();
            assert!(err < 1e-14, "N = {N}: |m m⁻¹ − I| = {err:e}");
        }
        let mut singular = Mat::<N>::identity();
        singular[(0, 0)] = 0.0;
        for i in 0..N {
            singular[(0, i)] = 0.0;
        }
        assert!(inverse(&singular).is_none());
        assert!(inverse(&Mat::<N>::from_element(f64::NAN)).is_none());
    }

    /// The closed-form inverses (n ≤ 3) and the LU fallback (n = 4).
    #[test]
    fn inverse_closed_forms() {
        let mut rng = xorshift(0x1234_5678_9abc_def1);
        check_inverse::<1>(&mut rng);
        check_inverse::<2>(&mut rng);
        check_inverse::<3>(&mut rng);
        check_inverse::<4>(&mut rng);
    }

    /// `tr(AB)` and the inverse of the rotational inertia operator
    /// `ω ↦ Jω + ωJ` on skew matrices.
    #[test]
    fn trace_of_product_and_rotational_solve() {
        let mut rng = xorshift(0x0bad_cafe_f00d_1234);
        for _ in 0..100 {
            let a = Mat::<3>::from_fn(|_, _| rng());
            let b = Mat::<3>::from_fn(|_, _| rng());
            assert!((trace_of_product(&a, &b) - (a * b).trace()).abs() < 1e-15);
            let l = Mat::<3>::from_fn(|_, _| rng());
            let inertia = Inertia::new(&(Mat::<3>::identity() * 0.1 + l * l.transpose() * 0.2)).unwrap();
            let c = Mat::<3>::from_fn(|_, _| rng());
            let c = c - c.transpose();
            let w = inertia.solve_rotational(&c);
            let j = inertia.matrix();
            assert!((j * w + w * j - c).amax() < 1e-13, "Jω + ωJ ≠ c");
            assert!((w + w.transpose()).amax() < 1e-14, "ω not skew");
            assert!((inertia.inverse() * j - Mat::<3>::identity()).amax() < 1e-13);
        }
    }

    /// `Inertia::new` rejects what `check_inertia` rejects, with the field `"J"`.
    #[test]
    fn inertia_validation() {
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, -1.0)), Err(Error::Constraint { field: "J", .. })));
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.5, 0.0, 1.0)), Err(Error::Constraint { field: "J", .. })));
        assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, f64::NAN)), Err(Error::NotFinite { field: "J" })));
    }
}
