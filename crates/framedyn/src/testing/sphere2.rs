//! The reference problems on the sphere S².
//!
//! The S² gyroscope of SPEC §5 — m = 1, R = 1, I = 0.3 in `V = 0.5 cos(r/R)`
//! (a uniform field along the z axis), from the chart state
//! `(r, φ, ψ) = (1, 0.3, 0.4)` with rates `(ṙ, φ̇) = (0.3, 0.6)` and the
//! angular velocity (a91) `ω = ψ̇ + cos(r/R) φ̇ = 1`, over `T = 100` — in two
//! constructions of the same physical state, which differ by round-off:
//! [`s2_gyro`] builds the group state from the embedded chart point and
//! velocity and the spin of `ω` ([`Gyroscope2Model::state_at`]), and
//! [`s2_gyro_from_chart`] from the paper's coordinate form (the ambient
//! position, velocity, body frame and co-moving spin of the chart state
//! through [`crate::coords`]), so that a coordinate solver starts from
//! exactly the group form's initial state. The step-cost bench and the
//! long-time stability runs use the first, the work-precision and
//! stability-map comparisons with coordinate solvers the second.

use nalgebra::{Matrix2, SVector, Vector2, Vector3};

use super::bodies::{AFFINE_INERTIA, AFFINE_RHO0, AFFINE_RHO_DOT0, AFFINE_U0};
use super::potentials::Axial;
use super::readouts::{affine_observable, affine_p_phi, gyroscope2_observable, gyroscope2_p_phi, point_observable, point_p_phi};
use super::Reference;
use crate::body::{Affine, Gyroscope, Point};
use crate::coords::{ambient_state, Gyroscope2, PlaneRotation, SphereChart};
use crate::dynamics::affine::AffineModel;
use crate::dynamics::point::bundle_element_at;
use crate::dynamics::{Gyroscope2Model, PointModel};
use crate::error::{finite, positive};
use crate::manifold::{Manifold, Sphere2};
use crate::potential::{Axis, Centre, CosineFamily, Elastic, Pole, Sum};
use crate::Result;

/// Why the problems without parameters cannot fail.
pub(super) const VALID: &str = "the documented parameters of a reference problem are valid";

// ---------------------------------------------------------------------------
// SPEC §5
// ---------------------------------------------------------------------------

/// Mass `m` of the SPEC §5 gyroscope.
pub const S2_MASS: f64 = 1.0;
/// Radius `R` of the sphere.
pub const S2_RADIUS: f64 = 1.0;
/// Moment of inertia `I` of the gyroscope.
pub const S2_MOMENT: f64 = 0.3;
/// Field strength `a` of `V = a cos(r/R)`.
pub const S2_A: f64 = 0.5;
/// Initial chart state `(r, φ, ψ)`: the chart position and the internal
/// angle.
pub const S2_Q0: [f64; 3] = [1.0, 0.3, 0.4];
/// Initial rates `(ṙ, φ̇, ω)`: the chart velocity and the angular velocity
/// `ω = ψ̇ + cos(r/R) φ̇` of (a91).
pub const S2_V0: [f64; 3] = [0.3, 0.6, 1.0];
/// Final time `T`.
pub const S2_T_END: f64 = 100.0;

/// S² gyroscope in `V = a cos(r/R)` about a runtime [`Centre`] (as scenes
/// and Python build it).
pub type S2Gyro = Gyroscope2Model<Sphere2, CosineFamily<3>>;
/// The same with the centre a compile-time [`Pole`] (the same numbers bit
/// for bit; the step-cost bench's `*_pole` rows).
pub type S2GyroPole = Gyroscope2Model<Sphere2, CosineFamily<3, Pole<3>>>;
/// The coordinate Lagrangian (a52)/(a91) of the S² gyroscope in
/// `V = a cos(r/R)`, on the chart state `(r, φ, ψ; ṙ, φ̇, ψ̇)`.
pub type S2GyroCoords = Gyroscope2<SphereChart, CosineFamily<3>>;

