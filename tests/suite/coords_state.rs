//! States from and to the paper's variables (`framedyn::coords::state`):
//! for every manifold × body, paper coordinates and velocities → frame-bundle
//! state → paper coordinates and velocities (relative 1e-13, angles mod 2π),
//! the same with the momenta `p = ∂L/∂q̇` of (a52), embedding-space data →
//! state → embedding-space data, and the energy of the state against the
//! energy `E = q̇·∂L/∂q̇ − L` of the coordinate Lagrangian (a52) at the same
//! paper variables (relative 1e-12). For n = 2 the momenta conjugate to the
//! internal angles are the model's spin `p_ψ` (gyroscope) and `p_α`, `p_β`
//! (two-polar affine body, SPEC §7). Typed errors outside the charts and the
//! fibre parametrisations.

use framedyn::body::{Affine, Gyroscope, Incompressible, Point, Signature, Weyl};
use framedyn::coords::*;
use framedyn::dynamics::affine::AffineModel;
use framedyn::dynamics::constrained::{IncompressibleModel, WeylModel};
use framedyn::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel};
use framedyn::manifold::{Hyperbolic2, Sphere2, Sphere3, Torus2};
use framedyn::potential::{Centre, Elastic, Free, Oscillator, Sum};
use framedyn::testing::Axial;
use framedyn::Error;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig { cases, failure_persistence: None, ..ProptestConfig::default() }
}

const TOL: f64 = 1e-13;
const ENERGY_TOL: f64 = 1e-12;

/// `a − b`, reduced to `(−π, π]` if `angle`.
fn diff(a: f64, b: f64, angle: bool) -> f64 {
    let d = a - b;
    if angle {
        d - TAU * (d / TAU).round()
    } else {
        d
    }
}

/// Largest difference of `a` and `b` relative to `max(1, |b|_max)`, the
/// entries flagged in `angles` modulo 2π.
fn rel_mod<const Q: usize>(a: &SVector<f64, Q>, b: &SVector<f64, Q>, angles: &[usize]) -> f64 {
    let m = (0..Q).map(|i| diff(a[i], b[i], angles.contains(&i)).abs()).fold(0.0, f64::max);
    m / b.amax().max(1.0)
}

fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

/// The round trips at `(q, q̇)`: `[q, q̇, energy, q (momenta), p, ambient]`
/// discrepancies, and the state.
fn round_trip<S, M, const Q: usize, const N: usize, const E: usize>(
    sys: &S,
    model: &M,
    q: SVector<f64, Q>,
    qd: SVector<f64, Q>,
    angles: &[usize],
) -> ([f64; 6], M::State)
where
    S: AmbientMap<Q, N, E>,
    M: AmbientBody<N, E>,
{
    let y = state_from_paper(sys, model, &q, &qd).expect("state from the paper's variables");
    let back = paper_from_state(sys, model, &y).expect("paper's variables of the state");
    let e_paper = energy(sys, &q, &qd).unwrap();
    let d = lagrangian_derivatives(sys, &q, &qd).unwrap();
    // Scale: the kinetic and potential energies (E is their sum, T = L + V).
    let t = d.momentum.dot(&qd) - e_paper;
    let de = (model.energy(&y) - e_paper).abs() / (t.abs() + (e_paper - t).abs()).max(1.0);
    let p = momenta(sys, &q, &qd).unwrap();
    let y2 = state_from_paper_momenta(sys, model, &q, &p).expect("state from the paper's momenta");
    let (q2, p2) = paper_momenta_from_state(sys, model, &y2).expect("paper's momenta of the state");
    let a = model.ambient(&y);
    let a2 = model.ambient(&model.state_from_ambient(&a, None).expect("state from ambient data"));
    let da = rel(&a2.position, &a.position)
        .max(rel(&a2.velocity, &a.velocity))
        .max(rel(&a2.frame, &a.frame))
        .max(rel(&a2.frame_rate, &a.frame_rate));
    ([rel_mod(&back.q, &q, angles), rel(&back.qdot, &qd), de, rel_mod(&q2, &q, angles), rel(&p2, &p), da], y)
}

fn check(what: &str, d: &[f64; 6]) -> Result<(), TestCaseError> {
    prop_assert!(
        d[0] <= TOL && d[1] <= TOL && d[2] <= ENERGY_TOL && d[3] <= TOL && d[4] <= TOL && d[5] <= TOL,
        "{what}: [q, q̇, E, q(p), p, ambient] differ by {d:?}"
    );
    Ok(())
}

