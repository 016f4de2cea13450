//! Symplectic splitting methods with exact free flows (SPEC §4).
//!
//! `H = T + V` is split into the **drift** — the flow of the kinetic energy
//! `T` alone (the free motion: geodesic flow of a point, free gyroscope) — and
//! the **kick** — the flow of the potential `V` alone, which freezes the
//! configuration and changes only the momenta:
//! ```text
//! kick(h):   u ← u + h F̂/m,   s ← s + h·(−∂V/∂α)   (n = 2),   π ← π + h τ   (n = 3)
//! drift(h):  the exact free flow (below)
//! ```
//! Both are exact flows of Hamiltonian vector fields, so every composition of
//! them is symplectic, and, when `V` is invariant under an ambient isometry,
//! conserves its momentum map (e.g. `p_φ`) exactly: the kick changes `J_A` by
//! `−h·(derivative of V along A) = 0`, the drift is an exact flow of the
//! invariant `T`.
//!
//! # Exact free flows on constant curvature ([`ConstantCurvature`])
//! On S², H², S³ the horizontal lift `ξ(u)` and the vertical generator are
//! constant in the bundle group, and rotating the frame by `exp(τ·vertical(w))`
//! rotates the lift: `Ad_{exp(τR)} ξ(u) = ξ(exp(τw) u)` with `R = vertical(w)`.
//! The free equations in the parallel frame ([`gyroscope`](crate::dynamics::gyroscope))
//! `ġ = g ξ(u)`, `m u̇ = K s ε u` (n = 2) or `K π × u` (n = 3), `π̇ = 0` have
//! `u(t) = exp(t w) u₀` with `w = (K s/m) ε` resp. `hat(K π/m)`, hence
//! ```text
//! g(t) = g₀ · exp(t (ξ(u₀) + R)) · exp(−t R),     R = vertical(g₀, w)
//! ```
//! (differentiate: `g⁻¹ġ = Ad_{exp(tR)}(ξ(u₀) + R) − R = ξ(u(t))`). This is
//! the parallel-frame form of SPEC §4's `Q(t) = Q₀ exp(tΠ̂₀/K)·exp(t(1/I − 1/K)Π₃ê₃)`
//! for the symmetric top on S² (and the Lorentz top on H²): the internal
//! rotation `ρ` separates. For the point (`s = 0`) it is the geodesic flow
//! `g₀ exp(t ξ(u₀))`.
//!
//! **Internal rotation.** n = 2: `ρ(t) = ρ₀ U(t σ s/I)`. n = 3: with the
//! body momentum `M = ρᵀπ` and the principal axes `P_k`, moments `I_k` of the
//! inertia operator `𝕀`, the internal energy splits as
//! `σ|M|²/(2I₁) + Σ_{k=2,3} c_k (P_k·M)²/2`, `c_k = σ(1/I_k − 1/I₁)`; each
//! piece has the exact flow `ρ ↦ ρ·exp(t·a·hat(axis))` with `π` fixed
//! (a rotation about `M` resp. about `P_k`, whose component of `M` it keeps).
//! The first commutes with the others. For a **symmetric** `𝕀` (two equal
//! moments, chosen as `I₁ = I₂`) `c₂ = 0` and the drift is exact — the free
//! symmetric top. For an **asymmetric** `𝕀` the pieces `c₂`, `c₃` do not
//! commute (the exact free flow would need Jacobi elliptic functions): the
//! drift then composes them by the symmetric sixth-order Yoshida composition
//! of their Strang splitting ([`YOSHIDA6`]), i.e. it is exact up to
//! `O(h⁷)` per step, symmetric and symplectic — every method here keeps its
//! order ≤ 6 and its conservation properties.
//!
//! # Methods ([`Splitting`])
//! A method is the palindromic sequence
//! `D(a₀h) K(b₀h) D(a₁h) … K(b_{s−1}h) D(a_s h)` (`Σa = Σb = 1`):
//! - [`Splitting::strang`]: `D(h/2) K(h) D(h/2)`, order 2;
//! - [`Splitting::yoshida4`]: the triple jump of Strang, weights
//!   `γ₁ = γ₃ = 1/(2 − 2^{1/3})`, `γ₂ = −2^{1/3}/(2 − 2^{1/3})` \[Yo90\], \[Su90\], order 4;
//! - [`Splitting::suzuki4`]: Suzuki's five-fold composition
//!   `p, p, 1 − 4p, p, p`, `p = 1/(4 − 4^{1/3})` \[Su90\], order 4 (smaller error constant);
//! - [`Splitting::yoshida6`]: Yoshida's seven-fold composition, solution A \[Yo90\], order 6;
//! - [`Splitting::blanes_moan4`]: the optimised six-kick method `S₆` of
//!   \[BM02\] (Table 2), order 4;
//! - [`Splitting::blanes_moan6`]: the optimised ten-kick method `S₁₀` of \[BM02\], order 6;
//! - [`Splitting::blanes_moan_rkn4`] / [`Splitting::blanes_moan_rkn6`]: the
//!   Runge–Kutta–Nyström methods `SRKN₆ᵇ` / `SRKN₁₁ᵇ` of \[BM02\], orders 4 / 6
//!   (`K D K … D K`), valid because `T` is quadratic in the momenta and `V`
//!   depends on the configuration only; far more accurate at the same
//!   number of drifts.
//!
//! \[Yo90\] H. Yoshida, *Construction of higher order symplectic integrators*,
//! Phys. Lett. A 150 (1990) 262–268. \[Su90\] M. Suzuki, *Fractal decomposition
//! of exponential operators with applications to many-body theories and Monte
//! Carlo simulations*, Phys. Lett. A 146 (1990) 319–323. \[BM02\] S. Blanes,
//! P. C. Moan, *Practical symplectic partitioned Runge–Kutta and
//! Runge–Kutta–Nyström methods*, J. Comput. Appl. Math. 142 (2002) 313–330.

