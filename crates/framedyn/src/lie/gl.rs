//! GL⁺(n): orientation-preserving invertible matrices, and the fixed-size
//! matrix functions (exponential, logarithm, square root, `dexp`, `dexp⁻¹`,
//! polar factor) shared by the other general-`n` matrix groups of this crate
//! ([`Sl`](super::Sl), [`SoN`](super::SoN), [`Co`](super::Co)).
//!
//! Everything works on stack-allocated `SMatrix<f64, N, N>`; nothing here
//! allocates except the eigenvalue test of the logarithm (a `DMatrix` Schur
//! decomposition) and the SVD fallback of the polar factor for det ≤ 0.
//!
//! References:
//! - \[H05\] N. J. Higham, *The scaling and squaring method for the matrix
//!   exponential revisited*, SIAM J. Matrix Anal. Appl. 26 (2005) 1179–1193.
//! - \[AH12\] A. H. Al-Mohy, N. J. Higham, *Improved inverse scaling and squaring
//!   algorithms for the matrix logarithm*, SIAM J. Sci. Comput. 34 (2012) C153–C169.
//! - \[CHKL01\] S. H. Cheng, N. J. Higham, C. S. Kenney, A. J. Laub, *Approximating
//!   the logarithm of a matrix to specified accuracy*, SIAM J. Matrix Anal.
//!   Appl. 22 (2001) 1112–1125 (product form of the Denman–Beavers iteration).
//! - \[H01\] N. J. Higham, *Evaluating Padé approximants of the matrix logarithm*,
//!   SIAM J. Matrix Anal. Appl. 22 (2001) 1126–1135 (partial fractions).
//! - \[H08\] N. J. Higham, *Functions of Matrices*, SIAM 2008 (§6.3, §8, §11).
//! - \[BB71\] Å. Björck, C. Bowie, *An iterative algorithm for computing the best
//!   estimate of an orthogonal matrix*, SIAM J. Numer. Anal. 8 (1971) 358–364.
//! - \[IMNZ00\] A. Iserles, H. Munthe-Kaas, S. Nørsett, A. Zanna, *Lie-group
//!   methods*, Acta Numerica 9 (2000) 215–365 (dexp, dexp⁻¹).

use nalgebra::{DMatrix, SMatrix};

use self::matfun::{amax, commutator, det, dexp_inv_matrix, dexp_matrix, expm, logm, nan_matrix, Basis, Lu, Mat};
use super::LieGroup;
use crate::{Error, Result};

