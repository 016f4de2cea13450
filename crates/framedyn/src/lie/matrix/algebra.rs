//! The Lie algebra gl(n) of `n×n` matrices: the commutator, the projections
//! onto so(n) (skew part) and sl(n) (traceless part), and the order of the
//! so(n) basis `E_ij − E_ji` in which coordinates are taken.

use super::Mat;

/// Skew-symmetric part `(M − Mᵀ)/2`.
pub(crate) fn skew_part<const N: usize>(m: &Mat<N>) -> Mat<N> {
    (m - m.transpose()) * 0.5
}

/// `M − (tr M / N)·I`.
pub(crate) fn traceless_part<const N: usize>(m: &Mat<N>) -> Mat<N> {
    let t = m.trace() / N as f64;
    let mut out = *m;
    for i in 0..N {
        out[(i, i)] -= t;
    }
    out
}

/// The commutator `[a, b] = ab − ba`.
#[inline]
pub(crate) fn commutator<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> Mat<N> {
    a * b - b * a
}

/// `(i, j)`, `i < j`, of the `k`-th so(n) basis element `E_ij − E_ji` in the
/// lexicographic order (0,1), (0,2), …, (0,N−1), (1,2), …
pub fn skew_index<const N: usize>(k: usize) -> (usize, usize) {
    let mut k = k;
    for i in 0..N {
        let row = N - 1 - i;
        if k < row {
            return (i, i + 1 + k);
        }
        k -= row;
    }
    (N, N) // unreachable for k < N(N−1)/2; out of range for the caller
}