use nalgebra::{Matrix2, Matrix3, SVector, SymmetricEigen, Vector1, Vector2, Vector3, Vector6};

use super::group::GroupNumerics;
use super::{Alg, DensePoly, Method, MethodInfo, NonFiniteSource, StepCost, StepFault, StepOutput, StepRequest};
use crate::bundle::FrameBundle;
use crate::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup, Product, Rn, So12, So2, So3};
use crate::manifold::{Hyperbolic2, Sphere2, Sphere3};
use crate::potential::Potential;

use super::tableau::DENSE_DEGREE;

/// Frame bundles of constant curvature whose horizontal lift and vertical
/// generator do not depend on the bundle element and are equivariant,
/// `Ad_{exp(τ·vertical(w))} horizontal_lift(u) = horizontal_lift(exp(τw)u)`
/// — S², H², S³ (SO(3), SO⁺(1,2), SO(4) acting on themselves). On these the
/// free flows are exact ([`free_translation`]). T² is not one (its curvature
/// varies).
pub trait ConstantCurvature<const N: usize, const E: usize>: FrameBundle<N, E> {}

impl ConstantCurvature<2, 3> for Sphere2 {}
impl ConstantCurvature<2, 3> for Hyperbolic2 {}
impl ConstantCurvature<3, 4> for Sphere3 {}

/// The n = 2 bundles of constant curvature (S², H²): the frame rotation
/// `g·exp(θ·vertical(g, ε))` in closed form, from `(cos θ, sin θ)` — two
/// columns of the matrix rotate — so that the drift of the gyroscope shares
/// one `sin_cos` between the frame and the velocity instead of forming a
/// second exponential and a full matrix product.
pub trait PlanarFrameRotation: ConstantCurvature<2, 3> {
    /// `g·exp(θ·vertical(g, ε))`, `ε = [[0, −1], [1, 0]]`, from `cos θ`, `sin θ`.
    fn rotate_frame(&self, g: &Self::Group, cos: f64, sin: f64) -> Self::Group;
}

/// `m` with columns `i`, `j` replaced by `c·mᵢ + s·mⱼ`, `c·mⱼ − s·mᵢ`.
#[inline]
fn rotate_columns(m: &Matrix3<f64>, i: usize, j: usize, cos: f64, sin: f64) -> Matrix3<f64> {
    let mut out = *m;
    let (a, b): (Vector3<f64>, Vector3<f64>) = (m.column(i).into(), m.column(j).into());
    out.set_column(i, &(a * cos + b * sin));
    out.set_column(j, &(b * cos - a * sin));
    out
}

