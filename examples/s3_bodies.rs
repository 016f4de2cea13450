//! The three-sphere S³(R) (§6; chart: the paper's rotation vector
//! `r̄ = (r1, r2, r3)`, `|r̄|` the distance from the pole): a point, a
//! gyroscope and an affine body.
//!
//! - **Point, Bertrand oscillator `V = (κ/2)R² tan²(r/R)`**: every bounded
//!   orbit closes; the radial period is `T_r = π√(mR²/(2E + κR²))` and the
//!   state returns after `2T_r` (the S² formula: the orbit lies on a great S²).
//! - **Gyroscope, no potential, `J = (I/2)δ`** (the paper's undefined `I`,
//!   see docs/validation.md §7): the momentum map of SO(4) (`J_ab`, six
//!   components) is conserved, and so is `|S_rl|²` (a186), the length of the
//!   spin's body components.
//! - **Affine body, neo-Hookean energy of the Green tensor**: energy and the
//!   six `J_ab` are conserved (the potential is invariant under isometries).
//!
//! Run: `cargo run --example s3_bodies` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{col, dist, drift, ends, position, run, Checks};

use std::f64::consts::PI;

fn momentum_map_drift(sink: &framedyn::scenes::MemorySink) -> f64 {
    ["J_01", "J_02", "J_03", "J_12", "J_13", "J_23"].iter().map(|c| drift(sink, c)).fold(0.0, f64::max)
}

fn point(t_end: f64) -> Result<framedyn::scenes::MemorySink, Box<dyn std::error::Error>> {
    run(&format!(
        r#"
        [manifold]
        kind = "S3"
        radius = 1.2
        [body]
        kind = "point"
        mass = 1.3
        [potential]
        kind = "oscillator"
        kappa = 0.8
        [initial]
        r1 = 0.5
        r2 = 0.0
        r3 = 0.1
        r1_dot = 0.1
        r2_dot = 0.6
        r3_dot = 0.0
        [method]
        name = "dopri5"
        rtol = 1e-12
        atol = 1e-12
        [time]
        t_end = {t_end}
        [output]
        times = [0.0, {t_end}]
        "#
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut checks = Checks::default();
    let (m, radius, kappa) = (1.3_f64, 1.2_f64, 0.8_f64);

    // The energy of the initial state, then a run over two radial periods.
    let energy = ends(&point(1e-3)?, "energy").0;
    let t_r = PI * (m * radius * radius / (2.0 * energy + kappa * radius * radius)).sqrt();
    let sink = point(2.0 * t_r)?;
    println!("S³ point, Bertrand oscillator: E = {energy:.12}, T_r = π√(mR²/(2E + κR²)) = {t_r:.12}");
    checks.le("|x(2T_r) − x(0)| / R", dist(&position(&sink, 0), &position(&sink, -1)) / radius, 1e-9);
    checks.le("|J_12(2T_r) − J_12(0)| (rotations fixing the centre)", drift(&sink, "J_12"), 1e-11);

    let sink = run(
        r#"
        [manifold]
        kind = "S3"
        radius = 1.0
        [body]
        kind = "gyroscope"
        mass = 1.0
        J = [[0.25, 0.0, 0.0], [0.0, 0.25, 0.0], [0.0, 0.0, 0.25]]
        [initial]
        r1 = 0.5
        r2 = 0.0
        r3 = 0.2
        r1_dot = 0.0
        r2_dot = 0.7
        r3_dot = 0.0
        orientation = [0.1, 0.2, 0.3]
        omega = [1.0, 0.5, -0.3]
        [method]
        name = "butcher6"
        h = 0.01
        [time]
        t_end = 5.0
        [output]
        every = 20
        "#,
    )?;
    let spin2: Vec<f64> = (0..sink.rows.len())
        .map(|i| (1..=3).map(|k| col(&sink, &format!("spin_{k}"))[i].powi(2)).sum())
        .collect();
    println!("S³ gyroscope, free, J = (I/2)δ with I = 0.5, t ≤ 5:");
    checks.le("max over J_ab of the drift (SO(4) momentum map)", momentum_map_drift(&sink), 1e-10);
    checks.le("drift of |spin|² (body components)", spin2.iter().map(|v| (v - spin2[0]).abs()).fold(0.0, f64::max), 1e-10);
    checks.le("energy drift", drift(&sink, "energy"), 1e-10);

    let sink = run(
        r#"
        [manifold]
        kind = "S3"
        radius = 1.0
        [body]
        kind = "affine"
        mass = 1.0
        inertia = 0.1
        [potential]
        kind = "neo_hookean"
        lambda = 1.0
        mu = 1.0
        [initial]
        r1 = 0.4
        r2 = 0.0
        r3 = 0.0
        r2_dot = 0.5
        rho = [[1.1, 0.0, 0.0], [0.0, 0.95, 0.0], [0.0, 0.05, 1.0]]
        rho_dot = [[0.0, 0.1, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.1]]
        [method]
        name = "rk4"
        h = 0.002
        [time]
        t_end = 1.0
        [output]
        every = 50
        "#,
    )?;
    println!("S³ affine body, neo-Hookean, RKMK4 h = 0.002, t ≤ 1:");
    checks.le("relative energy drift", drift(&sink, "energy") / ends(&sink, "energy").0.abs(), 1e-9);
    checks.le("max over J_ab of the drift", momentum_map_drift(&sink), 1e-9);

    checks.finish();
    Ok(())
}
