//! SO(3): rotations of space, stored as a rotation matrix.

use nalgebra::{DMatrix, Matrix3, Vector3, Vector4};

use super::special::{dexp_cross, dexp_inv_cross, sinc_cosc};
use super::LieGroup;
use crate::{Error, Result};

/// A rotation of ℝ³, stored as its 3×3 matrix `R` (`RᵀR = I`, `det R = 1`).
///
/// **Algebra.** `Vector3` `ω` with `hat(ω) = [[0, −ω₃, ω₂], [ω₃, 0, −ω₁], [−ω₂, ω₁, 0]]`
/// (so `hat(ω)·v = ω × v`); the bracket is the cross product,
/// `[a, b] = a × b`, and `Ad_R ω = R ω`.
///
/// **Closed forms**, with `s = θ² = |ω|²` and the coefficient functions of
/// [`special`](super::special) (analytic in `s`, accurate near `θ = 0`):
/// - `exp(ω) = I + sinc(s)·hat(ω) + cosc(s)·hat(ω)²` (Rodrigues);
/// - `dexp_ω(v) = v + cosc(s)·ω × v + sinc3(s)·ω × (ω × v)`;
/// - `dexp_ω⁻¹(v) = v − ½·ω × v + dexpinv(s)·ω × (ω × v)` (singular at `θ = 2π`).
///
/// These follow from `ad_ω³ = −s·ad_ω` applied to the series of
/// [`LieGroup::dexp`] and [`LieGroup::dexp_inv`].
///
/// **Logarithm.** The rotation's unit quaternion `(w, v)` is extracted with
/// Shepperd's method (from the largest of `1 + tr R`, `1 + 2R_ii − tr R`,
/// which is ≥ 1, so no division by a small number), sign-fixed to `w ≥ 0`, and
/// `ω = 2·atan2(|v|, w)·v/|v|`. This is accurate to round-off for every
/// rotation, including near `θ = π` where the textbook formula
/// `θ/(2 sin θ)(R − Rᵀ)` loses all digits; at `θ = π` exactly one of the two
/// valid axes `±n` is returned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So3 {
    m: Matrix3<f64>,
}

impl So3 {
    /// Largest orthonormality/determinant defect accepted by [`So3::new`].
    pub const TOLERANCE: f64 = 1e-9;

    /// The rotation with matrix `m`. Fails unless `m` is finite, `|mᵀm − I|`
    /// (max entry) and `|det m − 1|` are ≤ [`So3::TOLERANCE`]; the accepted
    /// matrix is replaced by the nearest rotation.
    pub fn new(m: Matrix3<f64>) -> Result<Self> {
        crate::error::finite("So3 matrix", m.iter())?;
        let g = So3 { m };
        let defect = g.constraint_defect();
        if defect > Self::TOLERANCE {
            return Err(Error::Constraint {
                field: "So3 matrix",
                constraint: "RᵀR = I and det R = 1",
                defect,
                tolerance: Self::TOLERANCE,
            });
        }
        Ok(g.renormalize())
    }

    /// The matrix `m` stored as is, without validation (hot paths).
    #[inline]
    pub fn new_unchecked(m: Matrix3<f64>) -> Self {
        So3 { m }
    }