/// The S² gyroscope of SPEC §5: m = 1, R = 1, I = 0.3, V = 0.5 cos(r/R),
/// chart start `(1, 0.3, 0.4)`, rates `(0.3, 0.6)`, ω = 1, T = 100 (the
/// constants `S2_*`). Momentum map `p_φ`.
pub fn s2_gyro() -> Reference<S2Gyro> {
    s2_gyro_with(S2_A, S2_RADIUS, S2_Q0, S2_V0, S2_T_END, "s2_gyro").expect(VALID)
}

/// [`s2_gyro`] about a compile-time [`Pole`].
pub fn s2_gyro_pole() -> Reference<S2GyroPole> {
    s2_gyro_about(Pole::sphere2, S2_A, S2_RADIUS, S2_Q0, S2_V0, S2_T_END, "s2_gyro").expect(VALID)
}

/// The S² gyroscope (m = 1, I = 0.3) on the sphere of radius `radius` in
/// `V = a cos(r/R)`, from the chart state `q0 = (r, φ, ψ)` with rates
/// `v0 = (ṙ, φ̇, ω)`, over `[0, t_end]`. The group state is built by
/// [`Gyroscope2Model::state_at`] from the embedded chart point and velocity
/// and the spin of the angular velocity `ω`.
///
/// Errors: [`crate::Error::InvalidParameter`] (`"radius"`, `"t_end"`: finite and
/// > 0; `"a"` via the potential); [`crate::Error::NotFinite`] or
/// [`crate::Error::Constraint`] for a non-finite chart state.
pub fn s2_gyro_with(a: f64, radius: f64, q0: [f64; 3], v0: [f64; 3], t_end: f64, name: &'static str) -> Result<Reference<S2Gyro>> {
    s2_gyro_about(Centre::sphere2, a, radius, q0, v0, t_end, name)
}

/// [`s2_gyro_with`] with the potential's centre built by `centre` (a
/// [`Centre`] or a [`Pole`]).
pub fn s2_gyro_about<C: Axis<3>>(
    centre: fn(&Sphere2) -> C,
    a: f64,
    radius: f64,
    q0: [f64; 3],
    v0: [f64; 3],
    t_end: f64,
    name: &'static str,
) -> Result<Reference<Gyroscope2Model<Sphere2, CosineFamily<3, C>>>> {
    positive("t_end", t_end)?;
    finite("q0", q0.iter())?;
    finite("v0", v0.iter())?;
    let s2 = Sphere2::new(radius)?;
    let pot = CosineFamily::new(0.0, a, centre(&s2))?;
    let m = Gyroscope2Model::new(s2, Gyroscope::<2>::isotropic(S2_MASS, S2_MOMENT)?, pot)?;
    let x = Vector2::new(q0[0], q0[1]);
    let (p, v) = (s2.embed(&x), s2.embed_tangent(&x, &Vector2::new(v0[0], v0[1])));
    let spin = m.spin_for_angular_velocity(v0[2]);
    let y0 = m.state_at(&p, &v, q0[2], spin)?;
    Ok(Reference {
        name,
        about: "S² gyroscope, m = 1, I = 0.3, V = a cos(r/R), chart start (r, φ, ψ), rates (ṙ, φ̇, ω) (SPEC §5)",
        system: m,
        y0,
        t_end,
        observable: gyroscope2_observable,
        momentum: gyroscope2_p_phi,
    })
}

