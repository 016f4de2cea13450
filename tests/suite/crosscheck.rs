//! Cross-check of the two formulations (issue "Bodies, potentials and
//! invariants"): the frame-bundle models (`dynamics::{PointModel,
//! Gyroscope2Model, Gyroscope3Model}`) against the paper's coordinate
//! Lagrangians (`coords`), built from the same ambient data `(X, Ẋ, e, ė)` at
//! random chart states away from the poles.
//!
//! Instantaneous: `Ẍ = Σ u̇_a q_a + Σ u_a q̇_a` from the bundle vector field
//! (with `q̇` from `FrameBundle::frame_velocity`) against
//! `coords::ambient_acceleration` at the Euler–Lagrange `q̈`; the first-order
//! data `Ẋ`, `ė = q̇ρ + qρ̇` (which checks the spin ↔ angular-velocity map and
//! the signature); for n = 2 the spin rate `ṡ` against `∂L/∂ψ` (`s = p_ψ`).
//! Trajectories: RK4 on `(q, q̇)` and RKMK4 on the bundle state, ambient
//! position and body frame compared over t = 1.

use framedyn::body::{Gyroscope, Point, Signature};
use framedyn::bundle::FrameBundle;
use framedyn::coords::*;
use framedyn::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use framedyn::lie::So3;
use framedyn::manifold::{Hyperbolic2, Sphere2, Sphere3, Torus2};
use framedyn::potential::{Centre, CosineFamily, Free, Oscillator, Potential, Sum};
use framedyn::testing::Axial;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;

use crate::bundle_laws::rkmk4_step;

pub(crate) fn config(cases: u32) -> ProptestConfig {
    ProptestConfig { cases, failure_persistence: None, ..ProptestConfig::default() }
}

/// Largest entry of `a − b` relative to `max(1, |b|_max)`.
fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

const EPS2: Matrix2<f64> = Matrix2::new(0.0, -1.0, 1.0, 0.0);

/// Discrepancies of the point model against the coordinate Lagrangian at
/// `(q, q̇)`: `[Ẋ, Ẍ]`.
fn point_derivs<C, B, P>(chart: C, bundle: B, m: f64, pot: P, q: Vector2<f64>, v: Vector2<f64>) -> [f64; 2]
where
    C: ChartGeometry<2, 3>,
    B: FrameBundle<2, 3> + Copy,
    P: Potential<2, 3> + Clone,
{
    let point = Point::new(m).unwrap();
    let sys = PointLagrangian::new(chart, &point, pot.clone());
    let amb = ambient_state(&sys, &q, &v).unwrap();
    let model = PointModel::<B, P, 2, 3>::new(bundle, point, pot).unwrap();
    let y = model.state(&amb.position, &amb.velocity).unwrap();
    let f = model.vector_field(0.0, &y);
    let (xdot, qdot) = bundle.frame_velocity(&y.0, &f.0);
    let u = model.velocity_components(&y);
    let xdd = bundle.frame_vectors(&y.0) * f.1 + qdot * u;
    let acc = accelerations(&sys, &q, &v).unwrap();
    let aa = ambient_acceleration(&sys, &q, &v, &acc).unwrap();
    [rel(&xdot, &amb.velocity), rel(&xdd, &aa.acceleration)]
}

/// n = 2 gyroscope: `[Ẋ, ė, Ẍ, ṡ]`.
fn gyro2_derivs<C, B, P>(chart: C, bundle: B, body: Gyroscope<2>, pot: P, q: Vector3<f64>, v: Vector3<f64>) -> [f64; 4]
where
    C: ChartGeometry<2, 3>,
    B: FrameBundle<2, 3> + Copy,
    P: Potential<2, 3> + Clone,
{
    let sys = Gyroscope2::gyroscope(chart, PlaneRotation, &body, pot.clone());
    let amb = ambient_state(&sys, &q, &v).unwrap();
    let s = sys.comoving(&q, &v).unwrap().spin[(0, 1)];
    let model = Gyroscope2Model::new(bundle, body, pot).unwrap();
    let y = model.state(&amb.position, &amb.velocity, &amb.frame, s).unwrap();
    let f = model.vector_field(0.0, &y);
    let g = &y.0 .0;
    let (xdot, qdot) = bundle.frame_velocity(g, &f.0 .0);
    let qf = bundle.frame_vectors(g);
    // ρ = 1 at the start: ė = q̇ + q·(α̇ ε).
    let edot = qdot + qf * (EPS2 * f.0 .1[0]);
    let u = model.velocity_components(&y);
    let udot = Vector2::new(f.1[0], f.1[1]);
    let xdd = qf * udot + qdot * u;
    let acc = accelerations(&sys, &q, &v).unwrap();
    let aa = ambient_acceleration(&sys, &q, &v, &acc).unwrap();
    let sdot = lagrangian_derivatives(&sys, &q, &v).unwrap().force[2];
    [
        rel(&xdot, &amb.velocity),
        rel(&edot, &amb.frame_rate),
        rel(&xdd, &aa.acceleration),
        (f.1[2] - sdot).abs() / sdot.abs().max(1.0),
    ]
}