    /// The rotation matrix.
    #[inline]
    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.m
    }

    /// Rotates the vector `v`: `R v`.
    #[inline]
    pub fn act(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.m * v
    }

    /// `hat(ω) = [[0, −ω₃, ω₂], [ω₃, 0, −ω₁], [−ω₂, ω₁, 0]]`, so `hat(ω) v = ω × v`.
    #[inline]
    pub fn hat(w: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::new(0.0, -w[2], w[1], w[2], 0.0, -w[0], -w[1], w[0], 0.0)
    }

    /// Inverse of [`So3::hat`] on the skew part: `vee(m) = vee((m − mᵀ)/2)`.
    #[inline]
    pub fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
        Vector3::new(
            0.5 * (m[(2, 1)] - m[(1, 2)]),
            0.5 * (m[(0, 2)] - m[(2, 0)]),
            0.5 * (m[(1, 0)] - m[(0, 1)]),
        )
    }

    /// The unit quaternion `(w, x, y, z)` of the rotation with `w ≥ 0`
    /// (Shepperd's method; the [`Su2`](super::Su2) element over `R` in the
    /// half-sphere `w ≥ 0`). For a matrix with round-off drift the result is
    /// normalised.
    pub fn quaternion(&self) -> Vector4<f64> {
        let q = shepperd(&self.m);
        let n = q.norm();
        if n > 0.0 && n.is_finite() {
            q / n
        } else {
            q
        }
    }

    /// The rotation angle `θ ∈ [0, π]` (accurate everywhere, see the type docs).
    pub fn angle(&self) -> f64 {
        let q = shepperd(&self.m);
        2.0 * q.fixed_rows::<3>(1).norm().atan2(q[0])
    }

    /// The nearest rotation by a singular value decomposition (fallback of
    /// [`LieGroup::renormalize`] for matrices far from SO(3) or with negative
    /// determinant); `None` if the SVD does not converge.
    fn nearest_by_svd(m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
        let svd = m.try_svd(true, true, f64::EPSILON, 500)?;
        let (u, vt) = (svd.u?, svd.v_t?);
        let mut d = Matrix3::identity();
        if (u * vt).determinant() < 0.0 {
            let k = svd.singular_values.imin();
            d[(k, k)] = -1.0;
        }
        Some(u * d * vt)
    }
}

/// Shepperd's quaternion extraction (unnormalised if `m` is not exactly
/// orthogonal), `w ≥ 0`. Each branch divides by `r = √(1 + …) ≥ 1` for a rotation.
fn shepperd(m: &Matrix3<f64>) -> Vector4<f64> {
    let (m00, m11, m22) = (m[(0, 0)], m[(1, 1)], m[(2, 2)]);
    let t = m00 + m11 + m22;
    let q = if t >= m00 && t >= m11 && t >= m22 {
        let r = (1.0 + t).sqrt();
        let f = 0.5 / r;
        Vector4::new(0.5 * r, (m[(2, 1)] - m[(1, 2)]) * f, (m[(0, 2)] - m[(2, 0)]) * f, (m[(1, 0)] - m[(0, 1)]) * f)
    } else if m00 >= m11 && m00 >= m22 {
        let r = (1.0 + m00 - m11 - m22).sqrt();
        let f = 0.5 / r;
        Vector4::new((m[(2, 1)] - m[(1, 2)]) * f, 0.5 * r, (m[(0, 1)] + m[(1, 0)]) * f, (m[(0, 2)] + m[(2, 0)]) * f)
    } else if m11 >= m22 {
        let r = (1.0 - m00 + m11 - m22).sqrt();
        let f = 0.5 / r;
        Vector4::new((m[(0, 2)] - m[(2, 0)]) * f, (m[(0, 1)] + m[(1, 0)]) * f, 0.5 * r, (m[(1, 2)] + m[(2, 1)]) * f)
    } else {
        let r = (1.0 - m00 - m11 + m22).sqrt();
        let f = 0.5 / r;
        Vector4::new((m[(1, 0)] - m[(0, 1)]) * f, (m[(0, 2)] + m[(2, 0)]) * f, (m[(1, 2)] + m[(2, 1)]) * f, 0.5 * r)
    };
    if q[0] < 0.0 {
        -q
    } else {
        q
    }
}

/// `ω = 2·atan2(|v|, w)·v/|v|` for the quaternion `(w, v)` (scale invariant;
/// `ω = 0` for `v = 0`, `w > 0`). Shared with [`Su2`](super::Su2).
pub(crate) fn quaternion_log_vector(q: &Vector4<f64>) -> Vector3<f64> {
    let v = Vector3::new(q[1], q[2], q[3]);
    let n = v.norm();
    if n == 0.0 {
        Vector3::zeros()
    } else {
        v * (2.0 * n.atan2(q[0]) / n)
    }
}

impl LieGroup for So3 {
    type Algebra = Vector3<f64>;
    const DOF: usize = 3;
    const NAME: &'static str = "SO(3)";

