//! S³(R): the group SO(4), the manifold S³ in the paper's rotation-vector
//! chart with the SU(2)-invariant frames, and its frame bundle as SO(4).

use framedyn::bundle::FrameBundle;
use framedyn::lie::{dexp_series, LieGroup, So4, So4Algebra};
use framedyn::manifold::{GeodesicDistance, Manifold, Sphere3};
use framedyn::Error;
use nalgebra::{Matrix3, Matrix4, Matrix4x3, Quaternion, Rotation3, Vector3, Vector4};
use proptest::prelude::*;
use std::f64::consts::PI;

use crate::bundle_laws::{
    check_bundle_at, frame_components, frame_defect, random_walk_defect, rkmk4_step, small_loop_holonomy,
    transport_along, transport_in_chart,
};
use crate::distance_laws::{check_distance_at, check_distance_laws};
use crate::manifold_laws::check_manifold_at;

// ---------------------------------------------------------------------------
// Helpers (independent of the library: nalgebra's quaternions, literal formulas).

fn quat(v: &Vector4<f64>) -> Quaternion<f64> {
    Quaternion::new(v[0], v[1], v[2], v[3])
}

fn unquat(q: &Quaternion<f64>) -> Vector4<f64> {
    Vector4::new(q.w, q.i, q.j, q.k)
}

fn e(a: usize) -> Quaternion<f64> {
    let mut v = Vector4::zeros();
    v[a] = 1.0;
    quat(&v)
}

fn eps3(a: usize, b: usize, c: usize) -> f64 {
    ((a as i64 - b as i64) * (b as i64 - c as i64) * (c as i64 - a as i64)) as f64 / 2.0
}

/// A chart point with direction `dir` (normalised) and length `frac·πR`.
fn chart_point(dir: &[f64], frac: f64, radius: f64) -> Vector3<f64> {
    let d = Vector3::new(dir[0], dir[1], dir[2]);
    let n = d.norm();
    let d = if n < 1e-3 { Vector3::new(0.3, -0.5, 0.8).normalize() } else { d / n };
    d * (frac * PI * radius)
}

/// Strategy: fraction of πR, log-uniform near 0 and uniform up to 0.95.
fn frac_strategy() -> impl Strategy<Value = f64> {
    prop_oneof![(-9.0..-2.0f64).prop_map(|l| 10f64.powf(l)), 1e-2..0.95f64]
}

fn dir_strategy() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-1.0..1.0f64, 3)
}

// ---------------------------------------------------------------------------
// SO(4)

/// The generic Lie-group laws. Algebra norm ≤ 3 keeps the rotation angles
/// `|a| ± |b|` below π, so `log` stays principal. (Wrapped in a module that
/// imports nothing but the group, so the macro's `use super::*` is used and its
/// `use proptest::prelude::*` is not shadowed: no warnings.)
mod so4_group {
    use framedyn::lie::So4;
    crate::lie_law_suite!(laws, So4, radius = 3.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 3.0);
}

fn alg(c: &[f64]) -> So4Algebra {
    So4::algebra_from_coords(c)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// `exp(X)·x = p·x·q̄` with `(p, q) = (exp a, exp b)` computed by nalgebra's
    /// quaternions, and `X·x = a·x − x·b`: the su(2)⊕su(2) split is the documented one.
    #[test]
    fn so4_quaternion_split(c in proptest::collection::vec(-2.0..2.0f64, 6), x in proptest::collection::vec(-1.0..1.0f64, 4)) {
        let xa = alg(&c);
        let x = Vector4::new(x[0], x[1], x[2], x[3]);
        let (a, b) = So4::left_right(&xa);
        let (qa, qb) = (Quaternion::from_imag(a), Quaternion::from_imag(b));
        let lin = unquat(&(qa * quat(&x) - quat(&x) * qb));
        prop_assert!((So4::hat(&xa) * x - lin).amax() < 1e-15);
        let (p, q) = (qa.exp(), qb.exp());
        let rot = unquat(&(p * quat(&x) * q.conjugate()));
        let g = So4::exp(&xa);
        prop_assert!((g.matrix() * x - rot).amax() < 4e-15, "{:e}", (g.matrix() * x - rot).amax());
        // The extracted pair is ±(p, q), with p₀ + q₀ ≥ 0.
        let (pe, qe) = g.quaternions().unwrap();
        prop_assert!(pe.w + qe.w >= 0.0);
        let sign = unquat(&pe).dot(&unquat(&p)).signum();
        let err = (unquat(&pe) - unquat(&p) * sign).amax().max((unquat(&qe) - unquat(&q) * sign).amax());
        prop_assert!(err < 4e-15, "pair error {err:e}");
        let back = So4::from_quaternions(&pe, &qe).unwrap();
        prop_assert!((back.matrix() - g.matrix()).amax() < 4e-15);
    }

    /// Closed-form `dexp` = its defining series beyond the suite's |a| < 1
    /// (spectral radius of ad up to 2·max(|a|, |b|) ≈ 5.7 < 2π).
    #[test]
    fn so4_dexp_series(c in proptest::collection::vec(-3.0..3.0f64, 6), v in proptest::collection::vec(-1.0..1.0f64, 6)) {
        let mut a = alg(&c);
        let n = a.norm();
        if n > 4.0 { a *= 4.0 / n; }
        let v = alg(&v);
        let closed = So4::dexp(&a, &v);
        let series = dexp_series::<So4>(&a, &v, 80);
        prop_assert!((closed - series).norm() <= 1e-14 * (1.0 + series.norm()), "{:e}", (closed - series).norm());
    }

    /// `renormalize` returns the nearest rotation: the orthogonal polar factor
    /// (SVD) of a perturbed rotation, to second order in the perturbation.
    #[test]
    fn so4_renormalize_is_polar_factor(c in proptest::collection::vec(-3.0..3.0f64, 6), d in proptest::collection::vec(-1.0..1.0f64, 16)) {
        let g = So4::exp(&alg(&c));
        let pert = Matrix4::from_column_slice(&d) * 1e-6;
        let m = g.matrix() + pert;
        // (nalgebra's SVD is not a usable reference here: with four nearly equal
        // singular values its U·Vᵀ is off by up to 3e-13.)
        let polar = polar_newton(&m);
        let r = So4::new_unchecked(m).renormalize();
        prop_assert!((r.matrix() - polar).amax() < 2e-15, "{:e}", (r.matrix() - polar).amax());
        // A few ulps of 1: the rebuilt matrix is a product of two exactly
        // orthogonal-in-exact-arithmetic quaternion matrices.
        prop_assert!(r.constraint_defect() < 2e-15, "{:e}", r.constraint_defect());
    }
}