/// Fixed-size dense matrix functions shared by the general-`n` groups
/// (kept in a module so that the `pub use gl::*` of `lie` re-exports none of
/// these helper names).
// NaN-rejecting comparisons such as `!(x > 0.0)` are intentional here.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(crate) mod matfun {
    use nalgebra::{DMatrix, SMatrix};

    use crate::lie::BERNOULLI_OVER_FACTORIAL;
    use crate::{Error, Result};

    /// Square `N×N` matrix of `f64`, the storage of every general-`n` group here.
    pub(crate) type Mat<const N: usize> = SMatrix<f64, N, N>;

    // ---------------------------------------------------------------------------
    // Small dense linear algebra (LU with partial pivoting)
    // ---------------------------------------------------------------------------

    /// LU factorisation `P·M = L·U` with partial pivoting (unit lower `L`).
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Lu<const N: usize> {
        lu: Mat<N>,
        perm: [usize; N],
        sign: f64,
    }

    impl<const N: usize> Lu<N> {
        /// Factorises `m`; `None` if a pivot is zero or not finite.
        pub(crate) fn new(m: &Mat<N>) -> Option<Self> {
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
        pub(crate) fn det(&self) -> f64 {
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
        pub(crate) fn inverse(&self) -> Mat<N> {
            self.solve(&Mat::<N>::identity())
        }
    }

    /// Determinant by LU (0 for a singular matrix, NaN for a non-finite one).
    pub(crate) fn det<const N: usize>(m: &Mat<N>) -> f64 {
        match Lu::new(m) {
            Some(lu) => lu.det(),
            None if m.iter().all(|x| x.is_finite()) => 0.0,
            None => f64::NAN,
        }
    }

    /// A matrix of NaNs: the result of a matrix function at an invalid argument.
    pub(crate) fn nan_matrix<const N: usize>() -> Mat<N> {
        Mat::<N>::from_element(f64::NAN)
    }

    /// Matrix 1-norm (largest absolute column sum).
    pub(crate) fn norm1<const N: usize>(m: &Mat<N>) -> f64 {
        (0..N)
            .map(|j| (0..N).map(|i| m[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }

    /// Largest absolute entry.
    pub(crate) fn amax<const N: usize>(m: &Mat<N>) -> f64 {
        m.iter().fold(0.0, |a, x| a.max(x.abs()))
    }

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

    /// `Ad_g x = g x g⁻¹` with `g⁻¹` supplied.
    #[inline]
    fn conj<const N: usize>(g: &Mat<N>, x: &Mat<N>, ginv: &Mat<N>) -> Mat<N> {
        g * x * ginv
    }

    /// The commutator `[a, b] = ab − ba`.
    #[inline]
    pub(crate) fn commutator<const N: usize>(a: &Mat<N>, b: &Mat<N>) -> Mat<N> {
        a * b - b * a
    }

    // ---------------------------------------------------------------------------
    // Matrix exponential: scaling and squaring with Padé approximants [H05]
    // ---------------------------------------------------------------------------

    /// θ_m of [H05, Table 2.3]: the largest 1-norm for which the [m/m] Padé
    /// approximant of `exp` has backward error ≤ 2⁻⁵³, for m = 3, 5, 7, 9, 13.
    pub(crate) const EXP_THETA: [(usize, f64); 5] = [
        (3, 1.495585217958292e-2),
        (5, 2.53939833006323e-1),
        (7, 9.504178996162932e-1),
        (9, 2.097847961257068e0),
        (13, 5.371920351148152e0),
    ];

    /// Coefficients `b_j = (2m−j)! m! / ((2m)! j! (m−j)!)` of the [m/m] Padé
    /// numerator `p_m(x) = Σ b_j x^j`, scaled so that the leading one is 1 as in \[H05\].
    pub(crate) const PADE3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
    pub(crate) const PADE5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
    pub(crate) const PADE7: [f64; 8] = [17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0];
    pub(crate) const PADE9: [f64; 10] = [
        17643225600.0,
        8821612800.0,
        2075673600.0,
        302702400.0,
        30270240.0,
        2162160.0,
        110880.0,
        3960.0,
        90.0,
        1.0,
    ];
    pub(crate) const PADE13: [f64; 14] = [
        64764752532480000.0,
        32382376266240000.0,
        7771770303897600.0,
        1187353796428800.0,
        129060195264000.0,
        10559470521600.0,
        670442572800.0,
        33522128640.0,
        1323241920.0,
        40840800.0,
        960960.0,
        16380.0,
        182.0,
        1.0,
    ];

    /// Odd part `U` and even part `V` of the Padé numerator `p_m(A) = V + U`
    /// (so `q_m(A) = p_m(−A) = V − U`), and the number `s` of squarings, chosen as
    /// in [H05, Alg. 2.3] from the 1-norm of `A`; `U`, `V` are of `A/2^s`.
    /// `None` if `A` is not finite.
    fn exp_pade_parts<const N: usize>(a: &Mat<N>) -> Option<(Mat<N>, Mat<N>, u32)> {
        let nrm = norm1(a);
        if !nrm.is_finite() {
            return None;
        }
        let id = Mat::<N>::identity();
        for &(m, theta) in &EXP_THETA[..4] {
            if nrm <= theta {
                let a2 = a * a;
                let (u, v) = match m {
                    3 => (a * (a2 * PADE3[3] + id * PADE3[1]), a2 * PADE3[2] + id * PADE3[0]),
                    5 => {
                        let a4 = a2 * a2;
                        (
                            a * (a4 * PADE5[5] + a2 * PADE5[3] + id * PADE5[1]),
                            a4 * PADE5[4] + a2 * PADE5[2] + id * PADE5[0],
                        )
                    }
                    7 => {
                        let a4 = a2 * a2;
                        let a6 = a4 * a2;
                        (
                            a * (a6 * PADE7[7] + a4 * PADE7[5] + a2 * PADE7[3] + id * PADE7[1]),
                            a6 * PADE7[6] + a4 * PADE7[4] + a2 * PADE7[2] + id * PADE7[0],
                        )
                    }
                    _ => {
                        let a4 = a2 * a2;
                        let a6 = a4 * a2;
                        let a8 = a6 * a2;
                        (
                            a * (a8 * PADE9[9] + a6 * PADE9[7] + a4 * PADE9[5] + a2 * PADE9[3] + id * PADE9[1]),
                            a8 * PADE9[8] + a6 * PADE9[6] + a4 * PADE9[4] + a2 * PADE9[2] + id * PADE9[0],
                        )
                    }
                };
                return Some((u, v, 0));
            }
        }
        // m = 13 with s = max(0, ⌈log₂(‖A‖₁/θ₁₃)⌉), by exact halvings.
        let theta13 = EXP_THETA[4].1;
        let mut s = 0u32;
        let mut scale = 1.0;
        while nrm * scale > theta13 {
            scale *= 0.5;
            s += 1;
        }
        let a = a * scale;
        let b = &PADE13;
        let a2 = a * a;
        let a4 = a2 * a2;
        let a6 = a4 * a2;
        let u = a * (a6 * (a6 * b[13] + a4 * b[11] + a2 * b[9]) + a6 * b[7] + a4 * b[5] + a2 * b[3] + id * b[1]);
        let v = a6 * (a6 * b[12] + a4 * b[10] + a2 * b[8]) + a6 * b[6] + a4 * b[4] + a2 * b[2] + id * b[0];
        Some((u, v, s))
    }

    /// The matrix exponential by scaling and squaring [H05, Alg. 2.3]:
    /// `exp(A) ≈ r_m(A/2^s)^{2^s}`, `r_m = q_m⁻¹ p_m` the [m/m] Padé approximant,
    /// `m ∈ {3, 5, 7, 9, 13}` the cheapest degree whose θ_m bounds `‖A‖₁` (else
    /// `m = 13` and the smallest `s` with `‖A/2^s‖₁ ≤ θ₁₃`). The backward error
    /// is below the unit round-off 2⁻⁵³ in exact arithmetic; the forward error is
    /// then governed by the conditioning of `exp` at `A` (≈ `‖A‖` for normal `A`).
    /// Returns a NaN matrix for non-finite input.
    pub(crate) fn expm<const N: usize>(a: &Mat<N>) -> Mat<N> {
        let Some((u, v, s)) = exp_pade_parts(a) else {
            return nan_matrix();
        };
        let Some(q) = Lu::new(&(v - u)) else {
            return nan_matrix();
        };
        let mut x = q.solve(&(v + u));
        for _ in 0..s {
            x = x * x;
        }
        x
    }

    /// `(exp(A), exp(−A))` from one Padé evaluation: `r_m(−A) = r_m(A)⁻¹`
    /// exactly, so `exp(−A)` costs one more solve and `s` more squarings.
    fn expm_pair<const N: usize>(a: &Mat<N>) -> (Mat<N>, Mat<N>) {
        let Some((u, v, s)) = exp_pade_parts(a) else {
            return (nan_matrix(), nan_matrix());
        };
        let (Some(q), Some(p)) = (Lu::new(&(v - u)), Lu::new(&(v + u))) else {
            return (nan_matrix(), nan_matrix());
        };
        let mut x = q.solve(&(v + u));
        let mut y = p.solve(&(v - u));
        for _ in 0..s {
            x = x * x;
            y = y * y;
        }
        (x, y)
    }

    // ---------------------------------------------------------------------------
    // dexp and dexp⁻¹
    // ---------------------------------------------------------------------------

    /// Frobenius norm.
    #[inline]
    fn fro<const N: usize>(m: &Mat<N>) -> f64 {
        m.norm()
    }

    /// Number of halvings `s` with `2‖A‖_F/2^s ≤ 1`, and the factor `2^{−s}`.
    /// Since `‖ad_A‖ ≤ 2‖A‖_F` (Frobenius norms), `‖ad_{A/2^s}‖ ≤ 1`.
    fn ad_scaling<const N: usize>(a: &Mat<N>) -> (u32, f64) {
        let n2 = 2.0 * fro(a);
        let mut s = 0;
        let mut scale = 1.0;
        while n2 * scale > 1.0 {
            scale *= 0.5;
            s += 1;
        }
        (s, scale)
    }

    /// Largest power of `ad` summed in the `dexp` Taylor series: with `‖ad‖ ≤ 1`
    /// the remainder after `ad^k/(k+1)!`, k ≤ 20, is below 1/22! ≈ 9e-22.
    const DEXP_TAYLOR_MAX: usize = 20;

    /// `φ(ad_b) v = Σ_k ad_b^k v/(k+1)!` for `‖ad_b‖ ≤ 1`, summed until the terms
    /// no longer change the result.
    fn phi_taylor<const N: usize>(b: &Mat<N>, v: &Mat<N>) -> Mat<N> {
        let mut term = *v;
        let mut sum = *v;
        for k in 1..=DEXP_TAYLOR_MAX {
            term = commutator(b, &term) * (1.0 / (k + 1) as f64);
            sum += term;
            let t = amax(&term);
            if t == 0.0 || t <= 1e-18 * amax(&sum) {
                break;
            }
        }
        sum
    }

    /// Applies `dexp_A = φ(ad_A)`, `φ(z) = (e^z − 1)/z`, to every matrix in `cols`.
    ///
    /// Method ("scaling and doubling"): from `φ(2z) = φ(z)(e^z + 1)/2` and
    /// `e^{ad_X} = Ad_{exp X}`,
    ///
    /// `φ(ad_A) = ∏_{k=1}^{s} ½(Ad_{exp(A/2^k)} + 1) · φ(ad_{A/2^s})`,
    ///
    /// with `s` the least integer making `‖ad_{A/2^s}‖ ≤ 2‖A‖_F/2^s ≤ 1`, the last
    /// factor summed as a Taylor series, and `exp(A/2^k)` obtained by squaring
    /// `exp(A/2^s)` (the intermediate results of scaling and squaring). Exact
    /// (no truncation beyond round-off) for every `A`: `dexp` is entire.
    /// When `orthogonal` is set, `A` must be skew, `exp(A/2^k)` is orthogonal
    /// and `Ad` uses the transpose instead of the inverse.
    pub(crate) fn dexp_apply<const N: usize>(a: &Mat<N>, cols: &mut [Mat<N>], orthogonal: bool) {
        if !fro(a).is_finite() {
            cols.iter_mut().for_each(|c| *c = nan_matrix());
            return;
        }
        let (s, scale) = ad_scaling(a);
        let b = a * scale;
        for c in cols.iter_mut() {
            *c = phi_taylor(&b, c);
        }
        if s == 0 {
            return;
        }
        let (mut g, mut ginv) = if orthogonal {
            let g = polar_factor(&expm(&b));
            (g, g.transpose())
        } else {
            expm_pair(&b)
        };
        for k in (1..=s).rev() {
            // g = exp(A/2^k), ginv = exp(−A/2^k).
            for c in cols.iter_mut() {
                *c = (conj(&g, c, &ginv) + *c) * 0.5;
            }
            if k > 1 {
                g = g * g;
                ginv = if orthogonal { g.transpose() } else { ginv * ginv };
            }
        }
    }

    /// `dexp_A v` (see [`dexp_apply`]).
    pub(crate) fn dexp_matrix<const N: usize>(a: &Mat<N>, v: &Mat<N>, orthogonal: bool) -> Mat<N> {
        let mut c = [*v];
        dexp_apply(a, &mut c, orthogonal);
        c[0]
    }

    /// Basis in which `dexp_A` is inverted by a linear solve.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub(crate) enum Basis {
        /// All of gl(n): `E_ij`, flat index `i·N + j` (`N²` elements).
        Full,
        /// so(n): `E_ij − E_ji`, `i < j` in lexicographic order (`N(N−1)/2`).
        Skew,
    }

    impl Basis {
        fn dim(self, n: usize) -> usize {
            match self {
                Basis::Full => n * n,
                Basis::Skew => n * (n - 1) / 2,
            }
        }
        /// Basis element `k`.
        fn element<const N: usize>(self, k: usize) -> Mat<N> {
            let mut m = Mat::<N>::zeros();
            match self {
                Basis::Full => m[(k / N, k % N)] = 1.0,
                Basis::Skew => {
                    let (i, j) = skew_index::<N>(k);
                    m[(i, j)] = 1.0;
                    m[(j, i)] = -1.0;
                }
            }
            m
        }
        /// Coordinate `k` of `m` (for `Skew`, of its skew part).
        fn coord<const N: usize>(self, m: &Mat<N>, k: usize) -> f64 {
            match self {
                Basis::Full => m[(k / N, k % N)],
                Basis::Skew => {
                    let (i, j) = skew_index::<N>(k);
                    0.5 * (m[(i, j)] - m[(j, i)])
                }
            }
        }
    }

    /// `(i, j)`, `i < j`, of the `k`-th so(n) basis element `E_ij − E_ji` in the
    /// lexicographic order (0,1), (0,2), …, (0,N−1), (1,2), …
    pub(crate) fn skew_index<const N: usize>(k: usize) -> (usize, usize) {
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

    /// Square matrix of order up to `N²` (a linear operator on gl(N)), stored on
    /// the stack as `N·N` rows of `N·N` numbers.
    struct OpMatrix<const N: usize> {
        rows: [[[[f64; N]; N]; N]; N],
    }

    impl<const N: usize> OpMatrix<N> {
        fn zeros() -> Self {
            OpMatrix {
                rows: [[[[0.0; N]; N]; N]; N],
            }
        }
        #[inline]
        fn rows_mut(&mut self) -> &mut [[[f64; N]; N]] {
            self.rows.as_flattened_mut()
        }
        /// Solves `M x = rhs` (first `d` rows/columns) by Gaussian elimination
        /// with partial pivoting; `None` if `M` is singular to working precision.
        fn solve(&mut self, d: usize, rhs: &mut [f64]) -> Option<()> {
            let rows = self.rows_mut();
            let scale = rows[..d]
                .iter()
                .flat_map(|r| r.as_flattened()[..d].iter())
                .fold(0.0f64, |a, x| a.max(x.abs()));
            if !(scale > 0.0 && scale.is_finite()) {
                return None;
            }
            for k in 0..d {
                let mut p = k;
                let mut best = rows[k].as_flattened()[k].abs();
                for (i, r) in rows.iter().enumerate().take(d).skip(k + 1) {
                    let v = r.as_flattened()[k].abs();
                    if v > best {
                        best = v;
                        p = i;
                    }
                }
                if !(best > scale * f64::EPSILON * 0.5) {
                    return None;
                }
                rows.swap(p, k);
                rhs.swap(p, k);
                let (top, bottom) = rows.split_at_mut(k + 1);
                let pivot_row = top[k].as_flattened();
                let piv = pivot_row[k];
                for (off, r) in bottom.iter_mut().take(d - k - 1).enumerate() {
                    let r = r.as_flattened_mut();
                    let f = r[k] / piv;
                    if f != 0.0 {
                        for j in k + 1..d {
                            r[j] -= f * pivot_row[j];
                        }
                        rhs[k + 1 + off] -= f * rhs[k];
                    }
                }
            }
            for k in (0..d).rev() {
                let r = rows[k].as_flattened();
                let mut s = rhs[k];
                for j in k + 1..d {
                    s -= r[j] * rhs[j];
                }
                rhs[k] = s / r[k];
            }
            Some(())
        }
    }

    /// Bernoulli series `Σ_{k≤20} B_k/k! ad_a^k v`, for `‖ad_a‖ ≤ 1`: the
    /// remainder is below `2·(2π)^{−22}` ≈ 5e-18 relative.
    fn dexp_inv_bernoulli<const N: usize>(a: &Mat<N>, v: &Mat<N>) -> Mat<N> {
        let mut term = *v;
        let mut sum = *v;
        let mut bound = 1.0; // (2π)^{-k}·2 ≥ |B_k/k!|
        for &c in BERNOULLI_OVER_FACTORIAL.iter().skip(1) {
            term = commutator(a, &term);
            bound /= std::f64::consts::TAU;
            if c != 0.0 {
                sum += term * c;
            }
            let t = amax(&term);
            if t == 0.0 || 2.0 * bound * t <= 1e-18 * amax(&sum) {
                break;
            }
        }
        sum
    }

    /// `dexp_A⁻¹ v`, the solution `x` of `dexp_A x = v`.
    ///
    /// - `‖ad_A‖ ≤ 2‖A‖_F ≤ 1`: the Bernoulli series `Σ_{k≤20} B_k/k! ad_A^k v`
    ///   (remainder < 5e-18 relative; this is the integrators' small-step regime).
    /// - otherwise: `dexp_A` is assembled as a `d×d` matrix in `basis` (columns
    ///   `dexp_A e_j` from [`dexp_apply`], all basis elements at once) and the
    ///   system solved by Gaussian elimination with partial pivoting; the result
    ///   is exact up to `cond(dexp_A)·ε`. No radius restriction: valid wherever
    ///   `dexp_A` is invertible, i.e. no eigenvalue of `ad_A` lies in
    ///   `2πi·ℤ∖{0}` (for `A` with eigenvalues `|Im λ| < π`, always).
    ///   Where it is singular to working precision the result is a NaN matrix.
    pub(crate) fn dexp_inv_matrix<const N: usize>(a: &Mat<N>, v: &Mat<N>, basis: Basis, orthogonal: bool) -> Mat<N> {
        let nf = fro(a);
        if !nf.is_finite() || !fro(v).is_finite() {
            return nan_matrix();
        }
        if 2.0 * nf <= 1.0 {
            return dexp_inv_bernoulli(a, v);
        }
        let d = basis.dim(N);
        let mut cols = [[Mat::<N>::zeros(); N]; N];
        {
            let flat = cols.as_flattened_mut();
            for (k, c) in flat.iter_mut().enumerate().take(d) {
                *c = basis.element::<N>(k);
            }
            dexp_apply(a, &mut flat[..d], orthogonal);
        }
        let flat = cols.as_flattened();
        let mut op = OpMatrix::<N>::zeros();
        let mut rhs = [[0.0; N]; N];
        let rhs_flat = rhs.as_flattened_mut();
        {
            let rows = op.rows_mut();
            for (r, row) in rows.iter_mut().enumerate().take(d) {
                let row = row.as_flattened_mut();
                for (j, col) in flat.iter().enumerate().take(d) {
                    row[j] = basis.coord(col, r);
                }
                rhs_flat[r] = basis.coord(v, r);
            }
        }
        if op.solve(d, rhs_flat).is_none() {
            return nan_matrix();
        }
        let mut x = Mat::<N>::zeros();
        for (k, &c) in rhs_flat.iter().enumerate().take(d) {
            x += basis.element::<N>(k) * c;
        }
        x
    }

    // ---------------------------------------------------------------------------
    // Matrix square root and logarithm: inverse scaling and squaring
    // ---------------------------------------------------------------------------

    /// Householder vector of `x` (length `len ≤ 3`): `(v, β)` with
    /// `(I − β v vᵀ) x = ∓‖x‖ e₀`; `β = 0` if `x = 0`.
    #[inline]
    fn house(x: [f64; 3], len: usize) -> ([f64; 3], f64) {
        let norm = x[..len].iter().map(|t| t * t).sum::<f64>().sqrt();
        if norm == 0.0 {
            return ([0.0; 3], 0.0);
        }
        let mut v = x;
        v[0] += if x[0] >= 0.0 { norm } else { -norm };
        let vv: f64 = v[..len].iter().map(|t| t * t).sum();
        (v, 2.0 / vv)
    }

    /// `M ← P M` on rows `r0..r0+len`, columns `c0..N`, `P = I − β v vᵀ`.
    #[inline]
    fn reflect_rows<const N: usize>(m: &mut Mat<N>, v: &[f64; 3], beta: f64, len: usize, r0: usize, c0: usize) {
        for c in c0..N {
            let s: f64 = (0..len).map(|i| v[i] * m[(r0 + i, c)]).sum::<f64>() * beta;
            for i in 0..len {
                m[(r0 + i, c)] -= s * v[i];
            }
        }
    }

    /// `M ← M P` on rows `0..r_end`, columns `c0..c0+len`.
    #[inline]
    fn reflect_cols<const N: usize>(m: &mut Mat<N>, v: &[f64; 3], beta: f64, len: usize, c0: usize, r_end: usize) {
        for r in 0..r_end {
            let s: f64 = (0..len).map(|j| v[j] * m[(r, c0 + j)]).sum::<f64>() * beta;
            for j in 0..len {
                m[(r, c0 + j)] -= s * v[j];
            }
        }
    }

    /// Real Schur decomposition `A = Q T Qᵀ` (`Q` orthogonal, `T` real
    /// quasi-upper-triangular with 1×1 and 2×2 diagonal blocks), on the stack:
    /// Householder reduction to Hessenberg form, then Francis double-shift QR
    /// steps [GVL13, Alg. 7.5.1–7.5.2] with the deflation test
    /// `|h_{k,k−1}| ≤ ε(|h_kk| + |h_{k−1,k−1}|)` and an exceptional shift every
    /// 10 iterations. `None` if it has not converged after `30·max(10, N)`
    /// iterations per eigenvalue (or for non-finite input).
    ///
    /// [GVL13] G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed. (2013).
    pub(crate) fn real_schur<const N: usize>(a: &Mat<N>) -> Option<(Mat<N>, Mat<N>)> {
        if !a.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut h = *a;
        let mut q = Mat::<N>::identity();
        // Hessenberg reduction, one column at a time (reflectors of any length
        // are applied as successive 3-vectors would not be; use a general loop).
        for k in 0..N.saturating_sub(2) {
            let len = N - k - 1;
            let norm = (k + 1..N).map(|i| h[(i, k)] * h[(i, k)]).sum::<f64>().sqrt();
            if norm == 0.0 {
                continue;
            }
            let alpha = if h[(k + 1, k)] >= 0.0 { -norm } else { norm };
            // v = x − α e₀, β = 2/vᵀv, stored in column k below the subdiagonal temporarily.
            let mut v = [0.0f64; N];
            for i in 0..len {
                v[i] = h[(k + 1 + i, k)];
            }
            v[0] -= alpha;
            let vv: f64 = v[..len].iter().map(|t| t * t).sum();
            if vv == 0.0 {
                continue;
            }
            let beta = 2.0 / vv;
            for c in k..N {
                let s: f64 = (0..len).map(|i| v[i] * h[(k + 1 + i, c)]).sum::<f64>() * beta;
                for i in 0..len {
                    h[(k + 1 + i, c)] -= s * v[i];
                }
            }
            for r in 0..N {
                let s: f64 = (0..len).map(|j| v[j] * h[(r, k + 1 + j)]).sum::<f64>() * beta;
                for j in 0..len {
                    h[(r, k + 1 + j)] -= s * v[j];
                }
                let s: f64 = (0..len).map(|j| v[j] * q[(r, k + 1 + j)]).sum::<f64>() * beta;
                for j in 0..len {
                    q[(r, k + 1 + j)] -= s * v[j];
                }
            }
            h[(k + 1, k)] = alpha;
            for i in k + 2..N {
                h[(i, k)] = 0.0;
            }
        }
        // Francis double-shift QR on the active window [l, hi].
        let max_iter = 30 * N.max(10) * N.max(1);
        let mut total = 0;
        let mut iter = 0;
        let mut hi = N.saturating_sub(1);
        let anorm = amax(&h);
        while hi >= 1 {
            let mut l = hi;
            while l > 0 {
                let mut sc = h[(l - 1, l - 1)].abs() + h[(l, l)].abs();
                if sc == 0.0 {
                    sc = anorm;
                }
                if h[(l, l - 1)].abs() <= f64::EPSILON * sc {
                    h[(l, l - 1)] = 0.0;
                    break;
                }
                l -= 1;
            }
            if l == hi {
                hi -= 1;
                iter = 0;
                continue;
            }
            if l + 1 == hi {
                if hi < 2 {
                    break;
                }
                hi -= 2;
                iter = 0;
                continue;
            }
            total += 1;
            iter += 1;
            if total > max_iter {
                return None;
            }
            let m = hi;
            // Shifts: the eigenvalues of the trailing 2×2 block, through
            // x + y = σ₁ + σ₂ and xy − w = σ₁σ₂ (exceptional shifts of EISPACK
            // hqr every 10 iterations). First column of (H − σ₁)(H − σ₂)
            // scaled by 1/h₁₀, in the differences form of hqr, which does not
            // cancel when all eigenvalues are close (e.g. near-identity input).
            let (mut xs, mut ys, mut w) = (h[(m, m)], h[(m - 1, m - 1)], h[(m, m - 1)] * h[(m - 1, m)]);
            if iter % 10 == 0 {
                let e = h[(m, m - 1)].abs() + h[(m - 1, m - 2)].abs();
                xs = h[(m, m)] + 0.75 * e;
                ys = xs;
                w = -0.4375 * e * e;
            }
            let z0 = h[(l, l)];
            let (r1, s1) = (xs - z0, ys - z0);
            let mut x = (r1 * s1 - w) / h[(l + 1, l)] + h[(l, l + 1)];
            let mut y = h[(l + 1, l + 1)] - z0 - r1 - s1;
            let mut z = h[(l + 2, l + 1)];
            for rs in l..=m - 2 {
                let (v, beta) = house([x, y, z], 3);
                if beta != 0.0 {
                    let c0 = if rs > l { rs - 1 } else { l };
                    reflect_rows(&mut h, &v, beta, 3, rs, c0);
                    reflect_cols(&mut h, &v, beta, 3, rs, (rs + 4).min(m + 1));
                    reflect_cols(&mut q, &v, beta, 3, rs, N);
                    if rs > l {
                        h[(rs + 1, rs - 1)] = 0.0;
                        h[(rs + 2, rs - 1)] = 0.0;
                    }
                }
                x = h[(rs + 1, rs)];
                y = h[(rs + 2, rs)];
                if rs + 3 <= m {
                    z = h[(rs + 3, rs)];
                }
            }
            let (v, beta) = house([x, y, 0.0], 2);
            if beta != 0.0 {
                reflect_rows(&mut h, &v, beta, 2, m - 1, m - 2);
                reflect_cols(&mut h, &v, beta, 2, m - 1, m + 1);
                reflect_cols(&mut q, &v, beta, 2, m - 1, N);
                h[(m, m - 2)] = 0.0;
            }
        }
        for c in 0..N {
            for r in c + 2..N {
                h[(r, c)] = 0.0;
            }
        }
        split_real_blocks(&mut h, &mut q);
        Some((q, h))
    }

    /// Splits every 2×2 diagonal block of the quasi-triangular `h` that has
    /// real eigenvalues into two 1×1 blocks by a rotation (as LAPACK's dlanv2
    /// standardisation does), updating `q`. Without it a strongly hyperbolic
    /// block (eigenvalues e^{±10}) would mix its two eigen-directions through
    /// every later matrix operation of the logarithm, which costs accuracy
    /// in the well-conditioned, large eigenvalue (measured: backward error
    /// 1400ε on a boost of rapidity 10, vs ~ε triangular).
    fn split_real_blocks<const N: usize>(h: &mut Mat<N>, q: &mut Mat<N>) {
        let mut i = 0;
        while i + 1 < N {
            if h[(i + 1, i)] == 0.0 {
                i += 1;
                continue;
            }
            let (a, b, c, d) = (h[(i, i)], h[(i, i + 1)], h[(i + 1, i)], h[(i + 1, i + 1)]);
            let (mu, disc) = block_eigen(a, b, c, d);
            if disc >= 0.0 {
                // Eigenvalue of larger magnitude (no cancellation) and its
                // eigenvector, from whichever row of B − λI is larger.
                let lam = mu + disc.sqrt().copysign(mu);
                let (v1, v2) = ((b, lam - a), (lam - d, c));
                let (x, y) = if v1.0.hypot(v1.1) >= v2.0.hypot(v2.1) { v1 } else { v2 };
                let n = x.hypot(y);
                if n > 0.0 {
                    let (cs, sn) = (x / n, y / n);
                    // G = [[cs, −sn], [sn, cs]]: T ← Gᵀ T G, Q ← Q G.
                    for col in i..N {
                        let (t0, t1) = (h[(i, col)], h[(i + 1, col)]);
                        h[(i, col)] = cs * t0 + sn * t1;
                        h[(i + 1, col)] = -sn * t0 + cs * t1;
                    }
                    for row in 0..N {
                        if row < i + 2 {
                            let (t0, t1) = (h[(row, i)], h[(row, i + 1)]);
                            h[(row, i)] = cs * t0 + sn * t1;
                            h[(row, i + 1)] = -sn * t0 + cs * t1;
                        }
                        let (q0, q1) = (q[(row, i)], q[(row, i + 1)]);
                        q[(row, i)] = cs * q0 + sn * q1;
                        q[(row, i + 1)] = -sn * q0 + cs * q1;
                    }
                    h[(i + 1, i)] = 0.0;
                }
            }
            i += 2;
        }
    }

    /// Largest number of Denman–Beavers iterations per square root.
    const DB_MAX_ITER: usize = 100;

    /// Principal square root by the scaled product form of the Denman–Beavers
    /// iteration \[CHKL01\], [H08, (6.29)]:
    ///
    /// `M₀ = Y₀ = A`, `μ_k = |det M_k|^{−1/(2n)}`,
    /// `Y_{k+1} = μ_k Y_k (I + μ_k⁻² M_k⁻¹)/2`,
    /// `M_{k+1} = (I + (μ_k² M_k + μ_k⁻² M_k⁻¹)/2)/2`,
    ///
    /// which keeps `Y_k² = A M_k` and drives `M_k → I` quadratically
    /// (`M_{k+1} − I = (M_k − I)² M_k⁻¹/4` without scaling). The determinant
    /// scaling is used while `‖M_k − I‖₁ > 10⁻²`. Stops one iteration after
    /// `‖M_k − I‖₁ ≤ 2·10⁻⁸` (then `‖M − I‖ ≲ 10⁻¹⁶` and `Y = A^{1/2} M^{1/2}`).
    /// Requires no eigenvalue of `A` on the closed negative real axis; its
    /// first step forms `(2I + M + M⁻¹)/4`, which cancels for eigenvalues near
    /// −1 — see [`logm`] for when it is used.
    pub(crate) fn sqrtm_db<const N: usize>(a: &Mat<N>) -> Result<Mat<N>> {
        let id = Mat::<N>::identity();
        let mut m = *a;
        let mut y = *a;
        let mut last = f64::INFINITY;
        for it in 0..DB_MAX_ITER {
            let dm = norm1(&(m - id));
            let Some(lu) = Lu::new(&m) else {
                return Err(Error::NoConvergence {
                    what: "matrix square root (Denman–Beavers)",
                    iterations: it,
                    residual: dm,
                });
            };
            let minv = lu.inverse();
            let mu = if dm > 1e-2 {
                lu.det().abs().powf(-0.5 / N as f64)
            } else {
                1.0
            };
            let mu2 = mu * mu;
            y = y * (id + minv / mu2) * (0.5 * mu);
            m = (id + (m * mu2 + minv / mu2) * 0.5) * 0.5;
            if dm <= 2e-8 {
                return Ok(y);
            }
            last = dm;
        }
        Err(Error::NoConvergence {
            what: "matrix square root (Denman–Beavers)",
            iterations: DB_MAX_ITER,
            residual: last,
        })
    }

    /// Largest number of square roots taken by the logarithm.
    const LOG_MAX_SQRT: usize = 100;

    /// Diagonal blocks `(start, size)` of a real quasi-upper-triangular
    /// (real Schur) matrix, `size ∈ {1, 2}`; `count` of them are used.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Blocks<const N: usize> {
        list: [(usize, usize); N],
        count: usize,
    }

    impl<const N: usize> Blocks<N> {
        /// Reads the block structure of `t` from its nonzero subdiagonal entries
        /// and zeroes everything below the block diagonal.
        pub(crate) fn of(t: &mut Mat<N>) -> Self {
            let mut list = [(0usize, 0usize); N];
            let mut count = 0;
            let mut i = 0;
            while i < N {
                let size = if i + 1 < N && t[(i + 1, i)] != 0.0 { 2 } else { 1 };
                list[count] = (i, size);
                count += 1;
                i += size;
            }
            let mut out = Blocks { list, count };
            for c in 0..N {
                for r in c + 1..N {
                    if out.block_of(r) != out.block_of(c) {
                        t[(r, c)] = 0.0;
                    }
                }
            }
            out.count = count;
            out
        }
        fn block_of(&self, row: usize) -> usize {
            (0..self.count)
                .find(|&b| row < self.list[b].0 + self.list[b].1)
                .unwrap_or(self.count)
        }
        pub(crate) fn slice(&self) -> &[(usize, usize)] {
            &self.list[..self.count]
        }
    }

    /// Half trace `μ` and discriminant `δ = p² + bc`, `p = (a − d)/2`, of a
    /// 2×2 block `[[a, b], [c, d]]`: its eigenvalues are `μ ± √δ`. For complex
    /// pairs `ν² = −δ` has no cancellation even for rotation-like blocks
    /// near angle π (where `det − μ²` would lose everything).
    fn block_eigen(a: f64, b: f64, c: f64, d: f64) -> (f64, f64) {
        let p = 0.5 * (a - d);
        (0.5 * (a + d), p * p + b * c)
    }

    /// Principal square root of a diagonal block of a real Schur form, or the
    /// reason it does not exist (an eigenvalue on the closed negative real axis).
    fn block_sqrt(t: &Mat2, size: usize) -> std::result::Result<Mat2, &'static str> {
        const AXIS: &str =
            "an eigenvalue lies on the closed negative real axis (rotation angle π or a negative real eigenvalue)";
        if size == 1 {
            let x = t[(0, 0)];
            return if x > 0.0 {
                Ok(Mat2::new(x.sqrt(), 0.0, 0.0, 0.0))
            } else {
                Err(AXIS)
            };
        }
        let (a, b, c, d) = (t[(0, 0)], t[(0, 1)], t[(1, 0)], t[(1, 1)]);
        let (mu, disc) = block_eigen(a, b, c, d);
        if disc >= 0.0 {
            // Real eigenvalues λ₁ ≥ λ₂ > 0: √B = (B + √(λ₁λ₂) I)/(√λ₁ + √λ₂).
            let r = disc.sqrt();
            let l1 = mu + r;
            let l2 = if mu > 0.0 { (a * d - b * c) / l1 } else { mu - r };
            if !(l1 > 0.0 && l2 > 0.0) {
                return Err(AXIS);
            }
            let (s1, s2) = (l1.sqrt(), l2.sqrt());
            let s = s1 * s2;
            let tt = s1 + s2;
            return Ok(Mat2::new((a + s) / tt, b / tt, c / tt, (d + s) / tt));
        }
        // Complex pair μ ± iν: √λ = α + iβ (principal, α > 0) computed without
        // cancellation, then √B = αI + (B − μI)/(2α) (Higham 1987), with
        // B − μI taken as [[p, b], [c, −p]], p = (a − d)/2, so that tr √B = 2α
        // exactly: near the negative axis α is tiny and (a − μ) + (d − μ)
        // (the rounding error of μ) divided by 2α would otherwise spoil
        // (√B)² by ε/α (measured 1e-10 at angle π − 1e-6).
        let nu = (-disc).sqrt();
        let r = mu.hypot(nu);
        if mu < 0.0 && nu <= 8.0 * f64::EPSILON * r {
            return Err(AXIS);
        }
        let alpha = if mu >= 0.0 {
            (0.5 * (r + mu)).sqrt()
        } else {
            nu / (2.0 * (0.5 * (r - mu)).sqrt())
        };
        let h = 0.5 / alpha;
        let ph = 0.5 * (a - d) * h;
        Ok(Mat2::new(alpha + ph, b * h, c * h, alpha - ph))
    }

    type Mat2 = SMatrix<f64, 2, 2>;

    /// Solves the small Sylvester equation `P X + X Q = C` (`X` is `p×q`,
    /// `p, q ≤ 2`) by Gaussian elimination with partial pivoting on its
    /// `pq×pq` Kronecker form; `None` if singular.
    fn small_sylvester(pm: &Mat2, p: usize, qm: &Mat2, q: usize, c: &Mat2) -> Option<Mat2> {
        let n = p * q;
        let mut m = [[0.0f64; 5]; 4];
        // Unknown index k = i + p·j for X[i][j].
        for j in 0..q {
            for i in 0..p {
                let row = i + p * j;
                for k in 0..p {
                    m[row][k + p * j] += pm[(i, k)];
                }
                for l in 0..q {
                    m[row][i + p * l] += qm[(l, j)];
                }
                m[row][4] = c[(i, j)];
            }
        }
        for k in 0..n {
            let piv = (k..n).max_by(|&x, &y| m[x][k].abs().total_cmp(&m[y][k].abs()))?;
            if !(m[piv][k].abs() > 0.0) {
                return None;
            }
            m.swap(piv, k);
            let pivot_row = m[k];
            for row in m.iter_mut().take(n).skip(k + 1) {
                let f = row[k] / pivot_row[k];
                for (x, &p) in row.iter_mut().zip(pivot_row.iter()).skip(k) {
                    *x -= f * p;
                }
            }
        }
        let mut x = [0.0f64; 4];
        for k in (0..n).rev() {
            let mut s = m[k][4];
            for j in k + 1..n {
                s -= m[k][j] * x[j];
            }
            x[k] = s / m[k][k];
        }
        let mut out = Mat2::zeros();
        for j in 0..q {
            for i in 0..p {
                out[(i, j)] = x[i + p * j];
            }
        }
        Some(out)
    }

    /// Copies the `p×q` block at `(r, c)` of `m` into a 2×2 matrix.
    fn get_block<const N: usize>(m: &Mat<N>, r: usize, p: usize, c: usize, q: usize) -> Mat2 {
        let mut out = Mat2::zeros();
        for i in 0..p {
            for j in 0..q {
                out[(i, j)] = m[(r + i, c + j)];
            }
        }
        out
    }

    /// Principal square root of a real quasi-upper-triangular matrix by the
    /// real Schur method (Higham 1987, [H08 §6.2]): diagonal blocks by
    /// [`block_sqrt`], then block by block `U_ii X + X U_jj = T_ij − Σ_k U_ik U_kj`.
    /// No iteration, no subtractive cancellation near the negative axis.
    pub(crate) fn sqrt_quasi_triangular<const N: usize>(
        t: &Mat<N>,
        blocks: &Blocks<N>,
    ) -> std::result::Result<Mat<N>, &'static str> {
        let mut u = Mat::<N>::zeros();
        for (jb, &(cj, q)) in blocks.slice().iter().enumerate() {
            let uj = block_sqrt(&get_block(t, cj, q, cj, q), q)?;
            for i in 0..q {
                for j in 0..q {
                    u[(cj + i, cj + j)] = uj[(i, j)];
                }
            }
            for &(ri, p) in blocks.slice()[..jb].iter().rev() {
                let mut rhs = get_block(t, ri, p, cj, q);
                for &(rk, s) in blocks.slice()[..jb].iter().filter(|&&(rk, _)| rk > ri) {
                    let uik = get_block(&u, ri, p, rk, s);
                    let ukj = get_block(&u, rk, s, cj, q);
                    rhs -= uik * ukj;
                }
                let uii = get_block(&u, ri, p, ri, p);
                let x =
                    small_sylvester(&uii, p, &uj, q, &rhs).ok_or("singular Sylvester equation in the square root")?;
                for i in 0..p {
                    for j in 0..q {
                        u[(ri + i, cj + j)] = x[(i, j)];
                    }
                }
            }
        }
        Ok(u)
    }

    /// θ_m, m = 1..=16: the largest `‖X‖₁` for which the [m/m] Padé
    /// approximant `r_m` of `log(1 + x)` has truncation error below `u/2·‖X‖`
    /// (`u = 2⁻⁵³`), from the bound `Σ_k |e_k| θ^{k−1} ≤ u/2` on the Taylor
    /// coefficients `e_k` of `log(1 + x) − r_m(x)` (computed for this crate in
    /// 60-digit arithmetic and rounded down; close to the backward-error θ_m
    /// of [AH12, Table 2.1] for large m, smaller for small m).
    pub(crate) const LOG_THETA: [f64; 16] = [
        2.58e-8, 3.16e-4, 7.30e-3, 3.46e-2, 8.65e-2, 1.56e-1, 2.33e-1, 3.10e-1, 3.84e-1, 4.50e-1, 5.09e-1, 5.61e-1,
        6.07e-1, 6.46e-1, 6.81e-1, 7.11e-1,
    ];

    /// Gauss–Legendre nodes and weights on [0, 1] for m = 1..=16 points:
    /// `GAUSS_LEGENDRE[m − 1][j] = (t_j, w_j)`, `j < m` (computed in 60-digit
    /// arithmetic, correctly rounded).
    pub(crate) const GAUSS_LEGENDRE: [[(f64, f64); 16]; 16] = [
        [
            (0.5, 1.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.7886751345948129, 0.5),
            (0.2113248654051871, 0.5),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.8872983346207417, 0.2777777777777778),
            (0.5, 0.4444444444444444),
            (0.11270166537925831, 0.2777777777777778),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9305681557970263, 0.17392742256872692),
            (0.6699905217924281, 0.32607257743127305),
            (0.33000947820757187, 0.32607257743127305),
            (0.06943184420297371, 0.17392742256872692),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.953089922969332, 0.11846344252809454),
            (0.7692346550528415, 0.23931433524968324),
            (0.5, 0.28444444444444444),
            (0.23076534494715845, 0.23931433524968324),
            (0.046910077030668004, 0.11846344252809454),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.966234757101576, 0.08566224618958518),
            (0.8306046932331322, 0.1803807865240693),
            (0.6193095930415985, 0.23395696728634552),
            (0.38069040695840156, 0.23395696728634552),
            (0.16939530676686773, 0.1803807865240693),
            (0.03376524289842399, 0.08566224618958518),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9745539561713793, 0.06474248308443485),
            (0.8707655927996972, 0.13985269574463832),
            (0.7029225756886985, 0.19091502525255946),
            (0.5, 0.2089795918367347),
            (0.2970774243113014, 0.19091502525255946),
            (0.12923440720030277, 0.13985269574463832),
            (0.025446043828620736, 0.06474248308443485),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9801449282487681, 0.05061426814518813),
            (0.8983332387068134, 0.11119051722668724),
            (0.7627662049581645, 0.15685332293894363),
            (0.591717321247825, 0.181341891689181),
            (0.4082826787521751, 0.181341891689181),
            (0.2372337950418355, 0.15685332293894363),
            (0.10166676129318664, 0.11119051722668724),
            (0.019855071751231884, 0.05061426814518813),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.984080119753813, 0.040637194180787206),
            (0.9180155536633179, 0.0903240803474287),
            (0.8066857163502952, 0.13030534820146772),
            (0.6621267117019045, 0.15617353852000143),
            (0.5, 0.1651196775006299),
            (0.33787328829809554, 0.15617353852000143),
            (0.1933142836497048, 0.13030534820146772),
            (0.0819844463366821, 0.0903240803474287),
            (0.015919880246186954, 0.040637194180787206),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9869532642585859, 0.03333567215434407),
            (0.9325316833444922, 0.0747256745752903),
            (0.8397047841495122, 0.10954318125799102),
            (0.7166976970646236, 0.13463335965499817),
            (0.5744371694908156, 0.14776211235737644),
            (0.4255628305091844, 0.14776211235737644),
            (0.2833023029353764, 0.13463335965499817),
            (0.1602952158504878, 0.10954318125799102),
            (0.06746831665550775, 0.0747256745752903),
            (0.01304673574141414, 0.03333567215434407),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9891143290730285, 0.02783428355808683),
            (0.9435312998840476, 0.0627901847324523),
            (0.8650760027870247, 0.09314510546386713),
            (0.759548064603406, 0.11659688229599524),
            (0.6347715779761725, 0.13140227225512333),
            (0.5, 0.1364625433889503),
            (0.3652284220238275, 0.13140227225512333),
            (0.2404519353965941, 0.11659688229599524),
            (0.13492399721297535, 0.09314510546386713),
            (0.05646870011595235, 0.0627901847324523),
            (0.010885670926971503, 0.02783428355808683),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9907803171233597, 0.023587668193255914),
            (0.9520586281852375, 0.05346966299765921),
            (0.8849513370971523, 0.08003916427167311),
            (0.7936589771433087, 0.10158371336153296),
            (0.6839157494990901, 0.1167462682691774),
            (0.5626167042557345, 0.12457352290670139),
            (0.43738329574426554, 0.12457352290670139),
            (0.3160842505009099, 0.1167462682691774),
            (0.2063410228566913, 0.10158371336153296),
            (0.11504866290284765, 0.08003916427167311),
            (0.04794137181476257, 0.05346966299765921),
            (0.009219682876640375, 0.023587668193255914),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9920915273592941, 0.02024200238265794),
            (0.958799199611489, 0.046060749918864226),
            (0.9007890453666549, 0.06943675510989362),
            (0.8211746697201701, 0.08907299038097287),
            (0.7242463755182235, 0.10390802376844425),
            (0.6152291579775674, 0.11314159013144862),
            (0.5, 0.11627577661543695),
            (0.3847708420224326, 0.11314159013144862),
            (0.2757536244817766, 0.10390802376844425),
            (0.17882533027982989, 0.08907299038097287),
            (0.09921095463334505, 0.06943675510989362),
            (0.04120080038851102, 0.046060749918864226),
            (0.007908472640705926, 0.02024200238265794),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9931419043484062, 0.01755973016587593),
            (0.9642174418317867, 0.040079043579880104),
            (0.9136006575348825, 0.06075928534395159),
            (0.8436464524058427, 0.07860158357909677),
            (0.757624318179077, 0.09276919873896891),
            (0.6595561844639449, 0.1025992318606478),
            (0.5540274743536718, 0.1076319267315789),
            (0.44597252564632817, 0.1076319267315789),
            (0.3404438155360551, 0.1025992318606478),
            (0.24237568182092295, 0.09276919873896891),
            (0.15635354759415726, 0.07860158357909677),
            (0.0863993424651175, 0.06075928534395159),
            (0.03578255816821324, 0.040079043579880104),
            (0.006858095651593831, 0.01755973016587593),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        [
            (0.9939962590102427, 0.015376620998058635),
            (0.968636696200353, 0.03518302374405406),
            (0.9241032917052137, 0.05357961023358597),
            (0.862208865680085, 0.06978533896307716),
            (0.7854860863042694, 0.08313460290849696),
            (0.6970756735387816, 0.0930805000077811),
            (0.6005970469987173, 0.09921574266355579),
            (0.5, 0.10128912096278064),
            (0.39940295300128276, 0.09921574266355579),
            (0.3029243264612183, 0.0930805000077811),
            (0.21451391369573058, 0.08313460290849696),
            (0.13779113431991497, 0.06978533896307716),
            (0.0758967082947864, 0.05357961023358597),
            (0.031363303799647045, 0.03518302374405406),
            (0.006003740989757286, 0.015376620998058635),
            (0.0, 0.0),
        ],
        [
            (0.994700467495825, 0.013576229705877048),
            (0.9722875115366163, 0.031126761969323947),
            (0.9328156011939158, 0.04757925584124639),
            (0.8777022041775016, 0.06231448562776694),
            (0.8089381222013219, 0.07479799440828837),
            (0.7290083888286137, 0.08457825969750127),
            (0.6408017753896295, 0.09130170752246179),
            (0.5475062549188188, 0.09472530522753425),
            (0.4524937450811813, 0.09472530522753425),
            (0.35919822461037054, 0.09130170752246179),
            (0.2709916111713863, 0.08457825969750127),
            (0.19106187779867811, 0.07479799440828837),
            (0.12229779582249849, 0.06231448562776694),
            (0.06718439880608412, 0.04757925584124639),
            (0.02771248846338371, 0.031126761969323947),
            (0.005299532504175033, 0.013576229705877048),
        ],
    ];

    /// The [m/m] Padé approximant of `log(I + X)` in partial fractions \[H01\]:
    /// `r_m(X) = Σ_j w_j X (I + t_j X)⁻¹`, the m-point Gauss–Legendre rule for
    /// `log(I + X) = ∫₀¹ X (I + tX)⁻¹ dt`. `None` if some `I + t_j X` is singular.
    pub(crate) fn log1p_pade<const N: usize>(x: &Mat<N>, m: usize) -> Option<Mat<N>> {
        let id = Mat::<N>::identity();
        let mut sum = Mat::<N>::zeros();
        for &(t, w) in &GAUSS_LEGENDRE[m - 1][..m] {
            let lu = Lu::new(&(id + x * t))?;
            sum += lu.solve(x) * w;
        }
        Some(sum)
    }

    /// Largest `|arg λ|` over the eigenvalues of the quasi-triangular `t`, or
    /// the reason the principal logarithm is undefined (an eigenvalue on, or
    /// within 8ε relative of, the closed negative real axis).
    fn spectrum_max_arg<const N: usize>(t: &Mat<N>, blocks: &Blocks<N>) -> std::result::Result<f64, &'static str> {
        const AXIS: &str =
            "an eigenvalue lies on the closed negative real axis (rotation angle π or a negative real eigenvalue)";
        let mut worst: f64 = 0.0;
        for &(i, size) in blocks.slice() {
            if size == 1 {
                if !(t[(i, i)] > 0.0) {
                    return Err(AXIS);
                }
                continue;
            }
            let (a, b, c, d) = (t[(i, i)], t[(i, i + 1)], t[(i + 1, i)], t[(i + 1, i + 1)]);
            let (mu, disc) = block_eigen(a, b, c, d);
            if disc >= 0.0 {
                let r = disc.sqrt();
                let l2 = if mu > 0.0 { (a * d - b * c) / (mu + r) } else { mu - r };
                if !(mu + r > 0.0 && l2 > 0.0) {
                    return Err(AXIS);
                }
            } else {
                let nu = (-disc).sqrt();
                if mu < 0.0 && nu <= 8.0 * f64::EPSILON * mu.hypot(nu) {
                    return Err(AXIS);
                }
                worst = worst.max(nu.atan2(mu));
            }
        }
        Ok(worst)
    }

    /// Largest `|arg λ|` for which [`logm`] takes its square roots by the
    /// Denman–Beavers iteration on the full matrix; beyond it (eigenvalues
    /// within 0.24 rad of the negative axis, where the iteration's first step
    /// `(2I + A + A⁻¹)/4` cancels like `cos²(arg λ/2)`) it uses the real Schur
    /// form. Measured crossover (`log_paths_crossover` unit test, 3×3
    /// non-normal): DB/Schur worst errors 1.9e-15/3.8e-15 at θ = 2.6,
    /// 8.3e-15/1.5e-14 at 3.0, 1.2e-13/4.1e-14 at 3.1, 3.1e-11/6.6e-13 at 3.14.
    pub(crate) const LOG_DB_MAX_ARG: f64 = 2.9;

    /// Largest 1-norm condition number `κ₁(A)` for which [`logm`] uses the
    /// Denman–Beavers square roots: their inverses lose `κ·ε`, while the
    /// Schur path's backward error (10–40ε, from the Schur form itself) does
    /// not depend on κ. Measured on 20 000 random 3×3 `exp(S + W + N)`
    /// (`debug` experiment, worst backward error `‖exp(log g) − g‖/(‖g‖‖A‖ε)`,
    /// DB vs Schur): 5.1 vs 26 for κ < 10, 7.2 vs 14 for κ ∈ [10, 100),
    /// 92 vs 13 for κ ∈ [100, 1000), 1.3e3 vs 14 for κ ∈ [1e3, 1e4).
    pub(crate) const LOG_DB_MAX_COND: f64 = 30.0;

    /// Inverse scaling and squaring from `r₀`: square roots by `sqrt` until
    /// `‖Z_k‖₁ ≤ θ₁₆`, `Z` carried by `Z_{j+1} = (R_{j+1} + I)⁻¹ Z_j`, then
    /// `2^k r_m(Z_k)`.
    fn inverse_scaling_squaring<const N: usize>(
        r0: &Mat<N>,
        mut sqrt: impl FnMut(&Mat<N>) -> Result<Mat<N>>,
    ) -> Result<Mat<N>> {
        let id = Mat::<N>::identity();
        let mut r = *r0;
        let mut z = r0 - id;
        let mut k = 0;
        loop {
            let nz = norm1(&z);
            if nz <= LOG_THETA[15] {
                let m = LOG_THETA.iter().position(|&th| nz <= th).unwrap_or(15) + 1;
                let l = log1p_pade(&z, m).ok_or(Error::NoConvergence {
                    what: "matrix logarithm (Padé step)",
                    iterations: k,
                    residual: nz,
                })?;
                return Ok(l * 2f64.powi(k as i32));
            }
            if k == LOG_MAX_SQRT || !nz.is_finite() {
                return Err(Error::NoConvergence {
                    what: "matrix logarithm (square roots)",
                    iterations: k,
                    residual: nz,
                });
            }
            let rn = sqrt(&r)?;
            let lu = Lu::new(&(rn + id)).ok_or(Error::NoConvergence {
                what: "matrix logarithm (square roots)",
                iterations: k,
                residual: nz,
            })?;
            z = lu.solve(&z);
            r = rn;
            k += 1;
        }
    }

    /// Principal matrix logarithm by inverse scaling and squaring \[AH12\],
    /// [H08 §11.5]:
    ///
    /// 1. `A = Q T Qᵀ` ([`real_schur`]); the diagonal blocks of `T` give the
    ///    spectrum, and a typed [`Error::LogUndefined`] is returned if an
    ///    eigenvalue lies on (or within 8ε relative of) the closed negative
    ///    real axis (a singular matrix included);
    /// 2. square roots `R_{j+1} = R_j^{1/2}` until `‖Z_k‖₁ ≤ θ₁₆`, carrying
    ///    `Z_j = R_j − I` by the cancellation-free recurrence
    ///    `Z_{j+1} = (R_{j+1} + I)⁻¹ Z_j` (so `Z_k` keeps a relative accuracy of
    ///    O(kε) instead of losing `2^k ε/‖log A‖` to a subtraction). The roots
    ///    are taken
    ///    - if every eigenvalue has `|arg λ| ≤` [`LOG_DB_MAX_ARG`] (2.9) and
    ///      `κ₁(A) ≤` [`LOG_DB_MAX_COND`] (30): of `R₀ = A` by the
    ///      Denman–Beavers iteration ([`sqrtm_db`]), which is accurate to a few
    ///      ε there (the Schur form's own backward error, ~10–40ε from the
    ///      accumulated reflections, is avoided);
    ///    - otherwise: of `R₀ = T` by the real Schur method
    ///      ([`sqrt_quasi_triangular`]), whose closed-form 2×2 block roots do
    ///      not cancel near the negative axis (the Denman–Beavers error there
    ///      grows like `ε/(π − θ)²` for eigenvalues `e^{±iθ}`) and whose
    ///      backward error does not grow with κ(A) (Denman–Beavers: ~κε);
    /// 3. `log R₀ = 2^k r_m(Z_k)` with the cheapest Padé degree `m ≤ 16` whose
    ///    `θ_m ≥ ‖Z_k‖₁` ([`log1p_pade`]), and `log A = Q log T Qᵀ` on the
    ///    Schur path.
    ///
    /// Near the negative axis (eigenvalues `e^{±iθ}`, θ → π) the forward error
    /// grows like the condition number `θ/sin θ` of the logarithm in the
    /// directions that leave SO(n); within so(n) it stays O(ε).
    pub(crate) fn logm<const N: usize>(a: &Mat<N>, group: &'static str) -> Result<Mat<N>> {
        logm_switch(a, group, LOG_DB_MAX_ARG, LOG_DB_MAX_COND)
    }

    /// [`logm`] with the path switch at `db_max_arg`, `db_max_cond` (`−1`:
    /// always Schur; `∞, ∞`: always Denman–Beavers).
    pub(crate) fn logm_switch<const N: usize>(
        a: &Mat<N>,
        group: &'static str,
        db_max_arg: f64,
        db_max_cond: f64,
    ) -> Result<Mat<N>> {
        if !a.iter().all(|x| x.is_finite()) {
            return Err(Error::NotFinite { field: "group element" });
        }
        let Some((q, mut t)) = real_schur(a) else {
            return Err(Error::NoConvergence {
                what: "real Schur form (matrix logarithm)",
                iterations: 30 * N.max(10) * N,
                residual: f64::NAN,
            });
        };
        let blocks = Blocks::of(&mut t);
        let max_arg = spectrum_max_arg(&t, &blocks).map_err(|reason| Error::LogUndefined { group, reason })?;
        let well_conditioned = || Lu::new(a).is_some_and(|lu| norm1(a) * norm1(&lu.inverse()) <= db_max_cond);
        if max_arg <= db_max_arg && well_conditioned() {
            inverse_scaling_squaring(a, sqrtm_db)
        } else {
            // (Replacing the diagonal blocks of log T by their closed forms, as
            // [AH12] does for the diagonal, was tried: without also recomputing
            // the superdiagonal it breaks the consistency of log T and raised
            // the backward error on a triangular e^{±20} matrix from 0.9 to
            // 1160 ε·‖log T‖.)
            let l = inverse_scaling_squaring(&t, |r| {
                sqrt_quasi_triangular(r, &blocks).map_err(|reason| Error::LogUndefined { group, reason })
            })?;
            Ok(q * l * q.transpose())
        }
    }

    // ---------------------------------------------------------------------------
    // Polar factor (nearest orthogonal matrix)
    // ---------------------------------------------------------------------------

    /// `max |MᵀM − I|`, the orthogonality defect.
    pub(crate) fn orthogonality_defect<const N: usize>(m: &Mat<N>) -> f64 {
        amax(&(m.transpose() * m - Mat::<N>::identity()))
    }

    /// The orthogonal polar factor `U` of `M = U H` (the orthogonal matrix
    /// nearest to `M` in the Frobenius norm), for `det M > 0` (then `U ∈ SO(n)`).
    ///
    /// - near-orthogonal input (`‖MᵀM − I‖_F < 1/2`): Newton–Schulz / Björck–Bowie
    ///   \[BB71\] steps `X ← X(3I − XᵀX)/2 = X − X E/2`, `E = XᵀX − I`, which square
    ///   the defect (`E' ≈ −¾E²`); iterated until `‖E‖_F ≤ 10⁻⁸`, then one last
    ///   step brings it to round-off. From round-off input this is one step
    ///   (two products, no inverse);
    /// - otherwise scaled Newton `X ← (γX + X⁻ᵀ/γ)/2`, `γ = (‖X⁻¹‖_F/‖X‖_F)^{1/2}`
    ///   [H08, §8.6], until near-orthogonal;
    /// - `det M ≤ 0`: SVD `M = UΣVᵀ`, last singular vector flipped so the result
    ///   is in SO(n) (nearest rotation); non-finite input is returned unchanged.
    pub(crate) fn polar_factor<const N: usize>(m: &Mat<N>) -> Mat<N> {
        if !m.iter().all(|x| x.is_finite()) {
            return *m;
        }
        let id = Mat::<N>::identity();
        let mut x = *m;
        let d = det(&x);
        if !(d > 0.0) {
            return nearest_rotation_svd(m);
        }
        for _ in 0..100 {
            let e = x.transpose() * x - id;
            let ne = fro(&e);
            if ne < 0.5 {
                x -= x * e * 0.5;
                if ne <= 1e-8 {
                    return x;
                }
            } else {
                let Some(lu) = Lu::new(&x) else {
                    return nearest_rotation_svd(m);
                };
                let xinv = lu.inverse();
                let g = (fro(&xinv) / fro(&x)).sqrt();
                x = (x * g + xinv.transpose() / g) * 0.5;
            }
        }
        x
    }

    /// Nearest rotation by SVD (heap copy), used only for det ≤ 0 or breakdown.
    fn nearest_rotation_svd<const N: usize>(m: &Mat<N>) -> Mat<N> {
        let dm = DMatrix::from_column_slice(N, N, m.as_slice());
        let Some(svd) = nalgebra::linalg::SVD::try_new(dm, true, true, f64::EPSILON, 10_000) else {
            return nan_matrix();
        };
        let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
            return nan_matrix();
        };
        let mut u = u;
        // Orientation: det(U Vᵀ) = ±1; flip the column of the smallest singular value.
        let uvt = &u * &vt;
        let dd = uvt.determinant();
        if dd < 0.0 {
            let (imin, _) = svd.singular_values.argmin();
            for i in 0..N {
                u[(i, imin)] = -u[(i, imin)];
            }
        }
        let r = Mat::<N>::from_column_slice((u * vt).as_slice());
        // nalgebra's SVD vectors are orthogonal only to ~1e-15: one
        // Björck–Bowie step brings the result to round-off.
        r - r * (r.transpose() * r - Mat::<N>::identity()) * 0.5
    }
}