/// The S³ gyroscope: spin `π` in components of the body frame `e = Eφ`
/// (`S_e = φᵀ S_E φ`, `S = −[π]×`).
fn gyro3_spin(cm: &CoMoving<3>) -> Vector3<f64> {
    let se = cm.phi.transpose() * cm.spin * cm.phi;
    -So3::vee(&se)
}

/// S³ gyroscope: `[Ẋ, ė, Ẍ]`.
fn gyro3_derivs<P>(radius: f64, body: Gyroscope<3>, pot: P, q: SVector<f64, 6>, v: SVector<f64, 6>) -> [f64; 3]
where
    P: Potential<3, 4> + Clone,
{
    let sys = Gyroscope3::gyroscope(Sphere3Chart::new(radius).unwrap(), RotationVector, &body, pot.clone());
    let amb = ambient_state(&sys, &q, &v).unwrap();
    let pi = gyro3_spin(&sys.comoving(&q, &v).unwrap());
    let bundle = Sphere3::new(radius).unwrap();
    let model = Gyroscope3Model::new(bundle, body, pot).unwrap();
    let y = model.state(&amb.position, &amb.velocity, &amb.frame, &pi).unwrap();
    let f = model.vector_field(0.0, &y);
    let g = &y.0 .0;
    let (xdot, qdot) = bundle.frame_velocity(g, &f.0 .0);
    let qf = bundle.frame_vectors(g);
    let edot = qdot + qf * So3::hat(&f.0 .1);
    let u = model.velocity_components(&y);
    let udot = Vector3::new(f.1[0], f.1[1], f.1[2]);
    let xdd = qf * udot + qdot * u;
    let acc = accelerations(&sys, &q, &v).unwrap();
    let aa = ambient_acceleration(&sys, &q, &v, &acc).unwrap();
    [rel(&xdot, &amb.velocity), rel(&edot, &amb.frame_rate), rel(&xdd, &aa.acceleration)]
}

fn sig(lorentz: bool) -> Signature {
    if lorentz {
        Signature::Lorentz
    } else {
        Signature::Riemannian
    }
}

const TOL: f64 = 1e-12;

