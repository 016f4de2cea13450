//! The method registry (`framedyn::method::registry`) is the one list of
//! methods: every entry builds with the properties it declares, runs through
//! the typed path (`solve`) and through a scene, and the guide's method table
//! is generated from it. No other source file names a method.

use std::sync::atomic::AtomicBool;

use framedyn::method::registry::{lookup, markdown_table, Built, MethodParams};
use framedyn::method::{Family, Method, Needs, METHODS};
use framedyn::scenes::{MemorySink, Scene, SceneError, SceneStop};
use framedyn::solve::{solve, Options, Problem, SolveError};

/// The S² gyroscope of the scene tests, away from the pole of the chart
/// (so that the coordinate methods apply), with a uniform field.
fn scene(method: &str, h: f64) -> Scene {
    Scene::from_toml_str(&format!(
        r#"
        manifold = {{ kind = "S2", radius = 1.0 }}
        body = {{ kind = "gyroscope", inertia = 0.2 }}
        potential = {{ kind = "cosine", beta_hat = -0.3 }}
        initial = {{ r = 1.2, phi = 0.3, r_dot = 0.4, phi_dot = 0.5, spin = 0.05 }}
        method = {{ name = "{method}", h = {h} }}
        time = {{ t_end = 1.0 }}
        output = {{ every = 1000000 }}
        "#
    ))
    .unwrap()
}

fn final_position(scene: &Scene) -> Result<[f64; 3], String> {
    let mut sim = scene.build().map_err(|e| e.to_string())?;
    let mut sink = MemorySink::default();
    sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).map_err(|f| f.to_string())?;
    let last = sink.rows.last().ok_or("no records")?;
    let j = |n: &str| sink.columns.iter().position(|c| c.name == n).unwrap();
    Ok([last[j("x0")], last[j("x1")], last[j("x2")]])
}

/// Every entry builds, and the built method reports the entry's display
/// name, order and embedded order; adaptive exactly when it has an
/// embedded pair; names unique.
#[test]
fn every_entry_builds_with_its_declared_properties() {
    use framedyn::dynamics::PointModel;
    use framedyn::manifold::Sphere2;
    use framedyn::potential::Free;
    type S = PointModel<Sphere2, Free, 2, 3>;
    let mut names: Vec<&str> = METHODS.iter().map(|e| e.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), METHODS.len(), "duplicate names");
    for e in METHODS {
        assert_eq!(lookup(e.name).unwrap().display, e.display);
        assert_eq!(e.adaptive, e.embedded_order.is_some(), "{}", e.name);
        let built = e.build(&MethodParams::default()).unwrap_or_else(|err| panic!("{}: {err}", e.name));
        assert_eq!(built.display(), e.display);
        match (&built, e.family) {
            (Built::Group(m), Family::Rkmk | Family::Splitting | Family::Implicit) => {
                let info = Method::<S>::info(m);
                assert_eq!((info.name, info.order, info.embedded_order), (e.display, e.order, e.embedded_order), "{}", e.name);
                assert_eq!(e.needs == Needs::ExactFreeFlow, e.family == Family::Splitting, "{}", e.name);
            }
            (Built::Chart(_), Family::Coordinate) => assert_eq!(e.needs, Needs::Chart),
            _ => panic!("{}: built kind does not match its family", e.name),
        }
        // Parameters a method does not take are refused, naming them.
        let newton = MethodParams { newton_tol: Some(1e-12), newton_max_iter: None };
        assert_eq!(e.build(&newton).is_ok(), e.params.contains(&"newton_tol"), "{}", e.name);
    }
    assert!(lookup("rk5").unwrap_err().to_string().contains("rk4"));
}

