//! Work-precision data: every method of the table on every reference
//! problem over a range of step sizes / tolerances, against a high-accuracy
//! reference.
//!
//! Run through the documented command `python3 scripts/work_precision.py`
//! (which also times scipy and draws the charts), or alone:
//! `cargo run --release --example work_precision -- --out docs/data [--quick]`.
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
//! The method table is `common::rkmk_table` (every system) plus the
//! per-problem entries pushed in `s2_entries` (coordinate RK4 here; the
//! splitting methods and coordinate baselines of the `methods` branch go
//! there with one line each).

#[path = "../benches/common/mod.rs"]
mod common;

use std::fmt::Write as _;
use std::io::Write;

use common::*;
use framedyn::body::Gyroscope;
use framedyn::coords::{accelerations, ambient_state, energy as coords_energy, Gyroscope2, PlaneRotation, SphereChart};
use framedyn::dynamics::{Gyroscope2Model, System};
use framedyn::manifold::Sphere2;
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::potential::{Centre, CosineFamily};
use framedyn::solve::{solve, Options, Save, Stepper};
use nalgebra::{SVector, Vector3};

/// Thread-CPU seconds (`CLOCK_THREAD_CPUTIME_ID`, as Python's `time.thread_time()`).
fn thread_time() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

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
    let p = r.problem();
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

/// The coordinate Lagrangian of the S² gyroscope (a52)/(a91) with
/// `V = a cos(r/R)`, from `framedyn::coords`.
type S2Coords = Gyroscope2<SphereChart, CosineFamily<3>>;

fn s2_coords(a: f64) -> S2Coords {
    let s2 = Sphere2::new(S2_RADIUS).unwrap();
    let pot = CosineFamily::new(0.0, a, Centre::sphere2(&s2)).unwrap();
    Gyroscope2::gyroscope(SphereChart::new(S2_RADIUS).unwrap(), PlaneRotation, &Gyroscope::<2>::isotropic(S2_MASS, S2_MOMENT).unwrap(), pot)
}

/// The chart state `(q, q̇)` of the SPEC §5 problem: `q = (r, φ, ψ)`, with
/// `ψ̇ = ω − cos(r/R) φ̇` so that the angular velocity (a91) is `ω`.
fn s2_chart_state() -> (SVector<f64, 3>, SVector<f64, 3>) {
    let q = Vector3::new(S2_Q0[0], S2_Q0[1], S2_Q0[2]);
    let c = (S2_Q0[0] / S2_RADIUS).cos();
    let v = Vector3::new(S2_V0[0], S2_V0[1], S2_V0[2] - c * S2_V0[1]);
    (q, v)
}

/// Ambient observable of a chart state (same layout as the group form's).
fn coords_obs(sys: &S2Coords, q: &SVector<f64, 3>, v: &SVector<f64, 3>) -> framedyn::Result<Vec<f64>> {
    let amb = ambient_state(sys, q, v)?;
    let s = sys.comoving(q, v)?.spin[(0, 1)];
    let mut o: Vec<f64> = amb.position.iter().copied().collect();
    o.extend(amb.velocity.iter());
    o.extend(amb.frame.iter());
    o.push(s);
    Ok(o)
}

/// `p_φ` in coordinates: `∂L/∂φ̇`.
fn coords_pphi(sys: &S2Coords, q: &SVector<f64, 3>, v: &SVector<f64, 3>) -> f64 {
    framedyn::coords::momenta(sys, q, v).map(|p| p[1]).unwrap_or(f64::NAN)
}

/// The S² reference problem, built from the chart state so that the group
/// and coordinate forms start from the same physical state.
fn s2_reference(t_end: f64, name: &'static str) -> Reference<S2Gyro> {
    let sys = s2_coords(S2_A);
    let (q, v) = s2_chart_state();
    let amb = ambient_state(&sys, &q, &v).unwrap();
    let spin = sys.comoving(&q, &v).unwrap().spin[(0, 1)];
    let mut r = s2_gyro_with(S2_A, S2_RADIUS, S2_Q0, S2_V0, t_end, name);
    let m: &Gyroscope2Model<_, _> = &r.system;
    r.y0 = m.state(&amb.position, &amb.velocity, &amb.frame, spin).unwrap();
    r
}

