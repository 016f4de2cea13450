//! The gauge directions of the frame-bundle models (`System::gauge`): the
//! rotations of the parallel frame in place, with the components stored in
//! it turned back, which change the stored state and not the physical one.
//! Checked against what they must be: the kernel of the derivative of the
//! ambient observables (position, velocity, body frame and its rate or the
//! spin), whole and nothing more, on every model family; the phase space
//! they leave has twice the body's degrees of freedom on every example
//! scene; and a step's tangent map takes them to the gauge directions at
//! the new state (equivariance: the quotient of GALI is well defined).

use framedyn::analysis::{flow_derivative, Linearisation};
use framedyn::bundle::FrameBundle;
use framedyn::dynamics::affine::{AffineBodyModel, BodyState, InternalConstraint};
use framedyn::dynamics::{Gyroscope3Model, System};
use framedyn::lie::LieGroup;
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::potential::Potential;
use framedyn::solve::{solve, Options};
use framedyn::testing::{self, Reference};
use nalgebra::{DMatrix, DVector};

/// The gauge directions at `y` as columns of algebra coordinates.
fn gauge_columns<S: System>(sys: &S, y: &S::State) -> DMatrix<f64> {
    let g = sys.gauge(y);
    DMatrix::from_fn(S::State::DOF, g.len(), |i, j| S::State::algebra_coords(&g[j])[i])
}

/// The derivative of `obs` at `y` along `y·exp(τξ)`, for every basis
/// direction `ξ` of the algebra (central differences, τ = 1e-5): one column
/// per direction.
fn observable_jacobian<S: System>(y: &S::State, obs: &dyn Fn(&S::State) -> Vec<f64>) -> DMatrix<f64> {
    let dof = S::State::DOF;
    let rows = obs(y).len();
    let tau = 1e-5;
    let mut jac = DMatrix::zeros(rows, dof);
    for j in 0..dof {
        let at = |s: f64| {
            let mut c = vec![0.0; dof];
            c[j] = s;
            DVector::from_vec(obs(&y.compose(&S::State::exp(&S::State::algebra_from_coords(&c)))))
        };
        jac.set_column(j, &((at(tau) - at(-tau)) / (2.0 * tau)));
    }
    jac
}

/// The gauge directions of `sys` at `y` number `expected`, are independent,
/// and span the kernel of the observables' derivative: `J·G ≈ 0` and the
/// rank of `J` is `DOF − expected` (its singular values: `expected` of them
/// at the differencing error, the rest far above it).
fn check_kernel<S: System>(name: &str, sys: &S, y: &S::State, obs: &dyn Fn(&S::State) -> Vec<f64>, expected: usize) {
    let g = gauge_columns(sys, y);
    assert_eq!(g.ncols(), expected, "{name}: number of gauge directions");
    let jac = observable_jacobian::<S>(y, obs);
    let scale = jac.amax();
    let along = if expected > 0 { (&jac * &g).amax() / (scale * g.amax()) } else { 0.0 };
    let mut sv: Vec<f64> = jac.clone().svd(false, false).singular_values.iter().map(|s| s / scale).collect();
    sv.sort_by(|a, b| a.partial_cmp(b).unwrap());
    sv.resize(S::State::DOF, 0.0);
    let null = &sv[..expected];
    let rest = sv[expected];
    println!("{name}: {expected} of {} directions; |J·G| = {along:.1e}, largest kernel singular value {:.1e}, smallest other {rest:.1e}", S::State::DOF, null.iter().fold(0.0f64, |a, b| a.max(*b)));
    assert!(along < 1e-8, "{name}: the observables change along a gauge direction ({along:e})");
    if expected > 0 {
        let gram = (g.transpose() * &g).determinant();
        assert!(gram > 1e-6, "{name}: dependent gauge directions (Gram determinant {gram:e})");
        assert!(null.iter().all(|s| *s < 1e-8), "{name}: kernel singular values {null:?}");
    }
    assert!(rest > 1e-4, "{name}: the observables miss a direction besides the gauge ({rest:e}): more kernel than gauge");
}

/// The state of a reference problem a little way along its trajectory (so
/// that frames, internal configuration and momenta are generic).
fn later<S: System + Clone>(r: &Reference<S>) -> S::State
where
    S::State: GroupNumerics,
{
    let mut short = r.clone();
    short.t_end = 0.7;
    *solve(&short.problem().unwrap(), &Rkmk::rk4(), &Options::fixed(0.01)).unwrap().last().1
}

fn check_reference<S: System + Clone>(r: Reference<S>, obs: &dyn Fn(&S, &S::State) -> Vec<f64>, expected: usize)
where
    S::State: GroupNumerics,
{
    for (when, y) in [("t = 0", r.y0), ("t = 0.7", later(&r))] {
        check_kernel(&format!("{} at {when}", r.name), &r.system, &y, &|y| obs(&r.system, y), expected);
    }
}

/// Position, velocity, body frame and the frame's rate `ė` of an affine
/// body: all ambient, so unchanged by a turn of the parallel frame (the
/// reference read-out carries `ρ̇`, which has parallel-frame components).
fn affine_ambient<B, V, C, const N: usize, const E: usize>(m: &AffineBodyModel<B, V, C, N, E>, y: &BodyState<B, C, N, E>) -> Vec<f64>
where
    B: FrameBundle<N, E>,
    V: Potential<N, E>,
    C: InternalConstraint<N>,
{
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.extend(m.frame_rate(y).iter());
    v
}

