//! `linkdyn clean F.csv …`: tidies up after runs that were killed outright (SIGKILL, an
//! out-of-memory kill, a power cut) while writing `F.csv`, without starting a new run.
//!
//! Taking the target's lock ([`linkdyn::output::OutputLock`]) does the work, as at the start of
//! every run: a commit cut between its renames is completed from `F.csv.commit`, temporary files
//! of the target whose process is dead are removed, and the stale lock file goes when the lock
//! is released. A target being written by a live run is left alone (exit 4, "being written").

use super::Failure;
use clap::Args;
use linkdyn::output::OutputLock;
use std::path::PathBuf;

/// Arguments of `clean`.
#[derive(Debug, Args)]
pub struct CleanArgs {
    /// Result files (`--out` of the killed runs).
    #[arg(required = true)]
    files: Vec<PathBuf>,
}

/// Runs `clean`.
pub fn run(args: &CleanArgs) -> Result<(), Failure> {
    for file in &args.files {
        let lock = OutputLock::acquire(file)?;
        if lock.notes().is_empty() {
            eprintln!("{}: nothing left by killed runs", file.display());
        }
        for note in lock.notes() {
            eprintln!("{note}");
        }
    }
    Ok(())
}
