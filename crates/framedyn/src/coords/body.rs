//! The Lagrangians `L = T − V` of (a52) in the paper's coordinate ("E-gauge")
//! form, for a structureless point and for bodies with an internal frame.

use nalgebra::{SMatrix, SVector};

use super::chart::ChartGeometry;
use super::fibre::{Fibre, GlEntries, PlaneRotation, PolarDecomposition, RotationVector, TwoPolar};
use super::{AmbientMap, Lagrangian};
use crate::body::{check_inertia, Affine, Gyroscope, Point, Signature};
use crate::error::{finite, positive};
use crate::potential::{Potential, Scalar};
use crate::{Error, Result};

/// A structureless point of mass `m` in the paper's chart:
/// `L(x, ẋ) = (m/2) g_ij(x) ẋ^i ẋ^j − V(X(x))` ((a52) without the internal
/// term; (a88) on S²). Generalised coordinates `q = x`.
///
/// The potential is evaluated at the embedded point `X(x)` with the **zero**
/// frame (a point carries none), so it should not use the frame.
#[derive(Debug, Clone)]
pub struct PointLagrangian<C, P, const N: usize, const E: usize> {
    chart: C,
    potential: P,
    mass: f64,
}

impl<C: ChartGeometry<N, E>, P: Potential<N, E>, const N: usize, const E: usize> PointLagrangian<C, P, N, E> {
    /// The point `body` moving on `chart` in the potential `potential`.
    pub fn new(chart: C, body: &Point, potential: P) -> Self {
        Self { chart, potential, mass: body.mass() }
    }
    /// The chart.
    pub fn chart(&self) -> &C {
        &self.chart
    }
    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
}

impl<C: ChartGeometry<N, E>, P: Potential<N, E>, const N: usize, const E: usize> Lagrangian<N>
    for PointLagrangian<C, P, N, E>
{
    fn coordinate_names(&self) -> [&'static str; N] {
        self.chart.coordinate_names()
    }
    fn check_configuration(&self, q: &SVector<f64, N>) -> Result<()> {
        self.chart.check_chart(q)
    }
    fn lagrangian<D: Scalar>(&self, q: &SVector<D, N>, qdot: &SVector<D, N>) -> D {
        let g = self.chart.metric(q);
        let t = (g * qdot).dot(qdot) * (0.5 * self.mass);
        let v = self.potential.value(&self.chart.embed(q), &SMatrix::zeros(), &self.chart.ambient_metric());
        t - v
    }
}

impl<C: ChartGeometry<N, E>, P: Potential<N, E>, const N: usize, const E: usize> AmbientMap<N, N, E>
    for PointLagrangian<C, P, N, E>
{
    fn ambient_metric(&self) -> SMatrix<f64, E, E> {
        self.chart.ambient_metric()
    }
    /// `(X(x), 0)`: the frame of a point is zero.
    fn ambient_configuration<D: Scalar>(&self, q: &SVector<D, N>) -> (SVector<D, E>, SMatrix<D, E, N>) {
        (self.chart.embed(q), SMatrix::zeros())
    }
    /// The chart point of `position` (the frame is ignored).
    fn configuration_from_ambient(&self, position: &SVector<f64, E>, _frame: &SMatrix<f64, E, N>) -> Result<SVector<f64, N>> {
        self.chart.chart_point(position)
    }
    /// `E(x)` in ambient components.
    fn reference_frame(&self, q: &SVector<f64, N>) -> SMatrix<f64, E, N> {
        self.chart.ambient_frame(q)
    }
}

/// Relative defect of a frame reconstructed from its components.
pub(crate) const FRAME_TANGENCY_TOLERANCE: f64 = 1e-9;