// ---------------------------------------------------------------------------
// GL⁺(n)
// ---------------------------------------------------------------------------

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

#[cfg(test)]
mod tests {
    use super::matfun::*;
    use nalgebra::SMatrix;

    fn pade_coeff(m: usize, j: usize) -> f64 {
        // b_j normalised so that b_m = 1: b_j ∝ (2m−j)!/(j!(m−j)!).
        let f = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
        f(2 * m - j) / (f(j) * f(m - j))
    }

    #[test]
    fn pade_coefficients_match_formula() {
        let check = |m: usize, b: &[f64]| {
            let norm = pade_coeff(m, m);
            for (j, &bj) in b.iter().enumerate() {
                let want = pade_coeff(m, j) / norm;
                assert!((bj - want).abs() <= 1e-15 * want, "m={m} j={j}: {bj} vs {want}");
            }
        };
        check(3, &PADE3);
        check(5, &PADE5);
        check(7, &PADE7);
        check(9, &PADE9);
        check(13, &PADE13);
    }

    #[test]
    fn gauss_legendre_rules_are_exact_for_polynomials() {
        for m in 1..=16 {
            let rule = &GAUSS_LEGENDRE[m - 1][..m];
            for p in 0..2 * m {
                let q: f64 = rule.iter().map(|&(t, w)| w * t.powi(p as i32)).sum();
                let exact = 1.0 / (p + 1) as f64;
                assert!((q - exact).abs() <= 4e-16, "m={m}, p={p}: {q} vs {exact}");
            }
        }
    }

