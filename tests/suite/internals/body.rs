//! Tests of `crates/framedyn/src/body/mod.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::body::{Affine, Gyroscope, Incompressible, Point, Weyl};
use framedyn::Error;
use nalgebra::Matrix2;

#[test]
fn rejects_bad_parameters_with_named_fields() {
    for m in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(Point::new(m), Err(Error::InvalidParameter { field: "mass", .. })));
        assert!(matches!(Gyroscope::<2>::isotropic(m, 1.0), Err(Error::InvalidParameter { field: "mass", .. })));
        assert!(matches!(Gyroscope::<2>::isotropic(1.0, m), Err(Error::InvalidParameter { field: "I", .. })));
    }
    let asym = Matrix2::new(1.0, 0.2, 0.0, 1.0);
    assert!(matches!(Affine::new(1.0, asym), Err(Error::Constraint { field: "J", .. })));
    let indefinite = Matrix2::new(1.0, 0.0, 0.0, -0.1);
    assert!(matches!(Weyl::new(1.0, indefinite), Err(Error::Constraint { field: "J", .. })));
    let nan = Matrix2::new(1.0, 0.0, 0.0, f64::NAN);
    assert!(matches!(Incompressible::new(1.0, nan), Err(Error::NotFinite { field: "J" })));
}

#[test]
fn isotropic_conventions() {
    let g = Gyroscope::<2>::isotropic(1.0, 0.3).unwrap();
    assert!((g.trace_inertia() - 0.3).abs() < 1e-16);
    let a = Affine::<2>::isotropic(1.0, 0.3).unwrap();
    assert_eq!(*a.inertia(), Matrix2::identity() * 0.3);
}
