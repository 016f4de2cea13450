//! Reference problems and the method table shared by the criterion benches
//! (`benches/step_cost.rs`) and the work-precision harness
//! (`examples/work_precision.rs`, driven by `scripts/work_precision.py`).
//!
//! A reference problem is a model, an initial state, a time span, and three
//! read-outs: an ambient *observable* (position, velocity, body frame,
//! internal momentum — the same numbers whatever the formulation, so that a
//! coordinate solver can be compared with the group form), the conserved
//! momentum map and the energy (from [`System::energy`]).
//!
//! **Adding a method.** The table [`rkmk_table`] lists `(name, runner)`
//! pairs; a runner solves a [`Reference`] at one step size or tolerance and
//! returns an [`Outcome`]. Any type implementing [`Method<S>`] is added with
//! one line, e.g. for a splitting method that only exists for the S²
//! gyroscope, in `examples/work_precision.rs` (function `s2_entries`):
//! `t.push(fixed("Strang", 2, Strang::new()));`. Coordinate baselines push an
//! [`Entry`] whose runner integrates their own state and maps it to the
//! observable (see `coords_rk4` in the example).
#![allow(dead_code)]

use framedyn::body::{Affine, Gyroscope, Point, Signature};
use framedyn::dynamics::affine::AffineModel;
use framedyn::dynamics::point::bundle_element_at;
use framedyn::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use framedyn::lie::{LieGroup, So3};
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2, Sphere3, Torus2};
use framedyn::method::{GroupNumerics, Method, Rkmk};
use framedyn::potential::{Axis, Centre, CosineFamily, Elastic, Pole, Potential, Scalar, Sum};
use framedyn::solve::{solve, Options, Problem, Save, Stepper};
use nalgebra::{Matrix2, Matrix3, Matrix4, SMatrix, SVector, Vector2, Vector3};

/// `V = a·x_z`: a uniform field along the ambient z axis (on the torus the
/// symmetry axis, so `p_φ` is conserved).
#[derive(Debug, Clone, Copy)]
pub struct ZField {
    /// Field strength `a`.
    pub a: f64,
}

impl<const N: usize, const E: usize> Potential<N, E> for ZField {
    fn uses_frame(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _m: &SMatrix<f64, E, E>) -> D {
        x[2] * self.a
    }
}

/// A reference problem: model, initial state, span and read-outs.
#[derive(Clone)]
pub struct Reference<S: System> {
    /// Short name (CSV key).
    pub name: &'static str,
    /// One-line description for the docs.
    pub about: &'static str,
    /// The model.
    pub system: S,
    /// Initial state.
    pub y0: S::State,
    /// Final time (t₀ = 0).
    pub t_end: f64,
    /// Ambient observable: position, velocity, body frame, internal momentum.
    pub observable: fn(&S, &S::State) -> Vec<f64>,
    /// A conserved momentum map (Noether charge of the potential's symmetry).
    pub momentum: fn(&S, &S::State) -> f64,
}

impl<S: System + Clone> Reference<S>
where
    S::State: GroupNumerics,
{
    /// The solve problem.
    pub fn problem(&self) -> Problem<S> {
        Problem::new(self.system.clone(), self.y0, (0.0, self.t_end)).expect("valid reference problem")
    }
}

/// Thread-CPU seconds (`CLOCK_THREAD_CPUTIME_ID`, as Python's
/// `time.thread_time()`): time the thread was descheduled by other processes
/// on the shared machine is not counted. Shared by the benches and the
/// timing examples.
pub fn thread_time() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Max-norm distance of two observables.
pub fn obs_dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------
// The models
// ---------------------------------------------------------------------------

