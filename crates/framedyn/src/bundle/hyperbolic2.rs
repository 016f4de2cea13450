//! The orthonormal frame bundle of H²(R) as the Lorentz group SO⁺(1,2)
//! (SPEC §3.2, §7).
//!
//! See [`H2Frame`] for the representation and the generators.

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};

use super::FrameBundle;
use crate::error::finite;
use crate::lie::{minkowski_dot, LieGroup, LorentzKak, So12};
use crate::manifold::{Hyperbolic2, Manifold, H2_TOLERANCE};
use crate::{Error, Result};

/// The orthonormal frame bundle of H²(R) as the Lorentz group SO⁺(1,2)
/// (SPEC §3.2, §7); see [`H2Frame`].
impl FrameBundle<2, 3> for Hyperbolic2 {
    type Group = So12;

    /// `Λ = [q₁ | q₂ | p/R]`, validated and then renormalised onto the group.
    ///
    /// Errors (tolerance [`H2_TOLERANCE`] = 1e-9, relative to the Euclidean
    /// sizes of the vectors, which is what double precision can hold far from
    /// the origin): [`Error::NotFinite`] (`"p"`, `"q"`); [`Error::Constraint`]
    /// with field `"p"` (not on the upper sheet), or `"q"` (not tangent:
    /// `⟨q_a, p⟩_η ≠ 0`; not Minkowski-orthonormal; not positively oriented,
    /// i.e. `det[q₁ | q₂ | n] < 0`, tested through the spatial minor
    /// `q₁ₓq₂ᵧ − q₁ᵧq₂ₓ = det·n_z`).
    fn from_frame(&self, p: &SVector<f64, 3>, q: &SMatrix<f64, 3, 2>) -> Result<So12> {
        self.check_point("p", p)?;
        finite("q", q.iter())?;
        let cols: [Vector3<f64>; 2] = [q.column(0).into(), q.column(1).into()];
        let tangent = cols.iter().map(|c| Hyperbolic2::tangency_defect(p, c)).fold(0.0, f64::max);
        if tangent.is_nan() || tangent > H2_TOLERANCE {
            return Err(Error::Constraint {
                field: "q",
                constraint: "frame vectors tangent to H² at p: ⟨q_a, p⟩_η = 0 (relative)",
                defect: tangent,
                tolerance: H2_TOLERANCE,
            });
        }
        let mut ortho: f64 = 0.0;
        for a in 0..2 {
            for b in a..2 {
                let target = if a == b { 1.0 } else { 0.0 };
                let scale = (cols[a].norm() * cols[b].norm()).max(1.0);
                ortho = ortho.max((minkowski_dot(&cols[a], &cols[b]) - target).abs() / scale);
            }
        }
        if ortho.is_nan() || ortho > H2_TOLERANCE {
            return Err(Error::Constraint {
                field: "q",
                constraint: "Minkowski-orthonormal: ⟨q_a, q_b⟩_η = δ_ab (relative)",
                defect: ortho,
                tolerance: H2_TOLERANCE,
            });
        }
        let minor = q[(0, 0)] * q[(1, 1)] - q[(1, 0)] * q[(0, 1)];
        if minor.is_nan() || minor <= 0.0 {
            return Err(Error::Constraint {
                field: "q",
                constraint: "positively oriented: det[q₁ | q₂ | p/R] = +1",
                defect: 2.0,
                tolerance: H2_TOLERANCE,
            });
        }
        let n = p / self.radius();
        let m = Matrix3::from_columns(&[cols[0], cols[1], n]);
        Ok(So12::new_unchecked(m).renormalize())
    }

    /// `Λ = R(φ)·B(r/R)·R(γ)` with `u = R(γ)`: columns `q = E(x)·u` and `n = x/R`,
    /// assembled with small relative errors at any distance.
    ///
    /// Errors: as [`Manifold::check_chart`] for `x` (`r ≤ 0` is
    /// [`Error::OutsideChart`]); [`Error::NotFinite`] / [`Error::Constraint`]
    /// with field `"u"` unless `u` is orthogonal to 1e-9 with `det u = +1`.
    fn from_chart(&self, x: &SVector<f64, 2>, u: &SMatrix<f64, 2, 2>) -> Result<So12> {
        self.check_chart(x)?;
        finite("u", u.iter())?;
        let ortho = (u.transpose() * u - Matrix2::identity()).amax();
        if ortho.is_nan() || ortho > H2_TOLERANCE {
            return Err(Error::Constraint {
                field: "u",
                constraint: "orthogonal: uᵀu = I",
                defect: ortho,
                tolerance: H2_TOLERANCE,
            });
        }
        if u.determinant() <= 0.0 {
            return Err(Error::Constraint {
                field: "u",
                constraint: "det u = +1 (E = (E_r, E_φ) is positively oriented, q = E·u must be too)",
                defect: 2.0,
                tolerance: H2_TOLERANCE,
            });
        }
        // The rotation part of u (its polar factor).
        let (vc, vs) = (u[(0, 0)] + u[(1, 1)], u[(1, 0)] - u[(0, 1)]);
        let vn = vc.hypot(vs);
        let t = x[0] / self.radius();
        let (sp, cp) = x[1].sin_cos();
        let kak = LorentzKak { alpha: (cp, sp), sinh_beta: t.sinh(), cosh_beta: t.cosh(), gamma: (vc / vn, vs / vn) };
        Ok(So12::new_unchecked(kak.to_matrix()))
    }

    /// `R·Λe₃`.
    fn position(&self, g: &So12) -> SVector<f64, 3> {
        g.matrix().column(2) * self.radius()
    }

    /// `(Λe₁, Λe₂)`.
    fn frame_vectors(&self, g: &So12) -> SMatrix<f64, 3, 2> {
        g.matrix().fixed_columns::<2>(0).into_owned()
    }

