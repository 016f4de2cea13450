//! The paper's coordinate formulation (`framedyn::coords`): its generic chart
//! geometry against the `f64` manifolds and against automatic differentiation
//! of its own metric; conservation laws along a classical RK4 on `(q, q̇)`;
//! the paper's printed formulas of §5–§6 (confirmed, or shown wrong as SPEC
//! §8 says); SPEC §7 reference results; the breakdown at the pole.

use framedyn::body::{Affine, Gyroscope, Point, Signature};
use framedyn::coords::*;
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2, Sphere3};
use framedyn::potential::{green_tensor, Free, Potential, Scalar};
use framedyn::Error;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3, Vector4};
use num_dual::{DualNum, DualSVec64};
use proptest::prelude::*;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

/// Largest entry of `a − b` relative to `max(1, |b|_max)`.
fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

fn conn_diff<const N: usize>(a: &[[[f64; N]; N]; N], b: &[[[f64; N]; N]; N]) -> f64 {
    let mut d: f64 = 0.0;
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                d = d.max((a[i][j][k] - b[i][j][k]).abs() / b[i][j][k].abs().max(1.0));
            }
        }
    }
    d
}

/// One classical RK4 step of `q̈ = a(q, q̇)` (the Euler–Lagrange accelerations).
fn rk4_step<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q: &SVector<f64, Q>,
    v: &SVector<f64, Q>,
    h: f64,
) -> (SVector<f64, Q>, SVector<f64, Q>) {
    let acc = |q: &SVector<f64, Q>, v: &SVector<f64, Q>| accelerations(sys, q, v).expect("EL accelerations");
    let a1 = acc(q, v);
    let (q2, v2) = (q + v * (h / 2.0), v + a1 * (h / 2.0));
    let a2 = acc(&q2, &v2);
    let (q3, v3) = (q + v2 * (h / 2.0), v + a2 * (h / 2.0));
    let a3 = acc(&q3, &v3);
    let (q4, v4) = (q + v3 * h, v + a3 * h);
    let a4 = acc(&q4, &v4);
    (q + (v + v2 * 2.0 + v3 * 2.0 + v4) * (h / 6.0), v + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0))
}

/// Integrates `n` RK4 steps of size `h`, calling `observe` after each.
fn integrate<L: Lagrangian<Q>, const Q: usize>(
    sys: &L,
    q0: &SVector<f64, Q>,
    v0: &SVector<f64, Q>,
    h: f64,
    n: usize,
    mut observe: impl FnMut(&SVector<f64, Q>, &SVector<f64, Q>),
) -> (SVector<f64, Q>, SVector<f64, Q>) {
    let (mut q, mut v) = (*q0, *v0);
    for _ in 0..n {
        (q, v) = rk4_step(sys, &q, &v, h);
        observe(&q, &v);
    }
    (q, v)
}

/// Largest drift of each invariant `inv(q, q̇)` along `n` RK4 steps of size `h`.
fn drifts<L: Lagrangian<Q>, const Q: usize, const M: usize>(
    sys: &L,
    q0: &SVector<f64, Q>,
    v0: &SVector<f64, Q>,
    h: f64,
    n: usize,
    inv: impl Fn(&SVector<f64, Q>, &SVector<f64, Q>) -> [f64; M],
) -> [f64; M] {
    let i0 = inv(q0, v0);
    let mut d = [0.0; M];
    integrate(sys, q0, v0, h, n, |q, v| {
        let i = inv(q, v);
        for k in 0..M {
            d[k] = f64::max(d[k], (i[k] - i0[k]).abs());
        }
    });
    d
}

/// Asserts `RK4`-like convergence of conservation errors: the drifts at `h`
/// and `h/2` over the same time are both below `tol` and their ratio is that
/// of a fourth-order method (16, accepted in [11, 23]).
fn assert_fourth_order<const M: usize>(name: &str, coarse: [f64; M], fine: [f64; M], tol: [f64; M]) {
    for k in 0..M {
        let ratio = coarse[k] / fine[k];
        eprintln!("{name}[{k}]: drift(h) = {:.3e}, drift(h/2) = {:.3e}, ratio {ratio:.2}", coarse[k], fine[k]);
        assert!(coarse[k] <= tol[k], "{name}[{k}]: drift {:e} > {:e}", coarse[k], tol[k]);
        assert!((11.0..=23.0).contains(&ratio), "{name}[{k}]: drift ratio {ratio} is not that of an order-4 method");
    }
}

