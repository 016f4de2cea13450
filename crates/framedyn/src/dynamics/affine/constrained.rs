//! The constrained affine bodies of §4 (after (b62)): incompressible (SL(N)),
//! Weyl (CO⁺(N): rotations and dilatations) and purely dilatational (ℝ⁺)
//! bodies, each carrying only its own degrees of freedom.
//!
//! All three are [`AffineBodyModel`]s with a different [`InternalConstraint`];
//! the common derivation (d'Alembert: the reaction torque does no work on
//! admissible motions, so the equations are the projection of the balance law
//! (c59) onto the constraint algebra `𝔥`) is on that trait. Here are the three
//! restrictions of `T_int = ½ tr(ρ̇Jρ̇ᵀ)` and their equations; `ρ̇ = ρΩ̂`,
//! `N = −ρ(∂V/∂ρ)ᵀ`, `G = ρᵀρ`.
//!
//! # Incompressible body: `ρ ∈ SL(N)` ([`Isochoric`], [`IncompressibleModel`])
//!
//! The paper's constraint `det[e^A_i] = √det g` is `det ρ = 1`; infinitesimally
//! `tr Ω̂ = 0`. The reaction force of the constraint on `ρ` is
//! `p ∂(det ρ)/∂ρ = p ρ⁻ᵀ`, so (d59) becomes `ρ̈J = −∂V/∂ρ + pρ⁻ᵀ`, i.e.
//! `ρJρ̈ᵀ = N + pI`: the reaction is an isotropic pressure `p`, and the
//! traceless part of (c59) — the paper's "g-traceless parts" — is free of it:
//!
//! ```text
//! ν = K − (tr K/N) I,      ν̇ = traceless(ρ̇Jρ̇ᵀ + N)               (N² − 1 equations)
//! ```
//!
//! Velocity from `ν`: `ρJΩ̂ᵀρᵀ = ν + cI` with `c` fixed by `tr Ω̂ = 0`:
//! `Ω̂ = (Aᵀ + cG⁻¹)J⁻¹`, `A = ρ⁻¹νρ⁻ᵀ`, `c = −tr(J⁻¹A)/tr(J⁻¹G⁻¹)`.
//! The pressure follows from `d²(det ρ)/dt² = 0`:
//! `p = [tr(Ω̂²) + tr(ρ⁻¹(∂V/∂ρ)J⁻¹)] / tr(G⁻¹J⁻¹)`
//! ([`AffineBodyModel::pressure`]). The spin is untouched (`pI` is
//! symmetric).
//!
//! # Weyl body: `ρ = λR ∈ CO⁺(N)` ([`Conformal`], [`WeylModel`])
//!
//! `Ω̂ = κI + ω`, `κ = λ̇/λ`, `ω = RᵀṘ` skew, and (`tr(ωJ) = 0`)
//! `T_int = ½λ̇² tr J + ½λ² tr(ωJωᵀ)`. The admissible `Ω = ρΩ̂ρ⁻¹` span
//! co(N), whose orthogonal complement is the symmetric traceless matrices: the
//! reaction is a symmetric traceless (shear) stress, and the equations are the
//! trace (b63) and the skew part (b61) of (c59):
//!
//! ```text
//! τ = tr K = λλ̇ tr J:   τ̇ = tr(ρ̇Jρ̇ᵀ) + tr N = 2T_int − tr(ρᵀ ∂V/∂ρ)     (virial)
//! S = K − Kᵀ:          Ṡ = N − Nᵀ
//! ```
//!
//! stored as `(τ/N) I + S/2 ∈ co(N)`. Velocity: `κ = τ/(λ² tr J)`, and
//! `Jω + ωJ = −RᵀSR/λ²` ([`Inertia::solve_rotational`]). Equivalently
//! `λ̈ tr J = λ tr(ωJωᵀ) − ∂V/∂λ` (centrifugal force) and the Euler equations
//! of the body angular momentum `λ²(Jω + ωJ)`.
//!
//! # Pure dilatation: `ρ = λρ₀`, `λ > 0` ([`PureDilatation`], [`DilatationModel`])
//!
//! The paper's condition is on the velocity only: `Ω^i_j = λδ^i_j`,
//! `Ω̂^A_B = λδ^A_B` — the body frame is rescaled, never rotated or sheared,
//! relative to the parallel frame, so `ρ(t) = λ(t)ρ₀` with a **fixed reference
//! shape** `ρ₀` (`PureDilatation::new`; the default `ρ₀ = I` makes the body
//! frame `λ` times an orthonormal parallel frame, as in
//! [`Dilatation`]). `ρ₀` is constraint data, not a
//! degree of freedom. With `c = tr(ρ₀Jρ₀ᵀ)`: `T_int = ½cλ̇²`, and the trace of
//! (c59), (b63):
//!
//! ```text
//! τ = tr K = cλλ̇  (conjugate to ln λ):   τ̇ = cλ̇² − λ ∂V/∂λ,   ∂V/∂λ = tr(ρ₀ᵀ ∂V/∂ρ)
//! ```
//!
//! i.e. `cλ̈ = −∂V/∂λ`. `K = cλλ̇ ρ₀Jρ₀ᵀ/c` is symmetric: the spin vanishes and
//! the translational motion feels no spin–curvature force. `λ` is stored as
//! `ln λ` ([`Rn`]`<1>`), so it stays positive.
//!
//! # When a constrained trajectory is also a free affine one
//!
//! Exactly when the reaction vanishes along it, i.e. the unconstrained
//! acceleration `ρ̈ = −(∂V/∂ρ)J⁻¹` is tangent to the constraint:
//! - SL: `p ≡ 0`. E.g. force-free internal motion with nilpotent `Ω̂`
//!   (simple shear: `Ω̂² = 0`, `ρ₀(I + tΩ̂)` has `det = 1`), any `J`.
//! - CO⁺(2) ∪ {0} = {`[[a, −b], [b, a]]`} is a linear space: exact for force-free
//!   internal motion (any `J`), and for `J ∝ I` with `∂V/∂ρ` conformal at
//!   conformal `ρ` (e.g. `V = V(x) + f(tr G, det G)`). For `N ≥ 3`, `ω²` is not
//!   `∝ I`: a rotating free affine body leaves CO⁺(N); exact only for `ω = 0`.
//! - ℝ⁺: force-free internal motion (any `J`, `ρ₀`); or `J ∝ I`, `ρ₀` conformal
//!   and `V = V(x) + f(tr G, det G)`.

