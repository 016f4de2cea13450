//! SO(2): rotations of the plane, stored as a unit complex number.

use nalgebra::{DMatrix, Matrix2, Vector1, Vector2};

use super::LieGroup;
use crate::{Error, Result};

/// A plane rotation by the angle `ψ`, stored as the unit complex number
/// `(cos ψ, sin ψ)` (not as the angle: products are complex multiplications, so
/// no angle ever grows without bound or needs wrapping, and the stored pair
/// carries its own constraint `cos² + sin² = 1`, restored by
/// [`LieGroup::renormalize`]).
///
/// Matrix (defining representation) `[[cos ψ, −sin ψ], [sin ψ, cos ψ]]`.
/// Algebra: `Vector1` holding the angular velocity `ω`, with matrix
/// `ω·[[0, −1], [1, 0]]` (the paper's `ω̂`, §5.1). The group is abelian:
/// brackets vanish, `Ad` is the identity, `dexp = dexp⁻¹ = id`,
/// `exp(ω) = (cos ω, sin ω)` and `log` returns the principal angle in `(−π, π]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So2 {
    /// `(cos ψ, sin ψ)`.
    cs: Vector2<f64>,
}

impl So2 {
    /// Largest `|cos² + sin² − 1|` accepted by [`So2::new`].
    pub const TOLERANCE: f64 = 1e-9;

    /// The rotation with `cos ψ = c`, `sin ψ = s`. Fails unless both are finite
    /// and `|c² + s² − 1| ≤` [`So2::TOLERANCE`]; the accepted pair is
    /// renormalised to unit length.
    pub fn new(c: f64, s: f64) -> Result<Self> {
        crate::error::finite("So2 (cos, sin)", [c, s].iter())?;
        let defect = (c * c + s * s - 1.0).abs();
        if defect > Self::TOLERANCE {
            return Err(Error::Constraint {
                field: "So2 (cos, sin)",
                constraint: "cos² + sin² = 1",
                defect,
                tolerance: Self::TOLERANCE,
            });
        }
        Ok(Self::new_unchecked(c, s).renormalize())
    }

    /// The pair `(c, s)` stored as is, without validation (for hot paths whose
    /// input is known to be a unit pair).
    #[inline]
    pub fn new_unchecked(c: f64, s: f64) -> Self {
        So2 { cs: Vector2::new(c, s) }
    }

    /// The rotation by the angle `psi` (radians); fails if `psi` is not finite.
    pub fn from_angle(psi: f64) -> Result<Self> {
        crate::error::finite("So2 angle", [psi].iter())?;
        Ok(Self::exp(&Vector1::new(psi)))
    }

    /// `cos ψ`.
    #[inline]
    pub fn cos(&self) -> f64 {
        self.cs[0]
    }

    /// `sin ψ`.
    #[inline]
    pub fn sin(&self) -> f64 {
        self.cs[1]
    }

    /// The principal angle `ψ = atan2(sin, cos) ∈ (−π, π]` (a stored
    /// `sin = −0.0` with `cos < 0` gives `π`, not `−π`).
    #[inline]
    pub fn angle(&self) -> f64 {
        let a = self.cs[1].atan2(self.cs[0]);
        if a == -std::f64::consts::PI {
            std::f64::consts::PI
        } else {
            a
        }
    }

    /// The rotation matrix `[[cos, −sin], [sin, cos]]`.
    #[inline]
    pub fn matrix(&self) -> Matrix2<f64> {
        let (c, s) = (self.cs[0], self.cs[1]);
        Matrix2::new(c, -s, s, c)
    }

    /// Rotates the plane vector `v` counter-clockwise by `ψ`.
    #[inline]
    pub fn act(&self, v: &Vector2<f64>) -> Vector2<f64> {
        self.matrix() * v
    }
}

impl LieGroup for So2 {
    type Algebra = Vector1<f64>;
    const DOF: usize = 1;
    const NAME: &'static str = "SO(2)";

    #[inline]
    fn identity() -> Self {
        So2::new_unchecked(1.0, 0.0)
    }
    /// Complex multiplication.
    #[inline(always)]
    fn compose(&self, rhs: &Self) -> Self {
        let (a, b) = (self.cs, rhs.cs);
        So2::new_unchecked(a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0])
    }
    /// Complex conjugation.
    #[inline]
    fn inverse(&self) -> Self {
        So2::new_unchecked(self.cs[0], -self.cs[1])
    }
    #[inline(always)]
    fn exp(a: &Self::Algebra) -> Self {
        let (s, c) = a[0].sin_cos();
        So2::new_unchecked(c, s)
    }
    /// `atan2(sin, cos) ∈ (−π, π]`; defined everywhere on the group, fails
    /// only for a non-finite or zero stored pair.
    fn log(&self) -> Result<Self::Algebra> {
        if !(self.cs[0].is_finite() && self.cs[1].is_finite()) || self.cs == Vector2::zeros() {
            return Err(Error::LogUndefined { group: Self::NAME, reason: "element is zero or not finite" });
        }
        Ok(Vector1::new(self.angle()))
    }
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        *a
    }
    #[inline]
    fn bracket(_a: &Self::Algebra, _b: &Self::Algebra) -> Self::Algebra {
        Vector1::zeros()
    }
    #[inline]
    fn dexp(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    #[inline]
    fn dexp_inv(_a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        *v
    }
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        Vector1::new(c[0])
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        vec![a[0]]
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        let m = self.matrix();
        DMatrix::from_fn(2, 2, |i, j| m[(i, j)])
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[0.0, -a[0], a[0], 0.0])
    }
    /// `|cos² + sin² − 1|`.
    fn constraint_defect(&self) -> f64 {
        (self.cs.norm_squared() - 1.0).abs()
    }
    /// Divides by `|(cos, sin)|` (the nearest unit pair). A zero or
    /// non-finite pair is returned unchanged.
    #[inline]
    fn renormalize(&self) -> Self {
        // The integrators' case, inline: |(c, s)| near 1 (the test fails for
        // NaN), one square root and one division.
        let q = self.cs[0] * self.cs[0] + self.cs[1] * self.cs[1];
        if q > 0.25 && q < 4.0 {
            return So2 { cs: self.cs * (1.0 / q.sqrt()) };
        }
        self.renormalize_general()
    }
}

impl So2 {
    /// [`LieGroup::renormalize`] far from the unit circle (out of line):
    /// `hypot` where the sum of squares over- or underflows.
    #[cold]
    #[inline(never)]
    fn renormalize_general(&self) -> Self {
        let q = self.cs[0] * self.cs[0] + self.cs[1] * self.cs[1];
        let n = if q > 1e-300 && q < 1e300 { q.sqrt() } else { self.cs[0].hypot(self.cs[1]) };
        if n > 0.0 && n.is_finite() {
            So2 { cs: self.cs / n }
        } else {
            *self
        }
    }
}
