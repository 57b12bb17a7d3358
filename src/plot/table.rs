//! A linkdyn CSV result file in memory: its `#` provenance lines, its column names and its
//! numbers, column by column.

use super::PlotError;
use std::path::{Path, PathBuf};

/// The contents of a CSV result file: `#` comment lines (provenance), one header row of
/// column names, then rows of numbers (`NaN` and `inf` are read as such).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The file it was read from (for messages and provenance look-ups).
    pub path: PathBuf,
    /// The comment lines without their leading `# `.
    pub comments: Vec<String>,
    /// Column names in file order.
    pub names: Vec<String>,
    /// `columns[j][i]`: row i of column j.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// Reads and parses `path`.
    pub fn read(path: &Path) -> Result<Table, PlotError> {
        let text = std::fs::read_to_string(path).map_err(|e| PlotError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Table::parse(path, &text)
    }

    /// Parses the text of a result file; `path` is only used in messages.
    pub fn parse(path: &Path, text: &str) -> Result<Table, PlotError> {
        let shown = path.display().to_string();
        let mut comments = Vec::new();
        let mut names: Option<Vec<String>> = None;
        let mut columns: Vec<Vec<f64>> = Vec::new();
        for (k, line) in text.lines().enumerate() {
            let line = line.trim_end_matches('\r');
            if let Some(c) = line.strip_prefix('#') {
                comments.push(c.strip_prefix(' ').unwrap_or(c).to_string());
                continue;
            }
            if line.trim().is_empty() {
                continue;
            }
            let Some(header) = &names else {
                let header: Vec<String> = line.split(',').map(|s| s.trim().to_string()).collect();
                columns = vec![Vec::new(); header.len()];
                names = Some(header);
                continue;
            };
            let mut n = 0;
            for (j, field) in line.split(',').enumerate() {
                let Some(column) = columns.get_mut(j) else {
                    n = j + 1;
                    continue;
                };
                let x: f64 = field.trim().parse().map_err(|_| PlotError::Parse {
                    path: shown.clone(),
                    line: k + 1,
                    reason: format!(
                        "column `{}`: `{}` is not a number",
                        header.get(j).map(String::as_str).unwrap_or("?"),
                        field.trim()
                    ),
                })?;
                column.push(x);
                n = j + 1;
            }
            if n != header.len() {
                return Err(PlotError::Parse {
                    path: shown,
                    line: k + 1,
                    reason: format!("{n} fields, the header has {}", header.len()),
                });
            }
        }
        let Some(names) = names else {
            return Err(PlotError::NoData {
                path: shown,
                reason: "no header row (is this a linkdyn CSV file?)".into(),
            });
        };
        Ok(Table {
            path: path.to_path_buf(),
            comments,
            names,
            columns,
        })
    }

    /// Reads `path` as [`Table::read`] does, except that the column called `text` holds words
    /// (a continuation file's `special`: `PD`, `fold`, or empty), returned beside the table
    /// one per row with the row's line number (1-based); the table keeps the other columns.
    pub fn read_with_text(
        path: &Path,
        text: &str,
    ) -> Result<(Table, Vec<(usize, String)>), PlotError> {
        let content = std::fs::read_to_string(path).map_err(|e| PlotError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        // The text column is cut out of every row, line for line (so that a parse error
        // still names the file's line), and the rest parsed as numbers.
        let mut at: Option<usize> = None;
        let mut words = Vec::new();
        let mut kept = String::with_capacity(content.len());
        for (k, line) in content.lines().enumerate() {
            let bare = line.trim_end_matches('\r');
            if bare.starts_with('#') || bare.trim().is_empty() {
                kept.push_str(bare);
                kept.push('\n');
                continue;
            }
            let mut fields: Vec<&str> = bare.split(',').collect();
            match at {
                None => {
                    let Some(j) = fields.iter().position(|f| f.trim() == text) else {
                        return Err(PlotError::MissingColumn {
                            path: path.display().to_string(),
                            column: text.to_string(),
                            available: fields
                                .iter()
                                .map(|f| f.trim())
                                .collect::<Vec<_>>()
                                .join(","),
                        });
                    };
                    at = Some(j);
                    fields.remove(j);
                }
                // A row cut short before the text column reads as an empty word; the
                // numbers are checked by `parse`.
                Some(j) if j < fields.len() => {
                    words.push((k + 1, fields.remove(j).trim().to_string()));
                }
                Some(_) => words.push((k + 1, String::new())),
            }
            kept.push_str(&fields.join(","));
            kept.push('\n');
        }
        let table = Table::parse(path, &kept)?;
        Ok((table, words))
    }

    /// Number of data rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// The column called `name`, or an error naming the file, the column and the file's
    /// columns.
    pub fn column(&self, name: &str) -> Result<&[f64], PlotError> {
        self.names
            .iter()
            .position(|n| n == name)
            .and_then(|j| self.columns.get(j))
            .map(Vec::as_slice)
            .ok_or_else(|| PlotError::MissingColumn {
                path: self.path.display().to_string(),
                column: name.to_string(),
                available: self.names.join(","),
            })
    }

    /// The column at position `j` with its name (for formats whose columns are known by
    /// position, e.g. a bifurcation file's parameter), or a missing-column error naming
    /// `what`.
    pub fn column_at(&self, j: usize, what: &str) -> Result<(&str, &[f64]), PlotError> {
        match (self.names.get(j), self.columns.get(j)) {
            (Some(n), Some(c)) => Ok((n.as_str(), c.as_slice())),
            _ => Err(PlotError::MissingColumn {
                path: self.path.display().to_string(),
                column: what.to_string(),
                available: self.names.join(","),
            }),
        }
    }

    /// The model file and its `--set` overrides named in the provenance (`model PATH sha256 H`
    /// and `set X=V` lines), unescaped; `None` without a `model` line.
    pub fn model_source(&self) -> Option<(PathBuf, Vec<String>)> {
        let model = self.comments.iter().find_map(|c| {
            let rest = c.strip_prefix("model ")?;
            // The path may contain spaces: the hash is the last field.
            let path = rest.rsplit_once(" sha256 ").map_or(rest, |(p, _)| p);
            Some(PathBuf::from(unescape(path)))
        })?;
        let sets = self
            .comments
            .iter()
            .filter_map(|c| c.strip_prefix("set ").map(unescape))
            .collect();
        Some((model, sets))
    }

    /// The value of a `key = value` setting line of the provenance (`observe = B.fn`), if any.
    pub fn setting(&self, key: &str) -> Option<String> {
        self.comments.iter().find_map(|c| {
            let (k, v) = c.split_once(" = ")?;
            (k == key).then(|| unescape(v))
        })
    }

    /// The model's file stem and the `--set` overrides from the provenance
    /// (`farahan2016`, `["drivers.motor.speed_rpm=3500"]`), for titles and legends that say
    /// what was run rather than where it was saved; `None` without a `model` line.
    pub fn run_description(&self) -> Option<(String, Vec<String>)> {
        let (path, sets) = self.model_source()?;
        let stem = path.file_stem().map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        Some((stem, sets))
    }

    /// What the file is a result of, for a title: `farahan2016 with a=1, b=2` from the
    /// provenance, or the file name without one.
    pub fn title_name(&self) -> String {
        match self.run_description() {
            Some((model, sets)) if sets.is_empty() => model,
            Some((model, sets)) => format!("{model} with {}", sets.join(", ")),
            None => self.file_name(),
        }
    }

    /// The file name for titles (`r.csv`).
    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(
            || self.path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        )
    }
}

