//! Data for the figures of `docs/validation.md` (issue 8: reproducing the
//! paper's claims of §5–§6). Heavier sweeps than the tests in
//! `tests/suite/validation*.rs`, same models and integrator (adaptive
//! DOPRI5 on the frame bundle, events on the dense output).
//!
//! Run (regenerates every figure):
//! ```text
//! cargo run --example validation_figures && python3 scripts/validation_figures.py
//! ```
//! Writes CSV files to `out/validation/`; the script turns them into PNGs in
//! `docs/figures/`.

use std::f64::consts::PI;
use std::fs::{create_dir_all, File};
use std::io::{BufWriter, Write};

use framedyn::body::{Gyroscope, Point};
use framedyn::bundle::FrameBundle;
use framedyn::dynamics::{Gyroscope2Model, PointModel, System};
use framedyn::manifold::{Hyperbolic2, Manifold, Sphere2};
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::potential::{Central, Centre, Free, Kepler, Oscillator, Potential, RadialFunction, Scalar};
use framedyn::solve::{solve, Direction, Event, Options, Problem, Save, Solution};
use nalgebra::{Vector2, Vector3};

const M: f64 = 1.3;
const R: f64 = 1.2;
const KAPPA: f64 = 0.8;
const ALPHA: f64 = 0.7;
const OUT: &str = "out/validation";

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// `V = (κ/2) r²` in the geodesic distance (not Bertrand).
#[derive(Debug, Clone, Copy)]
struct GeodesicHarmonic(f64);
impl RadialFunction for GeodesicHarmonic {
    fn v<D: Scalar>(&self, r: D) -> D {
        r * r * (0.5 * self.0)
    }
}

fn run<S>(sys: &S, y0: S::State, t_end: f64, tol: f64, configure: impl FnOnce(Options<S::State>) -> Options<S::State>) -> Res<Solution<S::State>>
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let problem = Problem::new(sys.clone(), y0, (0.0, t_end))?;
    solve(&problem, &Rkmk::dopri5(), &configure(Options::adaptive(tol, tol))).map_err(|f| format!("solve failed: {:?}", f.error).into())
}

fn csv(name: &str, header: &str) -> Res<BufWriter<File>> {
    let mut f = BufWriter::new(File::create(format!("{OUT}/{name}.csv"))?);
    writeln!(f, "{header}")?;
    Ok(f)
}

fn point_at<B: FrameBundle<2, 3> + Clone, P: Potential<2, 3>>(b: B, pot: P, r0: f64, rdot: f64, phidot: f64) -> Res<(PointModel<B, P, 2, 3>, framedyn::dynamics::PointState<B::Group, 2>)> {
    let model = PointModel::new(b.clone(), Point::new(M)?, pot)?;
    let x = Vector2::new(r0, 0.0);
    let y0 = model.state(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(rdot, phidot)))?;
    Ok((model, y0))
}

/// Orbits (ambient x, y, z sampled densely) of the Bertrand and a
/// non-Bertrand potential on S² and H².
fn orbits() -> Res<()> {
    let mut f = csv("orbits", "case,t,x,y,z")?;
    let s2 = Sphere2::new(R)?;
    let h2 = Hyperbolic2::new(R)?;
    let times: Vec<f64> = (0..=4000).map(|k| k as f64 * 0.01).collect();
    let mut write = |case: &str, pts: Vec<(f64, Vector3<f64>)>| -> Res<()> {
        for (t, p) in pts {
            writeln!(f, "{case},{t},{},{},{}", p[0], p[1], p[2])?;
        }
        Ok(())
    };
    macro_rules! orbit {
        ($case:expr, $b:expr, $pot:expr, $scale:expr) => {{
            let (m, y0) = point_at($b, $pot, 0.8, 0.3 * $scale, 0.5 * $scale)?;
            let sol = run(&m, y0, 40.0, 1e-11, |o| o.save(Save::At(times.clone())))?;
            write($case, sol.times().iter().zip(sol.states()).map(|(t, y)| (*t, m.position(y))).collect())?;
        }};
    }
    orbit!("S2 oscillator", s2, Oscillator::new(KAPPA, Centre::sphere2(&s2))?, 1.0);
    orbit!("S2 Kepler", s2, Kepler::new(ALPHA, Centre::sphere2(&s2))?, 1.0);
    orbit!("S2 (κ/2)r² (not Bertrand)", s2, Central::new(GeodesicHarmonic(KAPPA), Centre::sphere2(&s2)), 1.0);
    orbit!("H2 oscillator", h2, Oscillator::new(KAPPA, Centre::hyperbolic2(&h2))?, 0.5);
    orbit!("H2 Kepler", h2, Kepler::new(ALPHA, Centre::hyperbolic2(&h2))?, 0.5);
    orbit!("H2 (κ/2)r² (not Bertrand)", h2, Central::new(GeodesicHarmonic(KAPPA), Centre::hyperbolic2(&h2)), 0.5);
    Ok(())
}

