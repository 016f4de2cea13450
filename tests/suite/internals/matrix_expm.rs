//! Tests of `crates/framedyn/src/lie/matrix/expm.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{PADE13, PADE3, PADE5, PADE7, PADE9};

fn pade_coeff(m: usize, j: usize) -> f64 {
    // b_j normalised so that b_m = 1: b_j ∝ (2m−j)!/(j!(m−j)!).
    let f = |n: usize| (1..=n).map(|k| k as f64).product::<f64>();
    f(2 * m - j) / (f(j) * f(m - j))
}

#[test]
fn pade_coefficients_match_formula() {
    let check = |m: usize, b: &[f64]| {
        let norm = pade_coeff(m, m);
        for (j, &bj) in b.iter().enumerate() {
            let want = pade_coeff(m, j) / norm;
            assert!((bj - want).abs() <= 1e-15 * want, "m={m} j={j}: {bj} vs {want}");
        }
    };
    check(3, &PADE3);
    check(5, &PADE5);
    check(7, &PADE7);
    check(9, &PADE9);
    check(13, &PADE13);
}
