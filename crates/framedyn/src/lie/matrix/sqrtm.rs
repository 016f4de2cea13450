//! Principal matrix square roots, the two the logarithm takes: the
//! Denman–Beavers iteration in product form \[CHKL01\] on a full matrix
//! ([`sqrtm_db`]), and the real Schur method [H08 §6.2] on a
//! quasi-triangular one ([`sqrt_quasi_triangular`]), whose closed-form
//! 2×2 block roots do not cancel near the negative real axis.
//!
//! References:
//! - \[CHKL01\] S. H. Cheng, N. J. Higham, C. S. Kenney, A. J. Laub, *Approximating
//!   the logarithm of a matrix to specified accuracy*, SIAM J. Matrix Anal.
//!   Appl. 22 (2001) 1112–1125 (product form of the Denman–Beavers iteration).
//! - \[H08\] N. J. Higham, *Functions of Matrices*, SIAM 2008 (§6).

use nalgebra::SMatrix;

use super::lu::Lu;
use super::norm::norm1;
use super::schur::{block_eigen, Blocks};
use super::Mat;
use crate::{Error, Result};

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
/// −1 — see [`logm`](fn@super::logm) for when it is used.
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
            let x = small_sylvester(&uii, p, &uj, q, &rhs).ok_or("singular Sylvester equation in the square root")?;
            for i in 0..p {
                for j in 0..q {
                    u[(ri + i, cj + j)] = x[(i, j)];
                }
            }
        }
    }
    Ok(u)
}