/// Position, velocity, body frame and the spin as an ambient vector of a
/// gyroscope on S³ (the reference read-out carries its parallel-frame
/// components).
fn gyroscope3_ambient<B: FrameBundle<3, 4>, P: Potential<3, 4>>(m: &Gyroscope3Model<B, P>, y: &<Gyroscope3Model<B, P> as System>::State) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.extend(m.spin_ambient(y).iter());
    v
}

/// Every model family on every manifold it has a reference problem on:
/// the point, the gyroscopes on surfaces and on S³, the affine bodies with
/// GL⁺(2), SL(2) and CO⁺(3) fibres; one direction on a surface, three on
/// S³.
#[test]
fn gauge_directions_are_the_kernel_of_the_observables() {
    check_reference(testing::s2_point(), &|m, y| testing::readouts::point_observable(m, y), 1);
    check_reference(testing::s2_tilted_point(), &|m, y| testing::readouts::point_observable(m, y), 1);
    check_reference(testing::s2_gyro(), &|m, y| testing::readouts::gyroscope2_observable(m, y), 1);
    check_reference(testing::h2_gyro(), &|m, y| testing::readouts::gyroscope2_observable(m, y), 1);
    check_reference(testing::t2_gyro(), &|m, y| testing::readouts::gyroscope2_observable(m, y), 1);
    check_reference(testing::s3_gyro(), &|m, y| gyroscope3_ambient(m, y), 3);
    check_reference(testing::s3_tilted_gyro(), &|m, y| gyroscope3_ambient(m, y), 3);
    check_reference(testing::s2_affine(), &|m, y| affine_ambient(m, y), 1);
    check_reference(testing::t2_affine(), &|m, y| affine_ambient(m, y), 1);
    check_reference(testing::h2_tilted_incompressible(), &|m, y| affine_ambient(m, y), 1);
    check_reference(testing::s3_tilted_weyl(), &|m, y| affine_ambient(m, y), 3);
}

/// The phase space the gauge directions leave has twice the body's degrees
/// of freedom (paper §4: a point `n`, a gyroscope `n + n(n−1)/2`, an affine
/// body `n + n²`, incompressible `n + n² − 1`, Weyl `n + 1 + n(n−1)/2`), on
/// every example scene. The pure dilatation (`n + 1` degrees of freedom)
/// has no gauge direction: its body frame is the parallel frame up to
/// scale, so the frame's orientation, carried by parallel transport without
/// a momentum of its own, is part of its state (`n(n−1)/2` more).
#[test]
fn every_example_scene_has_the_phase_space_of_its_body() {
    for (name, _) in framedyn::scenes::EXAMPLES {
        let scene = framedyn::scenes::example(name).unwrap();
        let n = if name.starts_with("s3") { 3 } else { 2 };
        let body = ["point", "gyroscope", "incompressible", "weyl", "dilatation", "affine"].into_iter().find(|b| name.contains(b)).unwrap();
        let freedom = n + match body {
            "point" => 0,
            "gyroscope" => n * (n - 1) / 2,
            "incompressible" => n * n - 1,
            "weyl" => 1 + n * (n - 1) / 2,
            "dilatation" => 1,
            _ => n * n,
        };
        let (state, phase) = (scene.state_dimension().unwrap(), scene.phase_space_dimension().unwrap());
        println!("{name}: state group {state}, phase space {phase}");
        let (orientation, gauge) = if body == "dilatation" { (n * (n - 1) / 2, 0) } else { (0, n * (n - 1) / 2) };
        assert_eq!(phase, 2 * freedom + orientation, "{name}");
        assert_eq!(state - phase, gauge, "{name}");
    }
}

/// A step's tangent map `D` (RKMK4 and DOP853, h = 0.05, the default
/// linearisation) takes the gauge directions at `y₀` into those at `y₁`:
/// their component outside is at the linearisation's error (measured
/// 1e-11 … 1e-9 of |D|; bound 1e-7).
#[test]
fn tangent_maps_take_gauge_directions_to_gauge_directions() {
    fn check<S: System + Clone>(r: Reference<S>)
    where
        S::State: GroupNumerics,
    {
        let y0 = later(&r);
        let lin = Linearisation::default();
        let steps = [
            ("RKMK4", flow_derivative(&r.system, &Rkmk::rk4(), 0.0, &y0, 0.05, 1, &lin).unwrap()),
            ("DOP853", flow_derivative(&r.system, &Rkmk::dop853(), 0.0, &y0, 0.05, 1, &lin).unwrap()),
        ];
        for (mname, (d, y1)) in steps {
            let (g0, g1) = (gauge_columns(&r.system, &y0), gauge_columns(&r.system, &y1));
            let q1 = g1.clone().qr().q();
            let image = &d * &g0;
            let outside = &image - &q1 * (q1.transpose() * &image);
            let rel = outside.amax() / d.amax();
            println!("{} ({mname}): gauge image outside the gauge directions {rel:.1e} of |D|", r.name);
            assert!(rel < 1e-7, "{} ({mname}): {rel:e}", r.name);
        }
    }
    check(testing::s2_tilted_point());
    check(testing::s2_gyro());
    check(testing::h2_gyro());
    check(testing::t2_gyro());
    check(testing::s3_tilted_gyro());
    check(testing::s2_affine());
    check(testing::h2_tilted_incompressible());
    check(testing::s3_tilted_weyl());
}
