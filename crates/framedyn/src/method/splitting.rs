//! Symplectic splitting methods with exact free flows (SPEC §4).
//!
//! `H = T + V` is split into the **drift** — the flow of the kinetic energy
//! `T` alone (the free motion: geodesic flow of a point, free gyroscope) — and
//! the **kick** — the flow of the potential `V` alone, which freezes the
//! configuration and changes only the momenta. What a model must provide is
//! the trait [`Splittable`] of [`dynamics::split`](crate::dynamics::split)
//! (implemented by the models in their own files, where the exact free
//! flows are derived); this module only composes kicks and drifts. Every
//! composition is symplectic and keeps the momentum maps of the symmetries
//! of `V` exactly.
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

use super::group::GroupNumerics;
use super::registry;
use super::{Alg, DensePoly, Method, MethodError, MethodInfo, NonFiniteSource, StepCost, StepFault, StepOutput, StepRequest};
use crate::dynamics::split::YOSHIDA6;
use crate::dynamics::Splittable;
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup};

use super::tableau::DENSE_DEGREE;

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
        Self::composition(registry::STRANG.display, 2, &[1.0]).expect("static weights")
    }

    /// Yoshida's (and Suzuki's) triple jump of Strang, order 4, three kicks \[Yo90\].
    pub fn yoshida4() -> Self {
        let c = 2f64.cbrt();
        let g1 = 1.0 / (2.0 - c);
        Self::composition(registry::YOSHIDA4.display, 4, &[g1, -c * g1, g1]).expect("static weights")
    }

    /// Suzuki's five-fold composition of Strang, order 4, five kicks \[Su90\].
    pub fn suzuki4() -> Self {
        let p = 1.0 / (4.0 - 4f64.cbrt());
        Self::composition(registry::SUZUKI4.display, 4, &[p, p, 1.0 - 4.0 * p, p, p]).expect("static weights")
    }

    /// Yoshida's seven-fold composition of Strang (solution A), order 6,
    /// seven kicks \[Yo90\].
    pub fn yoshida6() -> Self {
        Self::composition(registry::YOSHIDA6.display, 6, &YOSHIDA6).expect("static weights")
    }

    /// Blanes–Moan `S₆` (\[BM02\], Table 2), order 4, six kicks and seven drifts.
    pub fn blanes_moan4() -> Self {
        let (a1, a2, a3) = (0.079_203_696_431_195_7, 0.353_172_906_049_774, -0.042_065_080_357_719_5);
        let a4 = 1.0 - 2.0 * (a1 + a2 + a3);
        let (b1, b2) = (0.209_515_106_613_362, -0.143_851_773_179_818);
        let b3 = 0.5 - (b1 + b2);
        Self::from_weights(registry::BLANES_MOAN4.display, 4, &[a1, a2, a3, a4, a3, a2, a1], &[b1, b2, b3, b3, b2, b1])
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
        Self::from_weights(registry::BLANES_MOAN6.display, 6, &aa, &bb).expect("static weights")
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
        Self::from_weights(registry::BLANES_MOAN_RKN6.display, 6, &aa, &bb).expect("static weights")
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
        Self::from_weights(registry::BLANES_MOAN_RKN4.display, 4, &aa, &bb).expect("static weights")
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

    /// Refuses a system whose drift is not its free flow
    /// ([`Splittable::has_free_flow`]: no exact free flow on its bundle).
    fn check(&self, sys: &S) -> Result<(), MethodError> {
        if sys.has_free_flow() {
            Ok(())
        } else {
            Err(MethodError::Unsupported {
                method: self.name,
                reason: "splitting needs exact free flows (points and gyroscopes on S2, H2, S3)",
            })
        }
    }

    /// The composition, then renormalisation. The vector field is evaluated
    /// only for dense output (`f` at both ends, cubic Hermite in
    /// `Θ = log(y₀⁻¹y₁)`); without it `theta` and `f_start` are zero.
    // Forced inline only in optimised builds, where inlining specialises the
    // step on the caller's constant request; a hint in builds with debug
    // assertions (tests), where forcing it copied the whole step into each of
    // the driver's call sites (docs/development.md, "What the core's size is
    // made of").
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline)]
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
