//! Tests of the torus T²(L, R): manifold laws, the numerical geodesic distance
//! (metric-space laws, exact special cases, an independent brute-force check of
//! minimality), the frame bundle laws, parallel transport, holonomy
//! (small loops and Gauss–Bonnet on bands) and typed errors.

use crate::bundle_laws::{check_bundle_at, random_walk_defect, small_loop_holonomy, transport_along, transport_in_chart};
use crate::distance_laws::{check_distance_at, check_distance_laws};
use crate::manifold_laws::check_manifold_at;
use framedyn::bundle::FrameBundle;
use framedyn::lie::Rn;
use framedyn::manifold::{GeodesicDistance, Manifold, Torus2};
use framedyn::Error;
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

type V2 = SVector<f64, 2>;
type V3 = SVector<f64, 3>;
/// Crossings of a ray with the lifts of the target meridian: `(lift, θ, length)`.
type Crossings = Vec<(i64, f64, f64)>;
/// A chart curve `t ↦ (x(t), ẋ(t))`.
type Curve = Box<dyn Fn(f64) -> (V2, V2)>;

fn v2(a: f64, b: f64) -> V2 {
    V2::new(a, b)
}

fn rot(a: f64) -> SMatrix<f64, 2, 2> {
    let (s, c) = a.sin_cos();
    SMatrix::<f64, 2, 2>::new(c, -s, s, c)
}

/// T²(λR, R).
fn torus(lambda: f64, r: f64) -> Torus2 {
    Torus2::new(lambda * r, r).expect("valid torus")
}

/// Deterministic uniform numbers in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn wrap_angle(a: f64) -> f64 {
    Torus2::reduce_angle(a)
}

/// Circle distance of two angles, in [0, π].
fn circ(a: f64, b: f64) -> f64 {
    wrap_angle(b - a).abs()
}

// ---------------------------------------------------------------------------
// Construction and typed errors.

#[test]
fn new_rejects_invalid_parameters() {
    assert!(Torus2::new(2.0, 1.0).is_ok());
    assert!(Torus2::new(1.0 + 1e-12, 1.0).is_ok());
    let field_of = |r: Result<Torus2, Error>| match r {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    };
    assert_eq!(field_of(Torus2::new(1.0, 1.0)), "L"); // L = R: horn torus
    assert_eq!(field_of(Torus2::new(0.5, 1.0)), "L"); // L < R: spindle torus
    assert_eq!(field_of(Torus2::new(-3.0, 1.0)), "L");
    assert_eq!(field_of(Torus2::new(f64::NAN, 1.0)), "L");
    assert_eq!(field_of(Torus2::new(f64::INFINITY, 1.0)), "L");
    assert_eq!(field_of(Torus2::new(2.0, 0.0)), "R");
    assert_eq!(field_of(Torus2::new(2.0, -1.0)), "R");
    assert_eq!(field_of(Torus2::new(2.0, f64::NAN)), "R");
    assert_eq!(field_of(Torus2::new(f64::NAN, f64::NAN)), "R");
    let msg = Torus2::new(1.0, 2.0).unwrap_err().to_string();
    assert!(msg.contains("L") && msg.contains("> R"), "message: {msg}");
}

#[test]
fn chart_and_distance_typed_errors() {
    let t = torus(2.0, 1.0);
    let on = t.embed(&v2(0.4, 1.0));
    let off = on * 1.01;
    for r in [t.chart(&off).map(|_| ()), t.distance(&off, &on).map(|_| ()), t.distance(&on, &off).map(|_| ())] {
        match r {
            Err(Error::Constraint { field: "p", defect, tolerance, .. }) => assert!(defect > tolerance),
            other => panic!("expected Constraint on p, got {other:?}"),
        }
    }
    let nan = V3::new(f64::NAN, 0.0, 0.0);
    assert!(matches!(t.chart(&nan), Err(Error::NotFinite { field: "p" })));
    assert!(matches!(t.chart_tangent(&on, &nan), Err(Error::NotFinite { field: "w" })));
    assert!(matches!(t.check_chart(&v2(f64::NAN, 0.0)), Err(Error::OutsideChart { .. })));
    assert!(matches!(t.minimal_geodesic(&v2(f64::INFINITY, 0.0), &v2(0.0, 0.0)), Err(Error::NotFinite { field: "x1" })));
    assert!(matches!(t.geodesic_endpoint(&v2(0.0, 0.0), 0.3, -1.0), Err(Error::InvalidParameter { field: "length", .. })));
    // A point on the axis is far from the torus and must not panic.
    assert!(t.chart(&V3::zeros()).is_err());
    assert!(t.point_defect(&t.project_point(&V3::zeros())) < 1e-15);
    assert!(t.point_defect(&t.project_point(&V3::new(2.0, 0.0, 0.0))) < 1e-15); // on the centre circle
}

