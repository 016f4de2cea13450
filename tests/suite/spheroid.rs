//! The spheroid (ellipsoid of revolution): the manifold and bundle law suites
//! for an oblate, a prolate and a nearly spherical spheroid; closed forms
//! (curvature, area, Gauss–Bonnet) against independent expressions; `a = c`
//! against S²; and physics through the typed API — S² trajectories reproduced
//! for `a = c`, conservation of energy and `p_φ` to the method's order past and
//! through a pole, geodesics against Bessel's auxiliary-sphere solution, the
//! spin–curvature force, and a meridian crossing of the pole against an
//! independent one-dimensional reference.

use framedyn::body::{Affine, Gyroscope, Point};
use framedyn::bundle::FrameBundle;
use framedyn::dynamics::affine::AffineModel;
use framedyn::dynamics::gyroscope2::Z_ROTATION;
use framedyn::dynamics::{Gyroscope2Model, PointModel, System};
use framedyn::lie::{LieGroup, So3};
use framedyn::manifold::{Manifold, Sphere2, Spheroid};
use framedyn::method::Rkmk;
use framedyn::potential::{green_tensor, Free, Potential, Scalar};
use framedyn::solve::{solve, Options, Problem, Save};
use framedyn::Error;
use nalgebra::{Matrix2, Matrix3x2, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::bundle_laws::{check_bundle_at, random_walk_defect, small_loop_holonomy, transport_along, transport_in_chart};
use crate::manifold_laws::check_manifold_at;

// ---------------------------------------------------------------------------
// Shapes, independent closed forms, helpers
// ---------------------------------------------------------------------------

/// `(a, c)`: oblate, prolate, nearly spherical.
const SHAPES: [(f64, f64); 3] = [(1.0, 0.7), (1.0, 1.6), (1.0, 1.0 - 1e-6)];

fn spheroid(a: f64, c: f64) -> Spheroid {
    Spheroid::new(a, c).unwrap()
}

fn rot2(a: f64) -> Matrix2<f64> {
    let (s, c) = a.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// Geodesy's radii of curvature in the textbook form, with the first
/// eccentricity `e² = 1 − c²/a²` (negative for a prolate spheroid, where the
/// formulas stay real): `M = a(1 − e²)/(1 − e² sin²φ)^{3/2}`,
/// `N = a/(1 − e² sin²φ)^{1/2}`.
fn radii_textbook(a: f64, c: f64, lat: f64) -> (f64, f64) {
    let e2 = 1.0 - (c * c) / (a * a);
    let w2 = 1.0 - e2 * lat.sin().powi(2);
    (a * (1.0 - e2) / w2.powf(1.5), a / w2.sqrt())
}

/// `K = 1/(M N)` from [`radii_textbook`].
fn k_textbook(a: f64, c: f64, lat: f64) -> f64 {
    let (m, n) = radii_textbook(a, c, lat);
    1.0 / (m * n)
}

/// The point of the spheroid at geodetic latitude `lat`, longitude `lon`, by
/// the textbook formula `(N cos φ cos λ, N cos φ sin λ, N(1 − e²) sin φ)`.
fn point_textbook(a: f64, c: f64, lat: f64, lon: f64) -> Vector3<f64> {
    let (_, n) = radii_textbook(a, c, lat);
    let e2 = 1.0 - (c * c) / (a * a);
    Vector3::new(n * lat.cos() * lon.cos(), n * lat.cos() * lon.sin(), n * (1.0 - e2) * lat.sin())
}

/// `(x² + y²)/a² + z²/c² − 1`.
fn quadric(a: f64, c: f64, p: &Vector3<f64>) -> f64 {
    (p[0] * p[0] + p[1] * p[1]) / (a * a) + p[2] * p[2] / (c * c) - 1.0
}

/// Deterministic xorshift stream in [−1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn vec3(&mut self) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next())
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on `P_n`).
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut w) = (vec![0.0; n], vec![0.0; n]);
    let legendre = |z: f64| {
        let (mut p1, mut p2) = (1.0, 0.0);
        for j in 0..n {
            let p3 = p2;
            p2 = p1;
            p1 = ((2 * j + 1) as f64 * z * p2 - j as f64 * p3) / (j + 1) as f64;
        }
        (p1, n as f64 * (z * p1 - p2) / (z * z - 1.0))
    };
    for i in 0..n.div_ceil(2) {
        let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(z);
            let dz = p / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(z);
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// `∫_lo^hi f` by composite Gauss–Legendre (20 nodes) on `panels` panels.
fn integrate(f: impl Fn(f64) -> f64, lo: f64, hi: f64, panels: usize) -> f64 {
    let (x, w) = gauss_legendre(20);
    let h = (hi - lo) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = lo + (p as f64 + 0.5) * h;
        for (xi, wi) in x.iter().zip(&w) {
            sum += wi * f(mid + 0.5 * h * xi);
        }
    }
    sum * 0.5 * h
}

#[test]
fn the_quadrature_is_exact_on_known_integrals() {
    let (x, w) = gauss_legendre(20);
    assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
    assert!(x.windows(2).all(|p| p[0] < p[1]));
    assert!((integrate(f64::sin, 0.0, PI, 3) - 2.0).abs() < 1e-15);
    // ∫₀^{π/2} √(1 − k² sin²) with k² = 1/2: the complete elliptic integral E(1/√2).
    let e = integrate(|t| (1.0 - 0.5 * t.sin().powi(2)).sqrt(), 0.0, FRAC_PI_2, 4);
    assert!((e - 1.350_643_881_047_675_5).abs() < 1e-15, "{e}");
}

// ---------------------------------------------------------------------------
// Construction, typed errors, chart
// ---------------------------------------------------------------------------

#[test]
fn construction_errors_are_typed_and_name_the_field() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = Spheroid::new(bad, 1.0).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { field: "equatorial_radius", .. }), "{e:?}");
        let e = Spheroid::new(1.0, bad).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { field: "polar_radius", .. }), "{e:?}");
    }
    // The aspect-ratio limit 10³, both ways, and its message.
    assert!(Spheroid::new(2.0, 2.0e3).is_ok() && Spheroid::new(2.0, 2.0e-3).is_ok());
    for c in [2.01e3, 1.99e-3] {
        let e = Spheroid::new(2.0, c).unwrap_err();
        assert!(matches!(e, Error::InvalidParameter { field: "polar_radius", .. }), "{e:?}");
        assert!(e.to_string().contains("1e3"), "{e}");
    }
    let m = spheroid(1.0, 0.7);
    assert_eq!(<Spheroid as Manifold<2, 3>>::NAME, "spheroid");
    assert_eq!(m.coordinate_names(), ["lat", "lon"]);
    assert_eq!((m.equatorial_radius(), m.polar_radius()), (1.0, 0.7));
}

#[test]
fn the_chart_is_singular_exactly_at_the_poles() {
    for &(a, c) in &SHAPES {
        let m = spheroid(a, c);
        for lat in [FRAC_PI_2, -FRAC_PI_2, 2.0, FRAC_PI_2 - 1e-13] {
            let e = m.check_chart(&Vector2::new(lat, 0.4)).unwrap_err();
            assert!(matches!(e, Error::OutsideChart { manifold: "spheroid", .. }), "{lat}: {e:?}");
        }
        assert!(matches!(m.check_chart(&Vector2::new(f64::NAN, 0.0)), Err(Error::NotFinite { .. })));
        assert!(m.check_chart(&Vector2::new(FRAC_PI_2 - 1e-10, 100.0)).is_ok());
        for z in [c, -c] {
            let pole = Vector3::new(0.0, 0.0, z);
            assert!(matches!(m.chart(&pole), Err(Error::OutsideChart { .. })));
            let g = m.from_frame(&pole, &Matrix3x2::new(1.0, 0.0, 0.0, z.signum(), 0.0, 0.0)).unwrap();
            assert!(matches!(m.to_chart(&g), Err(Error::OutsideChart { .. })));
            assert_eq!(m.position(&g), pole);
        }
        // Off the surface, not finite: typed errors naming p.
        assert!(matches!(m.chart(&Vector3::new(a * 1.001, 0.0, 0.0)), Err(Error::Constraint { field: "p", .. })));
        assert!(matches!(m.chart(&Vector3::new(f64::NAN, 0.0, 0.0)), Err(Error::NotFinite { field: "p" })));
    }
}

