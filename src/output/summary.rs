//! Provenance (what made a result) and the JSON summary.

use super::OutputError;
use super::atomic::AtomicFile;
use crate::model::ModelSource;
use serde::Serialize;
use std::path::Path;

/// What made a result: linkdyn version, model file and hash, overrides, every setting.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// `linkdyn` version and git commit.
    pub linkdyn_version: String,
    /// The model file, its SHA-256 and the `--set` overrides.
    pub model: ModelSource,
    /// Every setting of the run by name (sorted, so files compare line by line).
    pub settings: std::collections::BTreeMap<String, String>,
}

impl Provenance {
    /// The provenance as text lines (for `#` comments in CSV files).
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            format!("linkdyn {}", self.linkdyn_version),
            format!("model {} sha256 {}", self.model.path, self.model.sha256),
        ];
        for o in &self.model.overrides {
            lines.push(format!("set {o}"));
        }
        for (k, v) in &self.settings {
            lines.push(format!("{k} = {v}"));
        }
        lines
    }
}

/// Serialises `value` as pretty JSON to `path` (prepared, not yet committed).
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<AtomicFile, OutputError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    let mut file = AtomicFile::create(path)?;
    file.write_str(&text)?;
    file.write_str("\n")?;
    Ok(file)
}
