//! `framedyn sweep`: a scene and a table of members (columns named by
//! dotted scene fields) in, one `.npz` of every member's records, status and
//! summary out (see [`write_ensemble`] for the layout).
//!
//! Tables are CSV (a header of field names, one member per line) or `.npz`
//! (one 1-D float64 or int64 array per field, as written by
//! `numpy.savez(path, **{"initial.r": r, ...})`).

use std::fs::{self, File};
use std::io::{self, BufRead, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use framedyn::scenes::{Column, Ensemble, Keep, MemberOutcome, MemberStatus, RunSummary, Scene, Simulation, Table};

use crate::output::{npy_header, npy_strings};
use crate::space::OutputEstimate;
use crate::target::Target;

/// Why a table could not be read: the message names the file, the line or
/// array, and what was expected.
#[derive(Debug)]
pub enum TableError {
    /// The file could not be read.
    Io(String),
    /// The file is not a valid table.
    Invalid(String),
}

impl std::fmt::Display for TableError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TableError::Io(m) | TableError::Invalid(m) => f.write_str(m),
        }
    }
}

/// Reads a table from `path` (`.npz`, else CSV).
pub fn read_table(path: &Path) -> Result<Table, TableError> {
    let shown = path.display();
    let columns = if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npz")) {
        let file = File::open(path).map_err(|e| TableError::Io(format!("cannot read table {shown}: {e}")))?;
        read_npz(file).map_err(|m| TableError::Invalid(format!("table {shown}: {m}")))?
    } else {
        let file = File::open(path).map_err(|e| TableError::Io(format!("cannot read table {shown}: {e}")))?;
        read_csv(BufReader::new(file)).map_err(|m| TableError::Invalid(format!("table {shown}: {m}")))?
    };
    Table::new(columns).map_err(|e| TableError::Invalid(format!("table {shown}: {e}")))
}

/// CSV: a header of dotted field names, then one line of numbers per member
/// (`#` lines and blank lines skipped).
fn read_csv(r: impl BufRead) -> Result<Vec<(String, Vec<f64>)>, String> {
    let mut names: Option<Vec<String>> = None;
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for (k, line) in r.lines().enumerate() {
        let line = line.map_err(|e| format!("line {}: {e}", k + 1))?;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        match &names {
            None => {
                cols = vec![Vec::new(); cells.len()];
                names = Some(cells.iter().map(|c| c.to_string()).collect());
            }
            Some(n) => {
                if cells.len() != n.len() {
                    return Err(format!("line {}: {} values for {} columns", k + 1, cells.len(), n.len()));
                }
                for (j, c) in cells.iter().enumerate() {
                    let v: f64 = c.parse().map_err(|_| format!("line {}, column `{}`: `{c}` is not a number", k + 1, n[j]))?;
                    cols[j].push(v);
                }
            }
        }
    }
    let names = names.ok_or("empty file: expected a header line of dotted scene fields (e.g. `initial.r,initial.spin`)")?;
    Ok(names.into_iter().zip(cols).collect())
}

/// `.npz`: every member a 1-D `<f8` or `<i8` array.
fn read_npz(file: File) -> Result<Vec<(String, Vec<f64>)>, String> {
    let mut zip = zip::ZipArchive::new(BufReader::new(file)).map_err(|e| format!("not an npz (zip) archive: {e}"))?;
    let mut out = Vec::new();
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).map_err(|e| format!("entry {i}: {e} (write tables with numpy.savez, not savez_compressed)"))?;
        let name = entry.name().trim_end_matches(".npy").to_string();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| format!("array `{name}`: {e}"))?;
        out.push((name.clone(), parse_npy_1d(&bytes).map_err(|m| format!("array `{name}`: {m}"))?));
    }
    Ok(out)
}

