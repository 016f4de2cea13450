//! Adaptive stepping: error norm, controller and first-step selection
//! (see [`Adaptive`] for the definitions).

use super::{fault_error, tol_vector, Adaptive, Run, SolveError, StopReason};
use crate::dynamics::System;
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup};
use crate::method::{GroupNumerics, Method, MethodInfo, NonFiniteSource, StepFault, StepRequest};

/// Checks the tolerances, step bounds and controller, and that the method
/// has an embedded pair.
pub(super) fn validate<G: LieGroup>(a: &Adaptive, info: &MethodInfo) -> Result<(), SolveError> {
    if info.embedded_order.is_none() {
        return Err(SolveError::InvalidOptions {
            reason: format!("adaptive stepping needs an embedded pair; {} has none", info.name),
        });
    }
    let len = <G::Algebra as AlgebraVector>::LEN;
    for (name, tol) in [("rtol", &a.rtol), ("atol", &a.atol)] {
        let values: Vec<f64> = match tol {
            super::Tol::Scalar(v) => vec![*v],
            super::Tol::PerComponent(v) => {
                if v.len() != len {
                    return Err(SolveError::InvalidOptions {
                        reason: format!("{name} has {} components, the state algebra stores {len}", v.len()),
                    });
                }
                v.clone()
            }
        };
        for v in values {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SolveError::InvalidParameter { field: name, value: v, allowed: "finite and ≥ 0" });
            }
        }
    }
    let (r, at) = (tol_vector::<G::Algebra>(&a.rtol), tol_vector::<G::Algebra>(&a.atol));
    for i in 0..len {
        if r.get(i) + at.get(i) <= 0.0 {
            return Err(SolveError::InvalidOptions {
                reason: format!("component {i}: atol + rtol must be > 0"),
            });
        }
    }
    if let Some(h0) = a.h0 {
        if !(h0.is_finite() && h0 > 0.0) {
            return Err(SolveError::InvalidParameter { field: "h0", value: h0, allowed: "finite and > 0" });
        }
    }
    if !(a.h_min.is_finite() && a.h_min >= 0.0) {
        return Err(SolveError::InvalidParameter { field: "h_min", value: a.h_min, allowed: "finite and ≥ 0" });
    }
    if !(a.h_max > a.h_min && a.h_max > 0.0) {
        return Err(SolveError::InvalidParameter { field: "h_max", value: a.h_max, allowed: "> h_min and > 0" });
    }
    let c = &a.controller;
    let checks = [
        ("controller.beta", c.beta, (0.0..=0.2).contains(&c.beta), "in [0, 0.2]"),
        ("controller.safety", c.safety, c.safety > 0.0 && c.safety <= 1.0, "in (0, 1]"),
        ("controller.fac_min", c.fac_min, c.fac_min > 0.0 && c.fac_min <= 1.0, "in (0, 1]"),
        ("controller.fac_max", c.fac_max, c.fac_max >= 1.0 && c.fac_max.is_finite(), "finite and ≥ 1"),
    ];
    for (field, value, ok, allowed) in checks {
        if !ok {
            return Err(SolveError::InvalidParameter { field, value, allowed });
        }
    }
    Ok(())
}

/// `√(Σᵢ (eᵢ/scᵢ)²/LEN)` with `scᵢ = atolᵢ + rtolᵢ·max(s0ᵢ, s1ᵢ)`.
#[inline]
pub(crate) fn error_norm<A: AlgebraVector>(e: &A, s0: &A, s1: &A, atol: &A, rtol: &A) -> f64 {
    let mut sum = 0.0;
    for i in 0..A::LEN {
        let sc = atol.get(i) + rtol.get(i) * s0.get(i).max(s1.get(i));
        let q = e.get(i) / sc;
        sum += q * q;
    }
    (sum / A::LEN as f64).sqrt()
}

