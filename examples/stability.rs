//! Stability data for `docs/stability.md`: where each method fails.
//!
//! Run through the documented command `python3 scripts/stability.py` (which
//! also runs scipy on the pole trajectory and draws the charts), or alone:
//! `cargo run --profile measure --example stability -- --out docs/data [--quick] [--long-steps N] [--only SECTIONS]`
//! (`--only steps,bounce` reruns those sections; the output is deterministic
//! apart from the CPU times).
//!
//! Writes into `--out`:
//! - `stability_steps.csv`: the largest stable fixed step against stiffness
//!   (elastic κ of the S² affine body; spin ω and curvature radius R of the
//!   S² gyroscope) for the RKMK methods, the splittings, the implicit Lie
//!   midpoint rule and the coordinate baselines;
//! - `stability_pole.csv`, `stability_pole_problem.csv`: the S² gyroscope
//!   swinging through the pole, group methods against the coordinate
//!   baselines (error, thread-CPU time, evaluations), and the problem (chart
//!   initial state, reference observable) for the scipy runs of the script;
//! - `stability_h2.csv`: a free gyroscope escaping to infinity on H²,
//!   compared with the closed-form free motion;
//! - `stability_long.csv`, `stability_long_summary.csv`: energy error,
//!   momentum-map error and constraint defect sampled log-spaced in time over
//!   `--long-steps` (default 1e7) fixed steps;
//! - `stability_collapse.csv`, `stability_collapse_steps.csv`: the affine
//!   body collapsing in finite time: what adaptive DOPRI5 and each fixed-step
//!   method do.

#[path = "../benches/common/mod.rs"]
mod common;

use std::io::Write;

use common::*;
use framedyn::body::{Affine, Gyroscope};
use framedyn::dynamics::affine::AffineModel;
use framedyn::dynamics::point::bundle_element_at;
use framedyn::dynamics::{Gyroscope2Model, System};
use framedyn::lie::So12;
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2};
use framedyn::method::baseline::{ChartSystem, CoordinateRk};
use framedyn::method::{GroupNumerics, ImplicitMidpoint, Method, Rkmk, Splitting};
use framedyn::potential::{Centre, CosineFamily, Elastic, Sum};
use framedyn::solve::{solve, Options, Problem, Save, SolveError, Stepper};
use framedyn::testing::*;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

/// Command-line options.
struct Args {
    out: String,
    quick: bool,
    long_steps: usize,
    /// Sections to run (all by default): steps, pole, h2, collapse, bounce, long.
    only: Vec<String>,
}

impl Args {
    fn runs(&self, section: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|s| s == section)
    }
}

fn args() -> Args {
    let mut a = Args { out: "docs/data".into(), quick: false, long_steps: 10_000_000, only: Vec::new() };
    let mut it = std::env::args().skip(1);
    while let Some(x) = it.next() {
        match x.as_str() {
            "--out" => a.out = it.next().expect("--out DIR"),
            "--quick" => {
                a.quick = true;
                a.long_steps = a.long_steps.min(100_000);
            }
            "--only" => a.only = it.next().expect("--only SECTION[,SECTION...]").split(',').map(String::from).collect(),
            "--long-steps" => a.long_steps = it.next().and_then(|s| s.parse::<f64>().ok()).expect("--long-steps N") as usize,
            other => {
                eprintln!("unknown argument {other}; usage: stability [--out DIR] [--quick] [--long-steps N] [--only steps,pole,h2,collapse,bounce,long]");
                std::process::exit(2);
            }
        }
    }
    a
}

// ---------------------------------------------------------------------------
// The stability criterion
// ---------------------------------------------------------------------------

/// A run with fixed steps `h` over `[0, t_end]` is *stable* if every step
/// succeeds and the energy error after every step stays ≤ 10 % of
/// max(|E₀|, 1). `Err` says why not: the typed step error, or the time at
/// which the energy left the band.
fn is_stable<S, M>(sys: &S, y0: &S::State, t_end: f64, m: &M, h: f64) -> Result<(), String>
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let n = (t_end / h).ceil() as usize;
    let e0 = sys.energy(y0);
    let tol = 0.1 * e0.abs().max(1.0);
    let mut st = Stepper::new(sys.clone(), m.clone(), 0.0, *y0).map_err(|e| e.to_string())?;
    for _ in 0..n {
        st.step(t_end / n as f64).map_err(|e| {
            let s = e.to_string();
            // The kind of failure, without the numbers.
            s.split(':').next().unwrap_or(&s).split(" with h").next().unwrap_or(&s).to_string()
        })?;
        let e = sys.energy(st.state());
        if !((e - e0).abs() <= tol) {
            return Err(format!("energy error > 10 % at t = {:.3}", st.t()));
        }
    }
    Ok(())
}

