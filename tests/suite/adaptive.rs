//! The adaptive driver: its error norm, first step, rejections, step-size
//! limits and tolerance errors; the tolerance proportionality of DOP853 and
//! DOPRI5 (their global error against `tol`) on a sharp Kepler pericentre
//! passage, a stiff affine body, a smooth gyroscope, an escape on H² and a
//! pole passage on S²; the global-error estimate of a scene; the energy
//! projection (`[method] project = "energy"`).
//!
//! The error of a run is measured in the variables a user reads — the
//! embedded position, velocity, each body-frame vector and the internal
//! momenta — as `max over records and quantities of ‖δ‖₂/(1 + ‖ref‖₂)`
//! (the same definition as `scripts/tolerance_proportionality.py`), against
//! a fixed-step DOP853 reference (no step-size control involved) whose own
//! error is checked by halving its step. Measured numbers:
//! `cargo test --workspace --test methods adaptive -- --nocapture`.

use std::sync::atomic::AtomicBool;

use framedyn::dynamics::System;
use framedyn::lie::Rn;
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::scenes::{MemorySink, Quantity, Scene};
use framedyn::solve::{solve, Adaptive, Controller, Options, Problem, Projection, Save, SolveError, Stats, Tol, RTOL_MIN};
use nalgebra::{Vector1, Vector2};

