//! Tests of `crates/framedyn/src/scenes/summary.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::scenes::{QualityWarning, RunSummary};

fn summary(e0: f64, drift: f64, defect: f64) -> RunSummary {
    let mut s = RunSummary::new("test", 0.0);
    s.records = 3;
    s.energy_initial = e0;
    s.energy_drift = drift;
    s.max_defect = defect;
    s
}

#[test]
fn judge_flags_drift_defect_and_non_finite_values() {
    let limits = (1e-3, 1e-9);
    let mut s = summary(2.0, 1.9e-3, 1e-15);
    s.judge(limits);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let mut s = summary(2.0, 2.1e-3, 1e-15);
    s.judge(limits);
    assert!(matches!(s.warnings[..], [QualityWarning::EnergyDrift { drift, .. }] if (drift - 1.05e-3).abs() < 1e-12));
    // |E₀| below 1e-12: the drift is judged absolutely.
    let mut s = summary(0.0, 5e-4, 1e-15);
    s.judge(limits);
    assert!(s.warnings.is_empty());
    let mut s = summary(-1e-13, 2e-3, 1e-15);
    s.judge(limits);
    assert_eq!(s.warnings.len(), 1);
    let mut s = summary(1.0, 0.0, 1e-8);
    s.judge(limits);
    assert!(matches!(s.warnings[..], [QualityWarning::Defect { .. }]));
    let mut s = summary(f64::INFINITY, f64::NAN, f64::NAN);
    s.judge(limits);
    assert_eq!(s.warnings, [QualityWarning::NonFinite { what: "energy" }, QualityWarning::NonFinite { what: "constraint defect" }]);
    assert!(s.to_string().contains("WARNING: the energy is not finite"));
    // An infinite limit switches the check off; no records, no verdict.
    let mut s = summary(1.0, 10.0, 0.0);
    s.judge((f64::INFINITY, 1e-9));
    assert!(s.warnings.is_empty());
    let mut s = summary(f64::NAN, f64::NAN, f64::NAN);
    s.records = 0;
    s.judge(limits);
    assert!(s.warnings.is_empty());
    assert_eq!(RunSummary::NUMBER_NAMES.len(), s.numbers().len());
}
