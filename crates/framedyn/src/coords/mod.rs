//! The paper's own coordinate formulation (SPEC §3.1): Lagrangians in the
//! charts and frame fields of §5–§6 and their Euler–Lagrange equations by
//! automatic differentiation.
//!
//! This module is an **independent** derivation used as the cross-check of
//! the chart-free frame-bundle form ([`dynamics`](crate::dynamics)) and as the
//! baseline that shows where coordinates fail (the poles of S² and H²). Its
//! chart geometry is re-implemented here, generic over the scalar type, and
//! tested against the `f64` [`Manifold`](crate::manifold::Manifold)s rather
//! than built on them.
//!
//! - [`ChartGeometry`]: metric `g_ij`, frame `E^i_A`, coframe, connection
//!   coefficients `Γ^A_{BC}(E)`, embedding — [`SphereChart`] (S², `(r, φ)`),
//!   [`HyperbolicChart`] (H², `(r, φ)`), [`TorusChart`] (T², `(θ, φ)`),
//!   [`Sphere3Chart`] (S³, rotation vector `r̄`).
//! - [`Fibre`]: the internal configuration `φ(ξ)`, `e = E(x)·φ` —
//!   [`PlaneRotation`] `U(ψ)`, [`RotationVector`] (SO(3)), [`GlEntries`]
//!   (GL⁺(2) and GL⁺(3)), [`TwoPolar`] `(α, β, λ, μ)`, its restrictions
//!   [`TwoPolarSl`] `(α, β, λ)` (incompressible) and [`TwoPolarWeyl`]
//!   `(α, λ)` (Weyl), [`PolarDecomposition`] `(ψ, ξ, η, ζ)`.
//! - [`Lagrangian`] `L(q, q̇) = T − V` from (a52) with the co-moving velocity
//!   (a74): [`PointLagrangian`], [`FrameLagrangian`] (aliases [`Gyroscope2`],
//!   [`Affine2`], [`TwoPolarAffine2`], [`PolarAffine2`], [`Gyroscope3`]).
//! - Euler–Lagrange accelerations [`accelerations`]: with `M = ∂²L/∂q̇²` and
//!   `C = ∂²L/∂q̇∂q`, `q̈ = M⁻¹(∂L/∂q − C q̇)`, all derivatives exact by
//!   hyper-dual numbers; [`energy`] `E = q̇·∂L/∂q̇ − L`, [`momenta`]
//!   `p = ∂L/∂q̇` and the inverse Legendre map [`velocities`],
//!   [`hamiltonian`].
//! - Ambient data for cross-checks: [`ambient_state`] (position, velocity,
//!   frame vectors and their rates in the embedding space),
//!   [`ambient_acceleration`] (second derivatives along a trajectory) and the
//!   inverse [`from_ambient`].
//! - States of the production models ([`dynamics`](crate::dynamics)) from
//!   and to the paper's variables and embedding-space data ([`AmbientBody`],
//!   [`state_from_paper`], [`paper_from_state`], [`state_from_paper_momenta`],
//!   [`paper_momenta_from_state`]).
//!
//! **Where it fails.** At the poles of S² (`r = 0, πR`) and the origin of H²
//! the chart and the frame `E_φ` are singular: the mass matrix degenerates
//! like `sin²(r/R)` and accelerations grow like `1/sin(r/R)`. Every function
//! returns [`Error::OutsideChart`] at a singular point and
//! [`Error::Constraint`] (field `"mass matrix ∂²L/∂q̇²"`) when `M` is
//! numerically singular (condition number above [`MAX_MASS_CONDITION`]);
//! between the two, results are computed but lose about
//! `log₁₀ cond(M)` digits — the frame-bundle form has no such region.

mod body;
mod chart;
mod fibre;
pub(crate) mod series;
mod state;

pub use body::*;
pub use chart::*;
pub use fibre::*;
pub use state::*;

use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use num_dual::{Dual2, Dual2SVec64, Dual64, HyperDualSVec64};

use crate::error::finite;
use crate::potential::Scalar;
use crate::{Error, Result};