#[test]
fn embedding_chart_and_radii_match_the_textbook_formulas() {
    let mut rng = Rng(0x5EED);
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6), (2.5, 0.02), (0.3, 250.0), (1.0, 1.0)] {
        let m = spheroid(a, c);
        for _ in 0..200 {
            let (lat, lon) = (0.999_999 * FRAC_PI_2 * rng.next(), PI * rng.next());
            let x = Vector2::new(lat, lon);
            let p = m.embed(&x);
            let scale = a.max(c);
            let ratio = (a / c).max(c / a);
            // The textbook form is conditioned like (a/c)² (1 − e² sin²φ near the
            // poles of a thin oblate spheroid).
            assert!((p - point_textbook(a, c, lat, lon)).amax() <= 1e-15 * scale * ratio * ratio, "{a} {c} {lat}");
            assert!(quadric(a, c, &p).abs() < 2e-15);
            // The textbook form loses (a/c)² digits to 1 − e² sin²φ near the
            // poles of a thin oblate spheroid.
            let (mm, nn) = radii_textbook(a, c, lat);
            let tol = 1e-14 * (a / c).max(1.0).powi(2);
            assert!((m.meridian_radius(lat) - mm).abs() <= tol * mm, "({a}, {c}) at {lat}: M = {} vs {mm}", m.meridian_radius(lat));
            assert!((m.prime_vertical_radius(lat) - nn).abs() <= tol * nn, "({a}, {c}) at {lat}: N = {} vs {nn}", m.prime_vertical_radius(lat));
            // chart ∘ embed, with the longitude conditioned like 1/cos φ.
            let back = m.chart(&p).unwrap();
            assert!((back[0] - lat).abs() < 2e-15 * ratio, "{lat} → {}", back[0]);
            assert!(((back[1] - lon) * lat.cos()).abs() < 1e-15, "{lon} → {}", back[1]);
            // The normal is the gradient of the quadric; the frame is ENU.
            let grad = Vector3::new(p[0] / (a * a), p[1] / (a * a), p[2] / (c * c)).normalize();
            assert!((m.normal(&x) - grad).amax() < 4e-15 * ratio);
            let e = m.ambient_frame(&x);
            let up: Vector3<f64> = e.column(0).cross(&e.column(1));
            assert!((up - m.normal(&x)).amax() < 1e-15);
        }
    }
}

#[test]
fn project_point_is_the_nearest_point() {
    let mut rng = Rng(0xBEEF);
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6), (1.0, 1.0 - 1e-6), (2.0, 0.01), (0.5, 300.0), (1.0, 1.0)] {
        let m = spheroid(a, c);
        let rmin = (a * a / c).min(c * c / a); // the smallest radius of curvature
        for i in 0..400 {
            let x = Vector2::new(FRAC_PI_2 * 0.999 * rng.next(), PI * rng.next());
            let (p0, n) = (m.embed(&x), m.normal(&x));
            // Along the normal, the foot point is the nearest point outside,
            // and inside up to the smallest radius of curvature.
            let delta = if i % 2 == 0 { 3.0 * a.max(c) * rng.next().abs() } else { -0.9 * rmin * rng.next().abs() };
            let q = m.project_point(&(p0 + n * delta));
            assert!((q - p0).amax() <= 1e-13 * a.max(c) * (a / c).max(c / a), "{a} {c} δ = {delta}: {q:?} vs {p0:?}");
            // Arbitrary points: on the surface, normal residual, and not
            // farther than any point of a fine sampling of the meridian.
            let p = match i % 4 {
                0 => rng.vec3() * (2.0 * a.max(c)),
                1 => rng.vec3() * (0.5 * a.min(c)),
                2 => Vector3::new(0.0, 0.0, c * rng.next()), // on the axis
                _ => Vector3::new(a * rng.next(), a * rng.next(), 0.0), // equatorial plane
            };
            let q = m.project_point(&p);
            assert!(quadric(a, c, &q).abs() < 2e-15 * (a / c).max(c / a), "defect {}", quadric(a, c, &q));
            assert!(m.point_defect(&q) < 2e-15);
            let d = (p - q).norm();
            let nq = m.normal_at(&q);
            let tangential = (p - q) - nq * nq.dot(&(p - q));
            assert!(tangential.norm() <= 1e-12 * a.max(c), "{p:?} → {q:?}: tangential {}", tangential.norm());
            let rho = p[0].hypot(p[1]);
            let best = (0..=20_000)
                .map(|k| {
                    let b = -FRAC_PI_2 + PI * k as f64 / 20_000.0;
                    (rho - a * b.cos()).hypot(p[2] - c * b.sin())
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d <= best + 1e-12 * a.max(c), "{p:?}: distance {d} > sampled {best}");
        }
    }
    // The defect: a radial scaling by s has defect |s − 1|.
    let m = spheroid(1.0, 0.7);
    let p = m.embed(&Vector2::new(0.6, 2.0));
    assert!((m.point_defect(&(p * 1.25)) - 0.25).abs() < 1e-15);
    assert!((m.point_defect(&(p * 0.5)) - 0.5).abs() < 1e-15);
    assert_eq!(m.point_defect(&Vector3::new(f64::NAN, 0.0, 0.0)), f64::INFINITY);
    assert!(m.project_point(&Vector3::new(f64::INFINITY, 0.0, 0.0)).iter().all(|v| v.is_nan()));
}

// ---------------------------------------------------------------------------
// Law suites
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// The manifold laws (Christoffel symbols and Riemann tensor against
    /// Ridders differences of the metric, frame and frame connection against
    /// their definitions, embedding and chart round trips) with the textbook
    /// `K = 1/(MN)`, on `|φ| ≤ 0.96·π/2` (the differences step 0.05 across
    /// the chart: they must not reach the pole), random size.
    #[test]
    fn manifold_laws(shape in 0..3usize, size in 0.3..3.0f64, t in -0.96..0.96f64, lon in -7.0..7.0f64) {
        let (a, c) = (SHAPES[shape].0 * size, SHAPES[shape].1 * size);
        let m = spheroid(a, c);
        let lat = t * FRAC_PI_2;
        let k = k_textbook(a, c, lat);
        prop_assert!((m.gaussian_curvature(lat) - k).abs() <= 1e-14 * k);
        let res = check_manifold_at(&m, &Vector2::new(lat, lon), |_, _| k, 1e-12);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
    }

    /// The bundle laws (chart round trips, from_frame, horizontal lift: ẋ = Σ
    /// v_a q_a and q̇_a normal, frame_velocity against differences, curvature_at
    /// = the Riemann tensor's sectional curvature, vertical generator) up to
    /// 1e-3 of the pole. The speed is scaled by the smallest radius of
    /// curvature min(M, N): the laws difference with a fixed step.
    #[test]
    fn bundle_laws(
        shape in 0..3usize, size in 0.3..3.0f64, t in -0.999..0.999f64, lon in -7.0..7.0f64,
        psi in -4.0..4.0f64, v in (-1.0..1.0f64, -1.0..1.0f64),
    ) {
        let (a, c) = (SHAPES[shape].0 * size, SHAPES[shape].1 * size);
        let m = spheroid(a, c);
        let lat = t * FRAC_PI_2;
        let r = m.meridian_radius(lat).min(m.prime_vertical_radius(lat));
        let res = check_bundle_at(&m, &Vector2::new(lat, lon), &rot2(psi), &(Vector2::new(v.0, v.1) * r), 1e-12);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
    }
}

#[test]
fn bundle_random_walk_stays_on_the_bundle() {
    for (i, &(a, c)) in SHAPES.iter().enumerate() {
        let m = spheroid(a, c);
        let g0 = m.from_chart(&Vector2::new(1.2, 0.4), &rot2(0.3)).unwrap();
        let worst = random_walk_defect(&m, &g0, 200_000, 0.05, 0xDEAD + i as u64);
        assert!(worst <= 1e-13, "({a}, {c}): frame defect {worst:e}");
    }
}

/// Parallel transport by the bundle's horizontal lift = the chart ODE
/// `V̇ = −Γ(ẋ)V` with the closed-form Christoffel symbols (themselves checked
/// against the metric by the law suite), along a wiggly curve.
#[test]
fn bundle_transport_agrees_with_the_chart_ode() {
    for &(a, c) in &SHAPES {
        let m = spheroid(a, c);
        let curve = |t: f64| {
            let lat = 0.2 + 1.1 * (TAU * t).sin();
            let dlat = 1.1 * TAU * (TAU * t).cos();
            let lon = 0.2 + 3.0 * t + 0.5 * (5.0 * t).sin();
            let dlon = 3.0 + 2.5 * (5.0 * t).cos();
            (Vector2::new(lat, lon), Vector2::new(dlat, dlon))
        };
        let u0 = rot2(0.7);
        let (x0, _) = curve(0.0);
        let g0 = m.from_chart(&x0, &u0).unwrap();
        let g1 = transport_along(&m, &g0, &curve, 4000);
        let v1 = transport_in_chart(&m, &(m.frame(&x0) * u0), &curve, 4000);
        let (x1, _) = curve(1.0);
        let q_chart = Matrix3x2::from_columns(&[m.embed_tangent(&x1, &v1.column(0).into()), m.embed_tangent(&x1, &v1.column(1).into())]);
        let err = (m.frame_vectors(&g1) - q_chart).amax();
        assert!(err < 1e-10, "({a}, {c}): transported frames differ by {err:e}");
        assert!((m.position(&g1) - m.embed(&x1)).amax() < 1e-10);
    }
}

