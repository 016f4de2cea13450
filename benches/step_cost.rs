//! Per-step cost of every RKMK method on each manifold × body, one
//! right-hand-side evaluation per model, and a **fixed-size hand-specialised
//! RKMK4 step of the S² gyroscope** as the baseline in the same run, and a
//! hand-written **Strang splitting step** of the same gyroscope as the
//! baseline of the library's `Splitting::strang` (row
//! `strang_vs_hand_strang`; checked against it to 1e-13 before timing).
//!
//! `cargo bench --bench step_cost` runs the criterion benches (statistics
//! only, no plots) and then an interleaved ratio table: rounds alternating
//! the baseline with each library step, so that load from other processes
//! hits both alike (thread-CPU time); the median per-round ratio is printed and written to
//! `docs/data/step_cost.csv`. `FRAMEDYN_RATIOS_ONLY=1` skips criterion.
//!
//! Rows `project_energy`: the energy projection of a state off its level
//! (`project = "energy"`) against one DOP853 step of the same model, the
//! baseline of these rows (`FRAMEDYN_RATIOS_FILTER=project_energy` runs them
//! alone and prints them).
//!
//! Rows `tangent_exact` and `tangent_differenced`: one step of RKMK4 with
//! one tangent vector carried (`TangentFlow`, as the analyses step it) —
//! exact (the lift on the tangent group) and by second-order central
//! differences — against one plain RKMK4 step of the same model, the
//! baseline of these rows (`FRAMEDYN_RATIOS_FILTER=tangent` runs them
//! alone). A run with `k` vectors pays the per-vector part `k` times. Row
//! `tangent_field`: one `System::tangent_field` (the vector field and its
//! exact derivative along one direction) against one `vector_field`.
//!
//! In test mode (`cargo test --all-targets`, no `--bench` argument)
//! criterion runs each bench once and the ratio table is skipped.
//!
//! Row `rkmk4_hand_rhs`: the library's RKMK4 step on the hand-written
//! right-hand side (`HandRhs`, the same numbers on the library's state
//! types). It converts the library's state to the hand-written variables at
//! every stage, which costs more than the library's own right-hand side
//! with a `Pole` since fc5fe8b: its ratio bounds the stage machinery's cost
//! from above, it no longer isolates it.
//!
//! Rows `rkmk4_pole`, `strang_pole` (and `strang_pole_vs_hand_strang`): the
//! same problem with the potential's centre a compile-time `Pole` instead of
//! a runtime `Centre` (checked to give the same step bit for bit): the
//! library as a Rust user writes the paper's problem, with the axial
//! coordinate a constant index as in the hand-written step.
//!
//! Before timing, the hand-written step is checked against the library's
//! RKMK4 step (same state after one step to 1e-13): the baseline computes
//! the same thing.

mod common;

use std::hint::black_box;
use std::io::Write;

use common::*;
use criterion::Criterion;
use framedyn::dynamics::System;
use framedyn::lie::{LieGroup, ProductAlgebra};
use framedyn::method::{GroupNumerics, Method, Rkmk, Splitting, StepRequest};
use framedyn::solve::projection::project_energy;
use framedyn::solve::Stats;
use framedyn::testing::*;
use nalgebra::{Matrix3, Vector1, Vector2, Vector3};

/// Step size of the benched steps.
const H: f64 = 0.01;

// ---------------------------------------------------------------------------
// The hand-specialised baseline
// ---------------------------------------------------------------------------

/// State of the S² gyroscope: `Q = [n | q₁ | q₂] ∈ SO(3)`, the internal angle
/// as `(cos α, sin α)`, velocity components `u` in the parallel frame, spin.
#[derive(Debug, Clone, Copy)]
struct Hand {
    q: Matrix3<f64>,
    cs: Vector2<f64>,
    u: Vector2<f64>,
    s: f64,
}

