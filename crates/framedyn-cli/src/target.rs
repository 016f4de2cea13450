//! Where an output file goes: the output policy of every file the CLI writes
//! (trajectories, events, sweeps) and of the Python module's
//! `Solution.save`.
//!
//! - **Symlinks are written through.** `-o link.csv` where `link.csv` is a
//!   symbolic link updates the file it points to (the link stays a link);
//!   the temporary file is made beside that file, so the final rename never
//!   crosses a file system. A dangling link is followed to the file it
//!   names, which is created.
//! - **Only regular files are replaced.** A directory, a device, a FIFO or a
//!   socket at the target (after following links) is refused, as is a file
//!   without any write permission bit (mode `0444`, even for root): the
//!   error names the path and what was found there.
//! - **Atomic.** The output is written to `.NAME.KIND-PID` beside the target
//!   and renamed onto it only when complete; the name is shortened to fit
//!   the 255-byte limit of file names. Temporaries left by a process that no
//!   longer runs (killed by `SIGKILL`, a second Ctrl-C) are removed the next
//!   time the same target is written.
//! - **Partial results never replace a file.** A run that fails or is
//!   interrupted writes what it computed to `STEM.partial.EXT` beside the
//!   target (see [`Target::partial`]), and the target itself is left as it
//!   was.

use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Longest file name most file systems accept, in bytes.
const NAME_MAX: usize = 255;
/// The kinds of temporary file ([`Target::temporary`]).
const KINDS: [&str; 2] = ["tmp", "raw"];
/// Symbolic links followed before giving up (as the kernel's `ELOOP`).
const MAX_LINKS: usize = 40;

/// An output path checked against the policy, with symlinks resolved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Target {
    requested: PathBuf,
    resolved: PathBuf,
}

fn refuse(path: &Path, kind: io::ErrorKind, what: &str) -> io::Error {
    io::Error::new(kind, format!("{}: {what}", path.display()))
}

impl Target {
    /// Checks `path` against the policy (module documentation): follows
    /// symbolic links, refuses anything but a regular file or a free name in
    /// an existing directory, and refuses read-only files.
    pub fn resolve(path: &Path) -> io::Result<Target> {
        if path.as_os_str().is_empty() {
            return Err(io::Error::new(io::ErrorKind::InvalidInput, "the output path is empty"));
        }
        let mut p = path.to_path_buf();
        for _ in 0..MAX_LINKS {
            match fs::symlink_metadata(&p) {
                Ok(m) if m.file_type().is_symlink() => {
                    let link = fs::read_link(&p)?;
                    p = if link.is_absolute() { link } else { parent_of(&p).join(link) };
                }
                Ok(m) => {
                    check_existing(&p, &m)?;
                    return Ok(Target { requested: path.to_path_buf(), resolved: p });
                }
                Err(e) if e.kind() == io::ErrorKind::NotFound => {
                    let dir = parent_of(&p);
                    match fs::metadata(dir) {
                        Ok(m) if m.is_dir() => {}
                        Ok(_) => return Err(refuse(dir, io::ErrorKind::NotADirectory, "not a directory")),
                        Err(e) if e.kind() == io::ErrorKind::NotFound => {
                            return Err(refuse(dir, io::ErrorKind::NotFound, "the output directory does not exist"))
                        }
                        Err(e) => return Err(e),
                    }
                    if p.file_name().is_none() {
                        return Err(refuse(&p, io::ErrorKind::InvalidInput, "the output path names no file"));
                    }
                    return Ok(Target { requested: path.to_path_buf(), resolved: p });
                }
                Err(e) => return Err(e),
            }
        }
        Err(refuse(path, io::ErrorKind::InvalidInput, "too many levels of symbolic links"))
    }

    /// The path as given.
    pub fn requested(&self) -> &Path {
        &self.requested
    }

    /// The file that is written (the path with symbolic links followed).
    pub fn resolved(&self) -> &Path {
        &self.resolved
    }

