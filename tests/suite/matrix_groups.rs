//! Tests of the general-`n` matrix groups GL⁺(n), SL(n), SO(n), CO⁺(n) and
//! of direct products: the generic law suite, accuracy of `exp` against
//! closed forms evaluated in 256-bit arithmetic, `log` near the boundary of
//! its domain and its typed errors, constructors, and the truncation order of
//! the `dexp⁻¹` series.

use crate::lie_law_suite;
use crate::lie_laws::expm_reference;
use framedyn::lie::*;
use nalgebra::DMatrix;

// ---------------------------------------------------------------------------
// Law suites.
//
// Radii. `radius` bounds the Euclidean norm of the coordinates. The laws
// include log(exp(a)) = a, which needs every eigenvalue of `a` to have
// |Im λ| < π:
// - GL⁺(n), SL(n): coordinates are matrix entries, so ‖a‖_F ≤ r and a complex
//   pair x ± iy has 2y² ≤ ‖a‖_F², y ≤ r/√2; r = 4.4 = 0.99·π√2 keeps y ≤ 3.11.
//   (The same bound keeps the spectral radius of ad_a, |λ_i − λ_j| ≤ √2 r,
//   below 2π.) Errors there are dominated by conditioning: κ(exp a) ≤ e^{2r}
//   ≈ 7e3, so the wide suites use tol = 2e-12 ≈ 7e3·ε·1.3; the `*_unit`
//   suites (r = 1) check the same laws at tol = 1e-14, where the reference
//   `expm_reference` (Taylor + squaring) itself errs by up to 7e-15.
// - SO(n), CO⁺(n): the rotation angles are at most the coordinate norm, so
//   r = 3.1 keeps them below π − 0.04; the region up to π − 1e-6 is covered by
//   `log_near_boundary` below.
//
// Product radii. The 64 generators of `million_products_stay_in_group` have a
// nonzero mean (about pr/8 per step in norm), so on the non-compact groups
// the walk drifts at FIRST order in pr, not O(pr²). Measured log₁₀‖g‖ after
// the 1e6 products: GL⁺(3) 11.5 / 1.3 / 0.17 and SL(3) 10.9 / 4.2 / 0.38 at
// pr = 1e-3 / 1e-4 / 1e-5. The SL constraint |det g − 1| can only be computed
// to about κ(g)·ε, and SL(3) reaches κ ≈ 1e8 at pr = 1e-4 (defect 1.3e-9,
// all of it the error of the determinant itself); pr = 1e-5 keeps
// κ(g) < 10 on all of GL⁺(2), GL⁺(3), SL(2), SL(3). Compact groups (SO(n))
// and CO⁺(n) (which stores ln λ, so its dilatation cannot overflow) use pr = 1.
// ---------------------------------------------------------------------------

lie_law_suite!(
    gl2,
    Gl<2>,
    radius = 4.4,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);
lie_law_suite!(
    gl3,
    Gl<3>,
    radius = 4.4,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);
lie_law_suite!(
    sl2,
    Sl<2>,
    radius = 4.4,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);
lie_law_suite!(
    sl3,
    Sl<3>,
    radius = 4.4,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);
lie_law_suite!(
    gl3_unit,
    Gl<3>,
    radius = 1.0,
    tol = 1e-14,
    fd_tol = 1e-10,
    product_radius = 1e-5
);
lie_law_suite!(
    sl3_unit,
    Sl<3>,
    radius = 1.0,
    tol = 1e-14,
    fd_tol = 1e-10,
    product_radius = 1e-5
);
lie_law_suite!(
    so3n,
    SoN<3>,
    radius = 3.1,
    tol = 1e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    so4n,
    SoN<4>,
    radius = 3.1,
    tol = 1e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    so5n,
    SoN<5>,
    radius = 3.1,
    tol = 1e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    co2,
    Co<2>,
    radius = 3.1,
    tol = 4e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    co3,
    Co<3>,
    radius = 3.1,
    tol = 4e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    gl2_x_r3,
    Product<Gl<2>, Rn<3>>,
    radius = 4.4,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);
lie_law_suite!(
    so3n_x_co2,
    Product<SoN<3>, Co<2>>,
    radius = 3.1,
    tol = 4e-14,
    fd_tol = 1e-9,
    product_radius = 1.0
);
lie_law_suite!(
    nested_product,
    Product<Product<SoN<3>, Sl<2>>, Product<Rn<2>, Co<3>>>,
    radius = 3.1,
    tol = 2e-12,
    fd_tol = 1e-8,
    product_radius = 1e-5
);

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

const EPS: f64 = f64::EPSILON;

type M2 = nalgebra::SMatrix<f64, 2, 2>;
type M3 = nalgebra::SMatrix<f64, 3, 3>;

use crate::internals::xorshift as rng;

fn dm<const N: usize>(m: &nalgebra::SMatrix<f64, N, N>) -> DMatrix<f64> {
    DMatrix::from_column_slice(N, N, m.as_slice())
}

/// `max|x − r| / max|r|`.
fn rel_err(x: &DMatrix<f64>, r: &DMatrix<f64>) -> f64 {
    (x - r).amax() / r.amax()
}

/// 256-bit reference arithmetic on small dense matrices (astro-float).
mod hp {
    use astro_float::{BigFloat, Consts, Radix, RoundingMode};
    use nalgebra::DMatrix;

    pub const P: usize = 256;
    pub const RM: RoundingMode = RoundingMode::ToEven;
    pub type M = Vec<Vec<BigFloat>>;

    pub struct Hp {
        pub cc: Consts,
    }