/// The coordinate Lagrangian of the S² gyroscope (m = 1, I = 0.3) on the
/// sphere of radius `radius` in `V = a cos(r/R)`: the paper's form, on the
/// chart `(r, φ)` with the internal angle `ψ` relative to the frame field
/// (a90).
///
/// Errors: [`crate::Error::InvalidParameter`] for `radius` (finite, > 0) or `a`.
pub fn s2_gyro_coords(a: f64, radius: f64) -> Result<S2GyroCoords> {
    let s2 = Sphere2::new(radius)?;
    let pot = CosineFamily::new(0.0, a, Centre::sphere2(&s2))?;
    Ok(Gyroscope2::gyroscope(SphereChart::new(radius)?, PlaneRotation, &Gyroscope::<2>::isotropic(S2_MASS, S2_MOMENT)?, pot))
}

/// The chart state `(q, q̇)` of a chart start `q0 = (r, φ, ψ)` with rates
/// `v0 = (ṙ, φ̇, ω)`: `q = q0`, `q̇ = (ṙ, φ̇, ω − cos(r/R) φ̇)`, so that the
/// angular velocity (a91) is `ω`.
pub fn s2_chart_state(radius: f64, q0: [f64; 3], v0: [f64; 3]) -> (SVector<f64, 3>, SVector<f64, 3>) {
    let q = Vector3::new(q0[0], q0[1], q0[2]);
    let v = Vector3::new(v0[0], v0[1], v0[2] - (q0[0] / radius).cos() * v0[1]);
    (q, v)
}

/// The ambient observable of a chart state of [`S2GyroCoords`], in the
/// layout of [`gyroscope2_observable`]: position, velocity, body frame and
/// the co-moving spin.
///
/// Errors: those of [`ambient_state`] and of the co-moving quantities (a
/// state at a pole of the chart, non-finite values).
pub fn s2_chart_observable(sys: &S2GyroCoords, q: &SVector<f64, 3>, v: &SVector<f64, 3>) -> Result<Vec<f64>> {
    let amb = ambient_state(sys, q, v)?;
    let s = sys.comoving(q, v)?.spin[(0, 1)];
    let mut o: Vec<f64> = amb.position.iter().copied().collect();
    o.extend(amb.velocity.iter());
    o.extend(amb.frame.iter());
    o.push(s);
    Ok(o)
}

/// The problem of [`s2_gyro_with`] with the group state built from the
/// coordinate form instead: the ambient position, velocity and body frame
/// and the co-moving spin of the chart state [`s2_chart_state`] of
/// [`s2_gyro_coords`], so that a coordinate solver and the group form start
/// from the same state to the last bit. It differs from [`s2_gyro_with`]'s
/// state by round-off only.
///
/// Errors: those of [`s2_gyro_with`] and [`s2_chart_observable`].
pub fn s2_gyro_from_chart(a: f64, radius: f64, q0: [f64; 3], v0: [f64; 3], t_end: f64, name: &'static str) -> Result<Reference<S2Gyro>> {
    let sys = s2_gyro_coords(a, radius)?;
    let (q, v) = s2_chart_state(radius, q0, v0);
    let amb = ambient_state(&sys, &q, &v)?;
    let spin = sys.comoving(&q, &v)?.spin[(0, 1)];
    let mut r = s2_gyro_with(a, radius, q0, v0, t_end, name)?;
    r.y0 = r.system.state(&amb.position, &amb.velocity, &amb.frame, spin)?;
    Ok(r)
}

// ---------------------------------------------------------------------------
// Through the pole
// ---------------------------------------------------------------------------

/// Field strength of the well at the pole: `V = −0.5 cos(r/R)`.
pub const S2_POLE_A: f64 = -0.5;
/// Chart start `(r, φ, ψ)` 1e-6 R from the pole.
pub const S2_POLE_Q0: [f64; 3] = [1e-6, 0.3, 0.4];
/// Rates `(ṙ, φ̇, ω)`: radial motion, so the trajectory swings through the
/// neighbourhood of the pole.
pub const S2_POLE_V0: [f64; 3] = [1.0, 0.0, 1.0];
/// Final time.
pub const S2_POLE_T_END: f64 = 20.0;