/// The largest `h = 2^{−k/4}` (k ≥ 0, h ≥ 1e-5) such that `h` and the next
/// two smaller grid steps are stable (NaN if none), and why the next larger
/// grid step failed.
fn largest_stable<S, M>(sys: &S, y0: &S::State, t_end: f64, m: &M) -> (f64, String)
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let grid: Vec<f64> = (0..=66).map(|k| 2f64.powf(-(k as f64) / 4.0)).collect();
    let mut why = String::new();
    for i in 0..grid.len() - 2 {
        match (0..3).try_for_each(|j| is_stable(sys, y0, t_end, m, grid[i + j]).map_err(|e| (j, e))) {
            Ok(()) => return (grid[i], why),
            Err((j, e)) => {
                if j == 0 {
                    why = e.replace(',', ";");
                }
            }
        }
    }
    (f64::NAN, why)
}

/// One CSV row of the stable-step sweep.
fn stable_row(f: &mut std::fs::File, sweep: &str, p: f64, name: &str, (h, why): (f64, String)) -> std::io::Result<()> {
    writeln!(f, "{sweep},{p},{name},{h:e},{why}")
}

/// Runs `$body` with `$name`, `$m` bound to each fixed-step RKMK method and
/// the implicit Lie midpoint rule (every system).
macro_rules! each_general {
    ($name:ident, $m:ident, $body:block) => {{
        { let ($name, $m) = ("lie_euler", Rkmk::lie_euler()); $body }
        { let ($name, $m) = ("heun", Rkmk::heun()); $body }
        { let ($name, $m) = ("kutta3", Rkmk::kutta3()); $body }
        { let ($name, $m) = ("rkmk4", Rkmk::rk4()); $body }
        { let ($name, $m) = ("dopri5_fixed", Rkmk::dopri5()); $body }
        { let ($name, $m) = ("butcher6", Rkmk::butcher6()); $body }
        { let ($name, $m) = ("implicit_midpoint", ImplicitMidpoint::new()); $body }
    }};
}

/// Runs `$body` for each splitting method (constant-curvature gyroscopes).
macro_rules! each_splitting {
    ($name:ident, $m:ident, $body:block) => {{
        { let ($name, $m) = ("strang", Splitting::strang()); $body }
        { let ($name, $m) = ("yoshida4", Splitting::yoshida4()); $body }
        { let ($name, $m) = ("suzuki4", Splitting::suzuki4()); $body }
        { let ($name, $m) = ("blanes_moan4", Splitting::blanes_moan4()); $body }
        { let ($name, $m) = ("yoshida6", Splitting::yoshida6()); $body }
        { let ($name, $m) = ("blanes_moan6", Splitting::blanes_moan6()); $body }
        { let ($name, $m) = ("blanes_moan_rkn4", Splitting::blanes_moan_rkn4()); $body }
        { let ($name, $m) = ("blanes_moan_rkn6", Splitting::blanes_moan_rkn6()); $body }
    }};
}

// ---------------------------------------------------------------------------
// The S² gyroscope in the paper's coordinates (the baselines' system)
// ---------------------------------------------------------------------------

/// The coordinate Lagrangian (a52)/(a91) of the S² gyroscope
/// (`framedyn::testing::S2GyroCoords`) as a first-order system on `(q, q̇)`.
type S2Chart = ChartSystem<S2GyroCoords, 3>;

/// The S² gyroscope from a chart state `(r, φ, ψ; ṙ, φ̇, ω)` (ω the angular
/// velocity (a91), so `ψ̇ = ω − cos(r/R) φ̇`), in both formulations starting
/// from the same physical state: the group state is built from the chart
/// state's ambient data ([`s2_gyro_from_chart`]).
fn s2_both(a: f64, radius: f64, q0: [f64; 3], v0: [f64; 3], t_end: f64, name: &'static str) -> (Reference<S2Gyro>, S2Chart, <S2Chart as System>::State) {
    let r = s2_gyro_from_chart(a, radius, q0, v0, t_end, name).expect("valid S² gyroscope parameters");
    let lag = s2_gyro_coords(a, radius).expect("valid S² gyroscope parameters");
    let (q, v) = s2_chart_state(radius, q0, v0);
    (r, ChartSystem::new(lag), S2Chart::state(&q, &v))
}

/// Ambient observable of a chart state (same layout as the group form's).
fn chart_obs(sys: &S2Chart, y: &<S2Chart as System>::State) -> Option<Vec<f64>> {
    s2_chart_observable(sys.lagrangian(), &y.0 .0, &y.1 .0).ok()
}

