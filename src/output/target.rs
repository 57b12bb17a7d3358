//! [`check_target`]: is a path fit to receive a result pair? Checked before any work.

use super::OutputError;
use super::pair::summary_path;
use std::fs::FileType;
use std::path::Path;

/// Checks that `csv` and its summary `csv.with_extension("json")` may be (re)written: the CSV
/// name must not end in `.json` (the summary's name), and neither path may be an existing
/// directory, device node, FIFO or socket (a rename would replace a device node such as
/// `/dev/null`), nor the model file `model`.
///
/// Errors: [`OutputError::Target`] with the path as given and the reason.
pub fn check_target(csv: &Path, model: Option<&Path>) -> Result<(), OutputError> {
    let refuse = |reason: String| OutputError::Target {
        path: csv.display().to_string(),
        reason,
    };
    if csv
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return Err(refuse(
            "the CSV file name ends in .json, the name of its summary file; give a name such as F.csv".into(),
        ));
    }
    check_file(csv, model).map_err(refuse)?;
    let json = summary_path(csv);
    check_file(&json, model)
        .map_err(|reason| refuse(format!("its summary {}: {reason}", json.display())))
}

/// Checks that `path` may be (re)written by a rename: it does not exist, or it is a regular
/// file other than the model file `model`. Errors: [`OutputError::Target`].
pub fn check_output_file(path: &Path, model: Option<&Path>) -> Result<(), OutputError> {
    check_file(path, model).map_err(|reason| OutputError::Target {
        path: path.display().to_string(),
        reason,
    })
}

/// Why `path` may not be replaced, if it may not.
fn check_file(path: &Path, model: Option<&Path>) -> Result<(), String> {
    if path.file_name().is_none() || path.as_os_str().to_string_lossy().ends_with('/') {
        return Err(
            "names a directory (ends in / or has no file name); expected a file name".into(),
        );
    }
    check_folder(path)?;
    // `metadata` follows symbolic links: a link to /dev/null is a character device.
    let Ok(meta) = std::fs::metadata(path) else {
        return Ok(());
    };
    let ft = meta.file_type();
    if !ft.is_file() {
        return Err(format!(
            "is {}; expected a regular file or a new name",
            kind(ft)
        ));
    }
    if let Some(model) = model
        && same_file(path, model)
    {
        return Err("is the model file; choose another name".into());
    }
    Ok(())
}

/// Why the folder that is to hold `path` cannot, if it cannot: it does not exist, or it is not
/// a folder. Checked before any work, so that a run is not lost to a missing folder at the end.
fn check_folder(path: &Path) -> Result<(), String> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => return Ok(()), // the current folder
    };
    match std::fs::metadata(folder) {
        Ok(meta) if meta.is_dir() => Ok(()),
        Ok(meta) => Err(format!(
            "{} is {}, not a folder",
            folder.display(),
            if meta.is_file() {
                "a file"
            } else {
                kind(meta.file_type())
            }
        )),
        Err(_) => Err(format!(
            "the folder {} does not exist; create it first (mkdir -p {}) or choose another",
            folder.display(),
            folder.display()
        )),
    }
}

/// What a non-regular file is.
fn kind(ft: FileType) -> &'static str {
    if ft.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
        if ft.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Whether two existing paths name the same file (the same device and inode on Unix, so a
/// second spelling, a hard link or a symbolic link counts); false if either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
        false
    }
    #[cfg(not(unix))]
    {
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}
