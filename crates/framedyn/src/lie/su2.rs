//! SU(2): unit quaternions, the double cover of SO(3) (paper §6).

use nalgebra::{Complex, DMatrix, Matrix2, Matrix4, Vector3, Vector4};

use super::so3::quaternion_log_vector;
use super::special::{dexp_cross, dexp_inv_cross, sinc};
use super::{LieGroup, So3};
use crate::{Error, Result};

/// An element of SU(2), stored as the unit quaternion `q = w + x i + y j + z k`
/// (components in the order `(w, x, y, z)`).
///
/// **Identification with the paper (§6).** `q` is the matrix
/// `u = w I₂ − i(x σ₁ + y σ₂ + z σ₃)`, and the Lie-algebra basis is the
/// paper's `a_J = σ_J/(2i) = −(i/2)σ_J`, which corresponds to the quaternion
/// `e_J/2` (`e₁, e₂, e₃ = i, j, k`). Algebra coordinates `k ∈ ℝ³` stand for
/// `k^J a_J`; then `[a_J, a_K] = ε_JKM a_M` (the bracket is the cross product)
/// and (a171)
/// `exp(k) = cos(|k|/2) + sin(|k|/2)·k/|k|`,
/// which maps to the SO(3) rotation by the rotation vector `k`
/// ([`Su2::to_so3`]). `exp` has period `4π` in `|k|`; `exp(k) = −1` for every
/// `|k| = 2π`.
///
/// **Matrix representation** ([`LieGroup::to_matrix`]): the real 4×4 matrix of
/// left multiplication `p ↦ q·p` on `(w, x, y, z)` — faithful, and
/// [`LieGroup::algebra_to_matrix`] is that of the quaternion `(0, k/2)`.
///
/// **Closed forms** (`s = |k|²`; `ad_k` is the cross product, as for SO(3)):
/// `dexp_k(v) = v + cosc(s)·k × v + sinc3(s)·k × (k × v)`,
/// `dexp_k⁻¹(v) = v − ½·k × v + dexpinv(s)·k × (k × v)` (valid for `|k| < 2π`),
/// `Ad_q k = R(q)·k`.
///
/// **Logarithm.** `k = 2·atan2(|v|, w)·v/|v|`, so `|k| ∈ [0, 2π]`: the inverse
/// of `exp` on `|k| < 2π`. At `q = −1` every `|k| = 2π` is a logarithm and
/// [`LieGroup::log`] fails with [`Error::LogUndefined`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Su2 {
    /// `(w, x, y, z)`.
    q: Vector4<f64>,
}

/// Quaternion product `a·b`, components `(w, x, y, z)`.
#[inline]
fn qmul(a: &Vector4<f64>, b: &Vector4<f64>) -> Vector4<f64> {
    Vector4::new(
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] + a[2] * b[0] + a[3] * b[1] - a[1] * b[3],
        a[0] * b[3] + a[3] * b[0] + a[1] * b[2] - a[2] * b[1],
    )
}

/// Left-multiplication matrix `L(q)`: `L(q)·p = q·p`.
#[inline]
fn left_matrix(q: &Vector4<f64>) -> Matrix4<f64> {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    Matrix4::new(w, -x, -y, -z, x, w, -z, y, y, z, w, -x, z, -y, x, w)
}

impl Su2 {
    /// Largest `|w² + x² + y² + z² − 1|` accepted by [`Su2::new`].
    pub const TOLERANCE: f64 = 1e-9;

    /// The element `w + x i + y j + z k`. Fails unless all four are finite and
    /// `|w² + x² + y² + z² − 1| ≤` [`Su2::TOLERANCE`]; the accepted quaternion
    /// is renormalised to unit length.
    pub fn new(w: f64, x: f64, y: f64, z: f64) -> Result<Self> {
        crate::error::finite("Su2 quaternion (w, x, y, z)", [w, x, y, z].iter())?;
        let g = Self::new_unchecked(w, x, y, z);
        let defect = g.constraint_defect();
        if defect > Self::TOLERANCE {
            return Err(Error::Constraint {
                field: "Su2 quaternion (w, x, y, z)",
                constraint: "w² + x² + y² + z² = 1",
                defect,
                tolerance: Self::TOLERANCE,
            });
        }
        Ok(g.renormalize())
    }

    /// The quaternion stored as is, without validation (hot paths).
    #[inline]
    pub fn new_unchecked(w: f64, x: f64, y: f64, z: f64) -> Self {
        Su2 { q: Vector4::new(w, x, y, z) }
    }

    /// The quaternion `(w, x, y, z)`.
    #[inline]
    pub fn quaternion(&self) -> Vector4<f64> {
        self.q
    }

    /// The scalar part `w`.
    #[inline]
    pub fn scalar(&self) -> f64 {
        self.q[0]
    }

