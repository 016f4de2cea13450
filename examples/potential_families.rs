//! One check per potential family of the paper, each against a closed form:
//!
//! - **Bertrand oscillator** (b88) on S²: `V = (κ/2)R² tan²(r/R)`; radial
//!   period `T_r = π√(mR²/(2E + κR²))`, the state returns after `2T_r`.
//! - **Bertrand Kepler** (c88) on S² and (b133) on H²: `V = −(α/R)cot(r/R)`,
//!   `−(α/R)coth(r/R)`; `T_r = 2π/(mα²/n³ ± n/(mR²))`,
//!   `n² = mR(RE + √(R²E² + α²))` on S², `n² = −mR(RE + √(R²E² − α²))` on
//!   H² (upper signs S², lower H²), the state returns after `T_r`.
//! - **The cosine family** of §5.1 (`α̂cos²(r/R) + β̂cos(r/R)`), gyroscope on
//!   S²: energy, spin and `p_φ` conserved. (The paper's claim that it keeps
//!   elementary integrals and total degeneracy is wrong, lines 3725–3746: see
//!   docs/validation.md §7.)
//! - **Separable affine** (b128) on S²: `p_φ`, spin `p_α = k₁₂ − k₂₁` and
//!   energy conserved ((a122)–(a129)).
//! - **Elastic** (a131) on S², `J = I·1`: the natural state `ρ = 1` is stable;
//!   small dilatations oscillate with `ω² = 4κ/I`, shears with `ω² = 2κ/I`.
//! - **Invariants of deformation** on S³: St Venant–Kirchhoff
//!   `W = (λ/2)(tr E)² + μ tr E²`, `E = (G − 1)/2`: small dilatations
//!   `ρ = (1 + ε)1` have `W ≈ (9λ/2 + 3μ)ε²` and kinetic energy `(3I/2)ε̇²`,
//!   so `ω² = (3λ + 2μ)/I`.
//!
//! The user-potential family is `examples/user_potential.rs`.
//!
//! Run: `cargo run --example potential_families` (exit code 1 if a check fails).

#[path = "support/mod.rs"]
mod support;
use support::{col, dist, drift, ends, position, run, Checks};

use std::f64::consts::PI;

const M: f64 = 1.3;
const R: f64 = 1.2;

/// A point scene on `manifold` with `potential` (TOML lines), from the chart
/// state `(r₀, 0)`, `(ṙ₀, φ̇₀)`, run to `t_end` with DOPRI5 at tolerance 1e-12.
fn point(manifold: &str, potential: &str, (r0, rd, pd): (f64, f64, f64), t_end: f64) -> String {
    format!(
        r#"
        [manifold]
        kind = "{manifold}"
        radius = {R}
        [body]
        kind = "point"
        mass = {M}
        [potential]
        {potential}
        [initial]
        r = {r0}
        phi = 0.0
        r_dot = {rd}
        phi_dot = {pd}
        [method]
        name = "dopri5"
        rtol = 1e-12
        atol = 1e-12
        [time]
        t_end = {t_end}
        [output]
        times = [0.0, {t_end}]
        "#
    )
}

/// Runs the point to `period(E)` (E from the initial state) and checks that it returns.
fn closes(checks: &mut Checks, what: &str, manifold: &str, potential: &str, start: (f64, f64, f64), periods: f64, period: impl Fn(f64) -> f64) -> Result<(), Box<dyn std::error::Error>> {
    let energy = ends(&run(&point(manifold, potential, start, 1e-3))?, "energy").0;
    let t_r = period(energy);
    let sink = run(&point(manifold, potential, start, periods * t_r))?;
    println!("{what}: E = {energy:.12}, T_r = {t_r:.12}");
    checks.le(&format!("|x({periods}·T_r) − x(0)| / R"), dist(&position(&sink, 0), &position(&sink, -1)) / R, 1e-9);
    Ok(())
}

