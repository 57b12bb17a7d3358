//! [`SampleSink`]: where a [`Simulation`](super::Simulation) sends its samples — the state and
//! the evaluated output columns together, so that the outputs are evaluated once per sample
//! for the summary and the consumer (a CSV file, a [`Trajectory`](super::Trajectory), an
//! analysis) alike.

use super::summary::SummaryBuilder;
use crate::formulation::{Formulation, Outputs};
use crate::solve::{EventRecord, Sink, SolveError};
use std::time::{Duration, Instant};

/// One output sample of a run.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Time (s), on the output grid t0 + k·dt.
    pub t: f64,
    /// The formulation's state vector at t (layout: the formulation's own).
    pub state: &'a [f64],
    /// The output columns at t, in the order of
    /// [`Simulation::column_names`](super::Simulation::column_names).
    pub outputs: &'a [f64],
    /// Constraint violation max |Φ| at t (m or rad; 0 for the reduced formulation).
    pub constraint_violation: f64,
}

/// Receives a run's samples and events as they are produced.
///
/// An error returned by a method aborts the run; the error is returned by
/// [`Simulation::run`](super::Simulation::run) as [`Error::Solve`](crate::Error::Solve)
/// unchanged. Report a failure as [`SolveError::Sink`] with the time of the sample.
pub trait SampleSink {
    /// A sample on the output grid.
    fn sample(&mut self, sample: &Sample<'_>) -> Result<(), SolveError>;

    /// A located event (all samples at or before its time were sent first). Default: ignored.
    fn event(&mut self, _event: &EventRecord) -> Result<(), SolveError> {
        Ok(())
    }
}

impl<S: SampleSink + ?Sized> SampleSink for &mut S {
    fn sample(&mut self, sample: &Sample<'_>) -> Result<(), SolveError> {
        (**self).sample(sample)
    }

    fn event(&mut self, event: &EventRecord) -> Result<(), SolveError> {
        (**self).event(event)
    }
}

/// A sink that ignores everything (a run for its summary only).
#[derive(Debug, Clone, Copy, Default)]
pub struct Discard;

impl SampleSink for Discard {
    fn sample(&mut self, _sample: &Sample<'_>) -> Result<(), SolveError> {
        Ok(())
    }
}

/// The [`solve::Sink`](Sink) a simulation integrates with: evaluates the outputs once per
/// sample, updates the summary, and forwards both to the consumer.
pub(super) struct Observed<'s, S: SampleSink + ?Sized> {
    pub(super) summary: SummaryBuilder,
    pub(super) consumer: &'s mut S,
    /// Wall time spent in the consumer (s), kept apart from the integration's.
    pub(super) consumer_time: Duration,
    row: Vec<f64>,
}

impl<'s, S: SampleSink + ?Sized> Observed<'s, S> {
    pub(super) fn new(summary: SummaryBuilder, consumer: &'s mut S, columns: usize) -> Self {
        Observed {
            summary,
            consumer,
            consumer_time: Duration::ZERO,
            row: Vec::with_capacity(columns),
        }
    }
}

impl<F: Formulation + Outputs, S: SampleSink + ?Sized> Sink<F> for Observed<'_, S> {
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        let violation = f
            .outputs_into(t, y, &mut self.row)
            .map_err(|source| SolveError::Formulation { t, source })?;
        self.summary.sample(&self.row, violation);
        let started = Instant::now();
        let result = self.consumer.sample(&Sample {
            t,
            state: y,
            outputs: &self.row,
            constraint_violation: violation,
        });
        self.consumer_time += started.elapsed();
        result
    }

    fn event(
        &mut self,
        _f: &F,
        event: &EventRecord,
        _before: &[f64],
        _after: &[f64],
    ) -> Result<(), SolveError> {
        self.summary.event(event);
        self.consumer.event(event)
    }

    // DENSE-OUTPUT HOOK (for the solvers helper): when `Sink` gains a per-step method with the
    // step's dense output, implement it here and pass it to `SummaryBuilder` (see the marker
    // in `summary.rs`) so that peak forces and penetrations are the true maxima between
    // samples; forward it to the consumer too if `SampleSink` grows the same method.
}
