//! S² area: the groups SO(2), SO(3), SU(2), the closed-form coefficient
//! functions of `lie::special` against extended precision, the sphere S²(R)
//! and its SO(3) frame bundle (parallel transport, holonomy, through the pole).

use framedyn::bundle::FrameBundle;
use framedyn::lie::{dexp_series, LieGroup, So2, So3, Su2};
use framedyn::manifold::{GeodesicDistance, Manifold, Sphere2};
use framedyn::Error;
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector1, Vector2, Vector3};
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};

use crate::bundle_laws::{
    check_bundle_at, frame_defect, random_walk_defect, rkmk4_step, small_loop_holonomy, transport_along,
    transport_in_chart,
};
use crate::distance_laws::{check_distance_at, check_distance_laws};
use crate::manifold_laws::check_manifold_at;

/// The generic Lie-group laws. SO(3)'s log is principal for |ω| < π, SU(2)'s
/// for |k| < 2π (radius 3 and 6); all three groups are compact, so the 10⁶
/// random products may use large steps.
mod group_laws {
    use framedyn::lie::{So2, So3, Su2};
    crate::lie_law_suite!(so2, So2, radius = 3.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 3.0);
    crate::lie_law_suite!(so3, So3, radius = 3.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 3.0);
    crate::lie_law_suite!(su2, Su2, radius = 6.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 6.0);
}

/// Deterministic xorshift stream in [−1, 1) for the non-proptest loops.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn unit3(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(self.next(), self.next(), self.next());
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

