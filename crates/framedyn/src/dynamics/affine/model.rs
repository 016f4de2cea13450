//! The affine body model: its state, its parameters, the state constructors
//! and checks, the kinematics and forces, the energies, and the equations of
//! motion (the [`System`] impl). Derivation in the [module documentation](super).

use nalgebra::{SMatrix, SVector};

use super::{check_regular, inverse, trace_of_product, Inertia, InternalConstraint, Kinematics, Mat, Unconstrained};
use crate::bundle::FrameBundle;
use crate::dynamics::{horizontal_force, internal_gradient, System};
use crate::error::finite;
use crate::lie::{LieGroup, Product, ProductAlgebra, Rn};
use crate::potential::Potential;
use crate::{Error, Result};

/// Relative tolerance of the state checks ([`AffineBodyModel::state`],
/// [`AffineBodyModel::check_state`]): bundle and fibre group constraints,
/// tangency of `ρ̇`.
pub const STATE_TOLERANCE: f64 = 1e-9;

/// The state of an (constrained) affine body on the frame bundle `B`:
/// `((g, ρ), (u, P(K)))` — see the [module documentation](super). Access:
/// `y.0 .0` = `g`, `y.0 .1` = `ρ` (fibre element), `y.1 .0 .0` = `u`,
/// `y.1 .1` = the momentum (`P(K)`, read as a matrix with
/// [`AffineBodyModel::momentum_matrix`]).
pub type BodyState<B, C, const N: usize, const E: usize> = Product<
    Product<<B as FrameBundle<N, E>>::Group, <C as InternalConstraint<N>>::Fibre>,
    Product<Rn<N>, <C as InternalConstraint<N>>::Momentum>,
>;

/// The left-trivialised velocity of a [`BodyState`].
pub type BodyVelocity<B, C, const N: usize, const E: usize> = <BodyState<B, C, N, E> as LieGroup>::Algebra;

/// An infinitesimal affinely-rigid body (or a constrained one, by `C`) of mass
/// `m` and inertia `J` on the frame bundle `B`, in the potential `V`.
///
/// Equations (see the [module documentation](super) for the derivation from
/// (a52), (a59), (d59), (c59)):
///
/// ```text
/// ġ = g·lift(u),   ρ̇ = ρΩ̂,   m u̇ = −K S u + F̂,   d/dt P(K) = P(ρ̇Jρ̇ᵀ + N)
/// ```
///
/// with `K` the sectional curvature at `g`, `S = P(K) − P(K)ᵀ` the spin,
/// `F̂_a = −H_aV`, `N = −ρ(∂V/∂ρ)ᵀ`. Use the aliases [`AffineModel`],
/// [`IncompressibleModel`](super::constrained::IncompressibleModel),
/// [`WeylModel`](super::constrained::WeylModel),
/// [`DilatationModel`](super::constrained::DilatationModel).
#[derive(Debug, Clone)]
pub struct AffineBodyModel<B, V, C, const N: usize, const E: usize> {
    pub(super) bundle: B,
    potential: V,
    constraint: C,
    pub(super) mass: f64,
    inv_mass: f64,
    pub(super) inertia: Inertia<N>,
    pub(super) metric: SMatrix<f64, E, E>,
    frame_dependent: bool,
}

/// The free (unconstrained) affinely-rigid body of §4: `ρ ∈ GL⁺(N)`,
/// `n + n²` degrees of freedom.
pub type AffineModel<B, V, const N: usize, const E: usize> = AffineBodyModel<B, V, Unconstrained, N, E>;

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N> + Default,
{
    /// The body `body` (mass and inertia, validated by its constructor) on
    /// the bundle `bundle` in the potential `potential`, with the default
    /// constraint data (for [`PureDilatation`](super::constrained::PureDilatation):
    /// the reference shape `ρ₀ = I`).
    pub fn new(bundle: B, body: C::Body, potential: V) -> Result<Self> {
        Self::with_constraint(bundle, body, potential, C::default())
    }
}