impl PlanarFrameRotation for Sphere2 {
    /// `vertical(ε) = e₁` (rotation about the normal `n = Q e₀`): columns
    /// `q₁, q₂` of `Q` rotate, `q₁ ← c q₁ + s q₂`, `q₂ ← −s q₁ + c q₂`.
    #[inline]
    fn rotate_frame(&self, g: &So3, cos: f64, sin: f64) -> So3 {
        So3::new_unchecked(rotate_columns(g.matrix(), 1, 2, cos, sin))
    }
}

impl PlanarFrameRotation for Hyperbolic2 {
    /// `vertical(ε) = (0, 0, 1)` (the rotation generator of so(1,2)): the
    /// spacelike columns `λ₀, λ₁` of `Λ` rotate like `q₁, q₂` on S².
    #[inline]
    fn rotate_frame(&self, g: &So12, cos: f64, sin: f64) -> So12 {
        So12::new_unchecked(rotate_columns(g.matrix(), 0, 1, cos, sin))
    }
}

/// The exact free translation of the bundle element: `g(t) = g₀·exp(t(ξ(u₀) + R))·exp(−tR)`,
/// `R = vertical(g₀, w)`, for the velocity `u(t) = exp(tw)u₀` (see the module
/// docs). Returns `g(h)`; two exponentials.
pub fn free_translation<B: ConstantCurvature<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g0: &B::Group,
    u0: &SVector<f64, N>,
    w: &nalgebra::SMatrix<f64, N, N>,
    h: f64,
) -> B::Group {
    let xi = bundle.horizontal_lift(g0, u0);
    let r = bundle.vertical(g0, w);
    g0.compose(&B::Group::exp(&((xi + r) * h))).compose(&B::Group::exp(&(r * (-h))))
}

/// A system whose Hamiltonian `T + V` splits into two exactly (or, see
/// [`Splittable::drift_exact`], to order 6) integrable parts.
pub trait Splittable: System {
    /// The flow of `V` over time `h`: the momenta change by `h` times the
    /// generalised forces at the frozen configuration.
    fn kick(&self, y: &Self::State, h: f64) -> Self::State;
    /// The flow of `T` over time `h`: the free motion.
    fn drift(&self, y: &Self::State, h: f64) -> Self::State;
    /// True if [`Splittable::drift`] is the exact free flow; false if it is a
    /// symmetric symplectic approximation with local error `O(h⁷)`.
    fn drift_exact(&self) -> bool {
        true
    }
    /// Group exponentials per drift.
    fn drift_exps(&self) -> u32;
}

const EPS: Matrix2<f64> = Matrix2::new(0.0, -1.0, 1.0, 0.0);

impl<B, P> Splittable for Gyroscope2Model<B, P>
where
    B: PlanarFrameRotation,
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
    /// (the formula of [`free_translation`], its second factor by
    /// [`PlanarFrameRotation::rotate_frame`]); `u ← U(hKs/m) u₀` with the
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

    fn drift_exps(&self) -> u32 {
        3
    }
}

impl<B, P, const N: usize, const E: usize> Splittable for PointModel<B, P, N, E>
where
    B: ConstantCurvature<N, E>,
    P: Potential<N, E>,
{
    /// `u ← u + hF̂/m`.
    #[inline(always)]
    fn kick(&self, y: &Self::State, h: f64) -> Self::State {
        Product(y.0, Rn(y.1 .0 + self.force(y) * (h * self.inv_mass())))
    }

    /// The geodesic flow `g ← g₀ exp(h ξ(u₀))`, `u` unchanged.
    #[inline(always)]
    fn drift(&self, y: &Self::State, h: f64) -> Self::State {
        let xi = self.bundle().horizontal_lift(&y.0, &y.1 .0);
        Product(y.0.compose(&B::Group::exp(&(xi * h))), y.1)
    }

    fn drift_exps(&self) -> u32 {
        1
    }
}

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

