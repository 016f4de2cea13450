//! LU factorisation with partial pivoting on the stack ([`Lu`]) and the
//! determinant from it ([`det`]): the linear solves of the Padé
//! approximants and of the square-root iteration, and the inverses and
//! determinants of the matrix groups.

use super::Mat;

/// LU factorisation `P·M = L·U` with partial pivoting (unit lower `L`).
#[derive(Clone, Copy, Debug)]
pub struct Lu<const N: usize> {
    lu: Mat<N>,
    perm: [usize; N],
    sign: f64,
}

impl<const N: usize> Lu<N> {
    /// Factorises `m`; `None` if a pivot is zero or not finite.
    pub fn new(m: &Mat<N>) -> Option<Self> {
        let mut lu = *m;
        let mut perm = [0usize; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        let mut sign = 1.0;
        for k in 0..N {
            let mut p = k;
            let mut best = lu[(k, k)].abs();
            for i in k + 1..N {
                let v = lu[(i, k)].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return None;
            }
            if p != k {
                lu.swap_rows(p, k);
                perm.swap(p, k);
                sign = -sign;
            }
            let piv = lu[(k, k)];
            for i in k + 1..N {
                let f = lu[(i, k)] / piv;
                lu[(i, k)] = f;
                if f != 0.0 {
                    for j in k + 1..N {
                        lu[(i, j)] -= f * lu[(k, j)];
                    }
                }
            }
        }
        Some(Lu { lu, perm, sign })
    }

    /// Determinant of the factorised matrix.
    pub fn det(&self) -> f64 {
        (0..N).fold(self.sign, |d, i| d * self.lu[(i, i)])
    }

    /// Solves `M·X = B`.
    pub(crate) fn solve(&self, b: &Mat<N>) -> Mat<N> {
        let mut x = Mat::<N>::zeros();
        for c in 0..N {
            for i in 0..N {
                let mut s = b[(self.perm[i], c)];
                for j in 0..i {
                    s -= self.lu[(i, j)] * x[(j, c)];
                }
                x[(i, c)] = s;
            }
            for i in (0..N).rev() {
                let mut s = x[(i, c)];
                for j in i + 1..N {
                    s -= self.lu[(i, j)] * x[(j, c)];
                }
                x[(i, c)] = s / self.lu[(i, i)];
            }
        }
        x
    }

    /// `M⁻¹`.
    pub fn inverse(&self) -> Mat<N> {
        self.solve(&Mat::<N>::identity())
    }
}

/// Determinant by LU (0 for a singular matrix, NaN for a non-finite one).
pub fn det<const N: usize>(m: &Mat<N>) -> f64 {
    match Lu::new(m) {
        Some(lu) => lu.det(),
        None if m.iter().all(|x| x.is_finite()) => 0.0,
        None => f64::NAN,
    }
}
