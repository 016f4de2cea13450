//! The exact derivatives of the vector fields (`System::tangent_field`,
//! issue 21): `Df(y)[ξ] = d/ds f(y·exp(sξ))` of every model that has one —
//! the point on all five manifolds, the n = 2 gyroscope on the four
//! surfaces (Riemannian and Lorentz-type energy), the S³ gyroscope with an
//! anisotropic body — against central differences of the vector field, with
//! a potential whose second derivatives in `x` and `e` are all non-zero.
//! (The affine bodies are checked in `dynamics_affine.rs`, with this
//! module's [`check`].) The differences converge to it at second order (the error falls by 4
//! when the step halves), so a wrong term cannot hide in the tolerance.

use framedyn::body::{Gyroscope, Point, Signature};
use framedyn::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use framedyn::lie::{AlgebraVector, LieGroup, So3};
#[allow(unused_imports)]
use framedyn::lie::ProductAlgebra;
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2, Sphere3, Spheroid, Torus2};
use framedyn::potential::{FnPotential, Potential, Scalar};
use nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};

/// `V = ½a z² + 0.3 x₀x₁ + 0.1 sin z + b (e₁ᶻ z + 0.2 (e_{N}⁰)³)`, `z = x[axis]/R`:
/// non-zero second derivatives in the position, the frame and across them.
#[derive(Debug, Clone, Copy)]
struct Coupled {
    a: f64,
    b: f64,
    radius: f64,
    axis: usize,
}

impl<const N: usize, const E: usize> Potential<N, E> for Coupled {
    fn uses_frame(&self) -> bool {
        self.b != 0.0
    }
    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, _m: &SMatrix<f64, E, E>) -> D {
        let z = x[self.axis] * (1.0 / self.radius);
        let pos = z * z * (0.5 * self.a) + x[0] * x[1] * (0.3 / (self.radius * self.radius)) + z.sin() * 0.1;
        if self.b == 0.0 {
            pos
        } else {
            pos + (e[(self.axis, 0)] * z + e[(0, N - 1)].powi(3) * 0.2) * self.b
        }
    }
}

/// A deterministic stream in [−1, 1) (xorshift64*).
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Checks `tangent_field` at `y` along 8 random directions: `f` is the
/// vector field; `Df` agrees with central differences to `1e-8` (relative,
/// step 1e-5), and the differences at steps `2e-2`, `1e-2` approach it at
/// second order. Returns the largest relative error at step 1e-5.
pub(crate) fn check<S: System>(name: &str, sys: &S, y: &S::State, seed: u64) -> f64 {
    let mut rng = Stream(seed);
    let vf = |z: &S::State| sys.vector_field(0.3, z);
    let mut worst: f64 = 0.0;
    for k in 0..8 {
        let c: Vec<f64> = (0..S::State::DOF).map(|_| rng.next()).collect();
        let xi = S::State::algebra_from_coords(&c);
        let (f, df) = sys.tangent_field(0.3, y, &xi).unwrap_or_else(|| panic!("{name}: no tangent field"));
        assert_eq!(f, vf(y), "{name}: the first part must be the vector field");
        let fd = |s: f64| (vf(&y.compose(&S::State::exp(&(xi * s)))) - vf(&y.compose(&S::State::exp(&(xi * -s))))) * (0.5 / s);
        let err = |s: f64| (fd(s) - df).amax() / (1.0 + df.amax());
        let (e_fine, e1, e2) = (err(1e-5), err(2e-2), err(1e-2));
        println!("{name} direction {k}: |Df| {:.3e}, error {e_fine:.2e} at 1e-5; {e1:.2e} → {e2:.2e} (ratio {:.2})", df.amax(), e1 / e2);
        assert!(e_fine < 1e-8, "{name}: Df differs from the differences by {e_fine:e} (direction {k})");
        if e1 > 1e-9 {
            assert!((3.5..=4.5).contains(&(e1 / e2)), "{name}: differences approach Df at ratio {} (not 4: a term of Df is wrong)", e1 / e2);
        }
        worst = worst.max(e_fine);
    }
    worst
}

#[test]
fn point_tangent_fields_on_every_manifold() {
    let v = Coupled { a: 0.7, b: 0.0, radius: 1.3, axis: 2 };
    let s2 = Sphere2::new(1.3).unwrap();
    let m = PointModel::new(s2, Point::new(1.1).unwrap(), v).unwrap();
    for (i, (x, u)) in [([0.4, 0.3], [0.5, -0.2]), ([2.9, 1.0], [-0.3, 0.8]), ([1e-9, 0.2], [0.7, 0.1])].into_iter().enumerate() {
        let (x, u) = (Vector2::from(x), Vector2::from(u));
        check(&format!("point on S² #{i}"), &m, &m.state(&s2.embed(&x), &s2.embed_tangent(&x, &u)).unwrap(), 1 + i as u64);
    }
    let h2 = Hyperbolic2::new(1.3).unwrap();
    let m = PointModel::new(h2, Point::new(1.1).unwrap(), v).unwrap();
    for (i, x) in [[0.4, 0.3], [2.0, -1.0]].into_iter().enumerate() {
        let x = Vector2::from(x);
        check(&format!("point on H² #{i}"), &m, &m.state(&h2.embed(&x), &h2.embed_tangent(&x, &Vector2::new(0.4, -0.6))).unwrap(), 10 + i as u64);
    }
    let t2 = Torus2::new(2.0, 0.7).unwrap();
    let m = PointModel::new(t2, Point::new(1.1).unwrap(), Coupled { radius: 0.7, ..v }).unwrap();
    let x = Vector2::new(0.8, -2.1);
    check("point on T²", &m, &m.state(&t2.embed(&x), &t2.embed_tangent(&x, &Vector2::new(0.4, 0.9))).unwrap(), 20);
    let sp = Spheroid::new(1.3, 0.9).unwrap();
    let m = PointModel::new(sp, Point::new(1.1).unwrap(), v).unwrap();
    let x = Vector2::new(0.6, 2.2);
    check("point on the spheroid", &m, &m.state(&sp.embed(&x), &sp.embed_tangent(&x, &Vector2::new(0.4, 0.9))).unwrap(), 30);
    let s3 = Sphere3::new(1.3).unwrap();
    let m = PointModel::new(s3, Point::new(1.1).unwrap(), Coupled { axis: 3, ..v }).unwrap();
    let x = Vector3::new(0.3, -0.5, 0.4);
    check("point on S³", &m, &m.state(&s3.embed(&x), &s3.embed_tangent(&x, &Vector3::new(0.4, 0.9, -0.2))).unwrap(), 40);
}

