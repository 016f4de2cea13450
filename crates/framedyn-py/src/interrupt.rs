//! Long calls that stop on Ctrl-C: the work runs on a scoped thread with
//! the GIL released while the calling (main) thread checks for signals
//! every few milliseconds, so `KeyboardInterrupt` arrives within about a
//! second however the work is split across threads.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::prelude::*;

/// How often the waiting thread checks for signals.
const SIGNAL_POLL: Duration = Duration::from_millis(10);

/// Runs `work(cancel)` on a scoped thread; a pending signal (Ctrl-C) raises
/// `cancel` (the work is expected to stop soon after, keeping what it has)
/// and is returned as the error to raise once the work has returned. A
/// panic in the work is returned as its message.
pub fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> T + Send) -> (Result<T, String>, Option<PyErr>) {
    let cancel = AtomicBool::new(false);
    let mut interrupt: Option<PyErr> = None;
    // The worker holds the sender until it returns (or unwinds): the waiting
    // thread wakes as soon as it is dropped, not at the next poll, so a
    // short call does not wait out a polling interval.
    let (done, finished) = mpsc::channel::<()>();
    let result = std::thread::scope(|s| {
        // The worker is attached to the interpreter once, for the whole
        // call, and then detached: a user potential called on it re-attaches
        // to that thread state instead of creating and destroying one per
        // call, which costs more than a short potential itself.
        let worker = s.spawn(|| {
            let _done = done;
            Python::attach(|py| py.detach(|| crate::errors::guard(|| work(&cancel))))
        });
        let mut finished = finished;
        loop {
            let (waited, rx) = py.detach(move || (finished.recv_timeout(SIGNAL_POLL), finished));
            finished = rx;
            if !matches!(waited, Err(RecvTimeoutError::Timeout)) {
                break;
            }
            if interrupt.is_none() {
                if let Err(e) = py.check_signals() {
                    interrupt = Some(e);
                    cancel.store(true, Ordering::Relaxed);
                }
            }
        }
        worker.join().unwrap_or_else(|_| Err("the worker thread panicked".to_string()))
    });
    (result, interrupt)
}