/// The holonomy of small loops approaches `K πε²` quadratically (Gauss–Bonnet),
/// at latitudes up to 1.5 (0.07 from the pole).
#[test]
fn small_loop_holonomy_is_the_enclosed_curvature() {
    for &(a, c) in &SHAPES {
        let m = spheroid(a, c);
        for lat in [-1.2, 0.0, 0.7, 1.5] {
            let x0 = Vector2::new(lat, 0.3);
            let rel = |eps: f64| {
                let (angle, expected) = small_loop_holonomy(&m, &x0, eps, 4000);
                (angle - expected) / expected
            };
            let (r1, r2) = (rel(2e-3), rel(1e-3));
            assert!(r1.abs() < 1e-4, "({a}, {c}) at {lat}: relative holonomy error {r1:e}");
            assert!(r2.abs() < 0.3 * r1.abs() || r2.abs() < 1e-8, "({a}, {c}) at {lat}: {r1:e} → {r2:e} is not O(ε²)");
        }
    }
}

// ---------------------------------------------------------------------------
// Closed forms
// ---------------------------------------------------------------------------

/// `K` four ways: the inherent closed form, `1/(M N)` with the textbook radii,
/// the sectional curvature of the Riemann tensor, and the bundle's
/// `curvature_at` (from the normal alone), up to 1e-9 from the poles; at the
/// poles themselves (through `from_frame`) `K = c²/a⁴`, at the equator `1/c²`.
#[test]
fn gaussian_curvature_four_ways() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6), (1.0, 1.0 - 1e-6), (3.0, 0.01), (0.2, 100.0)] {
        let m = spheroid(a, c);
        for i in 0..=200 {
            let lat = (FRAC_PI_2 - 1e-9) * (2.0 * i as f64 / 200.0 - 1.0);
            let x = Vector2::new(lat, 0.7 - i as f64);
            let k = m.gaussian_curvature(lat);
            let k_mn = k_textbook(a, c, lat);
            let k_mn_own = 1.0 / (m.meridian_radius(lat) * m.prime_vertical_radius(lat));
            let fr = m.frame(&x);
            let k_riemann = m.sectional_curvature(&x, &fr.column(0).into(), &fr.column(1).into());
            let k_chart = m.sectional_curvature(&x, &Vector2::new(1.0, 0.0), &Vector2::new(0.0, 1.0));
            let k_bundle = m.curvature_at(&m.from_chart(&x, &rot2(0.2 * i as f64)).unwrap());
            // The textbook form loses (a/c)² digits to 1 − e² sin²φ on a thin oblate spheroid.
            for (name, other, tol) in
                [("1/(MN) textbook", k_mn, 2e-14 * (a / c).max(1.0).powi(2)), ("1/(MN)", k_mn_own, 1e-15), ("Riemann, frame", k_riemann, 1e-14), ("Riemann, chart", k_chart, 1e-13), ("bundle", k_bundle, 1e-14)]
            {
                assert!((k - other).abs() <= tol * k, "({a}, {c}) at {lat}: K = {k} vs {name} {other}");
            }
        }
        assert!((m.gaussian_curvature(0.0) - 1.0 / (c * c)).abs() <= 1e-15 / (c * c));
        for z in [c, -c] {
            let g = m.from_frame(&Vector3::new(0.0, 0.0, z), &Matrix3x2::new(1.0, 0.0, 0.0, z.signum(), 0.0, 0.0)).unwrap();
            let kp = c * c / a.powi(4);
            assert!((m.curvature_at(&g) - kp).abs() <= 1e-15 * kp, "pole: {} vs {kp}", m.curvature_at(&g));
        }
    }
}

/// Gauss–Bonnet: `∫K dA = 4π` with `K` from the Riemann tensor and `dA` from
/// the metric's determinant (Gauss–Legendre in latitude); and the area `∫dA`
/// equals the classical closed forms of the oblate and prolate spheroid.
#[test]
fn gauss_bonnet_and_the_area() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6), (1.0, 1.0 - 1e-6), (2.0, 0.05), (0.5, 40.0)] {
        let m = spheroid(a, c);
        let sqrt_g = |lat: f64| m.metric(&Vector2::new(lat, 0.0)).determinant().sqrt();
        let k_riemann = |lat: f64| {
            let x = Vector2::new(lat, 0.0);
            m.sectional_curvature(&x, &Vector2::new(1.0, 0.0), &Vector2::new(0.0, 1.0))
        };
        let total = TAU * integrate(|lat| k_riemann(lat) * sqrt_g(lat), -FRAC_PI_2, FRAC_PI_2, 64);
        assert!((total - 2.0 * TAU).abs() < 1e-12, "({a}, {c}): ∫K dA = {total}");
        // The area element is peaked (width ~min(c/a, a/c)) at the poles of a
        // thin oblate and the equator of a thin prolate spheroid: 256 panels.
        let area = TAU * integrate(|lat| sqrt_g(lat), -FRAC_PI_2, FRAC_PI_2, 256);
        let exact = if c < a {
            let e = (1.0 - (c / a).powi(2)).sqrt();
            TAU * a * a * (1.0 + (1.0 - e * e) / e * e.atanh())
        } else if c > a {
            let e = (1.0 - (a / c).powi(2)).sqrt();
            TAU * a * a * (1.0 + c / (a * e) * e.asin())
        } else {
            2.0 * TAU * a * a
        };
        // The closed forms cancel like 1/e² near the sphere.
        let tol = if (a - c).abs() < 1e-3 { 1e-9 } else { 1e-11 };
        assert!((area - exact).abs() < tol * exact, "({a}, {c}): area {area} vs {exact}");
    }
}

/// `a = c = R` is S² exactly: embedding, metric (with `r = R(π/2 − φ)`),
/// Christoffel symbols, curvature, frame `(east, north) = (E_φ, −E_r)`, frame
/// connection; and on the bundle the same element `Q` has the same position,
/// frame, horizontal lift, frame velocities and curvature.
#[test]
fn equal_radii_give_the_sphere() {
    let r = 1.3;
    let (sp, s2) = (spheroid(r, r), Sphere2::new(r).unwrap());
    let mut rng = Rng(0xC0DE);
    for _ in 0..500 {
        let (lat, lon) = (0.99 * FRAC_PI_2 * rng.next(), PI * rng.next());
        let (x, xs) = (Vector2::new(lat, lon), Vector2::new(r * (FRAC_PI_2 - lat), lon));
        let tight = 4.0 * f64::EPSILON;
        assert!((sp.embed(&x) - s2.embed(&xs)).amax() <= tight * r);
        let jac = Matrix2::new(-r, 0.0, 0.0, 1.0); // ∂(r, φ)/∂(lat, lon)
        let g_s2 = jac.transpose() * s2.metric(&xs) * jac;
        assert!((sp.metric(&x) - g_s2).amax() <= tight * r * r);
        let (gam, gam_s2) = (sp.christoffel(&x), s2.christoffel(&xs));
        assert!((gam[0][1][1] - gam_s2[0][1][1] * (-1.0 / r)).abs() <= 1e-15 * (1.0 + gam[0][1][1].abs()));
        // −tan φ against cot ϑ · (−R): the change of chart rounds φ by ~ε, and
        // tan is conditioned like 1 + tan².
        assert!((gam[1][0][1] - gam_s2[1][0][1] * (-r)).abs() <= 1e-15 * (1.0 + gam[1][0][1].powi(2)));
        assert_eq!(gam[0][0][0], 0.0);
        assert!((sp.gaussian_curvature(lat) - s2.curvature()).abs() <= tight * s2.curvature());
        let (e, es) = (sp.ambient_frame(&x), s2.ambient_frame(&xs));
        assert!((e.column(0) - es.column(1)).amax() <= tight && (e.column(1) + es.column(0)).amax() <= tight);
        let (fc, fcs) = (sp.frame_connection(&x), s2.frame_connection(&xs));
        // ∇_east east = (tan φ/R) north; on S²: ∇_{E_φ} E_φ = Γ^r_φφ E_r = −Γ^r_φφ north.
        assert!((fc[1][0][0] + fcs[0][1][1]).abs() * r <= 1e-15 * (1.0 + (fc[1][0][0] * r).powi(2)));

        // The bundle: the same rotation Q on both.
        let q = So3::exp(&(rng.vec3() * 3.0));
        let u = Vector2::new(rng.next(), rng.next());
        let (lift, lift_s2) = (sp.horizontal_lift(&q, &u), s2.horizontal_lift(&q, &u));
        assert!((lift - lift_s2).amax() <= 4.0 * tight * lift_s2.amax(), "{lift:?} vs {lift_s2:?}");
        assert!((sp.position(&q) - s2.position(&q)).amax() <= tight * r);
        assert_eq!(sp.frame_vectors(&q), s2.frame_vectors(&q));
        // K = |n|⁴/c²: |n|² = 1 only to a few ulps for a computed rotation.
        assert!((sp.curvature_at(&q) - s2.curvature_at(&q)).abs() <= 4.0 * tight * s2.curvature());
        let xi = rng.vec3();
        let ((xd, qd), (xd2, qd2)) = (sp.frame_velocity(&q, &xi), s2.frame_velocity(&q, &xi));
        assert!((xd - xd2).amax() <= 4.0 * tight * r * xi.amax() && (qd - qd2).amax() == 0.0);
    }
}

