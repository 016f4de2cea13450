//! Tests of `crates/framedyn/src/lie/matrix/log_pade.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{log1p_pade, GAUSS_LEGENDRE, LOG_THETA};
use nalgebra::SMatrix;

#[test]
fn gauss_legendre_rules_are_exact_for_polynomials() {
    for m in 1..=16 {
        let rule = &GAUSS_LEGENDRE[m - 1][..m];
        for p in 0..2 * m {
            let q: f64 = rule.iter().map(|&(t, w)| w * t.powi(p as i32)).sum();
            let exact = 1.0 / (p + 1) as f64;
            assert!((q - exact).abs() <= 4e-16, "m={m}, p={p}: {q} vs {exact}");
        }
    }
}

/// The θ_m of the log Padé approximants: forward error of r_m(x) for
/// complex x on the circle |x| = θ_m (2×2 real representation) ≤ 2ε.
#[test]
fn log_pade_thresholds() {
    for m in 1..=16 {
        let th = LOG_THETA[m - 1];
        let mut worst: f64 = 0.0;
        for k in 0..64 {
            let ang = std::f64::consts::TAU * k as f64 / 64.0;
            let (re, im) = (th * ang.cos(), th * ang.sin());
            let x = SMatrix::<f64, 2, 2>::new(re, -im, im, re);
            let l = log1p_pade(&x, m).unwrap();
            let want_re = 0.5 * (2.0 * re + re * re + im * im).ln_1p();
            let want_im = im.atan2(1.0 + re);
            let err = ((l[(0, 0)] - want_re).powi(2) + (l[(1, 0)] - want_im).powi(2)).sqrt()
                / (want_re.powi(2) + want_im.powi(2)).sqrt();
            worst = worst.max(err);
        }
        assert!(
            worst <= 2.0 * f64::EPSILON,
            "m={m}: relative error {worst:e} at |x| = θ_m"
        );
    }
}