    impl Hp {
        pub fn new() -> Self {
            Hp {
                cc: Consts::new().expect("astro-float constants"),
            }
        }
        pub fn f(&self, x: f64) -> BigFloat {
            BigFloat::from_f64(x, P)
        }
        /// Correctly rounded to f64 (through a full-precision decimal string).
        pub fn round(&mut self, x: &BigFloat) -> f64 {
            x.format(Radix::Dec, RM, &mut self.cc)
                .expect("format")
                .parse()
                .expect("parse")
        }
        pub fn mat(&self, a: &DMatrix<f64>) -> M {
            (0..a.nrows())
                .map(|i| (0..a.ncols()).map(|j| self.f(a[(i, j)])).collect())
                .collect()
        }
        pub fn round_matrix(&mut self, m: &M) -> DMatrix<f64> {
            let (r, c) = (m.len(), m[0].len());
            DMatrix::from_fn(r, c, |i, j| self.round(&m[i][j]))
        }
        pub fn zeros(&self, n: usize) -> M {
            vec![vec![self.f(0.0); n]; n]
        }
        pub fn identity(&self, n: usize) -> M {
            let mut m = self.zeros(n);
            for (i, row) in m.iter_mut().enumerate() {
                row[i] = self.f(1.0);
            }
            m
        }
        pub fn mul(&self, a: &M, b: &M) -> M {
            let n = a.len();
            let k = b.len();
            let c = b[0].len();
            (0..n)
                .map(|i| {
                    (0..c)
                        .map(|j| (0..k).fold(self.f(0.0), |s, l| s.add(&a[i][l].mul(&b[l][j], P, RM), P, RM)))
                        .collect()
                })
                .collect()
        }
        pub fn add(&self, a: &M, b: &M) -> M {
            a.iter()
                .zip(b)
                .map(|(ra, rb)| ra.iter().zip(rb).map(|(x, y)| x.add(y, P, RM)).collect())
                .collect()
        }
        pub fn scale(&self, a: &M, s: &BigFloat) -> M {
            a.iter().map(|r| r.iter().map(|x| x.mul(s, P, RM)).collect()).collect()
        }
        /// exp by Taylor series (to 2⁻²⁴⁰ relative) of `A/2^s`, `‖A/2^s‖ ≤ 1/16`,
        /// and `s` squarings, all in 256-bit arithmetic.
        pub fn expm(&mut self, a: &M) -> M {
            let n = a.len();
            let norm: f64 = a.iter().flatten().map(|x| self.round(x).abs()).sum::<f64>();
            let mut s = 0;
            while norm / 2f64.powi(s) > 1.0 / 16.0 {
                s += 1;
            }
            let b = self.scale(a, &self.f(0.5f64.powi(s)));
            let mut term = self.identity(n);
            let mut sum = self.identity(n);
            for k in 1..80 {
                term = self.scale(&self.mul(&term, &b), &self.f(1.0).div(&self.f(k as f64), P, RM));
                sum = self.add(&sum, &term);
            }
            for _ in 0..s {
                sum = self.mul(&sum, &sum);
            }
            sum
        }
    }
}

// ---------------------------------------------------------------------------
// exp against closed forms evaluated in 256-bit arithmetic
// ---------------------------------------------------------------------------

/// Worst relative error (max-norm) of `exp` over the cases, in units of
/// `ε·max(1, ‖A‖_F)` (the relative condition number of `exp` is about ‖A‖ for
/// normal `A`), separately for ‖A‖_F ≤ 1 and ‖A‖_F > 1; cases are
/// `(A, exact exp(A))`.
fn worst_exp_error<G: LieGroup>(cases: &[(G::Algebra, DMatrix<f64>)]) -> [f64; 2] {
    let mut worst = [0.0f64; 2];
    for (a, reference) in cases {
        let n = G::algebra_to_matrix(a).norm();
        let e = rel_err(&G::exp(a).to_matrix(), reference) / EPS / n.max(1.0);
        let band = usize::from(n > 1.0);
        worst[band] = worst[band].max(e);
    }
    worst
}

/// `P = U L` with unit triangular integer factors: `det P = 1`, integer inverse.
const P3: [[f64; 3]; 3] = [[2.0, 1.0, 0.0], [1.0, 2.0, 1.0], [0.0, 1.0, 1.0]];
const P3_INV: [[f64; 3]; 3] = [[1.0, -1.0, 1.0], [-1.0, 2.0, -2.0], [1.0, -2.0, 3.0]];

fn m3(rows: [[f64; 3]; 3]) -> M3 {
    M3::from_fn(|i, j| rows[i][j])
}

#[test]
fn exp_accuracy_closed_forms() {
    let mut hp = hp::Hp::new();
    let (p, pinv) = (m3(P3), m3(P3_INV));
    assert_eq!(p * pinv, M3::identity());
    let hpp = hp.mat(&dm(&p));
    let hppinv = hp.mat(&dm(&pinv));
    let mut diag_cases = Vec::new();
    let mut nil_cases = Vec::new();
    // t = 2^e: A = P D P⁻¹ has entries (small integer)·t, exactly representable.
    for e in -42..=2 {
        let t = 2f64.powi(e);
        // Real spectrum (t, −2t, 3t) and a complex pair t ± 3it with −2t.
        let d_real = M3::from_diagonal(&nalgebra::Vector3::new(t, -2.0 * t, 3.0 * t));
        let d_cplx = m3([[t, -3.0 * t, 0.0], [3.0 * t, t, 0.0], [0.0, 0.0, -2.0 * t]]);
        for (k, d) in [d_real, d_cplx].iter().enumerate() {
            let a = p * d * pinv;
            let mut ed = hp.zeros(3);
            if k == 0 {
                for i in 0..3 {
                    ed[i][i] = hp.f(d[(i, i)]).exp(hp::P, hp::RM, &mut hp.cc);
                }
            } else {
                let ea = hp.f(t).exp(hp::P, hp::RM, &mut hp.cc);
                let b = hp.f(3.0 * t);
                let (c, s) = (b.cos(hp::P, hp::RM, &mut hp.cc), b.sin(hp::P, hp::RM, &mut hp.cc));
                ed[0][0] = ea.mul(&c, hp::P, hp::RM);
                ed[1][1] = ed[0][0].clone();
                ed[1][0] = ea.mul(&s, hp::P, hp::RM);
                ed[0][1] = ed[1][0].neg();
                ed[2][2] = hp.f(-2.0 * t).exp(hp::P, hp::RM, &mut hp.cc);
            }
            let reference = hp.round_matrix(&hp.mul(&hp.mul(&hpp, &ed), &hppinv));
            diag_cases.push((a, reference));
        }
        // Nilpotent: exp(A) = I + A + A²/2 exactly.
        let n = m3([[0.0, 1.0, -2.0], [0.0, 0.0, 3.0], [0.0, 0.0, 0.0]]) * t;
        let hn = hp.mat(&dm(&n));
        let half = hp.f(0.5);
        let reference = hp.add(&hp.add(&hp.identity(3), &hn), &hp.scale(&hp.mul(&hn, &hn), &half));
        nil_cases.push((n, hp.round_matrix(&reference)));
    }
    let diag = worst_exp_error::<Gl<3>>(&diag_cases);
    let nil = worst_exp_error::<Gl<3>>(&nil_cases);
    println!("GL+(3) P D P⁻¹: {diag:.2?}, nilpotent: {nil:.2?} (ε·max(1, ‖A‖), ‖A‖ ≤ 1 / > 1)");
    assert!(diag[0] <= 2.0 && diag[1] <= 4.0, "{diag:?}");
    assert!(nil[0] <= 1.0 && nil[1] <= 1.0, "{nil:?}");
    // 2×2 rotation and boost generators, θ log-spaced over [1e-12, 50].
    let mut rot = Vec::new();
    let mut boost = Vec::new();
    for k in 0..=140 {
        let th = 1e-12 * 10f64.powf(k as f64 * (50f64.log10() + 12.0) / 140.0);
        let b = hp.f(th);
        let vals = [
            b.cos(hp::P, hp::RM, &mut hp.cc),
            b.sin(hp::P, hp::RM, &mut hp.cc),
            b.cosh(hp::P, hp::RM, &mut hp.cc),
            b.sinh(hp::P, hp::RM, &mut hp.cc),
        ];
        let [c, s, ch, sh] = vals.map(|v| hp.round(&v));
        rot.push((M2::new(0.0, -th, th, 0.0), dm(&M2::new(c, -s, s, c))));
        boost.push((M2::new(0.0, th, th, 0.0), dm(&M2::new(ch, sh, sh, ch))));
    }
    for (name, w) in [
        ("GL+(2) rotation", worst_exp_error::<Gl<2>>(&rot)),
        ("SO(2) rotation", worst_exp_error::<SoN<2>>(&rot)),
        ("CO+(2) rotation", worst_exp_error::<Co<2>>(&rot)),
    ] {
        println!("{name}: {w:.2?}");
        assert!(w[0] <= 2.0 && w[1] <= 2.0, "{name}: {w:?}");
    }
    for (name, w) in [
        ("GL+(2) boost", worst_exp_error::<Gl<2>>(&boost)),
        ("SL(2) boost", worst_exp_error::<Sl<2>>(&boost)),
    ] {
        println!("{name}: {w:.2?}");
        assert!(w[0] <= 2.0 && w[1] <= 16.0, "{name}: {w:?}");
    }
}

