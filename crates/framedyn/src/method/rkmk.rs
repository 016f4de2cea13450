//! The Runge–Kutta–Munthe-Kaas engine: one generic implementation for every
//! explicit [`Tableau`].
//!
//! For `ẏ = y·f(t, y)` and a tableau `(A, b, c)` with `S` stages, one step from
//! `(t₀, y₀)` reads \[MK98\], \[MK99\], \[IMNZ00\]:
//!
//! ```text
//! θᵢ = h Σⱼ aᵢⱼ Kⱼ,                 Fᵢ = f(t₀ + cᵢh, y₀·exp(θᵢ)),
//! Kᵢ = dexp⁻¹_{−θᵢ} Fᵢ  (truncated), Θ = h Σᵢ bᵢ Kᵢ,     y₁ = y₀·exp(Θ),
//! ```
//!
//! i.e. the classical method applied to `θ̇ = dexp⁻¹_{−θ} f(t, y₀·exp θ)`.
//! With `dexp⁻¹_{−θ} v = v + ½[θ, v] + (1/12)[θ, [θ, v]] − …` truncated after
//! `ad^{q−2}` the method keeps the classical order `q` \[MK99\]: the dropped
//! `ad^k_θ f` terms are `O(h^{k+1})` at stage level and their leading parts
//! `ad^k_{hf₀} f₀` vanish. Truncating one term earlier lowers the order (the
//! test suite measures this). The new state is renormalised onto the group
//! after every step ([`LieGroup::renormalize`]), and every step starts from
//! `θ = 0` at `y₁` (rebasing).
//!
//! Stage arrays live on the stack (`[𝔤; S]`, `S` a const generic), the
//! tableau is `'static` data, and no trait objects are involved: a step
//! allocates nothing. [`Rkmk::rk4`] runs its plain steps through a kernel
//! written out stage by stage with the coefficients as constants (the
//! compiler does not unroll the engine's stage loops over runtime tableau
//! data); it performs the engine's operations in the engine's order, and the
//! test suite checks the two agree bit for bit.
//!
//! \[MK98\] H. Munthe-Kaas, *Runge–Kutta methods on Lie groups*, BIT 38 (1998)
//! 92–111. \[MK99\] H. Munthe-Kaas, *High order Runge–Kutta methods on
//! manifolds*, Appl. Numer. Math. 29 (1999) 115–127. \[IMNZ00\] A. Iserles,
//! H. Z. Munthe-Kaas, S. P. Nørsett, A. Zanna, *Lie-group methods*, Acta
//! Numerica 9 (2000) 215–365.

use super::group::GroupNumerics;
use super::tableau::{self, BracketForm, DenseStages, Tableau, DENSE_DEGREE, EXTENDED_STAGES};
use super::{Alg, DensePoly, Method, MethodInfo, NonFiniteSource, StepCost, StepFault, StepOutput, StepRequest};
use crate::dynamics::System;
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup};
use super::{registry, MethodError};

/// How the stages apply `dexp⁻¹`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DexpInv {
    /// The method's economical exact-order choice: its commutator form
    /// ([`Tableau::brackets`], RK4: two commutators per step) if it has one,
    /// otherwise the series truncated after `ad^{q−2}` (`q` the order; since
    /// the odd Bernoulli numbers beyond `B₁` vanish, an odd `q − 2 ≥ 3` is
    /// lowered by one at no loss).
    #[default]
    Auto,
    /// The Bernoulli series truncated after `ad^m`
    /// ([`dexp_inv_series`], `m ≤ 20`); `m < q − 2` lowers the order.
    Series(usize),
    /// The group's closed form [`LieGroup::dexp_inv`] (exact).
    ClosedForm,
}

/// The resolved `dexp⁻¹` treatment of a step.
#[derive(Debug, Clone, Copy)]
enum Correction {
    Brackets(&'static BracketForm),
    Series(usize),
    Closed,
}

/// Default radius guard: `ρ(ad_θ) ≤ π`, half the convergence radius `2π` of
/// the Bernoulli series of `dexp⁻¹`.
pub const DEFAULT_RADIUS_LIMIT: f64 = std::f64::consts::PI;

/// A Runge–Kutta–Munthe-Kaas method with `S` stages.
///
/// ```
/// use framedyn::method::Rkmk;
/// let rk4 = Rkmk::rk4();                 // two-commutator RKMK4
/// let dp5 = Rkmk::dopri5();              // DOPRI5(4), adaptive + dense
/// # let _ = (rk4, dp5);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rkmk<const S: usize> {
    name: &'static str,
    tableau: &'static Tableau<S>,
    dexp_inv: DexpInv,
    radius_limit: f64,
    kernel: Kernel,
}

