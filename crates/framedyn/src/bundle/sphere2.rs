//! The orthonormal frame bundle of S²(R) as SO(3) (SPEC §3.2, §7).

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

use super::FrameBundle;
use crate::lie::{LieGroup, So3};
use crate::manifold::{Manifold, Sphere2};
use crate::{Error, Result};

/// A point of S²(R) with a positively oriented orthonormal tangent frame,
/// stored as the rotation `Q = [n | q₁ | q₂] ∈ SO(3)`: `n = x/R` the outward
/// unit normal, `(q₁, q₂)` the frame, `q₁ × q₂ = n` (SPEC §7).
///
/// **Horizontal lift.** Parallel transport along a velocity `ẋ = u₁q₁ + u₂q₂`
/// is `Q̇ = Q h(u)` with
/// `h(u) = (1/R)[[0, −u₁, −u₂], [u₁, 0, 0], [u₂, 0, 0]]`, i.e. the so(3) vector
/// `(0, −u₂/R, u₁/R)` (see [`So3`]): then `ẋ = R ṅ = u₁q₁ + u₂q₂` and
/// `q̇_a = −(u_a/R) n` is normal, so the frame is parallel. Nothing in `h` or in
/// the exponential is singular anywhere on the sphere, the poles included.
///
/// **Vertical generator.** `q̇ = q w`, `w = [[0, −ω], [ω, 0]]`, is `Q̇ = Q·hat(ω, 0, 0)`:
/// the so(3) vector `(ω, 0, 0)` (a rotation in the `q₁–q₂` plane).
///
/// **Charts.** `from_chart(x, U)` has `q = E(x)·U` with the paper's frame
/// `E = (E_r, E_φ)` (a90); `E_r × E_φ = n`, so `U ∈ SO(2)` gives a positively
/// oriented frame. For `U = [[cos ψ, −sin ψ], [sin ψ, cos ψ]]` `ψ` is the
/// paper's angle of §5.1.
pub type Sphere2Frame = So3;

/// Tolerance of [`FrameBundle::from_frame`] / [`FrameBundle::from_chart`] checks.
const FRAME_TOL: f64 = 1e-9;

fn constraint(field: &'static str, constraint: &'static str, defect: f64) -> Error {
    Error::Constraint { field, constraint, defect, tolerance: FRAME_TOL }
}

/// Checks that the 2×2 matrix `u` is a rotation (orthogonal, det = +1).
fn check_rotation2(u: &Matrix2<f64>) -> Result<()> {
    crate::error::finite("u", u.iter())?;
    let orth = (u.transpose() * u - Matrix2::identity()).amax();
    if orth > FRAME_TOL {
        return Err(constraint("u", "u orthogonal, uᵀu = I", orth));
    }
    let det = u.determinant();
    if det <= 0.0 {
        return Err(constraint("u", "det u = +1 (positively oriented frame)", (det - 1.0).abs()));
    }
    Ok(())
}

impl FrameBundle<2, 3> for Sphere2 {
    type Group = So3;

    /// `Q = [p/|p| | q₁ | q₂]`, projected to the nearest rotation. Fails
    /// (tolerance 1e-9) unless `p` and `q` are finite, `p` is on the sphere,
    /// `q₁, q₂` are tangent (`|n·q_a| ≤ 1e-9`), orthonormal
    /// (`max|qᵀq − I| ≤ 1e-9`) and positively oriented (`(q₁ × q₂)·n > 0`).
    fn from_frame(&self, p: &Vector3<f64>, q: &Matrix3x2<f64>) -> Result<So3> {
        self.check_point("p", p)?;
        crate::error::finite("q", q.iter())?;
        let n = p / p.norm();
        let (q1, q2): (Vector3<f64>, Vector3<f64>) = (q.column(0).into(), q.column(1).into());
        let tangent = n.dot(&q1).abs().max(n.dot(&q2).abs());
        if tangent > FRAME_TOL {
            return Err(constraint("q", "frame vectors tangent to the sphere, n·q_a = 0", tangent));
        }
        let orth = (q.transpose() * q - Matrix2::identity()).amax();
        if orth > FRAME_TOL {
            return Err(constraint("q", "frame orthonormal, qᵀq = I", orth));
        }
        let det = q1.cross(&q2).dot(&n);
        if det <= 0.0 {
            return Err(constraint("q", "frame positively oriented, q₁ × q₂ = n", (det - 1.0).abs()));
        }
        Ok(So3::new_unchecked(Matrix3::from_columns(&[n, q1, q2])).renormalize())
    }

