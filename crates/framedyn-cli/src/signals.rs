//! Stopping on signals. SIGINT (Ctrl-C), SIGTERM (`kill`, `timeout`, batch
//! schedulers, `docker stop`) and SIGHUP (a closed terminal) all stop a run
//! the same way: the steps end at the driver's next poll, what was computed
//! is written as a partial result (`STEM.partial.EXT`, see
//! [`crate::target`]), the temporary files are removed, and the exit code
//! is 128 + the signal's number (130, 143, 129). A second signal ends the
//! process at once with the same code; the temporaries it leaves are
//! removed by the next run that writes the same target.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, LazyLock, Once};

static CANCEL: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
static SIGNAL: LazyLock<Arc<AtomicUsize>> = LazyLock::new(|| Arc::new(AtomicUsize::new(0)));
static INSTALL: Once = Once::new();

/// Installs the handlers (once per process), lowers the flag and returns
/// it: the cancellation flag the driver polls.
pub fn arm() -> &'static AtomicBool {
    INSTALL.call_once(install);
    CANCEL.store(false, Ordering::SeqCst);
    SIGNAL.store(0, Ordering::SeqCst);
    &CANCEL
}

/// After a run stopped by the flag: the exit code (128 + the signal's
/// number) and the signal's name. SIGINT when no signal was recorded (the
/// flag raised by Ctrl-C's fallback handler off unix).
pub fn interruption() -> (u8, &'static str) {
    let sig = i32::try_from(SIGNAL.load(Ordering::SeqCst)).ok().filter(|&s| s != 0).unwrap_or(2);
    let name = match sig {
        1 => "SIGHUP",
        2 => "SIGINT",
        15 => "SIGTERM",
        _ => "a signal",
    };
    (u8::try_from(128 + sig).unwrap_or(130), name)
}

#[cfg(unix)]
fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    use signal_hook::flag;
    for sig in [SIGINT, SIGTERM, SIGHUP] {
        // In registration order: a signal arriving when the flag is already
        // up (the second one) ends the process; otherwise it is recorded
        // and raises the flag.
        let _ = flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&CANCEL));
        let _ = flag::register_usize(sig, Arc::clone(&SIGNAL), sig as usize);
        let _ = flag::register(sig, Arc::clone(&CANCEL));
    }
}

#[cfg(not(unix))]
fn install() {
    let _ = ctrlc::set_handler(|| {
        if CANCEL.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
}
