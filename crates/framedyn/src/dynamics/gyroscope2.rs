//! The two-dimensional infinitesimal gyroscope on S², H², T² (paper §5,
//! (a92), (a135), (a138); SPEC §7). See [`Gyroscope2Model`] and the
//! derivation in [`gyroscope`](super::gyroscope).

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector1, Vector2, Vector3};

use super::gyroscope::signature_sign;
use super::point::{
    bundle_element_at, check_bundle_element, combine_defects, finite_defect, momentum_map_generator_check,
    rename_field, tangent_components, STATE_TOLERANCE,
};
use crate::body::{Gyroscope, Signature};
use crate::bundle::FrameBundle;
use crate::dynamics::split::{SplitDispatch, Splittable};
use crate::dynamics::{position_force, System};
use crate::error::finite;
use crate::lie::{LieGroup, Product, ProductAlgebra, Rn, So2};
use crate::potential::Potential;
use crate::{Error, Result};

/// State of a [`Gyroscope2Model`]: `((g, ρ), (u₁, u₂, s))` — the bundle element
/// `g` (point `x` and parallel frame `q`), the internal rotation
/// `ρ = U(α) ∈ SO(2)` of the body frame relative to `q` (`e = q·ρ`), the
/// velocity components `u` in `q` and the spin `s` (canonical, `s = σ I α̇`).
pub type Gyroscope2State<G> = Product<Product<G, So2>, Rn<3>>;

/// `ε = [[0, −1], [1, 0]]`, the rotation by +90° in the frame plane.
const EPS: Matrix2<f64> = Matrix2::new(0.0, -1.0, 1.0, 0.0);

/// The generator of rotations about the ambient z axis, `A = e_y e_xᵀ − e_x e_yᵀ`.
pub const Z_ROTATION: Matrix3<f64> = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);

/// An infinitesimal gyroscope (n = 2) of mass `m` and moment of inertia
/// `I = Tr J` on a two-dimensional manifold with a global frame bundle
/// (`FrameBundle<2, 3>`: S², H², T²), in a potential `V(x, e)`.
///
/// **State** [`Gyroscope2State`] `((g, ρ), (u₁, u₂, s))`: `e = q·ρ`,
/// `ρ = U(α) = [[cos α, −sin α], [sin α, cos α]]`, `ẋ = q u`, `s` the spin.
///
/// **Equations** (derived in [`gyroscope`](super::gyroscope); (a59), (b61)):
/// ```text
/// ġ = g · horizontal_lift(g, u)
/// m u̇ = K s ε u + F̂,        K = curvature_at(g),  ε = [[0, −1], [1, 0]]
/// α̇ = σ s / I               (ρ̇ = ρ·α̇ε)
/// ṡ = −∂V/∂α = −⟨G, ρε⟩,     G = qᵀ ∂V/∂e
/// ```
/// with `σ = +1` for (a52)/(a135), `σ = −1` for the Lorentz-type energy of
/// (a138). `s` is the canonical spin, `s = (S_σ)¹² = σ I α̇`: for `σ = +1` the
/// paper's `S¹²` (constant without torque, `= p_ψ`); for `σ = −1` it is still
/// `p_ψ` of (a143)/(a144), opposite to the kinematical `S¹²`, and the force
/// `K s ε u` keeps its form. The geometric force `K s ε u` has magnitude
/// `K|s||u|`, is perpendicular to `u` (no work) and vanishes where `K = 0`
/// (on T² along `θ = ±π/2`). `F̂_a = −H_a V` includes the frame term for
/// frame-dependent potentials (skipped, with the torque, when
/// [`Potential::uses_frame`] is false).
///
/// **Invariants**: energy `E = (m/2)|u|² + σ s²/(2I) + V`; the spin `s` when
/// `V` does not depend on the frame; the momentum map
/// `J_A = m⟨Ax, ẋ⟩_η + s⟨A q₁, q₂⟩_η` of every ambient isometry generator `A`
/// leaving `V` invariant ([`Gyroscope2Model::momentum_map`]); in particular
/// the paper's `p_φ` ([`Gyroscope2Model::p_phi`]).
///
/// **The S² gyroscope is the symmetric top** (b93)–(d94): `Q_e = [e₁ | e₂ | n]`
/// (`n = x/R`) moves in SO(3) with body angular velocity `Ω`,
/// `T = (mR²/2)(Ω₁² + Ω₂²) + (σI/2)Ω₃²`; on H², `Λ_e = [e₁ | e₂ | n] ∈ SO⁺(1,2)`
/// is the Lorentz top (a142)/(b142).
#[derive(Debug, Clone)]
pub struct Gyroscope2Model<B, P> {
    bundle: B,
    body: Gyroscope<2>,
    potential: P,
    metric: Matrix3<f64>,
    inv_mass: f64,
    moment: f64,
    sigma: f64,
    /// `σ / I`.
    rate: f64,
}