/// A scene from its TOML tables and a `[method]` table.
fn scene(body: &str, method: &str, t_end: f64, samples: usize) -> Scene {
    let text = format!("{body}\n[method]\n{method}\nmax_steps = 10000000\n[time]\nt0 = 0.0\nt_end = {t_end}\n[output]\nsamples = {samples}\n");
    Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn run(s: &Scene) -> (MemorySink, u64) {
    let mut sim = s.build().unwrap();
    let mut sink = MemorySink::default();
    let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap_or_else(|f| panic!("{f}"));
    (sink, summary.rhs_evals)
}

/// The column indices of each measured vector: position, velocity, each
/// frame vector (`e1_*`, `e2_*`, …) and the momenta.
fn quantities(sink: &MemorySink) -> Vec<Vec<usize>> {
    let of = |q: Quantity| sink.columns.iter().enumerate().filter(|(_, c)| c.group == Some(q)).map(|(j, _)| j).collect::<Vec<_>>();
    let mut out = vec![of(Quantity::Position), of(Quantity::Velocity)];
    let frame = of(Quantity::Frame);
    let mut prefixes: Vec<String> = frame.iter().map(|&j| sink.columns[j].name.split('_').next().unwrap().to_string()).collect();
    prefixes.dedup();
    for p in prefixes {
        out.push(frame.iter().copied().filter(|&j| sink.columns[j].name.split('_').next() == Some(p.as_str())).collect());
    }
    let momenta = of(Quantity::Momenta);
    if !momenta.is_empty() {
        out.push(momenta);
    }
    out
}

/// `max over records and quantities of ‖a − b‖₂/(1 + ‖b‖₂)`.
fn error(a: &MemorySink, b: &MemorySink) -> f64 {
    assert_eq!(a.rows.len(), b.rows.len());
    let qs = quantities(b);
    let mut worst = 0.0f64;
    for (ra, rb) in a.rows.iter().zip(&b.rows) {
        assert_eq!(ra[0], rb[0], "records at the same times");
        for q in &qs {
            let d = q.iter().map(|&j| (ra[j] - rb[j]).powi(2)).sum::<f64>().sqrt();
            let n = q.iter().map(|&j| rb[j].powi(2)).sum::<f64>().sqrt();
            worst = worst.max(d / (1.0 + n));
        }
    }
    worst
}

/// Least-squares slope of `log err` against `log tol`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|&(t, e)| (t.ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Runs `method` at tol = 1e-6 … 1e-10 (rtol = atol = tol); returns
/// `(tol, error)`; checks the reference (fixed-step DOP853 with `h_ref`)
/// against one with twice the step first: their difference is about 255
/// times the reference's own error (order 8), and must be below `ref_tol`.
fn errors(label: &str, body: &str, t_end: f64, h_ref: f64, ref_tol: f64) -> Vec<(&'static str, Vec<(f64, f64)>)> {
    errors_with(label, body, t_end, h_ref, ref_tol, "")
}

/// [`errors`] with `extra` lines in the adaptive runs' `[method]` table.
fn errors_with(label: &str, body: &str, t_end: f64, h_ref: f64, ref_tol: f64, extra: &str) -> Vec<(&'static str, Vec<(f64, f64)>)> {
    let samples = 161;
    let (reference, _) = run(&scene(body, &format!("name = \"dop853\"\nh = {h_ref}"), t_end, samples));
    let (coarse, _) = run(&scene(body, &format!("name = \"dop853\"\nh = {}", 2.0 * h_ref), t_end, samples));
    let ref_err = error(&coarse, &reference);
    eprintln!("{label}: reference h = {h_ref}: differs from h = {} by {ref_err:.1e}", 2.0 * h_ref);
    assert!(ref_err < ref_tol, "{label}: reference not converged ({ref_err:e})");
    let mut out = Vec::new();
    for method in ["dop853", "dopri5"] {
        let mut row = Vec::new();
        for k in 6..=10 {
            let tol = 10f64.powi(-k);
            let (sol, rhs) = run(&scene(body, &format!("name = \"{method}\"\nrtol = {tol:e}\natol = {tol:e}\n{extra}"), t_end, samples));
            let e = error(&sol, &reference);
            eprintln!("{label} {method} {extra} tol {tol:.0e}: max error {e:.2e} = {:.3} × tol, {rhs} rhs evaluations", e / tol);
            row.push((tol, e));
        }
        eprintln!("{label} {method}: slope {:.3}", slope(&row));
        out.push((if method == "dop853" { "dop853" } else { "dopri5" }, row));
    }
    out
}

/// Every error within `bound × tol`; the slope in [0.8, 1.2] for the methods
/// in `slopes`.
fn check(label: &str, results: &[(&str, Vec<(f64, f64)>)], bound: &[(&str, f64)], slopes: &[&str]) {
    for (method, row) in results {
        let b = bound.iter().find(|(m, _)| m == method).unwrap().1;
        for &(tol, e) in row {
            assert!(e <= b * tol, "{label} {method} tol {tol:e}: error {e:e} = {:.1} × tol > {b} × tol", e / tol);
        }
        if slopes.contains(method) {
            let s = slope(row);
            assert!((0.8..=1.2).contains(&s), "{label} {method}: slope of log error against log tol {s:.3} outside [0.8, 1.2]");
        }
    }
}

const H2_KEPLER: &str = r#"
[manifold]
kind = "H2"
radius = 1.0
[body]
kind = "gyroscope"
inertia = 0.2
[potential]
kind = "kepler"
alpha = 1.0
[initial]
r = 1.0
phi = 0.0
r_dot = 0.0
phi_dot = 0.3
spin = 0.1
"#;

const S2_AFFINE_STIFF: &str = r#"
[manifold]
kind = "S2"
radius = 1.0
[body]
kind = "affine"
mass = 1.0
inertia = 0.1
[potential]
kind = "elastic"
kappa = 100.0
[initial]
r = 0.7
phi = 0.0
r_dot = 0.0
phi_dot = 0.6
rho = [[1.1, 0.0], [0.0, 0.9]]
rho_dot = [[0.0, 0.2], [-0.1, 0.0]]
"#;

const S2_GYRO: &str = r#"
[manifold]
kind = "S2"
radius = 1.0
[body]
kind = "gyroscope"
inertia = 0.2
[potential]
kind = "cosine"
alpha_hat = 0.0
beta_hat = -0.3
[initial]
r = 0.6
phi = 0.0
r_dot = 0.3
phi_dot = 0.8
spin = 0.2
"#;

/// Measures: on an H² gyroscope in the Kepler-type potential with a
/// pericentre passage at r ≈ 0.13 R (the flow amplifies every local error
/// there: no local-error controller keeps this near tol), DOP853's error is
/// proportional to tol (slope in [0.8, 1.2]; DOPRI5's is 1.2, its error at
/// tol 1e-6 being the largest) and within 2000 × tol, DOPRI5's within
/// 4000 × tol (measured: 490 – 1310 × tol and 270 – 2630 × tol). With a
/// root-mean-square error norm over the components instead of the maximum,
/// DOP853 reached 4790 × tol and DOPRI5 8810 × tol.
#[test]
fn adaptive_error_is_proportional_to_tol_through_a_kepler_pericentre() {
    let r = errors("H² gyroscope Kepler", H2_KEPLER, 8.0, 1e-4, 1e-10);
    check("H² gyroscope Kepler", &r, &[("dop853", 2000.0), ("dopri5", 4000.0)], &["dop853"]);
}

const S2_KEPLER_POINT: &str = r#"
[manifold]
kind = "S2"
radius = 1.0
[body]
kind = "point"
mass = 1.0
[potential]
kind = "kepler"
alpha = 1.0
[initial]
r = 1.0
phi = 0.0
r_dot = 0.0
phi_dot = 0.3
"#;

/// Measures: with `[method] project = "energy"` (every accepted step put
/// back on the initial energy), the Kepler pericentre passages of a point on
/// S² (r_min = 0.023 R) and of the H² gyroscope above no longer turn each
/// passage's energy error into a growing phase error: DOP853 stays within
/// 30 × tol and DOPRI5 within 100 × tol at tol 1e-6 … 1e-10, proportionally
/// to tol (measured: DOP853 5.9 – 13.5 × on S², 1.1 – 3.6 × on H²; DOPRI5
/// 32 – 44 × and 18 – 61 ×; slopes 0.86 – 1.13). Without the projection the
/// same runs are 450 – 3 700 × tol (DOP853) and 220 – 11 000 × tol (DOPRI5),
/// and scipy's DOP853 68 – 7 000 × tol (`scripts/tolerance_proportionality.py`).
#[test]
fn energy_projection_keeps_kepler_passages_near_tol() {
    for (label, body, h_ref) in [("S² point Kepler", S2_KEPLER_POINT, 5e-5), ("H² gyroscope Kepler", H2_KEPLER, 1e-4)] {
        let r = errors_with(label, body, 8.0, h_ref, 1e-10, "project = \"energy\"");
        check(label, &r, &[("dop853", 30.0), ("dopri5", 100.0)], &["dop853", "dopri5"]);
    }
}

/// Measures: on a stiff elastic affine body (κ = 100) on S², which does not
/// amplify errors strongly, DOP853 stays within 20 × tol and DOPRI5 within
/// 50 × tol (the targets of issue 22), proportionally to tol (measured:
/// 4.8 – 8.5 × and 25 – 34 × tol). A root-mean-square norm over the 13
/// components reached 30 × and 103 × tol.
#[test]
fn adaptive_error_is_proportional_to_tol_on_a_stiff_affine_body() {
    let r = errors("S² affine κ = 100", S2_AFFINE_STIFF, 4.0, 1e-4, 1e-12);
    check("S² affine κ = 100", &r, &[("dop853", 20.0), ("dopri5", 50.0)], &["dop853", "dopri5"]);
}

/// Measures: on a smooth S² gyroscope both methods stay within 20 × tol
/// (DOP853) and 50 × tol (DOPRI5), proportionally to tol (measured: 0.7 –
/// 1.5 × and 1.8 – 2.6 × tol; with a root-mean-square norm too).
#[test]
fn adaptive_error_is_proportional_to_tol_on_a_smooth_gyroscope() {
    let r = errors("S² gyroscope", S2_GYRO, 10.0, 2e-3, 1e-12);
    check("S² gyroscope", &r, &[("dop853", 20.0), ("dopri5", 50.0)], &["dop853", "dopri5"]);
}

const H2_ESCAPE: &str = r#"
[manifold]
kind = "H2"
radius = 1.0
[body]
kind = "point"
[potential]
kind = "oscillator"
kappa = 1.0
[initial]
r = 0.5
phi = 0.0
r_dot = 1.2
phi_dot = 0.1
"#;

const S2_POLE: &str = r#"
[manifold]
kind = "S2"
radius = 1.0
[body]
kind = "gyroscope"
inertia = 0.2
[potential]
kind = "cosine"
alpha_hat = 0.0
beta_hat = -0.3
[initial]
r = 0.6
phi = 0.0
r_dot = -1.0
phi_dot = 1e-7
alpha = 0.3
spin = 0.0
"#;

/// Measures: on short runs whose optimal step changes a lot — an escape on
/// H² to r = 17 R and a passage 3e-8 R from the S² pole — DOP853's error is
/// proportional to tol (slope in [0.8, 1.2]) and within 20 × tol, DOPRI5's
/// within 50 × tol (measured: escape 0.24 – 1.2 × and 7.0 – 12.5 × tol,
/// pole 0.47 – 0.96 × and 0.46 – 0.78 × tol). The test fails if the first
/// step of [HNW93] is accepted as it is (no probe): DOP853's error then
/// falls to 0.009 × and 0.03 × tol at tol 1e-6 — the run is a ramp of
/// under-sized steps there — with slopes 0.62 and 0.64 over these
/// tolerances. On the escape the global-error estimate of the run at
/// tol 1e-11 is within a factor 3 of the error at the last record too
/// (measured 1.01; without the probe 3.46, the reference run at tol/100
/// being only 36 × more accurate than the run, not 100 ×).
#[test]
fn adaptive_error_is_proportional_to_tol_on_an_escape_and_a_pole_passage() {
    let r = errors("H² escape", H2_ESCAPE, 20.0, 2e-3, 1e-12);
    check("H² escape", &r, &[("dop853", 20.0), ("dopri5", 50.0)], &["dop853", "dopri5"]);
    let r = errors("S² pole passage", S2_POLE, 4.0, 1e-3, 1e-12);
    check("S² pole passage", &r, &[("dop853", 20.0), ("dopri5", 50.0)], &["dop853", "dopri5"]);

    let samples = 161;
    let (reference, _) = run(&scene(H2_ESCAPE, "name = \"dop853\"\nh = 2e-3", 20.0, samples));
    let asked = scene(H2_ESCAPE, "name = \"dop853\"\nrtol = 1e-11\natol = 1e-11\nglobal_error = true", 20.0, samples);
    let mut sim = asked.build().unwrap();
    let mut sink = MemorySink::default();
    let g = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap().global_error.expect("an estimate");
    let last = |s: &MemorySink| MemorySink { columns: s.columns.clone(), rows: vec![s.rows.last().unwrap().clone()], events: Vec::new() };
    let (true_max, true_last) = (error(&sink, &reference), error(&last(&sink), &last(&reference)));
    eprintln!("H² escape tol 1e-11: estimate max {:.3e} / {true_max:.3e} = {:.2}, last {:.3e} / {true_last:.3e} = {:.2}", g.max, g.max / true_max, g.last, g.last / true_last);
    assert!((1.0 / 3.0..=3.0).contains(&(g.max / true_max)), "estimate {:e}, error {true_max:e}", g.max);
    assert!((1.0 / 3.0..=3.0).contains(&(g.last / true_last)), "estimate at the last record {:e}, error {true_last:e}", g.last);
}

// ---------------------------------------------------------------------------
// The driver: error norm, first step, rejections, limits, tolerance errors
// ---------------------------------------------------------------------------

/// `ẏ = λy` on ℝ (left-trivialised on the additive group: `f = λy`).
#[derive(Debug, Clone)]
struct Growth(f64);
impl System for Growth {
    type State = Rn<1>;
    fn vector_field(&self, _t: f64, y: &Rn<1>) -> Vector1<f64> {
        y.0 * self.0
    }
    fn energy(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
    fn defect(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
}

/// The harmonic oscillator `(q, p)` on ℝ².
#[derive(Debug, Clone)]
struct Oscillator;
impl System for Oscillator {
    type State = Rn<2>;
    fn vector_field(&self, _t: f64, y: &Rn<2>) -> Vector2<f64> {
        Vector2::new(y.0[1], -y.0[0])
    }
    fn energy(&self, y: &Rn<2>) -> f64 {
        0.5 * y.0.norm_squared()
    }
    fn defect(&self, _y: &Rn<2>) -> f64 {
        0.0
    }
}

/// Measures: the error norm is the largest scaled component,
/// `maxᵢ |eᵢ|/(atolᵢ + rtolᵢ·max(s0ᵢ, s1ᵢ))`.
#[test]
fn error_norm_is_the_largest_scaled_component() {
    use framedyn::__internals::error_norm;
    let e = Vector2::new(3e-6, 1e-6);
    let s = Vector2::new(2.0, 0.0);
    let tol = Vector2::new(1e-6, 1e-6);
    // sc = (1e-6 + 1e-6·2, 1e-6): ratios (1, 1).
    assert!((error_norm(&e, &s, &s, &tol, &tol) - 1.0).abs() < 1e-15);
    // The larger of the two reference magnitudes is used.
    let s1 = Vector2::new(5.0, 0.0);
    assert!((error_norm(&Vector2::new(3e-6, 0.0), &s, &s1, &tol, &tol) - 0.5).abs() < 1e-15);
    // One component 10 % over its tolerance fails the step however small
    // the others are (a root-mean-square would pass it at 1.1/√2).
    assert!(error_norm(&Vector2::new(3.3e-6, 0.0), &s, &s, &tol, &tol) > 1.0);
    assert!(error_norm(&Vector2::new(f64::NAN, 0.0), &s, &s, &tol, &tol).is_nan());
}

/// Measures: the first trial step is that of [HNW93] §II.4, computed here
/// by hand for `ẏ = λy`, `y₀ = 1`, DOP853 (`q = 7`), `atol = rtol = tol`:
/// `d₀ = 1/(2tol)`, `d₁ = λ/(2tol)`, `h = 0.01·d₀/d₁ = 0.01/λ`, the Euler step
/// `y₁ = 1 + λh`, `d₂ = |λy₁ − λ|/(2 tol h) = λ²/(2tol)`,
/// `h₁ = (0.01/max(d₁, d₂))^{1/8}`, `h₀ = min(100h, h₁)`. It is a probe:
/// while the PI controller's own next step (`0.9·err^{−α}·err_prev^β`,
/// `α = 1/8 − 0.75·0.04`, `β = 0.04`, `err_prev = 1e-4`) would leave the
/// error of an `O(h⁸)` estimate below 1e-2, it is taken again with
/// `h·clamp((0.9^{1/(α−β)}/err)^{1/8}, 1, 10)`, at most three times; the
/// first accepted step is the end of that chain, replayed here with the
/// method's own steps and error norm (to 1e-6: the estimate, 5e-12 here, is
/// a difference of stage sums of size λh ≈ 0.25, so it is known to ~1e-16/5e-12
/// relative, and its 8th root, the growth, to ~1e-6 — the driver's first
/// step differs from the formula's in its last bits). A first step the user gives (`h0`) is taken as given, and
/// `h_max` caps it. DOPRI5, whose controller climbs faster, keeps the first
/// step here (its error norm 2e-4 would reach 0.03 in one step).
#[test]
fn first_step_follows_hairer_and_is_a_probe() {
    use framedyn::__internals::error_norm;
    use framedyn::method::{Method, StepRequest};
    let (lambda, tol) = (3.0_f64, 1e-6_f64);
    let y0 = Rn(Vector1::new(1.0));
    let p = Problem::new(Growth(lambda), y0, (0.0, 1.0)).unwrap();
    let h = 0.01 / lambda;
    let (d1, d2) = (lambda / (2.0 * tol), lambda * lambda / (2.0 * tol));
    let (alpha, beta) = (1.0 / 8.0 - 0.75 * 0.04, 0.04);
    let aim = 0.9f64.powf(1.0 / (alpha - beta));
    let tv = Vector1::new(tol);
    for (name, q) in [("dop853", 7), ("dopri5", 4)] {
        let hairer = (100.0 * h).min((0.01 / d1.max(d2)).powf(1.0 / (q as f64 + 1.0)));
        let mut want = hairer;
        let mut probes = 0;
        if q == 7 {
            for _ in 0..3 {
                // The driver's request (f(t₀, y₀) known; DOP853 is not FSAL).
                let req = StepRequest { f_start: Some(y0.0 * lambda), error: true, dense: false, f_end: false };
                let out = Method::step(&Rkmk::dop853(), &Growth(lambda), 0.0, &y0, want, req).unwrap();
                let err = error_norm(&out.error.unwrap(), &y0.tolerance_scale(), &out.y.tolerance_scale(), &tv, &tv);
                let ramp = err * (0.9 * err.powf(-alpha) * 1e-4f64.powf(beta)).clamp(0.2, 10.0).powf(8.0);
                eprintln!("first step {want:e}: error norm {err:.3e}, the controller's next {ramp:.3e}");
                if ramp >= 1e-2 || want >= 1.0 {
                    break;
                }
                want *= (aim / err).powf(1.0 / 8.0).clamp(1.0, 10.0);
                probes += 1;
            }
        }
        let opts = Options::adaptive(tol, tol).save(Save::Steps);
        let sol = if q == 7 { solve(&p, &Rkmk::dop853(), &opts) } else { solve(&p, &Rkmk::dopri5(), &opts) }.unwrap();
        let first = sol.times()[1];
        eprintln!("{name}: Hairer's first step {hairer:e}; after {probes} probes {want:e}; taken {first:e}");
        assert!((first - want).abs() <= 1e-6 * want, "{name}: first step {first:e}, by hand {want:e}");
        assert_eq!((sol.stats().rejected, sol.stats().first_step_probes), (0, probes), "{name}: a probe is not a rejection");
        if q == 7 {
            assert!(probes >= 1 && want > 2.0 * hairer, "the test should exercise the probe");
        }
    }
    // Given by the user: taken as given (no probe).
    let hairer = (100.0 * h).min((0.01 / d1.max(d2)).powf(1.0 / 8.0));
    let given = Adaptive { h0: Some(hairer), ..Adaptive::new(tol, tol) };
    let sol = solve(&p, &Rkmk::dop853(), &Options::adaptive_with(given).save(Save::Steps)).unwrap();
    assert_eq!((sol.times()[1], sol.stats().first_step_probes), (hairer, 0));
    let a = Adaptive { h_max: 1e-3, ..Adaptive::new(tol, tol) };
    let capped = solve(&p, &Rkmk::dop853(), &Options::adaptive_with(a).save(Save::Steps)).unwrap();
    assert_eq!(capped.times()[1], 1e-3);
}

/// Measures: a component that is zero at `t₀` is scaled by `atol` alone; an
/// `atol` that makes the first step underflow is an error naming `atol`.
#[test]
fn an_underflowing_first_step_names_atol() {
    let p = Problem::new(Oscillator, Rn(Vector2::new(1.0, 0.0)), (0.0, 1.0)).unwrap();
    let f = solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-300)).expect_err("underflow");
    // The value as the user would write it, not 1e-300 as 300 decimals.
    let message = f.error.to_string();
    assert!(message.starts_with("invalid atol = 1e-300: must be"), "{message}");
    match f.error {
        SolveError::InvalidParameter { field, value, .. } => assert_eq!((field, value), ("atol", 1e-300)),
        e => panic!("wrong error {e:?}"),
    }
    assert!(solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-12)).is_ok());
}

