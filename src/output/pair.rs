//! [`ResultPair`]: a CSV, its JSON summary and any further result files (the impact log),
//! committed together or not at all.

use super::atomic::{AtomicFile, create_new};
use super::journal;
use super::lock::OutputLock;
use super::scratch::{self, Kind};
use super::summary::json_text;
use super::target::{check_output_file, check_target};
use super::{OutputError, io_error};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The summary file beside a CSV: `F.csv` → `F.json`.
pub fn summary_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// The impact log beside a CSV: `F.csv` → `F.impacts.csv`.
pub fn impacts_path(csv: &Path) -> PathBuf {
    csv.with_extension("impacts.csv")
}

/// A CSV, its JSON summary and optional further files (e.g. the impact log) being written.
///
/// [`ResultPair::begin`] (or [`ResultPair::begin_with`] for further files) checks the targets
/// ([`check_target`], [`check_output_file`]), takes the target's [`OutputLock`] and creates the
/// CSV's temporary file; stream the rows into [`ResultPair::csv`], then [`ResultPair::commit`]
/// (or [`ResultPair::commit_with_files`]) writes the summary and the further files to their
/// own temporary files, flushes all to disk, writes the commit journal `F.csv.commit`
/// (the `journal` module), renames each over its target, flushes the directory and removes the
/// journal. If anything fails, or the pair is dropped uncommitted, every temporary file and the
/// lock file are removed and the earlier files at the targets are left untouched: if a rename
/// fails after earlier ones succeeded, the files they replaced are put back (kept meanwhile as
/// hard links `.F.linkdyn-<pid>-<nonce>.old`).
///
/// A process killed outright cannot clean up; the next [`ResultPair::begin`] on the same
/// target does (its [`ResultPair::notes`] say what it did): a commit cut between its renames is
/// completed from the journal, and leftover temporary files of dead processes are removed.
/// Between the renames (microseconds) a reader that does not take the lock can see a new file
/// beside earlier ones; every file carries the full provenance to tell, and `F.csv.commit`
/// exists meanwhile.
pub struct ResultPair {
    csv: AtomicFile,
    json: PathBuf,
    extras: Vec<PathBuf>,
    // Declared last: dropped (released, file removed) after the temporary files are gone.
    _lock: OutputLock,
}

impl ResultPair {
    /// Starts writing `csv` and its summary; `model` is the model file, which may not be
    /// overwritten.
    pub fn begin(csv: &Path, model: Option<&Path>) -> Result<Self, OutputError> {
        Self::begin_with(csv, model, &[])
    }