impl<B, P> Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3>,
    P: Potential<2, 3>,
{
    /// The gyroscope `body` (mass, `I = Tr J`, signature) on `bundle` in the
    /// potential `potential` (the parameters themselves are validated by
    /// [`Gyroscope::new`] and the manifold's constructor).
    ///
    /// Errors: [`Error::InvalidParameter`] (field `"I"`) if `1/I` is not
    /// finite (a `J` with subnormal entries).
    pub fn new(bundle: B, body: Gyroscope<2>, potential: P) -> Result<Self> {
        let moment = body.trace_inertia();
        let sigma = signature_sign(body.signature());
        if !(sigma / moment).is_finite() {
            return Err(Error::InvalidParameter {
                field: "I",
                value: moment,
                allowed: "I = Tr J finite and > 0 with a finite reciprocal",
            });
        }
        Ok(Self {
            metric: bundle.ambient_metric(),
            inv_mass: 1.0 / body.mass(),
            moment,
            sigma,
            rate: sigma / moment,
            bundle,
            body,
            potential,
        })
    }

    /// The manifold (and its frame bundle).
    pub fn bundle(&self) -> &B {
        &self.bundle
    }

    /// `1/m` (stored: the integrators multiply by it).
    #[inline]
    pub fn inv_mass(&self) -> f64 {
        self.inv_mass
    }

    /// The body parameters.
    pub fn body(&self) -> &Gyroscope<2> {
        &self.body
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The moment of inertia `I = Tr J`.
    pub fn moment_of_inertia(&self) -> f64 {
        self.moment
    }

    /// The signature of the internal kinetic energy.
    pub fn signature(&self) -> Signature {
        self.body.signature()
    }

    /// The spin of a body turning with angular velocity `omega` relative to a
    /// parallel frame (`omega = α̇`, the paper's `ω = ψ̇ + ω_dr` of (a91)):
    /// `s = σ I ω`.
    pub fn spin_for_angular_velocity(&self, omega: f64) -> f64 {
        self.sigma * self.moment * omega
    }

    /// The state at the embedded point `p` with ambient velocity `v`, body
    /// frame `e` (columns `e₁, e₂`, ambient components, orthonormal in the
    /// ambient metric, positively oriented as the bundle's frames) and spin
    /// `spin`. The parallel frame starts as `q = e` (`ρ = 1`).
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] naming `"p"` (not
    /// on the manifold), `"e"` (not tangent, orthonormal, positively oriented;
    /// tolerance of [`FrameBundle::from_frame`]), `"v"` (not tangent,
    /// [`STATE_TOLERANCE`]), `"spin"` (not finite).
    pub fn state(
        &self,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        e: &Matrix3x2<f64>,
        spin: f64,
    ) -> Result<Gyroscope2State<B::Group>> {
        finite("spin", [spin].iter())?;
        finite("p", p.iter())?;
        let g = self.bundle.from_frame(p, e).map_err(|err| rename_field(err, "q", "e"))?;
        let u = tangent_components(&self.bundle, &g, v, "v")?;
        Ok(Product(Product(g, So2::identity()), Rn(Vector3::new(u[0], u[1], spin))))
    }

    /// The state at `p` with velocity `v` and spin `spin`, the body frame
    /// being the one of [`bundle_element_at`] rotated by the angle `alpha`
    /// (for a position-only potential the body's orientation is irrelevant
    /// to the motion of `x`). Errors as [`Gyroscope2Model::state`], and
    /// `"alpha"` if not finite.
    pub fn state_at(
        &self,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        alpha: f64,
        spin: f64,
    ) -> Result<Gyroscope2State<B::Group>> {
        finite("spin", [spin].iter())?;
        finite("alpha", [alpha].iter())?;
        let g = bundle_element_at(&self.bundle, p)?;
        let u = tangent_components(&self.bundle, &g, v, "v")?;
        let rho = So2::exp(&Vector1::new(alpha));
        Ok(Product(Product(g, rho), Rn(Vector3::new(u[0], u[1], spin))))
    }

    /// The state from its parts, validated: `g` within [`STATE_TOLERANCE`] of
    /// the bundle, `rho` a rotation to [`So2::TOLERANCE`], everything finite.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] naming `"g"`,
    /// `"rho"`, `"u"`, `"spin"`.
    pub fn state_from_parts(
        &self,
        g: &B::Group,
        rho: &So2,
        u: &Vector2<f64>,
        spin: f64,
    ) -> Result<Gyroscope2State<B::Group>> {
        check_bundle_element(&self.bundle, g)?;
        let rho = So2::new(rho.cos(), rho.sin()).map_err(|err| rename_field(err, "So2 (cos, sin)", "rho"))?;
        finite("u", u.iter())?;
        finite("spin", [spin].iter())?;
        Ok(Product(Product(*g, rho), Rn(Vector3::new(u[0], u[1], spin))))
    }

    /// Validates a state (e.g. after integration): finite, `g` and `ρ`
    /// within [`STATE_TOLERANCE`] of their groups.
    ///
    /// Errors: [`Error::NotFinite`] (field `"state"`) or [`Error::Constraint`]
    /// (field `"state"`, the defect of [`System::defect`]).
    pub fn check_state(&self, y: &Gyroscope2State<B::Group>) -> Result<()> {
        let d = self.defect(y);
        if d.is_nan() {
            return Err(Error::NotFinite { field: "state" });
        }
        if d > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "state",
                constraint: "g in the frame bundle and ρ in SO(2)",
                defect: d,
                tolerance: STATE_TOLERANCE,
            });
        }
        Ok(())
    }

    /// The position `x` (ambient components).
    pub fn position(&self, y: &Gyroscope2State<B::Group>) -> Vector3<f64> {
        self.bundle.position(&y.0 .0)
    }

    /// The velocity `ẋ = u₁q₁ + u₂q₂` (ambient components).
    pub fn velocity(&self, y: &Gyroscope2State<B::Group>) -> Vector3<f64> {
        self.bundle.frame_vectors(&y.0 .0) * self.velocity_components(y)
    }

    /// The velocity components `u` in the parallel frame `q`.
    pub fn velocity_components(&self, y: &Gyroscope2State<B::Group>) -> Vector2<f64> {
        y.1 .0.fixed_rows::<2>(0).into_owned()
    }

    /// The parallel frame `q` (columns, ambient components).
    pub fn parallel_frame(&self, y: &Gyroscope2State<B::Group>) -> Matrix3x2<f64> {
        self.bundle.frame_vectors(&y.0 .0)
    }

    /// The body frame `e = q·ρ` (columns, ambient components).
    pub fn body_frame(&self, y: &Gyroscope2State<B::Group>) -> Matrix3x2<f64> {
        self.bundle.frame_vectors(&y.0 .0) * y.0 .1.matrix()
    }

    /// The angle `α ∈ (−π, π]` of the body frame relative to the parallel frame.
    pub fn internal_angle(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        y.0 .1.angle()
    }

    /// The spin `s` (canonical: `σ I α̇`; the paper's `p_ψ`).
    pub fn spin(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        y.1 .0[2]
    }

    /// The angular velocity `α̇ = σ s / I` of the body relative to a parallel
    /// frame (the paper's `ω` of (a91)).
    pub fn angular_velocity(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        self.rate * y.1 .0[2]
    }

    /// The translational kinetic energy `(m/2)|u|²`.
    pub fn translational_energy(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        0.5 * self.body.mass() * self.velocity_components(y).norm_squared()
    }

    /// The internal kinetic energy `σ·(I/2)α̇² = σ s²/(2I)` (negative for the
    /// Lorentz-type model (a138)).
    pub fn internal_energy(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        0.5 * self.rate * y.1 .0[2].powi(2)
    }

    /// The potential energy `V(x, e)`.
    pub fn potential_energy(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        let x = self.position(y);
        self.potential.value::<f64>(&x, &self.body_frame(y), &self.metric)
    }

    /// The spin–curvature (geometric) force `K s ε u` of (a59), frame components.
    pub fn geometric_force(&self, y: &Gyroscope2State<B::Group>) -> Vector2<f64> {
        let k = self.bundle.curvature_at(&y.0 .0);
        EPS * self.velocity_components(y) * (k * y.1 .0[2])
    }

    /// The power `u·F_geom` of the geometric force: zero (the force only
    /// bends the path, after (a57)). Evaluated, not assumed, as a diagnostic.
    pub fn geometric_power(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        self.velocity_components(y).dot(&self.geometric_force(y))
    }

    /// The horizontal force `F̂` (frame components) and the torque
    /// `−∂V/∂α` of the potential.
    #[inline(always)]
    pub fn potential_forces(&self, y: &Gyroscope2State<B::Group>) -> (Vector2<f64>, f64) {
        self.forces(&y.0 .0, &y.0 .1)
    }

    /// The momentum map (Noether charge) of the ambient isometries `exp(tA)`:
    /// `J_A = m⟨A x, ẋ⟩_η + s⟨A q₁, q₂⟩_η` (derivation in
    /// [`gyroscope`](super::gyroscope)). Conserved when `exp(tA)` maps the
    /// manifold to itself and leaves `V` invariant.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (field
    /// `"generator"`) unless `Aᵀη + ηA = 0`.
    pub fn momentum_map(&self, y: &Gyroscope2State<B::Group>, generator: &Matrix3<f64>) -> Result<f64> {
        momentum_map_generator_check(&self.metric, generator)?;
        Ok(self.momentum_map_unchecked(y, generator))
    }

    fn momentum_map_unchecked(&self, y: &Gyroscope2State<B::Group>, a: &Matrix3<f64>) -> f64 {
        let g = &y.0 .0;
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let u = self.velocity_components(y);
        let eta_a = self.metric * a;
        let (q1, q2) = (q.column(0), q.column(1));
        let translational = self.body.mass() * (q * u).dot(&(eta_a * x));
        let spin = y.1 .0[2] * q2.dot(&(eta_a * q1));
        translational + spin
    }

    /// The paper's `p_φ`: the momentum map of rotations about the ambient z
    /// axis ([`Z_ROTATION`]), a symmetry of S², H² and T² and of every
    /// axially symmetric potential. On S² `p_φ = mR² sin²ϑ φ̇ + s cos ϑ`, on
    /// H² `mR² sh²ϑ φ̇ + s ch ϑ`, on T² `m(L + R cos θ)² φ̇ − s sin θ`
    /// (the sign from the orientation of `(E_θ, E_φ)`, SPEC §8).
    pub fn p_phi(&self, y: &Gyroscope2State<B::Group>) -> f64 {
        self.momentum_map_unchecked(y, &Z_ROTATION)
    }

    /// `(F̂, −∂V/∂α)` at `(g, ρ)`.
    #[inline(always)]
    fn forces(&self, g: &B::Group, rho: &So2) -> (Vector2<f64>, f64) {
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let rm = rho.matrix();
        let e = q * rm;
        let grad = self.potential.gradient(&x, &e, &self.metric);
        let mut f = position_force(&q, &grad.dx);
        // Asked of the potential, not cached: a constant for most potential
        // types, so for a `V(x)` this branch and with it every use of the
        // body angle ρ fold away (its exponential at every stage included).
        if !self.potential.uses_frame() {
            return (f, 0.0);
        }
        // Frame term of F̂_a = −H_a V: the body frame transported along q_a.
        for a in 0..2 {
            let xi = self.bundle.horizontal_lift(g, &Vector2::ith(a, 1.0));
            let (_, dq) = self.bundle.frame_velocity(g, &xi);
            f[a] -= grad.de.component_mul(&(dq * rm)).sum();
        }
        // −∂V/∂α = −Σ G_{cb} (ρε)_{cb},  G = qᵀ ∂V/∂e.
        let gi = q.transpose() * grad.de;
        let torque = -gi.component_mul(&(rm * EPS)).sum();
        (f, torque)
    }
}

