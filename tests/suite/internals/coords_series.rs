//! Tests of `crates/framedyn/src/coords/series.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::series::*;
use num_dual::Dual2_64;

/// The truncated Horner sums equal the full ones in value, first and
/// second derivative to 1e-17 relative, at every scale of `s` from 1e-14
/// to the switch — derivatives along a coordinate `x` with `s = x²`, as
/// in the charts (`s = |r̄|²/R²`), where `d²f/dx² = 2f'(s) + 4s f''(s)`.
#[test]
fn truncation_keeps_derivatives_exact() {
    let tables: [&[f64]; 7] = [&SINC, &COS, &DSINC, &SINCCOS_DEFECT, &SINC2_DEFECT, &COT_DEFECT, &VERSC];
    for c in tables {
        for s in [1e-14f64, 1e-10, 1e-7, 1e-4, 1e-2, 0.3, 0.99] {
            let xs = Dual2_64::new(s.sqrt(), 1.0, 0.0);
            let x = xs * xs;
            let full = c.iter().rev().fold(Dual2_64::from_re(0.0), |acc, &ck| acc * x + ck);
            let cut = horner(c, x);
            let scale = c[0].abs();
            assert!((full.re - cut.re).abs() <= 1e-17 * scale, "value at {s}");
            assert!((full.v1 - cut.v1).abs() <= 1e-17 * scale, "first derivative at {s}");
            assert!((full.v2 - cut.v2).abs() <= 1e-17 * scale, "second derivative at {s}");
        }
    }
}

/// Series and closed forms agree at the switch `s = 1` (both sides), and
/// the series match the closed forms where those are well conditioned.
/// Name, the implementation, and the closed form.
type Case = (&'static str, fn(f64) -> f64, fn(f64) -> f64);

#[test]
fn series_match_closed_forms() {
    let closed: [Case; 7] = [
        ("sinc", sinc::<f64>, |s| s.sqrt().sin() / s.sqrt()),
        ("cos", cos::<f64>, |s| s.sqrt().cos()),
        ("dsinc", dsinc::<f64>, |s| {
            let t = s.sqrt();
            (t.cos() - t.sin() / t) / s
        }),
        ("sinccos", sinccos_defect::<f64>, |s| {
            let t = s.sqrt();
            (1.0 - t.cos() * t.sin() / t) / s
        }),
        ("sinc2", sinc2_defect::<f64>, |s| {
            let t = s.sqrt();
            (1.0 - (t.sin() / t).powi(2)) / s
        }),
        ("cot", cot_defect::<f64>, |s| {
            let t = s.sqrt();
            (1.0 - t / t.tan()) / s
        }),
        ("versc", versc::<f64>, |s| (1.0 - s.sqrt().cos()) / s),
    ];
    for (name, f, c) in closed {
        for s in [0.3, 0.6, 0.9, 0.999_999, 1.0, 1.000_001, 1.5] {
            let (a, b) = (f(s), c(s));
            // The closed forms cancel by up to ~10× at s = 0.3, so allow 1e-14.
            assert!((a - b).abs() <= 1e-14 * b.abs(), "{name}({s}): {a} vs {b}");
        }
    }
}
