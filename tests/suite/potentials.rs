//! Built-in potentials: closed-form gradients against automatic
//! differentiation, automatic differentiation against extrapolated finite
//! differences, values against the paper's chart formulas, symmetries, the
//! elastic natural state, invariance of deformation potentials, singular
//! points and typed errors.
//!
//! Every property test tracks its worst error and prints it (`--nocapture`).

use std::cell::Cell;
use std::f64::consts::PI;

use framedyn::manifold::{GeodesicDistance, Hyperbolic2, Manifold, Sphere2, Sphere3};
use framedyn::potential::{
    autodiff_gradient, deformation_invariants, Axis, polar_invariants, principal_invariants, Central, Centre, CosineFamily,
    Elastic, FnPotential, Gradient, InvariantFunction, InvariantPotential, Kepler, NeoHookean, Oscillator, Pole, Potential,
    RadialFunction, Scalar, Scaled, Separable, SeparableFunctions, StVenantKirchhoff, Sum, TorusAngle,
};
use framedyn::Error;
use nalgebra::{Matrix2, Matrix3, Rotation3, SMatrix, SVector, Vector2, Vector3, Vector4};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

// ---------------------------------------------------------------- helpers

const EPS: f64 = f64::EPSILON;

fn eta() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))
}

fn rot2(a: f64) -> Matrix2<f64> {
    let (s, c) = a.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// `L(α) D(λ, μ) R(β)⁻¹`, the paper's two-polar decomposition.
fn two_polar(alpha: f64, beta: f64, lambda: f64, mu: f64) -> Matrix2<f64> {
    rot2(alpha) * Matrix2::new(lambda, 0.0, 0.0, mu) * rot2(beta).transpose()
}

/// An orthonormal tangent frame of H² at the chart point `x`: `(E_r, E_φ)`.
fn h2_frame(h: &Hyperbolic2, x: &Vector2<f64>) -> SMatrix<f64, 3, 2> {
    let er = h.embed_tangent(x, &Vector2::new(1.0, 0.0));
    let ephi = h.embed_tangent(x, &Vector2::new(0.0, 1.0 / (h.radius() * (x[0] / h.radius()).sinh())));
    SMatrix::from_columns(&[er, ephi])
}

/// Infinity norm.
fn amax<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> f64 {
    m.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// Largest component difference of two gradients relative to the largest
/// component of `b` (value compared relative to `|b.value|`).
fn grad_error<const N: usize, const E: usize>(a: &Gradient<N, E>, b: &Gradient<N, E>) -> f64 {
    let scale = amax(&b.dx).max(amax(&b.de));
    let d = amax(&(a.dx - b.dx)).max(amax(&(a.de - b.de)));
    let dv = (a.value - b.value).abs() / b.value.abs().max(f64::MIN_POSITIVE);
    if scale == 0.0 {
        d.max(dv)
    } else {
        (d / scale).max(dv)
    }
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / b.abs()
    }
}

/// Ridders' extrapolation of central differences (step ratio 1.4, all 12
/// levels, the estimate with the smallest error estimate), independent of
/// the library's.
fn ridders(f: impl Fn(f64) -> f64, h0: f64) -> f64 {
    const LEVELS: usize = 12;
    const CON: f64 = 1.4;
    let mut a = [[0.0f64; LEVELS]; LEVELS];
    let mut h = h0;
    a[0][0] = (f(h) - f(-h)) / (2.0 * h);
    let (mut best, mut err) = (a[0][0], f64::INFINITY);
    for i in 1..LEVELS {
        h /= CON;
        a[0][i] = (f(h) - f(-h)) / (2.0 * h);
        let mut fac = CON * CON;
        for j in 1..=i {
            a[j][i] = (a[j - 1][i] * fac - a[j - 1][i - 1]) / (fac - 1.0);
            fac *= CON * CON;
            let e = (a[j][i] - a[j - 1][i]).abs().max((a[j][i] - a[j - 1][i - 1]).abs());
            if e <= err {
                err = e;
                best = a[j][i];
            }
        }
    }
    best
}

/// Autodiff against Ridders differences ([`fd_gradient`]): the largest
/// component difference relative to the larger of the largest component and
/// `|V|/ℓ`, `ℓ` the smallest step scale (differences of values carry
/// rounding `≈ ε|V|/h` whatever the size of the gradient).
fn fd_error<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
    len_x: f64,
) -> f64 {
    let auto = autodiff_gradient(p, x, e, g);
    let (fd, len) = fd_gradient(p, x, e, g, len_x);
    let scale = amax(&auto.dx).max(amax(&auto.de)).max(auto.value.abs() / len);
    amax(&(auto.dx - fd.dx)).max(amax(&(auto.de - fd.de))) / scale
}

/// Gradient of `p.value::<f64>` by Ridders differences, steps `0.05·len_x`
/// for `x` and `0.05·λ_min(G)/|e|` for the frame; with the smaller of the
/// two step scales.
fn fd_gradient<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
    len_x: f64,
) -> (Gradient<N, E>, f64) {
    let mut len_min = len_x;
    let mut dx = SVector::<f64, E>::zeros();
    for i in 0..E {
        dx[i] = ridders(
            |h| {
                let mut y = *x;
                y[i] += h;
                p.value(&y, e, g)
            },
            0.05 * len_x,
        );
    }
    let mut de = SMatrix::<f64, E, N>::zeros();
    if p.uses_frame() {
        // A perturbation δe changes G = eᵀge by ~2|δe||e|: steps well below
        // λ_min(G)/|e| stay away from the collapse det G = 0 (in Minkowski
        // space far below the Euclidean smallest singular value of e).
        let gram = nalgebra::DMatrix::from_column_slice(N, N, (e.transpose() * g * e).as_slice());
        let len = gram.symmetric_eigenvalues().min() / e.norm();
        len_min = len_min.min(len);
        for a in 0..N {
            for i in 0..E {
                de[(i, a)] = ridders(
                    |h| {
                        let mut f = *e;
                        f[(i, a)] += h;
                        p.value(x, &f, g)
                    },
                    0.05 * len,
                );
            }
        }
    }
    (Gradient { value: p.value(x, e, g), dx, de }, len_min)
}

/// A Killing field `x ↦ A x` of the ambient metric `g` fixing `c`:
/// `A = u (g v)ᵀ − v (g u)ᵀ` with `u, v` `g`-orthonormal and `g`-orthogonal
/// to `c`, by Gram–Schmidt from `w₁, w₂` (then the coordinate axes, for
/// candidates nearly dependent on the previous ones).
fn killing_fixing<const E: usize>(
    g: &SMatrix<f64, E, E>,
    c: &SVector<f64, E>,
    w1: &SVector<f64, E>,
    w2: &SVector<f64, E>,
) -> SMatrix<f64, E, E> {
    let dot = |a: &SVector<f64, E>, b: &SVector<f64, E>| a.dot(&(g * b));
    let mut basis: Vec<SVector<f64, E>> = Vec::new();
    let axes = (0..E).map(|i| SVector::<f64, E>::from_fn(|k, _| if k == i { 1.0 } else { 0.0 }));
    for w in [*w1, *w2].into_iter().chain(axes) {
        let mut r = w - c * (dot(&w, c) / dot(c, c));
        for b in &basis {
            r -= b * dot(&r, b);
        }
        let n2 = dot(&r, &r);
        if n2 > 1e-4 * w.norm_squared() && n2 > 0.0 {
            basis.push(r / n2.sqrt());
            if basis.len() == 2 {
                break;
            }
        }
    }
    let (u, v) = (basis[0], basis[1]);
    u * (g * v).transpose() - v * (g * u).transpose()
}

/// `dV(A x, A e) / (|dV| ‖A‖ |(x, e)|)`: the derivative of `V` along the
/// one-parameter group generated by `A`, relative to the rounding of `A x`.
fn along<const N: usize, const E: usize>(
    grad: &Gradient<N, E>,
    a: &SMatrix<f64, E, E>,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
) -> f64 {
    let ax = a * x;
    let ae = a * e;
    let d = grad.dx.dot(&ax) + grad.de.component_mul(&ae).sum();
    let scale = (grad.dx.norm() + grad.de.norm()) * a.norm() * (x.norm() + e.norm());
    if scale == 0.0 {
        d.abs()
    } else {
        d.abs() / scale
    }
}