/// The S² gyroscope (m = 1, R = 1, I = 0.3) in the well at the pole,
/// `V = −0.5 cos(r/R)`, starting 1e-6 R from the pole and moving radially
/// (the constants `S2_POLE_*`), T = 20: it swings through the neighbourhood
/// of the pole, where the coordinate form is singular (SPEC §5).
pub fn s2_pole() -> Reference<S2Gyro> {
    let mut r = s2_gyro_with(S2_POLE_A, S2_RADIUS, S2_POLE_Q0, S2_POLE_V0, S2_POLE_T_END, "s2_pole").expect(VALID);
    r.about = "S² gyroscope, V = −0.5 cos(r/R), start 1e-6 R from the pole moving radially";
    r
}

// ---------------------------------------------------------------------------
// The point
// ---------------------------------------------------------------------------

/// Structureless point on S² in `V = a cos(r/R)`.
pub type S2Point = PointModel<Sphere2, CosineFamily<3>, 2, 3>;

/// A structureless point (m = 1) on the unit S² in `V = 0.5 cos(r/R)`: the
/// SPEC §5 problem without the internal degrees of freedom, chart start
/// `(r, φ) = (1, 0.3)`, rates `(0.3, 0.6)`, T = 20. Momentum map `p_φ`.
pub fn s2_point() -> Reference<S2Point> {
    let s2 = Sphere2::new(S2_RADIUS).expect(VALID);
    let pot = CosineFamily::new(0.0, S2_A, Centre::sphere2(&s2)).expect(VALID);
    let m: S2Point = PointModel::new(s2, Point::new(S2_MASS).expect(VALID), pot).expect(VALID);
    let x = Vector2::new(S2_Q0[0], S2_Q0[1]);
    let y0 = m.state(&s2.embed(&x), &s2.embed_tangent(&x, &Vector2::new(S2_V0[0], S2_V0[1]))).expect(VALID);
    Reference {
        name: "s2_point",
        about: "S² point, m = 1, R = 1, V = 0.5 cos(r/R), chart start (1, 0.3), rates (0.3, 0.6)",
        system: m,
        y0,
        t_end: 20.0,
        observable: point_observable,
        momentum: point_p_phi,
    }
}

// ---------------------------------------------------------------------------
// Affine bodies
// ---------------------------------------------------------------------------

/// Affine body on S²: the elastic potential (a131) plus `a cos(r/R)`.
pub type S2Affine = AffineModel<Sphere2, Sum<Elastic, CosineFamily<3>>, 2, 3>;

/// Affine body on the unit S² (m = 1, J = [`AFFINE_INERTIA`]) in the
/// elastic potential (a131) with stiffness `kappa` plus `0.5 cos(r/R)`,
/// starting at the chart point `(0.8, 0.2)` with the internal state
/// [`AFFINE_RHO0`], [`AFFINE_U0`], [`AFFINE_RHO_DOT0`], T = 20. Momentum map
/// `p_φ`.
///
/// Errors: [`crate::Error::InvalidParameter`] for `kappa` (see [`Elastic::new`]).
pub fn s2_affine_kappa(kappa: f64) -> Result<Reference<S2Affine>> {
    let s2 = Sphere2::new(1.0)?;
    let pot = Sum::new(Elastic::new(kappa)?, CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2))?);
    let m = AffineModel::new(s2, Affine::new(1.0, AFFINE_INERTIA)?, pot)?;
    let g = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2)))?;
    let y0 = m.state(&g, &AFFINE_RHO0, &AFFINE_U0, &AFFINE_RHO_DOT0)?;
    Ok(Reference {
        name: "s2_affine",
        about: "S² affine body, elastic κ (a131) + 0.5 cos(r/R)",
        system: m,
        y0,
        t_end: 20.0,
        observable: affine_observable,
        momentum: affine_p_phi,
    })
}

/// [`s2_affine_kappa`] with κ = 1.
pub fn s2_affine() -> Reference<S2Affine> {
    s2_affine_kappa(1.0).expect(VALID)
}

