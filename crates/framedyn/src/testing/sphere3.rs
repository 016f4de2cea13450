//! The reference problems on the 3-sphere S³ ⊂ ℝ⁴ (R = 1).

use nalgebra::{Matrix3, Matrix4, Vector3};

use super::potentials::Axial;
use super::readouts::{affine_observable, gyroscope3_observable};
use super::sphere2::{TILTED_T_END, VALID};
use super::Reference;
use crate::body::{Gyroscope, Weyl};
use crate::dynamics::constrained::WeylModel;
use crate::dynamics::point::bundle_element_at;
use crate::dynamics::{Gyroscope3Model, System};
use crate::error::finite;
use crate::lie::{LieGroup, So3};
use crate::manifold::{Manifold, Sphere3};
use crate::potential::{Centre, CosineFamily};
use crate::Result;

/// S³ gyroscope in `V = a cos(r/R)`.
pub type S3Gyro = Gyroscope3Model<Sphere3, CosineFamily<4>>;
/// S³ gyroscope in the [`Axial`] tilt with frame coupling.
pub type S3TiltedGyro = Gyroscope3Model<Sphere3, Axial>;
/// S³ Weyl body (rotations and dilatations) in the [`Axial`] tilt.
pub type S3TiltedWeyl = WeylModel<Sphere3, Axial, 3, 4>;

/// The anisotropic inertia `J = diag(0.2, 0.35, 0.5)` of the S³ gyroscopes.
pub const S3_ANISOTROPIC_J: Vector3<f64> = Vector3::new(0.2, 0.35, 0.5);
/// A symmetric inertia `J = diag(0.2, 0.2, 0.5)` (the free flow is then
/// exactly solvable, SPEC §4).
pub const S3_SYMMETRIC_J: Vector3<f64> = Vector3::new(0.2, 0.2, 0.5);

/// The rotation generator of the plane of the ambient axes `i`, `j`
/// (`A e_i = e_j`).
fn plane_rotation(i: usize, j: usize) -> Matrix4<f64> {
    let mut a = Matrix4::zeros();
    a[(j, i)] = 1.0;
    a[(i, j)] = -1.0;
    a
}

/// The (x₂, x₃)-plane rotation of ℝ⁴: a symmetry of `V = a cos(r/R)` about
/// the centre `(R, 0, 0, 0)` of [`s3_gyro`].
pub fn s3_centre_rotation() -> Matrix4<f64> {
    plane_rotation(2, 3)
}

/// The (x₀, x₂)-plane rotation of ℝ⁴: a symmetry of the [`Axial`] potential
/// about the axis 1 of the tilted S³ problems.
pub fn s3_axial_rotation() -> Matrix4<f64> {
    plane_rotation(0, 2)
}

/// The S³ gyroscope (R = 1, m = 1, J = [`S3_ANISOTROPIC_J`]) in
/// `V = 0.5 cos(r/R)` about `(R, 0, 0, 0)`, from the chart point
/// `k = (0.5, −0.3, 0.4)` with chart velocity `(0.3, 0.5, −0.4)`, internal
/// rotation `exp(0.2, −0.1, 0.3)` and angular velocity `(0.4, −0.3, 0.5)`,
/// T = 20. Momentum map: [`s3_centre_rotation`].
pub fn s3_gyro() -> Reference<S3Gyro> {
    let s3 = Sphere3::new(1.0).expect(VALID);
    let body = Gyroscope::<3>::new(1.0, Matrix3::from_diagonal(&S3_ANISOTROPIC_J)).expect(VALID);
    let pot = CosineFamily::new(0.0, 0.5, Centre::sphere3(&s3)).expect(VALID);
    let m = Gyroscope3Model::new(s3, body, pot).expect(VALID);
    let x = Vector3::new(0.5, -0.3, 0.4);
    let (p, v) = (s3.embed(&x), s3.embed_tangent(&x, &Vector3::new(0.3, 0.5, -0.4)));
    let rho = So3::exp(&Vector3::new(0.2, -0.1, 0.3));
    let y0 = m.state_at(&p, &v, &rho, &Vector3::new(0.4, -0.3, 0.5)).expect(VALID);
    fn momentum(m: &S3Gyro, y: &<S3Gyro as System>::State) -> f64 {
        m.momentum_map(y, &s3_centre_rotation()).expect("a plane rotation generates isometries of ℝ⁴")
    }
    Reference {
        name: "s3_gyro",
        about: "S³ gyroscope, J = diag(0.2, 0.35, 0.5), V = 0.5 cos(r/R)",
        system: m,
        y0,
        t_end: 20.0,
        observable: gyroscope3_observable,
        momentum,
    }
}

