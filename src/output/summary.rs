//! The JSON summary file.

use super::OutputError;
use super::atomic::AtomicFile;
use serde::Serialize;
use std::path::Path;

/// Pretty JSON of `value`, with a final newline.
pub(crate) fn json_text<T: Serialize>(path: &Path, value: &T) -> Result<String, OutputError> {
    let mut text = serde_json::to_string_pretty(value).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    text.push('\n');
    Ok(text)
}

/// Serialises `value` as pretty JSON to `path` (prepared, not yet committed: call
/// [`AtomicFile::commit`]).
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<AtomicFile, OutputError> {
    let text = json_text(path, value)?;
    let mut file = AtomicFile::create(path)?;
    file.write_str(&text)?;
    Ok(file)
}
