//! Tests of `crates/framedyn/src/lie/matrix/schur.rs` (through `framedyn::__internals` where it is not public API).
use super::xorshift;
use framedyn::__internals::{amax, real_schur};
use nalgebra::SMatrix;

fn check_schur<const N: usize>(a: &SMatrix<f64, N, N>) -> (f64, f64) {
    let (q, t) = real_schur(a).expect("Schur converges");
    for c in 0..N {
        for r in c + 2..N {
            assert_eq!(t[(r, c)], 0.0);
        }
    }
    for c in 0..N.saturating_sub(2) {
        // no two consecutive nonzero subdiagonals (blocks are at most 2×2)
        assert!(t[(c + 1, c)] == 0.0 || t[(c + 2, c + 1)] == 0.0, "{t}");
    }
    for c in 0..N.saturating_sub(1) {
        if t[(c + 1, c)] != 0.0 {
            // 2×2 blocks only for complex pairs (real ones are split)
            let p = 0.5 * (t[(c, c)] - t[(c + 1, c + 1)]);
            assert!(p * p + t[(c, c + 1)] * t[(c + 1, c)] < 0.0, "{t}");
        }
    }
    let orth = amax(&(q.transpose() * q - SMatrix::<f64, N, N>::identity()));
    let back = amax(&(q * t * q.transpose() - a)) / amax(a).max(f64::MIN_POSITIVE);
    (orth, back)
}

/// Backward error and orthogonality of the real Schur form. Each Francis
/// step adds 2–3ε of orthogonality loss (rounding of the reflectors), so
/// after the 4–15 steps needed here the worst cases measured are
/// orthogonality 15ε (3×3) / 19ε (5×5) and backward error 22ε / 38ε;
/// bounds 32ε and 64ε (nalgebra's Schur: 30ε / 45ε on 3×3).
#[test]
fn real_schur_is_backward_stable() {
    let mut next = xorshift(99);
    let mut w = [(0.0f64, 0.0f64); 3];
    for _ in 0..500 {
        let r = [
            check_schur(&SMatrix::<f64, 2, 2>::from_fn(|_, _| next())),
            check_schur(&SMatrix::<f64, 3, 3>::from_fn(|_, _| next())),
            check_schur(&SMatrix::<f64, 5, 5>::from_fn(|_, _| next() * 10.0)),
        ];
        for (wi, ri) in w.iter_mut().zip(r) {
            *wi = (wi.0.max(ri.0), wi.1.max(ri.1));
        }
    }
    assert!(
        w.iter()
            .all(|&(o, b)| o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON),
        "{w:?}"
    );
    // Structured cases: identity, zero, Jordan block, rotation near π,
    // repeated eigenvalues, companion matrix of (x−1)(x−2)(x−3)(x−4).
    let _ = check_schur(&SMatrix::<f64, 4, 4>::identity());
    let _ = check_schur(&SMatrix::<f64, 4, 4>::zeros());
    let mut j = SMatrix::<f64, 4, 4>::identity() * 2.0;
    for i in 0..3 {
        j[(i, i + 1)] = 1.0;
    }
    let (o, b) = check_schur(&j);
    assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON);
    let th = std::f64::consts::PI - 1e-6;
    let r = SMatrix::<f64, 3, 3>::new(th.cos(), -th.sin(), 0.0, th.sin(), th.cos(), 0.0, 0.0, 0.0, 1.0);
    let p = SMatrix::<f64, 3, 3>::new(0.0, 0.6, 0.8, 1.0, 0.0, 0.0, 0.0, 0.8, -0.6);
    let (o, b) = check_schur(&(p * r * p.transpose()));
    assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON);
    let c = SMatrix::<f64, 4, 4>::new(
        10.0, -35.0, 50.0, -24.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
    );
    let (o, b) = check_schur(&c);
    assert!(o <= 32.0 * f64::EPSILON && b <= 64.0 * f64::EPSILON, "{o:e} {b:e}");
}
