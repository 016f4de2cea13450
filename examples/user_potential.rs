//! Your own potential, two ways.
//!
//! 1. **Generic Rust code** (preferred): implement
//!    [`framedyn::potential::Potential`] once, generic over `D: Scalar`
//!    (plain `f64` or a dual number); forces `F̂_A = −H_A V` and torques
//!    `N̂^A_B = −E^A_B V` (§4, after (a53)) follow by automatic
//!    differentiation, exactly. Here the Bertrand oscillator of S² is written
//!    by hand in the ambient coordinates, `V = (κ/2)R²(x² + y²)/z²`
//!    (`= (κ/2)R² tan²(r/R)`, (b88)), and run with the typed API
//!    (model → problem → `solve`). Checks: the trajectory equals the one of
//!    the built-in `Oscillator` to round-off, and the orbit closes after two
//!    radial periods `T_r = π√(mR²/(2E + κR²))`.
//! 2. **An `f64` closure** in a scene (what the Python module does with a
//!    Python callable): gradients by extrapolated finite differences, slower
//!    and accurate to ~1e-12. Here a frame-dependent dipole
//!    `V = b⟨e₁, ẑ⟩` on a gyroscope, run both as a closure in a scene and as
//!    generic code: the two agree to the integration tolerance, energy is
//!    conserved and `p_φ` (the potential is symmetric about the z axis) too.
//!
//! Run: `cargo run --example user_potential` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{drift, ends, Checks};

use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use framedyn::body::{Gyroscope, Point};
use framedyn::dynamics::{Gyroscope2Model, PointModel, System};
use framedyn::manifold::{Manifold, Sphere2};
use framedyn::method::Rkmk;
use framedyn::potential::{Centre, Oscillator, Potential, Scalar};
use framedyn::scenes::{MemorySink, Scene};
use framedyn::solve::{solve, Options, Problem, Save};
use nalgebra::{Matrix3, Matrix3x2, SMatrix, SVector, Vector2, Vector3};

/// The S² oscillator (b88), centred at the north pole, in ambient coordinates.
#[derive(Debug, Clone)]
struct MyOscillator {
    kappa: f64,
    radius: f64,
}

impl Potential<2, 3> for MyOscillator {
    fn uses_frame(&self) -> bool {
        false // V(x) only
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, _e: &SMatrix<D, 3, 2>, _metric: &SMatrix<f64, 3, 3>) -> D {
        (x[0] * x[0] + x[1] * x[1]) / (x[2] * x[2]) * (0.5 * self.kappa * self.radius * self.radius)
    }
}

/// A dipole: `V = b⟨e₁, ẑ⟩` (the frame's columns are the body vectors).
#[derive(Debug, Clone)]
struct Dipole {
    b: f64,
}

impl Potential<2, 3> for Dipole {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, _x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, _metric: &SMatrix<f64, 3, 3>) -> D {
        e[(2, 0)] * self.b
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut checks = Checks::default();
    let (m, radius, kappa) = (1.3, 1.2, 0.8);
    let sphere = Sphere2::new(radius)?;