// ---------------------------------------------------------------------------
// dexp and dexp⁻¹ against the block exponential in 256-bit arithmetic
// ---------------------------------------------------------------------------

/// `dexp_A V = F e^{−A}`, `F` the top-right block of `exp([[A, V], [0, A]])`.
fn dexp_reference(hp: &mut hp::Hp, a: &DMatrix<f64>, v: &DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    let mut big = DMatrix::zeros(2 * n, 2 * n);
    big.view_mut((0, 0), (n, n)).copy_from(a);
    big.view_mut((n, n), (n, n)).copy_from(a);
    big.view_mut((0, n), (n, n)).copy_from(v);
    let e = hp.expm(&hp.mat(&big));
    let f: hp::M = (0..n).map(|i| e[i][n..].to_vec()).collect();
    let einv = hp.expm(&hp.mat(&(-a)));
    hp.round_matrix(&hp.mul(&f, &einv))
}

/// Worst relative errors of `dexp` and residuals of `dexp⁻¹`
/// (`|dexp(a, dexp_inv(a, v)) − v|/|v|`, both dexp in 256 bits), over random
/// `a` of the given Frobenius norms.
fn dexp_errors<G: LieGroup>(norms: &[f64], count: usize) -> (f64, f64) {
    let mut hp = hp::Hp::new();
    let mut next = rng(31);
    let (mut wd, mut wi) = (0.0f64, 0.0f64);
    for &r in norms {
        for _ in 0..count {
            let c: Vec<f64> = (0..G::DOF).map(|_| next()).collect();
            let n = c.iter().map(|x| x * x).sum::<f64>().sqrt();
            let a = G::algebra_from_coords(&c.iter().map(|x| x * r / n).collect::<Vec<_>>());
            let cv: Vec<f64> = (0..G::DOF).map(|_| next()).collect();
            let v = G::algebra_from_coords(&cv);
            let (ha, hv) = (G::algebra_to_matrix(&a), G::algebra_to_matrix(&v));
            let reference = dexp_reference(&mut hp, &ha, &hv);
            wd = wd.max(rel_err(&G::algebra_to_matrix(&G::dexp(&a, &v)), &reference));
            let x = G::dexp_inv(&a, &v);
            let back = dexp_reference(&mut hp, &ha, &G::algebra_to_matrix(&x));
            wi = wi.max(rel_err(&back, &hv));
        }
    }
    (wd / EPS, wi / EPS)
}

/// dexp (scaling and doubling) and dexp⁻¹ (Bernoulli series for 2‖a‖_F ≤ 1,
/// else linear solve) against the 256-bit block exponential, at norms on both
/// sides of the switch and up to the law-suite radii. Bound:
/// 8ε·max(1, ‖a‖_F)³ for the dexp error and for the dexp⁻¹ residual. Measured
/// worst: dexp 2.9ε / dexp⁻¹ 3.1ε up to ‖a‖ = 1; at ‖a‖ = 4 dexp 18ε and the
/// dexp⁻¹ residual 91ε (SL(3)), consistent with a backward-stable solve:
/// ‖dexp_a‖·‖dexp_a⁻¹‖ ≈ φ(z)/φ(−z) ≈ 270 at the spectral radius z ≈ 5.6 of ad_a.
#[test]
fn dexp_and_dexp_inv_against_block_exponential() {
    let norms = [1e-8, 0.1, 0.49, 0.51, 1.0, 2.0, 4.0];
    fn check<G: LieGroup>(norms: &[f64]) {
        for &r in norms {
            let (d, i) = dexp_errors::<G>(&[r], 8);
            let bound = 8.0 * r.max(1.0).powi(3);
            println!(
                "{} ‖a‖ = {r}: dexp error {d:.1} ε, dexp⁻¹ residual {i:.1} ε (bound {bound} ε)",
                G::NAME
            );
            assert!(d <= bound && i <= bound, "{} at ‖a‖ = {r}: {d} ε, {i} ε", G::NAME);
        }
    }
    check::<Gl<3>>(&norms);
    check::<Sl<3>>(&norms);
    check::<SoN<4>>(&norms[..6]);
    check::<Co<3>>(&norms[..6]);
}

// ---------------------------------------------------------------------------
// log near the boundary of its domain, and typed errors
// ---------------------------------------------------------------------------

/// The rotation by `th` in 256 bits.
fn rot2_hp(hp: &mut hp::Hp, th: f64) -> hp::M {
    let b = hp.f(th);
    let (c, s) = (b.cos(hp::P, hp::RM, &mut hp.cc), b.sin(hp::P, hp::RM, &mut hp.cc));
    vec![vec![c.clone(), s.neg()], vec![s, c]]
}

