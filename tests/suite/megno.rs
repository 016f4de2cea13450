//! MEGNO (`framedyn::analysis::megno`, issue 21): `⟨Y⟩ → 2` on regular
//! orbits, growth at half the maximal Lyapunov exponent on a chaotic one,
//! typed errors for bad options. Run with `--nocapture` to see the numbers.

use std::sync::atomic::AtomicBool;

use framedyn::analysis::{lyapunov_spectrum, megno, AnalysisError, Linearisation, LyapunovOptions, MegnoOptions};
use framedyn::method::{Rkmk, Splitting};
use framedyn::testing::s2_gyro_with;

use super::lyapunov::tilted;

/// Quasi-periodic orbits: the Kepler orbit of the embedded scene
/// `s2-point-kepler` (Bertrand: integrable and maximally degenerate), by
/// the scene, and the S² gyroscope in the separable `V = 0.5 cos(r/R)`
/// (typed). Tangent vectors grow linearly, `Y(t) = 2 − O(log t/t)`, so
/// `⟨Y⟩` lies within 0.1 of 2 (measured 1.923 and 1.959 at T = 200 and
/// 300) and its slope is below 0.005 (measured 4.7e-4 and 2.0e-4; the
/// chaotic gyroscope below: 0.088).
#[test]
fn megno_tends_to_two_on_regular_orbits() {
    let mut kepler = framedyn::scenes::example("s2-point-kepler").unwrap();
    kepler.time.t_end = 200.0;
    let k = kepler.megno(&kepler.megno_options().unwrap(), &AtomicBool::new(false)).unwrap();
    let gyro = s2_gyro_with(0.5, 1.0, [1.0, 0.3, 0.4], [0.3, 0.6, 1.0], 300.0, "regular").unwrap();
    let g = megno(&gyro.system, &Splitting::blanes_moan_rkn4(), 0.0, &gyro.y0, &MegnoOptions::new(0.02, 300.0), None).unwrap();
    for (name, e) in [("Kepler (scene)", &k), ("separable gyroscope", &g)] {
        println!("{name}: Y = {:.4}, <Y> = {:.4}, slope {:.2e}, finite-time λ {:.4}", e.megno, e.mean, e.slope, e.lyapunov);
        assert!((e.mean - 2.0).abs() < 0.1, "{name}: <Y> = {}", e.mean);
        assert!(e.slope.abs() < 0.005, "{name}: slope of <Y> {}", e.slope);
    }
}

/// A chaotic orbit: the tilted S² gyroscope with a dipole coupling of the
/// frame. `⟨Y⟩ ≈ λ₁t/2` (Cincotta & Simó 2000): twice the slope of `⟨Y⟩`
/// over the second half agrees with Benettin's λ₁ of the same run (same
/// initial tangent vector) within 3 of its batch-means standard errors
/// (measured at T = 400: 0.175 against 0.145 ± 0.013, 2.4 standard errors;
/// the slope weights the run's second half, the Benettin average the whole
/// run). `⟨Y⟩` ends far above 2 (measured 28.6).
#[test]
fn megno_grows_at_half_the_maximal_exponent() {
    let (sys, y0) = tilted(0.8, 0.6, [1.2, 0.3], [0.9, 0.7], 0.4, 0.6);
    let (h, t) = (0.02, 400.0);
    let m = Splitting::blanes_moan_rkn4();
    let e = megno(&sys, &m, 0.0, &y0, &MegnoOptions::new(h, t), None).unwrap();
    let b = lyapunov_spectrum(&sys, &m, 0.0, &y0, &LyapunovOptions::new(h, t), None).unwrap();
    println!("tilted gyroscope: Y = {:.3}, <Y> = {:.3}, 2·slope = {:.4}, finite-time λ {:.4}; Benettin λ₁ = {:.4} ± {:.4}", e.megno, e.mean, 2.0 * e.slope, e.lyapunov, b.exponents[0], b.stderr[0]);
    assert!(e.mean > 10.0, "<Y> = {}: not far above 2", e.mean);
    assert!((2.0 * e.slope - b.exponents[0]).abs() <= 3.0 * b.stderr[0], "2·slope {} vs λ₁ = {} ± {}", 2.0 * e.slope, b.exponents[0], b.stderr[0]);
}

