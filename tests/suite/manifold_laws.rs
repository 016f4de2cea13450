//! The manifold law suite: [`check_manifold_at`] is called by every manifold's
//! tests (proptest over random chart points) with the closed-form curvature.
//! The laws of the optional geodesic distance are in `distance_laws`.

use framedyn::manifold::{Manifold, Tensor3};
use nalgebra::{SMatrix, SVector};

/// Derivative at 0 of a vector-valued function by Ridders' extrapolation of
/// central differences (Numerical Recipes `dfridr`), componentwise: the step
/// starts at 0.05 and shrinks by 1.4 per level, and each component keeps the
/// estimate with the smallest extrapolation-error estimate. Accurate to ~1e-10
/// even close to a coordinate pole where derivatives grow like 1/r^k.
fn ridders(f: impl Fn(f64) -> Vec<f64>) -> Vec<f64> {
    const LEVELS: usize = 16;
    const CON: f64 = 1.4;
    let central = |h: f64| -> Vec<f64> {
        let (p, m) = (f(h), f(-h));
        p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect()
    };
    let mut h = 0.05;
    let first = central(h);
    let len = first.len();
    let mut best = first.clone();
    let mut err = vec![f64::INFINITY; len];
    let mut prev: Vec<Vec<f64>> = vec![first];
    for _ in 1..LEVELS {
        h /= CON;
        let mut row = vec![central(h)];
        let mut fac = CON * CON;
        for j in 1..=prev.len() {
            let next: Vec<f64> = (0..len).map(|c| (row[j - 1][c] * fac - prev[j - 1][c]) / (fac - 1.0)).collect();
            fac *= CON * CON;
            for c in 0..len {
                let e = (next[c] - row[j - 1][c]).abs().max((next[c] - prev[j - 1][c]).abs());
                if e <= err[c] {
                    err[c] = e;
                    best[c] = next[c];
                }
            }
            row.push(next);
        }
        prev = row;
    }
    best
}

fn d_mat<const R: usize, const C: usize>(f: impl Fn(f64) -> SMatrix<f64, R, C>) -> SMatrix<f64, R, C> {
    SMatrix::from_column_slice(&ridders(|h| f(h).as_slice().to_vec()))
}

fn d_t3<const N: usize>(f: impl Fn(f64) -> Tensor3<N>) -> Tensor3<N> {
    let flat = ridders(|h| f(h).iter().flatten().flatten().copied().collect());
    let mut out = [[[0.0; N]; N]; N];
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                out[i][j][k] = flat[(i * N + j) * N + k];
            }
        }
    }
    out
}

fn unit<const N: usize>(i: usize) -> SVector<f64, N> {
    let mut e = SVector::zeros();
    e[i] = 1.0;
    e
}

/// Christoffel symbols from Ridders-extrapolated differences of the metric:
/// `Γ^i_{jk} = ½ g^{il}(∂_j g_{lk} + ∂_k g_{lj} − ∂_l g_{jk})`.
pub fn christoffel_fd<M: Manifold<N, E>, const N: usize, const E: usize>(m: &M, x: &SVector<f64, N>) -> Tensor3<N> {
    let dg: Vec<SMatrix<f64, N, N>> = (0..N).map(|l| d_mat(|h| m.metric(&(x + unit::<N>(l) * h)))).collect();
    let ginv = m.metric(x).try_inverse().expect("metric invertible");
    let mut out = [[[0.0; N]; N]; N];
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                out[i][j][k] = (0..N)
                    .map(|l| 0.5 * ginv[(i, l)] * (dg[j][(l, k)] + dg[k][(l, j)] - dg[l][(j, k)]))
                    .sum();
            }
        }
    }
    out
}

/// `check(name, err, bound)`: `Ok` if `err` is finite and `≤ bound`, else a
/// message naming the manifold, the point and the law.
fn law_check<M: Manifold<N, E>, const N: usize, const E: usize>(
    x: &SVector<f64, N>,
) -> impl Fn(&str, f64, f64) -> Result<(), String> + '_ {
    move |name: &str, err: f64, bound: f64| {
        if err <= bound && err.is_finite() {
            Ok(())
        } else {
            Err(format!("{} at {x:?}: law `{name}` violated, error {err:e} > {bound:e}", M::NAME))
        }
    }
}