fn rot2(psi: f64) -> Matrix2<f64> {
    let (s, c) = psi.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// Angle in (−π, π] congruent to `a`.
fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

// ---------------------------------------------------------------------------
// Special functions against 512-bit evaluations (astro-float).
// ---------------------------------------------------------------------------
mod special_vs_bigfloat {
    use astro_float::{BigFloat, Consts, Radix, RoundingMode};
    use framedyn::lie::special::{cosc, dexpinv, sinc, sinc3, SERIES_SMALL, SERIES_WIDE};
    use std::f64::consts::TAU;

    const P: usize = 512;
    const RM: RoundingMode = RoundingMode::ToEven;
    const NAMES: [&str; 4] = ["sinc", "cosc", "sinc3", "dexpinv"];

    struct Ref {
        cc: Consts,
    }

    impl Ref {
        fn new() -> Self {
            Ref { cc: Consts::new().expect("astro-float constants") }
        }
        fn to_f64(&mut self, x: &BigFloat) -> f64 {
            x.format(Radix::Dec, RM, &mut self.cc).expect("format").parse().expect("parse")
        }
        /// The closed form of function `which` at the (exact) signed square `s ≠ 0`.
        fn f(&mut self, which: usize, s: &BigFloat) -> BigFloat {
            let cc = &mut self.cc;
            let one = BigFloat::from_f64(1.0, P);
            let two = BigFloat::from_f64(2.0, P);
            if s.is_positive() {
                let x = s.sqrt(P, RM);
                match which {
                    0 => x.sin(P, RM, cc).div(&x, P, RM),
                    1 => one.sub(&x.cos(P, RM, cc), P, RM).div(s, P, RM),
                    2 => x.sub(&x.sin(P, RM, cc), P, RM).div(&s.mul(&x, P, RM), P, RM),
                    _ => {
                        let h = x.div(&two, P, RM);
                        let cot = h.cos(P, RM, cc).div(&h.sin(P, RM, cc), P, RM);
                        one.sub(&h.mul(&cot, P, RM), P, RM).div(s, P, RM)
                    }
                }
            } else {
                let t = s.neg();
                let y = t.sqrt(P, RM);
                match which {
                    0 => y.sinh(P, RM, cc).div(&y, P, RM),
                    1 => y.cosh(P, RM, cc).sub(&one, P, RM).div(&t, P, RM),
                    2 => y.sinh(P, RM, cc).sub(&y, P, RM).div(&t.mul(&y, P, RM), P, RM),
                    _ => {
                        let h = y.div(&two, P, RM);
                        let coth = h.cosh(P, RM, cc).div(&h.sinh(P, RM, cc), P, RM);
                        h.mul(&coth, P, RM).sub(&one, P, RM).div(&t, P, RM)
                    }
                }
            }
        }
    }

    fn f64_fn(which: usize, s: f64) -> f64 {
        [sinc, cosc, sinc3, dexpinv][which](s)
    }

    /// Relative error of the f64 implementation at `s`, and the condition
    /// number `κ = |θ f'(θ)/f|` (θ = √|s|) of the function, both from 512-bit
    /// arithmetic (κ by a central difference with relative step 1e-40).
    fn measure(r: &mut Ref, which: usize, s: f64) -> (f64, f64) {
        let sb = BigFloat::from_f64(s, P);
        let exact = r.f(which, &sb);
        let got = BigFloat::from_f64(f64_fn(which, s), P);
        let rel = r.to_f64(&got.sub(&exact, P, RM).div(&exact, P, RM)).abs();
        let delta = BigFloat::from_f64(1e-40, P);
        let one = BigFloat::from_f64(1.0, P);
        let theta = sb.abs().sqrt(P, RM);
        let sq = |t: &BigFloat| {
            let v = t.mul(t, P, RM);
            if s > 0.0 {
                v
            } else {
                v.neg()
            }
        };
        let tp = theta.mul(&one.add(&delta, P, RM), P, RM);
        let tm = theta.mul(&one.sub(&delta, P, RM), P, RM);
        let (fp, fm) = (r.f(which, &sq(&tp)), r.f(which, &sq(&tm)));
        let two_delta = delta.mul(&BigFloat::from_f64(2.0, P), P, RM);
        let kappa = r.to_f64(&fp.sub(&fm, P, RM).div(&two_delta.mul(&exact, P, RM), P, RM)).abs();
        (rel, kappa)
    }

    fn log_grid(a: f64, b: f64, n: usize) -> Vec<f64> {
        (0..n).map(|i| a * (b / a).powf(i as f64 / (n - 1) as f64)).collect()
    }

    fn thresholds(sign: f64) -> Vec<f64> {
        let mut v = Vec::new();
        for t in [SERIES_SMALL, SERIES_WIDE] {
            let t = sign * t;
            v.extend([t.next_down().next_down(), t.next_down(), t, t.next_up(), t.next_up().next_up()]);
        }
        v
    }

    /// Worst errors of one function over a grid.
    #[derive(Default, Clone, Copy)]
    struct Worst {
        /// Largest relative error where κ ≤ 2.
        well: f64,
        /// Largest rel/(1e-14·max(1, κ)), and where.
        ratio: f64,
        ratio_s: f64,
        /// Largest relative error anywhere, with its κ and s.
        rel: f64,
        rel_kappa: f64,
        rel_s: f64,
    }

    /// Runs the grid; every point must satisfy `rel ≤ 1e-14·max(1, κ)`:
    /// 1e-14 where the function is well conditioned, and a bound
    /// proportional to the condition number where it is not (near the zeros
    /// of sinc at θ = π, 2π and of cosc at 2π, near the pole of dexpinv at
    /// θ = 2π, and for large hyperbolic θ): there even a correctly rounded
    /// evaluation of the closed form from the rounded θ = √s errs by ~κ·ulp.
    fn run(s_values: &[f64]) -> [Worst; 4] {
        let mut r = Ref::new();
        let mut worst = [Worst::default(); 4];
        for &s in s_values {
            for (which, w) in worst.iter_mut().enumerate() {
                let (rel, kappa) = measure(&mut r, which, s);
                let tol = 1e-14 * kappa.max(1.0);
                assert!(
                    rel <= tol,
                    "{} at s = {s:e} (θ = {:e}): relative error {rel:e} > {tol:e} (κ = {kappa:e})",
                    NAMES[which],
                    s.abs().sqrt()
                );
                if kappa <= 2.0 {
                    w.well = w.well.max(rel);
                }
                if rel / tol > w.ratio {
                    (w.ratio, w.ratio_s) = (rel / tol, s);
                }
                if rel > w.rel {
                    (w.rel, w.rel_kappa, w.rel_s) = (rel, kappa, s);
                }
            }
        }
        worst
    }

    fn report(label: &str, worst: &[Worst; 4]) {
        for (name, w) in NAMES.iter().zip(worst) {
            eprintln!(
                "special {name} ({label}): worst rel err where κ ≤ 2: {:.2e}; worst rel err {:.2e} (κ = {:.1e}, s = {:e}); worst err/tol {:.3} at s = {:e}",
                w.well, w.rel, w.rel_kappa, w.rel_s, w.ratio, w.ratio_s
            );
        }
    }

    #[test]
    fn elliptic_grid_up_to_two_pi() {
        // θ log-spaced on [1e-12, 2π − 1e-6], refined towards the pole of
        // dexpinv at 2π (2π − δ, δ log-spaced down to 1e-6), plus the series
        // thresholds ± 2 ulp.
        let mut s: Vec<f64> = log_grid(1e-12, TAU - 1e-6, 1200).iter().map(|t| t * t).collect();
        s.extend(log_grid(1e-6, 1.0, 200).iter().map(|d| (TAU - d) * (TAU - d)));
        s.extend(thresholds(1.0));
        report("s > 0", &run(&s));
    }

    #[test]
    fn hyperbolic_grid_up_to_thirty() {
        let mut s: Vec<f64> = log_grid(1e-12, 30.0, 800).iter().map(|t| -t * t).collect();
        s.extend(thresholds(-1.0));
        report("s < 0", &run(&s));
    }
}

// ---------------------------------------------------------------------------
// Groups: beyond the generic laws.
// ---------------------------------------------------------------------------

/// Rotation by `angle` about the unit `axis`, built independently of the
/// library (nalgebra's axis–angle constructor).
fn rotation_reference(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    *nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(*axis), angle).matrix()
}