// ---------------------------------------------------------------------------
// Physics: potentials and drivers
// ---------------------------------------------------------------------------

/// A test potential: `tilt·z + well·z²` (height field), `dipole·e₁_z` (a
/// frame coupling invariant under rotations about z), `shear·x·e₂_y` (a frame
/// coupling that breaks the axial symmetry) and the elastic
/// `elastic·(1/√det G + tr G/2)` of the Green tensor.
#[derive(Debug, Clone, Copy, Default)]
struct Field {
    tilt: f64,
    well: f64,
    dipole: f64,
    shear: f64,
    elastic: f64,
}

impl Potential<2, 3> for Field {
    fn uses_frame(&self) -> bool {
        self.dipole != 0.0 || self.shear != 0.0 || self.elastic != 0.0
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, m: &SMatrix<f64, 3, 3>) -> D {
        let mut v = x[2] * self.tilt + x[2] * x[2] * self.well;
        if self.dipole != 0.0 {
            v += e[(2, 0)] * self.dipole;
        }
        if self.shear != 0.0 {
            v += x[0] * e[(1, 1)] * self.shear;
        }
        if self.elastic != 0.0 {
            let g = green_tensor(e, m);
            let det = g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)];
            v += (det.sqrt().recip() + (g[(0, 0)] + g[(1, 1)]) * 0.5) * self.elastic;
        }
        v
    }
}

/// All saved `(t, y)` of a fixed-step RKMK4 run.
fn run_rk4<S: System + Clone>(sys: &S, y0: S::State, t_end: f64, h: f64) -> (Vec<f64>, Vec<S::State>)
where
    S::State: framedyn::method::GroupNumerics,
{
    let problem = Problem::new(sys.clone(), y0, (0.0, t_end)).unwrap();
    let sol = solve(&problem, &Rkmk::rk4(), &Options::fixed(h)).unwrap();
    (sol.times().to_vec(), sol.states().to_vec())
}

/// Distance of `p` from the nearer pole `(0, 0, ±c)`.
fn pole_distance(c: f64, p: &Vector3<f64>) -> f64 {
    (p - Vector3::new(0.0, 0.0, c.copysign(p[2]))).norm()
}

// ---------------------------------------------------------------------------
// (a) a = c = R reproduces the S² trajectories
// ---------------------------------------------------------------------------

/// A sampled trajectory: position, velocity, body frame, energy.
type Samples = Vec<(Vector3<f64>, Vector3<f64>, Matrix3x2<f64>, f64)>;

/// Checks that two sampled trajectories (same times) agree to 1e-12 in every
/// quantity, and that they went somewhere (≥ 0.5 from the start).
fn assert_same(what: &str, a: &Samples, b: &Samples) {
    assert_eq!(a.len(), b.len());
    let mut w = [0.0f64; 4];
    for (p, q) in a.iter().zip(b) {
        w[0] = w[0].max((p.0 - q.0).amax());
        w[1] = w[1].max((p.1 - q.1).amax());
        w[2] = w[2].max((p.2 - q.2).amax());
        w[3] = w[3].max((p.3 - q.3).abs());
    }
    let moved = a.iter().map(|p| (p.0 - a[0].0).norm()).fold(0.0, f64::max);
    eprintln!("{what}: a = c vs S²: position {:.1e}, velocity {:.1e}, frame {:.1e}, energy {:.1e} (moved {moved:.2})", w[0], w[1], w[2], w[3]);
    assert!(moved > 0.5, "{what}: the trajectory must go somewhere (moved {moved})");
    for (name, v) in ["position", "velocity", "frame", "energy"].iter().zip(w) {
        assert!(v <= 1e-12, "{what}: {name} differs by {v:e}");
    }
}

#[test]
fn equal_radii_reproduce_the_sphere_trajectories() {
    let r = 1.3;
    let (sp, s2) = (spheroid(r, r), Sphere2::new(r).unwrap());
    let p = s2.embed(&Vector2::new(0.7, 0.4));
    let e_s2 = s2.ambient_frame(&Vector2::new(0.7, 0.4)) * rot2(0.9);
    let v = e_s2 * Vector2::new(0.8, -0.5);
    let (t_end, h) = (6.0, 0.01);

    // The point, in a height field.
    let height = Field { tilt: 0.6, well: 0.3, ..Field::default() };
    let pm = |b: Spheroid| PointModel::new(b, Point::new(1.2).unwrap(), height).unwrap();
    let pm2 = PointModel::new(s2, Point::new(1.2).unwrap(), height).unwrap();
    let (msp, ms2) = (pm(sp), pm2);
    let (_, ya) = run_rk4(&msp, msp.state(&p, &v).unwrap(), t_end, h);
    let (_, yb) = run_rk4(&ms2, ms2.state(&p, &v).unwrap(), t_end, h);
    let sa: Samples = ya.iter().map(|y| (msp.position(y), msp.velocity(y), Matrix3x2::zeros(), msp.energy(y))).collect();
    let sb: Samples = yb.iter().map(|y| (ms2.position(y), ms2.velocity(y), Matrix3x2::zeros(), ms2.energy(y))).collect();
    assert_same("point", &sa, &sb);

    // The gyroscope with a frame coupling that breaks the axial symmetry.
    let field = Field { tilt: 0.6, well: 0.3, dipole: 0.4, shear: 0.35, ..Field::default() };
    let body = Gyroscope::<2>::isotropic(1.2, 0.3).unwrap();
    let gsp = Gyroscope2Model::new(sp, body, field).unwrap();
    let gs2 = Gyroscope2Model::new(s2, body, field).unwrap();
    let (y0a, y0b) = (gsp.state(&p, &v, &e_s2, 0.7).unwrap(), gs2.state(&p, &v, &e_s2, 0.7).unwrap());
    let (_, ya) = run_rk4(&gsp, y0a, t_end, h);
    let (_, yb) = run_rk4(&gs2, y0b, t_end, h);
    let sa: Samples = ya.iter().map(|y| (gsp.position(y), gsp.velocity(y), gsp.body_frame(y), gsp.energy(y))).collect();
    let sb: Samples = yb.iter().map(|y| (gs2.position(y), gs2.velocity(y), gs2.body_frame(y), gs2.energy(y))).collect();
    assert_same("gyroscope, RKMK4", &sa, &sb);
    // The same with adaptive DOP853, sampled by its dense output.
    let times: Vec<f64> = (0..=60).map(|k| t_end * k as f64 / 60.0).collect();
    let opts = || Options::adaptive(1e-10, 1e-10).save(Save::At(times.clone()));
    let sol_a = solve(&Problem::new(gsp.clone(), y0a, (0.0, t_end)).unwrap(), &Rkmk::dop853(), &opts()).unwrap();
    let sol_b = solve(&Problem::new(gs2.clone(), y0b, (0.0, t_end)).unwrap(), &Rkmk::dop853(), &opts()).unwrap();
    let sa: Samples = sol_a.states().iter().map(|y| (gsp.position(y), gsp.velocity(y), gsp.body_frame(y), gsp.energy(y))).collect();
    let sb: Samples = sol_b.states().iter().map(|y| (gs2.position(y), gs2.velocity(y), gs2.body_frame(y), gs2.energy(y))).collect();
    assert_same("gyroscope, DOP853", &sa, &sb);

    // The affine body: each bundle starts from its own reference frame (the
    // chart frames (east, north) and (E_r, E_φ), rotated differently), so ρ,
    // ρ̇ and u are converted: e = q_s ρ_s = q_e ρ_e ⇒ ρ_e = (q_eᵀ q_s) ρ_s.
    let field = Field { tilt: 0.6, well: 0.3, dipole: 0.4, shear: 0.35, elastic: 0.8 };
    let j = Matrix2::new(0.3, 0.05, 0.05, 0.2);
    let asp = AffineModel::new(sp, Affine::new(1.2, j).unwrap(), field).unwrap();
    let as2 = AffineModel::new(s2, Affine::new(1.2, j).unwrap(), field).unwrap();
    let (lat, lon) = (0.35, -0.8);
    let gs = s2.from_chart(&Vector2::new(r * (FRAC_PI_2 - lat), lon), &rot2(0.3)).unwrap();
    let ge = sp.from_chart(&Vector2::new(lat, lon), &rot2(-1.1)).unwrap();
    assert!((s2.position(&gs) - sp.position(&ge)).amax() < 1e-15);
    let w = sp.frame_vectors(&ge).transpose() * s2.frame_vectors(&gs);
    assert!((w.transpose() * w - Matrix2::identity()).amax() < 1e-15 && (w - Matrix2::identity()).amax() > 0.1);
    let (rho, rho_dot, u) = (Matrix2::new(1.1, 0.2, -0.1, 0.9), Matrix2::new(0.1, -0.3, 0.25, -0.05), Vector2::new(0.6, 0.4));
    let y0b = as2.state(&gs, &rho, &u, &rho_dot).unwrap();
    let y0a = asp.state(&ge, &(w * rho), &(w * u), &(w * rho_dot)).unwrap();
    assert!((asp.body_frame(&y0a) - as2.body_frame(&y0b)).amax() < 1e-15);
    let (_, ya) = run_rk4(&asp, y0a, t_end, h);
    let (_, yb) = run_rk4(&as2, y0b, t_end, h);
    let sa: Samples = ya.iter().map(|y| (asp.position(y), asp.velocity(y), asp.body_frame(y), asp.energy(y))).collect();
    let sb: Samples = yb.iter().map(|y| (as2.position(y), as2.velocity(y), as2.body_frame(y), as2.energy(y))).collect();
    assert_same("affine body", &sa, &sb);
}

