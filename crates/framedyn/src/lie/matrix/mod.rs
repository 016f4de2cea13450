//! Fixed-size dense matrix functions: the numerics behind the general-`n`
//! matrix groups [`Gl`](super::Gl), [`Sl`](super::Sl), [`SoN`](super::SoN)
//! and [`Co`](super::Co) (and the affine-body dynamics, which uses the
//! determinant, LU and the projections onto so(n) and sl(n)).
//!
//! Everything works on stack-allocated [`Mat<N>`] = `SMatrix<f64, N, N>`;
//! nothing here allocates except the SVD fallback of the polar factor for
//! det ≤ 0. A function evaluated at an argument where it is undefined
//! returns a NaN matrix ([`nan_matrix`]) or, where the caller must be told
//! why (square root, logarithm), a typed [`Error`](crate::Error).
//!
//! One file per function family, each citing the literature it follows:
//!
//! | file | contents | references |
//! |------|----------|------------|
//! | `lu.rs` | LU with partial pivoting ([`Lu`]), determinant ([`det`]) | |
//! | `norm.rs` | 1-norm, max-norm, Frobenius norm | |
//! | `algebra.rs` | gl(n): commutator, skew and traceless parts, so(n) basis order | |
//! | `expm.rs` | matrix exponential, scaling and squaring with Padé ([`expm`](fn@expm)) | \[H05\] |
//! | `dexp.rs` | `dexp` and `dexp⁻¹` on gl(n) and so(n) ([`dexp_matrix`], [`dexp_inv_matrix`]) | \[IMNZ00\] |
//! | `schur.rs` | real Schur form (own Francis QR), its diagonal blocks | \[GVL13\] |
//! | `sqrtm.rs` | principal square root: Denman–Beavers, real Schur method | \[CHKL01\], \[H08\] |
//! | `log_pade.rs` | Padé approximants of `log(I + X)` in partial fractions | \[H01\], \[AH12\] |
//! | `logm.rs` | principal logarithm, inverse scaling and squaring ([`logm`](fn@logm)) | \[AH12\], \[H08\] |
//! | `polar.rs` | orthogonal polar factor, nearest rotation ([`polar_factor`]) | \[BB71\], \[H08\] |
//!
//! `lu`, `norm` and `algebra` underlie the rest; `dexp` builds on `expm` and
//! `polar`, `sqrtm` on `schur`, and `logm` on `schur`, `sqrtm` and
//! `log_pade`.
//!
//! Each file cites in full the references it follows; their keys: \[H05\]
//! Higham 2005, \[IMNZ00\] Iserles, Munthe-Kaas, Nørsett, Zanna 2000,
//! \[GVL13\] Golub, Van Loan 2013, \[CHKL01\] Cheng, Higham, Kenney, Laub
//! 2001, \[H01\] Higham 2001, \[AH12\] Al-Mohy, Higham 2012, \[BB71\]
//! Björck, Bowie 1971, \[H08\] Higham, *Functions of Matrices*, 2008.

// NaN-rejecting comparisons such as `!(x > 0.0)` are intentional here.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub(crate) mod algebra;
mod dexp;
pub(crate) mod expm;
pub(crate) mod log_pade;
pub(crate) mod logm;
pub(crate) mod lu;
pub(crate) mod norm;
mod polar;
pub(crate) mod schur;
mod sqrtm;

pub(crate) use algebra::{commutator, skew_index, skew_part, traceless_part};
pub(crate) use dexp::{dexp_inv_matrix, dexp_matrix, Basis};
pub(crate) use expm::expm;
pub(crate) use logm::logm;
pub(crate) use lu::{det, Lu};
pub(crate) use norm::{amax, norm1};
pub(crate) use polar::{orthogonality_defect, polar_factor};

use nalgebra::SMatrix;

/// Square `N×N` matrix of `f64`, the storage of every general-`n` group here.
pub type Mat<const N: usize> = SMatrix<f64, N, N>;

/// A matrix of NaNs: the result of a matrix function at an invalid argument.
pub(crate) fn nan_matrix<const N: usize>() -> Mat<N> {
    Mat::<N>::from_element(f64::NAN)
}
