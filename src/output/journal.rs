//! The commit journal `F.csv.commit`: makes the renames of a [`super::ResultPair`] complete
//! even when the process is killed between them.
//!
//! The pair's files are renamed one after the other (CSV, summary, impact log). A process
//! killed between two renames (SIGKILL, a power cut) would leave the new CSV beside the earlier
//! summary for good. So before the first rename, once every temporary file is whole on disk,
//! the list of renames still to do (`temporary<TAB>target` per line, file names in the target's
//! directory) is written to the journal `F.csv.commit` (itself through a temporary file and a
//! rename, so it is whole or absent), and the journal is removed after the last rename. A
//! journal found by the next process that takes the target's lock ([`super::OutputLock`]) is
//! from a writer that died in the middle of its renames: [`complete`] does the renames whose
//! temporary files are still there (those done before the kill are gone), which gives the dead
//! run's whole set of files, then removes the journal. Until then, a reader that finds
//! `F.csv.commit` knows the files beside it may be from two runs.

use super::scratch::{self, Kind};
use super::{OutputError, io_error};
use std::io::Read;
use std::path::{Path, PathBuf};

/// First line of a journal.
const MAGIC: &str = "linkdyn commit journal";

/// Largest journal read back: a few file names (anything longer is not ours).
const MAX_BYTES: u64 = 64 * 1024;

/// The journal of `target`: `F.csv.commit`.
pub fn journal_path(target: &Path) -> PathBuf {
    let mut p = target.as_os_str().to_owned();
    p.push(".commit");
    PathBuf::from(p)
}

/// The file name of `path` as text.
fn name_of(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Writes the journal of `target` listing the renames `(temporary, target)` (all in the
/// target's directory), flushed to disk with its directory.
pub(crate) fn write(target: &Path, renames: &[(PathBuf, PathBuf)]) -> Result<(), OutputError> {
    let mut text = format!("{MAGIC}\n");
    for (temp, to) in renames {
        text.push_str(&format!("{}\t{}\n", name_of(temp), name_of(to)));
    }
    let mut file = super::AtomicFile::create(&journal_path(target))?;
    file.write_str(&text)?;
    file.commit()
}

/// Removes the journal of `target` after the renames it lists are done (or undone).
pub(crate) fn remove(target: &Path) {
    let _ = std::fs::remove_file(journal_path(target));
    scratch::sync_dir(target);
}

/// Completes the renames of an interrupted commit of `target` (module docs) and removes its
/// journal; returns a note saying what was done, or `None` if there was no journal. Call it
/// holding the target's lock, before leftover temporary files are removed.
///
/// A rename is done only if both names are plain file names, the temporary one is a
/// temporary file of that very target (`.T.linkdyn-<pid>-<nonce>.tmp`) and the target shares
/// the locked target's stem; anything else in the file is ignored (and the journal removed).
pub(crate) fn complete(target: &Path) -> Result<Option<String>, OutputError> {
    let path = journal_path(target);
    let mut text = String::new();
    match std::fs::File::open(&path) {
        Ok(f) => {
            // A journal that is not UTF-8 text is not ours: it is ignored and removed below.
            let _ = f.take(MAX_BYTES).read_to_string(&mut text);
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io_error(&path, e)),
    }
    let dir = scratch::dir_of(target);
    let mut done = Vec::new();
    let mut lines = text.lines();
    if lines.next() == Some(MAGIC) {
        for line in lines {
            let Some((temp, to)) = line.split_once('\t') else {
                continue;
            };
            let plain = |n: &str| !n.is_empty() && !n.contains(['/', '\\']) && n != "..";
            let ours = matches!(scratch::parse(temp), Some((of, _, Kind::Temp)) if of == to);
            if !(plain(temp) && plain(to) && ours && scratch::related(target, to)) {
                continue;
            }
            let from = dir.join(temp);
            if from.exists() {
                std::fs::rename(&from, dir.join(to)).map_err(|e| io_error(&dir.join(to), e))?;
                done.push(to.to_string());
            }
        }
    }
    scratch::sync_dir(target);
    std::fs::remove_file(&path).map_err(|e| io_error(&path, e))?;
    scratch::sync_dir(target);
    Ok(Some(if done.is_empty() {
        format!(
            "{} was left by a run killed after its last rename; removed it (the files were already whole)",
            path.display()
        )
    } else {
        format!(
            "a run writing {} was killed between its renames; completed its commit (renamed its {} into place), so the files beside it are again from one run",
            target.display(),
            done.join(", ")
        )
    }))
}