/// Largest 1-norm condition number of the mass matrix `∂²L/∂q̇²` accepted by
/// [`accelerations`] and [`velocities`]; beyond it fewer than about two
/// significant digits of `q̈` would remain.
pub const MAX_MASS_CONDITION: f64 = 1e14;

/// Relative residual above which [`from_ambient`] reports ambient velocities
/// that no chart velocity produces (not tangent, or not compatible with the
/// fibre).
pub const AMBIENT_RESIDUAL_TOLERANCE: f64 = 1e-9;

/// A Lagrangian system in `Q` generalised coordinates, written once over the
/// scalar type so that its derivatives come by automatic differentiation.
pub trait Lagrangian<const Q: usize> {
    /// Names of the generalised coordinates, in order.
    fn coordinate_names(&self) -> [&'static str; Q];
    /// `Ok` where the coordinates are regular, else a typed error.
    fn check_configuration(&self, q: &SVector<f64, Q>) -> Result<()>;
    /// `L(q, q̇)`. Must be a polynomial of degree ≤ 2 in `q̇` for
    /// [`velocities`] (true of every Lagrangian here).
    fn lagrangian<D: Scalar>(&self, q: &SVector<D, Q>, qdot: &SVector<D, Q>) -> D;
}

/// A system whose configuration is a point of an embedded manifold with `N`
/// frame vectors: the map `q ↦ (X, e)` into the ambient space.
pub trait AmbientMap<const Q: usize, const N: usize, const E: usize>: Lagrangian<Q> {
    /// The metric of the ambient space.
    fn ambient_metric(&self) -> SMatrix<f64, E, E>;
    /// Position `X(q)` and frame vectors `e_A(q)` (columns) in ambient
    /// components.
    fn ambient_configuration<D: Scalar>(&self, q: &SVector<D, Q>) -> (SVector<D, E>, SMatrix<D, E, N>);
    /// The generalised coordinates of an ambient configuration (one branch
    /// where several exist), with typed errors off the configuration space
    /// or at singular points of the coordinates.
    fn configuration_from_ambient(&self, position: &SVector<f64, E>, frame: &SMatrix<f64, E, N>) -> Result<SVector<f64, Q>>;
    /// The paper's frame field `E_A(x)` at the configuration `q` (columns,
    /// ambient components; orthonormal, tangent, of the frame bundles'
    /// orientation): the parallel frame of the states built by
    /// [`state_from_paper`], in which the internal configuration is `φ(ξ)`.
    fn reference_frame(&self, q: &SVector<f64, Q>) -> SMatrix<f64, E, N>;
}

/// `L` and its first and second derivatives at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LagrangianDerivatives<const Q: usize> {
    /// `L(q, q̇)`.
    pub lagrangian: f64,
    /// `p = ∂L/∂q̇`.
    pub momentum: SVector<f64, Q>,
    /// `∂L/∂q`.
    pub force: SVector<f64, Q>,
    /// `M = ∂²L/∂q̇∂q̇` (the mass matrix; `m·G_ij` in the paper's notation
    /// `T = (m/2) G_ij q̇^i q̇^j`).
    pub mass: SMatrix<f64, Q, Q>,
    /// `C_ij = ∂²L/∂q̇_i ∂q_j`.
    pub mixed: SMatrix<f64, Q, Q>,
}

fn check_state<L: Lagrangian<Q>, const Q: usize>(sys: &L, q: &SVector<f64, Q>, qdot: &SVector<f64, Q>) -> Result<()> {
    sys.check_configuration(q)?;
    finite("qdot", qdot.iter())
}

/// All first and second derivatives of `L` needed by the Euler–Lagrange
/// equations, exactly: one evaluation with hyper-dual numbers
/// (`ε₁` along `q̇`, `ε₂` along `q`) gives `∂L/∂q̇`, `∂L/∂q` and `C`; one
/// with second-order dual numbers along `q̇` gives `M`.
///
/// Errors: those of [`Lagrangian::check_configuration`];
/// [`Error::NotFinite`] (field `"qdot"`).
pub fn lagrangian_derivatives<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
) -> Result<LagrangianDerivatives<Q>> {
    check_state(sys, q, qdot)?;
    let (lagrangian, momentum, force, mixed) = num_dual::partial_hessian(
        |(v, x): (SVector<HyperDualSVec64<Q, Q>, Q>, SVector<HyperDualSVec64<Q, Q>, Q>)| sys.lagrangian(&x, &v),
        (qdot, q),
    );
    let qd2 = q.map(Dual2SVec64::<Q>::from_re);
    let (_, _, mass) = num_dual::hessian(|v: SVector<Dual2SVec64<Q>, Q>| sys.lagrangian(&qd2, &v), qdot);
    Ok(LagrangianDerivatives { lagrangian, momentum, force, mass, mixed })
}