/// A body with an internal frame `e = E(x)·φ(ξ)` in the paper's coordinate
/// form (§4, §5, §6): generalised coordinates `q = (x, ξ)` — the `N` chart
/// coordinates of the position, then the `K` coordinates of the fibre
/// parametrisation `F` — with `Q = N + K` (checked at compile time).
///
/// Lagrangian, from (a52) with the co-moving velocities of (a74):
///
/// `L = (m/2) g_ij ẋ^i ẋ^j + (σ/2) Tr(X J Xᵀ) − V(X(x), e)`,
///
/// - `X = φ̇ + Γ(E)(V̂)·φ` are the `E`-components of the covariant
///   derivatives `De_A/Dt = E_F X^F_A` (so `X = φ Ω̂` with Ω̂ of (a74)),
///   `V̂ = E⁻¹(x) ẋ` the frame components of the velocity and
///   `Γ(E)(V̂)^F_D = Γ^F_{DC} V̂^C`;
/// - `½ Tr(X J Xᵀ) = ½ g(De_A/Dt, De_B/Dt) J^{AB}` because `E` is orthonormal;
/// - `σ = +1`, or `−1` for the indefinite "Lorentz-type" energy (a138)
///   ([`Signature::Lorentz`]);
/// - `V` is the potential evaluated at the embedded point with the ambient
///   components of the body frame `e_A = Σ_B (∂X/∂x^i E^i_B) φ^B_A`.
///
/// Nothing is specialised by hand: the paper's printed forms — (a92) on S²,
/// (a135)/(a138) on H², the torus energy of §5.3, (a83)/(a84) for affine
/// bodies, the S³ energy before (a184) — are consequences, checked by the
/// test suite (`tests/suite/coords.rs`), which also documents the printed
/// formulas that are wrong (SPEC §8).
#[derive(Debug, Clone)]
pub struct FrameLagrangian<C, F, P, const N: usize, const E: usize, const K: usize, const Q: usize> {
    chart: C,
    fibre: F,
    potential: P,
    mass: f64,
    inertia: SMatrix<f64, N, N>,
    signature: Signature,
}

/// A two-dimensional gyroscope, `e = E(x)·U(ψ)`, `q = (x¹, x², ψ)` (§5).
pub type Gyroscope2<C, P> = FrameLagrangian<C, PlaneRotation, P, 2, 3, 1, 3>;
/// A two-dimensional affine body by the entries of `φ`, `q = (x¹, x², φ₁₁, φ₁₂, φ₂₁, φ₂₂)`.
pub type Affine2<C, P> = FrameLagrangian<C, GlEntries, P, 2, 3, 4, 6>;
/// A two-dimensional affine body in two-polar variables, `q = (x¹, x², α, β, λ, μ)`.
pub type TwoPolarAffine2<C, P> = FrameLagrangian<C, TwoPolar, P, 2, 3, 4, 6>;
/// A two-dimensional affine body in polar variables, `q = (x¹, x², ψ, ξ, η, ζ)`.
pub type PolarAffine2<C, P> = FrameLagrangian<C, PolarDecomposition, P, 2, 3, 4, 6>;
/// A gyroscope on S³ (§6), `e = ˡE(R)(r̄)·exp([κ]×)`, `q = (r̄, κ)`.
pub type Gyroscope3<P> = FrameLagrangian<super::chart::Sphere3Chart, RotationVector, P, 3, 4, 3, 6>;

/// Co-moving kinematic quantities of a [`FrameLagrangian`] at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoMoving<const N: usize> {
    /// `V̂ = E⁻¹ ẋ`: the components of the velocity in the frame field `E`
    /// (the paper's `V̂` of (a74) when `φ = 1`).
    pub velocity: SVector<f64, N>,
    /// `Γ(E)(V̂)`: the rotation rate of the frame field `E` along the path
    /// (the drive term; `φ⁻¹Γ(E)(V̂)φ` is `Ω̂_dr` of (a81)).
    pub drive: SMatrix<f64, N, N>,
    /// `φ`.
    pub phi: SMatrix<f64, N, N>,
    /// `φ̇`.
    pub phi_dot: SMatrix<f64, N, N>,
    /// `X = φ̇ + Γ(E)(V̂)φ`: column `A` holds the `E`-components of `De_A/Dt`.
    /// In a parallel-transported frame that coincides with `E` at this
    /// instant, the internal configuration `ρ` has `ρ = φ`, `ρ̇ = X`.
    pub covariant_rate: SMatrix<f64, N, N>,
    /// `Ω̂ = φ⁻¹ X` (a74): the co-moving affine velocity.
    pub omega_hat: SMatrix<f64, N, N>,
    /// The spin `S = σ(K − Kᵀ)`, `K = φ J Xᵀ` (`K^{ab} = e^a_K (De^b_L/Dt)
    /// J^{KL}`, §1 of SPEC, (a59)), in `E`-components, `σ` the signature.
    /// For n = 2, `S¹²` equals `p_ψ` (gyroscope) or `p_α` (two-polar).
    pub spin: SMatrix<f64, N, N>,
}