/// Derivative of `f` along `v` at `x`, by forward-mode AD.
fn directional<const N: usize, const K: usize>(
    f: impl Fn(&SVector<num_dual::Dual64, N>) -> SMatrix<num_dual::Dual64, K, K>,
    x: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> SMatrix<f64, K, K> {
    let xd = SVector::<num_dual::Dual64, N>::from_fn(|i, _| num_dual::Dual64::new(x[i], v[i]));
    f(&xd).map(|d| d.eps)
}

/// The Levi-Civita connection coefficients of the chart's frame field,
/// computed independently from the chart's metric and frame by automatic
/// differentiation: Christoffel symbols from `∂g` (Koszul), then
/// `Γ^A_{BC} = E^A_i (∂_C E^i_B + Γ^i_{jk} E^j_C E^k_B)`.
fn koszul_frame_connection<C: ChartGeometry<N, E>, const N: usize, const E: usize>(
    c: &C,
    x: &SVector<f64, N>,
) -> [[[f64; N]; N]; N] {
    let g = c.metric(x);
    let gi = g.try_inverse().unwrap();
    let unit = |j: usize| SVector::<f64, N>::from_fn(|i, _| if i == j { 1.0 } else { 0.0 });
    let dg: Vec<SMatrix<f64, N, N>> = (0..N).map(|j| directional(|y| c.metric(y), x, &unit(j))).collect();
    let de: Vec<SMatrix<f64, N, N>> = (0..N).map(|j| directional(|y| c.frame(y), x, &unit(j))).collect();
    let mut chr = [[[0.0; N]; N]; N];
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                let mut s = 0.0;
                for l in 0..N {
                    s += 0.5 * gi[(i, l)] * (dg[j][(l, k)] + dg[k][(l, j)] - dg[l][(j, k)]);
                }
                chr[i][j][k] = s;
            }
        }
    }
    let e = c.frame(x);
    let ei = e.try_inverse().unwrap();
    let mut out = [[[0.0; N]; N]; N];
    for a in 0..N {
        for b in 0..N {
            for cc in 0..N {
                // ∇_{E_C} E_B in chart components.
                let mut nab = SVector::<f64, N>::zeros();
                for i in 0..N {
                    let mut s = 0.0;
                    for j in 0..N {
                        s += e[(j, cc)] * de[j][(i, b)];
                        for k in 0..N {
                            s += chr[i][j][k] * e[(j, cc)] * e[(k, b)];
                        }
                    }
                    nab[i] = s;
                }
                out[a][b][cc] = (ei * nab)[a];
            }
        }
    }
    out
}

/// Self-consistency of a generic chart at `x`, independent of any other
/// implementation: the embedding Jacobian is the AD derivative of the
/// embedding, the metric is the induced one (`JᵀηJ`), the frame is
/// orthonormal, the coframe is its inverse, and the frame connection equals
/// the Levi-Civita one computed from the metric. Returns the worst defect.
fn chart_self_consistency<C: ChartGeometry<N, E>, const N: usize, const E: usize>(c: &C, x: &SVector<f64, N>) -> f64 {
    let jac = c.embed_jacobian(x);
    let mut worst: f64 = 0.0;
    for j in 0..N {
        let xd = SVector::<num_dual::Dual64, N>::from_fn(|i, _| num_dual::Dual64::new(x[i], if i == j { 1.0 } else { 0.0 }));
        let col = c.embed(&xd).map(|d| d.eps);
        worst = worst.max((col - jac.column(j)).amax() / jac.amax().max(1.0));
    }
    let g = c.metric(x);
    worst = worst.max(rel(&(jac.transpose() * c.ambient_metric() * jac), &g));
    let e = c.frame(x);
    worst = worst.max(rel(&(e.transpose() * g * e), &SMatrix::<f64, N, N>::identity()));
    worst = worst.max(rel(&(c.coframe(x) * e), &SMatrix::<f64, N, N>::identity()));
    worst = worst.max(conn_diff(&c.frame_connection(x), &koszul_frame_connection(c, x)));
    worst
}

// ---------------------------------------------------------------------------
// Potentials written for these tests through the `Potential` trait
// ---------------------------------------------------------------------------

