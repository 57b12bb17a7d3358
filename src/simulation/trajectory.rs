//! [`Trajectory`]: a whole run in memory, column by column (one `Vec<f64>` per output column,
//! ready to become a NumPy array), with its events and summary.

use super::sink::{Sample, SampleSink};
use super::{Provenance, RunSummary};
use crate::analysis::Sampled;
use crate::solve::{EventRecord, SolveError, SolverStats};

/// A finished run kept in memory.
#[derive(Debug, Clone)]
pub struct Trajectory {
    /// Output column names (without `t`), as in the CSV header.
    pub names: Vec<String>,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// One vector per column of `names`, each as long as `t`.
    pub columns: Vec<Vec<f64>>,
    /// Constraint violation max |Φ| at each sample (m or rad).
    pub constraint_violation: Vec<f64>,
    /// Located events, in time order.
    pub events: Vec<EventRecord>,
    /// The run's summary (with its provenance and solver statistics).
    pub summary: RunSummary,
}

impl Trajectory {
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

    /// A column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .get(self.column_index(name)?)
            .map(Vec::as_slice)
    }

    /// The solver statistics.
    pub fn stats(&self) -> &SolverStats {
        &self.summary.solver_stats
    }

    /// What made this trajectory.
    pub fn provenance(&self) -> &Provenance {
        &self.summary.provenance
    }
}

/// Collects samples column by column (used by
/// [`Simulation::run_to_memory`](super::Simulation::run_to_memory)).
#[derive(Debug, Clone, Default)]
pub struct Columns {
    /// Sample times (s).
    pub t: Vec<f64>,
    /// One vector per output column.
    pub columns: Vec<Vec<f64>>,
    /// Constraint violation at each sample.
    pub constraint_violation: Vec<f64>,
    /// Events.
    pub events: Vec<EventRecord>,
}

/// A finished run as the comparison tool reads it ([`crate::analysis::compare()`]).
impl Sampled for Trajectory {
    fn names(&self) -> &[String] {
        &self.names
    }
    fn samples(&self) -> usize {
        self.len()
    }
    fn time(&self, i: usize) -> f64 {
        self.t[i]
    }
    fn value(&self, i: usize, k: usize) -> f64 {
        self.columns[k][i]
    }
    fn events(&self) -> &[EventRecord] {
        &self.events
    }
}

impl Columns {
    /// Empty columns for `n` outputs, with room for `samples` samples.
    pub fn with_capacity(n: usize, samples: usize) -> Self {
        Columns {
            t: Vec::with_capacity(samples),
            columns: (0..n).map(|_| Vec::with_capacity(samples)).collect(),
            constraint_violation: Vec::with_capacity(samples),
            events: Vec::new(),
        }
    }
}

impl SampleSink for Columns {
    fn sample(&mut self, s: &Sample<'_>) -> Result<(), SolveError> {
        if s.outputs.len() != self.columns.len() {
            return Err(SolveError::Sink {
                t: s.t,
                reason: format!(
                    "{} output values for {} columns",
                    s.outputs.len(),
                    self.columns.len()
                ),
            });
        }
        self.t.push(s.t);
        for (c, v) in self.columns.iter_mut().zip(s.outputs) {
            c.push(*v);
        }
        self.constraint_violation.push(s.constraint_violation);
        Ok(())
    }

    fn event(&mut self, event: &EventRecord) -> Result<(), SolveError> {
        self.events.push(*event);
        Ok(())
    }
}
