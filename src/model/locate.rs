//! Turning a byte span of the model text into `file:line:column` and a dotted field path.

use super::error::ModelError;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// Knows the model text and file name; builds located errors.
pub struct Locator<'a> {
    text: &'a str,
    file: &'a str,
}

impl<'a> Locator<'a> {
    /// A locator for `text` read from `file`.
    pub fn new(text: &'a str, file: &'a str) -> Self {
        Locator { text, file }
    }

    /// An [`ModelError::Invalid`] at `span`, with the field path found from the document.
    pub fn error(&self, span: Range<usize>, message: impl Into<String>) -> ModelError {
        let (line, column) = line_column(self.text, span.start);
        ModelError::Invalid {
            file: self.file.to_string(),
            line,
            column,
            field: field_path(self.text, span.start),
            message: message.into(),
        }
    }

    /// Bytes from `offset` to the first character inside the string that starts there: the
    /// length of its opening quote (`"`, `'`, `"""` or `'''`), 0 if no string starts there.
    pub fn string_body_offset(&self, offset: usize) -> usize {
        let rest = self.text.get(offset..).unwrap_or("");
        if rest.starts_with("\"\"\"") || rest.starts_with("'''") {
            3
        } else if rest.starts_with('"') || rest.starts_with('\'') {
            1
        } else {
            0
        }
    }

    /// An error about the file as a whole.
    pub fn whole(&self, message: impl Into<String>) -> ModelError {
        ModelError::WholeFile {
            file: self.file.to_string(),
            message: message.into(),
        }
    }
}

/// 1-based line and column (in characters) of a byte offset.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before.get(line_start..).map_or(0, |s| s.chars().count()) + 1;
    (line, column)
}

/// Dotted path (array entries by their `name`, as `--set` takes it) of the field at `offset`.
/// Falls back to the innermost table header before the offset, or "(file)".
pub fn field_path(text: &str, offset: usize) -> String {
    let Ok(doc) = DeTable::parse(text) else {
        return "(TOML syntax)".to_string();
    };
    let mut entries = Vec::new();
    walk_table(doc.get_ref(), "", &mut entries);
    // The innermost span that contains the offset names the field; otherwise the last header
    // (the start of an array-of-tables entry) before it.
    let containing = entries
        .iter()
        .filter(|e| e.span.start <= offset && offset < e.span.end.max(e.span.start + 1))
        .min_by_key(|e| e.span.end - e.span.start);
    if let Some(entry) = containing {
        return entry.path.clone();
    }
    entries
        .iter()
        .filter(|e| e.span.start <= offset)
        .max_by_key(|e| e.span.start)
        .map_or_else(|| "(file)".to_string(), |e| e.path.clone())
}

/// Byte offset of the value of the field with dotted `path` (as [`field_path`] names it) in
/// `text`, if the file has that field.
pub fn span_of_path(text: &str, path: &str) -> Option<usize> {
    let doc = DeTable::parse(text).ok()?;
    let mut entries = Vec::new();
    walk_table(doc.get_ref(), "", &mut entries);
    // The value's span comes after the key's; prefer it.
    entries
        .iter()
        .filter(|e| e.path == path)
        .map(|e| e.span.start)
        .max()
}

struct Entry {
    span: Range<usize>,
    path: String,
}

/// `prefix.key`; a key that is not a valid name (see `names`) is quoted as TOML quotes it, so
/// that a hostile key (a newline, a comma) cannot break the one-line error message.
fn join(prefix: &str, key: &str) -> String {
    let key = if super::names::is_valid(key) {
        key.to_string()
    } else {
        format!("{key:?}")
    };
    if prefix.is_empty() {
        key
    } else {
        format!("{prefix}.{key}")
    }
}

fn walk_table(table: &DeTable<'_>, prefix: &str, out: &mut Vec<Entry>) {
    for (key, value) in table.iter() {
        let path = join(prefix, key.get_ref());
        out.push(Entry {
            span: key.span(),
            path: path.clone(),
        });
        walk_value(value.get_ref(), value.span(), &path, out);
    }
}

fn walk_value(value: &DeValue<'_>, span: Range<usize>, path: &str, out: &mut Vec<Entry>) {
    out.push(Entry {
        span,
        path: path.to_string(),
    });
    match value {
        DeValue::Table(t) => walk_table(t, path, out),
        DeValue::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                let element = match item.get_ref() {
                    // An entry whose name is not valid is named by its index: the name could
                    // hold a newline, or a '.' that would read as another level of the path.
                    DeValue::Table(t) => match t.get("name").map(|n| n.get_ref()) {
                        Some(DeValue::String(name)) if super::names::is_valid(name) => {
                            join(path, name)
                        }
                        _ => format!("{path}[{i}]"),
                    },
                    _ => format!("{path}[{i}]"),
                };
                walk_value(item.get_ref(), item.span(), &element, out);
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = "[model]\nname = \"m\"\n\n[[bodies]]\nname = \"crank\"\nmass = 1.0\n\n[[bodies]]\nname = \"rod\"\nmass = -2.0\ninitial = { x = 1.0, y = 2.0, phi = 0.0 }\n";

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_column(DOC, 0), (1, 1));
        let at = DOC.find("mass = -2.0").unwrap_or(0);
        assert_eq!(line_column(DOC, at), (10, 1));
    }

    #[test]
    fn paths_name_array_entries_by_name() {
        let at = DOC.find("-2.0").unwrap_or(0);
        assert_eq!(field_path(DOC, at), "bodies.rod.mass");
        let at = DOC.find("y = 2.0").unwrap_or(0) + 4;
        assert_eq!(field_path(DOC, at), "bodies.rod.initial.y");
    }
}