/// `V = a·(z/R)² + b·z/R` (on S² the paper's integrable `α̂ cos²(r/R) + β̂ cos(r/R)`,
/// §5.1 after (a109)); on T² with `R` the tube radius it is `a sin²θ + b sin θ`.
#[derive(Debug, Clone, Copy)]
struct ZPoly {
    a: f64,
    b: f64,
    radius: f64,
}
impl<const N: usize> Potential<N, 3> for ZPoly {
    fn uses_frame(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, _e: &SMatrix<D, 3, N>, _m: &SMatrix<f64, 3, 3>) -> D {
        let c = x[2] / self.radius;
        c * c * self.a + c * self.b
    }
}

/// The Bertrand oscillator `V = (κ/2) R² tan²(r/R)` on S² (b88) — and
/// `(κ/2) R² th²(r/R)` on H² (a133) — as `(κ/2) R² (x² + y²)/z²`.
#[derive(Debug, Clone, Copy)]
struct Oscillator {
    kappa: f64,
    radius: f64,
}
impl<const N: usize> Potential<N, 3> for Oscillator {
    fn uses_frame(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, _e: &SMatrix<D, 3, N>, _m: &SMatrix<f64, 3, 3>) -> D {
        (x[0] * x[0] + x[1] * x[1]) / (x[2] * x[2]) * (0.5 * self.kappa * self.radius * self.radius)
    }
}

/// A frame-dependent potential `V = b·⟨e₁, ẑ⟩ + c·z` (a dipole in a field):
/// breaks the internal rotation symmetry, keeps the one about the z axis.
#[derive(Debug, Clone, Copy)]
struct Dipole {
    b: f64,
    c: f64,
}
impl<const N: usize> Potential<N, 3> for Dipole {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, N>, _m: &SMatrix<f64, 3, 3>) -> D {
        e[(2, 0)] * self.b + x[2] * self.c
    }
}

/// The paper's elastic potential (a131) through the Green tensor
/// `G = ⟨e_A, e_B⟩`: `V = κ(1/√det G + tr G/2) + c·z` (`= κ(1/(λμ) + (λ² + μ²)/2)`
/// in two-polar variables), invariant under internal rotations on both sides.
#[derive(Debug, Clone, Copy)]
struct Elastic {
    kappa: f64,
    c: f64,
}
impl Potential<2, 3> for Elastic {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, m: &SMatrix<f64, 3, 3>) -> D {
        let g = green_tensor(e, m);
        let det = g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)];
        (det.sqrt().recip() + (g[(0, 0)] + g[(1, 1)]) * 0.5) * self.kappa + x[2] * self.c
    }
}

/// A potential on S³ depending on position and frame: `V = a·x⁰/R + b·e₁⁽¹⁾`.
#[derive(Debug, Clone, Copy)]
struct S3Tilt {
    a: f64,
    b: f64,
    radius: f64,
}
impl Potential<3, 4> for S3Tilt {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 4>, e: &SMatrix<D, 4, 3>, _m: &SMatrix<f64, 4, 4>) -> D {
        x[0] * (self.a / self.radius) + e[(1, 0)] * self.b
    }
}

