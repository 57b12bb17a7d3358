//! [`ResultPair`]: a CSV and its JSON summary, committed together or not at all.

use super::atomic::AtomicFile;
use super::lock::OutputLock;
use super::summary::json_text;
use super::target::check_target;
use super::{OutputError, io_error};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The summary file beside a CSV: `F.csv` → `F.json`.
pub fn summary_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// A CSV and its JSON summary being written.
///
/// [`ResultPair::begin`] checks the target ([`check_target`]), takes the target's
/// [`OutputLock`] and creates the CSV's temporary file; stream the rows into
/// [`ResultPair::csv`], then [`ResultPair::commit`] writes the summary to its own temporary
/// file, flushes both to disk and renames both over their targets. If anything fails, or the
/// pair is dropped uncommitted, both temporary files and the lock file are removed and an
/// earlier pair at the target is left untouched: if the summary's rename fails after the
/// CSV's succeeded, the earlier CSV is put back (kept meanwhile as a hard link
/// `F.csv.<pid>.old`).
///
/// Between the two renames (microseconds) a reader that does not take the lock can see the
/// new CSV beside the earlier summary; both files carry the full provenance to tell.
pub struct ResultPair {
    csv: AtomicFile,
    json: PathBuf,
    // Declared last: dropped (released, file removed) after the temporary files are gone.
    _lock: OutputLock,
}

impl ResultPair {
    /// Starts writing `csv` and its summary; `model` is the model file, which may not be
    /// overwritten.
    pub fn begin(csv: &Path, model: Option<&Path>) -> Result<Self, OutputError> {
        check_target(csv, model)?;
        let lock = OutputLock::acquire(csv)?;
        let file = AtomicFile::create(csv)?;
        Ok(ResultPair {
            csv: file,
            json: summary_path(csv),
            _lock: lock,
        })
    }

    /// The CSV being written.
    pub fn csv(&mut self) -> &mut AtomicFile {
        &mut self.csv
    }

    /// The summary's path.
    pub fn summary_path(&self) -> &Path {
        &self.json
    }

    /// Every scratch file this pair may create besides its targets: the two temporary files,
    /// the lock file and the backup of the earlier CSV. For a signal handler that must clean up
    /// when the writing thread cannot.
    pub fn scratch_paths(&self) -> Vec<PathBuf> {
        let with = |p: &Path, suffix: String| {
            let mut s = p.as_os_str().to_owned();
            s.push(suffix);
            PathBuf::from(s)
        };
        let pid = std::process::id();
        let csv = self.csv.target();
        vec![
            self.csv.temp_path().to_path_buf(),
            with(&self.json, format!(".{pid}.tmp")),
            with(csv, format!(".{pid}.old")),
            OutputLock::path_for(csv),
        ]
    }

    /// Writes `summary` as pretty JSON and makes both files appear.
    pub fn commit<T: Serialize>(self, summary: &T) -> Result<(), OutputError> {
        self.commit_with(summary, |_| Ok(()))
    }

    /// [`ResultPair::commit`] with a hook between the two renames (tests inject failures).
    fn commit_with<T: Serialize>(
        self,
        summary: &T,
        between: impl FnOnce(&Path) -> Result<(), OutputError>,
    ) -> Result<(), OutputError> {
        let ResultPair {
            mut csv,
            json: json_path,
            _lock,
        } = self;
        let mut json = AtomicFile::create(&json_path)?;
        json.write_str(&json_text(&json_path, summary)?)?;
        json.sync()?;
        csv.sync()?;
        let target = csv.target().to_path_buf();
        let backup = Backup::of(&target)?;
        csv.rename_into_place()?;
        // From here on the CSV target holds the new file: undo that on any failure.
        let result = between(&json_path).and_then(|()| json.rename_into_place());
        match result {
            Ok(()) => {
                backup.discard();
                Ok(())
            }
            Err(e) => {
                backup.restore(&target);
                Err(e)
            }
        }
    }
}

