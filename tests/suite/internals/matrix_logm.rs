//! Tests of `crates/framedyn/src/lie/matrix/logm.rs` (through `framedyn::__internals` where it is not public API).
use super::xorshift;
use framedyn::__internals::{amax, expm, logm_switch, norm1, Lu, LOG_DB_MAX_ARG, LOG_DB_MAX_COND};
use nalgebra::SMatrix;

/// Log round-trip errors of the two square-root paths as the eigenvalue
/// angle θ approaches π: the switch `LOG_DB_MAX_ARG` must pick the better
/// one (within a factor 2) at every angle.
#[test]
fn log_paths_crossover() {
    let mut next = xorshift(5);
    for &th in &[1.0, 2.0, 2.2, 2.4, 2.6, 2.8, 3.0, 3.1, std::f64::consts::PI - 0.0016] {
        let mut w = [0.0f64; 3];
        for _ in 0..300 {
            // a = P diag(θJ, x) P⁻¹ with random P (non-normal, moderately conditioned).
            let p = SMatrix::<f64, 3, 3>::identity() + SMatrix::<f64, 3, 3>::from_fn(|_, _| 0.3 * next());
            let d = SMatrix::<f64, 3, 3>::new(0.1 * next(), -th, 0.0, th, 0.1 * next(), 0.0, 0.0, 0.0, next());
            let a = p * d * Lu::new(&p).unwrap().inverse();
            let g = expm(&a);
            let paths = [
                (10.0, f64::INFINITY),
                (-1.0, f64::INFINITY),
                (LOG_DB_MAX_ARG, LOG_DB_MAX_COND),
            ];
            for (i, &(sw, cond)) in paths.iter().enumerate() {
                let l = logm_switch(&g, "test", sw, cond).unwrap();
                w[i] = w[i].max(amax(&(l - a)) / amax(&a));
            }
        }
        println!("θ = {th}: DB {:.1e}  Schur {:.1e}  logm {:.1e}", w[0], w[1], w[2]);
        assert!(
            w[2] <= 2.0 * w[0].min(w[1]),
            "θ = {th}: the switch picks the worse path"
        );
    }
}

/// The measurement behind `LOG_DB_MAX_COND` (slow in the dev profile;
/// run with `--ignored --nocapture`): worst forward error
/// `|log(exp A) − A|/|A|` and backward error `|exp(log g) − g|/(|g||A|)`,
/// in ε, of the two square-root paths binned by κ₁(exp A).
#[test]
#[ignore]
fn log_path_measurement() {
    let mut st = 12345u64;
    type M3 = SMatrix<f64, 3, 3>;
    let mut next = move || {
        st ^= st << 13;
        st ^= st >> 7;
        st ^= st << 17;
        (st >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    // bins of log10 kappa
    let mut w = [[0.0f64; 4]; 12];
    let mut cnt = [0usize; 12];
    for _ in 0..20000 {
        let r1 = 12.0 * (next() + 1.0) / 2.0;
        let r2 = 3.0 * (next() + 1.0) / 2.0;
        let s0 = M3::from_fn(|_, _| next());
        let s0 = s0 + s0.transpose();
        let w0 = M3::from_fn(|_, _| next());
        let w0 = w0 - w0.transpose();
        let n0 = M3::from_fn(|_, _| next());
        let a = s0 * (r1 / s0.norm()) + w0 * (r2 / w0.norm()) + n0 * (0.5 * next());
        let g = expm(&a);
        let ginv = Lu::new(&g).unwrap().inverse();
        let kappa = norm1(&g) * norm1(&ginv);
        let bin = (kappa.log10() as usize).min(11);
        cnt[bin] += 1;
        for (i, sw) in [10.0, -1.0].iter().enumerate() {
            let Ok(l) = logm_switch(&g, "t", *sw, f64::INFINITY) else {
                continue;
            };
            let fwd = amax(&(l - a)) / amax(&a) / f64::EPSILON;
            let back = amax(&(expm(&l) - g)) / amax(&g) / f64::EPSILON / a.norm();
            w[bin][2 * i] = w[bin][2 * i].max(fwd);
            w[bin][2 * i + 1] = w[bin][2 * i + 1].max(back);
        }
    }
    for (b, row) in w.iter().enumerate() {
        print!("n={} ", cnt[b]);
        println!(
            "kappa 1e{b}: DB fwd {:.1} back {:.2} | Schur fwd {:.1} back {:.2}",
            row[0], row[1], row[2], row[3]
        );
    }
}
