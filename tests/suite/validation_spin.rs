//! Claim (a59): the spin–curvature force `½ S^k_l R^l_k{}^a{}_j V^j` does no
//! work, bends the path, and vanishes for zero spin or zero curvature. In the
//! parallel frame it is `K s ε u` (SPEC §7), so a free gyroscope's velocity
//! turns at the constant rate `c = K s/m` relative to a parallel frame and its
//! path is a curve of constant geodesic curvature `c/|u|`; in closed form
//! `Q(t) = Q₀ exp(t(h(u₀) + cG))·exp(−tcG)` (SPEC §7).

use std::f64::consts::PI;

use framedyn::body::{Gyroscope, Point};
use framedyn::bundle::FrameBundle;
use framedyn::dynamics::gyroscope2::{Gyroscope2Model, Gyroscope2State};
use framedyn::dynamics::{PointModel, System};
use framedyn::lie::{LieGroup, ProductAlgebra};
use framedyn::method::GroupNumerics;
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2};
use framedyn::potential::Free;
use framedyn::solve::Save;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

use super::{loglog_slope, run};

const M: f64 = 1.3;
const I: f64 = 0.4;

/// A free gyroscope on `b` at the chart point `(0.7, 0.2)` with chart
/// velocity `(0.4, 0.9)` (S²: `(ṙ, φ̇)`), internal angle 0.1 and spin `s`.
fn gyro<B: FrameBundle<2, 3> + Clone>(b: B, s: f64) -> (Gyroscope2Model<B, Free>, Gyroscope2State<B::Group>) {
    let model = Gyroscope2Model::new(b.clone(), Gyroscope::<2>::isotropic(M, I).unwrap(), Free).unwrap();
    let x = Vector2::new(0.7, 0.2);
    let (p, v) = (b.embed(&x), b.embed_tangent(&x, &Vector2::new(0.4, 0.9)));
    let y0 = model.state_at(&p, &v, 0.1, s).unwrap();
    (model, y0)
}

/// The gyroscope with its spin–curvature force `K s ε u` replaced by the
/// same force rotated by the angle `delta`, `K s Rot(δ) ε u` — a force of the
/// same magnitude that is no longer perpendicular to `u`. Its power is
/// `−K s sin δ |u|²`, so `|u|² = |u₀|² exp(−2K s sin δ t/m)`.
#[derive(Clone)]
struct TiltedForce<B: FrameBundle<2, 3>> {
    inner: Gyroscope2Model<B, Free>,
    delta: f64,
}

impl<B: FrameBundle<2, 3> + Clone> System for TiltedForce<B>
where
    B::Group: GroupNumerics,
{
    type State = Gyroscope2State<B::Group>;
    fn vector_field(&self, t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        let ProductAlgebra(a, mut w) = self.inner.vector_field(t, y);
        let u = self.inner.velocity_components(y);
        let eps_u = Vector2::new(-u[1], u[0]);
        let k = self.inner.bundle().curvature_at(&y.0 .0);
        let extra = (eps_u * (self.delta.cos() - 1.0) - u * self.delta.sin()) * (k * self.inner.spin(y) / M);
        w[0] += extra[0];
        w[1] += extra[1];
        ProductAlgebra(a, w)
    }
    fn energy(&self, y: &Self::State) -> f64 {
        self.inner.energy(y)
    }
    fn defect(&self, y: &Self::State) -> f64 {
        self.inner.defect(y)
    }
}

/// Worst relative change of `(m/2)|u|²` along a saved trajectory.
fn kinetic_drift<B: FrameBundle<2, 3> + Clone>(model: &Gyroscope2Model<B, Free>, states: &[Gyroscope2State<B::Group>]) -> f64 {
    let k0 = model.translational_energy(&states[0]);
    states.iter().map(|y| (model.translational_energy(y) / k0 - 1.0).abs()).fold(0.0, f64::max)
}

