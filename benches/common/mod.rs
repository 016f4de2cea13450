//! Support code of the measurements shared by the criterion benches
//! (`benches/step_cost.rs`), the work-precision harness
//! (`examples/work_precision.rs`, driven by `scripts/work_precision.py`), the
//! stability maps (`examples/stability.rs`) and the scene timing
//! (`examples/scene_timing.rs`): the thread-CPU clock, the distance of
//! observables, and the method table with its runners.
//!
//! The reference problems themselves — model, initial state, span, the
//! observable and the momentum map — are in the library, `framedyn::testing`
//! (one file per manifold, each problem defined once with its parameters and
//! checked by `tests/suite/testing.rs`).
//!
//! **Adding a method.** The table [`rkmk_table`] lists `(name, runner)`
//! pairs; a runner solves a [`Reference`] at one step size or tolerance and
//! returns an [`Outcome`]. Any type implementing [`Method<S>`] is added with
//! one line, e.g. for a splitting method that only exists for the S²
//! gyroscope, in `examples/work_precision.rs` (function `s2_entries`):
//! `t.push(fixed("Strang", 2, Strang::new()));`. Coordinate baselines push an
//! [`Entry`] whose runner integrates their own state and maps it to the
//! observable (see `coords_rk4` in the example).
#![allow(dead_code)]

use framedyn::dynamics::System;
use framedyn::method::{GroupNumerics, Method, Rkmk};
use framedyn::solve::{solve, Options, Save, Stepper};
use framedyn::testing::Reference;

/// Thread-CPU seconds (`CLOCK_THREAD_CPUTIME_ID`, as Python's
/// `time.thread_time()`): time the thread was descheduled by other processes
/// on the shared machine is not counted. Shared by the benches and the
/// timing examples.
pub fn thread_time() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Max-norm distance of two observables.
pub fn obs_dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------
// Running a method: the table
// ---------------------------------------------------------------------------

/// The result of one run at one setting.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// Observable at `t_end` (empty on failure).
    pub obs: Vec<f64>,
    /// Thread-CPU seconds of the timed run (minimum over repeats).
    pub cpu: f64,
    /// Vector-field evaluations.
    pub rhs: usize,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// `max |E(t) − E(0)|` over the accepted steps.
    pub energy_drift: f64,
    /// `max |J(t) − J(0)|` of the momentum map over the accepted steps.
    pub momentum_drift: f64,
    /// Largest [`System::defect`] over the accepted steps.
    pub defect: f64,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

/// A runner: solves a reference at a step size (fixed methods) or a
/// tolerance (adaptive ones), timed with `clock` (a thread-CPU clock in
/// seconds).
pub type Runner<S> = Box<dyn Fn(&Reference<S>, f64, &dyn Fn() -> f64) -> Outcome>;

/// One row of the method table.
pub struct Entry<S: System> {
    /// Method name (CSV key).
    pub name: &'static str,
    /// Order (of the propagated solution).
    pub order: u32,
    /// `true`: the setting is a tolerance; `false`: a step size.
    pub adaptive: bool,
    /// The runner.
    pub run: Runner<S>,
}

/// Minimum thread-CPU time of `f` over repeats (at least one run, repeats
/// until 0.05 s have been spent or 5 runs), and the last result.
pub fn timed<T>(clock: &dyn Fn() -> f64, mut f: impl FnMut() -> T) -> (f64, T) {
    let (mut best, mut spent, mut k) = (f64::INFINITY, 0.0, 0);
    loop {
        let t0 = clock();
        let r = f();
        let dt = clock() - t0;
        best = best.min(dt);
        spent += dt;
        k += 1;
        if spent >= 0.05 || k >= 5 {
            return (best, r);
        }
    }
}

/// Runs a group method with `n = ⌈T/h⌉` fixed steps: timed pass through
/// [`solve`] (final state only), then an untimed pass with a [`Stepper`]
/// recording energy, momentum and defect after every step.
pub fn run_fixed<S, M>(r: &Reference<S>, method: &M, h: f64, clock: &dyn Fn() -> f64) -> Outcome
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let problem = r.problem().expect("valid reference problem");
    let opts = Options::fixed(h).save(Save::Ends).max_steps(usize::MAX);
    let (cpu, res) = timed(clock, || solve(&problem, method, &opts));
    let sol = match res {
        Ok(s) => s,
        Err(f) => return Outcome { cpu, failure: Some(format!("{}", f.error)), ..Outcome::default() },
    };
    let mut out = Outcome {
        obs: (r.observable)(&r.system, sol.last().1),
        cpu,
        rhs: sol.stats().rhs_evals,
        steps: sol.stats().accepted,
        rejected: sol.stats().rejected,
        ..Outcome::default()
    };
    let n = (r.t_end / h).ceil() as usize;
    let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
    let mut st = Stepper::new(r.system.clone(), method.clone(), 0.0, r.y0).expect("stepper");
    let hh = r.t_end / n as f64;
    for _ in 0..n {
        if st.step(hh).is_err() {
            break;
        }
        let y = st.state();
        out.energy_drift = out.energy_drift.max((r.system.energy(y) - e0).abs());
        out.momentum_drift = out.momentum_drift.max(((r.momentum)(&r.system, y) - j0).abs());
        out.defect = out.defect.max(r.system.defect(y));
    }
    out
}