/// A gyroscope (R = 1, m = 1, inertia `diag(j)`) on S³ in
/// `V = a·x₁ + b·e₁[1]` ([`Axial`] about the ambient axis 1), from the
/// start of [`s3_gyro`] (chart point, velocity, internal rotation) with the
/// spin `(0.4, −0.3, 0.5)`. Momentum map: [`s3_axial_rotation`].
///
/// Errors: [`crate::Error::NotFinite`] for a non-finite `a` or `b`;
/// [`crate::Error::InvalidParameter`] for an inertia that is not positive.
pub fn s3_tilted_gyro_with(j: Vector3<f64>, a: f64, b: f64) -> Result<Reference<S3TiltedGyro>> {
    finite("a, b", [a, b].iter())?;
    let s3 = Sphere3::new(1.0)?;
    let body = Gyroscope::<3>::new(1.0, Matrix3::from_diagonal(&j))?;
    let m = Gyroscope3Model::new(s3, body, Axial { a, b, radius: 1.0, axis: 1 })?;
    let x = Vector3::new(0.5, -0.3, 0.4);
    let (p, v) = (s3.embed(&x), s3.embed_tangent(&x, &Vector3::new(0.3, 0.5, -0.4)));
    let rho = So3::exp(&Vector3::new(0.2, -0.1, 0.3));
    let y0 = m.state_at(&p, &v, &rho, &Vector3::new(0.4, -0.3, 0.5))?;
    fn momentum(m: &S3TiltedGyro, y: &<S3TiltedGyro as System>::State) -> f64 {
        m.momentum_map(y, &s3_axial_rotation()).expect("a plane rotation generates isometries of ℝ⁴")
    }
    Ok(Reference {
        name: "s3_tilted_gyro",
        about: "S³ gyroscope, J = diag(j), V = a x₁ + b e₁[1]",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: gyroscope3_observable,
        momentum,
    })
}

/// [`s3_tilted_gyro_with`] with J = [`S3_ANISOTROPIC_J`], a = 0.8, b = 0.3.
pub fn s3_tilted_gyro() -> Reference<S3TiltedGyro> {
    s3_tilted_gyro_with(S3_ANISOTROPIC_J, 0.8, 0.3).expect(VALID)
}

/// A Weyl body (ρ ∈ CO⁺(3): rotation and dilatation; m = 1.2,
/// J = (0.3, 0.05, 0; 0.05, 0.2, 0.04; 0, 0.04, 0.25)) on S³ (R = 1) in
/// `V = 0.6·x₁ + 0.3·e₁[1]` ([`Axial`] about the axis 1), at the chart
/// point `(0.5, −0.3, 0.9)` with `ρ₀ = 1.1·exp(0.3, −0.5, 0.2)`,
/// `u₀ = (0.6, −0.9, 0.4)` and `ρ̇₀ = ρ₀ Ω`, `Ω` = 0.2·I plus a skew part.
/// Chaotic (perturbations grow ≈ 600× over T = 10). Momentum map:
/// [`s3_axial_rotation`].
pub fn s3_tilted_weyl() -> Reference<S3TiltedWeyl> {
    let s3 = Sphere3::new(1.0).expect(VALID);
    let j3 = Matrix3::new(0.3, 0.05, 0.0, 0.05, 0.2, 0.04, 0.0, 0.04, 0.25);
    let m = WeylModel::new(s3, Weyl::new(1.2, j3).expect(VALID), Axial { a: 0.6, b: 0.3, radius: 1.0, axis: 1 }).expect(VALID);
    let g = bundle_element_at(&s3, &s3.embed(&Vector3::new(0.5, -0.3, 0.9))).expect(VALID);
    let rho = *So3::exp(&Vector3::new(0.3, -0.5, 0.2)).matrix() * 1.1;
    let om = Matrix3::new(0.2, -0.7, 0.4, 0.7, 0.2, -0.5, -0.4, 0.5, 0.2);
    let y0 = m.state(&g, &rho, &Vector3::new(0.6, -0.9, 0.4), &(rho * om)).expect(VALID);
    fn momentum(m: &S3TiltedWeyl, y: &<S3TiltedWeyl as System>::State) -> f64 {
        m.noether_charge(y, &s3_axial_rotation()).expect("a plane rotation generates isometries of ℝ⁴")
    }
    Reference {
        name: "s3_tilted_weyl",
        about: "S³ Weyl body, m = 1.2, V = 0.6 x₁ + 0.3 e₁[1]",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: affine_observable,
        momentum,
    }
}
