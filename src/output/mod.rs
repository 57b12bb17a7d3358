//! Result files: a CSV of sampled outputs and a JSON summary, both with provenance (model,
//! settings, version), both written whole or not at all (temporary file + rename).

mod atomic;
mod csv;
mod summary;

pub use atomic::{AtomicFile, commit_all};
pub use csv::write_csv;
pub use summary::{ClearanceSummary, Provenance, write_json};

use thiserror::Error;

/// A result file that cannot be written.
#[derive(Debug, Error)]
pub enum OutputError {
    /// Creating, writing or renaming a file failed.
    #[error("cannot write {path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// OS error text.
        reason: String,
    },
}

/// Formats a number exactly (shortest round-trip digits) and readably: plain notation for
/// magnitudes in [1e-4, 1e15), scientific otherwise.
pub fn format_number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e15).contains(&a) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