// ---------------------------------------------------------------------------
// Manifold laws.

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The generic manifold laws at random points of random tori
    /// (L/R from 1.05 to 10), with the closed-form K = cos θ / (R (L + R cos θ)).
    /// The angles range beyond (−π, π]: the chart is global.
    #[test]
    fn manifold_laws(lambda in 1.05..10.0f64, r in 0.3..3.0f64, th in -7.0..7.0f64, ph in -7.0..7.0f64) {
        let t = torus(lambda, r);
        let k = th.cos() / (r * (lambda * r + r * th.cos()));
        prop_assert!((t.gaussian_curvature(th) - k).abs() <= 1e-15 * k.abs().max(1e-300));
        let res = check_manifold_at(&t, &v2(th, ph), |_, _| k, 1e-12);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
    }
}

#[test]
fn chart_reduces_angles_and_handles_the_branch_cut() {
    let t = torus(3.0, 1.0);
    for (th, ph) in [(PI, PI), (-PI, -PI), (7.0, -7.0), (0.0, 1e-300), (-0.0, -0.0)] {
        let x = t.chart(&t.embed(&v2(th, ph))).unwrap();
        assert!(x[0] > -PI && x[0] <= PI && x[1] > -PI && x[1] <= PI, "{x:?}");
        assert!(circ(x[0], th) < 1e-15 && circ(x[1], ph) < 1e-15, "{x:?} vs ({th}, {ph})");
    }
    // −0.0 in the embedding (z = −0 on the inner equator, y = −0) must give +π, not −π.
    let x = t.chart(&V3::new(-2.0, -0.0, -0.0)).unwrap();
    assert_eq!(x, v2(PI, PI));
}

// ---------------------------------------------------------------------------
// Distance.

/// Lengths of explicit paths between two chart points (upper bounds of the
/// distance): meridian then parallel, parallel then meridian, and via the
/// inner and outer equators.
fn path_upper_bound(t: &Torus2, a: &V2, b: &V2) -> f64 {
    let (r, l) = (t.small_r(), t.big_l());
    let dphi = circ(a[1], b[1]);
    let dth = circ(a[0], b[0]);
    [
        r * dth + t.rho(b[0]) * dphi,
        t.rho(a[0]) * dphi + r * dth,
        r * (circ(a[0], PI) + circ(PI, b[0])) + (l - r) * dphi,
        r * (circ(a[0], 0.0) + circ(0.0, b[0])) + (l + r) * dphi,
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The distance laws at the chart points of `manifold_laws`: zero on the
    /// diagonal, `√(g dx dx)` for nearby points.
    #[test]
    fn distance_at_chart_points(lambda in 1.05..10.0f64, r in 0.3..3.0f64, th in -7.0..7.0f64, ph in -7.0..7.0f64) {
        let res = check_distance_at(&torus(lambda, r), &v2(th, ph));
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Symmetry, positivity and the triangle inequality; the flat lower bound
    /// √(R² Δθ² + (L − R)² Δφ²) ≤ d ≤ explicit paths; the returned geodesic,
    /// integrated by the exponential map, ends at the target; its half is a
    /// minimal geodesic of half the length.
    #[test]
    fn distance_laws(
        lambda in 1.05..10.0f64, r in 0.5..2.0f64,
        a in (-PI..PI, -PI..PI), b in (-PI..PI, -PI..PI), c in (-PI..PI, -PI..PI),
    ) {
        let t = torus(lambda, r);
        let (xa, xb, xc) = (v2(a.0, a.1), v2(b.0, b.1), v2(c.0, c.1));
        let (pa, pb, pc) = (t.embed(&xa), t.embed(&xb), t.embed(&xc));
        let res = check_distance_laws(&t, &pa, &pb, &pc);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());

        let g = t.minimal_geodesic(&xa, &xb).unwrap();
        let d = g.length;
        let lower = (r * r * circ(a.0, b.0).powi(2) + ((lambda - 1.0) * r * circ(a.1, b.1)).powi(2)).sqrt();
        prop_assert!(d >= lower * (1.0 - 1e-14), "d = {d} below the flat bound {lower}");
        let upper = path_upper_bound(&t, &xa, &xb);
        prop_assert!(d <= upper * (1.0 + 1e-14), "d = {d} above an explicit path {upper}");
        let end = t.geodesic_endpoint(&xa, g.direction, d).unwrap();
        let miss = (t.embed(&end) - pb).norm();
        prop_assert!(miss <= 1e-9 * r, "geodesic misses the target by {miss:e}");
        prop_assert!(circ(g.end_lift[0], b.0) < 1e-9 && circ(g.end_lift[1], b.1) < 1e-12, "{:?}", g.end_lift);
        let mid = t.geodesic_endpoint(&xa, g.direction, 0.5 * d).unwrap();
        let dm = t.chart_distance(&xa, &mid).unwrap();
        prop_assert!((dm - 0.5 * d).abs() <= 1e-10 * d, "half geodesic: {dm} vs {}", 0.5 * d);
    }
}

/// Points on one meridian circle: the arc R|Δθ| (Δθ wrapped to [−π, π]) is
/// minimal (any path is at least R × its θ-variation); nearly-meridian pairs
/// (Δφ = 1e-9 … 1e-6, above the exact shortcut) lie between R|Δθ| and the
/// meridian-then-parallel path, and follow R|Δθ| + Δφ²/(2R ∫dθ/ρ̃²).
#[test]
fn distance_along_a_meridian() {
    let mut rng = Rng(0x5EED_0001);
    for _ in 0..40 {
        let (lambda, r) = (rng.range(1.05, 10.0), rng.range(0.5, 2.0));
        let t = torus(lambda, r);
        let (th1, th2, ph) = (rng.range(-PI, PI), rng.range(-PI, PI), rng.range(-PI, PI));
        let dth = circ(th1, th2);
        let d = t.distance(&t.embed(&v2(th1, ph)), &t.embed(&v2(th2, ph))).unwrap();
        assert!((d - r * dth).abs() <= 1e-15 * r * (1.0 + dth), "meridian: {d} vs {}", r * dth);

        let dphi = 10f64.powf(rng.range(-9.0, -6.0));
        let d = t.chart_distance(&v2(th1, ph), &v2(th2, ph + dphi)).unwrap();
        // Second-order excess of the near-meridian geodesic (units of R):
        // Δφ²/(2 I), I = ∫ dθ/ρ̃² over the shorter arc, by Simpson's rule.
        let n = 2000;
        let dsig = wrap_angle(th2 - th1);
        let integral: f64 = (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n { 1.0 } else if i % 2 == 1 { 4.0 } else { 2.0 };
                w / (lambda + (th1 + dsig * i as f64 / n as f64).cos()).powi(2)
            })
            .sum::<f64>()
            * dsig.abs()
            / (3.0 * n as f64);
        let predicted = r * (dth + dphi * dphi / (2.0 * integral));
        assert!(d >= r * dth * (1.0 - 1e-13) && d <= r * dth + t.rho(th2) * dphi, "near-meridian bounds: {d}, R dth = {}, dphi = {dphi:e}, λ = {lambda}, θ = {th1} → {th2}", r * dth);
        if dth > 0.3 {
            assert!((d - predicted).abs() <= 1e-13 * r, "near-meridian: {d} vs {predicted}");
        }
    }
}