// ---------------------------------------------------------------------------
// 1. Largest stable step against stiffness
// ---------------------------------------------------------------------------

fn stable_steps(out: &str, quick: bool) -> std::io::Result<()> {
    let mut f = std::fs::File::create(format!("{out}/stability_steps.csv"))?;
    writeln!(f, "sweep,param,method,h_max_stable,failure_above")?;
    let t = 10.0;
    let kappas: &[f64] = if quick { &[1.0, 100.0] } else { &[1.0, 10.0, 100.0, 1e3, 1e4] };
    for &k in kappas {
        let r = s2_affine_kappa(k).expect("valid stiffness");
        each_general!(name, m, { stable_row(&mut f, "kappa", k, name, largest_stable(&r.system, &r.y0, t, &m))?; });
        eprintln!("  steps: kappa {k} done");
    }
    let omegas: &[f64] = if quick { &[1.0, 100.0] } else { &[1.0, 10.0, 100.0, 1e3] };
    for &w in omegas {
        let (r, cs, cy) = s2_both(S2_A, 1.0, S2_Q0, [0.3, 0.6, w], t, "spin");
        each_general!(name, m, { stable_row(&mut f, "spin_omega", w, name, largest_stable(&r.system, &r.y0, t, &m))?; });
        each_splitting!(name, m, { stable_row(&mut f, "spin_omega", w, name, largest_stable(&r.system, &r.y0, t, &m))?; });
        stable_row(&mut f, "spin_omega", w, "coords_rk4", largest_stable(&cs, &cy, t, &CoordinateRk::rk4()))?;
        stable_row(&mut f, "spin_omega", w, "coords_dopri5_fixed", largest_stable(&cs, &cy, t, &CoordinateRk::dopri5()))?;
        eprintln!("  steps: omega {w} done");
    }
    let radii: &[f64] = if quick { &[0.1, 1.0] } else { &[0.03, 0.1, 0.3, 1.0, 3.0, 10.0] };
    for &rad in radii {
        let (r, cs, cy) = s2_both(S2_A, rad, [rad, 0.3, 0.4], [0.3, 0.6 / rad, 1.0], t, "radius");
        each_general!(name, m, { stable_row(&mut f, "radius", rad, name, largest_stable(&r.system, &r.y0, t, &m))?; });
        each_splitting!(name, m, { stable_row(&mut f, "radius", rad, name, largest_stable(&r.system, &r.y0, t, &m))?; });
        stable_row(&mut f, "radius", rad, "coords_rk4", largest_stable(&cs, &cy, t, &CoordinateRk::rk4()))?;
        stable_row(&mut f, "radius", rad, "coords_dopri5_fixed", largest_stable(&cs, &cy, t, &CoordinateRk::dopri5()))?;
        eprintln!("  steps: radius {rad} done");
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// 2. Through the pole of S²
// ---------------------------------------------------------------------------

/// Step budget of the adaptive coordinate DOPRI5 at the pole (without it,
/// tol 1e-12 took 3.8e6 steps and 100 s CPU before its step size collapsed).
const COORD_MAX_STEPS: usize = 200_000;

fn pole(out: &str, quick: bool) -> std::io::Result<()> {
    // The pole trajectory of `framedyn::testing::s2_pole` (the constants
    // `S2_POLE_*`), built from its chart state for the coordinate baselines.
    let (r, cs, cy) = s2_both(S2_POLE_A, S2_RADIUS, S2_POLE_Q0, S2_POLE_V0, S2_POLE_T_END, "pole");
    let mut st = Stepper::new(r.system.clone(), Rkmk::butcher6(), 0.0, r.y0).expect("stepper");
    st.advance(r.t_end, 80_000).expect("reference");
    let reference = (r.observable)(&r.system, st.state());
    let mut st2 = Stepper::new(r.system.clone(), Rkmk::butcher6(), 0.0, r.y0).expect("stepper");
    st2.advance(r.t_end, 40_000).expect("reference");
    let ref_err = obs_dist(&(r.observable)(&r.system, st2.state()), &reference);
    eprintln!("  pole reference: butcher6 40k vs 80k steps: {ref_err:.1e}");

    let mut p = std::fs::File::create(format!("{out}/stability_pole_problem.csv"))?;
    writeln!(p, "key,value")?;
    for (k, x) in [("m", S2_MASS), ("R", S2_RADIUS), ("I", S2_MOMENT), ("a", S2_POLE_A), ("T", r.t_end), ("ref_error", ref_err)] {
        writeln!(p, "{k},{x:.17e}")?;
    }
    for i in 0..3 {
        writeln!(p, "q{i},{:.17e}", cy.0 .0[i])?;
        writeln!(p, "v{i},{:.17e}", cy.1 .0[i])?;
    }
    for (i, x) in reference.iter().enumerate() {
        writeln!(p, "ref{i},{x:.17e}")?;
    }

    let mut f = std::fs::File::create(format!("{out}/stability_pole.csv"))?;
    writeln!(f, "method,kind,setting,error,cpu_s,rhs_evals,steps,rejected,min_distance_to_pole,failure")?;
    let pole_pt = Vector3::z();
    // Fixed steps: timed through `solve`, then a Stepper pass for the closest approach.
    macro_rules! group_fixed {
        ($name:expr, $m:expr) => {{
            let m = $m;
            for k in 0..if quick { 4 } else { 8 } {
                let h = 0.02 / 2f64.powi(k);
                let o = run_fixed(&r, &m, h, &thread_time);
                let n = (r.t_end / h).round() as usize;
                let mut st = Stepper::new(r.system.clone(), m, 0.0, r.y0).expect("stepper");
                let mut dmin = f64::INFINITY;
                for _ in 0..n {
                    if st.step(r.t_end / n as f64).is_err() {
                        break;
                    }
                    dmin = dmin.min((r.system.position(st.state()) - pole_pt).norm());
                }
                let err = if o.obs.is_empty() { f64::NAN } else { obs_dist(&o.obs, &reference) };
                let fail = o.failure.unwrap_or_default().replace(',', ";");
                writeln!(f, "{},h,{h:e},{err:e},{:e},{},{},0,{dmin:e},{fail}", $name, o.cpu, o.rhs, o.steps)?;
            }
        }};
    }
    group_fixed!("rkmk4", Rkmk::rk4());
    group_fixed!("strang", Splitting::strang());
    group_fixed!("blanes_moan4", Splitting::blanes_moan4());
    let tols: Vec<f64> = (4..=12).step_by(if quick { 4 } else { 1 }).map(|k| 10f64.powi(-k)).collect();
    for &tol in &tols {
        let o = run_adaptive(&r, &Rkmk::dopri5(), tol, &thread_time);
        let err = if o.obs.is_empty() { f64::NAN } else { obs_dist(&o.obs, &reference) };
        let fail = o.failure.unwrap_or_default().replace(',', ";");
        writeln!(f, "dopri5,tol,{tol:e},{err:e},{:e},{},{},{},,{fail}", o.cpu, o.rhs, o.steps, o.rejected)?;
    }
    // Coordinate baselines on (r, φ, ψ; ṙ, φ̇, ψ̇): the library's CoordinateRk.
    let cp = Problem::new(cs.clone(), cy, (0.0, r.t_end)).unwrap();
    let mut coord_run = |name: &str, kind: &str, setting: f64, opts: Options<<S2Chart as System>::State>, adaptive: bool| -> std::io::Result<()> {
        let (cpu, res) = if adaptive {
            timed(&thread_time, || solve(&cp, &CoordinateRk::dopri5(), &opts))
        } else {
            timed(&thread_time, || solve(&cp, &CoordinateRk::rk4(), &opts))
        };
        match res {
            Ok(sol) => {
                let err = chart_obs(&cs, sol.last().1).map(|o| obs_dist(&o, &reference)).unwrap_or(f64::NAN);
                let st = sol.stats();
                writeln!(f, "{name},{kind},{setting:e},{err:e},{cpu:e},{},{},{},,", st.rhs_evals, st.accepted, st.rejected)
            }
            Err(fl) => {
                let st = fl.solution.stats();
                let msg = fl.error.to_string().replace(',', ";");
                writeln!(f, "{name},{kind},{setting:e},NaN,{cpu:e},{},{},{},,{msg}", st.rhs_evals, st.accepted, st.rejected)
            }
        }
    };
    for k in 0..if quick { 4 } else { 8 } {
        let h = 0.02 / 2f64.powi(k);
        coord_run("coords_rk4", "h", h, Options::fixed(h).save(Save::Ends).max_steps(usize::MAX), false)?;
    }
    for &tol in &tols {
        coord_run("coords_dopri5", "tol", tol, Options::adaptive(tol, tol).save(Save::Ends).max_steps(COORD_MAX_STEPS), true)?;
    }
    eprintln!("  pole done");
    Ok(())
}

// ---------------------------------------------------------------------------
// 3. Escape to infinity on H², against the closed-form free motion
// ---------------------------------------------------------------------------

/// `exp(tA)` of an so(1,2) matrix `A` with `A³ = λ²A` (λ² > 0: a
/// hyperbolic generator): `I + sinh(λt)/λ·A + (cosh(λt) − 1)/λ²·A²`.
fn exp_hyperbolic(a: &Matrix3<f64>, lambda2: f64, t: f64) -> Matrix3<f64> {
    let l = lambda2.sqrt();
    Matrix3::identity() + a * ((l * t).sinh() / l) + a * a * (((l * t).cosh() - 1.0) / lambda2)
}

fn h2_escape(out: &str, quick: bool) -> std::io::Result<()> {
    type H2Free = Gyroscope2Model<Hyperbolic2, CosineFamily<3>>;
    let radius = 1.0;
    let h2 = Hyperbolic2::new(radius).unwrap();
    let pot = CosineFamily::new(0.0, 0.0, Centre::hyperbolic2(&h2)).unwrap();
    let m: H2Free = Gyroscope2Model::new(h2, Gyroscope::<2>::isotropic(1.0, 0.3).unwrap(), pot).unwrap();
    let x = Vector2::new(0.5, 0.3);
    let (p, v) = (h2.embed(&x), h2.embed_tangent(&x, &Vector2::new(1.0, 0.2)));
    let y0 = m.state_at(&p, &v, 0.4, m.spin_for_angular_velocity(1.0)).unwrap();
    let t_end = if quick { 20.0 } else { 40.0 };
    let e0 = m.energy(&y0);

    // Closed form (SPEC §4, parallel frame): x(t) = R Λ₀ exp(tA) e₃ with the
    // constant generator A = hat(u₀/R, K s/m), K = −1/R² (the rotation
    // exp(−tR) fixes e₃). A³ = λ²A with λ² = |u₀|²/R² − (Ks/m)².
    let u0 = m.velocity_components(&y0);
    let c = -m.spin(&y0) / (radius * radius * m.body().mass());
    let a = So12::hat(&Vector3::new(u0[0] / radius, u0[1] / radius, c));
    let lambda2 = (u0[0] * u0[0] + u0[1] * u0[1]) / (radius * radius) - c * c;
    let cubic = (a * a * a - a * lambda2).amax();
    assert!(lambda2 > 0.0 && cubic < 1e-14, "A³ = λ²A: {cubic:e}, λ² = {lambda2}");
    let lambda0 = *y0.0 .0.matrix();
    let exact = |t: f64| -> Vector3<f64> { (lambda0 * exp_hyperbolic(&a, lambda2, t)).column(2) * radius };

    let mut f = std::fs::File::create(format!("{out}/stability_h2.csv"))?;
    writeln!(f, "method,t,distance,distance_exact,position_rel_error,defect,relative_energy_error")?;
    let row = |f: &mut std::fs::File, name: &str, t: f64, y: &<H2Free as System>::State| -> std::io::Result<()> {
        let xp = m.position(y);
        let xe = exact(t);
        writeln!(
            f,
            "{name},{t},{:e},{:e},{:e},{:e},{:e}",
            (xp[2] / radius).acosh() * radius,
            (xe[2] / radius).acosh() * radius,
            (xp - xe).norm() / xe.norm(),
            m.defect(y),
            ((m.energy(y) - e0) / e0).abs()
        )
    };
    macro_rules! fixed_run {
        ($name:expr, $m:expr, $h:expr) => {{
            let mut st = Stepper::new(m.clone(), $m, 0.0, y0).expect("stepper");
            let n = (t_end / ($h as f64)).round() as usize;
            let every = (n / 400).max(1);
            for i in 1..=n {
                if let Err(e) = st.step(t_end / n as f64) {
                    eprintln!("  H² {}: {e}", $name);
                    break;
                }
                if i % every == 0 || i == n {
                    row(&mut f, $name, st.t(), st.state())?;
                }
            }
        }};
    }
    fixed_run!("rkmk4_h0.01", Rkmk::rk4(), 0.01);
    fixed_run!("strang_h0.01", Splitting::strang(), 0.01);
    fixed_run!("blanes_moan4_h0.05", Splitting::blanes_moan4(), 0.05);
    let prob = Problem::new(m.clone(), y0, (0.0, t_end)).unwrap();
    let sol = solve(&prob, &Rkmk::dopri5(), &Options::adaptive(1e-10, 1e-10).save(Save::Steps).max_steps(10_000_000));
    let (states, times): (Vec<_>, Vec<f64>) = match &sol {
        Ok(s) => (s.states().to_vec(), s.times().to_vec()),
        Err(fl) => (fl.solution.states().to_vec(), fl.solution.times().to_vec()),
    };
    let every = (states.len() / 400).max(1);
    for (k, (y, t)) in states.iter().zip(&times).enumerate() {
        if k % every == 0 || k + 1 == states.len() {
            row(&mut f, "dopri5_tol1e-10", *t, y)?;
        }
    }
    if let Err(fl) = sol {
        eprintln!("  H² dopri5 stopped: {}", fl.error);
    }
    eprintln!("  H² done");
    Ok(())
}

// ---------------------------------------------------------------------------
// 4. Long-time energy behaviour
// ---------------------------------------------------------------------------

/// Step indices log-spaced (20 per decade) from 1 to `n`, and `n`.
fn log_samples(n: usize) -> Vec<usize> {
    let mut v: Vec<usize> = (0..).map(|k| 10f64.powf(k as f64 / 20.0).round() as usize).take_while(|&i| i <= n).collect();
    v.push(n);
    v.dedup();
    v
}

/// `n` fixed steps of `h`; samples energy error, momentum-map error and
/// defect at log-spaced steps (not inside the timed loop's hot path: the
/// read-outs are evaluated only at the samples).
#[allow(clippy::too_many_arguments)]
fn long_run<S, M>(
    f: &mut std::fs::File,
    summary: &mut std::fs::File,
    problem: &str,
    name: &str,
    sys: &S,
    y0: &S::State,
    mom: fn(&S, &S::State) -> f64,
    m: M,
    h: f64,
    n: usize,
) -> std::io::Result<()>
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let (e0, j0) = (sys.energy(y0), mom(sys, y0));
    let scale = e0.abs().max(1e-300);
    let mut st = Stepper::new(sys.clone(), m, 0.0, *y0).expect("stepper");
    let samples = log_samples(n);
    let (mut done, mut emax, mut jmax, mut dmax) = (0usize, 0.0f64, 0.0f64, 0.0f64);
    let c0 = thread_time();
    let mut failure = String::new();
    'outer: for &k in &samples {
        while done < k {
            if let Err(e) = st.step(h) {
                failure = e.to_string().replace(',', ";");
                break 'outer;
            }
            done += 1;
        }
        let y = st.state();
        let (de, dj, d) = ((sys.energy(y) - e0).abs() / scale, (mom(sys, y) - j0).abs(), sys.defect(y));
        emax = emax.max(de);
        jmax = jmax.max(dj);
        dmax = dmax.max(d);
        writeln!(f, "{problem},{name},{h},{k},{:e},{de:e},{dj:e},{d:e}", st.t())?;
    }
    let cpu = thread_time() - c0;
    writeln!(summary, "{problem},{name},{h},{done},{cpu:e},{emax:e},{jmax:e},{dmax:e},{failure}")?;
    eprintln!("  long: {problem} {name} h = {h}: {done} steps in {cpu:.1} s CPU, max rel. energy error {emax:.2e}, momentum {jmax:.2e}, defect {dmax:.1e}");
    Ok(())
}

