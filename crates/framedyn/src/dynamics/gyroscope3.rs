//! The three-dimensional infinitesimal gyroscope on S³ (paper §6,
//! (a184)–(a186); SPEC §7). See [`Gyroscope3Model`] and the derivation in
//! [`gyroscope`](super::gyroscope).

use nalgebra::{Matrix3, Matrix4, Matrix4x3, SymmetricEigen, Vector3, Vector4, Vector6};

use super::gyroscope::signature_sign;
use super::point::{
    bundle_element_at, check_bundle_element, combine_defects, finite_defect, momentum_map_generator_check,
    rename_field, tangent_components, STATE_TOLERANCE,
};
use crate::body::{Gyroscope, Signature};
use crate::bundle::{free_translation, FrameBundle};
use crate::dynamics::split::{SplitDispatch, Splittable, YOSHIDA6};
use crate::dynamics::{position_force, System};
use crate::error::finite;
use crate::lie::{LieGroup, Product, ProductAlgebra, Rn, So3};
use crate::manifold::Sphere3;
use crate::potential::Potential;
use crate::{Error, Result};

/// State of a [`Gyroscope3Model`]: `((g, ρ), (u, π))` — the bundle element `g`
/// (point `x`, parallel frame `q`), the internal rotation `ρ ∈ SO(3)` of the
/// body frame relative to `q` (`e = q·ρ`), the velocity components `u ∈ ℝ³`
/// in `q` (stored first) and the spin vector `π ∈ ℝ³` in `q`-components
/// (stored last).
pub type Gyroscope3State<G> = Product<Product<G, So3>, Rn<6>>;

/// An infinitesimal gyroscope (n = 3) with mass `m` and any symmetric
/// positive-definite inertia `J` on a three-dimensional manifold of constant
/// curvature with a global frame bundle (`FrameBundle<3, 4>`: S³), in a
/// potential `V(x, e)`.
///
/// **State** [`Gyroscope3State`] `((g, ρ), (u, π))`: `e = q·ρ`, `ẋ = q u`,
/// `π = −vee(S_σ) = σ ρ 𝕀 W` the canonical spin as an axial vector in the
/// parallel frame (`S_σ = σ(K − Kᵀ)`, `K = ρJρ̇ᵀ`, the paper's spin of (a59)),
/// `W` the body angular velocity (`ρ̇ = ρŴ`), `𝕀 = (tr J)·1 − J` the inertia
/// operator (`Ŵ ↦ JŴ + ŴJ`). For the paper's isotropic body `J = (I/2)δ`,
/// `𝕀 = I` (SPEC §7). The spin is carried in the parallel frame because there
/// it is constant in free motion (`DS/Dt = Ṡ`).
///
/// **Equations** (derived in [`gyroscope`](super::gyroscope); (a59), (b61)/(b62)):
/// ```text
/// ġ = g · horizontal_lift(g, u)
/// m u̇ = −K S_σ u + F̂ = K π × u + F̂        (K = curvature_at(g); SPEC §7)
/// ρ̇ = ρ Ŵ,   W = σ 𝕀⁻¹ ρᵀ π                 (rigid body, inertia operator 𝕀)
/// π̇ = τ = −vee(Gρᵀ − ρGᵀ),   G = qᵀ ∂V/∂e  (b61: Ṡ = N − Nᵀ, N = −ρGᵀ)
/// ```
/// In the body frame `M = ρᵀπ` obeys Euler's equations `Ṁ = M × W + ρᵀτ`.
/// `σ = −1` ([`Signature::Lorentz`]) is the indefinite energy of (a138)
/// carried over to n = 3 (`J → −J`).
///
/// **Invariants**: energy `E = (m/2)|u|² + ½ π·(σρ𝕀ρᵀ)⁻¹π + V`; `|π|` when
/// `V` does not depend on the frame; the momentum map
/// `J_A = m⟨Ax, ẋ⟩ + vee(qᵀAq)·π` of every `A ∈ so(4)` leaving `V` invariant
/// ([`Gyroscope3Model::momentum_map`]); on S³ the quantities of
/// (a184)–(a186) ([`Gyroscope3Model::paper_momenta`]).
#[derive(Debug, Clone)]
pub struct Gyroscope3Model<B, P> {
    bundle: B,
    body: Gyroscope<3>,
    potential: P,
    metric: Matrix4<f64>,
    inv_mass: f64,
    sigma: f64,
    /// `𝕀 = (tr J)·1 − J`.
    inertia_operator: Matrix3<f64>,
    /// `σ 𝕀⁻¹`.
    inv_inertia: Matrix3<f64>,
    frame_dependent: bool,
}