impl<B, V, C, const N: usize, const E: usize> AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    /// As [`Self::new`] with explicit constraint data. Fails only if the
    /// body's parameters do not validate (mass finite and > 0, field `"mass"`;
    /// `J` symmetric positive definite, field `"J"`).
    pub fn with_constraint(bundle: B, body: C::Body, potential: V, constraint: C) -> Result<Self> {
        let (mass, j) = C::body_parameters(&body);
        let mass = crate::error::positive("mass", mass)?;
        let inertia = Inertia::new(&j)?;
        let metric = bundle.ambient_metric();
        let frame_dependent = potential.uses_frame();
        Ok(Self { bundle, potential, constraint, mass, inv_mass: 1.0 / mass, inertia, metric, frame_dependent })
    }

    /// The same model with other constraint data of the same kind.
    pub(super) fn replace_constraint(mut self, constraint: C) -> Self {
        self.constraint = constraint;
        self
    }

    /// The frame bundle.
    pub fn bundle(&self) -> &B {
        &self.bundle
    }
    /// The potential.
    pub fn potential(&self) -> &V {
        &self.potential
    }
    /// The constraint data.
    pub fn constraint(&self) -> &C {
        &self.constraint
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// The inertia `J` and its derived data.
    pub fn inertia(&self) -> &Inertia<N> {
        &self.inertia
    }

    // -- states ---------------------------------------------------------------

    /// The state at bundle element `g` with internal configuration `ρ`,
    /// velocity `u` (parallel-frame components) and internal velocity `ρ̇`.
    ///
    /// For a constrained body `ρ̇` is checked and the stored momentum is the
    /// projection `P(ρJρ̇ᵀ)`; `ρ` is stored as the fibre element (e.g. for SL
    /// rescaled to `det ρ = 1` exactly).
    ///
    /// Errors: [`Error::NotFinite`] (fields `"g"`, `"rho"`, `"u"`,
    /// `"rho_dot"`); [`Error::Constraint`] field `"g"` if
    /// [`FrameBundle::bundle_defect`] exceeds [`STATE_TOLERANCE`];
    /// [`Error::InvalidParameter`] field `"det(rho)"` unless `det ρ > 0`;
    /// [`Error::Constraint`] field `"rho"` for a collapsed `ρ` (see
    /// [`COLLAPSE_TOLERANCE`](super::COLLAPSE_TOLERANCE)) or one violating the fibre's configuration
    /// constraint (`det ρ = 1`, `ρ` conformal, `ρ ∝ ρ₀`, relative 1e-9);
    /// [`Error::Constraint`] field `"rho_dot"` unless `ρ⁻¹ρ̇` lies in the
    /// fibre's algebra (relative 1e-9).
    pub fn state(
        &self,
        g: &B::Group,
        rho: &Mat<N>,
        u: &SVector<f64, N>,
        rho_dot: &Mat<N>,
    ) -> Result<BodyState<B, C, N, E>> {
        self.check_bundle_element(g)?;
        finite("rho", rho.iter())?;
        check_regular(rho)?;
        let f = self.constraint.fibre(rho)?;
        finite("u", u.iter())?;
        finite("rho_dot", rho_dot.iter())?;
        let rho_s = self.constraint.rho(&f);
        let omega = inverse(&rho_s).unwrap_or_else(|| Mat::<N>::from_element(f64::NAN)) * rho_dot;
        let scale = omega.amax();
        let defect = if scale > 0.0 { self.constraint.velocity_defect(&omega) / scale } else { 0.0 };
        if defect.is_nan() || defect > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "rho_dot",
                constraint: C::TANGENCY,
                defect,
                tolerance: STATE_TOLERANCE,
            });
        }
        let k = rho_s * self.inertia.j * rho_dot.transpose();
        Ok(Product(Product(*g, f), Product(Rn(*u), self.constraint.momentum(&k))))
    }

    /// The state from the fibre element `f`, the velocity `u` and the
    /// hypermomentum `k = ρJρ̇ᵀ` (projected onto the fibre's algebra; for the
    /// unconstrained body `k` itself). Errors as [`Self::state`] (field
    /// `"momentum"` for a non-finite `k`), and [`Error::Constraint`] field
    /// `"rho"` if the group constraint of `f` is violated.
    pub fn state_from_momentum(
        &self,
        g: &B::Group,
        f: &C::Fibre,
        u: &SVector<f64, N>,
        k: &Mat<N>,
    ) -> Result<BodyState<B, C, N, E>> {
        self.check_bundle_element(g)?;
        let rho = self.constraint.rho(f);
        finite("rho", rho.iter())?;
        check_regular(&rho)?;
        self.check_fibre_group(f)?;
        finite("u", u.iter())?;
        finite("momentum", k.iter())?;
        Ok(Product(Product(*g, *f), Product(Rn(*u), self.constraint.momentum(k))))
    }

    fn check_bundle_element(&self, g: &B::Group) -> Result<()> {
        let p = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        finite("g", p.iter().chain(q.iter()))?;
        let d = self.bundle.bundle_defect(g);
        if d <= STATE_TOLERANCE {
            Ok(())
        } else {
            Err(Error::Constraint {
                field: "g",
                constraint: "valid frame-bundle element (group constraint)",
                defect: d,
                tolerance: STATE_TOLERANCE,
            })
        }
    }

    fn check_fibre_group(&self, f: &C::Fibre) -> Result<()> {
        let d = f.constraint_defect();
        if d <= STATE_TOLERANCE {
            Ok(())
        } else {
            Err(Error::Constraint { field: "rho", constraint: C::CONFIGURATION, defect: d, tolerance: STATE_TOLERANCE })
        }
    }

    /// `Ok` if `y` is a valid state: everything finite, `g` a bundle element
    /// and the fibre element on its group (to [`STATE_TOLERANCE`]), `det ρ > 0`
    /// and `ρ` not collapsed ([`COLLAPSE_TOLERANCE`](super::COLLAPSE_TOLERANCE)). The typed errors are
    /// those of [`Self::state`]; collapse is
    /// `Error::Constraint { field: "rho", .. }` with the measured
    /// `max(σ_max, 1)/σ_min` as the defect.
    pub fn check_state(&self, y: &BodyState<B, C, N, E>) -> Result<()> {
        self.check_bundle_element(&y.0 .0)?;
        let rho = self.constraint.rho(&y.0 .1);
        finite("rho", rho.iter())?;
        check_regular(&rho)?;
        self.check_fibre_group(&y.0 .1)?;
        finite("u", y.1 .0 .0.iter())?;
        finite("momentum", self.constraint.momentum_matrix(&y.1 .1).iter())?;
        Ok(())
    }

    // -- kinematics -------------------------------------------------------------

    /// The projected hypermomentum `P(K)` of the state as a matrix.
    #[inline]
    pub fn momentum_matrix(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.constraint.momentum_matrix(&y.1 .1)
    }
    /// `ρ`, `ρ̇` and `Ω̂ = ρ⁻¹ρ̇` at `y`.
    #[inline]
    pub fn kinematics(&self, y: &BodyState<B, C, N, E>) -> Kinematics<C::Fibre, N> {
        self.constraint.kinematics(&y.0 .1, &self.momentum_matrix(y), &self.inertia)
    }
    /// `ρ`: components of the body frame in the parallel frame, `e = qρ`.
    pub fn rho(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.constraint.rho(&y.0 .1)
    }
    /// `ρ̇`.
    pub fn rho_dot(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        self.kinematics(y).rho_dot
    }
    /// The position `x` (ambient coordinates).
    pub fn position(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, E> {
        self.bundle.position(&y.0 .0)
    }
    /// The velocity `ẋ = Σ u_a q_a` (ambient coordinates).
    pub fn velocity(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, E> {
        self.bundle.frame_vectors(&y.0 .0) * y.1 .0 .0
    }
    /// The body frame `e = qρ` (columns `e_A`, ambient coordinates).
    pub fn body_frame(&self, y: &BodyState<B, C, N, E>) -> SMatrix<f64, E, N> {
        self.bundle.frame_vectors(&y.0 .0) * self.rho(y)
    }
    /// The covariant rate of the body frame, `De/Dt = qρ̇ = eΩ̂` (column `A`
    /// is `De_A/Dt`, ambient coordinates, the layout of [`Self::body_frame`]):
    /// the paper's internal velocity `V^i_A = De^i_A/Dt` of §2, the velocity
    /// of the internal kinetic energy `½⟨De_A/Dt, De_B/Dt⟩J^{AB}` of (a52),
    /// `De_A/Dt = e_B Ω̂^B_A` (before (a74)). The frame `q` is
    /// parallel-transported, `Dq_a/Dt = 0`, so only `ρ` contributes.
    ///
    /// It is the tangential part of the ordinary derivative of the embedded
    /// frame. `de/dt = q̇ρ + qρ̇`, and `q̇` is normal
    /// ([`FrameBundle::frame_velocity`] of the horizontal lift), so (Gauss
    /// formula)
    ///
    /// ```text
    /// de_A/dt = De_A/Dt − ε II(ẋ, e_A) n,      II(X, Y) = ⟨dn(X), Y⟩,   ε = ⟨n, n⟩
    /// ```
    ///
    /// with `n` the unit normal, `II` the second fundamental form and `⟨·,·⟩`
    /// the ambient metric (`ε = −1` on H², `+1` otherwise). On a sphere or
    /// hyperboloid (`n = x/R`) the normal part is `−⟨ẋ, e_A⟩ x/⟨x, x⟩`.
    pub fn frame_rate(&self, y: &BodyState<B, C, N, E>) -> SMatrix<f64, E, N> {
        self.bundle.frame_vectors(&y.0 .0) * self.rho_dot(y)
    }

    // -- forces -------------------------------------------------------------------

    /// `(F̂, ∂V/∂ρ)` at `g` for the internal configuration `rho`.
    #[inline]
    fn forces(&self, g: &B::Group, rho: &Mat<N>) -> (SVector<f64, N>, Mat<N>) {
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let grad = self.potential.gradient(&x, &(q * rho), &self.metric);
        let f = horizontal_force(&self.bundle, g, rho, &grad, self.frame_dependent);
        let v_rho = if self.frame_dependent { internal_gradient(&q, &grad) } else { Mat::<N>::zeros() };
        (f, v_rho)
    }

    /// The horizontal force `F̂_a = −H_aV` (parallel-frame components).
    pub fn horizontal_force(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, N> {
        self.forces(&y.0 .0, &self.rho(y)).0
    }

    /// The internal force (torque) `N = −ρ(∂V/∂ρ)ᵀ` of (d59), parallel-frame
    /// components.
    pub fn torque(&self, y: &BodyState<B, C, N, E>) -> Mat<N> {
        let rho = self.rho(y);
        -(rho * self.forces(&y.0 .0, &rho).1.transpose())
    }

    /// The spin–curvature force of (a59), `½ S^k_l R^l_k{}^a{}_j u^j = −K S u`
    /// (SPEC §7).
    pub fn geometric_force(&self, y: &BodyState<B, C, N, E>) -> SVector<f64, N> {
        -(self.spin(y) * y.1 .0 .0) * self.bundle.curvature_at(&y.0 .0)
    }

    /// The power `u · (−K S u)` of the geometric force: zero (S skew), up to
    /// round-off.
    pub fn geometric_power(&self, y: &BodyState<B, C, N, E>) -> f64 {
        y.1 .0 .0.dot(&self.geometric_force(y))
    }

    // -- invariants -----------------------------------------------------------------

    /// Translational kinetic energy `(m/2)|u|²`.
    pub fn translational_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        0.5 * self.mass * y.1 .0 .0.norm_squared()
    }
    /// Internal kinetic energy `½ tr(ρ̇Jρ̇ᵀ)`.
    pub fn internal_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let rd = self.rho_dot(y);
        0.5 * trace_of_product(&(rd * self.inertia.j), &rd.transpose())
    }
    /// Potential energy `V(x, e)`.
    pub fn potential_energy(&self, y: &BodyState<B, C, N, E>) -> f64 {
        let g = &y.0 .0;
        let e = self.bundle.frame_vectors(g) * self.rho(y);
        self.potential.value(&self.bundle.position(g), &e, &self.metric)
    }
}