#[test]
fn so4_log_cut_and_validation() {
    // Rotation angles (π, 0): the log is not unique.
    let half_turn = Matrix4::from_diagonal(&Vector4::new(-1.0, -1.0, 1.0, 1.0));
    let g = So4::new(half_turn).unwrap();
    assert!(matches!(g.log(), Err(Error::LogUndefined { .. })));
    // −I (angles π, π) and exp of a generator with |a| + |b| = π.
    assert!(matches!(So4::new(-Matrix4::identity()).unwrap().log(), Err(Error::LogUndefined { .. })));
    let cut = So4::exp(&So4::from_left_right(&Vector3::new(2.0, 0.0, 0.0), &Vector3::new(0.0, PI - 2.0, 0.0)));
    assert!(matches!(cut.log(), Err(Error::LogUndefined { .. })), "{:?}", cut.log());
    // Just inside the cut the principal log is recovered.
    let a = So4::from_left_right(&Vector3::new(1.5, 0.2, 0.0), &Vector3::new(0.0, 0.0, 1.3));
    let l = So4::exp(&a).log().unwrap();
    assert!((l - a).amax() < 1e-14, "{:e}", (l - a).amax());
    // Validation of new().
    assert!(matches!(So4::new(Matrix4::from_diagonal(&Vector4::new(-1.0, 1.0, 1.0, 1.0))), Err(Error::Constraint { .. })));
    assert!(matches!(So4::new(Matrix4::identity() * 1.001), Err(Error::Constraint { .. })));
    let mut nan = Matrix4::identity();
    nan[(2, 1)] = f64::NAN;
    assert!(matches!(So4::new(nan), Err(Error::NotFinite { .. })));
    assert!(matches!(So4::new_unchecked(nan).log(), Err(Error::LogUndefined { .. })));
    assert!(matches!(
        So4::from_quaternions(&Quaternion::new(0.0, 0.0, 0.0, 0.0), &Quaternion::identity()),
        Err(Error::Constraint { .. })
    ));
}

/// Orthogonal polar factor by Newton's iteration `X ← (X + X⁻ᵀ)/2` (quadratic
/// convergence, backward stable near orthogonal matrices).
fn polar_newton(m: &Matrix4<f64>) -> Matrix4<f64> {
    let mut x = *m;
    for _ in 0..8 {
        x = (x + x.try_inverse().unwrap().transpose()) * 0.5;
    }
    x
}

// ---------------------------------------------------------------------------
// The manifold S³(R)

fn s3(radius: f64) -> Sphere3 {
    Sphere3::new(radius).unwrap()
}

/// Fourth-order central difference `∂_k f` of a matrix-valued chart function
/// (error O(h⁴)).
fn fd4(f: &impl Fn(&Vector3<f64>) -> Matrix3<f64>, x: &Vector3<f64>, k: usize, h: f64) -> Matrix3<f64> {
    let mut dx = Vector3::zeros();
    dx[k] = h;
    (f(&(x - dx * 2.0)) - f(&(x + dx * 2.0)) + (f(&(x + dx)) - f(&(x - dx))) * 8.0) / (12.0 * h)
}

/// Derivatives `∂_k` of the chart frame field `f` (fourth-order differences).
fn frame_fd(f: &impl Fn(&Vector3<f64>) -> Matrix3<f64>, x: &Vector3<f64>, h: f64) -> [Matrix3<f64>; 3] {
    [fd4(f, x, 0, h), fd4(f, x, 1, h), fd4(f, x, 2, h)]
}

/// Step for fourth-order differences: 1e-3 of the fields' length scale
/// `R·min(1, π − θ)` (truncation ~1e-12 relative, round-off ~1e-12).
fn fd_step(radius: f64, frac: f64) -> f64 {
    1e-3 * radius * (PI * (1.0 - frac)).min(1.0)
}

