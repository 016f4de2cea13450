//! Poincaré sections of scenes (`Scene::section`, issue 21): crossings
//! located on the method's continuous extension against closed forms, the
//! direction filter, a section through the pole of S² (where the paper's
//! chart is singular), and bad sections as typed errors naming the field.

use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

use framedyn::scenes::{example, EventDirection, EventKind, EventSpec, Scene, SceneAnalysisError, SceneError};

fn plane(normal: Vec<f64>, offset: f64, direction: EventDirection) -> EventSpec {
    EventSpec { kind: EventKind::Plane, name: None, normal: Some(normal), offset: Some(offset), point: None, distance: None, column: None, value: None, direction, terminal: false }
}

fn column(name: &str, value: f64, direction: EventDirection) -> EventSpec {
    EventSpec { kind: EventKind::Column, name: Some("r_section".into()), normal: None, offset: None, point: None, distance: None, column: Some(name.into()), value: Some(value), direction, terminal: false }
}

/// A point on the equator of the unit S² moving east at speed 1:
/// `x = (cos t, sin t, 0)`, a great circle.
fn equator() -> Scene {
    Scene::from_toml_str(
        r#"
        manifold = { kind = "S2", radius = 1.0 }
        body = { kind = "point", mass = 1.0 }
        initial = { r = 1.5707963267948966, phi = 0.0, r_dot = 0.0, phi_dot = 1.0 }
        method = { name = "rk4", h = 0.01 }
        time = { t_end = 20.0 }
        "#,
    )
    .unwrap()
}

/// The plane x₀ = 0 is crossed at t = π/2 + kπ, falling at π/2 + 2kπ and
/// rising at 3π/2 + 2kπ, with x₁ = ±1 there; the direction filter keeps
/// the rising ones only.
#[test]
fn plane_crossings_of_a_great_circle_at_their_closed_form_times() {
    let no = AtomicBool::new(false);
    let s = equator().section(&plane(vec![1.0, 0.0, 0.0], 0.0, EventDirection::Either), &no).unwrap();
    let t = s.column("t").unwrap();
    let x1 = s.column("x1").unwrap();
    println!("{} crossings, first times {:?}", s.len(), &t[..3]);
    assert_eq!(s.len(), 6, "t = π/2 + kπ < 20: 6 crossings");
    assert_eq!(s.name, "section");
    assert_eq!(s.columns[0].name, "t");
    for (k, (&tk, &xk)) in t.iter().zip(&x1).enumerate() {
        let exact = PI / 2.0 + k as f64 * PI;
        assert!((tk - exact).abs() < 1e-8, "crossing {k}: t = {tk}, exact {exact}");
        let rising = k % 2 == 1;
        assert_eq!(s.rising[k], rising, "crossing {k}");
        assert!((xk - if rising { -1.0 } else { 1.0 }).abs() < 1e-8, "crossing {k}: x1 = {xk}");
    }
    let up = equator().section(&plane(vec![1.0, 0.0, 0.0], 0.0, EventDirection::Rising), &no).unwrap();
    assert_eq!(up.len(), 3);
    assert!(up.rising.iter().all(|r| *r));
    assert!((up.column("t").unwrap()[0] - 1.5 * PI).abs() < 1e-8);
}

/// A column section of a Bertrand (Kepler) orbit: the chart radius r crosses
/// the middle of its range falling once per radial period, at that value to
/// the locator's accuracy, as often as the records of a plain run change
/// sign there, at equal intervals (the orbit is closed).
#[test]
fn column_section_of_a_kepler_orbit() {
    let mut scene = example("s2-point-kepler").unwrap();
    scene.output.every = Some(1);
    let mut sink = framedyn::scenes::MemorySink::default();
    scene.build().unwrap().run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
    let records = sink.column("r").unwrap();
    let (lo, hi) = records.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let mid = 0.5 * (lo + hi);
    let falling = records.windows(2).filter(|w| w[0] > mid && w[1] <= mid).count();
    let s = scene.section(&column("r", mid, EventDirection::Falling), &AtomicBool::new(false)).unwrap();
    let r = s.column("r").unwrap();
    let t = s.column("t").unwrap();
    println!("Kepler: r in [{lo:.4}, {hi:.4}], crossings of r = {mid:.4} at {t:?}");
    assert!(s.len() >= 2 && s.len() == falling, "{} crossings, {falling} sign changes in the records", s.len());
    assert_eq!(s.name, "r_section");
    assert!(r.iter().all(|x| (x - mid).abs() < 1e-9), "r at the crossings: {r:?}");
    assert!(s.rising.iter().all(|x| !x));
    let periods: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(periods.iter().all(|p| (p - periods[0]).abs() < 1e-6), "radial periods {periods:?}");
}

/// The gyroscope of `s2-gyroscope-pole` crosses the plane x₀ = 0 near the
/// north pole, where the chart coordinates are undefined: the crossing is
/// located all the same, with x₂ ≈ R.
#[test]
fn section_through_the_pole() {
    let scene = example("s2-gyroscope-pole").unwrap();
    let s = scene.section(&plane(vec![1.0, 0.0, 0.0], 0.0, EventDirection::Either), &AtomicBool::new(false)).unwrap();
    assert!(!s.is_empty());
    let x2 = s.column("x2").unwrap();
    println!("pole section: x2 = {x2:?} at t = {:?}", s.column("t").unwrap());
    assert!(x2[0] > 0.9999, "first crossing at the pole: x2 = {}", x2[0]);
}

/// Bad sections name the field under `section`; a section needs no output.
#[test]
fn bad_sections_are_typed_errors() {
    let no = AtomicBool::new(false);
    let invalid = |e: SceneAnalysisError| match e {
        SceneAnalysisError::Scene(SceneError::Invalid { path, allowed, .. }) => (path, allowed),
        other => panic!("not an invalid scene: {other}"),
    };
    let (path, allowed) = invalid(equator().section(&plane(vec![1.0, 0.0], 0.0, EventDirection::Either), &no).unwrap_err());
    assert_eq!(path, "section.normal");
    assert!(allowed.contains("exactly 3"), "{allowed}");
    let (path, _) = invalid(equator().section(&plane(vec![0.0, 0.0, 0.0], 0.0, EventDirection::Either), &no).unwrap_err());
    assert_eq!(path, "section.normal");
    let (path, allowed) = invalid(equator().section(&column("no_such_column", 1.0, EventDirection::Either), &no).unwrap_err());
    assert_eq!(path, "section.column");
    assert!(allowed.contains("phi_dot"), "{allowed}");
    let (path, _) = invalid(equator().section(&column("r", f64::NAN, EventDirection::Either), &no).unwrap_err());
    assert_eq!(path, "section.value");
}