/// Classical RK4 on `(q, q̇)` with the Euler–Lagrange accelerations of
/// `framedyn::coords` (automatic differentiation): the paper's form as a
/// user would integrate it. A stand-in for the coordinate baselines of the
/// `methods` branch.
fn coords_rk4_run(sys: &S2Coords, q0: SVector<f64, 3>, v0: SVector<f64, 3>, t_end: f64, n: usize) -> Result<(SVector<f64, 3>, SVector<f64, 3>, usize), String> {
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
            let (q0, v0) = s2_chart_state();
            let n = (r.t_end / h).ceil() as usize;
            let (cpu, res) = timed(clock, || coords_rk4_run(&sys, q0, v0, r.t_end, n));
            match res.and_then(|(q, v, rhs)| coords_obs(&sys, &q, &v).map(|o| (o, q, v, rhs)).map_err(|e| e.to_string())) {
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

/// The entries for the S² gyroscope: the RKMK table plus system-specific
/// methods. ADD the `methods` branch's methods here, one line each, e.g.
/// `t.push(fixed("strang", 2, Strang::new()));`,
/// `t.push(fixed("yoshida4", 4, Yoshida4::new()));`,
/// `t.push(fixed("lie_midpoint", 2, LieMidpoint::new()));`; coordinate
/// baselines as an [`Entry`] like [`coords_rk4_entry`].
fn s2_entries() -> Vec<Entry<S2Gyro>> {
    let mut t = rkmk_table();
    t.push(coords_rk4_entry(S2_A));
    t
}

/// Writes the S² problem data and coordinate-form samples for the script.
fn write_s2_data(out: &str, reference: &[f64], t_end: f64) -> std::io::Result<()> {
    let sys = s2_coords(S2_A);
    let (q, v) = s2_chart_state();
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
        let o = coords_obs(&sys, &q, &v).unwrap();
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


// ---------------------------------------------------------------------------
// Stability (docs/stability.md)
// ---------------------------------------------------------------------------

/// Runs `$body` with `$name`, `$m` bound to each fixed-step RKMK method.
macro_rules! each_fixed {
    ($name:ident, $m:ident, $body:block) => {{
        { let ($name, $m) = ("lie_euler", Rkmk::lie_euler()); $body }
        { let ($name, $m) = ("heun", Rkmk::heun()); $body }
        { let ($name, $m) = ("kutta3", Rkmk::kutta3()); $body }
        { let ($name, $m) = ("rkmk4", Rkmk::rk4()); $body }
        { let ($name, $m) = ("dopri5_fixed", Rkmk::dopri5()); $body }
        { let ($name, $m) = ("butcher6", Rkmk::butcher6()); $body }
    }};
}

/// A run with fixed steps `h` over the span is *stable* if every step
/// succeeds and the energy error at every step stays ≤ 10 % of max(|E₀|, 1).
fn is_stable<S, M>(r: &Reference<S>, m: &M, h: f64) -> bool
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: framedyn::method::Method<S>,
{
    let n = (r.t_end / h).ceil() as usize;
    let e0 = r.system.energy(&r.y0);
    let tol = 0.1 * e0.abs().max(1.0);
    let Ok(mut st) = Stepper::new(r.system.clone(), m.clone(), 0.0, r.y0) else { return false };
    for _ in 0..n {
        if st.step(r.t_end / n as f64).is_err() {
            return false;
        }
        let e = r.system.energy(st.state());
        if !((e - e0).abs() <= tol) {
            return false;
        }
    }
    true
}

/// The largest `h = 2^{−k/4}` (k ≥ 0, h ≥ 1e-5) such that `h` and the next
/// two smaller grid steps are stable.
fn largest_stable<S, M>(r: &Reference<S>, m: &M) -> f64
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: framedyn::method::Method<S>,
{
    let grid: Vec<f64> = (0..=66).map(|k| 2f64.powf(-(k as f64) / 4.0)).collect();
    for i in 0..grid.len() - 2 {
        if is_stable(r, m, grid[i]) && is_stable(r, m, grid[i + 1]) && is_stable(r, m, grid[i + 2]) {
            return grid[i];
        }
    }
    f64::NAN
}

/// The S² gyroscope built from a chart state `(r, φ, ψ; ṙ, φ̇, ω)` (ω the
/// angular velocity (a91)), so that the coordinate form starts identically.
fn s2_from_chart(a: f64, q0: [f64; 3], v0: [f64; 3], t_end: f64, name: &'static str) -> (Reference<S2Gyro>, S2Coords, SVector<f64, 3>, SVector<f64, 3>) {
    let sys = s2_coords(a);
    let q = Vector3::new(q0[0], q0[1], q0[2]);
    let v = Vector3::new(v0[0], v0[1], v0[2] - (q0[0] / S2_RADIUS).cos() * v0[1]);
    let amb = ambient_state(&sys, &q, &v).unwrap();
    let spin = sys.comoving(&q, &v).unwrap().spin[(0, 1)];
    let mut r = s2_gyro_with(a, S2_RADIUS, q0, v0, t_end, name);
    r.y0 = r.system.state(&amb.position, &amb.velocity, &amb.frame, spin).unwrap();
    (r, sys, q, v)
}

fn stability(out: &str, quick: bool) -> std::io::Result<()> {
    // 1. Largest stable step against stiffness.
    let mut f = std::fs::File::create(format!("{out}/stability_steps.csv"))?;
    writeln!(f, "sweep,param,method,h_max_stable")?;
    let t = 10.0;
    let kappas: &[f64] = if quick { &[1.0, 100.0] } else { &[1.0, 10.0, 100.0, 1e3, 1e4] };
    for &k in kappas {
        let mut r = s2_affine_kappa(k);
        r.t_end = t;
        each_fixed!(name, m, { writeln!(f, "kappa,{k},{name},{:e}", largest_stable(&r, &m))?; });
        eprintln!("  stability: kappa {k} done");
    }
    let omegas: &[f64] = if quick { &[1.0, 100.0] } else { &[1.0, 10.0, 100.0, 1e3] };
    for &w in omegas {
        let r = s2_gyro_with(S2_A, 1.0, S2_Q0, [0.3, 0.6, w], t, "spin");
        each_fixed!(name, m, { writeln!(f, "spin_omega,{w},{name},{:e}", largest_stable(&r, &m))?; });
        eprintln!("  stability: omega {w} done");
    }
    let radii: &[f64] = if quick { &[0.1, 1.0] } else { &[0.03, 0.1, 0.3, 1.0, 3.0, 10.0] };
    for &rad in radii {
        let r = s2_gyro_with(S2_A, rad, [rad, 0.3, 0.4], [0.3, 0.6 / rad, 1.0], t, "radius");
        each_fixed!(name, m, { writeln!(f, "radius,{rad},{name},{:e}", largest_stable(&r, &m))?; });
        eprintln!("  stability: radius {rad} done");
    }

    // 2. Through the pole: group RKMK4 against coordinate RK4, same physical start.
    let mut f = std::fs::File::create(format!("{out}/stability_pole.csv"))?;
    writeln!(f, "method,h,error,min_distance_to_pole,failure")?;
    let (r, sys, q0, v0) = s2_from_chart(-0.5, [1e-6, 0.3, 0.4], [1.0, 0.0, 1.0], 20.0, "pole");
    let mut st = Stepper::new(r.system.clone(), Rkmk::butcher6(), 0.0, r.y0).expect("stepper");
    st.advance(r.t_end, 80_000).expect("reference");
    let reference = (r.observable)(&r.system, st.state());
    for k in 0..8 {
        let h = 0.02 / 2f64.powi(k);
        let n = (r.t_end / h).round() as usize;
        let mut st = Stepper::new(r.system.clone(), Rkmk::rk4(), 0.0, r.y0).expect("stepper");
        let mut dmin = f64::INFINITY;
        for _ in 0..n {
            st.step(r.t_end / n as f64).expect("group step");
            let x = r.system.position(st.state());
            dmin = dmin.min((x - Vector3::z() * S2_RADIUS).norm());
        }
        let err = obs_dist(&(r.observable)(&r.system, st.state()), &reference);
        writeln!(f, "rkmk4_group,{h:e},{err:e},{dmin:e},")?;
        match coords_rk4_run(&sys, q0, v0, r.t_end, n) {
            Ok((q, v, _)) => {
                let e = coords_obs(&sys, &q, &v).map(|o| obs_dist(&o, &reference)).unwrap_or(f64::NAN);
                writeln!(f, "rk4_coords,{h:e},{e:e},,")?;
            }
            Err(e) => writeln!(f, "rk4_coords,{h:e},NaN,,{}", e.replace(',', ";"))?,
        }
    }
    eprintln!("  stability: pole done");

    // 3. Escape to infinity on H²: a free gyroscope moving outward.
    let mut f = std::fs::File::create(format!("{out}/stability_h2.csv"))?;
    writeln!(f, "method,t,distance,defect,relative_energy_error")?;
    let h2 = framedyn::manifold::Hyperbolic2::new(1.0).unwrap();
    let pot = CosineFamily::new(0.0, 0.0, Centre::hyperbolic2(&h2)).unwrap();
    let m = Gyroscope2Model::new(h2, Gyroscope::<2>::isotropic(1.0, 0.3).unwrap(), pot).unwrap();
    let x = nalgebra::Vector2::new(0.5, 0.3);
    use framedyn::manifold::Manifold;
    let (p, v) = (h2.embed(&x), h2.embed_tangent(&x, &nalgebra::Vector2::new(1.0, 0.2)));
    let y0 = m.state_at(&p, &v, 0.4, m.spin_for_angular_velocity(1.0)).unwrap();
    let t_end = if quick { 20.0 } else { 40.0 };
    let e0 = m.energy(&y0);
    let mut st = Stepper::new(m.clone(), Rkmk::rk4(), 0.0, y0).expect("stepper");
    let n = (t_end / 0.01) as usize;
    for i in 1..=n {
        if st.step(0.01).is_err() {
            writeln!(f, "rkmk4_h0.01,{},NaN,NaN,NaN", st.t())?;
            break;
        }
        if i % 100 == 0 {
            let y = st.state();
            let z = m.position(y)[2];
            writeln!(f, "rkmk4_h0.01,{},{:e},{:e},{:e}", st.t(), z.acosh(), m.defect(y), ((m.energy(y) - e0) / e0).abs())?;
        }
    }
    let p = framedyn::solve::Problem::new(m.clone(), y0, (0.0, t_end)).unwrap();
    let sol = solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-10, 1e-10).save(Save::Steps).max_steps(10_000_000));
    let (states, times): (Vec<_>, Vec<f64>) = match &sol {
        Ok(s) => (s.states().to_vec(), s.times().to_vec()),
        Err(fl) => (fl.solution.states().to_vec(), fl.solution.times().to_vec()),
    };
    let every = (states.len() / 400).max(1);
    for (k, (y, t)) in states.iter().zip(&times).enumerate() {
        if k % every == 0 {
            let z = m.position(y)[2];
            writeln!(f, "dopri5_tol1e-10,{t},{:e},{:e},{:e}", z.acosh(), m.defect(y), ((m.energy(y) - e0) / e0).abs())?;
        }
    }
    if let Err(fl) = sol {
        eprintln!("  H² dopri5 stopped: {}", fl.error);
    }
    eprintln!("  stability: H² done");
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
    run_problem(&s2_pole(), &rkmk_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&h2_gyro(), &rkmk_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&h2_lorentz(), &rkmk_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&t2_gyro(), &rkmk_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&s3_gyro(), &rkmk_table(), 20_000, q, &mut csv, &mut refs);
    run_problem(&s2_affine(), &rkmk_table(), 40_000, q, &mut csv, &mut refs);
    run_problem(&t2_affine(), &rkmk_table(), 40_000, q, &mut csv, &mut refs);
    defect_series(&a.out, q)?;
    stability(&a.out, q)?;

    std::fs::write(format!("{}/wp_rust.csv", a.out), csv)?;
    std::fs::write(format!("{}/references.csv", a.out), refs)?;
    eprintln!("written: {0}/wp_rust.csv, {0}/references.csv, {0}/s2_problem.csv, {0}/s2_samples.csv, {0}/defect_series.csv", a.out);
    Ok(())
}