/// Which code runs a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kernel {
    /// The engine for every tableau (runtime tableau data, stage loops).
    General,
    /// [`Rkmk::rk4`]: `rk4_kernel`, the engine's RKMK4 step written out.
    Rk4,
}

impl Rkmk<1> {
    /// Lie–Euler, order 1 ([`tableau::LIE_EULER`]).
    pub const fn lie_euler() -> Self {
        Self::new(&tableau::LIE_EULER).named(registry::LIE_EULER.display)
    }
}

impl Rkmk<2> {
    /// RKMK2 on Heun's method, order 2 ([`tableau::HEUN`]; no `dexp⁻¹`
    /// correction is needed at order 2).
    pub const fn heun() -> Self {
        Self::new(&tableau::HEUN).named(registry::HEUN.display)
    }
}

impl Rkmk<3> {
    /// RKMK3 on Kutta's third-order method ([`tableau::KUTTA3`]), one
    /// commutator per stage (`dexp⁻¹ ≈ I + ½ad_θ`).
    pub const fn kutta3() -> Self {
        Self::new(&tableau::KUTTA3).named(registry::KUTTA3.display)
    }
}

impl Rkmk<4> {
    /// RKMK4 on the classical RK4 ([`tableau::RK4`]), by default in the
    /// two-commutator form [`tableau::RK4_BRACKETS`].
    ///
    /// Its plain steps (and those asking for `f` at either end) run a
    /// dedicated unrolled kernel that computes exactly what the general
    /// engine computes ([`Rkmk::new`]`(&tableau::RK4)` runs the general
    /// engine); dense-output steps and other `dexp⁻¹` treatments use the
    /// general engine.
    pub const fn rk4() -> Self {
        let mut m = Self::new(&tableau::RK4).named(registry::RK4.display);
        m.kernel = Kernel::Rk4;
        m
    }
}

impl Rkmk<7> {
    /// RKMK5 on Dormand–Prince 5(4) ([`tableau::DOPRI5`]): order 5, embedded
    /// order 4 for adaptive stepping, dense output of order 4, FSAL.
    pub const fn dopri5() -> Self {
        Self::new(&tableau::DOPRI5).named(registry::DOPRI5.display)
    }

    /// RKMK6 on Butcher's seven-stage sixth-order method
    /// ([`tableau::BUTCHER6`]), `dexp⁻¹` to `ad⁴`.
    pub const fn butcher6() -> Self {
        Self::new(&tableau::BUTCHER6).named(registry::BUTCHER6.display)
    }
}

impl Rkmk<12> {
    /// RKMK8 on DOP853 ([`tableau::DOP853`]): order 8, `dexp⁻¹` to `ad⁶`,
    /// the combined 5th/3rd-order error estimate of the code DOP853 for
    /// adaptive stepping, and its continuous extension of order 7 (3 extra
    /// evaluations of `f` per step, only when dense output is requested).
    pub const fn dop853() -> Self {
        Self::new(&tableau::DOP853).named(registry::DOP853.display)
    }
}

impl<const S: usize> Rkmk<S> {
    /// The RKMK method of `tableau` (named after it), with [`DexpInv::Auto`]
    /// and the radius guard [`DEFAULT_RADIUS_LIMIT`].
    pub const fn new(tableau: &'static Tableau<S>) -> Self {
        Rkmk { name: tableau.name, tableau, dexp_inv: DexpInv::Auto, radius_limit: DEFAULT_RADIUS_LIMIT, kernel: Kernel::General }
    }

    /// The same method with another `dexp⁻¹` treatment.
    pub const fn with_dexp_inv(mut self, mode: DexpInv) -> Self {
        self.dexp_inv = mode;
        if !matches!(mode, DexpInv::Auto) {
            // The unrolled RKMK4 kernel is the commutator form only.
            self.kernel = Kernel::General;
        }
        self
    }

