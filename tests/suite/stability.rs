//! Where methods fail, cheaply: adaptive DOPRI5 running into the finite-time
//! collapse of an affine body must stop with the typed step-size-collapse
//! error carrying `t` and `h`, and keep the solution computed so far. The
//! full stability maps are in `docs/stability.md`
//! (`cargo run --release --example stability`).

use framedyn::body::Affine;
use framedyn::dynamics::affine::AffineModel;
use framedyn::dynamics::point::bundle_element_at;
use framedyn::dynamics::System;
use framedyn::manifold::{Manifold, Sphere2};
use framedyn::method::Rkmk;
use framedyn::potential::{Centre, CosineFamily};
use framedyn::solve::{solve, Options, Problem, Save, SolveError, StopReason};
use nalgebra::{Matrix2, Vector2};

/// An affine body on S² (m = 1, anisotropic J) in the position-only
/// potential `0.5 cos(r/R)`: `∂V/∂ρ = 0`, so the internal motion is free,
/// `ρ(t) = I + tρ̇₀` exactly, and the compression rate `ρ̇₀` flattens the body
/// at the smallest positive root `t*` of `det(I + tρ̇₀) = 1 + t tr ρ̇₀ + t² det ρ̇₀`.
///
/// Adaptive DOPRI5 (tol 1e-8) tracks `det ρ` to the exact polynomial
/// (absolute error ≤ 1e-6 = 100·tol while `t* − t > 1e-3`; measured 2.1e-8),
/// shrinks its step as `t → t*` (`‖Ω̂‖ ~ 1/(t* − t)`), and
/// stops with `SolveError::StepSizeTooSmall { t, h, h_min }`: `|h| < h_min`
/// and `t` within 1e-6 of `t*` — at the collapse of the *numerical*
/// solution, which the integration error shifts by ~1e-8 (measured with the
/// release example: t* − t = 1.7e-4, −3.6e-7, −1.6e-8, −6.9e-11, 2.5e-11 at
/// tol 1e-4 … 1e-12); the model's own prediction `t + t*(y)` from the last
/// kept state agrees with where it stopped. The failure keeps the
/// partial solution: every accepted step, ending exactly at the error's `t`,
/// with stop reason `Failed` carrying the same error. Measured numbers:
/// `cargo test --test methods collapse_stops -- --nocapture`.
#[test]
fn collapse_stops_adaptive_dopri5_with_typed_error_and_keeps_partial_solution() {
    let s2 = Sphere2::new(1.0).unwrap();
    let pot = CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2)).unwrap();
    let m = AffineModel::new(s2, Affine::new(1.0, Matrix2::new(0.3, 0.07, 0.07, 0.15)).unwrap(), pot).unwrap();
    let g = bundle_element_at(&s2, &s2.embed(&Vector2::new(0.8, 0.2))).unwrap();
    let rd = Matrix2::new(-1.0, 0.2, 0.1, 0.3);
    let y0 = m.state(&g, &Matrix2::identity(), &Vector2::new(0.6, -0.9), &rd).unwrap();
    let (tr, dt) = (rd.trace(), rd.determinant());
    let disc = (tr * tr - 4.0 * dt).sqrt();
    let t_star = [(-tr + disc) / (2.0 * dt), (-tr - disc) / (2.0 * dt)].into_iter().filter(|t| *t > 0.0).fold(f64::INFINITY, f64::min);
    assert!(t_star > 0.5 && t_star < 1.0, "t* = {t_star}");

    let prob = Problem::new(m.clone(), y0, (0.0, 2.0)).unwrap();
    let res = solve(&prob, &Rkmk::dopri5(), &Options::adaptive(1e-8, 1e-8).save(Save::Steps).max_steps(100_000));
    let fl = match res {
        Ok(sol) => panic!("integrated through the collapse at t* = {t_star} to t = {}", sol.last().0),
        Err(fl) => fl,
    };
    let (t, h, h_min) = match fl.error {
        SolveError::StepSizeTooSmall { t, h, h_min } => (t, h, h_min),
        ref other => panic!("expected StepSizeTooSmall, got {other:?}"),
    };
    let sol = &fl.solution;
    let stats = sol.stats();
    println!(
        "collapse at t* = {t_star:.15}: {} after {} accepted / {} rejected steps; t* − t = {:.2e}",
        fl.error,
        stats.accepted,
        stats.rejected,
        t_star - t
    );
    assert!((t_star - t).abs() < 1e-6, "stopped at t = {t}, t* = {t_star}");
    assert!(h.abs() < h_min && h_min > 0.0, "h = {h:e}, h_min = {h_min:e}");

    // The partial solution: every accepted step up to the failure.
    assert_eq!(*sol.stop_reason(), StopReason::Failed(fl.error.clone()));
    let (ts, ys) = (sol.times(), sol.states());
    assert_eq!(ts.len(), ys.len());
    assert_eq!(ts.len(), stats.accepted + 1, "Save::Steps keeps t₀ and every accepted step");
    assert_eq!(sol.last().0, t, "the partial solution ends where the error says");
    assert!(ts.windows(2).all(|w| w[1] > w[0]));
    // It is the motion: det ρ follows det(I + tρ̇₀) while the body is not
    // nearly flat, and the kept states are valid up to the last one.
    // The controller bounds the local error in absolute terms, so the
    // *absolute* error of det ρ stays near the tolerance (1e-8) while its
    // relative error grows like 1/(t* − t) (docs/stability.md, collapse chart).
    let mut worst = 0.0f64;
    for (ti, yi) in ts.iter().zip(ys) {
        let exact = (Matrix2::identity() + rd * *ti).determinant();
        assert!(m.defect(yi).is_finite());
        if t_star - ti > 1e-3 {
            worst = worst.max((m.det_rho(yi) - exact).abs());
        }
    }
    println!("det ρ absolute error while t* − t > 1e-3: {worst:.1e}; last det ρ = {:.1e}", m.det_rho(sol.last().1));
    assert!(worst < 1e-6, "det ρ absolute error {worst:e} (tol 1e-8)");
    assert!(m.det_rho(sol.last().1) < 1e-4, "did not get close to the collapse");
    let own = t + m.free_collapse_time(sol.last().1).expect("still collapsing");
    println!("collapse time predicted from the last kept state: {own:.15} (t* − it = {:.1e})", t_star - own);
    assert!((own - t).abs() < 1e-9, "stopped at {t}, the kept state collapses at {own}");
    // The step shrank towards the collapse.
    let last_h = ts[ts.len() - 1] - ts[ts.len() - 2];
    assert!(last_h < 1e-6 * stats.h_max, "last step {last_h:e}, largest {:e}", stats.h_max);
}