use nalgebra::{SMatrix, SVector};

use super::{
    conformality_defect, inverse, linear_collapse_time, trace_of_product, Additive, AffineBodyModel, BodyState,
    Inertia, InternalConstraint, Kinematics, MatrixAlgebra, STATE_TOLERANCE,
};
use crate::body::{Dilatation, Incompressible, Weyl};
use crate::bundle::FrameBundle;
use crate::error::finite;
use crate::lie::matrix::{det, traceless_part};
use crate::lie::{Co, Rn, Sl, SoN};
use crate::potential::Potential;
use crate::{Error, Result};

type Mat<const N: usize> = SMatrix<f64, N, N>;

// ---------------------------------------------------------------------------
// SL(N)
// ---------------------------------------------------------------------------

/// The incompressibility constraint `det ρ = 1`: fibre [`Sl`], momentum the
/// traceless part `ν` of the hypermomentum (`N² − 1` components). See the
/// [module documentation](self).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Isochoric;

impl<const N: usize> InternalConstraint<N> for Isochoric {
    type Body = Incompressible<N>;
    type Fibre = Sl<N>;
    type Momentum = Additive<Sl<N>>;
    const NAME: &'static str = "SL(n)";
    const TANGENCY: &'static str = "incompressible motion: tr(ρ⁻¹ρ̇) = 0";
    const CONFIGURATION: &'static str = "incompressible: det ρ = 1";