fn long_time(out: &str, n: usize) -> std::io::Result<()> {
    let mut f = std::fs::File::create(format!("{out}/stability_long.csv"))?;
    writeln!(f, "problem,method,h,step,t,rel_energy_error,momentum_error,defect")?;
    let mut s = std::fs::File::create(format!("{out}/stability_long_summary.csv"))?;
    writeln!(s, "problem,method,h,steps,cpu_s,max_rel_energy_error,max_momentum_error,max_defect,failure")?;
    let r = s2_gyro();
    let h = 0.05;
    long_run(&mut f, &mut s, "s2_gyro", "strang", &r.system, &r.y0, r.momentum, Splitting::strang(), h, n)?;
    long_run(&mut f, &mut s, "s2_gyro", "blanes_moan4", &r.system, &r.y0, r.momentum, Splitting::blanes_moan4(), h, n)?;
    long_run(&mut f, &mut s, "s2_gyro", "rkmk4", &r.system, &r.y0, r.momentum, Rkmk::rk4(), h, n)?;
    long_run(&mut f, &mut s, "s2_gyro", "dopri5_fixed", &r.system, &r.y0, r.momentum, Rkmk::dopri5(), h, n)?;
    let t = t2_gyro();
    long_run(&mut f, &mut s, "t2_gyro", "implicit_midpoint", &t.system, &t.y0, t.momentum, ImplicitMidpoint::new(), h, n)?;
    long_run(&mut f, &mut s, "t2_gyro", "rkmk4", &t.system, &t.y0, t.momentum, Rkmk::rk4(), h, n)?;
    Ok(())
}

