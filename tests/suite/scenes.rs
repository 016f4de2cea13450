//! Scenes: every embedded example parses, validates and runs; errors name the
//! field, the value, what is allowed and the line/column; sampling, stepping,
//! cancellation, adaptive runs and user potentials agree with the direct
//! library calls.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use framedyn::scenes::{example, MemorySink, RunSummary, Scene, SceneError, SceneStop, UserFunctions, UserGradientFn, UserPotentialFn, DEFAULT_SCENE, EXAMPLES};
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
    for b in [BodyKind::Point, BodyKind::Gyroscope, BodyKind::Affine] {
        assert!(scenes.iter().any(|s| s.manifold.kind == ManifoldKind::Spheroid && s.body.kind == b), "spheroid x {b:?}");
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
    // The potential is axially symmetric about the pole: p_φ is conserved.
    let p_phi = col(&sink, "p_phi");
    assert!(p_phi[0].abs() > 1e-3);
    assert!(s.momentum_map_drift < 1e-10 * p_phi[0].abs().max(1.0), "{:e}", s.momentum_map_drift);
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

/// `every = k` records the initial state, every k-th step and the final
/// state; `times` are sampled from the method's continuous extension (a
/// sub-step from the last grid point, for fixed steps) without changing the
/// grid.
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
    // The grid does not depend on what is sampled.
    assert_eq!(s2.steps, 100);
    // The sample at 0.123 is the method's step of 0.003 from the grid point
    // 0.12 (reached here by the stepping API, whose grid rounds differently
    // in the last bits).
    let mut sim = scene.build().unwrap();
    sim.advance(0.01, 12).unwrap();
    sim.step(0.003).unwrap();
    let stepped = sim.row();
    let sampled = &sink2.rows[1];
    let worst = stepped.iter().zip(sampled).skip(1).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-13, "sample off the grid differs from the sub-step by {worst:e}");
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

