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
    assert_eq!(field(run(MegnoOptions { linearisation: lin, ..MegnoOptions::new(0.01, 1.0) })), ("eps", "finite, > 0 and ≤ 0.1".to_string()));
    assert_eq!(field(megno(&sys, &m, f64::INFINITY, &y0, &MegnoOptions::new(0.01, 1.0), None).unwrap_err()).0, "t0");
    let stop = AtomicBool::new(true);
    assert!(matches!(megno(&sys, &m, 0.0, &y0, &MegnoOptions::new(0.01, 1.0), Some(&stop)), Err(AnalysisError::Cancelled { .. })));
}
