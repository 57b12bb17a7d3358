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
mod suggest;
mod types;

pub use error::ModelError;
pub use expr::{BinOp, Expr, Func, Jet, Table, Variable};
pub use ideal::idealise;
pub use types::*;

use sha2::{Digest, Sha256};
use std::path::Path;

/// Reads, overrides, validates and converts a model file.
///
/// `overrides` are `KEY=VALUE` strings as given to `--set` (dotted path, array entries by name).
pub fn load(path: &Path, overrides: &[String]) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
        file: path.display().to_string(),
        reason: e.to_string(),
    })?;
    load_str(&text, &path.display().to_string(), overrides)
}

/// As [`load`], from text already in memory; `file` is the name used in error messages.
pub fn load_str(text: &str, file: &str, overrides: &[String]) -> Result<Model, ModelError> {
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
        sha256: hex_sha256(text.as_bytes()),
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
    Ok(model)
}

fn hex_sha256(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