/// Measures: `rtol` below 1e-14, not finite or not positive, and `atol`
/// not finite or not positive (also one component of a per-component
/// tolerance) are typed errors naming the field, before any work.
#[test]
fn tolerances_out_of_range_are_typed_errors() {
    let p = Problem::new(Oscillator, Rn(Vector2::new(1.0, 0.0)), (0.0, 1.0)).unwrap();
    let cases: [(f64, f64, &str); 8] = [
        (0.0, 1e-8, "rtol"),
        (-1e-8, 1e-8, "rtol"),
        (f64::NAN, 1e-8, "rtol"),
        (1e-300, 1e-300, "rtol"),
        (1e-15, 1e-8, "rtol"),
        (1e-8, 0.0, "atol"),
        (1e-8, -1.0, "atol"),
        (1e-8, f64::INFINITY, "atol"),
    ];
    for (rtol, atol, field) in cases {
        let f = solve(&p, &Rkmk::dopri5(), &Options::adaptive(rtol, atol)).expect_err("bad tolerance");
        match f.error {
            SolveError::InvalidParameter { field: got, .. } => assert_eq!(got, field, "rtol {rtol:e}, atol {atol:e}"),
            e => panic!("rtol {rtol:e}, atol {atol:e}: wrong error {e:?}"),
        }
        assert_eq!(f.solution.stats().rhs_evals, 0, "validated before any work");
    }
    let per = Adaptive { atol: Tol::PerComponent(vec![1e-8, 0.0]), ..Adaptive::new(1e-8, 1e-8) };
    assert!(matches!(
        solve(&p, &Rkmk::dopri5(), &Options::adaptive_with(per)).unwrap_err().error,
        SolveError::InvalidParameter { field: "atol", .. }
    ));
    assert!(solve(&p, &Rkmk::dopri5(), &Options::adaptive(RTOL_MIN, 1e-14)).is_ok());
}