/// Through the typed path: every Lie-group entry integrates the S²
/// gyroscope with `solve` (fixed steps) and lands within `C·h^p` of a
/// reference; every coordinate entry integrates the chart equations of the
/// same gyroscope likewise.
#[test]
fn every_entry_runs_through_the_typed_path() {
    use framedyn::body::Gyroscope;
    use framedyn::coords::{ambient_state, paper_from_state, Gyroscope2, PlaneRotation, SphereChart};
    use framedyn::dynamics::Gyroscope2Model;
    use framedyn::lie::{LieGroup, So2};
    use framedyn::manifold::{Manifold, Sphere2};
    use framedyn::method::baseline::ChartSystem;
    use framedyn::potential::{Centre, CosineFamily};
    use nalgebra::{Vector1, Vector2, Vector3};

    let s2 = Sphere2::new(1.0).unwrap();
    let pot = CosineFamily::new(0.0, -0.3, Centre::sphere2(&s2)).unwrap();
    let body = Gyroscope::<2>::isotropic(1.0, 0.2).unwrap();
    let model = Gyroscope2Model::new(s2.clone(), body.clone(), pot.clone()).unwrap();
    let (x, xd) = (Vector2::new(1.2, 0.3), Vector2::new(0.4, 0.5));
    let v = s2.embed_tangent(&x, &xd);
    let g = framedyn::bundle::FrameBundle::from_chart(&s2, &x, &nalgebra::Matrix2::identity()).unwrap();
    let u = framedyn::dynamics::point::tangent_components(&s2, &g, &v, "v").unwrap();
    let y0 = model.state_from_parts(&g, &So2::exp(&Vector1::new(0.0)), &u, 0.05).unwrap();
    let problem = Problem::new(model.clone(), y0, (0.0, 1.0)).unwrap();
    let reference = {
        let m = lookup("butcher6").unwrap().build(&MethodParams::default()).unwrap();
        let Built::Group(m) = m else { unreachable!() };
        let sol = solve(&problem, &m, &Options::fixed(1e-3)).unwrap();
        model.position(sol.last().1)
    };
    let chart = ChartSystem::new(Gyroscope2::gyroscope(SphereChart::new(1.0).unwrap(), PlaneRotation, &body, pot));
    let paper = paper_from_state(chart.lagrangian(), &model, &y0).unwrap();
    let chart_y0 = ChartSystem::<Gyroscope2<SphereChart, CosineFamily<3>>, 3>::state(&paper.q, &paper.qdot);
    let chart_problem = Problem::new(chart.clone(), chart_y0, (0.0, 1.0)).unwrap();
    let h = 0.01;
    for e in METHODS {
        let built = e.build(&MethodParams::default()).unwrap();
        let end: Vector3<f64> = match built {
            Built::Group(m) => {
                let sol = solve(&problem, &m, &Options::fixed(h)).unwrap_or_else(|f| panic!("{}: {f}", e.name));
                model.position(sol.last().1)
            }
            Built::Chart(m) => {
                let sol = solve(&chart_problem, &m, &Options::fixed(h)).unwrap_or_else(|f| panic!("{}: {f}", e.name));
                let y = sol.last().1;
                ambient_state(chart.lagrangian(), &y.0 .0, &y.1 .0).unwrap().position
            }
        };
        let err = (end - reference).norm();
        let bound = (10.0 * h.powi(e.order as i32)).max(1e-13);
        assert!(err <= bound, "{}: error {err:e} > {bound:e}", e.name);
    }
}

/// Through the scene path: every name is a scene method; on the S²
/// gyroscope each lands within `C·h^p` of the Butcher 6 reference.
#[test]
fn every_entry_runs_through_the_scene_path() {
    let reference = final_position(&scene("butcher6", 1e-3)).unwrap();
    let h = 0.01;
    for e in METHODS {
        let s = scene(e.name, h);
        s.validate().unwrap_or_else(|err| panic!("{}: {err}", e.name));
        assert!(s.allowed_methods().unwrap().contains(&e.name), "{}", e.name);
        let end = final_position(&s).unwrap_or_else(|err| panic!("{}: {err}", e.name));
        let err = (0..3).map(|i| (end[i] - reference[i]).powi(2)).sum::<f64>().sqrt();
        let bound = (10.0 * h.powi(e.order as i32)).max(1e-13);
        assert!(err <= bound, "{}: error {err:e} > {bound:e}", e.name);
        let built = scene(e.name, h).build().unwrap();
        assert_eq!(built.method_name(), e.display);
    }
}

