//! The torus T²(L, R) (`L` the distance of the tube's centre from the axis,
//! `R` the tube radius, angles `(θ, φ)`): a point, a gyroscope and an affine
//! body, checked against the paper's conservation laws.
//!
//! - **Point, no potential**: Clairaut's integral — the momentum of rotations
//!   about the axis, `p_φ = m(L + R cos θ)² φ̇`, and the energy
//!   `(m/2)(R²θ̇² + (L + R cos θ)²φ̇²)` are conserved; both are compared with
//!   their closed forms at the start.
//! - **Gyroscope, potential `V(θ) = 0.3 cos θ`** (separable, independent of φ):
//!   energy, spin and `p_φ` are conserved (the paper's §5.3; note its sign
//!   error in `ψ̇ + sin θ φ̇`, lines 5362/5486, see docs/validation.md §7).
//! - **Affine body, elastic potential (a131)**: energy and `p_φ` conserved.
//!
//! Run: `cargo run --example t2_bodies` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{col, drift, ends, run, Checks};

const TORUS: &str = r#"
[manifold]
kind = "T2"
L = 2.0
R = 0.7
"#;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut checks = Checks::default();
    let (big_l, small_r, m) = (2.0_f64, 0.7_f64, 1.3_f64);

    let (theta, theta_dot, phi_dot) = (0.4_f64, 0.9_f64, 0.35_f64);
    let sink = run(&format!(
        r#"{TORUS}
        [body]
        kind = "point"
        mass = {m}
        [initial]
        theta = {theta}
        phi = 0.0
        theta_dot = {theta_dot}
        phi_dot = {phi_dot}
        [method]
        name = "butcher6"
        h = 0.01
        [time]
        t_end = 10.0
        [output]
        every = 50
        "#
    ))?;
    let rho = big_l + small_r * theta.cos();
    println!("T² point (geodesic), t ≤ 10:");
    checks.close("p_φ at t = 0 vs m(L + R cos θ)²φ̇", ends(&sink, "p_phi").0, m * rho * rho * phi_dot, 1e-13);
    let energy = 0.5 * m * ((small_r * theta_dot).powi(2) + (rho * phi_dot).powi(2));
    checks.close("E at t = 0 vs (m/2)(R²θ̇² + (L + R cos θ)²φ̇²)", ends(&sink, "energy").0, energy, 1e-13);
    checks.le("p_φ drift (Clairaut)", drift(&sink, "p_phi"), 1e-10);
    checks.le("energy drift", drift(&sink, "energy"), 1e-10);

    let sink = run(&format!(
        r#"{TORUS}
        [body]
        kind = "gyroscope"
        mass = {m}
        inertia = 0.2
        [potential]
        kind = "separable"
        v_r = {{ cos = [[0.3, 1.0]] }}
        [initial]
        theta = 0.4
        phi = 0.0
        theta_dot = 0.5
        phi_dot = 0.3
        alpha = 0.0
        spin = 0.4
        [method]
        name = "butcher6"
        h = 0.01
        [time]
        t_end = 10.0
        [output]
        every = 50
        "#
    ))?;
    println!("T² gyroscope, V = 0.3 cos θ, t ≤ 10:");
    checks.le("energy drift", drift(&sink, "energy"), 1e-10);
    checks.le("spin drift", drift(&sink, "spin"), 1e-12);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-10);

    let sink = run(&format!(
        r#"{TORUS}
        [body]
        kind = "affine"
        mass = {m}
        inertia = 0.1
        [potential]
        kind = "elastic"
        kappa = 1.0
        [initial]
        theta = 0.3
        phi = 0.0
        theta_dot = 0.2
        phi_dot = 0.3
        rho = [[1.1, 0.0], [0.1, 0.9]]
        [method]
        name = "rk4"
        h = 0.002
        [time]
        t_end = 2.0
        [output]
        every = 50
        "#
    ))?;
    println!("T² affine body, elastic potential (a131), RKMK4 h = 0.002, t ≤ 2:");
    checks.le("relative energy drift", drift(&sink, "energy") / ends(&sink, "energy").0.abs(), 1e-9);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-10);
    checks.le("max constraint defect", col(&sink, "defect").iter().fold(0.0, |a: f64, &b| a.max(b)), 1e-12);

    checks.finish();
    Ok(())
}
