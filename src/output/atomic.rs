//! Files that appear whole or not at all: content goes to a temporary file in the same
//! directory, which is renamed over the target only once everything is written and flushed.

use super::OutputError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written; [`AtomicFile::commit`] makes it appear, dropping it removes the
/// temporary file.
pub struct AtomicFile {
    target: PathBuf,
    temp: PathBuf,
    writer: Option<BufWriter<File>>,
}

fn io_error(path: &Path, e: std::io::Error) -> OutputError {
    OutputError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

impl AtomicFile {
    /// Starts writing `target` (through `target.<pid>.tmp` beside it).
    pub fn create(target: &Path) -> Result<Self, OutputError> {
        let mut temp = target.as_os_str().to_owned();
        temp.push(format!(".{}.tmp", std::process::id()));
        let temp = PathBuf::from(temp);
        let file = File::create(&temp).map_err(|e| io_error(target, e))?;
        Ok(AtomicFile {
            target: target.to_path_buf(),
            temp,
            writer: Some(BufWriter::new(file)),
        })
    }

    /// The writer for the content.
    pub fn writer(&mut self) -> Result<&mut BufWriter<File>, OutputError> {
        let target = self.target.clone();
        self.writer
            .as_mut()
            .ok_or_else(|| io_error(&target, std::io::Error::other("file already committed")))
    }

    /// Flushes the content to disk and renames the temporary file over the target.
    pub fn commit(mut self) -> Result<(), OutputError> {
        if let Some(w) = self.writer.take() {
            let file = w
                .into_inner()
                .map_err(|e| io_error(&self.target, e.into_error()))?;
            file.sync_all().map_err(|e| io_error(&self.target, e))?;
        }
        std::fs::rename(&self.temp, &self.target).map_err(|e| io_error(&self.target, e))
    }

    /// Writes a whole string.
    pub fn write_str(&mut self, s: &str) -> Result<(), OutputError> {
        let target = self.target.clone();
        self.writer()?
            .write_all(s.as_bytes())
            .map_err(|e| io_error(&target, e))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.is_some() {
            // Never committed: leave no partial file behind.
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

/// Commits several files only after all of them have been written; if one commit fails the
/// others already renamed stay (each is whole).
pub fn commit_all(files: Vec<AtomicFile>) -> Result<(), OutputError> {
    for f in files {
        f.commit()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncommitted_file_leaves_nothing_and_committed_file_appears_whole() {
        let dir = std::env::temp_dir().join(format!("linkdyn-atomic-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let target = dir.join("a.csv");
        let _ = std::fs::remove_file(&target);
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