fn sig(lorentz: bool) -> Signature {
    if lorentz {
        Signature::Lorentz
    } else {
        Signature::Riemannian
    }
}

proptest! {
    #![proptest_config(config(64))]

    /// Points and gyroscopes on S², H², T²: `(r, φ, ψ, ṙ, φ̇, ψ̇)` and
    /// `(θ, φ, ψ, θ̇, φ̇, ψ̇)`; the spin of the state is `p_ψ = ∂L/∂ψ̇`.
    #[test]
    fn surface_points_and_gyroscopes_round_trip(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, moment in 0.1..1.0f64, lorentz in proptest::bool::ANY,
        k in 0.1..1.0f64, b in -1.0..1.0f64, t in 0.2..(PI - 0.2), phi in -3.0..3.0f64, psi in -3.0..3.0f64,
        v in proptest::collection::vec(-2.0..2.0f64, 3),
    ) {
        let point = Point::new(m).unwrap();
        let body = Gyroscope::<2>::isotropic(m, moment).unwrap().with_signature(sig(lorentz));
        let vp = Vector2::new(v[0], v[1]);
        let vg = Vector3::new(v[0], v[1], v[2]);
        macro_rules! case {
            ($name:expr, $chart:expr, $bundle:expr, $x:expr, $pot:expr, $angles:expr) => {{
                let (chart, bundle, x) = ($chart, $bundle, $x);
                let pot = $pot;
                let sys = PointLagrangian::new(chart.clone(), &point, Free);
                let model = PointModel::<_, _, 2, 3>::new(bundle, point, Free).unwrap();
                check(&format!("{} point", $name), &round_trip(&sys, &model, x, vp, &$angles[..1]).0)?;
                let sys = Gyroscope2::gyroscope(chart, PlaneRotation, &body, pot);
                let model = Gyroscope2Model::new(bundle, body, pot).unwrap();
                let q = Vector3::new(x[0], x[1], psi);
                let (d, y) = round_trip(&sys, &model, q, vg, &$angles);
                check(&format!("{} gyroscope", $name), &d)?;
                let p = momenta(&sys, &q, &vg).unwrap();
                prop_assert!((model.spin(&y) - p[2]).abs() <= TOL * p[2].abs().max(1.0), "{}: spin {} vs p_ψ {}", $name, model.spin(&y), p[2]);
            }};
        }
        let s2 = Sphere2::new(radius).unwrap();
        let pot = Sum::new(Oscillator::new(k, Centre::sphere2_at(&s2, &Vector3::new(radius, 0.0, 0.0)).unwrap()).unwrap(), Axial { a: 0.3, b, radius: 1.0, axis: 1 });
        case!("S2", SphereChart::new(radius).unwrap(), s2, Vector2::new(t * radius, phi / 3.0), pot, [1usize, 2]);
        let h2 = Hyperbolic2::new(radius).unwrap();
        let pot = Sum::new(Oscillator::new(k, Centre::hyperbolic2(&h2)).unwrap(), Axial { a: 0.0, b, radius: 1.0, axis: 0 });
        case!("H2", HyperbolicChart::new(radius).unwrap(), h2, Vector2::new(t * radius * 0.5, phi), pot, [1usize, 2]);
        let t2 = Torus2::new(2.5 * radius, radius).unwrap();
        let pot = Axial { a: k, b, radius: 1.0, axis: 2 };
        case!("T2", TorusChart::new(2.5 * radius, radius).unwrap(), t2, Vector2::new(2.0 * t - PI, phi), pot, [0usize, 1, 2]);
    }

    /// Affine bodies on S², H², T² in the two-polar variables
    /// `(α, β, λ, μ)` (`λ > μ`, the branch of `TwoPolar::coordinates`;
    /// `|α ± β| < π`), incompressible `(α, β, λ)` (`λ > 1`) and Weyl
    /// `(α, λ)`; `p_α`, `p_β` of the two-polar Lagrangian are the model's
    /// spin and vorticity scalars.
    #[test]
    fn surface_affine_bodies_round_trip(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, j in proptest::collection::vec(0.2..0.8f64, 2), joff in -0.1..0.1f64,
        k in 0.2..1.5f64, b in -1.0..1.0f64, t in 0.2..(PI - 0.2), phi in -3.0..3.0f64,
        alpha in -1.5..1.5f64, beta in -1.5..1.5f64, lambda in 1.1..1.8f64, mu in 0.4..0.9f64,
        v in proptest::collection::vec(-1.0..1.0f64, 6),
    ) {
        let jm = Matrix2::new(j[0], joff, joff, j[1]);
        let body = Affine::new(m, jm).unwrap();
        let qd6 = SVector::<f64, 6>::from_column_slice(&v);
        let qd5 = SVector::<f64, 5>::from_column_slice(&v[..5]);
        let qd4 = SVector::<f64, 4>::from_column_slice(&v[..4]);
        macro_rules! case {
            ($name:expr, $chart:expr, $bundle:expr, $x:expr, $pot:expr, $angle0:expr) => {{
                let (chart, bundle, x) = ($chart, $bundle, $x);
                let pot = $pot;
                let a0: &[usize] = if $angle0 { &[0, 1, 2, 3] } else { &[1, 2, 3] };
                let sys = FrameLagrangian::affine(chart.clone(), TwoPolar, &body, pot);
                let model = AffineModel::new(bundle, body, pot).unwrap();
                let q = SVector::<f64, 6>::from_column_slice(&[x[0], x[1], alpha, beta, lambda, mu]);
                let (d, y) = round_trip(&sys, &model, q, qd6, a0);
                check(&format!("{} affine", $name), &d)?;
                let p = momenta(&sys, &q, &qd6).unwrap();
                let (pa, pb) = (model.p_alpha(&y), model.p_beta(&y));
                prop_assert!((pa - p[2]).abs() <= 1e-12 * p.amax().max(1.0) && (pb - p[3]).abs() <= 1e-12 * p.amax().max(1.0),
                    "{}: (p_α, p_β) = ({pa}, {pb}) vs ∂L/∂(α̇, β̇) = ({}, {})", $name, p[2], p[3]);
                let model = IncompressibleModel::new(bundle, Incompressible::new(m, jm).unwrap(), pot).unwrap();
                let sys = FrameLagrangian::new(chart.clone(), TwoPolarSl, m, jm, Signature::Riemannian, pot).unwrap();
                let q = SVector::<f64, 5>::from_column_slice(&[x[0], x[1], alpha, beta, lambda]);
                check(&format!("{} incompressible", $name), &round_trip(&sys, &model, q, qd5, a0).0)?;
                let model = WeylModel::new(bundle, Weyl::new(m, jm).unwrap(), pot).unwrap();
                let sys = FrameLagrangian::new(chart, TwoPolarWeyl, m, jm, Signature::Riemannian, pot).unwrap();
                let q = SVector::<f64, 4>::from_column_slice(&[x[0], x[1], alpha, lambda]);
                check(&format!("{} Weyl", $name), &round_trip(&sys, &model, q, qd4, a0).0)?;
            }};
        }
        let pot = Sum::new(Elastic::new(k).unwrap(), Axial { a: 0.3, b, radius: 1.0, axis: 1 });
        case!("S2", SphereChart::new(radius).unwrap(), Sphere2::new(radius).unwrap(), Vector2::new(t * radius, phi), pot, false);
        case!("H2", HyperbolicChart::new(radius).unwrap(), Hyperbolic2::new(radius).unwrap(), Vector2::new(t * radius * 0.5, phi), pot, false);
        let pot = Sum::new(Elastic::new(k).unwrap(), Axial { a: 0.3, b, radius: 1.0, axis: 2 });
        case!("T2", TorusChart::new(2.5 * radius, radius).unwrap(), Torus2::new(2.5 * radius, radius).unwrap(), Vector2::new(2.0 * t - PI, phi), pot, true);
    }

    /// S³: the point `r̄`, the gyroscope `(r̄, κ)` (rotation vectors, principal
    /// `|κ| < π`) with anisotropic `J` and either signature, and the affine
    /// body `(r̄, φ_ij)` with `φ ∈ GL⁺(3)`.
    #[test]
    fn sphere3_bodies_round_trip(
        radius in 0.5..2.0f64, m in 0.5..2.0f64, lorentz in proptest::bool::ANY,
        j in proptest::collection::vec(0.2..1.0f64, 3), off in proptest::collection::vec(-0.05..0.05f64, 3),
        k in 0.1..1.0f64, b in -1.0..1.0f64,
        x in proptest::collection::vec(-0.9..0.9f64, 3), kappa in proptest::collection::vec(-1.5..1.5f64, 3),
        f in proptest::collection::vec(-0.3..0.3f64, 9), v in proptest::collection::vec(-1.0..1.0f64, 12),
    ) {
        let jm = Matrix3::new(j[0], off[0], off[1], off[0], j[1], off[2], off[1], off[2], j[2]);
        let s3 = Sphere3::new(radius).unwrap();
        let chart = Sphere3Chart::new(radius).unwrap();
        let rbar = Vector3::new(x[0], x[1], x[2]) * radius;
        let pot = Sum::new(Oscillator::new(k, Centre::sphere3(&s3)).unwrap(), Axial { a: 0.2, b, radius: 1.0, axis: 1 });
        let point = Point::new(m).unwrap();
        let free = Oscillator::new(k, Centre::sphere3(&s3)).unwrap();
        let sys = PointLagrangian::new(chart, &point, free);
        let model = PointModel::<_, _, 3, 4>::new(s3, point, free).unwrap();
        check("S3 point", &round_trip(&sys, &model, rbar, Vector3::new(v[0], v[1], v[2]), &[]).0)?;
        let body = Gyroscope::<3>::new(m, jm).unwrap().with_signature(sig(lorentz));
        let sys = Gyroscope3::gyroscope(chart, RotationVector, &body, pot);
        let model = Gyroscope3Model::new(s3, body, pot).unwrap();
        let q = SVector::<f64, 6>::from_column_slice(&[rbar[0], rbar[1], rbar[2], kappa[0], kappa[1], kappa[2]]);
        check("S3 gyroscope", &round_trip(&sys, &model, q, SVector::<f64, 6>::from_column_slice(&v[..6]), &[]).0)?;
        let body = Affine::<3>::new(m, jm).unwrap();
        let sys = FrameLagrangian::<_, GlEntries, _, 3, 4, 9, 12>::affine(chart, GlEntries, &body, pot);
        let model = AffineModel::new(s3, body, pot).unwrap();
        let phi0 = RotationVector.matrix(&Vector3::new(kappa[0], kappa[1], kappa[2])) + SMatrix::<f64, 3, 3>::from_column_slice(&f);
        prop_assume!(phi0.determinant() > 0.2);
        let q = SVector::<f64, 12>::from_fn(|i, _| if i < 3 { rbar[i] } else { phi0[((i - 3) / 3, (i - 3) % 3)] });
        check("S3 affine", &round_trip(&sys, &model, q, SVector::<f64, 12>::from_column_slice(&v), &[]).0)?;
    }
}