/// Undoes [`crate::simulation::escape_line`]-style escapes: `\\`, `\n`, `\r`, `\t`, `\u{XX}`.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('r') => out.push('\r'),
            Some('t') => out.push('\t'),
            Some('u') => {
                let code: String = chars
                    .by_ref()
                    .skip_while(|&c| c == '{')
                    .take_while(|&c| c != '}')
                    .collect();
                if let Some(ch) = u32::from_str_radix(&code, 16).ok().and_then(char::from_u32) {
                    out.push(ch);
                }
            }
            Some(other) => out.push(other),
            None => out.push('\\'),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUN: &str = "# linkdyn 0.1.0 (abc)\n# model dir with space/m.toml sha256 00ff\n\
                       # set joints.B.clearance=0.001\n# dt = 0.001\nt,B.ex\n0,1e-4\n0.001,NaN\n";

    #[test]
    fn reads_provenance_header_and_numbers() {
        let t = Table::parse(Path::new("r.csv"), RUN).map_err(|e| e.to_string());
        let Ok(t) = t else {
            panic!("parse failed: {t:?}");
        };
        assert_eq!(t.names, vec!["t", "B.ex"]);
        assert_eq!(t.rows(), 2);
        assert_eq!(t.column("t").ok(), Some(&[0.0, 0.001][..]));
        assert!(t.column("B.ex").is_ok_and(|c| c[1].is_nan()));
        assert_eq!(
            t.model_source(),
            Some((
                PathBuf::from("dir with space/m.toml"),
                vec!["joints.B.clearance=0.001".to_string()]
            ))
        );
    }

    #[test]
    fn titles_name_the_model_and_its_overrides() {
        let t = Table::parse(Path::new("r.csv"), RUN).map_err(|e| e.to_string());
        assert_eq!(
            t.map(|t| t.title_name()),
            Ok("m with joints.B.clearance=0.001".to_string())
        );
        let t = Table::parse(Path::new("dir/s.csv"), "# observe = B.fn\nf\n1\n");
        assert_eq!(
            t.map(|t| (t.title_name(), t.setting("observe"), t.setting("window")))
                .map_err(|e| e.to_string()),
            Ok(("s.csv".to_string(), Some("B.fn".to_string()), None))
        );
    }

    #[test]
    fn missing_column_names_file_and_column() {
        let t = Table::parse(Path::new("r.csv"), RUN).map_err(|e| e.to_string());
        let msg = t.map(|t| t.column("B.fn").map(|_| ()).map_err(|e| e.to_string()));
        assert_eq!(
            msg,
            Ok(Err("r.csv: no column `B.fn` (columns: t,B.ex)".to_string()))
        );
    }

    #[test]
    fn ragged_row_and_text_are_reported_with_line() {
        let e = Table::parse(Path::new("a.csv"), "t,x\n0,1\n1\n").map(|_| ());
        assert_eq!(
            e.map_err(|e| e.to_string()),
            Err("a.csv:3: 1 fields, the header has 2".to_string())
        );
        let e = Table::parse(Path::new("a.csv"), "t,x\n0,abc\n").map(|_| ());
        assert_eq!(
            e.map_err(|e| e.to_string()),
            Err("a.csv:2: column `x`: `abc` is not a number".to_string())
        );
    }

    #[test]
    fn escapes_round_trip() {
        let raw = "a\\b\nc\t\u{7}";
        assert_eq!(unescape(&crate::simulation::escape_line(raw)), raw);
    }
}