/// Measures: a first step far too large for the tolerance is rejected and
/// shrunk by at most `fac_min` = 0.2 per rejection, and the run still ends
/// accurate; `h_max` bounds every accepted step; `fac_max` bounds the growth
/// between accepted steps.
#[test]
fn rejections_and_step_size_limits() {
    let t_end = 6.0;
    let p = Problem::new(Oscillator, Rn(Vector2::new(1.0, 0.0)), (0.0, t_end)).unwrap();

    let a = Adaptive { h0: Some(3.0), ..Adaptive::new(1e-9, 1e-9) };
    let sol = solve(&p, &Rkmk::dopri5(), &Options::adaptive_with(a).save(Save::Steps)).unwrap();
    let st = sol.stats();
    assert!(st.rejected >= 2, "rejected {}", st.rejected);
    let first = sol.times()[1];
    assert!(first >= 3.0 * 0.2f64.powi(st.rejected as i32) * (1.0 - 1e-12) && first < 3.0, "first accepted step {first}");
    let y = sol.last().1 .0;
    let err = (y - Vector2::new(t_end.cos(), -t_end.sin())).abs().max();
    assert!(err < 1e-7, "error after rejections {err:e}");

    let a = Adaptive { h_max: 0.05, ..Adaptive::new(1e-6, 1e-6) };
    let sol = solve(&p, &Rkmk::dop853(), &Options::adaptive_with(a).save(Save::Steps)).unwrap();
    assert!(sol.times().windows(2).all(|w| w[1] - w[0] <= 0.05 * (1.0 + 1e-12)));

    let ctl = Controller { fac_max: 1.5, ..Controller::pi() };
    let a = Adaptive { h0: Some(1e-4), controller: ctl, ..Adaptive::new(1e-6, 1e-6) };
    let sol = solve(&p, &Rkmk::dopri5(), &Options::adaptive_with(a).save(Save::Steps)).unwrap();
    let hs: Vec<f64> = sol.times().windows(2).map(|w| w[1] - w[0]).collect();
    // (The last step is cut to land on t_end.)
    for w in hs[..hs.len() - 1].windows(2) {
        assert!(w[1] <= 1.5 * w[0] * (1.0 + 1e-12), "growth {} > fac_max", w[1] / w[0]);
    }
    assert!(hs[1] > hs[0], "the step grows from a tiny h0");
}

