//! The reference problems of `framedyn::testing` are what their documentation
//! says: each conserves its energy and its stated momentum map along a fine
//! integration (so a wrong momentum map, a potential without the claimed
//! symmetry or an inconsistent initial state fails here), and the two
//! constructions of the SPEC §5 gyroscope (group form, chart form) start from
//! the same physical state.

use framedyn::dynamics::System;
use framedyn::method::{GroupNumerics, Rkmk};
use framedyn::solve::{solve, Options};
use framedyn::testing::*;

/// Integrates `r` with RK4 (h = `h`) over `[0, span]` and checks that the
/// energy and the momentum map change by at most `tol` relative to their
/// scale (max(1, |value|)), and that the observable stays finite.
fn conserves<S>(r: Reference<S>, span: f64, h: f64, tol: f64)
where
    S: System + Clone,
    S::State: GroupNumerics,
{
    let mut r = r;
    let name = r.name;
    r.t_end = span;
    let (e0, j0) = (r.system.energy(&r.y0), (r.momentum)(&r.system, &r.y0));
    assert!(e0.is_finite() && j0.is_finite(), "{name}: E0 = {e0}, J0 = {j0}");
    let sol = solve(&r.problem().unwrap(), &Rkmk::rk4(), &Options::fixed(h)).unwrap();
    let (mut de, mut dj) = (0.0f64, 0.0f64);
    for y in sol.states() {
        de = de.max((r.system.energy(y) - e0).abs());
        dj = dj.max(((r.momentum)(&r.system, y) - j0).abs());
        assert!((r.observable)(&r.system, y).iter().all(|v| v.is_finite()), "{name}: non-finite observable");
    }
    eprintln!("{name}: max|ΔE| = {de:.1e} (E0 = {e0:.4}), max|ΔJ| = {dj:.1e} (J0 = {j0:.4})");
    assert!(de <= tol * e0.abs().max(1.0), "{name}: energy changed by {de:e}");
    assert!(dj <= tol * j0.abs().max(1.0), "{name}: momentum map changed by {dj:e}");
}

#[test]
fn measured_problems_conserve_energy_and_momentum() {
    conserves(s2_gyro(), 2.0, 1e-3, 1e-10);
    conserves(s2_gyro_pole(), 2.0, 1e-3, 1e-10);
    conserves(s2_pole(), 2.0, 1e-3, 1e-10);
    conserves(s2_point(), 2.0, 1e-3, 1e-10);
    conserves(s2_affine(), 1.0, 1e-3, 1e-9);
    conserves(s2_affine_collapse(), 0.5 * s2_collapse_time(), 1e-4, 1e-9);
    conserves(h2_gyro(), 2.0, 1e-3, 1e-10);
    conserves(h2_lorentz(), 2.0, 1e-3, 1e-10);
    conserves(t2_gyro(), 2.0, 1e-3, 1e-10);
    conserves(t2_affine(), 1.0, 1e-3, 1e-9);
    conserves(s3_gyro(), 2.0, 1e-3, 1e-10);
}

#[test]
fn tilted_problems_conserve_energy_and_momentum() {
    conserves(s2_tilted_gyro(), 2.0, 1e-3, 1e-10);
    conserves(s2_tilted_point(), 2.0, 1e-3, 1e-10);
    conserves(s2_tilted_affine(), 1.0, 1e-3, 1e-9);
    conserves(h2_tilted_gyro(), 2.0, 1e-3, 1e-10);
    conserves(h2_tilted_incompressible(), 1.0, 1e-3, 1e-9);
    conserves(t2_tilted_gyro(), 2.0, 1e-3, 1e-10);
    conserves(s3_tilted_gyro(), 2.0, 1e-3, 1e-10);
    conserves(s3_tilted_weyl(), 2.0, 1e-3, 1e-10);
}

#[test]
fn group_problems_conserve_energy_and_momentum() {
    conserves(rigid_body(), 2.0, 1e-3, 1e-10);
    conserves(heavy_top(), 2.0, 1e-3, 1e-10);
    conserves(lagrange_top(), 2.0, 1e-3, 1e-10);
    conserves(symmetric_top(), 2.0, 1e-3, 1e-10);
    conserves(hyperbolic_oscillator(), 2.0, 1e-3, 1e-10);
}

/// The group-form and chart-form constructions of the SPEC §5 gyroscope
/// describe one physical state: their observables (ambient position,
/// velocity, frame, internal momentum) agree to round-off, and both match
/// the documented chart values through the embedding.
#[test]
fn the_two_constructions_of_the_s2_gyroscope_agree() {
    let a = s2_gyro();
    let b = s2_gyro_from_chart(S2_A, S2_RADIUS, S2_Q0, S2_V0, S2_T_END, "s2_gyro").unwrap();
    let (oa, ob) = ((a.observable)(&a.system, &a.y0), (b.observable)(&b.system, &b.y0));
    assert_eq!(oa.len(), ob.len());
    let d = oa.iter().zip(&ob).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(d <= 1e-14, "group and chart constructions differ by {d:e}");
    // The position is the embedding of the documented chart point (r, φ).
    let (r, phi) = (S2_Q0[0] / S2_RADIUS, S2_Q0[1]);
    let x = [S2_RADIUS * r.sin() * phi.cos(), S2_RADIUS * r.sin() * phi.sin(), S2_RADIUS * r.cos()];
    for k in 0..3 {
        assert!((oa[k] - x[k]).abs() <= 1e-15, "position component {k}: {} vs {}", oa[k], x[k]);
    }
    assert!((a.system.energy(&a.y0) - b.system.energy(&b.y0)).abs() <= 1e-14);
}

/// Parametrised problems reject invalid parameters with a typed error.
#[test]
fn parametrised_problems_reject_invalid_parameters() {
    assert!(s2_gyro_with(0.5, -1.0, S2_Q0, S2_V0, 1.0, "x").is_err());
    assert!(s2_gyro_with(f64::NAN, 1.0, S2_Q0, S2_V0, 1.0, "x").is_err());
    assert!(s2_affine_kappa(-1.0).is_err());
}