    fn body_parameters(body: &Incompressible<N>) -> (f64, Mat<N>) {
        (body.mass(), *body.inertia())
    }
    #[inline]
    fn rho(&self, f: &Sl<N>) -> Mat<N> {
        *f.matrix()
    }
    fn fibre(&self, rho: &Mat<N>) -> Result<Sl<N>> {
        let defect = (det(rho) - 1.0).abs();
        if defect.is_nan() || defect > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "rho",
                constraint: "incompressible: det ρ = 1",
                defect,
                tolerance: STATE_TOLERANCE,
            });
        }
        Sl::normalized(*rho)
    }
    #[inline]
    fn momentum(&self, k: &Mat<N>) -> Additive<Sl<N>> {
        Additive(traceless_part(k))
    }
    #[inline]
    fn momentum_matrix(&self, m: &Additive<Sl<N>>) -> Mat<N> {
        m.0
    }
    #[inline]
    fn project(&self, a: &Mat<N>) -> Mat<N> {
        traceless_part(a)
    }
    #[inline]
    fn kinematics(&self, f: &Sl<N>, k: &Mat<N>, inertia: &Inertia<N>) -> Kinematics<Sl<N>, N> {
        let rho = *f.matrix();
        let rho_inv = inverse(&rho).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN));
        let a = rho_inv * k * rho_inv.transpose();
        let g_inv = rho_inv * rho_inv.transpose();
        let j_inv = inertia.inverse();
        let c = -trace_of_product(j_inv, &a) / trace_of_product(j_inv, &g_inv);
        let omega = (a.transpose() + g_inv * c) * j_inv;
        Kinematics { rho, rho_dot: rho * omega, xi: omega }
    }
    /// The derivative of `a = ρ⁻¹Kρ⁻ᵀ`, `G⁻¹ = ρ⁻¹ρ⁻ᵀ`, `c` and
    /// `Ω̂ = (aᵀ + cG⁻¹)J⁻¹` with `δρ = ρX`, `δ(ρ⁻¹) = −Xρ⁻¹`.
    fn kinematics_derivative(&self, _f: &Sl<N>, k: &Mat<N>, inertia: &Inertia<N>, kin: &Kinematics<Sl<N>, N>, df: &Mat<N>, dk: &Mat<N>) -> Kinematics<Sl<N>, N> {
        let rho = kin.rho;
        let rho_inv = inverse(&rho).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN));
        let d_inv = -(df * rho_inv);
        let a = rho_inv * k * rho_inv.transpose();
        let da = d_inv * k * rho_inv.transpose() + rho_inv * dk * rho_inv.transpose() + rho_inv * k * d_inv.transpose();
        let g_inv = rho_inv * rho_inv.transpose();
        let dg_inv = d_inv * rho_inv.transpose() + rho_inv * d_inv.transpose();
        let j_inv = inertia.inverse();
        let (num, den) = (trace_of_product(j_inv, &a), trace_of_product(j_inv, &g_inv));
        let c = -num / den;
        let dc = -(trace_of_product(j_inv, &da) - c * -trace_of_product(j_inv, &dg_inv)) / den;
        let d_omega = (da.transpose() + dg_inv * c + g_inv * dc) * j_inv;
        let d_rho = rho * df;
        Kinematics { rho: d_rho, rho_dot: d_rho * kin.xi + rho * d_omega, xi: d_omega }
    }
    fn momentum_direction(&self, dm: &Mat<N>) -> Mat<N> {
        *dm
    }
    fn velocity_defect(&self, omega: &Mat<N>) -> f64 {
        (omega.trace() / N as f64).abs()
    }
    /// `ρ⁻¹(−w)ρ`: traceless, so in sl(N).
    fn frame_gauge(&self, f: &Sl<N>, w: &Mat<N>) -> Option<Mat<N>> {
        inverse(f.matrix()).map(|inv| -(inv * w * f.matrix()))
    }
}

/// The incompressible affine body of §4: `ρ ∈ SL(N)`, `N + N² − 1` degrees of
/// freedom.
pub type IncompressibleModel<B, V, const N: usize, const E: usize> = AffineBodyModel<B, V, Isochoric, N, E>;

impl<B, V, const N: usize, const E: usize> AffineBodyModel<B, V, Isochoric, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
{
    /// The reaction pressure `p` that keeps `det ρ = 1` (reaction force `pρ⁻ᵀ`
    /// on `ρ`, reaction torque `pI`):
    /// `p = [tr(Ω̂²) + tr(ρ⁻¹(∂V/∂ρ)J⁻¹)] / tr(G⁻¹J⁻¹)`, from
    /// `d²(det ρ)/dt² = 0`. The trajectory is also one of the free affine body
    /// iff `p ≡ 0`.
    pub fn pressure(&self, y: &BodyState<B, Isochoric, N, E>) -> f64 {
        let kin = self.kinematics(y);
        let rho_inv = inverse(&kin.rho).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN));
        let j_inv = self.inertia().inverse();
        let v_rho = -(self.torque(y).transpose() * rho_inv.transpose());
        let num = trace_of_product(&kin.xi, &kin.xi) + trace_of_product(&(rho_inv * v_rho), j_inv);
        num / trace_of_product(&(rho_inv * rho_inv.transpose()), j_inv)
    }
}

