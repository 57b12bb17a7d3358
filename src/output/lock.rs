//! [`OutputLock`]: one writer per result target at a time.
//!
//! The lock is an advisory exclusive lock ([`File::try_lock`], `flock` on Unix) on the file
//! `F.csv.lock` beside the target, taken before the first byte is written and released after
//! the commit. A second run on the same target finds it held and stops at once with
//! [`OutputError::Busy`] (before integrating) instead of waiting: two runs can never interleave
//! their renames into a mixed pair. The lock file is removed on release so that nothing is
//! left behind; because a run may have opened the file just before it was removed, a lock is
//! only accepted once the path is seen to still name the very file that was locked (else the
//! run opens the new file and tries again).
//!
//! The lock also makes a run the one to clean up after a killed one: a process killed outright
//! leaves its lock file (no holder: the kernel released the `flock`), its temporary files and
//! perhaps a half-done commit. Whoever takes the lock next first completes such a commit
//! ([`super::journal`]), then removes the temporary files of the target whose writers are dead
//! ([`super::scratch`]); [`OutputLock::notes`] says what was done.

use super::{OutputError, io_error};
use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};

/// A held lock on a result target; released (and its file removed) on drop.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    file: Option<File>,
    notes: Vec<String>,
}

/// Attempts at opening and locking before giving up on a lock file that keeps being replaced.
const ATTEMPTS: usize = 8;

impl OutputLock {
    /// The lock file of `target`: `target.lock`.
    pub fn path_for(target: &Path) -> PathBuf {
        let mut p = target.as_os_str().to_owned();
        p.push(".lock");
        PathBuf::from(p)
    }

    /// Takes the lock of `target`, or fails with [`OutputError::Busy`] if another process
    /// holds it.
    pub fn acquire(target: &Path) -> Result<Self, OutputError> {
        let path = Self::path_for(target);
        for _ in 0..ATTEMPTS {
            let file = OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .map_err(|e| io_error(&path, e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    return Err(OutputError::Busy {
                        path: target.display().to_string(),
                        lock: path.display().to_string(),
                    });
                }
                Err(TryLockError::Error(e)) => return Err(io_error(&path, e)),
            }
            if still_named(&path, &file) {
                let mut lock = OutputLock {
                    path,
                    file: Some(file),
                    notes: Vec::new(),
                };
                // The commit first: it needs the temporary files that the cleanup would remove.
                lock.notes.extend(super::journal::complete(target)?);
                let removed = super::scratch::remove_stale(target);
                if !removed.is_empty() {
                    lock.notes.push(format!(
                        "removed {} temporary file{} of killed runs beside {}: {}",
                        removed.len(),
                        if removed.len() == 1 { "" } else { "s" },
                        target.display(),
                        removed.join(", ")
                    ));
                }
                return Ok(lock);
            }
        }
        Err(io_error(
            &path,
            std::io::Error::other("the lock file keeps being replaced"),
        ))
    }
}

impl OutputLock {
    /// What taking the lock cleaned up after killed runs (a completed commit, removed
    /// temporary files), one sentence each; empty if nothing was left.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }
}

/// Whether `path` still names the open file `file` (it may have been removed by the previous
/// holder between our open and our lock).
#[cfg(unix)]
fn still_named(path: &Path, file: &File) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(path), file.metadata()) {
        (Ok(p), Ok(f)) => p.dev() == f.dev() && p.ino() == f.ino(),
        _ => false,
    }
}

/// Without inode numbers, accept the lock if the path still exists.
#[cfg(not(unix))]
fn still_named(path: &Path, _file: &File) -> bool {
    path.exists()
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Remove the file while still holding the lock, then unlock by closing it.
        let _ = std::fs::remove_file(&self.path);
        drop(self.file.take());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_the_same_target_is_refused_and_nothing_is_left() {
        let dir = std::env::temp_dir().join(format!("linkdyn-lock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::create_dir_all(&dir);
        let target = dir.join("r.csv");
        let first = OutputLock::acquire(&target).map_err(|e| e.to_string());
        assert!(first.is_ok(), "{first:?}");
        match OutputLock::acquire(&target) {
            Err(OutputError::Busy { lock, .. }) => {
                assert!(lock.ends_with("r.csv.lock"), "{lock}")
            }
            other => panic!("expected Busy, got {other:?}"),
        }
        drop(first);
        let again = OutputLock::acquire(&target).map_err(|e| e.to_string());
        assert!(again.is_ok(), "released lock can be taken again: {again:?}");
        drop(again);
        assert_eq!(
            std::fs::read_dir(&dir).map(|d| d.count()).unwrap_or(99),
            0,
            "lock file removed on release"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
