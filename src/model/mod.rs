//! Model files: parsing (`file.rs`), `--set` overrides (`overrides.rs`), validation and unit
//! conversion into a [`Model`] with typed ids (`build.rs`).
//!
//! The raw file structs never leave this module; everything downstream sees [`Model`], in SI units.

mod bounds;
mod build;
mod error;
mod expr;
mod file;
pub mod ideal;
mod laws;
mod locate;
mod names;
mod overrides;
mod params;
pub mod plausibility;
mod schema;
mod suggest;
mod types;

pub use error::ModelError;
pub use expr::{BinOp, Expr, Func, Jet, Table, Variable};
pub use ideal::idealise;
pub use schema::json_schema;
pub use types::*;

use sha2::{Digest, Sha256};
use std::path::Path;

/// Largest model file accepted, in bytes (4 MiB). A model with tables of measured data is a
/// few hundred kilobytes; the TOML parser needs up to about 50 bytes of memory per byte of
/// file (a 100 MB file of blank lines took 5 GB and 20 s to be refused), so a larger file is
/// refused before it is read whole, let alone parsed.
pub const MAX_FILE_BYTES: usize = 4 << 20;

/// Reads, overrides, validates and converts a model file.
///
/// `overrides` are `KEY=VALUE` strings as given to `--set` (dotted path, array entries by name).
/// Errors include a file larger than [`MAX_FILE_BYTES`] (read no further than that).
pub fn load(path: &Path, overrides: &[String]) -> Result<Model, ModelError> {
    let text = read(path)?;
    load_str(&text, &path.display().to_string(), overrides)
}

/// The text of a model file, as [`load`] reads it: at most [`MAX_FILE_BYTES`], UTF-8.
pub fn read(path: &Path) -> Result<String, ModelError> {
    use std::io::Read;
    let io = |e: std::io::Error| ModelError::Io {
        file: path.display().to_string(),
        reason: e.to_string(),
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES as u64 + 1).read_to_end(&mut bytes))
        .map_err(io)?;
    if bytes.len() > MAX_FILE_BYTES {
        return Err(too_large(&path.display().to_string()));
    }
    String::from_utf8(bytes).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        ))
    })
}

/// The model text with `overrides` applied, as [`load_str`] validates it: a model file that
/// loads without overrides to the same [`Model`] (the same numbers; only the provenance's hash
/// and override list differ). Without overrides, `text` itself, comments and all; with them,
/// the document written anew (TOML has no comments to carry through a rewrite).
pub fn effective_text(text: &str, file: &str, overrides: &[String]) -> Result<String, ModelError> {
    if overrides.is_empty() {
        return Ok(text.to_string());
    }
    let patched = overrides::apply(text, file, overrides)?.0;
    // Written again in the documentation's order of tables (`[model]` first), not alphabetical.
    let doc: toml::Table = patched
        .parse()
        .map_err(|e: toml::de::Error| ModelError::WholeFile {
            file: file.to_string(),
            message: e.message().trim().to_string(),
        })?;
    document_text(&doc).map_err(|e| ModelError::WholeFile {
        file: file.to_string(),
        message: format!("cannot write the model after the overrides: {e}"),
    })
}

/// The top-level tables of a model file in the order docs/model_format.md writes them.
const SECTION_ORDER: &[&str] = &[
    "model",
    "settings",
    "parameters",
    "tables",
    "ground",
    "bodies",
    "joints",
    "drivers",
    "forces",
    "repeat",
    "outputs",
];

/// A model document as TOML text with its top-level tables in the order of the documentation
/// (`[model]` first, then settings, parameters, … outputs; unknown ones last) rather than
/// alphabetical: the same document, easier to read. A document with a top-level value that is
/// neither a table nor an array of tables (which TOML must write before every table) is
/// written as `toml` orders it.
pub fn document_text(doc: &toml::Table) -> Result<String, toml::ser::Error> {
    let is_section = |v: &toml::Value| match v {
        toml::Value::Table(_) => true,
        toml::Value::Array(a) => !a.is_empty() && a.iter().all(toml::Value::is_table),
        _ => false,
    };
    if !doc.values().all(is_section) {
        return toml::to_string(doc);
    }
    let mut entries: Vec<(&String, &toml::Value)> = doc.iter().collect();
    let rank = |k: &str| {
        SECTION_ORDER
            .iter()
            .position(|s| *s == k)
            .unwrap_or(SECTION_ORDER.len())
    };
    entries.sort_by_key(|(k, _)| rank(k));
    let mut out = String::new();
    for (k, v) in entries {
        let mut one = toml::Table::new();
        one.insert(k.clone(), v.clone());
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&toml::to_string(&one)?);
    }
    Ok(out)
}

/// The error for a model larger than [`MAX_FILE_BYTES`].
fn too_large(file: &str) -> ModelError {
    ModelError::WholeFile {
        file: file.to_string(),
        message: format!(
            "the model file is larger than {MAX_FILE_BYTES} bytes (4 MiB); expected at most that"
        ),
    }
}

/// As [`load`], from text already in memory; `file` is the name used in error messages.
pub fn load_str(text: &str, file: &str, overrides: &[String]) -> Result<Model, ModelError> {
    if text.len() > MAX_FILE_BYTES {
        return Err(too_large(file));
    }
    let raw = file::parse(text, file)?;
    let (raw, effective_text, notes) = if overrides.is_empty() {
        (raw, None, Vec::new())
    } else {
        let (patched, notes) = overrides::apply(text, file, overrides)?;
        (
            file::parse(&patched, file).map_err(|e| e.after_overrides(text, overrides))?,
            Some(patched),
            notes,
        )
    };
    let source = ModelSource {
        path: file.to_string(),
        sha256: text_sha256(text),
        overrides: overrides.to_vec(),
    };
    let located = locate::Locator::new(effective_text.as_deref().unwrap_or(text), file);
    let mut model = build::build(raw, source, &located).map_err(|e| {
        if effective_text.is_some() {
            e.after_overrides(text, overrides)
        } else {
            e
        }
    })?;
    model.notes = notes;
    model.warnings = plausibility::warnings(&model);
    Ok(model)
}

/// The SHA-256 of a model's text (hex), as [`ModelSource::sha256`] records it.
pub fn text_sha256(text: &str) -> String {
    let digest = Sha256::digest(text.as_bytes());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::document_text;

    /// The reordered text is the same document (parsed back equal), `[model]` first and the
    /// tables in the documentation's order; a stray top-level value keeps its meaning.
    #[test]
    fn document_text_orders_the_tables_and_keeps_the_document() {
        let text = "[[joints]]\nname = \"O\"\n\n[model]\nname = \"m\"\n\n[[bodies]]\nname = \"b\"\n\n[ground.points]\nO = [0.0, 0.0]\n";
        let doc: toml::Table = text.parse().unwrap_or_else(|e| panic!("{e}"));
        let written = document_text(&doc).unwrap_or_else(|e| panic!("{e}"));
        let back: toml::Table = written.parse().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, doc, "{written}");
        let at = |s: &str| {
            written
                .find(s)
                .unwrap_or_else(|| panic!("{s} in {written}"))
        };
        assert!(at("[model]") < at("[ground") && at("[ground") < at("[[bodies]]"));
        assert!(at("[[bodies]]") < at("[[joints]]"), "{written}");
        let stray: toml::Table = "x = 1\n[model]\nname = \"m\"\n"
            .parse()
            .unwrap_or_else(|e| panic!("{e}"));
        let written = document_text(&stray).unwrap_or_else(|e| panic!("{e}"));
        let back: toml::Table = written.parse().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, stray, "{written}");
    }
}