impl<B, P> Splittable for Gyroscope3Model<B, P>
where
    B: ConstantCurvature<3, 4>,
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
        let sigma = crate::dynamics::gyroscope::signature_sign(self.signature());
        let split = internal_split(self.inertia_operator(), sigma);
        let rho1 = split.drift(rho, &pi, h);
        Product(Product(g1, rho1), Rn(Vector6::new(u1[0], u1[1], u1[2], w[3], w[4], w[5])))
    }

    fn drift_exact(&self) -> bool {
        let sigma = crate::dynamics::gyroscope::signature_sign(self.signature());
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

/// Yoshida's sixth-order composition weights, solution A of \[Yo90\]
/// (`w₃, w₂, w₁, w₀, w₁, w₂, w₃`; `w₀ = 1 − 2(w₁ + w₂ + w₃)`).
pub const YOSHIDA6: [f64; 7] = [
    0.784_513_610_477_557_3,
    0.235_573_213_359_358_13,
    -1.177_679_984_178_871,
    1.315_186_320_683_911_2,
    -1.177_679_984_178_871,
    0.235_573_213_359_358_13,
    0.784_513_610_477_557_3,
];

/// Largest number of kicks of a method.
pub const MAX_KICKS: usize = 12;

/// A palindromic splitting method `D(a₀h) K(b₀h) D(a₁h) … K(b_{s−1}h) D(a_s h)`
/// (module docs). `Copy`, no heap data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Splitting {
    name: &'static str,
    order: u32,
    a: [f64; MAX_KICKS + 1],
    b: [f64; MAX_KICKS],
    kicks: usize,
    /// Number of non-zero drift weights (drifts per step).
    drifts: u32,
}

impl Splitting {
    /// The method from its drift weights `a` (`s + 1` of them) and kick
    /// weights `b` (`s ≤` [`MAX_KICKS`]), with its order as cited.
    ///
    /// Panics never; returns `None` if the lengths do not fit.
    pub fn from_weights(name: &'static str, order: u32, a: &[f64], b: &[f64]) -> Option<Self> {
        if b.is_empty() || b.len() > MAX_KICKS || a.len() != b.len() + 1 {
            return None;
        }
        let drifts = a.iter().filter(|&&w| w != 0.0).count() as u32;
        let mut s = Splitting { name, order, a: [0.0; MAX_KICKS + 1], b: [0.0; MAX_KICKS], kicks: b.len(), drifts };
        s.a[..a.len()].copy_from_slice(a);
        s.b[..b.len()].copy_from_slice(b);
        Some(s)
    }

    /// The composition `S(γ₁h)…S(γ_m h)` of the Strang step `S(h) = D(h/2)K(h)D(h/2)`
    /// (adjacent half drifts merged).
    pub fn composition(name: &'static str, order: u32, gamma: &[f64]) -> Option<Self> {
        if gamma.is_empty() || gamma.len() > MAX_KICKS {
            return None;
        }
        let mut a = [0.0; MAX_KICKS + 1];
        let m = gamma.len();
        a[0] = 0.5 * gamma[0];
        for i in 1..m {
            a[i] = 0.5 * (gamma[i - 1] + gamma[i]);
        }
        a[m] = 0.5 * gamma[m - 1];
        Self::from_weights(name, order, &a[..=m], gamma)
    }

    /// Strang (Störmer–Verlet): `D(h/2) K(h) D(h/2)`, order 2, one kick.
    pub fn strang() -> Self {
        Self::composition("Strang", 2, &[1.0]).expect("static weights")
    }

    /// Yoshida's (and Suzuki's) triple jump of Strang, order 4, three kicks \[Yo90\].
    pub fn yoshida4() -> Self {
        let c = 2f64.cbrt();
        let g1 = 1.0 / (2.0 - c);
        Self::composition("Yoshida4", 4, &[g1, -c * g1, g1]).expect("static weights")
    }

    /// Suzuki's five-fold composition of Strang, order 4, five kicks \[Su90\].
    pub fn suzuki4() -> Self {
        let p = 1.0 / (4.0 - 4f64.cbrt());
        Self::composition("Suzuki4", 4, &[p, p, 1.0 - 4.0 * p, p, p]).expect("static weights")
    }

    /// Yoshida's seven-fold composition of Strang (solution A), order 6,
    /// seven kicks \[Yo90\].
    pub fn yoshida6() -> Self {
        Self::composition("Yoshida6", 6, &YOSHIDA6).expect("static weights")
    }