    /// The same method with another radius guard `limit` (finite, `0 < limit < 2π`):
    /// a step fails with [`StepFault::DexpRadius`] if some algebra argument
    /// `θ` has `ρ(ad_θ) > limit`.
    pub fn with_radius_limit(mut self, limit: f64) -> Result<Self, MethodError> {
        if !(limit > 0.0 && limit < std::f64::consts::TAU) {
            return Err(MethodError::InvalidParameter {
                field: "radius_limit",
                value: limit,
                allowed: "in (0, 2π)",
            });
        }
        self.radius_limit = limit;
        Ok(self)
    }

    /// The same method under another display name ([`MethodInfo::name`]).
    pub const fn named(mut self, name: &'static str) -> Self {
        self.name = name;
        self
    }

    /// The display name ([`MethodInfo::name`]): the registry's for the
    /// named constructors, the tableau's for [`Rkmk::new`].
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// The tableau.
    pub const fn tableau(&self) -> &'static Tableau<S> {
        self.tableau
    }

    /// The `dexp⁻¹` treatment.
    pub const fn dexp_inv(&self) -> DexpInv {
        self.dexp_inv
    }

    fn correction(&self) -> Correction {
        match self.dexp_inv {
            DexpInv::Auto => match &self.tableau.brackets {
                Some(form) => Correction::Brackets(form),
                None => {
                    let d = (self.tableau.order as usize).saturating_sub(2);
                    Correction::Series(if d >= 3 && d % 2 == 1 { d - 1 } else { d })
                }
            },
            DexpInv::Series(m) => Correction::Series(m.min(20)),
            DexpInv::ClosedForm => Correction::Closed,
        }
    }

    /// [`Method::info`], which depends on the method only (so it is compiled
    /// once per stage count, not once per system).
    fn method_info(&self) -> MethodInfo {
        MethodInfo {
            name: self.name,
            order: self.tableau.order,
            embedded_order: self.tableau.embedded.map(|e| e.estimate_order()),
            dense_order: self.dense_order(),
            stages: S,
            fsal: self.tableau.is_fsal()
                && !matches!(self.correction(), Correction::Brackets(f) if !f.output.is_empty()),
            radius_limit: self.radius_limit,
        }
    }

    /// Order of the dense output: the tableau's continuous extension, else
    /// the cubic Hermite interpolant in `θ` (local error `O(h^{min(p,3)+1})`).
    fn dense_order(&self) -> u32 {
        match (&self.tableau.dense, self.tableau.dense_stages) {
            (Some(d), _) => d.order,
            (None, Some(ds)) => ds.dense.order,
            (None, None) => self.tableau.order.min(3),
        }
    }
}

/// `dexp⁻¹_{−θ} f` as the correction asks (identity for the commutator form).
#[inline(always)]
fn correct<G: LieGroup>(c: Correction, theta: &G::Algebra, f: &G::Algebra, cost: &mut StepCost) -> G::Algebra {
    match c {
        Correction::Brackets(_) | Correction::Series(0) => *f,
        Correction::Series(m) => {
            cost.brackets += m as u32;
            dexp_inv_series::<G>(&(-*theta), f, m)
        }
        Correction::Closed => {
            cost.dexp_inv += 1;
            G::dexp_inv(&(-*theta), f)
        }
    }
}

#[inline(always)]
fn guard<G: GroupNumerics>(theta: &G::Algebra, limit: f64, t_eval: f64, done: StepCost) -> Result<(), StepFault> {
    if G::within_radius(theta, limit) {
        return Ok(());
    }
    guard_fault::<G>(theta, limit, t_eval, done)
}

