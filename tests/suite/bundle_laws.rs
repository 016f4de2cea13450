//! The frame-bundle law suite: written once, called by every manifold's tests.

use framedyn::bundle::FrameBundle;
use framedyn::lie::{AlgebraVector, LieGroup};
use nalgebra::{SMatrix, SVector};

type Alg<B, const N: usize, const E: usize> = <<B as FrameBundle<N, E>>::Group as LieGroup>::Algebra;

/// One classical RKMK4 step for `ġ = g·ξ(t, g)`, with `g = g₀ exp(θ)` and
/// `θ̇ = dexp⁻¹_{−θ} ξ` (a small reference integrator for the tests; the
/// library's integrators are tested on their own).
pub fn rkmk4_step<G: LieGroup>(g0: &G, t: f64, h: f64, xi: &impl Fn(f64, &G) -> G::Algebra) -> G {
    let f = |tt: f64, th: &G::Algebra| -> G::Algebra {
        let g = g0.compose(&G::exp(th));
        G::dexp_inv(&(-*th), &xi(tt, &g))
    };
    let z = G::Algebra::zero();
    let k1 = f(t, &z);
    let k2 = f(t + 0.5 * h, &(k1 * (0.5 * h)));
    let k3 = f(t + 0.5 * h, &(k2 * (0.5 * h)));
    let k4 = f(t + h, &(k3 * h));
    let th = (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
    g0.compose(&G::exp(&th)).renormalize()
}

/// Frame components (w.r.t. the ambient metric) of an ambient vector.
pub fn frame_components<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    g: &B::Group,
    w: &SVector<f64, E>,
) -> SVector<f64, N> {
    b.frame_vectors(g).transpose() * b.ambient_metric() * w
}

/// Parallel transport of the bundle element `g0` along the chart curve
/// `t ↦ curve(t) = (x(t), ẋ(t))`, `t ∈ [0, 1]`, with `steps` RKMK4 steps.
pub fn transport_along<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    g0: &B::Group,
    curve: &impl Fn(f64) -> (SVector<f64, N>, SVector<f64, N>),
    steps: usize,
) -> B::Group {
    let xi = |t: f64, g: &B::Group| -> Alg<B, N, E> {
        let (x, xd) = curve(t);
        let w = b.embed_tangent(&x, &xd);
        b.horizontal_lift(g, &frame_components(b, g, &w))
    };
    let h = 1.0 / steps as f64;
    let mut g = *g0;
    for i in 0..steps {
        g = rkmk4_step(&g, i as f64 * h, h, &xi);
    }
    g
}

/// Parallel transport of chart vectors along the same curve by the coordinate
/// ODE `V̇^i = −Γ^i_{jk} ẋ^j V^k` (classical RK4): the paper's formulation.
pub fn transport_in_chart<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    v0: &SMatrix<f64, N, N>,
    curve: &impl Fn(f64) -> (SVector<f64, N>, SVector<f64, N>),
    steps: usize,
) -> SMatrix<f64, N, N> {
    let f = |t: f64, v: &SMatrix<f64, N, N>| -> SMatrix<f64, N, N> {
        let (x, xd) = curve(t);
        let gam = b.christoffel(&x);
        SMatrix::from_fn(|i, col| {
            let mut s = 0.0;
            for j in 0..N {
                for k in 0..N {
                    s -= gam[i][j][k] * xd[j] * v[(k, col)];
                }
            }
            s
        })
    };
    let h = 1.0 / steps as f64;
    let mut v = *v0;
    for i in 0..steps {
        let t = i as f64 * h;
        let k1 = f(t, &v);
        let k2 = f(t + 0.5 * h, &(v + k1 * (0.5 * h)));
        let k3 = f(t + 0.5 * h, &(v + k2 * (0.5 * h)));
        let k4 = f(t + h, &(v + k3 * h));
        v += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
    }
    v
}

/// Largest violation of the bundle's constraints at `g`: group defect, point
/// on the manifold, frame vectors tangent and orthonormal in the ambient
/// metric — the last two relative to the Euclidean sizes of the vectors
/// involved, since on H² far from the origin the components of `q` grow like
/// cosh(r/R) and their round-off with them.
pub fn frame_defect<B: FrameBundle<N, E>, const N: usize, const E: usize>(b: &B, g: &B::Group) -> f64 {
    let p = b.position(g);
    let q = b.frame_vectors(g);
    let gram = q.transpose() * b.ambient_metric() * q - SMatrix::<f64, N, N>::identity();
    let norms: Vec<f64> = (0..N).map(|a| q.column(a).norm()).collect();
    let mut worst: f64 = 0.0;
    for a in 0..N {
        let qa: SVector<f64, E> = q.column(a).into();
        worst = worst.max((b.project_tangent(&p, &qa) - qa).amax() / norms[a]);
        for c in 0..N {
            worst = worst.max(gram[(a, c)].abs() / (norms[a] * norms[c]));
        }
    }
    b.bundle_defect(g).max(b.point_defect(&p)).max(worst)
}

