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
    /// A failed integration.
    #[error(transparent)]
    Solve(#[from] crate::solve::SolveError),
    /// A result file that cannot be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

/// `Result` with [`enum@Error`].
pub type Result<T> = std::result::Result<T, Error>;
