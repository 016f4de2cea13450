//! The orthonormal frame bundle of the torus T²(L, R): see the
//! `FrameBundle` implementation of [`Torus2`].

use nalgebra::{SMatrix, SVector};

use super::FrameBundle;
use crate::error::finite;
use crate::lie::Rn;
use crate::manifold::{Manifold, Torus2};
use crate::{Error, Result};

/// Tolerance of the frame checks in [`FrameBundle::from_frame`] and
/// [`FrameBundle::from_chart`] (orthonormality, tangency, orientation).
pub const TORUS_FRAME_TOLERANCE: f64 = 1e-9;

/// `U(a)`, the rotation by the angle `a`.
fn rot(a: f64) -> SMatrix<f64, 2, 2> {
    let (s, c) = a.sin_cos();
    SMatrix::<f64, 2, 2>::new(c, -s, s, c)
}

/// Embedded unit frame field `(Ê_θ, Ê_φ)` as columns and the outward normal.
fn frame_field(theta: f64, phi: f64) -> (SMatrix<f64, 3, 2>, SVector<f64, 3>) {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    let e = SMatrix::<f64, 3, 2>::new(-st * cp, -sp, -st * sp, cp, ct, 0.0);
    (e, SVector::<f64, 3>::new(ct * cp, ct * sp, st))
}

/// The orthonormal frame bundle of the torus T²(L, R) in the global angles
/// `(θ, φ, a)` (SPEC §3.2, §7).
///
/// A bundle element is stored as `Rn<3>` holding `(θ, φ, a)`: the point with
/// chart angles `(θ, φ)` and the frame
/// `(q₁, q₂) = (E_θ, E_φ)·U(a)`, `U(a) = [[cos a, −sin a], [sin a, cos a]]`,
/// i.e. `q₁ = cos a E_θ + sin a E_φ`, `q₂ = −sin a E_θ + cos a E_φ`, positively
/// oriented with respect to the paper's frame field `(E_θ, E_φ)` (l.5345).
/// The three angles are unbounded in the group (an integrator just adds to
/// them); [`FrameBundle::to_chart`] and [`Manifold::chart`] reduce `θ, φ` to
/// `(−π, π]`, and `a` enters only through `U(a)`.
///
/// **Horizontal lift** (parallel transport, `ġ = g·ξ = ξ` in the additive
/// group): for frame velocity components `u` the chart velocity components are
/// `v = U(a) u` in `(E_θ, E_φ)` and
/// `θ̇ = v₁/R`, `φ̇ = v₂/(L + R cos θ)`, `ȧ = +sin θ · φ̇`.
///
/// *Derivation of the sign.* From the embedding, `∂_φ Ê_θ = −sin θ Ê_φ` and the
/// tangential part of `∂_φ Ê_φ` is `+sin θ Ê_θ`; `∂_θ Ê_θ = −n` and `∂_θ Ê_φ = 0`.
/// Hence `D q₁/dt = ȧ q₂ + cos a (−sin θ φ̇ Ê_φ) + sin a (sin θ φ̇ Ê_θ)
/// = (ȧ − sin θ φ̇) q₂`, which vanishes (parallel transport) iff
/// `ȧ = sin θ φ̇`. Equivalently the frame field turns by `−sin θ φ̇` relative to a
/// parallel frame, so the gyroscope's angular velocity relative to `(E_θ, E_φ)`
/// is `ψ̇ − sin θ φ̇`; the paper's `ψ̇ + sin θ φ̇` (l.5362, l.5486) belongs to the
/// ordering `(E_φ, E_θ)` (SPEC §8). The bundle law "`q̇_a` has no tangential
/// component" tests this sign. Around the parallel `θ = θ₀` (`φ: 0 → 2π`) the
/// frame turns by `2π sin θ₀` relative to `E`; the difference between two
/// parallels is `∫K dA = 2π (sin θ₂ − sin θ₁)` (Gauss–Bonnet).
///
/// **Vertical generator**: `q̇ = q w` (`w` skew) is `ȧ = w₂₁`.
impl FrameBundle<2, 3> for Torus2 {
    type Group = Rn<3>;