    /// [`ResultPair::begin`] with further files `extras` committed with the pair (their text
    /// is given to [`ResultPair::commit_with_files`], in this order). Each is checked as the
    /// CSV is; a further file may not be the CSV or its summary.
    pub fn begin_with(
        csv: &Path,
        model: Option<&Path>,
        extras: &[PathBuf],
    ) -> Result<Self, OutputError> {
        check_target(csv, model)?;
        let json = summary_path(csv);
        for extra in extras {
            if extra == csv || *extra == json {
                return Err(OutputError::Target {
                    path: extra.display().to_string(),
                    reason: "is also the CSV or its summary; choose another name".into(),
                });
            }
            check_output_file(extra, model)?;
        }
        let lock = OutputLock::acquire(csv)?;
        let file = AtomicFile::create(csv)?;
        Ok(ResultPair {
            csv: file,
            json,
            extras: extras.to_vec(),
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

    /// What taking the target's lock cleaned up after killed runs ([`OutputLock::notes`]).
    pub fn notes(&self) -> &[String] {
        self._lock.notes()
    }

    /// The scratch files that exist before the commit: the CSV's temporary file and the lock
    /// file (the other temporary files and the backups are made by the commit, which a signal
    /// handler lets finish). For a signal handler that must clean up when the writing thread
    /// cannot.
    pub fn scratch_paths(&self) -> Vec<PathBuf> {
        vec![
            self.csv.temp_path().to_path_buf(),
            OutputLock::path_for(self.csv.target()),
        ]
    }

    /// Writes `summary` as pretty JSON and makes both files appear.
    pub fn commit<T: Serialize>(self, summary: &T) -> Result<(), OutputError> {
        self.commit_with_files(summary, &[])
    }

    /// Writes `summary` as pretty JSON and `texts[i]` to the i-th further file given to
    /// [`ResultPair::begin_with`], and makes them all appear with the CSV. Errors: a count of
    /// texts other than the further files' (nothing is written), or an I/O error.
    pub fn commit_with_files<T: Serialize>(
        self,
        summary: &T,
        texts: &[String],
    ) -> Result<(), OutputError> {
        self.commit_with(summary, texts, |_| Ok(()))
    }

    /// [`ResultPair::commit_with_files`] with a hook before each rename after the CSV's (tests
    /// inject failures).
    fn commit_with<T: Serialize>(
        self,
        summary: &T,
        texts: &[String],
        mut before_rename: impl FnMut(&Path) -> Result<(), OutputError>,
    ) -> Result<(), OutputError> {
        let ResultPair {
            mut csv,
            json: json_path,
            extras,
            _lock,
        } = self;
        if texts.len() != extras.len() {
            return Err(OutputError::Io {
                path: csv.target().display().to_string(),
                reason: format!(
                    "{} further result files were opened but {} texts given (a bug)",
                    extras.len(),
                    texts.len()
                ),
            });
        }
        let mut others = Vec::with_capacity(1 + extras.len());
        let mut json = AtomicFile::create(&json_path)?;
        json.write_str(&json_text(&json_path, summary)?)?;
        others.push(json);
        for (path, text) in extras.iter().zip(texts) {
            let mut file = AtomicFile::create(path)?;
            file.write_str(text)?;
            others.push(file);
        }
        for file in &mut others {
            file.sync()?;
        }
        csv.sync()?;
        // From here on every file is whole on disk: the journal lets the next run finish the
        // renames if this process is killed between them.
        let renames: Vec<(PathBuf, PathBuf)> = std::iter::once(&csv)
            .chain(&others)
            .map(|f| (f.temp_path().to_path_buf(), f.target().to_path_buf()))
            .collect();
        let csv_target = csv.target().to_path_buf();
        journal::write(&csv_target, &renames)?;
        let result = Self::rename_all(csv, others, &mut before_rename);
        // Every rename is on disk before the journal goes; after a failure (rolled back, or
        // nothing renamed) the journal has nothing left to do either.
        scratch::sync_dir(&csv_target);
        journal::remove(&csv_target);
        result
    }

    /// Renames `csv`, then each of `others`, over its target; on a failure puts back what was
    /// replaced so far.
    fn rename_all(
        csv: AtomicFile,
        others: Vec<AtomicFile>,
        before_rename: &mut impl FnMut(&Path) -> Result<(), OutputError>,
    ) -> Result<(), OutputError> {
        // Each target's earlier file is kept until all renames succeeded; on a failure every
        // target renamed so far gets its earlier file back (or is removed if it had none).
        let mut done: Vec<(PathBuf, Backup)> = Vec::with_capacity(1 + others.len());
        let target = csv.target().to_path_buf();
        let backup = Backup::of(&target)?;
        csv.rename_into_place()?;
        done.push((target, backup));
        let mut result = Ok(());
        for file in others {
            let target = file.target().to_path_buf();
            let step = before_rename(&target)
                .and_then(|()| Backup::of(&target))
                .and_then(|backup| {
                    file.rename_into_place()?;
                    Ok(backup)
                });
            match step {
                Ok(backup) => done.push((target, backup)),
                Err(e) => {
                    result = Err(e);
                    break;
                }
            }
        }
        match result {
            Ok(()) => Ok(()),
            Err(e) => {
                // Rolling back: the journal must not roll the commit forward any more (the
                // temporary files not renamed are already gone with the loop's iterator).
                if let Some((first, _)) = done.first() {
                    journal::remove(first);
                }
                for (target, backup) in done.into_iter().rev() {
                    backup.restore(&target);
                }
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
        // A hard link costs nothing (and, like `O_EXCL`, never replaces an existing name); a
        // file system without them gets a copy into a file created exclusively.
        for _ in 0..8 {
            let path = scratch::scratch_path(target, Kind::Backup);
            match std::fs::hard_link(target, &path) {
                Ok(()) => return Ok(Backup { path: Some(path) }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(_) => break,
            }
        }
        let (path, mut copy) = create_new(target, Kind::Backup)?;
        let backup = Backup {
            path: Some(path.clone()),
        };
        std::fs::File::open(target)
            .and_then(|mut from| std::io::copy(&mut from, &mut copy))
            .map_err(|e| io_error(target, e))?;
        Ok(backup)
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
        let mut journal = String::new();
        let failed = pair.commit_with(&"new", &[], |json| {
            // Between the renames the journal lists them (the CSV's already done).
            journal = std::fs::read_to_string(journal::journal_path(&d.join("r.csv")))
                .unwrap_or_default();
            Err(io_error(json, std::io::Error::other("injected failure")))
        });
        assert!(failed.is_err());
        let lines: Vec<&str> = journal.lines().collect();
        assert_eq!(lines.len(), 3, "{journal}");
        assert_eq!(lines[0], "linkdyn commit journal");
        for (line, target) in lines[1..].iter().zip(["r.csv", "r.json"]) {
            let (temp, to) = line.split_once('\t').unwrap_or_default();
            assert_eq!(to, target);
            assert_eq!(
                scratch::parse(temp),
                Some((target, std::process::id(), Kind::Temp))
            );
        }
        assert_eq!(
            listing(&d),
            ["r.csv", "r.json"],
            "no temporary, journal or lock file left"
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
        let failed = pair.commit_with(&"new", &[], |json| {
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

    fn write3(csv: &Path, text: &str) -> Result<(), OutputError> {
        let mut pair = ResultPair::begin_with(csv, None, &[impacts_path(csv)])?;
        pair.csv().write_str(text)?;
        pair.commit_with_files(&text, &[format!("log {text}")])
    }

    #[test]
    fn a_failed_third_rename_puts_both_earlier_files_back() {
        let d = dir("third");
        let csv = d.join("r.csv");
        assert!(write3(&csv, "old\n").is_ok());
        assert_eq!(listing(&d), ["r.csv", "r.impacts.csv", "r.json"]);
        let read = |p: &str| std::fs::read_to_string(d.join(p)).unwrap_or_default();
        assert_eq!(read("r.impacts.csv"), "log old\n");
        let mut pair = ResultPair::begin_with(&csv, None, &[impacts_path(&csv)])
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(pair.csv().write_str("new\n").is_ok());
        // The summary's rename goes through, the impact log's fails.
        let failed = pair.commit_with(&"new", &["log new\n".to_string()], |p| {
            if p.ends_with("r.impacts.csv") {
                Err(io_error(p, std::io::Error::other("injected failure")))
            } else {
                Ok(())
            }
        });
        assert!(failed.is_err());
        assert_eq!(
            listing(&d),
            ["r.csv", "r.impacts.csv", "r.json"],
            "no temporary, backup or lock file left"
        );
        assert_eq!(read("r.csv"), "old\n", "earlier CSV restored");
        assert_eq!(read("r.json"), "\"old\\n\"\n", "earlier summary restored");
        assert_eq!(read("r.impacts.csv"), "log old\n", "earlier log untouched");
        // A fresh target: a failure leaves nothing.
        let fresh = d.join("f.csv");
        let mut pair = ResultPair::begin_with(&fresh, None, &[impacts_path(&fresh)])
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(pair.csv().write_str("new\n").is_ok());
        let failed = pair.commit_with(&"new", &["x".to_string()], |p| {
            if p.ends_with("f.impacts.csv") {
                Err(io_error(p, std::io::Error::other("injected failure")))
            } else {
                Ok(())
            }
        });
        assert!(failed.is_err());
        assert_eq!(listing(&d), ["r.csv", "r.impacts.csv", "r.json"]);
        // A wrong number of texts writes nothing.
        let pair = ResultPair::begin_with(&fresh, None, &[impacts_path(&fresh)])
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(pair.commit(&"x").is_err(), "one further file, no text");
        assert_eq!(listing(&d), ["r.csv", "r.impacts.csv", "r.json"]);
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