/// Lie bracket `[E_A, E_B]^i = E_A^j ∂_j E_B^i − E_B^j ∂_j E_A^i` of the columns
/// of two frame fields, by finite differences.
fn bracket_fd(
    f1: &impl Fn(&Vector3<f64>) -> Matrix3<f64>,
    f2: &impl Fn(&Vector3<f64>) -> Matrix3<f64>,
    x: &Vector3<f64>,
    a: usize,
    b: usize,
    h: f64,
) -> Vector3<f64> {
    let (e1, e2) = (f1(x), f2(x));
    let (d1, d2) = (frame_fd(f1, x, h), frame_fd(f2, x, h));
    Vector3::from_fn(|i, _| (0..3).map(|j| e1[(j, a)] * d2[j][(i, b)] - e2[(j, b)] * d1[j][(i, a)]).sum())
}

/// The paper's (a178a)/(a178b), literally: `E_A = n_A ∂_r − (1/R)cot(r/R) ε_ABC n^B D^C ± (1/R) D_A`
/// with `∂_r = n^J ∂_J`, `D_A = ε_ABJ r^B ∂_J` (needs r > 0).
fn paper_frame(radius: f64, x: &Vector3<f64>, sign: f64) -> Matrix3<f64> {
    let r = x.norm();
    let n = x / r;
    let cot = 1.0 / (r / radius).tan();
    let d = |a: usize, j: usize| (0..3).map(|b| eps3(a, b, j) * x[b]).sum::<f64>();
    Matrix3::from_fn(|j, a| {
        let mut v = n[a] * n[j] + sign * d(a, j) / radius;
        for b in 0..3 {
            for c in 0..3 {
                v -= cot / radius * eps3(a, b, c) * n[b] * d(c, j);
            }
        }
        v
    })
}

/// Tolerance of the exact manifold laws at θ = frac·π (see `manifold_laws`).
fn law_tol(frac: f64) -> f64 {
    2e-15 * (1.0 + frac / (1.0 - frac))
}