    /// The directory that holds the resolved file and its temporary files.
    pub fn directory(&self) -> &Path {
        parent_of(&self.resolved)
    }

    /// Where a failed or interrupted run's records go: `STEM.partial.EXT`
    /// beside the file that would have been written (`traj.csv` →
    /// `traj.partial.csv`), itself checked against the policy.
    pub fn partial(&self) -> io::Result<Target> {
        let stem = self.resolved.file_stem().map(OsString::from).unwrap_or_else(|| "output".into());
        let mut name = stem;
        name.push(".partial");
        if let Some(ext) = self.resolved.extension() {
            name.push(".");
            name.push(ext);
        }
        Target::resolve(&self.resolved.with_file_name(name))
    }

    /// A temporary file for this target: `.NAME.KIND-PID` beside the
    /// resolved file, `NAME` shortened so that the whole name fits in 255
    /// bytes. Stale temporaries of the same target (of processes that no
    /// longer run) are removed first.
    pub fn temporary(&self, kind: &str) -> PathBuf {
        remove_stale(&self.resolved);
        self.temporary_name(kind)
    }

    /// The name [`Self::temporary`] gives, without the removal of stale
    /// files (for a second temporary file of the same target, the directory
    /// already cleaned).
    pub fn temporary_name(&self, kind: &str) -> PathBuf {
        parent_of(&self.resolved).join(temp_name(&file_name(&self.resolved), kind, std::process::id()))
    }

    /// Renames the complete temporary file `tmp` onto the target.
    pub fn commit(&self, tmp: &Path) -> io::Result<()> {
        // Checked again: the target may have changed while the run went on.
        if let Ok(m) = fs::symlink_metadata(&self.resolved) {
            check_existing(&self.resolved, &m)?;
        }
        fs::rename(tmp, &self.resolved)
    }
}

fn parent_of(p: &Path) -> &Path {
    p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or_else(|| Path::new("."))
}

fn file_name(p: &Path) -> String {
    p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "output".into())
}

fn check_existing(p: &Path, m: &fs::Metadata) -> io::Result<()> {
    let ft = m.file_type();
    if ft.is_dir() {
        return Err(refuse(p, io::ErrorKind::IsADirectory, "is a directory"));
    }
    if !ft.is_file() {
        return Err(refuse(p, io::ErrorKind::InvalidInput, &format!("is a {}, not a regular file; framedyn writes regular files only", special_kind(&ft))));
    }
    if m.permissions().readonly() {
        return Err(refuse(p, io::ErrorKind::PermissionDenied, "is read-only; make it writable or choose another output path"));
    }
    Ok(())
}