/// The earlier CSV at a target, kept as a hard link while the new one is renamed over it.
struct Backup {
    path: Option<PathBuf>,
}

impl Backup {
    fn of(target: &Path) -> Result<Self, OutputError> {
        if std::fs::symlink_metadata(target).is_err() {
            return Ok(Backup { path: None });
        }
        let mut p = target.as_os_str().to_owned();
        p.push(format!(".{}.old", std::process::id()));
        let path = PathBuf::from(p);
        let _ = std::fs::remove_file(&path);
        // A hard link costs nothing; a file system without them gets a copy.
        if std::fs::hard_link(target, &path).is_err() {
            std::fs::copy(target, &path).map_err(|e| io_error(target, e))?;
        }
        Ok(Backup { path: Some(path) })
    }

    /// Puts the earlier file back (or removes the new one if there was none).
    fn restore(mut self, target: &Path) {
        match self.path.take() {
            Some(p) => {
                let _ = std::fs::rename(&p, target);
            }
            None => {
                let _ = std::fs::remove_file(target);
            }
        }
    }

    fn discard(self) {}
}

impl Drop for Backup {
    fn drop(&mut self) {
        if let Some(p) = self.path.take() {
            let _ = std::fs::remove_file(p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("linkdyn-pair-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        let _ = std::fs::create_dir_all(&d);
        d
    }

    fn listing(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .map(|r| {
                r.filter_map(|e| e.ok())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        v.sort();
        v
    }

    fn write(csv: &Path, text: &str) -> Result<(), OutputError> {
        let mut pair = ResultPair::begin(csv, None)?;
        pair.csv().write_str(text)?;
        pair.commit(&text)
    }

    #[test]
    fn a_failed_second_rename_puts_the_earlier_pair_back_and_leaves_no_temporaries() {
        let d = dir("rollback");
        let csv = d.join("r.csv");
        assert!(write(&csv, "old csv\n").is_ok());
        assert_eq!(listing(&d), ["r.csv", "r.json"]);
        let mut pair = ResultPair::begin(&csv, None).unwrap_or_else(|e| panic!("{e}"));
        assert!(pair.csv().write_str("new csv\n").is_ok());
        let failed = pair.commit_with(&"new", |json| {
            Err(io_error(json, std::io::Error::other("injected failure")))
        });
        assert!(failed.is_err());
        assert_eq!(
            listing(&d),
            ["r.csv", "r.json"],
            "no temporary or lock file left"
        );
        let read = |p: &str| std::fs::read_to_string(d.join(p)).unwrap_or_default();
        assert_eq!(read("r.csv"), "old csv\n", "earlier CSV restored");
        assert_eq!(
            read("r.json"),
            "\"old csv\\n\"\n",
            "earlier summary untouched"
        );
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_failed_first_pair_leaves_nothing() {
        let d = dir("fresh");
        let csv = d.join("r.csv");
        let mut pair = ResultPair::begin(&csv, None).unwrap_or_else(|e| panic!("{e}"));
        assert!(pair.csv().write_str("new csv\n").is_ok());
        let failed = pair.commit_with(&"new", |json| {
            Err(io_error(json, std::io::Error::other("injected failure")))
        });
        assert!(failed.is_err());
        assert!(listing(&d).is_empty(), "left: {:?}", listing(&d));
        // Dropped before commit: nothing either.
        let pair = ResultPair::begin(&csv, None).unwrap_or_else(|e| panic!("{e}"));
        drop(pair);
        assert!(listing(&d).is_empty(), "left: {:?}", listing(&d));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_committed_pair_replaces_the_earlier_one() {
        let d = dir("replace");
        let csv = d.join("r.csv");
        assert!(write(&csv, "one\n").is_ok());
        assert!(write(&csv, "two\n").is_ok());
        assert_eq!(listing(&d), ["r.csv", "r.json"]);
        assert_eq!(std::fs::read_to_string(&csv).unwrap_or_default(), "two\n");
        let _ = std::fs::remove_dir_all(&d);
    }
}