/// Runs `cases` random cases of `test` (fixed seed unless
/// `PROPTEST_RNG_SEED` is set), tracking the worst value it returns, and
/// fails when it exceeds `tol`.
fn check<S: Strategy>(
    name: &str,
    cases: u32,
    strategy: S,
    tol: f64,
    test: impl Fn(S::Value) -> Result<f64, TestCaseError>,
) {
    let worst = Cell::new(0.0f64);
    let mut config = Config { cases, failure_persistence: None, ..Config::default() };
    // Reproducible by default; set PROPTEST_RNG_SEED to explore other cases.
    if matches!(config.rng_seed, RngSeed::Random) {
        config.rng_seed = RngSeed::Fixed(0x00f7_a3ed_d1e5_2024);
    }
    let mut runner = TestRunner::new(config);
    let result = runner.run(&strategy, |v| {
        let err = test(v)?;
        worst.set(worst.get().max(err));
        prop_assert!(err <= tol, "{name}: error {err:e} > {tol:e}");
        Ok(())
    });
    eprintln!("{name}: worst {:.3e} (tolerance {tol:e})", worst.get());
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

// ------------------------------------------------------ configurations

/// A random configuration on S²: radius, chart point, body frame `e = qφ`.
#[derive(Debug, Clone)]
struct Cfg2 {
    radius: f64,
    chart: Vector2<f64>,
    x: SVector<f64, 3>,
    q: SMatrix<f64, 3, 2>,
    phi: Matrix2<f64>,
    e: SMatrix<f64, 3, 2>,
    lm: (f64, f64),
    g: Matrix3<f64>,
    /// Rounding amplification of the embedding: 1 on S², `cosh²(r/R)` on H²
    /// (ambient components of points and tangent vectors grow like
    /// `cosh(r/R)` while their Minkowski products stay O(1)).
    amp: f64,
}

impl Cfg2 {
    fn g(&self) -> Matrix3<f64> {
        self.g
    }
    /// Rounding amplification of the Green-tensor invariants,
    /// `(tr G)²/det G = ((λ² + μ²)/λμ)²` (`det G` from the entries of `G`),
    /// times that of the embedding.
    fn cond(&self) -> f64 {
        let (l, m) = self.lm;
        ((l * l + m * m) / (l * m)).powi(2) * self.amp
    }
}

fn deform2() -> impl Strategy<Value = (f64, f64, f64, f64)> {
    (-PI..PI, -PI..PI, 0.3f64..3.0, 0.3f64..3.0)
}

fn s2_cfg(t_lo: f64, t_hi: f64) -> impl Strategy<Value = Cfg2> {
    (0.5f64..3.0, t_lo..t_hi, -PI..PI, deform2()).prop_map(|(radius, t, ph, (a, b, l, m))| {
        let s = Sphere2::new(radius).unwrap();
        let chart = Vector2::new(t * radius, ph);
        let x = s.embed(&chart);
        let q = s.ambient_frame(&chart);
        let phi = two_polar(a, b, l, m);
        Cfg2 { radius, chart, x, q, phi, e: q * phi, lm: (l, m), g: Matrix3::identity(), amp: 1.0 }
    })
}

fn h2_cfg(t_lo: f64, t_hi: f64) -> impl Strategy<Value = Cfg2> {
    (0.5f64..3.0, t_lo..t_hi, -PI..PI, deform2()).prop_map(|(radius, t, ph, (a, b, l, m))| {
        let h = Hyperbolic2::new(radius).unwrap();
        let chart = Vector2::new(t * radius, ph);
        let x = h.embed(&chart);
        let q = h2_frame(&h, &chart);
        let phi = two_polar(a, b, l, m);
        Cfg2 { radius, chart, x, q, phi, e: q * phi, lm: (l, m), g: eta(), amp: t.cosh().powi(2) }
    })
}

/// A random configuration on S³: chart point `r̄` with `|r̄| = tR`, the frame
/// `ˡE(R)` and `φ = U₁ diag(λᵢ) U₂ᵀ`.
#[derive(Debug, Clone)]
struct Cfg3 {
    radius: f64,
    rbar: Vector3<f64>,
    x: Vector4<f64>,
    q: SMatrix<f64, 4, 3>,
    e: SMatrix<f64, 4, 3>,
    l: Vector3<f64>,
}

fn unit3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..1.0, -PI..PI).prop_map(|(z, ph): (f64, f64)| {
        let s = (1.0 - z * z).sqrt();
        Vector3::new(s * ph.cos(), s * ph.sin(), z)
    })
}

fn rot3() -> impl Strategy<Value = Matrix3<f64>> {
    (unit3(), -PI..PI).prop_map(|(n, a)| Rotation3::new(n * a).into_inner())
}

fn s3_cfg(t_lo: f64, t_hi: f64) -> impl Strategy<Value = Cfg3> {
    (0.5f64..3.0, t_lo..t_hi, unit3(), rot3(), rot3(), (0.3f64..3.0, 0.3f64..3.0, 0.3f64..3.0)).prop_map(
        |(radius, t, n, u1, u2, (l1, l2, l3))| {
            let s = Sphere3::new(radius).unwrap();
            let rbar = n * (t * radius);
            let x = s.embed(&rbar);
            let q = s.frame_l_ambient(&x);
            let l = Vector3::new(l1, l2, l3);
            let phi = u1 * Matrix3::from_diagonal(&l) * u2.transpose();
            Cfg3 { radius, rbar, x, q, e: q * phi, l }
        },
    )
}

fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

fn vec4() -> impl Strategy<Value = Vector4<f64>> {
    (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0).prop_map(|(a, b, c, d)| Vector4::new(a, b, c, d))
}

/// A random centre of S² (any point).
fn s2_centre(radius: f64, d: &Vector3<f64>) -> Centre<3> {
    let s = Sphere2::new(radius).unwrap();
    let d = if d.norm() < 1e-3 { Vector3::new(0.3, -0.2, 0.9) } else { *d };
    Centre::sphere2_at(&s, &(d * (radius / d.norm()))).unwrap()
}

/// A random centre of H² within distance ≈ 2R of the origin.
fn h2_centre(radius: f64, d: &Vector3<f64>) -> Centre<3> {
    let h = Hyperbolic2::new(radius).unwrap();
    let (x, y) = (2.0 * radius * d[0], 2.0 * radius * d[1]);
    let z = (radius * radius + x * x + y * y).sqrt();
    Centre::hyperbolic2_at(&h, &Vector3::new(x, y, z)).unwrap()
}

fn s3_centre(radius: f64, d: &Vector4<f64>) -> Centre<4> {
    let s = Sphere3::new(radius).unwrap();
    let d = if d.norm() < 1e-3 { Vector4::new(0.3, -0.2, 0.9, 0.1) } else { *d };
    Centre::sphere3_at(&s, &(d * (radius / d.norm()))).unwrap()
}

/// The point of the torus T²(L, R) at the paper's angles `(ϑ, φ)` and its
/// orthonormal frame `(E_ϑ, E_φ)`.
fn torus_point(l: f64, r: f64, th: f64, ph: f64) -> (Vector3<f64>, SMatrix<f64, 3, 2>) {
    let x = Vector3::new((l + r * th.cos()) * ph.cos(), (l + r * th.cos()) * ph.sin(), r * th.sin());
    let et = Vector3::new(-th.sin() * ph.cos(), -th.sin() * ph.sin(), th.cos());
    let ep = Vector3::new(-ph.sin(), ph.cos(), 0.0);
    (x, SMatrix::from_columns(&[et, ep]))
}

// ------------------------------------------------- user functions for tests

/// `V_r = a r² + b cos(r/R)`, `V_ϱ = c ϱ² + d/ϱ²`, `V_ε = k cos 2ε + m ε²`
/// (even in ε).
#[derive(Debug, Clone, Copy)]
struct TestSep {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    k: f64,
    m: f64,
    radius: f64,
}

impl SeparableFunctions for TestSep {
    fn v_r<D: Scalar>(&self, r: D) -> D {
        r * r * self.a + (r * (1.0 / self.radius)).cos() * self.b
    }
    fn v_rho<D: Scalar>(&self, rho: D) -> D {
        rho * rho * self.c + (rho * rho).recip() * self.d
    }
    fn v_eps<D: Scalar>(&self, eps: D) -> D {
        (eps * 2.0).cos() * self.k + eps * eps * self.m
    }
}

impl TestSep {
    fn formula(&self, r: f64, rho: f64, eps: f64) -> f64 {
        self.a * r * r
            + self.b * (r / self.radius).cos()
            + self.c * rho * rho
            + self.d / (rho * rho)
            + (self.k * (2.0 * eps).cos() + self.m * eps * eps) / (rho * rho)
    }
}

fn test_sep(radius: f64) -> impl Strategy<Value = TestSep> {
    (-1.0f64..1.0, -1.0f64..1.0, 0.1f64..1.0, 0.1f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
        .prop_map(move |(a, b, c, d, k, m)| TestSep { a, b, c, d, k, m, radius })
}

/// The elastic potential (a131) in the separated form `κϱ²/2 + 2κ/(ϱ² cos 2ε)`.
#[derive(Debug, Clone, Copy)]
struct ElasticSep {
    kappa: f64,
}

impl SeparableFunctions for ElasticSep {
    fn v_r<D: Scalar>(&self, _r: D) -> D {
        D::from(0.0)
    }
    fn v_rho<D: Scalar>(&self, rho: D) -> D {
        rho * rho * (0.5 * self.kappa)
    }
    fn v_eps<D: Scalar>(&self, eps: D) -> D {
        (eps * 2.0).cos().recip() * (2.0 * self.kappa)
    }
}

/// `V(r) = a r² + b r⁴` (smooth in r²).
#[derive(Debug, Clone, Copy)]
struct Quartic {
    a: f64,
    b: f64,
}

impl RadialFunction for Quartic {
    fn v<D: Scalar>(&self, r: D) -> D {
        let r2 = r * r;
        r2 * self.a + r2 * r2 * self.b
    }
}

/// `W = a(I₁ − 3)² + b(I₂ − 3) + c·ln I₃` — exercises all three partials.
#[derive(Debug, Clone, Copy)]
struct TestW {
    a: f64,
    b: f64,
    c: f64,
}

impl InvariantFunction for TestW {
    fn energy<D: Scalar>(&self, i1: D, i2: D, i3: D) -> D {
        let d = i1 - 3.0;
        d * d * self.a + (i2 - 3.0) * self.b + i3.ln() * self.c
    }
}

// ------------------------------------- 1. closed forms vs automatic ones

const CLOSED_TOL: f64 = 1e-13;

fn closed_vs_auto<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
) -> f64 {
    let closed = p.gradient(x, e, g);
    let auto = autodiff_gradient(p, x, e, g);
    grad_error(&closed, &auto)
}