impl Hand {
    /// The library's S² gyroscope state in these variables.
    #[inline(always)]
    fn of(y: &<S2Gyro as System>::State) -> Hand {
        Hand { q: *y.0 .0.matrix(), cs: Vector2::new(y.0 .1.cos(), y.0 .1.sin()), u: Vector2::new(y.1 .0[0], y.1 .0[1]), s: y.1 .0[2] }
    }
}

/// Its algebra: so(3) vector, α̇, (u̇, ṡ).
#[derive(Debug, Clone, Copy)]
struct HandAlg {
    w: Vector3<f64>,
    a: f64,
    du: Vector2<f64>,
    ds: f64,
}

impl HandAlg {
    #[inline(always)]
    fn lin(&self, c: f64) -> HandAlg {
        HandAlg { w: self.w * c, a: self.a * c, du: self.du * c, ds: self.ds * c }
    }
    #[inline(always)]
    fn add(&self, o: &HandAlg) -> HandAlg {
        HandAlg { w: self.w + o.w, a: self.a + o.a, du: self.du + o.du, ds: self.ds + o.ds }
    }
    /// `[a, b]`: only the so(3) part is non-abelian.
    #[inline(always)]
    fn bracket(&self, o: &HandAlg) -> HandAlg {
        HandAlg { w: self.w.cross(&o.w), a: 0.0, du: Vector2::zeros(), ds: 0.0 }
    }
}

/// Parameters: `1/R`, `1/m`, `σ/I`, `β/R` of `V = β cos(r/R)` about the z axis.
#[derive(Debug, Clone, Copy)]
struct HandSys {
    inv_r: f64,
    inv_m: f64,
    rate: f64,
    grad: f64,
}

impl HandSys {
    /// `f(y)`: horizontal lift `(0, −u₂/R, u₁/R)`, `α̇ = s/I`,
    /// `u̇ = (F̂ + K s ε u)/m` with `F̂ = −(β/R) (q₁_z, q₂_z)`, `ṡ = 0`.
    #[inline(always)]
    fn f(&self, y: &Hand) -> HandAlg {
        let ks = self.inv_r * self.inv_r * y.s;
        let f = Vector2::new(-self.grad * y.q[(2, 1)], -self.grad * y.q[(2, 2)]);
        HandAlg {
            w: Vector3::new(0.0, -y.u[1] * self.inv_r, y.u[0] * self.inv_r),
            a: self.rate * y.s,
            du: Vector2::new(f[0] - ks * y.u[1], f[1] + ks * y.u[0]) * self.inv_m,
            ds: 0.0,
        }
    }
}

/// `y·exp(θ)` (Rodrigues with a series near 0).
#[inline(always)]
fn compose_exp(y: &Hand, t: &HandAlg) -> Hand {
    let s2 = t.w.norm_squared();
    let (a, b) = if s2 < 1e-6 {
        (1.0 - s2 / 6.0 * (1.0 - s2 / 20.0), 0.5 - s2 / 24.0 * (1.0 - s2 / 30.0))
    } else {
        let th = s2.sqrt();
        (th.sin() / th, (1.0 - th.cos()) / s2)
    };
    let k = Matrix3::new(0.0, -t.w[2], t.w[1], t.w[2], 0.0, -t.w[0], -t.w[1], t.w[0], 0.0);
    let e = Matrix3::identity() + k * a + k * k * b;
    let (c, s) = (t.a.cos(), t.a.sin());
    Hand {
        q: y.q * e,
        cs: Vector2::new(y.cs[0] * c - y.cs[1] * s, y.cs[1] * c + y.cs[0] * s),
        u: y.u + t.du,
        s: y.s + t.ds,
    }
}

