//! Files that appear whole or not at all: content goes to a temporary file in the same
//! directory (`.F.linkdyn-<pid>-<nonce>.tmp`, created exclusively; see [`super::scratch`] for
//! the name and for how a later run removes those of killed runs), which is renamed over the
//! target only once everything is written and flushed to disk; the directory is then flushed
//! too, so that the rename survives a power cut. Dropping an uncommitted file removes its
//! temporary file.

use super::scratch::{self, Kind};
use super::{OutputError, io_error};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written; [`AtomicFile::commit`] makes it appear, dropping it removes the
/// temporary file.
pub struct AtomicFile {
    target: PathBuf,
    temp: PathBuf,
    writer: BufWriter<File>,
    committed: bool,
}

impl AtomicFile {
    /// Starts writing `target` (through `.F.linkdyn-<pid>-<nonce>.tmp` beside it, created
    /// exclusively: an existing file or link of that name is never opened).
    pub fn create(target: &Path) -> Result<Self, OutputError> {
        let (temp, file) = create_new(target, Kind::Temp)?;
        Ok(AtomicFile {
            target: target.to_path_buf(),
            temp,
            writer: BufWriter::with_capacity(1 << 16, file),
            committed: false,
        })
    }

    /// The target path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The temporary file's path.
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    /// The writer for the content.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        &mut self.writer
    }

    /// Writes a whole string.
    pub fn write_str(&mut self, s: &str) -> Result<(), OutputError> {
        self.writer
            .write_all(s.as_bytes())
            .map_err(|e| io_error(&self.target, e))
    }

    /// Flushes the content to disk (the temporary file stays where it is).
    pub fn sync(&mut self) -> Result<(), OutputError> {
        self.writer.flush().map_err(|e| io_error(&self.target, e))?;
        self.writer
            .get_ref()
            .sync_all()
            .map_err(|e| io_error(&self.target, e))
    }

    /// Renames the temporary file over the target (call [`AtomicFile::sync`] first). On
    /// failure the temporary file is removed.
    pub(crate) fn rename_into_place(mut self) -> Result<(), OutputError> {
        std::fs::rename(&self.temp, &self.target).map_err(|e| io_error(&self.target, e))?;
        self.committed = true;
        Ok(())
    }

    /// Flushes the content to disk, renames the temporary file over the target and flushes
    /// the directory.
    pub fn commit(mut self) -> Result<(), OutputError> {
        self.sync()?;
        let target = self.target.clone();
        self.rename_into_place()?;
        scratch::sync_dir(&target);
        Ok(())
    }
}

/// Creates a fresh scratch file of `kind` for `target` (`O_EXCL`), trying new names while one
/// exists (a name is 64 random bits: a clash is a leftover or a planted file, not bad luck).
pub(crate) fn create_new(target: &Path, kind: Kind) -> Result<(PathBuf, File), OutputError> {
    let mut last = None;
    for _ in 0..8 {
        let path = scratch::scratch_path(target, kind);
        match OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(file) => return Ok((path, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(io_error(target, e)),
        }
    }
    Err(io_error(
        target,
        last.unwrap_or_else(|| std::io::Error::other("no free temporary file name")),
    ))
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed {
            // Never committed: leave no partial file behind.
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncommitted_file_leaves_nothing_and_committed_file_appears_whole() {
        let dir = std::env::temp_dir().join(format!("linkdyn-atomic-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::create_dir_all(&dir);
        let target = dir.join("a.csv");
        {
            let mut f = AtomicFile::create(&target).map_err(|e| e.to_string());
            if let Ok(f) = f.as_mut() {
                let _ = f.write_str("partial");
            }
        }
        assert!(!target.exists(), "dropped file must not appear");
        assert_eq!(
            std::fs::read_dir(&dir).map(|d| d.count()).unwrap_or(99),
            0,
            "no temp left"
        );
        let mut f = AtomicFile::create(&target).map_err(|e| e.to_string());
        if let Ok(f) = f.as_mut() {
            assert!(f.write_str("whole\n").is_ok());
        }
        assert!(
            f.and_then(|f| f.commit().map_err(|e| e.to_string()))
                .is_ok()
        );
        assert_eq!(
            std::fs::read_to_string(&target).unwrap_or_default(),
            "whole\n"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