/// Closed form vs autodiff relative to explicit sizes `(gradient, value)`
/// of the terms they are sums of (which can cancel; num-dual also rounds
/// differently, e.g. divides through the reciprocal).
fn closed_vs_auto_scaled<P: Potential<N, E>, const N: usize, const E: usize>(
    p: &P,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
    (gscale, vscale): (f64, f64),
) -> f64 {
    let closed = p.gradient(x, e, g);
    let auto = autodiff_gradient(p, x, e, g);
    let d = amax(&(closed.dx - auto.dx)).max(amax(&(closed.de - auto.de)));
    (d / gscale).max((closed.value - auto.value).abs() / vscale)
}

/// Sizes of the terms of the elastic gradient κ ge (I − adj G/det^{3/2}),
/// which cancel near the natural state, and of its (positive) value.
fn elastic_scale<const E: usize>(k: f64, e: &SMatrix<f64, E, 2>, g: &SMatrix<f64, E, E>) -> (f64, f64) {
    let gm = e.transpose() * g * e;
    let det = gm.determinant();
    (k * amax(&(g * e)) * (1.0 + gm.trace() / det.powf(1.5)), k * (1.0 / det.sqrt() + 0.5 * gm.trace()))
}

/// Sizes of the terms of the gradient and of the value of a separable
/// potential with the test functions `f`: `Σ |coefficient| · |part|` over
/// the six one-coefficient parts (the potential is linear in them).
fn sep_scale(
    f: &TestSep,
    make: impl Fn(TestSep) -> Separable<TestSep>,
    x: &Vector3<f64>,
    e: &SMatrix<f64, 3, 2>,
    g: &Matrix3<f64>,
) -> (f64, f64) {
    let zero = TestSep { a: 0.0, b: 0.0, c: 0.0, d: 0.0, k: 0.0, m: 0.0, ..*f };
    let parts = [
        (f.a, TestSep { a: 1.0, ..zero }),
        (f.b, TestSep { b: 1.0, ..zero }),
        (f.c, TestSep { c: 1.0, ..zero }),
        (f.d, TestSep { d: 1.0, ..zero }),
        (f.k, TestSep { k: 1.0, ..zero }),
        (f.m, TestSep { m: 1.0, ..zero }),
    ];
    parts.iter().fold((0.0, 0.0), |(gs, vs), (c, part)| {
        let gr = make(*part).gradient(x, e, g);
        (gs + c.abs() * amax(&gr.dx).max(amax(&gr.de)), vs + c.abs() * gr.value.abs())
    })
}

#[test]
fn bertrand_closed_form_gradients_match_autodiff() {
    let params = || (0.1f64..10.0, vec3());
    check("S2 oscillator/Kepler, any centre", 256, (s2_cfg(0.01, PI - 0.01), params()), CLOSED_TOL, |(c, (k, d))| {
        let s = Sphere2::new(c.radius).unwrap();
        let mut err = 0.0f64;
        for centre in [Centre::sphere2(&s), s2_centre(c.radius, &d)] {
            err = err.max(closed_vs_auto(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g));
            err = err.max(closed_vs_auto(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g));
        }
        Ok(err)
    });
    check("H2 oscillator/Kepler, any centre", 256, (h2_cfg(0.01, 6.0), params()), CLOSED_TOL, |(c, (k, d))| {
        let h = Hyperbolic2::new(c.radius).unwrap();
        let mut err = 0.0f64;
        for centre in [Centre::hyperbolic2(&h), h2_centre(c.radius, &d)] {
            err = err.max(closed_vs_auto(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g));
            err = err.max(closed_vs_auto(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g));
        }
        Ok(err)
    });
    check(
        "S3 oscillator/Kepler, any centre",
        256,
        (s3_cfg(0.01, PI - 0.01), 0.1f64..10.0, vec4()),
        CLOSED_TOL,
        |(c, k, d)| {
            let s = Sphere3::new(c.radius).unwrap();
            let mut err = 0.0f64;
            for centre in [Centre::sphere3(&s), s3_centre(c.radius, &d)] {
                err = err.max(closed_vs_auto(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g()));
                err = err.max(closed_vs_auto(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g()));
            }
            Ok(err)
        },
    );
}

impl Cfg3 {
    fn g(&self) -> SMatrix<f64, 4, 4> {
        SMatrix::identity()
    }
    /// `(tr G)³/det G`: rounding amplification of the invariants of `G`.
    fn cond(&self) -> f64 {
        let l2 = self.l.map(|v| v * v);
        l2.sum().powi(3) / l2.product()
    }
}

/// Closed form vs autodiff for the cosine family, relative to the sizes of
/// its terms (`2α̂ cos + β̂` and `α̂ cos² + β̂ cos` cancel on a level set).
fn cosine_err<const N: usize, const E: usize>(
    p: &CosineFamily<E>,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
) -> f64
where
    CosineFamily<E>: Potential<N, E>,
{
    let closed = p.gradient(x, e, g);
    let auto = autodiff_gradient(p, x, e, g);
    let c = p.centre().cos_r(x);
    let (a, b, r) = (p.alpha_hat().abs(), p.beta_hat().abs(), p.centre().radius());
    let dscale = (2.0 * a * c.abs() + b) / r * p.centre().point().norm() / r;
    let vscale = a * c * c + b * c.abs();
    (amax(&(closed.dx - auto.dx)) / dscale).max((closed.value - auto.value).abs() / vscale)
}

/// Also at `α̂ = 0`, where the closed-form gradient does not read `x`.
#[test]
fn cosine_family_and_central_closed_forms_match_autodiff() {
    let ab = || (-5.0f64..5.0, -5.0f64..5.0, vec3());
    check("S2 cosine family, central", 256, (s2_cfg(0.01, PI - 0.01), ab()), CLOSED_TOL, |(c, (a, b, d))| {
        let s = Sphere2::new(c.radius).unwrap();
        let mut err = 0.0f64;
        for centre in [Centre::sphere2(&s), s2_centre(c.radius, &d)] {
            for a in [a, 0.0] {
                err = err.max(cosine_err(&CosineFamily::new(a, b, centre).unwrap(), &c.x, &c.e, &c.g));
            }
            let q = Quartic { a: a.abs() + 0.1, b: b.abs() };
            err = err.max(closed_vs_auto(&Central::new(q, centre), &c.x, &c.e, &c.g));
        }
        Ok(err)
    });
    check("H2 cosine family, central", 256, (h2_cfg(0.01, 6.0), ab()), CLOSED_TOL, |(c, (a, b, d))| {
        let h = Hyperbolic2::new(c.radius).unwrap();
        let mut err = 0.0f64;
        for centre in [Centre::hyperbolic2(&h), h2_centre(c.radius, &d)] {
            for a in [a, 0.0] {
                err = err.max(cosine_err(&CosineFamily::new(a, b, centre).unwrap(), &c.x, &c.e, &c.g));
            }
            let q = Quartic { a: a.abs() + 0.1, b: b.abs() };
            err = err.max(closed_vs_auto(&Central::new(q, centre), &c.x, &c.e, &c.g));
        }
        Ok(err)
    });
    check(
        "S3 cosine family, central",
        256,
        (s3_cfg(0.01, PI - 0.01), -5.0f64..5.0, -5.0f64..5.0),
        CLOSED_TOL,
        |(c, a, b)| {
            let centre = Centre::sphere3(&Sphere3::new(c.radius).unwrap());
            let mut err = cosine_err(&CosineFamily::new(a, b, centre).unwrap(), &c.x, &c.e, &c.g());
            err = err.max(cosine_err(&CosineFamily::new(0.0, b, centre).unwrap(), &c.x, &c.e, &c.g()));
            let q = Quartic { a: a.abs() + 0.1, b: b.abs() };
            err = err.max(closed_vs_auto(&Central::new(q, centre), &c.x, &c.e, &c.g()));
            Ok(err)
        },
    );
}

