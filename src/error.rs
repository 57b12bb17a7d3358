//! The crate's top-level error: one variant per layer.

use thiserror::Error;

/// Any linkdyn error.
#[derive(Debug, Error)]
pub enum Error {
    /// A model file that cannot be read or accepted.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// A model that cannot be turned into equations (e.g. cannot be assembled).
    #[error(transparent)]
    Formulation(#[from] crate::formulation::FormulationError),
    /// A setting of a run (end time, output interval, solver option, formulation choice) that
    /// is out of range or does not fit the model; raised before any work is done.
    #[error("{option}: {reason}")]
    Settings {
        /// The setting by its library name (`dt`, `t_end`, `revs`, `rtol`, `energy`, …).
        option: &'static str,
        /// What was expected and what was given. Other settings are named in backticks
        /// (`` `t_end` ``) so that a front end can spell them its own way.
        reason: String,
    },
    /// A failed integration.
    #[error(transparent)]
    Solve(#[from] crate::solve::SolveError),
    /// A result file that cannot be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// An analysis (spectrum, Poincaré section, Lyapunov exponent, sweep) that cannot be done.
    #[error(transparent)]
    Analysis(#[from] crate::analysis::AnalysisError),
}

impl Error {
    /// A [`Error::Settings`] error.
    pub fn settings(option: &'static str, reason: impl Into<String>) -> Self {
        Error::Settings {
            option,
            reason: reason.into(),
        }
    }
}

/// `Result` with [`enum@Error`].
pub type Result<T> = std::result::Result<T, Error>;
