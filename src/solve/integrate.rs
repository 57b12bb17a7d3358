//! [`integrate`]: a whole run, with samples on a fixed time grid taken from the dense output and
//! events, streamed to a [`Sink`].
//!
//! **Output grid.** Samples are taken at t_k = t0 + k·dt_out, k = 0, 1, …, while
//! t_k ≤ t_end + 1e-9·dt_out, from the dense output — never at solver steps, so their spacing
//! is exact (what spectra and Poincaré maps need) and independent of the tolerances. A grid
//! point within 1e-9·dt_out of t_end is sampled at exactly t_end. The end time is always
//! sampled: if t_end is not on the grid, one more sample at exactly t_end follows the last grid
//! point (dt_out = 0.3 s on a 0.48 s run gives 0, 0.3 and 0.48 s), so only the last interval
//! may be shorter than dt_out.
//!
//! **Order at events.** All samples at or before an event time are sent before the event; a
//! sample exactly at the event time therefore shows the state before the event's change.
//!
//! **Step hook.** Once an accepted step is final (no event can cut it any more: at its end, or
//! at an event that restarted the integrator inside it), [`Sink::on_step`] receives its dense
//! output, after the samples and events inside it.

use super::dense::DenseStep;
use super::error::SolveError;
use super::events::EventRecord;
use super::options::SolverOptions;
use super::stats::SolverStats;
use super::stepper::{Stepper, Stop};
use crate::formulation::Formulation;

/// Receives the output of [`integrate`] as it is produced (so a long run can stream to disk).
///
/// An error returned by a method aborts the run and is returned by [`integrate`] unchanged;
/// sinks report their own failures as [`SolveError::Sink`] with the time of the sample.
pub trait Sink<F: ?Sized> {
    /// A sample of the state y (length n) at time t (s) on the output grid; `f` is the
    /// formulation being integrated (to evaluate outputs at the sample).
    fn sample(&mut self, f: &F, t: f64, y: &[f64]) -> Result<(), SolveError>;

    /// An event, with the states just before and just after
    /// [`Formulation::apply_event`] (equal unless the formulation restarted the integrator).
    /// Default: ignored.
    fn event(
        &mut self,
        _f: &F,
        _event: &EventRecord,
        _y_before: &[f64],
        _y_after: &[f64],
    ) -> Result<(), SolveError> {
        Ok(())
    }

    /// An accepted step is final: `step` gives its time range and its dense output, to look
    /// between the samples (e.g. for the true extremum of a contact force). Called once per
    /// accepted step, including steps cut short at an event that restarted the integrator,
    /// after the samples and events inside the step. Default: ignored.
    fn on_step(&mut self, _step: &mut DenseStep<'_, F>) -> Result<(), SolveError>
    where
        F: Formulation,
    {
        Ok(())
    }
}

/// Integrates `f` from (t0, y0) to t_end with options `opts`, sending samples every `dt_out`
/// seconds and every event to `sink`; returns the cost of the run.
///
/// Errors: the options or arguments are invalid ([`SolveError::InvalidOption`],
/// [`SolveError::StateLength`]), the integration fails (see [`SolveError`]), or the sink fails.
pub fn integrate<F: Formulation>(
    f: &mut F,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    dt_out: f64,
    opts: &SolverOptions,
    sink: &mut impl Sink<F>,
) -> Result<SolverStats, SolveError> {
    if !(dt_out.is_finite() && dt_out > 0.0) {
        return Err(SolveError::invalid(
            "dt_out",
            format!("expected a finite output interval > 0 s, got {dt_out}"),
        ));
    }
    let mut stepper = Stepper::new(f, t0, y0, t_end, opts)?;
    let mut grid = Grid::new(t0, t_end, dt_out);
    let mut out = vec![0.0; stepper.n_states()];
    emit_samples(&mut stepper, &mut grid, &mut out, sink)?;
    loop {
        let stop = stepper.step()?;
        emit_samples(&mut stepper, &mut grid, &mut out, sink)?;
        match stop {
            Stop::Step => {}
            Stop::Event { .. } => {
                if let Some(event) = stepper.last_event().copied() {
                    let (before, after) = stepper.event_states();
                    sink.event(stepper.formulation(), &event, before, after)?;
                }
            }
            Stop::EndReached => {}
        }
        if stepper.take_final_step() {
            sink.on_step(&mut stepper.dense_step())?;
        }
        if stop == Stop::EndReached {
            return Ok(stepper.stats().clone());
        }
    }
}

/// Sends every grid sample up to the stepper's final time.
fn emit_samples<F: Formulation>(
    stepper: &mut Stepper<'_, F>,
    grid: &mut Grid,
    out: &mut [f64],
    sink: &mut impl Sink<F>,
) -> Result<(), SolveError> {
    while let Some(t) = grid.current() {
        if t > stepper.t_reached() {
            break;
        }
        stepper.interpolate(t, out)?;
        sink.sample(stepper.formulation(), t, out)?;
        grid.advance();
    }
    Ok(())
}

/// The output grid t_k = t0 + k·dt, k = 0..=k_last, then t_end if it is not on the grid (see
/// the module documentation).
#[derive(Debug, Clone)]
struct Grid {
    t0: f64,
    t_end: f64,
    dt: f64,
    k: u64,
    k_last: u64,
    /// t_end is not within the slack of the grid point k_last: sample it as index k_last + 1.
    end_extra: bool,
}

impl Grid {
    /// Relative slack (in units of dt) within which a grid point counts as t_end.
    const END_SLACK: f64 = 1e-9;