/// `f(t, y)` at a stage. A stage value that enters `Θ` with a non-zero
/// weight (`in_theta`) is not tested here: a non-finite `Kᵢ` makes `Θ`
/// non-finite (`bᵢh·∞`, `bᵢh·NaN`, `0·∞` are not finite, and adding finite
/// terms keeps them so), which the step tests once; the others are tested
/// here. A non-finite value that enters `Θ` shows first as a failed radius
/// guard at a later stage or as a non-finite `Θ`, and [`stage_fault`] then
/// reports it as that value's fault, as a per-stage test would have.
#[inline(always)]
fn eval_stage<Sys: System>(sys: &Sys, t: f64, y: &Sys::State, in_theta: bool) -> Result<Alg<Sys>, StepFault> {
    if in_theta {
        Ok(sys.vector_field(t, y))
    } else {
        eval(sys, t, y)
    }
}

/// The first non-finite stage value among `k` (stage `i` evaluated at
/// `t + cᵢh`), as a fault; `None` if all are finite (out of line: only
/// reached when a step fails).
#[cold]
#[inline(never)]
fn stage_fault<G: LieGroup>(k: &[G::Algebra], c: &[f64], t: f64, h: f64) -> Option<StepFault> {
    k.iter()
        .position(|ki| !ki.is_finite())
        .map(|i| StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: t + c[i] * h })
}

/// The failing branch of [`guard`] (out of line): the fault with the bound found.
#[cold]
#[inline(never)]
fn guard_fault<G: GroupNumerics>(theta: &G::Algebra, limit: f64, t_eval: f64, done: StepCost) -> Result<(), StepFault> {
    let r = G::ad_radius(theta);
    if r <= limit {
        Ok(())
    } else if r.is_nan() {
        Err(StepFault::NonFinite { source: NonFiniteSource::Increment, t_eval })
    } else {
        Err(StepFault::DexpRadius { radius: r, limit, cost: done })
    }
}

/// `h Σⱼ wⱼ kⱼ` over the non-zero weights (no multiplications by zero, no
/// explicit zero element unless every weight vanishes).
#[inline(always)]
fn combine<A: AlgebraVector>(k: &[A], w: &[f64], h: f64) -> A {
    combine_weights(k, w.iter().copied(), h)
}

/// [`combine`] with the weights given one by one.
#[inline(always)]
fn combine_weights<A: AlgebraVector>(k: &[A], w: impl Iterator<Item = f64>, h: f64) -> A {
    let mut acc: Option<A> = None;
    for (kj, wj) in k.iter().zip(w) {
        if wj != 0.0 {
            let term = *kj * (h * wj);
            acc = Some(match acc {
                Some(a) => a + term,
                None => term,
            });
        }
    }
    acc.unwrap_or_else(A::zero)
}

#[inline(always)]
fn eval<Sys: System>(sys: &Sys, t: f64, y: &Sys::State) -> Result<Alg<Sys>, StepFault> {
    let f = sys.vector_field(t, y);
    if f.is_finite() {
        Ok(f)
    } else {
        Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: t })
    }
}

/// The dense output of a continuous extension with stages of its own
/// ([`DenseStages`]): `K_S = dexp⁻¹_{−Θ} f(t₁, y₁)` from the step's end, the
/// extra stages as in the step, then `θ(σ) = h Σᵢ bᵢ(σ) Kᵢ`.
#[allow(clippy::too_many_arguments)]
fn extended_dense<Sys: System>(
    sys: &Sys,
    ds: &DenseStages,
    corr: Correction,
    k: &[Alg<Sys>],
    theta: &Alg<Sys>,
    f1: &Alg<Sys>,
    t: f64,
    h: f64,
    y0: &Sys::State,
    radius_limit: f64,
    cost: &mut StepCost,
) -> Result<DensePoly<Alg<Sys>>, StepFault>
where
    Sys::State: GroupNumerics,
{
    type G<Sys> = <Sys as System>::State;
    let s = k.len();
    let mut kk = [Alg::<Sys>::zero(); EXTENDED_STAGES];
    kk[..s].copy_from_slice(k);
    kk[s] = correct::<G<Sys>>(corr, theta, f1, cost);
    for i in s + 1..ds.stages {
        let th = combine(&kk[..i], &ds.a[i][..i], h);
        guard::<G<Sys>>(&th, radius_limit, t + ds.c[i] * h, *cost)?;
        let yi = y0.compose(&G::<Sys>::exp(&th));
        cost.exps += 1;
        cost.rhs += 1;
        let f = eval(sys, t + ds.c[i] * h, &yi)?;
        kk[i] = correct::<G<Sys>>(corr, &th, &f, cost);
    }
    // The weights reach ~550 while Σᵢ bᵢ(σ) = σ exactly: combining the
    // differences Kᵢ − K₁ (O(h)) instead of the Kᵢ keeps the cancellation
    // out of the coefficients (cᵐ = h Σᵢ wₘᵢ (Kᵢ − K₁) + δₘ₁ h K₁), and the
    // top coefficient is closed so that θ(1) = Θ to round-off.
    let n = ds.stages;
    for i in (1..n).rev() {
        kk[i] = kk[i] - kk[0];
    }
    let mut coeffs = [Alg::<Sys>::zero(); DENSE_DEGREE];
    let mut degree = 0;
    for (m, c) in coeffs.iter_mut().enumerate() {
        if ds.dense.coeffs[m].iter().any(|&w| w != 0.0) {
            *c = combine(&kk[1..n], &ds.dense.coeffs[m][1..n], h);
            degree = m + 1;
        }
    }
    coeffs[0] = coeffs[0] + kk[0] * h;
    if degree > 0 {
        let top = degree - 1;
        let mut rest = *theta;
        for c in &coeffs[..top] {
            rest = rest - *c;
        }
        coeffs[top] = rest;
    }
    Ok(DensePoly { coeffs, degree })
}

