//! Claims (b93)–(d94), (a142), (b142): the S² gyroscope is the symmetric top
//! with moments `(mR², mR², I)`, the H² gyroscope is the SO(1,2) top; for
//! `I = mR²` the S² metric is bi-invariant and the H² Lorentz-type metric
//! (a138) is (a multiple of) the Killing form. The equivalence of the
//! *motions* is tested in `dynamics_gyro::s2_gyroscope_is_the_symmetric_top`
//! and `dynamics_gyro::h2_gyroscope_is_the_lorentz_top` (trajectories of the
//! gyroscope against RKMK integrations of the tops' Euler–Poincaré
//! equations); here the kinetic energy is compared with the tops' metrics on
//! the Lie algebra at random states.

use framedyn::body::{Gyroscope, Signature};
use framedyn::bundle::FrameBundle;
use framedyn::dynamics::gyroscope2::{Gyroscope2Model, Gyroscope2State};
use framedyn::dynamics::System;
use framedyn::lie::So3;
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2};
use framedyn::potential::Free;
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};
use proptest::prelude::*;

/// `(Λ_e, Λ̇_e)` with `Λ_e = [e₁ | e₂ | x/R]`: the body frame and the unit
/// normal (S²) or unit timelike position (H²), and its exact time derivative
/// from the vector field (`q̇` from the horizontal lift, `ρ̇ = ρ α̇ ε`).
fn frame_and_rate<B: FrameBundle<2, 3> + Clone>(model: &Gyroscope2Model<B, Free>, y: &Gyroscope2State<B::Group>, radius: f64) -> (Matrix3<f64>, Matrix3<f64>) {
    let b = model.bundle();
    let g = &y.0 .0;
    let u = model.velocity_components(y);
    let (xdot, qdot) = b.frame_velocity(g, &b.horizontal_lift(g, &u));
    let rho = y.0 .1.matrix();
    let eps = Matrix2::new(0.0, -1.0, 1.0, 0.0);
    let rho_dot = rho * eps * model.angular_velocity(y);
    let q = b.frame_vectors(g);
    let e: Matrix3x2<f64> = q * rho;
    let edot: Matrix3x2<f64> = qdot * rho + q * rho_dot;
    let x = b.position(g);
    let lam = Matrix3::from_columns(&[e.column(0).into(), e.column(1).into(), x / radius]);
    let lam_dot = Matrix3::from_columns(&[edot.column(0).into(), edot.column(1).into(), xdot / radius]);
    (lam, lam_dot)
}

/// Killing form `B(X, X) = tr(ad_X ad_X)` on the 3-dimensional matrix Lie
/// algebra with the given basis (ad computed numerically in it).
fn killing(x: &Matrix3<f64>, basis: &[Matrix3<f64>; 3], coords: impl Fn(&Matrix3<f64>) -> Vector3<f64>) -> f64 {
    let ad = Matrix3::from_columns(&[0, 1, 2].map(|j| coords(&(x * basis[j] - basis[j] * x))));
    (ad * ad).trace()
}

fn so3_basis() -> [Matrix3<f64>; 3] {
    [0, 1, 2].map(|i| So3::hat(&Vector3::ith(i, 1.0)))
}

/// so(1,2) for `η = diag(1, 1, −1)`: boosts `K₁`, `K₂` and the rotation `L₃`.
fn so12_basis() -> [Matrix3<f64>; 3] {
    [
        Matrix3::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0),
        Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0),
        Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    ]
}
fn so12_coords(x: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(x[(0, 2)], x[(1, 2)], x[(1, 0)])
}

