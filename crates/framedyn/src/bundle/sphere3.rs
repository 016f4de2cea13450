//! The orthonormal frame bundle of S³(R) as SO(4): see the `FrameBundle`
//! implementation of [`Sphere3`].

use nalgebra::{Matrix3, Matrix4, Matrix4x3, Vector3, Vector4};

use super::FrameBundle;
use crate::error::finite;
use crate::lie::{LieGroup, So4, So4Algebra};
use crate::manifold::{Manifold, Sphere3};
use crate::{Error, Result};

/// Tolerance of [`FrameBundle::from_frame`] and [`FrameBundle::from_chart`]
/// for the point, tangency, orthonormality and orthogonality of `u`.
pub const S3_FRAME_TOLERANCE: f64 = 1e-9;

fn constraint(field: &'static str, constraint: &'static str, defect: f64) -> Error {
    Error::Constraint { field, constraint, defect, tolerance: S3_FRAME_TOLERANCE }
}

fn check_rotation(field: &'static str, u: &Matrix3<f64>) -> Result<()> {
    finite(field, u.iter())?;
    let orth = (u.transpose() * u - Matrix3::identity()).amax();
    if orth > S3_FRAME_TOLERANCE {
        return Err(constraint(field, "uᵀu = I", orth));
    }
    let det = u.determinant();
    if det <= 0.0 {
        return Err(constraint(field, "det u = +1", (det - 1.0).abs()));
    }
    Ok(())
}

impl Sphere3 {
    fn bundle_matrix(&self, p: &Vector4<f64>, q: &Matrix4x3<f64>) -> Matrix4<f64> {
        let mut m = Matrix4::zeros();
        m.set_column(0, &(p / self.radius()));
        m.fixed_view_mut::<4, 3>(0, 1).copy_from(q);
        m
    }
}

/// The orthonormal frame bundle of S³(R) as SO(4) (SPEC §3.2).
///
/// A bundle element — a point `x ∈ S³(R) ⊂ ℝ⁴` with an orthonormal frame
/// `(q₁, q₂, q₃)` of `T_xS³` — is the rotation `Q = [x/R | q₁ | q₂ | q₃] ∈ SO(4)`
/// ([`So4`] stores exactly this matrix). **Orientation:** a frame is positively
/// oriented when `det Q = +1`. Both of the paper's frames are: along `ˡE(R)`,
/// `Q = [u | e₁u | e₂u | e₃u]` is right multiplication by the unit quaternion
/// `u = x/R`, along `ʳE(R)` it is left multiplication; both are the identity at
/// the chart centre `x = R·1`.
///
/// **Horizontal lift.** Moving with velocity `Σ u_a q_a` while transporting the
/// frame parallel is `Q̇ = Q h`, `h = (1/R) Σ_a u_a (E_{a0} − E_{0a})`: `x/R`
/// tilts towards `q_a` and `q_a` towards `−x/R`, exactly as S² in SO(3). In
/// the [`So4Algebra`] basis `h = (β, ω) = (u/R, 0)`; the vertical generator of
/// `q̇ = q·w` is `(0, ω)` with `[ω]× = w`. Nothing is singular anywhere: the
/// chart (and its singular antipode `−R·1`) enters only through
/// [`FrameBundle::from_chart`] and [`FrameBundle::to_chart`], which are relative
/// to the paper's frame `ˡE(R)` (`q = ˡE(x)·u`).
impl FrameBundle<3, 4> for Sphere3 {
    type Group = So4;

    /// Validates (finite; `||p| − R| ≤ 1e-9 R`; `|q_a·p|/R ≤ 1e-9`;
    /// `|qᵀq − I| ≤ 1e-9`; `det[p/R | q] > 0`) and stores the nearest rotation
    /// to `[p/R | q]`.
    fn from_frame(&self, p: &Vector4<f64>, q: &Matrix4x3<f64>) -> Result<So4> {
        finite("p", p.iter())?;
        finite("q", q.iter())?;
        let pd = self.point_defect(p);
        if pd > S3_FRAME_TOLERANCE {
            return Err(constraint("p", "|p| = R", pd));
        }
        let tangency = (q.transpose() * p).amax() / self.radius();
        if tangency > S3_FRAME_TOLERANCE {
            return Err(constraint("q", "q_a · p = 0 (tangent)", tangency));
        }
        let orth = (q.transpose() * q - Matrix3::identity()).amax();
        if orth > S3_FRAME_TOLERANCE {
            return Err(constraint("q", "q_a · q_b = δ_ab (orthonormal)", orth));
        }
        let m = self.bundle_matrix(p, q);
        let det = m.determinant();
        if det <= 0.0 {
            return Err(constraint("q", "det[p/R | q₁ | q₂ | q₃] = +1 (positively oriented)", (det - 1.0).abs()));
        }
        Ok(So4::new_unchecked(m).renormalize())
    }