/// The inner equator θ = π is a geodesic and minimal for every |Δφ| ≤ π: any
/// path is at least ∫ρ|dφ| ≥ (L − R)|Δφ| long.
#[test]
fn distance_along_the_inner_equator() {
    let mut worst: f64 = 0.0;
    for &lambda in &[1.05, 1.5, 2.0, 4.0, 10.0] {
        let t = torus(lambda, 0.7);
        for k in 0..=16 {
            let dphi = PI * k as f64 / 16.0;
            let p = t.embed(&v2(PI, 0.3));
            let q = t.embed(&v2(PI, 0.3 + dphi));
            let d = t.distance(&p, &q).unwrap();
            let exact = (t.big_l() - t.small_r()) * dphi;
            let err = (d - exact).abs() / exact.max(1e-300);
            worst = worst.max(if exact == 0.0 { d } else { err });
        }
    }
    assert!(worst <= 1e-13, "inner equator: worst relative error {worst:e}");
}

/// The outer equator θ = 0 is a geodesic; it is minimal exactly up to its
/// first conjugate point Δφ_c = π √(R/(L + R)) (Jacobi equation with
/// K = 1/(R(L + R))) and strictly longer than the distance beyond it (where the
/// minimal geodesics leave the equator).
#[test]
fn distance_along_the_outer_equator() {
    let mut worst: f64 = 0.0;
    for &lambda in &[1.05, 2.0, 4.0, 10.0] {
        let t = torus(lambda, 1.3);
        let (l, r) = (t.big_l(), t.small_r());
        let conj = PI * (r / (l + r)).sqrt();
        for k in 1..=20 {
            let dphi = 0.99 * conj * k as f64 / 20.0;
            let g = t.minimal_geodesic(&v2(0.0, -1.0), &v2(0.0, -1.0 + dphi)).unwrap();
            worst = worst.max((g.length / ((l + r) * dphi) - 1.0).abs());
            assert!((g.direction - FRAC_PI_2).abs() < 1e-12);
        }
        for k in 0..=10 {
            let dphi = 1.01 * conj + (PI - 1.01 * conj) * k as f64 / 10.0;
            let g = t.minimal_geodesic(&v2(0.0, -1.0), &v2(0.0, -1.0 + dphi)).unwrap();
            let arc = (l + r) * dphi;
            assert!(g.length < arc * (1.0 - 1e-5), "λ = {lambda}, Δφ = {dphi}: {} not below the arc {arc}", g.length);
            assert!((g.direction - FRAC_PI_2).abs() > 1e-3, "minimal geodesic should leave the equator");
        }
    }
    assert!(worst <= 1e-13, "outer equator below the conjugate point: worst relative error {worst:e}");
}