/// Relative defects at one state on S² with `I = moment`: the symmetric-top
/// form `(mR²/2)(Ω₁² + Ω₂²) + (I/2)Ω₃²` (`Ω = vee(Λᵀ Λ̇)`, body), the
/// Killing-form multiple `−(mR²/4) B(X, X)`, and the same left-invariant
/// form evaluated at the spatial velocity `Λ̇Λᵀ` (equal iff bi-invariant),
/// and the gap `(T_Killing − T)/T_int = mR²/I − 1` (the difference is
/// `(mR² − I)Ω₃²/2`) — exactly 2 for `I = mR²/3`.
fn s2_defects(m: f64, radius: f64, moment: f64, r: f64, phi: f64, v: [f64; 2], alpha: f64, spin: f64) -> (f64, f64, f64, f64) {
    let b = Sphere2::new(radius).unwrap();
    let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(m, moment).unwrap(), Free).unwrap();
    let x = Vector2::new(r * radius, phi);
    let y = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(v[0], v[1])), alpha, spin).unwrap();
    let t = model.energy(&y);
    let (lam, lam_dot) = frame_and_rate(&model, &y, radius);
    let mr2 = m * radius * radius;
    let top = |w: Vector3<f64>| 0.5 * mr2 * (w[0] * w[0] + w[1] * w[1]) + 0.5 * moment * w[2] * w[2];
    let body = lam.transpose() * lam_dot;
    let spatial = lam_dot * lam.transpose();
    let t_top = top(So3::vee(&body));
    let t_killing = -0.25 * mr2 * killing(&body, &so3_basis(), So3::vee);
    let t_spatial = top(So3::vee(&spatial));
    let gap = (t_killing - t) / model.internal_energy(&y);
    ((t_top / t - 1.0).abs(), (t_killing / t - 1.0).abs(), (t_spatial / t - 1.0).abs(), gap)
}