    /// From the Cartan decomposition `Λ = R(φ)·B(r/R)·R(γ)`
    /// ([`LorentzKak::of_matrix`]), which keeps full relative precision in
    /// `r`, `φ` and `γ` at any distance.
    ///
    /// Errors: [`Error::OutsideChart`] at (within round-off of) the origin;
    /// [`Error::NotFinite`] (field `"Lambda"`) for non-finite entries.
    fn to_chart(&self, g: &So12) -> Result<(SVector<f64, 2>, SMatrix<f64, 2, 2>)> {
        finite("Lambda", g.matrix().iter())?;
        let k = g.kak();
        Hyperbolic2::check_not_origin(k.sinh_beta, k.cosh_beta)?;
        let x = Vector2::new(self.radius() * k.beta(), k.alpha.1.atan2(k.alpha.0));
        let (c, s) = k.gamma;
        Ok((x, Matrix2::new(c, -s, s, c)))
    }

    /// `(u₁/R, u₂/R, 0)`: the boost `(1/R)[[0, 0, u₁], [0, 0, u₂], [u₁, u₂, 0]]`.
    fn horizontal_lift(&self, _g: &So12, u: &SVector<f64, 2>) -> SVector<f64, 3> {
        Vector3::new(u[0] * self.inv_radius(), u[1] * self.inv_radius(), 0.0)
    }

    /// `(0, 0, ω)` with `ω = (w₂₁ − w₁₂)/2` (the skew part of `w`).
    fn vertical(&self, _g: &So12, w: &SMatrix<f64, 2, 2>) -> SVector<f64, 3> {
        Vector3::new(0.0, 0.0, 0.5 * (w[(1, 0)] - w[(0, 1)]))
    }

    /// [`So12::constraint_defect`](crate::lie::LieGroup::constraint_defect)
    /// (relative to `|Λ|²`): every element of SO⁺(1,2) is a valid bundle element.
    fn bundle_defect(&self, g: &So12) -> f64 {
        g.constraint_defect()
    }

    /// `Λ̇ = Λ·hat(ξ)`: `ẋ = R·(Λ̇)₂`, `q̇ = (Λ̇)₀,₁`.
    #[inline]
    fn frame_velocity(&self, g: &So12, xi: &SVector<f64, 3>) -> (SVector<f64, 3>, SMatrix<f64, 3, 2>) {
        let ldot = g.matrix() * So12::hat(xi);
        (ldot.column(2) * self.radius(), ldot.fixed_columns::<2>(0).into_owned())
    }

    /// `K = −1/R²`.
    fn curvature_at(&self, _g: &So12) -> f64 {
        self.curvature()
    }

    /// Zero: the lift does not depend on `g`.
    fn lift_derivative(&self, _g: &So12, _u: &SVector<f64, 2>, _eta: &SVector<f64, 3>) -> SVector<f64, 3> {
        SVector::<f64, 3>::zeros()
    }

    /// Zero: constant curvature.
    fn curvature_derivative(&self, _g: &So12, _eta: &SVector<f64, 3>) -> f64 {
        0.0
    }

    /// `Λ·hat(η)·hat(ξ)`, read as in [`frame_velocity`](FrameBundle::frame_velocity).
    fn frame_velocity_derivative(&self, g: &So12, xi: &SVector<f64, 3>, eta: &SVector<f64, 3>) -> (SVector<f64, 3>, SMatrix<f64, 3, 2>) {
        let m = g.matrix() * So12::hat(eta) * So12::hat(xi);
        (m.column(2) * self.radius(), m.fixed_columns::<2>(0).into_owned())
    }

    /// Constant curvature: exact free flows.
    fn exact_free_flow(&self) -> bool {
        true
    }

    /// `vertical(ε) = (0, 0, 1)` (the rotation generator of so(1,2)): the
    /// spacelike columns `λ₀, λ₁` of `Λ` rotate like `q₁, q₂` on S².
    #[inline]
    fn rotate_frame(&self, g: &So12, cos: f64, sin: f64) -> So12 {
        So12::new_unchecked(super::rotate_columns(g.matrix(), 0, 1, cos, sin))
    }
}

/// An element of the orthonormal frame bundle of H²(R) (SPEC §3.2, §7), as
/// stored by `impl FrameBundle<2, 3> for Hyperbolic2`.
///
/// A point `x` of the hyperboloid with a Minkowski-orthonormal, positively
/// oriented tangent frame `(q₁, q₂)` is stored as `Λ = [q₁ | q₂ | n] ∈ SO⁺(1,2)`
/// with `n = x/R` the future unit normal. Orientation: the paper's frame
/// `(E_r, E_φ)` is positively oriented, `det[E_r | E_φ | n] = cosh²ϑ − sinh²ϑ
/// = +1`; so `q = E·u` is admissible exactly for `u ∈ SO(2)`, and then
/// `Λ = R(φ)·B(ϑ)·R(γ)` with `u = R(γ)` (see [`LorentzKak`]).
///
/// Parallel transport along a velocity with frame components `u` is
/// `Λ̇ = Λ h`, `h = (1/R)[[0, 0, u₁], [0, 0, u₂], [u₁, u₂, 0]]`: in the
/// algebra coordinates `(b₁, b₂, ω)` of [`So12`], `h = (u₁/R, u₂/R, 0)` (pure
/// boosts: `ẋ = u₁q₁ + u₂q₂` and `q̇_a = (u_a/R) n` is normal). The vertical
/// generator (in-place rotation of the frame, `q̇ = q w`) is the rotation
/// `ω = (w₂₁ − w₁₂)/2` (`= w₂₁` for skew `w`).
pub type H2Frame = So12;
