//! Claims of §6 on the S³ gyroscope ((a184)–(a186)): the reduced equations
//! (a185) hold along trajectories of the full system, and the quantities of
//! (a186) — `|S(R)|²`, `|S_rl|²` and `C = (R/2)S(R) + S_rl` — are conserved
//! in free motion. The paper's momenta are those of its frame `ˡE(R)`
//! (right-invariant; SPEC §7 "S³ frames"), with `J = (I/2)δ` (SPEC §7
//! "Inertia"), from [`Gyroscope3Model::paper_momenta`].

use framedyn::body::Gyroscope;
use framedyn::dynamics::{Gyroscope3Model, Gyroscope3State, System};
use framedyn::lie::{LieGroup, So3};
use framedyn::manifold::{Manifold, Sphere3};
use framedyn::potential::{Centre, Free, Oscillator, Potential};
use framedyn::solve::Save;
use nalgebra::{Matrix3, Vector3};

use super::run;

const M: f64 = 1.3;
const R: f64 = 1.4;
const I: f64 = 0.5;

type State = Gyroscope3State<<Sphere3 as framedyn::bundle::FrameBundle<3, 4>>::Group>;

fn setup<P: Potential<3, 4>>(pot: P, moment: f64) -> (Gyroscope3Model<Sphere3, P>, State) {
    let b = Sphere3::new(R).unwrap();
    let model = Gyroscope3Model::new(b, Gyroscope::<3>::new(M, Matrix3::identity() * (0.5 * moment)).unwrap(), pot).unwrap();
    let x = Vector3::new(0.3, -0.5, 0.4);
    let (p, v) = (b.embed(&x), b.embed_tangent(&x, &Vector3::new(0.4, 0.2, -0.3)));
    let rho = So3::exp(&Vector3::new(0.3, -0.2, 0.5));
    let y0 = model.state_at(&p, &v, &rho, &Vector3::new(0.2, -0.4, 0.35)).unwrap();
    (model, y0)
}

/// (a185): along a free trajectory (m = 1.3, R = 1.4, I = 0.5, DOPRI5 tol
/// 1e-13, t ∈ [0, 10]) the time derivatives of the paper's momenta — by the
/// fourth-order five-point difference of dense-output samples, δ = 1e-2 — are
/// `dS(R)/dt = (2/(mR²)) S_rl × S(R)` and `dS_rl/dt = (1/(mR)) S(R) × S_rl`
/// (measured ≤ 2.1e-11 relative to the rates' scale; bound 1e-8). Contrary
/// case: the equations with the opposite signs (those of a left-invariant
/// frame, SPEC §7) are off by 2.00 (twice the rates). The same for I = 0.5
/// and I = 2.0: the reduced equations contain only m and R — the first and
/// third terms of (a184) are Casimirs (line 6580 says "first and second").
#[test]
fn a185_reduced_equations_hold_along_the_full_flow() {
    for moment in [I, 4.0 * I] {
        let (model, y0) = setup(Free, moment);
        let d = 1e-2;
        let centres: Vec<f64> = (1..=9).map(|k| k as f64).collect();
        let mut times = Vec::new();
        for &t in &centres {
            times.extend([t - 2.0 * d, t - d, t, t + d, t + 2.0 * d]);
        }
        let sol = run(&model, y0, 10.0, 1e-13, |o| o.save(Save::At(times.clone())));
        let mom: Vec<_> = sol.states().iter().map(|y| model.paper_momenta(y)).collect();
        let (mut worst, mut flipped) = (0.0f64, f64::INFINITY);
        for k in 0..centres.len() {
            let w = &mom[5 * k..5 * k + 5];
            let diff = |f: &dyn Fn(usize) -> Vector3<f64>| (f(0) - f(1) * 8.0 + f(3) * 8.0 - f(4)) / (12.0 * d);
            let ds = diff(&|i| w[i].s);
            let dsrl = diff(&|i| w[i].s_rl);
            let (s, srl) = (w[2].s, w[2].s_rl);
            let rhs_s = srl.cross(&s) * (2.0 / (M * R * R));
            let rhs_rl = s.cross(&srl) * (1.0 / (M * R));
            let scale = rhs_s.norm().max(rhs_rl.norm());
            worst = worst.max((ds - rhs_s).norm().max((dsrl - rhs_rl).norm()) / scale);
            flipped = flipped.min((ds + rhs_s).norm().max((dsrl + rhs_rl).norm()) / scale);
        }
        eprintln!("(a185) I = {moment}: along the full flow: worst relative defect {worst:.1e}; with the opposite signs {flipped:.2}");
        assert!(worst <= 1e-8 && flipped >= 0.5);
    }
}

/// (a186): along the same free trajectory `|S(R)|²`, `|S_rl|²` and the three
/// components of `C = (R/2)S(R) + S_rl` are constant (measured ≤ 2.5e-13
/// relative to their scale over t ∈ [0, 20], DOPRI5 tol 1e-13; bound 1e-10),
/// while `S(R)` itself changes by 177 %. Contrary case: in the
/// oscillator potential `(κ/2)R² tan²(r/R)` about the chart centre (not
/// invariant under left translations) `C` is not conserved (relative change 1.73; asserted ≥ 1e-2).
#[test]
fn a186_casimirs_and_c_are_conserved() {
    let (model, y0) = setup(Free, I);
    let sol = run(&model, y0, 20.0, 1e-13, |o| o);
    let m0 = model.paper_momenta(&y0);
    let (c0, (a0, b0)) = (m0.c(R), m0.casimirs());
    let (mut dc, mut da, mut db, mut moved) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for y in sol.states() {
        let p = model.paper_momenta(y);
        let (a, b) = p.casimirs();
        dc = dc.max((p.c(R) - c0).norm() / c0.norm());
        da = da.max((a / a0 - 1.0).abs());
        db = db.max((b / b0 - 1.0).abs());
        moved = moved.max((p.s - m0.s).norm() / m0.s.norm());
    }
    eprintln!("(a186) free: |ΔC|/|C| ≤ {dc:.1e}, |S|² rel {da:.1e}, |S_rl|² rel {db:.1e}; S itself moves by {moved:.2} (relative)");
    assert!(dc <= 1e-10 && da <= 1e-10 && db <= 1e-10 && moved >= 0.1);
    let b = Sphere3::new(R).unwrap();
    let (model, y0) = setup(Oscillator::new(0.8, Centre::sphere3(&b)).unwrap(), I);
    let sol = run(&model, y0, 20.0, 1e-12, |o| o);
    let c0 = model.paper_momenta(&y0).c(R);
    let dc = sol.states().iter().map(|y| (model.paper_momenta(y).c(R) - c0).norm() / c0.norm()).fold(0.0, f64::max);
    eprintln!("(a186) in the oscillator potential: |ΔC|/|C| reaches {dc:.2}");
    assert!(dc >= 1e-2);
    let _ = model.energy(&y0);
}