impl<B, V, C, const N: usize, const E: usize> System for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    type State = BodyState<B, C, N, E>;

    /// `(ġ, ρ̇, u̇, d P(K)/dt)` left-trivialised:
    /// `(lift(u), Ω̂, (−K S u + F̂)/m, P(sym(ρ̇Jρ̇ᵀ) − ρ(∂V/∂ρ)ᵀ))`.
    #[inline]
    fn vector_field(&self, _t: f64, y: &Self::State) -> BodyVelocity<B, C, N, E> {
        let g = &y.0 .0;
        let u = y.1 .0 .0;
        let k = self.constraint.momentum_matrix(&y.1 .1);
        let kin = self.constraint.kinematics(&y.0 .1, &k, &self.inertia);
        let (f_hat, v_rho) = self.forces(g, &kin.rho);
        let curvature = self.bundle.curvature_at(g);
        let spin = k - k.transpose();
        let u_dot = (f_hat - spin * u * curvature) * self.inv_mass;
        let a = kin.rho_dot * self.inertia.j * kin.rho_dot.transpose();
        let k_dot = (a + a.transpose()) * 0.5 - kin.rho * v_rho.transpose();
        ProductAlgebra(
            ProductAlgebra(self.bundle.horizontal_lift(g, &u), kin.xi),
            ProductAlgebra(u_dot, self.constraint.project(&k_dot)),
        )
    }

    /// The derivative along `((η, X), (δu, δm))`: the lift's as for a point,
    /// `δΩ̂` from [`InternalConstraint::kinematics_derivative`], and the
    /// derivatives of `u̇ = (F̂ − K_G A u)/m` (`A = P(K) − P(K)ᵀ`) and of
    /// `P(sym(ρ̇Jρ̇ᵀ) − ρ(∂V/∂ρ)ᵀ)` ([`force_derivative`](crate::dynamics::force_derivative)).
    fn tangent_field(&self, t: f64, y: &Self::State, xi: &BodyVelocity<B, C, N, E>) -> Option<crate::dynamics::FieldAndDerivative<Self::State>> {
        if !self.potential.second_derivatives() {
            return None;
        }
        let g = &y.0 .0;
        let u = y.1 .0 .0;
        let (eta, dfib) = (&xi.0 .0, &xi.0 .1);
        let (du, dmom) = (xi.1 .0, &xi.1 .1);
        let k = self.constraint.momentum_matrix(&y.1 .1);
        let dk = self.constraint.momentum_direction(dmom);
        let kin = self.constraint.kinematics(&y.0 .1, &k, &self.inertia);
        let dkin = self.constraint.kinematics_derivative(&y.0 .1, &k, &self.inertia, &kin, dfib, &dk);
        let d = crate::dynamics::force_derivative(&self.bundle, &self.potential, &self.metric, g, &kin.rho, eta, &dkin.rho);
        let curvature = self.bundle.curvature_at(g);
        let d_curvature = self.bundle.curvature_derivative(g, eta);
        let (spin, dspin) = (k - k.transpose(), dk - dk.transpose());
        let du_dot = (d.d_force - (dspin * u + spin * du) * curvature - spin * u * d_curvature) * self.inv_mass;
        let da = dkin.rho_dot * self.inertia.j * kin.rho_dot.transpose() + kin.rho_dot * self.inertia.j * dkin.rho_dot.transpose();
        let dk_dot = (da + da.transpose()) * 0.5 - dkin.rho * d.internal.transpose() - kin.rho * d.d_internal.transpose();
        let dlift = self.bundle.horizontal_lift(g, &du) + self.bundle.lift_derivative(g, &u, eta);
        Some((self.vector_field(t, y), ProductAlgebra(ProductAlgebra(dlift, dkin.xi), ProductAlgebra(du_dot, self.constraint.project(&dk_dot)))))
    }

    /// `(m/2)|u|² + ½tr(ρ̇Jρ̇ᵀ) + V(x, qρ)`.
    fn energy(&self, y: &Self::State) -> f64 {
        self.translational_energy(y) + self.internal_energy(y) + self.potential_energy(y)
    }

    /// The largest of the bundle defect, the fibre group's defect (≥ 1 for
    /// `det ρ ≤ 0` on GL⁺), the momentum's distance from its subspace; `+∞`
    /// for non-finite entries.
    fn defect(&self, y: &Self::State) -> f64 {
        let parts = [
            self.bundle.bundle_defect(&y.0 .0),
            y.0 .1.constraint_defect(),
            y.1 .1.constraint_defect(),
            if y.1 .0 .0.iter().all(|v| v.is_finite()) { 0.0 } else { f64::INFINITY },
        ];
        if parts.iter().any(|d| d.is_nan()) {
            f64::INFINITY
        } else {
            parts.iter().fold(0.0, |a, &b| a.max(b))
        }
    }

    /// `q ↦ qk`, `ρ ↦ kᵀρ`, `u ↦ kᵀu`, `P(K) ↦ kᵀP(K)k` (`K = ρJρ̇ᵀ` has
    /// parallel-frame components); none for a fibre that is not closed
    /// under rotations ([`InternalConstraint::frame_gauge`]).
    fn gauge(&self, y: &Self::State) -> Vec<BodyVelocity<B, C, N, E>> {
        let p = self.constraint.momentum_matrix(&y.1 .1);
        let mut out = Vec::new();
        for w in crate::dynamics::skew_basis::<N>() {
            let Some(fibre) = self.constraint.frame_gauge(&y.0 .1, &w) else {
                return Vec::new();
            };
            let g = self.bundle.vertical(&y.0 .0, &w);
            let u = -(w * y.1 .0 .0);
            out.push(ProductAlgebra(ProductAlgebra(g, fibre), ProductAlgebra(u, self.constraint.project(&(p * w - w * p)))));
        }
        out
    }
}

/// Affine bodies have no exact free flow on a curved manifold: the
/// splitting methods refuse them.
impl<B, V, C, const N: usize, const E: usize> crate::dynamics::SplitDispatch for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    type Split = crate::dynamics::NoSplit<BodyState<B, C, N, E>>;
    fn as_splittable(&self) -> Option<&Self::Split> {
        None
    }
}
