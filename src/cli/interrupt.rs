//! SIGINT, SIGTERM and SIGHUP during `run`.
//!
//! The handler raises a flag; the run's sink checks it at every sample and aborts, so the
//! result files are dropped (their temporary files removed, the lock released) and the command
//! exits with code 130. If the run does not get there within [`GRACE`] (the solver may spend a
//! long time between two samples when `--dt` is large), the handler thread removes the
//! registered scratch files itself and exits with code 130 — unless the result files are being
//! committed, which is left to finish (then the run ends normally with a complete pair).

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static REQUESTED: AtomicBool = AtomicBool::new(false);
static COMMITTING: AtomicBool = AtomicBool::new(false);
static SCRATCH: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// How long the run may take to notice a signal before the handler cleans up itself.
const GRACE: Duration = Duration::from_secs(2);

/// Installs the handler (once per process; a second call is a no-op).
pub fn install() {
    // If a handler cannot be installed the default action (termination) stays: temporary files
    // may then be left behind, as before.
    let _ = ctrlc::set_handler(|| {
        REQUESTED.store(true, Ordering::SeqCst);
        // This runs on the handler's own thread: the main thread normally exits first.
        std::thread::sleep(GRACE);
        if COMMITTING.load(Ordering::SeqCst) {
            return;
        }
        if let Ok(paths) = SCRATCH.lock() {
            for p in paths.iter() {
                let _ = std::fs::remove_file(p);
            }
        }
        eprintln!("error: {}", super::Failure::interrupted().message);
        std::process::exit(i32::from(super::EXIT_INTERRUPTED));
    });
}

/// Whether a signal arrived.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Files the handler removes if the run does not stop in time.
pub fn remove_on_abort(paths: Vec<PathBuf>) {
    if let Ok(mut s) = SCRATCH.lock() {
        *s = paths;
    }
}

/// Marks the start of the commit, after which a signal no longer aborts the run; returns
/// false if a signal came first (then do not commit).
pub fn begin_commit() -> bool {
    COMMITTING.store(true, Ordering::SeqCst);
    !REQUESTED.load(Ordering::SeqCst)
}