impl<B, P> System for Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3>,
    P: Potential<2, 3>,
{
    type State = Gyroscope2State<B::Group>;

    /// `((horizontal_lift(g, u), σ s/I), ((K s ε u + F̂)/m, −∂V/∂α))`.
    #[inline(always)]
    fn vector_field(&self, _t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        let (g, rho) = (&y.0 .0, &y.0 .1);
        let w = &y.1 .0;
        let u = Vector2::new(w[0], w[1]);
        let s = w[2];
        let xi = self.bundle.horizontal_lift(g, &u);
        let ks = self.bundle.curvature_at(g) * s;
        let (f, torque) = self.forces(g, rho);
        let acc = Vector2::new(f[0] - ks * u[1], f[1] + ks * u[0]) * self.inv_mass;
        ProductAlgebra(ProductAlgebra(xi, Vector1::new(self.rate * s)), Vector3::new(acc[0], acc[1], torque))
    }

    /// The derivative along `((η, δα), (δu, δs))` (`ρ ↦ ρ·exp(δα ε)`):
    /// `D_g lift(u)[η] + lift(δu)`, `σ δs/I`, the derivative of the
    /// acceleration with `δ(Ks) = (D_g K[η]) s + K δs`, and of the torque
    /// `−⟨∂V/∂ρ, ρε⟩` ([`force_derivative`](super::force_derivative)).
    fn tangent_field(&self, t: f64, y: &Self::State, xi: &<Self::State as LieGroup>::Algebra) -> Option<super::FieldAndDerivative<Self::State>> {
        if !self.potential.second_derivatives() {
            return None;
        }
        let (g, rho) = (&y.0 .0, &y.0 .1);
        let w = &y.1 .0;
        let (u, s) = (Vector2::new(w[0], w[1]), w[2]);
        let (eta, dalpha) = (&xi.0 .0, xi.0 .1[0]);
        let dw = &xi.1;
        let (du, ds) = (Vector2::new(dw[0], dw[1]), dw[2]);
        let rm = rho.matrix();
        let drm = rm * EPS * dalpha;
        let d = super::force_derivative(&self.bundle, &self.potential, &self.metric, g, &rm, eta, &drm);
        let k = self.bundle.curvature_at(g);
        let dks = self.bundle.curvature_derivative(g, eta) * s + k * ds;
        let ks = k * s;
        let dacc = Vector2::new(d.d_force[0] - dks * u[1] - ks * du[1], d.d_force[1] + dks * u[0] + ks * du[0]) * self.inv_mass;
        let dtorque = if self.potential.uses_frame() { -(d.d_internal.component_mul(&(rm * EPS)).sum() + d.internal.component_mul(&(drm * EPS)).sum()) } else { 0.0 };
        let dlift = self.bundle.horizontal_lift(g, &du) + self.bundle.lift_derivative(g, &u, eta);
        Some((self.vector_field(t, y), ProductAlgebra(ProductAlgebra(dlift, Vector1::new(self.rate * ds)), Vector3::new(dacc[0], dacc[1], dtorque))))
    }

    /// `E = (m/2)|u|² + σ s²/(2I) + V(x, e)`.
    fn energy(&self, y: &Self::State) -> f64 {
        self.translational_energy(y) + self.internal_energy(y) + self.potential_energy(y)
    }

    /// The larger of [`FrameBundle::bundle_defect`] and the SO(2) defect of
    /// `ρ`; `NaN` if the state is not finite.
    fn defect(&self, y: &Self::State) -> f64 {
        combine_defects(&[
            self.bundle.bundle_defect(&y.0 .0),
            finite_defect(self.bundle.position(&y.0 .0).iter()),
            y.0 .1.constraint_defect(),
            finite_defect(y.1 .0.iter()),
            finite_defect([y.0 .1.cos(), y.0 .1.sin()].iter()),
        ])
    }

    /// `q ↦ qk`, `ρ ↦ kᵀρ`, `u ↦ kᵀu`, the spin unchanged: with `w = ε`,
    /// `(vertical(g, ε), −1, −ε·u, 0)`.
    fn gauge(&self, y: &Self::State) -> Vec<<Self::State as LieGroup>::Algebra> {
        let u = -(EPS * Vector2::new(y.1 .0[0], y.1 .0[1]));
        vec![ProductAlgebra(ProductAlgebra(self.bundle.vertical(&y.0 .0, &EPS), Vector1::new(-1.0)), Vector3::new(u[0], u[1], 0.0))]
    }
}