/// S² gyroscope in `V = a cos(r/R)` (the centre a runtime [`Centre`], as
/// scenes and Python build it).
pub type S2Gyro = Gyroscope2Model<Sphere2, CosineFamily<3>>;
/// The same with the centre a compile-time [`Pole`] (same numbers bit for
/// bit; the step-cost bench's `*_pole` rows).
pub type S2GyroPole = Gyroscope2Model<Sphere2, CosineFamily<3, Pole<3>>>;
/// H² gyroscope in `V = a cosh(r/R)`.
pub type H2Gyro = Gyroscope2Model<Hyperbolic2, CosineFamily<3>>;
/// T² gyroscope in a uniform field along the symmetry axis.
pub type T2Gyro = Gyroscope2Model<Torus2, ZField>;
/// S³ gyroscope in `V = a cos(r/R)`.
pub type S3Gyro = Gyroscope3Model<Sphere3, CosineFamily<4>>;
/// Affine body on S²: elastic (a131) plus `a cos(r/R)`.
pub type S2Affine = AffineModel<Sphere2, Sum<Elastic, CosineFamily<3>>, 2, 3>;
/// Affine body on T²: elastic (a131) plus a uniform field.
pub type T2Affine = AffineModel<Torus2, Sum<Elastic, ZField>, 2, 3>;
/// Structureless point on S² in `V = a cos(r/R)`.
pub type S2Point = PointModel<Sphere2, CosineFamily<3>, 2, 3>;

fn gyro2_obs<B: framedyn::bundle::FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &Gyroscope2Model<B, P>,
    y: &<Gyroscope2Model<B, P> as System>::State,
) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.push(m.spin(y));
    v
}

fn gyro2_pphi<B: framedyn::bundle::FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &Gyroscope2Model<B, P>,
    y: &<Gyroscope2Model<B, P> as System>::State,
) -> f64 {
    m.p_phi(y)
}

fn affine_obs<B: framedyn::bundle::FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &AffineModel<B, P, 2, 3>,
    y: &<AffineModel<B, P, 2, 3> as System>::State,
) -> Vec<f64> {
    let mut v: Vec<f64> = m.position(y).iter().copied().collect();
    v.extend(m.velocity(y).iter());
    v.extend(m.body_frame(y).iter());
    v.extend(m.rho_dot(y).iter());
    v
}

fn affine_pphi<B: framedyn::bundle::FrameBundle<2, 3>, P: Potential<2, 3>>(
    m: &AffineModel<B, P, 2, 3>,
    y: &<AffineModel<B, P, 2, 3> as System>::State,
) -> f64 {
    m.p_phi(y)
}

/// Parameters of the SPEC §5 problem: m = 1, R = 1, I = 0.3, V = a cos(r/R).
pub const S2_MASS: f64 = 1.0;
/// Radius.
pub const S2_RADIUS: f64 = 1.0;
/// Moment of inertia `I`.
pub const S2_MOMENT: f64 = 0.3;
/// Field strength `a`.
pub const S2_A: f64 = 0.5;
/// Initial chart state `(r, φ, ψ)` and rates `(ṙ, φ̇, ψ̇ + cos(r/R) φ̇ = ω)`:
/// the chart position and velocity, the internal angle and the angular
/// velocity ω of (a91).
pub const S2_Q0: [f64; 3] = [1.0, 0.3, 0.4];
/// `(ṙ, φ̇)` and `ω`.
pub const S2_V0: [f64; 3] = [0.3, 0.6, 1.0];

/// The S² gyroscope of SPEC §5 (m = 1, R = 1, I = 0.3, V = 0.5 cos(r/R)),
/// over `t_end` (100 in the SPEC).
pub fn s2_gyro_with(a: f64, radius: f64, q0: [f64; 3], v0: [f64; 3], t_end: f64, name: &'static str) -> Reference<S2Gyro> {
    s2_gyro_about(Centre::sphere2, a, radius, q0, v0, t_end, name)
}

/// [`s2_gyro_with`] with the potential's centre built by `centre` (a
/// [`Centre`] or a [`Pole`]).
pub fn s2_gyro_about<C: Axis<3>>(
    centre: fn(&Sphere2) -> C,
    a: f64,
    radius: f64,
    q0: [f64; 3],
    v0: [f64; 3],
    t_end: f64,
    name: &'static str,
) -> Reference<Gyroscope2Model<Sphere2, CosineFamily<3, C>>> {
    let s2 = Sphere2::new(radius).unwrap();
    let pot = CosineFamily::new(0.0, a, centre(&s2)).unwrap();
    let m = Gyroscope2Model::new(s2, Gyroscope::<2>::isotropic(S2_MASS, S2_MOMENT).unwrap(), pot).unwrap();
    let x = Vector2::new(q0[0], q0[1]);
    let (p, v) = (s2.embed(&x), s2.embed_tangent(&x, &Vector2::new(v0[0], v0[1])));
    let spin = m.spin_for_angular_velocity(v0[2]);
    let y0 = m.state_at(&p, &v, q0[2], spin).unwrap();
    Reference {
        name,
        about: "S² gyroscope, m = 1, R = 1, I = 0.3, V = 0.5 cos(r/R) (SPEC §5)",
        system: m,
        y0,
        t_end,
        observable: gyro2_obs,
        momentum: gyro2_pphi,
    }
}