    /// `(θ, φ)` from [`Manifold::chart`]; checks that the columns of `q` are
    /// tangent (`|n·q_a| ≤ 1e-9`), orthonormal (`|qᵀq − I| ≤ 1e-9`) and
    /// positively oriented w.r.t. `(E_θ, E_φ)` (`det((Ê_θ, Ê_φ)ᵀ q) > 0`);
    /// `a = atan2(q₁·Ê_φ, q₁·Ê_θ)`. Errors: [`Error::NotFinite`],
    /// [`Error::Constraint`] naming `p` or `q`.
    fn from_frame(&self, p: &SVector<f64, 3>, q: &SMatrix<f64, 3, 2>) -> Result<Rn<3>> {
        let x = self.chart(p)?;
        finite("q", q.iter())?;
        let (e, n) = frame_field(x[0], x[1]);
        let normal = (n.transpose() * q).amax();
        if normal > TORUS_FRAME_TOLERANCE {
            return Err(Error::Constraint {
                field: "q",
                constraint: "frame vectors tangent to the torus (n·q_a = 0)",
                defect: normal,
                tolerance: TORUS_FRAME_TOLERANCE,
            });
        }
        let gram = (q.transpose() * q - SMatrix::<f64, 2, 2>::identity()).amax();
        if gram > TORUS_FRAME_TOLERANCE {
            return Err(Error::Constraint {
                field: "q",
                constraint: "orthonormal frame (q^T q = I)",
                defect: gram,
                tolerance: TORUS_FRAME_TOLERANCE,
            });
        }
        let m = e.transpose() * q;
        let det = m.determinant();
        if det <= 0.0 {
            return Err(Error::Constraint {
                field: "q",
                constraint: "positively oriented w.r.t. (E_theta, E_phi) (det = +1)",
                defect: (det - 1.0).abs(),
                tolerance: TORUS_FRAME_TOLERANCE,
            });
        }
        let a = m[(1, 0)].atan2(m[(0, 0)]);
        Ok(Rn(SVector::<f64, 3>::new(x[0], x[1], a)))
    }

    /// `(θ, φ, a)` with `a = atan2(u₂₁, u₁₁)` the angle of the rotation `u`.
    /// Errors: [`Error::NotFinite`]; [`Error::Constraint`] on `u` if
    /// `|uᵀu − I| > 1e-9` or `det u < 0`.
    fn from_chart(&self, x: &SVector<f64, 2>, u: &SMatrix<f64, 2, 2>) -> Result<Rn<3>> {
        finite("x", x.iter())?;
        finite("u", u.iter())?;
        let gram = (u.transpose() * u - SMatrix::<f64, 2, 2>::identity()).amax();
        if gram > TORUS_FRAME_TOLERANCE {
            return Err(Error::Constraint {
                field: "u",
                constraint: "orthogonal (u^T u = I)",
                defect: gram,
                tolerance: TORUS_FRAME_TOLERANCE,
            });
        }
        let det = u.determinant();
        if det <= 0.0 {
            return Err(Error::Constraint {
                field: "u",
                constraint: "a rotation (det u = +1)",
                defect: (det - 1.0).abs(),
                tolerance: TORUS_FRAME_TOLERANCE,
            });
        }
        Ok(Rn(SVector::<f64, 3>::new(x[0], x[1], u[(1, 0)].atan2(u[(0, 0)]))))
    }

    /// `embed(θ, φ)`.
    fn position(&self, g: &Rn<3>) -> SVector<f64, 3> {
        self.embed(&SVector::<f64, 2>::new(g.0[0], g.0[1]))
    }

