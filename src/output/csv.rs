//! The CSV result file: `#` provenance lines, a header row, then one row per sample.
//! Numbers are written in Rust's shortest round-trip form, so the file holds the exact f64s.

use super::OutputError;
use super::atomic::AtomicFile;
use super::summary::Provenance;
use crate::solve::Recorder;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `rec` to `path` (prepared, not yet committed: call [`AtomicFile::commit`]).
pub fn write_csv(
    path: &Path,
    provenance: &Provenance,
    rec: &Recorder,
) -> Result<AtomicFile, OutputError> {
    let mut file = AtomicFile::create(path)?;
    let mut head = String::new();
    for line in provenance.lines() {
        let _ = writeln!(head, "# {line}");
    }
    head.push('t');
    for name in &rec.names {
        head.push(',');
        head.push_str(name);
    }
    head.push('\n');
    file.write_str(&head)?;
    let mut line = String::with_capacity(32 * (rec.names.len() + 1));
    for (i, t) in rec.t.iter().enumerate() {
        line.clear();
        line.push_str(&super::format_number(*t));
        for v in rec.row(i) {
            line.push(',');
            line.push_str(&super::format_number(*v));
        }
        line.push('\n');
        file.write_str(&line)?;
    }
    Ok(file)
}