#[test]
fn so3_log_near_pi() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut worst: [f64; 2] = [0.0; 2];
    for _ in 0..500 {
        let n = rng.unit3();
        for (k, theta) in [PI - 1e-8, PI - 1e-12].into_iter().enumerate() {
            let r = So3::new(rotation_reference(&n, theta)).unwrap();
            let w = r.log().unwrap();
            let err = (w - n * theta).amax();
            worst[k] = worst[k].max(err);
            assert!(err <= 4e-15, "log at θ = π − {:e}: error {err:e}", PI - theta);
            // The textbook formula loses the axis here; ours must not.
            assert!((w.norm() - theta).abs() <= 4e-15);
        }
    }
    eprintln!("SO(3) log: worst abs error at π−1e-8: {:.2e}, at π−1e-12: {:.2e}", worst[0], worst[1]);
    // Exactly π: any of the two valid axes, and exp(log R) = R.
    for _ in 0..200 {
        let n = rng.unit3();
        let m = rotation_reference(&n, PI);
        let w = So3::new_unchecked(m).log().unwrap();
        assert!((w.norm() - PI).abs() <= 4e-15, "|log| = {} at π", w.norm());
        let axis_err = (w / w.norm() - n).amax().min((w / w.norm() + n).amax());
        assert!(axis_err <= 4e-15, "axis error {axis_err:e} at π");
        assert!((So3::exp(&w).matrix() - m).amax() <= 4e-15);
    }
    // The diagonal rotations by π, where Shepperd's branches switch.
    for m in [Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0), Matrix3::from_diagonal(&Vector3::new(-1.0, -1.0, 1.0))] {
        let w = So3::new(m).unwrap().log().unwrap();
        assert!((w.norm() - PI).abs() <= 1e-15 && (So3::exp(&w).matrix() - m).amax() <= 1e-15);
    }
}

#[test]
fn so3_log_near_identity_is_relatively_accurate() {
    let mut rng = Rng(77);
    let mut worst: f64 = 0.0;
    for _ in 0..500 {
        let n = rng.unit3();
        for theta in [1e-3, 1e-7, 1e-12, 1e-200] {
            let a = n * theta;
            let w = So3::exp(&a).log().unwrap();
            let rel = (w - a).norm() / theta;
            worst = worst.max(rel);
            assert!(rel <= 2e-15, "θ = {theta:e}: relative error {rel:e}");
        }
    }
    assert_eq!(So3::identity().log().unwrap(), Vector3::zeros());
    eprintln!("SO(3) log near identity: worst relative error {worst:.2e}");
}

#[test]
fn so3_closed_forms_match_series_on_the_whole_ball() {
    // The law suite compares dexp_inv with the Bernoulli series only for
    // |a| < 1; dexp's Taylor series converges everywhere (ad has norm |a|),
    // so check the closed form against it up to |a| = 3.
    let mut rng = Rng(99);
    for _ in 0..2000 {
        let a = rng.unit3() * (3.0 * rng.next().abs());
        let v = rng.unit3();
        for (lib, ser) in [
            (So3::dexp(&a, &v), dexp_series::<So3>(&a, &v, 80)),
            (Su2::dexp(&a, &v), dexp_series::<Su2>(&a, &v, 80)),
        ] {
            assert!((lib - ser).norm() <= 2e-15, "dexp closed form vs series at |a| = {}: {:e}", a.norm(), (lib - ser).norm());
        }
    }
}

#[test]
fn su2_covers_so3_and_matches_the_paper() {
    let mut rng = Rng(5);
    let (s1, s2, s3) = (
        Matrix2::new(0.0, 1.0, 1.0, 0.0).map(|x| nalgebra::Complex::new(x, 0.0)),
        Matrix2::new(nalgebra::Complex::new(0.0, 0.0), nalgebra::Complex::new(0.0, -1.0), nalgebra::Complex::new(0.0, 1.0), nalgebra::Complex::new(0.0, 0.0)),
        Matrix2::new(1.0, 0.0, 0.0, -1.0).map(|x| nalgebra::Complex::new(x, 0.0)),
    );
    let i = nalgebra::Complex::new(0.0, 1.0);
    for _ in 0..300 {
        let k = rng.unit3() * (6.0 * rng.next().abs());
        let v = rng.unit3();
        let q = Su2::exp(&k);
        // Covering map, adjoint and action agree with SO(3).
        assert!((q.to_so3().matrix() - So3::exp(&k).matrix()).amax() <= 1e-15);
        assert!((q.act(&v) - So3::exp(&k).act(&v)).amax() <= 1e-15);
        assert!((q.adjoint(&v) - So3::exp(&k).adjoint(&v)).amax() <= 1e-15);
        // (a171): u(k) = I cos(k/2) − i σ_B (k^B/k) sin(k/2).
        let (kn, n) = (k.norm(), k.normalize());
        let a171 = Matrix2::identity().map(|x: f64| nalgebra::Complex::new(x * (0.5 * kn).cos(), 0.0))
            - (s1 * nalgebra::Complex::new(n[0], 0.0) + s2 * nalgebra::Complex::new(n[1], 0.0) + s3 * nalgebra::Complex::new(n[2], 0.0))
                * (i * (0.5 * kn).sin());
        assert!((q.to_complex_matrix() - a171).iter().map(|z| z.norm()).fold(0.0, f64::max) <= 1e-15);
        // The complex representation is a homomorphism.
        let p = Su2::exp(&(rng.unit3() * 2.0));
        let lhs = q.compose(&p).to_complex_matrix();
        let rhs = q.to_complex_matrix() * p.to_complex_matrix();
        assert!((lhs - rhs).iter().map(|z| z.norm()).fold(0.0, f64::max) <= 1e-15);
        // SO(3)'s quaternion is the w ≥ 0 representative of ±q.
        let qq = q.to_so3().quaternion();
        let qs = q.quaternion() * q.scalar().signum();
        assert!((qq - qs).amax() <= 1e-15 || q.scalar().abs() < 1e-8);
    }
    // The SU(2) log reaches |k| → 2π (SO(3)'s stops at π).
    let k = Vector3::new(0.0, 0.0, TAU - 1e-6);
    assert!((Su2::exp(&k).log().unwrap() - k).amax() <= 1e-12);
    // Brackets of the paper's basis: [a_1, a_2] = a_3.
    assert_eq!(Su2::bracket(&Vector3::x(), &Vector3::y()), Vector3::z());
}

