//! States of the production (frame-bundle) models of
//! [`dynamics`](crate::dynamics) from and to the paper's variables, and from
//! and to embedding-space data.
//!
//! **Embedding space** ([`AmbientBody`]): every model converts its state to
//! an [`AmbientState`] — position `X`, velocity `Ẋ`, body frame `e_A` and
//! the ordinary rates `ė_A` — and builds a state from one
//! ([`AmbientBody::state_from_ambient`]), checking that the data are those
//! of a motion on the manifold: `Ẋ` tangent, `e` tangent (orthonormal and
//! positively oriented for a gyroscope), and
//! `ė = De/Dt − II(Ẋ, e)`, whose normal part is fixed by the second
//! fundamental form (for a gyroscope `De/Dt = e·ω̂` with `ω̂` skew).
//!
//! **The paper's variables** ([`state_from_paper`], [`paper_from_state`]):
//! the generalised coordinates and velocities `(q, q̇)` of a coordinate
//! Lagrangian of [`coords`](super) — the chart `x` of §5–§6 followed by the
//! fibre coordinates `ξ` of `φ` with `e = E(x)·φ(ξ)` (§4):
//!
//! | manifold × body | `q` | Lagrangian |
//! |---|---|---|
//! | S², H² point | `(r, φ)` | [`PointLagrangian`] with [`SphereChart`], [`HyperbolicChart`] ((a88)) |
//! | T² point | `(θ, φ)` | [`PointLagrangian`] with [`TorusChart`] |
//! | S², H², T² gyroscope | `(r, φ, ψ)`, `(θ, φ, ψ)` | [`Gyroscope2`] ((a92), (a135), (a138)) |
//! | S², H², T² affine body | `(r, φ, α, β, λ, μ)` | [`TwoPolarAffine2`] (`φ = L(α)·diag(λ, μ)·R(β)⁻¹`, (a83)/(a84) with the deformation term of SPEC §8) |
//! | incompressible body | `(r, φ, α, β, λ)` | [`FrameLagrangian`] with [`TwoPolarSl`] (`μ = 1/λ`) |
//! | Weyl body | `(r, φ, α, λ)` | [`FrameLagrangian`] with [`TwoPolarWeyl`] (`λ = μ`) |
//! | S³ point, gyroscope | `r̄`, `(r̄, κ)` | [`PointLagrangian`] with [`Sphere3Chart`], [`Gyroscope3`] (rotation vectors, (a172), (a179)) |
//! | S³ affine body | `(r̄, φ_ij)` | [`FrameLagrangian`] with [`GlEntries`] (3 × 3) |
//!
//! and the momenta `p = ∂L/∂q̇` of (a52) ([`state_from_paper_momenta`],
//! [`paper_momenta_from_state`]). The state built from `(q, q̇)` has the
//! paper's frame field as its parallel frame at that instant, `q = E(x)`
//! ([`AmbientMap::reference_frame`]), so that its internal configuration
//! is `ρ = φ(ξ)` and `ρ̇ = φ̇ + Γ(E)(V̂)φ` (the covariant rate of (a74)).
//! The reverse map reads the embedding-space data of the state and inverts
//! the chart ([`from_ambient`]): it is defined wherever the paper's
//! coordinates are (not at the poles of S², the origin of H², the antipode
//! of the S³ chart, nor where `λ = μ` for the two-polar variables), with
//! typed errors elsewhere, while [`AmbientBody::ambient`] is defined
//! everywhere.
//!
//! Errors name the field and the allowed range: [`Error::OutsideChart`]
//! (chart singularities), [`Error::InvalidParameter`] (`"lambda"`, `"mu"`
//! ≤ 0, `"|kappa|"`), [`Error::NotFinite`] (`"x = (r, phi)"`, `"qdot"`,
//! `"p"`, …), [`Error::Constraint`] (ambient data off the manifold, field
//! `"position"`, `"velocity"`, `"frame"`, `"frame_rate"`).

use nalgebra::{SMatrix, SVector};

