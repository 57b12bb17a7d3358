//! [`Integrator`]: the one trait every integration method implements, and the types it trades
//! with the driver ([`Stepper`](crate::solve::Stepper)).
//!
//! # Who owns what
//!
//! | the integrator (one method) | the driver ([`Stepper`](crate::solve::Stepper)) |
//! |---|---|
//! | one step attempt from (t, y) with size h: stages or Newton iterations, Jacobians | the current state (t, y) and the state at the start of the last step |
//! | its error estimate, the error test, the next step size (its own controller) | the clamps of h: `t_end`, `h_max`, [`Formulation::max_step`], `fixed_step` |
//! | the dense output of the last accepted step | which part of that step is valid (cut at an event), its exact ends |
//! | its statistics: RHS calls it makes, dense-output calls, Newton iterations and failures, Jacobians, error-test failures | accepted steps, the total of rejections, recovered rejections, events, restarts, the f(t, y) of every (re)start |
//! | (re)initialising its history at a restart | events (detection, location, [`Formulation::apply_event`]), restarts, `max_steps`, `max_wall`, the step floor, the no-progress rule, NaN checks at step ends, sampling |
//!
//! The driver calls, in this order: [`Integrator::restart`] with f(t0, y0) (then
//! [`Integrator::initial_step`] unless the options give the first step), then repeatedly
//! [`Integrator::attempt`] until one is accepted. Between an accepted attempt and the next
//! attempt it may call [`Integrator::interpolate`] (samples, event location, the sinks' step
//! hook) any number of times, and [`Integrator::restart`] after an event changed the state; a
//! restart must not invalidate the dense output of the last accepted step (the driver reads it
//! up to the event time after the restart).
//!
//! # Contract of an attempt
//!
//! * The committed state (the start of the next attempt and the dense output of the last
//!   accepted step) changes only when an attempt returns [`Attempt::Accepted`]. A rejected or
//!   failed attempt may overwrite scratch space (stages, the last dense output) but the next
//!   attempt from the same (t, y) must work.
//! * A right-hand-side failure is returned as `Err(SolveError::Formulation { .. })` as it is;
//!   the driver retries with h/4 when it is recoverable
//!   ([`FormulationError::is_recoverable`](crate::formulation::FormulationError::is_recoverable))
//!   and counts it in [`SolverStats::recovered_rejections`].
//! * With `trial.error_control == false` (fixed-step mode) no error estimate is made and the
//!   attempt is accepted (an implicit method may still reject for Newton non-convergence).
//! * No method panics: an internal inconsistency is a `debug_assert!` plus a safe fallback.
//!
//! # Adding a method
//! Write a type implementing [`Integrator`] for every `F: Formulation`, add a variant to
//! [`Method`] (its name, order, description and whether it is implicit, all in `options.rs`) and
//! one arm in `solve::methods::new_integrator` (private). Events, the driver,
//! [`integrate`](fn@crate::solve::integrate) and the sinks need no change.

use super::error::SolveError;
use super::options::Method;
use super::rk::scaled;
use super::stats::SolverStats;
use crate::formulation::Formulation;

/// Weights of the error norm shared by every method: the tolerances and which state
/// components are error-controlled ([`Formulation::error_controlled`]).
///
/// The norm of an error vector e between states y and y_new is the root mean square over the
/// controlled components only, sqrt(1/m Σ_{i controlled} (e_i/sk_i)²) with
/// sk_i = atol + rtol·max(|y_i|, |y_new_i|) and m the number of controlled components.
/// Bookkeeping components (stored impact velocities, energy integrals) take no part: they
/// neither limit the step nor dilute the norm.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorWeights {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (units of the state components).
    pub atol: f64,
    /// Indices of the error-controlled components, ascending.
    pub controlled: Vec<usize>,
    /// 1 for a controlled component, 0 for a bookkeeping one (length n): the error sums run
    /// over all components times this weight, branch-free and in index order.
    pub(crate) mask: Vec<f64>,
}