/// The coordinate methods from a scene fail where the chart does, with the
/// typed error and the records up to the last good state: a geodesic of S²
/// passing 1e-6 R from the pole (SPEC §5's baseline case; the group method
/// RKMK4 with the same steps follows the closed form), and a state at the
/// pole itself (no paper coordinates at all). Where the body has no chart
/// equations (a Weyl body) they are refused at validation, naming
/// `method.name`.
#[test]
fn coordinate_methods_from_scenes_fail_at_the_pole_with_a_typed_error() {
    // The unit-speed geodesic from (r, φ) = (1, 0) with angular momentum
    // sin²r·φ̇ = 1e-6: it passes 1e-6 from the pole at t ≈ 1.
    let (r0, lz) = (1.0f64, 1e-6);
    let phi_dot = lz / r0.sin().powi(2);
    let r_dot = -(1.0 - (r0.sin() * phi_dot).powi(2)).sqrt();
    let geodesic = |method: &str| {
        Scene::from_toml_str(&format!(
            r#"
            manifold = {{ kind = "S2", radius = 1.0 }}
            body = {{ kind = "point" }}
            initial = {{ r = {r0}, phi = 0.0, r_dot = {r_dot}, phi_dot = {phi_dot} }}
            method = {{ name = "{method}", h = 0.01 }}
            time = {{ t_end = 2.0 }}
            "#
        ))
        .unwrap()
    };
    let closed_form = |t: f64| {
        // x(t) = cos t·x₀ + sin t·v₀ (great circle, unit speed).
        let (x0, v0) = ([r0.sin(), 0.0, r0.cos()], [r_dot * r0.cos(), phi_dot * r0.sin(), -r_dot * r0.sin()]);
        [0, 1, 2].map(|i| t.cos() * x0[i] + t.sin() * v0[i])
    };
    let group = final_position(&geodesic("rk4")).unwrap();
    let exact = closed_form(2.0);
    assert!((0..3).all(|i| (group[i] - exact[i]).abs() < 1e-8), "rk4 {group:?} vs {exact:?}");
    let mut sim = geodesic("coordinate_rk4").build().unwrap();
    let mut sink = MemorySink::default();
    let failure = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).expect_err("the chart is singular near the pole");
    match &failure.summary.stop {
        SceneStop::Failed(SolveError::OutsideChart { t, .. }) => {
            assert!(*t > 0.9 && *t < 1.1, "fails at the passage, t = {t}");
            let ts = sink.column("t").unwrap();
            let last = *ts.last().unwrap();
            assert!(last <= *t && last > 0.9, "records up to the last good state, last t = {last}");
            let x0 = sink.column("x0").unwrap();
            let j = ts.len() - 1;
            assert!((x0[j] - closed_form(ts[j])[0]).abs() < 1e-6, "the kept records are good");
        }
        other => panic!("expected OutsideChart, got {other:?}"),
    }
    // At the pole there are no paper coordinates to start from.
    let mut at_pole = geodesic("coordinate_dopri5");
    at_pole.initial = framedyn::scenes::InitialSpec { position: Some(vec![0.0, 0.0, 1.0]), velocity: Some(vec![1.0, 0.0, 0.0]), ..Default::default() };
    let failure = at_pole.build().unwrap().run(&mut MemorySink::default(), &AtomicBool::new(false), &mut |_| {}).expect_err("no chart at the pole");
    assert!(matches!(failure.summary.stop, SceneStop::Failed(SolveError::OutsideChart { .. })), "{:?}", failure.summary.stop);
    let mut weyl = framedyn::scenes::example("s2-weyl-separable").unwrap();
    weyl.method.name = "coordinate_dopri5".into();
    match weyl.validate() {
        Err(SceneError::Invalid { path, allowed, .. }) => {
            assert_eq!(path, "method.name");
            assert!(allowed.contains("rk4") && !allowed.contains("coordinate_"), "{allowed}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
}

/// The method table of the guide is `markdown_table()` (write it anew with
/// `FRAMEDYN_BLESS_DOCS=1`).
#[test]
fn the_guide_method_table_is_the_registry() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/guide.md");
    let text = std::fs::read_to_string(path).unwrap();
    let open = "<!-- methods: generated from framedyn::method::registry::markdown_table(); tests/suite/registry.rs checks it -->\n";
    let close = "<!-- /methods -->";
    let a = text.find(open).expect("start marker") + open.len();
    let b = text[a..].find(close).expect("end marker") + a;
    let table = markdown_table();
    if std::env::var_os("FRAMEDYN_BLESS_DOCS").is_some() {
        let new = format!("{}{}{}", &text[..a], table, &text[b..]);
        std::fs::write(path, new).unwrap();
        return;
    }
    assert_eq!(&text[a..b], table, "docs/guide.md's method table differs from the registry; FRAMEDYN_BLESS_DOCS=1 rewrites it");
}

/// No source file of the crates or of the Python package names a method
/// (its scene name or display name as a string literal) except the
/// registry.
#[test]
fn method_names_appear_only_in_the_registry() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut files = Vec::new();
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "rs" || e == "py") {
                out.push(p);
            }
        }
    }
    for d in ["crates/framedyn/src", "crates/framedyn-cli/src", "crates/framedyn-py/src", "python/framedyn"] {
        walk(&std::path::Path::new(root).join(d), &mut files);
    }
    let mut bad = Vec::new();
    for f in &files {
        if f.ends_with("method/registry.rs") {
            continue;
        }
        // Code only: Rust comments and Python docstrings may show names.
        let mut code = String::new();
        let mut in_docstring = false;
        for line in std::fs::read_to_string(f).unwrap().lines() {
            let l = line.trim_start();
            if l.starts_with("//") || l.starts_with('#') {
                continue;
            }
            let quotes = l.matches("\"\"\"").count();
            if in_docstring || quotes > 0 {
                if quotes % 2 == 1 {
                    in_docstring = !in_docstring;
                }
                continue;
            }
            code.push_str(line);
            code.push('\n');
        }
        for e in METHODS {
            for name in [e.name, e.display] {
                for quoted in [format!("\"{name}\""), format!("'{name}'")] {
                    if code.contains(&quoted) {
                        bad.push(format!("{}: {quoted}", f.display()));
                    }
                }
            }
        }
    }
    assert!(bad.is_empty(), "method names outside the registry:\n{}", bad.join("\n"));
}