use super::{ambient_state, from_ambient, momenta, velocities, AmbientMap, AmbientState};
#[allow(unused_imports)] // doc links
use super::{FrameLagrangian, GlEntries, Gyroscope2, Gyroscope3, HyperbolicChart, PointLagrangian, Sphere3Chart, SphereChart};
#[allow(unused_imports)] // doc links
use super::{TorusChart, TwoPolarAffine2, TwoPolarSl, TwoPolarWeyl};
use crate::bundle::FrameBundle;
use crate::dynamics::affine::{AffineBodyModel, BodyState, InternalConstraint, STATE_TOLERANCE};
use crate::dynamics::point::{bundle_element_at, rename_field, tangent_components};
use crate::dynamics::{Gyroscope2Model, Gyroscope2State, Gyroscope3Model, Gyroscope3State, PointModel, PointState, System};
use crate::error::finite;
use crate::lie::{So2, So3};
use crate::potential::Potential;
use crate::{Error, Result};

/// A model whose states convert exactly to and from embedding-space data
/// `(X, Ẋ, e, ė)` ([`AmbientState`]; the frame is zero for a point).
pub trait AmbientBody<const N: usize, const E: usize>: System {
    /// The embedding-space data of `y`: `X`, `Ẋ = q u`, `e = q ρ` and
    /// `ė = q̇ ρ + q ρ̇`, where `q̇ = −II(Ẋ, q)` is the rate of the
    /// parallel frame (from the bundle's horizontal lift, exactly). Defined
    /// everywhere (no chart).
    fn ambient(&self, y: &Self::State) -> AmbientState<N, E>;

    /// The state with embedding-space data `a`, the parallel frame starting
    /// as `parallel` (orthonormal, tangent at `a.position`, positively
    /// oriented as the bundle's frames). Without one: the body frame `e` for
    /// a gyroscope (`ρ = 1`, as [`Gyroscope2Model::state`]), the frame of
    /// [`bundle_element_at`] for a point and an affine body.
    ///
    /// Errors: [`Error::NotFinite`] naming `"position"`, `"velocity"`,
    /// `"frame"`, `"frame_rate"`; [`Error::Constraint`] naming `"position"`
    /// (not on the manifold), `"parallel"` (not an orthonormal tangent frame
    /// of the bundle's orientation), `"velocity"` (not tangent), `"frame"`
    /// (not tangent; a gyroscope's not orthonormal and positively oriented;
    /// nonzero for a point), `"frame_rate"` (its normal part is not
    /// `−II(Ẋ, e)`, or, for a gyroscope, `De/Dt ≠ e·ω̂` with `ω̂` skew; relative
    /// tolerance [`STATE_TOLERANCE`]); and those of the model's own state
    /// constructor (e.g. `"rho"`, `"rho_dot"` off the fibre of a constrained
    /// body).
    fn state_from_ambient(&self, a: &AmbientState<N, E>, parallel: Option<&SMatrix<f64, E, N>>) -> Result<Self::State>;
}

/// The paper's generalised coordinates `q` and velocities `q̇`, in the order
/// of [`Lagrangian::coordinate_names`](super::Lagrangian::coordinate_names).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperState<const Q: usize> {
    /// `q = (x, ξ)`: chart coordinates, then fibre coordinates.
    pub q: SVector<f64, Q>,
    /// `q̇`.
    pub qdot: SVector<f64, Q>,
}

/// The state of `model` at the paper's coordinates and velocities `(q, q̇)`
/// of the coordinate Lagrangian `sys` (which must describe the same body on
/// the same manifold), with parallel frame `E(x)` at this instant, so that
/// `ρ = φ(ξ)`, `ρ̇ = φ̇ + Γ(E)(V̂)φ` and `u = V̂ = E⁻¹ẋ` ((a74)).
///
/// Errors: those of [`ambient_state`] (the chart and fibre checks of `sys`:
/// [`Error::OutsideChart`], [`Error::InvalidParameter`] for `λ, μ ≤ 0`,
/// [`Error::NotFinite`] for `"qdot"`) and of
/// [`AmbientBody::state_from_ambient`].
pub fn state_from_paper<S, M, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    model: &M,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
) -> Result<M::State>
where
    S: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let a = ambient_state(sys, q, qdot)?;
    model.state_from_ambient(&a, Some(&sys.reference_frame(q)))
}