    /// The θ_m of the log Padé approximants: forward error of r_m(x) for
    /// complex x on the circle |x| = θ_m (2×2 real representation) ≤ 2ε.
    #[test]
    fn log_pade_thresholds() {
        for m in 1..=16 {
            let th = LOG_THETA[m - 1];
            let mut worst: f64 = 0.0;
            for k in 0..64 {
                let ang = std::f64::consts::TAU * k as f64 / 64.0;
                let (re, im) = (th * ang.cos(), th * ang.sin());
                let x = SMatrix::<f64, 2, 2>::new(re, -im, im, re);
                let l = log1p_pade(&x, m).unwrap();
                let want_re = 0.5 * (2.0 * re + re * re + im * im).ln_1p();
                let want_im = im.atan2(1.0 + re);
                let err = ((l[(0, 0)] - want_re).powi(2) + (l[(1, 0)] - want_im).powi(2)).sqrt()
                    / (want_re.powi(2) + want_im.powi(2)).sqrt();
                worst = worst.max(err);
            }
            assert!(
                worst <= 2.0 * f64::EPSILON,
                "m={m}: relative error {worst:e} at |x| = θ_m"
            );
        }
    }

    #[test]
    fn lu_solves_and_detects_singularity() {
        let m = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let lu = Lu::new(&m).unwrap();
        assert!((lu.det() - m.determinant()).abs() < 1e-14);
        assert!(amax(&(lu.inverse() * m - SMatrix::<f64, 3, 3>::identity())) < 1e-15);
        let s = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 4.0);
        assert!(Lu::new(&s).is_none());
        assert_eq!(det(&s), 0.0);
    }

    #[test]
    fn skew_index_enumerates_upper_triangle() {
        let got: Vec<_> = (0..6).map(skew_index::<4>).collect();
        assert_eq!(got, vec![(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]);
    }

    fn check_schur<const N: usize>(a: &SMatrix<f64, N, N>) -> (f64, f64) {
        let (q, t) = real_schur(a).expect("Schur converges");
        for c in 0..N {
            for r in c + 2..N {
                assert_eq!(t[(r, c)], 0.0);
            }
        }
        for c in 0..N.saturating_sub(2) {
            // no two consecutive nonzero subdiagonals (blocks are at most 2×2)
            assert!(t[(c + 1, c)] == 0.0 || t[(c + 2, c + 1)] == 0.0, "{t}");
        }
        for c in 0..N.saturating_sub(1) {
            if t[(c + 1, c)] != 0.0 {
                // 2×2 blocks only for complex pairs (real ones are split)
                let p = 0.5 * (t[(c, c)] - t[(c + 1, c + 1)]);
                assert!(p * p + t[(c, c + 1)] * t[(c + 1, c)] < 0.0, "{t}");
            }
        }
        let orth = amax(&(q.transpose() * q - SMatrix::<f64, N, N>::identity()));
        let back = amax(&(q * t * q.transpose() - a)) / amax(a).max(f64::MIN_POSITIVE);
        (orth, back)
    }

    fn xorshift(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// Backward error and orthogonality of the real Schur form. Each Francis
    /// step adds 2–3ε of orthogonality loss (rounding of the reflectors), so
    /// after the 4–15 steps needed here the worst cases measured are
    /// orthogonality 15ε (3×3) / 19ε (5×5) and backward error 22ε / 38ε;
    /// bounds 32ε and 64ε (nalgebra's Schur: 30ε / 45ε on 3×3).
    #[test]
    fn real_schur_is_backward_stable() {
        let mut next = xorshift(99);
        let mut w = [(0.0f64, 0.0f64); 3];
        for _ in 0..500 {
            let r = [
                check_schur(&SMatrix::<f64, 2, 2>::from_fn(|_, _| next())),
                check_schur(&SMatrix::<f64, 3, 3>::from_fn(|_, _| next())),
                check_schur(&SMatrix::<f64, 5, 5>::from_fn(|_, _| next() * 10.0)),
            ];
            for (wi, ri) in w.iter_mut().zip(r) {
                *wi = (wi.0.max(ri.0), wi.1.max(ri.1));
            }
        }
        assert!(
            w.iter()
                .all(|&(o, b)| o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON),
            "{w:?}"
        );
        // Structured cases: identity, zero, Jordan block, rotation near π,
        // repeated eigenvalues, companion matrix of (x−1)(x−2)(x−3)(x−4).
        let _ = check_schur(&SMatrix::<f64, 4, 4>::identity());
        let _ = check_schur(&SMatrix::<f64, 4, 4>::zeros());
        let mut j = SMatrix::<f64, 4, 4>::identity() * 2.0;
        for i in 0..3 {
            j[(i, i + 1)] = 1.0;
        }
        let (o, b) = check_schur(&j);
        assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON);
        let th = std::f64::consts::PI - 1e-6;
        let r = SMatrix::<f64, 3, 3>::new(th.cos(), -th.sin(), 0.0, th.sin(), th.cos(), 0.0, 0.0, 0.0, 1.0);
        let p = SMatrix::<f64, 3, 3>::new(0.0, 0.6, 0.8, 1.0, 0.0, 0.0, 0.0, 0.8, -0.6);
        let (o, b) = check_schur(&(p * r * p.transpose()));
        assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON);
        let c = SMatrix::<f64, 4, 4>::new(
            10.0, -35.0, 50.0, -24.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
        );
        let (o, b) = check_schur(&c);
        assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON, "{o:e} {b:e}");
    }

    /// Log round-trip errors of the two square-root paths as the eigenvalue
    /// angle θ approaches π: the switch `LOG_DB_MAX_ARG` must pick the better
    /// one (within a factor 2) at every angle.
    #[test]
    fn log_paths_crossover() {
        let mut next = xorshift(5);
        for &th in &[1.0, 2.0, 2.2, 2.4, 2.6, 2.8, 3.0, 3.1, std::f64::consts::PI - 0.0016] {
            let mut w = [0.0f64; 3];
            for _ in 0..300 {
                // a = P diag(θJ, x) P⁻¹ with random P (non-normal, moderately conditioned).
                let p = SMatrix::<f64, 3, 3>::identity() + SMatrix::<f64, 3, 3>::from_fn(|_, _| 0.3 * next());
                let d = SMatrix::<f64, 3, 3>::new(0.1 * next(), -th, 0.0, th, 0.1 * next(), 0.0, 0.0, 0.0, next());
                let a = p * d * Lu::new(&p).unwrap().inverse();
                let g = expm(&a);
                let paths = [
                    (10.0, f64::INFINITY),
                    (-1.0, f64::INFINITY),
                    (LOG_DB_MAX_ARG, LOG_DB_MAX_COND),
                ];
                for (i, &(sw, cond)) in paths.iter().enumerate() {
                    let l = logm_switch(&g, "test", sw, cond).unwrap();
                    w[i] = w[i].max(amax(&(l - a)) / amax(&a));
                }
            }
            println!("θ = {th}: DB {:.1e}  Schur {:.1e}  logm {:.1e}", w[0], w[1], w[2]);
            assert!(
                w[2] <= 2.0 * w[0].min(w[1]),
                "θ = {th}: the switch picks the worse path"
            );
        }
    }

    /// The measurement behind `LOG_DB_MAX_COND` (slow in the dev profile;
    /// run with `--ignored --nocapture`): worst forward error
    /// `|log(exp A) − A|/|A|` and backward error `|exp(log g) − g|/(|g||A|)`,
    /// in ε, of the two square-root paths binned by κ₁(exp A).
    #[test]
    #[ignore]
    fn log_path_measurement() {
        let mut st = 12345u64;
        type M3 = SMatrix<f64, 3, 3>;
        let mut next = move || {
            st ^= st << 13;
            st ^= st >> 7;
            st ^= st << 17;
            (st >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        // bins of log10 kappa
        let mut w = [[0.0f64; 4]; 12];
        let mut cnt = [0usize; 12];
        for _ in 0..20000 {
            let r1 = 12.0 * (next() + 1.0) / 2.0;
            let r2 = 3.0 * (next() + 1.0) / 2.0;
            let s0 = M3::from_fn(|_, _| next());
            let s0 = s0 + s0.transpose();
            let w0 = M3::from_fn(|_, _| next());
            let w0 = w0 - w0.transpose();
            let n0 = M3::from_fn(|_, _| next());
            let a = s0 * (r1 / s0.norm()) + w0 * (r2 / w0.norm()) + n0 * (0.5 * next());
            let g = expm(&a);
            let ginv = Lu::new(&g).unwrap().inverse();
            let kappa = norm1(&g) * norm1(&ginv);
            let bin = (kappa.log10() as usize).min(11);
            cnt[bin] += 1;
            for (i, sw) in [10.0, -1.0].iter().enumerate() {
                let Ok(l) = logm_switch(&g, "t", *sw, f64::INFINITY) else {
                    continue;
                };
                let fwd = amax(&(l - a)) / amax(&a) / f64::EPSILON;
                let back = amax(&(expm(&l) - g)) / amax(&g) / f64::EPSILON / a.norm();
                w[bin][2 * i] = w[bin][2 * i].max(fwd);
                w[bin][2 * i + 1] = w[bin][2 * i + 1].max(back);
            }
        }
        for (b, row) in w.iter().enumerate() {
            print!("n={} ", cnt[b]);
            println!(
                "kappa 1e{b}: DB fwd {:.1} back {:.2} | Schur fwd {:.1} back {:.2}",
                row[0], row[1], row[2], row[3]
            );
        }
    }
}