/// Measures: the reference magnitude of an additive factor is the size of
/// each of its coordinates.
#[test]
fn additive_scale_is_the_coordinates() {
    assert_eq!(Rn(Vector2::new(-3.0, 0.5)).tolerance_scale(), Vector2::new(3.0, 0.5));
}

// ---------------------------------------------------------------------------
// The global-error estimate of a scene
// ---------------------------------------------------------------------------

/// Measures: with `[method] global_error = true` the summary carries an
/// estimate of the run's error (max over the records, and at the last one)
/// within a factor 3 of the error measured against the fixed-step reference
/// — on the Kepler passage (adaptive DOP853 and DOPRI5) and with a fixed
/// step (RK4); a run that does not ask has none and costs the same as before.
#[test]
fn global_error_estimate_is_within_a_factor_3() {
    let samples = 161;
    let (reference, _) = run(&scene(H2_KEPLER, "name = \"dop853\"\nh = 1e-4", 8.0, samples));
    for method in ["name = \"dop853\"\nrtol = 1e-8\natol = 1e-8", "name = \"dopri5\"\nrtol = 1e-7\natol = 1e-7", "name = \"rk4\"\nh = 2e-3"] {
        let plain = scene(H2_KEPLER, method, 8.0, samples);
        let asked = scene(H2_KEPLER, &format!("{method}\nglobal_error = true"), 8.0, samples);
        let mut sim = asked.build().unwrap();
        let mut sink = MemorySink::default();
        let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
        let g = summary.global_error.expect("an estimate");
        let true_max = error(&sink, &reference);
        let last = |s: &MemorySink| MemorySink { columns: s.columns.clone(), rows: vec![s.rows.last().unwrap().clone()], events: Vec::new() };
        let true_last = error(&last(&sink), &last(&reference));
        eprintln!(
            "{}: estimate max {:.3e} (true {true_max:.3e}, ratio {:.2}), last {:.3e} (true {true_last:.3e}, ratio {:.2}); reference run {} rhs",
            method.replace('\n', " "),
            g.max,
            g.max / true_max,
            g.last,
            g.last / true_last,
            g.rhs_evals
        );
        assert!((1.0 / 3.0..=3.0).contains(&(g.max / true_max)), "{method}: estimate {:e}, error {true_max:e}", g.max);
        assert!((1.0 / 3.0..=3.0).contains(&(g.last / true_last)), "{method}: estimate {:e}, error {true_last:e}", g.last);
        assert!(summary.to_string().contains("global error:"));
        let mut sim = plain.build().unwrap();
        let mut sink2 = MemorySink::default();
        let s2 = sim.run(&mut sink2, &AtomicBool::new(false), &mut |_| {}).unwrap();
        assert!(s2.global_error.is_none() && !s2.to_string().contains("global error"));
        assert_eq!((s2.steps, s2.rhs_evals), (summary.steps, summary.rhs_evals), "the run itself is the same");
        assert_eq!(sink2.rows, sink.rows, "the same records");
    }
}