fn assert_all(what: &str, d: &[f64]) -> Result<(), TestCaseError> {
    prop_assert!(d.iter().all(|x| *x <= TOL), "{what}: {d:?}");
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn point_derivatives_agree(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, k in 0.1..2.0f64, b in -1.0..1.0f64,
        th in 0.3..2.8f64, phi in -3.0..3.0f64, v in proptest::collection::vec(-1.0..1.0f64, 2),
    ) {
        let vv = Vector2::new(v[0], v[1]);
        let s2 = Sphere2::new(radius).unwrap();
        let sc = SphereChart::new(radius).unwrap();
        let q = Vector2::new(th * radius, phi);
        assert_all("S2 free", &point_derivs(sc.clone(), s2, m, Free, q, vv))?;
        let osc = Oscillator::new(k, Centre::sphere2(&s2)).unwrap();
        assert_all("S2 oscillator", &point_derivs(sc.clone(), s2, m, osc, q, vv))?;
        let cos = CosineFamily::new(k, b, Centre::sphere2(&s2)).unwrap();
        assert_all("S2 cosine family", &point_derivs(sc, s2, m, cos, q, vv))?;
        let h2 = Hyperbolic2::new(radius).unwrap();
        let hc = HyperbolicChart::new(radius).unwrap();
        let qh = Vector2::new(th * radius * 0.7, phi);
        assert_all("H2 free", &point_derivs(hc.clone(), h2, m, Free, qh, vv))?;
        let osc = Oscillator::new(k, Centre::hyperbolic2(&h2)).unwrap();
        assert_all("H2 oscillator", &point_derivs(hc, h2, m, osc, qh, vv))?;
        let (bl, r) = (2.5 * radius, radius);
        let t2 = Torus2::new(bl, r).unwrap();
        let tc = TorusChart::new(bl, r).unwrap();
        let qt = Vector2::new(th * 2.0, phi);
        assert_all("T2 free", &point_derivs(tc.clone(), t2, m, Free, qt, vv))?;
        let ax = Axial { a: k, b: 0.0, radius: r, axis: 2 };
        assert_all("T2 axial", &point_derivs(tc, t2, m, ax, qt, vv))?;
    }

    #[test]
    fn gyroscope2_derivatives_agree(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, moment in 0.1..1.0f64, lorentz in proptest::bool::ANY,
        k in 0.1..2.0f64, b in -1.0..1.0f64,
        th in 0.3..2.8f64, phi in -3.0..3.0f64, psi in -3.0..3.0f64, v in proptest::collection::vec(-1.0..1.0f64, 3),
    ) {
        let body = Gyroscope::<2>::isotropic(m, moment).unwrap().with_signature(sig(lorentz));
        let vv = Vector3::new(v[0], v[1], v[2]);
        let s2 = Sphere2::new(radius).unwrap();
        let sc = SphereChart::new(radius).unwrap();
        let q = Vector3::new(th * radius, phi, psi);
        assert_all("S2 free", &gyro2_derivs(sc.clone(), s2, body, Free, q, vv))?;
        let osc = Oscillator::new(k, Centre::sphere2(&s2)).unwrap();
        assert_all("S2 oscillator", &gyro2_derivs(sc.clone(), s2, body, osc, q, vv))?;
        let ax = Sum::new(osc, Axial { a: 0.3, b, radius, axis: 0 });
        assert_all("S2 oscillator + frame", &gyro2_derivs(sc, s2, body, ax, q, vv))?;
        let h2 = Hyperbolic2::new(radius).unwrap();
        let hc = HyperbolicChart::new(radius).unwrap();
        let qh = Vector3::new(th * radius * 0.7, phi, psi);
        assert_all("H2 free", &gyro2_derivs(hc.clone(), h2, body, Free, qh, vv))?;
        let osc = Oscillator::new(k, Centre::hyperbolic2(&h2)).unwrap();
        let ax = Sum::new(osc, Axial { a: 0.0, b, radius, axis: 0 });
        assert_all("H2 oscillator + frame", &gyro2_derivs(hc, h2, body, ax, qh, vv))?;
        let (bl, r) = (2.5 * radius, radius);
        let t2 = Torus2::new(bl, r).unwrap();
        let tc = TorusChart::new(bl, r).unwrap();
        let qt = Vector3::new(th * 2.0, phi, psi);
        assert_all("T2 free", &gyro2_derivs(tc.clone(), t2, body, Free, qt, vv))?;
        let ax = Axial { a: k, b, radius: r, axis: 2 };
        assert_all("T2 axial + frame", &gyro2_derivs(tc, t2, body, ax, qt, vv))?;
    }

    #[test]
    fn gyroscope3_derivatives_agree(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, lorentz in proptest::bool::ANY,
        j in proptest::collection::vec(0.1..1.0f64, 3), off in proptest::collection::vec(-0.05..0.05f64, 3),
        k in 0.1..2.0f64, b in -1.0..1.0f64,
        x in proptest::collection::vec(-0.8..0.8f64, 6), v in proptest::collection::vec(-1.0..1.0f64, 6),
    ) {
        let jm = Matrix3::new(j[0], off[0], off[1], off[0], j[1], off[2], off[1], off[2], j[2]);
        let body = Gyroscope::<3>::new(m, jm).unwrap().with_signature(sig(lorentz));
        let mut q = SVector::<f64, 6>::from_column_slice(&x);
        for i in 0..3 { q[i] *= radius; }
        let vv = SVector::<f64, 6>::from_column_slice(&v);
        assert_all("S3 free", &gyro3_derivs(radius, body, Free, q, vv))?;
        let s3 = Sphere3::new(radius).unwrap();
        let pot = Sum::new(Oscillator::new(k, Centre::sphere3(&s3)).unwrap(), Axial { a: 0.2, b, radius, axis: 1 });
        assert_all("S3 oscillator + frame", &gyro3_derivs(radius, body, pot, q, vv))?;
    }
}

