//! The trajectory of a run: a sink that evaluates a formulation's output columns at every sample and keeps them.

use super::{EventRecord, Sink, SolveError};
use crate::formulation::{Formulation, Outputs};

/// Output columns sampled over a run, row-major, plus the events seen.
#[derive(Debug, Clone, Default)]
pub struct Recorder {
    /// Column names (without `t`).
    pub names: Vec<String>,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Values, `names.len()` per sample.
    pub values: Vec<f64>,
    /// Constraint violation max |Φ| at each sample (m or rad).
    pub violation: Vec<f64>,
    /// Largest constraint violation |Φ| over the samples.
    pub max_constraint_violation: f64,
    /// Events located by the integrator, in time order.
    pub events: Vec<EventRecord>,
    row: Vec<f64>,
}

impl Recorder {
    /// A recorder for the columns of `f`.
    pub fn new<F: Outputs>(f: &F) -> Self {
        Recorder {
            names: f.output_names(),
            ..Recorder::default()
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// True if nothing was sampled.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Index of a column by name.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// A whole column by name.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.column_index(name)?;
        let n = self.names.len();
        Some(self.values.chunks(n).map(|row| row[k]).collect())
    }

    /// The row of sample `i`.
    pub fn row(&self, i: usize) -> &[f64] {
        let n = self.names.len();
        &self.values[i * n..(i + 1) * n]
    }
}

impl<F: Formulation + Outputs> Sink<F> for Recorder {
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        let violation = f
            .outputs_into(t, y, &mut self.row)
            .map_err(|source| SolveError::Formulation { t, source })?;
        self.max_constraint_violation = self.max_constraint_violation.max(violation);
        self.violation.push(violation);
        self.t.push(t);
        self.values.extend_from_slice(&self.row);
        Ok(())
    }

    fn event(
        &mut self,
        _f: &F,
        event: &EventRecord,
        _before: &[f64],
        _after: &[f64],
    ) -> Result<(), SolveError> {
        self.events.push(*event);
        Ok(())
    }
}