/// Bad options are typed errors naming the option and its allowed range;
/// a set cancel flag stops the run.
#[test]
fn bad_megno_options_are_refused() {
    let (sys, y0) = tilted(0.8, 0.6, [1.2, 0.3], [0.9, 0.7], 0.4, 0.6);
    let m = Rkmk::rk4();
    let run = |o: MegnoOptions| megno(&sys, &m, 0.0, &y0, &o, None).unwrap_err();
    let field = |e: AnalysisError| match e {
        AnalysisError::InvalidParameter { field, allowed, .. } => (field, allowed),
        other => panic!("not an invalid parameter: {other}"),
    };
    assert_eq!(field(run(MegnoOptions::new(f64::NAN, 1.0))), ("h", "finite and > 0".to_string()));
    assert_eq!(field(run(MegnoOptions::new(-0.01, 1.0))).0, "h");
    assert_eq!(field(run(MegnoOptions::new(0.01, 0.0))), ("duration", "finite and > 0".to_string()));
    assert_eq!(field(run(MegnoOptions::new(1e-12, 1.0))).0, "h"); // more than 1e9 steps
    let lin = Linearisation { eps: 0.5, ..Linearisation::default() };
    assert_eq!(field(run(MegnoOptions { linearisation: lin, ..MegnoOptions::new(0.01, 1.0) })), ("eps", "finite, ≥ 1e-12 and ≤ 0.1".to_string()));
    // A subnormal ε would perturb nothing (0/0 in the difference quotient).
    let tiny = Linearisation { eps: 1e-320, ..Linearisation::default() };
    assert_eq!(field(run(MegnoOptions { linearisation: tiny, ..MegnoOptions::new(0.01, 1.0) })).0, "eps");
    assert_eq!(field(megno(&sys, &m, f64::INFINITY, &y0, &MegnoOptions::new(0.01, 1.0), None).unwrap_err()).0, "t0");
    let stop = AtomicBool::new(true);
    assert!(matches!(megno(&sys, &m, 0.0, &y0, &MegnoOptions::new(0.01, 1.0), Some(&stop)), Err(AnalysisError::Cancelled { .. })));
}

/// The Kepler scene with a table of five members: two regular orbits, an
/// invalid member (negative step) in the middle, a radial fall into the
/// centre of the potential, and a member at another step.
fn kepler_table() -> (framedyn::scenes::Scene, framedyn::scenes::Table) {
    let mut base = framedyn::scenes::example("s2-point-kepler").unwrap();
    base.time.t_end = 5.0;
    let table = framedyn::scenes::Table::new([
        ("initial.r", vec![0.8, 0.6, 0.7, 0.3, 0.9]),
        ("initial.phi_dot", vec![1.3, 1.5, 1.3, 0.0, 1.2]),
        ("method.h", vec![0.005, 0.005, -0.01, 0.005, 0.01]),
    ])
    .unwrap();
    (base, table)
}

