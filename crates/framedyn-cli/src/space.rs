//! How large an output will be, and whether the file system that will hold
//! it has room: checked before `framedyn run` and `framedyn sweep` start.
//!
//! The estimate ([`OutputEstimate`]) is made once, from the record count
//! known before the run ([`Simulation::record_bound`]: fixed steps, or
//! `output.times`/`output.samples`), the number of columns and the format,
//! and serves both the note printed above [`LARGE_OUTPUT_BYTES`] and the
//! refusal when the output cannot fit ([`check`]): the space needed is
//! compared with the space an unprivileged process may still use on the
//! file system of the directory that will hold the temporary file (statvfs
//! `f_bavail × f_frsize`). Runs whose record count is not known in advance
//! (adaptive steps saving every step) are not checked.
//!
//! [`Simulation::record_bound`]: framedyn::scenes::Simulation::record_bound

use std::io;
use std::path::{Path, PathBuf};

use framedyn::scenes::Format;

/// Estimated output size above which a run says so before starting.
pub const LARGE_OUTPUT_BYTES: f64 = 10e9;

/// Bytes a value takes in a CSV output, separator included. Values are
/// written in the shortest form that reads back exactly, without an
/// exponent: a full-precision number of order one takes 18–20 characters,
/// a small one (a constraint defect of 1e-16) more than 30, a zero two.
/// The embedded scenes write 12 to 24 bytes per value (19 on average); the
/// estimate takes their largest, so that a run allowed to start does not
/// fill the disk on the way (`--no-space-check` runs one refused anyway).
/// The CLI test `free_space_is_checked_before_a_run` compares it with what
/// the default scene writes.
pub const CSV_BYTES_PER_VALUE: f64 = 24.0;

/// Bytes a value takes in an `.npz` output (little-endian float64).
pub const NPZ_BYTES_PER_VALUE: f64 = 8.0;

/// Fixed bytes of an output beside its values: the CSV header, the `.npz`
/// archive's `.npy` headers, column names, units and zip directory.
const HEADER_BYTES: f64 = 64.0 * 1024.0;

/// What a run will write, before it starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputEstimate {
    /// Records (an upper bound: a terminal event or a failure ends earlier).
    pub records: u64,
    /// Values per record.
    pub columns: usize,
    /// The output format.
    pub format: Format,
    /// Bytes of the finished file.
    pub file_bytes: f64,
    /// Bytes on disk while it is written: an `.npz` streams its rows to a
    /// raw temporary file and copies them into the archive, so both exist
    /// at the end of the run.
    pub peak_bytes: f64,
}

impl OutputEstimate {
    /// The estimate for `records` records of `columns` values in `format`.
    pub fn new(records: u64, columns: usize, format: Format) -> OutputEstimate {
        let values = records as f64 * columns as f64;
        let (file_bytes, peak_bytes) = match format {
            Format::Csv => {
                let b = values * CSV_BYTES_PER_VALUE + HEADER_BYTES;
                (b, b)
            }
            Format::Npz => {
                let raw = values * NPZ_BYTES_PER_VALUE;
                (raw + HEADER_BYTES, 2.0 * raw + HEADER_BYTES)
            }
        };
        OutputEstimate { records, columns, format, file_bytes, peak_bytes }
    }

    /// A sweep's `.npz`: `records` records of `columns` values in all,
    /// `members` members each with `per_member` further numbers (offsets,
    /// summaries, table values, statuses). The records are streamed to a
    /// raw temporary file and copied into the archive
    /// ([`EnsembleWriter`](crate::sweep::EnsembleWriter)), so both exist at
    /// the end, as for a run's `.npz`.
    pub fn sweep(records: u64, columns: usize, members: u64, per_member: usize) -> OutputEstimate {
        let raw = records as f64 * columns as f64 * NPZ_BYTES_PER_VALUE;
        let b = raw + members as f64 * per_member as f64 * NPZ_BYTES_PER_VALUE + HEADER_BYTES;
        OutputEstimate { records, columns, format: Format::Npz, file_bytes: b, peak_bytes: b + raw }
    }

    /// `csv` or `npz`.
    pub fn format_name(&self) -> &'static str {
        match self.format {
            Format::Csv => "csv",
            Format::Npz => "npz",
        }
    }

    /// `up to N records × C columns, about X GB as csv` (with the raw
    /// temporary file for npz).
    pub fn describe(&self) -> String {
        let raw = if self.format == Format::Npz && self.peak_bytes > self.file_bytes { " with its raw temporary file" } else { "" };
        format!("up to {} records × {} columns, about {} as {}{raw}", self.records, self.columns, human(self.peak_bytes), self.format_name())
    }

    /// True if the estimate is over [`LARGE_OUTPUT_BYTES`].
    pub fn is_large(&self) -> bool {
        self.peak_bytes > LARGE_OUTPUT_BYTES
    }
}