/// One two-commutator RKMK4 step (the library's tableau: `θ₃ += h²/8 [k₁, k₂]`,
/// `Θ += h²/12 [k₁, k₄]`), renormalised by one Newton–Schulz step on `Q`
/// and normalising `(cos α, sin α)`.
#[inline(always)]
fn hand_rkmk4(sys: &HandSys, y: &Hand, h: f64) -> Hand {
    let k1 = sys.f(y);
    let k2 = sys.f(&compose_exp(y, &k1.lin(0.5 * h)));
    let t3 = k2.lin(0.5 * h).add(&k1.bracket(&k2).lin(h * h / 8.0));
    let k3 = sys.f(&compose_exp(y, &t3));
    let k4 = sys.f(&compose_exp(y, &k3.lin(h)));
    let th = k1.add(&k2.lin(2.0)).add(&k3.lin(2.0)).add(&k4).lin(h / 6.0).add(&k1.bracket(&k4).lin(h * h / 12.0));
    let mut y1 = compose_exp(y, &th);
    let d = y1.q.transpose() * y1.q - Matrix3::identity();
    y1.q -= y1.q * d * 0.5;
    y1.cs /= y1.cs.norm();
    y1
}

/// The exact free flow over `h` (the library's `Splittable::drift` for the
/// S² gyroscope, specialised): `Q ← Q exp(h(ξ(u) + c e₁)) exp(−h c e₁)`
/// with `c = K s/m`, `u ← U(hc) u`, `(cos α, sin α)` rotated by `h s σ/I`.
/// The rotation about `e₁` and the rotation of `u` share one `sin_cos`.
#[inline(always)]
fn hand_drift(sys: &HandSys, y: &Hand, h: f64) -> Hand {
    let c = sys.inv_r * sys.inv_r * y.s * sys.inv_m;
    let xi = HandAlg {
        w: Vector3::new(c * h, -y.u[1] * sys.inv_r * h, y.u[0] * sys.inv_r * h),
        a: sys.rate * y.s * h,
        du: Vector2::zeros(),
        ds: 0.0,
    };
    let mut z = compose_exp(y, &xi);
    let (sn, cs) = (h * c).sin_cos();
    // Q·exp(−hc hat(e₁)): columns 1, 2 rotate by −hc.
    let (q1, q2): (Vector3<f64>, Vector3<f64>) = (z.q.column(1).into(), z.q.column(2).into());
    z.q.set_column(1, &(q1 * cs - q2 * sn));
    z.q.set_column(2, &(q1 * sn + q2 * cs));
    z.u = Vector2::new(cs * y.u[0] - sn * y.u[1], sn * y.u[0] + cs * y.u[1]);
    z
}

/// One Strang step `D(h/2) K(h) D(h/2)` (kick: `u ← u + h F̂/m`, the potential
/// does not depend on the frame), renormalised like [`hand_rkmk4`].
#[inline(always)]
fn hand_strang(sys: &HandSys, y: &Hand, h: f64) -> Hand {
    let mut z = hand_drift(sys, y, 0.5 * h);
    let f = sys.f(&z).du;
    let ks = sys.inv_r * sys.inv_r * z.s * sys.inv_m;
    // f.du = (F̂ + K s ε u)/m: remove the gyroscopic term to keep F̂/m.
    z.u += Vector2::new(f[0] + ks * z.u[1], f[1] - ks * z.u[0]) * h;
    let mut y1 = hand_drift(sys, &z, 0.5 * h);
    let d = y1.q.transpose() * y1.q - Matrix3::identity();
    y1.q -= y1.q * d * 0.5;
    y1.cs /= y1.cs.norm();
    y1
}

/// The hand-written right-hand side [`HandSys::f`] on the library's state
/// types, as a [`System`]: the library's RKMK4 step on it (row
/// `rkmk4_hand_rhs`) separates the cost of the generic stage machinery from
/// that of the generic right-hand side.
#[derive(Debug, Clone)]
struct HandRhs(HandSys);