/// Checks at chart point `x` with frame rotation `u` (`q = E(x)·u`):
/// `from_chart`/`to_chart` round trip and agree with `embed`/`frame`; the
/// horizontal lift moves the point with velocity `Σ v_a q_a` and the frame
/// with purely normal acceleration (parallel transport = tangential part of the
/// ambient derivative vanishes); the vertical generator rotates the frame in place.
pub fn check_bundle_at<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    x: &SVector<f64, N>,
    u: &SMatrix<f64, N, N>,
    v: &SVector<f64, N>,
    tol: f64,
) -> Result<(), String> {
    let check = |name: &str, err: f64, bound: f64| -> Result<(), String> {
        if err <= bound && err.is_finite() {
            Ok(())
        } else {
            Err(format!("{} at {x:?}: law `{name}` violated, error {err:e} > {bound:e}", B::NAME))
        }
    };
    let g = b.from_chart(x, u).map_err(|e| format!("from_chart failed: {e}"))?;
    check("bundle element valid", frame_defect(b, &g), tol)?;
    let p = b.embed(x);
    check("position = embed(x)", (b.position(&g) - p).amax() / (1.0 + p.amax()), tol)?;
    let mut q_expected = SMatrix::<f64, E, N>::zeros();
    let e = b.frame(x) * u;
    for a in 0..N {
        q_expected.set_column(a, &b.embed_tangent(x, &e.column(a).into()));
    }
    check("frame_vectors = embed(E·u)", (b.frame_vectors(&g) - q_expected).amax(), tol)?;
    let (xb, ub) = b.to_chart(&g).map_err(|e| format!("to_chart failed: {e}"))?;
    check("to_chart ∘ from_chart (point)", (b.embed(&xb) - p).amax() / (1.0 + p.amax()), tol)?;
    check("to_chart ∘ from_chart (frame)", (ub - u).amax(), tol)?;
    let gf = b.from_frame(&p, &q_expected).map_err(|e| format!("from_frame failed: {e}"))?;
    check("from_frame = from_chart", (b.frame_vectors(&gf) - q_expected).amax(), tol)?;

    // Horizontal lift: first and second derivatives along g·exp(εξ). The step
    // shrinks with |ξ|; errors are relative to the size of the frame vectors
    // (which grow like cosh(r/R) on H²) times the speed.
    let xi = b.horizontal_lift(&g, v);
    let eps = 1e-4 / (1.0 + xi.amax());
    let qsize = b.frame_vectors(&g).amax().max(1.0);
    let at = |s: f64| <B::Group as LieGroup>::exp(&(xi * s));
    let (gp, gm) = (g.compose(&at(eps)), g.compose(&at(-eps)));
    let vel = (b.position(&gp) - b.position(&gm)) / (2.0 * eps);
    let vel_expected = b.frame_vectors(&g) * v;
    check("horizontal lift: ẋ = Σ v_a q_a", (vel - vel_expected).amax() / (qsize * (1.0 + v.amax())), 1e-7)?;
    let qdot = (b.frame_vectors(&gp) - b.frame_vectors(&gm)) / (2.0 * eps);
    let (vel_exact, qdot_exact) = b.frame_velocity(&g, &xi);
    check("frame_velocity (point) = FD", (vel_exact - vel).amax() / (qsize * (1.0 + v.amax())), 1e-7)?;
    check("frame_velocity (frame) = FD", (qdot_exact - qdot).amax() / (qsize * qsize * (1.0 + v.amax())), 1e-7)?;
    let k_chart = b.sectional_curvature(x, &e.column(0).into(), &e.column(1).into());
    check("curvature_at = sectional curvature", (b.curvature_at(&g) - k_chart).abs() / (1.0 + k_chart.abs()), 1e-12)?;
    for a in 0..N {
        let d: SVector<f64, E> = qdot.column(a).into();
        check(
            "horizontal lift: q̇_a normal (parallel)",
            b.project_tangent(&p, &d).amax() / (qsize * qsize * (1.0 + v.amax())),
            1e-7,
        )?;
    }
    // Derivatives along a generic direction η of the group (every
    // coordinate non-zero): the lift's, the curvature's and the frame
    // velocity's, against central differences along g·exp(±sη).
    let coords: Vec<f64> = (0..<B::Group as LieGroup>::DOF).map(|i| 0.3 + 0.17 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 }).collect();
    let eta = <B::Group as LieGroup>::algebra_from_coords(&coords);
    let s = 1e-4 / (1.0 + eta.amax());
    let (gp, gm) = (g.compose(&<B::Group as LieGroup>::exp(&(eta * s))), g.compose(&<B::Group as LieGroup>::exp(&(eta * -s))));
    let lift_fd = (b.horizontal_lift(&gp, v) - b.horizontal_lift(&gm, v)) * (1.0 / (2.0 * s));
    let lift_exact = b.lift_derivative(&g, v, &eta);
    check("lift_derivative = FD", (lift_exact - lift_fd).amax() / (1.0 + v.amax() * (1.0 + b.horizontal_lift(&g, v).amax())), 1e-7)?;
    let k_fd = (b.curvature_at(&gp) - b.curvature_at(&gm)) / (2.0 * s);
    check("curvature_derivative = FD", (b.curvature_derivative(&g, &eta) - k_fd).abs() / (1.0 + b.curvature_at(&g).abs()), 1e-7)?;
    let ((xp, qp), (xm, qm)) = (b.frame_velocity(&gp, &xi), b.frame_velocity(&gm, &xi));
    let (dx_exact, dq_exact) = b.frame_velocity_derivative(&g, &xi, &eta);
    let scale = qsize * qsize * (1.0 + v.amax()) * (1.0 + eta.amax());
    check("frame_velocity_derivative (point) = FD", (dx_exact - (xp - xm) / (2.0 * s)).amax() / scale, 1e-7)?;
    check("frame_velocity_derivative (frame) = FD", (dq_exact - (qp - qm) / (2.0 * s)).amax() / scale, 1e-7)?;

    // Vertical: point fixed, q̇ = q w.
    let mut w = SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        for j in (i + 1)..N {
            let val = 0.4 + 0.3 * (i + 2 * j) as f64;
            w[(i, j)] = -val;
            w[(j, i)] = val;
        }
    }
    let zeta = b.vertical(&g, &w);
    let eps = 1e-4 / (1.0 + zeta.amax());
    let at = |s: f64| <B::Group as LieGroup>::exp(&(zeta * s));
    let (gp, gm) = (g.compose(&at(eps)), g.compose(&at(-eps)));
    check("vertical: point fixed", (b.position(&gp) - b.position(&gm)).amax() / (2.0 * eps * qsize), 1e-7)?;
    let qdot = (b.frame_vectors(&gp) - b.frame_vectors(&gm)) / (2.0 * eps);
    check("vertical: q̇ = q w", (qdot - b.frame_vectors(&g) * w).amax() / qsize, 1e-7)?;
    Ok(())
}

