//! Every embedded scene produces the records it produced when
//! `tests/data/scene_records.csv` was written, bit for bit.
//!
//! The file holds, per scene and per record column (and one line for the
//! located events), the number of values and a 64-bit FNV-1a digest of
//! their IEEE bit patterns, with the first and last value for diagnosis.
//! It was written from the code before the driver and method registry were
//! unified, so that refactoring cannot change a trajectory unnoticed. A
//! column a later version adds is allowed; a column that disappears or
//! changes fails.
//!
//! To write the file anew (only for an intended change of the numbers, named
//! in the commit message): `FRAMEDYN_BLESS_RECORDS=1 cargo test --workspace
//! --test methods scenes_golden`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;

use framedyn::scenes::{example, MemorySink, EXAMPLES};

const FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/scene_records.csv");

/// FNV-1a over the bytes of the bit patterns.
fn digest(values: impl IntoIterator<Item = f64>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// `(count, digest, first, last)` per `(scene, column)`; the located events
/// of a scene are the column `#events` (time, direction, terminal flag and
/// the whole record of each, in order).
type Table = BTreeMap<(String, String), (usize, u64, String, String)>;

fn current() -> Table {
    let mut out = Table::new();
    for (name, _) in EXAMPLES {
        let scene = example(name).unwrap();
        let mut sim = scene.build().unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut sink = MemorySink::default();
        sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap_or_else(|f| panic!("{name}: {f}"));
        for (j, c) in sink.columns.iter().enumerate() {
            let vals: Vec<f64> = sink.rows.iter().map(|r| r[j]).collect();
            let first = vals.first().map_or(String::new(), |v| format!("{v:e}"));
            let last = vals.last().map_or(String::new(), |v| format!("{v:e}"));
            out.insert((name.to_string(), c.name.clone()), (vals.len(), digest(vals), first, last));
        }
        if !sink.events.is_empty() {
            let mut vals = Vec::new();
            for e in &sink.events {
                vals.push(e.t);
                vals.push(if e.rising { 1.0 } else { -1.0 });
                vals.push(if e.terminal { 1.0 } else { 0.0 });
                vals.extend_from_slice(&e.row);
            }
            let (first, last) = (format!("{:e}", sink.events[0].t), format!("{:e}", sink.events[sink.events.len() - 1].t));
            out.insert((name.to_string(), "#events".into()), (sink.events.len(), digest(vals), first, last));
        }
    }
    out
}

fn parse(text: &str) -> Table {
    let mut out = Table::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 6, "malformed line {line:?}");
        let digest = u64::from_str_radix(f[3], 16).unwrap_or_else(|e| panic!("{line:?}: {e}"));
        out.insert((f[0].into(), f[1].into()), (f[2].parse().unwrap(), digest, f[4].into(), f[5].into()));
    }
    out
}

#[test]
fn scenes_golden_records_are_unchanged() {
    let now = current();
    if std::env::var_os("FRAMEDYN_BLESS_RECORDS").is_some() {
        let mut text = String::from("scene,column,count,fnv1a64,first,last\n");
        for ((s, c), (n, d, first, last)) in &now {
            writeln!(text, "{s},{c},{n},{d:016x},{first},{last}").unwrap();
        }
        std::fs::write(FILE, text).unwrap();
        return;
    }
    let text = std::fs::read_to_string(FILE).unwrap_or_else(|e| panic!("{FILE}: {e}"));
    let old = parse(&text);
    assert!(!old.is_empty(), "{FILE} is empty");
    let mut bad = Vec::new();
    for ((s, c), (n, d, first, last)) in &old {
        match now.get(&(s.clone(), c.clone())) {
            None => bad.push(format!("{s}: column {c} is gone")),
            Some((n2, d2, first2, last2)) => {
                if (n, d) != (n2, d2) {
                    bad.push(format!("{s}: {c}: {n} values, first {first}, last {last} -> {n2} values, first {first2}, last {last2}"));
                }
            }
        }
    }
    assert!(bad.is_empty(), "records changed:\n{}", bad.join("\n"));
}
