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
    /// A `--set KEY=VALUE` override that cannot be applied.
    #[error("--set {assignment}: {message}")]
    Override {
        /// The assignment as given.
        assignment: String,
        /// What is wrong.
        message: String,
    },
}

impl ModelError {
    /// Marks an error found after `--set` overrides were applied: its line and column refer to
    /// the file as overridden, which is the same as the file except on overridden lines.
    pub(crate) fn after_overrides(self) -> Self {
        match self {
            ModelError::Invalid {
                file,
                line,
                column,
                field,
                message,
            } => ModelError::Invalid {
                file,
                line,
                column,
                field,
                message: format!("{message} (after --set overrides)"),
            },
            other => other,
        }
    }
}