// ---------------------------------------------------------------------------
// Energy projection (`Options::project`, `[method] project = "energy"`)
// ---------------------------------------------------------------------------

/// The error at `t_end` of RK4 with fixed step `h` on the oscillator from
/// `(1, 0)` (exact: `(cos t, −sin t)`), and the run's statistics and largest
/// energy deviation over its steps.
fn oscillator_rk4(h: f64, t_end: f64, projection: Projection) -> (f64, Stats, f64) {
    let p = Problem::new(Oscillator, Rn(Vector2::new(1.0, 0.0)), (0.0, t_end)).unwrap();
    let sol = solve(&p, &Rkmk::rk4(), &Options::fixed(h).project(projection).save(Save::Steps)).unwrap();
    let y = sol.states().last().unwrap().0;
    let err = (y - Vector2::new(t_end.cos(), -t_end.sin())).norm();
    let drift = sol.states().iter().map(|s| (0.5 * s.0.norm_squared() - 0.5).abs()).fold(0.0, f64::max);
    (err, *sol.stats(), drift)
}

/// Measures: with the energy projection, fixed-step RK4 on the harmonic
/// oscillator keeps the energy to round-off at every step (without it the
/// energy decays by 1e-5 over t = 20 at h = 0.2), its error still falls
/// like h⁴ (the correction is of the size of the local energy error), and
/// the error is smaller than without it (the amplitude error is gone, the
/// phase error is left). Every step is projected; each projection costs one
/// energy evaluation per algebra coordinate (2) plus the residual and the
/// Newton steps.
#[test]
fn energy_projection_holds_the_energy_and_keeps_the_order() {
    let t_end = 20.0;
    let mut errs = Vec::new();
    for h in [0.2, 0.1, 0.05] {
        let (e, stats, drift) = oscillator_rk4(h, t_end, Projection::Energy);
        let (e_plain, plain, drift_plain) = oscillator_rk4(h, t_end, Projection::None);
        eprintln!("h {h}: projected error {e:.3e}, energy drift {drift:.1e}; plain {e_plain:.3e}, {drift_plain:.1e}; {} energy evaluations / {} steps", stats.energy_evals, stats.accepted);
        assert!(drift <= 2e-15, "h {h}: energy drift {drift:e} with the projection (E = 0.5: a few ε)");
        assert!(drift_plain > 1e-9, "h {h}: the plain run's drift {drift_plain:e} (the test needs one)");
        assert!(e < e_plain, "h {h}: projected error {e:e} not below the plain {e_plain:e}");
        assert_eq!((stats.projections, stats.projections_skipped), (stats.accepted, 0));
        assert!(stats.energy_evals >= 3 * stats.accepted && stats.energy_evals <= 6 * stats.accepted, "{stats:?}");
        assert_eq!((plain.projections, plain.energy_evals), (0, 0), "a run that does not ask pays nothing");
        assert_eq!(stats.rhs_evals, plain.rhs_evals, "RK4 has no FSAL stage to lose");
        errs.push(e);
    }
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((3.7..=4.3).contains(&order), "observed order {order:.2} with the projection");
    }
}

