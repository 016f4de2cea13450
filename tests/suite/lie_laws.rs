//! The Lie-group law suite, written once and instantiated for every group with
//! [`lie_law_suite!`](crate::lie_law_suite).

use framedyn::lie::{dexp_inv_series, AlgebraVector, LieGroup};
use nalgebra::DMatrix;

/// Matrix exponential by scaling and squaring of a Taylor series: an
/// implementation independent of the library's, used as the reference.
pub fn expm_reference(a: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    let norm = a.iter().map(|x| x.abs()).fold(0.0, f64::max) * n as f64;
    let mut s = 0;
    while norm / 2f64.powi(s) > 0.25 {
        s += 1;
    }
    let b = a / 2f64.powi(s);
    let mut term = DMatrix::identity(n, n);
    let mut sum = DMatrix::identity(n, n);
    for k in 1..30 {
        term = &term * &b / k as f64;
        sum += &term;
    }
    for _ in 0..s {
        sum = &sum * &sum;
    }
    sum
}

/// Max-abs difference of two matrices, relative to `1 + max|b|`.
pub fn mat_rel_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let scale = 1.0 + b.iter().map(|x| x.abs()).fold(0.0, f64::max);
    (a - b).iter().map(|x| x.abs()).fold(0.0, f64::max) / scale
}

/// Algebra-element difference relative to `1 + |b|`.
pub fn alg_rel_diff<A: AlgebraVector>(a: &A, b: &A) -> f64 {
    (*a - *b).norm() / (1.0 + b.norm())
}

/// Checks all laws at one triple of algebra elements; returns the first
/// violated law with its error, or `Ok(())`. `tol` bounds the errors of exact
/// identities; finite-difference checks use `fd_tol`.
pub fn check_laws<G: LieGroup>(
    a: &G::Algebra,
    b: &G::Algebra,
    c: &G::Algebra,
    tol: f64,
    fd_tol: f64,
) -> Result<(), String> {
    let check = |name: &str, err: f64, bound: f64| -> Result<(), String> {
        if err <= bound && err.is_finite() {
            Ok(())
        } else {
            Err(format!("{}: law `{name}` violated, error {err:e} > {bound:e}", G::NAME))
        }
    };
    let ga = G::exp(a);
    let gb = G::exp(b);
    let (ma, mb) = (ga.to_matrix(), gb.to_matrix());

    // exp agrees with the matrix exponential of the algebra matrix.
    check("exp = expm(hat)", mat_rel_diff(&ma, &expm_reference(&G::algebra_to_matrix(a))), tol)?;
    // compose / inverse / identity agree with matrices.
    check("compose = matrix product", mat_rel_diff(&ga.compose(&gb).to_matrix(), &(&ma * &mb)), tol)?;
    let n = ma.nrows();
    // `g⁻¹·g − I` relative to the entries of `|g⁻¹|·|g|`: the rounding
    // error of a backward-stable inverse and of the product grows with the
    // size of the terms they sum. For orthogonal matrices these are ≤ 1
    // (Cauchy–Schwarz), so the bound stays `2·tol` there; on SL(3) at
    // radius 4.4 they reach ~3e3, and a fixed bound (the earlier
    // `|g⁻¹g − I|/2 ≤ tol`) failed on a random case with residual 4e-12.
    let inv = ga.inverse().to_matrix();
    let terms = (inv.abs() * ma.abs()).amax();
    let residual = (&inv * &ma - DMatrix::identity(n, n)).amax();
    check("inverse", residual / (1.0 + terms), tol)?;
    check("identity", mat_rel_diff(&G::identity().to_matrix(), &DMatrix::identity(n, n)), 0.0)?;
    // exp ∘ log round trips.
    let la = ga.log().map_err(|e| format!("{}: log failed at exp(a): {e}", G::NAME))?;
    check("log(exp(a)) = a", alg_rel_diff(&la, a), tol)?;
    check("exp(log(g)) = g", mat_rel_diff(&G::exp(&la).to_matrix(), &ma), tol)?;
    // Coordinates round trip.
    let coords = G::algebra_coords(a);
    check("coords round trip", alg_rel_diff(&G::algebra_from_coords(&coords), a), 0.0)?;
    // Bracket = matrix commutator; Jacobi identity.
    let (ha, hb) = (G::algebra_to_matrix(a), G::algebra_to_matrix(b));
    check(
        "bracket = commutator",
        mat_rel_diff(&G::algebra_to_matrix(&G::bracket(a, b)), &(&ha * &hb - &hb * &ha)),
        tol,
    )?;
    let jac = G::bracket(a, &G::bracket(b, c)) + G::bracket(b, &G::bracket(c, a)) + G::bracket(c, &G::bracket(a, b));
    let scale = (1.0 + a.norm()) * (1.0 + b.norm()) * (1.0 + c.norm());
    check("Jacobi identity", jac.norm() / scale, tol)?;
    // Ad: matrix conjugation, and Ad_{exp a} = exp(ad_a).
    let adj = ga.adjoint(b);
    check(
        "Ad = conjugation",
        mat_rel_diff(&G::algebra_to_matrix(&adj), &(&ma * &hb * ga.inverse().to_matrix())),
        tol,
    )?;
    let mut term = *b;
    let mut series = *b;
    for k in 1..60 {
        term = G::bracket(a, &term) * (1.0 / k as f64);
        series = series + term;
    }
    check("Ad_exp(a) = exp(ad_a)", alg_rel_diff(&adj, &series), tol * 10.0)?;
    // dexp_inv ∘ dexp = id, and dexp ∘ dexp_inv = id.
    check("dexp_inv(dexp v) = v", alg_rel_diff(&G::dexp_inv(a, &G::dexp(a, b)), b), tol)?;
    check("dexp(dexp_inv v) = v", alg_rel_diff(&G::dexp(a, &G::dexp_inv(a, b)), b), tol)?;
    // Closed forms agree with the Bernoulli series where it converges fast.
    if a.norm() < 1.0 {
        check(
            "dexp_inv = Bernoulli series",
            alg_rel_diff(&G::dexp_inv(a, b), &dexp_inv_series::<G>(a, b, 20)),
            tol,
        )?;
    }
    // dexp against central finite differences of exp:
    // d/dε exp(a + εv)|₀ · exp(a)⁻¹ = hat(dexp_a v).
    let eps = 1e-5;
    let plus = G::exp(&(*a + *b * eps)).to_matrix();
    let minus = G::exp(&(*a - *b * eps)).to_matrix();
    let fd = (plus - minus) / (2.0 * eps) * ga.inverse().to_matrix();
    check("dexp = finite differences of exp", mat_rel_diff(&fd, &G::algebra_to_matrix(&G::dexp(a, b))), fd_tol)?;
    Ok(())
}

