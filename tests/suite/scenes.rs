//! Scenes: every embedded example parses, validates and runs; errors name the
//! field, the value, what is allowed and the line/column; sampling, stepping,
//! cancellation, adaptive runs and user potentials agree with the direct
//! library calls.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use framedyn::scenes::{example, MemorySink, RunSummary, Scene, SceneError, SceneStop, DEFAULT_SCENE, EXAMPLES};
use proptest::prelude::*;

fn run(scene: &Scene) -> (RunSummary, MemorySink) {
    let mut sim = scene.build().unwrap_or_else(|e| panic!("{:?}: {e}", scene.name));
    let mut sink = MemorySink::default();
    let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap_or_else(|f| panic!("{:?}: {f}", scene.name));
    (summary, sink)
}

fn col(sink: &MemorySink, name: &str) -> Vec<f64> {
    sink.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// Every embedded scene parses, validates and runs to its end with finite
/// records, a conserved energy and a constraint defect at round-off.
#[test]
fn every_example_runs() {
    assert!(EXAMPLES.len() >= 24, "one per manifold x body at least");
    for (name, _) in EXAMPLES {
        let scene = example(name).unwrap();
        scene.validate().unwrap();
        let (s, sink) = run(&scene);
        assert_eq!(s.stop, SceneStop::Finished, "{name}");
        assert!(s.records >= 2 && s.records as usize == sink.rows.len(), "{name}");
        assert!(sink.rows.iter().all(|r| r.len() == sink.columns.len()));
        let t = col(&sink, "t");
        assert_eq!(t[0], scene.time.t0, "{name}");
        assert_eq!(*t.last().unwrap(), scene.time.t_end, "{name}");
        // Energy: RK4 with the scene's step; the drift is O(h⁴) — a
        // wrong force or mass matrix gives O(1).
        let rel = s.relative_energy_drift();
        assert!(rel < 1e-6, "{name}: relative energy drift {rel:e}");
        assert!(s.max_defect < 1e-9, "{name}: defect {:e}", s.max_defect);
        for c in ["x0", "v0", "energy", "defect"] {
            assert!(col(&sink, c).iter().all(|v| v.is_finite()), "{name}: {c}");
        }
    }
}

/// The manifold × body grid is covered, and every potential family.
#[test]
fn examples_cover_every_manifold_body_and_potential() {
    use framedyn::scenes::{BodyKind, ManifoldKind, PotentialKind};
    let scenes: Vec<Scene> = EXAMPLES.iter().map(|(n, _)| example(n).unwrap()).collect();
    for m in [ManifoldKind::S2, ManifoldKind::H2, ManifoldKind::T2, ManifoldKind::S3] {
        for b in [BodyKind::Point, BodyKind::Gyroscope, BodyKind::Affine, BodyKind::Incompressible, BodyKind::Weyl, BodyKind::Dilatation] {
            assert!(scenes.iter().any(|s| s.manifold.kind == m && s.body.kind == b), "{m:?} x {b:?}");
        }
    }
    fn kinds(p: &framedyn::scenes::PotentialSpec, out: &mut Vec<PotentialKind>) {
        out.push(p.kind);
        for t in p.terms.iter().flatten() {
            kinds(t, out);
        }
    }
    let mut all = Vec::new();
    for s in &scenes {
        kinds(&s.potential, &mut all);
    }
    for k in [
        PotentialKind::Oscillator,
        PotentialKind::Kepler,
        PotentialKind::Cosine,
        PotentialKind::Central,
        PotentialKind::Elastic,
        PotentialKind::Separable,
        PotentialKind::NeoHookean,
        PotentialKind::StVenantKirchhoff,
        PotentialKind::Sum,
    ] {
        assert!(all.contains(&k), "{k:?}");
    }
    assert!(scenes.iter().any(|s| s.body.signature == Some(framedyn::scenes::SignatureSpec::Lorentz)));
}

/// The default scene: a gyroscope on S² whose path crosses the north pole
/// (where the paper's chart fails) with bounded energy drift.
#[test]
fn default_scene_crosses_the_pole() {
    let scene = example(DEFAULT_SCENE).unwrap();
    let (s, sink) = run(&scene);
    let (x, y, z) = (col(&sink, "x0"), col(&sink, "x1"), col(&sink, "x2"));
    let r = scene.manifold.radius.unwrap();
    let min_dist = (0..x.len())
        .map(|i| {
            let c = (z[i] / r).clamp(-1.0, 1.0);
            let _ = y[i];
            r * c.acos()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(min_dist < 0.02 * r, "closest approach to the pole {min_dist}");
    // It passes the pole: φ jumps by ≈ π across it (the chart's coordinate singularity).
    assert!(z.iter().any(|&z| z > 0.9995 * r));
    assert!(s.relative_energy_drift() < 1e-8, "{:e}", s.relative_energy_drift());
    assert!(s.max_defect < 1e-12, "{:e}", s.max_defect);
}

/// Bertrand: the S² oscillator orbit is closed — after the period of the
/// ellipse `2π/√(κ/m)·…` the point returns. Checked without the formula:
/// the orbit's minimum distance to its start after the first half-period
/// is reached again with error at the integrator's level.
#[test]
fn bertrand_orbit_closes() {
    let mut scene = example("s2-point-oscillator").unwrap();
    scene.output.every = Some(1);
    let (_, sink) = run(&scene);
    let (x, y, z) = (col(&sink, "x0"), col(&sink, "x1"), col(&sink, "x2"));
    let t = col(&sink, "t");
    let d = |i: usize| ((x[i] - x[0]).powi(2) + (y[i] - y[0]).powi(2) + (z[i] - z[0]).powi(2)).sqrt();
    // First return after leaving: the first local minimum of d beyond the
    // first maximum.
    let n = t.len();
    let imax = (1..n).find(|&i| i + 1 < n && d(i) >= d(i - 1) && d(i) > d(i + 1)).unwrap();
    let imin = (imax..n - 1).find(|&i| d(i) <= d(i - 1) && d(i) < d(i + 1)).unwrap();
    // With h = 0.005 the discrete minimum is within |v|·h of the exact return.
    let speed = (col(&sink, "v0")[0].powi(2) + col(&sink, "v1")[0].powi(2) + col(&sink, "v2")[0].powi(2)).sqrt();
    assert!(d(imin) < speed * 0.005, "return distance {} at t = {}", d(imin), t[imin]);
}

/// H² escape threshold: below sup V the oscillator orbit turns back, above
/// it the point escapes (r keeps growing).
#[test]
fn h2_escape_threshold() {
    let (_, below) = run(&example("h2-point-bound").unwrap());
    let (_, above) = run(&example("h2-point-escape").unwrap());
    let rb = col(&below, "r");
    let ra = col(&above, "r");
    let max_b = rb.iter().cloned().fold(0.0, f64::max);
    assert!((max_b - 0.98f64.sqrt().atanh()).abs() < 1e-3, "turning point {max_b}");
    assert!(rb.last().unwrap() < &max_b);
    assert!(ra.windows(2).all(|w| w[1] > w[0]), "escaping orbit turned back");
    assert!(*ra.last().unwrap() > max_b);
}

/// `every = k` records the initial state, every k-th step and the final state.
#[test]
fn sampling_every_and_times() {
    let mut scene = example(DEFAULT_SCENE).unwrap();
    scene.method.h = Some(0.01);
    scene.time.t_end = 1.0;
    scene.output.every = Some(7);
    let (s, sink) = run(&scene);
    assert_eq!(s.steps, 100);
    assert_eq!(sink.rows.len(), 1 + 100 / 7 + 1);
    scene.output.every = None;
    scene.output.times = Some(vec![0.5, 0.123, 1.0, 0.0]);
    let (s2, sink2) = run(&scene);
    assert_eq!(col(&sink2, "t"), vec![0.0, 0.123, 0.5, 1.0]);
    // Sample times off the step grid are breakpoints: 0.123 adds a step,
    // 0.5 and 1.0 are grid points.
    assert_eq!(s2.steps, 101);
    scene.output.times = None;
    scene.output.samples = Some(11);
    let (_, sink3) = run(&scene);
    assert_eq!(sink3.rows.len(), 11);
}

/// The stepping API reproduces a run.
#[test]
fn stepping_matches_run() {
    let mut scene = example("s3-gyroscope").unwrap();
    scene.time.t_end = 0.5;
    scene.method.h = Some(0.005);
    scene.output.every = Some(1000);
    let (_, sink) = run(&scene);
    let mut sim = scene.build().unwrap();
    sim.advance(0.005, 100).unwrap();
    let row = sim.row();
    let last = sink.rows.last().unwrap();
    for (j, c) in sim.columns().iter().enumerate() {
        let scale = 1.0f64.max(last[j].abs());
        assert!((row[j] - last[j]).abs() <= 1e-12 * scale, "{}: {} vs {}", c.name, row[j], last[j]);
    }
    sim.reset();
    assert_eq!(sim.t(), 0.0);
}

/// A raised cancel flag stops the run cleanly with the last state recorded.
#[test]
fn cancel_stops_cleanly() {
    let scene = example(DEFAULT_SCENE).unwrap();
    let mut sim = scene.build().unwrap();
    let mut sink = MemorySink::default();
    let s = sim.run(&mut sink, &AtomicBool::new(true), &mut |_| {}).unwrap();
    assert_eq!(s.stop, SceneStop::Cancelled);
    assert!(s.steps <= 256 && s.steps > 0);
    assert_eq!(*col(&sink, "t").last().unwrap(), s.t_reached);
}

/// Adaptive DOPRI5 through the scene layer: records exactly at the requested
/// times, agreeing with a fine fixed-step run to the tolerance.
#[test]
fn adaptive_run_agrees_with_fixed() {
    let mut scene = example("s2-point-kepler").unwrap();
    scene.output.every = None;
    scene.output.samples = Some(21);
    let mut fine = scene.clone();
    fine.method.h = Some(0.001);
    let (_, reference) = run(&fine);
    scene.method.name = "dopri5".into();
    scene.method.h = None;
    scene.method.rtol = Some(1e-10);
    scene.method.atol = Some(1e-12);
    let (s, sink) = run(&scene);
    assert_eq!(col(&sink, "t"), col(&reference, "t"));
    assert!(s.steps > 10 && s.steps < 20_000);
    for c in ["x0", "x1", "x2"] {
        let (a, b) = (col(&sink, c), col(&reference, c));
        let err = a.iter().zip(&b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(err < 1e-7, "{c}: {err:e}");
    }
    // Many chunks: more steps than one chunk of the streamed driver.
    scene.time.t_end = 200.0;
    scene.output.samples = Some(3);
    scene.method.rtol = Some(1e-12);
    let (s, _) = run(&scene);
    assert!(s.steps > 1024, "{}", s.steps);
    assert!(s.relative_energy_drift() < 1e-8, "{:e}", s.relative_energy_drift());
}

/// A user potential (finite-difference gradient) reproduces the built-in one.
#[test]
fn user_potential_matches_builtin() {
    let mut scene = example("s2-gyroscope-cosine").unwrap();
    scene.time.t_end = 1.0;
    let (_, builtin) = run(&scene);
    let (a, b) = (scene.potential.alpha_hat.unwrap(), scene.potential.beta_hat.unwrap());
    scene.potential = Default::default();
    let f = Arc::new(move |x: &[f64], _e: &[f64]| a * x[2] * x[2] + b * x[2]);
    let mut sim = scene.build_with_user_potential(f).unwrap();
    let mut sink = MemorySink::default();
    sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
    for c in ["x0", "x1", "x2", "spin", "energy"] {
        let (p, q) = (col(&sink, c), col(&builtin, c));
        let err = p.iter().zip(&q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(err < 1e-8, "{c}: {err:e}");
    }
}

/// JSON and TOML describe the same scene.
#[test]
fn json_round_trip() {
    let scene = example("s3-gyroscope").unwrap();
    let json = scene.to_json_string();
    let back = Scene::from_json_str(&json).unwrap();
    let toml_back = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    let (s1, a) = run(&scene);
    let (s2, b) = run(&back);
    let (_, c) = run(&toml_back);
    assert_eq!(a, b);
    assert_eq!(a, c);
    assert_eq!(s1.steps, s2.steps);
}

fn base() -> String {
    EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1.to_string()
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

/// Errors name the field, the value, what is allowed, and the line/column.
#[test]
fn errors_name_field_value_and_location() {
    let text = base();
    // Wrong type.
    let bad = text.replace("mass = 1.0", "mass = \"heavy\"");
    match Scene::from_toml_str(&bad).unwrap_err() {
        SceneError::Parse { path, message, location, .. } => {
            assert_eq!(path, "body.mass");
            assert!(message.contains("heavy") || message.contains("string"), "{message}");
            assert_eq!(location.unwrap().line, line_of(&bad, "heavy"));
        }
        e => panic!("{e}"),
    }
    // Unknown field.
    let bad = text.replace("inertia = 0.2", "inertia = 0.2\nmoment = 3");
    let e = Scene::from_toml_str(&bad).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("moment") && msg.contains("body"), "{msg}");
    assert!(e.location().is_some(), "{msg}");
    // Unknown enum variant lists the allowed ones.
    let bad = text.replace("kind = \"S2\"", "kind = \"S5\"");
    let msg = Scene::from_toml_str(&bad).unwrap_err().to_string();
    assert!(msg.contains("S5") && msg.contains("H2"), "{msg}");
    assert!(msg.contains(&format!("line {}", line_of(&bad, "S5"))), "{msg}");
    // Out of range: located by path.
    let bad = text.replace("mass = 1.0", "mass = -2.0");
    let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
    match &e {
        SceneError::Invalid { path, value, allowed, location } => {
            assert!(path.starts_with("body"), "{path}");
            assert!(value.contains("-2"), "{value}");
            assert!(allowed.contains("> 0"), "{allowed}");
            assert_eq!(location.unwrap().line, line_of(&bad, "mass = -2.0"), "{e}");
        }
        e => panic!("{e}"),
    }
    // Method names.
    let bad = text.replace("name = \"rk4\"", "name = \"rk45\"");
    let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("method.name") && msg.contains("rk45") && msg.contains("dopri5"), "{msg}");
    assert_eq!(e.location().unwrap().line, line_of(&bad, "rk45"));
    // Parameters a potential does not take.
    let bad = text.replace("beta_hat = -0.3", "beta_hat = -0.3\nkappa = 1.0");
    let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
    assert_eq!(e.path(), Some("potential.kappa"));
    assert_eq!(e.location().unwrap().line, line_of(&bad, "kappa = 1.0"));
    // Coordinates of another manifold.
    let bad = text.replace("phi = 0.0\n", "phi = 0.0\ntheta = 1.0\n");
    let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
    assert_eq!(e.path(), Some("initial.theta"), "{e}");
    // A sample time outside the span, in an array.
    let bad = text.replace("every = 4", "times = [0.0, 9.0]");
    let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
    assert_eq!(e.path(), Some("output.times[1]"), "{e}");
    let loc = e.location().unwrap();
    assert_eq!(loc.line, line_of(&bad, "times = [0.0, 9.0]"));
    assert_eq!(loc.column, "times = [0.0, ".len() + 1);
    // JSON parse errors carry line and column too.
    let e = Scene::from_json_str("{\n  \"manifold\": {\"kind\": 3}\n}").unwrap_err();
    assert_eq!(e.location().unwrap().line, 2, "{e}");
    assert_eq!(e.path(), Some("manifold.kind"));
    // Unknown embedded scene lists the available ones.
    let msg = example("nope").unwrap_err().to_string();
    assert!(msg.contains(DEFAULT_SCENE));
}

/// Physically invalid initial states are rejected with the field named.
#[test]
fn invalid_states_are_typed_errors() {
    let text = base();
    let cases = [
        ("r = 0.6\nphi = 0.0\nr_dot = -1.0\nphi_dot = 0.0\n", "position = [0.0, 0.0, 2.0]\n", "initial.position"),
        ("r = 0.6\nphi = 0.0\nr_dot = -1.0\nphi_dot = 0.0\n", "position = [0.0, 0.0, 1.0]\nvelocity = [0.0, 0.0, 1.0]\n", "initial.velocity"),
        ("spin = 0.02", "spin = [0.1, 0.2]", "initial.spin"),
        ("inertia = 0.2", "J = [[1.0, 2.0], [2.0, 1.0]]", "body"),
        ("radius = 1.0", "radius = 0.0", "manifold.radius"),
        ("h = 0.005", "h = -1.0", "method.h"),
        ("t_end = 4.0", "t_end = 0.0", "time.t_end"),
    ];
    for (from, to, path) in cases {
        assert!(text.contains(from), "{from}");
        let bad = text.replace(from, to);
        let e = Scene::from_toml_str(&bad).unwrap().validate().unwrap_err();
        assert!(e.path().unwrap().starts_with(path), "{to}: {e}");
        assert!(e.location().is_some(), "{to}: {e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Mutated scene text never panics: parsing and validation return a
    /// value or a typed error with a message.
    #[test]
    fn mutated_scenes_never_panic(pos in 0usize..2000, len in 0usize..8, junk in "[\\x00-\\x7f\u{e9}\u{3c0}]{0,8}") {
        let text = base();
        let mut start = pos.min(text.len());
        while !text.is_char_boundary(start) { start -= 1; }
        let mut end = (start + len).min(text.len());
        while !text.is_char_boundary(end) { end -= 1; }
        let mutated = format!("{}{}{}", &text[..start], junk, &text[end..]);
        match Scene::from_toml_str(&mutated) {
            Ok(s) => { let _ = s.validate().map_err(|e| assert!(!e.to_string().is_empty())); }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