impl System for HandRhs {
    type State = <S2Gyro as System>::State;
    #[inline(always)]
    fn vector_field(&self, _t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        let f = self.0.f(&Hand::of(y));
        ProductAlgebra(ProductAlgebra(f.w, Vector1::new(f.a)), Vector3::new(f.du[0], f.du[1], f.ds))
    }
    fn energy(&self, _y: &Self::State) -> f64 {
        f64::NAN
    }
    fn defect(&self, _y: &Self::State) -> f64 {
        f64::NAN
    }
}

/// The hand state and parameters of the library's S² reference state.
fn hand_of(r: &Reference<S2Gyro>) -> (HandSys, Hand) {
    let m = &r.system;
    let y = &r.y0;
    let radius = S2_RADIUS;
    let sys = HandSys {
        inv_r: 1.0 / radius,
        inv_m: 1.0 / S2_MASS,
        rate: 1.0 / m.moment_of_inertia(),
        grad: S2_A / radius,
    };
    (sys, Hand::of(y))
}

/// The baseline computes the library's RKMK4 step: compares after 10 steps.
fn check_hand(r: &Reference<S2Gyro>) {
    let (hs, mut hy) = hand_of(r);
    let mut y = r.y0;
    let m = Rkmk::rk4();
    for _ in 0..10 {
        hy = hand_rkmk4(&hs, &hy, H);
        y = m.step(&r.system, 0.0, &y, H, StepRequest::plain()).expect("step").y;
    }
    let dq = (hy.q - y.0 .0.matrix()).amax();
    let da = (hy.cs - Vector2::new(y.0 .1.cos(), y.0 .1.sin())).amax();
    let du = (hy.u - Vector2::new(y.1 .0[0], y.1 .0[1])).amax().max((hy.s - y.1 .0[2]).abs());
    let err = dq.max(da).max(du);
    assert!(err <= 1e-13, "hand-written RKMK4 differs from the library's by {err:e}");
}

/// The hand-written Strang step computes the library's `Splitting::strang`
/// step: compares after 10 steps (to 1e-13).
fn check_hand_strang(r: &Reference<S2Gyro>) {
    let (hs, mut hy) = hand_of(r);
    let mut y = r.y0;
    let m = Splitting::strang();
    for _ in 0..10 {
        hy = hand_strang(&hs, &hy, H);
        y = m.step(&r.system, 0.0, &y, H, StepRequest::plain()).expect("step").y;
    }
    let dq = (hy.q - y.0 .0.matrix()).amax();
    let da = (hy.cs - Vector2::new(y.0 .1.cos(), y.0 .1.sin())).amax();
    let du = (hy.u - Vector2::new(y.1 .0[0], y.1 .0[1])).amax().max((hy.s - y.1 .0[2]).abs());
    let err = dq.max(da).max(du);
    assert!(err <= 1e-13, "hand-written Strang differs from the library's by {err:e}");
}

// ---------------------------------------------------------------------------
// Benches
// ---------------------------------------------------------------------------

/// Runs `$body` with `$name`, `$m` bound to each RKMK method benched per
/// step (plain steps: no error estimate). The methods are different types
/// (`Rkmk<STAGES>`), hence a macro. Add further `Method` types here.
macro_rules! each_method {
    ($name:ident, $m:ident, $body:block) => {{
        { let ($name, $m) = ("lie_euler", Rkmk::lie_euler()); $body }
        { let ($name, $m) = ("heun", Rkmk::heun()); $body }
        { let ($name, $m) = ("kutta3", Rkmk::kutta3()); $body }
        { let ($name, $m) = ("rkmk4", Rkmk::rk4()); $body }
        { let ($name, $m) = ("dopri5", Rkmk::dopri5()); $body }
        { let ($name, $m) = ("butcher6", Rkmk::butcher6()); $body }
    }};
}

