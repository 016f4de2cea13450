//! The `framedyn` binary: every embedded scene against the library call,
//! CSV and npz round trips, exit codes and messages, atomic output,
//! interruption, flat memory on long streamed runs, mutated scene files.

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use framedyn::analysis::{GaliOptions, LyapunovOptions};
use framedyn::scenes::{example, MemorySink, Scene, DEFAULT_SCENE, EXAMPLES};
use proptest::prelude::*;

const BIN: &str = env!("CARGO_BIN_EXE_framedyn");

/// A test's scratch directory (`framedyn-cli-TAG-PID` in the system's
/// temporary directory), removed when the test passes and kept when it
/// fails, for inspection.
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = fs::remove_dir_all(&self.0);
        }
    }
}

fn tmpdir(tag: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("framedyn-cli-{tag}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

fn framedyn(args: &[&str], dir: &Path) -> Output {
    Command::new(BIN).args(args).current_dir(dir).stdin(Stdio::null()).output().unwrap()
}

fn code(o: &Output) -> i32 {
    o.status.code().unwrap_or(-1)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Parses a CSV written by the tool: header and rows of numbers (a partial
/// result's closing `# partial: …` line is skipped).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let r: Vec<f64> = l.split(',').map(|v| v.parse::<f64>().unwrap()).collect();
            assert_eq!(r.len(), header.len(), "ragged row");
            r
        })
        .collect();
    (header, rows)
}

/// Parses one `.npy` member: header dict and payload.
fn parse_npy(bytes: &[u8]) -> (String, &[u8]) {
    assert_eq!(&bytes[..6], b"\x93NUMPY");
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + hlen) % 64, 0, "npy header not aligned");
    (String::from_utf8(bytes[10..10 + hlen].to_vec()).unwrap(), &bytes[10 + hlen..])
}

fn read_npz(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut z = zip::ZipArchive::new(fs::File::open(path).unwrap()).unwrap();
    let mut member = |name: &str| {
        let mut v = Vec::new();
        z.by_name(name).unwrap().read_to_end(&mut v).unwrap();
        v
    };
    let data = member("data.npy");
    let cols = member("columns.npy");
    let (h, payload) = parse_npy(&data);
    assert!(h.contains("'descr': '<f8'") && h.contains("'fortran_order': False"), "{h}");
    let shape = h.split("'shape': (").nth(1).unwrap().split(')').next().unwrap();
    let dims: Vec<usize> = shape.split(',').filter_map(|s| s.trim().parse().ok()).collect();
    let (n, m) = (dims[0], dims[1]);
    assert_eq!(payload.len(), n * m * 8);
    let vals: Vec<f64> = payload.chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
    let (ch, cp) = parse_npy(&cols);
    let width: usize = ch.split("'<U").nth(1).unwrap().split('\'').next().unwrap().parse().unwrap();
    let names: Vec<String> = cp
        .chunks(4 * width)
        .map(|c| c.chunks(4).map(|u| u32::from_le_bytes(u.try_into().unwrap())).filter(|&u| u != 0).filter_map(char::from_u32).collect())
        .collect();
    assert_eq!(names.len(), m);
    (names, vals.chunks(m).map(|r| r.to_vec()).collect())
}

/// The one string of `stop.npy` in a run's `.npz`.
fn npz_stop(path: &Path) -> String {
    let mut z = zip::ZipArchive::new(fs::File::open(path).unwrap()).unwrap();
    let mut v = Vec::new();
    z.by_name("stop.npy").unwrap().read_to_end(&mut v).unwrap();
    let (_, payload) = parse_npy(&v);
    payload.chunks(4).map(|u| u32::from_le_bytes(u.try_into().unwrap())).filter(|&u| u != 0).filter_map(char::from_u32).collect()
}

/// Equal values, NaN equal to NaN (coordinates at a chart pole).
fn same_rows(a: &[Vec<f64>], b: &[Vec<f64>]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p == q || (p.is_nan() && q.is_nan())))
}

fn library_run(scene: &Scene) -> (framedyn::scenes::RunSummary, MemorySink) {
    let mut sim = scene.build().unwrap();
    let mut sink = MemorySink::default();
    let s = sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
    (s, sink)
}

/// The number after `key` in the summary.
fn summary_number(out: &str, key: &str) -> u64 {
    let line = out.lines().find(|l| l.starts_with(key)).unwrap_or_else(|| panic!("no {key} in {out}"));
    line[key.len()..].split_whitespace().next().unwrap().parse().unwrap()
}

/// Every embedded scene through the binary equals the library call: same
/// summary counts and bit-identical CSV records.
#[test]
fn every_embedded_scene_matches_the_library() {
    let dir = tmpdir("all");
    for (name, _) in EXAMPLES {
        let out = dir.join(format!("{name}.csv"));
        let o = framedyn(&["run", name, "--output", out.to_str().unwrap()], &dir);
        assert_eq!(code(&o), 0, "{name}: {}", stderr(&o));
        assert!(stderr(&o).is_empty(), "{name}: no progress bar without a terminal: {}", stderr(&o));
        let (s, sink) = library_run(&example(name).unwrap());
        let text = stdout(&o);
        assert_eq!(summary_number(&text, "steps:"), s.steps, "{name}");
        assert_eq!(summary_number(&text, "records:"), s.records, "{name}");
        assert!(text.contains("stop:            finished"), "{text}");
        let (header, rows) = read_csv(&out);
        assert_eq!(header, sink.columns.iter().map(|c| c.name.clone()).collect::<Vec<_>>());
        assert!(same_rows(&rows, &sink.rows), "{name}: CSV differs from the library records");
    }
}