/// Distance from the centre against time for the H² oscillator at energies
/// around the threshold `κR²/2`.
fn h2_threshold() -> Res<()> {
    let mut f = csv("h2_threshold", "ratio,t,r")?;
    let h2 = Hyperbolic2::new(R)?;
    let sup = 0.5 * KAPPA * R * R;
    let (r0, ell) = (0.6, 0.25);
    let sh0 = (r0 / R).sinh();
    let phidot = ell / (M * R * R * sh0 * sh0);
    let times: Vec<f64> = (0..=1500).map(|k| k as f64 * 0.02).collect();
    for ratio in [0.5, 0.8, 0.95, 1.0 - 1e-3, 1.0 + 1e-3, 1.05, 1.5] {
        let e = ratio * sup;
        let v0 = 0.5 * KAPPA * R * R * (r0 / R).tanh().powi(2);
        let rdot = (2.0 * (e - v0) / M - (R * sh0 * phidot).powi(2)).sqrt();
        let (m, y0) = point_at(h2, Oscillator::new(KAPPA, Centre::hyperbolic2(&h2))?, r0, rdot, phidot)?;
        let sol = match run(&m, y0, 30.0, 1e-11, |o| o.save(Save::At(times.clone()))) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("H2 threshold ratio {ratio}: {e}");
                continue;
            }
        };
        for (t, y) in sol.times().iter().zip(sol.states()) {
            let z = m.position(y)[2];
            writeln!(f, "{ratio},{t},{}", R * (z / R).max(1.0).acosh())?;
        }
    }
    Ok(())
}

/// Periapsis azimuths of a gyroscope on S² in `pot`, started at
/// `(r, φ) = (0.8, 0)` with `(ṙ, φ̇) = (0.3, 0.5)` and spin `s`: mean
/// precession per radial period relative to `base`.
fn precession<P: Potential<2, 3> + Clone + 'static>(pot: P, s: f64, base: f64) -> Res<f64> {
    let b = Sphere2::new(R)?;
    let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(M, 0.3)?, pot)?;
    let x = Vector2::new(0.8, 0.0);
    let y0 = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(0.3, 0.5)), 0.0, s)?;
    let mm = model.clone();
    let sol = run(&model, y0, 60.0, 1e-12, |o| {
        o.save(Save::Ends).event(Event::new("periapsis", move |_, y| mm.velocity(y)[2]).direction(Direction::Falling)).event_tolerance(1e-14)
    })?;
    let az: Vec<f64> = sol.events().iter().map(|e| {
        let p = model.position(&e.y);
        p[1].atan2(p[0])
    }).collect();
    let n = az.len() - 1;
    Ok((0..n)
        .map(|i| {
            let d = az[i + 1] - az[i] - base;
            d - 2.0 * PI * (d / (2.0 * PI)).round()
        })
        .sum::<f64>()
        / n as f64)
}

fn precession_vs_spin() -> Res<()> {
    let mut f = csv("precession", "potential,spin,precession")?;
    let b = Sphere2::new(R)?;
    for k in -12..=12 {
        let s = 0.025 * k as f64;
        let pk = precession(Kepler::new(ALPHA, Centre::sphere2(&b))?, s, 2.0 * PI)?;
        let po = precession(Oscillator::new(KAPPA, Centre::sphere2(&b))?, s, PI)?;
        writeln!(f, "Kepler,{s},{pk}")?;
        writeln!(f, "oscillator,{s},{po}")?;
        println!("spin {s:+.3}: precession per radial period Kepler {pk:+.6}, oscillator {po:+.6}");
    }
    Ok(())
}

