//! The implicit Lie midpoint rule: a symmetric, second-order Lie-group
//! method for systems without an exact free flow (the T² gyroscope, affine
//! bodies), the energy-stable option where [`Splitting`](super::Splitting)
//! does not apply.
//!
//! One step from `(t₀, y₀)` solves for `Θ ∈ 𝔤`
//! ```text
//! Θ = h·f(t₀ + h/2, y₀·exp(Θ/2)),        y₁ = y₀·exp(Θ)
//! ```
//! (the RKMK method of the implicit midpoint rule, `dexp⁻¹` truncated to the
//! identity at order 2 \[IMNZ00\]). **Symmetric:** the step from `y₁` with
//! `−h` is solved by `−Θ` (its midpoint `y₁·exp(−Θ/2) = y₀·exp(Θ/2)` is the
//! same), so it returns `y₀` exactly; symmetric methods have even order and,
//! on reversible systems, no secular energy drift \[HLW06, XI\].
//!
//! **Newton.** The residual `F(Θ) = Θ − h f(t₀ + h/2, y₀ exp(Θ/2))` is solved
//! by simplified Newton iterations from the explicit guess `Θ₀ = h f(t₀, y₀)`,
//! with the Jacobian `I − h ∂f/∂Θ` by forward differences (one evaluation of
//! `f` per algebra component), factored by nalgebra's partial-pivoting dense
//! LU (a few heap allocations per step; why not faer: docs/development.md,
//! "Dependencies"). The Jacobian is refreshed once if the iteration contracts
//! slower than `1/2`. Converged when the update falls below `tol·max(1, |Θ|)`
//! (max norm); otherwise — too many iterations, a non-finite value, or a
//! singular Jacobian — the step fails with [`StepFault::NoConvergence`]
//! carrying the iterations and the last update (the driver adds `t` and `h`).
//! Never a silently accepted step.
//!
//! \[IMNZ00\] A. Iserles, H. Z. Munthe-Kaas, S. P. Nørsett, A. Zanna,
//! *Lie-group methods*, Acta Numerica 9 (2000) 215–365. \[HLW06\] E. Hairer,
//! C. Lubich, G. Wanner, *Geometric Numerical Integration*, 2nd ed., Springer 2006.

use nalgebra::{DMatrix, DVector, Dyn, LU};

use super::group::GroupNumerics;
use super::{Alg, DensePoly, Method, MethodInfo, NonFiniteSource, StepCost, StepFault, StepOutput, StepRequest};
use crate::dynamics::System;
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup};
use super::MethodError;

use super::tableau::DENSE_DEGREE;

/// The implicit Lie midpoint rule (order 2, symmetric).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitMidpoint {
    tol: f64,
    max_iter: u32,
}

impl Default for ImplicitMidpoint {
    fn default() -> Self {
        Self::new()
    }
}

impl ImplicitMidpoint {
    /// Newton tolerance 1e-14 (relative, max norm), at most 30 iterations.
    pub const fn new() -> Self {
        ImplicitMidpoint { tol: 1e-14, max_iter: 30 }
    }

    /// The same method with Newton tolerance `tol` (finite, in
    /// `[1e-16, 1e-2]`) and at most `max_iter` iterations (`1 ..= 1000`).
    pub fn with_newton(mut self, tol: f64, max_iter: u32) -> Result<Self, MethodError> {
        if !(tol.is_finite() && (1e-16..=1e-2).contains(&tol)) {
            return Err(MethodError::InvalidParameter { field: "newton_tol", value: tol, allowed: "in [1e-16, 1e-2]" });
        }
        if !(1..=1000).contains(&max_iter) {
            return Err(MethodError::InvalidParameter { field: "newton_max_iter", value: f64::from(max_iter), allowed: "in 1 ..= 1000" });
        }
        self.tol = tol;
        self.max_iter = max_iter;
        Ok(self)
    }
}

/// Work buffers of one step: the Jacobian, the right-hand side (the
/// update after [`Work::solve`]) and the Jacobian's LU factors.
struct Work {
    jac: DMatrix<f64>,
    rhs: DVector<f64>,
    lu: Option<LU<f64, Dyn, Dyn>>,
}

impl Work {
    fn new(n: usize) -> Self {
        Work { jac: DMatrix::zeros(n, n), rhs: DVector::zeros(n), lu: None }
    }

    /// LU-factors the Jacobian (partial pivoting); false if it is not
    /// finite or a pivot is zero.
    fn factor(&mut self) -> bool {
        if self.jac.iter().any(|v| !v.is_finite()) {
            return false;
        }
        let lu = self.jac.clone().lu();
        let ok = lu.is_invertible();
        self.lu = Some(lu);
        ok
    }

    /// Solves `J x = rhs` in place in `rhs` with the factors.
    fn solve(&mut self) {
        if let Some(lu) = &self.lu {
            lu.solve_mut(&mut self.rhs);
        }
    }
}

#[inline]
fn max_abs<A: AlgebraVector>(a: &A) -> f64 {
    (0..A::LEN).fold(0.0f64, |m, i| m.max(a.get(i).abs()))
}

impl ImplicitMidpoint {
    /// `G(Θ) = f(t_m, y₀ exp(Θ/2))`.
    #[inline]
    fn g<S: System>(sys: &S, tm: f64, y0: &S::State, theta: &Alg<S>) -> Alg<S> {
        sys.vector_field(tm, &y0.compose(&S::State::exp(&(*theta * 0.5))))
    }