/// The adaptive loop.
pub(super) fn run<S, M>(run: &mut Run<'_, S, M>, a: &Adaptive) -> Result<StopReason, SolveError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let info = run.info;
    let q = info.order.min(info.embedded_order.unwrap_or(info.order));
    let expo = 1.0 / (q as f64 + 1.0);
    let ctl = a.controller;
    let alpha = expo - 0.75 * ctl.beta;
    let atol = tol_vector::<<S::State as LieGroup>::Algebra>(&a.atol);
    let rtol = tol_vector::<<S::State as LieGroup>::Algebra>(&a.rtol);
    let dir = run.dir;
    let span = (run.t_end - run.t0).abs();
    let h_max = a.h_max.min(span);

    let f0 = run.sys.vector_field(run.t0, &run.y);
    run.sol.stats.rhs_evals += 1;
    if !f0.is_finite() {
        return Err(SolveError::NonFinite { what: NonFiniteSource::VectorField, t_eval: run.t0, t: run.t0, h: 0.0 });
    }
    let mut h = match a.h0 {
        Some(h0) => h0.min(h_max),
        None => initial_step(run, &f0, &atol, &rtol, h_max, q)?,
    } * dir;
    let mut f_cache = Some(f0);
    let mut err_prev: f64 = 1e-4;
    let mut rejected_last = false;
    loop {
        let t = run.t;
        let remaining = run.t_end - t;
        if remaining * dir <= 0.0 {
            return Ok(StopReason::Finished);
        }
        if run.sol.stats.accepted >= run.opts.max_steps {
            return Err(SolveError::MaxSteps { t, h, max_steps: run.opts.max_steps });
        }
        let h_min = a.h_min.max(16.0 * f64::EPSILON * t.abs());
        let mut t1 = t + h;
        if (t1 - run.t_end) * dir >= 0.0 {
            h = remaining;
            t1 = run.t_end;
        } else if h.abs() < h_min {
            return Err(SolveError::StepSizeTooSmall { t, h, h_min });
        }
        // f(t₁, y₁) is free for FSAL methods; otherwise it is left to the
        // next step's first stage, so a rejected step does not pay for it.
        let req = StepRequest { f_start: f_cache, error: true, dense: run.need_dense, f_end: info.fsal };
        let out = match run.method.step(run.sys, t, &run.y, h, req) {
            Ok(out) => out,
            Err(StepFault::DexpRadius { radius, limit, cost }) => {
                // Too large for dexp⁻¹: a rejection, not a failure.
                run.sol.stats.add_cost(&cost);
                run.sol.stats.rejected += 1;
                run.sol.stats.rejected_radius += 1;
                h *= (ctl.safety * limit / radius).clamp(ctl.fac_min, ctl.safety);
                rejected_last = true;
                continue;
            }
            Err(fault) => return Err(fault_error(fault, t, h)),
        };
        run.sol.stats.add_cost(&out.cost);
        let Some(e) = out.error else {
            return Err(SolveError::InvalidOptions { reason: format!("{} returned no error estimate", info.name) });
        };
        let err = error_norm(&e, &run.y.tolerance_scale(), &out.y.tolerance_scale(), &atol, &rtol);
        if err.is_nan() {
            return Err(SolveError::NonFinite { what: NonFiniteSource::Increment, t_eval: t1, t, h });
        }
        if err <= 1.0 {
            let mut fac = (ctl.safety * err.powf(-alpha) * err_prev.powf(ctl.beta)).clamp(ctl.fac_min, ctl.fac_max);
            if rejected_last {
                fac = fac.min(1.0);
            }
            if fac.is_nan() {
                fac = ctl.fac_max;
            }
            err_prev = err.max(1e-4);
            rejected_last = false;
            f_cache = out.f_end;
            let stop = run.accept(t1, h, &out)?;
            if let Some(index) = stop {
                return Ok(StopReason::Event { index });
            }
            h = (h * fac).clamp(-h_max, h_max);
        } else {
            run.sol.stats.rejected += 1;
            f_cache = Some(out.f_start);
            h *= (ctl.safety * err.powf(-alpha)).max(ctl.fac_min);
            rejected_last = true;
        }
    }
}

/// First step after \[HNW93\] §II.4 ("Starting step size"), in the algebra:
/// `d₀ = ‖s(y₀)‖`, `d₁ = ‖f₀‖` in the scaled norm; `h = 0.01·d₀/d₁`; one
/// Lie–Euler step `y₁ = y₀·exp(h f₀)` gives `d₂ = ‖dexp⁻¹_{−hf₀}f(t₀+h, y₁) − f₀‖/h`;
/// `h₁ = (0.01/max(d₁, d₂))^{1/(q+1)}`; the result is `min(100h, h₁, h_max)`,
/// and `|h|·ρ(ad f₀)` at most half the radius guard.
fn initial_step<S, M>(
    run: &mut Run<'_, S, M>,
    f0: &<S::State as LieGroup>::Algebra,
    atol: &<S::State as LieGroup>::Algebra,
    rtol: &<S::State as LieGroup>::Algebra,
    h_max: f64,
    q: u32,
) -> Result<f64, SolveError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    // Scaled norms with scᵢ = atolᵢ + rtolᵢ·sᵢ(y₀).
    let s0 = run.y.tolerance_scale();
    let d0 = error_norm(&s0, &s0, &s0, atol, rtol);
    let d1 = error_norm(f0, &s0, &s0, atol, rtol);
    let mut h = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h = h.min(h_max);
    let rad = <S::State as GroupNumerics>::ad_radius(f0);
    let cap = 0.5 * run.info.radius_limit;
    if rad * h > cap {
        h = cap / rad;
    }
    let dir = run.dir;
    let th = *f0 * (h * dir);
    let y1 = run.y.compose(&<S::State as LieGroup>::exp(&th));
    let f1 = run.sys.vector_field(run.t0 + h * dir, &y1);
    run.sol.stats.rhs_evals += 1;
    run.sol.stats.exps += 1;
    if !f1.is_finite() {
        // The trial step left the domain of f: start far more cautiously.
        return Ok((h * 1e-3).max(f64::MIN_POSITIVE));
    }
    run.sol.stats.brackets += 2;
    let slope = dexp_inv_series::<S::State>(&(-th), &f1, 2);
    let d2 = error_norm(&(slope - *f0), &s0, &s0, atol, rtol) / h;
    let dmax = d1.max(d2);
    let h1 = if dmax <= 1e-15 { (h * 1e-3).max(1e-6) } else { (0.01 / dmax).powf(1.0 / (q as f64 + 1.0)) };
    Ok((100.0 * h).min(h1).min(h_max))
}