/// The correctly rounded rotation by `th`, and its generator `thJ`.
fn rot2(hp: &mut hp::Hp, th: f64) -> (M2, M2) {
    let r = rot2_hp(hp, th);
    (
        M2::from_column_slice(hp.round_matrix(&r).as_slice()),
        M2::new(0.0, -th, th, 0.0),
    )
}

/// Rotation angles θ = π − δ, δ = 1e-1 … 1e-6. The input matrices are the
/// correctly rounded exact rotations (256-bit), so every error below is the
/// logarithm's. Errors are relative to θ; bounds, with measured worst:
/// - SO(n), CO⁺(2): 4ε·κ, κ = max φ/(2 sin(φ/2)) over the eigenvalues iφ of
///   ad_log R, the condition number of log = dexp⁻¹ within SO(n): κ = 1 for
///   SO(2), ≈ π/2 for SO(3), but ≈ 2π/(3δ) for the SO(4) rotation by θ and
///   θ − δ (φ = θ₁ + θ₂ → 2π). Measured: SO(2) 0.66ε, SO(3) 2.6ε,
///   SO(4) 0.25ε·κ (8e4 ε at δ = 1e-6, κ = 2e6).
/// - GL⁺(2) on the same rotation matrix: 4ε (0.7ε; the 2×2 Schur block is
///   the matrix itself and its square root is taken in closed form).
/// - GL⁺(3), SL(2) non-normal (P R P⁻¹, κ₂(P) ≈ 20 resp. 6.9), where the GL
///   logarithm's condition number grows like κ(P)²·θ/sin θ:
///   0.05ε·κ(P)²·θ/sin θ (measured 0.0099 resp. 0.0054).
#[test]
fn log_near_boundary() {
    let mut hp = hp::Hp::new();
    let mut worst = [0.0f64; 6];
    for k in 1..=6 {
        let delta = 10f64.powi(-k);
        let th = std::f64::consts::PI - delta;
        let cond = th / th.sin();
        let (r, w) = rot2(&mut hp, th);
        // SO(2), CO⁺(2), GL⁺(2) on the rotation itself.
        let l_so = SoN::<2>::new_unchecked(r).log().unwrap();
        let l_co = Co::<2>::from_parts(0.0, SoN::new_unchecked(r)).log().unwrap();
        let l_gl = Gl::<2>::new_unchecked(r).log().unwrap();
        let e_so = (l_so - w).amax().max((l_co - w).amax()) / th / EPS;
        let e_gl = (l_gl - w).amax() / th / EPS;
        println!("δ = {delta:e}: SO(2)/CO(2) {e_so:.2} ε, GL(2) {e_gl:.2} ε");
        assert!(
            e_so <= 4.0 && e_gl <= 4.0,
            "SO(2)/CO(2)/GL(2) at δ = {delta:e}: {e_so} ε, {e_gl} ε"
        );
        worst[0] = worst[0].max(e_so);
        worst[1] = worst[1].max(e_gl);
        // SO(3): rotation by θ about the unit axis n = (2, 3, 6)/7, by
        // Rodrigues' formula in 256 bits (K and θK rounded once at the end).
        let seven = hp.f(7.0);
        let nb = [2.0, 3.0, 6.0].map(|x| hp.f(x).div(&seven, hp::P, hp::RM));
        let z = hp.f(0.0);
        let hk: hp::M = vec![
            vec![z.clone(), nb[2].neg(), nb[1].clone()],
            vec![nb[2].clone(), z.clone(), nb[0].neg()],
            vec![nb[1].neg(), nb[0].clone(), z.clone()],
        ];
        let b = hp.f(th);
        let (s, c) = (b.sin(hp::P, hp::RM, &mut hp.cc), b.cos(hp::P, hp::RM, &mut hp.cc));
        let one_minus_c = hp.f(1.0).sub(&c, hp::P, hp::RM);
        let rr = hp.add(
            &hp.add(&hp.identity(3), &hp.scale(&hk, &s)),
            &hp.scale(&hp.mul(&hk, &hk), &one_minus_c),
        );
        let r3 = M3::from_column_slice(hp.round_matrix(&rr).as_slice());
        let w3 = hp.round_matrix(&hp.scale(&hk, &b));
        let l3 = SoN::<3>::new_unchecked(r3).log().unwrap();
        let e3 = (dm(&l3) - &w3).amax() / th / EPS;
        let kappa3 = th / (2.0 * (th / 2.0).sin());
        println!("δ = {delta:e}: SO(3) {e3:.2} ε");
        assert!(e3 <= 4.0 * kappa3, "SO(3) at δ = {delta:e}: {e3} ε");
        worst[2] = worst[2].max(e3);
        // SO(4): angles θ and θ − δ in the planes of Q = I − 2vvᵀ/|v|²,
        // v = (1, 2, 2, 4), all in 256 bits.
        let v = [1.0, 2.0, 2.0, 4.0];
        let twenty_five = hp.f(25.0);
        let hq: hp::M = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        let d = hp.f(if i == j { 1.0 } else { 0.0 });
                        d.sub(&hp.f(2.0 * v[i] * v[j]).div(&twenty_five, hp::P, hp::RM), hp::P, hp::RM)
                    })
                    .collect()
            })
            .collect();
        let mut blocks = hp.zeros(4);
        let mut gens = hp.zeros(4);
        for (p, ang) in [(0, th), (2, th - delta)] {
            let b = hp.f(ang);
            let (c, s) = (b.cos(hp::P, hp::RM, &mut hp.cc), b.sin(hp::P, hp::RM, &mut hp.cc));
            blocks[p][p] = c.clone();
            blocks[p + 1][p + 1] = c;
            blocks[p + 1][p] = s.clone();
            blocks[p][p + 1] = s.neg();
            gens[p + 1][p] = hp.f(ang);
            gens[p][p + 1] = hp.f(-ang);
        }
        // Q is symmetric: Qᵀ = Q.
        let r4 = hp.round_matrix(&hp.mul(&hp.mul(&hq, &blocks), &hq));
        let w4 = hp.round_matrix(&hp.mul(&hp.mul(&hq, &gens), &hq));
        let l4 = SoN::<4>::new_unchecked(nalgebra::SMatrix::<f64, 4, 4>::from_column_slice(r4.as_slice()))
            .log()
            .unwrap();
        let phi = 2.0 * th - delta;
        let kappa4 = phi / (2.0 * (phi / 2.0).sin());
        let e4 = (dm(&l4) - &w4).amax() / th / EPS / kappa4;
        println!("δ = {delta:e}: SO(4) {e4:.3} ε·κ (κ = {kappa4:.1e})");
        assert!(e4 <= 4.0, "SO(4) at δ = {delta:e}: {e4} ε·κ");
        worst[3] = worst[3].max(e4);
        // GL⁺(3): A = P diag(θJ, 1/2) P⁻¹, g = P diag(R(θ), e^{1/2}) P⁻¹.
        let (hpp, hppinv) = (hp.mat(&dm(&m3(P3))), hp.mat(&dm(&m3(P3_INV))));
        let mut d = hp.zeros(3);
        let mut e = hp.zeros(3);
        let hr = rot2_hp(&mut hp, th);
        for i in 0..2 {
            for j in 0..2 {
                e[i][j] = hr[i][j].clone();
            }
        }
        d[1][0] = hp.f(th);
        d[0][1] = hp.f(-th);
        d[2][2] = hp.f(0.5);
        e[2][2] = hp.f(0.5).exp(hp::P, hp::RM, &mut hp.cc);
        let g = hp.round_matrix(&hp.mul(&hp.mul(&hpp, &e), &hppinv));
        let a = hp.round_matrix(&hp.mul(&hp.mul(&hpp, &d), &hppinv));
        let l = Gl::<3>::new_unchecked(M3::from_column_slice(g.as_slice()))
            .log()
            .unwrap();
        let kp = 20.0f64; // κ₁(P) = ‖P‖₁‖P⁻¹‖₁ = 4·7 = 28 ≥ κ₂(P) ≈ 20
        let eg = (dm(&l) - &a).amax() / a.amax() / EPS / cond / (kp * kp);
        println!("δ = {delta:e}: GL(3) {eg:.4} ε·κ²θ/sinθ");
        assert!(eg <= 0.05, "GL+(3) at δ = {delta:e}: {eg} ε·κ²θ/sin θ");
        worst[4] = worst[4].max(eg);
        // SL(2): g = P R(θ) P⁻¹, P = [[2, 1], [1, 1]] (κ₂ ≈ 6.9).
        let p2 = M2::new(2.0, 1.0, 1.0, 1.0);
        let p2inv = M2::new(1.0, -1.0, -1.0, 2.0);
        let (hp2, hp2i) = (hp.mat(&dm(&p2)), hp.mat(&dm(&p2inv)));
        let g2 = hp.round_matrix(&hp.mul(&hp.mul(&hp2, &hr), &hp2i));
        let a2 = dm(&(p2 * w * p2inv));
        let l2 = Sl::<2>::new_unchecked(M2::from_column_slice(g2.as_slice()))
            .log()
            .unwrap();
        let es = (dm(&l2) - &a2).amax() / a2.amax() / EPS / cond / (6.9 * 6.9);
        println!("δ = {delta:e}: SL(2) {es:.4} ε·κ²θ/sinθ");
        assert!(es <= 0.05, "SL(2) at δ = {delta:e}: {es} ε·κ²θ/sin θ");
        worst[5] = worst[5].max(es);
    }
    println!(
        "log near π, worst: SO(2)/CO(2) {:.2} ε, GL(2) {:.2} ε, SO(3) {:.2} ε, SO(4) {:.3} ε·κ, GL(3) {:.4} ε·κ²θ/sinθ, SL(2) {:.4} ε·κ²θ/sinθ",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
    );
}

