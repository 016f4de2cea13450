//! The sphere S²(R): a point, a gyroscope and an affine body, each checked
//! against a closed form of the paper (equation labels as in the paper).
//!
//! - **Point, no potential**: a geodesic (great circle) of speed `|v|` returns
//!   to its initial state after `T = 2πR/|v|`.
//! - **Gyroscope, no potential**: in the parallel frame `m u̇ = K s ε u`
//!   ((a59), `K = 1/R²`, `s` the spin), so the bundle element moves as
//!   `Q(t) = Q₀ exp(t(h(u₀) + cG))`, `c = s/(mR²)`: the path is a small
//!   circle, closed after `T = 2π/√(|u|²/R² + c²)`, and `s` is constant. The
//!   start heads straight for the north pole, where the paper's chart
//!   `(r, φ)` is singular.
//! - **Affine body, elastic potential (a131)**: energy and `p_φ` (rotations
//!   about the z axis) are conserved; the constraint defect stays at round-off.
//!
//! Run: `cargo run --example s2_bodies` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{col, drift, dist, ends, position, run, Checks};

use std::f64::consts::PI;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut checks = Checks::default();

    // Point: geodesic on S²(1.5), m = 1.
    let (radius, r0, r_dot, phi_dot) = (1.5_f64, 0.6_f64, 0.3_f64, 0.8_f64);
    let speed = (r_dot.powi(2) + (radius * (r0 / radius).sin() * phi_dot).powi(2)).sqrt();
    let period = 2.0 * PI * radius / speed;
    let sink = run(&format!(
        r#"
        [manifold]
        kind = "S2"
        radius = {radius}
        [body]
        kind = "point"
        [initial]
        r = {r0}
        phi = 0.0
        r_dot = {r_dot}
        phi_dot = {phi_dot}
        [method]
        name = "dopri5"
        rtol = 1e-12
        atol = 1e-12
        [time]
        t_end = {period}
        [output]
        times = [0.0, {period}]
        "#
    ))?;
    println!("S² point (geodesic): period 2πR/|v| = {period:.12}");
    checks.le("|x(T) − x(0)| / R", dist(&position(&sink, 0), &position(&sink, -1)) / radius, 1e-9);
    checks.le("energy drift", drift(&sink, "energy"), 1e-11);

    // Gyroscope: m = 1, I = 0.2, spin s = 0.5 on the unit sphere, heading for the pole.
    let (m, s, u) = (1.0_f64, 0.5_f64, 1.0_f64);
    let c = s / m; // s/(mR²), R = 1
    let period = 2.0 * PI / (u * u + c * c).sqrt();
    let sink = run(&format!(
        r#"
        [manifold]
        kind = "S2"
        radius = 1.0
        [body]
        kind = "gyroscope"
        mass = {m}
        inertia = 0.2
        [initial]
        r = 0.3
        phi = 0.0
        r_dot = -{u}
        phi_dot = 0.0
        alpha = 0.0
        spin = {s}
        [method]
        name = "dopri5"
        rtol = 1e-12
        atol = 1e-12
        [time]
        t_end = {period}
        [output]
        samples = 201
        "#
    ))?;
    let closest = col(&sink, "x2").iter().fold(-1.0_f64, |a, &z| a.max(z));
    println!("S² gyroscope (free, s = {s}): period 2π/√(|u|² + (s/m)²) = {period:.12}");
    println!("  closest approach to the north pole: 1 − max z = {:.3e} R", 1.0 - closest);
    checks.le("|x(T) − x(0)| / R", dist(&position(&sink, 0), &position(&sink, -1)), 1e-9);
    let (s0, s1) = ends(&sink, "spin");
    checks.le("|s(T) − s(0)| (the spin p_ψ is conserved)", (s1 - s0).abs(), 1e-12);
    checks.le("energy drift", drift(&sink, "energy"), 1e-11);

    // Affine body with the elastic potential (a131).
    let sink = run(
        r#"
        [manifold]
        kind = "S2"
        radius = 1.0
        [body]
        kind = "affine"
        mass = 1.0
        inertia = 0.1
        [potential]
        kind = "elastic"
        kappa = 1.0
        [initial]
        r = 0.7
        phi = 0.0
        phi_dot = 0.6
        rho = [[1.1, 0.0], [0.0, 0.9]]
        rho_dot = [[0.0, 0.2], [-0.1, 0.0]]
        [method]
        name = "rk4"
        h = 0.002
        [time]
        t_end = 2.0
        [output]
        every = 10
        "#,
    )?;
    println!("S² affine body, elastic potential (a131), RKMK4 h = 0.002, t ≤ 2:");
    checks.le("relative energy drift", drift(&sink, "energy") / ends(&sink, "energy").0.abs(), 1e-9);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-10);
    checks.le("max constraint defect", col(&sink, "defect").iter().fold(0.0, |a: f64, &b| a.max(b)), 1e-12);

    checks.finish();
    Ok(())
}