#[cfg(unix)]
fn special_kind(ft: &fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_char_device() {
        "character device"
    } else if ft.is_block_device() {
        "block device"
    } else if ft.is_fifo() {
        "FIFO"
    } else if ft.is_socket() {
        "socket"
    } else {
        "special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &fs::FileType) -> &'static str {
    "special file"
}

/// `.NAME.KIND-PID`, with `NAME` cut (at a character boundary) so that the
/// whole fits in [`NAME_MAX`] bytes.
fn temp_name(name: &str, kind: &str, pid: u32) -> String {
    let suffix = format!(".{kind}-{pid}");
    let room = NAME_MAX - 1 - suffix.len();
    let mut cut = name.len().min(room);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!(".{}{suffix}", &name[..cut])
}

/// Removes `.NAME.KIND-PID` files beside `target` whose process is gone
/// (checked in `/proc`; elsewhere nothing is removed).
fn remove_stale(target: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let dir = parent_of(target);
    let own = std::process::id();
    let name = file_name(target);
    let Ok(entries) = fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let fname = entry.file_name();
        let Some(fname) = fname.to_str() else { continue };
        let Some((_, pid)) = stale_parts(fname, &name) else { continue };
        if pid == own || Path::new("/proc").join(pid.to_string()).exists() {
            continue;
        }
        if entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// `(KIND, PID)` if `fname` is the temporary name [`temp_name`] gives
/// `target_name` for some kind and process.
fn stale_parts(fname: &str, target_name: &str) -> Option<(&'static str, u32)> {
    let (head, pid) = fname.rsplit_once('-')?;
    let pid: u32 = pid.parse().ok()?;
    KINDS.iter().copied().find(|k| head.ends_with(k) && fname == temp_name(target_name, k, pid)).map(|k| (k, pid))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("framedyn-target-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn temporary_names_fit_and_are_recognised() {
        let long = "é".repeat(125) + ".csv"; // 254 bytes
        let t = temp_name(&long, "tmp", 4_000_000);
        assert!(t.len() <= NAME_MAX, "{} bytes", t.len());
        assert_eq!(stale_parts(&t, &long), Some(("tmp", 4_000_000)));
        assert_eq!(stale_parts(".a.csv.tmp-12", "a.csv"), Some(("tmp", 12)));
        assert_eq!(stale_parts(".a.csv.raw-12", "a.csv"), Some(("raw", 12)));
        assert_eq!(stale_parts(".b.csv.tmp-12", "a.csv"), None);
        assert_eq!(stale_parts(".a.csv.tmp-x", "a.csv"), None);
        assert_eq!(stale_parts("a.csv", "a.csv"), None);
    }

    #[test]
    fn policy() {
        let d = dir("policy");
        let real = d.join("real.csv");
        fs::write(&real, "old").unwrap();
        let link = d.join("link.csv");
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        let t = Target::resolve(&link).unwrap();
        assert_eq!(t.resolved(), real.as_path());
        assert_eq!(t.partial().unwrap().resolved(), d.join("real.partial.csv"));

        let dangling = d.join("dangling.csv");
        std::os::unix::fs::symlink("sub/none.csv", &dangling).unwrap();
        assert_eq!(Target::resolve(&dangling).unwrap_err().kind(), io::ErrorKind::NotFound);
        let fresh = d.join("fresh.csv");
        std::os::unix::fs::symlink("created.csv", &fresh).unwrap();
        assert_eq!(Target::resolve(&fresh).unwrap().resolved(), d.join("created.csv"));

        let ro = d.join("ro.csv");
        fs::write(&ro, "x").unwrap();
        let mut p = fs::metadata(&ro).unwrap().permissions();
        p.set_readonly(true);
        fs::set_permissions(&ro, p).unwrap();
        let e = Target::resolve(&ro).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::PermissionDenied);
        assert!(e.to_string().contains("read-only"), "{e}");

        let e = Target::resolve(Path::new("/dev/null")).unwrap_err();
        assert!(e.to_string().contains("character device"), "{e}");
        assert_eq!(Target::resolve(&d).unwrap_err().kind(), io::ErrorKind::IsADirectory);
        assert_eq!(Target::resolve(&d.join("no/such/dir.csv")).unwrap_err().kind(), io::ErrorKind::NotFound);

        let loop_a = d.join("loop_a");
        let loop_b = d.join("loop_b");
        std::os::unix::fs::symlink(&loop_b, &loop_a).unwrap();
        std::os::unix::fs::symlink(&loop_a, &loop_b).unwrap();
        assert!(Target::resolve(&loop_a).unwrap_err().to_string().contains("symbolic links"));
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let d = dir("stale");
        let target = d.join("out.csv");
        // PID 4_000_000 is above Linux's pid_max limit (2^22), so it never runs.
        let dead = d.join(".out.csv.tmp-4000000");
        let other = d.join(".other.csv.tmp-4000000");
        let live = d.join(format!(".out.csv.raw-{}", std::process::id()));
        for f in [&dead, &other, &live] {
            fs::write(f, "x").unwrap();
        }
        let t = Target::resolve(&target).unwrap();
        let tmp = t.temporary("tmp");
        assert!(!dead.exists());
        assert!(other.exists() && live.exists());
        assert_eq!(tmp, d.join(format!(".out.csv.tmp-{}", std::process::id())));
        let _ = fs::remove_dir_all(&d);
    }
}