/// `steps` random horizontal and vertical steps `g ← g·exp(h ξ)` (renormalised
/// after each, as integrators do); returns the largest [`frame_defect`] met.
pub fn random_walk_defect<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    g0: &B::Group,
    steps: usize,
    h: f64,
    seed: u64,
) -> f64 {
    let mut rng = seed | 1;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut g = *g0;
    let mut worst: f64 = 0.0;
    for i in 0..steps {
        let v: SVector<f64, N> = SVector::from_fn(|_, _| next());
        let mut xi = b.horizontal_lift(&g, &v);
        if i % 3 == 0 {
            let mut w = SMatrix::<f64, N, N>::zeros();
            for r in 0..N {
                for c in (r + 1)..N {
                    let val = next();
                    w[(r, c)] = -val;
                    w[(c, r)] = val;
                }
            }
            xi = xi + b.vertical(&g, &w);
        }
        g = g.compose(&<B::Group as LieGroup>::exp(&(xi * h))).renormalize();
        if i % 101 == 0 {
            worst = worst.max(frame_defect(b, &g));
        }
    }
    worst.max(frame_defect(b, &g))
}

/// Holonomy of the small chart loop `x(t) = x₀ + ε(cos 2πt·E₁ + sin 2πt·E₂)`
/// (E the paper's frame at `x₀`): the rotation angle of the transported frame
/// in its (1, 2) plane, and `K(x₀)·πε²` which it must approach as `O(ε²)`
/// relative (Gauss–Bonnet: holonomy = ∫K dA, the first-order corrections
/// integrate to zero over the symmetric disc).
pub fn small_loop_holonomy<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    b: &B,
    x0: &SVector<f64, N>,
    eps: f64,
    steps: usize,
) -> (f64, f64) {
    let fr = b.frame(x0);
    let (e1, e2): (SVector<f64, N>, SVector<f64, N>) = (fr.column(0).into(), fr.column(1).into());
    let tau = std::f64::consts::TAU;
    let curve = |t: f64| {
        let (s, c) = (tau * t).sin_cos();
        (x0 + (e1 * c + e2 * s) * eps, (e2 * c - e1 * s) * (eps * tau))
    };
    let (xs, _) = curve(0.0);
    let g0 = b.from_chart(&xs, &SMatrix::identity()).expect("loop start in chart");
    let g1 = transport_along(b, &g0, &curve, steps);
    let q0 = b.frame_vectors(&g0);
    let q1 = b.frame_vectors(&g1);
    let wmat = q0.transpose() * b.ambient_metric() * q1;
    let angle = wmat[(1, 0)].atan2(wmat[(0, 0)]);
    let k = b.sectional_curvature(x0, &e1, &e2);
    (angle, k * std::f64::consts::PI * eps * eps)
}
