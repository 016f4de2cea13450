//! The hyperbolic plane H²(R): a point, the gyroscope (Riemannian (a135) and
//! Lorentz-type (a138)) and an affine body, each checked against a closed
//! form or a conservation law of the paper.
//!
//! - **Point, no potential**: a radial geodesic from the origin's chart
//!   `(r, φ)` has `r(t) = r₀ + ṙ₀t` exactly (r is the geodesic distance).
//! - **Gyroscope, no potential**: in the parallel frame `m u̇ = K s ε u`
//!   ((a59) with `K = −1/R²`): the bundle element is
//!   `Λ(t) = Λ₀ exp(t(h(u₀) + cG))`, `c = −s/(mR²)`; for `c² > |u|²/R²` the
//!   algebra element is elliptic and the path is a closed circle with period
//!   `T = 2π/√(c² − |u|²/R²)`. The Lorentz-type gyroscope (a138) has the
//!   indefinite internal kinetic energy `−s²/(2I)`: same energy conservation,
//!   same conserved spin.
//! - **Affine body, separable potential (b128)**: energy, `p_φ` and the spin
//!   `p_α = k₁₂ − k₂₁` (hypermomentum `k = ρJρ̇ᵀ`, `J = I·1`) are conserved
//!   ((a122)–(a129)).
//!
//! Run: `cargo run --example h2_bodies` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{col, dist, drift, ends, position, run, Checks};

use std::f64::consts::PI;

fn gyroscope(signature: &str, s: f64, u: f64, t_end: f64) -> Result<framedyn::scenes::MemorySink, Box<dyn std::error::Error>> {
    run(&format!(
        r#"
        [manifold]
        kind = "H2"
        radius = 1.0
        [body]
        kind = "gyroscope"
        mass = 1.0
        inertia = 0.3
        signature = "{signature}"
        [initial]
        r = 0.4
        phi = 0.0
        r_dot = {u}
        phi_dot = 0.0
        spin = {s}
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

    // Point: radial geodesic.
    let (r0, v, t_end) = (0.2, 0.7, 3.0);
    let sink = run(&format!(
        r#"
        [manifold]
        kind = "H2"
        radius = 1.0
        [body]
        kind = "point"
        [initial]
        r = {r0}
        phi = 0.5
        r_dot = {v}
        phi_dot = 0.0
        [method]
        name = "butcher6"
        h = 0.01
        [time]
        t_end = {t_end}
        [output]
        every = 100
        "#
    ))?;
    let (_, r_end) = ends(&sink, "r");
    println!("H² point (radial geodesic):");
    checks.close("r(T) vs r₀ + ṙ₀T", r_end, r0 + v * t_end, 1e-12);

    // Gyroscopes: m = 1, R = 1, u = 0.3, s = 0.6 → c² − |u|² = 0.27.
    let (s, u) = (0.6_f64, 0.3_f64);
    let period = 2.0 * PI / (s * s - u * u).sqrt();
    let sink = gyroscope("riemannian", s, u, period)?;
    println!("H² gyroscope (a135), free, s = {s}: period 2π/√(c² − |u|²/R²) = {period:.12}");
    checks.le("|x(T) − x(0)| / R (Minkowski components)", dist(&position(&sink, 0), &position(&sink, -1)), 1e-9);
    let (s0, s1) = ends(&sink, "spin");
    checks.le("|s(T) − s(0)|", (s1 - s0).abs(), 1e-12);
    checks.le("energy drift", drift(&sink, "energy"), 1e-11);

    let sink = gyroscope("lorentz", s, u, period)?;
    println!("H² Lorentz-type gyroscope (a138), free, s = {s}:");
    let (e0, _) = ends(&sink, "energy");
    println!("  energy E = (m/2)|u|² − s²/(2I) = {e0:.12} (closed form {:.12})", 0.5 * u * u - s * s / (2.0 * 0.3));
    checks.le("  |E − ((m/2)|u|² − s²/(2I))|", (e0 - (0.5 * u * u - s * s / 0.6)).abs(), 1e-12);
    let (s0, s1) = ends(&sink, "spin");
    checks.le("|s(T) − s(0)|", (s1 - s0).abs(), 1e-12);
    checks.le("energy drift", drift(&sink, "energy"), 1e-11);

    // Affine body, separable potential (b128): V_r = 0.2 r², V_ϱ = ϱ²/2, V_ε = 2/cos 2ε.
    let sink = run(
        r#"
        [manifold]
        kind = "H2"
        radius = 1.0
        [body]
        kind = "affine"
        mass = 1.0
        inertia = 0.1
        [potential]
        kind = "separable"
        v_r = { poly = [0.0, 0.0, 0.2] }
        v_rho = { poly = [0.0, 0.0, 0.5] }
        v_eps = { sec_2x = 2.0 }
        [initial]
        r = 0.5
        phi = 0.0
        phi_dot = 0.5
        rho = [[1.1, 0.1], [0.0, 0.9]]
        rho_dot = [[0.0, 0.1], [0.0, 0.0]]
        [method]
        name = "dopri5"
        rtol = 1e-11
        atol = 1e-11
        [time]
        t_end = 3.0
        [output]
        samples = 31
        "#,
    )?;
    let spin: Vec<f64> = col(&sink, "k_12").iter().zip(col(&sink, "k_21")).map(|(a, b)| a - b).collect();
    println!("H² affine body, separable potential (b128), t ≤ 3:");
    checks.le("relative energy drift", drift(&sink, "energy") / ends(&sink, "energy").0.abs(), 1e-9);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-9);
    checks.le("spin p_α = k₁₂ − k₂₁ drift", spin.iter().map(|v| (v - spin[0]).abs()).fold(0.0, f64::max), 1e-9);

    checks.finish();
    Ok(())
}