/// Solves `M y = b` after checking the condition of `M`.
fn solve_mass<const Q: usize>(m: &SMatrix<f64, Q, Q>, b: &SVector<f64, Q>) -> Result<SVector<f64, Q>> {
    let singular = |cond: f64| Error::Constraint {
        field: "mass matrix ∂²L/∂q̇²",
        constraint: "non-singular: 1-norm condition number ≤ 1e14 (the chart or the fibre parametrisation is singular here)",
        defect: cond,
        tolerance: MAX_MASS_CONDITION,
    };
    let norm1 = |a: &SMatrix<f64, Q, Q>| a.column_iter().map(|c| c.iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
    // nalgebra's LU needs typenum-backed dimensions for generic `Q`; the
    // dynamic one costs an allocation, negligible next to the AD evaluation.
    let lu = DMatrix::from_column_slice(Q, Q, m.as_slice()).lu();
    let inv = lu.try_inverse().ok_or_else(|| singular(f64::INFINITY))?;
    let inv = SMatrix::<f64, Q, Q>::from_column_slice(inv.as_slice());
    let cond = norm1(m) * norm1(&inv);
    if cond.is_nan() || cond > MAX_MASS_CONDITION {
        return Err(singular(if cond.is_nan() { f64::INFINITY } else { cond }));
    }
    let y = lu.solve(&DVector::from_column_slice(b.as_slice())).ok_or_else(|| singular(f64::INFINITY))?;
    Ok(SVector::from_column_slice(y.as_slice()))
}

/// Euler–Lagrange accelerations `q̈ = M⁻¹(∂L/∂q − C q̇)`.
///
/// Errors: those of [`lagrangian_derivatives`]; [`Error::Constraint`]
/// (field `"mass matrix ∂²L/∂q̇²"`, `defect` = its condition number) when
/// `cond₁(M) >` [`MAX_MASS_CONDITION`].
pub fn accelerations<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
) -> Result<SVector<f64, Q>> {
    let d = lagrangian_derivatives(sys, q, qdot)?;
    solve_mass(&d.mass, &(d.force - d.mixed * qdot))
}

/// Conjugate momenta `p = ∂L/∂q̇` (first-order dual numbers).
///
/// Errors: those of [`lagrangian_derivatives`].
pub fn momenta<L: Lagrangian<Q>, const Q: usize>(sys: &L, q: &SVector<f64, Q>, qdot: &SVector<f64, Q>) -> Result<SVector<f64, Q>> {
    Ok(value_and_momenta(sys, q, qdot)?.1)
}

fn value_and_momenta<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
) -> Result<(f64, SVector<f64, Q>)> {
    check_state(sys, q, qdot)?;
    let qd = q.map(num_dual::DualSVec64::<Q>::from_re);
    Ok(num_dual::gradient(|v: SVector<num_dual::DualSVec64<Q>, Q>| sys.lagrangian(&qd, &v), qdot))
}

/// The energy `E = q̇·∂L/∂q̇ − L` (`= T + V` for the Lagrangians here).
///
/// Errors: those of [`lagrangian_derivatives`].
pub fn energy<L: Lagrangian<Q>, const Q: usize>(sys: &L, q: &SVector<f64, Q>, qdot: &SVector<f64, Q>) -> Result<f64> {
    let (l, p) = value_and_momenta(sys, q, qdot)?;
    Ok(p.dot(qdot) - l)
}