// ---------------------------------------------------------------------------
// (b) conservation of energy and p_φ to the method's order, past and through a pole
// ---------------------------------------------------------------------------

/// Least-squares slope of `log e` against `log h`.
fn slope(hs: &[f64], es: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = (hs.iter().map(|h| h.ln()).collect(), es.iter().map(|e| e.ln()).collect());
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Runs RKMK4 at `h`, `h/2`, `h/4` over `[0, t_end]` and checks that
/// the largest drifts of the energy and of `p_φ` converge with order 4
/// (least-squares slope within ±0.35, every drift above the round-off floor
/// 1e-14; where `p_φ` starts at exactly 0 — a point leaving the pole — it must
/// stay 0 to round-off instead). Returns the closest approach to a pole — the step of the finest
/// run nearest to it, refined by re-integrating the two steps around it with
/// 200 substeps each — and the failed checks.
fn conservation_order<S>(
    what: &str,
    sys: &S,
    y0: S::State,
    c: f64,
    t_end: f64,
    h: f64,
    p_phi: impl Fn(&S::State) -> f64,
    position: impl Fn(&S::State) -> Vector3<f64>,
) -> (f64, Vec<String>)
where
    S: System + Clone,
    S::State: framedyn::method::GroupNumerics,
{
    let hs: Vec<f64> = (0..3).map(|k| h / f64::powi(2.0, k)).collect();
    let zero_p_phi = p_phi(&y0) == 0.0;
    let (mut de, mut dp) = (Vec::new(), Vec::new());
    let (e0, p0) = (sys.energy(&y0), p_phi(&y0));
    let mut finest = Vec::new();
    for &hh in &hs {
        let (_, ys) = run_rk4(sys, y0, t_end, hh);
        de.push(ys.iter().map(|y| (sys.energy(y) - e0).abs()).fold(0.0, f64::max));
        dp.push(ys.iter().map(|y| (p_phi(y) - p0).abs()).fold(0.0, f64::max));
        finest = ys;
    }
    let dist: Vec<f64> = finest.iter().map(|y| pole_distance(c, &position(y))).collect();
    let i = (0..dist.len()).min_by(|&i, &j| dist[i].total_cmp(&dist[j])).unwrap();
    let h_fine = *hs.last().unwrap();
    let (_, around) = run_rk4(sys, finest[i.saturating_sub(1)], 2.0 * h_fine, h_fine / 200.0);
    let closest = around.iter().map(|y| pole_distance(c, &position(y))).fold(dist[i], f64::min);
    let (se, sp) = (slope(&hs, &de), slope(&hs, &dp));
    let fmt = |v: &[f64]| v.iter().map(|x| format!("{x:.1e}")).collect::<Vec<_>>().join(", ");
    eprintln!("{what}: closest to a pole {closest:.1e}; energy drifts [{}] (order {se:.2}); p_φ drifts [{}] (order {sp:.2})", fmt(&de), fmt(&dp));
    let mut failures = Vec::new();
    for (name, d, s) in [("energy", &de, se), ("p_φ", &dp, sp)] {
        if name == "p_φ" && zero_p_phi {
            // A point started at the pole moves in a meridian plane: p_φ = 0
            // exactly, and the discrete flow keeps it to round-off.
            if !d.iter().all(|&x| x < 1e-14) {
                failures.push(format!("{what}: p_φ = 0 initially drifts by {d:?}"));
            }
            continue;
        }
        if !d.iter().all(|&x| x > 1e-14) {
            failures.push(format!("{what}: {name} drifts {d:?} reach the round-off floor: no order measurable"));
        }
        if !((s - 4.0).abs() <= 0.35) {
            failures.push(format!("{what}: {name} drift converges with order {s:.2}, not 4 ({d:?})"));
        }
    }
    (closest, failures)
}

/// Initial conditions at `lat₁ = 0.3`, `λ₁ = 0.2` for a body of mass `mass`
/// and (constant) spin `spin`: speed `speed`, mostly north, with the east
/// component chosen from `p_φ = m ρ v_east + s n_z` so that near the north
/// pole, where `p_φ ≈ s + m ρ v`, the closest approach to the axis is about
/// `rho_min`. Returns `(p, v, e)`: position, velocity, ENU frame.
fn near_pole_start(m: &Spheroid, mass: f64, spin: f64, speed: f64, rho_min: f64) -> (Vector3<f64>, Vector3<f64>, Matrix3x2<f64>) {
    let x = Vector2::new(0.3, 0.2);
    let p = m.embed(&x);
    let n = m.normal(&x);
    let e = m.ambient_frame(&x);
    let rho1 = p[0].hypot(p[1]);
    let v_east = (spin * (1.0 - n[2]) + mass * rho_min * speed) / (mass * rho1);
    let v_north = (speed * speed - v_east * v_east).sqrt();
    (p, e * Vector2::new(v_east, v_north), e)
}

/// Energy and `p_φ` (the rotations about the symmetry axis; Clairaut's
/// integral for geodesics) are conserved to the order of RKMK4 by the point,
/// the gyroscope and the affine body on an oblate and a prolate spheroid in
/// axially symmetric potentials, on trajectories that pass within 1e-3 of the
/// north pole (spin kept constant there, so that `p_φ` aims them) and on
/// trajectories that start exactly at the pole (with a frame coupling that
/// exchanges spin and orbital momentum).
#[test]
fn energy_and_p_phi_converge_with_order_four_past_and_through_a_pole() {
    let mut failures = Vec::new();
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6)] {
        let m = spheroid(a, c);
        let pole = Vector3::new(0.0, 0.0, c);
        let pole_frame = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        let v_pole = Vector3::new(1.3, 0.9, 0.0);
        let axial = Field { tilt: -0.3, well: 0.2, ..Field::default() };
        let coupled = Field { dipole: 0.3, ..axial };
        let (t_end, h) = (6.0, 0.02);

        // The point, in V = −0.3 z + 0.2 z².
        let pm = PointModel::new(m, Point::new(1.0).unwrap(), axial).unwrap();
        let (p, v, _) = near_pole_start(&m, 1.0, 0.0, 2.0, 4e-4);
        let (d, f) = conservation_order(
            &format!("point ({a}, {c}), past the pole"),
            &pm,
            pm.state(&p, &v).unwrap(),
            c,
            t_end,
            h,
            |y| pm.momentum_map(y, &Z_ROTATION).unwrap(),
            |y| pm.position(y),
        );
        failures.extend(f);
        assert!(d <= 1e-3, "point ({a}, {c}): closest approach to the pole {d:e}");
        let (_, f) = conservation_order(
            &format!("point ({a}, {c}), from the pole"),
            &pm,
            pm.state(&pole, &v_pole).unwrap(),
            c,
            t_end,
            h,
            |y| pm.momentum_map(y, &Z_ROTATION).unwrap(),
            |y| pm.position(y),
        );
        failures.extend(f);

        // The gyroscope.
        let body = Gyroscope::<2>::isotropic(1.0, 0.3).unwrap();
        let gm = Gyroscope2Model::new(m, body, axial).unwrap();
        let (p, v, e) = near_pole_start(&m, 1.0, 0.5, 2.0, 4e-4);
        let y0 = gm.state(&p, &v, &e, 0.5).unwrap();
        let (d, f) = conservation_order(&format!("gyroscope ({a}, {c}), past the pole"), &gm, y0, c, t_end, h, |y| gm.p_phi(y), |y| gm.position(y));
        failures.extend(f);
        assert!(d <= 1e-3, "gyroscope ({a}, {c}): closest approach to the pole {d:e}");
        let gm = Gyroscope2Model::new(m, body, coupled).unwrap();
        let y0 = gm.state(&pole, &v_pole, &pole_frame, 0.5).unwrap();
        let (_, f) = conservation_order(&format!("gyroscope ({a}, {c}), from the pole"), &gm, y0, c, t_end, h, |y| gm.p_phi(y), |y| gm.position(y));
        failures.extend(f);

        // The affine body (elastic: its torque is symmetric and the spin constant).
        let affine = Affine::new(1.0, Matrix2::new(0.3, 0.04, 0.04, 0.2)).unwrap();
        let am = AffineModel::new(m, affine, Field { elastic: 1.0, ..axial }).unwrap();
        let g = m.from_chart(&Vector2::new(0.3, 0.2), &Matrix2::identity()).unwrap();
        let (rho, rho_dot) = (Matrix2::new(1.05, 0.1, -0.05, 0.95), Matrix2::new(0.0, -0.6, 0.6, 0.1));
        let spin = am.spin(&am.state(&g, &rho, &Vector2::zeros(), &rho_dot).unwrap())[(0, 1)];
        let (_, v, _) = near_pole_start(&m, 1.0, spin, 2.0, 4e-4);
        let y0 = am.state(&g, &rho, &(m.frame_vectors(&g).transpose() * v), &rho_dot).unwrap();
        let (d, f) = conservation_order(&format!("affine ({a}, {c}), past the pole"), &am, y0, c, t_end, h, |y| am.p_phi(y), |y| am.position(y));
        failures.extend(f);
        assert!(d <= 1e-3, "affine ({a}, {c}): closest approach to the pole {d:e}");
        let am = AffineModel::new(m, affine, Field { elastic: 1.0, ..coupled }).unwrap();
        let gp = m.from_frame(&pole, &pole_frame).unwrap();
        let y0 = am.state(&gp, &rho, &Vector2::new(1.3, 0.9), &rho_dot).unwrap();
        let (_, f) = conservation_order(&format!("affine ({a}, {c}), from the pole"), &am, y0, c, t_end, h, |y| am.p_phi(y), |y| am.position(y));
        failures.extend(f);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------
// (c) geodesics against Bessel's auxiliary sphere
// ---------------------------------------------------------------------------

/// A geodesic of the spheroid by Bessel's method, independent of the bundle.
///
/// Points are mapped to the unit "auxiliary sphere" by the reduced latitude
/// `β` (`(ρ, z) = (a cos β, c sin β)`, `tan β = (c/a) tan φ`). Clairaut's
/// integral `ρ sin α = a cos β sin α = a sin α₀` is the one of a great circle
/// on the auxiliary sphere with the same azimuths, and since the meridian arc
/// is `√(a² sin²β + c² cos²β) dβ` while `dβ = cos α dσ` on the auxiliary
/// sphere, the geodesic is the image of the great circle through the node
/// (northward equator crossing) with azimuth `α₀`, arc `σ` from the node:
///
/// ```text
/// sin β = cos α₀ sin σ,   (cos β cos ω, cos β sin ω) = (cos σ, sin α₀ sin σ),
/// ds/dσ = √(a² sin²β + c² cos²β) = c √(1 + k² sin²σ),   k² = (a² − c²)/c² · cos²α₀,
/// dλ = (ds/dσ)/a · dω  ⇒  λ = λ_node + ω − Δ(σ),
/// Δ(σ) = (1 − c²/a²) sin α₀ ∫₀^σ dσ′ / (1 + √(sin²β + (c²/a²) cos²β)),
/// ```
///
/// the last from `dω = sin α₀ dσ/cos²β` and `√(1 − (1 − c²/a²) cos²β) − 1 =
/// −(1 − c²/a²) cos²β/(1 + √…)`: no singularity at the vertices. For a
/// prolate spheroid `k² ∈ (−1, 0]` and `1 − c²/a² < 0`; nothing changes. The
/// position is `(a R_z(λ_node − Δ)(cos σ, sin α₀ sin σ), c cos α₀ sin σ)`. Both
/// integrands have period π; they are integrated by 20-point Gauss–Legendre
/// on panels of width π/16, accumulated once.
struct Bessel {
    a: f64,
    c: f64,
    sa0: f64,
    ca0: f64,
    lon_node: f64,
    k2: f64,
    q2: f64,
    f: f64,
    panel: f64,
    nodes: (Vec<f64>, Vec<f64>),
    cum_s: Vec<f64>,
    cum_d: Vec<f64>,
}

impl Bessel {
    fn new(a: f64, c: f64, alpha0: f64, lon_node: f64, sigma_max: f64) -> Self {
        let (sa0, ca0) = alpha0.sin_cos();
        let q2 = (c / a).powi(2);
        let mut b = Bessel {
            a,
            c,
            sa0,
            ca0,
            lon_node,
            k2: (a - c) * (a + c) / (c * c) * ca0 * ca0,
            q2,
            f: (a - c) * (a + c) / (a * a),
            panel: PI / 16.0,
            nodes: gauss_legendre(20),
            cum_s: vec![0.0],
            cum_d: vec![0.0],
        };
        let panels = (sigma_max / b.panel).ceil() as usize + 1;
        for k in 0..panels {
            let (lo, hi) = (k as f64 * b.panel, (k + 1) as f64 * b.panel);
            let (s, d) = (b.gl(|x| b.ds(x), lo, hi), b.gl(|x| b.dd(x), lo, hi));
            b.cum_s.push(b.cum_s[k] + s);
            b.cum_d.push(b.cum_d[k] + d);
        }
        b
    }
    fn gl(&self, f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        self.nodes.0.iter().zip(&self.nodes.1).map(|(x, w)| w * f(mid + half * x)).sum::<f64>() * half
    }
    /// `ds/dσ`.
    fn ds(&self, sigma: f64) -> f64 {
        self.c * (1.0 + self.k2 * sigma.sin().powi(2)).sqrt()
    }
    /// `dΔ/dσ`.
    fn dd(&self, sigma: f64) -> f64 {
        let sb2 = (self.ca0 * sigma.sin()).powi(2);
        self.f * self.sa0 / (1.0 + (sb2 + self.q2 * (1.0 - sb2)).sqrt())
    }
    /// `(s(σ), Δ(σ))`, `σ ≥ 0`.
    fn integrals(&self, sigma: f64) -> (f64, f64) {
        assert!(sigma >= 0.0);
        let k = (sigma / self.panel).floor() as usize;
        assert!(k + 1 < self.cum_s.len(), "σ = {sigma} beyond the table");
        let lo = k as f64 * self.panel;
        (self.cum_s[k] + self.gl(|x| self.ds(x), lo, sigma), self.cum_d[k] + self.gl(|x| self.dd(x), lo, sigma))
    }
    fn position(&self, sigma: f64) -> Vector3<f64> {
        let (_, delta) = self.integrals(sigma);
        let (st, ct) = (self.lon_node - delta).sin_cos();
        let (s, c) = sigma.sin_cos();
        let (u, v) = (c, self.sa0 * s);
        Vector3::new(self.a * (ct * u - st * v), self.a * (st * u + ct * v), self.c * self.ca0 * s)
    }
    /// The unit tangent `dX/ds`.
    fn tangent(&self, sigma: f64) -> Vector3<f64> {
        let (_, delta) = self.integrals(sigma);
        let (st, ct) = (self.lon_node - delta).sin_cos();
        let (s, c) = sigma.sin_cos();
        let rot = |u: f64, v: f64| (ct * u - st * v, st * u + ct * v);
        let (ru, rv) = rot(-s, self.sa0 * c);
        let (pu, pv) = rot(c, self.sa0 * s);
        let dd = self.dd(sigma);
        Vector3::new(self.a * (ru + dd * pv), self.a * (rv - dd * pu), self.c * self.ca0 * c) / self.ds(sigma)
    }
    /// `σ` with `s(σ) = s`, by Newton's method (`ds/dσ ≥ c√(1 − |k²|) > 0`).
    fn sigma_of(&self, s: f64, guess: f64) -> f64 {
        let mut sigma = guess;
        for _ in 0..50 {
            let step = (self.integrals(sigma).0 - s) / self.ds(sigma);
            sigma -= step;
            if step.abs() < 1e-15 * (1.0 + sigma) {
                break;
            }
        }
        sigma
    }
}

/// The reference itself is checked without the bundle: on the surface, unit
/// speed in `s` (differences of `X(σ(s))`), and its acceleration `d²X/ds²` is
/// normal to the surface (the geodesic equation), for oblate and prolate
/// spheroids and several azimuths.
#[test]
fn bessel_reference_is_a_unit_speed_geodesic() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6)] {
        for alpha0 in [0.0, 0.4, 1.2, -0.8] {
            let b = Bessel::new(a, c, alpha0, 0.3, 20.0);
            for i in 1..40 {
                let sigma = 0.45 * i as f64;
                let x = b.position(sigma);
                assert!(quadric(a, c, &x).abs() < 1e-15);
                let s = b.integrals(sigma).0;
                let h = 1e-3;
                let (xm, xp) = (b.position(b.sigma_of(s - h, sigma)), b.position(b.sigma_of(s + h, sigma)));
                let vel = (xp - xm) / (2.0 * h);
                assert!((vel - b.tangent(sigma)).amax() < 1e-6, "{alpha0} {sigma}: {vel:?} vs {:?}", b.tangent(sigma));
                assert!((b.tangent(sigma).norm() - 1.0).abs() < 1e-14);
                let acc = (xp - x * 2.0 + xm) / (h * h);
                let n = Vector3::new(x[0] / (a * a), x[1] / (a * a), x[2] / (c * c)).normalize();
                let tangential = acc - n * n.dot(&acc);
                assert!(tangential.amax() < 1e-5, "{alpha0} {sigma}: tangential acceleration {tangential:?}");
                assert!(acc.norm() > 0.1);
            }
        }
    }
}