impl<C, F, P, const N: usize, const E: usize, const K: usize, const Q: usize> FrameLagrangian<C, F, P, N, E, K, Q>
where
    C: ChartGeometry<N, E>,
    F: Fibre<N, K>,
    P: Potential<N, E>,
{
    /// A body of mass `mass` (finite, > 0) and inertia `inertia` (symmetric
    /// positive definite, [`check_inertia`]) whose frame is parametrised by
    /// `fibre`, with kinetic-energy signature `signature`.
    pub fn new(
        chart: C,
        fibre: F,
        mass: f64,
        inertia: SMatrix<f64, N, N>,
        signature: Signature,
        potential: P,
    ) -> Result<Self> {
        const { assert!(Q == N + K, "FrameLagrangian: Q must equal N + K") };
        Ok(Self { chart, fibre, potential, mass: positive("mass", mass)?, inertia: check_inertia(&inertia)?, signature })
    }

    /// The gyroscope `body` (its mass, inertia and signature) with a rigid
    /// fibre parametrisation (compile-time check of [`Fibre::RIGID`]).
    pub fn gyroscope(chart: C, fibre: F, body: &Gyroscope<N>, potential: P) -> Self {
        const { assert!(Q == N + K && F::RIGID, "FrameLagrangian::gyroscope: needs Q = N + K and a rigid fibre") };
        Self { chart, fibre, potential, mass: body.mass(), inertia: *body.inertia(), signature: body.signature() }
    }

    /// The affine body `body` with a non-rigid (GL⁺) fibre parametrisation.
    pub fn affine(chart: C, fibre: F, body: &Affine<N>, potential: P) -> Self {
        const { assert!(Q == N + K && !F::RIGID, "FrameLagrangian::affine: needs Q = N + K and a GL+ fibre") };
        Self { chart, fibre, potential, mass: body.mass(), inertia: *body.inertia(), signature: Signature::Riemannian }
    }

    /// The chart.
    pub fn chart(&self) -> &C {
        &self.chart
    }
    /// The fibre parametrisation.
    pub fn fibre(&self) -> &F {
        &self.fibre
    }
    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// The inertia `J`.
    pub fn inertia(&self) -> &SMatrix<f64, N, N> {
        &self.inertia
    }
    /// The signature of the internal kinetic energy.
    pub fn signature(&self) -> Signature {
        self.signature
    }

    fn sign(&self) -> f64 {
        match self.signature {
            Signature::Riemannian => 1.0,
            Signature::Lorentz => -1.0,
        }
    }

    fn split<D: Scalar>(q: &SVector<D, Q>) -> (SVector<D, N>, SVector<D, K>) {
        (SVector::from_fn(|i, _| q[i]), SVector::from_fn(|k, _| q[N + k]))
    }

    /// `(V̂, Γ(E)(V̂), φ, φ̇, X)` at any scalar type.
    fn kinematics<D: Scalar>(&self, q: &SVector<D, Q>, qdot: &SVector<D, Q>) -> Kin<D, N> {
        let (x, xi) = Self::split(q);
        let (xd, xid) = Self::split(qdot);
        let w = self.chart.coframe(&x) * xd;
        let drive = self.chart.connection_matrix(&x, &w);
        let (phi, phi_dot) = self.fibre.matrix_and_rate(&xi, &xid);
        let rate = phi_dot + drive * phi;
        Kin { x, xd, w, drive, phi, phi_dot, rate }
    }

    /// The co-moving quantities at the state `(q, q̇)`; fails with a typed
    /// error outside the chart or the fibre parametrisation, for non-finite
    /// `q̇`, or if `φ` is singular.
    pub fn comoving(&self, q: &SVector<f64, Q>, qdot: &SVector<f64, Q>) -> Result<CoMoving<N>> {
        self.check_configuration(q)?;
        finite("qdot", qdot.iter())?;
        let k = self.kinematics(q, qdot);
        let inv = k.phi.try_inverse().ok_or(Error::Constraint {
            field: "phi",
            constraint: "invertible internal configuration",
            defect: 0.0,
            tolerance: 0.0,
        })?;
        let kk = k.phi * self.inertia * k.rate.transpose();
        Ok(CoMoving {
            velocity: k.w,
            drive: k.drive,
            phi: k.phi,
            phi_dot: k.phi_dot,
            covariant_rate: k.rate,
            omega_hat: inv * k.rate,
            spin: (kk - kk.transpose()) * self.sign(),
        })
    }

    /// The internal configuration `φ(ξ)` at `q` (no checks).
    pub fn internal_matrix(&self, q: &SVector<f64, Q>) -> SMatrix<f64, N, N> {
        self.fibre.matrix(&Self::split(q).1)
    }
}