    /// Blanes–Moan `S₆` (\[BM02\], Table 2), order 4, six kicks and seven drifts.
    pub fn blanes_moan4() -> Self {
        let (a1, a2, a3) = (0.079_203_696_431_195_7, 0.353_172_906_049_774, -0.042_065_080_357_719_5);
        let a4 = 1.0 - 2.0 * (a1 + a2 + a3);
        let (b1, b2) = (0.209_515_106_613_362, -0.143_851_773_179_818);
        let b3 = 0.5 - (b1 + b2);
        Self::from_weights("Blanes-Moan S6", 4, &[a1, a2, a3, a4, a3, a2, a1], &[b1, b2, b3, b3, b2, b1])
            .expect("static weights")
    }

    /// Blanes–Moan `S₁₀` (\[BM02\], Table 2), order 6, ten kicks and eleven drifts.
    pub fn blanes_moan6() -> Self {
        let a = [0.050_262_764_400_392_2, 0.413_514_300_428_344, 0.045_079_889_794_397_7, -0.188_054_853_819_569, 0.541_960_678_450_780];
        let a6 = 1.0 - 2.0 * a.iter().sum::<f64>();
        let b = [0.148_816_447_901_042, -0.132_385_865_767_784, 0.067_307_604_692_185, 0.432_666_402_578_175];
        let b5 = 0.5 - b.iter().sum::<f64>();
        let aa = [a[0], a[1], a[2], a[3], a[4], a6, a[4], a[3], a[2], a[1], a[0]];
        let bb = [b[0], b[1], b[2], b[3], b5, b5, b[3], b[2], b[1], b[0]];
        Self::from_weights("Blanes-Moan S10", 6, &aa, &bb).expect("static weights")
    }

    /// Blanes–Moan `SRKN₁₁ᵇ` (\[BM02\], Table 3), order 6: eleven drifts
    /// between twelve kicks (`K D K … D K`, drift weights `a₀ = a_s = 0`).
    ///
    /// A Runge–Kutta–Nyström method: its order needs `{V, {V, {V, T}}} = 0`,
    /// which holds here because the kinetic energy is quadratic in the momenta
    /// (`m|u|²/2 + σs²/(2I)`, also indefinite, and `½π·𝕀⁻¹π`) and `V` depends
    /// on the configuration only, so `{V, {V, T}}` is a function of the
    /// configuration. Under that condition it needs far fewer order
    /// conditions than a general splitting, and \[BM02\] optimised the free
    /// parameters for a small error: at equal step it is more accurate than
    /// [`Self::blanes_moan6`] at the same number of drifts (the measured ratios
    /// are in `tests/suite/splitting.rs`).
    pub fn blanes_moan_rkn6() -> Self {
        let a = [0.123_229_775_946_271, 0.290_553_797_799_558, -0.127_049_212_625_417, -0.246_331_761_062_075, 0.357_208_872_795_928];
        let a5 = 1.0 - 2.0 * a.iter().sum::<f64>();
        let b = [0.041_464_998_518_262_4, 0.198_128_671_918_067, -0.040_006_192_104_153_3, 0.075_253_984_301_580_7, -0.011_511_387_420_687_9];
        let b5 = 0.5 - b.iter().sum::<f64>();
        let aa = [0.0, a[0], a[1], a[2], a[3], a[4], a5, a[4], a[3], a[2], a[1], a[0], 0.0];
        let bb = [b[0], b[1], b[2], b[3], b[4], b5, b5, b[4], b[3], b[2], b[1], b[0]];
        Self::from_weights("Blanes-Moan SRKN11b", 6, &aa, &bb).expect("static weights")
    }

    /// Blanes–Moan `SRKN₆ᵇ` (\[BM02\], Table 3), order 4: six drifts between
    /// seven kicks; a Runge–Kutta–Nyström method like [`Self::blanes_moan_rkn6`].
    pub fn blanes_moan_rkn4() -> Self {
        let a = [0.245_298_957_184_271, 0.604_872_665_711_080];
        let a2 = 0.5 - (a[0] + a[1]);
        let b = [0.082_984_406_417_405_2, 0.396_309_801_498_368, -0.039_056_304_922_348_6];
        let b3 = 1.0 - 2.0 * (b[0] + b[1] + b[2]);
        let aa = [0.0, a[0], a[1], a2, a2, a[1], a[0], 0.0];
        let bb = [b[0], b[1], b[2], b3, b[2], b[1], b[0]];
        Self::from_weights("Blanes-Moan SRKN6b", 4, &aa, &bb).expect("static weights")
    }