/// One two-commutator RKMK4 step ([`tableau::RK4`] with
/// [`tableau::RK4_BRACKETS`]) written out: what the general engine of
/// [`Rkmk::step`] does for this tableau with `req.dense` and `req.error`
/// unset, operation for operation (the same [`combine`] sums, guards, stage
/// tests, costs and faults), with the tableau's coefficients as constants.
#[inline(always)]
fn rk4_kernel<Sys: System>(
    sys: &Sys,
    t: f64,
    y0: &Sys::State,
    h: f64,
    f_start: Option<Alg<Sys>>,
    f_end: bool,
    radius_limit: f64,
) -> Result<StepOutput<Sys::State>, StepFault>
where
    Sys::State: GroupNumerics,
{
    type G<Sys> = <Sys as System>::State;
    const TAB: Tableau<4> = tableau::RK4;
    // The commutator coefficients of `RK4_BRACKETS` (θ₃ and Θ).
    const STAGE_BRACKET: f64 = tableau::RK4_BRACKETS.stages[0].1.coeff;
    const OUTPUT_BRACKET: f64 = tableau::RK4_BRACKETS.output[0].coeff;
    let mut cost = StepCost::default();
    // Every bᵢ ≠ 0: no stage value is tested on its own (see `eval_stage`).
    let k0 = match f_start {
        Some(f) => f,
        None => {
            cost.rhs += 1;
            sys.vector_field(t, y0)
        }
    };
    // Stage 2: θ₂ = (h/2) K₁.
    let th = combine(&[k0], &[TAB.a[1][0]], h);
    guard::<G<Sys>>(&th, radius_limit, t + TAB.c[1] * h, cost)
        .map_err(|e| stage_fault::<G<Sys>>(&[k0], &TAB.c, t, h).unwrap_or(e))?;
    let yi = y0.compose(&G::<Sys>::exp(&th));
    cost.exps += 1;
    cost.rhs += 1;
    let k1 = sys.vector_field(t + TAB.c[1] * h, &yi);
    // Stage 3: θ₃ = (h/2) K₂ + (h²/8)[K₁, K₂].
    let mut th = combine(&[k0, k1], &[TAB.a[2][0], TAB.a[2][1]], h);
    cost.brackets += 1;
    th = th + G::<Sys>::bracket(&k0, &k1) * (h * h * STAGE_BRACKET);
    guard::<G<Sys>>(&th, radius_limit, t + TAB.c[2] * h, cost)
        .map_err(|e| stage_fault::<G<Sys>>(&[k0, k1], &TAB.c, t, h).unwrap_or(e))?;
    let yi = y0.compose(&G::<Sys>::exp(&th));
    cost.exps += 1;
    cost.rhs += 1;
    let k2 = sys.vector_field(t + TAB.c[2] * h, &yi);
    // Stage 4: θ₄ = h K₃.
    let th = combine(&[k0, k1, k2], &[TAB.a[3][0], TAB.a[3][1], TAB.a[3][2]], h);
    guard::<G<Sys>>(&th, radius_limit, t + TAB.c[3] * h, cost)
        .map_err(|e| stage_fault::<G<Sys>>(&[k0, k1, k2], &TAB.c, t, h).unwrap_or(e))?;
    let yi = y0.compose(&G::<Sys>::exp(&th));
    cost.exps += 1;
    cost.rhs += 1;
    let k3 = sys.vector_field(t + TAB.c[3] * h, &yi);
    // Θ = h Σ bᵢ Kᵢ + (h²/12)[K₁, K₄].
    let k = [k0, k1, k2, k3];
    let mut theta = combine(&k, &TAB.b, h);
    cost.brackets += 1;
    theta = theta + G::<Sys>::bracket(&k0, &k3) * (h * h * OUTPUT_BRACKET);
    if !theta.is_finite() {
        return Err(stage_fault::<G<Sys>>(&k, &TAB.c, t, h)
            .unwrap_or(StepFault::NonFinite { source: NonFiniteSource::Increment, t_eval: t + h }));
    }
    guard::<G<Sys>>(&theta, radius_limit, t + h, cost)?;
    cost.exps += 1;
    let y1 = y0.compose(&G::<Sys>::exp(&theta)).renormalize();
    if !y1.is_finite() {
        return Err(StepFault::NonFinite { source: NonFiniteSource::State, t_eval: t + h });
    }
    let f_end = if f_end {
        cost.rhs += 1;
        Some(eval(sys, t + h, &y1)?)
    } else {
        None
    };
    Ok(StepOutput { y: y1, theta, f_start: k0, f_end, error: None, dense: None, cost })
}