/// The inverse Legendre map: the velocities `q̇` with `∂L/∂q̇(q, q̇) = p`, by
/// Newton's method from `q̇ = 0` (exact after one step for a Lagrangian
/// quadratic in `q̇`; iterated to a relative residual of 1e-14, at most 8
/// steps).
///
/// Errors: those of [`Lagrangian::check_configuration`];
/// [`Error::NotFinite`] (field `"p"`); the mass-matrix error of
/// [`accelerations`]; [`Error::NoConvergence`] if the residual does not fall
/// (a Lagrangian not quadratic in `q̇`).
pub fn velocities<L: Lagrangian<Q>, const Q: usize>(sys: &L, q: &SVector<f64, Q>, p: &SVector<f64, Q>) -> Result<SVector<f64, Q>> {
    sys.check_configuration(q)?;
    finite("p", p.iter())?;
    const MAX_ITER: usize = 8;
    let qd2 = q.map(Dual2SVec64::<Q>::from_re);
    let mut v = SVector::<f64, Q>::zeros();
    let mut residual = f64::INFINITY;
    for _ in 0..MAX_ITER {
        let (_, grad, mass) = num_dual::hessian(|w: SVector<Dual2SVec64<Q>, Q>| sys.lagrangian(&qd2, &w), &v);
        let r = p - grad;
        let scale = p.amax().max(grad.amax()).max(f64::MIN_POSITIVE);
        residual = r.amax() / scale;
        if residual <= 1e-14 {
            return Ok(v);
        }
        v += solve_mass(&mass, &r)?;
    }
    Err(Error::NoConvergence { what: "inverse Legendre map q̇(p)", iterations: MAX_ITER, residual })
}

/// The Hamiltonian `H(q, p) = p·q̇ − L(q, q̇)` with `q̇ =` [`velocities`]`(q, p)`.
///
/// Errors: those of [`velocities`].
pub fn hamiltonian<L: Lagrangian<Q>, const Q: usize>(sys: &L, q: &SVector<f64, Q>, p: &SVector<f64, Q>) -> Result<f64> {
    let v = velocities(sys, q, p)?;
    Ok(p.dot(&v) - sys.lagrangian(q, &v))
}

/// Position, velocity, frame vectors and their rates in ambient components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmbientState<const N: usize, const E: usize> {
    /// The point `X`.
    pub position: SVector<f64, E>,
    /// Its velocity `dX/dt`.
    pub velocity: SVector<f64, E>,
    /// The body frame vectors `e_A` (columns; zero for a point).
    pub frame: SMatrix<f64, E, N>,
    /// Their ordinary time derivatives `de_A/dt` in the ambient space (whose
    /// tangential part is `De_A/Dt` and normal part `−II(Ẋ, e_A)`).
    pub frame_rate: SMatrix<f64, E, N>,
}

/// Second time derivatives along a trajectory, in ambient components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmbientAcceleration<const N: usize, const E: usize> {
    /// `d²X/dt²`.
    pub acceleration: SVector<f64, E>,
    /// `d²e_A/dt²` (columns).
    pub frame_acceleration: SMatrix<f64, E, N>,
}

/// The ambient data of the chart state `(q, q̇)`: `X`, `Ẋ`, `e`, `ė`, exactly
/// (one evaluation with dual numbers along `q̇`).
///
/// Errors: those of [`Lagrangian::check_configuration`];
/// [`Error::NotFinite`] (field `"qdot"`).
pub fn ambient_state<S: AmbientMap<Q, N, E>, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
) -> Result<AmbientState<N, E>> {
    check_state(sys, q, qdot)?;
    let qd = SVector::<Dual64, Q>::from_fn(|i, _| Dual64::new(q[i], qdot[i]));
    let (x, e) = sys.ambient_configuration(&qd);
    Ok(AmbientState {
        position: x.map(|v| v.re),
        velocity: x.map(|v| v.eps),
        frame: e.map(|v| v.re),
        frame_rate: e.map(|v| v.eps),
    })
}