/// A force-free point follows the geodesic: DOP853 at tolerance 1e-13 against
/// Bessel's solution over five circuits (σ advances by 10π): generic,
/// over the poles (α₀ = 0, ten pole passages) and nearly polar
/// (closest approach 5e-4·a to the axis).
#[test]
fn free_point_follows_the_bessel_geodesic() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6)] {
        let m = spheroid(a, c);
        let pm = PointModel::new(m, Point::new(1.0).unwrap(), Free).unwrap();
        for (name, alpha0) in [("generic", 0.9), ("over the poles", 0.0), ("nearly polar", 5e-4f64.asin())] {
            let sigma1 = 0.7;
            let b = Bessel::new(a, c, alpha0, -0.4, sigma1 + 10.0 * PI + 1.0);
            let s1 = b.integrals(sigma1).0;
            let t_end = b.integrals(sigma1 + 10.0 * PI).0 - s1;
            let y0 = pm.state(&b.position(sigma1), &b.tangent(sigma1)).unwrap();
            let problem = Problem::new(pm.clone(), y0, (0.0, t_end)).unwrap();
            let sol = solve(&problem, &Rkmk::dop853(), &Options::adaptive(1e-13, 1e-13)).unwrap();
            let (mut worst, mut guess, mut clairaut) = (0.0f64, sigma1, 0.0f64);
            let l0 = pm.momentum_map(&y0, &Z_ROTATION).unwrap();
            let mut closest_axis = f64::INFINITY;
            for (t, y) in sol.times().iter().zip(sol.states()) {
                guess = b.sigma_of(s1 + t, guess);
                let p = pm.position(y);
                worst = worst.max((p - b.position(guess)).norm() / a);
                clairaut = clairaut.max((pm.momentum_map(y, &Z_ROTATION).unwrap() - l0).abs());
                closest_axis = closest_axis.min(p[0].hypot(p[1]));
            }
            eprintln!(
                "geodesic ({a}, {c}) {name}: {} steps, length {t_end:.2}, max position error {worst:.1e} a, Clairaut drift {clairaut:.1e}, closest to the axis {closest_axis:.1e}",
                sol.stats().accepted
            );
            assert!(worst <= 1e-10, "({a}, {c}) {name}: position error {worst:e}");
            assert!(clairaut <= 1e-11, "({a}, {c}) {name}: Clairaut drift {clairaut:e}");
        }
    }
}

