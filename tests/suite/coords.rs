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

/// Asserts RK4 convergence of conservation errors: the drift at `h` is below
/// `tol` and the ratio of the drifts at `h` and `h/2` over the same time is
/// that of a method of order 3.5–5.3 (ratio in [11, 40]). Most invariants
/// measure 15.8–18.2; the energy of the H² affine body has a suppressed `h⁴`
/// term (ratios 29, 27, 24 measured for h = 0.04 … 0.005), hence the upper
/// bound. A ratio near 1 (round-off floor, or an invariant that is not
/// conserved at all) fails.
fn assert_fourth_order<const M: usize>(name: &str, coarse: [f64; M], fine: [f64; M], tol: [f64; M]) {
    for k in 0..M {
        let ratio = coarse[k] / fine[k];
        eprintln!("{name}[{k}]: drift(h) = {:.3e}, drift(h/2) = {:.3e}, ratio {ratio:.2}", coarse[k], fine[k]);
        assert!(coarse[k] <= tol[k], "{name}[{k}]: drift {:e} > {:e}", coarse[k], tol[k]);
        assert!((11.0..=40.0).contains(&ratio), "{name}[{k}]: drift ratio {ratio} is not that of RK4");
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

// ---------------------------------------------------------------------------
// 2. Conservation laws along RK4 trajectories, with fourth-order scaling
// ---------------------------------------------------------------------------

fn so3_vee(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]) * 0.5
}

/// S² gyroscope (m = 1, R = 1, I = 0.3) in the integrable potential
/// `0.4 cos²(r/R) + 0.5 cos(r/R)`: energy, `p_φ`, `p_ψ` (cyclic) over
/// t ∈ [0, 10] at h = 0.02 and 0.01. Measured drifts at h = 0.02: 2.0e-7,
/// 1.5e-7, 2.5e-8; ratios 16.3–16.4.
#[test]
fn sphere_gyroscope_conservation() {
    let sys = Gyroscope2::gyroscope(
        SphereChart::new(1.0).unwrap(),
        PlaneRotation,
        &Gyroscope::isotropic(1.0, 0.3).unwrap(),
        ZPoly { a: 0.4, b: 0.5, radius: 1.0 },
    );
    let (q0, v0) = (Vector3::new(1.0, 0.2, 0.1), Vector3::new(0.3, 0.8, -0.5));
    let inv = |q: &Vector3<f64>, v: &Vector3<f64>| {
        let p = momenta(&sys, q, v).unwrap();
        [energy(&sys, q, v).unwrap(), p[1], p[2]]
    };
    let coarse = drifts(&sys, &q0, &v0, 0.02, 500, inv);
    let fine = drifts(&sys, &q0, &v0, 0.01, 1000, inv);
    assert_fourth_order("S2 gyroscope (E, p_phi, p_psi)", coarse, fine, [3e-7, 2e-7, 4e-8]);
}

/// H² gyroscope in the Bertrand oscillator `(κ/2)R² th²(r/R)`, both
/// signatures of the internal energy ((a135) and the Lorentz-type (a138)):
/// energy, `p_φ`, `p_ψ` over t ∈ [0, 8], h = 0.02 and 0.01. Measured drifts
/// at h = 0.02: Riemannian 6.0e-10, 1.6e-9, 1.2e-10; Lorentz 1.2e-8, 1.7e-8,
/// 1.6e-9; ratios 16.05–16.44.
#[test]
fn hyperbolic_gyroscope_conservation() {
    for signature in [Signature::Riemannian, Signature::Lorentz] {
        let sys = Gyroscope2::gyroscope(
            HyperbolicChart::new(1.5).unwrap(),
            PlaneRotation,
            &Gyroscope::isotropic(1.0, 0.4).unwrap().with_signature(signature),
            Oscillator { kappa: 1.0, radius: 1.5 },
        );
        let (q0, v0) = (Vector3::new(1.2, 0.0, 0.3), Vector3::new(0.2, 0.4, 0.7));
        let inv = |q: &Vector3<f64>, v: &Vector3<f64>| {
            let p = momenta(&sys, q, v).unwrap();
            [energy(&sys, q, v).unwrap(), p[1], p[2]]
        };
        let coarse = drifts(&sys, &q0, &v0, 0.02, 400, inv);
        let fine = drifts(&sys, &q0, &v0, 0.01, 800, inv);
        let tol = match signature {
            Signature::Riemannian => [1e-9, 2.5e-9, 2e-10],
            Signature::Lorentz => [2e-8, 2.5e-8, 2.5e-9],
        };
        assert_fourth_order(&format!("H2 gyroscope {signature:?} (E, p_phi, p_psi)"), coarse, fine, tol);
    }
}

