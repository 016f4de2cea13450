//! Tests of `crates/framedyn/src/lie/special.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::lie::special::{cosc, dexpinv, sinc, sinc3, sinc_cosc, SERIES_SMALL, SERIES_WIDE};

#[test]
fn continuous_at_thresholds() {
    for f in [sinc, cosc, sinc3, dexpinv] {
        for t in [SERIES_SMALL, SERIES_WIDE] {
            for sign in [1.0, -1.0] {
                // One ulp either side of the switch: no jump beyond round-off.
                let a = f((sign * t).next_down());
                let b = f((sign * t).next_up());
                assert!((a - b).abs() <= 1e-15 * a.abs(), "jump at {}: {a} vs {b}", sign * t);
            }
        }
    }
}

#[test]
fn sinc_cosc_matches_the_separate_functions() {
    for &s in &[0.0, 5e-7, -5e-7, 2e-6, -2e-6, 1e-3, -1e-3, 0.3, -0.3, 1.0, -1.0, 4.0, -4.0, 9.0, -9.0, 30.0, -30.0, 39.0] {
        let (a, b) = sinc_cosc(s);
        assert!((a - sinc(s)).abs() <= 1e-15 * sinc(s).abs().max(1e-300), "sinc at {s}: {a} vs {}", sinc(s));
        assert!((b - cosc(s)).abs() <= 1e-15 * cosc(s).abs().max(1e-300), "cosc at {s}: {b} vs {}", cosc(s));
    }
}

#[test]
fn values_at_zero() {
    assert_eq!(sinc(0.0), 1.0);
    assert_eq!(cosc(0.0), 0.5);
    assert_eq!(sinc3(0.0), 1.0 / 6.0);
    assert_eq!(dexpinv(0.0), 1.0 / 12.0);
}
