//! The reference problems on the torus T²(L, R) (tube radius R about the
//! circle of radius L in the plane z = 0; curvature of both signs, no
//! exact free flow).

use nalgebra::Vector2;

use super::bodies::{AFFINE_INERTIA, AFFINE_RHO0, AFFINE_RHO_DOT0, AFFINE_U0};
use super::potentials::{Axial, UniformField};
use super::readouts::{affine_observable, affine_p_phi, gyroscope2_observable, gyroscope2_p_phi};
use super::sphere2::{TILTED_T_END, VALID};
use super::Reference;
use crate::body::{Affine, Gyroscope};
use crate::dynamics::affine::AffineModel;
use crate::dynamics::point::bundle_element_at;
use crate::dynamics::Gyroscope2Model;
use crate::manifold::{Manifold, Torus2};
use crate::error::finite;
use crate::potential::{Elastic, Sum};
use crate::Result;

/// T² gyroscope in a uniform field along the symmetry axis.
pub type T2Gyro = Gyroscope2Model<Torus2, UniformField>;
/// Affine body on T²: the elastic potential (a131) plus a uniform field.
pub type T2Affine = AffineModel<Torus2, Sum<Elastic, UniformField>, 2, 3>;
/// T² gyroscope in the [`Axial`] tilt with frame coupling.
pub type T2TiltedGyro = Gyroscope2Model<Torus2, Axial>;

/// The T²(L = 2, R = 0.7) gyroscope (m = 1, I = 0.3) in `V = 0.8 z`
/// ([`UniformField`]), from the chart point `(θ, φ) = (0.6, 0.2)` with chart
/// velocity `(0.9, 0.4)`, internal angle 0.4 and angular velocity ω = 1,
/// T = 20. Momentum map `p_φ`.
pub fn t2_gyro() -> Reference<T2Gyro> {
    let t2 = Torus2::new(2.0, 0.7).expect(VALID);
    let m = Gyroscope2Model::new(t2, Gyroscope::<2>::isotropic(1.0, 0.3).expect(VALID), UniformField { a: 0.8 }).expect(VALID);
    let x = Vector2::new(0.6, 0.2);
    let (p, v) = (t2.embed(&x), t2.embed_tangent(&x, &Vector2::new(0.9, 0.4)));
    let spin = m.spin_for_angular_velocity(1.0);
    let y0 = m.state_at(&p, &v, 0.4, spin).expect(VALID);
    Reference {
        name: "t2_gyro",
        about: "T²(L = 2, R = 0.7) gyroscope, I = 0.3, V = 0.8 z",
        system: m,
        y0,
        t_end: 20.0,
        observable: gyroscope2_observable,
        momentum: gyroscope2_p_phi,
    }
}

/// Affine body (m = 1, J = [`AFFINE_INERTIA`]) on T²(L = 2, R = 0.7) in the
/// elastic potential (a131) with κ = 1 plus `0.8 z`, at the chart point
/// `(0.6, 0.2)` with the internal state [`AFFINE_RHO0`], [`AFFINE_U0`],
/// [`AFFINE_RHO_DOT0`], T = 20. Momentum map `p_φ`.
pub fn t2_affine() -> Reference<T2Affine> {
    let t2 = Torus2::new(2.0, 0.7).expect(VALID);
    let pot = Sum::new(Elastic::new(1.0).expect(VALID), UniformField { a: 0.8 });
    let m = AffineModel::new(t2, Affine::new(1.0, AFFINE_INERTIA).expect(VALID), pot).expect(VALID);
    let g = bundle_element_at(&t2, &t2.embed(&Vector2::new(0.6, 0.2))).expect(VALID);
    let y0 = m.state(&g, &AFFINE_RHO0, &AFFINE_U0, &AFFINE_RHO_DOT0).expect(VALID);
    Reference {
        name: "t2_affine",
        about: "T²(L = 2, R = 0.7) affine body, elastic κ = 1 + 0.8 z",
        system: m,
        y0,
        t_end: 20.0,
        observable: affine_observable,
        momentum: affine_p_phi,
    }
}

/// A gyroscope (m = 1, I = 0.3) on T²(L = 2, R = 0.7) in
/// `V = a·z/0.7 + b·e₁ᶻ` ([`Axial`] about z with the tube radius), from the
/// chart point `(θ, φ) = (0.6, 0.2)` with chart velocity `(0.9, 0.4)`,
/// internal angle 0.4 and spin 0.6. Momentum map `p_φ`.
///
/// Errors: [`crate::Error::NotFinite`] for a non-finite `a` or `b`.
pub fn t2_tilted_gyro_with(a: f64, b: f64) -> Result<Reference<T2TiltedGyro>> {
    finite("a, b", [a, b].iter())?;
    let t2 = Torus2::new(2.0, 0.7)?;
    let m = Gyroscope2Model::new(t2, Gyroscope::<2>::isotropic(1.0, 0.3)?, Axial { a, b, radius: 0.7, axis: 2 })?;
    let x = Vector2::new(0.6, 0.2);
    let (p, v) = (t2.embed(&x), t2.embed_tangent(&x, &Vector2::new(0.9, 0.4)));
    let y0 = m.state_at(&p, &v, 0.4, 0.6)?;
    Ok(Reference {
        name: "t2_tilted_gyro",
        about: "T²(L = 2, R = 0.7) gyroscope, I = 0.3, V = a z/0.7 + b e₁ᶻ, chart start (0.6, 0.2), rates (0.9, 0.4), spin 0.6",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: gyroscope2_observable,
        momentum: gyroscope2_p_phi,
    })
}

/// [`t2_tilted_gyro_with`] with a = 0.8, b = 0.3.
pub fn t2_tilted_gyro() -> Reference<T2TiltedGyro> {
    t2_tilted_gyro_with(0.8, 0.3).expect(VALID)
}