/// T² gyroscope (L = 2, R = 0.7) in `V = 0.3 sin θ`: energy, `p_φ`, `p_ψ`
/// over t ∈ [0, 10], h = 0.04 and 0.02. Measured drifts at h = 0.04: 5.2e-8,
/// 1.2e-7, 1.3e-9; ratios 15.9–18.2.
#[test]
fn torus_gyroscope_conservation() {
    let sys = Gyroscope2::gyroscope(
        TorusChart::new(2.0, 0.7).unwrap(),
        PlaneRotation,
        &Gyroscope::isotropic(1.0, 0.25).unwrap(),
        ZPoly { a: 0.0, b: 0.3, radius: 0.7 },
    );
    let (q0, v0) = (Vector3::new(0.4, 0.0, 0.0), Vector3::new(0.5, 0.6, -0.4));
    let inv = |q: &Vector3<f64>, v: &Vector3<f64>| {
        let p = momenta(&sys, q, v).unwrap();
        [energy(&sys, q, v).unwrap(), p[1], p[2]]
    };
    let coarse = drifts(&sys, &q0, &v0, 0.04, 250, inv);
    let fine = drifts(&sys, &q0, &v0, 0.02, 500, inv);
    assert_fourth_order("T2 gyroscope (E, p_phi, p_psi)", coarse, fine, [8e-8, 1.8e-7, 2e-9]);
}

/// The S³ momenta of §6 at a state of an isotropic gyroscope (`J = (I/2)δ`,
/// SPEC §7): `S(R) = (m + I/R²)Ω(R) − (I/R)Ω_rl`, `S_rl = −(I/R)Ω(R) + IΩ_rl`
/// (the Legendre map printed before (a184)), with `Ω(R) = ˡE⁻¹ ṙ̄` and
/// `Ω_rl = vee(φ̇φᵀ)` (spatial angular velocity of `φ` relative to `ˡE`).
fn s3_momenta(sys: &Gyroscope3<Free>, q: &SVector<f64, 6>, v: &SVector<f64, 6>, moment: f64) -> (Vector3<f64>, Vector3<f64>) {
    let cm = sys.comoving(q, v).unwrap();
    let r = sys.chart().radius();
    let m = sys.mass();
    let om_r = cm.velocity;
    let om_rl = so3_vee(&(cm.phi_dot * cm.phi.transpose()));
    (om_r * (m + moment / (r * r)) - om_rl * (moment / r), om_rl * moment - om_r * (moment / r))
}

/// S³ gyroscope, free, isotropic (`J = (I/2)δ`, m = 1, R = 1.3, I = 0.5):
/// energy, the conserved vector (a186) `(R/2)S(R) + S_rl` (three
/// components), `|S(R)|²` and `|S_rl|²` — with the paper's momenta built
/// from the coordinate state (SPEC §7: exact with the frame `ˡE`), over
/// t ∈ [0, 5], h = 0.02 and 0.01. Measured drifts at h = 0.02: 1.0e-10,
/// 5.1e-11, 1.4e-11, 5.1e-11, 2.4e-10, 6.6e-11; ratios 15.8–16.0.
#[test]
fn sphere3_gyroscope_conservation() {
    let moment = 0.5;
    let sys = Gyroscope3::gyroscope(
        Sphere3Chart::new(1.3).unwrap(),
        RotationVector,
        &Gyroscope::isotropic(1.0, moment).unwrap(),
        Free,
    );
    let q0 = SVector::<f64, 6>::from([0.3, -0.2, 0.5, 0.4, 0.1, -0.3]);
    let v0 = SVector::<f64, 6>::from([0.2, 0.5, -0.1, 0.3, -0.6, 0.4]);
    let inv = |q: &SVector<f64, 6>, v: &SVector<f64, 6>| {
        let (s, srl) = s3_momenta(&sys, q, v, moment);
        let c = s * (1.3 / 2.0) + srl;
        [energy(&sys, q, v).unwrap(), c[0], c[1], c[2], s.norm_squared(), srl.norm_squared()]
    };
    let coarse = drifts(&sys, &q0, &v0, 0.02, 250, inv);
    let fine = drifts(&sys, &q0, &v0, 0.01, 500, inv);
    assert_fourth_order(
        "S3 gyroscope (E, C1, C2, C3, |S|^2, |S_rl|^2)",
        coarse,
        fine,
        [1.5e-10, 8e-11, 2.5e-11, 8e-11, 4e-10, 1e-10],
    );
}

