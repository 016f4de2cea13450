//! `dexp_A = φ(ad_A)`, `φ(z) = (e^z − 1)/z`, and its inverse on gl(n) and
//! so(n) \[IMNZ00\], in the convention of [`LieGroup::dexp`](crate::lie::LieGroup::dexp)
//! (`d/dt exp(A(t)) = dexp_A(Ȧ)·exp(A)`): `dexp` exactly for every `A` by
//! "scaling and doubling" ([`dexp_apply`]); `dexp⁻¹` by the Bernoulli
//! series for small `A`, else by a linear solve in a [`Basis`] of the
//! algebra ([`dexp_inv_matrix`]).
//!
//! Reference: \[IMNZ00\] A. Iserles, H. Munthe-Kaas, S. Nørsett, A. Zanna,
//! *Lie-group methods*, Acta Numerica 9 (2000) 215–365 (dexp, dexp⁻¹).

use super::algebra::{commutator, skew_index};
use super::expm::{expm, expm_pair};
use super::norm::{amax, fro};
use super::polar::polar_factor;
use super::{nan_matrix, Mat};
use crate::lie::BERNOULLI_OVER_FACTORIAL;

/// `Ad_g x = g x g⁻¹` with `g⁻¹` supplied.
#[inline]
fn conj<const N: usize>(g: &Mat<N>, x: &Mat<N>, ginv: &Mat<N>) -> Mat<N> {
    g * x * ginv
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
