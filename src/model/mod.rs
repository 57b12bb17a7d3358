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
mod suggest;
mod types;

pub use error::ModelError;
pub use expr::{BinOp, Expr, Func, Jet, Table, Variable};
pub use ideal::idealise;
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
    let text = String::from_utf8(bytes).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        ))
    })?;
    load_str(&text, &path.display().to_string(), overrides)
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
    model.warnings = plausibility::warnings(&model);
    Ok(model)
}

fn hex_sha256(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