    /// Forward-difference Jacobian of `F(Θ) = Θ − hG(Θ)` at `Θ` with
    /// `G(Θ) = g0` known; `n` evaluations.
    fn jacobian<S: System>(sys: &S, tm: f64, y0: &S::State, theta: &Alg<S>, g0: &Alg<S>, h: f64, w: &mut Work, cost: &mut StepCost) {
        let n = w.rhs.len();
        for j in 0..n {
            let d = 1e-7 * theta.get(j).abs().max(1e-2);
            let mut tp = *theta;
            tp.set(j, theta.get(j) + d);
            let gp = Self::g(sys, tm, y0, &tp);
            cost.rhs += 1;
            cost.exps += 1;
            for i in 0..n {
                let dg = (gp.get(i) - g0.get(i)) / d;
                w.jac[(i, j)] = if i == j { 1.0 } else { 0.0 } - h * dg;
            }
        }
    }

    fn newton<S: System>(&self, sys: &S, t: f64, y0: &S::State, h: f64, f0: &Alg<S>, w: &mut Work, cost: &mut StepCost) -> Result<Alg<S>, StepFault> {
        let tm = t + 0.5 * h;
        let n = w.rhs.len();
        let mut theta = *f0 * h;
        let fail = |iterations: u32, residual: f64| StepFault::NoConvergence { iterations, residual, t_eval: tm };
        let mut g = Self::g(sys, tm, y0, &theta);
        cost.rhs += 1;
        cost.exps += 1;
        Self::jacobian(sys, tm, y0, &theta, &g, h, w, cost);
        if !w.factor() {
            return Err(fail(0, f64::INFINITY));
        }
        let mut refreshed = false;
        let mut prev = f64::INFINITY;
        for k in 1..=self.max_iter {
            let r = theta - g * h;
            for i in 0..n {
                w.rhs[i] = -r.get(i);
            }
            w.solve();
            let mut delta = Alg::<S>::zero();
            for i in 0..n {
                delta.set(i, w.rhs[i]);
            }
            theta = theta + delta;
            let step = max_abs(&delta);
            if !step.is_finite() || !theta.is_finite() {
                return Err(fail(k, step));
            }
            let scale = max_abs(&theta).max(1.0);
            if step <= self.tol * scale {
                return Ok(theta);
            }
            g = Self::g(sys, tm, y0, &theta);
            cost.rhs += 1;
            cost.exps += 1;
            if !g.is_finite() {
                return Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: tm });
            }
            // Round-off stagnation at a tiny update: converged to what the
            // arithmetic allows.
            if step >= prev && step <= 1e3 * self.tol * scale {
                return Ok(theta);
            }
            if step > 0.5 * prev {
                if refreshed {
                    if step > prev {
                        return Err(fail(k, step));
                    }
                } else {
                    refreshed = true;
                    Self::jacobian(sys, tm, y0, &theta, &g, h, w, cost);
                    if !w.factor() {
                        return Err(fail(k, step));
                    }
                }
            }
            prev = step;
        }
        Err(fail(self.max_iter, prev))
    }
}

impl<S> Method<S> for ImplicitMidpoint
where
    S: System,
    S::State: GroupNumerics,
{
    fn info(&self) -> MethodInfo {
        MethodInfo {
            name: super::registry::IMPLICIT_MIDPOINT.display,
            order: 2,
            embedded_order: None,
            dense_order: 2,
            stages: 1,
            fsal: false,
            radius_limit: f64::INFINITY,
        }
    }

    /// The Newton iteration solves the lifted midpoint equations, whose
    /// tangent part is the linearisation of the plain ones: the tangent
    /// image is exact up to the Newton tolerance.
    fn tangent_step(&self, sys: &S, t: f64, y0: &S::State, h: f64, xi0: &Alg<S>) -> Option<super::TangentStep<S>> {
        Some(super::lifted_step(self, sys, t, y0, h, xi0))
    }

    fn step(
        &self,
        sys: &S,
        t: f64,
        y0: &S::State,
        h: f64,
        req: StepRequest<Alg<S>>,
    ) -> Result<StepOutput<S::State>, StepFault> {
        let n = <Alg<S> as AlgebraVector>::LEN;
        let mut cost = StepCost::default();
        let f0 = match req.f_start {
            Some(f) => f,
            None => {
                cost.rhs += 1;
                sys.vector_field(t, y0)
            }
        };
        if !f0.is_finite() {
            return Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: t });
        }
        let mut w = Work::new(n);
        let theta = self.newton(sys, t, y0, h, &f0, &mut w, &mut cost)?;
        let y1 = y0.compose(&S::State::exp(&theta)).renormalize();
        cost.exps += 1;
        if !y1.is_finite() {
            return Err(StepFault::NonFinite { source: NonFiniteSource::State, t_eval: t + h });
        }
        let mut out = StepOutput { y: y1, theta, f_start: f0, f_end: None, error: None, dense: None, cost };
        if req.f_end || req.dense {
            let f1 = sys.vector_field(t + h, &y1);
            out.cost.rhs += 1;
            if !f1.is_finite() {
                return Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: t + h });
            }
            out.f_end = Some(f1);
            if req.dense {
                // Cubic Hermite in θ (local error O(h³), the method's order).
                out.cost.brackets += 2;
                let d0 = f0 * h;
                let d1 = dexp_inv_series::<S::State>(&(-theta), &f1, 2) * h;
                let mut coeffs = [Alg::<S>::zero(); DENSE_DEGREE];
                coeffs[0] = d0;
                coeffs[1] = theta * 3.0 - d0 * 2.0 - d1;
                coeffs[2] = d0 + d1 - theta * 2.0;
                out.dense = Some(DensePoly { coeffs, degree: 3 });
            }
        }
        Ok(out)
    }
}