    /// `(q₁, q₂) = (Ê_θ, Ê_φ)·U(a)`.
    fn frame_vectors(&self, g: &Rn<3>) -> SMatrix<f64, 3, 2> {
        let (e, _) = frame_field(g.0[0], g.0[1]);
        e * rot(g.0[2])
    }

    /// `((θ, φ) reduced to (−π, π], U(a))`. Errors: [`Error::NotFinite`].
    fn to_chart(&self, g: &Rn<3>) -> Result<(SVector<f64, 2>, SMatrix<f64, 2, 2>)> {
        finite("g", g.0.iter())?;
        Ok((SVector::<f64, 2>::new(Torus2::reduce_angle(g.0[0]), Torus2::reduce_angle(g.0[1])), rot(g.0[2])))
    }

    /// `v = U(a) u`; `ξ = (v₁/R, v₂/ρ, sin θ · v₂/ρ)`, `ρ = L + R cos θ`.
    fn horizontal_lift(&self, g: &Rn<3>, u: &SVector<f64, 2>) -> SVector<f64, 3> {
        let v = rot(g.0[2]) * u;
        let theta = g.0[0];
        let phidot = v[1] / self.rho(theta);
        SVector::<f64, 3>::new(v[0] / self.small_r(), phidot, theta.sin() * phidot)
    }

    /// `ξ = (0, 0, w₂₁)`, using the skew part `½(w₂₁ − w₁₂)` of `w`.
    fn vertical(&self, _g: &Rn<3>, w: &SMatrix<f64, 2, 2>) -> SVector<f64, 3> {
        SVector::<f64, 3>::new(0.0, 0.0, 0.5 * (w[(1, 0)] - w[(0, 1)]))
    }

    /// Every finite `(θ, φ, a)` is a valid element: 0, or `+∞` if not finite.
    fn bundle_defect(&self, g: &Rn<3>) -> f64 {
        if g.0.iter().all(|v| v.is_finite()) {
            0.0
        } else {
            f64::INFINITY
        }
    }

    /// For `ξ = (θ̇, φ̇, ȧ)`: `ẋ = Rθ̇ Ê_θ + (L + R cos θ)φ̇ Ê_φ`;
    /// `dÊ_θ/dt = −θ̇ n − sin θ φ̇ Ê_φ`, `dÊ_φ/dt = −φ̇ (cos φ, sin φ, 0)`;
    /// `q̇₁ = ȧ q₂ + cos a dÊ_θ + sin a dÊ_φ`, `q̇₂ = −ȧ q₁ − sin a dÊ_θ + cos a dÊ_φ`.
    #[inline]
    fn frame_velocity(&self, g: &Rn<3>, xi: &SVector<f64, 3>) -> (SVector<f64, 3>, SMatrix<f64, 3, 2>) {
        let (theta, phi, a) = (g.0[0], g.0[1], g.0[2]);
        let (td, pd, ad) = (xi[0], xi[1], xi[2]);
        let (e, n) = frame_field(theta, phi);
        let (et, ep): (SVector<f64, 3>, SVector<f64, 3>) = (e.column(0).into(), e.column(1).into());
        let xdot = et * (self.small_r() * td) + ep * (self.rho(theta) * pd);
        let (sp, cp) = phi.sin_cos();
        let d_et = -n * td - ep * (theta.sin() * pd);
        let d_ep = SVector::<f64, 3>::new(-cp, -sp, 0.0) * pd;
        let (sa, ca) = a.sin_cos();
        let (q1, q2) = (et * ca + ep * sa, -et * sa + ep * ca);
        let dq1 = q2 * ad + d_et * ca + d_ep * sa;
        let dq2 = -q1 * ad - d_et * sa + d_ep * ca;
        (xdot, SMatrix::<f64, 3, 2>::from_columns(&[dq1, dq2]))
    }

    /// `K = cos θ / (R (L + R cos θ))`.
    fn curvature_at(&self, g: &Rn<3>) -> f64 {
        self.gaussian_curvature(g.0[0])
    }