// ---------------------------------------------------------------------------
// 1. Chart geometry: generic implementation vs the f64 manifolds, and
//    self-consistency by automatic differentiation
// ---------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// S²: metric, frame, coframe·frame, frame connection, embedding, its
    /// Jacobian (via `embed_tangent`), ambient frame and the inverse chart map
    /// against `manifold::Sphere2`, to 1e-14 relative (measured ≤ 3e-16),
    /// for r/R ∈ [0.01, π − 0.01]; and the self-consistency checks.
    #[test]
    fn sphere_chart_matches_manifold(radius in 0.5..3.0f64, t in 0.01..(PI - 0.01), phi in -10.0..10.0f64,
                                     v0 in -1.0..1.0f64, v1 in -1.0..1.0f64) {
        let c = SphereChart::new(radius).unwrap();
        let m = Sphere2::new(radius).unwrap();
        let x = Vector2::new(t * radius, phi);
        let v = Vector2::new(v0, v1);
        prop_assert!(rel(&c.metric(&x), &m.metric(&x)) < 1e-14);
        prop_assert!(rel(&c.frame(&x), &m.frame(&x)) < 1e-14);
        prop_assert!(conn_diff(&c.frame_connection(&x), &m.frame_connection(&x)) < 1e-14);
        prop_assert!(rel(&c.embed(&x), &m.embed(&x)) < 1e-14);
        prop_assert!(rel(&(c.embed_jacobian(&x) * v), &m.embed_tangent(&x, &v)) < 1e-14);
        prop_assert!(rel(&c.ambient_frame(&x), &m.ambient_frame(&x)) < 1e-14);
        let back = c.chart_point(&m.embed(&x)).unwrap();
        prop_assert!((back[0] - x[0]).abs() < 1e-13 * radius);
        prop_assert!((back - m.chart(&m.embed(&x)).unwrap()).amax() < 1e-13);
        prop_assert!(chart_self_consistency(&c, &x) < 1e-12);
    }

    /// H²: as for S² against `manifold::Hyperbolic2`, r/R ∈ [0.01, 4]
    /// (relative 1e-13: entries grow like e^{r/R}).
    #[test]
    fn hyperbolic_chart_matches_manifold(radius in 0.5..3.0f64, t in 0.01..4.0f64, phi in -10.0..10.0f64,
                                         v0 in -1.0..1.0f64, v1 in -1.0..1.0f64) {
        let c = HyperbolicChart::new(radius).unwrap();
        let m = Hyperbolic2::new(radius).unwrap();
        let x = Vector2::new(t * radius, phi);
        let v = Vector2::new(v0, v1);
        prop_assert!(rel(&c.metric(&x), &m.metric(&x)) < 1e-13);
        prop_assert!(rel(&c.frame(&x), &m.frame(&x)) < 1e-13);
        prop_assert!(conn_diff(&c.frame_connection(&x), &m.frame_connection(&x)) < 1e-13);
        prop_assert!(rel(&c.embed(&x), &m.embed(&x)) < 1e-13);
        prop_assert!(rel(&(c.embed_jacobian(&x) * v), &m.embed_tangent(&x, &v)) < 1e-13);
        prop_assert!(rel(&c.ambient_metric(), &m.ambient_metric()) == 0.0);
        let back = c.chart_point(&m.embed(&x)).unwrap();
        prop_assert!((back - m.chart(&m.embed(&x)).unwrap()).amax() < 1e-12 * radius);
        prop_assert!(chart_self_consistency(&c, &x) < 1e-11);
    }

    /// S³: metric, frame `ˡE`, frame connection, embedding and tangent map,
    /// ambient frame (`e_A·x/R`, `Sphere3::frame_l_ambient`) and the inverse
    /// chart against `manifold::Sphere3`, at |r̄|/R from 1e-9 (series branch)
    /// to 3 (closed forms near the antipode), relative 1e-13; plus the
    /// self-consistency checks (coframe, Koszul connection).
    #[test]
    fn sphere3_chart_matches_manifold(radius in 0.5..3.0f64, lt in -9.0..0.48f64,
                                      d0 in -1.0..1.0f64, d1 in -1.0..1.0f64, d2 in -1.0..1.0f64,
                                      v0 in -1.0..1.0f64, v1 in -1.0..1.0f64, v2 in -1.0..1.0f64) {
        let dir = Vector3::new(d0, d1, d2);
        prop_assume!(dir.norm() > 0.1);
        let c = Sphere3Chart::new(radius).unwrap();
        let m = Sphere3::new(radius).unwrap();
        let x = dir.normalize() * (10f64.powf(lt) * radius);
        let v = Vector3::new(v0, v1, v2);
        prop_assert!(rel(&c.metric(&x), &m.metric(&x)) < 1e-13);
        prop_assert!(rel(&c.frame(&x), &m.frame(&x)) < 1e-13);
        prop_assert!(conn_diff(&c.frame_connection(&x), &m.frame_connection(&x)) < 1e-15);
        prop_assert!(rel(&c.embed(&x), &m.embed(&x)) < 1e-14);
        prop_assert!(rel(&(c.embed_jacobian(&x) * v), &m.embed_tangent(&x, &v)) < 1e-13);
        prop_assert!(rel(&c.ambient_frame(&x), &m.frame_l_ambient(&m.embed(&x))) < 1e-13);
        let back = c.chart_point(&m.embed(&x)).unwrap();
        prop_assert!((back - x).amax() < 1e-13 * radius * (1.0 + x.norm() / radius));
        prop_assert!(chart_self_consistency(&c, &x) < 1e-11);
    }

    /// T²: self-consistency (the torus manifold is not on this branch yet):
    /// Jacobian = AD of the embedding, induced metric, orthonormal frame,
    /// coframe, and `Γ(E)` = the Levi-Civita connection from the metric —
    /// which fixes the sign of the drive term independently of the paper.
    #[test]
    fn torus_chart_self_consistent(l in 1.5..4.0f64, r in 0.3..1.0f64, th in -10.0..10.0f64, phi in -10.0..10.0f64) {
        let c = TorusChart::new(l, r).unwrap();
        let x = Vector2::new(th, phi);
        prop_assert!(chart_self_consistency(&c, &x) < 1e-12);
        let back = c.chart_point(&c.embed(&x)).unwrap();
        let wrap = |a: f64| (a + PI).rem_euclid(2.0 * PI) - PI;
        prop_assert!(wrap(back[0] - th).abs() < 1e-13 && wrap(back[1] - phi).abs() < 1e-13);
    }
}