/// Geodesic rays by classical RK4 on the Christoffel form
/// `θ'' = −Γ^θ_φφ φ'²`, `φ'' = −2Γ^φ_θφ θ'φ'` (arc length), independent of the
/// library's Clairaut shooting, with steps `h·min(R, ρ(θ))` (the local
/// length scale). Returns every crossing of a lift `φ₂ + 2πj` within arc
/// length `limit`: `(j, θ, length)`.
fn ray_crossings(t: &Torus2, x1: &V2, alpha: f64, phi2: f64, limit: f64, h: f64) -> Crossings {
    let f = |y: &[f64; 4]| -> [f64; 4] {
        let g = t.christoffel(&v2(y[0], y[1]));
        [y[2], y[3], -g[0][1][1] * y[3] * y[3], -2.0 * g[1][0][1] * y[2] * y[3]]
    };
    let rk4 = |y: &[f64; 4], h: f64| -> [f64; 4] {
        let add = |a: &[f64; 4], b: &[f64; 4], s: f64| [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]];
        let k1 = f(y);
        let k2 = f(&add(y, &k1, 0.5 * h));
        let k3 = f(&add(y, &k2, 0.5 * h));
        let k4 = f(&add(y, &k3, h));
        [0, 1, 2, 3].map(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    let (sa, ca) = alpha.sin_cos();
    let mut y = [x1[0], x1[1], ca / t.small_r(), sa / t.rho(x1[0])];
    let mut s = 0.0;
    let mut out = Vec::new();
    while s < limit {
        let h = h * t.small_r().min(t.rho(y[0]));
        let yn = rk4(&y, h);
        let (lo, hi) = (y[1].min(yn[1]), y[1].max(yn[1]));
        let j0 = ((lo - phi2) / TAU).ceil() as i64;
        let mut j = j0;
        while phi2 + TAU * j as f64 <= hi {
            let target = phi2 + TAU * j as f64;
            // Secant on a partial RK4 step from y for φ(τ) = target.
            let (mut ta, mut fa) = (0.0, y[1] - target);
            let (mut tb, mut fb) = (h, yn[1] - target);
            let mut yt = yn;
            let mut tau = h;
            for _ in 0..30 {
                if fb == fa {
                    break;
                }
                tau = tb - fb * (tb - ta) / (fb - fa);
                yt = rk4(&y, tau);
                let ft = yt[1] - target;
                ta = tb;
                fa = fb;
                tb = tau;
                fb = ft;
                if ft.abs() < 1e-15 {
                    break;
                }
            }
            if s + tau <= limit {
                out.push((j, yt[0], s + tau));
            }
            j += 1;
        }
        y = yn;
        s += h;
    }
    out
}

/// Brute-force minimality check: shoots `n` rays in all directions from `x1`
/// over arc length `horizon` (refining where the end angle at a lift of the
/// target meridian jumps), detects every ray pair between which a geodesic to
/// `x2` passes, refines those that may be shorter than `limit` (first-variation
/// bound) by the Illinois method on the direction, and returns the shortest
/// length found.
fn fan_shortest(t: &Torus2, x1: &V2, x2: &V2, limit: f64, horizon: f64, n: usize, h: f64) -> f64 {
    let th2 = x2[0];
    let rays = |alpha: f64| ray_crossings(t, x1, alpha, x2[1], horizon, h);
    // For a ray pair and a lift j: the level θ₂ + 2πm crossed between them.
    let mut dirs: Vec<(f64, Crossings)> = Vec::new();
    for k in 0..n {
        let alpha = -PI + TAU * (k as f64 + 0.5) / n as f64;
        dirs.push((alpha, rays(alpha)));
    }
    dirs.push((dirs[0].0 + TAU, dirs[0].1.clone()));
    let mut best = limit;
    let mut i = 0;
    while i + 1 < dirs.len() {
        let (a0, ref c0) = dirs[i];
        let (a1, ref c1) = dirs[i + 1];
        // Subdivide where a common lift's end angle jumps, or where a lift is
        // reached by one ray only (towards the edge of the reaching set, e.g.
        // near-meridian directions, where Θ → ±∞): an unresolved ray pair.
        let jump = c0.iter().any(|&(j, th, _)| c1.iter().any(|&(j1, th1, _)| j1 == j && (th1 - th).abs() > 0.2));
        let edge = c0.iter().any(|&(j, _, _)| c1.iter().all(|c| c.0 != j))
            || c1.iter().any(|&(j, _, _)| c0.iter().all(|c| c.0 != j));
        if (jump && a1 - a0 > 1e-9) || (edge && a1 - a0 > 1e-7) {
            let am = 0.5 * (a0 + a1);
            let cm = rays(am);
            dirs.insert(i + 1, (am, cm));
            continue;
        }
        for &(j, tha, la) in c0 {
            let Some(&(_, thb, lb)) = c1.iter().find(|c| c.0 == j) else { continue };
            let m = ((0.5 * (tha + thb) - th2) / TAU).round();
            let level = th2 + TAU * m;
            if (tha - level) * (thb - level) > 0.0 {
                continue;
            }
            // First-variation bound: the root is at least min(la, lb) − R|Δθ| long.
            if la.min(lb) - t.small_r() * (tha - thb).abs() > best {
                continue;
            }
            let (mut xa, mut fa, mut xb, mut fb) = (a0, tha - level, a1, thb - level);
            let mut root = None;
            for _ in 0..80 {
                let x = xb - fb * (xb - xa) / (fb - fa);
                let Some(&(_, th, l)) = rays(x).iter().find(|c| c.0 == j) else { break };
                let fx = th - level;
                if fx.abs() < 1e-10 {
                    root = Some(l);
                    break;
                }
                if fx * fb < 0.0 {
                    xa = xb;
                    fa = fb;
                } else {
                    fa *= 0.5;
                }
                xb = x;
                fb = fx;
                if (xb - xa).abs() < 1e-15 {
                    break;
                }
            }
            // Only converged roots count (an unconverged bracket is not a geodesic).
            let Some(len) = root else { continue };
            best = best.min(len);
        }
        i += 1;
    }
    best
}

/// No geodesic shorter than the returned distance exists, and the brute-force
/// fan finds the returned one (to its RK4 accuracy): an independent check of
/// the global minimality, on hand-picked hard pairs (competing families,
/// inner-equator crossings, antipodes) and random ones.
#[test]
fn distance_is_minimal_against_brute_force_fan() {
    let mut pairs: Vec<(f64, V2, V2)> = vec![
        (10.0, v2(0.0, 0.0), v2(0.0, PI)),          // wrapping and oscillating families within 4e-5
        (10.0, v2(0.2, 0.0), v2(2.9, -3.0)),        // through the inner half
        (2.0, v2(PI - 0.1, 0.0), v2(-PI + 0.1, PI)), // across the inner equator
        (2.0, v2(0.0, 0.0), v2(0.0, 1.9)),          // past the conjugate point of the outer equator
        (1.05, v2(0.5, 0.1), v2(-2.0, 2.5)),
        (4.0, v2(1.5, 0.0), v2(-1.5, 3.0)),
        // Two oscillating geodesics within 5e-9 of each other: a coarser
        // sampling of the oscillating family returns the longer one.
        (9.536_351_164_693_055, v2(0.808_707_672_121_032_7, 0.0), v2(1.418_273_214_266_801_7, 2.846_829_278_829_918)),
    ];
    let mut rng = Rng(0x5EED_0002);
    for _ in 0..4 {
        let lambda = rng.range(1.05, 10.0);
        pairs.push((lambda, v2(rng.range(-PI, PI), 0.0), v2(rng.range(-PI, PI), rng.range(-PI, PI))));
    }
    for (lambda, x1, x2) in pairs {
        let t = torus(lambda, 1.0);
        let d = t.chart_distance(&x1, &x2).unwrap();
        let fan = fan_shortest(&t, &x1, &x2, d * (1.0 + 1e-3), 1.2 * d + PI, 180, 0.01);
        let rel = (fan - d) / d;
        // The fan's RK4 (steps 0.01 min(R, ρ)) is accurate to ~1e-8 on the
        // thinnest tori, to ~1e-10 from L/R = 1.5 on.
        let tol = if lambda < 1.5 { 1e-7 } else { 1e-9 };
        assert!(rel >= -tol, "λ = {lambda}, {x1:?} → {x2:?}: brute force found a shorter geodesic: {fan} < {d}");
        assert!(rel <= tol, "λ = {lambda}, {x1:?} → {x2:?}: brute force did not find the geodesic: {fan} vs {d}");
    }
}

/// Extended version of the brute-force check (about 30 s; run with
/// `--ignored`): 150 random pairs, biased towards thin tori, the inner
/// equator, θ-symmetric pairs and near-antipodal meridians.
#[test]
#[ignore]
fn distance_is_minimal_against_brute_force_fan_extended() {
    let mut rng = Rng(0x5EED_0003);
    let mut worst: f64 = 0.0;
    for k in 0..150 {
        let lambda = if k % 4 == 0 { rng.range(1.05, 1.2) } else { rng.range(1.05, 12.0) };
        let t = torus(lambda, 1.0);
        let th1 = if k % 3 == 0 { PI - rng.range(0.0, 0.3) } else { rng.range(-PI, PI) };
        let th2 = if k % 5 == 0 { -th1 + rng.range(-0.01, 0.01) } else { rng.range(-PI, PI) };
        let dphi = if k % 7 == 0 { PI - rng.range(0.0, 0.01) } else { rng.range(-PI, PI) };
        let (x1, x2) = (v2(th1, 0.0), v2(th2, dphi));
        let d = t.chart_distance(&x1, &x2).unwrap();
        let fan = fan_shortest(&t, &x1, &x2, d * (1.0 + 1e-3), 1.2 * d + PI, 180, 0.015);
        let rel = (fan - d) / d;
        let tol = if lambda < 1.5 { 1e-7 } else { 5e-9 };
        assert!(rel.abs() <= tol, "λ = {lambda}, {x1:?} → {x2:?}: d = {d}, brute force {fan}");
        worst = worst.max(rel.abs());
    }
    println!("worst relative difference {worst:e}");
}

// ---------------------------------------------------------------------------
// Frame bundle.

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The generic bundle laws: chart round trips, from_frame, horizontal lift
    /// (ẋ = Σ v_a q_a, q̇_a normal — this fixes the sign ȧ = +sin θ φ̇) and the
    /// vertical generator. The velocity is scaled by the local radii
    /// `min(R, ρ)`: the laws differentiate with a fixed step 1e-4, whose
    /// truncation error `~1e-9 |v|³/min(R, ρ)²` must stay below their 1e-7.
    #[test]
    fn bundle_laws(
        lambda in 1.05..10.0f64, r in 0.3..3.0f64,
        th in -7.0..7.0f64, ph in -7.0..7.0f64, a in -7.0..7.0f64,
        v in (-1.0..1.0f64, -1.0..1.0f64),
    ) {
        let t = torus(lambda, r);
        let scale = r.min(t.rho(th));
        let res = check_bundle_at(&t, &v2(th, ph), &rot(a), &v2(v.0 * scale, v.1 * scale), 1e-12);
        prop_assert!(res.is_ok(), "{}", res.unwrap_err());
        // The chart reduces the unbounded group angles.
        let g = t.from_chart(&v2(th, ph), &rot(a)).unwrap();
        let (x, u) = t.to_chart(&g).unwrap();
        prop_assert!(x[0] > -PI && x[0] <= PI && x[1] > -PI && x[1] <= PI);
        prop_assert!(circ(x[0], th) < 1e-14 && circ(x[1], ph) < 1e-14 && (u - rot(a)).amax() < 1e-15);
    }
}