impl<Sys: System, const S: usize> Method<Sys> for Rkmk<S>
where
    Sys::State: GroupNumerics,
{
    fn info(&self) -> MethodInfo {
        self.method_info()
    }

    fn tangent_step(&self, sys: &Sys, t: f64, y0: &Sys::State, h: f64, xi0: &Alg<Sys>) -> Option<super::TangentStep<Sys>> {
        Some(super::lifted_step(self, sys, t, y0, h, xi0))
    }

    // Forced inline only in optimised builds, where inlining specialises the
    // step on the caller's constant request; a hint in builds with debug
    // assertions (tests), where forcing it copied the whole step into each of
    // the driver's call sites (docs/development.md, "What the core's size is
    // made of").
    #[cfg_attr(not(debug_assertions), inline(always))]
    #[cfg_attr(debug_assertions, inline)]
    fn step(
        &self,
        sys: &Sys,
        t: f64,
        y0: &Sys::State,
        h: f64,
        req: StepRequest<Alg<Sys>>,
    ) -> Result<StepOutput<Sys::State>, StepFault> {
        if self.kernel == Kernel::Rk4 && !req.dense && !req.error {
            return rk4_kernel(sys, t, y0, h, req.f_start, req.f_end, self.radius_limit);
        }
        let tab = self.tableau;
        let corr = self.correction();
        let data = StageData {
            a: tab.a.as_flattened(),
            b: &tab.b,
            c: &tab.c,
            fsal: tab.is_fsal() && !matches!(corr, Correction::Brackets(f) if !f.output.is_empty()),
            solution_stages: tab.solution_stages(),
            b_hat: tab.embedded.as_ref().map(|e| &e.b_hat[..]),
            secondary: tab.embedded.as_ref().and_then(|e| e.secondary.as_ref()).map(|sec| (&sec.b_hat[..], sec.weight)),
            dense: tab.dense.as_ref().map(|d| d.coeffs.as_flattened()),
            dense_stages: tab.dense_stages,
        };
        let mut k = [Alg::<Sys>::zero(); S];
        general_step(sys, &data, corr, self.radius_limit, &mut k, t, y0, h, req)
    }
}