/// `run` without a scene runs the default scene into `trajectory.csv`.
#[test]
fn default_run_and_listing() {
    let dir = tmpdir("default");
    let o = framedyn(&["run"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("trajectory.csv"));
    let (_, rows) = read_csv(&dir.join("trajectory.csv"));
    assert!(rows.len() > 100);
    let o = framedyn(&["scenes"], &dir);
    assert_eq!(code(&o), 0);
    for (name, _) in EXAMPLES {
        assert!(stdout(&o).contains(name));
    }
    assert!(stdout(&o).contains(&format!("{DEFAULT_SCENE} ")));
    let o = framedyn(&["scenes", "show", "s3-gyroscope"], &dir);
    assert_eq!(code(&o), 0);
    assert_eq!(stdout(&o), EXAMPLES.iter().find(|(n, _)| *n == "s3-gyroscope").unwrap().1);
    // The shown scene is a valid starting point.
    fs::write(dir.join("mine.toml"), stdout(&o)).unwrap();
    let o = framedyn(&["validate", "mine.toml"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let o = framedyn(&["scenes", "show", "nope"], &dir);
    assert_eq!(code(&o), 3);
    assert!(stderr(&o).contains(DEFAULT_SCENE));
}

/// The npz archive holds the same numbers as the CSV, and numpy reads it.
#[test]
fn npz_round_trip() {
    let dir = tmpdir("npz");
    let o = framedyn(&["run", "s2-affine-elastic", "--output", "a.csv", "--quiet"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).is_empty(), "--quiet prints nothing");
    let o = framedyn(&["run", "s2-affine-elastic", "--output", "a.npz", "--quiet"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let (h1, r1) = read_csv(&dir.join("a.csv"));
    let (h2, r2) = read_npz(&dir.join("a.npz"));
    assert_eq!(h1, h2);
    assert!(same_rows(&r1, &r2));
    // numpy, where available, loads it without pickle.
    let script = "import numpy as np, sys\nd = np.load(sys.argv[1])\nprint(d['data'].shape[0], d['data'].shape[1], list(d['columns'])[0], float(d['data'][-1, 0]))";
    if let Ok(out) = Command::new("python3").arg("-c").arg(script).arg(dir.join("a.npz")).output() {
        if out.status.success() {
            let s = String::from_utf8_lossy(&out.stdout);
            let f: Vec<&str> = s.split_whitespace().collect();
            assert_eq!(f[0].parse::<usize>().unwrap(), r1.len());
            assert_eq!(f[1].parse::<usize>().unwrap(), h1.len());
            assert_eq!(f[2], "t");
            assert_eq!(f[3].parse::<f64>().unwrap(), r1.last().unwrap()[0]);
        } else {
            eprintln!("numpy not available: {}", String::from_utf8_lossy(&out.stderr));
        }
    }
}

/// Exit codes and messages: invalid scene (field, line, column), unknown
/// scene, integration failure with partial output, I/O error.
#[test]
fn exit_codes_and_messages() {
    let dir = tmpdir("codes");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    fs::write(dir.join("bad.toml"), text.replace("mass = 1.0", "mass = -1.0")).unwrap();
    fs::write(dir.join("out.csv"), "OLD").unwrap();
    let o = framedyn(&["run", "bad.toml", "--output", "out.csv"], &dir);
    assert_eq!(code(&o), 3);
    let e = stderr(&o);
    assert!(e.contains("body") && e.contains("-1") && e.contains("> 0") && e.contains("line 10"), "{e}");
    assert_eq!(fs::read_to_string(dir.join("out.csv")).unwrap(), "OLD", "an invalid scene leaves the output untouched");
    let o = framedyn(&["validate", "bad.toml"], &dir);
    assert_eq!(code(&o), 3);
    fs::write(dir.join("typo.toml"), text.replace("[time]", "[time]\nt_ned = 3.0")).unwrap();
    let o = framedyn(&["validate", "typo.toml"], &dir);
    assert_eq!(code(&o), 3);
    assert!(stderr(&o).contains("t_ned") && stderr(&o).contains("line"), "{}", stderr(&o));
    let o = framedyn(&["validate", "no-such-scene"], &dir);
    assert_eq!(code(&o), 3);
    let o = framedyn(&["run", "--bogus-flag"], &dir);
    assert_eq!(code(&o), 2);
    // Integration failure: the step limit is hit after 50 adaptive steps.
    let failing = text.replace("name = \"rk4\"\nh = 0.005", "name = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\nmax_steps = 50").replace("every = 4", "every = 1");
    fs::write(dir.join("fail.toml"), &failing).unwrap();
    // A complete file from an earlier run is not replaced by the failed
    // run's records: those go to STEM.partial.EXT, marked as partial.
    fs::write(dir.join("fail.csv"), "GOOD").unwrap();
    let o = framedyn(&["run", "fail.toml", "--output", "fail.csv"], &dir);
    assert_eq!(code(&o), 4, "{}", stderr(&o));
    assert!(stderr(&o).contains("maximum number of steps") && stderr(&o).contains("fail.partial.csv"), "{}", stderr(&o));
    assert_eq!(fs::read_to_string(dir.join("fail.csv")).unwrap(), "GOOD");
    let (_, rows) = read_csv(&dir.join("fail.partial.csv"));
    assert_eq!(rows.len(), 51, "the initial state and 50 steps are kept");
    let last = fs::read_to_string(dir.join("fail.partial.csv")).unwrap().lines().last().unwrap().to_string();
    assert!(last.starts_with("# partial: integration failed") && last.contains("maximum number of steps"), "{last}");
    let o = framedyn(&["run", "fail.toml", "--output", "fail.npz"], &dir);
    assert_eq!(code(&o), 4, "{}", stderr(&o));
    assert!(!dir.join("fail.npz").exists());
    assert_eq!(read_npz(&dir.join("fail.partial.npz")).1.len(), 51);
    assert!(npz_stop(&dir.join("fail.partial.npz")).starts_with("partial: integration failed"));
    // I/O error: the output directory does not exist.
    let o = framedyn(&["run", "--output", "missing/dir/out.csv"], &dir);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    // Garbage bytes.
    fs::write(dir.join("garbage.toml"), [0xff, 0xfe, 0x00, 0x41]).unwrap();
    let o = framedyn(&["validate", "garbage.toml"], &dir);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    // JSON scenes.
    let scene = example("s2-point-kepler").unwrap();
    fs::write(dir.join("k.json"), scene.to_json_string()).unwrap();
    let o = framedyn(&["validate", "k.json"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let leftovers: Vec<_> = fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()).filter(|e| e.file_name().to_string_lossy().contains(".tmp-")).collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

/// Tolerances out of range are scene errors (exit 3) naming the field, the
/// value and the allowed range, before any run; `global_error = true` adds
/// the estimate to the printed summary.
#[test]
fn tolerance_errors_and_the_global_error_line() {
    let dir = tmpdir("tol");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    for (tols, field, allowed) in [
        ("rtol = 1e-300\natol = 1e-300", "method.rtol", "≥ 1e-14"),
        ("rtol = 0.0\natol = 1e-8", "method.rtol", "≥ 1e-14"),
        ("rtol = 1e-8\natol = 0.0", "method.atol", "> 0"),
        ("rtol = 1e-8\natol = -1e-8", "method.atol", "> 0"),
    ] {
        fs::write(dir.join("tol.toml"), text.replace("name = \"rk4\"\nh = 0.005", &format!("name = \"dop853\"\n{tols}"))).unwrap();
        let o = framedyn(&["run", "tol.toml", "--output", "tol.csv"], &dir);
        assert_eq!(code(&o), 3, "{tols}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(field) && e.contains(allowed), "{tols}: {e}");
        assert!(!dir.join("tol.csv").exists());
    }
    fs::write(dir.join("ge.toml"), text.replace("name = \"rk4\"\nh = 0.005", "name = \"dop853\"\nrtol = 1e-8\natol = 1e-8\nglobal_error = true")).unwrap();
    let o = framedyn(&["run", "ge.toml", "--output", "ge.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("global error:    estimated max"), "{}", stdout(&o));
    let o = framedyn(&["run", "--output", "plain.csv"], &dir);
    assert!(!stdout(&o).contains("global error"), "{}", stdout(&o));
}

/// `project = "energy"` adds the projection's counts to the printed summary
/// (every step projected, the energy held); any other value is a scene error
/// (exit 3) naming `method.project` and the allowed values, before any run.
#[test]
fn energy_projection_line_and_errors() {
    let dir = tmpdir("project");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    let with = |extra: &str| text.replace("name = \"rk4\"\nh = 0.005", &format!("name = \"dop853\"\nrtol = 1e-8\natol = 1e-8\n{extra}"));
    fs::write(dir.join("p.toml"), with("project = \"energy\"")).unwrap();
    let o = framedyn(&["run", "p.toml", "--output", "p.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    let steps = summary_number(&out, "steps:");
    assert!(out.contains(&format!("projection:      energy, {steps} steps projected, 0 skipped")), "{out}");
    for bad in ["\"momentum\"", "1"] {
        fs::write(dir.join("bad.toml"), with(&format!("project = {bad}"))).unwrap();
        let o = framedyn(&["run", "bad.toml", "--output", "bad.csv"], &dir);
        assert_eq!(code(&o), 3, "{bad}: {}", stderr(&o));
        assert!(stderr(&o).contains("method.project"), "{bad}: {}", stderr(&o));
        assert!(!dir.join("bad.csv").exists());
    }
}

/// SIGINT, SIGTERM and SIGHUP stop a long run cleanly: exit 128 + signal,
/// the complete file already at the output path is left as it was, the
/// records computed so far are a valid partial result beside it, and no
/// temporary file is left.
#[test]
fn signals_keep_a_valid_partial_result() {
    let dir = tmpdir("signals");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    fs::write(dir.join("long.toml"), text.replace("t_end = 4.0", "t_end = 400000.0").replace("every = 4", "every = 100")).unwrap();
    for (sig, exit, fmt) in [("INT", 130, "csv"), ("TERM", 143, "npz"), ("HUP", 129, "csv"), ("TERM", 143, "csv")] {
        let out = format!("long.{fmt}");
        fs::write(dir.join(&out), "COMPLETE").unwrap();
        let _ = fs::remove_file(dir.join(format!("long.partial.{fmt}")));
        let child = Command::new(BIN).args(["run", "long.toml", "--output", &out]).current_dir(&dir).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        let st = Command::new("kill").args([format!("-{sig}"), child.id().to_string()]).status().unwrap();
        assert!(st.success());
        let o = child.wait_with_output().unwrap();
        assert_eq!(code(&o), exit, "SIG{sig}: {}", stderr(&o));
        assert!(stderr(&o).contains(&format!("interrupted by SIG{sig}")), "{}", stderr(&o));
        assert_eq!(fs::read_to_string(dir.join(&out)).unwrap(), "COMPLETE", "SIG{sig} replaced the complete output");
        let path = dir.join(format!("long.partial.{fmt}"));
        let rows = if fmt == "csv" { read_csv(&path).1 } else { read_npz(&path).1 };
        assert!(!rows.is_empty());
        let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        assert!(t.windows(2).all(|w| w[1] > w[0]));
        assert!(*t.last().unwrap() < 400000.0);
        if fmt == "npz" {
            assert!(npz_stop(&path).starts_with(&format!("partial: interrupted by SIG{sig}")), "{}", npz_stop(&path));
        }
    }
    let leftovers: Vec<_> = fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()).filter(|e| e.file_name().to_string_lossy().starts_with('.')).collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

/// A run whose output could reach hundreds of GB is announced before it
/// starts (estimate from the step count, the sampling and the columns);
/// with `--no-space-check` it starts even where it cannot fit.
#[test]
fn huge_outputs_are_announced() {
    let dir = tmpdir("huge");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    fs::write(dir.join("huge.toml"), text.replace("h = 0.005", "h = 4e-9").replace("every = 4", "every = 1")).unwrap();
    let child = Command::new(BIN)
        .args(["run", "-q", "huge.toml", "--output", "huge.csv", "--no-space-check"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(500));
    assert!(Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap().success());
    let o = child.wait_with_output().unwrap();
    let e = stderr(&o);
    assert!(e.contains("note: this run can write up to 1000000002 records") && e.contains("GB as csv") && e.contains("output.every"), "{e}");
    assert_eq!(code(&o), 143, "{e}");
}

/// Runs `args` in `dir`, killing it if it has not ended after `limit`.
fn framedyn_within(args: &[&str], dir: &Path, limit: Duration) -> (Output, Duration) {
    let started = Instant::now();
    let mut child = Command::new(BIN).args(args).current_dir(dir).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > limit {
            let _ = child.kill();
            let o = child.wait_with_output().unwrap();
            panic!("`framedyn {}` still running after {limit:?}: the check did not come before the run; stderr: {}", args.join(" "), stderr(&o));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    (child.wait_with_output().unwrap(), started.elapsed())
}

/// An output that cannot fit in the free space of its file system is
/// refused before the run starts: exit 5, a message naming the estimate,
/// the free space, the directory and the settings to change, and no file
/// written — for `run` (CSV and npz) and `sweep`. A small run still runs,
/// and the CSV estimate per value is near what a real run writes.
#[test]
fn free_space_is_checked_before_a_run() {
    use framedyn_cli::space::{OutputEstimate, CSV_BYTES_PER_VALUE};
    let dir = tmpdir("space");
    let shown = fs::canonicalize(&dir).unwrap().display().to_string();
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    // 10^12 fixed steps, every one recorded: hundreds of TB as CSV; a run
    // that started would take days.
    let huge = text.replace("h = 0.005", "h = 4e-12\nmax_steps = 10000000000000").replace("every = 4", "every = 1");
    fs::write(dir.join("huge.toml"), &huge).unwrap();
    assert_eq!(code(&framedyn(&["validate", "huge.toml"], &dir)), 0, "the scene must be valid: the refusal is about space");
    let limit = Duration::from_secs(30);
    for (format, unit) in [("csv", "as csv"), ("npz", "as npz with its raw temporary file")] {
        let out = format!("huge.{format}");
        let (o, took) = framedyn_within(&["run", "-q", "huge.toml", "--output", &out], &dir, limit);
        let e = stderr(&o);
        assert_eq!(code(&o), 5, "{e}");
        for part in ["not enough free space", "up to 1000000000002 records", unit, " free", &shown, "output.every", "output.samples", "--output", "nothing was written"] {
            assert!(e.contains(part), "`{part}` missing from: {e}");
        }
        let left: Vec<_> = fs::read_dir(&dir).unwrap().map(|f| f.unwrap().file_name().into_string().unwrap()).filter(|f| f != "huge.toml").collect();
        assert!(left.is_empty(), "files written: {left:?}");
        assert!(took < Duration::from_secs(10), "refused after {took:?}");
    }
    // A sweep of two such members.
    fs::write(dir.join("members.csv"), "initial.r\n0.5\n0.6\n").unwrap();
    let (o, _) = framedyn_within(&["sweep", "huge.toml", "--table", "members.csv", "--output", "sweep.npz"], &dir, limit);
    let e = stderr(&o);
    assert_eq!(code(&o), 5, "{e}");
    for part in ["not enough free space", "up to 2000000000004 records", &shown, "--keep final", "--samples", "--output"] {
        assert!(e.contains(part), "`{part}` missing from: {e}");
    }
    assert!(!dir.join("sweep.npz").exists() && !dir.join("sweep.partial.npz").exists());
    // A small run and a small sweep still run.
    let o = framedyn(&["run", "-q", "--output", "small.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    let o = framedyn(&["sweep", DEFAULT_SCENE, "--table", "members.csv", "--output", "small.npz", "-q"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(dir.join("small.npz").exists());
    // The CSV estimate against what the default scene wrote.
    let (header, rows) = read_csv(&dir.join("small.csv"));
    let values = (rows.len() * header.len()) as f64;
    let per_value = fs::metadata(dir.join("small.csv")).unwrap().len() as f64 / values;
    assert!((0.5 * CSV_BYTES_PER_VALUE..=1.5 * CSV_BYTES_PER_VALUE).contains(&per_value), "{per_value} bytes per value");
    assert!(OutputEstimate::new(rows.len() as u64, header.len(), framedyn::scenes::Format::Csv).file_bytes >= values * per_value);
}

/// The output policy: symbolic links written through, special and
/// read-only files refused with exit 5 and left as they were, long names,
/// stale temporaries of dead processes removed, and an events file that
/// cannot be written leaves no trajectory either (exit 5: nothing written).
#[test]
fn output_policy() {
    use std::os::unix::fs::{symlink, PermissionsExt};
    let dir = tmpdir("policy");
    // Symlink: the file it points to is updated, the link stays a link.
    fs::create_dir_all(dir.join("data")).unwrap();
    fs::write(dir.join("data/real.csv"), "OLD").unwrap();
    symlink("data/real.csv", dir.join("link.csv")).unwrap();
    let o = framedyn(&["run", "-q", "--output", "link.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(fs::symlink_metadata(dir.join("link.csv")).unwrap().file_type().is_symlink());
    assert!(read_csv(&dir.join("data/real.csv")).1.len() > 1);
    assert!(fs::read_dir(dir.join("data")).unwrap().count() == 1, "a temporary file was left beside the real file");
    // Read-only file: refused, untouched (also when run as root).
    fs::write(dir.join("ro.csv"), "KEEP").unwrap();
    fs::set_permissions(dir.join("ro.csv"), fs::Permissions::from_mode(0o444)).unwrap();
    let o = framedyn(&["run", "-q", "--output", "ro.csv"], &dir);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("ro.csv") && stderr(&o).contains("read-only"), "{}", stderr(&o));
    assert_eq!(fs::read_to_string(dir.join("ro.csv")).unwrap(), "KEEP");
    // Special files: refused, never replaced by a regular file.
    let o = framedyn(&["run", "-q", "--output", "/dev/null"], &dir);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("character device"), "{}", stderr(&o));
    assert!(!fs::metadata("/dev/null").unwrap().is_file());
    let fifo = dir.join("pipe.csv");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let o = framedyn(&["run", "-q", "--output", "pipe.csv"], &dir);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("FIFO"), "{}", stderr(&o));
    // A 250-byte file name: its temporary name is shortened to fit.
    let long = format!("{}.csv", "x".repeat(246));
    let o = framedyn(&["run", "-q", "--output", &long], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(read_csv(&dir.join(&long)).1.len() > 1);
    // Stale temporaries of the same target (PID 4000000 exceeds Linux's
    // pid_max, so that process cannot be running) are removed.
    fs::write(dir.join(".stale.csv.tmp-4000000"), "junk").unwrap();
    fs::write(dir.join(".stale.csv.raw-4000000"), "junk").unwrap();
    let o = framedyn(&["run", "-q", "--output", "stale.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(!dir.join(".stale.csv.tmp-4000000").exists() && !dir.join(".stale.csv.raw-4000000").exists());
    // The events file cannot be written (a directory is in its place):
    // exit 5 and no trajectory either.
    let scene = example("s2-gyroscope-splitting").unwrap();
    assert!(!scene.events.is_empty(), "the scene has events");
    fs::write(dir.join("k.json"), scene.to_json_string()).unwrap();
    fs::create_dir_all(dir.join("k.events.csv")).unwrap();
    let o = framedyn(&["run", "-q", "k.json", "--output", "k.csv"], &dir);
    assert_eq!(code(&o), 5, "{}", stderr(&o));
    assert!(stderr(&o).contains("no output written"), "{}", stderr(&o));
    assert!(!dir.join("k.csv").exists());
    let leftovers: Vec<_> = fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()).filter(|e| e.file_name().to_string_lossy().starts_with('.')).collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

/// Peak resident memory (kB) of a run, polled from /proc while it runs.
fn peak_rss_kb(args: &[&str], dir: &Path) -> (u64, Output) {
    let mut child = Command::new(BIN).args(args).current_dir(dir).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let status = format!("/proc/{}/status", child.id());
    let mut peak = 0u64;
    let start = Instant::now();
    loop {
        if let Ok(s) = fs::read_to_string(&status) {
            for l in s.lines() {
                if let Some(v) = l.strip_prefix("VmHWM:").or_else(|| l.strip_prefix("VmRSS:")) {
                    if let Some(kb) = v.split_whitespace().next().and_then(|x| x.parse::<u64>().ok()) {
                        peak = peak.max(kb);
                    }
                }
            }
        }
        if child.try_wait().unwrap().is_some() || start.elapsed() > Duration::from_secs(300) {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    (peak, child.wait_with_output().unwrap())
}

/// Memory stays flat on a long streamed run: ten times the records (tens of
/// megabytes of output) cost no more resident memory.
#[test]
fn streaming_memory_is_flat() {
    if !Path::new("/proc/self/status").exists() {
        eprintln!("no /proc: skipped");
        return;
    }
    let dir = tmpdir("rss");
    let text = EXAMPLES.iter().find(|(n, _)| *n == "s2-point-kepler").unwrap().1;
    let make = |steps: u64, name: &str| {
        let t_end = steps as f64 * 0.005;
        fs::write(
            dir.join(name),
            text.replace("t_end = 10.0", &format!("t_end = {t_end}")).replace("every = 10", "every = 1\nquantities = [\"position\"]"),
        )
        .unwrap();
    };
    make(100_000, "short.toml");
    make(1_000_000, "long.toml");
    for fmt in ["csv", "npz"] {
        let (small, o1) = peak_rss_kb(&["run", "short.toml", "--quiet", "--output", &format!("short.{fmt}")], &dir);
        assert_eq!(code(&o1), 0, "{}", stderr(&o1));
        let (large, o2) = peak_rss_kb(&["run", "long.toml", "--quiet", "--output", &format!("long.{fmt}")], &dir);
        assert_eq!(code(&o2), 0, "{}", stderr(&o2));
        let size = fs::metadata(dir.join(format!("long.{fmt}"))).unwrap().len();
        // 1e6 records of 4 numbers: 32 MB as f64 in memory.
        assert!(size > 30_000_000, "{fmt}: output {size} bytes");
        eprintln!("{fmt}: peak RSS {small} kB for 1e5 records, {large} kB for 1e6 ({size} bytes written)");
        assert!(large < small + 8_000, "{fmt}: peak RSS {small} kB for 1e5 records, {large} kB for 1e6");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Mutated scene files (wrong types, out-of-range values, missing and
    /// unknown fields, garbage bytes) never crash the tool: a clean exit
    /// code with a message.
    #[test]
    fn mutated_scene_files_never_panic(
        pos in 0usize..900,
        len in 0usize..12,
        junk in proptest::collection::vec(any::<u8>(), 0..10),
        choice in 0usize..6,
    ) {
        let dir = tmpdir(&format!("prop{}", pos * 1000 + len));
        let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1.as_bytes().to_vec();
        let mutated: Vec<u8> = match choice {
            0 => { let s = pos.min(text.len()); let e = (s + len).min(text.len()); [&text[..s], &junk[..], &text[e..]].concat() }
            1 => String::from_utf8_lossy(&text).replace("mass = 1.0", "mass = [1, 2]").into_bytes(),
            2 => String::from_utf8_lossy(&text).replace("t_end = 4.0", "").into_bytes(),
            3 => String::from_utf8_lossy(&text).replace("[output]", "[output]\ncolour = \"red\"").into_bytes(),
            4 => String::from_utf8_lossy(&text).replace("radius = 1.0", &format!("radius = {}", -(pos as f64))).into_bytes(),
            _ => junk.clone(),
        };
        fs::write(dir.join("m.toml"), &mutated).unwrap();
        let o = framedyn(&["validate", "m.toml"], &dir);
        let c = code(&o);
        prop_assert!(c == 0 || c == 3, "exit {c}: {}", stderr(&o));
        prop_assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
        if c == 3 { prop_assert!(stderr(&o).contains("invalid scene") || stderr(&o).contains("no scene")); }
        if choice >= 1 && choice <= 3 { prop_assert_eq!(c, 3); }
    }
}

/// `framedyn validate` refuses a method the model does not support (exit 3,
/// naming `method.name`, the value and the allowed methods); a scene with
/// events writes `STEM.events.csv` whose rows match the library's events.
#[test]
fn methods_and_events_files() {
    let dir = tmpdir("events");
    let text = EXAMPLES.iter().find(|(n, _)| *n == "s2-affine-elastic").unwrap().1;
    let bad = text.replacen("name = \"rk4\"", "name = \"strang\"", 1);
    assert_ne!(bad, text, "the example uses rk4");
    fs::write(dir.join("bad.toml"), &bad).unwrap();
    let o = framedyn(&["validate", "bad.toml"], &dir);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("method.name") && e.contains("strang") && e.contains("implicit_midpoint") && e.contains("line"), "{e}");

    let scene = example("s2-gyroscope-splitting").unwrap();
    let mut short = scene.clone();
    short.time.t_end = 40.0;
    fs::write(dir.join("split.toml"), short.to_toml_string()).unwrap();
    let o = framedyn(&["run", "split.toml", "--output", "traj.npz", "--quiet"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = fs::read_to_string(dir.join("traj.events.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let mut f = l.split(',');
            assert_eq!(f.next(), Some("section"));
            f.map(|v| v.parse::<f64>().unwrap()).collect()
        })
        .collect();
    let (_, sink) = library_run(&short);
    assert!(!sink.events.is_empty());
    assert_eq!(rows.len(), sink.events.len());
    assert_eq!(header[..3], ["event", "rising", "terminal"]);
    for (r, e) in rows.iter().zip(&sink.events) {
        assert_eq!(r[2..], e.row[..]);
        assert_eq!((r[0], r[1]), (1.0, 0.0));
    }
}

/// An invalid parameter is reported at that parameter: also when a
/// constructor takes several (`mu` of a neo-Hookean body, not `lambda`;
/// `beta_hat` of the cosine family, not `alpha_hat`), when a value is
/// derived from it (J from `inertia`, the embedding from `r`), when the TOML
/// parser rejects it before any field is read, and when two fields conflict.
#[test]
fn errors_name_the_parameter_at_fault() {
    let dir = tmpdir("blame");
    let cases = [
        ("s3-affine-neo-hookean", "mu = ", "mu = -1.0", "potential.mu"),
        ("s3-affine-neo-hookean", "lambda = ", "lambda = -1.0", "potential.lambda"),
        ("s3-incompressible-svk", "mu = ", "mu = -1.0", "potential.mu"),
        (DEFAULT_SCENE, "beta_hat = ", "beta_hat = nan", "potential.beta_hat"),
        (DEFAULT_SCENE, "alpha_hat = ", "alpha_hat = inf", "potential.alpha_hat"),
        // J built from an inertia too small for double precision.
        ("s2-affine-elastic", "inertia = ", "inertia = 1e-300", "body.inertia"),
        // Both inertia and J: one would be ignored.
        (DEFAULT_SCENE, "inertia = ", "inertia = -5.0\nJ = [[0.1, 0.0], [0.0, 0.1]]", "body.inertia"),
        // An integer beyond 64 bits, rejected by the TOML parser itself.
        (DEFAULT_SCENE, "every = ", "every = 99999999999999999999", "output.every"),
        // A point of H² whose embedding overflows: the coordinate is at fault.
        ("h2-gyroscope", "r = ", "r = 800.0", "initial.r"),
    ];
    for (scene, key, line, field) in cases {
        let text = EXAMPLES.iter().find(|(n, _)| *n == scene).unwrap().1;
        let mut found = false;
        let changed: String = text
            .lines()
            .map(|l| if l.starts_with(key) && !found { found = true; line.to_string() } else { l.to_string() })
            .collect::<Vec<_>>()
            .join("\n");
        assert!(found, "{scene} has no `{key}`");
        fs::write(dir.join("s.toml"), changed).unwrap();
        let o = framedyn(&["validate", "s.toml"], &dir);
        assert_eq!(code(&o), 3, "{scene}: {}", stderr(&o));
        assert!(stderr(&o).contains(&format!("`{field}`")), "{scene} with {line}: {}", stderr(&o));
    }
}

/// The quality check: a finished run whose energy drift exceeds the limit
/// exits 6 with its complete output in place and the warning in the
/// summary; `[quality]` sets the limits (inf switches the check off) and a
/// bad limit is an invalid scene naming the field.
#[test]
fn quality_check() {
    let dir = tmpdir("quality");
    let text = EXAMPLES.iter().find(|(n, _)| *n == DEFAULT_SCENE).unwrap().1;
    let crude = text.replace("name = \"rk4\"\nh = 0.005", "name = \"lie_euler\"\nh = 0.05");
    assert_ne!(crude, text);
    fs::write(dir.join("crude.toml"), &crude).unwrap();
    let o = framedyn(&["run", "crude.toml", "--output", "crude.csv"], &dir);
    assert_eq!(code(&o), 6, "{}", stderr(&o));
    assert!(stderr(&o).contains("quality check failed") && stderr(&o).contains("quality.energy_drift"), "{}", stderr(&o));
    assert!(stdout(&o).contains("quality:         WARNING: the energy drift"), "{}", stdout(&o));
    let (_, rows) = read_csv(&dir.join("crude.csv"));
    assert_eq!(rows.len(), 21, "the complete run is written to the output");
    fs::write(dir.join("off.toml"), format!("{crude}\n[quality]\nenergy_drift = inf\n")).unwrap();
    let o = framedyn(&["run", "off.toml", "--output", "off.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("quality:         ok"), "{}", stdout(&o));
    fs::write(dir.join("bad.toml"), format!("{text}\n[quality]\ndefect = -1.0\n")).unwrap();
    let o = framedyn(&["validate", "bad.toml"], &dir);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("quality.defect") && stderr(&o).contains("> 0"), "{}", stderr(&o));
    let o = framedyn(&["run", "--output", "default.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("quality:         ok"), "{}", stdout(&o));
}

/// `framedyn sweep`: a CSV table of members gives one npz whose members
/// equal the library's single runs bit for bit; an invalid member is
/// recorded, not fatal; a bad table exits 3 naming the column.
#[test]
fn sweep_writes_every_member() {
    let dir = tmpdir("sweep");
    fs::write(dir.join("members.csv"), "initial.r,initial.spin\n0.5,0.0\n-3,0.01\n0.7,0.02\n").unwrap();
    let o = framedyn(&["sweep", DEFAULT_SCENE, "--table", "members.csv", "--output", "out.npz", "--keep", "final"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("3 (2 finished, 1 invalid)") && text.contains("member 1") && text.contains("initial.r"), "{text}");
    let mut z = zip::ZipArchive::new(fs::File::open(dir.join("out.npz")).unwrap()).unwrap();
    let mut member = |name: &str| {
        let mut v = Vec::new();
        z.by_name(name).unwrap_or_else(|e| panic!("{name}: {e}")).read_to_end(&mut v).unwrap();
        v
    };
    let offsets: Vec<i64> = parse_npy(&member("offsets.npy")).1.chunks(8).map(|c| i64::from_le_bytes(c.try_into().unwrap())).collect();
    assert_eq!(offsets, [0, 1, 1, 2]);
    let data = member("data.npy");
    let (_, payload) = parse_npy(&data);
    let vals: Vec<f64> = payload.chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
    let status = member("status.npy");
    let (sh, sp) = parse_npy(&status);
    assert!(sh.contains("'shape': (3,)"), "{sh}");
    assert!(!sp.is_empty());
    for (k, (r, spin)) in [(0usize, (0.5, 0.0)), (1, (0.7, 0.02))] {
        let mut s = example(DEFAULT_SCENE).unwrap();
        s.set("initial.r", r).unwrap();
        s.set("initial.spin", spin).unwrap();
        let (_, sink) = library_run(&s);
        let last = sink.rows.last().unwrap();
        let got = &vals[k * last.len()..(k + 1) * last.len()];
        assert!(same_rows(&[got.to_vec()], &[last.clone()]), "member {k}");
    }
    fs::write(dir.join("bad.csv"), "initial.r,body.colour\n0.5,1\n").unwrap();
    let o = framedyn(&["sweep", DEFAULT_SCENE, "--table", "bad.csv", "--output", "bad.npz"], &dir);
    assert_eq!(code(&o), 3);
    assert!(stderr(&o).contains("body.colour"), "{}", stderr(&o));
    assert!(!dir.join("bad.npz").exists());
}

// ---------------------------------------------------------------------------
// `framedyn lyapunov` and `framedyn section` (issue 21)
// ---------------------------------------------------------------------------

/// `lyapunov -k all` prints the scene's full spectrum and writes the running
/// estimates; the numbers are those of the library call on the same scene.
#[test]
fn lyapunov_prints_the_spectrum_and_writes_running_estimates() {
    let dir = tmpdir("lyapunov");
    let o = framedyn(&["lyapunov", "s2-point-kepler", "-k", "all", "--output", "run.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("state dimension: 5 (exponents computed: 5)"), "{out}");
    assert!(out.contains("(6 method steps each)") && out.contains("tangent maps:    exact (the method on the tangent group)"), "{out}");
    let (header, rows) = read_csv(&dir.join("run.csv"));
    assert_eq!(header, ["t", "lambda_1", "lambda_2", "lambda_3", "lambda_4", "lambda_5"]);
    let scene = example("s2-point-kepler").unwrap();
    let e = scene.lyapunov(&scene.lyapunov_options().unwrap().exponents(5), &AtomicBool::new(false)).unwrap();
    assert_eq!(rows.len(), e.times.len());
    assert_eq!(rows.last().unwrap()[1..], e.exponents[..]);
    for (i, l) in e.exponents.iter().enumerate() {
        assert!(out.contains(&format!("{:>3}  {l:>12.6}", i + 1)), "exponent {i} missing from:\n{out}");
    }
    // Differenced on request: 2 steps per vector, named in the summary.
    let o = framedyn(&["lyapunov", "s2-point-kepler", "-k", "all", "--differenced", "--fourth-order"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("(21 method steps each)") && out.contains("tangent maps:    central differences of order 4, eps = 1e-3"), "{out}");
    let o = framedyn(&["lyapunov", "s2-point-kepler", "--two-trajectory"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("two trajectories:"), "{}", stdout(&o));
    // The phase space's spectrum: the library's values with `quotient`.
    let o = framedyn(&["lyapunov", "s2-point-kepler", "-k", "all", "--phase-space"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("phase space:     4 (the state group's 5 less 1 gauge direction(s) of the parallel frame; exponents computed: 4)"), "{out}");
    let q = scene.lyapunov(&LyapunovOptions { quotient: true, ..scene.lyapunov_options().unwrap().exponents(4) }, &AtomicBool::new(false)).unwrap();
    for (i, l) in q.exponents.iter().enumerate() {
        assert!(out.contains(&format!("{:>3}  {l:>12.6}", i + 1)), "exponent {i} missing from:\n{out}");
    }
    assert!(out.contains("sum:"), "{out}");
}

/// Bad options exit 2 naming the option and its range; an unsuitable scene
/// exits 3 naming the field; an error-controlled scene is analysed with its
/// steps.
#[test]
fn lyapunov_and_section_refuse_bad_input() {
    let dir = tmpdir("lyapunov-bad");
    for (args, needle) in [
        (&["lyapunov", "s2-point-kepler", "-k", "0"][..], "invalid --exponents = 0: must be between 1 and 5"),
        (&["lyapunov", "s2-point-kepler", "-k", "x"][..], "invalid --exponents = \"x\""),
        (&["lyapunov", "s2-point-kepler", "--every", "0"][..], "invalid --every = 0"),
        (&["lyapunov", "s2-point-kepler", "--eps", "1"][..], "invalid --eps = 1"),
        (&["lyapunov", "s2-point-kepler", "--transient", "20"][..], "invalid --transient = 20"),
        (&["section", "s2-point-kepler"][..], "no section"),
        (&["section", "s2-point-kepler", "--plane", "1,0"][..], "section.normal"),
        (&["section", "s2-point-kepler", "--column", "nope", "--value", "1"][..], "section.column"),
        (&["section", "s2-point-kepler", "--column", "r"][..], "--column needs --value"),
    ] {
        let o = framedyn(args, &dir);
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
    let adaptive = dir.join("adaptive.toml");
    let mut s = example("s2-point-kepler").unwrap();
    s.method.name = "dopri5".into();
    s.method.h = None;
    s.method.rtol = Some(1e-8);
    fs::write(&adaptive, s.to_toml_string()).unwrap();
    s.method.atol = Some(1e-8);
    fs::write(&adaptive, s.to_toml_string()).unwrap();
    // Error-controlled steps are taken, and said so.
    let o = framedyn(&["lyapunov", adaptive.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("error-controlled (rtol 1e-8, atol 1e-8)"), "{}", stdout(&o));
    // A method without an error estimate cannot take them: the scene is refused.
    s.method.name = "rk4".into();
    fs::write(&adaptive, s.to_toml_string()).unwrap();
    let o = framedyn(&["lyapunov", adaptive.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("method.rtol") && stderr(&o).contains("embedded pair"), "{}", stderr(&o));
}

/// The S² gyroscope of the atlas's tilted map (docs/integrability.md), a
/// chaotic orbit; the Python tests read the same file.
const TILTED_GYROSCOPE: &str = include_str!("../../../tests/data/tilted_gyroscope.toml");

/// `sali` calls the tilted gyroscope chaotic at the time the library's
/// `Scene::sali` finds, and the Kepler orbit regular; bad settings exit 2
/// naming the option.
#[test]
fn sali_tells_chaotic_from_regular() {
    let dir = tmpdir("sali");
    let path = dir.join("tilted.toml");
    fs::write(&path, TILTED_GYROSCOPE).unwrap();
    let o = framedyn(&["sali", path.to_str().unwrap(), "--threshold", "1e-6"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let scene = Scene::from_toml_str(TILTED_GYROSCOPE).unwrap();
    let mut opts = scene.sali_options().unwrap();
    opts.threshold = 1e-6;
    let e = scene.sali(&opts, &AtomicBool::new(false)).unwrap();
    let t = e.chaotic_at.expect("the tilted gyroscope is chaotic");
    assert!(t < 200.0, "chaotic only at t = {t}");
    let out = stdout(&o);
    assert!(out.contains(&format!("verdict:         chaotic (SALI < 1e-6 at t = {t:?})")), "{out}");
    assert!(out.contains(&format!("min:             {:.6e}", e.min)), "{out}");

    let o = framedyn(&["sali", "s2-point-kepler"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("verdict:         regular"), "{}", stdout(&o));

    for (args, needle) in [
        (&["sali", "s2-point-kepler", "--threshold", "0"][..], "invalid --threshold = 0"),
        (&["sali", "s2-point-kepler", "--threshold", "1"][..], "invalid --threshold = 1"),
        (&["sali", "s2-point-kepler", "--eps", "1"][..], "invalid --eps = 1"),
    ] {
        let o = framedyn(args, &dir);
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

/// `megno` prints the library's `Scene::megno` values and writes the running
/// `Y` and `⟨Y⟩`: the tilted gyroscope's `⟨Y⟩` far above 2 (chaotic, about
/// λ₁t/2) and twice the slope of `⟨Y⟩` near its λ₁; bad settings exit 2
/// naming the option, an adaptive scene exits 3 naming `method.h`.
#[test]
fn megno_prints_the_library_values_and_writes_the_running_values() {
    let dir = tmpdir("megno");
    let path = dir.join("tilted.toml");
    fs::write(&path, TILTED_GYROSCOPE).unwrap();
    let o = framedyn(&["megno", path.to_str().unwrap(), "-o", "megno.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let scene = Scene::from_toml_str(TILTED_GYROSCOPE).unwrap();
    let e = scene.megno(&scene.megno_options().unwrap(), &AtomicBool::new(false)).unwrap();
    assert!(e.mean > 5.0 && e.slope > 0.02, "not chaotic: {e:?}");
    let out = stdout(&o);
    assert!(out.contains(&format!("mean:            {:.6} (<Y>", e.mean)), "{out}");
    assert!(out.contains(&format!("2 x slope:       {:.6} ", 2.0 * e.slope)), "{out}");
    let (header, rows) = read_csv(&dir.join("megno.csv"));
    assert_eq!(header, ["t", "megno", "mean"]);
    assert_eq!(rows.len(), e.times.len());
    assert_eq!(rows.last().unwrap(), &vec![300.0, e.megno, e.mean]);

    // An error-controlled scene is analysed with its steps.
    let adaptive = dir.join("adaptive.toml");
    let mut s = example("s2-point-kepler").unwrap();
    s.method.name = "dopri5".into();
    s.method.h = None;
    s.method.rtol = Some(1e-8);
    fs::write(&adaptive, s.to_toml_string()).unwrap();
    let o = framedyn(&["megno", adaptive.to_str().unwrap()], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("error-controlled (rtol 1e-8"), "{}", stdout(&o));
    let chart = dir.join("chart.toml");
    let mut s = example("s2-point-kepler").unwrap();
    s.method.name = "coordinate_rk4".into();
    fs::write(&chart, s.to_toml_string()).unwrap();
    for (args, needle, exit) in [
        (&["megno", "s2-point-kepler", "--eps", "1"][..], "invalid --eps = 1: must be finite, ≥ 1e-12 and ≤ 0.1", 2),
        (&["megno", "s2-point-kepler", "--eps=-1e-5"][..], "invalid --eps = -0.00001", 2),
        (&["megno", "s2-point-kepler", "--seed", "x"][..], "--seed", 2),
        (&["megno", chart.to_str().unwrap()][..], "method.name", 3),
    ] {
        let o = framedyn(args, &dir);
        assert_eq!(code(&o), exit, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

/// `gali` prints the library's values and writes the running values; bad
/// options exit 2 naming them.
#[test]
fn gali_prints_the_library_values_and_refuses_bad_options() {
    let dir = tmpdir("gali");
    let path = dir.join("tilted.toml");
    fs::write(&path, TILTED_GYROSCOPE).unwrap();
    let o = framedyn(&["gali", path.to_str().unwrap(), "-k", "3", "-o", "gali.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let scene = Scene::from_toml_str(TILTED_GYROSCOPE).unwrap();
    let e = scene.gali(&scene.gali_options(3).unwrap(), &AtomicBool::new(false)).unwrap();
    let out = stdout(&o);
    assert!(e.below_at.is_some(), "{e:?}");
    assert!(out.contains(&format!("gali_3:          {:.6e} (log10 {:.6})", e.gali, e.log10)), "{out}");
    assert!(out.contains("dimension:       6 (the phase space: the state group's 7 less 1 gauge direction(s)"), "{out}");
    assert!(out.contains(&format!("at t = {:?}", e.below_at.unwrap())), "{out}");
    let (header, rows) = read_csv(&dir.join("gali.csv"));
    assert_eq!(header, ["t", "log10_gali"]);
    assert_eq!(rows.len(), e.times.len());
    assert_eq!(rows.last().unwrap(), &vec![e.below_at.unwrap(), e.log10]);
    // On the stored state: the library's value without the quotient, and k up to the group's dimension.
    let o = framedyn(&["gali", path.to_str().unwrap(), "-k", "7", "--stored-state"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let stored = scene.gali(&GaliOptions { quotient: false, ..scene.gali_options(7).unwrap() }, &AtomicBool::new(false)).unwrap();
    let out = stdout(&o);
    assert!(out.contains("dimension:       7 (the stored state)"), "{out}");
    assert!(out.contains(&format!("gali_7:          {:.6e} (log10 {:.6})", stored.gali, stored.log10)), "{out}");
    for (args, needle) in [
        (&["gali", "s2-point-kepler", "-k", "1"][..], "invalid -k = 1: must be between 2 and 4 (the phase space's dimension"),
        (&["gali", "s2-point-kepler", "-k", "5"][..], "invalid -k = 5: must be between 2 and 4"),
        (&["gali", "s2-point-kepler", "-k", "x"][..], "invalid -k = \"x\""),
        (&["gali", "s2-point-kepler", "--threshold", "0"][..], "invalid --threshold = 0"),
        (&["gali", "s2-point-kepler", "--eps", "1"][..], "invalid --eps = 1"),
    ] {
        let o = framedyn(args, &dir);
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

/// `section` writes the crossings as CSV (`rising` then every record column)
/// at the crossed value.
#[test]
fn section_writes_the_crossings() {
    let dir = tmpdir("section");
    let o = framedyn(&["section", "s2-point-kepler", "--column", "r", "--value", "0.5", "--direction", "falling", "-o", "sec.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("crossings"), "{}", stdout(&o));
    let (header, rows) = read_csv(&dir.join("sec.csv"));
    assert_eq!(&header[..3], ["rising", "t", "x0"]);
    let r = header.iter().position(|h| h == "r").unwrap();
    assert!(rows.len() >= 2);
    for row in &rows {
        assert_eq!(row[0], 0.0);
        assert!((row[r] - 0.5).abs() < 1e-9, "{row:?}");
    }
    let o = framedyn(&["section", "s2-gyroscope-pole", "--plane", "1,0,0", "-o", "pole.csv"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let (header, rows) = read_csv(&dir.join("pole.csv"));
    let x2 = header.iter().position(|h| h == "x2").unwrap();
    assert!(rows[0][x2] > 0.9999, "{rows:?}");
}

/// `sali --table` and `megno --table` write one CSV line per member with
/// exactly (as `{:?}`, i.e. bit for bit) the values of `Scene::sali` and
/// `Scene::megno` on that member's scene; an invalid member in the middle
/// gets its status and message and NaN; an option out of range exits 2
/// naming it.
#[test]
fn sali_and_megno_map_a_member_table() {
    use framedyn::scenes::Table;
    let dir = tmpdir("chaos-map");
    let mut base = example("s2-point-kepler").unwrap();
    base.time.t_end = 5.0;
    fs::write(dir.join("kepler.toml"), base.to_toml_string()).unwrap();
    fs::write(dir.join("members.csv"), "initial.r,initial.phi_dot,method.h\n0.8,1.3,0.005\n0.7,1.3,-0.01\n0.6,1.5,0.01\n").unwrap();
    let table = Table::new([("initial.r", vec![0.8, 0.7, 0.6]), ("initial.phi_dot", vec![1.3, 1.3, 1.5]), ("method.h", vec![0.005, -0.01, 0.01])]).unwrap();
    let no = AtomicBool::new(false);
    let o = framedyn(&["sali", "kepler.toml", "--table", "members.csv", "--threshold", "1e-3", "--seed", "3", "-o", "map.csv", "--threads", "2"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("members:         3 (2 finished, 1 invalid)"), "{}", stdout(&o));
    let sali_csv = fs::read_to_string(dir.join("map.csv")).unwrap();
    let o = framedyn(&["megno", "kepler.toml", "--table", "members.csv", "--seed", "3"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let megno_csv = stdout(&o);
    let lines = |text: &str| text.lines().map(|l| l.splitn(if l.contains('"') { 2 } else { usize::MAX }, '"').next().unwrap().split(',').map(str::to_string).collect::<Vec<_>>()).collect::<Vec<_>>();
    let (s, m) = (lines(&sali_csv), lines(&megno_csv));
    assert_eq!(s[0], ["initial.r", "initial.phi_dot", "method.h", "sali", "sali_min", "chaotic_at", "sali_steps", "status", "error"]);
    assert_eq!(m[0], ["initial.r", "initial.phi_dot", "method.h", "megno", "megno_mean", "megno_slope", "lyapunov", "megno_steps", "status", "error"]);
    for i in [0, 2] {
        let scene = table.member(&base, i).unwrap();
        let mut so = scene.sali_options().unwrap();
        so.threshold = 1e-3;
        so.seed = 3;
        let e = scene.sali(&so, &no).unwrap();
        let at = e.chaotic_at.unwrap_or(f64::NAN);
        assert_eq!(s[i + 1][3..], [format!("{:?}", e.sali), format!("{:?}", e.min), format!("{at:?}"), e.steps.to_string(), "finished".into(), String::new()], "member {i}");
        let mut mo = scene.megno_options().unwrap();
        mo.seed = 3;
        let y = scene.megno(&mo, &no).unwrap();
        assert_eq!(m[i + 1][3..8], [format!("{:?}", y.megno), format!("{:?}", y.mean), format!("{:?}", y.slope), format!("{:?}", y.lyapunov), y.steps.to_string()], "member {i}");
    }
    assert_eq!(s[2][3..8], ["NaN", "NaN", "NaN", "0", "invalid"]);
    // GALI over the same table: its columns, the single call's values.
    let o = framedyn(&["gali", "kepler.toml", "-k", "3", "--table", "members.csv", "--threshold", "1e-6", "--seed", "3"], &dir);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let g = lines(&stdout(&o));
    assert_eq!(g[0], ["initial.r", "initial.phi_dot", "method.h", "gali_log10", "gali_below_at", "gali_steps", "status", "error"]);
    for i in [0, 2] {
        let scene = table.member(&base, i).unwrap();
        let mut go = scene.gali_options(3).unwrap();
        go.threshold = 1e-6;
        go.seed = 3;
        let e = scene.gali(&go, &no).unwrap();
        assert_eq!(g[i + 1][3..6], [format!("{:?}", e.log10), format!("{:?}", e.below_at.unwrap_or(f64::NAN)), e.steps.to_string()], "member {i}");
    }
    assert!(sali_csv.lines().nth(2).unwrap().contains("\"member 1: sali: invalid `method.h` = -0.01"), "{sali_csv}");
    for (args, needle) in [
        (&["sali", "kepler.toml", "--table", "members.csv", "--threshold", "2"][..], "invalid --threshold = 2"),
        (&["megno", "kepler.toml", "--table", "members.csv", "--threads", "0"][..], "invalid --threads = 0"),
    ] {
        let o = framedyn(args, &dir);
        assert_eq!(code(&o), 2, "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}