// ---------------------------------------------------------------------------
// CO⁺(N)
// ---------------------------------------------------------------------------

/// The Weyl constraint: rotations and dilatations only, `ρ = λR`; fibre
/// [`Co`], momentum `(τ/N)I + S/2 ∈ co(N)` (`τ = tr K`, `S` the spin;
/// `1 + N(N−1)/2` components). See the [module documentation](self).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Conformal;

/// `(tr a/N)I + (a − aᵀ)/2`: the orthogonal projection onto co(N).
#[inline]
fn co_part<const N: usize>(a: &Mat<N>) -> Mat<N> {
    <Co<N> as MatrixAlgebra>::project_algebra(a)
}

impl<const N: usize> InternalConstraint<N> for Conformal {
    type Body = Weyl<N>;
    type Fibre = Co<N>;
    type Momentum = Additive<Co<N>>;
    const NAME: &'static str = "CO+(n)";
    const TANGENCY: &'static str = "Weyl motion: ρ⁻¹ρ̇ = κI + ω, ω skew";
    const CONFIGURATION: &'static str = "conformal: ρ = λR, R ∈ SO(n)";

    fn body_parameters(body: &Weyl<N>) -> (f64, Mat<N>) {
        (body.mass(), *body.inertia())
    }
    #[inline]
    fn rho(&self, f: &Co<N>) -> Mat<N> {
        f.matrix()
    }
    fn fibre(&self, rho: &Mat<N>) -> Result<Co<N>> {
        let defect = conformality_defect(rho);
        if defect.is_nan() || defect > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "rho",
                constraint: "conformal: ρᵀρ = λ²I, λ = det(ρ)^{1/n}",
                defect,
                tolerance: STATE_TOLERANCE,
            });
        }
        let ln_lambda = det(rho).ln() / N as f64;
        Ok(Co::from_parts(ln_lambda, SoN::nearest(rho * (-ln_lambda).exp())?))
    }
    #[inline]
    fn momentum(&self, k: &Mat<N>) -> Additive<Co<N>> {
        Additive(co_part(k))
    }
    #[inline]
    fn momentum_matrix(&self, m: &Additive<Co<N>>) -> Mat<N> {
        m.0
    }
    #[inline]
    fn project(&self, a: &Mat<N>) -> Mat<N> {
        co_part(a)
    }
    #[inline]
    fn kinematics(&self, f: &Co<N>, k: &Mat<N>, inertia: &Inertia<N>) -> Kinematics<Co<N>, N> {
        let lambda = f.lambda();
        let r = f.rotation().matrix();
        let rho = r * lambda;
        let inv_l2 = 1.0 / (lambda * lambda);
        let kappa = k.trace() * inv_l2 / inertia.matrix().trace();
        let spin = k - k.transpose();
        let mut omega = inertia.solve_rotational(&(-(r.transpose() * spin * r) * inv_l2));
        for i in 0..N {
            omega[(i, i)] += kappa;
        }
        Kinematics { rho, rho_dot: rho * omega, xi: omega }
    }
    /// With `X = κ_X I + W` (`δλ = κ_X λ`, `δR = RW`): the derivative of
    /// `κ = tr K/(λ² tr J)` and of `Ω̂ = S(−RᵀAR/λ²) + κI`, `A = K − Kᵀ`
    /// (`S` = [`Inertia::solve_rotational`], linear).
    fn kinematics_derivative(&self, f: &Co<N>, k: &Mat<N>, inertia: &Inertia<N>, kin: &Kinematics<Co<N>, N>, df: &Mat<N>, dk: &Mat<N>) -> Kinematics<Co<N>, N> {
        let lambda = f.lambda();
        let r = f.rotation().matrix();
        let kx = df.trace() / N as f64;
        let w = (df - df.transpose()) * 0.5;
        let dr = r * w;
        let inv_l2 = 1.0 / (lambda * lambda);
        let d_inv_l2 = -2.0 * kx * inv_l2;
        let tr_j = inertia.matrix().trace();
        let dkappa = (dk.trace() * inv_l2 + k.trace() * d_inv_l2) / tr_j;
        let (spin, dspin) = (k - k.transpose(), dk - dk.transpose());
        let arg = dr.transpose() * spin * r + r.transpose() * dspin * r + r.transpose() * spin * dr;
        let mut d_omega = inertia.solve_rotational(&(-(arg * inv_l2 + r.transpose() * spin * r * d_inv_l2)));
        for i in 0..N {
            d_omega[(i, i)] += dkappa;
        }
        let d_rho = kin.rho * df;
        Kinematics { rho: d_rho, rho_dot: d_rho * kin.xi + kin.rho * d_omega, xi: d_omega }
    }
    fn momentum_direction(&self, dm: &Mat<N>) -> Mat<N> {
        *dm
    }
    fn velocity_defect(&self, omega: &Mat<N>) -> f64 {
        (omega - co_part(omega)).amax()
    }
    /// `ρ⁻¹(−w)ρ = −Rᵀ w R` for `ρ = λR`: skew, so in co(N).
    fn frame_gauge(&self, f: &Co<N>, w: &Mat<N>) -> Option<Mat<N>> {
        let r = f.rotation().matrix();
        Some(-(r.transpose() * w * *r))
    }
}

