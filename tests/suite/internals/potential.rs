//! Tests of `crates/framedyn/src/potential/mod.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::potential::{green_tensor, Free, Potential, Scalar};
use nalgebra::{SMatrix, SVector};

/// A frame-dependent test potential: V = x·x·e₁·e₂ + sin(e₁₁) with the
/// Green tensor, exercising every derivative path.
#[derive(Debug)]
struct Mixed;
impl Potential<2, 3> for Mixed {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, m: &SMatrix<f64, 3, 3>) -> D {
        let g = green_tensor(e, m);
        (x[0] * x[0] + x[1] * x[1] - x[2] * x[2]) * g[(0, 1)] + e[(0, 0)].sin()
    }
}

#[test]
fn autodiff_matches_central_differences() {
    let m = SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from([1.0, 1.0, -1.0]));
    let x = SVector::from([0.3, -0.7, 1.4]);
    let e = SMatrix::<f64, 3, 2>::from_column_slice(&[0.2, 0.5, -0.1, 0.9, -0.4, 0.3]);
    let grad = Mixed.gradient(&x, &e, &m);
    assert!((grad.value - Mixed.value(&x, &e, &m)).abs() < 1e-15);
    let h = 1e-6;
    for i in 0..3 {
        let mut dx = SVector::zeros();
        dx[i] = h;
        let fd = (Mixed.value(&(x + dx), &e, &m) - Mixed.value(&(x - dx), &e, &m)) / (2.0 * h);
        assert!((fd - grad.dx[i]).abs() < 1e-8, "dx[{i}]: {fd} vs {}", grad.dx[i]);
    }
    for k in 0..6 {
        let mut de = SMatrix::<f64, 3, 2>::zeros();
        de[k] = h;
        let fd = (Mixed.value(&x, &(e + de), &m) - Mixed.value(&x, &(e - de), &m)) / (2.0 * h);
        assert!((fd - grad.de[k]).abs() < 1e-8, "de[{k}]: {fd} vs {}", grad.de[k]);
    }
}

#[test]
fn free_is_zero() {
    let g = Potential::<2, 3>::gradient(&Free, &SVector::from([1.0, 2.0, 3.0]), &SMatrix::zeros(), &SMatrix::identity());
    assert_eq!(g.value, 0.0);
    assert_eq!(g.dx, SVector::<f64, 3>::zeros());
}