/// Outside the charts and fibre parametrisations, and for ambient data that
/// are not a motion on the manifold: typed errors naming the field.
#[test]
fn paper_state_errors_are_typed() {
    let s2 = Sphere2::new(1.0).unwrap();
    let chart = SphereChart::new(1.0).unwrap();
    let body = Affine::new(1.0, Matrix2::new(0.5, 0.0, 0.0, 0.3)).unwrap();
    let sys = FrameLagrangian::affine(chart, TwoPolar, &body, Free);
    let model = AffineModel::new(s2, body, Free).unwrap();
    let q = SVector::<f64, 6>::from_column_slice(&[1.0, 0.5, 0.2, -0.3, 1.4, 0.7]);
    let v = SVector::<f64, 6>::from_column_slice(&[0.1, -0.2, 0.3, 0.1, 0.05, -0.1]);
    let with = |i: usize, x: f64| {
        let mut w = q;
        w[i] = x;
        w
    };
    for (i, field) in [(4, "lambda"), (5, "mu")] {
        for bad in [0.0, -0.5] {
            match state_from_paper(&sys, &model, &with(i, bad), &v) {
                Err(Error::InvalidParameter { field: f, value, .. }) => assert!(f == field && value == bad, "{f} {value}"),
                other => panic!("{field} = {bad}: {other:?}"),
            }
        }
    }
    for r in [0.0, PI, -0.1, 4.0] {
        assert!(matches!(state_from_paper(&sys, &model, &with(0, r), &v), Err(Error::OutsideChart { manifold: "S2", .. })), "r = {r}");
    }
    assert!(matches!(state_from_paper(&sys, &model, &with(2, f64::NAN), &v), Err(Error::NotFinite { .. })));
    let mut vn = v;
    vn[3] = f64::INFINITY;
    assert!(matches!(state_from_paper(&sys, &model, &q, &vn), Err(Error::NotFinite { field: "qdot" })));
    assert!(matches!(state_from_paper_momenta(&sys, &model, &q, &vn), Err(Error::NotFinite { field: "p" })));

    // Paper variables of a state where they are not defined: the pole, λ = μ.
    let y = state_from_paper(&sys, &model, &q, &v).unwrap();
    // At the pole X = e₃ with Ẋ = 0.1 e₁, e = (1.2 e₁, 0.8 e₂), ρ̇ = 0: the
    // normal part of ė₁ is −(Ẋ·e₁)X = −0.12 e₃.
    let pole = AmbientState {
        position: Vector3::new(0.0, 0.0, 1.0),
        velocity: Vector3::new(0.1, 0.0, 0.0),
        frame: SMatrix::<f64, 3, 2>::new(1.2, 0.0, 0.0, 0.8, 0.0, 0.0),
        frame_rate: SMatrix::<f64, 3, 2>::new(0.0, 0.0, 0.0, 0.0, -0.12, 0.0),
    };
    let yp = model.state_from_ambient(&pole, None).expect("a state at the pole");
    assert!(rel(&model.ambient(&yp).frame_rate, &pole.frame_rate) <= TOL);
    assert!(matches!(paper_from_state(&sys, &model, &yp), Err(Error::OutsideChart { manifold: "S2", .. })));
    let round = FrameLagrangian::affine(chart, GlEntries, &body, Free);
    let qr = SVector::<f64, 6>::from_column_slice(&[1.0, 0.5, 1.2, 0.0, 0.0, 1.2]);
    let yr = state_from_paper(&round, &model, &qr, &v).unwrap();
    assert!(matches!(paper_from_state(&sys, &model, &yr), Err(Error::OutsideChart { .. })));
    let qp = SVector::<f64, 6>::from_column_slice(&[1e-13, 0.5, 1.2, 0.1, -0.1, 0.9]);
    let yp = state_from_paper(&round, &model, &SVector::<f64, 6>::from_column_slice(&[0.3, 0.5, 1.2, 0.1, -0.1, 0.9]), &v).unwrap();
    assert!(matches!(paper_from_state(&round, &model, &yp), Ok(_)));
    assert!(matches!(state_from_paper(&round, &model, &qp, &v), Err(Error::OutsideChart { .. })));

    // Ambient data that are not a motion on the manifold.
    let mut a = model.ambient(&y);
    a.velocity += a.position * 0.1;
    assert!(matches!(model.state_from_ambient(&a, None), Err(Error::Constraint { field: "velocity", .. })));
    let mut a = model.ambient(&y);
    a.frame_rate += a.position * SMatrix::<f64, 1, 2>::new(0.1, 0.0);
    assert!(matches!(model.state_from_ambient(&a, None), Err(Error::Constraint { field: "frame_rate", .. })));
    let mut a = model.ambient(&y);
    a.frame[(0, 0)] = f64::NAN;
    assert!(matches!(model.state_from_ambient(&a, None), Err(Error::NotFinite { field: "frame" })));

    // A gyroscope whose frame rate is not a rotation, or whose frame is not orthonormal.
    let g = Gyroscope::<2>::isotropic(1.0, 0.4).unwrap();
    let gsys = Gyroscope2::gyroscope(chart, PlaneRotation, &g, Free);
    let gmodel = Gyroscope2Model::new(s2, g, Free).unwrap();
    let qg = Vector3::new(1.0, 0.5, 0.3);
    let gy = state_from_paper(&gsys, &gmodel, &qg, &Vector3::new(0.1, 0.2, 0.3)).unwrap();
    let mut a = gmodel.ambient(&gy);
    let e0: Vector3<f64> = a.frame.column(0).into();
    a.frame_rate.set_column(0, &(a.frame_rate.column(0) + e0 * 0.1));
    assert!(matches!(gmodel.state_from_ambient(&a, None), Err(Error::Constraint { field: "frame_rate", .. })));
    let mut a = gmodel.ambient(&gy);
    a.frame *= 1.1;
    assert!(matches!(gmodel.state_from_ambient(&a, None), Err(Error::Constraint { field: "frame", .. })));
    // A point with a frame.
    let p = Point::new(1.0).unwrap();
    let pmodel = PointModel::<_, _, 2, 3>::new(s2, p, Free).unwrap();
    assert!(matches!(pmodel.state_from_ambient(&gmodel.ambient(&gy), None), Err(Error::Constraint { field: "frame", .. })));
}