/// Largest difference between the cosine family about a [`Pole`] and about
/// the same point as a runtime [`Centre`]: value, closed-form gradient and
/// autodiff gradient (dual numbers through `value`). Zero means bit for bit.
fn pole_vs_centre<const N: usize, const E: usize>(
    pole: &CosineFamily<E, Pole<E>>,
    centre: &CosineFamily<E>,
    x: &SVector<f64, E>,
    e: &SMatrix<f64, E, N>,
    g: &SMatrix<f64, E, E>,
) -> f64
where
    Pole<E>: Axis<E>,
    CosineFamily<E, Pole<E>>: Potential<N, E>,
    CosineFamily<E>: Potential<N, E>,
{
    let bits = |a: &Gradient<N, E>, b: &Gradient<N, E>| {
        let same = a.value.to_bits() == b.value.to_bits()
            && a.dx.iter().zip(b.dx.iter()).all(|(p, q)| p.to_bits() == q.to_bits())
            && a.de == b.de;
        if same {
            0.0
        } else {
            grad_error(a, b).max(f64::MIN_POSITIVE)
        }
    };
    assert_eq!(pole.centre(), centre.centre());
    bits(&pole.gradient(x, e, g), &centre.gradient(x, e, g)).max(bits(&autodiff_gradient(pole, x, e, g), &autodiff_gradient(centre, x, e, g)))
}

/// [`Pole`] is [`Centre`]'s default centre fixed at compile time: the same
/// numbers bit for bit on S², H² and S³, at the pole itself included, and
/// at `α̂ = 0` (the gradient's branch that does not read `x`).
#[test]
fn cosine_family_about_a_pole_is_the_default_centre_bit_for_bit() {
    let ab = || (-5.0f64..5.0, -5.0f64..5.0);
    check("S2 pole vs centre", 256, (s2_cfg(0.0, PI), ab()), 0.0, |(c, (a, b))| {
        let s = Sphere2::new(c.radius).unwrap();
        let (p, q) = (CosineFamily::new(a, b, Pole::sphere2(&s)).unwrap(), CosineFamily::new(a, b, Centre::sphere2(&s)).unwrap());
        let (p0, q0) = (CosineFamily::new(0.0, b, Pole::sphere2(&s)).unwrap(), CosineFamily::new(0.0, b, Centre::sphere2(&s)).unwrap());
        Ok(pole_vs_centre(&p, &q, &c.x, &c.e, &c.g).max(pole_vs_centre(&p0, &q0, &c.x, &c.e, &c.g)))
    });
    check("H2 pole vs centre", 256, (h2_cfg(0.0, 6.0), ab()), 0.0, |(c, (a, b))| {
        let h = Hyperbolic2::new(c.radius).unwrap();
        let (p, q) = (CosineFamily::new(a, b, Pole::hyperbolic2(&h)).unwrap(), CosineFamily::new(a, b, Centre::hyperbolic2(&h)).unwrap());
        let (p0, q0) = (CosineFamily::new(0.0, b, Pole::hyperbolic2(&h)).unwrap(), CosineFamily::new(0.0, b, Centre::hyperbolic2(&h)).unwrap());
        Ok(pole_vs_centre(&p, &q, &c.x, &c.e, &c.g).max(pole_vs_centre(&p0, &q0, &c.x, &c.e, &c.g)))
    });
    check("S3 pole vs centre", 256, (s3_cfg(0.0, PI), -5.0f64..5.0, -5.0f64..5.0), 0.0, |(c, a, b)| {
        let s = Sphere3::new(c.radius).unwrap();
        let (p, q) = (CosineFamily::new(a, b, Pole::sphere3(&s)).unwrap(), CosineFamily::new(a, b, Centre::sphere3(&s)).unwrap());
        let (p0, q0) = (CosineFamily::new(0.0, b, Pole::sphere3(&s)).unwrap(), CosineFamily::new(0.0, b, Centre::sphere3(&s)).unwrap());
        Ok(pole_vs_centre(&p, &q, &c.x, &c.e, &c.g()).max(pole_vs_centre(&p0, &q0, &c.x, &c.e, &c.g())))
    });
}

#[test]
fn deformation_closed_forms_match_autodiff() {
    check("elastic S2/H2", 256, (s2_cfg(0.01, 3.1), h2_cfg(0.01, 6.0), 0.1f64..10.0), CLOSED_TOL, |(s, h, k)| {
        let v = Elastic::new(k).unwrap();
        Ok(closed_vs_auto_scaled(&v, &s.x, &s.e, &s.g, elastic_scale(k, &s.e, &s.g)).max(closed_vs_auto_scaled(
            &v,
            &h.x,
            &h.e,
            &h.g,
            elastic_scale(k, &h.e, &h.g),
        )))
    });
    check(
        "separable S2/H2/T2",
        256,
        (s2_cfg(0.01, 3.1), h2_cfg(0.01, 6.0), test_sep(1.0), vec3(), 0.2f64..0.9),
        CLOSED_TOL,
        |(s, h, f, d, ratio)| {
            let fs = TestSep { radius: s.radius, ..f };
            let fh = TestSep { radius: h.radius, ..f };
            let mut err = 0.0f64;
            for centre in [Centre::sphere2(&Sphere2::new(s.radius).unwrap()), s2_centre(s.radius, &d)] {
                let scale = sep_scale(&fs, |f| Separable::new(f, centre), &s.x, &s.e, &s.g);
                err = err.max(closed_vs_auto_scaled(&Separable::new(fs, centre), &s.x, &s.e, &s.g, scale));
            }
            for centre in [Centre::hyperbolic2(&Hyperbolic2::new(h.radius).unwrap()), h2_centre(h.radius, &d)] {
                let scale = sep_scale(&fh, |f| Separable::new(f, centre), &h.x, &h.e, &h.g);
                err = err.max(closed_vs_auto_scaled(&Separable::new(fh, centre), &h.x, &h.e, &h.g, scale));
            }
            // Torus T²(1, R): a point at angles (ϑ, φ) from s.chart.
            let (l, r) = (1.0, ratio);
            let (x, q) = torus_point(l, r, s.chart[0] / s.radius * 2.0 - PI, s.chart[1]);
            let e = q * s.phi;
            let angle = TorusAngle::new(l, r).unwrap();
            let scale = sep_scale(&f, |f| Separable::torus(f, angle), &x, &e, &Matrix3::identity());
            err = err.max(closed_vs_auto_scaled(&Separable::torus(f, angle), &x, &e, &Matrix3::identity(), scale));
            Ok(err)
        },
    );
    check(
        "invariant potentials S3",
        256,
        (s3_cfg(0.01, 3.1), 0.0f64..5.0, 0.1f64..5.0, (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)),
        CLOSED_TOL,
        |(c, lam, mu, (a, b, cc))| {
            let g = c.g();
            let mut err = closed_vs_auto(&InvariantPotential::new(NeoHookean::new(lam, mu).unwrap()), &c.x, &c.e, &g);
            err = err.max(closed_vs_auto(
                &InvariantPotential::new(StVenantKirchhoff::new(lam, mu).unwrap()),
                &c.x,
                &c.e,
                &g,
            ));
            err = err.max(closed_vs_auto(&InvariantPotential::new(TestW { a, b, c: cc }), &c.x, &c.e, &g));
            Ok(err)
        },
    );
}

#[test]
fn combinators_add_and_scale_gradients() {
    check("sum/scaled", 128, (s2_cfg(0.05, 1.4), 0.1f64..5.0, -3.0f64..3.0), CLOSED_TOL, |(c, k, f)| {
        let centre = Centre::sphere2(&Sphere2::new(c.radius).unwrap());
        let osc = Oscillator::new(k, centre).unwrap();
        let ela = Elastic::new(k).unwrap();
        let v = Sum::new(Scaled::new(f, osc).unwrap(), ela);
        prop_assert!(Potential::<2, 3>::uses_frame(&v));
        prop_assert!(!Potential::<2, 3>::uses_frame(&Scaled::new(f, osc).unwrap()));
        let total = v.gradient(&c.x, &c.e, &c.g);
        let a = Potential::<2, 3>::gradient(&osc, &c.x, &c.e, &c.g);
        let b = ela.gradient(&c.x, &c.e, &c.g);
        let by_hand = Gradient { value: f * a.value + b.value, dx: a.dx * f + b.dx, de: a.de * f + b.de };
        prop_assert_eq!(total, by_hand);
        let (ge, ve) = elastic_scale(k, &c.e, &c.g);
        let scale = (f.abs() * amax(&a.dx) + ge, f.abs() * a.value + ve);
        Ok(closed_vs_auto_scaled(&v, &c.x, &c.e, &c.g, scale))
    });
}

// ---------------------------------- 2. automatic vs finite differences

/// Ridders differences (relative to max(|∇V|, |V|/ℓ)) reached 4.4e-11 at
/// worst over 80 seeds of these configurations (typically 1e-12); a wrong
/// derivative term shows up at 1e-7 or more.
const FD_TOL: f64 = 1e-9;