/// Connection coefficients `Γ^A_{BC}` of a chart frame field from their
/// definition `E⁻¹(∂_{E_C} E_B + Γ(E_C) E_B)`, derivatives with step `h`.
fn connection_fd(
    m: &Sphere3,
    f: &impl Fn(&Vector3<f64>) -> Matrix3<f64>,
    x: &Vector3<f64>,
    h: f64,
) -> [[[f64; 3]; 3]; 3] {
    let fr = f(x);
    let gam = m.christoffel(x);
    let d = frame_fd(f, x, h);
    let finv = fr.try_inverse().unwrap();
    let mut out = [[[0.0; 3]; 3]; 3];
    for b in 0..3 {
        for c in 0..3 {
            let nab = Vector3::from_fn(|i, _| {
                (0..3).map(|k| fr[(k, c)] * (d[k][(i, b)] + (0..3).map(|j| gam[i][j][k] * fr[(j, b)]).sum::<f64>())).sum()
            });
            let comps = finv * nab;
            for a in 0..3 {
                out[a][b][c] = comps[a];
            }
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The generic manifold laws over the chart (|r̄| from 1e-9·πR up to
    /// 0.95πR), sectional curvature 1/R² for every frame plane;
    /// tolerance `2e-15·(1 + θ/(π − θ))`, θ = r/R: round-off times the condition
    /// number of the chart coefficients (cot θ) near the antipode.
    #[test]
    fn manifold_laws(dir in dir_strategy(), frac in frac_strategy(), radius in 0.3..5.0f64) {
        let m = s3(radius);
        let x = chart_point(&dir, frac, radius);
        let k = 1.0 / (radius * radius);
        let r = check_manifold_at(&m, &x, |_, _| k, law_tol(frac));
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    /// The distance laws at the chart points of `manifold_laws`.
    #[test]
    fn distance_at_chart_points(dir in dir_strategy(), frac in frac_strategy(), radius in 0.3..5.0f64) {
        let m = s3(radius);
        let r = check_distance_at(&m, &chart_point(&dir, frac, radius));
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    /// The connection coefficients of both of the paper's frames, ˡE (also
    /// covered by the shared laws) and ʳE, from their definition
    /// `E⁻¹(∂_{E_C} E_B + Γ(E_C) E_B)` with steps scaled to the fields' length
    /// scale `R(π − θ)`, over the whole range |r̄| < 0.95πR.
    #[test]
    fn frame_connections_both_frames(dir in dir_strategy(), frac in frac_strategy(), radius in 0.3..5.0f64) {
        let m = s3(radius);
        let x = chart_point(&dir, frac, radius);
        let h = fd_step(radius, frac);
        let el = connection_fd(&m, &|y: &Vector3<f64>| m.frame_l(y), &x, h);
        let er = connection_fd(&m, &|y: &Vector3<f64>| m.frame_r(y), &x, h);
        let (wl, wr) = (m.frame_connection(&x), m.frame_r_connection());
        let mut worst: f64 = 0.0;
        for a in 0..3 { for b in 0..3 { for c in 0..3 {
            worst = worst.max((el[a][b][c] - wl[a][b][c]).abs() * radius);
            worst = worst.max((er[a][b][c] - wr[a][b][c]).abs() * radius);
            prop_assert!(wl[a][b][c] == eps3(a, b, c) / radius && wr[a][b][c] == -eps3(a, b, c) / radius);
        }}}
        prop_assert!(worst < 1e-9, "Γ^A_BC vs definition: {worst:e}");
    }

    #[test]
    fn distance_laws(
        a in dir_strategy(), fa in frac_strategy(),
        b in dir_strategy(), fb in frac_strategy(),
        c in dir_strategy(), fc in frac_strategy(),
        radius in 0.3..5.0f64,
    ) {
        let m = s3(radius);
        let p = m.embed(&chart_point(&a, fa, radius));
        let q = m.embed(&chart_point(&b, fb, radius));
        let r = m.embed(&chart_point(&c, fc, radius));
        let res = check_distance_laws(&m, &p, &q, &r);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        // Against the geodesic distance from the chart centre, which is |r̄|.
        let o = Vector4::new(radius, 0.0, 0.0, 0.0);
        let d = m.distance(&o, &q).unwrap();
        prop_assert!((d - fb * PI * radius).abs() <= 4e-16 * PI * radius, "{:e}", d - fb * PI * radius);
    }

    /// The frame two independent ways: the paper's coordinate formula (a178a)
    /// and the quaternion products `e_A·x/R` (ˡE) / `x·e_A/R` (ʳE) pushed through
    /// the embedding; also the literal metric (a179).
    #[test]
    fn frames_match_paper_and_quaternions(dir in dir_strategy(), frac in 1e-3..0.95f64, radius in 0.3..5.0f64) {
        let m = s3(radius);
        let x = chart_point(&dir, frac, radius);
        let (fl, fr) = (m.frame_l(&x), m.frame_r(&x));
        prop_assert_eq!(fl, m.frame(&x));
        let scale = 1.0 + fl.amax();
        prop_assert!((fl - paper_frame(radius, &x, 1.0)).amax() <= 1e-14 * scale, "ˡE vs (a178a): {:e}", (fl - paper_frame(radius, &x, 1.0)).amax());
        prop_assert!((fr - paper_frame(radius, &x, -1.0)).amax() <= 1e-14 * scale, "ʳE vs (a178b): {:e}", (fr - paper_frame(radius, &x, -1.0)).amax());
        let p = m.embed(&x);
        let u = quat(&(p / radius));
        for a in 0..3 {
            let left = unquat(&(e(a + 1) * u));
            let right = unquat(&(u * e(a + 1)));
            let el = m.embed_tangent(&x, &fl.column(a).into());
            let er = m.embed_tangent(&x, &fr.column(a).into());
            prop_assert!((el - left).amax() <= 1e-14 * scale, "ˡE_{a} vs e_A·x/R: {:e}", (el - left).amax());
            prop_assert!((er - right).amax() <= 1e-14 * scale, "ʳE_{a} vs x·e_A/R: {:e}", (er - right).amax());
            prop_assert!((m.frame_l_ambient(&p).column(a) - left).amax() < 1e-15);
            prop_assert!((m.frame_r_ambient(&p).column(a) - right).amax() < 1e-15);
        }
        let r = x.norm();
        let n = x / r;
        let f = (radius / r * (r / radius).sin()).powi(2);
        let g_paper = Matrix3::identity() * f + n * n.transpose() * (1.0 - f);
        prop_assert!((m.metric(&x) - g_paper).amax() < 1e-15);
    }

    /// Brackets of the frame fields by finite differences in the chart:
    /// [ˡE_A, ˡE_B] = −(2/R) ε_ABC ˡE_C (b178a), [ʳE_A, ʳE_B] = +(2/R) ε_ABC ʳE_C
    /// (b178b), [ˡE_A, ʳE_B] = 0 (b178c).
    #[test]
    fn frame_brackets(dir in dir_strategy(), frac in frac_strategy(), radius in 0.3..5.0f64) {
        let m = s3(radius);
        let x = chart_point(&dir, frac, radius);
        let fl = |y: &Vector3<f64>| m.frame_l(y);
        let fr = |y: &Vector3<f64>| m.frame_r(y);
        let (el, er) = (m.frame_l(&x), m.frame_r(&x));
        let h = fd_step(radius, frac);
        let mut worst: f64 = 0.0;
        for a in 0..3 {
            for b in 0..3 {
                let mut want_l = Vector3::zeros();
                let mut want_r = Vector3::zeros();
                for c in 0..3 {
                    want_l -= el.column(c) * (2.0 / radius * eps3(a, b, c));
                    want_r += er.column(c) * (2.0 / radius * eps3(a, b, c));
                }
                worst = worst.max((bracket_fd(&fl, &fl, &x, a, b, h) - want_l).amax() * radius);
                worst = worst.max((bracket_fd(&fr, &fr, &x, a, b, h) - want_r).amax() * radius);
                worst = worst.max(bracket_fd(&fl, &fr, &x, a, b, h).amax() * radius);
            }
        }
        prop_assert!(worst < 1e-8, "bracket error {worst:e}");
    }
}

#[test]
fn manifold_at_chart_centre_and_special_points() {
    for radius in [0.3, 1.0, 4.7] {
        let m = s3(radius);
        let k = 1.0 / (radius * radius);
        check_manifold_at(&m, &Vector3::zeros(), |_, _| k, 1e-15).unwrap();
        check_distance_at(&m, &Vector3::zeros()).unwrap();
        // Tiny points: the series branches, no division by r.
        for r in [1e-300, 1e-160, 1e-20] {
            let x = Vector3::new(r, -r, 0.5 * r);
            assert!((m.frame(&x) - Matrix3::identity()).amax() <= 2.0 * r / radius);
            assert!(m.christoffel(&x).iter().flatten().flatten().all(|v| v.is_finite()));
            assert_eq!(m.chart(&m.embed(&x)).unwrap(), x);
        }
        // Antipodal and nearly coincident points.
        let p = Vector4::new(0.6, 0.0, -0.8, 0.0) * radius;
        assert!((m.distance(&p, &-p).unwrap() - PI * radius).abs() < 1e-15 * radius);
        let q = (p + Vector4::new(0.0, 1e-12, 0.0, 0.0) * radius).normalize() * radius;
        let d = m.distance(&p, &q).unwrap();
        assert!((d / (1e-12 * radius) - 1.0).abs() < 1e-14, "{:e}", d / (1e-12 * radius) - 1.0);
        // Chart: exactly the antipode, and next to it.
        let anti = Vector4::new(-radius, 0.0, 0.0, 0.0);
        assert!(matches!(m.chart(&anti), Err(Error::OutsideChart { .. })));
        let near = Vector4::new(-(1.0f64 - 1e-14).sqrt(), 1e-7, 0.0, 0.0) * radius;
        assert!(matches!(m.chart(&near), Err(Error::OutsideChart { .. })));
        assert!(matches!(m.chart_tangent(&anti, &Vector4::new(0.0, 1.0, 0.0, 0.0)), Err(Error::OutsideChart { .. })));
        assert!(matches!(m.check_chart(&Vector3::new(PI * radius, 0.0, 0.0)), Err(Error::OutsideChart { .. })));
        assert!(matches!(m.check_chart(&Vector3::new(0.0, -4.0 * radius, 0.0)), Err(Error::OutsideChart { .. })));
        assert!(matches!(m.check_chart(&Vector3::new(0.0, f64::NAN, 0.0)), Err(Error::NotFinite { .. })));
        assert!(m.check_chart(&Vector3::new(0.0, 0.0, (PI - 2e-6) * radius)).is_ok());
        // Points off the sphere.
        assert!(matches!(m.chart(&(anti * -1.001)), Err(Error::Constraint { .. })));
        assert!(matches!(m.distance(&(p * 1.1), &p), Err(Error::Constraint { .. })));
        assert!(matches!(m.chart(&Vector4::new(f64::INFINITY, 0.0, 0.0, 0.0)), Err(Error::NotFinite { .. })));
    }
}

#[test]
fn bad_radius() {
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(Sphere3::new(r), Err(Error::InvalidParameter { field: "R", .. })), "R = {r}");
    }
}

// ---------------------------------------------------------------------------
// The frame bundle F(S³) = SO(4)

fn rotation(c: &[f64]) -> Matrix3<f64> {
    Rotation3::new(Vector3::new(c[0], c[1], c[2])).into_inner()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The generic bundle laws (from_chart/to_chart/from_frame round trips,
    /// horizontal lift = parallel transport, vertical = rotation in place).
    #[test]
    fn bundle_laws(
        dir in dir_strategy(), frac in frac_strategy(), radius in 0.3..5.0f64,
        rot in proptest::collection::vec(-3.0..3.0f64, 3),
        v in proptest::collection::vec(-1.0..1.0f64, 3),
    ) {
        let m = s3(radius);
        let x = chart_point(&dir, frac, radius);
        let u = rotation(&rot);
        let v = Vector3::new(v[0], v[1], v[2]);
        let r = check_bundle_at(&m, &x, &u, &v, law_tol(frac));
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        // Orientation convention: det[x/R | ˡE·u] = +1, and also for ʳE.
        let p = m.embed(&x);
        let mut q = Matrix4::zeros();
        q.set_column(0, &(p / radius));
        q.fixed_view_mut::<4, 3>(0, 1).copy_from(&m.frame_r_ambient(&p));
        prop_assert!((q.determinant() - 1.0).abs() < 1e-14);
        prop_assert!(m.from_frame(&p, &m.frame_r_ambient(&p)).is_ok());
    }
}

#[test]
fn random_walk_stays_in_bundle() {
    // 10⁶ random horizontal + vertical steps of size ≈ 0.1–0.3 rad, renormalised.
    let m = s3(1.3);
    let g0 = m.from_chart(&Vector3::new(0.4, -1.1, 0.7), &rotation(&[0.3, -0.2, 1.0])).unwrap();
    let defect = random_walk_defect(&m, &g0, 1_000_000, 0.2, 0x5EED_0003);
    assert!(defect <= 1e-13, "frame defect {defect:e} after 1e6 steps");
}

/// Chart curve `x(t)` with velocity, staying inside |r̄| < 0.93πR.
fn test_curve(radius: f64) -> impl Fn(f64) -> (Vector3<f64>, Vector3<f64>) {
    let c0 = Vector3::new(-1.2, 0.5, 0.3) * radius;
    let c1 = Vector3::new(2.5, -0.4, 1.1) * radius;
    let c2 = Vector3::new(0.2, 0.9, -0.6) * radius;
    move |t: f64| {
        let (s, c) = (3.0 * PI * t).sin_cos();
        (c0 + c1 * t + c2 * s, c1 + c2 * (3.0 * PI * c))
    }
}

#[test]
fn transport_group_form_matches_chart_form() {
    for radius in [0.7, 2.0] {
        let m = s3(radius);
        let curve = test_curve(radius);
        for t in 0..=100 {
            assert!(curve(t as f64 / 100.0).0.norm() < 0.93 * PI * radius);
        }
        let (x0, _) = curve(0.0);
        let u0 = rotation(&[0.5, 1.0, -0.7]);
        let g0 = m.from_chart(&x0, &u0).unwrap();
        let g1 = transport_along(&m, &g0, &curve, 2000);
        let v1 = transport_in_chart(&m, &(m.frame(&x0) * u0), &curve, 2000);
        let (x1, _) = curve(1.0);
        let mut q1 = Matrix4x3::zeros();
        for a in 0..3 {
            q1.set_column(a, &m.embed_tangent(&x1, &v1.column(a).into()));
        }
        let err = (m.frame_vectors(&g1) - q1).amax();
        let perr = (m.position(&g1) - m.embed(&x1)).amax() / radius;
        // Measured 3.1e-12 (both RK4 integrations at 2000 steps).
        assert!(err < 3e-11 && perr < 3e-11, "R = {radius}: frame {err:e}, point {perr:e}");
        assert!(frame_defect(&m, &g1) < 1e-14);
    }
}

#[test]
fn small_loop_holonomy_converges_like_eps_squared() {
    let radius = 1.7;
    let m = s3(radius);
    let x0 = Vector3::new(0.9, -1.4, 2.2);
    let mut errs = vec![];
    for eps in [0.2, 0.1, 0.05, 0.025] {
        let (angle, expected) = small_loop_holonomy(&m, &x0, eps * radius, 800);
        errs.push((angle / expected - 1.0).abs());
    }
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.5..4.5).contains(&ratio), "relative errors {errs:?}: ratio {ratio}");
    }
    assert!(errs[3] < 1e-3, "{errs:?}");
}

/// Parallel transport in the group form along an ambient curve `t ↦ (x, ẋ)`.
fn transport_ambient(m: &Sphere3, g0: &So4, curve: &impl Fn(f64) -> (Vector4<f64>, Vector4<f64>), steps: usize) -> So4 {
    let xi = |t: f64, g: &So4| {
        let (_, xd) = curve(t);
        m.horizontal_lift(g, &frame_components(m, g, &xd))
    };
    let h = 1.0 / steps as f64;
    let mut g = *g0;
    for i in 0..steps {
        g = rkmk4_step(&g, i as f64 * h, h, &xi);
    }
    g
}

/// Half a great circle from `R·1` to the chart's singular point `−R·1`, a small
/// circle of angular radius α through `−R·1` on the totally geodesic
/// S² = S³ ∩ {x₃ = 0}, and the other half of the great circle back to `R·1`.
/// The great circle alone has trivial holonomy; the cap has area
/// 2πR²(1 − cos α), so the frame returns rotated by θ = 2π(1 − cos α) in the
/// (e₁, e₂) plane (q₁ → cos θ e₁ + sin θ e₂), with e₃ fixed. Each piece is mapped
/// by the isometry `x ↦ v·x` (`v = 1`: through the antipode; other `v`: a
/// congruent path elsewhere) to compare accuracy.
fn antipode_path_holonomy(radius: f64, alpha: f64, v: &Quaternion<f64>, steps: usize) -> (f64, f64) {
    let m = s3(radius);
    let lv = |y: Vector4<f64>| unquat(&(v * quat(&y)));
    let c = Vector4::new(-alpha.cos(), alpha.sin(), 0.0, 0.0);
    let m1 = Vector4::new(-alpha.sin(), -alpha.cos(), 0.0, 0.0);
    let m2 = Vector4::new(0.0, 0.0, 1.0, 0.0);
    let great = |t0: f64| {
        move |t: f64| {
            let (s, co) = (PI * (t0 + t)).sin_cos();
            (lv(Vector4::new(co, s, 0.0, 0.0) * radius), lv(Vector4::new(-s, co, 0.0, 0.0) * (PI * radius)))
        }
    };
    let small = |t: f64| {
        let (s, co) = (2.0 * PI * t).sin_cos();
        let x = (c * alpha.cos() + (m1 * co + m2 * s) * alpha.sin()) * radius;
        let xd = (m2 * co - m1 * s) * (2.0 * PI * alpha.sin() * radius);
        (lv(x), lv(xd))
    };
    // Start: the point v·R·1 with frame v·e_a (the left-translated identity).
    let mut q0 = Matrix4::zeros();
    for a in 0..4 {
        q0.set_column(a, &lv(Vector4::from_fn(|i, _| if i == a { 1.0 } else { 0.0 })));
    }
    let g0 = So4::new(q0).unwrap();
    let mut g = transport_ambient(&m, &g0, &great(0.0), steps);
    let at_antipode = (m.position(&g) - lv(Vector4::new(-radius, 0.0, 0.0, 0.0))).amax() / radius;
    g = transport_ambient(&m, &g, &small, steps);
    g = transport_ambient(&m, &g, &great(1.0), steps);
    let th = 2.0 * PI * (1.0 - alpha.cos());
    let mut want = Matrix4::identity();
    want[(1, 1)] = th.cos();
    want[(2, 1)] = th.sin();
    want[(1, 2)] = -th.sin();
    want[(2, 2)] = th.cos();
    let want = q0 * want;
    ((g.matrix() - want).amax(), at_antipode)
}

#[test]
fn transport_through_the_antipode() {
    for (radius, alpha) in [(1.0, 0.7), (3.2, 1.9)] {
        // 3 × 2000 RKMK4 steps: truncation ≈ 1.8e-13, just above the round-off
        // floor (≈ 1e-13 at 3 × 8000 steps).
        let (err, dist) = antipode_path_holonomy(radius, alpha, &Quaternion::identity(), 2000);
        assert!(dist < 1e-13, "path misses the antipode by {dist:e}");
        // The chart cannot represent the element there; the group form does not care.
        let (err_elsewhere, _) =
            antipode_path_holonomy(radius, alpha, &Quaternion::new(0.3, -0.5, 0.7, 0.4).normalize(), 2000);
        assert!(err < 3e-13, "holonomy error {err:e} through the antipode");
        assert!(err < 2.0 * err_elsewhere, "through the antipode {err:e}, elsewhere {err_elsewhere:e}");
    }
    // RKMK4 converges (at fourth order) to the closed form.
    let (e1, _) = antipode_path_holonomy(1.0, 0.7, &Quaternion::identity(), 50);
    let (e2, _) = antipode_path_holonomy(1.0, 0.7, &Quaternion::identity(), 100);
    assert!((12.0..20.0).contains(&(e1 / e2)), "order check: {e1:e} → {e2:e}");
    // The element at the antipode itself has no chart.
    let m = s3(1.0);
    let anti = So4::new(Matrix4::from_diagonal(&Vector4::new(-1.0, -1.0, 1.0, 1.0))).unwrap();
    assert!(matches!(m.to_chart(&anti), Err(Error::OutsideChart { .. })));
}

#[test]
fn bundle_typed_errors() {
    let radius = 2.0;
    let m = s3(radius);
    let x = Vector3::new(0.3, 1.0, -0.4);
    let p = m.embed(&x);
    let q = m.frame_l_ambient(&p);
    assert!(m.from_frame(&p, &q).is_ok());
    // Point off the sphere.
    assert!(matches!(m.from_frame(&(p * 1.01), &q), Err(Error::Constraint { field: "p", .. })));
    // Not orthonormal.
    let mut q2 = q;
    q2.set_column(1, &(q.column(1) * 1.01));
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::Constraint { field: "q", .. })));
    let mut q2 = q;
    q2.set_column(2, &((q.column(2) + q.column(1) * 0.1).normalize()));
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::Constraint { field: "q", .. })));
    // Not tangent: a unit vector with a component along p.
    let mut q2 = q;
    q2.set_column(0, &((q.column(0) + p * (0.01 / radius)).normalize()));
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::Constraint { field: "q", .. })));
    // Negatively oriented: two vectors swapped, or one reversed.
    let mut q2 = q;
    q2.swap_columns(0, 1);
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::Constraint { field: "q", .. })));
    let mut q2 = q;
    q2.set_column(2, &-q.column(2));
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::Constraint { field: "q", .. })));
    // Non-finite.
    let mut q2 = q;
    q2[(3, 1)] = f64::NAN;
    assert!(matches!(m.from_frame(&p, &q2), Err(Error::NotFinite { .. })));
    // from_chart: outside the chart, u not a rotation.
    assert!(matches!(m.from_chart(&Vector3::new(0.0, PI * radius, 0.0), &Matrix3::identity()), Err(Error::OutsideChart { .. })));
    assert!(matches!(m.from_chart(&x, &Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))), Err(Error::Constraint { field: "u", .. })));
    assert!(matches!(m.from_chart(&x, &(Matrix3::identity() * 1.001)), Err(Error::Constraint { field: "u", .. })));
}

