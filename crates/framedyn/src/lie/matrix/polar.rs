//! The orthogonal polar factor, the rotation nearest to a matrix in the
//! Frobenius norm ([`polar_factor`]: Björck–Bowie steps \[BB71\] near
//! orthogonality, scaled Newton [H08 §8.6] farther away, an SVD for
//! det ≤ 0), and the orthogonality defect.
//!
//! References:
//! - \[BB71\] Å. Björck, C. Bowie, *An iterative algorithm for computing the best
//!   estimate of an orthogonal matrix*, SIAM J. Numer. Anal. 8 (1971) 358–364.
//! - \[H08\] N. J. Higham, *Functions of Matrices*, SIAM 2008 (§8).

use nalgebra::DMatrix;

use super::lu::{det, Lu};
use super::norm::{amax, fro};
use super::{nan_matrix, Mat};

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