/// Far from the identity in the non-compact directions (eigenvalues e^{±20},
/// κ(g) = e^{40}) `log` is normwise ill-conditioned (an ε‖g‖ perturbation moves
/// the eigenvalue e^{−20} relatively by ε e^{40}), so the meaningful check is
/// its backward error: exp(log g) = g to c·ε·‖log g‖ relative (the
/// conditioning of exp). Bound 4kε·‖A‖_F with k = ⌈log₂(‖A‖_F/0.7)⌉ + 1
/// ≈ the number of square roots taken, each of which costs O(ε) relative
/// (measured ≤ 1.5ε·‖A‖ on GL⁺(3), 12.9ε·‖A‖ on the boost, k = 6). These inputs take
/// the Schur path (κ₁(g) > 30); the Denman–Beavers path's backward error on
/// them was 5e4–4e5 ε·‖A‖, which is why it is restricted to κ₁ ≤ 30.
fn sqrt_count(norm: f64) -> f64 {
    (norm / 0.7).log2().ceil().max(0.0) + 1.0
}

#[test]
fn log_of_large_elements() {
    let cases: [(&str, M3); 3] = [
        (
            "triangular e^±20",
            m3([[20.0, 1.0, 0.5], [0.0, -3.0, 2.0], [0.0, 0.0, -20.0]]),
        ),
        (
            "non-normal",
            m3(P3) * m3([[12.0, 0.0, 0.0], [0.0, -3.0, -2.5], [0.0, 2.5, -3.0]]) * m3(P3_INV),
        ),
        ("symmetric", m3([[5.0, 8.0, 1.0], [8.0, -2.0, 4.0], [1.0, 4.0, -3.0]])),
    ];
    for (name, a) in cases {
        let g = Gl::<3>::exp(&a);
        let l = g.log().unwrap();
        let back = rel_err(&Gl::<3>::exp(&l).to_matrix(), &g.to_matrix()) / EPS / a.norm();
        let fwd = (l - a).amax() / a.amax();
        println!("GL+(3) {name}: exp(log g) error {back:.2} ε·‖A‖, log error {fwd:.1e}");
        assert!(back <= 4.0 * sqrt_count(a.norm()), "{name}: {back} ε·‖A‖");
    }
    // A boost of rapidity 10 (κ₁ ≈ 5e8). At rapidity 20 the eigenvalue e^{−20}
    // of the rounded matrix would be below ε·e^{20} and may come out negative,
    // where log is genuinely undefined. exp(b) has det = 1 + 8.6e-9 (≈ κε):
    // GL⁺(2)'s log must reproduce it (backward error), SL(2)'s log must accept
    // it (its trace tolerance grows with κ) and return b to within that κε.
    let b = M2::new(0.0, 10.0, 10.0, 0.0);
    let g = Gl::<2>::exp(&b);
    let back = rel_err(&Gl::<2>::exp(&g.log().unwrap()).to_matrix(), &g.to_matrix()) / EPS / b.norm();
    println!("GL+(2) boost 10: exp(log g) error {back:.2} ε·‖A‖");
    assert!(back <= 4.0 * sqrt_count(b.norm()), "{back}");
    let l = Sl::<2>::exp(&b).log().unwrap();
    let fwd = (l - b).amax() / 10.0;
    println!("SL(2) boost 10: log error {fwd:.1e}");
    assert!(fwd <= 1e-8, "{fwd:e}");
}