#[test]
fn autodiff_matches_finite_differences() {
    check(
        "FD: S2 Bertrand/cosine/central/elastic/separable",
        64,
        (s2_cfg(0.3, PI / 2.0 - 0.3), test_sep(1.0), 0.1f64..5.0),
        FD_TOL,
        |(c, f, k)| {
            let s = Sphere2::new(c.radius).unwrap();
            let centre = Centre::sphere2(&s);
            let f = TestSep { radius: c.radius, ..f };
            let mut err = 0.0f64;
            macro_rules! one {
                ($p:expr) => {{
                    let p = $p;
                    let e1 = fd_error(&p, &c.x, &c.e, &c.g, c.radius);
                    prop_assert!(e1 <= FD_TOL, "{}: {e1:e}", stringify!($p));
                    err = err.max(e1);
                }};
            }
            one!(Oscillator::new(k, centre).unwrap());
            one!(Kepler::new(k, centre).unwrap());
            one!(CosineFamily::new(k, -0.7, centre).unwrap());
            one!(Central::new(Quartic { a: k, b: 0.3 }, centre));
            one!(Elastic::new(k).unwrap());
            one!(Separable::new(f, centre));
            Ok(err)
        },
    );
    check(
        "FD: H2 Bertrand/cosine/elastic/separable",
        64,
        (h2_cfg(0.3, 3.0), test_sep(1.0), 0.1f64..5.0),
        FD_TOL,
        |(c, f, k)| {
            let centre = Centre::hyperbolic2(&Hyperbolic2::new(c.radius).unwrap());
            let f = TestSep { radius: c.radius, ..f };
            let mut err = 0.0f64;
            macro_rules! one {
                ($p:expr) => {{
                    let p = $p;
                    let e1 = fd_error(&p, &c.x, &c.e, &c.g, c.radius);
                    prop_assert!(e1 <= FD_TOL, "{}: {e1:e}", stringify!($p));
                    err = err.max(e1);
                }};
            }
            one!(Oscillator::new(k, centre).unwrap());
            one!(Kepler::new(k, centre).unwrap());
            one!(CosineFamily::new(k, -0.7, centre).unwrap());
            one!(Elastic::new(k).unwrap());
            one!(Separable::new(f, centre));
            Ok(err)
        },
    );
    check(
        "FD: S3 Bertrand/invariants",
        64,
        (s3_cfg(0.3, PI / 2.0 - 0.3), 0.0f64..5.0, 0.1f64..5.0),
        FD_TOL,
        |(c, lam, mu)| {
            let centre = Centre::sphere3(&Sphere3::new(c.radius).unwrap());
            let g = c.g();
            let mut err = 0.0f64;
            macro_rules! one {
                ($p:expr) => {{
                    let p = $p;
                    let e1 = fd_error(&p, &c.x, &c.e, &g, c.radius);
                    prop_assert!(e1 <= FD_TOL, "{}: {e1:e}", stringify!($p));
                    err = err.max(e1);
                }};
            }
            one!(Oscillator::new(mu, centre).unwrap());
            one!(Kepler::new(mu, centre).unwrap());
            one!(InvariantPotential::new(NeoHookean::new(lam, mu).unwrap()));
            one!(InvariantPotential::new(StVenantKirchhoff::new(lam, mu).unwrap()));
            Ok(err)
        },
    );
}

// ------------------------------------------- 3. paper's chart formulas

#[test]
fn values_match_chart_formulas() {
    check(
        "S2 chart formulas (b88), (c88), cos family",
        512,
        (s2_cfg(0.001, PI - 0.001), 0.1f64..10.0),
        1e-14,
        |(c, k)| {
            let centre = Centre::sphere2(&Sphere2::new(c.radius).unwrap());
            let (r, rr) = (c.chart[0], c.radius);
            let t = (r / rr).tan();
            let osc = Potential::<2, 3>::value(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g);
            let kep = Potential::<2, 3>::value(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g);
            let cosf = Potential::<2, 3>::value(&CosineFamily::new(k, -1.3, centre).unwrap(), &c.x, &c.e, &c.g);
            let cs = (r / rr).cos();
            let cos_err = (cosf - (k * cs * cs - 1.3 * cs)).abs() / (k + 1.3);
            Ok(rel(osc, 0.5 * k * rr * rr * t * t).max(rel(kep, -k / rr / t)).max(cos_err))
        },
    );
    check("H2 chart formulas (a133), (b133), cosh family", 512, (h2_cfg(0.001, 8.0), 0.1f64..10.0), 1e-14, |(c, k)| {
        let centre = Centre::hyperbolic2(&Hyperbolic2::new(c.radius).unwrap());
        let (r, rr) = (c.chart[0], c.radius);
        let t = (r / rr).tanh();
        let osc = Potential::<2, 3>::value(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g);
        let kep = Potential::<2, 3>::value(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g);
        let cosf = Potential::<2, 3>::value(&CosineFamily::new(k, -1.3, centre).unwrap(), &c.x, &c.e, &c.g);
        let ch = (r / rr).cosh();
        let cos_err = (cosf - (k * ch * ch - 1.3 * ch)).abs() / (k * ch * ch + 1.3 * ch);
        Ok(rel(osc, 0.5 * k * rr * rr * t * t).max(rel(kep, -k / rr / t)).max(cos_err))
    });
    check("S3 chart formulas", 512, (s3_cfg(0.001, PI - 0.001), 0.1f64..10.0), 1e-14, |(c, k)| {
        let centre = Centre::sphere3(&Sphere3::new(c.radius).unwrap());
        // r/R exactly as the embedding forms it (√s, s = |r̄|²/R²): near
        // r = πR the chart itself amplifies a different rounding of r/R by
        // 1/(π − r/R) (S3_CHART_MARGIN).
        let rr = c.radius;
        let t = (c.rbar.norm_squared() / (rr * rr)).sqrt().tan();
        let osc = Potential::<3, 4>::value(&Oscillator::new(k, centre).unwrap(), &c.x, &c.e, &c.g());
        let kep = Potential::<3, 4>::value(&Kepler::new(k, centre).unwrap(), &c.x, &c.e, &c.g());
        Ok(rel(osc, 0.5 * k * rr * rr * t * t).max(rel(kep, -k / rr / t)))
    });
}

#[test]
fn distances_and_deformation_variables_match_their_definitions() {
    // r from the centre (in units of ε); (λ, μ) and (ϱ, ε) from the
    // two-polar decomposition (in units of ε·cond).
    check(
        "r, ϑ, λ, μ, ϱ, ε [units of ε·cond]",
        512,
        (s2_cfg(0.001, PI - 0.001), h2_cfg(0.001, 8.0), 0.1f64..0.95, -PI..PI),
        32.0,
        |(s, h, ratio, th)| {
            let cs = Centre::sphere2(&Sphere2::new(s.radius).unwrap());
            let ch = Centre::hyperbolic2(&Hyperbolic2::new(h.radius).unwrap());
            let mut err = rel(cs.distance(&s.x), s.chart[0]).max(rel(ch.distance(&h.x), h.chart[0])) / EPS;
            // The torus angle: absolute error relative to π.
            let (x, _) = torus_point(2.0, 2.0 * ratio, th, s.chart[1]);
            err = err.max((TorusAngle::new(2.0, 2.0 * ratio).unwrap().angle(&x) - th).abs() / (PI * EPS));
            for c in [&s, &h] {
                let (l, m) = (c.lm.0.max(c.lm.1), c.lm.0.min(c.lm.1));
                let (dl, dm) = deformation_invariants(&c.e, &c.g);
                let (rho, eps) = polar_invariants(&c.e, &c.g);
                // x = (λ − μ)/√2 = ϱ sin ε, y = (λ + μ)/√2 = ϱ cos ε (a125).
                let e = rel(dl, l).max(rel(dm, m)).max(rel(rho, l.hypot(m))).max((eps - (l - m).atan2(l + m)).abs());
                err = err.max(e / (EPS * c.cond()));
            }
            Ok(err)
        },
    );
}

#[test]
fn distances_from_any_centre_match_the_manifolds() {
    // Centre::distance against GeodesicDistance::distance (an independent formula:
    // atan2 of cross and dot products on S², spatial parts on H²), relative,
    // in units of ε (H²: times cosh² of the centre's distance from the origin).
    check(
        "r from any centre vs GeodesicDistance::distance [units of ε·cond]",
        512,
        (s2_cfg(0.001, PI - 0.001), h2_cfg(0.001, 5.0), s3_cfg(0.001, 3.1), vec3(), vec4()),
        64.0,
        |(s, h, c3, d, d4)| {
            let (ms, mh, m3) = (
                Sphere2::new(s.radius).unwrap(),
                Hyperbolic2::new(h.radius).unwrap(),
                Sphere3::new(c3.radius).unwrap(),
            );
            let (cs, ch, c4) = (s2_centre(s.radius, &d), h2_centre(h.radius, &d), s3_centre(c3.radius, &d4));
            let amp_c = (ch.point()[2] / h.radius).powi(2);
            // Distances below ~1e-3 R lose relative precision in both forms
            // (points rounded to ε R): compare them absolutely.
            let cmp = |a: f64, b: f64, r: f64| (a - b).abs() / b.max(1e-3 * r);
            let es = cmp(cs.distance(&s.x), ms.distance(cs.point(), &s.x).unwrap(), s.radius);
            let eh = cmp(ch.distance(&h.x), mh.distance(ch.point(), &h.x).unwrap(), h.radius) / (h.amp * amp_c);
            let e3 = cmp(c4.distance(&c3.x), m3.distance(c4.point(), &c3.x).unwrap(), c3.radius);
            Ok(es.max(eh).max(e3) / EPS)
        },
    );
}

