//! A downstream crate: a scene, a typed problem, and a potential of its own.
//!
//! 1. A scene file (format version 1) of a gyroscope on S² crossing the
//!    north pole, run through the scene engine.
//! 2. The typed API: a gyroscope on S² under a potential this crate defines,
//!    `V = g z + b ⟨e₁, ẑ⟩` (height in a uniform field plus a dipole
//!    coupling of the body frame), written once over `Scalar` so that forces
//!    and torques come by automatic differentiation; integrated with the
//!    adaptive RKMK Dormand–Prince pair.
//!
//! Checks (exit status 1 and a message when one fails): the scene's energy
//! drift and its pole crossing; the typed run's energy and its angular
//! momentum about the z axis (`V` is symmetric about it) conserved.

use std::error::Error;
use std::sync::atomic::AtomicBool;

use framedyn::body::Gyroscope;
use framedyn::dynamics::{Gyroscope2Model, System};
use framedyn::manifold::{Manifold, Sphere2};
use framedyn::method::Rkmk;
use framedyn::potential::{Potential, Scalar};
use framedyn::scenes::{MemorySink, Scene};
use framedyn::solve::{solve, Options, Problem, Save};
use nalgebra::{Matrix3, Matrix3x2, SMatrix, SVector, Vector2, Vector3};

/// `V = g z + b ⟨e₁, ẑ⟩` on the sphere embedded in ℝ³.
#[derive(Debug, Clone)]
struct FieldAndDipole {
    g: f64,
    b: f64,
}

impl Potential<2, 3> for FieldAndDipole {
    fn uses_frame(&self) -> bool {
        true
    }
    fn value<D: Scalar>(&self, x: &SVector<D, 3>, e: &SMatrix<D, 3, 2>, _metric: &SMatrix<f64, 3, 3>) -> D {
        x[2] * self.g + e[(2, 0)] * self.b
    }
}

/// A failed check: what was measured against what was required.
#[derive(Debug)]
struct CheckFailed(String);

impl std::fmt::Display for CheckFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl Error for CheckFailed {}

fn check(what: &str, value: f64, limit: f64) -> Result<(), CheckFailed> {
    let ok = value.is_finite() && value <= limit;
    println!("{} {what}: {value:.3e} (limit {limit:.0e})", if ok { "ok  " } else { "FAIL" });
    if ok {
        Ok(())
    } else {
        Err(CheckFailed(format!("{what} = {value:e} exceeds {limit:e}")))
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    // 1. A scene.
    let scene = Scene::from_toml_str(
        r#"
        format = 1
        name = "downstream-pole"
        manifold = { kind = "S2", radius = 1.0 }
        body = { kind = "gyroscope", inertia = 0.2 }
        potential = { kind = "cosine", beta_hat = -0.3 }
        initial = { r = 0.6, phi = 0.0, r_dot = -1.0, spin = 0.02 }
        method = { name = "rk4", h = 0.005 }
        time = { t_end = 4.0 }
        "#,
    )?;
    let mut sink = MemorySink::default();
    let summary = scene.build()?.run(&mut sink, &AtomicBool::new(false), &mut |_| {})?;
    println!("scene: {summary}");
    check("scene: energy drift max |E − E0|", summary.energy_drift, 1e-8)?;
    let top = sink.column("x2").map(|z| z.iter().cloned().fold(f64::NEG_INFINITY, f64::max)).unwrap_or(f64::NAN);
    check("scene: 1 − max z (the path crosses the pole)", 1.0 - top, 1e-3)?;

    // 2. A typed problem with this crate's potential.
    let sphere = Sphere2::new(1.0)?;
    let model = Gyroscope2Model::new(sphere, Gyroscope::<2>::isotropic(1.0, 0.25)?, FieldAndDipole { g: 0.7, b: 0.3 })?;
    let chart = Vector2::new(0.9_f64, 0.0); // (r, φ)
    let theta = chart[0];
    // The paper's frame at φ = 0: E_r = (cos ϑ, 0, −sin ϑ), E_φ = (0, 1, 0).
    let e0 = Matrix3x2::from_columns(&[Vector3::new(theta.cos(), 0.0, -theta.sin()), Vector3::new(0.0, 1.0, 0.0)]);
    let y0 = model.state(&sphere.embed(&chart), &sphere.embed_tangent(&chart, &Vector2::new(0.3, 0.8)), &e0, 0.4)?;
    let t_end = 10.0;
    let sol = solve(&Problem::new(model.clone(), y0, (0.0, t_end))?, &Rkmk::dopri5(), &Options::adaptive(1e-10, 1e-10).save(Save::Ends))?;
    let y1 = sol.last().1;
    let rotation_z = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (e_start, e_end) = (model.energy(&y0), model.energy(y1));
    let (p_start, p_end) = (model.momentum_map(&y0, &rotation_z)?, model.momentum_map(y1, &rotation_z)?);
    println!("typed: t = {t_end}, E = {e_start:.12} -> {e_end:.12}, p_phi = {p_start:.12} -> {p_end:.12}");
    check("typed: relative energy drift", (e_end - e_start).abs() / e_start.abs(), 1e-8)?;
    check("typed: p_phi drift", (p_end - p_start).abs(), 1e-8)?;
    println!("downstream: all checks passed");
    Ok(())
}
