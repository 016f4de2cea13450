//! Streamed, atomic output files: CSV with a header, or a numpy `.npz`.
//!
//! Where the file goes — symlinks, special and read-only files, temporary
//! names, partial results — is the policy of [`crate::target`]. Records go
//! to a temporary file beside the target (`.NAME.tmp-PID`); the target
//! appears only by a rename once the file is complete, so an interrupted or
//! failed run never leaves a corrupt file at the output path. For `.npz` the
//! rows are streamed to a raw temporary file first (the `.npy` header needs
//! the row count), then copied into the archive: memory stays flat however
//! many records are written.

use std::fs::{self, File};
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use framedyn::scenes::{Column, EventHit, Format, RecordSink};

use crate::target::Target;

/// A record sink writing a CSV or `.npz` file atomically.
pub struct FileSink {
    target: Target,
    tmp: PathBuf,
    raw: Option<PathBuf>,
    format: Format,
    out: Option<BufWriter<File>>,
    names: Vec<String>,
    units: Vec<String>,
    rows: u64,
    line: String,
    events: Vec<EventHit>,
}

impl FileSink {
    /// A sink for `target`, checked against the output policy
    /// ([`Target::resolve`]).
    pub fn create(target: &Path, format: Format) -> io::Result<FileSink> {
        FileSink::create_at(Target::resolve(target)?, format)
    }

    /// A sink for a target already checked against the output policy.
    pub fn create_at(target: Target, format: Format) -> io::Result<FileSink> {
        let tmp = target.temporary("tmp");
        let create = |p: &Path| File::create(p).map_err(|e| io::Error::new(e.kind(), format!("cannot create {}: {e}", p.display())));
        let (raw, file) = match format {
            Format::Csv => (None, create(&tmp)?),
            Format::Npz => {
                let raw = target.temporary_name("raw");
                let f = create(&raw)?;
                (Some(raw), f)
            }
        };
        Ok(FileSink {
            target,
            tmp,
            raw,
            format,
            out: Some(BufWriter::with_capacity(1 << 16, file)),
            names: Vec::new(),
            units: Vec::new(),
            rows: 0,
            line: String::new(),
            events: Vec::new(),
        })
    }

    fn out(&mut self) -> io::Result<&mut BufWriter<File>> {
        self.out.as_mut().ok_or_else(|| io::Error::other("output already closed"))
    }

    /// The target as resolved (symbolic links followed).
    pub fn target(&self) -> &Target {
        &self.target
    }

    /// Completes the file and renames it onto the target. `stop` is how
    /// the run ended (`.npz` keeps it as `stop.npy`).
    pub fn finish(self, stop: &str) -> io::Result<PathBuf> {
        let target = self.target.clone();
        self.finish_to(&target, stop, None)
    }

    /// Completes the file as a partial result: renamed onto
    /// `STEM.partial.EXT` ([`Target::partial`]), never onto the target; a
    /// CSV ends with the comment line `# partial: REASON`, an `.npz` has
    /// `stop.npy` = `partial: REASON`. Returns the path written.
    pub fn finish_partial(self, reason: &str) -> io::Result<PathBuf> {
        let partial = match self.target.partial() {
            Ok(p) => p,
            Err(e) => {
                self.abort();
                return Err(e);
            }
        };
        self.finish_to(&partial, &format!("partial: {reason}"), Some(reason))
    }

    fn finish_to(mut self, dest: &Target, stop: &str, partial: Option<&str>) -> io::Result<PathBuf> {
        let res = self.finish_inner(dest, stop, partial);
        if res.is_err() {
            self.cleanup();
        }
        res.map(|()| dest.resolved().to_path_buf())
    }

    fn finish_inner(&mut self, dest: &Target, stop: &str, partial: Option<&str>) -> io::Result<()> {
        let mut out = self.out.take().ok_or_else(|| io::Error::other("output already closed"))?;
        if let (Format::Csv, Some(reason)) = (self.format, partial) {
            writeln!(out, "# partial: {}", reason.replace('\n', " "))?;
        }
        out.flush()?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        if let (Format::Npz, Some(raw)) = (self.format, &self.raw) {
            write_npz(&self.tmp, raw, &self.names, &self.units, self.rows, stop)?;
            let _ = fs::remove_file(raw);
        }
        dest.commit(&self.tmp)
    }