    fn new(t0: f64, t_end: f64, dt: f64) -> Self {
        // Saturating float-to-int cast: an astronomically fine grid just never ends early.
        let k_last = ((t_end - t0) / dt + Self::END_SLACK).floor().max(0.0) as u64;
        let t_last = t0 + k_last as f64 * dt;
        let end_extra = t_end - t_last > Self::END_SLACK * dt;
        Self {
            t0,
            t_end,
            dt,
            k: 0,
            k_last,
            end_extra,
        }
    }

    /// Time of the next sample, if any is left.
    fn current(&self) -> Option<f64> {
        if self.k > self.k_last {
            return (self.end_extra && self.k == self.k_last + 1).then_some(self.t_end);
        }
        let t = self.t0 + self.k as f64 * self.dt;
        if (t - self.t_end).abs() <= Self::END_SLACK * self.dt || t > self.t_end {
            Some(self.t_end)
        } else {
            Some(t)
        }
    }

    fn advance(&mut self) {
        self.k += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn times(t0: f64, t_end: f64, dt: f64) -> Vec<f64> {
        let mut g = Grid::new(t0, t_end, dt);
        let mut v = Vec::new();
        while let Some(t) = g.current() {
            v.push(t);
            g.advance();
        }
        v
    }

    #[test]
    fn grid_always_ends_at_t_end() {
        assert_eq!(times(0.0, 1.0, 0.25), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        // 0.1·3 = 0.30000000000000004 > 0.3, but within 1e-9·dt: sampled at exactly 0.3.
        assert_eq!(times(0.0, 0.3, 0.1), vec![0.0, 0.1, 0.2, 0.3]);
        // Off the grid: one more, shorter interval to t_end (the end time is always sampled).
        assert_eq!(times(0.0, 1.1, 0.25), vec![0.0, 0.25, 0.5, 0.75, 1.0, 1.1]);
        assert_eq!(times(0.0, 0.48, 0.3), vec![0.0, 0.3, 0.48]);
        assert_eq!(times(0.0, 0.48, 1.0), vec![0.0, 0.48]);
        // t_end 1e-9 s past the grid point 0.1·3 (beyond the slack 1e-9·dt = 1e-10 s): both.
        assert_eq!(
            times(0.0, 0.3 + 1e-9, 0.1),
            vec![0.0, 0.1, 0.2, 0.1 * 3.0, 0.3 + 1e-9]
        );
        assert_eq!(times(2.0, 2.0, 0.1), vec![2.0]);
    }

    #[test]
    fn grid_times_are_not_accumulated() {
        let v = times(0.0, 1000.0, 0.001);
        assert_eq!(v.len(), 1_000_001);
        assert_eq!(v[123_456], 123_456.0 * 0.001);
        assert_eq!(v.last().copied(), Some(1000.0));
    }
}