    // 1. The hand-written oscillator against the built-in one.
    let chart = Vector2::new(0.5, 0.0); // (r, φ)
    let (x0, v0) = (sphere.embed(&chart), sphere.embed_tangent(&chart, &Vector2::new(0.0, 0.9)));
    let mine = PointModel::new(sphere, Point::new(m)?, MyOscillator { kappa, radius })?;
    let builtin = PointModel::new(sphere, Point::new(m)?, Oscillator::new(kappa, Centre::sphere2(&sphere))?)?;
    let (y_mine, y_builtin) = (mine.state(&x0, &v0)?, builtin.state(&x0, &v0)?);
    let energy = mine.energy(&y_mine);
    let t_r = PI * (m * radius * radius / (2.0 * energy + kappa * radius * radius)).sqrt();
    let options = Options::adaptive(1e-12, 1e-12).save(Save::Ends);
    let end_mine = *solve(&Problem::new(mine.clone(), y_mine, (0.0, 2.0 * t_r))?, &Rkmk::dopri5(), &options)?.last().1;
    let end_builtin = *solve(&Problem::new(builtin.clone(), y_builtin, (0.0, 2.0 * t_r))?, &Rkmk::dopri5(), &options)?.last().1;
    println!("S² point, hand-written oscillator (dual numbers): E = {energy:.12}, 2T_r = {:.12}", 2.0 * t_r);
    checks.le("|E(mine) − E(built-in)| at t = 0", (energy - builtin.energy(&y_builtin)).abs(), 1e-14);
    checks.le("|x_mine(2T_r) − x_built-in(2T_r)| / R", (mine.position(&end_mine) - builtin.position(&end_builtin)).norm() / radius, 1e-11);
    checks.le("|x(2T_r) − x(0)| / R (Bertrand: the orbit closes)", (mine.position(&end_mine) - x0).norm() / radius, 1e-9);

    // 2. A dipole on a gyroscope: closure in a scene vs generic code.
    let (b, spin, t_end) = (0.4, 0.3, 5.0);
    let scene = Scene::from_toml_str(&format!(
        r#"
        [manifold]
        kind = "S2"
        radius = {radius}
        [body]
        kind = "gyroscope"
        mass = {m}
        inertia = 0.25
        [initial]
        r = 0.7
        phi = 0.0
        r_dot = 0.2
        phi_dot = 0.6
        alpha = 0.0
        spin = {spin}
        [method]
        name = "dopri5"
        rtol = 1e-11
        atol = 1e-11
        [time]
        t_end = {t_end}
        [output]
        samples = 51
        quantities = ["position", "energy", "momentum_map"]
        "#
    ))?;
    // x: the embedding position; e: the body frame, column-major (e₁ then e₂).
    let mut sim = scene.build_with_user_potential(Arc::new(move |_x: &[f64], e: &[f64]| b * e[2]))?;
    let mut sink = MemorySink::default();
    sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {})?;

    let model = Gyroscope2Model::new(sphere, Gyroscope::<2>::isotropic(m, 0.25)?, Dipole { b })?;
    let chart = Vector2::new(0.7, 0.0);
    let theta = chart[0] / radius;
    // The paper's frame at φ = 0: E_r = (cos ϑ, 0, −sin ϑ), E_φ = (0, 1, 0); alpha = 0 means e = E.
    let e0 = Matrix3x2::from_columns(&[Vector3::new(theta.cos(), 0.0, -theta.sin()), Vector3::new(0.0, 1.0, 0.0)]);
    let y0 = model.state(&sphere.embed(&chart), &sphere.embed_tangent(&chart, &Vector2::new(0.2, 0.6)), &e0, spin)?;
    let sol = solve(&Problem::new(model.clone(), y0, (0.0, t_end))?, &Rkmk::dopri5(), &Options::adaptive(1e-11, 1e-11).save(Save::Ends))?;
    let x_generic = model.position(sol.last().1);
    let x_closure = Vector3::new(ends(&sink, "x0").1, ends(&sink, "x1").1, ends(&sink, "x2").1);
    let rotation_z = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    println!("S² gyroscope with the dipole V = b⟨e₁, ẑ⟩, t ≤ {t_end}:");
    checks.le("|E(closure) − E(generic)| at t = 0", (ends(&sink, "energy").0 - model.energy(&y0)).abs(), 1e-12);
    checks.le("|p_φ(closure) − p_φ(generic)| at t = 0", (ends(&sink, "p_phi").0 - model.momentum_map(&y0, &rotation_z)?).abs(), 1e-12);
    checks.le("|x_closure(T) − x_generic(T)| / R", (x_closure - x_generic).norm() / radius, 1e-7);
    checks.le("energy drift (closure)", drift(&sink, "energy"), 1e-9);
    checks.le("p_φ drift (closure)", drift(&sink, "p_phi"), 1e-9);

    checks.finish();
    Ok(())
}