/// Affine body on S² in a position-only potential (free internal motion).
pub type S2FreeAffine = AffineModel<Sphere2, CosineFamily<3>, 2, 3>;

/// The compression rate `ρ̇₀` of [`s2_affine_collapse`].
pub const S2_COLLAPSE_RATE: Matrix2<f64> = Matrix2::new(-1.0, 0.2, 0.1, 0.3);

/// An affine body on the unit S² (m = 1, J = [`AFFINE_INERTIA`]) in the
/// position-only potential `0.5 cos(r/R)`: `∂V/∂ρ = 0`, so the internal
/// motion is free, `ρ(t) = I + tρ̇₀`, and the compression rate
/// `ρ̇₀ =` [`S2_COLLAPSE_RATE`] flattens the body (`det ρ = 0`) at
/// [`s2_collapse_time`] ≈ 0.985. Starts at the chart point `(0.8, 0.2)` with
/// `ρ₀ = I` and `u₀ =` [`AFFINE_U0`]; T = 2, beyond the collapse (the
/// stability measurements run into it). Momentum map `p_φ`.
pub fn s2_affine_collapse() -> Reference<S2FreeAffine> {
    let s2 = Sphere2::new(1.0).expect(VALID);
    let pot = CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2)).expect(VALID);
    let m = AffineModel::new(s2, Affine::new(1.0, AFFINE_INERTIA).expect(VALID), pot).expect(VALID);
    let g = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2))).expect(VALID);
    let y0 = m.state(&g, &Matrix2::identity(), &AFFINE_U0, &S2_COLLAPSE_RATE).expect(VALID);
    Reference {
        name: "s2_affine_collapse",
        about: "S² affine body, V = 0.5 cos(r/R), ρ₀ = I compressed at ρ̇₀: collapses at t* ≈ 0.985",
        system: m,
        y0,
        t_end: 2.0,
        observable: affine_observable,
        momentum: affine_p_phi,
    }
}

/// The collapse time of [`s2_affine_collapse`]: the smallest positive root
/// `t*` of `det(I + tρ̇₀) = 1 + t tr ρ̇₀ + t² det ρ̇₀` (≈ 0.985).
pub fn s2_collapse_time() -> f64 {
    let rd = S2_COLLAPSE_RATE;
    let (tr, dt) = (rd.trace(), rd.determinant());
    let disc = (tr * tr - 4.0 * dt).sqrt();
    [(-tr + disc) / (2.0 * dt), (-tr - disc) / (2.0 * dt)].into_iter().filter(|t| *t > 0.0).fold(f64::INFINITY, f64::min)
}

// ---------------------------------------------------------------------------
// The tilted problems of the integrator tests
// ---------------------------------------------------------------------------

/// S² gyroscope in the [`Axial`] tilt with frame coupling.
pub type S2TiltedGyro = Gyroscope2Model<Sphere2, Axial>;
/// S² point in the [`Axial`] tilt.
pub type S2TiltedPoint = PointModel<Sphere2, Axial, 2, 3>;
/// S² affine body in the elastic potential plus the [`Axial`] tilt with
/// frame coupling.
pub type S2TiltedAffine = AffineModel<Sphere2, Sum<Elastic, Axial>, 2, 3>;

/// The span of the tilted problems: that of the RKMK order measurements.
pub const TILTED_T_END: f64 = 4.0;