#[test]
fn random_walk_keeps_frames_exact() {
    for (k, &lambda) in [1.05, 2.0, 10.0].iter().enumerate() {
        let t = torus(lambda, 0.8);
        let g0 = t.from_chart(&v2(0.3, -1.0), &rot(0.4)).unwrap();
        let n = if k == 1 { 1_000_000 } else { 200_000 };
        let defect = random_walk_defect(&t, &g0, n, 0.01, 0xC0FFEE + k as u64);
        assert!(defect <= 1e-13, "λ = {lambda}: defect {defect:e} after {n} steps");
    }
}

/// Parallel transport by the horizontal lift (RKMK4 in the group) agrees with
/// the paper's coordinate transport V̇ = −Γ ẋ V on curves crossing both
/// equators and winding around the tube.
#[test]
fn transport_agrees_with_chart_transport() {
    let curves: Vec<(f64, Curve)> = vec![
        (2.0, Box::new(|t: f64| (v2(0.3 + 2.8 * (TAU * t).sin(), -1.0 + 4.0 * t), v2(2.8 * TAU * (TAU * t).cos(), 4.0)))),
        (1.05, Box::new(|t: f64| (v2(2.0 + 7.0 * t, 0.5 * t * t), v2(7.0, t)))),
        (10.0, Box::new(|t: f64| (v2(PI - 1.0 + 2.0 * t, 3.0 * (PI * t).sin()), v2(2.0, 3.0 * PI * (PI * t).cos())))),
    ];
    let mut worst: f64 = 0.0;
    for (lambda, curve) in &curves {
        let t = torus(*lambda, 1.0);
        let (x0, _) = curve(0.0);
        let (x1, _) = curve(1.0);
        let u0 = rot(0.7);
        let g0 = t.from_chart(&x0, &u0).unwrap();
        let g1 = transport_along(&t, &g0, curve, 4000);
        let v1 = transport_in_chart(&t, &(t.frame(&x0) * u0), curve, 4000);
        let q1 = t.frame_vectors(&g1);
        for a in 0..2 {
            let e = t.embed_tangent(&x1, &v1.column(a).into_owned());
            worst = worst.max((q1.column(a) - e).amax());
        }
        assert!((t.position(&g1) - t.embed(&x1)).amax() <= 1e-10 * t.big_l());
    }
    assert!(worst <= 1e-10, "transport: worst frame difference {worst:e}");
}