/// The state of `model` at the paper's coordinates `q` and momenta
/// `p = ∂L/∂q̇` ((a52)): [`velocities`] (the inverse Legendre map), then
/// [`state_from_paper`].
///
/// Errors: those of [`velocities`] (field `"p"`) and [`state_from_paper`].
pub fn state_from_paper_momenta<S, M, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    model: &M,
    q: &SVector<f64, Q>,
    p: &SVector<f64, Q>,
) -> Result<M::State>
where
    S: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let v = velocities(sys, q, p)?;
    state_from_paper(sys, model, q, &v)
}

/// The paper's coordinates and velocities of the state `y` of `model`:
/// [`AmbientBody::ambient`], then [`from_ambient`] (the chart point, the
/// fibre coordinates of `φ = Eᵀe` on the branch documented by the fibre,
/// and `q̇` from the rates).
///
/// Errors: those of [`from_ambient`]: [`Error::OutsideChart`] where the
/// paper's coordinates are singular (the poles of S², the origin of H², the
/// antipode of the S³ chart, `λ = μ` of the two-polar variables),
/// [`Error::Constraint`] when the state's internal configuration is not in
/// the fibre of `sys`.
pub fn paper_from_state<S, M, const Q: usize, const N: usize, const E: usize>(sys: &S, model: &M, y: &M::State) -> Result<PaperState<Q>>
where
    S: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let (q, qdot) = from_ambient(sys, &model.ambient(y))?;
    Ok(PaperState { q, qdot })
}

/// The paper's coordinates `q` and momenta `p = ∂L/∂q̇` ((a52)) of the state
/// `y`: [`paper_from_state`], then [`momenta`].
///
/// Errors: those of [`paper_from_state`].
pub fn paper_momenta_from_state<S, M, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    model: &M,
    y: &M::State,
) -> Result<(SVector<f64, Q>, SVector<f64, Q>)>
where
    S: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let s = paper_from_state(sys, model, y)?;
    Ok((s.q, momenta(sys, &s.q, &s.qdot)?))
}

// ---------------------------------------------------------------------------
// Embedding-space data → bundle element, u, ρ, ρ̇
// ---------------------------------------------------------------------------

/// The parts of a state in the parallel frame `q`.
struct Parts<G, const N: usize> {
    g: G,
    u: SVector<f64, N>,
    rho: SMatrix<f64, N, N>,
    rho_dot: SMatrix<f64, N, N>,
}

fn relative_check(field: &'static str, constraint: &'static str, residual: f64, scale: f64) -> Result<()> {
    let d = if scale > 0.0 { residual / scale } else { residual };
    if d.is_nan() || d > STATE_TOLERANCE {
        return Err(Error::Constraint { field, constraint, defect: if d.is_nan() { f64::INFINITY } else { d }, tolerance: STATE_TOLERANCE });
    }
    Ok(())
}

/// `ẋ` and `q̇` of the horizontal lift of `u` at `g` (parallel transport).
fn parallel_rates<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g: &B::Group,
    u: &SVector<f64, N>,
) -> (SVector<f64, E>, SMatrix<f64, E, N>) {
    bundle.frame_velocity(g, &bundle.horizontal_lift(g, u))
}

/// `(X, Ẋ, q ρ, q̇ρ + qρ̇)`.
fn assemble<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g: &B::Group,
    u: &SVector<f64, N>,
    rho: &SMatrix<f64, N, N>,
    rho_dot: &SMatrix<f64, N, N>,
) -> AmbientState<N, E> {
    let q = bundle.frame_vectors(g);
    let (velocity, qdot) = parallel_rates(bundle, g, u);
    AmbientState { position: bundle.position(g), velocity, frame: q * rho, frame_rate: qdot * rho + q * rho_dot }
}