#[test]
fn deformation_potentials_match_their_formulas() {
    check(
        "elastic (a131), separable (b128), neo-Hookean, invariants [units of ε·cond]",
        512,
        (s2_cfg(0.01, PI - 0.01), h2_cfg(0.01, 5.0), test_sep(1.0), 0.1f64..10.0, s3_cfg(0.01, 3.1)),
        64.0,
        |(s, h, f, k, c3)| {
            let mut err = 0.0f64;
            for (c, geo) in [(&s, 0), (&h, 1)] {
                let (l, m) = c.lm;
                let el = Elastic::new(k).unwrap().value(&c.x, &c.e, &c.g);
                let mut e2 = rel(el, k * (1.0 / (l * m) + 0.5 * (l * l + m * m)));
                let (lmax, lmin) = (l.max(m), l.min(m));
                let (rho, eps) = (lmax.hypot(lmin), (lmax - lmin).atan2(lmax + lmin));
                let f = TestSep { radius: c.radius, ..f };
                let centre = if geo == 0 {
                    Centre::sphere2(&Sphere2::new(c.radius).unwrap())
                } else {
                    Centre::hyperbolic2(&Hyperbolic2::new(c.radius).unwrap())
                };
                let v = Separable::new(f, centre).value(&c.x, &c.e, &c.g);
                let want = f.formula(c.chart[0], rho, eps);
                // Terms of either sign: relative to the sum of magnitudes.
                let scale = (f.a * c.chart[0] * c.chart[0]).abs()
                    + f.b.abs()
                    + (f.c * rho * rho).abs()
                    + (f.d / (rho * rho)).abs()
                    + (f.k.abs() + (f.m * eps * eps).abs()) / (rho * rho);
                e2 = e2.max((v - want).abs() / scale);
                err = err.max(e2 / (EPS * c.cond()));
            }
            let (lam, mu) = (0.7 * k, k);
            let nh = InvariantPotential::new(NeoHookean::new(lam, mu).unwrap()).value(&c3.x, &c3.e, &c3.g());
            let j = c3.l.product();
            let want = 0.5 * mu * (c3.l.norm_squared() - 3.0) - mu * j.ln() + 0.5 * lam * j.ln() * j.ln();
            let scale = 0.5 * mu * (c3.l.norm_squared() + 3.0) + mu * j.ln().abs() + 0.5 * lam * j.ln() * j.ln();
            let (i1, i2, i3) = principal_invariants(&(c3.e.transpose() * c3.e));
            let l2 = c3.l.map(|v| v * v);
            let e3 = ((nh - want).abs() / scale)
                .max(rel(i1, l2.sum()))
                .max(rel(i2, l2[0] * l2[1] + l2[0] * l2[2] + l2[1] * l2[2]))
                .max(rel(i3, l2.product()));
            Ok(err.max(e3 / (EPS * c3.cond())))
        },
    );
}

// -------------------------------------------------------- 4. symmetries

#[test]
fn central_potentials_are_invariant_under_rotations_about_their_centre() {
    // In units of ε·cond (H²: times cosh² of the centre's distance from the
    // origin, the size of the boost that moves it there).
    const TOL: f64 = 64.0;
    macro_rules! all_along {
        ($err:ident, $centre:expr, $a:expr, $c:expr, $f:expr, $n:literal, $e:literal, $scale:expr) => {{
            let (centre, a, c) = ($centre, $a, $c);
            let g = c.g();
            let mut worst = along(
                &Potential::<$n, $e>::gradient(&Oscillator::new(1.0, centre).unwrap(), &c.x, &c.e, &g),
                &a,
                &c.x,
                &c.e,
            );
            worst = worst.max(along(
                &Potential::<$n, $e>::gradient(&Kepler::new(1.0, centre).unwrap(), &c.x, &c.e, &g),
                &a,
                &c.x,
                &c.e,
            ));
            worst = worst.max(along(
                &Potential::<$n, $e>::gradient(&CosineFamily::new(1.0, 0.5, centre).unwrap(), &c.x, &c.e, &g),
                &a,
                &c.x,
                &c.e,
            ));
            worst = worst.max(along(
                &Potential::<$n, $e>::gradient(&Central::new(Quartic { a: 1.0, b: 0.2 }, centre), &c.x, &c.e, &g),
                &a,
                &c.x,
                &c.e,
            ));
            if let Some(f) = $f {
                worst = worst.max(along(&f(centre).gradient(&c.x, &c.e, &g), &a, &c.x, &c.e));
            }
            $err = $err.max(worst / (EPS * $scale));
        }};
    }
    let jz = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    check(
        "S2: z-rotations (default centre) and rotations about any centre [units of ε·cond]",
        256,
        (s2_cfg(0.05, 3.1), vec3(), vec3(), vec3(), test_sep(1.0)),
        TOL,
        |(c, d, w1, w2, f)| {
            let s = Sphere2::new(c.radius).unwrap();
            let f = TestSep { radius: c.radius, ..f };
            let sep = Some(|centre| Separable::new(f, centre));
            let mut err = 0.0f64;
            let other = s2_centre(c.radius, &d);
            all_along!(err, Centre::sphere2(&s), jz, &c, sep, 2, 3, c.cond());
            all_along!(err, other, killing_fixing(&c.g, other.point(), &w1, &w2), &c, sep, 2, 3, c.cond());
            Ok(err)
        },
    );
    check(
        "H2: rotations about the origin and about any centre [units of ε·cond]",
        256,
        (h2_cfg(0.05, 4.0), vec3(), vec3(), vec3(), test_sep(1.0)),
        TOL,
        |(c, d, w1, w2, f)| {
            let h = Hyperbolic2::new(c.radius).unwrap();
            let f = TestSep { radius: c.radius, ..f };
            let sep = Some(|centre| Separable::new(f, centre));
            let mut err = 0.0f64;
            let other = h2_centre(c.radius, &d);
            let amp_c = (other.point()[2] / c.radius).powi(2);
            all_along!(err, Centre::hyperbolic2(&h), jz, &c, sep, 2, 3, c.cond());
            all_along!(err, other, killing_fixing(&c.g, other.point(), &w1, &w2), &c, sep, 2, 3, c.cond() * amp_c);
            Ok(err)
        },
    );
    check(
        "T2: z-rotations [units of ε·cond]",
        256,
        (s2_cfg(0.01, 3.1), 0.1f64..0.9, test_sep(1.0)),
        TOL,
        |(c, ratio, f)| {
            let (x, q) = torus_point(1.0, ratio, c.chart[0] / c.radius * 2.0 - PI, c.chart[1]);
            let e = q * c.phi;
            let t = Separable::torus(f, TorusAngle::new(1.0, ratio).unwrap());
            Ok(along(&t.gradient(&x, &e, &c.g), &jz, &x, &e) / (EPS * c.cond()))
        },
    );
    check(
        "S3: rotations fixing the centre [units of ε]",
        256,
        (s3_cfg(0.05, 3.1), vec4(), vec4(), vec4()),
        TOL,
        |(c, d, w1, w2)| {
            let s = Sphere3::new(c.radius).unwrap();
            let mut err = 0.0f64;
            let none: Option<fn(Centre<4>) -> Oscillator<4>> = None;
            for centre in [Centre::sphere3(&s), s3_centre(c.radius, &d)] {
                all_along!(err, centre, killing_fixing(&c.g(), centre.point(), &w1, &w2), &c, none, 3, 4, 1.0);
            }
            Ok(err)
        },
    );
}

#[test]
fn bertrand_gradients_annihilate_the_position_vector() {
    // The ambient forms are homogeneous of degree 0 in x: ∂V·x = 0.
    check("∂V·x = 0 [units of ε·cond]", 256, (s2_cfg(0.05, 1.5), h2_cfg(0.05, 5.0), vec3()), 64.0, |(s, h, d)| {
        let mut err = 0.0f64;
        for (c, centre) in [(&s, s2_centre(s.radius, &d)), (&h, h2_centre(h.radius, &d))] {
            for g in [
                Potential::<2, 3>::gradient(&Oscillator::new(1.0, centre).unwrap(), &c.x, &c.e, &c.g),
                Potential::<2, 3>::gradient(&Kepler::new(1.0, centre).unwrap(), &c.x, &c.e, &c.g),
            ] {
                err = err.max(g.dx.dot(&c.x).abs() / (g.dx.norm() * c.x.norm()) / (EPS * c.amp));
            }
        }
        Ok(err)
    });
}

