//! Work-precision data: every method of the table on every reference
//! problem over a range of step sizes / tolerances, against a high-accuracy
//! reference.
//!
//! Run through the documented command `python3 scripts/work_precision.py`
//! (which also times scipy and draws the charts), or alone:
//! `cargo run --profile measure --example work_precision -- --out docs/data [--quick]`.
//!
//! Writes into `--out`:
//! - `wp_rust.csv`: method, problem, setting (h or tol), final error (max
//!   norm of the ambient observable — position, velocity, body frame,
//!   internal momentum — against the reference), thread-CPU seconds (minimum
//!   over repeats), RHS evaluations, steps, energy and momentum-map drift,
//!   largest constraint defect, failure;
//! - `references.csv`: how each reference was computed and its estimated
//!   error (Butcher 6 at h and h/2, and adaptive DOPRI5 at tol 1e-13);
//! - `s2_problem.csv`, `s2_samples.csv`: the S² gyroscope of SPEC §5 in the
//!   paper's coordinates (parameters, initial state, the reference
//!   observable at T) and sample values of the Rust coordinate form
//!   (`framedyn::coords`: accelerations, ambient observable, energy, p_φ) at
//!   random chart states, which the script checks its numpy right-hand side
//!   against (≤ 1e-12) before timing;
//! - `defect_series.csv`: energy error and constraint defect against time
//!   for the fixed-step methods on the S² gyroscope over T = 1000.
//!
//! The method table is `common::rkmk_table` (every system) plus, per
//! problem, the splittings (`splitting_entries`: gyroscopes on S², H², S³),
//! the implicit Lie midpoint rule (S², T², affine bodies) and, on the S²
//! gyroscope, the coordinate baselines (`s2_entries`).

#[path = "../benches/common/mod.rs"]
mod common;

use std::fmt::Write as _;
use std::io::Write;

use common::*;
use framedyn::coords::{accelerations, energy as coords_energy};
use framedyn::dynamics::{Splittable, System};
use framedyn::method::baseline::{ChartSystem, CoordinateRk};
use framedyn::method::{GroupNumerics, ImplicitMidpoint, Method, Rkmk, Splitting};
use framedyn::solve::{solve, Options, Problem, Save, Stepper};
use framedyn::testing::*;
use nalgebra::{SVector, Vector3};

/// Command-line options.
struct Args {
    out: String,
    quick: bool,
}

fn args() -> Args {
    let mut a = Args { out: "docs/data".into(), quick: false };
    let mut it = std::env::args().skip(1);
    while let Some(x) = it.next() {
        match x.as_str() {
            "--out" => a.out = it.next().expect("--out DIR"),
            "--quick" => a.quick = true,
            other => {
                eprintln!("unknown argument {other}; usage: work_precision [--out DIR] [--quick]");
                std::process::exit(2);
            }
        }
    }
    a
}

/// The reference observable: Butcher 6 with `n` and `2n` steps (the finer
/// one is the reference, their difference its error estimate), and adaptive
/// DOPRI5 at 1e-13 as an independent check.
fn reference<S>(r: &Reference<S>, n: usize, log: &mut String) -> Vec<f64>
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let run = |n: usize| {
        let mut st = Stepper::new(r.system.clone(), Rkmk::butcher6(), 0.0, r.y0).expect("stepper");
        st.advance(r.t_end, n).expect("reference run");
        (r.observable)(&r.system, st.state())
    };
    let (coarse, fine) = (run(n), run(2 * n));
    let p = r.problem().expect("valid reference problem");
    let dp = solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-13, 1e-13).save(Save::Ends).max_steps(50_000_000))
        .map(|s| obs_dist(&(r.observable)(&r.system, s.last().1), &fine))
        .unwrap_or(f64::NAN);
    let self_err = obs_dist(&coarse, &fine);
    eprintln!("reference {}: butcher6 n = {} vs {}: {:.1e}; dopri5 tol 1e-13: {:.1e}", r.name, n, 2 * n, self_err, dp);
    writeln!(log, "{},butcher6,{},{:e},{:e}", r.name, 2 * n, self_err, dp).unwrap();
    fine
}

