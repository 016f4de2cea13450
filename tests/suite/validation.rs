//! Reproduction of the paper's claims of §4–§6 (issue 8), one test per claim,
//! named after it with the paper's equation labels. The measured numbers are
//! collected in `docs/validation.md`; the heavier measurements and the
//! figures come from `cargo run --release --example validation_figures`.
//!
//! Every test also shows the contrary case (a non-Bertrand potential, a force
//! that is not perpendicular, `I ≠ mR²`, …), so that it can fail.

#[path = "validation_actions.rs"]
mod actions;
#[path = "validation_affine.rs"]
mod affine;
#[path = "validation_errors.rs"]
mod errors;
#[path = "validation_bertrand.rs"]
mod bertrand;
#[path = "validation_s3.rs"]
mod s3;
#[path = "validation_spin.rs"]
mod spin;
#[path = "validation_tops.rs"]
mod tops;

use framedyn::dynamics::System;
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::solve::{solve, Options, Problem, Solution};

/// Adaptive DOPRI5 from `y0` over `[0, t_end]` at `rtol = atol = tol`, with
/// the extra options of `configure` (events, observers, saving).
pub fn run<S>(sys: &S, y0: S::State, t_end: f64, tol: f64, configure: impl FnOnce(Options<S::State>) -> Options<S::State>) -> Solution<S::State>
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let problem = Problem::new(sys.clone(), y0, (0.0, t_end)).expect("valid problem");
    match solve(&problem, &Rkmk::dopri5(), &configure(Options::adaptive(tol, tol))) {
        Ok(sol) => sol,
        Err(f) => panic!("solve failed: {:?}", f.error),
    }
}

/// Fixed-step RKMK (Butcher 6) from `y0` over `[0, t_end]` in `n` steps;
/// the final state.
pub fn run_fixed<S>(sys: &S, y0: S::State, t_end: f64, n: usize) -> S::State
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let problem = Problem::new(sys.clone(), y0, (0.0, t_end)).expect("valid problem");
    let sol = solve(&problem, &Rkmk::butcher6(), &Options::fixed(t_end / n as f64).save(framedyn::solve::Save::Ends))
        .unwrap_or_else(|f| panic!("solve failed: {:?}", f.error));
    *sol.last().1
}

/// Least-squares slope of `log y` against `log x`.
pub fn loglog_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Brent root of `f` on `[a, b]` (`f(a)·f(b) ≤ 0`) to `xtol`.
pub fn root(f: impl Fn(f64) -> f64, a: f64, b: f64, xtol: f64) -> f64 {
    let (fa, fb) = (f(a), f(b));
    assert!(fa * fb <= 0.0, "root not bracketed: f({a}) = {fa}, f({b}) = {fb}");
    framedyn::solve::event::brent(&f, a, b, fa, fb, xtol).0
}

/// `∫_a^b √f(r) dr` for `f` with simple zeros at `a` and `b` (positive in
/// between): substitution `r = (a + b)/2 − (b − a)/2·cos χ`, which makes the
/// integrand smooth and periodic, then the trapezoidal rule in `χ ∈ [0, π]`
/// with `n` points (spectrally accurate).
pub fn sqrt_integral(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let (c, d) = (0.5 * (a + b), 0.5 * (b - a));
    let h = std::f64::consts::PI / n as f64;
    let mut sum = 0.0;
    for k in 1..n {
        let chi = k as f64 * h;
        let r = c - d * chi.cos();
        sum += f(r).max(0.0).sqrt() * d * chi.sin();
    }
    sum * h
}