fn bench_system<S>(c: &mut Criterion, group: &str, sys: &S, y0: S::State)
where
    S: System,
    S::State: GroupNumerics,
{
    let mut g = c.benchmark_group(group);
    g.bench_function("rhs", |b| b.iter(|| black_box(sys.vector_field(0.0, black_box(&y0)))));
    each_method!(name, m, {
        g.bench_function(name, |b| {
            b.iter(|| black_box(m.step(sys, 0.0, black_box(&y0), H, StepRequest::plain()).map(|o| o.y).ok()))
        });
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    let r = s2_gyro();
    check_hand(&r);
    let (hs, hy) = hand_of(&r);
    c.bench_function("s2_gyroscope/hand_rkmk4", |b| b.iter(|| black_box(hand_rkmk4(&hs, black_box(&hy), H))));
    check_hand_strang(&r);
    c.bench_function("s2_gyroscope/hand_strang", |b| b.iter(|| black_box(hand_strang(&hs, black_box(&hy), H))));
    let strang = Splitting::strang();
    c.bench_function("s2_gyroscope/strang", |b| {
        b.iter(|| black_box(strang.step(&r.system, 0.0, black_box(&r.y0), H, StepRequest::plain()).map(|o| o.y).ok()))
    });
    c.bench_function("s2_gyroscope/hand_rhs", |b| b.iter(|| black_box(hs.f(black_box(&hy)))));
    bench_system(c, "s2_gyroscope", &r.system, r.y0);
    let r = s2_point();
    bench_system(c, "s2_point", &r.system, r.y0);
    let r = h2_gyro();
    bench_system(c, "h2_gyroscope", &r.system, r.y0);
    let r = h2_lorentz();
    bench_system(c, "h2_lorentz", &r.system, r.y0);
    let r = t2_gyro();
    bench_system(c, "t2_gyroscope", &r.system, r.y0);
    let r = s3_gyro();
    bench_system(c, "s3_gyroscope", &r.system, r.y0);
    let r = s2_affine();
    bench_system(c, "s2_affine", &r.system, r.y0);
    let r = t2_affine();
    bench_system(c, "t2_affine", &r.system, r.y0);
}

// ---------------------------------------------------------------------------
// Interleaved ratio table
// ---------------------------------------------------------------------------

/// Thread-CPU nanoseconds ([`thread_time`]): time the thread was descheduled
/// by other processes on the shared machine is not counted.
fn thread_ns() -> f64 {
    thread_time() * 1e9
}

/// Thread-CPU nanoseconds per call of `f` over `n` calls (the rounds are
/// interleaved with the baseline, and medians of ratios are reported).
fn ns_per(n: usize, mut f: impl FnMut()) -> f64 {
    let t0 = thread_ns();
    for _ in 0..n {
        f();
    }
    (thread_ns() - t0) / n as f64
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One row: per-step ns of `step` and of the baseline, alternating, 15 rounds.
fn ratio_row(hs: &HandSys, hy: &Hand, step: impl FnMut()) -> (f64, f64, f64) {
    ratio_row_against(
        || {
            black_box(hand_rkmk4(hs, black_box(hy), H));
        },
        step,
    )
}

/// As [`ratio_row`] against any baseline.
fn ratio_row_against(mut baseline: impl FnMut(), mut step: impl FnMut()) -> (f64, f64, f64) {
    let n = 20_000;
    let (mut own, mut base, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..15 {
        let b = ns_per(n, &mut baseline);
        let o = ns_per(n, &mut step);
        own.push(o);
        base.push(b);
        ratio.push(o / b);
    }
    (median(&mut own), median(&mut base), median(&mut ratio))
}

/// The energy projection of a state `1e-8` off its level in every algebra
/// coordinate (gradient, Newton steps) against one DOP853 step from the
/// state: the projection's cost per accepted step as a fraction of the
/// step's (`project = "energy"`; docs/performance.md, "Tolerance
/// proportionality").
fn projection_row<S>(sys: &S, y0: &S::State) -> (f64, f64, f64)
where
    S: System,
    S::State: GroupNumerics,
{
    let off = y0.compose(&S::State::exp(&S::State::algebra_from_coords(&vec![1e-8; S::State::DOF]))).renormalize();
    let e0 = sys.energy(y0);
    let mut stats = Stats::default();
    let _ = project_energy(sys, &off, e0, &mut stats);
    assert_eq!((stats.projections, stats.projections_skipped), (1, 0), "the projection runs in full");
    let m = Rkmk::dop853();
    ratio_row_against(
        || {
            black_box(m.step(sys, 0.0, black_box(y0), H, StepRequest::plain()).map(|o| o.y).ok());
        },
        || {
            black_box(project_energy(sys, black_box(&off), e0, &mut Stats::default()));
        },
    )
}

/// One `tangent_field` (along a direction with every coordinate non-zero)
/// against one `vector_field` of the same model.
fn tangent_field_row<S: System>(sys: &S, y0: &S::State) -> (f64, f64, f64) {
    let xi = S::State::algebra_from_coords(&(0..S::State::DOF).map(|i| 1.0 / (1.0 + i as f64)).collect::<Vec<_>>());
    assert!(sys.tangent_field(0.0, y0, &xi).is_some(), "the model has an exact tangent field");
    ratio_row_against(
        || {
            black_box(sys.vector_field(0.0, black_box(y0)));
        },
        || {
            black_box(sys.tangent_field(0.0, black_box(y0), black_box(&xi)));
        },
    )
}

/// One RKMK4 step carrying one tangent vector (exact, or differenced with
/// `differenced`) against one plain RKMK4 step of the same model.
fn tangent_row<S>(sys: &S, y0: &S::State, differenced: bool) -> (f64, f64, f64)
where
    S: System,
    S::State: GroupNumerics,
{
    use framedyn::analysis::{Linearisation, TangentFlow};
    let m = Rkmk::rk4();
    let lin = if differenced { Linearisation::default().differenced() } else { Linearisation::default() };
    let dof = S::State::DOF;
    let col = nalgebra::DMatrix::from_fn(dof, 1, |i, _| 1.0 / (1.0 + i as f64));
    let flow = TangentFlow::new(sys, &m, 0.0, *y0, col, lin).expect("tangent flow");
    assert_eq!(flow.linearisation().exact, !differenced, "the row measures what it names");
    ratio_row_against(
        || {
            black_box(m.step(sys, 0.0, black_box(y0), H, StepRequest::plain()).map(|o| o.y).ok());
        },
        || {
            let mut f = flow.clone();
            black_box(f.step(H).ok());
        },
    )
}

/// `FRAMEDYN_RATIOS_FILTER=<text>` keeps only the rows whose
/// `system/method` contains `<text>` (profiling one step); the CSV is then
/// not written.
fn filter() -> Option<String> {
    std::env::var("FRAMEDYN_RATIOS_FILTER").ok()
}

fn wanted(system: &str, method: &str) -> bool {
    filter().map_or(true, |f| format!("{system}/{method}").contains(&f))
}

fn ratio_table() {
    let r = s2_gyro();
    check_hand(&r);
    let (hs, hy) = hand_of(&r);
    let mut rows: Vec<(String, String, f64, f64, f64)> = Vec::new();
    macro_rules! system {
        ($name:expr, $sys:expr, $y0:expr) => {{
            let (sys, y0) = ($sys, $y0);
            if wanted($name, "rhs") {
                let (o, b, q) = ratio_row(&hs, &hy, || {
                    black_box(sys.vector_field(0.0, black_box(&y0)));
                });
                rows.push(($name.to_string(), "rhs".into(), o, b, q));
            }
            each_method!(mname, m, {
                if wanted($name, mname) {
                    let (o, b, q) = ratio_row(&hs, &hy, || {
                        black_box(m.step(&sys, 0.0, black_box(&y0), H, StepRequest::plain()).map(|o| o.y).ok());
                    });
                    rows.push(($name.to_string(), mname.into(), o, b, q));
                }
            });
            if wanted($name, "project_energy") {
                let (o, b, q) = projection_row(&sys, &y0);
                rows.push(($name.to_string(), "project_energy".into(), o, b, q));
            }
            if wanted($name, "tangent_field") {
                let (o, b, q) = tangent_field_row(&sys, &y0);
                rows.push(($name.to_string(), "tangent_field".into(), o, b, q));
            }
            for (row, differenced) in [("tangent_exact", false), ("tangent_differenced", true)] {
                if wanted($name, row) {
                    let (o, b, q) = tangent_row(&sys, &y0, differenced);
                    rows.push(($name.to_string(), row.into(), o, b, q));
                }
            }
        }};
    }
    let (o, b, q) = ratio_row(&hs, &hy, || {
        black_box(hand_rkmk4(&hs, black_box(&hy), H));
    });
    rows.push(("s2_gyroscope".into(), "hand_rkmk4".into(), o, b, q));
    let (o, b, q) = ratio_row(&hs, &hy, || {
        black_box(hs.f(black_box(&hy)));
    });
    rows.push(("s2_gyroscope".into(), "hand_rhs".into(), o, b, q));
    // The Strang target: library step against the hand-written Strang step.
    check_hand_strang(&r);
    let strang = Splitting::strang();
    let hand_strang_row = || {
        black_box(hand_strang(&hs, black_box(&hy), H));
    };
    let (o, b, q) = ratio_row(&hs, &hy, hand_strang_row);
    rows.push(("s2_gyroscope".into(), "hand_strang".into(), o, b, q));
    if wanted("s2_gyroscope", "strang") {
        let (o, b, q) = ratio_row(&hs, &hy, || {
            black_box(strang.step(&r.system, 0.0, black_box(&r.y0), H, StepRequest::plain()).map(|o| o.y).ok());
        });
        rows.push(("s2_gyroscope".into(), "strang".into(), o, b, q));
        let (o, b, q) = ratio_row_against(hand_strang_row, || {
            black_box(strang.step(&r.system, 0.0, black_box(&r.y0), H, StepRequest::plain()).map(|o| o.y).ok());
        });
        rows.push(("s2_gyroscope".into(), "strang_vs_hand_strang".into(), o, b, q));
    }
    system!("s2_gyroscope", r.system.clone(), r.y0);
    if wanted("s2_gyroscope", "rkmk4_hand_rhs") {
        // The library's RKMK4 step with the hand-written right-hand side.
        let (sys, m) = (HandRhs(hs), Rkmk::rk4());
        let y = m.step(&sys, 0.0, &r.y0, H, StepRequest::plain()).expect("step").y;
        let lib = m.step(&r.system, 0.0, &r.y0, H, StepRequest::plain()).expect("step").y;
        let d = (y.0 .0.matrix() - lib.0 .0.matrix()).amax().max((y.1 .0 - lib.1 .0).amax());
        assert!(d <= 1e-13, "the hand right-hand side differs from the library's: {d:e}");
        let (o, b, q) = ratio_row(&hs, &hy, || {
            black_box(m.step(&sys, 0.0, black_box(&r.y0), H, StepRequest::plain()).map(|o| o.y).ok());
        });
        rows.push(("s2_gyroscope".into(), "rkmk4_hand_rhs".into(), o, b, q));
    }
    // The same problem about a compile-time `Pole` (bit for bit the same
    // steps): the potential's axial coordinate is x₂ instead of a dot product
    // with a runtime row, as in the hand-written step.
    let rp = s2_gyro_pole();
    let same = |a: Option<<S2Gyro as System>::State>, b: Option<<S2Gyro as System>::State>, name: &str| {
        assert!(a.is_some() && a == b, "{name}: the step about a Pole differs from the step about the Centre");
    };
    let plain = StepRequest::plain;
    same(Rkmk::rk4().step(&r.system, 0.0, &r.y0, H, plain()).ok().map(|o| o.y), Rkmk::rk4().step(&rp.system, 0.0, &rp.y0, H, plain()).ok().map(|o| o.y), "rkmk4");
    same(strang.step(&r.system, 0.0, &r.y0, H, plain()).ok().map(|o| o.y), strang.step(&rp.system, 0.0, &rp.y0, H, plain()).ok().map(|o| o.y), "strang");
    if wanted("s2_gyroscope", "rkmk4_pole") {
        let m = Rkmk::rk4();
        let (o, b, q) = ratio_row(&hs, &hy, || {
            black_box(m.step(&rp.system, 0.0, black_box(&rp.y0), H, StepRequest::plain()).map(|o| o.y).ok());
        });
        rows.push(("s2_gyroscope".into(), "rkmk4_pole".into(), o, b, q));
    }
    if wanted("s2_gyroscope", "strang_pole") {
        let step = || {
            black_box(strang.step(&rp.system, 0.0, black_box(&rp.y0), H, StepRequest::plain()).map(|o| o.y).ok());
        };
        let (o, b, q) = ratio_row(&hs, &hy, step);
        rows.push(("s2_gyroscope".into(), "strang_pole".into(), o, b, q));
        let (o, b, q) = ratio_row_against(hand_strang_row, step);
        rows.push(("s2_gyroscope".into(), "strang_pole_vs_hand_strang".into(), o, b, q));
    }
    let r = s2_point();
    system!("s2_point", r.system.clone(), r.y0);
    let r = h2_gyro();
    system!("h2_gyroscope", r.system.clone(), r.y0);
    let r = h2_lorentz();
    system!("h2_lorentz", r.system.clone(), r.y0);
    let r = t2_gyro();
    system!("t2_gyroscope", r.system.clone(), r.y0);
    let r = s3_gyro();
    system!("s3_gyroscope", r.system.clone(), r.y0);
    let r = s2_affine();
    system!("s2_affine", r.system.clone(), r.y0);
    let r = t2_affine();
    system!("t2_affine", r.system.clone(), r.y0);

    if filter().is_some() {
        for (s, m, o, b, q) in &rows {
            println!("{s:<14} {m:<11} {o:>10.1} {b:>12.1} {q:>10.3}");
        }
        return;
    }
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/data/step_cost.csv");
    let _ = std::fs::create_dir_all(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/data"));
    let mut out = std::fs::File::create(path).expect("create docs/data/step_cost.csv");
    writeln!(out, "system,method,ns_per_call,baseline,baseline_ns,ratio_to_baseline").unwrap();
    println!("\n{:<14} {:<11} {:>10} {:>12} {:>10}", "system", "call", "ns/call", "baseline ns", "ratio");
    for (s, m, o, b, q) in &rows {
        let base = if m.ends_with("_vs_hand_strang") {
            "hand_strang"
        } else if m == "project_energy" {
            "dop853"
        } else if m == "tangent_field" {
            "rhs"
        } else if m.starts_with("tangent_") {
            "rkmk4"
        } else {
            "hand_rkmk4"
        };
        writeln!(out, "{s},{m},{o:.1},{base},{b:.1},{q:.3}").unwrap();
        println!("{s:<14} {m:<11} {o:>10.1} {b:>12.1} {q:>10.3}");
    }
    println!("written: docs/data/step_cost.csv");
}

fn main() {
    let bench_mode = std::env::args().any(|a| a == "--bench");
    let ratios_only = std::env::var_os("FRAMEDYN_RATIOS_ONLY").is_some();
    if !(bench_mode && ratios_only) {
        let mut c = Criterion::default()
            .warm_up_time(std::time::Duration::from_millis(300))
            .measurement_time(std::time::Duration::from_millis(1000))
            .sample_size(20)
            .configure_from_args();
        benches(&mut c);
        c.final_summary();
    }
    if bench_mode {
        ratio_table();
    }
}