impl<B, P> Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4>,
    P: Potential<3, 4>,
{
    /// The gyroscope `body` (mass, `J`, signature) on `bundle` in `potential`.
    ///
    /// Errors: [`Error::Constraint`] (field `"J"`) if the inertia operator
    /// `(tr J)·1 − J` has no finite inverse (possible only for a `J` whose
    /// entries are at the limits of the floating-point range; for every
    /// positive-definite `J` it is positive definite, its eigenvalues being
    /// the sums of pairs of eigenvalues of `J`).
    pub fn new(bundle: B, body: Gyroscope<3>, potential: P) -> Result<Self> {
        let j = body.inertia();
        let op = Matrix3::identity() * j.trace() - j;
        let inv = op.cholesky().map(|c| c.inverse()).filter(|m| m.iter().all(|v| v.is_finite())).ok_or(
            Error::Constraint {
                field: "J",
                constraint: "inertia operator (tr J)·1 − J positive definite with a finite inverse",
                defect: f64::INFINITY,
                tolerance: 0.0,
            },
        )?;
        let sigma = signature_sign(body.signature());
        Ok(Self {
            metric: bundle.ambient_metric(),
            inv_mass: 1.0 / body.mass(),
            sigma,
            inertia_operator: op,
            inv_inertia: inv * sigma,
            frame_dependent: potential.uses_frame(),
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
    pub fn body(&self) -> &Gyroscope<3> {
        &self.body
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The signature of the internal kinetic energy.
    pub fn signature(&self) -> Signature {
        self.body.signature()
    }

    /// The inertia operator `𝕀 = (tr J)·1 − J` (body frame): `T_int = ½ W·𝕀W`.
    pub fn inertia_operator(&self) -> &Matrix3<f64> {
        &self.inertia_operator
    }

    /// The spin (body components) of a body with body angular velocity
    /// `omega` relative to a parallel frame: `σ 𝕀 W`.
    pub fn spin_for_angular_velocity(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        self.inertia_operator * omega * self.sigma
    }

    /// The state at the embedded point `p` with ambient velocity `v`, body
    /// frame `e` (columns `e₁, e₂, e₃`, orthonormal, tangent, positively
    /// oriented: `det[p/R | e] = +1`) and spin `spin` in components of `e`
    /// (for a body angular velocity `W` use
    /// [`Gyroscope3Model::spin_for_angular_velocity`]). The parallel frame
    /// starts as `q = e` (`ρ = 1`).
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] naming `"p"`,
    /// `"e"` (tolerance of [`FrameBundle::from_frame`]), `"v"` (not tangent,
    /// [`STATE_TOLERANCE`]), `"spin"`.
    pub fn state(
        &self,
        p: &Vector4<f64>,
        v: &Vector4<f64>,
        e: &Matrix4x3<f64>,
        spin: &Vector3<f64>,
    ) -> Result<Gyroscope3State<B::Group>> {
        finite("spin", spin.iter())?;
        let g = self.bundle.from_frame(p, e).map_err(|err| rename_field(err, "q", "e"))?;
        let u = tangent_components(&self.bundle, &g, v, "v")?;
        Ok(Product(Product(g, So3::identity()), Rn(join(&u, spin))))
    }

    /// The state at `p` with velocity `v`, the body frame being the one of
    /// [`bundle_element_at`] rotated by `rho`, and the spin `spin` in body
    /// components. Errors as [`Gyroscope3Model::state`] and `"rho"`.
    pub fn state_at(
        &self,
        p: &Vector4<f64>,
        v: &Vector4<f64>,
        rho: &So3,
        spin: &Vector3<f64>,
    ) -> Result<Gyroscope3State<B::Group>> {
        finite("spin", spin.iter())?;
        let rho = So3::new(*rho.matrix()).map_err(|err| rename_field(err, "So3 matrix", "rho"))?;
        let g = bundle_element_at(&self.bundle, p)?;
        let u = tangent_components(&self.bundle, &g, v, "v")?;
        Ok(Product(Product(g, rho), Rn(join(&u, &(rho.matrix() * spin)))))
    }

    /// The state from its parts (`pi` in `q`-components), validated: `g`
    /// within [`STATE_TOLERANCE`] of the bundle, `rho` a rotation to
    /// [`So3::TOLERANCE`], everything finite.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] naming `"g"`,
    /// `"rho"`, `"u"`, `"spin"`.
    pub fn state_from_parts(
        &self,
        g: &B::Group,
        rho: &So3,
        u: &Vector3<f64>,
        pi: &Vector3<f64>,
    ) -> Result<Gyroscope3State<B::Group>> {
        check_bundle_element(&self.bundle, g)?;
        let rho = So3::new(*rho.matrix()).map_err(|err| rename_field(err, "So3 matrix", "rho"))?;
        finite("u", u.iter())?;
        finite("spin", pi.iter())?;
        Ok(Product(Product(*g, rho), Rn(join(u, pi))))
    }

    /// Validates a state (e.g. after integration): finite, `g` and `ρ`
    /// within [`STATE_TOLERANCE`] of their groups.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (field `"state"`).
    pub fn check_state(&self, y: &Gyroscope3State<B::Group>) -> Result<()> {
        let d = self.defect(y);
        if d.is_nan() {
            return Err(Error::NotFinite { field: "state" });
        }
        if d > STATE_TOLERANCE {
            return Err(Error::Constraint {
                field: "state",
                constraint: "g in the frame bundle and ρ in SO(3)",
                defect: d,
                tolerance: STATE_TOLERANCE,
            });
        }
        Ok(())
    }

    /// The position `x` (ambient components).
    pub fn position(&self, y: &Gyroscope3State<B::Group>) -> Vector4<f64> {
        self.bundle.position(&y.0 .0)
    }

    /// The velocity `ẋ = q u` (ambient components).
    pub fn velocity(&self, y: &Gyroscope3State<B::Group>) -> Vector4<f64> {
        self.bundle.frame_vectors(&y.0 .0) * self.velocity_components(y)
    }

    /// The velocity components `u` in the parallel frame.
    pub fn velocity_components(&self, y: &Gyroscope3State<B::Group>) -> Vector3<f64> {
        y.1 .0.fixed_rows::<3>(0).into_owned()
    }

    /// The parallel frame `q` (columns, ambient components).
    pub fn parallel_frame(&self, y: &Gyroscope3State<B::Group>) -> Matrix4x3<f64> {
        self.bundle.frame_vectors(&y.0 .0)
    }

    /// The body frame `e = q·ρ` (columns, ambient components).
    pub fn body_frame(&self, y: &Gyroscope3State<B::Group>) -> Matrix4x3<f64> {
        self.bundle.frame_vectors(&y.0 .0) * y.0 .1.matrix()
    }

    /// The spin vector `π` in `q`-components (canonical; `σ ρ𝕀W`).
    pub fn spin(&self, y: &Gyroscope3State<B::Group>) -> Vector3<f64> {
        y.1 .0.fixed_rows::<3>(3).into_owned()
    }

    /// The spin vector in body components, `M = ρᵀπ`.
    pub fn spin_body(&self, y: &Gyroscope3State<B::Group>) -> Vector3<f64> {
        y.0 .1.matrix().transpose() * self.spin(y)
    }

    /// The spin as an ambient tangent vector `q π` (independent of the frames).
    pub fn spin_ambient(&self, y: &Gyroscope3State<B::Group>) -> Vector4<f64> {
        self.bundle.frame_vectors(&y.0 .0) * self.spin(y)
    }

    /// The spin tensor `S_σ^{ab} = −[π]×` in the parallel frame (the paper's
    /// `S = K − Kᵀ` of (a59), times `σ`).
    pub fn spin_tensor(&self, y: &Gyroscope3State<B::Group>) -> Matrix3<f64> {
        -So3::hat(&self.spin(y))
    }

    /// The body angular velocity `W = σ𝕀⁻¹ρᵀπ` (`ρ̇ = ρŴ`; relative to a
    /// parallel frame, so it is the covariant angular velocity of `e`).
    pub fn angular_velocity(&self, y: &Gyroscope3State<B::Group>) -> Vector3<f64> {
        self.inv_inertia * self.spin_body(y)
    }

    /// The translational kinetic energy `(m/2)|u|²`.
    pub fn translational_energy(&self, y: &Gyroscope3State<B::Group>) -> f64 {
        0.5 * self.body.mass() * self.velocity_components(y).norm_squared()
    }

    /// The internal kinetic energy `σ·½ W·𝕀W = ½ M·(σ𝕀)⁻¹M`.
    pub fn internal_energy(&self, y: &Gyroscope3State<B::Group>) -> f64 {
        let m = self.spin_body(y);
        0.5 * m.dot(&(self.inv_inertia * m))
    }

    /// The potential energy `V(x, e)`.
    pub fn potential_energy(&self, y: &Gyroscope3State<B::Group>) -> f64 {
        self.potential.value::<f64>(&self.position(y), &self.body_frame(y), &self.metric)
    }

    /// The spin–curvature force `K π × u` of (a59) (`= −K S_σ u`), frame components.
    pub fn geometric_force(&self, y: &Gyroscope3State<B::Group>) -> Vector3<f64> {
        self.spin(y).cross(&self.velocity_components(y)) * self.bundle.curvature_at(&y.0 .0)
    }

    /// The power `u·F_geom` of the geometric force (zero up to round-off).
    pub fn geometric_power(&self, y: &Gyroscope3State<B::Group>) -> f64 {
        self.velocity_components(y).dot(&self.geometric_force(y))
    }

    /// The horizontal force `F̂` and the torque `τ` (both `q`-components) of
    /// the potential.
    pub fn potential_forces(&self, y: &Gyroscope3State<B::Group>) -> (Vector3<f64>, Vector3<f64>) {
        self.forces(&y.0 .0, y.0 .1.matrix())
    }

    /// The momentum map (Noether charge) of the ambient isometries `exp(tA)`:
    /// `J_A = m⟨Ax, ẋ⟩_η + vee(qᵀηAq)·π` (derivation in
    /// [`gyroscope`](super::gyroscope)). On S³ every `A ∈ so(4)` is a
    /// symmetry of the kinetic energy.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (field
    /// `"generator"`) unless `Aᵀη + ηA = 0`.
    pub fn momentum_map(&self, y: &Gyroscope3State<B::Group>, generator: &Matrix4<f64>) -> Result<f64> {
        momentum_map_generator_check(&self.metric, generator)?;
        let g = &y.0 .0;
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let eta_a = self.metric * generator;
        let translational = self.body.mass() * (q * self.velocity_components(y)).dot(&(eta_a * x));
        let w = So3::vee(&(q.transpose() * eta_a * q));
        Ok(translational + w.dot(&self.spin(y)))
    }

    /// `(F̂, τ)` at `(g, ρ)`.
    #[inline]
    fn forces(&self, g: &B::Group, rm: &Matrix3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let x = self.bundle.position(g);
        let q = self.bundle.frame_vectors(g);
        let e = q * rm;
        let grad = self.potential.gradient(&x, &e, &self.metric);
        let mut f = position_force(&q, &grad.dx);
        let mut torque = Vector3::zeros();
        if self.frame_dependent {
            for a in 0..3 {
                let xi = self.bundle.horizontal_lift(g, &Vector3::ith(a, 1.0));
                let (_, dq) = self.bundle.frame_velocity(g, &xi);
                f[a] -= grad.de.component_mul(&(dq * rm)).sum();
            }
            // τ = −vee(Gρᵀ − ρGᵀ) = −2·vee(skew(Gρᵀ)).
            let gi = q.transpose() * grad.de;
            torque = So3::vee(&(gi * rm.transpose())) * -2.0;
        }
        (f, torque)
    }
}

/// The quantities of the paper's §6 for the S³ gyroscope, in components of the
/// paper's frame `ˡE(R)` (`ˡE_A(x) = e_A·x/R`, right-invariant,
/// [`Sphere3::frame_l_ambient`]; SPEC §7 "S³ frames").
///
/// With `ω = Ω_rl − V/R` the covariant angular velocity of the body in
/// `ˡE`-components, `T = (m/2)|V|² + ½ ω·𝕀_E ω` and the canonical momenta
/// conjugate to `V = ˡΩ(R)` and `Ω_rl = ˡΩ_rl` are
/// `S_rl = 𝕀_E ω` (the spin) and `S(R) = mV − S_rl/R` — for `J = (I/2)δ`
/// exactly the paper's `(m + I/R²)V − (I/R)Ω_rl` and `−(I/R)V + IΩ_rl`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperMomenta {
    /// `ˡS(R)_A`, the momentum conjugate to the velocity components `V^A = ˡΩ(R)^A`.
    pub s: Vector3<f64>,
    /// `ˡS_rl A`, the internal (spin) momentum.
    pub s_rl: Vector3<f64>,
    /// `ˡV^A`, the velocity components in `ˡE(R)` (units of velocity).
    pub v: Vector3<f64>,
}

impl PaperMomenta {
    /// `(|S(R)|², |S_rl|²)`, the Casimirs of (a185): constant in free motion.
    pub fn casimirs(&self) -> (f64, f64) {
        (self.s.norm_squared(), self.s_rl.norm_squared())
    }

    /// `C = (R/2)·S(R) + S_rl` (a186): constant in free motion; `2C = mRV + S_rl`
    /// is the momentum map of the left translations `x ↦ exp(t e_A)·x`.
    pub fn c(&self, radius: f64) -> Vector3<f64> {
        self.s * (0.5 * radius) + self.s_rl
    }
}

impl<P: Potential<3, 4>> Gyroscope3Model<Sphere3, P> {
    /// The paper's `ˡS(R)`, `ˡS_rl` and `ˡV` at the state `y` (see
    /// [`PaperMomenta`]). In free motion `|S(R)|²`, `|S_rl|²` and
    /// `C = (R/2)S(R) + S_rl` are conserved ((a185), (a186)), and `S(R)`,
    /// `S_rl` rotate rigidly about `C` with angular velocity `2C/(mR²)`
    /// ((b185a), (b185b); SPEC §7).
    pub fn paper_momenta(&self, y: &Gyroscope3State<So4Group>) -> PaperMomenta {
        let p = self.bundle.position(&y.0 .0);
        let gamma = self.bundle.frame_l_ambient(&p).transpose() * self.bundle.frame_vectors(&y.0 .0);
        let v = gamma * self.velocity_components(y);
        let s_rl = gamma * self.spin(y);
        let s = v * self.body.mass() - s_rl / self.bundle.radius();
        PaperMomenta { s, s_rl, v }
    }

    /// `C = (R/2)·ˡS(R) + ˡS_rl` of (a186).
    pub fn a186(&self, y: &Gyroscope3State<So4Group>) -> Vector3<f64> {
        self.paper_momenta(y).c(self.bundle.radius())
    }
}

/// The bundle group of S³, SO(4).
type So4Group = <Sphere3 as FrameBundle<3, 4>>::Group;

impl<B, P> System for Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4>,
    P: Potential<3, 4>,
{
    type State = Gyroscope3State<B::Group>;

    /// `((horizontal_lift(g, u), σ𝕀⁻¹ρᵀπ), ((K π × u + F̂)/m, τ))`.
    #[inline]
    fn vector_field(&self, _t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        let (g, rm) = (&y.0 .0, y.0 .1.matrix());
        let w = &y.1 .0;
        let u = Vector3::new(w[0], w[1], w[2]);
        let pi = Vector3::new(w[3], w[4], w[5]);
        let xi = self.bundle.horizontal_lift(g, &u);
        let omega = self.inv_inertia * (rm.transpose() * pi);
        let (f, torque) = self.forces(g, rm);
        let acc = (pi.cross(&u) * self.bundle.curvature_at(g) + f) * self.inv_mass;
        ProductAlgebra(ProductAlgebra(xi, omega), join(&acc, &torque))
    }

    /// The derivative along `((η, δr), (δu, δπ))` (`ρ ↦ ρ·exp(hat δr)`):
    /// `D_g lift(u)[η] + lift(δu)`, `δΩ = σ𝕀⁻¹(δρᵀπ + ρᵀδπ)`,
    /// `δu̇ = (δπ × u K + π × δu K + π × u δK + δF̂)/m`, and the torque's
    /// `−2 vee(δ(Gρᵀ))` ([`force_derivative`](super::force_derivative)).
    fn tangent_field(&self, t: f64, y: &Self::State, xi: &<Self::State as LieGroup>::Algebra) -> Option<super::FieldAndDerivative<Self::State>> {
        if !self.potential.second_derivatives() {
            return None;
        }
        let (g, rm) = (&y.0 .0, y.0 .1.matrix());
        let w = &y.1 .0;
        let (u, pi) = (Vector3::new(w[0], w[1], w[2]), Vector3::new(w[3], w[4], w[5]));
        let (eta, dr) = (&xi.0 .0, &xi.0 .1);
        let dw = &xi.1;
        let (du, dpi) = (Vector3::new(dw[0], dw[1], dw[2]), Vector3::new(dw[3], dw[4], dw[5]));
        let drm = rm * So3::hat(dr);
        let d = super::force_derivative(&self.bundle, &self.potential, &self.metric, g, rm, eta, &drm);
        let domega = self.inv_inertia * (drm.transpose() * pi + rm.transpose() * dpi);
        let k = self.bundle.curvature_at(g);
        let dk = self.bundle.curvature_derivative(g, eta);
        let dacc = ((dpi.cross(&u) + pi.cross(&du)) * k + pi.cross(&u) * dk + d.d_force) * self.inv_mass;
        let dtorque = if self.frame_dependent { So3::vee(&(d.d_internal * rm.transpose() + d.internal * drm.transpose())) * -2.0 } else { Vector3::zeros() };
        let dlift = self.bundle.horizontal_lift(g, &du) + self.bundle.lift_derivative(g, &u, eta);
        Some((self.vector_field(t, y), ProductAlgebra(ProductAlgebra(dlift, domega), join(&dacc, &dtorque))))
    }

    /// `E = (m/2)|u|² + ½ M·(σ𝕀)⁻¹M + V(x, e)`, `M = ρᵀπ`.
    fn energy(&self, y: &Self::State) -> f64 {
        self.translational_energy(y) + self.internal_energy(y) + self.potential_energy(y)
    }

    /// The larger of [`FrameBundle::bundle_defect`] and the SO(3) defect of
    /// `ρ`; `NaN` if the state is not finite.
    fn defect(&self, y: &Self::State) -> f64 {
        combine_defects(&[
            self.bundle.bundle_defect(&y.0 .0),
            finite_defect(self.bundle.position(&y.0 .0).iter()),
            y.0 .1.constraint_defect(),
            finite_defect(y.0 .1.matrix().iter()),
            finite_defect(y.1 .0.iter()),
        ])
    }

    /// `q ↦ qk`, `ρ ↦ kᵀρ`, `u ↦ kᵀu`, `π ↦ kᵀπ` (an axial vector of the
    /// parallel frame): `(vertical(g, w), −ρᵀ·vee(w), −w·u, −w·π)`.
    fn gauge(&self, y: &Self::State) -> Vec<<Self::State as LieGroup>::Algebra> {
        let rho = y.0 .1.matrix();
        let (u, pi) = (y.1 .0.fixed_rows::<3>(0).into_owned(), y.1 .0.fixed_rows::<3>(3).into_owned());
        crate::dynamics::skew_basis::<3>()
            .iter()
            .map(|w| {
                let (du, dpi) = (-(w * u), -(w * pi));
                let rates = Vector6::new(du[0], du[1], du[2], dpi[0], dpi[1], dpi[2]);
                ProductAlgebra(ProductAlgebra(self.bundle.vertical(&y.0 .0, w), -(rho.transpose() * So3::vee(w))), rates)
            })
            .collect()
    }
}

#[inline]
fn join(a: &Vector3<f64>, b: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(a[0], a[1], a[2], b[0], b[1], b[2])
}

// -- splitting ---------------------------------------------------------------

/// The principal decomposition of the inertia operator used by the internal
/// drift of the n = 3 gyroscope: reference moment `I₁`, the two other axes
/// `P₂`, `P₃` with `c_k = σ(1/I_k − 1/I₁)`, and whether `c₂ = 0` (symmetric).
#[derive(Debug, Clone, Copy)]
struct InternalSplit {
    /// `σ/I₁`.
    casimir: f64,
    axes: [Vector3<f64>; 2],
    c: [f64; 2],
    symmetric: bool,
}

fn internal_split(op: &Matrix3<f64>, sigma: f64) -> InternalSplit {
    let eig = SymmetricEigen::new(*op);
    let ev = eig.eigenvalues;
    let scale = ev.amax();
    // The pair of closest moments: I₁ := one of them, the odd one out is P₃.
    let pairs = [(0usize, 1usize, 2usize), (1, 2, 0), (0, 2, 1)];
    let mut best = pairs[0];
    let mut gap = f64::INFINITY;
    for p in pairs {
        let d = (ev[p.0] - ev[p.1]).abs();
        if d < gap {
            gap = d;
            best = p;
        }
    }
    let (i1, i2, i3) = best;
    let symmetric = gap <= 1e-14 * scale;
    let c2 = if symmetric { 0.0 } else { sigma * (1.0 / ev[i2] - 1.0 / ev[i1]) };
    let c3 = sigma * (1.0 / ev[i3] - 1.0 / ev[i1]);
    let col = |i: usize| eig.eigenvectors.column(i).into_owned();
    InternalSplit { casimir: sigma / ev[i1], axes: [col(i2), col(i3)], c: [c2, c3], symmetric }
}

impl InternalSplit {
    /// `ρ ← ρ·exp(h c_k (P_k·M) hat(P_k))`, `M = ρᵀπ`.
    #[inline]
    fn axis_rotation(&self, rho: &So3, pi: &Vector3<f64>, k: usize, h: f64) -> So3 {
        let m = rho.matrix().transpose() * pi;
        let p = &self.axes[k];
        rho.compose(&So3::exp(&(p * (h * self.c[k] * p.dot(&m)))))
    }

    /// The internal drift over `h`: exact for a symmetric operator, Yoshida-6
    /// composition of the Strang splitting of the two axis rotations otherwise.
    fn drift(&self, rho: &So3, pi: &Vector3<f64>, h: f64) -> So3 {
        // Casimir part: ρ ← ρ exp(h σ M/I₁) (commutes with the rest).
        let m = rho.matrix().transpose() * pi;
        let mut r = rho.compose(&So3::exp(&(m * (h * self.casimir))));
        if self.symmetric {
            return self.axis_rotation(&r, pi, 1, h);
        }
        for &gam in YOSHIDA6.iter() {
            let hh = gam * h;
            r = self.axis_rotation(&r, pi, 0, 0.5 * hh);
            r = self.axis_rotation(&r, pi, 1, hh);
            r = self.axis_rotation(&r, pi, 0, 0.5 * hh);
        }
        r.renormalize()
    }
}

/// The kick and the free flow of the n = 3 gyroscope (exact for a symmetric
/// inertia operator, to order 6 otherwise; see [`split`](super::split)); on
/// S³.
impl<B, P> Splittable for Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4>,
    P: Potential<3, 4>,
{
    /// `u ← u + hF̂/m`, `π ← π + hτ`.
    #[inline(always)]
    fn kick(&self, y: &Self::State, h: f64) -> Self::State {
        let (f, torque) = self.potential_forces(y);
        let w = y.1 .0;
        let a = f * (h * self.inv_mass());
        let t = torque * h;
        Product(y.0, Rn(Vector6::new(w[0] + a[0], w[1] + a[1], w[2] + a[2], w[3] + t[0], w[4] + t[1], w[5] + t[2])))
    }

    /// `g ← g₀ exp(h(ξ(u₀) + R)) exp(−hR)`, `R = vertical(hat(Kπ/m))`;
    /// `u ← exp(h hat(Kπ/m)) u₀`; `ρ` by the internal drift; `π` unchanged.
    fn drift(&self, y: &Self::State, h: f64) -> Self::State {
        let (g, rho) = (&y.0 .0, &y.0 .1);
        let w = y.1 .0;
        let u = Vector3::new(w[0], w[1], w[2]);
        let pi = Vector3::new(w[3], w[4], w[5]);
        let omega = pi * (self.bundle().curvature_at(g) * self.inv_mass());
        let g1 = free_translation(self.bundle(), g, &u, &So3::hat(&omega), h);
        let u1 = So3::exp(&(omega * h)).matrix() * u;
        let sigma = signature_sign(self.signature());
        let split = internal_split(self.inertia_operator(), sigma);
        let rho1 = split.drift(rho, &pi, h);
        Product(Product(g1, rho1), Rn(Vector6::new(u1[0], u1[1], u1[2], w[3], w[4], w[5])))
    }

    fn has_free_flow(&self) -> bool {
        self.bundle().exact_free_flow()
    }

    fn drift_exact(&self) -> bool {
        let sigma = signature_sign(self.signature());
        internal_split(self.inertia_operator(), sigma).symmetric
    }

    fn drift_exps(&self) -> u32 {
        if self.drift_exact() {
            5
        } else {
            4 + 3 * YOSHIDA6.len() as u32
        }
    }
}

impl<B, P> SplitDispatch for Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4>,
    P: Potential<3, 4>,
{
    type Split = Self;
    #[inline(always)]
    fn as_splittable(&self) -> Option<&Self> {
        self.has_free_flow().then_some(self)
    }
}
