//! The matrix exponential by scaling and squaring with Padé approximants
//! \[H05\] ([`expm`]), and the pair `(exp A, exp(−A))` from one Padé
//! evaluation that `dexp` uses.
//!
//! Reference: \[H05\] N. J. Higham, *The scaling and squaring method for the
//! matrix exponential revisited*, SIAM J. Matrix Anal. Appl. 26 (2005) 1179–1193.

use super::lu::Lu;
use super::norm::norm1;
use super::{nan_matrix, Mat};

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
pub const PADE3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
/// The coefficients of the [5/5] approximant (see [`PADE3`]).
pub const PADE5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
/// The coefficients of the [7/7] approximant (see [`PADE3`]).
pub const PADE7: [f64; 8] = [17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0];
/// The coefficients of the [9/9] approximant (see [`PADE3`]).
pub const PADE9: [f64; 10] = [
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
/// The coefficients of the [13/13] approximant (see [`PADE3`]).
pub const PADE13: [f64; 14] = [
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
pub fn expm<const N: usize>(a: &Mat<N>) -> Mat<N> {
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
pub(super) fn expm_pair<const N: usize>(a: &Mat<N>) -> (Mat<N>, Mat<N>) {
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