/// Runs a group method adaptively at `rtol = atol = tol`: timed pass (final
/// state only), then an untimed pass saving every step for the invariants.
pub fn run_adaptive<S, M>(r: &Reference<S>, method: &M, tol: f64, clock: &dyn Fn() -> f64) -> Outcome
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let problem = r.problem().expect("valid reference problem");
    let opts = Options::adaptive(tol, tol).save(Save::Ends).max_steps(10_000_000);
    let (cpu, res) = timed(clock, || solve(&problem, method, &opts));
    let sol = match res {
        Ok(s) => s,
        Err(f) => return Outcome { cpu, failure: Some(format!("{}", f.error)), ..Outcome::default() },
    };
    let mut out = Outcome {
        obs: (r.observable)(&r.system, sol.last().1),
        cpu,
        rhs: sol.stats().rhs_evals,
        steps: sol.stats().accepted,
        rejected: sol.stats().rejected,
        ..Outcome::default()
    };
    let opts = Options::adaptive(tol, tol).save(Save::Steps).max_steps(10_000_000);
    if let Ok(sol) = solve(&problem, method, &opts) {
        let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
        for y in sol.states() {
            out.energy_drift = out.energy_drift.max((r.system.energy(y) - e0).abs());
            out.momentum_drift = out.momentum_drift.max(((r.momentum)(&r.system, y) - j0).abs());
            out.defect = out.defect.max(r.system.defect(y));
        }
    }
    out
}

/// A fixed-step table entry for any [`Method`].
pub fn fixed<S, M>(name: &'static str, order: u32, method: M) -> Entry<S>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
    M: Method<S> + 'static,
{
    Entry { name, order, adaptive: false, run: Box::new(move |r, h, c| run_fixed(r, &method, h, c)) }
}

/// An adaptive table entry for any [`Method`] with an embedded pair.
pub fn adaptive<S, M>(name: &'static str, order: u32, method: M) -> Entry<S>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
    M: Method<S> + 'static,
{
    Entry { name, order, adaptive: true, run: Box::new(move |r, tol, c| run_adaptive(r, &method, tol, c)) }
}

/// The RKMK family on any system: Lie–Euler, Heun, Kutta 3, RK4
/// (two-commutator RKMK4), Butcher 6 with fixed steps, DOPRI5 adaptive.
/// Methods for every system are added here; system-specific ones (splittings
/// of the S² gyroscope, coordinate baselines) in the example's per-problem
/// functions.
pub fn rkmk_table<S>() -> Vec<Entry<S>>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
{
    vec![
        fixed("lie_euler", 1, Rkmk::lie_euler()),
        fixed("heun", 2, Rkmk::heun()),
        fixed("kutta3", 3, Rkmk::kutta3()),
        fixed("rkmk4", 4, Rkmk::rk4()),
        fixed("dopri5_fixed", 5, Rkmk::dopri5()),
        fixed("butcher6", 6, Rkmk::butcher6()),
        adaptive("dopri5", 5, Rkmk::dopri5()),
    ]
}

/// Step sizes for a method of order `p` over a span: from coarse (error
/// ≈ 1e-2) to the round-off floor, 2^{1/2} apart, capped at `max_steps`.
pub fn step_ladder(p: u32, t_end: f64, max_steps: f64) -> Vec<f64> {
    // Coarsest step: where the methods of each order start to be accurate on
    // the reference problems (|f| ~ 1); finest: 1e-12-ish error or budget.
    let (h_max, h_min): (f64, f64) = match p {
        1 => (0.05, 1e-4),
        2 => (0.2, 2e-4),
        3 => (0.3, 1e-3),
        4 => (0.5, 2e-3),
        5 => (0.6, 5e-3),
        _ => (0.8, 1e-2),
    };
    let h_min = h_min.max(t_end / max_steps);
    let mut v = Vec::new();
    let mut h = h_max;
    while h >= h_min * 0.999 {
        v.push(h);
        h /= 2f64.sqrt();
    }
    v
}

/// Tolerances for adaptive methods: 1e-3 … 1e-12 in half decades.
pub fn tol_ladder() -> Vec<f64> {
    (6..=24).map(|k| 10f64.powf(-(k as f64) / 2.0)).collect()
}