/// Composes `count` random elements `exp(±a_i)` (generator and sign drawn at
/// random from `gens`), renormalising after each product as integrators do;
/// returns the largest constraint defect met. Random order and signs make the
/// product a genuine random walk (drift O(pr²) per step in non-compact groups)
/// rather than one fixed block repeated.
pub fn product_drift<G: LieGroup>(gens: &[G::Algebra], count: usize) -> f64 {
    let elems: Vec<G> = gens.iter().flat_map(|a| [G::exp(a), G::exp(&(-*a))]).collect();
    let mut rng = 0x2545F4914F6CDD1Du64;
    let mut g = G::identity();
    let mut worst: f64 = 0.0;
    for i in 0..count {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        g = g.compose(&elems[(rng % elems.len() as u64) as usize]).renormalize();
        if i % 97 == 0 {
            worst = worst.max(g.constraint_defect());
        }
    }
    worst.max(g.constraint_defect())
}

/// Instantiates the law suite for a group. From a submodule of the suite call
/// it as `crate::lie_law_suite!(...)`.
///
/// `lie_law_suite!(name, Group, radius = r, tol = t, fd_tol = f, product_radius = pr)`
/// draws algebra coordinates uniformly in `[-r, r]` (rescaled so the norm stays
/// below `r`), checks every law of [`check_laws`] with proptest, and checks
/// that 10⁶ renormalised random products of `exp(a)`, `|a| ≤ pr`, stay in the
/// group to `1e-13` (for non-compact groups `pr` must be small enough that the
/// random walk does not overflow: its growth rate is O(pr²) per step).
#[macro_export]
macro_rules! lie_law_suite {
    ($name:ident, $G:ty, radius = $r:expr, tol = $tol:expr, fd_tol = $fd:expr, product_radius = $pr:expr) => {
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            use framedyn::lie::LieGroup;
            #[allow(unused_imports)]
            use proptest::prelude::*;
            use $crate::lie_laws::{check_laws, product_drift};

            type G = $G;

            fn alg(c: Vec<f64>) -> <G as LieGroup>::Algebra {
                let norm = c.iter().map(|x| x * x).sum::<f64>().sqrt();
                let scale = if norm > $r { $r / norm } else { 1.0 };
                let c: Vec<f64> = c.iter().map(|x| x * scale).collect();
                G::algebra_from_coords(&c)
            }

            proptest! {
                #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
                #[test]
                fn laws(
                    a in proptest::collection::vec(-$r..$r, <G as LieGroup>::DOF),
                    b in proptest::collection::vec(-$r..$r, <G as LieGroup>::DOF),
                    c in proptest::collection::vec(-$r..$r, <G as LieGroup>::DOF),
                ) {
                    let r = check_laws::<G>(&alg(a), &alg(b), &alg(c), $tol, $fd);
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }

                #[test]
                fn laws_near_identity(
                    a in proptest::collection::vec(-1e-7..1e-7f64, <G as LieGroup>::DOF),
                    b in proptest::collection::vec(-$r..$r, <G as LieGroup>::DOF),
                    c in proptest::collection::vec(-1e-3..1e-3f64, <G as LieGroup>::DOF),
                ) {
                    let r = check_laws::<G>(&alg(a), &alg(b), &alg(c), $tol, $fd);
                    prop_assert!(r.is_ok(), "{}", r.unwrap_err());
                }
            }

            #[test]
            fn million_products_stay_in_group() {
                let mut rng = 0x9E3779B97F4A7C15u64;
                let mut next = || {
                    rng ^= rng << 13;
                    rng ^= rng >> 7;
                    rng ^= rng << 17;
                    (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
                };
                let gens: Vec<_> = (0..64)
                    .map(|_| {
                        let c: Vec<f64> = (0..<G as LieGroup>::DOF).map(|_| next()).collect();
                        let n = c.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-300);
                        G::algebra_from_coords(&c.iter().map(|x| x * $pr / n).collect::<Vec<_>>())
                    })
                    .collect();
                let drift = product_drift::<G>(&gens, 1_000_000);
                assert!(drift <= 1e-13, "{}: defect {drift:e} after 1e6 products", <G as LieGroup>::NAME);
            }
        }
    };
}