/// SPEC §5: the S² gyroscope, T = 100.
pub fn s2_gyro() -> Reference<S2Gyro> {
    s2_gyro_with(S2_A, S2_RADIUS, S2_Q0, S2_V0, 100.0, "s2_gyro")
}

/// [`s2_gyro`] about a compile-time [`Pole`].
pub fn s2_gyro_pole() -> Reference<S2GyroPole> {
    s2_gyro_about(Pole::sphere2, S2_A, S2_RADIUS, S2_Q0, S2_V0, 100.0, "s2_gyro")
}

/// The S² gyroscope in a well at the pole, `V = −0.5 cos(r/R)`, starting
/// 1e-6 R from the pole and moving radially: it swings through the
/// neighbourhood of the pole (T = 20).
pub fn s2_pole() -> Reference<S2Gyro> {
    let mut r = s2_gyro_with(-0.5, 1.0, [1e-6, 0.3, 0.4], [1.0, 0.0, 1.0], 20.0, "s2_pole");
    r.about = "S² gyroscope, V = −0.5 cos(r/R), start 1e-6 R from the pole moving radially";
    r
}

fn h2_gyro_sig(sig: Signature, name: &'static str, about: &'static str) -> Reference<H2Gyro> {
    let h2 = Hyperbolic2::new(1.0).unwrap();
    let pot = CosineFamily::new(0.0, 0.5, Centre::hyperbolic2(&h2)).unwrap();
    let body = Gyroscope::<2>::isotropic(1.0, 0.3).unwrap().with_signature(sig);
    let m = Gyroscope2Model::new(h2, body, pot).unwrap();
    let x = Vector2::new(0.7, 0.3);
    let (p, v) = (h2.embed(&x), h2.embed_tangent(&x, &Vector2::new(0.4, 0.9)));
    let spin = m.spin_for_angular_velocity(1.0);
    let y0 = m.state_at(&p, &v, 0.4, spin).unwrap();
    Reference { name, about, system: m, y0, t_end: 20.0, observable: gyro2_obs, momentum: gyro2_pphi }
}

/// H² gyroscope (R = 1, m = 1, I = 0.3) confined by `V = 0.5 cosh(r/R)`, T = 20.
pub fn h2_gyro() -> Reference<H2Gyro> {
    h2_gyro_sig(Signature::Riemannian, "h2_gyro", "H² gyroscope, I = 0.3, V = 0.5 cosh(r/R)")
}

/// The same with the Lorentz-type internal energy (a138).
pub fn h2_lorentz() -> Reference<H2Gyro> {
    h2_gyro_sig(Signature::Lorentz, "h2_lorentz", "H² Lorentz-type gyroscope (a138), I = 0.3, V = 0.5 cosh(r/R)")
}

/// T²(L = 2, R = 0.7) gyroscope (m = 1, I = 0.3) in `V = 0.8 z`, T = 20.
pub fn t2_gyro() -> Reference<T2Gyro> {
    let t2 = Torus2::new(2.0, 0.7).unwrap();
    let m = Gyroscope2Model::new(t2, Gyroscope::<2>::isotropic(1.0, 0.3).unwrap(), ZField { a: 0.8 }).unwrap();
    let x = Vector2::new(0.6, 0.2);
    let (p, v) = (t2.embed(&x), t2.embed_tangent(&x, &Vector2::new(0.9, 0.4)));
    let spin = m.spin_for_angular_velocity(1.0);
    let y0 = m.state_at(&p, &v, 0.4, spin).unwrap();
    Reference {
        name: "t2_gyro",
        about: "T²(L = 2, R = 0.7) gyroscope, I = 0.3, V = 0.8 z",
        system: m,
        y0,
        t_end: 20.0,
        observable: gyro2_obs,
        momentum: gyro2_pphi,
    }
}

/// The (x₂, x₃)-plane rotation of ℝ⁴, a symmetry of `V = a cos(r/R)` about
/// the centre `(R, 0, 0, 0)`.
fn s3_generator() -> Matrix4<f64> {
    let mut a = Matrix4::zeros();
    a[(3, 2)] = 1.0;
    a[(2, 3)] = -1.0;
    a
}

