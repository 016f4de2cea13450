//! The principal matrix logarithm by inverse scaling and squaring \[AH12\],
//! [H08 §11.5] ([`logm`]): real Schur form and spectrum test, square roots
//! by one of the two methods of `sqrtm` (the switch between them is
//! measured, see [`LOG_DB_MAX_ARG`] and [`LOG_DB_MAX_COND`]), then a Padé
//! approximant of `log(I + Z)`.
//!
//! References:
//! - \[AH12\] A. H. Al-Mohy, N. J. Higham, *Improved inverse scaling and squaring
//!   algorithms for the matrix logarithm*, SIAM J. Sci. Comput. 34 (2012) C153–C169.
//! - \[H08\] N. J. Higham, *Functions of Matrices*, SIAM 2008 (§11).

use super::log_pade::{log1p_pade, LOG_THETA};
use super::lu::Lu;
use super::norm::norm1;
use super::schur::{block_eigen, real_schur, Blocks};
use super::sqrtm::{sqrt_quasi_triangular, sqrtm_db};
use super::Mat;
use crate::{Error, Result};

/// Largest number of square roots taken by the logarithm.
const LOG_MAX_SQRT: usize = 100;

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

/// Largest `|arg λ|` for which `logm` takes its square roots by the
/// Denman–Beavers iteration on the full matrix; beyond it (eigenvalues
/// within 0.24 rad of the negative axis, where the iteration's first step
/// `(2I + A + A⁻¹)/4` cancels like `cos²(arg λ/2)`) it uses the real Schur
/// form. Measured crossover (the `log_paths_crossover` test, 3×3
/// non-normal): DB/Schur worst errors 1.9e-15/3.8e-15 at θ = 2.6,
/// 8.3e-15/1.5e-14 at 3.0, 1.2e-13/4.1e-14 at 3.1, 3.1e-11/6.6e-13 at 3.14.
pub const LOG_DB_MAX_ARG: f64 = 2.9;

/// Largest 1-norm condition number `κ₁(A)` for which `logm` uses the
/// Denman–Beavers square roots: their inverses lose `κ·ε`, while the
/// Schur path's backward error (10–40ε, from the Schur form itself) does
/// not depend on κ. Measured on 20 000 random 3×3 `exp(S + W + N)`
/// (`debug` experiment, worst backward error `‖exp(log g) − g‖/(‖g‖‖A‖ε)`,
/// DB vs Schur): 5.1 vs 26 for κ < 10, 7.2 vs 14 for κ ∈ [10, 100),
/// 92 vs 13 for κ ∈ [100, 1000), 1.3e3 vs 14 for κ ∈ [1e3, 1e4).
pub const LOG_DB_MAX_COND: f64 = 30.0;

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

/// `logm` with the path switch at `db_max_arg`, `db_max_cond` (`−1`:
/// always Schur; `∞, ∞`: always Denman–Beavers).
pub fn logm_switch<const N: usize>(
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
