//! [`DenseStep`]: the dense output of one accepted step, as the driver and the sinks see it.

use super::error::SolveError;
use super::integrator::Integrator;
use super::rk::eval_rhs;
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
    /// The end state in `end` is the method's own solution (not corrected by
    /// [`StepHooks::accept_step`](crate::formulation::StepHooks::accept_step)), so the method's
    /// slope there is f at that state.
    pub(crate) end_is_solution: bool,
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

    /// Writes f(t, y) at the start of the valid range into `out` (length n): the method's own
    /// where it holds it ([`Integrator::step_slopes`]), else one RHS call (counted in the run's
    /// statistics). Returns whether that call was made.
    pub fn start_slope(&mut self, out: &mut [f64]) -> Result<bool, SolveError> {
        if self.h_step > 0.0
            && let Some((start, _)) = self.integrator.step_slopes()
            && start.len() == out.len()
        {
            out.copy_from_slice(start);
            return Ok(false);
        }
        eval_rhs(
            self.f,
            self.t_old,
            self.y_old,
            out,
            &mut self.stats.rhs_evals,
        )?;
        Ok(true)
    }

    /// Writes the state at the end of the valid range into `y` and f(t, y) there into `slope`
    /// (each of length n): the method's own slope where the range ends at the method's own
    /// step end ([`Integrator::step_slopes`]), else one RHS call (counted; a step cut at an
    /// event, or an end state corrected by the formulation). Returns whether that call was made.
    pub fn end_state_and_slope(
        &mut self,
        y: &mut [f64],
        slope: &mut [f64],
    ) -> Result<bool, SolveError> {
        let t = self.dense_end;
        self.interpolate(t, y)?;
        if self.end_is_solution
            && self.h_step > 0.0
            && matches!(self.end, Some((t_end, _)) if t_end == t)
            && let Some((_, end)) = self.integrator.step_slopes()
            && end.len() == slope.len()
        {
            slope.copy_from_slice(end);
            return Ok(false);
        }
        eval_rhs(self.f, t, y, slope, &mut self.stats.rhs_evals)?;
        Ok(true)
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