    /// The drift weights `a₀ … a_s`.
    pub fn drift_weights(&self) -> &[f64] {
        &self.a[..=self.kicks]
    }

    /// What [`Method::info`] reports, for any system (the splitting's
    /// order, its kicks as stages, cubic Hermite dense output, no estimate,
    /// no radius limit).
    pub fn method_info(&self) -> MethodInfo {
        MethodInfo {
            name: self.name,
            order: self.order,
            embedded_order: None,
            dense_order: self.order.min(3),
            stages: self.kicks,
            fsal: false,
            radius_limit: f64::INFINITY,
        }
    }

    /// The kick weights `b₀ … b_{s−1}`.
    pub fn kick_weights(&self) -> &[f64] {
        &self.b[..self.kicks]
    }

    /// The cited order.
    pub fn order(&self) -> u32 {
        self.order
    }

    /// Advances `y` by `h` (no checks): the composition itself.
    #[inline(always)]
    pub fn advance<S: Splittable>(&self, sys: &S, y: &S::State, h: f64) -> S::State {
        let mut y = *y;
        for i in 0..self.kicks {
            if self.a[i] != 0.0 {
                y = sys.drift(&y, self.a[i] * h);
            }
            y = sys.kick(&y, self.b[i] * h);
        }
        if self.a[self.kicks] != 0.0 {
            y = sys.drift(&y, self.a[self.kicks] * h);
        }
        y
    }
}

impl<S> Method<S> for Splitting
where
    S: Splittable,
    S::State: GroupNumerics,
{
    fn info(&self) -> MethodInfo {
        self.method_info()
    }

    /// The composition, then renormalisation. The vector field is evaluated
    /// only for dense output (`f` at both ends, cubic Hermite in
    /// `Θ = log(y₀⁻¹y₁)`); without it `theta` and `f_start` are zero.
    #[inline(always)]
    fn step(
        &self,
        sys: &S,
        t: f64,
        y0: &S::State,
        h: f64,
        req: StepRequest<Alg<S>>,
    ) -> Result<StepOutput<S::State>, StepFault> {
        let y1 = self.advance(sys, y0, h).renormalize();
        if !y1.is_finite() {
            return Err(StepFault::NonFinite { source: NonFiniteSource::State, t_eval: t + h });
        }
        let mut cost = StepCost { rhs: self.kicks as u32, exps: self.drifts * sys.drift_exps(), brackets: 0, dexp_inv: 0 };
        let zero = Alg::<S>::zero();
        let mut out = StepOutput { y: y1, theta: zero, f_start: zero, f_end: None, error: None, dense: None, cost };
        if req.dense || req.f_end {
            let f1 = sys.vector_field(t + h, &y1);
            cost.rhs += 1;
            if !f1.is_finite() {
                return Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: t + h });
            }
            out.f_end = Some(f1);
        }
        if req.dense {
            let f0 = match req.f_start {
                Some(f) => f,
                None => {
                    cost.rhs += 1;
                    sys.vector_field(t, y0)
                }
            };
            let theta = y0
                .inverse()
                .compose(&y1)
                .log()
                .map_err(|_| StepFault::NonFinite { source: NonFiniteSource::Increment, t_eval: t + h })?;
            let f1 = out.f_end.unwrap_or(zero);
            cost.brackets += 2;
            let d0 = f0 * h;
            let d1 = dexp_inv_series::<S::State>(&(-theta), &f1, 2) * h;
            let mut coeffs = [zero; DENSE_DEGREE];
            coeffs[0] = d0;
            coeffs[1] = theta * 3.0 - d0 * 2.0 - d1;
            coeffs[2] = d0 + d1 - theta * 2.0;
            out.theta = theta;
            out.f_start = f0;
            out.dense = Some(DensePoly { coeffs, degree: 3 });
        }
        out.cost = cost;
        Ok(out)
    }
}