fn no_work_on<B: FrameBundle<2, 3> + Clone>(name: &str, b: B) -> (f64, f64)
where
    B::Group: GroupNumerics,
{
    let mut worst = (0.0f64, 0.0f64);
    for s in [0.3, -0.5] {
        let (model, y0) = gyro(b.clone(), s);
        let k = model.bundle().curvature_at(&y0.0 .0);
        let sol = run(&model, y0, 10.0, 1e-12, |o| o);
        let drift = kinetic_drift(&model, sol.states());
        let power = sol
            .states()
            .iter()
            .map(|y| model.geometric_power(y).abs() / (model.geometric_force(y).norm() * model.velocity_components(y).norm()))
            .fold(0.0, f64::max);
        // The tilted force does work, exactly as its power predicts.
        let delta = 0.1;
        let tilted = TiltedForce { inner: model.clone(), delta };
        let t_end = 10.0;
        let sol_t = run(&tilted, y0, t_end, 1e-12, |o| o.save(Save::Ends));
        let ratio = model.translational_energy(sol_t.last().1) / model.translational_energy(&y0);
        let predicted = (-2.0 * k * s * delta.sin() * t_end / M).exp();
        eprintln!(
            "(a59) no work, {name}, s = {s}: |Δ(m|u|²/2)|/(m|u|²/2) = {drift:.1e}, max |u·F|/(|u||F|) = {power:.1e}; \
             force tilted by 0.1 rad: kinetic energy × {ratio:.6} (predicted {predicted:.6})"
        );
        assert!(drift <= 1e-10, "{name}: the spin–curvature force did work: {drift:e}");
        assert!(power <= 1e-15);
        assert!((ratio - 1.0).abs() >= 0.05, "{name}: the tilted force should do work");
        assert!((ratio / predicted - 1.0).abs() <= 1e-9, "{name}: tilted-force work {ratio} vs {predicted}");
        worst = (worst.0.max(drift), worst.1.max(power));
    }
    worst
}

/// (a59) does no work: along free gyroscope trajectories on S² and H²
/// (m = 1.3, I = 0.4, s = 0.3 and −0.5, t ∈ [0, 10], DOPRI5 tol 1e-12) the
/// translational kinetic energy `(m/2)|u|²` is constant (measured relative
/// change ≤ 8.4e-13; bound 1e-10) and `u·F_geom = 0` to round-off. Contrary
/// case: the same force rotated by 0.1 rad does work and changes the kinetic
/// energy by the factor `exp(−2K s sin δ t/m)` it predicts (0.53–1.89 here,
/// agreement to 7 printed digits; asserted 1e-9).
#[test]
fn a59_spin_curvature_force_does_no_work() {
    no_work_on("S2", Sphere2::new(1.1).unwrap());
    no_work_on("H2", Hyperbolic2::new(1.1).unwrap());
}

/// Closed-form position of the free gyroscope on S² (SPEC §7): with
/// `Q = [n | q₁ | q₂]`, `x(t) = R·Q₀ exp(t(h(u₀) + cG)) ê₀`, `c = K s/m`.
fn s2_closed_form(model: &Gyroscope2Model<Sphere2, Free>, y0: &Gyroscope2State<framedyn::lie::So3>, c: f64, t: f64) -> Vector3<f64> {
    let r = model.bundle().radius();
    let u = model.velocity_components(y0);
    let h = Matrix3::new(0.0, -u[0], -u[1], u[0], 0.0, 0.0, u[1], 0.0, 0.0) / r;
    let g = Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
    let q0 = *y0.0 .0.matrix();
    (q0 * ((h + g * c) * t).exp()).column(0) * r
}

/// The same on H² with `Λ = [q₁ | q₂ | n]`: `x(t) = R·Λ₀ exp(t(h(u₀) + cG)) ê₂`.
fn h2_closed_form(model: &Gyroscope2Model<Hyperbolic2, Free>, y0: &Gyroscope2State<framedyn::lie::So12>, c: f64, t: f64) -> Vector3<f64> {
    let r = model.bundle().radius();
    let u = model.velocity_components(y0);
    let h = Matrix3::new(0.0, 0.0, u[0], 0.0, 0.0, u[1], u[0], u[1], 0.0) / r;
    let g = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let l0 = *y0.0 .0.matrix();
    (l0 * ((h + g * c) * t).exp()).column(2) * r
}

fn rot(a: f64) -> Matrix2<f64> {
    Matrix2::new(a.cos(), -a.sin(), a.sin(), a.cos())
}