// ---------------------------------------------------------------------------
// Trajectories over t = 1
// ---------------------------------------------------------------------------

/// One classical RK4 step of the Euler–Lagrange equations (as in coords.rs);
/// `None` if a stage leaves the chart.
pub(crate) fn rk4_step<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q: &SVector<f64, Q>,
    v: &SVector<f64, Q>,
    h: f64,
) -> Option<(SVector<f64, Q>, SVector<f64, Q>)> {
    let acc = |q: &SVector<f64, Q>, v: &SVector<f64, Q>| accelerations(sys, q, v).ok();
    let a1 = acc(q, v)?;
    let (q2, v2) = (q + v * (h / 2.0), v + a1 * (h / 2.0));
    let a2 = acc(&q2, &v2)?;
    let (q3, v3) = (q + v2 * (h / 2.0), v + a2 * (h / 2.0));
    let a3 = acc(&q3, &v3)?;
    let (q4, v4) = (q + v3 * h, v + a3 * h);
    let a4 = acc(&q4, &v4)?;
    Some((q + (v + v2 * 2.0 + v3 * 2.0 + v4) * (h / 6.0), v + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0)))
}

/// Chart conditioning along a coordinate path: the smallest value of
/// `clear(q)` (e.g. `sin(r/R)` on S², `r/R` at the origin of H²), or `None`
/// if RK4 left the chart.
pub(crate) type Traj = Option<(f64, f64)>;

/// Worst difference (max over steps) of ambient position and body frame
/// between RK4 on `(q, q̇)` and RKMK4 on the bundle state built from the
/// same paper variables (`coords::state_from_paper`), `n` steps to t = 1,
/// with the chart clearance of the path ([`Traj`]).
pub(crate) fn trajectory_diff<L, M, const Q: usize, const N: usize, const E: usize>(
    sys: &L,
    model: &M,
    q0: SVector<f64, Q>,
    v0: SVector<f64, Q>,
    n: usize,
    clear: impl Fn(&SVector<f64, Q>) -> f64,
) -> Traj
where
    L: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let h = 1.0 / n as f64;
    let f = |t: f64, y: &M::State| model.vector_field(t, y);
    let mut y = state_from_paper(sys, model, &q0, &v0).ok()?;
    let (mut q, mut v) = (q0, v0);
    let mut worst: f64 = 0.0;
    let mut clearance = clear(&q);
    for i in 0..n {
        (q, v) = rk4_step(sys, &q, &v, h)?;
        clearance = clearance.min(clear(&q));
        y = rkmk4_step(&y, i as f64 * h, h, &f);
        let amb = ambient_state(sys, &q, &v).ok()?;
        let a = model.ambient(&y);
        worst = worst.max((a.position - amb.position).amax()).max((a.frame - amb.frame).amax());
    }
    Some((worst, clearance))
}

/// Case count of the trajectory proptests: `PROPTEST_CASES` (or the
/// test's default) but at most this many. Each case integrates several
/// manifold × potential × body combinations over t = 1 with RK4 on the
/// coordinate equations (automatic second derivatives at every stage) and
/// RKMK4, refined up to 8× — seconds per case in the debug build, unlike
/// the derivative checks at one state, which run the full count. At 256
/// cases these tests took most of the integration suite's CI time.
pub(crate) const TRAJECTORY_CASES: u32 = 32;

/// Runs `test` as `proptest!` does (the `PROPTEST_*` environment, e.g. the
/// seed, applies), on `default_cases` cases or `PROPTEST_CASES`, capped at
/// `cap`. Panics with proptest's report (minimal failing input) on failure.
pub(crate) fn run_capped<S>(name: &'static str, default_cases: u32, cap: u32, strategy: S, test: impl Fn(S::Value) -> Result<(), TestCaseError>)
where
    S: Strategy,
    S::Value: std::fmt::Debug,
{
    let mut cfg = proptest::test_runner::contextualize_config(config(default_cases));
    cfg.cases = cfg.cases.min(cap);
    cfg.test_name = Some(name);
    let mut runner = proptest::test_runner::TestRunner::new(cfg);
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{name}: {e}");
    }
}