    /// `Q = [n(x) | E(x)·u]`; fails outside the chart (see
    /// [`Manifold::check_chart`]) or unless `u` is a rotation (tolerance 1e-9).
    fn from_chart(&self, x: &Vector2<f64>, u: &Matrix2<f64>) -> Result<So3> {
        self.check_chart(x)?;
        check_rotation2(u)?;
        let n = self.embed(x) / self.radius();
        let q = self.ambient_frame(x) * u;
        Ok(So3::new_unchecked(Matrix3::from_columns(&[n, q.column(0).into(), q.column(1).into()])).renormalize())
    }

    /// `R·Q e₁` (first column).
    #[inline]
    fn position(&self, g: &So3) -> Vector3<f64> {
        g.matrix().column(0) * self.radius()
    }

    /// Columns 2 and 3 of `Q`.
    #[inline]
    fn frame_vectors(&self, g: &So3) -> Matrix3x2<f64> {
        g.matrix().fixed_columns::<2>(1).into()
    }

    /// `x = chart(position)`, `u = E(x)ᵀ q`. Fails near the poles (see
    /// [`Sphere2::POLE_TOLERANCE`]). The map back, `from_chart(to_chart(g))`,
    /// reproduces `g` to round-off even close to a pole, although `u` itself
    /// is ill-conditioned there (it is the angle between `q` and `E_r`).
    fn to_chart(&self, g: &So3) -> Result<(Vector2<f64>, Matrix2<f64>)> {
        let x = self.chart(&self.position(g))?;
        let u = self.ambient_frame(&x).transpose() * self.frame_vectors(g);
        Ok((x, u))
    }

    /// The so(3) vector `(0, −u₂/R, u₁/R)` of `h(u)`.
    #[inline]
    fn horizontal_lift(&self, _g: &So3, u: &Vector2<f64>) -> Vector3<f64> {
        let k = self.inv_radius();
        Vector3::new(0.0, -u[1] * k, u[0] * k)
    }

    /// The so(3) vector `(ω, 0, 0)`, `ω = (w₂₁ − w₁₂)/2` (the skew part of `w`).
    #[inline]
    fn vertical(&self, _g: &So3, w: &Matrix2<f64>) -> Vector3<f64> {
        Vector3::new(0.5 * (w[(1, 0)] - w[(0, 1)]), 0.0, 0.0)
    }

    /// [`So3`]'s `constraint_defect` (orthonormality and determinant of `Q`).
    #[inline]
    fn bundle_defect(&self, g: &So3) -> f64 {
        g.constraint_defect()
    }

    /// `Q̇ = Q·hat(ξ)`: `ẋ = R·(Q̇)₀`, `q̇ = (Q̇)₁,₂`.
    #[inline]
    fn frame_velocity(&self, g: &So3, xi: &Vector3<f64>) -> (Vector3<f64>, Matrix3x2<f64>) {
        let qdot = g.matrix() * So3::hat(xi);
        (qdot.column(0) * self.radius(), qdot.fixed_columns::<2>(1).into_owned())
    }

    /// `K = 1/R²`.
    fn curvature_at(&self, _g: &So3) -> f64 {
        self.curvature()
    }

    /// Zero: the lift does not depend on `g`.
    fn lift_derivative(&self, _g: &So3, _u: &Vector2<f64>, _eta: &Vector3<f64>) -> Vector3<f64> {
        Vector3::zeros()
    }

    /// Zero: constant curvature.
    fn curvature_derivative(&self, _g: &So3, _eta: &Vector3<f64>) -> f64 {
        0.0
    }

    /// `Q·hat(η)·hat(ξ)`, read as in [`frame_velocity`](FrameBundle::frame_velocity).
    fn frame_velocity_derivative(&self, g: &So3, xi: &Vector3<f64>, eta: &Vector3<f64>) -> (Vector3<f64>, Matrix3x2<f64>) {
        let m = g.matrix() * So3::hat(eta) * So3::hat(xi);
        (m.column(0) * self.radius(), m.fixed_columns::<2>(1).into_owned())
    }

    /// Constant curvature: exact free flows.
    fn exact_free_flow(&self) -> bool {
        true
    }

    /// `vertical(ε) = e₁` (rotation about the normal `n = Q e₀`): columns
    /// `q₁, q₂` of `Q` rotate, `q₁ ← c q₁ + s q₂`, `q₂ ← −s q₁ + c q₂`.
    #[inline]
    fn rotate_frame(&self, g: &So3, cos: f64, sin: f64) -> So3 {
        So3::new_unchecked(super::rotate_columns(g.matrix(), 1, 2, cos, sin))
    }
}