/// Holonomy of small loops: angle = K π ε² (1 + O(ε²)). K varies on the torus
/// but its first-order variation integrates to zero over the disc, so the
/// relative error falls by 4 when ε halves. Sharper, Gauss–Bonnet is exact for
/// the chart loop itself: it bounds the ellipse θ = θ₀ + (ε/R)x,
/// φ = φ₀ + (ε/ρ₀)y, x² + y² ≤ 1, on which K√g = cos θ, so the holonomy is
/// ∫∫ cos θ dθ dφ = K(θ₀) π ε² · 2J₁(a)/a, a = ε/R (the relative correction is
/// −a²/8 + …, whatever K).
#[test]
fn small_loop_holonomy_converges_quadratically() {
    // 2J₁(a)/a = Σ (−a²/4)^k / (k! (k+1)!)
    let bessel = |a: f64| (0..12).fold((1.0, 0.0), |(term, sum), k| (term * (-a * a / 4.0) / ((k + 1) * (k + 2)) as f64, sum + term)).1;
    let mut worst_exact: f64 = 0.0;
    for &(lambda, r) in &[(2.0, 1.0), (5.0, 1.0), (1.3, 0.6)] {
        let t = torus(lambda, r);
        for &th in &[0.0, 0.4, 1.2, 2.2, PI, -2.7] {
            let x0 = v2(th, 0.5);
            let mut errs = Vec::new();
            for &eps in &[0.08, 0.04, 0.02, 0.01] {
                let eps = eps * r;
                let (angle, expected) = small_loop_holonomy(&t, &x0, eps, 400);
                errs.push(((angle - expected) / expected).abs());
                let exact = expected * bessel(eps / r);
                worst_exact = worst_exact.max(((angle - exact) / exact).abs());
            }
            for w in errs.windows(2) {
                let order = (w[0] / w[1]).log2();
                assert!((order - 2.0).abs() < 0.05, "λ = {lambda}, θ = {th}: errors {errs:?}, order {order}");
            }
            assert!(errs[3] < 2e-5, "λ = {lambda}, θ = {th}: errors {errs:?}");
        }
    }
    assert!(worst_exact <= 1e-9, "small loops: holonomy vs exact ∫K dA, worst relative error {worst_exact:e}");
}