/// S³ gyroscope (R = 1, m = 1, J = diag(0.2, 0.35, 0.5)) in `V = 0.5 cos(r/R)`, T = 20.
pub fn s3_gyro() -> Reference<S3Gyro> {
    let s3 = Sphere3::new(1.0).unwrap();
    let body = Gyroscope::<3>::new(1.0, Matrix3::from_diagonal(&Vector3::new(0.2, 0.35, 0.5))).unwrap();
    let pot = CosineFamily::new(0.0, 0.5, Centre::sphere3(&s3)).unwrap();
    let m = Gyroscope3Model::new(s3, body, pot).unwrap();
    let x = Vector3::new(0.5, -0.3, 0.4);
    let (p, v) = (s3.embed(&x), s3.embed_tangent(&x, &Vector3::new(0.3, 0.5, -0.4)));
    let rho = So3::exp(&Vector3::new(0.2, -0.1, 0.3));
    let y0 = m.state_at(&p, &v, &rho, &Vector3::new(0.4, -0.3, 0.5)).unwrap();
    fn obs(m: &S3Gyro, y: &<S3Gyro as System>::State) -> Vec<f64> {
        let mut v: Vec<f64> = m.position(y).iter().copied().collect();
        v.extend(m.velocity(y).iter());
        v.extend(m.body_frame(y).iter());
        v.extend(m.spin(y).iter());
        v
    }
    fn mom(m: &S3Gyro, y: &<S3Gyro as System>::State) -> f64 {
        m.momentum_map(y, &s3_generator()).unwrap_or(f64::NAN)
    }
    Reference {
        name: "s3_gyro",
        about: "S³ gyroscope, J = diag(0.2, 0.35, 0.5), V = 0.5 cos(r/R)",
        system: m,
        y0,
        t_end: 20.0,
        observable: obs,
        momentum: mom,
    }
}

/// The affine bodies' inertia `J` (as in the test suite).
pub fn affine_inertia() -> Matrix2<f64> {
    Matrix2::new(0.3, 0.07, 0.07, 0.15)
}

/// Affine body on S² (m = 1, J as [`affine_inertia`]) in the elastic
/// potential (a131) with stiffness `kappa` plus `0.5 cos(r/R)`, T = 20.
pub fn s2_affine_kappa(kappa: f64) -> Reference<S2Affine> {
    let s2 = Sphere2::new(1.0).unwrap();
    let pot = Sum::new(Elastic::new(kappa).unwrap(), CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2)).unwrap());
    let m = AffineModel::new(s2, Affine::new(1.0, affine_inertia()).unwrap(), pot).unwrap();
    let g = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2))).unwrap();
    let y0 = m
        .state(&g, &Matrix2::new(1.1, 0.3, -0.2, 0.8), &Vector2::new(0.6, -0.9), &Matrix2::new(0.4, -0.6, 0.5, 0.2))
        .unwrap();
    Reference {
        name: "s2_affine",
        about: "S² affine body, elastic κ = 1 (a131) + 0.5 cos(r/R)",
        system: m,
        y0,
        t_end: 20.0,
        observable: affine_obs,
        momentum: affine_pphi,
    }
}

/// [`s2_affine_kappa`] with κ = 1.
pub fn s2_affine() -> Reference<S2Affine> {
    s2_affine_kappa(1.0)
}

/// Affine body on T²(L = 2, R = 0.7) in the elastic potential (κ = 1) plus
/// `0.8 z`, T = 20.
pub fn t2_affine() -> Reference<T2Affine> {
    let t2 = Torus2::new(2.0, 0.7).unwrap();
    let pot = Sum::new(Elastic::new(1.0).unwrap(), ZField { a: 0.8 });
    let m = AffineModel::new(t2, Affine::new(1.0, affine_inertia()).unwrap(), pot).unwrap();
    let g = bundle_element_at(&t2, &t2.embed(&Vector2::new(0.6, 0.2))).unwrap();
    let y0 = m
        .state(&g, &Matrix2::new(1.1, 0.3, -0.2, 0.8), &Vector2::new(0.6, -0.9), &Matrix2::new(0.4, -0.6, 0.5, 0.2))
        .unwrap();
    Reference {
        name: "t2_affine",
        about: "T²(L = 2, R = 0.7) affine body, elastic κ = 1 + 0.8 z",
        system: m,
        y0,
        t_end: 20.0,
        observable: affine_obs,
        momentum: affine_pphi,
    }
}