/// (a59) bends the path: for a free gyroscope with spin `s` the velocity
/// turns relative to a parallel frame at the rate `c = K s/m`, `u(t) =
/// Rot(ct)u₀` (S²: to the left for `s > 0`, H²: to the right; measured
/// ≤ 3e-13 over t ∈ [0, 10], bound 1e-9), and the position follows the closed
/// form `R Q₀ exp(t(h(u₀) + cG)) ê₀` (measured ≤ 1.5e-12 on S², 2.7e-12 relative on
/// H²; bound 1e-9) — with the force's sign flipped (`c → −c`) the closed form is
/// off by O(1) (0.35–1.33; asserted > 0.1). The gyroscope leaves the geodesic from the same
/// initial data: at t = 10 its distance from it is 0.28 (s = 0.3) and 0.70
/// (s = −0.5), asserted ≥ 0.1, and doubling a small spin doubles the early
/// deviation (ratio 2.0000 measured at t = 1; asserted 2 ± 0.02).
#[test]
fn a59_spin_curvature_force_bends_the_path() {
    let times: Vec<f64> = (0..=20).map(|k| 0.5 * k as f64).collect();
    for s in [0.3, -0.5] {
        // S².
        let (model, y0) = gyro(Sphere2::new(1.1).unwrap(), s);
        let c = model.bundle().curvature() * s / M;
        let sol = run(&model, y0, 10.0, 1e-12, |o| o.save(Save::At(times.clone())));
        let u0 = model.velocity_components(&y0);
        let (mut du, mut dx, mut dflip) = (0.0f64, 0.0f64, 0.0f64);
        for (t, y) in sol.times().iter().zip(sol.states()) {
            du = du.max((model.velocity_components(y) - rot(c * t) * u0).amax());
            dx = dx.max((model.position(y) - s2_closed_form(&model, &y0, c, *t)).amax());
            dflip = dflip.max((model.position(y) - s2_closed_form(&model, &y0, -c, *t)).amax());
        }
        let (geo, g0) = gyro(Sphere2::new(1.1).unwrap(), 0.0);
        let dev = (model.position(sol.last().1) - geo.position(&super::run_fixed(&geo, g0, 10.0, 2000))).norm();
        eprintln!("(a59) bends the path, S2, s = {s}: |u − Rot(ct)u0| ≤ {du:.1e}, |x − closed form| ≤ {dx:.1e}, flipped sign {dflip:.2}, distance from the geodesic at t = 10: {dev:.3}");
        assert!(du <= 1e-9 && dx <= 1e-9);
        assert!(dflip >= 0.1 && dev >= 0.1);
        // H².
        let (model, y0) = gyro(Hyperbolic2::new(1.1).unwrap(), s);
        let c = model.bundle().curvature() * s / M;
        assert!(c * s < 0.0);
        let sol = run(&model, y0, 10.0, 1e-12, |o| o.save(Save::At(times.clone())));
        let u0 = model.velocity_components(&y0);
        let (mut du, mut dx, mut dflip) = (0.0f64, 0.0f64, 0.0f64);
        for (t, y) in sol.times().iter().zip(sol.states()) {
            let scale = model.position(y).amax();
            du = du.max((model.velocity_components(y) - rot(c * t) * u0).amax());
            dx = dx.max((model.position(y) - h2_closed_form(&model, &y0, c, *t)).amax() / scale);
            dflip = dflip.max((model.position(y) - h2_closed_form(&model, &y0, -c, *t)).amax() / scale);
        }
        eprintln!("(a59) bends the path, H2, s = {s}: |u − Rot(ct)u0| ≤ {du:.1e}, |x − closed form|/|x| ≤ {dx:.1e}, flipped sign {dflip:.2}");
        assert!(du <= 1e-9 && dx <= 1e-9);
        assert!(dflip >= 0.1);
    }
    // Linear response: the early deviation from the geodesic is ∝ s.
    let dev_at = |s: f64| {
        let (model, y0) = gyro(Sphere2::new(1.1).unwrap(), s);
        let (geo, g0) = gyro(Sphere2::new(1.1).unwrap(), 0.0);
        (model.position(&super::run_fixed(&model, y0, 1.0, 200)) - geo.position(&super::run_fixed(&geo, g0, 1.0, 200))).norm()
    };
    let (d1, d2) = (dev_at(1e-3), dev_at(2e-3));
    eprintln!("(a59) deviation from the geodesic at t = 1: s = 1e-3: {d1:.3e}, s = 2e-3: {d2:.3e}, ratio {:.4}", d2 / d1);
    assert!((d2 / d1 - 2.0).abs() <= 0.02);
}

