//! Tests of `crates/framedyn/src/manifold/geodesic/torus2.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{clairaut_integrals, Family, Shooter, Shot, Target, FINE_TOL};

/// h = 0 (δ = λ₁): the meridian, Δφ = 0 and s = |Δθ|.
#[test]
fn clairaut_meridian_limit() {
    for lm1 in [0.05, 1.0, 9.0] {
        let (dphi, s) = clairaut_integrals(lm1, lm1, -2.0, 5.5).unwrap();
        assert_eq!(dphi, 0.0);
        assert!((s - 7.5).abs() < 1e-14, "{s}");
    }
}

/// The quadratures agree with the shooting integrator on wrapping
/// geodesics, including ones that thread the neck of a thin torus.
#[test]
fn clairaut_agrees_with_shooting() {
    for (lm1, th1, eps, dphi) in [(1.0, 0.3, 0.2, 0.8), (0.05, 2.0, 0.01, 0.3), (9.0, -1.0, 0.5, 0.2), (0.2, -2.8, 0.05, 0.25)] {
        let sh = Shooter { lm1 };
        let tg = Target { th1, dphi, lo: th1 - 20.0, hi: th1 + 20.0 };
        let Shot::Hit { theta, length, .. } = sh.shoot(&tg, Family::Up, eps, FINE_TOL).unwrap() else {
            panic!("shot escaped")
        };
        let h = sh.rho(th1) * eps.sin();
        assert!(h < lm1, "not a wrapping geodesic");
        let (q_dphi, q_len) = clairaut_integrals(lm1, lm1 - h, th1, theta).unwrap();
        assert!((q_dphi - dphi).abs() < 1e-11, "λ₁ = {lm1}: Δφ {q_dphi} vs {dphi}");
        assert!((q_len - length).abs() < 1e-11 * length, "λ₁ = {lm1}: s {q_len} vs {length}");
    }
}

/// Near the separatrix (δ → 0) the φ-advance across the inner equator
/// diverges like ln(1/δ) but stays finite and accurate for any δ > 0.
#[test]
fn clairaut_near_separatrix() {
    let lm1 = 0.5;
    let mut prev = 0.0;
    for e in [2, 10, 50, 150, 300] {
        let delta = 10f64.powi(-e);
        let (dphi, s) = clairaut_integrals(lm1, delta, 2.0, 4.0).unwrap();
        assert!(dphi.is_finite() && s.is_finite() && dphi > prev, "δ = 1e-{e}: {dphi}");
        prev = dphi;
    }
    // Per decade of δ the advance grows by ln(10)/√(2(λ₁+1)·...) ≈ constant.
    let d1 = clairaut_integrals(lm1, 1e-100, 2.0, 4.0).unwrap().0;
    let d2 = clairaut_integrals(lm1, 1e-200, 2.0, 4.0).unwrap().0;
    let d3 = clairaut_integrals(lm1, 1e-300, 2.0, 4.0).unwrap().0;
    assert!(((d3 - d2) - (d2 - d1)).abs() < 1e-10 * (d2 - d1), "{d1} {d2} {d3}");
}
