//! Tests of `crates/framedyn/src/dynamics/affine/inertia.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{matrix_inverse as inverse, trace_of_product, Mat};
use framedyn::dynamics::affine::Inertia;
use framedyn::Error;

use super::xorshift;

fn check_inverse<const N: usize>(rng: &mut impl FnMut() -> f64) {
    for _ in 0..200 {
        let m = Mat::<N>::identity() + Mat::<N>::from_fn(|_, _| rng()) * (0.6 / N as f64);
        let inv = inverse(&m).expect("invertible");
        let err = (m * inv - Mat::<N>::identity()).amax();
        assert!(err < 1e-14, "N = {N}: |m m⁻¹ − I| = {err:e}");
    }
    let mut singular = Mat::<N>::identity();
    singular[(0, 0)] = 0.0;
    for i in 0..N {
        singular[(0, i)] = 0.0;
    }
    assert!(inverse(&singular).is_none());
    assert!(inverse(&Mat::<N>::from_element(f64::NAN)).is_none());
}

/// The closed-form inverses (n ≤ 3) and the LU fallback (n = 4).
#[test]
fn inverse_closed_forms() {
    let mut rng = xorshift(0x1234_5678_9abc_def1);
    check_inverse::<1>(&mut rng);
    check_inverse::<2>(&mut rng);
    check_inverse::<3>(&mut rng);
    check_inverse::<4>(&mut rng);
}

/// `tr(AB)` and the inverse of the rotational inertia operator
/// `ω ↦ Jω + ωJ` on skew matrices.
#[test]
fn trace_of_product_and_rotational_solve() {
    let mut rng = xorshift(0x0bad_cafe_f00d_1234);
    for _ in 0..100 {
        let a = Mat::<3>::from_fn(|_, _| rng());
        let b = Mat::<3>::from_fn(|_, _| rng());
        assert!((trace_of_product(&a, &b) - (a * b).trace()).abs() < 1e-15);
        let l = Mat::<3>::from_fn(|_, _| rng());
        let inertia = Inertia::new(&(Mat::<3>::identity() * 0.1 + l * l.transpose() * 0.2)).unwrap();
        let c = Mat::<3>::from_fn(|_, _| rng());
        let c = c - c.transpose();
        let w = inertia.solve_rotational(&c);
        let j = inertia.matrix();
        assert!((j * w + w * j - c).amax() < 1e-13, "Jω + ωJ ≠ c");
        assert!((w + w.transpose()).amax() < 1e-14, "ω not skew");
        assert!((inertia.inverse() * j - Mat::<3>::identity()).amax() < 1e-13);
    }
}

/// `Inertia::new` rejects what `check_inertia` rejects, with the field `"J"`.
#[test]
fn inertia_validation() {
    assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, -1.0)), Err(Error::Constraint { field: "J", .. })));
    assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.5, 0.0, 1.0)), Err(Error::Constraint { field: "J", .. })));
    assert!(matches!(Inertia::new(&Mat::<2>::new(1.0, 0.0, 0.0, f64::NAN)), Err(Error::NotFinite { field: "J" })));
}