// ---------------------------------------------------------------------------
// 5. Collapse of the affine body
// ---------------------------------------------------------------------------

/// `det(I + tρ̇₀)`: the exact `det ρ` of the free internal motion of
/// `framedyn::testing::s2_affine_collapse` (`ρ(t) = I + tρ̇₀`, ρ̇₀ =
/// `S2_COLLAPSE_RATE`), which flattens the body at `s2_collapse_time()`.
fn exact_det(t: f64) -> f64 {
    (Matrix2::identity() + S2_COLLAPSE_RATE * t).determinant()
}

fn collapse(out: &str) -> std::io::Result<()> {
    let r = s2_affine_collapse();
    let (m, y0, t_star) = (r.system, r.y0, s2_collapse_time());
    eprintln!("  collapse: t* = {t_star:.15} (model predicts {:?})", m.free_collapse_time(&y0));
    let mut f = std::fs::File::create(format!("{out}/stability_collapse.csv"))?;
    writeln!(f, "method,setting,outcome,t_stop,h_stop,t_star_minus_t,steps,rejected,det_rel_error_last,t_det_off_10pct,collapse_ratio_last,h_omega_last,detail")?;
    let mut g = std::fs::File::create(format!("{out}/stability_collapse_steps.csv"))?;
    writeln!(g, "method,setting,t,h,t_star_minus_t,det_rho,det_rel_error,deformation_rate")?;
    let prob = Problem::new(m.clone(), y0, (0.0, 2.0)).unwrap();
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        let res = solve(&prob, &Rkmk::dopri5(), &Options::adaptive(tol, tol).save(Save::Steps).max_steps(1_000_000));
        let (sol, outcome, detail, t_stop, h_stop) = match &res {
            Ok(s) => (s, "finished".to_string(), String::new(), s.last().0, f64::NAN),
            Err(fl) => {
                let (kind, t, h) = match fl.error {
                    SolveError::StepSizeTooSmall { t, h, .. } => ("StepSizeTooSmall", t, h),
                    SolveError::NonFinite { t, h, .. } => ("NonFinite", t, h),
                    SolveError::MaxSteps { t, h, .. } => ("MaxSteps", t, h),
                    SolveError::DexpRadius { t, h, .. } => ("DexpRadius", t, h),
                    _ => ("other", f64::NAN, f64::NAN),
                };
                (&*fl.solution, kind.to_string(), fl.error.to_string().replace(',', ";"), t, h)
            }
        };
        let (ts, ys) = (sol.times(), sol.states());
        for i in 1..ts.len() {
            let ex = exact_det(ts[i]);
            writeln!(g, "dopri5,{tol:e},{},{:e},{:e},{:e},{:e},{:e}", ts[i], ts[i] - ts[i - 1], t_star - ts[i], m.det_rho(&ys[i]), ((m.det_rho(&ys[i]) - ex) / ex).abs(), m.deformation_rate(&ys[i]))?;
        }
        let (tl, yl) = sol.last();
        let ex = exact_det(tl);
        let st = sol.stats();
        writeln!(
            f,
            "dopri5,tol {tol:e},{outcome},{t_stop},{h_stop:e},{:e},{},{},{:e},NaN,{:e},{:e},{detail}",
            t_star - t_stop,
            st.accepted,
            st.rejected,
            ((m.det_rho(yl) - ex) / ex).abs(),
            m.collapse_ratio(yl),
            h_stop.abs() * m.deformation_rate(yl)
        )?;
        eprintln!("  collapse: dopri5 tol {tol:e}: {outcome} at t* − t = {:.2e}, h = {h_stop:.1e}, {} steps; last saved t = {tl}", t_star - t_stop, st.accepted);
    }
    // Fixed steps: march until a typed error or the first step that ends
    // past t* (where the exact motion has no state); record where det ρ
    // first went wrong by > 10 % and h‖Ω̂‖ at the start of the last step.
    macro_rules! fixed_collapse {
        ($name:expr, $m:expr) => {{
            for h in [0.01, 1e-3] {
                let mut st = Stepper::new(m.clone(), $m, 0.0, y0).expect("stepper");
                let mut steps = 0usize;
                let mut t_wrong = f64::NAN;
                let (outcome, detail, t_stop, hw) = loop {
                    let hw = h * m.deformation_rate(st.state());
                    let t0 = st.t();
                    if let Err(e) = st.step(h) {
                        break ("typed error".to_string(), e.to_string().replace(',', ";"), t0, hw);
                    }
                    steps += 1;
                    let y = st.state();
                    let ex = exact_det(st.t());
                    if ex > 0.0 && t_wrong.is_nan() && !(((m.det_rho(y) - ex) / ex).abs() <= 0.1) {
                        t_wrong = st.t();
                    }
                    if ex <= 0.0 {
                        let chk = match m.check_state(y) {
                            Ok(()) => "passes check_state".to_string(),
                            Err(e) => format!("check_state: {e}").replace(',', ";"),
                        };
                        break ("crossed t*".to_string(), format!("det rho = {:e} (exact {:e}); {chk}", m.det_rho(y), ex), t0, hw);
                    }
                };
                writeln!(f, "{},h {h:e},{outcome},{t_stop},{h:e},{:e},{steps},0,NaN,{t_wrong},{:e},{hw:e},{detail}", $name, t_star - t_stop, m.collapse_ratio(st.state()))?;
                eprintln!("  collapse: {} h = {h}: {outcome} in the step from t = {t_stop:.4} (t* − t = {:.1e}, h‖Ω̂‖ = {hw:.2}); det ρ off by > 10 % from t = {t_wrong:.4}: {detail}", $name, t_star - t_stop);
            }
        }};
    }
    fixed_collapse!("lie_euler", Rkmk::lie_euler());
    fixed_collapse!("heun", Rkmk::heun());
    fixed_collapse!("kutta3", Rkmk::kutta3());
    fixed_collapse!("rkmk4", Rkmk::rk4());
    fixed_collapse!("dopri5_fixed", Rkmk::dopri5());
    fixed_collapse!("butcher6", Rkmk::butcher6());
    fixed_collapse!("implicit_midpoint", ImplicitMidpoint::new());
    Ok(())
}