    /// The vector part `(x, y, z)`.
    #[inline]
    pub fn vector(&self) -> Vector3<f64> {
        Vector3::new(self.q[1], self.q[2], self.q[3])
    }

    /// The rotation `R(q)` (`R(q)v = q v q̄`), for a unit quaternion:
    /// `R = (w² − |v|²) I + 2 v vᵀ + 2 w hat(v)`. The covering map
    /// SU(2) → SO(3): `Su2::exp(k).to_so3() = So3::exp(k)`.
    pub fn to_so3(&self) -> So3 {
        let (w, v) = (self.q[0], self.vector());
        let m = nalgebra::Matrix3::identity() * (w * w - v.norm_squared())
            + v * v.transpose() * 2.0
            + So3::hat(&v) * (2.0 * w);
        So3::new_unchecked(m)
    }

    /// Rotates the vector `v` by the SO(3) image of `q`: `q v q̄`.
    #[inline]
    pub fn act(&self, v: &Vector3<f64>) -> Vector3<f64> {
        // v + 2w (u × v) + 2 u × (u × v), u the vector part.
        let u = self.vector();
        let t = u.cross(v) * 2.0;
        v + t * self.q[0] + u.cross(&t)
    }

    /// The paper's complex 2×2 matrix `u = w I₂ − i(x σ₁ + y σ₂ + z σ₃)`
    /// = `[[w − i z, −y − i x], [y − i x, w + i z]]`.
    pub fn to_complex_matrix(&self) -> Matrix2<Complex<f64>> {
        let (w, x, y, z) = (self.q[0], self.q[1], self.q[2], self.q[3]);
        Matrix2::new(Complex::new(w, -z), Complex::new(-y, -x), Complex::new(y, -x), Complex::new(w, z))
    }
}

impl LieGroup for Su2 {
    type Algebra = Vector3<f64>;
    const DOF: usize = 3;
    const NAME: &'static str = "SU(2)";

    #[inline]
    fn identity() -> Self {
        Su2::new_unchecked(1.0, 0.0, 0.0, 0.0)
    }
    /// Quaternion product.
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Su2 { q: qmul(&self.q, &rhs.q) }
    }
    /// Quaternion conjugate (the inverse of a unit quaternion).
    #[inline]
    fn inverse(&self) -> Self {
        Su2::new_unchecked(self.q[0], -self.q[1], -self.q[2], -self.q[3])
    }
    /// `(cos(|k|/2), ½ sinc(|k|²/4)·k)`.
    #[inline]
    fn exp(a: &Self::Algebra) -> Self {
        let s = a.norm_squared();
        let v = a * (0.5 * sinc(0.25 * s));
        Su2::new_unchecked((0.5 * s.sqrt()).cos(), v[0], v[1], v[2])
    }
    /// `k = 2·atan2(|v|, w)·v/|v|`, `|k| ∈ [0, 2π)`. Fails with
    /// [`Error::LogUndefined`] at `q = −1` (every `|k| = 2π` is a
    /// logarithm), for the zero quaternion and for non-finite input.
    fn log(&self) -> Result<Self::Algebra> {
        if !self.q.iter().all(|x| x.is_finite()) {
            return Err(Error::LogUndefined { group: Self::NAME, reason: "quaternion is not finite" });
        }
        if self.q[1] == 0.0 && self.q[2] == 0.0 && self.q[3] == 0.0 {
            if self.q[0] < 0.0 {
                return Err(Error::LogUndefined {
                    group: Self::NAME,
                    reason: "element is −1: every k with |k| = 2π is a logarithm",
                });
            }
            if self.q[0] == 0.0 {
                return Err(Error::LogUndefined { group: Self::NAME, reason: "quaternion is zero" });
            }
        }
        Ok(quaternion_log_vector(&self.q))
    }
    /// `R(q)·k`.
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        self.act(a)
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
    /// The 4×4 left-multiplication matrix `L(q)`.
    fn to_matrix(&self) -> DMatrix<f64> {
        let m = left_matrix(&self.q);
        DMatrix::from_fn(4, 4, |i, j| m[(i, j)])
    }
    /// `L((0, k/2))`, the generator of `t ↦ L(exp(t k))`.
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let m = left_matrix(&Vector4::new(0.0, 0.5 * a[0], 0.5 * a[1], 0.5 * a[2]));
        DMatrix::from_fn(4, 4, |i, j| m[(i, j)])
    }
    /// `|w² + x² + y² + z² − 1|`.
    fn constraint_defect(&self) -> f64 {
        (self.q.norm_squared() - 1.0).abs()
    }
    /// `q/|q|`; a zero or non-finite quaternion is returned unchanged.
    fn renormalize(&self) -> Self {
        let n = self.q.norm();
        if n > 0.0 && n.is_finite() {
            Su2 { q: self.q / n }
        } else {
            *self
        }
    }
}