/// The paper's holonomic Christoffel symbol on S² (line 2988) is printed as
/// `Γ^r_φφ = −(R/2) sin(r/R)`; the Koszul formula applied by AD to the metric
/// (a87) gives `−R sin(r/R) cos(r/R)` (SPEC §8). Measured: the AD value equals
/// `−R sin cos` to 1e-16; the printed one is off by 0.034R at r = R.
#[test]
fn sphere_christoffel_typo() {
    let r_big = 1.7;
    let c = SphereChart::new(r_big).unwrap();
    let x = Vector2::new(r_big, 0.3);
    let dg = directional(|y| c.metric(y), &x, &Vector2::new(1.0, 0.0));
    // Γ^r_φφ = −½ g^{rr} ∂_r g_φφ (diagonal metric).
    let gamma = -0.5 * dg[(1, 1)];
    let (s, co) = (1.0f64).sin_cos();
    assert!((gamma - (-r_big * s * co)).abs() < 1e-14 * r_big, "{gamma}");
    let printed = -(r_big / 2.0) * s;
    assert!((gamma - printed).abs() > 0.03 * r_big);
}

/// Chart errors are typed and name the singular set; no panics on bad input.
#[test]
fn chart_errors_are_typed() {
    let s = SphereChart::new(1.0).unwrap();
    for r in [0.0, PI, -0.1, 4.0, 1e-13] {
        assert!(matches!(s.check_chart(&Vector2::new(r, 0.0)), Err(Error::OutsideChart { manifold: "S2", .. })), "{r}");
    }
    assert!(matches!(s.check_chart(&Vector2::new(f64::NAN, 0.0)), Err(Error::NotFinite { .. })));
    assert!(matches!(s.chart_point(&Vector3::new(0.0, 0.0, 1.0)), Err(Error::OutsideChart { .. })));
    assert!(matches!(s.chart_point(&Vector3::new(0.0, 0.5, 1.0)), Err(Error::Constraint { field: "p", .. })));
    let h = HyperbolicChart::new(2.0).unwrap();
    assert!(matches!(h.check_chart(&Vector2::new(0.0, 1.0)), Err(Error::OutsideChart { manifold: "H2", .. })));
    assert!(matches!(h.chart_point(&Vector3::new(0.0, 0.0, -2.0)), Err(Error::Constraint { .. })));
    let s3 = Sphere3Chart::new(1.0).unwrap();
    assert!(matches!(s3.check_chart(&Vector3::new(PI, 0.0, 0.0)), Err(Error::OutsideChart { manifold: "S3", .. })));
    assert!(matches!(s3.chart_point(&Vector4::new(-1.0, 0.0, 0.0, 0.0)), Err(Error::OutsideChart { .. })));
    assert!(matches!(SphereChart::new(0.0), Err(Error::InvalidParameter { field: "R", .. })));
    assert!(matches!(TorusChart::new(1.0, 2.0), Err(Error::InvalidParameter { field: "L", .. })));
    assert!(matches!(TorusChart::new(3.0, f64::NAN), Err(Error::InvalidParameter { field: "R", .. })));
}