/// A near-collapse that the elastic potential (a131) turns back: the body
/// is compressed hard (`ρ̇₀ = −c·I`) against the barrier `κ/(λμ)`. Largest
/// stable fixed step per method and what adaptive DOPRI5 spends.
fn bounce(out: &str, quick: bool) -> std::io::Result<()> {
    type ElasticAffine = AffineModel<Sphere2, Sum<Elastic, CosineFamily<3>>, 2, 3>;
    let mut f = std::fs::File::create(format!("{out}/stability_bounce.csv"))?;
    writeln!(f, "rate,min_stretch,method,h_max_stable,failure_above,adaptive_steps,adaptive_h_min,adaptive_failure")?;
    let rates: &[f64] = if quick { &[30.0] } else { &[3.0, 30.0, 300.0] };
    for &c in rates {
        let s2 = Sphere2::new(1.0).unwrap();
        let pot = Sum::new(Elastic::new(1.0).unwrap(), CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2)).unwrap());
        let m: ElasticAffine = AffineModel::new(s2, Affine::new(1.0, AFFINE_INERTIA).unwrap(), pot).unwrap();
        let gq = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2))).unwrap();
        let y0 = m.state(&gq, &Matrix2::identity(), &Vector2::new(0.6, -0.9), &(Matrix2::identity() * -c)).unwrap();
        let t_end = 10.0;
        let prob = Problem::new(m.clone(), y0, (0.0, t_end)).unwrap();
        let (steps, hmin, smin, afail) = match solve(&prob, &Rkmk::dopri5(), &Options::adaptive(1e-10, 1e-10).save(Save::Steps).max_steps(10_000_000)) {
            Ok(sol) => {
                let smin = sol.states().iter().map(|y| m.stretches(y)[1]).fold(f64::INFINITY, f64::min);
                (sol.stats().accepted, sol.stats().h_min, smin, String::new())
            }
            Err(fl) => {
                let smin = fl.solution.states().iter().map(|y| m.stretches(y)[1]).fold(f64::INFINITY, f64::min);
                (fl.solution.stats().accepted, fl.solution.stats().h_min, smin, fl.error.to_string().replace(',', ";"))
            }
        };
        each_general!(name, mm, {
            let (hs, why) = largest_stable(&m, &y0, t_end, &mm);
            writeln!(f, "{c},{smin:e},{name},{hs:e},{why},{steps},{hmin:e},{afail}")?;
        });
        eprintln!("  bounce: rate {c}: smallest stretch {smin:.2e}, adaptive DOPRI5 (1e-10) {steps} steps, h_min {hmin:.1e} {afail}");
    }
    Ok(())
}

fn main() -> std::io::Result<()> {
    let a = args();
    std::fs::create_dir_all(&a.out)?;
    let c0 = thread_time();
    if a.runs("steps") {
        stable_steps(&a.out, a.quick)?;
        eprintln!("stable steps: {:.0} s", thread_time() - c0);
    }
    if a.runs("pole") {
        pole(&a.out, a.quick)?;
    }
    if a.runs("h2") {
        h2_escape(&a.out, a.quick)?;
    }
    if a.runs("collapse") {
        collapse(&a.out)?;
    }
    if a.runs("bounce") {
        bounce(&a.out, a.quick)?;
    }
    let c1 = thread_time();
    if a.runs("long") {
        long_time(&a.out, a.long_steps)?;
    }
    eprintln!("long-time runs: {:.0} s; total {:.0} s CPU", thread_time() - c1, thread_time() - c0);
    eprintln!("written: {}/stability_*.csv", a.out);
    Ok(())
}