// ---------------------------------------------------------------------------
// (d) the spin–curvature force
// ---------------------------------------------------------------------------

/// The translational acceleration of the gyroscope model is
/// `(K s ε u + F̂)/m` with `K` the textbook `1/(MN)` at the point (and
/// `c²/a⁴` at a pole), `ε = [[0, −1], [1, 0]]`, and `F̂_a = −q_a·∇V` computed
/// here for `V = tilt·z + well·z²` — the force of S² (SPEC §7) with the
/// spheroid's local curvature. Checked at latitudes from the equator to 1e-7
/// from the pole and at the poles, oblate and prolate.
#[test]
fn spin_curvature_force_uses_the_local_curvature() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6), (2.0, 0.2)] {
        let m = spheroid(a, c);
        let v = Field { tilt: 0.7, well: -0.4, ..Field::default() };
        let mass = 1.7;
        let gm = Gyroscope2Model::new(m, Gyroscope::<2>::isotropic(mass, 0.45).unwrap(), v).unwrap();
        let mut cases: Vec<(Vector3<f64>, Matrix3x2<f64>, f64)> = [0.0, 0.4, -1.1, 1.5, FRAC_PI_2 - 1e-7, -FRAC_PI_2 + 1e-7]
            .iter()
            .map(|&lat| {
                let x = Vector2::new(lat, 0.8);
                (m.embed(&x), m.ambient_frame(&x) * rot2(0.6), k_textbook(a, c, lat))
            })
            .collect();
        for z in [c, -c] {
            cases.push((Vector3::new(0.0, 0.0, z), Matrix3x2::new(0.6, 0.8, -0.8 * z.signum(), 0.6 * z.signum(), 0.0, 0.0), c * c / a.powi(4)));
        }
        for (p, e, k) in cases {
            for &(s, u) in &[(0.9, Vector2::new(0.7, -0.3)), (-2.0, Vector2::new(-0.2, 1.1))] {
                let y = gm.state(&p, &(e * u), &e, s).unwrap();
                let f = gm.vector_field(0.0, &y);
                let acc = Vector2::new(f.1[0], f.1[1]);
                let grad = Vector3::new(0.0, 0.0, 0.7 - 0.8 * p[2]);
                let force = -(e.transpose() * grad);
                let expected = (Vector2::new(-u[1], u[0]) * (k * s) + force) / mass;
                assert!((acc - expected).amax() <= 1e-13 * (1.0 + expected.amax()), "({a}, {c}) at {p:?}: {acc:?} vs {expected:?}");
                // Without the curvature term the equation would be visibly wrong.
                assert!((acc - force / mass).amax() > 0.05 * k * s.abs() * u.amax());
                assert!(gm.geometric_power(&y).abs() < 1e-14);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// (e) a point along a meridian crosses the pole
// ---------------------------------------------------------------------------

/// The motion along a meridian is one-dimensional (meridians are geodesics
/// and the height field is axially symmetric). In the meridian plane the
/// reduced latitude `β`, `(ρ, z) = (a cos β, c sin β)` with `β ∈ ℝ`, is a
/// global coordinate of the meridian ellipse — through the poles — with
/// `L = ½ g(β) β̇² − V(c sin β)`, `g = a² sin²β + c² cos²β`:
/// `β̈ = −(V′(z) c cos β + ½ g′(β) β̇²)/g`. Integrated here by classical RK4
/// (`h = 10⁻⁴`), it is the reference for the bundle form, which must cross
/// the pole (where `check_chart` fails) with the same motion and a conserved
/// energy.
#[test]
fn a_meridian_motion_crosses_the_pole() {
    for &(a, c) in &[(1.0, 0.7), (1.0, 1.6)] {
        let m = spheroid(a, c);
        let v = Field { tilt: 0.5, well: 0.1, ..Field::default() };
        let pm = PointModel::new(m, Point::new(1.0).unwrap(), v).unwrap();
        let lon: f64 = 0.3;
        let beta0 = 0.4f64;
        let beta_dot0 = 1.6;
        let g = |b: f64| a * a * b.sin().powi(2) + c * c * b.cos().powi(2);
        let rhs = |b: f64, bd: f64| {
            let z = c * b.sin();
            let dvdz = v.tilt + 2.0 * v.well * z;
            let dg = 2.0 * (a * a - c * c) * b.sin() * b.cos();
            (bd, -(dvdz * c * b.cos() + 0.5 * dg * bd * bd) / g(b))
        };
        let embed_beta = |b: f64| Vector3::new(a * b.cos() * lon.cos(), a * b.cos() * lon.sin(), c * b.sin());
        let p0 = embed_beta(beta0);
        let v0 = Vector3::new(-a * beta0.sin() * lon.cos(), -a * beta0.sin() * lon.sin(), c * beta0.cos()) * beta_dot0;
        let y0 = pm.state(&p0, &v0).unwrap();
        let t_end = 4.0;
        let (ts, ys) = run_rk4(&pm, y0, t_end, 0.002);
        // The reference on a finer grid, sampled at the same times.
        let hr = 1e-4;
        let mut state = (beta0, beta_dot0);
        let mut tr = 0.0;
        let (mut worst, mut max_beta) = (0.0f64, beta0);
        let e0 = pm.energy(&y0);
        let mut energy_drift = 0.0f64;
        let mut beyond = false;
        for (t, y) in ts.iter().zip(&ys) {
            while tr < t - 0.5 * hr {
                let (b, bd) = state;
                let k1 = rhs(b, bd);
                let k2 = rhs(b + 0.5 * hr * k1.0, bd + 0.5 * hr * k1.1);
                let k3 = rhs(b + 0.5 * hr * k2.0, bd + 0.5 * hr * k2.1);
                let k4 = rhs(b + hr * k3.0, bd + hr * k3.1);
                state = (b + hr / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0), bd + hr / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1));
                tr += hr;
            }
            max_beta = max_beta.max(state.0);
            let p = pm.position(y);
            worst = worst.max((p - embed_beta(state.0)).norm());
            energy_drift = energy_drift.max((pm.energy(y) - e0).abs());
            // It stays in its meridian plane, and gets to the far side of the axis.
            assert!((p[0] * lon.sin() - p[1] * lon.cos()).abs() < 1e-14);
            beyond |= p[0] * lon.cos() + p[1] * lon.sin() < -0.1;
        }
        eprintln!("meridian ({a}, {c}): β reaches {max_beta:.3}, position vs 1-D reference {worst:.1e}, energy drift {energy_drift:.1e}");
        assert!(beyond && max_beta > FRAC_PI_2 + 0.3, "({a}, {c}): the motion must cross the pole (β up to {max_beta})");
        assert!(worst < 1e-9, "({a}, {c}): position error {worst:e}");
        assert!(energy_drift < 1e-9, "({a}, {c}): energy drift {energy_drift:e}");
        // The chart cannot describe the crossing: it fails at the pole.
        assert!(matches!(m.check_chart(&Vector2::new(FRAC_PI_2, lon)), Err(Error::OutsideChart { .. })));
        assert!(matches!(m.chart(&Vector3::new(0.0, 0.0, c)), Err(Error::OutsideChart { .. })));
    }
}

// ---------------------------------------------------------------------------
// Through scenes
// ---------------------------------------------------------------------------

/// A scene on the spheroid with `a = c = 1` reproduces the same scene on the
/// unit sphere (point and gyroscope, initial state in embedding components,
/// a potential in the height) to ≤ 1e-12 in every embedding column and the
/// energy; the spheroid's chart columns are its own (`lat`, `lon`).
#[test]
fn a_round_spheroid_scene_reproduces_the_sphere_scene() {
    use framedyn::scenes::{MemorySink, Scene};
    use std::sync::atomic::AtomicBool;
    let run = |manifold: &str, body: &str, initial: &str| {
        let text = format!(
            r#"
            manifold = {manifold}
            body = {body}
            potential = {{ kind = "cosine", alpha_hat = 0.2, beta_hat = -0.3 }}
            initial = {initial}
            method = {{ name = "dop853", h = 0.01 }}
            time = {{ t_end = 3.0 }}
            output = {{ every = 20 }}
            "#
        );
        let mut sim = Scene::from_toml_str(&text).unwrap().build().unwrap();
        let mut sink = MemorySink::default();
        sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
        sink
    };
    let (x, v) = (Vector3::new(0.6f64.sin(), 0.0, 0.6f64.cos()), Vector3::new(0.0, 0.7, 0.2));
    let v = v - x * x.dot(&v);
    let e1 = v.normalize();
    let e2 = x.cross(&e1);
    let fmt = |u: &Vector3<f64>| format!("[{}, {}, {}]", u[0], u[1], u[2]);
    for (body, initial) in [
        ("{ kind = \"point\" }".to_string(), format!("{{ position = {}, velocity = {} }}", fmt(&x), fmt(&v))),
        (
            "{ kind = \"gyroscope\", inertia = 0.2 }".to_string(),
            format!("{{ position = {}, velocity = {}, frame = [{}, {}], spin = 0.07 }}", fmt(&x), fmt(&v), fmt(&e1), fmt(&e2)),
        ),
    ] {
        let s2 = run("{ kind = \"S2\", radius = 1.0 }", &body, &initial);
        let sph = run("{ kind = \"spheroid\", equatorial_radius = 1.0, polar_radius = 1.0 }", &body, &initial);
        assert_eq!(s2.rows.len(), sph.rows.len());
        for name in ["t", "x0", "x1", "x2", "v0", "v1", "v2", "energy"] {
            let (a, b) = (s2.column(name).unwrap(), sph.column(name).unwrap());
            let worst = a.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
            assert!(worst <= 1e-12, "{body}: {name} differs by {worst:e}");
        }
        if body.contains("gyroscope") {
            for name in ["e1_0", "e1_1", "e1_2", "e2_0", "e2_1", "e2_2", "spin"] {
                let (a, b) = (s2.column(name).unwrap(), sph.column(name).unwrap());
                let worst = a.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
                assert!(worst <= 1e-12, "{body}: {name} differs by {worst:e}");
            }
        }
        assert!(sph.column("lat").is_some() && sph.column("lon_dot").is_some() && s2.column("r").is_some());
    }
}

/// Scene errors on the spheroid name the field: missing or non-positive
/// radii, a ratio beyond 1e3, the fields of other manifolds, central
/// potentials (no closed-form geodesic distance), splittings (no exact free
/// flow), coordinate methods (no chart equations), coordinates of other
/// manifolds.
#[test]
fn spheroid_scene_errors_name_the_field() {
    use framedyn::scenes::{example, SceneError};
    let base = example("spheroid-gyroscope").unwrap();
    let path_of = |s: &framedyn::scenes::Scene| match s.validate() {
        Err(SceneError::Invalid { path, .. }) => path,
        other => panic!("expected an invalid scene, got {other:?}"),
    };
    let mut s = base.clone();
    s.manifold.polar_radius = None;
    assert_eq!(path_of(&s), "manifold.polar_radius");
    let mut s = base.clone();
    s.manifold.equatorial_radius = Some(-1.0);
    assert!(path_of(&s).starts_with("manifold"));
    let mut s = base.clone();
    s.manifold.polar_radius = Some(2e3);
    assert!(path_of(&s).contains("polar_radius"));
    let mut s = base.clone();
    s.manifold.radius = Some(1.0);
    assert_eq!(path_of(&s), "manifold.radius");
    let mut s = base.clone();
    s.potential = framedyn::scenes::PotentialSpec { kind: framedyn::scenes::PotentialKind::Oscillator, kappa: Some(1.0), ..Default::default() };
    assert_eq!(path_of(&s), "potential.kind");
    for m in ["strang", "coordinate_rk4"] {
        let mut s = base.clone();
        s.method.name = m.into();
        assert_eq!(path_of(&s), "method.name", "{m}");
    }
    let mut s = base.clone();
    s.initial = s.initial.clone().with_coordinate("r", 0.5);
    assert_eq!(path_of(&s), "initial.r");
    // The cosine family on the spheroid is α̂ (z/c)² + β̂ z/c.
    let sim = base.build().unwrap();
    let z = sim.value("x2").unwrap();
    let c = base.manifold.polar_radius.unwrap();
    let kinetic = 0.5 * (sim.value("v0").unwrap().powi(2) + sim.value("v1").unwrap().powi(2) + sim.value("v2").unwrap().powi(2));
    let spin_energy = 0.5 * 0.1f64.powi(2) / 0.2;
    let e = sim.energy();
    assert!((e - (kinetic + spin_energy - 0.3 * z / c)).abs() < 1e-14, "energy {e}");
}
