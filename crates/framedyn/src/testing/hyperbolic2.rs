//! The reference problems on the hyperbolic plane H² (the hyperboloid
//! `−x² − y² + z² = R²`, `z > 0`, in ℝ^{2,1}).

use nalgebra::{Matrix2, Vector2};

use super::bodies::AFFINE_INERTIA;
use super::potentials::Axial;
use super::readouts::{affine_observable, affine_p_phi, gyroscope2_observable, gyroscope2_p_phi};
use super::sphere2::{TILTED_T_END, VALID};
use super::Reference;
use crate::body::{Gyroscope, Incompressible, Signature};
use crate::dynamics::constrained::IncompressibleModel;
use crate::dynamics::point::bundle_element_at;
use crate::dynamics::Gyroscope2Model;
use crate::error::finite;
use crate::manifold::{Hyperbolic2, Manifold};
use crate::potential::{Centre, CosineFamily, Elastic, Sum};
use crate::Result;

/// H² gyroscope in `V = a cosh(r/R)`.
pub type H2Gyro = Gyroscope2Model<Hyperbolic2, CosineFamily<3>>;

/// The H² gyroscope (R = 1, m = 1, I = 0.3, internal energy of signature
/// `sig`) confined by `V = 0.5 cosh(r/R)`, from the chart point
/// `(r, φ) = (0.7, 0.3)` with chart velocity `(0.4, 0.9)`, internal angle 0.4
/// and angular velocity ω = 1, T = 20. Momentum map `p_φ`.
fn h2_gyro_signature(sig: Signature, name: &'static str, about: &'static str) -> Reference<H2Gyro> {
    let h2 = Hyperbolic2::new(1.0).expect(VALID);
    let pot = CosineFamily::new(0.0, 0.5, Centre::hyperbolic2(&h2)).expect(VALID);
    let body = Gyroscope::<2>::isotropic(1.0, 0.3).expect(VALID).with_signature(sig);
    let m = Gyroscope2Model::new(h2, body, pot).expect(VALID);
    let x = Vector2::new(0.7, 0.3);
    let (p, v) = (h2.embed(&x), h2.embed_tangent(&x, &Vector2::new(0.4, 0.9)));
    let spin = m.spin_for_angular_velocity(1.0);
    let y0 = m.state_at(&p, &v, 0.4, spin).expect(VALID);
    Reference { name, about, system: m, y0, t_end: 20.0, observable: gyroscope2_observable, momentum: gyroscope2_p_phi }
}

/// H² gyroscope (R = 1, m = 1, I = 0.3) confined by `V = 0.5 cosh(r/R)`,
/// chart start `(0.7, 0.3)`, rates `(0.4, 0.9)`, ψ = 0.4, ω = 1, T = 20.
pub fn h2_gyro() -> Reference<H2Gyro> {
    h2_gyro_signature(Signature::Riemannian, "h2_gyro", "H² gyroscope, I = 0.3, V = 0.5 cosh(r/R)")
}

/// [`h2_gyro`] with the Lorentz-type internal energy (a138).
pub fn h2_lorentz() -> Reference<H2Gyro> {
    h2_gyro_signature(Signature::Lorentz, "h2_lorentz", "H² Lorentz-type gyroscope (a138), I = 0.3, V = 0.5 cosh(r/R)")
}

/// H² gyroscope in the [`Axial`] tilt with frame coupling.
pub type H2TiltedGyro = Gyroscope2Model<Hyperbolic2, Axial>;
/// H² incompressible body in the elastic potential plus the [`Axial`] tilt.
pub type H2TiltedIncompressible = IncompressibleModel<Hyperbolic2, Sum<Elastic, Axial>, 2, 3>;

/// A gyroscope (m = 1, I = 0.3, internal energy of signature `sig`) on H²
/// (R = 1) in `V = a·z + b·e₁ᶻ` ([`Axial`] about z: `a cosh(r/R)` plus a
/// frame coupling), from the chart point `(0.7, 0.3)` with chart velocity
/// `(0.4, 0.9)`, internal angle 0.4 and spin 0.6. Momentum map `p_φ`.
///
/// Errors: [`crate::Error::NotFinite`] for a non-finite `a` or `b`.
pub fn h2_tilted_gyro_with(a: f64, b: f64, sig: Signature) -> Result<Reference<H2TiltedGyro>> {
    finite("a, b", [a, b].iter())?;
    let h2 = Hyperbolic2::new(1.0)?;
    let body = Gyroscope::<2>::isotropic(1.0, 0.3)?.with_signature(sig);
    let m = Gyroscope2Model::new(h2, body, Axial { a, b, radius: 1.0, axis: 2 })?;
    let x = Vector2::new(0.7, 0.3);
    let (p, v) = (h2.embed(&x), h2.embed_tangent(&x, &Vector2::new(0.4, 0.9)));
    let y0 = m.state_at(&p, &v, 0.4, 0.6)?;
    Ok(Reference {
        name: "h2_tilted_gyro",
        about: "H² gyroscope, I = 0.3, V = a z + b e₁ᶻ, chart start (0.7, 0.3), rates (0.4, 0.9), spin 0.6",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: gyroscope2_observable,
        momentum: gyroscope2_p_phi,
    })
}

/// [`h2_tilted_gyro_with`] with a = 0.8, b = 0.3 and the Riemannian
/// internal energy.
pub fn h2_tilted_gyro() -> Reference<H2TiltedGyro> {
    h2_tilted_gyro_with(0.8, 0.3, Signature::Riemannian).expect(VALID)
}

/// An incompressible body (ρ ∈ SL(2), m = 1, J = [`AFFINE_INERTIA`]) on H²
/// (R = 1) in the elastic potential (a131) with κ = 0.8 plus `0.4·z`
/// ([`Axial`] without frame coupling: on the hyperboloid the z components
/// of tangent vectors grow like sinh r, and with a coupling b = 0.3 the body
/// runs away near t = 5.4), at the chart point `(0.7, −0.4)` with
/// `ρ₀ = ρ/√det ρ` for `ρ = (1.1, 0.3; −0.2, 0.8)`, `u₀ = (0.6, −0.9)` and
/// `ρ̇₀ = ρ₀ W`, `W = (0.3, −0.6; 0.5, −0.3)` (traceless). Momentum map `p_φ`.
pub fn h2_tilted_incompressible() -> Reference<H2TiltedIncompressible> {
    let h2 = Hyperbolic2::new(1.0).expect(VALID);
    let pot = Sum::new(Elastic::new(0.8).expect(VALID), Axial { a: 0.4, b: 0.0, radius: 1.0, axis: 2 });
    let m = IncompressibleModel::new(h2, Incompressible::new(1.0, AFFINE_INERTIA).expect(VALID), pot).expect(VALID);
    let g = bundle_element_at(&h2, &h2.embed(&Vector2::new(0.7, -0.4))).expect(VALID);
    let rho: Matrix2<f64> = Matrix2::new(1.1, 0.3, -0.2, 0.8);
    let rho = rho / rho.determinant().sqrt();
    let w = Matrix2::new(0.3, -0.6, 0.5, -0.3);
    let y0 = m.state(&g, &rho, &Vector2::new(0.6, -0.9), &(rho * w)).expect(VALID);
    Reference {
        name: "h2_tilted_incompressible",
        about: "H² incompressible body, elastic κ = 0.8 (a131) + 0.4 z",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: affine_observable,
        momentum: affine_p_phi,
    }
}