// ---------------------------------------------------------------------------
// Closed-form coefficients against extended precision

mod extended {
    use super::*;
    use astro_float::{BigFloat, Consts, RoundingMode};

    const P: usize = 512;
    const RM: RoundingMode = RoundingMode::ToEven;

    struct Hp {
        cc: Consts,
    }

    fn bf(x: f64) -> BigFloat {
        BigFloat::from_f64(x, P)
    }

    fn to_f64(b: &BigFloat) -> f64 {
        format!("{b}").parse().expect("decimal string")
    }

    impl Hp {
        /// (αR², δR², γR⁴, sinc θ, θ cot θ, cos θ, (1 − sinc²θ)/θ², (1 − θcotθ)/θ²)
        /// at θ, in 512-bit arithmetic from the trigonometric closed forms
        /// (their cancellation is harmless at that precision).
        fn coefficients(&mut self, theta: f64) -> [f64; 8] {
            let th = bf(theta);
            let s = th.sin(P, RM, &mut self.cc);
            let c = th.cos(P, RM, &mut self.cc);
            let th2 = th.mul(&th, P, RM);
            let th3 = th2.mul(&th, P, RM);
            let th5 = th3.mul(&th2, P, RM);
            let cot = c.div(&s, P, RM);
            let thcot = th.mul(&cot, P, RM);
            let one = bf(1.0);
            let sc = s.mul(&c, P, RM);
            let alpha = thcot.sub(&one, P, RM).div(&th2, P, RM);
            let delta = th.sub(&sc, P, RM).div(&th3, P, RM);
            let gamma = th.add(&sc, P, RM).sub(&th2.mul(&cot, P, RM).mul(&bf(2.0), P, RM), P, RM).div(&th5, P, RM);
            let sinc = s.div(&th, P, RM);
            let metric_b = one.sub(&sinc.mul(&sinc, P, RM), P, RM).div(&th2, P, RM);
            let frame_c = one.sub(&thcot, P, RM).div(&th2, P, RM);
            [alpha, delta, gamma, sinc, thcot, c, metric_b, frame_c].map(|v| to_f64(&v))
        }
    }