/// Runs the table on one reference problem and appends CSV rows.
fn run_problem<S>(r: &Reference<S>, table: &[Entry<S>], n_ref: usize, quick: bool, csv: &mut String, refs: &mut String) -> Vec<f64>
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let reference = reference(r, n_ref, refs);
    let max_steps = if quick { 2e4 } else { 1e6 };
    for e in table {
        let settings: Vec<f64> = if e.adaptive {
            let t = tol_ladder();
            if quick {
                t.into_iter().step_by(4).collect()
            } else {
                t
            }
        } else {
            let l = step_ladder(e.order, r.t_end, max_steps);
            if quick {
                l.into_iter().step_by(4).collect()
            } else {
                l
            }
        };
        for s in settings {
            let o = (e.run)(r, s, &thread_time);
            let err = if o.obs.is_empty() { f64::NAN } else { obs_dist(&o.obs, &reference) };
            let fail = o.failure.as_deref().unwrap_or("").replace(',', ";");
            writeln!(
                csv,
                "{},{},{},{:e},{:e},{:e},{},{},{},{:e},{:e},{:e},{}",
                e.name,
                r.name,
                if e.adaptive { "tol" } else { "h" },
                s,
                err,
                o.cpu,
                o.rhs,
                o.steps,
                o.rejected,
                o.energy_drift,
                o.momentum_drift,
                o.defect,
                fail
            )
            .unwrap();
        }
        eprintln!("  {} on {} done", e.name, r.name);
    }
    reference
}

// ---------------------------------------------------------------------------
// The S² gyroscope in the paper's coordinates
// ---------------------------------------------------------------------------

/// The coordinate form of the SPEC §5 problem (`framedyn::testing`), at
/// field strength `a`.
fn s2_coords(a: f64) -> S2GyroCoords {
    s2_gyro_coords(a, S2_RADIUS).expect("valid SPEC §5 parameters")
}

/// The chart state `(q, q̇)` of the SPEC §5 problem: `q = (r, φ, ψ)`, with
/// `ψ̇ = ω − cos(r/R) φ̇` so that the angular velocity (a91) is `ω`.
fn s2_start() -> (SVector<f64, 3>, SVector<f64, 3>) {
    s2_chart_state(S2_RADIUS, S2_Q0, S2_V0)
}

/// The S² reference problem, built from the chart state so that the group
/// and coordinate forms start from the same physical state
/// ([`s2_gyro_from_chart`]).
fn s2_reference(t_end: f64, name: &'static str) -> Reference<S2Gyro> {
    s2_gyro_from_chart(S2_A, S2_RADIUS, S2_Q0, S2_V0, t_end, name).expect("valid SPEC §5 parameters")
}

/// `p_φ` in coordinates: `∂L/∂φ̇`.
fn coords_pphi(sys: &S2GyroCoords, q: &SVector<f64, 3>, v: &SVector<f64, 3>) -> f64 {
    framedyn::coords::momenta(sys, q, v).map(|p| p[1]).unwrap_or(f64::NAN)
}

/// Classical RK4 on `(q, q̇)` with the Euler–Lagrange accelerations of
/// `framedyn::coords` (automatic differentiation): the paper's form as a
/// user would integrate it. A stand-in for the coordinate baselines of the
/// `methods` branch.
fn coords_rk4_run(sys: &S2GyroCoords, q0: SVector<f64, 3>, v0: SVector<f64, 3>, t_end: f64, n: usize) -> Result<(SVector<f64, 3>, SVector<f64, 3>, usize), String> {
    let h = t_end / n as f64;
    let f = |q: &SVector<f64, 3>, v: &SVector<f64, 3>| accelerations(sys, q, v).map_err(|e| e.to_string());
    let (mut q, mut v) = (q0, v0);
    for _ in 0..n {
        let a1 = f(&q, &v)?;
        let (q2, v2) = (q + v * (0.5 * h), v + a1 * (0.5 * h));
        let a2 = f(&q2, &v2)?;
        let (q3, v3) = (q + v2 * (0.5 * h), v + a2 * (0.5 * h));
        let a3 = f(&q3, &v3)?;
        let (q4, v4) = (q + v3 * h, v + a3 * h);
        let a4 = f(&q4, &v4)?;
        q += (v + v2 * 2.0 + v3 * 2.0 + v4) * (h / 6.0);
        v += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0);
    }
    Ok((q, v, 4 * n))
}