/// Splits `a` in the frame `q` (`parallel_field` names `q` in errors):
/// `g = (X, q)`, `u = qᵀηẊ`, `ρ = qᵀηe`, `ρ̇ = qᵀηė`, checking that `e` is
/// tangent and that `ė − (q̇ρ + qρ̇)` (its normal part against `−II(Ẋ, e)`)
/// vanishes.
fn parts<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    a: &AmbientState<N, E>,
    q: &SMatrix<f64, E, N>,
    parallel_field: &'static str,
) -> Result<Parts<B::Group, N>> {
    finite("position", a.position.iter())?;
    finite("velocity", a.velocity.iter())?;
    finite("frame", a.frame.iter())?;
    finite("frame_rate", a.frame_rate.iter())?;
    finite(parallel_field, q.iter())?;
    let g = bundle.from_frame(&a.position, q).map_err(|e| rename_field(rename_field(e, "q", parallel_field), "p", "position"))?;
    let u = tangent_components(bundle, &g, &a.velocity, "velocity")?;
    let qv = bundle.frame_vectors(&g);
    let eta = bundle.ambient_metric();
    let grow = qv.amax().powi(2).max(1.0);
    let rho = qv.transpose() * eta * a.frame;
    relative_check("frame", "frame vectors tangent to the manifold at the point", (a.frame - qv * rho).amax(), a.frame.amax() * grow)?;
    let rho_dot = qv.transpose() * eta * a.frame_rate;
    let (_, qdot) = parallel_rates(bundle, &g, &u);
    let want = qdot * rho + qv * rho_dot;
    relative_check(
        "frame_rate",
        "ė = De/Dt − II(Ẋ, e): the normal part of the frame rate is fixed by the second fundamental form",
        (a.frame_rate - want).amax(),
        a.frame_rate.amax().max((qdot * rho).amax()).max(f64::MIN_POSITIVE) * grow,
    )?;
    Ok(Parts { g, u, rho, rho_dot })
}

/// `ω̂ = ρᵀρ̇` of a rigid body, after checking that `ρ` is a rotation and
/// `ω̂` skew (field `"frame"`, `"frame_rate"`).
fn rigid_rate<const N: usize>(rho: &SMatrix<f64, N, N>, rho_dot: &SMatrix<f64, N, N>) -> Result<SMatrix<f64, N, N>> {
    let orth = (rho.transpose() * rho - SMatrix::<f64, N, N>::identity()).amax();
    let det = nalgebra::DMatrix::from_column_slice(N, N, rho.as_slice()).determinant();
    if orth.is_nan() || orth > STATE_TOLERANCE || det <= 0.0 {
        return Err(Error::Constraint {
            field: "frame",
            constraint: "body frame orthonormal and of the parallel frame's orientation (a gyroscope is rigid)",
            defect: if orth > STATE_TOLERANCE { orth } else { f64::INFINITY },
            tolerance: STATE_TOLERANCE,
        });
    }
    let w = rho.transpose() * rho_dot;
    relative_check("frame_rate", "De/Dt = e·ω̂ with ω̂ skew (a gyroscope is rigid)", (w + w.transpose()).amax() / 2.0, w.amax())?;
    Ok((w - w.transpose()) / 2.0)
}

// ---------------------------------------------------------------------------
// The models
// ---------------------------------------------------------------------------

impl<B, P, const N: usize, const E: usize> AmbientBody<N, E> for PointModel<B, P, N, E>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    /// `(X, Ẋ, 0, 0)`.
    fn ambient(&self, y: &PointState<B::Group, N>) -> AmbientState<N, E> {
        let (position, velocity) = (self.position(y), self.velocity(y));
        AmbientState { position, velocity, frame: SMatrix::zeros(), frame_rate: SMatrix::zeros() }
    }
    /// `a.frame` and `a.frame_rate` must be zero (field `"frame"`).
    fn state_from_ambient(&self, a: &AmbientState<N, E>, parallel: Option<&SMatrix<f64, E, N>>) -> Result<PointState<B::Group, N>> {
        finite("frame", a.frame.iter().chain(a.frame_rate.iter()))?;
        let d = a.frame.amax().max(a.frame_rate.amax());
        if d > 0.0 {
            return Err(Error::Constraint {
                field: "frame",
                constraint: "zero frame and frame rate (a structureless point has no body frame)",
                defect: d,
                tolerance: 0.0,
            });
        }
        finite("position", a.position.iter())?;
        let q = match parallel {
            Some(q) => *q,
            None => self.bundle().frame_vectors(&bundle_element_at(self.bundle(), &a.position).map_err(|e| rename_field(e, "p", "position"))?),
        };
        let p = parts(self.bundle(), a, &q, "parallel")?;
        self.state_from_parts(&p.g, &p.u)
    }
}

