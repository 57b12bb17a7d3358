//! Errors of reading result files and drawing figures.

use crate::output::OutputError;
use thiserror::Error;

/// A figure that cannot be made: the input file, a column, the output.
#[derive(Debug, Error)]
pub enum PlotError {
    /// The input file cannot be read.
    #[error("cannot read {path}: {reason}")]
    Read {
        /// The file.
        path: String,
        /// OS error text.
        reason: String,
    },
    /// The input file is not a linkdyn CSV table.
    #[error("{path}:{line}: {reason}")]
    Parse {
        /// The file.
        path: String,
        /// Line number (1-based).
        line: usize,
        /// What was expected.
        reason: String,
    },
    /// A column the figure needs is not in the file.
    #[error("{path}: no column `{column}` (columns: {available})")]
    MissingColumn {
        /// The file.
        path: String,
        /// The requested column.
        column: String,
        /// The file's columns, comma-separated.
        available: String,
    },
    /// Nothing to draw: no rows, or no finite (for a log axis: positive) value.
    #[error("{path}: {reason}")]
    NoData {
        /// The file (or the figure's title when it has no file).
        path: String,
        /// What is missing.
        reason: String,
    },
    /// The clearance of a joint could not be found (model file or joint missing).
    #[error("{path}: clearance of joint `{joint}`: {reason}")]
    Clearance {
        /// The result file whose provenance names the model.
        path: String,
        /// The joint.
        joint: String,
        /// Why it is unknown, and what to do.
        reason: String,
    },
    /// The output name does not say which format to write.
    #[error("--out {path}: unknown figure format (use a .png or .svg file name)")]
    Format {
        /// The output path as given.
        path: String,
    },
    /// An option of the figure is out of range.
    #[error("{option}: {reason}")]
    Option {
        /// The option, as spelled on the command line.
        option: String,
        /// Why it is refused.
        reason: String,
    },
    /// The drawing library failed.
    #[error("cannot draw {path}: {reason}")]
    Draw {
        /// The output file.
        path: String,
        /// The library's message.
        reason: String,
    },
    /// Writing the figure file failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl PlotError {
    /// True for errors in the request (files, columns, options) as opposed to failures
    /// to draw or write.
    pub fn is_bad_input(&self) -> bool {
        match self {
            PlotError::Draw { .. } => false,
            PlotError::Output(o) => o.is_bad_input(),
            _ => true,
        }
    }
}
