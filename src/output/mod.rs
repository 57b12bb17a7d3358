//! Result files: a CSV of sampled outputs, a JSON summary and the impact log
//! `F.impacts.csv` ([`impacts_csv`]), all with provenance (model, settings, version), written
//! whole or not at all.
//!
//! * [`CsvSink`] streams the rows of a run into the CSV as the samples arrive (O(1) memory in
//!   the run length);
//! * [`ResultPair`] makes the CSV, its JSON summary and any further files (the impact log)
//!   appear together or not at all: each is written to its own temporary file beside its
//!   target, all are flushed to disk, then all are renamed over their targets (the earlier
//!   files are restored if a later rename fails);
//!   a lock file held from the first write to the commit keeps two runs on the same target
//!   from mixing their files; a commit journal (`F.csv.commit`) lets the next run complete a
//!   commit cut between its renames, and that run removes the temporary files of killed runs
//!   (named after their process: `.F.linkdyn-<pid>-<nonce>.tmp`);
//!   [`check_target`] refuses targets that are not regular files;
//! * [`write_npz`] writes a run kept in memory as a NumPy `.npz` archive (one array per
//!   column, the provenance as JSON), for the same [`ResultPair`] in place of the CSV;
//! * [`write_mat`] writes it as a MATLAB Level-5 MAT-file instead (one double column vector
//!   per column under a valid MATLAB name, the provenance, the names back), the same way;
//! * [`AtomicFile`] is one such file on its own (temporary file + rename).

mod atomic;
mod csv;
mod impacts;
mod journal;
mod lock;
mod mat;
mod npz;
mod pair;
mod scratch;
mod summary;
mod target;

pub use crate::numbers::{format_for_people, format_number, push_number};
pub use crate::simulation::Provenance;
pub use atomic::AtomicFile;
pub use csv::{CsvSink, csv_header};
pub use impacts::{IMPACTS_HEADER, impacts_csv};
pub use journal::journal_path;
pub use lock::OutputLock;
pub use mat::{FIXED_VARIABLES, MAX_NAME_LEN, check_mat, matlab_name, matlab_names, write_mat};
pub use npz::{PROVENANCE_MEMBER, check_npz_size, write_npz};
pub use pair::{ResultPair, impacts_path, summary_path};
pub use summary::write_json;
pub use target::{check_output_file, check_target, same_file};

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
    /// The requested target cannot be a result file (a directory, a device, the model file…);
    /// refused before any work.
    #[error("{path}: {reason}")]
    Target {
        /// The target as given.
        path: String,
        /// Why it is refused.
        reason: String,
    },
    /// Another process is writing the same result files.
    #[error(
        "{path} is being written by another run (lock {lock} is held); wait for it or choose another output name"
    )]
    Busy {
        /// The target.
        path: String,
        /// The lock file.
        lock: String,
    },
}

impl OutputError {
    /// True for errors in the request itself (a target that can never be written), as
    /// opposed to failures of the file system.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, OutputError::Target { .. })
    }
}

/// An I/O error on `path`.
pub(crate) fn io_error(path: &std::path::Path, e: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}