    #[inline]
    fn identity() -> Self {
        So3 { m: Matrix3::identity() }
    }
    #[inline(always)]
    fn compose(&self, rhs: &Self) -> Self {
        So3 { m: self.m * rhs.m }
    }
    /// The transpose.
    #[inline]
    fn inverse(&self) -> Self {
        So3 { m: self.m.transpose() }
    }
    /// Rodrigues: `I + sinc(θ²)·hat(ω) + cosc(θ²)·hat(ω)²`, with
    /// `hat(ω)² = ωωᵀ − θ² I`.
    #[inline(always)]
    fn exp(a: &Self::Algebra) -> Self {
        let s = a.norm_squared();
        let (sa, ca) = sinc_cosc(s);
        let k = Self::hat(a);
        let k2 = a * a.transpose() - Matrix3::identity() * s;
        So3 { m: Matrix3::identity() + k * sa + k2 * ca }
    }
    /// Principal logarithm, `θ = |ω| ∈ [0, π]`, via the quaternion (see the
    /// type docs). Fails only for a non-finite matrix.
    fn log(&self) -> Result<Self::Algebra> {
        if !self.m.iter().all(|x| x.is_finite()) {
            return Err(Error::LogUndefined { group: Self::NAME, reason: "matrix is not finite" });
        }
        Ok(quaternion_log_vector(&shepperd(&self.m)))
    }
    /// `R ω`.
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        self.m * a
    }
    /// `a × b`.
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        a.cross(b)
    }
    /// `v + cosc(s)·a × v + sinc3(s)·a × (a × v)`, `s = |a|²`.
    #[inline]
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_cross(a, v)
    }
    /// `v − ½·a × v + dexpinv(s)·a × (a × v)`, `s = |a|²` (valid for `|a| < 2π`).
    #[inline]
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        dexp_inv_cross(a, v)
    }
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        Vector3::new(c[0], c[1], c[2])
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        vec![a[0], a[1], a[2]]
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_fn(3, 3, |i, j| self.m[(i, j)])
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let h = Self::hat(a);
        DMatrix::from_fn(3, 3, |i, j| h[(i, j)])
    }
    /// `max(max|RᵀR − I|, |det R − 1|)`.
    fn constraint_defect(&self) -> f64 {
        let o = (self.m.transpose() * self.m - Matrix3::identity()).amax();
        o.max((self.m.determinant() - 1.0).abs())
    }
    /// The nearest rotation in the Frobenius norm (the orthogonal polar factor
    /// when `det > 0`). Near SO(3) (`max|RᵀR − I| ≤ ½`) by the quadratically
    /// convergent Newton–Schulz iteration `R ← R(3I − RᵀR)/2` (one step for
    /// round-off drift); otherwise, or if the result is a reflection, by an
    /// SVD `U diag(1, 1, ±1) Vᵀ`. Non-finite matrices are returned unchanged.
    #[inline]
    fn renormalize(&self) -> Self {
        // The integrators' case, inline: round-off drift, one Newton–Schulz
        // step. `Σ|dᵢⱼ|` is NaN for a non-finite matrix, which fails the test.
        let d = self.m.tr_mul(&self.m) - Matrix3::identity();
        if d.iter().fold(0.0, |acc, x| acc + x.abs()) < 1e-8 {
            let x = self.m - self.m * d * 0.5;
            if x.determinant() > 0.0 {
                return So3 { m: x };
            }
        }
        self.renormalize_general()
    }
}

impl So3 {
    /// [`LieGroup::renormalize`] beyond round-off drift (out of line).
    #[cold]
    #[inline(never)]
    fn renormalize_general(&self) -> Self {
        if !self.m.iter().all(|x| x.is_finite()) {
            return *self;
        }
        let mut x = self.m;
        let mut converged = false;
        for _ in 0..12 {
            let d = x.transpose() * x - Matrix3::identity();
            let e = d.amax();
            if e > 0.5 {
                break;
            }
            x -= x * d * 0.5;
            if e < 1e-8 {
                converged = true;
                break;
            }
        }
        if converged && x.determinant() > 0.0 {
            So3 { m: x }
        } else {
            Self::nearest_by_svd(&self.m).map_or(*self, |m| So3 { m })
        }
    }
}