/// Table entry: coordinate RK4 on the S² problem.
fn coords_rk4_entry(a: f64) -> Entry<S2Gyro> {
    Entry {
        name: "coords_rk4",
        order: 4,
        adaptive: false,
        run: Box::new(move |r, h, clock| {
            let sys = s2_coords(a);
            let (q0, v0) = s2_start();
            let n = (r.t_end / h).ceil() as usize;
            let (cpu, res) = timed(clock, || coords_rk4_run(&sys, q0, v0, r.t_end, n));
            match res.and_then(|(q, v, rhs)| s2_chart_observable(&sys, &q, &v).map(|o| (o, q, v, rhs)).map_err(|e| e.to_string())) {
                Ok((obs, q, v, rhs)) => {
                    let e0 = coords_energy(&sys, &q0, &v0).unwrap_or(f64::NAN);
                    let j0 = coords_pphi(&sys, &q0, &v0);
                    Outcome {
                        obs,
                        cpu,
                        rhs,
                        steps: n,
                        rejected: 0,
                        // End values (the coordinate run is not re-stepped for maxima).
                        energy_drift: (coords_energy(&sys, &q, &v).unwrap_or(f64::NAN) - e0).abs(),
                        momentum_drift: (coords_pphi(&sys, &q, &v) - j0).abs(),
                        defect: f64::NAN,
                        failure: None,
                    }
                }
                Err(e) => Outcome { cpu, failure: Some(e), ..Outcome::default() },
            }
        }),
    }
}