/// `ẋ = 1` on ℝ with an energy that is 0 at the start and 1 everywhere
/// else: flat around every later state, so the projection has no gradient
/// to follow.
#[derive(Debug, Clone)]
struct Plateau;
impl System for Plateau {
    type State = Rn<1>;
    fn vector_field(&self, _t: f64, _y: &Rn<1>) -> Vector1<f64> {
        Vector1::new(1.0)
    }
    fn energy(&self, y: &Rn<1>) -> f64 {
        if y.0[0] == 0.0 {
            0.0
        } else {
            1.0
        }
    }
    fn defect(&self, _y: &Rn<1>) -> f64 {
        0.0
    }
}

/// Measures: where the energy has no gradient the projection is skipped,
/// counted, and the state is the method's own; a scene's summary turns
/// skipped projections into a quality warning. An initial energy that is
/// not finite is an error naming the projection, before any step.
#[test]
fn energy_projection_skips_where_it_cannot_and_says_so() {
    let p = Problem::new(Plateau, Rn(Vector1::new(0.0)), (0.0, 1.0)).unwrap();
    let sol = solve(&p, &Rkmk::rk4(), &Options::fixed(0.25).project(Projection::Energy)).unwrap();
    let s = sol.stats();
    assert_eq!((s.accepted, s.projections, s.projections_skipped), (4, 0, 4));
    assert!((sol.states().last().unwrap().0[0] - 1.0).abs() < 1e-15, "the method's own states");

    let mut summary = framedyn::scenes::RunSummary::new("rk4", 0.0);
    (summary.records, summary.energy_initial, summary.steps) = (1, 1.0, 10);
    summary.projection = Some(framedyn::scenes::ProjectionCounts { projected: 7, skipped: 3, energy_evals: 70 });
    summary.judge((1.0, 1.0));
    let texts = summary.warning_texts();
    assert!(texts.iter().any(|t| t.contains("skipped on 3 of 10 steps")), "{texts:?}");
    assert!(summary.to_string().contains("projection:      energy, 7 steps projected, 3 skipped (70 energy evaluations)"));

    #[derive(Debug, Clone)]
    struct Undefined;
    impl System for Undefined {
        type State = Rn<1>;
        fn vector_field(&self, _t: f64, _y: &Rn<1>) -> Vector1<f64> {
            Vector1::new(1.0)
        }
        fn energy(&self, _y: &Rn<1>) -> f64 {
            f64::NAN
        }
        fn defect(&self, _y: &Rn<1>) -> f64 {
            0.0
        }
    }
    let p = Problem::new(Undefined, Rn(Vector1::new(0.0)), (0.0, 1.0)).unwrap();
    let f = solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-8).project(Projection::Energy)).unwrap_err();
    assert!(matches!(&f.error, SolveError::InvalidOptions { reason } if reason.contains("projection") && reason.contains("NaN")), "{:?}", f.error);
    assert_eq!(f.solution.stats().rhs_evals, 0);
    assert!(solve(&p, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-8)).is_ok(), "without the projection the energy is not needed");
}