impl ErrorWeights {
    /// Weights for `f` with tolerances `rtol`, `atol`.
    pub fn new<F: Formulation + ?Sized>(f: &F, rtol: f64, atol: f64) -> Self {
        let mut mask = vec![true; f.n_states()];
        f.error_controlled(&mut mask);
        if !mask.contains(&true) {
            // Nothing left to control (the generalised formulation of a fully driven linkage
            // integrates only bookkeeping): control everything, or the steps would be unbounded
            // and the states between them mere guesses.
            mask.fill(true);
        }
        Self {
            rtol,
            atol,
            controlled: mask
                .iter()
                .enumerate()
                .filter_map(|(i, &c)| c.then_some(i))
                .collect(),
            mask: mask.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect(),
        }
    }

    /// Number m of controlled components.
    #[must_use]
    pub fn len(&self) -> usize {
        self.controlled.len()
    }

    /// True if no component is controlled (every error norm is then 0).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.controlled.is_empty()
    }

    /// Σ over controlled components of (e_i/sk_i)², e_i = `err(i)`.
    pub fn sum_of_squares(&self, y: &[f64], y_new: &[f64], err: impl Fn(usize) -> f64) -> f64 {
        let (rtol, atol) = (self.rtol, self.atol);
        self.controlled
            .iter()
            .map(|&i| match (y.get(i), y_new.get(i)) {
                (Some(&a), Some(&b)) => {
                    let r = scaled(err(i), a, b, rtol, atol);
                    r * r
                }
                _ => 0.0,
            })
            .sum()
    }

    /// Σ over controlled components of (factor·e_i/sk_i)² for an error vector e (length n).
    /// A bookkeeping component adds exactly +0 (its error is finite whenever the state is), so
    /// the sum equals the one over controlled components only, bit for bit.
    pub(crate) fn sum_of_squares_of(
        &self,
        factor: f64,
        err: &[f64],
        y: &[f64],
        y_new: &[f64],
    ) -> f64 {
        let (rtol, atol) = (self.rtol, self.atol);
        let mut sum = 0.0;
        for (((&w, &e), &a), &b) in self.mask.iter().zip(err).zip(y).zip(y_new) {
            let r = scaled(factor * e, a, b, rtol, atol);
            sum += w * (r * r);
        }
        sum
    }

    /// The RMS norm sqrt(1/m Σ (e_i/sk_i)²) (0 if m = 0).
    pub fn rms(&self, y: &[f64], y_new: &[f64], err: impl Fn(usize) -> f64) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        (self.sum_of_squares(y, y_new, err) / self.len() as f64).sqrt()
    }
}

/// One step attempt asked of an integrator.
#[derive(Debug, Clone, Copy)]
pub struct Trial<'a> {
    /// Start time t (s).
    pub t: f64,
    /// State at t (the driver's current state).
    pub y: &'a [f64],
    /// Step size h (s), already clamped by the driver.
    pub h: f64,
    /// End time of the step (s): t + h, except for the last step of a run where it is exactly
    /// `t_end`.
    pub t_new: f64,
    /// `false` in fixed-step mode: no error estimate, the step is accepted unless the method
    /// cannot compute it at all (Newton failure).
    pub error_control: bool,
}

/// Start of an integration (or a restart) for [`Integrator::initial_step`].
#[derive(Debug, Clone, Copy)]
pub struct Start<'a> {
    /// Time (s).
    pub t: f64,
    /// State at t.
    pub y: &'a [f64],
    /// f(t, y).
    pub f0: &'a [f64],
    /// Largest step the driver will allow (s): min(h_max, max_step, t_end − t).
    pub h_cap: f64,
}

/// Why an attempt was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejection {
    /// The error estimate was above tolerance.
    ErrorTest,
    /// The error estimate was NaN or infinite (a stage blew up).
    NonFinite,
    /// The Newton iteration of an implicit method did not converge.
    NewtonFailure,
}