#[test]
fn gyroscope_tangent_fields_on_every_surface() {
    let v = Coupled { a: 0.7, b: 0.45, radius: 1.3, axis: 2 };
    let body = Gyroscope::<2>::isotropic(1.1, 0.35).unwrap();
    let s2 = Sphere2::new(1.3).unwrap();
    let m = Gyroscope2Model::new(s2, body, v).unwrap();
    for (i, x) in [[0.4, 0.3], [1e-9, 0.0], [2.5, -1.0]].into_iter().enumerate() {
        let x = Vector2::from(x);
        check(&format!("gyroscope on S² #{i}"), &m, &m.state_at(&s2.embed(&x), &s2.embed_tangent(&x, &Vector2::new(0.5, -0.3)), 0.7, 0.9).unwrap(), 50 + i as u64);
    }
    let h2 = Hyperbolic2::new(1.3).unwrap();
    for (i, sig) in [Signature::Riemannian, Signature::Lorentz].into_iter().enumerate() {
        let m = Gyroscope2Model::new(h2, body.with_signature(sig), v).unwrap();
        let x = Vector2::new(1.2, 0.8);
        check(&format!("gyroscope on H² ({sig:?})"), &m, &m.state_at(&h2.embed(&x), &h2.embed_tangent(&x, &Vector2::new(0.5, -0.3)), -0.4, 0.6).unwrap(), 60 + i as u64);
    }
    let t2 = Torus2::new(2.0, 0.7).unwrap();
    let m = Gyroscope2Model::new(t2, body, Coupled { radius: 0.7, ..v }).unwrap();
    let x = Vector2::new(0.8, -2.1);
    check("gyroscope on T²", &m, &m.state_at(&t2.embed(&x), &t2.embed_tangent(&x, &Vector2::new(0.4, 0.9)), 1.1, -0.5).unwrap(), 70);
    let sp = Spheroid::new(1.3, 0.9).unwrap();
    let m = Gyroscope2Model::new(sp, body, v).unwrap();
    let x = Vector2::new(0.6, 2.2);
    check("gyroscope on the spheroid", &m, &m.state_at(&sp.embed(&x), &sp.embed_tangent(&x, &Vector2::new(0.4, 0.9)), 0.2, 1.3).unwrap(), 80);
}

#[test]
fn s3_gyroscope_tangent_field() {
    let s3 = Sphere3::new(1.3).unwrap();
    let body = Gyroscope::<3>::new(1.1, Matrix3::from_diagonal(&Vector3::new(0.2, 0.35, 0.5))).unwrap();
    for (i, b) in [0.0, 0.45].into_iter().enumerate() {
        let m = Gyroscope3Model::new(s3, body, Coupled { a: 0.7, b, radius: 1.3, axis: 3 }).unwrap();
        let x = Vector3::new(0.3, -0.5, 0.4);
        let rho = So3::exp(&Vector3::new(0.3, -0.2, 0.9));
        let y = m.state_at(&s3.embed(&x), &s3.embed_tangent(&x, &Vector3::new(0.4, 0.9, -0.2)), &rho, &Vector3::new(0.5, -0.7, 0.2)).unwrap();
        check(&format!("S³ gyroscope, b = {b}"), &m, &y, 90 + i as u64);
    }
}

/// A potential given as an `f64` closure has no second derivatives: the
/// model then has no exact tangent field (the analyses difference its steps).
#[test]
fn closure_potentials_have_no_tangent_field() {
    let s2 = Sphere2::new(1.0).unwrap();
    let v = FnPotential::<_, 2, 3>::new(|x: &SVector<f64, 3>, _e: &SMatrix<f64, 3, 2>, _m: &SMatrix<f64, 3, 3>| x[2] * x[2], false, 1.0).unwrap();
    let m = PointModel::new(s2, Point::new(1.0).unwrap(), v).unwrap();
    let x = Vector2::new(0.4, 0.3);
    let y = m.state(&s2.embed(&x), &s2.embed_tangent(&x, &Vector2::new(0.5, -0.2))).unwrap();
    let zero = framedyn::lie::ProductAlgebra(Vector3::zeros(), Vector2::zeros());
    assert!(m.tangent_field(0.0, &y, &zero).is_none());
}