/// Free gyroscope paths on S² for several spins (the geodesic for s = 0).
fn gyro_paths() -> Res<()> {
    let mut f = csv("gyro_paths", "manifold,spin,t,x,y,z")?;
    let times: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.01).collect();
    for s in [0.0, 0.1, 0.3, 0.6, -0.3] {
        let b = Sphere2::new(1.0)?;
        let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(1.0, 0.3)?, Free)?;
        let x = Vector2::new(1.2, 0.0);
        let y0 = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(-0.6, 0.8 / 1.2f64.sin())), 0.0, s)?;
        let sol = run(&model, y0, 10.0, 1e-11, |o| o.save(Save::At(times.clone())))?;
        for (t, y) in sol.times().iter().zip(sol.states()) {
            let p = model.position(y);
            writeln!(f, "S2,{s},{t},{},{},{}", p[0], p[1], p[2])?;
        }
        let b = Hyperbolic2::new(1.0)?;
        let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(1.0, 0.3)?, Free)?;
        let x = Vector2::new(0.8, 0.0);
        let y0 = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(-0.6, 0.8 / 0.8f64.sinh())), 0.0, s)?;
        let sol = run(&model, y0, 4.0, 1e-11, |o| o.save(Save::At(times.iter().map(|t| 0.4 * t).collect())))?;
        for (t, y) in sol.times().iter().zip(sol.states()) {
            let p = model.position(y);
            writeln!(f, "H2,{s},{t},{},{},{}", p[0], p[1], p[2])?;
        }
    }
    Ok(())
}

/// Rotation number `ω_ψ/ω_r` of the free S² gyroscope against the spin,
/// measured on trajectories, for `I = mR²` and `I ≠ mR²`.
fn rotation_numbers() -> Res<()> {
    let mut f = csv("rotation_numbers", "moment,spin,omega_r,omega_psi_over_omega_r,predicted")?;
    let b = Sphere2::new(R)?;
    let mr2 = M * R * R;
    for moment in [0.6, mr2, 3.0] {
        for k in 1..=16 {
            let s = 0.1 * k as f64;
            let model = Gyroscope2Model::new(b, Gyroscope::<2>::isotropic(M, moment)?, Free)?;
            let x = Vector2::new(0.9, 0.0);
            let y0 = model.state_at(&b.embed(&x), &b.embed_tangent(&x, &Vector2::new(0.3, 0.8)), 0.2, s)?;
            let mm = model.clone();
            let sol = run(&model, y0, 40.0, 1e-12, |o| {
                o.dense(true).event(Event::new("periapsis", move |_, y| mm.velocity(y)[2]).direction(Direction::Falling)).event_tolerance(1e-14)
            })?;
            let ev = sol.events();
            if ev.len() < 2 {
                continue;
            }
            let (t0, t1) = (ev[0].t, ev[1].t);
            let n = 2000;
            let angle = |y: &_| -> Res<f64> {
                let (_, u) = model.bundle().to_chart(&model_g(y))?;
                let w = u * rho_of(y);
                Ok(w[(1, 0)].atan2(w[(0, 0)]))
            };
            let mut psi = angle(&ev[0].y)?;
            let mut dpsi = 0.0;
            for k in 1..=n {
                let y = if k == n { ev[1].y } else { sol.sample(t0 + (t1 - t0) * k as f64 / n as f64).ok_or("sample")? };
                let p1 = angle(&y)?;
                let d = p1 - psi;
                dpsi += d - 2.0 * PI * (d / (2.0 * PI)).round();
                psi = p1;
            }
            let omega_r = 2.0 * PI / (t1 - t0);
            // Prediction 2π∂E/∂J from E(J) (SPEC §7) with the measured ω_r.
            let ell = model.p_phi(&y0);
            let w_big = if s.abs() > ell.abs() { omega_r * s.signum() } else { 0.0 };
            let predicted = (w_big + (1.0 / moment - 1.0 / mr2) * s) / omega_r;
            writeln!(f, "{moment},{s},{omega_r},{},{predicted}", dpsi / (t1 - t0) / omega_r)?;
        }
    }
    Ok(())
}

type GState = framedyn::dynamics::Gyroscope2State<framedyn::lie::So3>;
fn model_g(y: &GState) -> framedyn::lie::So3 {
    y.0 .0
}
fn rho_of(y: &GState) -> nalgebra::Matrix2<f64> {
    y.0 .1.matrix()
}

fn main() -> Res<()> {
    create_dir_all(OUT)?;
    orbits()?;
    h2_threshold()?;
    gyro_paths()?;
    rotation_numbers()?;
    precession_vs_spin()?;
    println!("CSV files written to {OUT}/; run `python3 scripts/validation_figures.py` for the PNGs in docs/figures/");
    Ok(())
}