#[test]
fn so2_basics() {
    let g = So2::from_angle(2.5).unwrap();
    assert!((g.angle() - 2.5).abs() <= 1e-15);
    assert!((g.compose(&So2::from_angle(1.0).unwrap()).angle() - wrap(3.5)).abs() <= 1e-15);
    assert!((g.act(&Vector2::x()) - Vector2::new(2.5f64.cos(), 2.5f64.sin())).amax() <= 1e-16);
    assert_eq!(So2::from_angle(PI).unwrap().log().unwrap(), Vector1::new(PI));
    assert_eq!(So2::new_unchecked(-1.0, -0.0).log().unwrap(), Vector1::new(PI));
    assert!(So2::new(0.6, 0.8).is_ok());
}

#[test]
fn groups_report_typed_errors() {
    assert!(matches!(So2::new(1.0, 0.1), Err(Error::Constraint { field: "So2 (cos, sin)", .. })));
    assert!(matches!(So2::new(f64::NAN, 0.0), Err(Error::NotFinite { .. })));
    assert!(matches!(So2::from_angle(f64::INFINITY), Err(Error::NotFinite { .. })));
    assert!(matches!(So3::new(Matrix3::identity() * 1.01), Err(Error::Constraint { field: "So3 matrix", .. })));
    // A reflection is orthogonal but not a rotation.
    assert!(matches!(So3::new(-Matrix3::identity()), Err(Error::Constraint { field: "So3 matrix", .. })));
    assert!(matches!(So3::new(Matrix3::from_element(f64::NAN)), Err(Error::NotFinite { .. })));
    assert!(matches!(Su2::new(1.0, 0.1, 0.0, 0.0), Err(Error::Constraint { .. })));
    assert!(matches!(Su2::new(-1.0, 0.0, 0.0, 0.0).unwrap().log(), Err(Error::LogUndefined { group: "SU(2)", .. })));
    assert!(matches!(Su2::new_unchecked(0.0, 0.0, 0.0, 0.0).log(), Err(Error::LogUndefined { .. })));
    assert!(matches!(So3::new_unchecked(Matrix3::from_element(f64::NAN)).log(), Err(Error::LogUndefined { .. })));
    // new() projects accepted input onto the group.
    let m = rotation_reference(&Vector3::new(1.0, 2.0, 3.0), 1.0) * (1.0 + 1e-10);
    assert!(So3::new(m).unwrap().constraint_defect() <= 1e-15);
}

#[test]
fn so3_renormalize_is_the_nearest_rotation() {
    // For R₀ exp(ε(S + W)) with S symmetric, W skew the nearest rotation is
    // R₀ exp(εW) + O(ε²): the symmetric part is removed, the skew part kept.
    let mut rng = Rng(31);
    for _ in 0..200 {
        let r0 = So3::exp(&(rng.unit3() * 2.0));
        let e = Matrix3::from_fn(|_, _| rng.next()) * 1e-6;
        let perturbed = So3::new_unchecked(r0.matrix() * (Matrix3::identity() + e));
        let fixed = perturbed.renormalize();
        let skew = (e - e.transpose()) * 0.5;
        let expected = r0.matrix() * (Matrix3::identity() + skew);
        assert!(fixed.constraint_defect() <= 1e-15);
        assert!((fixed.matrix() - expected).amax() <= 1e-11, "{:e}", (fixed.matrix() - expected).amax());
    }
    // Far from SO(3) (SVD branch), including a reflection.
    let m = Matrix3::new(2.0, 0.1, 0.0, 0.0, 1.0, 0.3, 0.0, 0.0, -0.5);
    let fixed = So3::new_unchecked(m).renormalize();
    assert!(fixed.constraint_defect() <= 1e-14);
    let direct = (fixed.matrix() - m).norm();
    // No rotation among a few random ones is closer.
    for _ in 0..2000 {
        let other = So3::exp(&(rng.unit3() * PI * rng.next().abs()));
        assert!((other.matrix() - m).norm() >= direct - 1e-12);
    }
}