    /// For `η = (δθ, δφ, δa)`: `δv = δa·ε v` (`U′(a) = εU(a)`),
    /// `δρ = −R sin θ δθ`, `δφ̇ = (δv₂ − φ̇ δρ)/ρ`, and
    /// `δξ = (δv₁/R, δφ̇, cos θ δθ φ̇ + sin θ δφ̇)`.
    fn lift_derivative(&self, g: &Rn<3>, u: &SVector<f64, 2>, eta: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (theta, a) = (g.0[0], g.0[2]);
        let v = rot(a) * u;
        let dv = SVector::<f64, 2>::new(-v[1], v[0]) * eta[2];
        let (st, ct) = theta.sin_cos();
        let rho = self.rho(theta);
        let phidot = v[1] / rho;
        let drho = -self.small_r() * st * eta[0];
        let dphidot = (dv[1] - phidot * drho) / rho;
        SVector::<f64, 3>::new(dv[0] / self.small_r(), dphidot, ct * eta[0] * phidot + st * dphidot)
    }

    /// `dK/dθ·δθ = −L sin θ/(R ρ²)·δθ`, `ρ = L + R cos θ`.
    fn curvature_derivative(&self, g: &Rn<3>, eta: &SVector<f64, 3>) -> f64 {
        let theta = g.0[0];
        let rho = self.rho(theta);
        -self.big_l() * theta.sin() / (self.small_r() * rho * rho) * eta[0]
    }

    /// The derivative of [`frame_velocity`](FrameBundle::frame_velocity)'s
    /// formulas in `(θ, φ, a)` along `η = (δθ, δφ, δa)`, with
    /// `δÊ_θ = −n δθ − sin θ Ê_φ δφ`, `δÊ_φ = P δφ` (`P = (−cos φ, −sin φ, 0)`,
    /// `δP = −Ê_φ δφ`), `δn = Ê_θ δθ + cos θ Ê_φ δφ`.
    fn frame_velocity_derivative(&self, g: &Rn<3>, xi: &SVector<f64, 3>, eta: &SVector<f64, 3>) -> (SVector<f64, 3>, SMatrix<f64, 3, 2>) {
        let (theta, phi, a) = (g.0[0], g.0[1], g.0[2]);
        let (td, pd, ad) = (xi[0], xi[1], xi[2]);
        let (dth, dph, da) = (eta[0], eta[1], eta[2]);
        let (e, n) = frame_field(theta, phi);
        let (et, ep): (SVector<f64, 3>, SVector<f64, 3>) = (e.column(0).into(), e.column(1).into());
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        let (sa, ca) = a.sin_cos();
        let r = self.small_r();
        let p = SVector::<f64, 3>::new(-cp, -sp, 0.0);
        let d_et_ = -n * dth - ep * (st * dph);
        let d_ep_ = p * dph;
        let d_n = et * dth + ep * (ct * dph);
        let d_p = -ep * dph;
        let dxdot = d_et_ * (r * td) + d_ep_ * (self.rho(theta) * pd) + ep * (-r * st * dth * pd);
        // The frame's velocity terms and their derivatives.
        let t_et = -n * td - ep * (st * pd);
        let t_ep = p * pd;
        let dt_et = -d_n * td - d_ep_ * (st * pd) - ep * (ct * dth * pd);
        let dt_ep = d_p * pd;
        let (q1, q2) = (et * ca + ep * sa, -et * sa + ep * ca);
        let dq1_ = d_et_ * ca + d_ep_ * sa + q2 * da;
        let dq2_ = -d_et_ * sa + d_ep_ * ca - q1 * da;
        let ddq1 = dq2_ * ad + dt_et * ca + dt_ep * sa + (-t_et * sa + t_ep * ca) * da;
        let ddq2 = -dq1_ * ad - dt_et * sa + dt_ep * ca + (-t_et * ca - t_ep * sa) * da;
        (dxdot, SMatrix::<f64, 3, 2>::from_columns(&[ddq1, ddq2]))
    }
}
