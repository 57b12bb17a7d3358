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

/// What a clearance joint did over a run.
#[derive(Debug, Clone, Serialize)]
pub struct ClearanceSummary {
    /// Joint name.
    pub joint: String,
    /// Number of impacts (located onsets of contact, δ rising through 0).
    pub impacts: usize,
    /// Number of separations (δ falling through 0).
    pub separations: usize,
    /// Times of the first ten impacts (s).
    pub first_impact_times: Vec<f64>,
    /// Largest penetration δ over the output samples (m; negative if never in contact).
    pub max_penetration: f64,
    /// Largest normal force over the output samples (N).
    pub peak_normal_force: f64,
}

impl ClearanceSummary {
    /// Summaries of the clearance joints named `joints`, whose δ event has index k (their order)
    /// and whose columns `J.delta`, `J.fn` are in the recorder.
    pub fn from_recorder(rec: &crate::solve::Recorder, joints: &[String]) -> Vec<ClearanceSummary> {
        use crate::formulation::Crossing;
        joints
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let impacts: Vec<f64> = rec
                    .events
                    .iter()
                    .filter(|e| e.index == k && e.crossing == Crossing::Rising)
                    .map(|e| e.t)
                    .collect();
                let max_of = |col: &str| {
                    rec.column(&format!("{name}.{col}"))
                        .unwrap_or_default()
                        .into_iter()
                        .fold(f64::NEG_INFINITY, f64::max)
                };
                ClearanceSummary {
                    joint: name.clone(),
                    impacts: impacts.len(),
                    separations: rec
                        .events
                        .iter()
                        .filter(|e| e.index == k && e.crossing == Crossing::Falling)
                        .count(),
                    first_impact_times: impacts.iter().take(10).copied().collect(),
                    max_penetration: max_of("delta"),
                    peak_normal_force: max_of("fn").max(0.0),
                }
            })
            .collect()
    }
}