// ---------------------------------------------------------------------------
// The manifold S²(R).
// ---------------------------------------------------------------------------

/// The point-wise (difference-free) laws of `check_manifold_at`, for the
/// band near the poles: E orthonormal and positively oriented (E_r × E_φ = n),
/// curvature 1/R², Γ^A_BC skew, embedding on the sphere, chart ∘ embed and
/// chart_tangent ∘ embed_tangent round trips.
fn pointwise_laws(m: &Sphere2, x: &Vector2<f64>) -> f64 {
    let radius = m.radius();
    let fr = m.frame(x);
    let mut err = (fr.transpose() * m.metric(x) * fr - Matrix2::identity()).amax();
    let k = m.sectional_curvature(x, &fr.column(0).into(), &fr.column(1).into());
    err = err.max((k * radius * radius - 1.0).abs());
    let fc = m.frame_connection(x);
    for a in 0..2 {
        for b in 0..2 {
            for c in 0..2 {
                err = err.max((fc[a][b][c] + fc[b][a][c]).abs() * radius);
            }
        }
    }
    let e = m.ambient_frame(x);
    let p = m.embed(x);
    let c: Vector3<f64> = e.column(0).cross(&e.column(1));
    err = err.max((c - p / radius).amax()).max(m.point_defect(&p));
    err = err.max((m.embed(&m.chart(&p).unwrap()) - p).amax() / radius);
    let v = Vector2::new(0.3, 1.0);
    let vb = m.chart_tangent(&p, &m.embed_tangent(x, &v)).unwrap();
    // chart_tangent's φ component is conditioned like 1/sin(r/R).
    err.max((vb - v).amax() * (x[0] / radius).sin())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The shared manifold laws with K = 1/R² on r ∈ (0.02πR, 0.98πR);
    /// orientation E_r × E_φ = n.
    #[test]
    fn sphere_manifold_laws(radius in 0.3..5.0f64, u in 0.0..1.0f64, phi in -10.0..10.0f64) {
        let m = Sphere2::new(radius).unwrap();
        let x = Vector2::new((0.02 + 0.96 * u) * PI * radius, phi);
        let k = 1.0 / (radius * radius);
        let r = check_manifold_at(&m, &x, |_, _| k, 1e-12);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        let e = m.ambient_frame(&x);
        let n = m.embed(&x) / radius;
        let c: Vector3<f64> = e.column(0).cross(&e.column(1));
        prop_assert!((c - n).amax() <= 1e-15);
    }

    /// The distance laws at the chart points of `sphere_manifold_laws`:
    /// zero on the diagonal, `√(g dx dx)` for nearby points.
    #[test]
    fn sphere_distance_at_chart_points(radius in 0.3..5.0f64, u in 0.0..1.0f64, phi in -10.0..10.0f64) {
        let m = Sphere2::new(radius).unwrap();
        let x = Vector2::new((0.02 + 0.96 * u) * PI * radius, phi);
        let r = check_distance_at(&m, &x);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    /// The point-wise laws on to within 1e-6·πR of the poles (difference
    /// checks of the Riemann tensor cannot go there: ∂Γ and Γ·Γ are each
    /// ~1/ϑ² and cancel to K, so any difference quotient's round-off is
    /// amplified by 1/ϑ²).
    #[test]
    fn sphere_manifold_laws_up_to_the_poles(radius in 0.3..5.0f64, t in 0.02..0.98f64, lt in -6.0..-1.7f64, phi in -10.0..10.0f64) {
        let m = Sphere2::new(radius).unwrap();
        for tt in [t, 10f64.powf(lt), 1.0 - 10f64.powf(lt)] {
            let x = Vector2::new(tt * PI * radius, phi);
            let ep = pointwise_laws(&m, &x);
            prop_assert!(ep <= 1e-14, "ϑ/π = {tt}: point-wise laws {ep:e}");
        }
    }

    #[test]
    fn sphere_distance_laws(radius in 0.3..5.0f64, a in proptest::collection::vec(-1.0..1.0f64, 9)) {
        let m = Sphere2::new(radius).unwrap();
        let pt = |i: usize| {
            let v = Vector3::new(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
            m.project_point(&(v + Vector3::new(1e-3, 0.0, 0.0)))
        };
        let r = check_distance_laws(&m, &pt(0), &pt(1), &pt(2));
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        let d = m.distance(&pt(0), &pt(1)).unwrap();
        prop_assert!((0.0..=PI * radius).contains(&d));
    }
}

/// The angle between two exactly given f64 vectors, in 512-bit arithmetic.
fn angle_reference(p: &Vector3<f64>, q: &Vector3<f64>) -> f64 {
    use astro_float::{BigFloat, Consts, Radix, RoundingMode};
    const P: usize = 512;
    const RM: RoundingMode = RoundingMode::ToEven;
    let mut cc = Consts::new().unwrap();
    let b = |x: f64| BigFloat::from_f64(x, P);
    let dop = |a: f64, bb: f64, c: f64, d: f64| b(a).mul(&b(bb), P, RM).sub(&b(c).mul(&b(d), P, RM), P, RM);
    let cx = [dop(p[1], q[2], p[2], q[1]), dop(p[2], q[0], p[0], q[2]), dop(p[0], q[1], p[1], q[0])];
    let cn = cx.iter().fold(b(0.0), |acc, c| acc.add(&c.mul(c, P, RM), P, RM)).sqrt(P, RM);
    let dot = (0..3).fold(b(0.0), |acc, i| acc.add(&b(p[i]).mul(&b(q[i]), P, RM), P, RM));
    let at = cn.div(&dot.abs(), P, RM).atan(P, RM, &mut cc);
    let angle = if dot.is_negative() { cc.pi(P, RM).sub(&at, P, RM) } else { at };
    angle.format(Radix::Dec, RM, &mut cc).unwrap().parse().unwrap()
}

#[test]
fn sphere_distance_is_accurate_near_and_far() {
    // Against the exact angle between the given floating-point points: a few
    // ulp relative for distances from 1e-12·R up to nearly πR; exactly πR for
    // antipodes.
    let mut rng = Rng(4242);
    let mut worst: f64 = 0.0;
    for &radius in &[0.3, 1.0, 5.0] {
        let m = Sphere2::new(radius).unwrap();
        for _ in 0..100 {
            let n = rng.unit3();
            let p = n * radius;
            assert_eq!(m.distance(&p, &(-p)).unwrap(), PI * radius);
            let axis = n.cross(&rng.unit3()).normalize();
            for angle in [1e-12, 1e-8, 1e-3, 1.0, 2.0, PI - 1e-3, PI - 1e-8] {
                let q = So3::exp(&(axis * angle)).act(&p);
                let d = m.distance(&p, &q).unwrap();
                let exact = radius * angle_reference(&p, &q);
                let rel = (d - exact).abs() / exact;
                worst = worst.max(rel);
                assert!(rel <= 1e-15, "R = {radius}, angle {angle:e}: distance {d} vs {exact} (rel {rel:e})");
            }
        }
    }
    eprintln!("S² distance: worst relative error vs 512-bit reference {worst:.2e}");
}

#[test]
fn sphere_reports_typed_errors() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        match Sphere2::new(bad) {
            Err(Error::InvalidParameter { field: "R", .. }) => {}
            other => panic!("Sphere2::new({bad}) gave {other:?}"),
        }
    }
    let m = Sphere2::new(2.0).unwrap();
    // check_chart: r outside (0, πR), non-finite, within POLE_TOLERANCE of a pole.
    for r in [0.0, -0.1, 2.0 * PI, 7.0, 1e-13] {
        assert!(matches!(m.check_chart(&Vector2::new(r, 0.3)), Err(Error::OutsideChart { manifold: "S2", .. })), "r = {r}");
    }
    assert!(m.check_chart(&Vector2::new(1e-11, 0.3)).is_ok());
    assert!(matches!(m.check_chart(&Vector2::new(f64::NAN, 0.3)), Err(Error::NotFinite { .. })));
    assert!(matches!(m.check_chart(&Vector2::new(1.0, f64::INFINITY)), Err(Error::NotFinite { .. })));
    // chart at and near the poles.
    for p in [Vector3::new(0.0, 0.0, 2.0), Vector3::new(0.0, 0.0, -2.0), Vector3::new(1e-13, 0.0, 2.0)] {
        assert!(matches!(m.chart(&p), Err(Error::OutsideChart { .. })), "{p:?}");
        assert!(matches!(m.chart_tangent(&p, &Vector3::x()), Err(Error::OutsideChart { .. })));
    }
    assert!(m.chart(&Vector3::new(1e-9, 0.0, 2.0)).is_ok());
    assert!(matches!(m.chart(&Vector3::new(1.0, 0.0, 0.0)), Err(Error::Constraint { field: "p", .. })));
    assert!(matches!(m.chart(&Vector3::new(f64::NAN, 0.0, 0.0)), Err(Error::NotFinite { field: "p" })));
    assert!(matches!(m.distance(&Vector3::new(2.0, 0.0, 0.0), &Vector3::new(3.0, 0.0, 0.0)), Err(Error::Constraint { field: "q", .. })));

    // Bundle: from_frame.
    let p = Vector3::new(0.0, 0.0, 2.0);
    let good = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
    assert!(m.from_frame(&p, &good).is_ok());
    let err_of = |q: Matrix3x2<f64>| m.from_frame(&p, &q).unwrap_err();
    match err_of(Matrix3x2::new(1.0, 0.1, 0.0, 1.0, 0.0, 0.0)) {
        Error::Constraint { field: "q", constraint, .. } => assert!(constraint.contains("orthonormal")),
        e => panic!("{e:?}"),
    }
    match err_of(Matrix3x2::new(0.0, 1.0, 1.0, 0.0, 0.0, 0.0)) {
        Error::Constraint { field: "q", constraint, .. } => assert!(constraint.contains("oriented")),
        e => panic!("{e:?}"),
    }
    match err_of(Matrix3x2::new(0.8, 0.0, 0.0, 1.0, 0.6, 0.0)) {
        Error::Constraint { field: "q", constraint, .. } => assert!(constraint.contains("tangent")),
        e => panic!("{e:?}"),
    }
    assert!(matches!(err_of(Matrix3x2::from_element(f64::NAN)), Error::NotFinite { field: "q" }));
    assert!(matches!(m.from_frame(&Vector3::new(0.0, 0.0, 2.1), &good), Err(Error::Constraint { field: "p", .. })));
    // Bundle: from_chart with a reflection, to_chart at the pole.
    let refl = Matrix2::new(1.0, 0.0, 0.0, -1.0);
    assert!(matches!(m.from_chart(&Vector2::new(1.0, 0.0), &refl), Err(Error::Constraint { field: "u", .. })));
    assert!(matches!(m.from_chart(&Vector2::new(0.0, 0.0), &Matrix2::identity()), Err(Error::OutsideChart { .. })));
    let at_pole = m.from_frame(&p, &good).unwrap();
    assert!(matches!(m.to_chart(&at_pole), Err(Error::OutsideChart { .. })));
}