    /// Removes the temporary files; the target is left untouched.
    pub fn abort(mut self) {
        self.out = None;
        self.cleanup();
    }

    fn cleanup(&mut self) {
        let _ = fs::remove_file(&self.tmp);
        if let Some(r) = &self.raw {
            let _ = fs::remove_file(r);
        }
    }
}

impl FileSink {
    /// The events located so far (taken out of the sink).
    pub fn take_events(&mut self) -> Vec<EventHit> {
        std::mem::take(&mut self.events)
    }

    /// The record columns.
    pub fn column_names(&self) -> Vec<String> {
        self.names.clone()
    }

    /// Starts the file with the column names and units (the CSV header).
    pub fn set_columns(&mut self, names: &[String], units: &[String]) -> io::Result<()> {
        if names.len() != units.len() {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("{} column names but {} units", names.len(), units.len())));
        }
        self.names = names.to_vec();
        self.units = units.to_vec();
        if self.format == Format::Csv {
            let header = names.join(",");
            let out = self.out()?;
            writeln!(out, "{header}")?;
        }
        Ok(())
    }
}

/// Writes `rows` (row-major, `names.len()` values per record) to `target`
/// in `format`, exactly as `framedyn run` writes a run's records (the same
/// sink: header, number format, `.npz` layout, atomic rename). The Python
/// module's `Solution.save` calls it.
pub fn write_records(target: &Path, format: Format, names: &[String], units: &[String], rows: &[f64]) -> io::Result<()> {
    let n = names.len();
    if n == 0 && !rows.is_empty() || n > 0 && rows.len() % n != 0 {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("{} values do not make whole records of {n} columns", rows.len())));
    }
    let mut sink = FileSink::create(target, format)?;
    sink.set_columns(names, units)?;
    if n > 0 {
        for row in rows.chunks_exact(n) {
            sink.record(row)?;
        }
    }
    sink.finish("finished").map(|_| ())
}

/// The events file of the output `target`: `NAME.events.csv` beside it
/// (`traj.csv` or `traj.npz` → `traj.events.csv`; a partial result's
/// `traj.partial.csv` → `traj.partial.events.csv`).
pub fn events_path(target: &Path) -> PathBuf {
    let stem = target.file_stem().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "output".into());
    target.with_file_name(format!("{stem}.events.csv"))
}

/// The events as CSV (header `event,rising,terminal,` and the record
/// columns; one line per located event, in time order), written to a
/// temporary file beside `target` (checked against the output policy):
/// [`PendingFile::commit`] renames it onto `target`, dropping it removes it.
pub fn prepare_events(target: &Path, columns: &[String], events: &[EventHit]) -> io::Result<PendingFile> {
    use std::fmt::Write as _;
    let target = Target::resolve(target)?;
    let mut text = String::from("event,rising,terminal");
    for c in columns {
        text.push(',');
        text.push_str(c);
    }
    text.push('\n');
    for e in events {
        let _ = write!(text, "{},{},{}", e.name, u8::from(e.rising), u8::from(e.terminal));
        for v in &e.row {
            let _ = write!(text, ",{v}");
        }
        text.push('\n');
    }
    let tmp = target.temporary("tmp");
    let pending = PendingFile { target, tmp: Some(tmp) };
    let path = pending.tmp.as_deref().unwrap_or(Path::new(""));
    let mut f = File::create(path)?;
    f.write_all(text.as_bytes())?;
    f.sync_all()?;
    Ok(pending)
}

/// A complete temporary file waiting to be renamed onto its target.
pub struct PendingFile {
    target: Target,
    tmp: Option<PathBuf>,
}

