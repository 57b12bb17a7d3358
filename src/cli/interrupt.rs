//! SIGINT, SIGTERM and SIGHUP during `run`.
//!
//! The handler raises a flag; the run's sink checks it at every sample and aborts, so the
//! result files are dropped (their temporary files removed, the lock released) and the command
//! exits with code 130. If the run does not get there within [`GRACE`] (the solver may spend a
//! long time between two samples when `--dt` is large), the handler thread removes the
//! registered scratch files itself and exits with code 130 — unless the result files are being
//! committed, which is left to finish (then the run ends normally with a complete pair).
//!
//! `bifurcation` calls [`defer_to_caller`] after [`install`]: a first signal only raises the
//! flag (the sweep stops starting points, lets the points in flight finish and be written, and
//! exits with code 130 itself), so the handler never ends the process in the middle of a write;
//! a second signal ends it at once (finished points are on disk; a row cut off by it is dropped
//! by `--resume`).

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static REQUESTED: AtomicBool = AtomicBool::new(false);
static COMMITTING: AtomicBool = AtomicBool::new(false);
static SCRATCH: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static DEFERRED: AtomicBool = AtomicBool::new(false);

/// How long the run may take to notice a signal before the handler cleans up itself.
const GRACE: Duration = Duration::from_secs(2);

/// Installs the handler (once per process; a second call is a no-op).
pub fn install() {
    // If a handler cannot be installed the default action (termination) stays: temporary files
    // may then be left behind, as before.
    let _ = ctrlc::set_handler(|| {
        let again = REQUESTED.swap(true, Ordering::SeqCst);
        if DEFERRED.load(Ordering::SeqCst) {
            if again {
                eprintln!("error: interrupted twice: stopped at once; finished points are kept");
                std::process::exit(i32::from(super::EXIT_INTERRUPTED));
            }
            eprintln!(
                "interrupted: finishing the points in flight (press Ctrl-C again to stop at once)"
            );
            return;
        }
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

/// After [`install`]: a first signal only raises the flag, the caller stops by itself; a second
/// one exits with code 130 at once (module docs).
pub fn defer_to_caller() {
    DEFERRED.store(true, Ordering::SeqCst);
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