#[test]
fn typed_errors() {
    let nan = M2::new(1.0, f64::NAN, 0.0, 1.0);
    assert_eq!(
        Gl::<2>::new(nan).unwrap_err(),
        framedyn::Error::NotFinite { field: "matrix" }
    );
    match Gl::<2>::new(M2::new(1.0, 0.0, 0.0, -1.0)) {
        Err(framedyn::Error::InvalidParameter {
            field: "det(matrix)",
            value,
            ..
        }) => assert_eq!(value, -1.0),
        other => panic!("{other:?}"),
    }
    match Gl::<2>::new(M2::new(1.0, 2.0, 2.0, 4.0)) {
        Err(framedyn::Error::InvalidParameter {
            field: "det(matrix)",
            value,
            ..
        }) => assert_eq!(value, 0.0),
        other => panic!("{other:?}"),
    }
    assert!(Gl::<2>::new(M2::new(0.0, -1.0, 1.0, 0.0)).is_ok());
    // Eigenvalues on the closed negative real axis (det > 0 nonetheless).
    let undefined = |r: framedyn::Result<M2>| matches!(r, Err(framedyn::Error::LogUndefined { .. }));
    assert!(undefined(Gl::<2>::new_unchecked(M2::new(-1.0, 0.0, 0.0, -2.0)).log()));
    assert!(
        undefined(Gl::<2>::new_unchecked(M2::new(-1.0, 1.0, 0.0, -1.0)).log()),
        "Jordan block at −1"
    );
    assert!(undefined(Gl::<2>::new_unchecked(M2::new(-1.0, 0.0, 0.0, -1.0)).log()));
    assert!(undefined(SoN::<2>::new_unchecked(M2::new(-1.0, 0.0, 0.0, -1.0)).log()));
    // exp(πJ) with the f64 π: sin π ≈ 1.2e-16, within round-off of angle π.
    assert!(undefined(
        SoN::<2>::exp(&M2::new(0.0, -std::f64::consts::PI, std::f64::consts::PI, 0.0)).log()
    ));
    assert!(undefined(Sl::<2>::new_unchecked(M2::new(-2.0, 0.0, 0.0, -0.5)).log()));
    let pi3 = m3([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]);
    assert!(matches!(
        SoN::<3>::new(pi3).unwrap().log(),
        Err(framedyn::Error::LogUndefined { group: "SO(3)", .. })
    ));
    assert!(matches!(
        Gl::<3>::new(pi3).unwrap().log(),
        Err(framedyn::Error::LogUndefined { group: "GL+(3)", .. })
    ));
    let pi4 = nalgebra::SMatrix::<f64, 4, 4>::from_diagonal(&nalgebra::Vector4::new(-1.0, -1.0, -1.0, -1.0));
    assert!(matches!(
        SoN::<4>::new(pi4).unwrap().log(),
        Err(framedyn::Error::LogUndefined { .. })
    ));
    // Non-finite elements through new_unchecked.
    assert_eq!(
        Gl::<2>::new_unchecked(nan).log().unwrap_err(),
        framedyn::Error::NotFinite { field: "group element" }
    );
    assert!(Co::<2>::from_parts(f64::INFINITY, SoN::identity()).log().is_err());
    // Non-finite algebra elements give NaN, never a panic.
    assert!(Gl::<2>::exp(&nan).matrix().iter().all(|x| x.is_nan()));
    assert!(!Gl::<2>::dexp(&nan, &M2::identity()).iter().all(|x| x.is_finite()));
    assert!(!Gl::<2>::dexp_inv(&nan, &M2::identity()).iter().all(|x| x.is_finite()));
    // SL(n): determinant constraint.
    assert!(matches!(
        Sl::<2>::new(M2::new(2.0, 0.0, 0.0, 1.0)),
        Err(framedyn::Error::Constraint { field: "matrix", .. })
    ));
    let s = Sl::<2>::normalized(M2::new(2.0, 0.0, 0.0, 1.0)).unwrap();
    assert!((s.det() - 1.0).abs() <= 2.0 * EPS);
    assert!(matches!(
        Sl::<2>::normalized(M2::new(-2.0, 0.0, 0.0, 1.0)),
        Err(framedyn::Error::InvalidParameter { .. })
    ));
    assert!(matches!(
        Sl::<2>::new_unchecked(M2::new(2.0, 0.0, 0.0, 1.0)).log(),
        Err(framedyn::Error::Constraint {
            field: "SL element",
            ..
        })
    ));
    // SO(n), CO⁺(n) constructors.
    assert!(matches!(
        SoN::<2>::new(M2::new(1.0, 0.1, 0.0, 1.0)),
        Err(framedyn::Error::Constraint { field: "rotation", .. })
    ));
    assert!(matches!(
        SoN::<2>::new(M2::new(1.0, 0.0, 0.0, -1.0)),
        Err(framedyn::Error::Constraint { .. })
    ));
    assert!(matches!(
        SoN::<2>::nearest(M2::new(1.0, 0.0, 0.0, -1.0)),
        Err(framedyn::Error::InvalidParameter { .. })
    ));
    assert!(matches!(
        Co::<2>::new(0.0, M2::identity()),
        Err(framedyn::Error::InvalidParameter { field: "lambda", .. })
    ));
    assert!(matches!(
        Co::<2>::new(2.0, M2::new(1.0, 0.1, 0.0, 1.0)),
        Err(framedyn::Error::Constraint { .. })
    ));
    assert!(matches!(
        Co::<2>::from_matrix(M2::new(1.0, 0.0, 0.0, 2.0)),
        Err(framedyn::Error::Constraint { .. })
    ));
    let c = Co::<2>::from_matrix(M2::new(0.0, -3.0, 3.0, 0.0)).unwrap();
    assert!((c.lambda() - 3.0).abs() <= 2.0 * EPS * 3.0);
    assert!((c.rotation().matrix() - M2::new(0.0, -1.0, 1.0, 0.0)).amax() <= EPS);
}

// ---------------------------------------------------------------------------
// Truncation order of the dexp⁻¹ series (the hook of the RKMK order tests)
// ---------------------------------------------------------------------------

/// Least-squares slope of log(err) against log(h).
fn loglog_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(h, e)| (a + h.ln(), b + e.ln()));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), &(h, e)| {
        (a + (h.ln() - mx) * (e.ln() - my), b + (h.ln() - mx).powi(2))
    });
    num / den
}