    /// Christoffel symbols, metric, frame and embedding at `x = (3t, 4t, 0)`
    /// (|x| = 5t exact), R = 1, against the same formulas with 512-bit
    /// coefficients, on a log-spaced grid of θ = 5t from 1e-8 to π − 1e-3
    /// (both sides of every series switch). Error per component relative to the
    /// sum of the magnitudes of its terms, bounded by 8ε·(1 + θ/(π − θ)).
    #[test]
    fn chart_coefficients_vs_extended_precision() {
        let mut hp = Hp { cc: Consts::new().expect("constants cache") };
        let m = s3(1.0);
        let mut thetas: Vec<f64> = (0..=56).map(|k| 1e-8 * 10f64.powf(k as f64 / 8.0)).collect();
        thetas.extend((1..=30).map(|k| 0.1 * k as f64 + 0.0137));
        thetas.extend([0.5, 0.9999, 1.0, 1.0001, 2.0, PI - 0.1, PI - 1e-2, PI - 1e-3]);
        let mut worst: f64 = 0.0;
        for theta in thetas {
            // t with a 40-bit mantissa, so 3t, 4t and 5t are exact.
            let e = (theta / 5.0).log2().floor() as i32;
            let t = ((theta / 5.0) * 2f64.powi(39 - e)).round() * 2f64.powi(e - 39);
            let th = 5.0 * t;
            let x = Vector3::new(3.0 * t, 4.0 * t, 0.0);
            let [al, de, ga, sinc, thcot, cos, metric_b, frame_c] = hp.coefficients(th);
            let bound = 8.0 * f64::EPSILON * (1.0 + th / (PI - th));
            // Christoffel symbols.
            let gam = m.christoffel(&x);
            let d = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
            for i in 0..3 {
                for j in 0..3 {
                    for k in 0..3 {
                        let terms = [al * x[j] * d(i, k), al * x[k] * d(i, j), de * d(j, k) * x[i], ga * x[i] * x[j] * x[k]];
                        let want: f64 = terms.iter().sum();
                        let scale: f64 = terms.iter().map(|v| v.abs()).sum();
                        if scale > 0.0 {
                            let err = (gam[i][j][k] - want).abs() / scale;
                            worst = worst.max(err / bound * 8.0 * f64::EPSILON);
                            assert!(err <= bound, "Γ^{i}_{j}{k} at θ = {th}: {err:e} > {bound:e}");
                        }
                    }
                }
            }
            // Metric sinc² I + (1 − sinc²)/θ² xxᵀ.
            let a = sinc * sinc;
            let g_want = Matrix3::identity() * a + x * x.transpose() * metric_b;
            let g = m.metric(&x);
            let err = (g - g_want).amax() / g_want.amax();
            assert!(err <= bound, "metric at θ = {th}: {err:e}");
            worst = worst.max(err / bound * 8.0 * f64::EPSILON);
            // Frame θcotθ I + (1 − θcotθ)/θ² xxᵀ − [x]×.
            let f = m.frame(&x);
            let f_want = Matrix3::identity() * thcot + x * x.transpose() * frame_c
                - Matrix3::new(0.0, -x[2], x[1], x[2], 0.0, -x[0], -x[1], x[0], 0.0);
            let err = (f - f_want).amax() / f_want.amax();
            assert!(err <= bound, "frame at θ = {th}: {err:e}");
            worst = worst.max(err / bound * 8.0 * f64::EPSILON);
            // Embedding (cos θ, sinc θ · x).
            let p = m.embed(&x);
            let p_want = Vector4::new(cos, sinc * x[0], sinc * x[1], 0.0);
            let err = (p - p_want).amax();
            assert!(err <= bound, "embedding at θ = {th}: {err:e}");
            worst = worst.max(err / bound * 8.0 * f64::EPSILON);
        }
        println!("worst error / (1 + θ/(π − θ)) = {worst:e}");
    }
}
