//! Adaptive stepping: error norm, controller and first-step selection
//! (see [`Adaptive`] for the definitions).

use super::{Adaptive, SolveError, Stats, RTOL_MIN};
use crate::dynamics::System;
use crate::lie::{dexp_inv_series, AlgebraVector, LieGroup};
use crate::method::{GroupNumerics, MethodInfo};

/// Checks the tolerances (per-component ones against the `len` components
/// of the state's algebra), step bounds and controller, and that the method
/// has an embedded pair. Not generic, so compiled once.
pub(super) fn validate(a: &Adaptive, info: &MethodInfo, len: usize) -> Result<(), SolveError> {
    if info.embedded_order.is_none() {
        return Err(SolveError::InvalidOptions {
            reason: format!("adaptive stepping needs an embedded pair; {} has none", info.name),
        });
    }
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
            let (ok, allowed) = if name == "rtol" {
                (v.is_finite() && v >= RTOL_MIN, "finite and ≥ 1e-14 (below it the local error estimate is round-off and the step underflows)")
            } else {
                (v.is_finite() && v > 0.0, "finite and > 0")
            };
            if !ok {
                return Err(SolveError::InvalidParameter { field: name, value: v, allowed });
            }
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

/// `maxᵢ |eᵢ|/scᵢ` with `scᵢ = atolᵢ + rtolᵢ·max(s0ᵢ, s1ᵢ)`: a step passes
/// (`≤ 1`) only if every component's local error is within its own
/// tolerance. (A root-mean-square over the `LEN` components would let one
/// component's error reach `√LEN` times its tolerance, so that the same
/// `tol` meant a different accuracy for a point, `LEN = 5`, and an affine
/// body, `LEN = 13`.) NaN if any component is NaN.
#[inline]
pub fn error_norm<A: AlgebraVector>(e: &A, s0: &A, s1: &A, atol: &A, rtol: &A) -> f64 {
    let mut m = 0.0f64;
    for i in 0..A::LEN {
        let sc = atol.get(i) + rtol.get(i) * s0.get(i).max(s1.get(i));
        let q = (e.get(i) / sc).abs();
        if q.is_nan() {
            return f64::NAN;
        }
        m = m.max(q);
    }
    m
}

/// How often the automatic first step may be taken again (see
/// [`FIRST_STEP_PROBE_BELOW`]).
pub(super) const FIRST_STEP_PROBES: u32 = 3;

/// The first step is a probe. The step of [`initial_step`] comes from
/// first-order estimates and is deliberately small: DOP853's error norm on
/// it is typically 1e-6 … 1e-5, against the 0.15 its PI controller settles
/// at (`safety^{1/(α−β)}`). Accepted as it is, the run began with a ramp of
/// under-sized steps — with `α − β = 0.055` the controller grows the step
/// by only 1.1 – 2× per step while the error stays far below its target —
/// and on a short run at a loose tolerance that ramp was most of the run,
/// so the error fell far below `tol` there and was proportional to `tol`
/// only at tight tolerances (0.009 × tol at 1e-6 and 0.64 × tol at 1e-12 on
/// an escape on H², a fitted slope of 0.72). So while the controller's own
/// next step, `err·(safety·err^{−α}·err_prev^β)^{q+1}` for an estimate
/// `O(h^{q+1})`, would still leave the error below this value, the first
/// step is not accepted but taken again with `h·clamp((aim/err)^{1/(q+1)},
/// 1, fac_max)`, `aim = safety^{1/(α−β)}`, at most [`FIRST_STEP_PROBES`]
/// times (never for a first step the user gives as `h0`, one that reaches
/// `t_end` or one at `h_max`). DOPRI5, whose controller climbs from its
/// first step in one or two steps, is rarely probed. The probes' work is
/// counted in the statistics, as `first_step_probes`, not as rejections.
pub(super) const FIRST_STEP_PROBE_BELOW: f64 = 1e-2;

/// The smallest step the driver takes away from `t_end`: `max(h_min,
/// 16ε·max(|t|, |t_end|))`. Relative to the size of the span's times, so that
/// a run starting at `t = 0` cannot shrink its step to zero either.
#[inline]
pub(super) fn min_step(h_min: f64, t: f64, t_end: f64) -> f64 {
    h_min.max(16.0 * f64::EPSILON * t.abs().max(t_end.abs()))
}

/// First step after \[HNW93\] §II.4 ("Starting step size"), in the algebra:
/// `d₀ = ‖s(y₀)‖`, `d₁ = ‖f₀‖` in the scaled norm; `h = 0.01·d₀/d₁`; one
/// Lie–Euler step `y₁ = y₀·exp(h f₀)` gives `d₂ = ‖dexp⁻¹_{−hf₀}f(t₀+h, y₁) − f₀‖/h`;
/// `h₁ = (0.01/max(d₁, d₂))^{1/(q+1)}`; the result is `min(100h, h₁, h_max)`,
/// and `|h|·ρ(ad f₀)` at most half the radius guard. The norm is the
/// driver's ([`error_norm`]).
///
/// Fails with an error naming `atol` when the step it finds is below
/// [`min_step`] (`h_floor`): with `rtol ≥ 1e-14` ([`validate`]) that happens
/// when an absolute tolerance is so small that a component which is zero at
/// `t₀` (so only `atol` scales it) forces a step that underflows.
#[allow(clippy::too_many_arguments)]
pub(super) fn initial_step<S>(
    sys: &S,
    info: &MethodInfo,
    t0: f64,
    y0: &S::State,
    dir: f64,
    f0: &<S::State as LieGroup>::Algebra,
    atol: &<S::State as LieGroup>::Algebra,
    rtol: &<S::State as LieGroup>::Algebra,
    h_max: f64,
    h_floor: f64,
    q: u32,
    stats: &mut Stats,
) -> Result<f64, SolveError>
where
    S: System,
    S::State: GroupNumerics,
{
    // Scaled norms with scᵢ = atolᵢ + rtolᵢ·sᵢ(y₀).
    let s0 = y0.tolerance_scale();
    let d0 = error_norm(&s0, &s0, &s0, atol, rtol);
    let d1 = error_norm(f0, &s0, &s0, atol, rtol);
    let mut h = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h = h.min(h_max);
    let rad = <S::State as GroupNumerics>::ad_radius(f0);
    let cap = 0.5 * info.radius_limit;
    if rad * h > cap {
        h = cap / rad;
    }
    let th = *f0 * (h * dir);
    let y1 = y0.compose(&<S::State as LieGroup>::exp(&th));
    let f1 = sys.vector_field(t0 + h * dir, &y1);
    stats.rhs_evals += 1;
    stats.exps += 1;
    let underflow = |h: f64| -> Result<f64, SolveError> {
        if h >= h_floor {
            return Ok(h);
        }
        let smallest = (0..<<S::State as LieGroup>::Algebra as AlgebraVector>::LEN).map(|i| atol.get(i)).fold(f64::INFINITY, f64::min);
        Err(SolveError::InvalidParameter {
            field: "atol",
            value: smallest,
            allowed: "large enough that the first step does not underflow (a component that is zero at t0 is scaled by atol alone)",
        })
    };
    if !f1.is_finite() {
        // The trial step left the domain of f: start far more cautiously.
        return underflow((h * 1e-3).max(f64::MIN_POSITIVE));
    }
    stats.brackets += 2;
    let slope = dexp_inv_series::<S::State>(&(-th), &f1, 2);
    let d2 = error_norm(&(slope - *f0), &s0, &s0, atol, rtol) / h;
    let dmax = d1.max(d2);
    let h1 = if dmax <= 1e-15 { (h * 1e-3).max(1e-6) } else { (0.01 / dmax).powf(1.0 / (q as f64 + 1.0)) };
    underflow((100.0 * h).min(h1).min(h_max))
}