/// The Weyl body of §4 (rigid rotations and dilatations): `ρ ∈ CO⁺(N)`,
/// `N + 1 + N(N−1)/2` degrees of freedom.
pub type WeylModel<B, V, const N: usize, const E: usize> = AffineBodyModel<B, V, Conformal, N, E>;

impl<B, V, const N: usize, const E: usize> AffineBodyModel<B, V, Conformal, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
{
    /// The dilatation `λ = det(ρ)^{1/N}` of `ρ = λR`.
    pub fn lambda(&self, y: &BodyState<B, Conformal, N, E>) -> f64 {
        y.0 .1.lambda()
    }
    /// The rotation `R` of `ρ = λR`.
    pub fn rotation(&self, y: &BodyState<B, Conformal, N, E>) -> Mat<N> {
        *y.0 .1.rotation().matrix()
    }
}

// ---------------------------------------------------------------------------
// ℝ⁺
// ---------------------------------------------------------------------------

/// Pure dilatations `ρ = λρ₀` of a fixed reference shape `ρ₀` (default `I`);
/// fibre `ln λ` ([`Rn`]`<1>`), momentum `τ = tr K` (1 component). See the
/// [module documentation](self).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PureDilatation<const N: usize> {
    shape: Mat<N>,
}

impl<const N: usize> Default for PureDilatation<N> {
    /// `ρ₀ = I`.
    fn default() -> Self {
        Self { shape: Mat::<N>::identity() }
    }
}

impl<const N: usize> PureDilatation<N> {
    /// Pure dilatations of the reference shape `rho0` (finite,
    /// [`Error::NotFinite`] field `"rho0"`; `det ρ₀ > 0`,
    /// [`Error::InvalidParameter`] field `"det(rho0)"`).
    pub fn new(rho0: &Mat<N>) -> Result<Self> {
        finite("rho0", rho0.iter())?;
        let d = det(rho0);
        if !(d > 0.0 && d.is_finite()) {
            return Err(Error::InvalidParameter { field: "det(rho0)", value: d, allowed: "finite and > 0" });
        }
        Ok(Self { shape: *rho0 })
    }
    /// The reference shape `ρ₀`.
    pub fn shape(&self) -> &Mat<N> {
        &self.shape
    }
    /// `c = tr(ρ₀Jρ₀ᵀ)`: `T_int = ½cλ̇²`.
    #[inline]
    pub fn dilatational_inertia(&self, inertia: &Inertia<N>) -> f64 {
        trace_of_product(&(self.shape * inertia.matrix()), &self.shape.transpose())
    }
}

impl<const N: usize> InternalConstraint<N> for PureDilatation<N> {
    type Body = Dilatation<N>;
    type Fibre = Rn<1>;
    type Momentum = Rn<1>;
    const NAME: &'static str = "R+";
    const TANGENCY: &'static str = "pure dilatation: ρ⁻¹ρ̇ = κI";
    const CONFIGURATION: &'static str = "pure dilatation of the reference shape: ρ = λρ₀";