/// The same on H² with the signature `sig`: the SO(1,2)-top form
/// `(mR²/2)(Ω₁² + Ω₂²) + σ(I/2)Ω₃²` ((a142)/(b142), `Ω` the boost and
/// rotation components of `Λ⁻¹Λ̇`, `Λ⁻¹ = ηΛᵀη`) and the Killing multiple
/// `(mR²/4) B(X, X)`, relative to `|T_tr| + |T_int|`; and the gap
/// `(T − T_Killing)/|T_int|` (exactly 2 in both contrary cases tested).
fn h2_defects(m: f64, radius: f64, moment: f64, sig: Signature, r: f64, phi: f64, v: [f64; 2], alpha: f64, spin: f64) -> (f64, f64, f64) {
    let b = Hyperbolic2::new(radius).unwrap();
    let body = Gyroscope::<2>::isotropic(m, moment).unwrap().with_signature(sig);
    let model = Gyroscope2Model::new(b, body, Free).unwrap();
    let x = Vector2::new(r * radius, phi);
    let y = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(v[0], v[1])), alpha, spin).unwrap();
    let t = model.energy(&y);
    let scale = model.translational_energy(&y) + model.internal_energy(&y).abs();
    let (lam, lam_dot) = frame_and_rate(&model, &y, radius);
    let eta = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    let xb = eta * lam.transpose() * eta * lam_dot;
    let w = so12_coords(&xb);
    let sigma = if sig == Signature::Lorentz { -1.0 } else { 1.0 };
    let mr2 = m * radius * radius;
    let t_top = 0.5 * mr2 * (w[0] * w[0] + w[1] * w[1]) + sigma * 0.5 * moment * w[2] * w[2];
    let t_killing = 0.25 * mr2 * killing(&xb, &so12_basis(), so12_coords);
    let gap = (t - t_killing) / model.internal_energy(&y).abs();
    ((t_top - t).abs() / scale, (t_killing - t).abs() / scale, gap)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// (b93)–(d94): at random states of a free S² gyroscope its kinetic
    /// energy is the symmetric top's `(mR²/2)(Ω₁² + Ω₂²) + (I/2)Ω₃²` with
    /// `Ω = vee(Λ_eᵀΛ̇_e)`, `Λ_e = [e₁ | e₂ | x/R]` (relative 1e-12; measured
    /// ≤ 5.6e-16). For `I = mR²` it is `−(mR²/4)` times the Killing form
    /// `tr(ad_X²)` and takes the same value at the spatial velocity
    /// `Λ̇Λᵀ` — bi-invariant (relative 1e-12, measured ≤ 6.7e-16). Contrary
    /// case: for `I = mR²/3` the energy is not the Killing multiple: they
    /// differ by `(mR²/3)Ω₃² = 2T_int` (gap 2 asserted to 1e-9; relative to T
    /// the difference was 0.025–1.5 over the cases).
    #[test]
    fn b93_d94_s2_gyroscope_is_the_symmetric_top_bi_invariant_iff_i_eq_mr2(
        m in 0.5..2.0f64, radius in 0.5..2.0f64, r in 0.1..3.0f64, phi in -3.0..3.0f64,
        v0 in 0.2..1.0f64, v1 in 0.2..1.0f64, alpha in -3.0..3.0f64, w in 0.2..1.0f64,
    ) {
        let mr2 = m * radius * radius;
        let spin = w * mr2;
        let (top, kill, spatial, _) = s2_defects(m, radius, mr2, r, phi, [v0, v1], alpha, spin);
        prop_assert!(top <= 1e-12 && kill <= 1e-12 && spatial <= 1e-12, "I = mR²: {top:e} {kill:e} {spatial:e}");
        let (top, _, _, gap) = s2_defects(m, radius, mr2 / 3.0, r, phi, [v0, v1], alpha, spin / 3.0);
        prop_assert!(top <= 1e-12, "I = mR²/3: top form {top:e}");
        prop_assert!((gap - 2.0).abs() <= 1e-9, "I = mR²/3: gap {gap} instead of 2");
    }

    /// (a142), (b142): at random states of a free H² gyroscope the kinetic
    /// energy is the SO(1,2) top's `(mR²/2)(Ω₁² + Ω₂²) + σ(I/2)Ω₃²` for both
    /// the Riemannian (a135, σ = +1) and the Lorentz-type (a138, σ = −1)
    /// internal energy (relative to |T_tr| + |T_int|: 1e-11; measured
    /// ≤ 7.6e-15 up to r = 3R). For the Lorentz-type metric with `I = mR²` it
    /// is `(mR²/4)` times the Killing form of so(1,2), `tr(ad_X²) =
    /// 2(Ω₁² + Ω₂² − Ω₃²)` (relative 1e-11; measured ≤ 1.3e-14). Contrary
    /// cases: the Riemannian (a135) with `I = mR²`, and (a138) with
    /// `I = mR²/3`, are not Killing: `T − T_Killing = 2|T_int|` (asserted to
    /// 1e-9).
    #[test]
    fn a142_b142_h2_gyroscope_is_the_so12_top_lorentz_metric_is_killing(
        m in 0.5..2.0f64, radius in 0.5..2.0f64, r in 0.0..3.0f64, phi in -3.0..3.0f64,
        v0 in 0.2..1.0f64, v1 in 0.2..1.0f64, alpha in -3.0..3.0f64, w in 0.2..1.0f64,
    ) {
        let mr2 = m * radius * radius;
        let spin = w * mr2;
        let (top, kill, _) = h2_defects(m, radius, mr2, Signature::Lorentz, r, phi, [v0, v1], alpha, -spin);
        prop_assert!(top <= 1e-11 && kill <= 1e-11, "Lorentz, I = mR²: {top:e} {kill:e}");
        let (top, _, gap) = h2_defects(m, radius, mr2, Signature::Riemannian, r, phi, [v0, v1], alpha, spin);
        prop_assert!(top <= 1e-11 && (gap - 2.0).abs() <= 1e-9, "Riemannian, I = mR²: {top:e}, gap {gap}");
        let (top, _, gap) = h2_defects(m, radius, mr2 / 3.0, Signature::Lorentz, r, phi, [v0, v1], alpha, -spin / 3.0);
        prop_assert!(top <= 1e-11 && (gap - 2.0).abs() <= 1e-9, "Lorentz, I = mR²/3: {top:e}, gap {gap}");
    }
}