// ---------------------------------------------------------------------------
// The frame bundle.
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn sphere_bundle_laws(
        radius in 0.3..5.0f64,
        t in 0.02..0.98f64,
        phi in -4.0..4.0f64,
        psi in -4.0..4.0f64,
        v in proptest::collection::vec(-2.0..2.0f64, 2),
    ) {
        let m = Sphere2::new(radius).unwrap();
        let x = Vector2::new(t * PI * radius, phi);
        let r = check_bundle_at(&m, &x, &rot2(psi), &Vector2::new(v[0], v[1]), 1e-12);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }
}

#[test]
fn sphere_bundle_million_random_steps_stay_orthonormal() {
    let m = Sphere2::new(1.7).unwrap();
    let g0 = m.from_chart(&Vector2::new(1.0, 0.4), &rot2(0.3)).unwrap();
    let worst = random_walk_defect(&m, &g0, 1_000_000, 0.05, 0xDEADBEEF);
    eprintln!("S² bundle: worst frame defect over 1e6 random steps: {worst:.2e}");
    assert!(worst <= 1e-13, "frame defect {worst:e}");
}

#[test]
fn sphere_bundle_transport_agrees_with_the_chart_ode() {
    // A wiggly curve that stays in ϑ ∈ [0.25, 0.85]π.
    let radius = 1.3;
    let m = Sphere2::new(radius).unwrap();
    let curve = |t: f64| {
        let r = radius * (1.7 + 0.9 * (TAU * t).sin());
        let rd = radius * 0.9 * TAU * (TAU * t).cos();
        let phi = 0.2 + 3.0 * t + 0.5 * (5.0 * t).sin();
        let phid = 3.0 + 2.5 * (5.0 * t).cos();
        (Vector2::new(r, phi), Vector2::new(rd, phid))
    };
    let u0 = rot2(0.7);
    let (x0, _) = curve(0.0);
    let g0 = m.from_chart(&x0, &u0).unwrap();
    let g1 = transport_along(&m, &g0, &curve, 2000);
    let v1 = transport_in_chart(&m, &(m.frame(&x0) * u0), &curve, 2000);
    let (x1, _) = curve(1.0);
    let q_chart = Matrix3x2::from_columns(&[m.embed_tangent(&x1, &v1.column(0).into()), m.embed_tangent(&x1, &v1.column(1).into())]);
    let err = (m.frame_vectors(&g1) - q_chart).amax();
    let pos_err = (m.position(&g1) - m.embed(&x1)).amax();
    eprintln!("S² transport: bundle vs chart ODE frame difference {err:.2e}, position error {pos_err:.2e}");
    assert!(err <= 1e-10 && pos_err <= 1e-10, "frame {err:e}, position {pos_err:e}");
}