/// Measures: `[method] project` of a scene: `"energy"` holds the energy
/// recorded at the ends of the steps (DOP853 at tol 1e-8 on the S² Kepler
/// point: relative drift below 1e-13, against 1e-6 without) and reports its counts in the summary;
/// `"none"` is the same run as leaving it out; any other value is an error
/// naming `method.project` and the allowed values.
#[test]
fn scene_projection_option() {
    let tol = "name = \"dop853\"\nrtol = 1e-8\natol = 1e-8";
    // Records at the ends of the steps (`every = 1`): samples between them
    // come from the dense output of the unprojected step and carry its
    // local energy error.
    let summary_of = |method: &str| {
        let text = format!("{S2_KEPLER_POINT}\n[method]\n{method}\n[time]\nt_end = 8.0\n[output]\nevery = 1\n");
        let mut sim = Scene::from_toml_str(&text).unwrap().build().unwrap();
        let mut sink = MemorySink::default();
        let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
        (summary, sink)
    };
    let (projected, _) = summary_of(&format!("{tol}\nproject = \"energy\""));
    let (plain, plain_sink) = summary_of(tol);
    let (none, none_sink) = summary_of(&format!("{tol}\nproject = \"none\""));
    eprintln!("relative energy drift: projected {:.2e}, plain {:.2e}", projected.relative_energy_drift(), plain.relative_energy_drift());
    assert!(projected.relative_energy_drift() < 1e-13 && plain.relative_energy_drift() > 1e-9);
    let counts = projected.projection.expect("counts");
    assert_eq!((counts.projected, counts.skipped), (projected.steps, 0));
    assert!(projected.warnings.is_empty(), "{:?}", projected.warnings);
    assert!(projected.to_string().contains("projection:      energy"));
    assert!(plain.projection.is_none() && !plain.to_string().contains("projection"));
    assert_eq!((none.projection, none.steps, none_sink.rows), (None, plain.steps, plain_sink.rows));
    for bad in ["\"momentum\"", "\"Energy\"", "1", "true"] {
        let text = format!("{S2_KEPLER_POINT}\n[method]\n{tol}\nproject = {bad}\n[time]\nt_end = 1.0\n");
        let err = Scene::from_toml_str(&text).and_then(|s| s.build().map(|_| ())).expect_err(bad).to_string();
        assert!(err.contains("method.project") || err.contains("project"), "{bad}: {err}");
        if bad.starts_with('"') {
            assert!(err.contains("\"none\" or \"energy\""), "{bad}: {err}");
        }
    }
}

/// Measures: the stepping API (`Simulation::step`, `advance`; Python
/// `Stepper`) honours `project = "energy"` as a run does, with a group method
/// and with a coordinate method: RK4 at h = 0.05 on the S² gyroscope keeps
/// the energy to round-off over 200 steps where the plain steps drift by
/// more than 1e-9 (measured relative drifts: 4.8e-14 and 3.4e-13 against
/// 3.7e-7 and 3.3e-5; the coordinate method's `advance` projects onto the
/// chart energy, which the conversion back to the model state rounds).
#[test]
fn stepping_projects_when_the_scene_asks() {
    for method in ["rk4", "coordinate_rk4"] {
        let drift = |project: &str| {
            let text = format!("{S2_GYRO}\n[method]\nname = \"{method}\"\nh = 0.05\n{project}\n[time]\nt_end = 10.0\n");
            let mut sim = Scene::from_toml_str(&text).unwrap().build().unwrap();
            let e0 = sim.energy();
            let mut worst = 0.0f64;
            for _ in 0..50 {
                sim.step(0.05).unwrap();
                worst = worst.max((sim.energy() - e0).abs());
            }
            sim.advance(0.05, 150).unwrap();
            worst.max((sim.energy() - e0).abs()) / e0.abs()
        };
        let (projected, plain) = (drift("project = \"energy\""), drift(""));
        eprintln!("{method}: relative energy drift {projected:.1e} projected, {plain:.1e} plain");
        assert!(projected < 1e-12 && plain > 1e-9, "{method}: {projected:e} / {plain:e}");
    }
}