/// Outcome of [`Integrator::attempt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Attempt {
    /// The step is accepted: [`Integrator::solution`] is the state at `trial.t_new` and the
    /// dense output covers [t, t_new].
    Accepted {
        /// The method's proposal for the next step size (s), before the driver's clamps.
        h_next: f64,
    },
    /// The step is rejected; retry from the same (t, y).
    Rejected {
        /// Step size to retry with (s), before the driver's clamps.
        h_next: f64,
        /// Why.
        cause: Rejection,
    },
}

/// One integration method, stepping a formulation `F` (see the module documentation for the
/// contract between the method and the driver).
///
/// Statistics: a method adds its own costs to the [`SolverStats`] it is handed
/// (`rhs_evals` of the calls it makes, `dense_evals`, `newton_iterations`, `newton_failures`,
/// `jacobian_evals`, `error_test_failures`); the driver counts steps, rejections and events.
pub trait Integrator<F: Formulation + ?Sized> {
    /// Which method this is (name, order and description come from [`Method`]).
    fn method(&self) -> Method;

    /// (Re)starts at (t, y) with f0 = f(t, y) (evaluated and counted by the driver): forgets
    /// the step-size history (and any Jacobian) but keeps the dense output of the last
    /// accepted step.
    fn restart(&mut self, t: f64, y: &[f64], f0: &[f64]);

    /// Proposes the first step size from `start` (s), at most `start.h_cap`. May call f
    /// (counted in `stats.rhs_evals`).
    fn initial_step(
        &mut self,
        f: &F,
        start: &Start<'_>,
        stats: &mut SolverStats,
    ) -> Result<f64, SolveError>;

    /// Attempts one step (see the module documentation for the contract).
    fn attempt(
        &mut self,
        f: &F,
        trial: &Trial<'_>,
        stats: &mut SolverStats,
    ) -> Result<Attempt, SolveError>;

    /// The state at the end of the last attempt (accepted or not; on rejection it may be
    /// meaningless, and the driver only looks for NaN/∞ in it).
    fn solution(&self) -> &[f64];

    /// Evaluates the dense output of the last accepted step at t ∈ [t_start, t_new] of that
    /// step into `out`. May call f (counted in `stats`).
    fn interpolate(
        &mut self,
        f: &F,
        t: f64,
        out: &mut [f64],
        stats: &mut SolverStats,
    ) -> Result<(), SolveError>;

    /// f(t, y) at the start and at the end of the last accepted step, where the method holds
    /// both without a further call (explicit pairs: the first and the FSAL stage; Radau5: f at
    /// the start and at the accepted end state). `None` (the default): whoever needs them
    /// evaluates f. Valid until the next attempt.
    fn step_slopes(&self) -> Option<(&[f64], &[f64])> {
        None
    }

    /// The event functions g(t_new, y_new) at the end of the last accepted step, where the
    /// method evaluated them there itself (the explicit pairs' cut at events). `None` (the
    /// default): the driver evaluates them. Valid until the next attempt or restart.
    fn step_end_events(&self) -> Option<&[f64]> {
        None
    }

    /// Whether the method's own indicator says the step size is currently limited by stability
    /// rather than accuracy (the problem is stiff for this method). Explicit pairs use
    /// Hairer's test; implicit methods keep the default `false`.
    fn stiffness_detected(&self) -> bool {
        false
    }

    /// For a method that integrates the residual form
    /// ([`Formulation::residual_form`]; IDA): the smallest pivot ratio of the constraint solve
    /// over the residuals of the last attempt, which are its stages (the driver hands it to
    /// [`StepHooks::residual_stages`](crate::formulation::StepHooks::residual_stages)). Taken
    /// once per attempt. `None` (the default): the stages are right-hand sides, which the
    /// formulation observes itself.
    fn take_residual_stages(&mut self) -> Option<f64> {
        None
    }
}