const STEPS: usize = 400;
const TRAJ_TOL: f64 = 1e-10;
/// Paths whose chart clearance drops below this are not compared: near a
/// coordinate singularity the chart equations are stiff (the RK4 error on
/// `(q, q̇)` grows like `1/clearance³`; measured 1e-3 at 400 steps for a
/// path within 0.05 of the S² pole) — that failure of coordinates is the
/// subject of the pole tests, not of this cross-check.
const MIN_CLEARANCE: f64 = 0.25;

/// `diff(n)` at [`STEPS`], doubled (at most three times) while above
/// [`TRAJ_TOL`]: every doubling must shrink the difference ≥ 10× (RK4/RKMK4
/// truncation error, 16× per doubling), so a real discrepancy, which does
/// not shrink, fails; reaching the tolerance, or three doublings that each
/// shrink it ≥ 10× (the difference is truncation error tending to zero at
/// fourth order — fast orbits measured 1.3e-5, 8.5e-7, 5.3e-8, 3.3e-9),
/// passes. A path that leaves the chart or comes closer than
/// [`MIN_CLEARANCE`] to a chart singularity is rejected (proptest draws
/// another case).
fn refine(what: &str, diff: impl Fn(usize) -> Traj) -> Result<(), TestCaseError> {
    refine_with(what, STEPS, 3, MIN_CLEARANCE, diff)
}