struct Kin<D: Scalar, const N: usize> {
    x: SVector<D, N>,
    xd: SVector<D, N>,
    w: SVector<D, N>,
    drive: SMatrix<D, N, N>,
    phi: SMatrix<D, N, N>,
    phi_dot: SMatrix<D, N, N>,
    rate: SMatrix<D, N, N>,
}

impl<C, F, P, const N: usize, const E: usize, const K: usize, const Q: usize> Lagrangian<Q>
    for FrameLagrangian<C, F, P, N, E, K, Q>
where
    C: ChartGeometry<N, E>,
    F: Fibre<N, K>,
    P: Potential<N, E>,
{
    /// The chart's names, then the fibre's.
    fn coordinate_names(&self) -> [&'static str; Q] {
        let (a, b) = (self.chart.coordinate_names(), self.fibre.coordinate_names());
        std::array::from_fn(|i| if i < N { a[i] } else { b[i - N] })
    }
    fn check_configuration(&self, q: &SVector<f64, Q>) -> Result<()> {
        let (x, xi) = Self::split(q);
        self.chart.check_chart(&x)?;
        self.fibre.check(&xi)
    }
    fn lagrangian<D: Scalar>(&self, q: &SVector<D, Q>, qdot: &SVector<D, Q>) -> D {
        let k = self.kinematics(q, qdot);
        let g = self.chart.metric(&k.x);
        let t_tr = (g * k.xd).dot(&k.xd) * (0.5 * self.mass);
        let mut t_int = D::from(0.0);
        for f in 0..N {
            for a in 0..N {
                for b in 0..N {
                    let j = self.inertia[(a, b)];
                    if j != 0.0 {
                        t_int += k.rate[(f, a)] * k.rate[(f, b)] * j;
                    }
                }
            }
        }
        // A potential that ignores the frame gets the zero frame (saves the
        // frame field and the embedding Jacobian at every evaluation).
        let e = if self.potential.uses_frame() { self.chart.ambient_frame(&k.x) * k.phi } else { SMatrix::zeros() };
        let v = self.potential.value(&self.chart.embed(&k.x), &e, &self.chart.ambient_metric());
        t_tr + t_int * (0.5 * self.sign()) - v
    }
}

impl<C, F, P, const N: usize, const E: usize, const K: usize, const Q: usize> AmbientMap<Q, N, E>
    for FrameLagrangian<C, F, P, N, E, K, Q>
where
    C: ChartGeometry<N, E>,
    F: Fibre<N, K>,
    P: Potential<N, E>,
{
    fn ambient_metric(&self) -> SMatrix<f64, E, E> {
        self.chart.ambient_metric()
    }
    /// `(X(x), E_amb(x)·φ(ξ))`.
    fn ambient_configuration<D: Scalar>(&self, q: &SVector<D, Q>) -> (SVector<D, E>, SMatrix<D, E, N>) {
        let (x, xi) = Self::split(q);
        (self.chart.embed(&x), self.chart.ambient_frame(&x) * self.fibre.matrix(&xi))
    }
    /// `x` from [`ChartGeometry::chart_point`], `φ^A_B = ⟨E_A, e_B⟩` (ambient
    /// metric), `ξ` from [`Fibre::coordinates`]. Fails with
    /// [`Error::Constraint`] (field `"frame"`) if the frame is not tangent
    /// (relative defect of `E·φ − e` above 1e-9).
    fn configuration_from_ambient(&self, position: &SVector<f64, E>, frame: &SMatrix<f64, E, N>) -> Result<SVector<f64, Q>> {
        finite("frame", frame.iter())?;
        let x = self.chart.chart_point(position)?;
        let ea = self.chart.ambient_frame(&x);
        let phi = ea.transpose() * self.chart.ambient_metric() * frame;
        let scale = frame.norm().max(f64::MIN_POSITIVE);
        let d = (ea * phi - frame).norm() / scale;
        if d.is_nan() || d > FRAME_TANGENCY_TOLERANCE {
            return Err(Error::Constraint {
                field: "frame",
                constraint: "frame vectors tangent to the manifold at the point",
                defect: d,
                tolerance: FRAME_TANGENCY_TOLERANCE,
            });
        }
        let xi = self.fibre.coordinates(&phi)?;
        Ok(SVector::from_fn(|i, _| if i < N { x[i] } else { xi[i - N] }))
    }
    /// `E(x)` in ambient components.
    fn reference_frame(&self, q: &SVector<f64, Q>) -> SMatrix<f64, E, N> {
        self.chart.ambient_frame(&Self::split(q).0)
    }
}