/// (a59) vanishes for zero spin or zero curvature. Zero spin: the
/// gyroscope's position coincides with the structureless point's geodesic
/// from the same initial data (S², H², t ∈ [0, 10]; measured ≤ 2.2e-15 — the
/// two models then integrate identical equations — bound 1e-12) and with the
/// great circle `x₀ cos(|v|t/R) + R v̂ sin(|v|t/R)` on S² (measured 2.6e-15,
/// bound 1e-9). Zero curvature: on S²(R) at fixed spin s = 0.2, |u| = 1, the
/// distance from the geodesic at t = 2 falls like `K = 1/R²` as R = 4 … 32
/// (least-squares slope −1.99 measured; asserted −2 ± 0.05) — the force
/// is linear in the curvature and vanishes with it.
#[test]
fn a59_spin_curvature_force_vanishes_for_zero_spin_or_curvature() {
    let times: Vec<f64> = (0..=10).map(|k| k as f64).collect();
    fn point_path<B: FrameBundle<2, 3> + Clone>(b: B, times: &[f64]) -> Vec<Vector3<f64>>
    where
        B::Group: GroupNumerics,
    {
        let model = PointModel::new(b.clone(), Point::new(M).unwrap(), Free).unwrap();
        let x = Vector2::new(0.7, 0.2);
        let y0 = model.state(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(0.4, 0.9))).unwrap();
        let sol = run(&model, y0, 10.0, 1e-12, |o| o.save(Save::At(times.to_vec())));
        sol.states().iter().map(|y| model.position(y)).collect()
    }
    fn gyro_path<B: FrameBundle<2, 3> + Clone>(b: B, times: &[f64]) -> Vec<Vector3<f64>>
    where
        B::Group: GroupNumerics,
    {
        let (model, y0) = gyro(b, 0.0);
        let sol = run(&model, y0, 10.0, 1e-12, |o| o.save(Save::At(times.to_vec())));
        sol.states().iter().map(|y| model.position(y)).collect()
    }
    let s2 = Sphere2::new(1.1).unwrap();
    let (a, b) = (point_path(s2, &times), gyro_path(s2, &times));
    let d_s2 = a.iter().zip(&b).map(|(p, q)| (p - q).amax()).fold(0.0, f64::max);
    let x = Vector2::new(0.7, 0.2);
    let (x0, v0) = (s2.embed(&x), s2.embed_tangent(&x, &Vector2::new(0.4, 0.9)));
    let w = v0.norm() / 1.1;
    let great = times.iter().zip(&b).map(|(t, p)| (p - (x0 * (w * t).cos() + v0 / w * (w * t).sin())).amax()).fold(0.0, f64::max);
    let h2 = Hyperbolic2::new(1.1).unwrap();
    let (a, b) = (point_path(h2, &times), gyro_path(h2, &times));
    let d_h2 = a.iter().zip(&b).map(|(p, q)| (p - q).amax() / p.amax()).fold(0.0, f64::max);
    eprintln!("(a59) s = 0: gyroscope vs point geodesic: S2 {d_s2:.1e}, H2 {d_h2:.1e}; vs great circle {great:.1e}");
    assert!(d_s2 <= 1e-12 && d_h2 <= 1e-12 && great <= 1e-9);

    let radii = [4.0, 8.0, 16.0, 32.0];
    let devs: Vec<f64> = radii
        .iter()
        .map(|&r| {
            let b = Sphere2::new(r).unwrap();
            let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(M, I).unwrap(), Free).unwrap();
            let geo = PointModel::new(b, Point::new(M).unwrap(), Free).unwrap();
            let x = Vector2::new(0.5 * r, 0.2);
            let (p, v) = (b.embed(&x), b.embed_tangent(&x, &Vector2::new(0.6, 0.8 / (r * (0.5f64).sin()))));
            let y0 = model.state_at(&p, &v, 0.0, 0.2).unwrap();
            let g0 = geo.state(&p, &v).unwrap();
            let a = model.position(&super::run_fixed(&model, y0, 2.0, 400));
            let b = geo.position(&super::run_fixed(&geo, g0, 2.0, 400));
            (a - b).norm()
        })
        .collect();
    let slope = loglog_slope(&radii, &devs);
    eprintln!("(a59) K → 0: distance from the geodesic at t = 2 for R = {radii:?}: {devs:.4?}, slope {slope:.4} (K ∝ R^-2)");
    assert!((slope + 2.0).abs() <= 0.05);
    let _ = PI;
}
