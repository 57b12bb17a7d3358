//! The CSV result file: a header row, `#` provenance lines, then one row per sample, streamed
//! as the samples arrive. Numbers are written in Rust's shortest round-trip form, so the file
//! holds the exact f64s.
//!
//! The header comes first so that readers which take the column names from the first line
//! and skip `#` lines anywhere read the file in one call: NumPy's
//! `np.genfromtxt(f, delimiter=",", names=True, deletechars="")` and
//! `np.loadtxt(f, delimiter=",", skiprows=1)`, pandas' `pd.read_csv(f, comment="#")`. (With
//! the provenance first, `genfromtxt(names=True)` takes the first comment line for the names.)

use super::push_number;
use crate::simulation::{Provenance, Sample, SampleSink};
use crate::solve::SolveError;
use std::io::Write;

/// The head of a CSV result file: the header row `t,<names>`, then one `# ` line per
/// provenance line (each escaped to one line). A name containing a comma, a quote or a line
/// break, or starting with `#`, is quoted as RFC 4180 says (`"a,b"`, `"say ""hi"""`).
pub fn csv_header(provenance: &Provenance, names: &[String]) -> String {
    let mut head = String::from("t");
    for name in names {
        head.push(',');
        if name.contains([',', '"', '\n', '\r']) || name.starts_with('#') {
            head.push('"');
            head.push_str(&name.replace('"', "\"\""));
            head.push('"');
        } else {
            head.push_str(name);
        }
    }
    head.push('\n');
    for line in provenance.lines() {
        head.push_str("# ");
        head.push_str(&line);
        head.push('\n');
    }
    head
}

/// A [`SampleSink`] that writes one CSV row per sample to `W` as it arrives (O(1) memory in
/// the run length). Write errors abort the run as [`SolveError::Sink`], naming `label` (the
/// file).
pub struct CsvSink<W: Write> {
    out: W,
    label: String,
    line: String,
    rows: usize,
}

impl<W: Write> CsvSink<W> {
    /// Writes the head ([`csv_header`]) to `out` and returns the sink for the rows.
    pub fn new(
        mut out: W,
        label: impl Into<String>,
        provenance: &Provenance,
        names: &[String],
    ) -> Result<Self, SolveError> {
        let label = label.into();
        out.write_all(csv_header(provenance, names).as_bytes())
            .map_err(|e| SolveError::Sink {
                t: 0.0,
                reason: format!("cannot write {label}: {e}"),
            })?;
        Ok(CsvSink {
            out,
            label,
            line: String::with_capacity(32 * (names.len() + 1)),
            rows: 0,
        })
    }

    /// Rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The writer back (not flushed).
    pub fn into_inner(self) -> W {
        self.out
    }
}

impl<W: Write> SampleSink for CsvSink<W> {
    fn sample(&mut self, s: &Sample<'_>) -> Result<(), SolveError> {
        self.line.clear();
        push_number(&mut self.line, s.t);
        for v in s.outputs {
            self.line.push(',');
            push_number(&mut self.line, *v);
        }
        self.line.push('\n');
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|e| SolveError::Sink {
                t: s.t,
                reason: format!("cannot write {}: {e}", self.label),
            })?;
        self.rows += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSource;

    #[test]
    fn rows_stream_exactly_and_names_cannot_break_the_header() {
        let provenance = Provenance {
            linkdyn_version: "v".into(),
            model: ModelSource {
                path: "m.toml".into(),
                sha256: "0".into(),
                overrides: vec!["bodies.crank.name=\"a\nb\"".into()],
            },
            settings: [("dt".to_string(), "0.1".to_string())].into(),
        };
        let names: Vec<String> = ["a.x", "b,c.y", "q\"d", "#e"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let sink = CsvSink::new(Vec::new(), "test", &provenance, &names);
        let mut sink = sink.unwrap_or_else(|e| panic!("{e}"));
        let row = [1.0, 0.1 + 0.2, -2.5e-7, 3e15];
        let sample = Sample {
            t: 0.5,
            state: &[],
            outputs: &row,
            constraint_violation: 0.0,
        };
        assert!(sink.sample(&sample).is_ok());
        assert_eq!(sink.rows(), 1);
        let text = String::from_utf8(sink.into_inner()).unwrap_or_default();
        assert_eq!(
            text,
            "t,a.x,\"b,c.y\",\"q\"\"d\",\"#e\"\n\
             # linkdyn v\n# model m.toml sha256 0\n# set bodies.crank.name=\"a\\nb\"\n# dt = 0.1\n\
             0.5,1,0.30000000000000004,-2.5e-7,3e15\n"
        );
    }
}