/// `Ẍ` and `ë` along the trajectory through `(q, q̇)` with acceleration `q̈`
/// (e.g. from [`accelerations`]), exactly (second-order dual numbers along
/// `q + t q̇ + t²q̈/2`).
///
/// Errors: those of [`ambient_state`]; [`Error::NotFinite`] (field `"qddot"`).
pub fn ambient_acceleration<S: AmbientMap<Q, N, E>, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    q: &SVector<f64, Q>,
    qdot: &SVector<f64, Q>,
    qddot: &SVector<f64, Q>,
) -> Result<AmbientAcceleration<N, E>> {
    check_state(sys, q, qdot)?;
    finite("qddot", qddot.iter())?;
    let qd = SVector::<Dual2<f64>, Q>::from_fn(|i, _| Dual2::new(q[i], qdot[i], qddot[i]));
    let (x, e) = sys.ambient_configuration(&qd);
    Ok(AmbientAcceleration { acceleration: x.map(|v| v.v2), frame_acceleration: e.map(|v| v.v2) })
}

/// The chart state `(q, q̇)` of ambient data: `q` from
/// [`AmbientMap::configuration_from_ambient`], `q̇` by least squares from
/// `(Ẋ, ė) = (∂(X, e)/∂q) q̇` (Jacobian by dual numbers).
///
/// Errors: those of [`AmbientMap::configuration_from_ambient`];
/// [`Error::NotFinite`] (fields `"velocity"`, `"frame_rate"`);
/// [`Error::Constraint`] (field `"velocity, frame_rate"`) when the rates are
/// not those of any chart velocity (relative residual above
/// [`AMBIENT_RESIDUAL_TOLERANCE`]), or the Jacobian is rank-deficient (a
/// singular point of the coordinates).
pub fn from_ambient<S: AmbientMap<Q, N, E>, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    state: &AmbientState<N, E>,
) -> Result<(SVector<f64, Q>, SVector<f64, Q>)> {
    finite("velocity", state.velocity.iter())?;
    finite("frame_rate", state.frame_rate.iter())?;
    let q = sys.configuration_from_ambient(&state.position, &state.frame)?;
    sys.check_configuration(&q)?;
    let rows = E + E * N;
    let mut jac = DMatrix::<f64>::zeros(rows, Q);
    for k in 0..Q {
        let qd = SVector::<Dual64, Q>::from_fn(|i, _| Dual64::new(q[i], if i == k { 1.0 } else { 0.0 }));
        let (x, e) = sys.ambient_configuration(&qd);
        for i in 0..E {
            jac[(i, k)] = x[i].eps;
        }
        for (j, v) in e.iter().enumerate() {
            jac[(E + j, k)] = v.eps;
        }
    }
    let mut rhs = DVector::<f64>::zeros(rows);
    for i in 0..E {
        rhs[i] = state.velocity[i];
    }
    for (j, v) in state.frame_rate.iter().enumerate() {
        rhs[E + j] = *v;
    }
    // Householder QR (nalgebra's SVD solve lost 4 digits on well-conditioned
    // examples); the ratio of the diagonal entries of R estimates the
    // condition of the Jacobian from below and detects rank deficiency.
    let qr = jac.clone().qr();
    let r = qr.r();
    let diag: Vec<f64> = (0..Q).map(|i| r[(i, i)].abs()).collect();
    let (dmax, dmin) = (diag.iter().cloned().fold(0.0, f64::max), diag.iter().cloned().fold(f64::INFINITY, f64::min));
    let rank_defect = |d: f64| Error::Constraint {
        field: "velocity, frame_rate",
        constraint: "the coordinates are regular here (Jacobian of q ↦ (X, e) of full rank, condition ≤ 1e14)",
        defect: d,
        tolerance: MAX_MASS_CONDITION,
    };
    if dmin.is_nan() || dmin <= 0.0 || dmax / dmin > MAX_MASS_CONDITION {
        return Err(rank_defect(dmax / dmin));
    }
    let qdot = r.solve_upper_triangular(&(qr.q().transpose() * &rhs)).ok_or_else(|| rank_defect(f64::INFINITY))?;
    let residual = (&jac * &qdot - &rhs).norm() / rhs.norm().max(f64::MIN_POSITIVE);
    if residual.is_nan() || residual > AMBIENT_RESIDUAL_TOLERANCE {
        return Err(Error::Constraint {
            field: "velocity, frame_rate",
            constraint: "rates of a curve in the configuration space (velocity tangent, frame rate compatible with the fibre)",
            defect: residual,
            tolerance: AMBIENT_RESIDUAL_TOLERANCE,
        });
    }
    Ok((q, SVector::from_fn(|i, _| qdot[i])))
}