#[test]
fn deformation_potentials_see_only_the_green_tensor() {
    // e = qφ → qUφ leaves G fixed; e → qφU changes G to UᵀGU (same
    // invariants). Any ambient isometry leaves G fixed: ∂V·(Ae) = 0.
    check(
        "invariance under orthonormal changes [units of ε·cond]",
        256,
        (s2_cfg(0.01, 3.1), h2_cfg(0.01, 5.0), -PI..PI, rot3(), s3_cfg(0.01, 3.1), vec3(), vec3(), test_sep(1.0)),
        64.0,
        |(s, h, a, u, c3, w1, w2, f)| {
            let mut err = 0.0f64;
            let ela = Elastic::new(1.3).unwrap();
            for c in [&s, &h] {
                // Terms of both signs in the separable test functions: relative
                // to |V_ϱ| + |V_ε|/ϱ².
                let f = TestSep { a: 0.0, b: 0.0, ..f };
                let sep = Separable::new(f, Centre::sphere2(&Sphere2::new(1.0).unwrap()));
                let (rho, eps) = polar_invariants(&c.e, &c.g);
                let sep_scale = f.formula(0.0, rho, eps).abs().max(f.c * rho * rho + f.d / (rho * rho));
                let el = ela.value(&c.x, &c.e, &c.g);
                let sp = sep.value(&c.x, &c.e, &c.g);
                let mut e2 = 0.0f64;
                for e in [c.q * rot2(a) * c.phi, c.q * c.phi * rot2(a)] {
                    e2 = e2
                        .max(rel(ela.value(&c.x, &e, &c.g), el))
                        .max((sep.value(&c.x, &e, &c.g) - sp).abs() / sep_scale);
                }
                // A generic Killing field u(gv)ᵀ − v(gu)ᵀ of the ambient metric
                // (isometries move x too).
                let k = w1 * (c.g * w2).transpose() - w2 * (c.g * w1).transpose();
                e2 = e2.max(along(&ela.gradient(&c.x, &c.e, &c.g), &k, &c.x, &c.e));
                err = err.max(e2 / (EPS * c.cond()));
            }
            let g4 = c3.g();
            let nh = InvariantPotential::new(NeoHookean::new(0.5, 1.0).unwrap());
            let v = nh.value(&c3.x, &c3.e, &g4);
            let scale =
                0.5 * (c3.l.norm_squared() + 3.0) + c3.l.product().ln().abs() * (1.0 + c3.l.product().ln().abs());
            let phi = c3.q.transpose() * c3.e;
            for e in [c3.q * u * phi, c3.q * phi * u] {
                err = err.max((nh.value(&c3.x, &e, &g4) - v).abs() / scale / (EPS * c3.cond()));
            }
            Ok(err)
        },
    );
}

// ----------------------------------------------- 5. natural states

fn sym_eigen4(h: SMatrix<f64, 4, 4>) -> Vec<f64> {
    let mut ev: Vec<f64> = h.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(|a, b| a.total_cmp(b));
    ev
}

#[test]
fn elastic_natural_state_is_a_stable_minimum() {
    check(
        "elastic: V = 2κ, ∇V = 0, Hessian eigenvalues {0, 2κ, 2κ, 4κ} at λ = μ = 1 [units of ε·cond]",
        128,
        (s2_cfg(0.01, 3.1), h2_cfg(0.01, 5.0), -PI..PI, 0.1f64..10.0),
        64.0,
        |(s, h, a, k)| {
            let v = Elastic::new(k).unwrap();
            let mut err = 0.0f64;
            for c in [&s, &h] {
                let e = c.q * rot2(a);
                let g = v.gradient(&c.x, &e, &c.g);
                // ∂V/∂e = κ g e (…) scales with |g e|.
                let mut e2 = rel(g.value, 2.0 * k).max(amax(&g.de) / (k * amax(&(c.g * e))));
                // Hessian in the entries of φ (e = qφ), exact by second-order duals.
                let phi0 = rot2(a);
                let (_, _, hess) = num_dual::hessian(
                    |p: SVector<_, 4>| {
                        let phi = SMatrix::<_, 2, 2>::from_column_slice(p.as_slice());
                        let e = c.q.map(num_dual::Dual2SVec64::<4>::from_re) * phi;
                        let x = c.x.map(num_dual::Dual2SVec64::<4>::from_re);
                        v.value(&x, &e, &c.g)
                    },
                    &SVector::<f64, 4>::from_column_slice(phi0.as_slice()),
                );
                let ev = sym_eigen4(hess);
                for (got, want) in ev.iter().zip([0.0, 2.0 * k, 2.0 * k, 4.0 * k]) {
                    e2 = e2.max((got - want).abs() / k);
                }
                // λ = μ = 1: (tr G)²/det G = 4.
                err = err.max(e2 / (EPS * c.cond()));
            }
            Ok(err)
        },
    );
    check("elastic: V ≥ 2κ [units of ε·cond]", 512, s2_cfg(0.01, 3.1), 1.0, |c| {
        let v = Elastic::new(1.0).unwrap().value(&c.x, &c.e, &c.g);
        Ok((2.0 - v).max(0.0) / (EPS * c.cond()))
    });
}

#[test]
fn hyperelastic_energies_vanish_and_are_stable_at_the_identity() {
    check(
        "neo-Hookean/SVK: W = 0, ∇W = 0, Hessian {0×3, 2μ×5, 3λ+2μ} at G = I",
        64,
        (s3_cfg(0.01, 3.1), rot3(), 0.0f64..5.0, 0.1f64..5.0),
        1e-13,
        |(c, u, lam, mu)| {
            let g4 = c.g();
            let e0 = c.q * u;
            let mut err = 0.0f64;
            let check_one = |p: &dyn Fn(&SMatrix<num_dual::Dual2SVec64<9>, 4, 3>) -> num_dual::Dual2SVec64<9>,
                             grad: Gradient<3, 4>|
             -> f64 {
                let mut err = grad.value.abs().max(amax(&grad.de)) / mu;
                let (_, _, hess) = num_dual::hessian(
                    |pv: SVector<_, 9>| {
                        let phi = SMatrix::<_, 3, 3>::from_column_slice(pv.as_slice());
                        p(&(c.q.map(num_dual::Dual2SVec64::<9>::from_re) * phi))
                    },
                    &SVector::<f64, 9>::from_column_slice(u.as_slice()),
                );
                let mut ev: Vec<f64> = hess.symmetric_eigen().eigenvalues.iter().copied().collect();
                ev.sort_by(|a, b| a.total_cmp(b));
                let want = [0.0, 0.0, 0.0, 2.0 * mu, 2.0 * mu, 2.0 * mu, 2.0 * mu, 2.0 * mu, 3.0 * lam + 2.0 * mu];
                let mut want = want.to_vec();
                want.sort_by(|a, b| a.total_cmp(b));
                for (got, w) in ev.iter().zip(want) {
                    err = err.max((got - w).abs() / (lam + mu));
                }
                err
            };
            let x2 = c.x.map(num_dual::Dual2SVec64::<9>::from_re);
            let nh = InvariantPotential::new(NeoHookean::new(lam, mu).unwrap());
            err = err.max(check_one(&|e| nh.value(&x2, e, &g4), nh.gradient(&c.x, &e0, &g4)));
            let svk = InvariantPotential::new(StVenantKirchhoff::new(lam, mu).unwrap());
            err = err.max(check_one(&|e| svk.value(&x2, e, &g4), svk.gradient(&c.x, &e0, &g4)));
            Ok(err)
        },
    );
}

#[test]
fn separable_form_of_the_elastic_potential_is_the_elastic_potential() {
    // (a131): κ(1/(λμ) + (λ² + μ²)/2) = 2κ/(ϱ² cos 2ε) + κϱ²/2, value and
    // gradient, including the gauge-singular set λ = μ (ε = 0).
    check(
        "separable (a131) = elastic [units of ε·cond]",
        256,
        (s2_cfg(0.01, 3.1), h2_cfg(0.01, 5.0), 0.1f64..10.0, -PI..PI, 0.3f64..3.0, proptest::bool::ANY),
        64.0,
        |(s, h, k, a, scale, equal)| {
            let el = Elastic::new(k).unwrap();
            let mut err = 0.0f64;
            for c in [&s, &h] {
                let centre = Centre::sphere2(&Sphere2::new(1.0).unwrap());
                let sep = Separable::new(ElasticSep { kappa: k }, centre);
                let (e, cond) = if equal { (c.q * rot2(a) * scale, 4.0 * c.amp) } else { (c.e, c.cond()) };
                let want = el.gradient(&c.x, &e, &c.g);
                // ∂V/∂e = κ ge (I − adj G/det^{3/2}): its terms cancel near the
                // natural state, so compare relative to their size.
                let gm = e.transpose() * c.g * e;
                let scale = k * amax(&(c.g * e)) * (1.0 + gm.trace() / gm.determinant().powf(1.5));
                for got in [sep.gradient(&c.x, &e, &c.g), autodiff_gradient(&sep, &c.x, &e, &c.g)] {
                    let e2 = rel(got.value, want.value).max(amax(&(got.de - want.de)) / scale);
                    prop_assert_eq!(got.dx, SVector::<f64, 3>::zeros());
                    err = err.max(e2 / (EPS * cond));
                }
            }
            Ok(err)
        },
    );
}

// ------------------------------------------- 6. singular points, errors