/// [`refine`] with its parameters: `steps` at first, at most `doublings`
/// doublings, paths below `min_clearance` rejected.
pub(crate) fn refine_with(
    what: &str,
    steps: usize,
    doublings: u32,
    min_clearance: f64,
    diff: impl Fn(usize) -> Traj,
) -> Result<(), TestCaseError> {
    let Some((mut d, clearance)) = diff(steps) else {
        return Err(TestCaseError::reject(format!("{what}: the coordinate path left the chart")));
    };
    if clearance < min_clearance {
        return Err(TestCaseError::reject(format!("{what}: chart clearance {clearance:.3}")));
    }
    let mut n = steps;
    let mut seen = vec![format!("{d:e} at {n} steps")];
    while d > TRAJ_TOL && n < (steps << doublings) {
        n *= 2;
        let Some((d2, _)) = diff(n) else {
            return Err(TestCaseError::reject(format!("{what}: the coordinate path left the chart at {n} steps")));
        };
        seen.push(format!("{d2:e} at {n}"));
        prop_assert!(d / d2 >= 10.0, "{what}: no fourth-order convergence: {}", seen.join(", "));
        d = d2;
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn gyro2_traj<C, B, P>(chart: C, bundle: B, body: Gyroscope<2>, pot: P, q: Vector3<f64>, v: Vector3<f64>, n: usize, clear: impl Fn(&Vector3<f64>) -> f64) -> Traj
where
    C: ChartGeometry<2, 3>,
    B: FrameBundle<2, 3> + Copy,
    P: Potential<2, 3> + Clone,
{
    let sys = Gyroscope2::gyroscope(chart, PlaneRotation, &body, pot.clone());
    let model = Gyroscope2Model::new(bundle, body, pot).unwrap();
    trajectory_diff(&sys, &model, q, v, n, clear)
}

#[allow(clippy::too_many_arguments)]
fn point_traj<C, B, P>(chart: C, bundle: B, m: f64, pot: P, q: Vector2<f64>, v: Vector2<f64>, n: usize, clear: impl Fn(&Vector2<f64>) -> f64) -> Traj
where
    C: ChartGeometry<2, 3>,
    B: FrameBundle<2, 3> + Copy,
    P: Potential<2, 3> + Clone,
{
    let point = Point::new(m).unwrap();
    let sys = PointLagrangian::new(chart, &point, pot.clone());
    let model = PointModel::<B, P, 2, 3>::new(bundle, point, pot).unwrap();
    // The point has no body frame (both sides report zeros).
    trajectory_diff(&sys, &model, q, v, n, clear)
}

#[test]
fn point_and_gyroscope2_trajectories_agree() {
    let strategy = (
        (0.7..1.5f64, 0.7..1.5f64, 0.3..1.0f64, proptest::bool::ANY, 0.1..1.0f64, -0.5..0.5f64),
        (1.2..1.9f64, -3.0..3.0f64, -3.0..3.0f64, proptest::collection::vec(-0.5..0.5f64, 3)),
    );
    run_capped("point_and_gyroscope2_trajectories_agree", 6, TRAJECTORY_CASES, strategy, |((radius, m, moment, lorentz, k, b), (th, phi, psi, v))| {
        let body = Gyroscope::<2>::isotropic(m, moment).unwrap().with_signature(sig(lorentz));
        let vv = Vector3::new(v[0], v[1], v[2]);
        let s2 = Sphere2::new(radius).unwrap();
        let sc = SphereChart::new(radius).unwrap();
        // Centred on the equator (a pole-centred oscillator drives the orbit into
        // the chart singularity).
        let osc = Oscillator::new(k, Centre::sphere2_at(&s2, &Vector3::new(radius, 0.0, 0.0)).unwrap()).unwrap();
        // Clearance: sin(r/R) on S² (poles), r/R on H² (origin); T² has none.
        let s2_clear = |q: &Vector2<f64>| (q[0] / radius).sin();
        // |φ| ≤ 1 keeps the start inside the oscillator's well (tan² is singular
        // on the great circle x = 0, a quarter turn from the centre).
        refine("S2 point oscillator", |n| point_traj(sc.clone(), s2, m, osc, Vector2::new(th * radius, phi / 3.0), Vector2::new(v[0], v[1]), n, s2_clear))?;
        let pot = Sum::new(osc, Axial { a: 0.3, b, radius, axis: 0 });
        refine("S2 gyro oscillator + frame", |n| gyro2_traj(sc.clone(), s2, body, pot, Vector3::new(th * radius, phi / 3.0, psi), vv, n, |q| (q[0] / radius).sin()))?;
        let h2 = Hyperbolic2::new(radius).unwrap();
        let hc = HyperbolicChart::new(radius).unwrap();
        // No pole-centred oscillator here either: a tilt plus the frame term.
        let pot = Axial { a: k, b, radius, axis: 0 };
        refine("H2 gyro tilt + frame", |n| gyro2_traj(hc.clone(), h2, body, pot, Vector3::new(th * radius * 0.7, phi, psi), vv, n, |q| q[0] / radius))?;
        let (bl, r) = (2.5 * radius, radius);
        let t2 = Torus2::new(bl, r).unwrap();
        let tc = TorusChart::new(bl, r).unwrap();
        let pot = Axial { a: k, b, radius: r, axis: 2 };
        refine("T2 gyro axial + frame", |n| gyro2_traj(tc.clone(), t2, body, pot, Vector3::new(th * 2.0, phi, psi), vv, n, |_| 1.0))?;
        Ok(())
    });
}

#[test]
fn gyroscope3_trajectories_agree() {
    let strategy = (
        (0.8..1.5f64, 0.7..1.5f64, proptest::bool::ANY, proptest::collection::vec(0.3..1.0f64, 3), -0.5..0.5f64),
        (proptest::collection::vec(-0.5..0.5f64, 6), proptest::collection::vec(-0.5..0.5f64, 6)),
    );
    run_capped("gyroscope3_trajectories_agree", 6, TRAJECTORY_CASES, strategy, |((radius, m, lorentz, j, b), (x, v))| {
        let body = Gyroscope::<3>::new(m, Matrix3::from_diagonal(&Vector3::new(j[0], j[1], j[2]))).unwrap()
            .with_signature(sig(lorentz));
        let mut q = SVector::<f64, 6>::from_column_slice(&x);
        for i in 0..3 { q[i] *= radius; }
        let vv = SVector::<f64, 6>::from_column_slice(&v);
        let pot = Axial { a: 0.2, b, radius, axis: 1 };
        let sys = Gyroscope3::gyroscope(Sphere3Chart::new(radius).unwrap(), RotationVector, &body, pot);
        let model = Gyroscope3Model::new(Sphere3::new(radius).unwrap(), body, pot).unwrap();
        // Clearance from the antipode, where the rotation-vector chart is singular.
        let clear = |q: &SVector<f64, 6>| 1.0 - q.fixed_rows::<3>(0).norm() / (std::f64::consts::PI * radius);
        refine("S3 gyro axial + frame", |n| trajectory_diff(&sys, &model, q, vv, n, clear))
    });
}