/// `dexp_inv_series(a, v, q)` truncated after `ad^q` has error
/// `B_p/p! ad_a^p v + …`, `p` the first index `> q` with `B_p ≠ 0`: since
/// `B_k = 0` for odd `k ≥ 3`, `p(q) = 1, 2, 4, 4, 6, 6, 8` for `q = 0…6`.
/// Measured as the residual `|dexp_a(s_q) − v|` (dexp exact, independent of
/// the Bernoulli series) over `a = h·a₀`, `h = 0.8·2^{−j/2}`; the slope is
/// fitted on the 4 smallest `h` whose residual is above 3e-14 (≥ 50× the
/// round-off of the residual; the smallest `h` are the asymptotic regime),
/// and must be within 0.15 of `p(q)`. So dropping the last term of a
/// `max_power = q` truncation lowers the observed order by 1 (q = 1), by 2
/// (q even) or not at all (q odd ≥ 3: the dropped term is 0).
fn dexp_inv_truncation_orders<G: LieGroup>(seed: u64) {
    let mut next = rng(seed);
    let c: Vec<f64> = (0..G::DOF).map(|_| next()).collect();
    let n = c.iter().map(|x| x * x).sum::<f64>().sqrt();
    let a0 = G::algebra_from_coords(&c.iter().map(|x| x / n).collect::<Vec<_>>());
    let v = G::algebra_from_coords(&(0..G::DOF).map(|_| next()).collect::<Vec<_>>());
    let p_of = |q: usize| {
        if q == 0 {
            1
        } else if q % 2 == 1 {
            q + 1
        } else {
            q + 2
        }
    };
    let hs: Vec<f64> = (0..16).map(|j| 0.8 * 0.5f64.powf(j as f64 / 2.0)).collect();
    let mut slopes = Vec::new();
    for q in 0..=6 {
        let pts: Vec<(f64, f64)> = hs
            .iter()
            .map(|&h| {
                let a = a0 * h;
                let s = dexp_inv_series::<G>(&a, &v, q);
                (h, (G::dexp(&a, &s) - v).norm() / v.norm())
            })
            .filter(|&(_, e)| e > 3e-14)
            .collect();
        let pts = &pts[pts.len().saturating_sub(4)..];
        assert!(pts.len() >= 4, "{}: q = {q}: too few points above round-off", G::NAME);
        let slope = loglog_slope(pts);
        println!("{}: max_power {q}: slope {slope:.3} (expected {})", G::NAME, p_of(q));
        assert!(
            (slope - p_of(q) as f64).abs() <= 0.15,
            "{}: q = {q}: slope {slope}",
            G::NAME
        );
        slopes.push(slope);
    }
    for q in 1..=6 {
        let drop = slopes[q] - slopes[q - 1];
        let want = (p_of(q) - p_of(q - 1)) as f64;
        assert!(
            (drop - want).abs() <= 0.3,
            "{}: q = {q}: slope change {drop}, expected {want}",
            G::NAME
        );
    }
}

#[test]
fn dexp_inv_series_truncation_order() {
    dexp_inv_truncation_orders::<Gl<3>>(3);
    dexp_inv_truncation_orders::<Sl<2>>(4);
    dexp_inv_truncation_orders::<SoN<4>>(5);
}

/// The two dexp⁻¹ paths (Bernoulli series for 2‖a‖_F ≤ 1, linear solve
/// above) agree across the switch, and the series path equals the trait's
/// generic `dexp_inv_series` with 20 terms there.
#[test]
fn dexp_inv_continuous_across_switch() {
    let mut next = rng(8);
    for _ in 0..20 {
        let a0 = M3::from_fn(|_, _| next());
        let v = M3::from_fn(|_, _| next());
        let a0 = a0 / a0.norm();
        let below = Gl::<3>::dexp_inv(&(a0 * 0.5f64.next_down()), &v);
        let above = Gl::<3>::dexp_inv(&(a0 * 0.5f64.next_up()), &v);
        assert!(
            (below - above).amax() <= 4.0 * EPS * v.amax(),
            "{:e}",
            (below - above).amax()
        );
        let series = dexp_inv_series::<Gl<3>>(&(a0 * 0.5f64.next_down()), &v, 20);
        assert!((below - series).amax() <= 2.0 * EPS * v.amax());
    }
}

// ---------------------------------------------------------------------------
// Bases, products, renormalisation
// ---------------------------------------------------------------------------

#[test]
fn algebra_bases_are_as_documented() {
    // GL⁺(n): row-major entries.
    let a = Gl::<2>::algebra_from_coords(&[1.0, 2.0, 3.0, 4.0]);
    assert_eq!(a, M2::new(1.0, 2.0, 3.0, 4.0));
    assert_eq!(Gl::<2>::algebra_coords(&a), vec![1.0, 2.0, 3.0, 4.0]);
    // SL(2): (h, e, f) ↔ [[h, e], [f, −h]].
    assert_eq!(
        Sl::<2>::algebra_from_coords(&[1.0, 2.0, 3.0]),
        M2::new(1.0, 2.0, 3.0, -1.0)
    );
    // SL(3): diagonal h₀, h₁ (basis E_kk − E_22), then off-diagonal row-major.
    let a = Sl::<3>::algebra_from_coords(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    assert_eq!(a, m3([[1.0, 3.0, 4.0], [5.0, 2.0, 6.0], [7.0, 8.0, -3.0]]));
    assert_eq!(
        Sl::<3>::algebra_coords(&a),
        vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
    );
    let mut next = rng(17);
    for _ in 0..1000 {
        let c: Vec<f64> = (0..8).map(|_| next() * 10f64.powi((next() * 8.0) as i32)).collect();
        let a = Sl::<3>::algebra_from_coords(&c);
        assert_eq!(
            a.trace(),
            0.0,
            "from_coords must give exactly traceless matrices: {c:?}"
        );
        assert_eq!(Sl::<3>::algebra_coords(&a), c);
    }
    // SO(n): ω_ij, i < j lexicographic, basis E_ij − E_ji.
    let w = SoN::<3>::algebra_from_coords(&[1.0, 2.0, 3.0]);
    assert_eq!(w, m3([[0.0, 1.0, 2.0], [-1.0, 0.0, 3.0], [-2.0, -3.0, 0.0]]));
    assert_eq!(
        SoN::<4>::algebra_coords(&SoN::<4>::algebra_from_coords(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0])).len(),
        6
    );
    // CO⁺(n): κ then ω.
    assert_eq!(Co::<2>::algebra_from_coords(&[0.5, 2.0]), M2::new(0.5, 2.0, -2.0, 0.5));
    assert_eq!(
        Co::<3>::algebra_coords(&Co::<3>::algebra_from_coords(&[0.1, 1.0, 2.0, 3.0])),
        vec![0.1, 1.0, 2.0, 3.0]
    );
    // DOF.
    assert_eq!((Gl::<3>::DOF, Sl::<3>::DOF, SoN::<5>::DOF, Co::<3>::DOF), (9, 8, 10, 4));
}

