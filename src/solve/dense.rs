//! [`DenseStep`]: the dense output of one accepted step, as the driver and the sinks see it.

use super::error::SolveError;
use super::integrator::Integrator;
use super::stats::SolverStats;
use crate::formulation::Formulation;

/// The dense output of the last accepted step on its valid range (the step, cut at the event
/// time if an event restarted the integrator): what [`Sink::on_step`](crate::solve::Sink::on_step)
/// receives to look between the samples (e.g. for the true peak of a contact force).
pub struct DenseStep<'s, F: Formulation + ?Sized> {
    pub(crate) f: &'s F,
    pub(crate) integrator: &'s mut dyn Integrator<F>,
    pub(crate) stats: &'s mut SolverStats,
    pub(crate) t_old: f64,
    pub(crate) dense_end: f64,
    pub(crate) h_step: f64,
    pub(crate) y_old: &'s [f64],
    /// (t, y) at the step end while y is still the step's end state.
    pub(crate) end: Option<(f64, &'s [f64])>,
}

impl<'s, F: Formulation + ?Sized> DenseStep<'s, F> {
    /// Interval [t_start, t_end] (s) on which [`DenseStep::interpolate`] works.
    #[must_use]
    pub fn range(&self) -> (f64, f64) {
        (self.t_old, self.dense_end)
    }

    /// The formulation being integrated (to evaluate outputs at interpolated states).
    #[must_use]
    pub fn formulation(&self) -> &'s F {
        self.f
    }

    /// Number of states n.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.y_old.len()
    }

    /// Writes the state at time t ∈ [`DenseStep::range`] (within a few ulps) into `out`
    /// (length n). At the exact ends of the step the stored states are returned as they are.
    /// May cost RHS calls the first time a step is interpolated (DOP853: 3), counted in the
    /// run's statistics.
    pub fn interpolate(&mut self, t: f64, out: &mut [f64]) -> Result<(), SolveError> {
        let n = self.y_old.len();
        if out.len() != n {
            return Err(SolveError::StateLength {
                what: "output buffer",
                expected: n,
                got: out.len(),
            });
        }
        let slack = 8.0 * f64::EPSILON * self.t_old.abs().max(self.dense_end.abs());
        if !(t >= self.t_old - slack && t <= self.dense_end + slack) {
            return Err(SolveError::OutsideStep {
                t,
                t_start: self.t_old,
                t_end: self.dense_end,
            });
        }
        if self.h_step == 0.0 || t == self.t_old {
            out.copy_from_slice(self.y_old);
            return Ok(());
        }
        if let Some((t_end, y_end)) = self.end
            && t == t_end
        {
            out.copy_from_slice(y_end);
            return Ok(());
        }
        self.integrator.interpolate(self.f, t, out, self.stats)
    }
}