/// A structureless point on S² in `V = 0.5 cos(r/R)` (benches only).
pub fn s2_point() -> (S2Point, <S2Point as System>::State) {
    let s2 = Sphere2::new(1.0).unwrap();
    let pot = CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2)).unwrap();
    let m: S2Point = PointModel::new(s2, Point::new(1.0).unwrap(), pot).unwrap();
    let x = Vector2::new(1.0, 0.3);
    let y0 = m.state(&s2.embed(&x), &s2.embed_tangent(&x, &Vector2::new(0.3, 0.6))).unwrap();
    (m, y0)
}

// ---------------------------------------------------------------------------
// Running a method: the table
// ---------------------------------------------------------------------------

/// The result of one run at one setting.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// Observable at `t_end` (empty on failure).
    pub obs: Vec<f64>,
    /// Thread-CPU seconds of the timed run (minimum over repeats).
    pub cpu: f64,
    /// Vector-field evaluations.
    pub rhs: usize,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// `max |E(t) − E(0)|` over the accepted steps.
    pub energy_drift: f64,
    /// `max |J(t) − J(0)|` of the momentum map over the accepted steps.
    pub momentum_drift: f64,
    /// Largest [`System::defect`] over the accepted steps.
    pub defect: f64,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

/// A runner: solves a reference at a step size (fixed methods) or a
/// tolerance (adaptive ones), timed with `clock` (a thread-CPU clock in
/// seconds).
pub type Runner<S> = Box<dyn Fn(&Reference<S>, f64, &dyn Fn() -> f64) -> Outcome>;

/// One row of the method table.
pub struct Entry<S: System> {
    /// Method name (CSV key).
    pub name: &'static str,
    /// Order (of the propagated solution).
    pub order: u32,
    /// `true`: the setting is a tolerance; `false`: a step size.
    pub adaptive: bool,
    /// The runner.
    pub run: Runner<S>,
}

/// Minimum thread-CPU time of `f` over repeats (at least one run, repeats
/// until 0.05 s have been spent or 5 runs), and the last result.
pub fn timed<T>(clock: &dyn Fn() -> f64, mut f: impl FnMut() -> T) -> (f64, T) {
    let (mut best, mut spent, mut k) = (f64::INFINITY, 0.0, 0);
    loop {
        let t0 = clock();
        let r = f();
        let dt = clock() - t0;
        best = best.min(dt);
        spent += dt;
        k += 1;
        if spent >= 0.05 || k >= 5 {
            return (best, r);
        }
    }
}

/// Runs a group method with `n = ⌈T/h⌉` fixed steps: timed pass through
/// [`solve`] (final state only), then an untimed pass with a [`Stepper`]
/// recording energy, momentum and defect after every step.
pub fn run_fixed<S, M>(r: &Reference<S>, method: &M, h: f64, clock: &dyn Fn() -> f64) -> Outcome
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let problem = r.problem();
    let opts = Options::fixed(h).save(Save::Ends).max_steps(usize::MAX);
    let (cpu, res) = timed(clock, || solve(&problem, method, &opts));
    let sol = match res {
        Ok(s) => s,
        Err(f) => return Outcome { cpu, failure: Some(format!("{}", f.error)), ..Outcome::default() },
    };
    let mut out = Outcome {
        obs: (r.observable)(&r.system, sol.last().1),
        cpu,
        rhs: sol.stats().rhs_evals,
        steps: sol.stats().accepted,
        rejected: sol.stats().rejected,
        ..Outcome::default()
    };
    let n = (r.t_end / h).ceil() as usize;
    let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
    let mut st = Stepper::new(r.system.clone(), method.clone(), 0.0, r.y0).expect("stepper");
    let hh = r.t_end / n as f64;
    for _ in 0..n {
        if st.step(hh).is_err() {
            break;
        }
        let y = st.state();
        out.energy_drift = out.energy_drift.max((r.system.energy(y) - e0).abs());
        out.momentum_drift = out.momentum_drift.max(((r.momentum)(&r.system, y) - j0).abs());
        out.defect = out.defect.max(r.system.defect(y));
    }
    out
}