/// A gyroscope (m = 1, I = 0.3) on the unit S² in general position in
/// `V = a·z + b·e₁ᶻ` ([`Axial`] about z), from the chart point
/// `(r, φ) = (0.9, 0.3)` with chart velocity `(0.5, 0.7)`, internal angle
/// 0.4 and spin 0.6. Momentum map `p_φ`.
///
/// Errors: [`crate::Error::NotFinite`] for a non-finite `a` or `b`.
pub fn s2_tilted_gyro_with(a: f64, b: f64) -> Result<Reference<S2TiltedGyro>> {
    finite("a, b", [a, b].iter())?;
    let s2 = Sphere2::new(1.0)?;
    let m = Gyroscope2Model::new(s2, Gyroscope::<2>::isotropic(1.0, 0.3)?, Axial { a, b, radius: 1.0, axis: 2 })?;
    let x = Vector2::new(0.9, 0.3);
    let (p, v) = (s2.embed(&x), s2.embed_tangent(&x, &Vector2::new(0.5, 0.7)));
    let y0 = m.state_at(&p, &v, 0.4, 0.6)?;
    Ok(Reference {
        name: "s2_tilted_gyro",
        about: "S² gyroscope, I = 0.3, V = a z + b e₁ᶻ, chart start (0.9, 0.3), rates (0.5, 0.7), spin 0.6",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: gyroscope2_observable,
        momentum: gyroscope2_p_phi,
    })
}

/// [`s2_tilted_gyro_with`] with a = 0.8, b = 0.4.
pub fn s2_tilted_gyro() -> Reference<S2TiltedGyro> {
    s2_tilted_gyro_with(0.8, 0.4).expect(VALID)
}

/// A point (m = 1) on the unit S² in `V = a·z` ([`Axial`] without frame
/// coupling), from the chart point `(0.9, 0.3)` with chart velocity
/// `(0.5, 0.7)` (the start of [`s2_tilted_gyro_with`]). Momentum map `p_φ`.
///
/// Errors: [`crate::Error::NotFinite`] for a non-finite `a`.
pub fn s2_tilted_point_with(a: f64) -> Result<Reference<S2TiltedPoint>> {
    finite("a", [a].iter())?;
    let s2 = Sphere2::new(1.0)?;
    let m = PointModel::new(s2, Point::new(1.0)?, Axial { a, b: 0.0, radius: 1.0, axis: 2 })?;
    let x = Vector2::new(0.9, 0.3);
    let (p, v) = (s2.embed(&x), s2.embed_tangent(&x, &Vector2::new(0.5, 0.7)));
    let y0 = m.state(&p, &v)?;
    Ok(Reference {
        name: "s2_tilted_point",
        about: "S² point, V = a z, chart start (0.9, 0.3), rates (0.5, 0.7)",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: point_observable,
        momentum: point_p_phi,
    })
}

/// [`s2_tilted_point_with`] with a = 0.8.
pub fn s2_tilted_point() -> Reference<S2TiltedPoint> {
    s2_tilted_point_with(0.8).expect(VALID)
}

/// An affinely-rigid body (m = 1, J = [`AFFINE_INERTIA`]) on the unit S² in
/// the elastic potential (a131) with κ = 0.8 plus `0.4·z + 0.3·e₁ᶻ`
/// ([`Axial`]), at the chart point `(0.8, 0.2)` with the internal state
/// [`AFFINE_RHO0`], [`AFFINE_U0`], [`AFFINE_RHO_DOT0`]. Momentum map `p_φ`.
pub fn s2_tilted_affine() -> Reference<S2TiltedAffine> {
    let s2 = Sphere2::new(1.0).expect(VALID);
    let pot = Sum::new(Elastic::new(0.8).expect(VALID), Axial { a: 0.4, b: 0.3, radius: 1.0, axis: 2 });
    let m = AffineModel::new(s2, Affine::new(1.0, AFFINE_INERTIA).expect(VALID), pot).expect(VALID);
    let g = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2))).expect(VALID);
    let y0 = m.state(&g, &AFFINE_RHO0, &AFFINE_U0, &AFFINE_RHO_DOT0).expect(VALID);
    Reference {
        name: "s2_tilted_affine",
        about: "S² affine body, elastic κ = 0.8 (a131) + 0.4 z + 0.3 e₁ᶻ",
        system: m,
        y0,
        t_end: TILTED_T_END,
        observable: affine_observable,
        momentum: affine_p_phi,
    }
}
