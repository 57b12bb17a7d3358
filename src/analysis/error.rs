//! [`AnalysisError`]: why an analysis could not be done, and where.

use thiserror::Error;

use crate::formulation::FormulationError;
use crate::solve::SolveError;

/// Errors of the analysis tools (spectra, Poincaré sections, period verdicts, Lyapunov exponents,
/// phase portraits, parameter sweeps). Each says which input or which point is at fault.
#[derive(Debug, Error)]
pub enum AnalysisError {
    /// A signal or a sequence is too short for the analysis.
    #[error("{what}: {got} samples, at least {need} needed")]
    TooFewSamples {
        /// What was too short ("spectrum signal", "phase portrait").
        what: &'static str,
        /// Length given.
        got: usize,
        /// Smallest length accepted.
        need: usize,
    },

    /// An argument is out of range or inconsistent with another.
    #[error("invalid {what}: {reason}")]
    InvalidInput {
        /// Name of the argument or option (`t`, `k_max`, `tau`, `--shard` …).
        what: &'static str,
        /// What was expected and what was given.
        reason: String,
    },

    /// A NaN or infinity in an input.
    #[error("{what}[{index}] is not finite ({value})")]
    NonFinite {
        /// Name of the input (`t`, `x`, `point 3`).
        what: String,
        /// Index of the first non-finite value.
        index: usize,
        /// The value.
        value: f64,
    },

    /// The integration behind an analysis failed (the source says when and why).
    #[error("{analysis}: the integration failed")]
    Solve {
        /// Which analysis was running ("Poincaré section", "Lyapunov exponent").
        analysis: &'static str,
        /// Why the integration stopped.
        #[source]
        source: SolveError,
    },

    /// The formulation could not evaluate its output columns at a sample.
    #[error("{analysis}: the outputs could not be evaluated at t = {t:.9} s")]
    Outputs {
        /// Which analysis was running.
        analysis: &'static str,
        /// Time of the sample (s).
        t: f64,
        /// Why the formulation failed.
        #[source]
        source: FormulationError,
    },

    /// Sweep results that reference points outside the parameter grid.
    #[error("{what}: point index {index} is outside the grid of {n_points} points (0..={last})", last = n_points.saturating_sub(1))]
    PointOutOfRange {
        /// Where the index was found ("merge", "resume").
        what: &'static str,
        /// The index.
        index: usize,
        /// Number of grid points.
        n_points: usize,
    },

    /// Sweep results that lack some points of the grid (or of a shard).
    #[error("{what}: {} missing: {}", plural_points(indices.len()), list_indices(indices))]
    MissingPoints {
        /// Where ("merge").
        what: &'static str,
        /// The missing 0-based point indices, ascending.
        indices: Vec<usize>,
    },

    /// Sweep results that hold some points more than once.
    #[error("{what}: {} given more than once: {}", plural_points(indices.len()), list_indices(indices))]
    DoubledPoints {
        /// Where ("merge", "resume").
        what: &'static str,
        /// The doubled 0-based point indices, ascending.
        indices: Vec<usize>,
    },

    /// A sweep result whose parameter value is not the grid's value at its index (results
    /// of another sweep, or a file edited by hand).
    #[error(
        "{what}: point {index} has parameter {value:e} but the grid has {expected:e} there (results of a different sweep?)"
    )]
    ParameterMismatch {
        /// Where ("merge").
        what: &'static str,
        /// 0-based point index.
        index: usize,
        /// Parameter value found with the result.
        value: f64,
        /// Grid value at that index.
        expected: f64,
    },

    /// Newton's method for a periodic orbit stopped without one: the residual history says
    /// how close it came.
    #[error(
        "{analysis}: no periodic orbit found: {reason}; residual max|P(x) - x| by iteration, in units of the integration tolerance: {}",
        list_residuals(history)
    )]
    NoConvergence {
        /// Which analysis ("periodic orbit").
        analysis: &'static str,
        /// Why Newton's method stopped.
        reason: String,
        /// The residual of each iterate (units of the integration tolerance).
        history: Vec<f64>,
    },

    /// Finished points read back for `--resume` that do not belong to the shard being resumed.
    #[error(
        "resume: point {index} is not in shard {shard} (the partial results belong to another shard or sweep)"
    )]
    NotInShard {
        /// 0-based point index.
        index: usize,
        /// The shard, as `i/n` (1-based i).
        shard: String,
    },
}

/// "1 point" / "3 points".
fn plural_points(n: usize) -> String {
    if n == 1 {
        "1 point".to_string()
    } else {
        format!("{n} points")
    }
}

/// At most [`LISTED`] indices, then how many more: "3, 7, 12" or "0, 1, …, 9 and 40 more".
fn list_indices(indices: &[usize]) -> String {
    let shown: Vec<String> = indices
        .iter()
        .take(LISTED)
        .map(ToString::to_string)
        .collect();
    let mut s = shown.join(", ");
    if indices.len() > LISTED {
        s.push_str(&format!(" and {} more", indices.len() - LISTED));
    }
    s
}

/// The residuals as `3.2e5, 1.1e2, …`.
fn list_residuals(history: &[f64]) -> String {
    let shown: Vec<String> = history.iter().map(|r| format!("{r:.3e}")).collect();
    shown.join(", ")
}

/// How many indices an error message lists before summarising the rest.
const LISTED: usize = 10;

impl AnalysisError {
    /// Shorthand for [`AnalysisError::InvalidInput`].
    pub(crate) fn invalid(what: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidInput {
            what,
            reason: reason.into(),
        }
    }
}

/// The first non-finite value of `values`, as an error naming `what`.
pub(crate) fn check_finite(what: &str, values: &[f64]) -> Result<(), AnalysisError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(AnalysisError::NonFinite {
            what: what.to_string(),
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_lists_are_cut_after_ten() {
        let e = AnalysisError::MissingPoints {
            what: "merge",
            indices: (0..13).collect(),
        };
        assert_eq!(
            e.to_string(),
            "merge: 13 points missing: 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 and 3 more"
        );
        let e = AnalysisError::DoubledPoints {
            what: "merge",
            indices: vec![4],
        };
        assert_eq!(e.to_string(), "merge: 1 point given more than once: 4");
    }

    #[test]
    fn non_finite_names_the_index() {
        let e = check_finite("x", &[0.0, 1.0, f64::NAN]).err();
        assert_eq!(
            e.map(|e| e.to_string()).as_deref(),
            Some("x[2] is not finite (NaN)")
        );
    }
}