/// Rotation angle of the frame transported once around the parallel θ₀
/// (φ: 0 → 2π), relative to its start, by the bundle (RKMK4) and by the
/// coordinate transport.
fn parallel_holonomy(t: &Torus2, th0: f64) -> (f64, f64) {
    let curve = |s: f64| (v2(th0, TAU * s), v2(0.0, TAU));
    let x0 = v2(th0, 0.0);
    let g0 = t.from_chart(&x0, &rot(0.3)).unwrap();
    let g1 = transport_along(t, &g0, &curve, 2000);
    let w = t.frame_vectors(&g0).transpose() * t.frame_vectors(&g1);
    let bundle = w[(1, 0)].atan2(w[(0, 0)]);
    let v1 = transport_in_chart(t, &t.frame(&x0), &curve, 2000);
    let m = t.frame(&x0).try_inverse().unwrap() * v1; // E⁻¹ V: the rotation U(angle)
    (bundle, m[(1, 0)].atan2(m[(0, 0)]))
}

/// ∫K dA over the band θ₁ ≤ θ ≤ θ₂ from the closed-form Riemann tensor and
/// metric (Gauss–Legendre, 8 nodes on each of 64 panels).
fn band_curvature(t: &Torus2, th1: f64, th2: f64) -> f64 {
    const X: [f64; 4] = [0.183_434_642_495_649_8, 0.525_532_409_916_329, 0.796_666_477_413_626_7, 0.960_289_856_497_536_3];
    const W: [f64; 4] = [0.362_683_783_378_362, 0.313_706_645_877_887_3, 0.222_381_034_453_374_5, 0.101_228_536_290_376_3];
    let panels = 64;
    let hw = 0.5 * (th2 - th1) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let c = th1 + (2 * p + 1) as f64 * hw;
        for (x, w) in X.iter().zip(W.iter()) {
            for th in [c - hw * x, c + hw * x] {
                let pt = v2(th, 0.0);
                let e = t.frame(&pt);
                let k = t.sectional_curvature(&pt, &e.column(0).into_owned(), &e.column(1).into_owned());
                sum += w * hw * k * t.metric(&pt).determinant().sqrt();
            }
        }
    }
    TAU * sum
}

