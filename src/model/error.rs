//! Errors in model files: every one names the file, the place and what was expected.

use thiserror::Error;

/// A model file that cannot be read, parsed or accepted.
#[derive(Debug, Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("{file}: cannot read the model file: {reason}")]
    Io {
        /// File path.
        file: String,
        /// OS error text.
        reason: String,
    },
    /// A syntax, type or unknown-field error, or a value that is not acceptable.
    #[error("{file}:{line}:{column}: {field}: {message}")]
    Invalid {
        /// File path.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Dotted path of the field, array entries by name (as `--set` takes it).
        field: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// An error in the whole file that has no single place (e.g. no bodies at all).
    #[error("{file}: {message}")]
    WholeFile {
        /// File path.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// An `--ideal NAME` that names no clearance joint of the model.
    #[error("{file}: --ideal {joint}: {message}")]
    Ideal {
        /// File path.
        file: String,
        /// The joint name as given.
        joint: String,
        /// What is wrong, with the model's clearance joints.
        message: String,
    },
    /// A `--set KEY=VALUE` override that cannot be applied.
    #[error("--set {assignment}: {message}")]
    Override {
        /// The assignment as given.
        assignment: String,
        /// What is wrong.
        message: String,
    },
}

/// `text` as quoted in a message: whole up to 80 characters, else its first 60 and the length,
/// so that a hostile value (an expression of 15 000 terms, a path of 20 000 parts) does not
/// fill the terminal; the message still says where and what is wrong.
pub(crate) fn abbreviate(text: &str) -> String {
    if text.chars().count() <= 80 {
        return text.to_string();
    }
    let head: String = text.chars().take(60).collect();
    format!("{head}… ({} characters)", text.chars().count())
}

impl ModelError {
    /// Re-locates an error found after `--set` overrides were applied: its line and column
    /// refer to the re-serialised document, so they are replaced by those of the same field in
    /// the original `text` (or dropped if the field is not in the file), and the message says
    /// which override set the value.
    pub(crate) fn after_overrides(self, text: &str, overrides: &[String]) -> Self {
        match self {
            ModelError::Invalid {
                file,
                field,
                message,
                ..
            } => {
                let from_set = overrides
                    .iter()
                    .rev()
                    .find(|o| o.split_once('=').is_some_and(|(k, _)| k.trim() == field));
                let message = match from_set {
                    Some(o) => format!("{message} (value from --set {})", abbreviate(o)),
                    None => format!("{message} (after --set overrides)"),
                };
                match super::locate::span_of_path(text, &field) {
                    Some(offset) => {
                        let (line, column) = super::locate::line_column(text, offset);
                        ModelError::Invalid {
                            file,
                            line,
                            column,
                            field,
                            message,
                        }
                    }
                    None => ModelError::WholeFile {
                        file,
                        message: format!("{field}: {message}"),
                    },
                }
            }
            other => other,
        }
    }
}