/// Why a run is refused before it starts.
#[derive(Debug, thiserror::Error)]
pub enum SpaceError {
    /// The output cannot fit in the free space of its file system.
    #[error(
        "not enough free space for the output: this run can write {}, but {} has {} free; {} (nothing was written; --no-space-check runs anyway)",
        .estimate.describe(), .dir.display(), human(*.available as f64), .advice
    )]
    Insufficient {
        /// The estimate.
        estimate: OutputEstimate,
        /// The directory of the temporary file.
        dir: PathBuf,
        /// Bytes available to an unprivileged process there.
        available: u64,
        /// The settings that make the output smaller.
        advice: String,
    },
    /// The free space could not be read.
    #[error("cannot read the free space of {}: {source} (--no-space-check runs without the check)", .dir.display())]
    Statvfs {
        /// The directory.
        dir: PathBuf,
        /// The system's error.
        source: io::Error,
    },
}

/// Refuses `estimate` if it cannot fit in the free space of `dir` (the
/// directory of the temporary file); `advice` names the settings to change.
/// Where the free space cannot be known (not a Unix system) it passes.
pub fn check(estimate: &OutputEstimate, dir: &Path, advice: &str) -> Result<(), SpaceError> {
    let Some(available) = free_space(dir).map_err(|source| SpaceError::Statvfs { dir: dir.to_path_buf(), source })? else {
        return Ok(());
    };
    if estimate.peak_bytes <= available as f64 {
        return Ok(());
    }
    // The directory as an absolute path: `.` would say little in a log.
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    Err(SpaceError::Insufficient { estimate: *estimate, dir, available, advice: advice.to_string() })
}

/// The bytes an unprivileged process may still write on the file system of
/// `dir` (`f_bavail × f_frsize`), or `None` where this is not known.
#[cfg(unix)]
pub fn free_space(dir: &Path) -> io::Result<Option<u64>> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "the path contains a NUL byte"))?;
    // SAFETY: `statvfs` writes into the zeroed struct and reads the
    // NUL-terminated path, which outlives the call.
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    if unsafe { libc::statvfs(c.as_ptr(), &mut st) } != 0 {
        return Err(io::Error::last_os_error());
    }
    #[allow(clippy::unnecessary_cast)] // the field types differ between platforms
    let bytes = (st.f_bavail as u128) * (st.f_frsize as u128);
    Ok(Some(u64::try_from(bytes).unwrap_or(u64::MAX)))
}

/// The bytes an unprivileged process may still write on the file system of
/// `dir`, or `None` where this is not known.
#[cfg(not(unix))]
pub fn free_space(_dir: &Path) -> io::Result<Option<u64>> {
    Ok(None)
}

/// Bytes in decimal units: `512 B`, `3.2 MB`, `425 GB`, `1.7 TB`.
pub fn human(bytes: f64) -> String {
    const UNITS: [&str; 7] = ["B", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut v = bytes;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < UNITS.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 || v >= 100.0 {
        format!("{v:.0} {}", UNITS[u])
    } else {
        format!("{v:.1} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_and_units() {
        let csv = OutputEstimate::new(1_000_000, 10, Format::Csv);
        assert_eq!(csv.file_bytes, csv.peak_bytes);
        assert_eq!(csv.file_bytes, 1e7 * CSV_BYTES_PER_VALUE + HEADER_BYTES);
        let npz = OutputEstimate::new(1_000_000, 10, Format::Npz);
        assert_eq!(npz.file_bytes, 8e7 + HEADER_BYTES);
        assert_eq!(npz.peak_bytes, 1.6e8 + HEADER_BYTES);
        assert!(npz.describe().contains("with its raw temporary file"), "{}", npz.describe());
        assert!(!OutputEstimate::new(1_000_000_000, 20, Format::Csv).describe().contains("raw"));
        assert!(OutputEstimate::new(1_000_000_000, 20, Format::Csv).is_large());
        assert!(!csv.is_large());
        assert_eq!(human(512.0), "512 B");
        assert_eq!(human(3.24e6), "3.2 MB");
        assert_eq!(human(4.25e11), "425 GB");
        assert_eq!(human(1.7e12), "1.7 TB");
        assert_eq!(human(3e25), "30000000 EB");
    }

    #[test]
    fn the_check_compares_with_the_free_space() {
        let dir = std::env::temp_dir();
        let free = free_space(&dir).unwrap().unwrap();
        assert!(free > 0);
        let small = OutputEstimate::new(10, 3, Format::Csv);
        check(&small, &dir, "x").unwrap();
        // More values than any file system holds.
        let huge = OutputEstimate::new(u64::MAX, 20, Format::Npz);
        let e = check(&huge, &dir, "record fewer").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("not enough free space") && msg.contains(&dir.display().to_string()) && msg.contains("record fewer"), "{msg}");
        let e = check(&small, Path::new("/no/such/directory"), "x").unwrap_err();
        assert!(matches!(e, SpaceError::Statvfs { .. }) && e.to_string().contains("/no/such/directory"), "{e}");
    }
}