    /// `Q = [x/R | ˡE(x)·u]` with `ˡE_A = e_A·x/R`; fails outside the chart or
    /// for a `u` that is not a rotation (tolerance 1e-9).
    fn from_chart(&self, x: &Vector3<f64>, u: &Matrix3<f64>) -> Result<So4> {
        self.check_chart(x)?;
        check_rotation("u", u)?;
        let p = self.embed(x);
        let m = self.bundle_matrix(&p, &(self.frame_l_ambient(&p) * u));
        Ok(So4::new_unchecked(m).renormalize())
    }

    #[inline]
    fn position(&self, g: &So4) -> Vector4<f64> {
        g.matrix().column(0) * self.radius()
    }

    #[inline]
    fn frame_vectors(&self, g: &So4) -> Matrix4x3<f64> {
        g.matrix().fixed_view::<4, 3>(0, 1).into_owned()
    }

    /// `x = chart(position)`, `u = ˡE(x)ᵀ q` (the ambient frame `ˡE_A = e_A x/R`
    /// is orthonormal). Fails near the antipode `−R·1` of the chart centre.
    fn to_chart(&self, g: &So4) -> Result<(Vector3<f64>, Matrix3<f64>)> {
        let p = self.position(g);
        let x = self.chart(&p)?;
        let u = self.frame_l_ambient(&p).transpose() * self.frame_vectors(g);
        Ok((x, u))
    }

    /// `(β, ω) = (u/R, 0)`: `h = (1/R) Σ u_a (E_{a0} − E_{0a})`.
    #[inline]
    fn horizontal_lift(&self, _g: &So4, u: &Vector3<f64>) -> So4Algebra {
        let b = u * self.inv_radius();
        So4Algebra::new(b[0], b[1], b[2], 0.0, 0.0, 0.0)
    }

    /// `(β, ω) = (0, ω)` with `[ω]×` the skew part of `w`.
    #[inline]
    fn vertical(&self, _g: &So4, w: &Matrix3<f64>) -> So4Algebra {
        So4Algebra::new(
            0.0,
            0.0,
            0.0,
            0.5 * (w[(2, 1)] - w[(1, 2)]),
            0.5 * (w[(0, 2)] - w[(2, 0)]),
            0.5 * (w[(1, 0)] - w[(0, 1)]),
        )
    }

    fn bundle_defect(&self, g: &So4) -> f64 {
        g.constraint_defect()
    }

    /// `Q̇ = Q·hat(ξ)`: `ẋ = R·(Q̇)₀`, `q̇ = (Q̇)₁,₂,₃`.
    #[inline]
    fn frame_velocity(&self, g: &So4, xi: &So4Algebra) -> (Vector4<f64>, Matrix4x3<f64>) {
        let qdot = g.matrix() * So4::hat(xi);
        (qdot.column(0) * self.radius(), qdot.fixed_columns::<3>(1).into_owned())
    }

    /// `K = 1/R²`.
    fn curvature_at(&self, _g: &So4) -> f64 {
        self.inv_radius() * self.inv_radius()
    }

    /// Zero: the lift does not depend on `g`.
    fn lift_derivative(&self, _g: &So4, _u: &Vector3<f64>, _eta: &So4Algebra) -> So4Algebra {
        So4Algebra::zeros()
    }

    /// Zero: constant curvature.
    fn curvature_derivative(&self, _g: &So4, _eta: &So4Algebra) -> f64 {
        0.0
    }

    /// `Q·hat(η)·hat(ξ)`, read as in [`frame_velocity`](FrameBundle::frame_velocity).
    fn frame_velocity_derivative(&self, g: &So4, xi: &So4Algebra, eta: &So4Algebra) -> (Vector4<f64>, Matrix4x3<f64>) {
        let m = g.matrix() * So4::hat(eta) * So4::hat(xi);
        (m.column(0) * self.radius(), m.fixed_columns::<3>(1).into_owned())
    }

    /// Constant curvature: exact free flows.
    fn exact_free_flow(&self) -> bool {
        true
    }
}