/// A small-oscillation scene of an affine body at rest at the pole.
fn breathing(manifold: &str, potential: &str, rho: &str, t_end: f64) -> String {
    let (chart, samples) = if manifold == "S3" { ("r1 = 0.3\nr2 = 0.0\nr3 = 0.0", 5) } else { ("r = 0.3\nphi = 0.0", 5) };
    format!(
        r#"
        [manifold]
        kind = "{manifold}"
        radius = 1.0
        [body]
        kind = "affine"
        mass = 1.0
        inertia = 0.35
        [potential]
        {potential}
        [initial]
        {chart}
        rho = {rho}
        [method]
        name = "dopri5"
        rtol = 1e-13
        atol = 1e-13
        [time]
        t_end = {t_end}
        [output]
        samples = {samples}
        quantities = ["frame"]
        "#
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut checks = Checks::default();
    let (kappa, alpha) = (0.8, 0.7);

    closes(&mut checks, "S² Bertrand oscillator (b88)", "S2", &format!("kind = \"oscillator\"\nkappa = {kappa}"), (0.5, 0.0, 0.9), 2.0, |e| {
        PI * (M * R * R / (2.0 * e + kappa * R * R)).sqrt()
    })?;
    closes(&mut checks, "S² Bertrand Kepler (c88)", "S2", &format!("kind = \"kepler\"\nalpha = {alpha}"), (0.8, 0.3, 0.5), 1.0, |e| {
        let n2 = M * R * (R * e + (R * R * e * e + alpha * alpha).sqrt());
        2.0 * PI / (M * alpha * alpha / (n2 * n2.sqrt()) + n2.sqrt() / (M * R * R))
    })?;
    closes(&mut checks, "H² Bertrand Kepler (b133)", "H2", &format!("kind = \"kepler\"\nalpha = {alpha}"), (0.5, 0.0, 0.5), 1.0, |e| {
        let n2 = M * R * (-R * e - (R * R * e * e - alpha * alpha).sqrt());
        2.0 * PI / (M * alpha * alpha / (n2 * n2.sqrt()) - n2.sqrt() / (M * R * R))
    })?;

    let sink = run(
        r#"
        [manifold]
        kind = "S2"
        radius = 1.0
        [body]
        kind = "gyroscope"
        mass = 1.0
        inertia = 0.2
        [potential]
        kind = "cosine"
        alpha_hat = 0.4
        beta_hat = -0.3
        [initial]
        r = 0.6
        phi = 0.0
        r_dot = -0.5
        phi_dot = 0.8
        spin = 0.3
        [method]
        name = "butcher6"
        h = 0.01
        [time]
        t_end = 10.0
        [output]
        every = 50
        "#,
    )?;
    println!("S² gyroscope in the cosine family α̂cos² + β̂cos (§5.1), t ≤ 10:");
    checks.le("energy drift", drift(&sink, "energy"), 1e-10);
    checks.le("spin drift", drift(&sink, "spin"), 1e-12);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-10);

    let sink = run(
        r#"
        [manifold]
        kind = "S2"
        radius = 1.0
        [body]
        kind = "affine"
        mass = 1.0
        inertia = 0.35
        [potential]
        kind = "separable"
        v_r = { cos = [[0.4, 1.0]] }
        v_rho = { poly = [0.0, 0.0, 0.45, 0.0, 0.05] }
        v_eps = { sec_2x = 1.8 }
        [initial]
        r = 0.5
        phi = 0.0
        r_dot = 0.2
        phi_dot = 0.5
        rho = [[1.1, 0.1], [0.0, 0.9]]
        rho_dot = [[0.0, 0.1], [-0.2, 0.05]]
        [method]
        name = "dopri5"
        rtol = 1e-11
        atol = 1e-11
        [time]
        t_end = 5.0
        [output]
        samples = 51
        "#,
    )?;
    let spin: Vec<f64> = col(&sink, "k_12").iter().zip(col(&sink, "k_21")).map(|(a, b)| a - b).collect();
    println!("S² affine body, separable potential (b128), t ≤ 5:");
    checks.le("relative energy drift", drift(&sink, "energy") / ends(&sink, "energy").0.abs(), 1e-9);
    checks.le("p_φ drift", drift(&sink, "p_phi"), 1e-9);
    checks.le("spin p_α = k₁₂ − k₂₁ drift", spin.iter().map(|v| (v - spin[0]).abs()).fold(0.0, f64::max), 1e-9);

    // Small oscillations about the natural state, amplitude ε: |e₁| is
    // 1 + ε at t = 0 and T, 1 − ε at T/2 (up to O(ε²) corrections).
    let eps = 1e-4;
    let (kappa, inertia) = (0.9, 0.35);
    let mut oscillation = |what: &str, manifold: &str, potential: &str, rho: String, omega2: f64| -> Result<(), Box<dyn std::error::Error>> {
        let period = 2.0 * PI / omega2.sqrt();
        let sink = run(&breathing(manifold, potential, &rho, period))?;
        // |e₁| = √G₁₁: the length of the first body vector (the parallel frame stays put).
        let s: Vec<f64> = (0..sink.rows.len())
            .map(|i| (0..4).filter_map(|k| sink.column(&format!("e1_{k}")).map(|c| c[i] * c[i])).sum::<f64>().sqrt())
            .collect();
        println!("{what}: period 2π/ω = {period:.12}");
        checks.le("| |e₁|(T/2) − (1 − ε)| / ε", (s[2] - (1.0 - eps)).abs() / eps, 1e-3);
        checks.le("| |e₁|(T) − (1 + ε)| / ε", (s[4] - (1.0 + eps)).abs() / eps, 1e-3);
        Ok(())
    };
    let elastic = format!("kind = \"elastic\"\nkappa = {kappa}");
    let d = 1.0 + eps;
    oscillation("S² elastic (a131), dilatation ω² = 4κ/I", "S2", &elastic, format!("[[{d}, 0.0], [0.0, {d}]]"), 4.0 * kappa / inertia)?;
    // ρ = 1 + ε·diag(1, −1): a pure shear (det ρ = 1 − ε²).
    oscillation("S² elastic (a131), shear ω² = 2κ/I", "S2", &elastic, format!("[[{d}, 0.0], [0.0, {}]]", 1.0 - eps), 2.0 * kappa / inertia)?;
    let (lambda, mu) = (1.1, 0.7);
    oscillation(
        "S³ St Venant–Kirchhoff, dilatation ω² = (3λ + 2μ)/I",
        "S3",
        &format!("kind = \"st_venant_kirchhoff\"\nlambda = {lambda}\nmu = {mu}"),
        format!("[[{d}, 0.0, 0.0], [0.0, {d}, 0.0], [0.0, 0.0, {d}]]"),
        (3.0 * lambda + 2.0 * mu) / inertia,
    )?;

    checks.finish();
    Ok(())
}