/// Checks, at the chart point `x`: closed-form Christoffel symbols = finite
/// differences of the metric; Riemann tensor = its definition from finite
/// differences of the Christoffel symbols; sectional curvature of the frame
/// planes = `k_expected(A, B)`; frame `E` orthonormal; `Γ^A_{BC}` skew in
/// `A, B` and equal to its definition `E⁻¹(∂_{E_C} E_B + Γ(E_C) E_B)`; the
/// embedding pulls the ambient metric back to `g`, `embed_tangent` is its
/// derivative, `chart`/`chart_tangent` invert `embed`/`embed_tangent`, and
/// `project_point`/`project_tangent` land on the manifold / its tangent space.
/// (The geodesic distance, optional, has its own suite: `distance_laws`.)
pub fn check_manifold_at<M: Manifold<N, E>, const N: usize, const E: usize>(
    m: &M,
    x: &SVector<f64, N>,
    k_expected: impl Fn(usize, usize) -> f64,
    tol: f64,
) -> Result<(), String> {
    let check = law_check::<M, N, E>(x);
    m.check_chart(x).map_err(|e| format!("{} at {x:?}: check_chart failed: {e}", M::NAME))?;
    let g = m.metric(x);
    check("metric symmetric", (g - g.transpose()).amax(), 0.0)?;

    // Christoffel symbols.
    let gam = m.christoffel(x);
    let gam_fd = christoffel_fd(m, x);
    let mut err: f64 = 0.0;
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                err = err.max((gam[i][j][k] - gam_fd[i][j][k]).abs() / (1.0 + gam[i][j][k].abs()));
                err = err.max((gam[i][j][k] - gam[i][k][j]).abs());
            }
        }
    }
    check("Christoffel = FD of metric", err, 1e-7)?;

    // Riemann tensor from its definition.
    let r = m.riemann(x);
    let dgam: Vec<Tensor3<N>> = (0..N).map(|l| d_t3(|h| m.christoffel(&(x + unit::<N>(l) * h)))).collect();
    let mut err: f64 = 0.0;
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                for l in 0..N {
                    let mut def = dgam[k][i][j][l] - dgam[l][i][j][k];
                    for mm in 0..N {
                        def += gam[i][mm][k] * gam[mm][j][l] - gam[i][mm][l] * gam[mm][j][k];
                    }
                    err = err.max((r[i][j][k][l] - def).abs() / (1.0 + def.abs()));
                }
            }
        }
    }
    check("Riemann = definition", err, 1e-6)?;

    // Frame: orthonormal; sectional curvatures of frame planes.
    let fr = m.frame(x);
    check("E orthonormal", (fr.transpose() * g * fr - SMatrix::<f64, N, N>::identity()).amax(), tol)?;
    for a in 0..N {
        for b in (a + 1)..N {
            let k = m.sectional_curvature(x, &fr.column(a).into(), &fr.column(b).into());
            let ke = k_expected(a, b);
            check("sectional curvature = closed form", (k - ke).abs() / (1.0 + ke.abs()), tol.max(1e-12))?;
        }
    }

    // Frame connection coefficients.
    let fc = m.frame_connection(x);
    let finv = fr.try_inverse().expect("frame invertible");
    let dfr: Vec<SMatrix<f64, N, N>> = (0..N).map(|k| d_mat(|h| m.frame(&(x + unit::<N>(k) * h)))).collect();
    let mut err_def: f64 = 0.0;
    let mut err_skew: f64 = 0.0;
    for b in 0..N {
        for c in 0..N {
            // ∇_{E_C} E_B in chart components.
            let mut nab = SVector::<f64, N>::zeros();
            for i in 0..N {
                for k in 0..N {
                    let mut v = dfr[k][(i, b)];
                    for j in 0..N {
                        v += gam[i][j][k] * fr[(j, b)];
                    }
                    nab[i] += fr[(k, c)] * v;
                }
            }
            let comps = finv * nab;
            for a in 0..N {
                err_def = err_def.max((fc[a][b][c] - comps[a]).abs() / (1.0 + comps[a].abs()));
                err_skew = err_skew.max((fc[a][b][c] + fc[b][a][c]).abs());
            }
        }
    }
    check("Γ^A_BC = definition", err_def, 1e-7)?;
    check("Γ^A_BC skew in A,B", err_skew, tol)?;

    // Embedding.
    let p = m.embed(x);
    check("embedded point on manifold", m.point_defect(&p), tol)?;
    let amb = m.ambient_metric();
    let mut jac = SMatrix::<f64, E, N>::zeros();
    for i in 0..N {
        let d = d_mat(|h| m.embed(&(x + unit::<N>(i) * h)));
        jac.set_column(i, &d);
        check("embed_tangent = FD of embed", (m.embed_tangent(x, &unit::<N>(i)) - d).amax() / (1.0 + d.amax()), 1e-8)?;
    }
    check("pull-back of ambient metric = g", (jac.transpose() * amb * jac - g).amax() / (1.0 + g.amax()), 1e-8)?;
    let back = m.chart(&p).map_err(|e| format!("{}: chart(embed(x)) failed: {e}", M::NAME))?;
    check("embed(chart(embed x)) = embed x", (m.embed(&back) - p).amax() / (1.0 + p.amax()), tol)?;
    let v: SVector<f64, N> = SVector::from_fn(|i, _| 0.3 + 0.7 * i as f64);
    let w = m.embed_tangent(x, &v);
    let vb = m.chart_tangent(&p, &w).map_err(|e| format!("{}: chart_tangent failed: {e}", M::NAME))?;
    check("chart_tangent inverts embed_tangent", (vb - v).amax() / (1.0 + v.amax()), tol)?;
    check("tangent vectors are tangent", (m.project_tangent(&p, &w) - w).amax() / (1.0 + w.amax()), tol)?;
    let off = p * 1.001;
    check("project_point lands on manifold", m.point_defect(&m.project_point(&off)), tol)?;
    Ok(())
}