    fn body_parameters(body: &Dilatation<N>) -> (f64, Mat<N>) {
        (body.mass(), *body.inertia())
    }
    #[inline]
    fn rho(&self, f: &Rn<1>) -> Mat<N> {
        self.shape * f.0[0].exp()
    }
    fn fibre(&self, rho: &Mat<N>) -> Result<Rn<1>> {
        let ln_lambda = (det(rho) / det(&self.shape)).ln() / N as f64;
        let defect = (rho - self.shape * ln_lambda.exp()).amax() / rho.amax();
        if defect.is_nan() || defect > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "rho",
                constraint: "pure dilatation of the reference shape: ρ = λρ₀",
                defect,
                tolerance: STATE_TOLERANCE,
            });
        }
        Ok(Rn(SVector::<f64, 1>::new(ln_lambda)))
    }
    #[inline]
    fn momentum(&self, k: &Mat<N>) -> Rn<1> {
        Rn(SVector::<f64, 1>::new(k.trace()))
    }
    #[inline]
    fn momentum_matrix(&self, m: &Rn<1>) -> Mat<N> {
        Mat::<N>::identity() * (m.0[0] / N as f64)
    }
    #[inline]
    fn project(&self, a: &Mat<N>) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(a.trace())
    }
    #[inline]
    fn kinematics(&self, f: &Rn<1>, k: &Mat<N>, inertia: &Inertia<N>) -> Kinematics<Rn<1>, N> {
        let lambda = f.0[0].exp();
        let rho = self.shape * lambda;
        let kappa = k.trace() / (lambda * lambda * self.dilatational_inertia(inertia));
        Kinematics { rho, rho_dot: rho * kappa, xi: SVector::<f64, 1>::new(kappa) }
    }
    /// `δλ = λ δl`, `δκ = tr δK/(λ²c) − 2κ δl`, `δρ = ρ δl`, `δρ̇ = δ(ρκ)`.
    fn kinematics_derivative(&self, f: &Rn<1>, _k: &Mat<N>, inertia: &Inertia<N>, kin: &Kinematics<Rn<1>, N>, df: &SVector<f64, 1>, dk: &Mat<N>) -> Kinematics<Rn<1>, N> {
        let lambda = f.0[0].exp();
        let kappa = kin.xi[0];
        let dkappa = dk.trace() / (lambda * lambda * self.dilatational_inertia(inertia)) - 2.0 * kappa * df[0];
        let d_rho = kin.rho * df[0];
        Kinematics { rho: d_rho, rho_dot: d_rho * kappa + kin.rho * dkappa, xi: SVector::<f64, 1>::new(dkappa) }
    }
    fn momentum_direction(&self, dm: &SVector<f64, 1>) -> Mat<N> {
        Mat::<N>::identity() * (dm[0] / N as f64)
    }
    fn velocity_defect(&self, omega: &Mat<N>) -> f64 {
        let mut d = *omega;
        let t = omega.trace() / N as f64;
        for i in 0..N {
            d[(i, i)] -= t;
        }
        d.amax()
    }
    fn frame_gauge(&self, _f: &Rn<1>, _w: &Mat<N>) -> Option<SVector<f64, 1>> {
        None
    }
}

/// The purely dilatational body of §4: `ρ = λρ₀`, `N + 1` degrees of freedom.
pub type DilatationModel<B, V, const N: usize, const E: usize> = AffineBodyModel<B, V, PureDilatation<N>, N, E>;

impl<B, V, const N: usize, const E: usize> AffineBodyModel<B, V, PureDilatation<N>, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
{
    /// The same model with the reference shape `rho0` (see
    /// [`PureDilatation::new`] for the errors).
    pub fn with_reference_shape(self, rho0: &Mat<N>) -> Result<Self> {
        let c = PureDilatation::new(rho0)?;
        Ok(self.replace_constraint(c))
    }
    /// The dilatation `λ` of `ρ = λρ₀`.
    pub fn lambda(&self, y: &BodyState<B, PureDilatation<N>, N, E>) -> f64 {
        y.0 .1 .0[0].exp()
    }
    /// In force-free motion `λ(t) = λ + tλ̇` reaches 0 after `t* = −λ/λ̇`
    /// (`None` unless `λ̇ < 0`).
    pub fn free_collapse_time(&self, y: &BodyState<B, PureDilatation<N>, N, E>) -> Option<f64> {
        let kin = self.kinematics(y);
        linear_collapse_time(&(Mat::<N>::identity() * kin.xi[0]))
    }
}
