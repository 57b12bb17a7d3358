//! SIGINT, SIGTERM and SIGHUP during `run`: the handler only raises a flag; the run's sink
//! checks it at every sample and aborts, so the result files are dropped (their temporary files
//! removed, the lock released) and the command exits with code 130.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once per process; a second call is a no-op).
pub fn install() {
    // If a handler cannot be installed the default action (termination) stays: temporary files
    // may then be left behind, as before.
    let _ = ctrlc::set_handler(|| REQUESTED.store(true, Ordering::SeqCst));
}

/// Whether a signal arrived.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}
