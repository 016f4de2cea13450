//! Tests of `crates/framedyn/src/lie/matrix/lu.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::{amax, det, Lu};
use nalgebra::SMatrix;

#[test]
fn lu_solves_and_detects_singularity() {
    let m = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
    let lu = Lu::new(&m).unwrap();
    assert!((lu.det() - m.determinant()).abs() < 1e-14);
    assert!(amax(&(lu.inverse() * m - SMatrix::<f64, 3, 3>::identity())) < 1e-15);
    let s = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 4.0);
    assert!(Lu::new(&s).is_none());
    assert_eq!(det(&s), 0.0);
}