#[test]
fn singular_points_give_non_finite_values_without_panicking() {
    let s = Sphere2::new(2.0).unwrap();
    let h = Hyperbolic2::new(2.0).unwrap();
    let g = Matrix3::identity();
    let e = SMatrix::<f64, 3, 2>::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
    let pole = Vector3::new(0.0, 0.0, 2.0);
    let south = Vector3::new(0.0, 0.0, -2.0);
    let equator = Vector3::new(2.0, 0.0, 0.0);
    let kep = Kepler::new(1.0, Centre::sphere2(&s)).unwrap();
    let osc = Oscillator::new(1.0, Centre::sphere2(&s)).unwrap();
    let all_nan = |gr: &Gradient<2, 3>| gr.dx.iter().all(|v| v.is_nan());
    let non_finite = |gr: &Gradient<2, 3>| gr.dx.iter().chain(gr.de.iter()).any(|v| !v.is_finite());
    for (x, want) in [(pole, f64::NEG_INFINITY), (south, f64::INFINITY)] {
        let gr = Potential::<2, 3>::gradient(&kep, &x, &e, &g);
        assert_eq!(gr.value, want);
        assert!(all_nan(&gr));
        let auto = autodiff_gradient(&kep, &x, &e, &g);
        assert_eq!(auto.value, want);
        assert!(non_finite(&auto));
    }
    let gr = Potential::<2, 3>::gradient(&osc, &equator, &e, &g);
    assert_eq!(gr.value, f64::INFINITY);
    assert!(all_nan(&gr));
    assert!(non_finite(&autodiff_gradient(&osc, &equator, &e, &g)));
    // H² Kepler at its centre.
    let kh = Kepler::new(1.0, Centre::hyperbolic2(&h)).unwrap();
    let gr = Potential::<2, 3>::gradient(&kh, &pole, &e, &eta());
    assert_eq!(gr.value, f64::NEG_INFINITY);
    assert!(all_nan(&gr));
    // Degenerate (collapsed) frames.
    let flat = SMatrix::<f64, 3, 2>::new(1.0, 2.0, 0.0, 0.0, 0.0, 0.0);
    let ela = Elastic::new(1.0).unwrap().gradient(&pole, &flat, &g);
    assert_eq!(ela.value, f64::INFINITY);
    assert!(ela.de.iter().all(|v| v.is_nan()));
    // The separated form 2κ/(ϱ² cos 2ε) at ε = π/4: cos(π/2) rounds to
    // 6e-17, so the value is huge (≈ 1e16κ) rather than infinite.
    let sep = Separable::new(ElasticSep { kappa: 1.0 }, Centre::sphere2(&s));
    assert!(sep.gradient(&pole, &flat, &g).value > 1e15);
    assert!(sep.value(&pole, &flat, &g) > 1e15);
    let nh = InvariantPotential::new(NeoHookean::new(1.0, 1.0).unwrap());
    let flat3 = SMatrix::<f64, 4, 3>::new(0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0);
    let gr = nh.gradient(&Vector4::new(1.0, 0.0, 0.0, 0.0), &flat3, &SMatrix::identity());
    assert_eq!(gr.value, f64::INFINITY);
    assert!(gr.de.iter().all(|v| v.is_nan()));
    // The cosine family and the oscillator on H² have no singular set.
    let far = h.embed(&Vector2::new(60.0, 0.3));
    let oh = Potential::<2, 3>::gradient(&Oscillator::new(1.0, Centre::hyperbolic2(&h)).unwrap(), &far, &e, &eta());
    assert!(oh.value.is_finite() && oh.value < 0.5 * 4.0 && oh.value > 0.5 * 4.0 * (1.0 - 1e-12));
}

#[test]
fn bad_parameters_give_typed_errors() {
    let s = Sphere2::new(1.0).unwrap();
    let c = Centre::sphere2(&s);
    let bad = [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    for v in bad {
        assert!(matches!(Oscillator::new(v, c), Err(Error::InvalidParameter { field: "kappa", .. })));
        assert!(matches!(Kepler::new(v, c), Err(Error::InvalidParameter { field: "alpha", .. })));
        assert!(matches!(Elastic::new(v), Err(Error::InvalidParameter { field: "kappa", .. })));
        assert!(matches!(NeoHookean::new(1.0, v), Err(Error::InvalidParameter { field: "mu", .. })));
        assert!(matches!(StVenantKirchhoff::new(1.0, v), Err(Error::InvalidParameter { field: "mu", .. })));
        assert!(matches!(TorusAngle::new(2.0, v), Err(Error::InvalidParameter { field: "R", .. })));
        let f = |_: &SVector<f64, 3>, _: &SMatrix<f64, 3, 2>, _: &SMatrix<f64, 3, 3>| 0.0;
        assert!(matches!(FnPotential::new(f, false, v), Err(Error::InvalidParameter { field: "length_scale", .. })));
    }
    for v in [f64::NAN, f64::INFINITY] {
        assert!(matches!(CosineFamily::new(v, 1.0, c), Err(Error::InvalidParameter { field: "alpha_hat", .. })));
        assert!(matches!(CosineFamily::new(1.0, v, c), Err(Error::InvalidParameter { field: "beta_hat", .. })));
        assert!(matches!(
            Scaled::new(v, Elastic::new(1.0).unwrap()),
            Err(Error::InvalidParameter { field: "factor", .. })
        ));
    }
    assert!(CosineFamily::new(-2.0, 0.0, c).is_ok());
    assert!(Scaled::new(-1.0, Elastic::new(1.0).unwrap()).is_ok());
    assert!(matches!(NeoHookean::new(-0.1, 1.0), Err(Error::InvalidParameter { field: "lambda", .. })));
    assert!(NeoHookean::new(0.0, 1.0).is_ok());
    assert!(matches!(StVenantKirchhoff::new(-0.7, 1.0), Err(Error::InvalidParameter { field: "lambda", .. })));
    assert!(StVenantKirchhoff::new(-0.6, 1.0).is_ok());
    assert!(matches!(TorusAngle::new(0.5, 0.5), Err(Error::InvalidParameter { field: "L", .. })));
    assert!(matches!(TorusAngle::new(f64::NAN, 0.5), Err(Error::InvalidParameter { field: "L", .. })));
    // Centres must be finite points of their manifold.
    assert!(matches!(
        Centre::sphere2_at(&s, &Vector3::new(0.0, 0.0, 1.1)),
        Err(Error::Constraint { field: "centre", .. })
    ));
    assert!(matches!(
        Centre::sphere2_at(&s, &Vector3::new(0.0, f64::NAN, 1.0)),
        Err(Error::NotFinite { field: "centre" })
    ));
    let h = Hyperbolic2::new(1.0).unwrap();
    assert!(matches!(
        Centre::hyperbolic2_at(&h, &Vector3::new(0.0, 0.0, -1.0)),
        Err(Error::Constraint { field: "centre", .. })
    ));
    assert!(matches!(
        Centre::hyperbolic2_at(&h, &Vector3::new(1.0, 0.0, 1.0)),
        Err(Error::Constraint { field: "centre", .. })
    ));
    let s3 = Sphere3::new(1.0).unwrap();
    assert!(matches!(
        Centre::sphere3_at(&s3, &Vector4::new(0.5, 0.0, 0.0, 0.0)),
        Err(Error::Constraint { field: "centre", .. })
    ));
    assert!(Centre::sphere3_at(&s3, &Vector4::new(0.0, 0.6, 0.0, -0.8)).is_ok());
}

// ----------------------------------------------- 7. f64 closures

#[test]
fn closure_potentials_match_closed_forms() {
    check("FnPotential (Ridders) vs closed forms", 64, (s2_cfg(0.2, PI / 2.0 - 0.2), 0.1f64..5.0), 1e-10, |(c, k)| {
        let centre = Centre::sphere2(&Sphere2::new(c.radius).unwrap());
        let osc = Oscillator::new(k, centre).unwrap();
        let ela = Elastic::new(k).unwrap();
        let v = Sum::new(osc, ela);
        let f = FnPotential::new(
            move |x: &SVector<f64, 3>, e: &SMatrix<f64, 3, 2>, g: &SMatrix<f64, 3, 3>| v.value(x, e, g),
            true,
            c.radius,
        )
        .unwrap();
        let exact = v.gradient(&c.x, &c.e, &c.g);
        let (approx, est) = f.gradient_with_error(&c.x, &c.e, &c.g);
        prop_assert_eq!(approx.value, exact.value);
        let err = grad_error(&approx, &exact);
        // The reported error estimate bounds the actual error (up to 10×).
        let actual = amax(&(approx.dx - exact.dx)).max(amax(&(approx.de - exact.de)));
        prop_assert!(actual <= 10.0 * est + 1e-14 * amax(&exact.de), "actual {actual:e} vs estimate {est:e}");
        // The dual-number path reproduces the difference gradient exactly.
        let auto = autodiff_gradient(&f, &c.x, &c.e, &c.g);
        prop_assert_eq!(auto.dx, approx.dx);
        prop_assert_eq!(auto.de, approx.de);
        Ok(err)
    });
    // Second-order duals are refused with NaN.
    let f = FnPotential::new(|x: &SVector<f64, 3>, _: &SMatrix<f64, 3, 2>, _: &SMatrix<f64, 3, 3>| x[2], false, 1.0)
        .unwrap();
    let (v, _, h) = num_dual::hessian(
        |x: SVector<_, 3>| f.value(&x, &SMatrix::<num_dual::Dual2SVec64<3>, 3, 2>::zeros(), &Matrix3::identity()),
        &Vector3::new(0.0, 0.0, 1.0),
    );
    assert!(v.is_nan() && h.iter().all(|v| v.is_nan()));
}
