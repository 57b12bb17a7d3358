//! [`Provenance`]: what made a result (linkdyn version, model file and hash, overrides, every
//! setting), and its text lines for comment headers, escaped so that no value can break them.

use crate::model::ModelSource;
use serde::Serialize;
use std::collections::BTreeMap;

/// What made a result: linkdyn version, model file and hash, overrides, every setting.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// `linkdyn` version and git commit.
    pub linkdyn_version: String,
    /// The model file, its SHA-256 and the `--set` overrides.
    pub model: ModelSource,
    /// Every setting of the run by name (sorted, so files compare line by line).
    pub settings: BTreeMap<String, String>,
}

impl Provenance {
    /// The provenance as text lines (for `#` comments in CSV files). Every line is one line:
    /// paths, overrides and values are passed through [`escape_line`].
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![
            format!("linkdyn {}", escape_line(&self.linkdyn_version)),
            format!(
                "model {} sha256 {}",
                escape_line(&self.model.path),
                escape_line(&self.model.sha256)
            ),
        ];
        for o in &self.model.overrides {
            lines.push(format!("set {}", escape_line(o)));
        }
        for (k, v) in &self.settings {
            lines.push(format!("{} = {}", escape_line(k), escape_line(v)));
        }
        lines
    }
}

/// Escapes text for one line of a comment header: `\` → `\\`, newline → `\n`, carriage
/// return → `\r`, tab → `\t`, any other control character → `\u{XX}`. Text without these is
/// returned unchanged, so ordinary files are byte-identical to unescaped ones.
pub fn escape_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// The provenance of a run: version, model source, and `settings` as (name, value) pairs.
pub(crate) fn provenance(source: &ModelSource, settings: Vec<(&str, String)>) -> Provenance {
    Provenance {
        linkdyn_version: crate::version(),
        model: source.clone(),
        settings: settings
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_value_can_add_a_line() {
        let p = Provenance {
            linkdyn_version: "0.1.0 (abc)".into(),
            model: ModelSource {
                path: "dir\nt,x\n0,1/m.toml".into(),
                sha256: "00".into(),
                overrides: vec!["bodies.crank.name=\"a\r\nb\"".into(), "x=a\\nb".into()],
            },
            settings: [("dt".to_string(), "1e-3\u{7}".to_string())].into(),
        };
        let lines = p.lines();
        assert_eq!(
            lines,
            vec![
                "linkdyn 0.1.0 (abc)",
                "model dir\\nt,x\\n0,1/m.toml sha256 00",
                "set bodies.crank.name=\"a\\r\\nb\"",
                "set x=a\\\\nb",
                "dt = 1e-3\\u{7}",
            ]
        );
        assert!(lines.iter().all(|l| !l.contains(['\n', '\r'])));
    }
}