/// A user potential reproduces the built-in one: to the differences'
/// accuracy with the finite-difference gradient, to round-off with the
/// exact gradient supplied (and a wrong supplied gradient is not).
#[test]
fn user_potential_matches_builtin() {
    let mut scene = example("s2-gyroscope-cosine").unwrap();
    scene.time.t_end = 1.0;
    let (_, builtin) = run(&scene);
    let (a, b) = (scene.potential.alpha_hat.unwrap(), scene.potential.beta_hat.unwrap());
    scene.potential = Default::default();
    let f: UserPotentialFn = Arc::new(move |x: &[f64], _e: &[f64]| a * x[2] * x[2] + b * x[2]);
    let grad = |scale: f64| -> UserGradientFn {
        Arc::new(move |x: &[f64], _e: &[f64], dx: &mut [f64], de: &mut [f64]| {
            dx.copy_from_slice(&[0.0, 0.0, scale * (2.0 * a * x[2] + b)]);
            de.fill(0.0);
        })
    };
    let max_err = |sink: &MemorySink, c: &str| {
        let (p, q) = (col(sink, c), col(&builtin, c));
        p.iter().zip(&q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    };
    let run_user = |sim: &mut framedyn::scenes::Simulation| {
        let mut sink = MemorySink::default();
        sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
        sink
    };
    let differenced = run_user(&mut scene.build_with_user_potential(f.clone()).unwrap());
    let supplied = run_user(&mut scene.build_with_user(UserFunctions { value: f.clone(), gradient: Some(grad(1.0)) }).unwrap());
    let wrong = run_user(&mut scene.build_with_user(UserFunctions { value: f, gradient: Some(grad(1.01)) }).unwrap());
    for c in ["x0", "x1", "x2", "spin", "energy"] {
        let err = max_err(&differenced, c);
        assert!(err < 1e-8, "differenced {c}: {err:e}");
        let err = max_err(&supplied, c);
        assert!(err < 1e-13, "supplied {c}: {err:e}");
    }
    let err = max_err(&wrong, "x2");
    assert!(err > 1e-5, "a 1% wrong gradient changed x2 by only {err:e}");
}

/// The flat sink (the Python module's) holds exactly the records and events
/// of the memory sink.
#[test]
fn flat_sink_holds_what_the_memory_sink_holds() {
    let scene = example("s2-gyroscope-pole").unwrap();
    let (_, memory) = run(&scene);
    let mut flat = framedyn::scenes::FlatSink::default();
    scene.build().unwrap().run(&mut flat, &AtomicBool::new(false), &mut |_| {}).unwrap();
    assert_eq!(flat.columns, memory.columns);
    assert_eq!(flat.rows, memory.rows.len());
    assert_eq!(flat.events, memory.events);
    for (i, r) in memory.rows.iter().enumerate() {
        assert_eq!(flat.row(i), r.as_slice());
    }
    assert_eq!(flat.column("x2"), memory.column("x2"));
    assert_eq!(flat.column("nope"), None);
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

/// Scenes carry a format version: absent or current reads as before, a
/// future version is refused naming the field, the value and the version
/// this build reads, also when the rest of the scene would not parse.
#[test]
fn scene_format_version_is_checked() {
    let text = base();
    let current = format!("format = {}\n{text}", Scene::FORMAT);
    let scene = Scene::from_toml_str(&current).unwrap();
    assert_eq!(scene.format, Some(Scene::FORMAT));
    assert_eq!(run(&scene).1, run(&Scene::from_toml_str(&text).unwrap()).1);
    assert_eq!(Scene::from_toml_str(&text).unwrap().format, None);
    let future = format!("# a comment\nformat = 2\n{text}");
    for (e, line) in [
        (Scene::from_toml_str(&future).unwrap_err(), Some(2)),
        // A field this version does not know: still the format error.
        (Scene::from_toml_str(&format!("{future}\n[wormhole]\nthroat = 1.0\n")).unwrap_err(), Some(2)),
        (Scene::from_json_str("{\"format\": 2, \"manifold\": {\"kind\": \"S2\"}}").unwrap_err(), Some(1)),
        (Scene::from_json_str("{\"format\": 7, \"future\": true}").unwrap_err(), Some(1)),
    ] {
        match &e {
            SceneError::Invalid { path, value, allowed, location } => {
                assert_eq!(path, "format", "{e}");
                assert!(value == "2" || value == "7", "{e}");
                assert!(allowed.contains(&format!("reads scene format {}", Scene::FORMAT)), "{e}");
                assert_eq!(location.map(|l| l.line), line, "{e}");
            }
            e => panic!("not a format error: {e}"),
        }
    }
    // Built in code: checked when built.
    let mut scene = Scene::from_toml_str(&text).unwrap();
    scene.format = Some(0);
    assert_eq!(scene.validate().unwrap_err().path(), Some("format"));
    // Not an integer: a parse error at the field.
    assert_eq!(Scene::from_toml_str(&format!("format = \"1\"\n{text}")).unwrap_err().path(), Some("format"));
    // Written back only when given.
    assert!(!Scene::from_toml_str(&text).unwrap().to_toml_string().contains("format ="));
    assert!(scene.to_toml_string().starts_with("format = 0"));
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

/// Every method name is either available for a manifold × body (it builds
/// and steps) or refused at validation with a typed error naming
/// `method.name`, the value and the methods allowed there; the splittings
/// are allowed exactly for points and gyroscopes on S², H², S³.
#[test]
fn method_availability_is_checked_at_validation() {
    use framedyn::method::{Needs, METHODS};
    use framedyn::scenes::{BodyKind, ManifoldKind};
    for (name, _) in EXAMPLES {
        let base = example(name).unwrap();
        let split_ok = matches!(base.manifold.kind, ManifoldKind::S2 | ManifoldKind::H2 | ManifoldKind::S3)
            && matches!(base.body.kind, BodyKind::Point | BodyKind::Gyroscope);
        let allowed = base.allowed_methods().unwrap();
        for entry in METHODS.iter().filter(|e| e.needs != Needs::Chart) {
            let m = &entry.name;
            let mut scene = base.clone();
            scene.method.name = m.to_string();
            scene.method.h = Some(1e-3);
            scene.method.rtol = None;
            scene.method.atol = None;
            let ok = split_ok || entry.needs == Needs::Nothing;
            assert_eq!(allowed.contains(m), ok, "{name} {m}");
            match scene.validate() {
                Ok(()) => {
                    assert!(ok, "{name}: {m} accepted");
                    let mut sim = scene.build().unwrap();
                    let e0 = sim.energy();
                    sim.advance(1e-3, 3).unwrap_or_else(|e| panic!("{name} {m}: {e}"));
                    // Three steps of 1e-3: even Lie–Euler changes E by O(h²) per step.
                    assert!((sim.energy() - e0).abs() < 1e-4 * e0.abs().max(1.0), "{name} {m}: {} -> {}", e0, sim.energy());
                    assert!(sim.defect() < 1e-12, "{name} {m}");
                }
                Err(e) => {
                    assert!(!ok, "{name}: {m} refused: {e}");
                    match &e {
                        SceneError::Invalid { path, value, allowed, location: Some(_) } => {
                            assert_eq!(path, "method.name");
                            assert!(value.contains(m), "{e}");
                            assert!(allowed.contains("implicit_midpoint") && allowed.contains("rk4") && !allowed.contains("strang"), "{e}");
                        }
                        _ => panic!("{name} {m}: {e:?}"),
                    }
                }
            }
        }
    }
    // Newton options only with the implicit rule, and in range.
    let mut scene = example("t2-gyroscope-separable").unwrap();
    scene.method.newton_tol = Some(1e-10);
    let e = scene.validate().unwrap_err().to_string();
    assert!(e.contains("method.newton_tol") && e.contains("implicit_midpoint"), "{e}");
    scene.method.name = "implicit_midpoint".into();
    scene.validate().unwrap();
    scene.method.newton_tol = Some(1.0);
    let e = scene.validate().unwrap_err().to_string();
    assert!(e.contains("method.newton_tol") && e.contains("1e-2"), "{e}");
    scene.method.newton_tol = None;
    scene.method.newton_max_iter = Some(0);
    assert!(scene.validate().unwrap_err().to_string().contains("method.newton_max_iter"));
    // Adaptive stepping stays a dopri5 option.
    let mut scene = example("s2-point-kepler").unwrap();
    scene.method.name = "strang".into();
    scene.method.h = None;
    scene.method.rtol = Some(1e-8);
    assert!(scene.validate().unwrap_err().to_string().contains("dopri5"));
}

/// The scene names select the right integrators: measured orders (least
/// squares over 4 step sizes against a Butcher-6 reference) of the
/// splittings and the implicit midpoint rule on the symmetric top (S²) and
/// the Kepler point (S³); the embedded Blanes–Moan run (10⁴ steps) keeps
/// the energy error and the momentum map at round-off.
#[test]
fn scene_methods_have_their_orders() {
    fn end_state(scene: &Scene, name: &str, h: f64) -> Vec<f64> {
        let mut s = scene.clone();
        s.method.name = name.into();
        s.method.h = Some(h);
        let (_, sink) = run(&s);
        let last = sink.rows.last().unwrap();
        ["x0", "x1", "x2", "x3"].iter().filter_map(|c| sink.columns.iter().position(|k| k.name == *c)).map(|j| last[j]).collect()
    }
    for (example_name, t_end) in [("s2-gyroscope-cosine", 1.6), ("s3-point-kepler", 1.6)] {
        let mut scene = example(example_name).unwrap();
        scene.time.t_end = t_end;
        scene.output.every = None;
        scene.output.samples = Some(2);
        let reference = end_state(&scene, "butcher6", 1e-3);
        for (name, order, h0) in [("strang", 2.0, 0.1), ("implicit_midpoint", 2.0, 0.1), ("suzuki4", 4.0, 0.2), ("blanes_moan4", 4.0, 0.2), ("blanes_moan6", 6.0, 0.8)] {
            // Kepler on S³ at h = 0.8 is pre-asymptotic for the sixth-order method.
            let h0 = if example_name == "s3-point-kepler" && name == "blanes_moan6" { 0.2 } else { h0 };
            let hs: Vec<f64> = (0..4).map(|k| h0 / 2f64.powi(k)).collect();
            let errs: Vec<f64> = hs
                .iter()
                .map(|&h| end_state(&scene, name, h).iter().zip(&reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max))
                .collect();
            let (xs, ys): (Vec<f64>, Vec<f64>) = hs.iter().zip(&errs).map(|(h, e)| (h.ln(), e.ln())).unzip();
            let (mx, my) = (xs.iter().sum::<f64>() / 4.0, ys.iter().sum::<f64>() / 4.0);
            let slope = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum::<f64>() / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
            eprintln!("{example_name} {name}: errors {errs:?}, slope {slope:.3}");
            assert!(errs[3] > 1e-13, "{example_name} {name}: round-off floor reached ({errs:?})");
            assert!((slope - order).abs() < 0.2, "{example_name} {name}: slope {slope} (nominal {order}), errors {errs:?}");
        }
    }
    // The long embedded run: bounded energy error, p_phi to round-off.
    let scene = example("s2-gyroscope-splitting").unwrap();
    let (s, sink) = run(&scene);
    assert_eq!(s.method, "Blanes-Moan 4 splitting");
    let e = col(&sink, "energy");
    let half = e.len() / 2;
    let drift = |r: &[f64]| r.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    let (first, second) = (drift(&e[..half]), drift(&e[half..]));
    eprintln!("splitting energy error: first half {first:e}, second half {second:e}; p_phi drift {:e}", s.momentum_map_drift);
    // Measured 3e-14 / 1.8e-13: at h = 0.02 the Blanes–Moan error is below
    // round-off, so the energy error is the round-off random walk of 10⁴
    // steps (an O(h) drift or a wrong kick would be ≥ 1e-8).
    assert!(first.max(second) < 1e-11, "energy error: {first:e}, {second:e}");
    assert!(s.momentum_map_drift < 1e-12, "{:e}", s.momentum_map_drift);
}

const GEODESIC: &str = r#"
[manifold]
kind = "S2"
radius = 2.0
[body]
kind = "point"
[initial]
r = 0.3
phi = 0.5
r_dot = 0.7
[method]
name = "rk4"
h = 0.1
[time]
t_end = 6.0
[output]
every = 5
[[events]]
kind = "plane"
name = "equator"
normal = [0.0, 0.0, 1.0]
[[events]]
kind = "column"
name = "r_two"
column = "r"
value = 2.0
direction = "rising"
[[events]]
kind = "column"
column = "r"
value = 2.5
direction = "falling"
[[events]]
kind = "distance"
name = "far"
point = [0.0, 0.0, 2.0]
distance = 3.0
terminal = true
"#;

/// Events on a meridian geodesic of S²(R = 2), r(t) = r₀ + ṙt: the equator
/// plane x2 = 0 at t = (πR/2 − r₀)/ṙ, the coordinate r = 2 at (2 − r₀)/ṙ
/// (rising only; the falling r = 2.5 event never fires), and the terminal
/// chordal distance 3 from the pole at r = 2R·asin(3/(2R)) — located to
/// 1e-10 in time by every kind of method (fixed RKMK, splitting, adaptive
/// DOPRI5 with its dense output).
#[test]
fn events_are_located_at_closed_form_times() {
    let (r0, v, big_r) = (0.3f64, 0.7f64, 2.0f64);
    let t_eq = (std::f64::consts::FRAC_PI_2 * big_r - r0) / v;
    let t_r2 = (2.0 - r0) / v;
    let t_far = (2.0 * big_r * (3.0 / (2.0 * big_r)).asin() - r0) / v;
    assert!(t_r2 < t_eq && t_eq < t_far && t_far < 6.0);
    for (name, h, adaptive) in [("rk4", 0.1, false), ("strang", 0.1, false), ("implicit_midpoint", 0.1, false), ("dopri5", 0.0, true), ("dop853", 0.0, true)] {
        let mut scene = Scene::from_toml_str(GEODESIC).unwrap();
        scene.method.name = name.into();
        if adaptive {
            scene.method.h = None;
            scene.method.rtol = Some(1e-10);
        } else {
            scene.method.h = Some(h);
        }
        let (s, sink) = run(&scene);
        assert_eq!(s.stop, SceneStop::Event("far".into()), "{name}");
        let names: Vec<&str> = sink.events.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["r_two", "equator", "far"], "{name}");
        for (e, t_exact) in sink.events.iter().zip([t_r2, t_eq, t_far]) {
            eprintln!("{name}: {} at {} (error {:e})", e.name, e.t, e.t - t_exact);
            assert!((e.t - t_exact).abs() < 1e-10, "{name} {}: {} vs {t_exact}", e.name, e.t);
            assert_eq!(e.row.len(), sink.columns.len());
            assert_eq!(e.row[0], e.t);
        }
        assert!(sink.events[0].rising && !sink.events[1].rising && sink.events[2].terminal);
        // The equator row: x2 = 0 to round-off.
        let j = sink.columns.iter().position(|c| c.name == "x2").unwrap();
        assert!(sink.events[1].row[j].abs() < 1e-12, "{name}");
        // The run ends at the terminal event, recorded.
        assert!((s.t_reached - t_far).abs() < 1e-10 && *col(&sink, "t").last().unwrap() == s.t_reached, "{name}");
        assert_eq!(s.events, 3);
    }
}

/// Bad `[[events]]` entries are typed errors naming the field.
#[test]
fn bad_events_are_typed_errors() {
    let cases = [
        ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 1.0]", "events[0].normal", "exactly 3"),
        ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 0.0]", "events[0].normal", "non-zero"),
        ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, nan]", "events[0].normal[2]", "finite"),
        ("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 1.0]\nvalue = 1.0", "events[0].value", "takes only"),
        ("column = \"r\"\nvalue = 2.0", "column = \"rr\"\nvalue = 2.0", "events[1].column", "phi"),
        ("column = \"r\"\nvalue = 2.0", "column = \"r\"", "events[1].value", "missing"),
        ("distance = 3.0", "distance = -3.0", "events[3].distance", "≥ 0"),
    ];
    for (from, to, path, needle) in cases {
        let text = GEODESIC.replacen(from, to, 1);
        let e = Scene::from_toml_str(&text).unwrap().validate().unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(&format!("`{path}`")) && msg.contains(needle), "{to}: {msg}");
        assert!(e.location().is_some(), "{msg}");
    }
    let bad = GEODESIC.replace("kind = \"plane\"", "kind = \"sphere\"");
    let msg = Scene::from_toml_str(&bad).unwrap_err().to_string();
    assert!(msg.contains("events") && msg.contains("plane"), "{msg}");
    let bad = GEODESIC.replace("direction = \"rising\"", "direction = \"up\"");
    assert!(Scene::from_toml_str(&bad).unwrap_err().to_string().contains("rising"));
}