impl PendingFile {
    /// Renames the file onto its target; returns the path written.
    pub fn commit(mut self) -> io::Result<PathBuf> {
        let tmp = self.tmp.take().ok_or_else(|| io::Error::other("already committed"))?;
        self.target.commit(&tmp).inspect_err(|_| {
            let _ = fs::remove_file(&tmp);
        })?;
        Ok(self.target.resolved().to_path_buf())
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if let Some(t) = &self.tmp {
            let _ = fs::remove_file(t);
        }
    }
}

impl RecordSink for FileSink {
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }

    fn columns(&mut self, columns: &[Column]) -> io::Result<()> {
        let names: Vec<String> = columns.iter().map(|c| c.name.clone()).collect();
        let units: Vec<String> = columns.iter().map(|c| c.unit.to_string()).collect();
        self.set_columns(&names, &units)
    }

    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        self.rows += 1;
        match self.format {
            Format::Csv => {
                use std::fmt::Write as _;
                let mut line = std::mem::take(&mut self.line);
                line.clear();
                for (i, v) in row.iter().enumerate() {
                    if i > 0 {
                        line.push(',');
                    }
                    // `{}` of f64 is the shortest representation that reads back exactly.
                    let _ = write!(line, "{v}");
                }
                line.push('\n');
                let res = self.out()?.write_all(line.as_bytes());
                self.line = line;
                res
            }
            Format::Npz => {
                let out = self.out()?;
                for v in row {
                    out.write_all(&v.to_le_bytes())?;
                }
                Ok(())
            }
        }
    }
}

impl Drop for FileSink {
    fn drop(&mut self) {
        if self.out.is_some() {
            self.out = None;
            self.cleanup();
        }
    }
}

/// The `.npy` (format 1.0) header for `descr` and `shape`.
pub(crate) fn npy_header(descr: &str, shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    let mut header = dict.into_bytes();
    // magic (6) + version (2) + length (2) + header + '\n' must be a multiple of 64.
    let total = 10 + header.len() + 1;
    let pad = (64 - total % 64) % 64;
    header.extend(std::iter::repeat_n(b' ', pad));
    header.push(b'\n');
    let mut out = Vec::with_capacity(10 + header.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(&header);
    out
}

/// A 1-D array of strings as `.npy` (`<U` = UTF-32LE, fixed width).
pub(crate) fn npy_strings(items: &[&str]) -> Vec<u8> {
    let width = items.iter().map(|s| s.chars().count()).max().unwrap_or(1).max(1);
    let mut out = npy_header(&format!("<U{width}"), &format!("({},)", items.len()));
    for s in items {
        let mut n = 0;
        for c in s.chars() {
            out.extend_from_slice(&(c as u32).to_le_bytes());
            n += 1;
        }
        for _ in n..width {
            out.extend_from_slice(&0u32.to_le_bytes());
        }
    }
    out
}

/// Writes the archive: `data` (rows × columns, float64), `columns` and
/// `units` (strings), and `stop` (one string: how the run ended).
fn write_npz(path: &Path, raw: &Path, names: &[String], units: &[String], rows: u64, stop: &str) -> io::Result<()> {
    use zip::write::SimpleFileOptions;
    let file = File::create(path)?;
    let mut zip = zip::ZipWriter::new(BufWriter::new(file));
    let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored).large_file(true);
    let to_io = |e: zip::result::ZipError| io::Error::other(e.to_string());
    zip.start_file("data.npy", opts).map_err(to_io)?;
    zip.write_all(&npy_header("<f8", &format!("({rows}, {})", names.len())))?;
    let mut reader = BufReader::with_capacity(1 << 16, File::open(raw)?);
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = reader.read(&mut buf)?;
        if n == 0 {
            break;
        }
        zip.write_all(&buf[..n])?;
    }
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let units: Vec<&str> = units.iter().map(String::as_str).collect();
    zip.start_file("columns.npy", opts).map_err(to_io)?;
    zip.write_all(&npy_strings(&names))?;
    zip.start_file("units.npy", opts).map_err(to_io)?;
    zip.write_all(&npy_strings(&units))?;
    zip.start_file("stop.npy", opts).map_err(to_io)?;
    zip.write_all(&npy_strings(&[stop]))?;
    let mut inner = zip.finish().map_err(to_io)?;
    inner.flush()?;
    inner.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}
