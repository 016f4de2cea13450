//! Time one scene run from Rust, the way the Python module's `fd.solve`
//! runs it: clone the scene, `build()`, `run()` into an in-memory sink with
//! a never-raised cancel flag — the Rust side of the Python-overhead
//! benchmark (`scripts/python_overhead.py`, docs/performance.md "From
//! Python").
//!
//! ```text
//! cargo run --release -p framedyn-tests --example scene_timing -- SCENE REPEATS [--sink memory|flat|both]
//! ```
//!
//! `SCENE` is a TOML/JSON scene file or the name of an embedded scene.
//! Each repeat is timed from the clone of the scene to the end of `run`
//! (the records are dropped after the clock stops, as Python frees its
//! array after `fd.solve` returns). Prints one JSON line with, per sink, the
//! minimum wall and thread-CPU seconds (`CLOCK_THREAD_CPUTIME_ID`, the clock
//! of Python's `time.thread_time()`) over the repeats, every repeat's times,
//! and a checksum of the records (Σ bits(xᵢ)·(2i+1) mod 2⁶⁴ over the
//! row-major values) for checking that Python produced the same numbers.
//!
//! Sinks: `memory` is the public [`MemorySink`] (one `Vec` per record: what
//! a Rust user writes); `flat` is [`FlatSink`], the Python module's sink (one
//! row-major buffer that becomes the numpy array), which isolates the cost
//! of the binding itself. `both` alternates them.

// The shared thread-CPU clock of the benches and timing examples.
#[path = "../benches/common/mod.rs"]
mod common;

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use common::thread_time;
use framedyn::scenes::{FlatSink, MemorySink, RecordSink, RunSummary, Scene, SceneStop};

/// Σ bits(xᵢ)·(2i+1) mod 2⁶⁴ over the row-major values (the script
/// computes the same over `Solution.data`).
fn checksum<'a>(values: impl Iterator<Item = &'a f64>) -> u64 {
    values.enumerate().fold(0u64, |acc, (i, x)| acc.wrapping_add(x.to_bits().wrapping_mul(2 * i as u64 + 1)))
}

/// What one timed run leaves: (wall s, thread-CPU s, summary, rows, columns, checksum).
struct Timed {
    wall: f64,
    cpu: f64,
    summary: RunSummary,
    rows: usize,
    columns: usize,
    checksum: u64,
}

fn time_one<S: RecordSink + Default>(scene: &Scene, inspect: impl Fn(&S) -> (usize, usize, u64)) -> Timed {
    let cancel = AtomicBool::new(false);
    let (w0, c0) = (Instant::now(), thread_time());
    // As `framedyn._framedyn.run`: clone the scene, build, run into a fresh sink.
    let s = scene.clone();
    let mut sim = s.build().unwrap_or_else(|e| panic!("scene does not build: {e}"));
    let mut sink = S::default();
    let summary = sim.run(&mut sink, &cancel, &mut |_| {}).unwrap_or_else(|f| panic!("run failed: {f}"));
    let (cpu, wall) = (thread_time() - c0, w0.elapsed().as_secs_f64());
    assert_eq!(summary.stop, SceneStop::Finished, "run did not finish");
    let (rows, columns, checksum) = inspect(&sink);
    drop(sink);
    Timed { wall, cpu, summary, rows, columns, checksum }
}

fn time_memory(scene: &Scene) -> Timed {
    time_one::<MemorySink>(scene, |s| (s.rows.len(), s.columns.len(), checksum(s.rows.iter().flatten())))
}

fn time_flat(scene: &Scene) -> Timed {
    time_one::<FlatSink>(scene, |s| (s.rows, s.columns.len(), checksum(s.data.iter())))
}

fn usage() -> ! {
    eprintln!("usage: scene_timing SCENE REPEATS [--sink memory|flat|both]   (SCENE: a TOML/JSON file or an embedded scene name)");
    std::process::exit(2)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (Some(which), Some(repeats)) = (args.next(), args.next()) else { usage() };
    let repeats: usize = repeats.parse().ok().filter(|&n| n >= 1).unwrap_or_else(|| usage());
    let mut sinks = vec!["memory"];
    while let Some(a) = args.next() {
        match (a.as_str(), args.next().as_deref()) {
            ("--sink", Some("memory")) => sinks = vec!["memory"],
            ("--sink", Some("flat")) => sinks = vec!["flat"],
            ("--sink", Some("both")) => sinks = vec!["memory", "flat"],
            _ => usage(),
        }
    }
    let scene = if std::path::Path::new(&which).is_file() {
        let text = std::fs::read_to_string(&which).unwrap_or_else(|e| panic!("cannot read {which}: {e}"));
        if which.to_ascii_lowercase().ends_with(".json") {
            Scene::from_json_str(&text)
        } else {
            Scene::from_toml_str(&text)
        }
    } else {
        framedyn::scenes::example(&which)
    }
    .unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });

    let mut results = serde_json::Map::new();
    let mut runs: Vec<Vec<Timed>> = sinks.iter().map(|_| Vec::new()).collect();
    for r in 0..repeats {
        // Alternate the order of the sinks between repeats.
        for k in 0..sinks.len() {
            let j = if r % 2 == 0 { k } else { sinks.len() - 1 - k };
            runs[j].push(if sinks[j] == "memory" { time_memory(&scene) } else { time_flat(&scene) });
        }
    }
    let mut agreed = None;
    for (name, ts) in sinks.iter().zip(&runs) {
        let first = &ts[0];
        for t in ts {
            assert_eq!((t.rows, t.columns, t.checksum), (first.rows, first.columns, first.checksum), "repeats differ");
        }
        let key = (first.summary.steps, first.rows, first.columns, first.checksum);
        assert!(agreed.is_none_or(|c| c == key), "the sinks recorded different data");
        agreed = Some(key);
        let min = |f: fn(&Timed) -> f64| ts.iter().map(f).fold(f64::INFINITY, f64::min);
        results.insert(
            name.to_string(),
            serde_json::json!({
                "wall_min_s": min(|t| t.wall),
                "cpu_min_s": min(|t| t.cpu),
                "wall_s": ts.iter().map(|t| t.wall).collect::<Vec<_>>(),
                "cpu_s": ts.iter().map(|t| t.cpu).collect::<Vec<_>>(),
            }),
        );
    }
    let first = &runs[0][0];
    let out = serde_json::json!({
        "scene": which,
        "repeats": repeats,
        "method": first.summary.method,
        "steps": first.summary.steps,
        "records": first.rows,
        "columns": first.columns,
        "checksum": format!("{:016x}", first.checksum),
        "energy_drift": first.summary.energy_drift,
        "sinks": results,
    });
    println!("{out}");
}