/// `name = "dop853"` in a scene is the adaptive DOP853 pair: on the default
/// scene (a gyroscope through the S² pole, T = 4) the final state at
/// rtol = atol = tol lies within 10·tol of a Butcher-6 run with h = 1e-3
/// (whose own error is ~1e-14), for tol = 1e-6 and 1e-9, with fewer steps
/// than fixed RK4 at h = 0.005 (measured: 2.9e-9 in 6 steps, 2.1e-11 in 11).
#[test]
fn dop853_scene_meets_its_tolerance() {
    let mut reference = example(DEFAULT_SCENE).unwrap();
    reference.method.name = "butcher6".into();
    reference.method.h = Some(1e-3);
    reference.output.every = None;
    reference.output.samples = Some(2);
    let (_, r) = run(&reference);
    for tol in [1e-6, 1e-9] {
        let mut scene = example(DEFAULT_SCENE).unwrap();
        scene.method.name = "dop853".into();
        scene.method.h = None;
        scene.method.rtol = Some(tol);
        scene.method.atol = Some(tol);
        scene.output.every = None;
        scene.output.samples = Some(2);
        let (s, sink) = run(&scene);
        assert_eq!(s.stop, SceneStop::Finished, "{tol}");
        let mut err = 0.0f64;
        for c in ["x0", "x1", "x2", "v0", "v1", "v2"] {
            err = err.max((col(&sink, c).last().unwrap() - col(&r, c).last().unwrap()).abs());
        }
        eprintln!("dop853 tol {tol:e}: final error {err:e} ({:.2} × tol), {} steps", err / tol, s.steps);
        assert!(err <= 10.0 * tol, "tol {tol:e}: error {err:e}");
        assert!(s.steps < 800, "{} steps", s.steps);
    }
}

/// Numbers in JSON scenes parse to the nearest f64 (serde_json's default
/// fast parser can be one ulp off: `0.9186334105401731` became
/// `0.9186334105401732`), as TOML does.
#[test]
fn json_numbers_parse_exactly() {
    let text = example(DEFAULT_SCENE).unwrap().to_json_string();
    for v in [0.9186334105401731, 0.1 + 0.2, 5e-324 * 3.0, f64::MAX / 3.0] {
        let mut scene = Scene::from_json_str(&text).unwrap();
        scene.set("initial.r", v).unwrap();
        let back = Scene::from_json_str(&scene.to_json_string()).unwrap();
        assert_eq!(back.initial.coordinate("r").map(f64::to_bits), Some(v.to_bits()), "{v:e}");
    }
}