/// A 1-D little-endian float64 or int64 `.npy` array.
fn parse_npy_1d(b: &[u8]) -> Result<Vec<f64>, String> {
    if b.len() < 10 || &b[..6] != b"\x93NUMPY" {
        return Err("not a .npy array".into());
    }
    let (hlen, start) = match b[6] {
        1 => (u16::from_le_bytes([b[8], b[9]]) as usize, 10),
        2 | 3 if b.len() >= 12 => (u32::from_le_bytes([b[8], b[9], b[10], b[11]]) as usize, 12),
        v => return Err(format!("unsupported .npy version {v}")),
    };
    let header = b.get(start..start + hlen).ok_or("truncated header")?;
    let header = std::str::from_utf8(header).map_err(|_| "header is not text")?;
    let descr = if header.contains("'<f8'") {
        'f'
    } else if header.contains("'<i8'") {
        'i'
    } else {
        return Err(format!("dtype in `{}`; allowed: float64 or int64", header.trim()));
    };
    if header.contains("'fortran_order': True") {
        return Err("Fortran-ordered arrays are not supported".into());
    }
    let shape = header.split("'shape':").nth(1).and_then(|s| s.split(')').next()).ok_or("no shape")?;
    let dims: Vec<&str> = shape.trim().trim_start_matches('(').split(',').map(str::trim).filter(|s| !s.is_empty()).collect();
    if dims.len() != 1 {
        return Err(format!("shape ({}); allowed: a 1-D array (one value per member)", dims.join(", ")));
    }
    let n: usize = dims[0].parse().map_err(|_| "bad shape")?;
    let data = &b[start + hlen..];
    if data.len() != 8 * n {
        return Err(format!("{} data bytes for {n} values", data.len()));
    }
    Ok(data
        .chunks_exact(8)
        .map(|c| {
            let a: [u8; 8] = c.try_into().unwrap_or([0; 8]);
            if descr == 'f' {
                f64::from_le_bytes(a)
            } else {
                i64::from_le_bytes(a) as f64
            }
        })
        .collect())
}

