//! [`SampleSink`]: where a [`Simulation`](super::Simulation) sends its samples — the state and
//! the evaluated output columns together, so that the outputs are evaluated once per sample
//! for the summary and the consumer (a CSV file, a [`Trajectory`](super::Trajectory), an
//! analysis) alike.

use super::impacts::{ContactProbe, PeakSearch};
use super::summary::SummaryBuilder;
use crate::formulation::{Crossing, Formulation, Outputs, Tolerances};
use crate::solve::{DenseStep, EventRecord, Sink, SolveError};
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
/// sample, updates the summary, locates the contact peaks of every step in contact on its
/// dense output, and forwards samples and events to the consumer.
pub(super) struct Observed<'s, S: SampleSink + ?Sized> {
    pub(super) summary: SummaryBuilder,
    pub(super) consumer: &'s mut S,
    /// Wall time spent in the consumer (s), kept apart from the integration's.
    pub(super) consumer_time: Duration,
    row: Vec<f64>,
    peaks: PeakSearch,
    /// The tolerances (rtol, atol) the method controls, for the constraint check of the samples
    /// ([`Outputs::check_constraints`]).
    tolerances: Tolerances,
}

impl<'s, S: SampleSink + ?Sized> Observed<'s, S> {
    pub(super) fn new(
        summary: SummaryBuilder,
        consumer: &'s mut S,
        columns: usize,
        tolerances: Tolerances,
    ) -> Self {
        Observed {
            summary,
            consumer,
            consumer_time: Duration::ZERO,
            row: Vec::with_capacity(columns),
            peaks: PeakSearch::default(),
            tolerances,
        }
    }
}

impl<F: Formulation + Outputs + ContactProbe, S: SampleSink + ?Sized> Sink<F> for Observed<'_, S> {
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        let violation = f
            .outputs_into(t, y, &mut self.row)
            .map_err(|source| SolveError::Formulation { t, source })?;
        // A sample between step ends is held to the same bound as the step ends.
        f.check_constraints(t, y, self.tolerances)
            .map_err(|source| SolveError::Formulation { t, source })?;
        self.summary.sample_at(t, &self.row, violation);
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
        f: &F,
        event: &EventRecord,
        _before: &[f64],
        after: &[f64],
    ) -> Result<(), SolveError> {
        let impact_velocity = if event.crossing == Crossing::Rising
            && event.index < self.summary.n_clearance_joints()
        {
            // δ̇⁽⁻⁾ as the formulation stored it at the event (in the state after it).
            f.contact_probe(event.index, event.t, after)
                .map_err(|source| SolveError::Formulation { t: event.t, source })?
                .impact_velocity
        } else {
            f64::NAN
        };
        self.summary.event(event, impact_velocity);
        if event.restarted {
            // The state after the event (a new stored impact velocity) starts the next step.
            self.peaks.forget_ends();
        }
        self.consumer.event(event)
    }

    /// The true peaks of every clearance joint in contact during the step (nothing at all
    /// without clearance joints, or while every joint is free).
    fn on_step(&mut self, step: &mut DenseStep<'_, F>) -> Result<(), SolveError> {
        let n = self.summary.n_clearance_joints();
        if n == 0 {
            return Ok(());
        }
        let (a, b) = step.range();
        self.peaks.begin_step();
        for k in 0..n {
            if self.summary.in_contact_during(k, b) {
                let floor = self.summary.contact_peaks_so_far(k, a);
                let peak = self.peaks.step_peak(step, k, floor)?;
                self.summary.step_peak(k, a, b, &peak);
            }
        }
        self.summary.peak_search_interpolations = self.peaks.interpolations;
        self.summary.peak_search_rhs_evals = self.peaks.rhs_evals;
        Ok(())
    }
}
