//! Shared by the examples: run a scene into memory, and compare what a run
//! measured with what the paper predicts (the example exits with code 1 if
//! any comparison fails, so the test suite catches a regression).

#![allow(dead_code)]

use std::sync::atomic::AtomicBool;

use framedyn::scenes::{MemorySink, Scene};

/// Runs the scene given as TOML text and returns all its records.
pub fn run(toml: &str) -> Result<MemorySink, Box<dyn std::error::Error>> {
    let scene = Scene::from_toml_str(toml)?;
    let mut sim = scene.build()?;
    let mut sink = MemorySink::default();
    let summary = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {})?;
    if summary.stop != framedyn::scenes::SceneStop::Finished {
        return Err(format!("run stopped early: {}", summary.stop).into());
    }
    Ok(sink)
}

/// A column of a run.
pub fn col(sink: &MemorySink, name: &str) -> Vec<f64> {
    sink.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// The value of `name` in the first and in the last record.
pub fn ends(sink: &MemorySink, name: &str) -> (f64, f64) {
    let c = col(sink, name);
    (c[0], c[c.len() - 1])
}

/// `max |c − c₀|` over the records of the column `name`.
pub fn drift(sink: &MemorySink, name: &str) -> f64 {
    let c = col(sink, name);
    c.iter().map(|v| (v - c[0]).abs()).fold(0.0, f64::max)
}

/// The embedding position (columns `x0 …`) of record `i` (negative: from the end).
pub fn position(sink: &MemorySink, i: isize) -> Vec<f64> {
    let n = sink.rows.len() as isize;
    let i = if i < 0 { n + i } else { i } as usize;
    (0..4).filter_map(|k| sink.column(&format!("x{k}")).map(|c| c[i])).collect()
}

/// Euclidean distance of two vectors.
pub fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Collects comparisons and reports them.
#[derive(Default)]
pub struct Checks {
    failed: Vec<String>,
}

impl Checks {
    /// Prints `what: measured` with the bound and remembers a failure when
    /// `measured > bound` (or is NaN).
    pub fn le(&mut self, what: &str, measured: f64, bound: f64) {
        let ok = measured <= bound;
        println!("  {what:<62} {measured:>10.3e}  (≤ {bound:.0e}) {}", if ok { "ok" } else { "FAILED" });
        if !ok {
            self.failed.push(what.to_string());
        }
    }

    /// Prints a value next to its closed form and checks the relative difference.
    pub fn close(&mut self, what: &str, measured: f64, expected: f64, rel: f64) {
        println!("  {what:<62} {measured:.12}  closed form {expected:.12}");
        self.le(&format!("  relative difference ({what})"), ((measured - expected) / expected).abs(), rel);
    }

    /// Exits with code 1 if any check failed.
    pub fn finish(self) {
        if self.failed.is_empty() {
            println!("all checks passed");
        } else {
            eprintln!("FAILED: {}", self.failed.join("; "));
            std::process::exit(1);
        }
    }
}