// -- splitting ---------------------------------------------------------------

/// The kick and the exact free flow of the n = 2 gyroscope (the drift
/// derivation is in [`split`](super::split)); exact on S² and H² (both
/// signatures).
impl<B, P> Splittable for Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3>,
    P: Potential<2, 3>,
{
    /// `u ← u + hF̂/m`, `s ← s − h ∂V/∂α`.
    #[inline(always)]
    fn kick(&self, y: &Self::State, h: f64) -> Self::State {
        let (f, torque) = self.potential_forces(y);
        let w = y.1 .0;
        let a = f * (h * self.inv_mass());
        Product(y.0, Rn(Vector3::new(w[0] + a[0], w[1] + a[1], w[2] + h * torque)))
    }

    /// `g ← g₀ exp(h(ξ(u₀) + R)) exp(−hR)`, `R = vertical((Ks/m)ε)`
    /// (the formula of [`free_translation`](crate::bundle::free_translation), its second factor by
    /// [`FrameBundle::rotate_frame`]); `u ← U(hKs/m) u₀` with the
    /// same `sin_cos`; `ρ ← ρ₀ U(hσs/I)`; `s` unchanged.
    #[inline(always)]
    fn drift(&self, y: &Self::State, h: f64) -> Self::State {
        let (g, rho) = (&y.0 .0, &y.0 .1);
        let w = y.1 .0;
        let (u, s) = (Vector2::new(w[0], w[1]), w[2]);
        let b = self.bundle();
        let c = b.curvature_at(g) * s * self.inv_mass();
        // vertical(cε) = c·vertical(ε) (linear): the product waits for `c` only.
        let xi = b.horizontal_lift(g, &u) + b.vertical(g, &EPS) * c;
        let (sn, cs) = (h * c).sin_cos();
        let g1 = b.rotate_frame(&g.compose(&B::Group::exp(&(xi * h))), cs, -sn);
        let u1 = Vector2::new(cs * u[0] - sn * u[1], sn * u[0] + cs * u[1]);
        let rho1 = rho.compose(&So2::exp(&Vector1::new(h * self.angular_velocity(y))));
        Product(Product(g1, rho1), Rn(Vector3::new(u1[0], u1[1], s)))
    }

    fn has_free_flow(&self) -> bool {
        self.bundle().exact_free_flow()
    }

    fn drift_exps(&self) -> u32 {
        3
    }
}

impl<B, P> SplitDispatch for Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3>,
    P: Potential<2, 3>,
{
    type Split = Self;
    #[inline(always)]
    fn as_splittable(&self) -> Option<&Self> {
        self.has_free_flow().then_some(self)
    }
}