#[test]
fn product_is_componentwise_and_zero_cost() {
    use std::mem::size_of;
    type P = Product<Gl<2>, Rn<3>>;
    type V3 = nalgebra::Vector3<f64>;
    assert_eq!(size_of::<P>(), size_of::<Gl<2>>() + size_of::<Rn<3>>());
    assert_eq!(size_of::<ProductAlgebra<M2, V3>>(), 7 * 8);
    assert_eq!(
        (<P as LieGroup>::DOF, <ProductAlgebra<M2, V3> as AlgebraVector>::LEN),
        (7, 7)
    );
    let a = M2::new(0.1, -0.3, 0.2, 0.05);
    let x = V3::new(1.0, 2.0, 3.0);
    let g = P::exp(&ProductAlgebra(a, x));
    assert_eq!(g, Product(Gl::<2>::exp(&a), Rn(x)));
    // Stored components: A's (column-major SMatrix storage) then B's.
    let pa = ProductAlgebra(a, x);
    let comps: Vec<f64> = (0..7).map(|i| pa.get(i)).collect();
    assert_eq!(comps, vec![0.1, 0.2, -0.3, 0.05, 1.0, 2.0, 3.0]);
    // Coordinates: A's coordinates (row-major for GL) then B's.
    assert_eq!(P::algebra_coords(&pa), vec![0.1, -0.3, 0.2, 0.05, 1.0, 2.0, 3.0]);
    assert_eq!(P::algebra_from_coords(&P::algebra_coords(&pa)), pa);
    // Block-diagonal matrices.
    let m = g.to_matrix();
    assert_eq!(m.shape(), (6, 6));
    assert_eq!(m.view((0, 0), (2, 2)), Gl::<2>::exp(&a).to_matrix());
    assert_eq!(m.view((2, 2), (4, 4)), Rn(x).to_matrix());
    assert!(m
        .view((0, 2), (2, 4))
        .iter()
        .chain(m.view((2, 0), (4, 2)).iter())
        .all(|&v| v == 0.0));
    // log fails with the failing component's typed error.
    let bad = Product(SoN::<2>::new_unchecked(-M2::identity()), Gl::<2>::identity());
    assert!(matches!(
        bad.log(),
        Err(framedyn::Error::LogUndefined { group: "SO(2)", .. })
    ));
    // Defect: the larger of the two, NaN propagates.
    let q = Product(
        Gl::<2>::new_unchecked(M2::new(1.0, 0.0, 0.0, -1.0)),
        SoN::<2>::identity(),
    );
    assert!(q.constraint_defect() >= 1.0);
}

#[test]
fn renormalisation() {
    let mut next = rng(23);
    for _ in 0..200 {
        // SO(3): the polar factor of a perturbed rotation (entries 1e-3 … 0.3 off).
        let r = SoN::<3>::exp(&SoN::<3>::algebra_from_coords(&[
            next() * 3.0,
            next() * 3.0,
            next() * 3.0,
        ]));
        let scale = 10f64.powf(-3.0 + 2.5 * (next() + 1.0) / 2.0);
        let m = r.matrix() + M3::from_fn(|_, _| scale * next());
        let p = SoN::<3>::new_unchecked(m).renormalize();
        // Defining properties of the polar factor (which they determine
        // uniquely): U orthogonal, UᵀM symmetric positive definite. (nalgebra's
        // SVD-based U Vᵀ is a worse reference: its UᵀM is symmetric only to
        // ~4e-14.)
        let u = dm(p.matrix());
        let h = u.transpose() * dm(&m);
        assert!((&h - h.transpose()).amax() <= 4.0 * EPS * h.amax(), "UᵀM not symmetric");
        assert!(h.symmetric_eigenvalues().min() > 0.0);
        assert!(p.constraint_defect() <= 4.0 * EPS);
    }
    // det < 0: the nearest rotation (smallest singular direction flipped).
    let m = m3([[1.0, 0.1, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -0.5]]);
    let p = SoN::<3>::new_unchecked(m).renormalize();
    assert!(p.constraint_defect() <= 4.0 * EPS, "{}", p.constraint_defect());
    // SO(5) exp of a large generator stays orthogonal to a few ε.
    let w = SoN::<5>::algebra_from_coords(&(0..10).map(|_| 20.0 * next()).collect::<Vec<_>>());
    assert!(SoN::<5>::exp(&w).constraint_defect() <= 4.0 * EPS);
    // SL: renormalize restores det = 1.
    let s = Sl::<3>::new_unchecked(m3([[2.0, 1.0, 0.0], [0.0, 1.0, 0.3], [0.1, 0.0, 0.7]]));
    assert!(s.renormalize().constraint_defect() <= 4.0 * EPS);
    // GL⁺: nothing to restore; the defect flags a lost orientation only.
    assert_eq!(
        Gl::<3>::exp(&m3([[1.0, 2.0, 3.0], [0.0, -1.0, 0.5], [2.0, 0.0, 0.3]])).constraint_defect(),
        0.0
    );
    assert_eq!(
        Gl::<2>::new_unchecked(M2::new(f64::NAN, 0.0, 0.0, 1.0)).constraint_defect(),
        f64::INFINITY
    );
}

/// This crate's `exp` against the suite's reference `expm_reference`
/// (Taylor + squaring), both against 256-bit arithmetic on random 3×3
/// matrices: ours must be at least as accurate in every norm band (the law
/// suites' `exp = expm(hat)` tolerance therefore measures the reference).
#[test]
fn exp_at_least_as_accurate_as_the_suite_reference() {
    let mut hp = hp::Hp::new();
    let mut next = rng(41);
    for r in [1e-3, 0.3, 1.0, 4.4] {
        let (mut ours, mut theirs) = (0.0f64, 0.0f64);
        for _ in 0..12 {
            let a = M3::from_fn(|_, _| next());
            let a = a * (r / a.norm());
            let ha = hp.mat(&dm(&a));
            let e = hp.expm(&ha);
            let exact = hp.round_matrix(&e);
            ours = ours.max(rel_err(&Gl::<3>::exp(&a).to_matrix(), &exact));
            theirs = theirs.max(rel_err(&expm_reference(&dm(&a)), &exact));
        }
        println!(
            "‖A‖ = {r}: Gl::exp {:.1} ε, expm_reference {:.1} ε",
            ours / EPS,
            theirs / EPS
        );
        assert!(ours <= theirs.max(2.0 * EPS), "‖A‖ = {r}: {ours:e} vs {theirs:e}");
    }
}