/// `chaos_map` gives every member exactly (bit for bit) the SALI, MEGNO and
/// GALI₃ values of `Scene::sali`, `Scene::megno` and `Scene::gali` on that
/// member's scene alone,
/// with the same threshold, seed and linearisation, serially and on two
/// threads; a member whose scene is invalid (negative `method.h`) or whose
/// run fails gets its status, its message and NaN in the failed
/// indicator's columns, and the members after it are computed as if it
/// were not there.
#[test]
fn chaos_map_equals_single_calls_member_for_member() {
    use framedyn::analysis::{chaos_map, ChaosMapOptions};
    use framedyn::scenes::MemberStatus;
    let (base, table) = kepler_table();
    let no = AtomicBool::new(false);
    let opts = ChaosMapOptions { threshold: 1e-3, seed: 7, gali: Some(3), gali_threshold: 1e-6, threads: Some(2), ..ChaosMapOptions::default() };
    let map = chaos_map(&base, &table, &opts, &no).unwrap();
    let serial = chaos_map(&base, &table, &ChaosMapOptions { threads: Some(1), ..opts }, &no).unwrap();
    assert_eq!(format!("{map:?}"), format!("{serial:?}"), "two threads and one differ");
    assert_eq!(map.len(), 5);
    let bits = |v: f64| v.to_bits();
    for i in 0..map.len() {
        let scene = table.member(&base, i).unwrap();
        println!("member {i}: {:?} sali {:e} min {:e} <Y> {:.4} λ {:.4} {:?}", map.status[i], map.sali[i], map.sali_min[i], map.megno_mean[i], map.lyapunov[i], map.errors[i]);
        let s = scene.sali_options().map_err(framedyn::scenes::SceneAnalysisError::from).and_then(|mut o| {
            o.threshold = 1e-3;
            o.seed = 7;
            scene.sali(&o, &no)
        });
        let m = scene.megno_options().map_err(framedyn::scenes::SceneAnalysisError::from).and_then(|mut o| {
            o.seed = 7;
            scene.megno(&o, &no)
        });
        let g = scene.gali_options(3).map_err(framedyn::scenes::SceneAnalysisError::from).and_then(|mut o| {
            o.seed = 7;
            o.threshold = 1e-6;
            scene.gali(&o, &no)
        });
        // Each indicator as alone: its values bit for bit, or NaN and the
        // message of the single call's error (the first failure's).
        match &s {
            Ok(s) => {
                assert_eq!(
                    [map.sali[i], map.sali_min[i], map.chaotic_at[i]].map(bits),
                    [s.sali, s.min, s.chaotic_at.unwrap_or(f64::NAN)].map(bits),
                    "member {i}: SALI"
                );
                assert_eq!(map.sali_steps[i], s.steps as u64);
            }
            Err(_) => assert!(map.sali[i].is_nan() && map.sali_min[i].is_nan() && map.chaotic_at[i].is_nan() && map.sali_steps[i] == 0, "member {i}"),
        }
        match &m {
            Ok(m) => {
                assert_eq!([map.megno[i], map.megno_mean[i], map.megno_slope[i], map.lyapunov[i]].map(bits), [m.megno, m.mean, m.slope, m.lyapunov].map(bits), "member {i}: MEGNO");
                assert_eq!(map.megno_steps[i], m.steps as u64);
            }
            Err(_) => assert!(map.megno[i].is_nan() && map.megno_mean[i].is_nan() && map.lyapunov[i].is_nan() && map.megno_steps[i] == 0, "member {i}"),
        }
        // GALI is computed unless the scene is invalid (then SALI's error ends the member).
        match (&g, map.status[i]) {
            (Ok(g), _) => {
                assert_eq!([map.gali_log10[i], map.gali_below_at[i]].map(bits), [g.log10, g.below_at.unwrap_or(f64::NAN)].map(bits), "member {i}: GALI");
                assert_eq!(map.gali_steps[i], g.steps as u64);
            }
            (Err(_), _) => assert!(map.gali_log10[i].is_nan() && map.gali_below_at[i].is_nan() && map.gali_steps[i] == 0, "member {i}"),
        }
        let first = [("sali", s.as_ref().err()), ("megno", m.as_ref().err()), ("gali", g.as_ref().err())].into_iter().find_map(|(what, e)| e.map(|e| (what, e)));
        match first {
            None => assert_eq!((map.status[i], &map.errors[i]), (MemberStatus::Finished, &None), "member {i}"),
            Some((what, e)) => {
                assert_eq!(map.errors[i].as_deref(), Some(format!("member {i}: {what}: {e}").as_str()));
                assert_ne!(map.status[i], MemberStatus::Finished, "member {i}");
            }
        }
    }
    assert_eq!(map.status[2], MemberStatus::Invalid);
    assert!(map.errors[2].as_deref().unwrap().contains("method.h"), "{:?}", map.errors[2]);
    // The radial fall: SALI falls below the threshold before the fall
    // breaks the step; MEGNO runs on and fails there.
    assert_eq!(map.status[3], MemberStatus::Failed);
    assert!(map.chaotic_at[3].is_finite() && map.megno_mean[3].is_nan());
    assert_eq!([map.status[0], map.status[1], map.status[4]], [MemberStatus::Finished; 3]);
}

/// Bad map options are typed errors naming the option; a set cancel flag
/// leaves every member cancelled, with NaN.
#[test]
fn chaos_map_refuses_bad_options_and_honours_cancel() {
    use framedyn::analysis::{chaos_map, ChaosMapOptions};
    use framedyn::scenes::MemberStatus;
    let (base, table) = kepler_table();
    let no = AtomicBool::new(false);
    let field = |o: ChaosMapOptions| match chaos_map(&base, &table, &o, &no).unwrap_err() {
        AnalysisError::InvalidParameter { field, allowed, .. } => (field, allowed),
        other => panic!("not an invalid parameter: {other}"),
    };
    let d = ChaosMapOptions::default();
    assert_eq!(field(ChaosMapOptions { sali: false, megno: false, ..d }), ("indicators", "at least one of sali, megno and gali".to_string()));
    assert_eq!(field(ChaosMapOptions { gali: Some(1), ..d }).0, "k");
    assert_eq!(field(ChaosMapOptions { gali: Some(2), gali_threshold: 0.0, ..d }).0, "gali_threshold");
    assert!(chaos_map(&base, &table, &ChaosMapOptions { sali: false, megno: false, gali: Some(2), ..d }, &no).is_ok());
    assert_eq!(field(ChaosMapOptions { threshold: 1.0, ..d }), ("threshold", "between 0 and 1 (exclusive)".to_string()));
    assert_eq!(field(ChaosMapOptions { threads: Some(0), ..d }), ("threads", "between 1 and 1024".to_string()));
    assert_eq!(field(ChaosMapOptions { linearisation: Linearisation { eps: 0.5, ..Linearisation::default() }, ..d }).0, "eps");
    let map = chaos_map(&base, &table, &d, &AtomicBool::new(true)).unwrap();
    assert!(map.status.iter().all(|s| *s == MemberStatus::Cancelled), "{:?}", map.status);
    assert!(map.sali.iter().chain(&map.megno_mean).all(|v| v.is_nan()));
}