impl<B, P> AmbientBody<2, 3> for Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3>,
    P: Potential<2, 3>,
{
    /// `ρ = U(α)`, `ρ̇ = ρ·α̇ε` with `α̇` the angular velocity.
    fn ambient(&self, y: &Gyroscope2State<B::Group>) -> AmbientState<2, 3> {
        let rho = y.0 .1.matrix();
        let w = self.angular_velocity(y);
        let rho_dot = rho * SMatrix::<f64, 2, 2>::new(0.0, -w, w, 0.0);
        assemble(self.bundle(), &y.0 .0, &self.velocity_components(y), &rho, &rho_dot)
    }
    /// The spin is `s = σ I ω` with `ω = (ρᵀρ̇)₂₁` ((a91): `ω = ψ̇ + ω_dr`).
    fn state_from_ambient(&self, a: &AmbientState<2, 3>, parallel: Option<&SMatrix<f64, 3, 2>>) -> Result<Gyroscope2State<B::Group>> {
        let (q, field) = match parallel {
            Some(q) => (*q, "parallel"),
            None => (a.frame, "frame"),
        };
        let p = parts(self.bundle(), a, &q, field)?;
        let w = rigid_rate(&p.rho, &p.rho_dot)?;
        let rho = So2::new(p.rho[(0, 0)], p.rho[(1, 0)]).map_err(|e| rename_field(e, "So2 (cos, sin)", "frame"))?;
        self.state_from_parts(&p.g, &rho, &p.u, self.spin_for_angular_velocity(w[(1, 0)]))
    }
}

impl<B, P> AmbientBody<3, 4> for Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4>,
    P: Potential<3, 4>,
{
    /// `ρ̇ = ρŴ` with `W` the body angular velocity.
    fn ambient(&self, y: &Gyroscope3State<B::Group>) -> AmbientState<3, 4> {
        let rho = *y.0 .1.matrix();
        let rho_dot = rho * So3::hat(&self.angular_velocity(y));
        assemble(self.bundle(), &y.0 .0, &self.velocity_components(y), &rho, &rho_dot)
    }
    /// The spin in parallel components is `π = ρ·σ𝕀W` with `Ŵ = ρᵀρ̇`.
    fn state_from_ambient(&self, a: &AmbientState<3, 4>, parallel: Option<&SMatrix<f64, 4, 3>>) -> Result<Gyroscope3State<B::Group>> {
        let (q, field) = match parallel {
            Some(q) => (*q, "parallel"),
            None => (a.frame, "frame"),
        };
        let p = parts(self.bundle(), a, &q, field)?;
        let w = rigid_rate(&p.rho, &p.rho_dot)?;
        let rho = So3::new(p.rho).map_err(|e| rename_field(e, "So3 matrix", "frame"))?;
        let pi = rho.matrix() * self.spin_for_angular_velocity(&So3::vee(&w));
        self.state_from_parts(&p.g, &rho, &p.u, &pi)
    }
}

impl<B, V, C, const N: usize, const E: usize> AmbientBody<N, E> for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    /// `ρ`, `ρ̇` from the fibre element and the (projected) hypermomentum.
    fn ambient(&self, y: &BodyState<B, C, N, E>) -> AmbientState<N, E> {
        let k = self.kinematics(y);
        assemble(self.bundle(), &y.0 .0, &y.1 .0 .0, &k.rho, &k.rho_dot)
    }
    /// Through [`AffineBodyModel::state`] (which checks `ρ`, `ρ̇` against the
    /// body's constraint).
    fn state_from_ambient(&self, a: &AmbientState<N, E>, parallel: Option<&SMatrix<f64, E, N>>) -> Result<BodyState<B, C, N, E>> {
        finite("position", a.position.iter())?;
        let q = match parallel {
            Some(q) => *q,
            None => self.bundle().frame_vectors(&bundle_element_at(self.bundle(), &a.position).map_err(|e| rename_field(e, "p", "position"))?),
        };
        let p = parts(self.bundle(), a, &q, "parallel")?;
        self.state(&p.g, &p.rho, &p.u, &p.rho_dot)
    }
}