/// A coordinate baseline of the library ([`CoordinateRk`] on the chart
/// system of the S² Lagrangian) as a table entry: solves the chart form from
/// the same physical state and maps the end state to the observable (energy
/// and momentum "drift" are the end values, as for `coords_rk4`).
fn coordinate_entry<M>(name: &'static str, order: u32, adaptive: bool, a: f64, method: M) -> Entry<S2Gyro>
where
    M: Method<ChartSystem<S2GyroCoords, 3>> + 'static,
{
    Entry {
        name,
        order,
        adaptive,
        run: Box::new(move |r, s, clock| {
            let sys = s2_coords(a);
            let (q0, v0) = s2_start();
            let problem = match Problem::new(ChartSystem::new(sys.clone()), ChartSystem::<S2GyroCoords, 3>::state(&q0, &v0), (0.0, r.t_end)) {
                Ok(p) => p,
                Err(e) => return Outcome { failure: Some(e.to_string()), ..Outcome::default() },
            };
            let opts = if adaptive { Options::adaptive(s, s).max_steps(10_000_000) } else { Options::fixed(s).max_steps(usize::MAX) };
            let opts = opts.save(Save::Ends);
            let (cpu, res) = timed(clock, || solve(&problem, &method, &opts));
            let sol = match res {
                Ok(sol) => sol,
                Err(f) => return Outcome { cpu, failure: Some(format!("{}", f.error)), ..Outcome::default() },
            };
            let y = sol.last().1;
            let (q, v) = (y.0 .0, y.1 .0);
            match s2_chart_observable(&sys, &q, &v) {
                Ok(obs) => Outcome {
                    obs,
                    cpu,
                    rhs: sol.stats().rhs_evals,
                    steps: sol.stats().accepted,
                    rejected: sol.stats().rejected,
                    energy_drift: (coords_energy(&sys, &q, &v).unwrap_or(f64::NAN) - coords_energy(&sys, &q0, &v0).unwrap_or(f64::NAN)).abs(),
                    momentum_drift: (coords_pphi(&sys, &q, &v) - coords_pphi(&sys, &q0, &v0)).abs(),
                    defect: f64::NAN,
                    failure: None,
                },
                Err(e) => Outcome { cpu, failure: Some(e.to_string()), ..Outcome::default() },
            }
        }),
    }
}

/// The splitting methods with exact free flows (systems on S², H², S³).
fn splitting_entries<S>() -> Vec<Entry<S>>
where
    S: Splittable + Clone + 'static,
    S::State: GroupNumerics,
{
    vec![
        fixed("strang", 2, Splitting::strang()),
        fixed("yoshida4", 4, Splitting::yoshida4()),
        fixed("suzuki4", 4, Splitting::suzuki4()),
        fixed("blanes_moan4", 4, Splitting::blanes_moan4()),
        fixed("yoshida6", 6, Splitting::yoshida6()),
        fixed("blanes_moan6", 6, Splitting::blanes_moan6()),
        fixed("blanes_moan_rkn4", 4, Splitting::blanes_moan_rkn4()),
        fixed("blanes_moan_rkn6", 6, Splitting::blanes_moan_rkn6()),
    ]
}

/// The RKMK table plus the splittings (gyroscopes on S², H², S³).
fn splittable_table<S>() -> Vec<Entry<S>>
where
    S: Splittable + Clone + 'static,
    S::State: GroupNumerics,
{
    let mut t = rkmk_table();
    t.extend(splitting_entries());
    t
}

/// The RKMK table plus the implicit Lie midpoint rule (systems without
/// exact free flows: T², affine bodies).
fn implicit_table<S>() -> Vec<Entry<S>>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
{
    let mut t = rkmk_table();
    t.push(fixed("lie_midpoint", 2, ImplicitMidpoint::new()));
    t
}

/// The entries for the S² gyroscope: the RKMK table, the splittings, the
/// implicit Lie midpoint rule, and the coordinate baselines (the hand loop
/// `coords_rk4`, and the library's [`CoordinateRk`] RK4 / adaptive DOPRI5).
fn s2_entries() -> Vec<Entry<S2Gyro>> {
    let mut t = splittable_table();
    t.push(fixed("lie_midpoint", 2, ImplicitMidpoint::new()));
    t.push(coords_rk4_entry(S2_A));
    t.push(coordinate_entry("coords_rk4_lib", 4, false, S2_A, CoordinateRk::rk4()));
    t.push(coordinate_entry("coords_dopri5", 5, true, S2_A, CoordinateRk::dopri5()));
    t
}

/// Writes the S² problem data and coordinate-form samples for the script.
fn write_s2_data(out: &str, reference: &[f64], t_end: f64) -> std::io::Result<()> {
    let sys = s2_coords(S2_A);
    let (q, v) = s2_start();
    let mut f = std::fs::File::create(format!("{out}/s2_problem.csv"))?;
    writeln!(f, "key,value")?;
    for (k, x) in [("m", S2_MASS), ("R", S2_RADIUS), ("I", S2_MOMENT), ("a", S2_A), ("T", t_end)] {
        writeln!(f, "{k},{x:.17e}")?;
    }
    for i in 0..3 {
        writeln!(f, "q{i},{:.17e}", q[i])?;
        writeln!(f, "v{i},{:.17e}", v[i])?;
    }
    for (i, x) in reference.iter().enumerate() {
        writeln!(f, "ref{i},{x:.17e}")?;
    }
    // Samples: a deterministic spread of chart states away from the poles.
    let mut s = std::fs::File::create(format!("{out}/s2_samples.csv"))?;
    let mut head = String::from("r,phi,psi,rdot,phidot,psidot,acc0,acc1,acc2,energy,p_phi");
    for i in 0..13 {
        write!(head, ",obs{i}").unwrap();
    }
    writeln!(s, "{head}")?;
    for k in 0..12 {
        let x = k as f64;
        let q = Vector3::new(0.2 + 2.7 * ((x * 0.618) % 1.0), 6.0 * ((x * 0.414) % 1.0) - 3.0, 2.0 * (x * 0.3).sin());
        let v = Vector3::new((x * 1.3).cos(), 0.8 * (x * 0.7).sin(), 1.5 * (x * 0.9).cos());
        let a = accelerations(&sys, &q, &v).expect("away from the poles");
        let e = coords_energy(&sys, &q, &v).unwrap();
        let p = coords_pphi(&sys, &q, &v);
        let o = s2_chart_observable(&sys, &q, &v).unwrap();
        let mut line = format!("{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}", q[0], q[1], q[2], v[0], v[1], v[2]);
        for y in a.iter().chain([e, p].iter()).chain(o.iter()) {
            write!(line, ",{y:.17e}").unwrap();
        }
        writeln!(s, "{line}")?;
    }
    Ok(())
}

/// Energy error and constraint defect against time, fixed steps, S² problem.
fn defect_series(out: &str, quick: bool) -> std::io::Result<()> {
    let t_end = if quick { 100.0 } else { 1000.0 };
    let r = s2_reference(t_end, "s2_gyro_long");
    let mut f = std::fs::File::create(format!("{out}/defect_series.csv"))?;
    writeln!(f, "method,h,t,energy_error,momentum_error,defect")?;
    macro_rules! series {
        ($name:expr, $m:expr, $h:expr) => {{
            let n = (t_end / $h).round() as usize;
            let every = (n / 400).max(1);
            let mut st = Stepper::new(r.system.clone(), $m, 0.0, r.y0).expect("stepper");
            let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
            for i in 1..=n {
                if st.step(t_end / n as f64).is_err() {
                    break;
                }
                if i % every == 0 {
                    let y = st.state();
                    writeln!(
                        f,
                        "{},{},{:e},{:e},{:e},{:e}",
                        $name,
                        $h,
                        st.t(),
                        (r.system.energy(y) - e0).abs(),
                        ((r.momentum)(&r.system, y) - j0).abs(),
                        r.system.defect(y)
                    )?;
                }
            }
        }};
    }
    series!("lie_euler", Rkmk::lie_euler(), 0.01);
    series!("heun", Rkmk::heun(), 0.05);
    series!("kutta3", Rkmk::kutta3(), 0.05);
    series!("rkmk4", Rkmk::rk4(), 0.05);
    series!("butcher6", Rkmk::butcher6(), 0.1);
    Ok(())
}

fn main() -> std::io::Result<()> {
    let a = args();
    std::fs::create_dir_all(&a.out)?;
    let mut csv = String::from(
        "method,problem,kind,setting,error,cpu_s,rhs_evals,steps,rejected,energy_drift,momentum_drift,max_defect,failure\n",
    );
    let mut refs = String::from("problem,method,steps,self_error,dopri5_1e-13_vs_ref\n");
    let q = a.quick;
    let t_s2 = if q { 20.0 } else { 100.0 };

    let r = s2_reference(t_s2, "s2_gyro");
    let reference = run_problem(&r, &s2_entries(), if q { 4000 } else { 40_000 }, q, &mut csv, &mut refs);
    write_s2_data(&a.out, &reference, t_s2)?;
    run_problem(&s2_pole(), &splittable_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&h2_gyro(), &splittable_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&h2_lorentz(), &splittable_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&t2_gyro(), &implicit_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&s3_gyro(), &splittable_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&s2_affine(), &implicit_table(), 40_000, q, &mut csv, &mut refs);
    run_problem(&t2_affine(), &implicit_table(), 40_000, q, &mut csv, &mut refs);
    defect_series(&a.out, q)?;

    std::fs::write(format!("{}/wp_rust.csv", a.out), csv)?;
    std::fs::write(format!("{}/references.csv", a.out), refs)?;
    eprintln!("written: {0}/wp_rust.csv, {0}/references.csv, {0}/s2_problem.csv, {0}/s2_samples.csv, {0}/defect_series.csv", a.out);
    Ok(())
}
