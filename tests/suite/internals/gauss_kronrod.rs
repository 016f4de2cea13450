//! Tests of `crates/framedyn/src/manifold/geodesic/gauss_kronrod.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{gauss_kronrod, WG, WGK};

/// The Kronrod rule is exact to degree 22, the embedded Gauss rule to 13:
/// checks the tabulated nodes and weights.
#[test]
fn gauss_kronrod_constants_are_exact_on_polynomials() {
    let mut wk = WGK[7];
    let mut wg = WG[3];
    for i in 0..7 {
        wk += 2.0 * WGK[i];
        if i % 2 == 1 {
            wg += 2.0 * WG[i / 2];
        }
    }
    assert!((wk - 2.0).abs() < 1e-15 && (wg - 2.0).abs() < 1e-15, "{wk} {wg}");
    for k in 0..=22i32 {
        let f = |x: f64| [x.powi(k), x.powi(k.min(13))];
        let v = gauss_kronrod(&f, -1.0, 1.5).unwrap();
        let exact = |k: i32| (1.5f64.powi(k + 1) - (-1.0f64).powi(k + 1)) / (k + 1) as f64;
        assert!((v[0] - exact(k)).abs() <= 1e-14 * exact(k).abs().max(1.0), "k = {k}: {} vs {}", v[0], exact(k));
        assert!((v[1] - exact(k.min(13))).abs() <= 1e-14 * exact(k.min(13)).abs().max(1.0));
    }
}