/// S³ gyroscope with anisotropic inertia and a frame-dependent potential:
/// only the energy is conserved. Measured drift 2.8e-7 at h = 0.02 over
/// t ∈ [0, 5], ratio 15.9.
#[test]
fn sphere3_anisotropic_energy() {
    let j = Matrix3::new(0.4, 0.05, 0.0, 0.05, 0.25, 0.02, 0.0, 0.02, 0.15);
    let sys = Gyroscope3::gyroscope(
        Sphere3Chart::new(1.3).unwrap(),
        RotationVector,
        &Gyroscope::new(1.0, j).unwrap(),
        S3Tilt { a: 0.5, b: 0.3, radius: 1.3 },
    );
    let q0 = SVector::<f64, 6>::from([0.3, -0.2, 0.5, 0.4, 0.1, -0.3]);
    let v0 = SVector::<f64, 6>::from([0.2, 0.5, -0.1, 0.3, -0.6, 0.4]);
    let inv = |q: &SVector<f64, 6>, v: &SVector<f64, 6>| [energy(&sys, q, v).unwrap()];
    let coarse = drifts(&sys, &q0, &v0, 0.02, 250, inv);
    let fine = drifts(&sys, &q0, &v0, 0.01, 500, inv);
    assert_fourth_order("S3 anisotropic gyroscope (E)", coarse, fine, [4e-7]);
}

/// Doubly isotropic affine body on S² (`J = I·1`, I = 0.2) in two-polar
/// variables, elastic potential (a131) plus `0.3 z`: energy, `p_φ`, spin
/// `p_α`, vorticity `p_β` (SPEC §6, §7), over t ∈ [0, 5], h = 0.02 and 0.01.
/// Measured drifts at h = 0.02: 1.9e-6, 6.9e-8, 5.6e-7, 6.0e-7; ratios
/// 16.1–17.5.
#[test]
fn two_polar_affine_conservation() {
    let sys = TwoPolarAffine2::affine(
        SphereChart::new(1.0).unwrap(),
        TwoPolar,
        &Affine::isotropic(1.0, 0.2).unwrap(),
        Elastic { kappa: 0.5, c: 0.3 },
    );
    let q0 = SVector::<f64, 6>::from([1.0, 0.0, 0.3, -0.2, 1.3, 0.8]);
    let v0 = SVector::<f64, 6>::from([0.2, 0.5, 0.9, -0.4, 0.1, -0.2]);
    let inv = |q: &SVector<f64, 6>, v: &SVector<f64, 6>| {
        let p = momenta(&sys, q, v).unwrap();
        [energy(&sys, q, v).unwrap(), p[1], p[2], p[3]]
    };
    let coarse = drifts(&sys, &q0, &v0, 0.02, 250, inv);
    let fine = drifts(&sys, &q0, &v0, 0.01, 500, inv);
    assert_fourth_order("S2 two-polar affine (E, p_phi, p_alpha, p_beta)", coarse, fine, [3e-6, 1e-7, 9e-7, 9e-7]);
}

/// Affine body on H² by the entries of `φ`, anisotropic `J`, elastic
/// potential plus `0.3 z` (confining on the hyperboloid): energy, `p_φ`, over
/// t ∈ [0, 5], h = 0.02 and 0.01. Measured drifts at h = 0.02: 2.5e-9,
/// 1.8e-9; ratios 27.0 and 17.7.
#[test]
fn hyperbolic_affine_entries_conservation() {
    let j = Matrix2::new(0.3, 0.05, 0.05, 0.2);
    let sys = Affine2::affine(
        HyperbolicChart::new(1.2).unwrap(),
        GlEntries,
        &Affine::new(1.0, j).unwrap(),
        Elastic { kappa: 0.5, c: 0.3 },
    );
    let q0 = SVector::<f64, 6>::from([0.8, 0.3, 1.1, 0.2, -0.1, 0.9]);
    let v0 = SVector::<f64, 6>::from([0.1, 0.4, 0.2, -0.3, 0.3, 0.1]);
    let inv = |q: &SVector<f64, 6>, v: &SVector<f64, 6>| {
        let p = momenta(&sys, q, v).unwrap();
        [energy(&sys, q, v).unwrap(), p[1]]
    };
    let coarse = drifts(&sys, &q0, &v0, 0.02, 250, inv);
    let fine = drifts(&sys, &q0, &v0, 0.01, 500, inv);
    assert_fourth_order("H2 affine entries (E, p_phi)", coarse, fine, [4e-9, 3e-9]);
}