#[test]
fn sphere_small_loop_holonomy_converges_like_eps_squared() {
    // Chart loop of radius ε in the E-frame at x₀; the enclosed area is
    // exactly 2πRεJ₁(ε/R) (area element R sin(r/R) dr dφ, the odd part
    // integrates to zero), so holonomy = K·area = 2π(ε/R)J₁(ε/R) and the
    // relative deviation from Kπε² is −ε²/(8R²) + O(ε⁴).
    let j1 = |x: f64| {
        let mut term = x / 2.0;
        let mut sum = term;
        for k in 1..20 {
            term *= -(x * x / 4.0) / (k as f64 * (k + 1) as f64);
            sum += term;
        }
        sum
    };
    for &radius in &[0.7, 1.0, 2.5] {
        let m = Sphere2::new(radius).unwrap();
        let x0 = Vector2::new(1.1 * radius, 0.3);
        let eps: Vec<f64> = [0.16, 0.08, 0.04, 0.02].iter().map(|e| e * radius).collect();
        let mut rel = Vec::new();
        for &e in &eps {
            // RKMK4 truncation measured at 2.0e-9 relative with 200 steps,
            // converging at order 4 (ratio 16 per halving), so ≈ 2e-13 with
            // 2000; the absolute round-off floor is ~2e-15.
            let (angle, approx) = small_loop_holonomy(&m, &x0, e, 2000);
            let exact = TAU * (e / radius) * j1(e / radius);
            assert!((angle - exact).abs() <= 1e-12 * exact + 1e-14, "ε = {e}: holonomy {angle} vs exact {exact}");
            rel.push((angle - approx).abs() / approx);
            let coef = (angle - approx) / approx / (e / radius).powi(2);
            assert!((coef + 0.125).abs() <= 0.01, "ε = {e}: coefficient {coef} (expected −1/8)");
        }
        // Least-squares slope of log(rel) against log(ε).
        let lx: Vec<f64> = eps.iter().map(|e| e.ln()).collect();
        let ly: Vec<f64> = rel.iter().map(|r| r.ln()).collect();
        let (mx, my) = (lx.iter().sum::<f64>() / 4.0, ly.iter().sum::<f64>() / 4.0);
        let slope = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
            / lx.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
        eprintln!("S² small-loop holonomy (R = {radius}): relative errors {rel:?}, slope {slope:.4}");
        assert!((slope - 2.0).abs() <= 0.02, "slope {slope}");
    }
}