/// Runs a group method adaptively at `rtol = atol = tol`: timed pass (final
/// state only), then an untimed pass saving every step for the invariants.
pub fn run_adaptive<S, M>(r: &Reference<S>, method: &M, tol: f64, clock: &dyn Fn() -> f64) -> Outcome
where
    S: System + Clone,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let problem = r.problem();
    let opts = Options::adaptive(tol, tol).save(Save::Ends).max_steps(10_000_000);
    let (cpu, res) = timed(clock, || solve(&problem, method, &opts));
    let sol = match res {
        Ok(s) => s,
        Err(f) => return Outcome { cpu, failure: Some(format!("{}", f.error)), ..Outcome::default() },
    };
    let mut out = Outcome {
        obs: (r.observable)(&r.system, sol.last().1),
        cpu,
        rhs: sol.stats().rhs_evals,
        steps: sol.stats().accepted,
        rejected: sol.stats().rejected,
        ..Outcome::default()
    };
    let opts = Options::adaptive(tol, tol).save(Save::Steps).max_steps(10_000_000);
    if let Ok(sol) = solve(&problem, method, &opts) {
        let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
        for y in sol.states() {
            out.energy_drift = out.energy_drift.max((r.system.energy(y) - e0).abs());
            out.momentum_drift = out.momentum_drift.max(((r.momentum)(&r.system, y) - j0).abs());
            out.defect = out.defect.max(r.system.defect(y));
        }
    }
    out
}

/// A fixed-step table entry for any [`Method`].
pub fn fixed<S, M>(name: &'static str, order: u32, method: M) -> Entry<S>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
    M: Method<S> + 'static,
{
    Entry { name, order, adaptive: false, run: Box::new(move |r, h, c| run_fixed(r, &method, h, c)) }
}

/// An adaptive table entry for any [`Method`] with an embedded pair.
pub fn adaptive<S, M>(name: &'static str, order: u32, method: M) -> Entry<S>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
    M: Method<S> + 'static,
{
    Entry { name, order, adaptive: true, run: Box::new(move |r, tol, c| run_adaptive(r, &method, tol, c)) }
}

/// The RKMK family on any system: Lie–Euler, Heun, Kutta 3, RK4
/// (two-commutator RKMK4), Butcher 6 with fixed steps, DOPRI5 adaptive.
/// Methods for every system are added here; system-specific ones (splittings
/// of the S² gyroscope, coordinate baselines) in the example's per-problem
/// functions.
pub fn rkmk_table<S>() -> Vec<Entry<S>>
where
    S: System + Clone + 'static,
    S::State: GroupNumerics,
{
    vec![
        fixed("lie_euler", 1, Rkmk::lie_euler()),
        fixed("heun", 2, Rkmk::heun()),
        fixed("kutta3", 3, Rkmk::kutta3()),
        fixed("rkmk4", 4, Rkmk::rk4()),
        fixed("dopri5_fixed", 5, Rkmk::dopri5()),
        fixed("butcher6", 6, Rkmk::butcher6()),
        adaptive("dopri5", 5, Rkmk::dopri5()),
    ]
}

/// Step sizes for a method of order `p` over a span: from coarse (error
/// ≈ 1e-2) to the round-off floor, 2^{1/2} apart, capped at `max_steps`.
pub fn step_ladder(p: u32, t_end: f64, max_steps: f64) -> Vec<f64> {
    // Coarsest step: where the methods of each order start to be accurate on
    // the reference problems (|f| ~ 1); finest: 1e-12-ish error or budget.
    let (h_max, h_min): (f64, f64) = match p {
        1 => (0.05, 1e-4),
        2 => (0.2, 2e-4),
        3 => (0.3, 1e-3),
        4 => (0.5, 2e-3),
        5 => (0.6, 5e-3),
        _ => (0.8, 1e-2),
    };
    let h_min = h_min.max(t_end / max_steps);
    let mut v = Vec::new();
    let mut h = h_max;
    while h >= h_min * 0.999 {
        v.push(h);
        h /= 2f64.sqrt();
    }
    v
}

/// Tolerances for adaptive methods: 1e-3 … 1e-12 in half decades.
pub fn tol_ladder() -> Vec<f64> {
    (6..=24).map(|k| 10f64.powf(-(k as f64) / 2.0)).collect()
}