/// A tableau's coefficients as slices (`S` = `b.len()` stages, `a` and
/// `dense` row-major with rows of `S`): what the engine's stage loops read,
/// of the same type for every stage count, so that [`general_step`] is
/// compiled once per system, not once per system and stage count.
struct StageData {
    a: &'static [f64],
    b: &'static [f64],
    c: &'static [f64],
    /// The last stage is at the new state ([`Tableau::is_fsal`] and no
    /// output commutators).
    fsal: bool,
    solution_stages: usize,
    b_hat: Option<&'static [f64]>,
    /// DOP853's second embedded solution and its weight.
    secondary: Option<(&'static [f64], f64)>,
    dense: Option<&'static [f64]>,
    dense_stages: Option<&'static DenseStages>,
}

/// `h Σⱼ (wⱼ − vⱼ) kⱼ` over the non-zero differences: [`combine`] with the
/// weights `w − v`.
#[inline(always)]
fn combine_difference<A: AlgebraVector>(k: &[A], w: &[f64], v: &[f64], h: f64) -> A {
    combine_weights(k, w.iter().zip(v).map(|(&wj, &vj)| wj - vj), h)
}

/// The engine's step for every tableau ([`Rkmk::step`] without the RK4
/// kernel), `k` the stage buffer (one slot per stage). Forced inline only
/// in optimised builds, like [`Rkmk::step`]; in builds with debug
/// assertions it is one function per system, called by every stage count.
#[cfg_attr(not(debug_assertions), inline(always))]
#[allow(clippy::too_many_arguments)]
fn general_step<Sys: System>(
    sys: &Sys,
    tab: &StageData,
    corr: Correction,
    radius_limit: f64,
    k: &mut [Alg<Sys>],
    t: f64,
    y0: &Sys::State,
    h: f64,
    req: StepRequest<Alg<Sys>>,
) -> Result<StepOutput<Sys::State>, StepFault>
where
    Sys::State: GroupNumerics,
{
    type G<Sys> = <Sys as System>::State;
    let s = k.len();
    let fsal = tab.fsal;
    let native_dense = req.dense && tab.dense.is_some();
    let want_f_end = req.f_end || (req.dense && tab.dense.is_none());
    let n = if req.error || native_dense || (fsal && want_f_end) { s } else { tab.solution_stages };
    let mut cost = StepCost::default();

    // Stage 1: θ₁ = 0, K₁ = f(t₀, y₀).
    let k0 = match req.f_start {
        Some(f) => f,
        None => {
            cost.rhs += 1;
            eval_stage(sys, t, y0, tab.b[0] != 0.0)?
        }
    };
    k.fill(k0);
    let mut last_stage_state: Option<G<Sys>> = None;
    let mut fsal_raw: Option<Alg<Sys>> = None;
    for i in 1..n {
        // θᵢ = h Σⱼ aᵢⱼ Kⱼ.
        let mut th = combine(&k[..i], &tab.a[i * s..i * s + i], h);
        if let Correction::Brackets(form) = corr {
            for (stage, term) in form.stages {
                if *stage == i {
                    cost.brackets += 1;
                    th = th + G::<Sys>::bracket(&k[term.left], &k[term.right]) * (h * h * term.coeff);
                }
            }
        }
        guard::<G<Sys>>(&th, radius_limit, t + tab.c[i] * h, cost)
            .map_err(|e| stage_fault::<G<Sys>>(&k[..i], tab.c, t, h).unwrap_or(e))?;
        let yi = y0.compose(&G::<Sys>::exp(&th));
        cost.exps += 1;
        cost.rhs += 1;
        let f = eval_stage(sys, t + tab.c[i] * h, &yi, tab.b[i] != 0.0)?;
        k[i] = correct::<G<Sys>>(corr, &th, &f, &mut cost);
        if fsal && i == s - 1 {
            // θ_S = h Σ a_Sj K_j = Θ (a_S = b): y₀·exp(θ_S) is the new state
            // before renormalisation and F_S = f(t₁, y₁) starts the next step.
            last_stage_state = Some(yi);
            fsal_raw = Some(f);
        }
    }

    // Θ = h Σ bᵢ Kᵢ (+ output commutators).
    let mut theta = combine(&k[..n], &tab.b[..n], h);
    if let Correction::Brackets(form) = corr {
        for term in form.output {
            cost.brackets += 1;
            theta = theta + G::<Sys>::bracket(&k[term.left], &k[term.right]) * (h * h * term.coeff);
        }
    }
    if !theta.is_finite() {
        return Err(stage_fault::<G<Sys>>(&k[..n], tab.c, t, h)
            .unwrap_or(StepFault::NonFinite { source: NonFiniteSource::Increment, t_eval: t + h }));
    }
    guard::<G<Sys>>(&theta, radius_limit, t + h, cost)?;
    let unnormalised = match last_stage_state {
        Some(y) => y,
        None => {
            cost.exps += 1;
            y0.compose(&G::<Sys>::exp(&theta))
        }
    };
    let y1 = unnormalised.renormalize();
    if !y1.is_finite() {
        return Err(StepFault::NonFinite { source: NonFiniteSource::State, t_eval: t + h });
    }

    let error = match (tab.b_hat, req.error) {
        (Some(b_hat), true) => {
            let e1 = combine_difference(k, tab.b, b_hat, h);
            match tab.secondary {
                None => Some(e1),
                Some((sec_b_hat, sec_weight)) => {
                    // DOP853: err = ‖e₁‖²/√(‖e₁‖² + w‖e₂‖²) = ‖ρe₁‖ with
                    // ρ = ‖e₁‖/√(‖e₁‖² + w‖e₂‖²), the norms weighted by
                    // 1/(1 + max(sᵢ(y₀), sᵢ(y₁))) — the driver's norm for
                    // atol = rtol, up to the common factor tol.
                    let e2 = combine_difference(k, tab.b, sec_b_hat, h);
                    let (s0, s1) = (y0.tolerance_scale(), y1.tolerance_scale());
                    let (mut n1, mut n2) = (0.0, 0.0);
                    for i in 0..<Alg<Sys> as AlgebraVector>::LEN {
                        let sc = 1.0 + s0.get(i).max(s1.get(i));
                        n1 += (e1.get(i) / sc).powi(2);
                        n2 += (e2.get(i) / sc).powi(2);
                    }
                    let den = n1 + sec_weight * n2;
                    Some(if den > 0.0 { e1 * (n1 / den).sqrt() } else { e1 })
                }
            }
        }
        _ => None,
    };

    let f_end = if want_f_end {
        match fsal_raw {
            Some(f) => Some(f),
            None => {
                cost.rhs += 1;
                Some(eval(sys, t + h, &y1)?)
            }
        }
    } else {
        fsal_raw
    };

    let dense = if !req.dense {
        None
    } else if let Some(dw) = tab.dense {
        let mut coeffs = [Alg::<Sys>::zero(); DENSE_DEGREE];
        let mut degree = 0;
        for (m, c) in coeffs.iter_mut().enumerate() {
            let row = &dw[m * s..(m + 1) * s];
            if row.iter().any(|&w| w != 0.0) {
                *c = combine(k, row, h);
                degree = m + 1;
            }
        }
        Some(DensePoly { coeffs, degree })
    } else if let Some(ds) = tab.dense_stages {
        let f1 = f_end.unwrap_or_else(Alg::<Sys>::zero);
        Some(extended_dense::<Sys>(sys, ds, corr, k, &theta, &f1, t, h, y0, radius_limit, &mut cost)?)
    } else {
        // Cubic Hermite in θ: θ(0) = 0, θ'(0) = h K₁, θ(1) = Θ,
        // θ'(1) = h dexp⁻¹_{−Θ} f(t₁, y₁).
        let f1 = f_end.unwrap_or_else(Alg::<Sys>::zero);
        let s1 = match corr {
            Correction::Closed => {
                cost.dexp_inv += 1;
                G::<Sys>::dexp_inv(&(-theta), &f1)
            }
            _ => {
                cost.brackets += 2;
                dexp_inv_series::<G<Sys>>(&(-theta), &f1, 2)
            }
        };
        let (d0, d1) = (k[0] * h, s1 * h);
        let mut coeffs = [Alg::<Sys>::zero(); DENSE_DEGREE];
        coeffs[0] = d0;
        coeffs[1] = theta * 3.0 - d0 * 2.0 - d1;
        coeffs[2] = d0 + d1 - theta * 2.0;
        Some(DensePoly { coeffs, degree: 3 })
    };

    Ok(StepOutput { y: y1, theta, f_start: k[0], f_end, error, dense, cost })
}