/// Parallel transport once around the circle of angular radius `alpha`
/// whose centre is `centre` (unit), starting at the point `start` (unit, at
/// angle `alpha` from `centre`), counter-clockwise about `centre`, with `steps`
/// RKMK4 steps of the bundle ODE (velocity from the ambient curve).
/// Returns (holonomy angle, return position error, max frame defect).
fn transport_around_circle(
    m: &Sphere2,
    centre: &Vector3<f64>,
    start: &Vector3<f64>,
    alpha: f64,
    steps: usize,
) -> (f64, f64, f64) {
    let radius = m.radius();
    let a = (start - centre * alpha.cos()) / alpha.sin();
    let b = centre.cross(&a);
    let vel = |t: f64| {
        let (s, c) = (TAU * t).sin_cos();
        (b * c - a * s) * (radius * alpha.sin() * TAU)
    };
    // Any frame at the start point.
    let q1 = a.cross(start).normalize();
    let q2 = start.cross(&q1);
    let g0 = m.from_frame(&(start * radius), &Matrix3x2::from_columns(&[q1, q2])).unwrap();
    let xi = |t: f64, g: &So3| {
        let q = m.frame_vectors(g);
        m.horizontal_lift(g, &(q.transpose() * vel(t)))
    };
    let h = 1.0 / steps as f64;
    let mut g = g0;
    let mut defect: f64 = 0.0;
    for i in 0..steps {
        g = rkmk4_step(&g, i as f64 * h, h, &xi);
        defect = defect.max(frame_defect(m, &g));
    }
    let w = m.frame_vectors(&g0).transpose() * m.frame_vectors(&g);
    let angle = w[(1, 0)].atan2(w[(0, 0)]);
    (angle, (m.position(&g) - start * radius).amax(), defect)
}

#[test]
fn sphere_transport_across_the_pole_gives_the_cap_holonomy() {
    // Circles through the north pole (started AT the pole, where the chart
    // ODE cannot even be set up), compared with the same circles rotated away
    // from both poles: the accuracy must be the same.
    let north = Vector3::z();
    let mut rng = Rng(2024);
    for &radius in &[1.0, 3.0] {
        let m = Sphere2::new(radius).unwrap();
        assert!(m.from_chart(&Vector2::new(0.0, 0.0), &Matrix2::identity()).is_err());
        for &alpha in &[0.3f64, 1.0, 2.0, 2.8] {
            let exact = TAU * (1.0 - alpha.cos());
            let centre = Vector3::new(alpha.sin(), 0.0, alpha.cos());
            let (angle, pos_err, defect) = transport_around_circle(&m, &centre, &north, alpha, 2000);
            let err = wrap(angle - exact).abs();
            // The same circle rigidly rotated to a generic place.
            let rot = So3::exp(&(rng.unit3() * 1.3));
            let (angle_r, _, _) = transport_around_circle(&m, &rot.act(&centre), &rot.act(&north), alpha, 2000);
            let err_r = wrap(angle_r - exact).abs();
            eprintln!(
                "S² cap holonomy R = {radius}, α = {alpha}: through pole err {err:.2e} (pos {pos_err:.2e}, defect {defect:.2e}); generic circle err {err_r:.2e}"
            );
            assert!(err <= 1e-12, "α = {alpha}: holonomy {angle} vs 2π(1 − cos α) = {exact} (mod 2π)");
            assert!(err_r <= 1e-12);
            assert!(pos_err <= 1e-12 * radius && defect <= 1e-14);
        }
    }
}