fn npy_f64(values: &[f64], shape: &str) -> Vec<u8> {
    let mut out = npy_header("<f8", shape);
    out.reserve(values.len() * 8);
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

fn npy_i64(values: &[i64]) -> Vec<u8> {
    let mut out = npy_header("<i8", &format!("({},)", values.len()));
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Writes the ensemble atomically (a temporary file renamed onto `target`);
/// the layout is [`EnsembleWriter`]'s. Returns the path written.
pub fn write_ensemble(target: &Path, table: &Table, out: &Ensemble, partial: bool) -> io::Result<PathBuf> {
    let mut w = EnsembleWriter::create(target)?;
    w.push(out)?;
    w.finish(table, partial)
}

/// A sweep's `.npz`, written while the members run
/// ([`run_ensemble_blocks`](framedyn::scenes::run_ensemble_blocks)): each
/// block's records go to a raw temporary file beside the target as soon as
/// the block is done, so memory holds one block of records plus every
/// member's status and summary; [`Self::finish`] assembles the archive in
/// a second temporary file and renames it onto the target (or, for an
/// interrupted sweep, onto `STEM.partial.npz`, leaving the target as it
/// was). Dropped without finishing, it removes its temporary files.
///
/// The archive holds `data` (all records, `(total, columns)`), `offsets`
/// (`(N + 1,)`, member `i` is `data[offsets[i]:offsets[i+1]]`), `columns`,
/// `units`, `status` and `error` (per member, strings; `error` empty when
/// none), the per-member summaries by the names of
/// [`RunSummary::NUMBER_NAMES`](framedyn::scenes::RunSummary::NUMBER_NAMES)
/// (`steps`, `rejected`, `rhs_evals`, `records`, `events`, `wall_time`,
/// `energy_initial`, `energy_drift`, `relative_energy_drift`,
/// `momentum_map_drift`, `max_defect`, `t_reached`, `global_error`,
/// `global_error_final`; NaN for invalid members, and the global error's
/// for runs that do not ask for its estimate), `warnings` (the quality warnings of each member joined by
/// `; `, empty when none), and the table itself as `table.<field>`.
pub struct EnsembleWriter {
    dest: Target,
    raw_path: PathBuf,
    raw: Option<BufWriter<File>>,
    tmp: Option<PathBuf>,
    columns: Vec<Column>,
    offsets: Vec<i64>,
    members: Vec<MemberOutcome>,
}

impl EnsembleWriter {
    /// Checks `target` against the output policy ([`crate::target`]) and
    /// opens the raw temporary file beside it.
    pub fn create(target: &Path) -> io::Result<EnsembleWriter> {
        EnsembleWriter::create_at(Target::resolve(target)?)
    }

    /// [`Self::create`] for a target already checked against the output policy.
    pub fn create_at(dest: Target) -> io::Result<EnsembleWriter> {
        let raw_path = dest.temporary("raw");
        let raw = BufWriter::with_capacity(1 << 16, File::create(&raw_path)?);
        Ok(EnsembleWriter { dest, raw_path, raw: Some(raw), tmp: None, columns: Vec::new(), offsets: vec![0], members: Vec::new() })
    }

    /// Appends the next block of members (in table order).
    pub fn push(&mut self, block: &Ensemble) -> io::Result<()> {
        if self.columns.is_empty() {
            self.columns = block.columns.clone();
        }
        let raw = self.raw.as_mut().ok_or_else(|| io::Error::other("the sweep's output is already finished"))?;
        for v in &block.data {
            raw.write_all(&v.to_le_bytes())?;
        }
        let base = *self.offsets.last().unwrap_or(&0);
        self.offsets.extend(block.offsets[1..].iter().map(|&o| base + o as i64));
        self.members.extend(block.members.iter().cloned());
        Ok(())
    }

    /// The members written so far.
    pub fn members(&self) -> &[MemberOutcome] {
        &self.members
    }

    /// The records written so far.
    pub fn records(&self) -> u64 {
        self.offsets.last().copied().unwrap_or(0) as u64
    }

    /// Assembles the archive and renames it onto the target (with
    /// `partial`, onto `STEM.partial.npz`). Returns the path written.
    pub fn finish(mut self, table: &Table, partial: bool) -> io::Result<PathBuf> {
        let dest = if partial { self.dest.partial()? } else { self.dest.clone() };
        let mut raw = self.raw.take().ok_or_else(|| io::Error::other("the sweep's output is already finished"))?;
        raw.flush()?;
        drop(raw);
        let tmp = dest.temporary_name("tmp");
        self.tmp = Some(tmp.clone());
        self.write_npz(&tmp, table)?;
        dest.commit(&tmp)?;
        self.tmp = None;
        Ok(dest.resolved().to_path_buf())
    }

    fn write_npz(&self, path: &Path, table: &Table) -> io::Result<()> {
        use zip::write::SimpleFileOptions;
        type Zip = zip::ZipWriter<BufWriter<File>>;
        let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored).large_file(true);
        let start = |zip: &mut Zip, name: &str| zip.start_file(format!("{name}.npy"), opts).map_err(|e| io::Error::other(e.to_string()));
        let put = |zip: &mut Zip, name: &str, bytes: &[u8]| -> io::Result<()> {
            start(zip, name)?;
            zip.write_all(bytes)
        };
        let mut zip: Zip = zip::ZipWriter::new(BufWriter::new(File::create(path)?));
        start(&mut zip, "data")?;
        zip.write_all(&npy_header("<f8", &format!("({}, {})", self.records(), self.columns.len())))?;
        io::copy(&mut BufReader::with_capacity(1 << 16, File::open(&self.raw_path)?), &mut zip)?;
        put(&mut zip, "offsets", &npy_i64(&self.offsets))?;
        let names: Vec<&str> = self.columns.iter().map(|c| c.name.as_str()).collect();
        put(&mut zip, "columns", &npy_strings(&names))?;
        let units: Vec<&str> = self.columns.iter().map(|c| c.unit).collect();
        put(&mut zip, "units", &npy_strings(&units))?;
        let status: Vec<&str> = self.members.iter().map(|m| m.status.name()).collect();
        put(&mut zip, "status", &npy_strings(&status))?;
        let errors: Vec<&str> = self.members.iter().map(|m| m.error.as_deref().unwrap_or("")).collect();
        put(&mut zip, "error", &npy_strings(&errors))?;
        let n = self.members.len();
        for (k, name) in RunSummary::NUMBER_NAMES.into_iter().enumerate() {
            let v: Vec<f64> = self.members.iter().map(|m| m.summary.as_ref().map_or(f64::NAN, |s| s.numbers()[k])).collect();
            put(&mut zip, name, &npy_f64(&v, &format!("({n},)")))?;
        }
        let warnings: Vec<String> = self.members.iter().map(|m| m.summary.as_ref().map_or_else(String::new, |s| s.warning_texts().join("; "))).collect();
        put(&mut zip, "warnings", &npy_strings(&warnings.iter().map(String::as_str).collect::<Vec<_>>()))?;
        for name in table.names() {
            let v = table.column(name).unwrap_or(&[]);
            put(&mut zip, &format!("table.{name}"), &npy_f64(v, &format!("({},)", v.len())))?;
        }
        let mut inner = zip.finish().map_err(|e| io::Error::other(e.to_string()))?;
        inner.flush()?;
        inner.into_inner().map_err(|e| e.into_error())?.sync_all()
    }
}

impl Drop for EnsembleWriter {
    fn drop(&mut self) {
        self.raw = None;
        let _ = fs::remove_file(&self.raw_path);
        if let Some(t) = &self.tmp {
            let _ = fs::remove_file(t);
        }
    }
}

/// Members per block of a streamed sweep: what keeps one block's records
/// near 64 MiB (from the base scene's record bound), at least a few per
/// worker thread and at most 65,536.
pub fn block_size(base: &Simulation, keep: Keep) -> usize {
    let records = match keep {
        Keep::Final => 1,
        Keep::Samples(k) => k,
        Keep::All => base.record_bound().unwrap_or(1_000),
    };
    let columns = base.columns().len() as u64;
    let per_member = records.saturating_mul(columns.max(1)).saturating_mul(8).max(1);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    ((64u64 << 20) / per_member).clamp(4 * cores, 65_536) as usize
}

/// The size of the `.npz` a sweep of `table` on `base` (a valid scene) will
/// write, before it runs ([`write_ensemble`]'s layout): per member, the
/// records it keeps (`keep`: its record bound, or `k` samples, or one),
/// plus its offset, summary numbers and table values. Members whose record
/// count is not known in advance (adaptive steps saving every step) and
/// invalid members count no records, and the strings (statuses, errors,
/// warnings) are not counted: the estimate is what the file needs at least.
/// `sim` is `base` built (its columns are every member's).
pub fn estimate(base: &Scene, sim: &Simulation, table: &Table, keep: Keep) -> OutputEstimate {
    let columns = sim.columns().len();
    let n = table.len() as u64;
    let records = match keep {
        Keep::Final => n,
        Keep::Samples(k) => n.saturating_mul(k),
        Keep::All => (0..table.len())
            .filter_map(|i| table.member(base, i).ok()?.build().ok()?.record_bound())
            .fold(0u64, u64::saturating_add),
    };
    let per_member = 1 + RunSummary::NUMBER_NAMES.len() + table.names().count();
    OutputEstimate::sweep(records, columns, n, per_member)
}

/// `N finished, k failed, …` for the summary.
pub fn status_counts(members: &[MemberOutcome]) -> String {
    let all = [MemberStatus::Finished, MemberStatus::Event, MemberStatus::Cancelled, MemberStatus::Failed, MemberStatus::Invalid];
    all.iter()
        .filter_map(|s| {
            let k = members.iter().filter(|m| m.status == *s).count();
            (k > 0).then(|| format!("{k} {}", s.name()))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_tables_parse_and_report_bad_cells() {
        let t = read_csv("# members\ninitial.r, initial.spin\n0.5, 0\n0.6,0.01\n".as_bytes()).unwrap();
        assert_eq!(t[0], ("initial.r".to_string(), vec![0.5, 0.6]));
        assert_eq!(t[1].1, vec![0.0, 0.01]);
        let e = read_csv("initial.r\n0.5\nx\n".as_bytes()).unwrap_err();
        assert!(e.contains("line 3") && e.contains("initial.r") && e.contains("`x`"), "{e}");
        let e = read_csv("a,b\n1\n".as_bytes()).unwrap_err();
        assert!(e.contains("line 2") && e.contains("1 values for 2 columns"), "{e}");
    }

    #[test]
    fn npy_arrays_round_trip_and_refuse_other_shapes() {
        let v = [0.5, -1.25, 3.0];
        assert_eq!(parse_npy_1d(&npy_f64(&v, "(3,)")).unwrap(), v);
        assert_eq!(parse_npy_1d(&npy_i64(&[1, -2])).unwrap(), [1.0, -2.0]);
        let e = parse_npy_1d(&npy_f64(&[1.0, 2.0], "(1, 2)")).unwrap_err();
        assert!(e.contains("1-D"), "{e}");
        let e = parse_npy_1d(&npy_strings(&["a"])).unwrap_err();
        assert!(e.contains("float64"), "{e}");
    }
}

#[cfg(test)]
mod streaming {
    use super::*;
    use framedyn::scenes::{example, run_ensemble_blocks, EnsembleOptions, DEFAULT_SCENE};
    use std::ops::ControlFlow;
    use std::sync::atomic::AtomicBool;

    /// Blocks pushed one by one give the archive of the whole ensemble,
    /// byte for byte, and leave no temporary file.
    #[test]
    fn blocks_streamed_equal_the_whole_ensemble() {
        let mut base = example(DEFAULT_SCENE).unwrap();
        base.time.t_end = 0.5;
        let table = Table::new([("initial.r", vec![0.3, 0.5, -0.7, 0.9, 1.1]), ("body.inertia", vec![0.2, 0.2, 0.2, -1.0, 0.2])]).unwrap();
        let mut blocks = Vec::new();
        let opts = EnsembleOptions { keep: Keep::All, threads: Some(2), oversubscribe: false };
        run_ensemble_blocks(&base, &table, &opts, None, &AtomicBool::new(false), &|_| {}, 2, &mut |_, b| {
            blocks.push(b);
            ControlFlow::Continue(())
        })
        .unwrap();
        assert_eq!(blocks.len(), 3);
        let mut whole = blocks[0].clone();
        for b in &blocks[1..] {
            let o = *whole.offsets.last().unwrap();
            whole.data.extend_from_slice(&b.data);
            whole.offsets.extend(b.offsets[1..].iter().map(|k| o + k));
            whole.members.extend(b.members.iter().cloned());
        }
        let dir = std::env::temp_dir().join(format!("framedyn-sweep-stream-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.npz"), dir.join("b.npz"));
        write_ensemble(&a, &table, &whole, false).unwrap();
        let mut w = EnsembleWriter::create(&b).unwrap();
        for blk in &blocks {
            w.push(blk).unwrap();
        }
        assert_eq!(w.records(), *whole.offsets.last().unwrap() as u64);
        w.finish(&table, false).unwrap();
        assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
        let left: Vec<_> = fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 2, "{left:?}");
        // A writer dropped unfinished removes its temporary file.
        let mut w = EnsembleWriter::create(&dir.join("c.npz")).unwrap();
        w.push(&blocks[0]).unwrap();
        drop(w);
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 2);
        fs::remove_dir_all(&dir).unwrap();
    }
}