/// Gauss–Bonnet on bands: the holonomies of two parallels differ by
/// ∫K dA = 2π (sin θ₂ − sin θ₁) (mod 2π), also across the inner equator where
/// K < 0; the total curvature of the torus is 0 (and ±4π on its outer/inner half).
#[test]
fn gauss_bonnet_on_bands() {
    let pairs: [(f64, f64); 7] = [(-0.5, 0.7), (0.2, 1.4), (1.2, 2.8), (2.5, 3.8), (2.9, 3.5), (-2.0, -1.0), (-1.0, 4.0)];
    let mut worst: f64 = 0.0;
    for &lambda in &[1.05, 2.0, 10.0] {
        let t = torus(lambda, 0.9);
        for &(th1, th2) in &pairs {
            let exact = TAU * (th2.sin() - th1.sin());
            let integral = band_curvature(&t, th1, th2);
            assert!((integral - exact).abs() <= 1e-12, "∫K dA = {integral} vs {exact}");
            let (b1, c1) = parallel_holonomy(&t, th1);
            let (b2, c2) = parallel_holonomy(&t, th2);
            worst = worst.max(wrap_angle(b2 - b1 - exact).abs());
            worst = worst.max(wrap_angle(c2 - c1 - exact).abs());
            // Each parallel alone: the frame turns by 2π sin θ₀ relative to E.
            worst = worst.max(wrap_angle(b1 - TAU * th1.sin()).abs());
        }
        let total = band_curvature(&t, -PI, PI);
        assert!(total.abs() <= 1e-12, "total curvature {total:e}");
        assert!((band_curvature(&t, -FRAC_PI_2, FRAC_PI_2) - 2.0 * TAU).abs() <= 1e-12);
        assert!((band_curvature(&t, FRAC_PI_2, 1.5 * PI) + 2.0 * TAU).abs() <= 1e-12);
    }
    assert!(worst <= 1e-10, "band holonomy: worst error {worst:e}");
}

#[test]
fn bundle_typed_errors() {
    let t = torus(2.5, 1.0);
    let x = v2(0.7, -0.4);
    let p = t.embed(&x);
    let g = t.from_chart(&x, &rot(0.3)).unwrap();
    let q = t.frame_vectors(&g);
    assert!(t.from_frame(&p, &q).is_ok());
    let constraint = |r: Result<Rn<3>, Error>| match r {
        Err(Error::Constraint { field, constraint, .. }) => (field, constraint),
        other => panic!("expected Constraint, got {other:?}"),
    };
    // Point off the torus.
    assert_eq!(constraint(t.from_frame(&(p * 1.001), &q)).0, "p");
    // Not orthonormal: scaled, or sheared.
    assert_eq!(constraint(t.from_frame(&p, &(q * 1.01))).0, "q");
    let mut sheared = q;
    sheared.set_column(1, &(q.column(1) + q.column(0) * 0.1).normalize());
    assert_eq!(constraint(t.from_frame(&p, &sheared)).0, "q");
    // Negatively oriented: columns swapped, or one reversed.
    let mut swapped = q;
    swapped.swap_columns(0, 1);
    let (field, what) = constraint(t.from_frame(&p, &swapped));
    assert!(field == "q" && what.contains("oriented"), "{what}");
    let mut flipped = q;
    flipped.set_column(1, &(-q.column(1)));
    assert!(constraint(t.from_frame(&p, &flipped)).1.contains("oriented"));
    // Not tangent: rotated out of the tangent plane.
    let n = V3::new(0.7f64.cos() * (-0.4f64).cos(), 0.7f64.cos() * (-0.4f64).sin(), 0.7f64.sin());
    let mut tilted = q;
    tilted.set_column(0, &(q.column(0) * 0.6 + n * 0.8));
    assert!(constraint(t.from_frame(&p, &tilted)).1.contains("tangent"));
    // Non-finite input.
    let mut nan = q;
    nan[(2, 1)] = f64::NAN;
    assert!(matches!(t.from_frame(&p, &nan), Err(Error::NotFinite { field: "q" })));
    assert!(matches!(t.from_frame(&V3::new(f64::NAN, 0.0, 0.0), &q), Err(Error::NotFinite { field: "p" })));
    // from_chart: u must be a rotation.
    let reflection = SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, -1.0);
    assert_eq!(constraint(t.from_chart(&x, &reflection)).0, "u");
    assert_eq!(constraint(t.from_chart(&x, &(rot(0.3) * 1.1))).0, "u");
    assert!(matches!(t.from_chart(&v2(f64::NAN, 0.0), &rot(0.3)), Err(Error::NotFinite { field: "x" })));
    assert!(matches!(t.to_chart(&Rn(V3::new(0.0, f64::INFINITY, 0.0))), Err(Error::NotFinite { field: "g" })));
    assert_eq!(t.bundle_defect(&Rn(V3::new(0.0, f64::NAN, 0.0))), f64::INFINITY);
}
