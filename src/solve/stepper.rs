//! [`Stepper`]: the driver of an [`Integrator`] — one accepted step (or one event) per call.
//!
//! The method (chosen by [`SolverOptions::method`]) owns stepping, error control and dense
//! output; the driver owns everything around it: the clamps of the step size, events and
//! restarts, the limits (`max_steps`, `max_wall`, the no-progress rule of `progress.rs` — its
//! error completed with the formulation's [`Formulation::diagnose`] at the stall state — the
//! step floor), NaN checks and the formulation's check of every accepted step end
//! ([`StepHooks::accept_step`](crate::formulation::StepHooks::accept_step)) (see [`Integrator`] for
//! the contract).
//!
//! Each call of [`Stepper::step`] says why it stopped ([`Stop`]). After it returns, the
//! trajectory is final up to [`Stepper::t_reached`] and the dense output of the last step can be
//! evaluated anywhere in [`Stepper::dense_range`] with [`Stepper::interpolate`] — which is how
//! [`integrate`](fn@crate::solve::integrate) samples a fixed output grid and how later analysis
//! (Poincaré sections) reads states between steps.
//!
//! **Step size.** At every step start h is clamped to `h_max`, to
//! [`Formulation::max_step`] at (t, y) and to the distance to `t_end`; a step that would leave
//! less than 1 % of itself before `t_end` is stretched to end exactly on `t_end` (as in Hairer's
//! codes), unless that breaks one of the other limits. A step below 16 machine epsilons of
//! max(|t|, |t_end|) is an error ([`SolveError::StepTooSmall`], or [`SolveError::NonFinite`]
//! if the rejections came from NaN/∞). A stage that fails recoverably
//! ([`FormulationError::is_recoverable`](crate::formulation::FormulationError::is_recoverable))
//! is retried with a quarter of the step.
//!
//! **Allocation.** All stage, dense-output and event vectors are allocated by
//! [`Stepper::new`]; stepping, interpolating and locating events allocate nothing.

use super::dense::DenseStep;
use super::error::SolveError;
use super::events::{EventRecord, EventState};
use super::integrator::{Attempt, ErrorWeights, Integrator, Rejection, Start, Trial};
use super::methods::new_integrator;
use super::options::{Method, SolverOptions};
use super::progress::{AttemptAt, Progress};
use super::rk::{eval_rhs, first_non_finite};
use super::stats::SolverStats;
use crate::formulation::{EventResponse, Formulation};

/// Why [`Stepper::step`] returned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// A step was accepted and holds no (further) event: the trajectory is final up to
    /// [`Stepper::t`].
    Step,
    /// An event was located at time `t` for event function `index` and handed to
    /// [`Formulation::apply_event`]; the trajectory is final up to `t`. Details in
    /// [`Stepper::last_event`] and [`Stepper::event_states`]. If the formulation asked for a
    /// restart, [`Stepper::t`] and [`Stepper::y`] are now the event time and the state after the
    /// event; otherwise they remain the end of the step, whose rest is scanned for more events
    /// on the next call.
    Event {
        /// Event time (s), to the event tolerance.
        t: f64,
        /// Index of the event function g_i that changed sign.
        index: usize,
    },
    /// `t_end` is reached: the trajectory is final up to `t_end`. Further calls return
    /// `EndReached` again and do nothing.
    EndReached,
}

/// Where the stepper is between calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Phase {
    /// Next call takes a new step.
    Ready,
    /// An accepted step may hold more events after `ev.t_lo`.
    Scanning,
    /// `t_end` reached.
    Done,
}

/// Adaptive explicit Runge–Kutta integrator of a [`Formulation`] from `t0` to `t_end`.
///
/// ```
/// use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
/// use linkdyn::solve::{SolverOptions, Stepper, Stop};
///
/// struct Decay;
/// impl NoStepHooks for Decay {}
///
/// impl Formulation for Decay {
///     fn n_states(&self) -> usize { 1 }
///     fn initial_state(&self) -> Vec<f64> { vec![1.0] }
///     fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
///         dy[0] = -y[0];
///         Ok(())
///     }
/// }
///
/// let mut f = Decay;
/// let mut stepper = Stepper::new(&mut f, 0.0, &[1.0], 2.0, &SolverOptions::default())?;
/// let mut mid = [0.0];
/// while stepper.step()? != Stop::EndReached {
///     let (a, b) = stepper.dense_range();
///     stepper.interpolate(0.5 * (a + b), &mut mid)?;
///     assert!((mid[0] - (-0.5 * (a + b)).exp()).abs() < 1e-8);
/// }
/// assert!((stepper.y()[0] - (-2f64).exp()).abs() < 1e-9);
/// # Ok::<(), linkdyn::solve::SolveError>(())
/// ```
/// Integrator of a [`Formulation`] from `t0` to `t_end` with the method of the options.
///
/// ```
/// use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
/// use linkdyn::solve::{SolverOptions, Stepper, Stop};
///
/// struct Decay;
/// impl NoStepHooks for Decay {}
///
/// impl Formulation for Decay {
///     fn n_states(&self) -> usize { 1 }
///     fn initial_state(&self) -> Vec<f64> { vec![1.0] }
///     fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
///         dy[0] = -y[0];
///         Ok(())
///     }
/// }
///
/// let mut f = Decay;
/// let mut stepper = Stepper::new(&mut f, 0.0, &[1.0], 2.0, &SolverOptions::default())?;
/// let mut mid = [0.0];
/// while stepper.step()? != Stop::EndReached {
///     let (a, b) = stepper.dense_range();
///     stepper.interpolate(0.5 * (a + b), &mut mid)?;
///     assert!((mid[0] - (-0.5 * (a + b)).exp()).abs() < 1e-8);
/// }
/// assert!((stepper.y()[0] - (-2f64).exp()).abs() < 1e-9);
/// # Ok::<(), linkdyn::solve::SolveError>(())
/// ```
pub struct Stepper<'a, F: Formulation> {
    pub(super) f: &'a mut F,
    pub(super) integrator: Box<dyn Integrator<F> + 'a>,
    pub(super) opts: SolverOptions,
    pub(super) n: usize,
    pub(super) t_end: f64,
    /// Current time and state (start of the next step).
    pub(super) t: f64,
    pub(super) y: Vec<f64>,
    /// f(t, y) at the last (re)start (for the events' look-ahead).
    pub(super) dy: Vec<f64>,
    /// Last accepted step: from (t_old, y_old) with size h_step.
    pub(super) t_old: f64,
    pub(super) h_step: f64,
    pub(super) y_old: Vec<f64>,
    /// The dense output is valid on [t_old, dense_end] (dense_end < t_old + h_step after a
    /// restart cut the step short).
    pub(super) dense_end: f64,
    /// Whether `y` is still the end of the last step (not replaced by an event restart).
    pub(super) y_is_step_end: bool,
    pub(super) h_next: f64,
    pub(super) t_reached: f64,
    pub(super) phase: Phase,
    pub(super) ev: EventState,
    pub(super) stats: SolverStats,
    progress: Progress,
    /// The last accepted step is final (no later event can cut it) ...
    pub(super) step_final: bool,
    /// ... and has been handed to the sink's step hook.
    step_hooked: bool,
    /// The formulation corrected the last step end
    /// ([`StepHooks::accept_step`](crate::formulation::StepHooks::accept_step)): restart the
    /// method from it before the next step.
    pub(super) restart_before_next_step: bool,
}

impl<'a, F: Formulation> Stepper<'a, F> {
    /// Prepares integration of `f` from (t0, y0) to t_end ≥ t0 (forward only): validates the
    /// options, evaluates f(t0, y0), chooses the first step (`h0`, the fixed step, or the
    /// method's own guess, e.g. Hairer's `hinit` with one more RHS call) and evaluates the
    /// event functions at t0.
    pub fn new(
        f: &'a mut F,
        t0: f64,
        y0: &[f64],
        t_end: f64,
        opts: &SolverOptions,
    ) -> Result<Self, SolveError> {
        opts.validate()?;
        if !t0.is_finite() {
            return Err(SolveError::invalid(
                "t0",
                format!("expected a finite time, got {t0}"),
            ));
        }
        if !(t_end.is_finite() && t_end >= t0) {
            return Err(SolveError::invalid(
                "t_end",
                format!(
                    "expected a finite time ≥ t0 = {t0} s (only forward integration is supported), got {t_end}"
                ),
            ));
        }
        let n = f.n_states();
        if y0.len() != n {
            return Err(SolveError::StateLength {
                what: "initial state",
                expected: n,
                got: y0.len(),
            });
        }
        if let Some(component) = first_non_finite(y0) {
            return Err(SolveError::NonFinite { t: t0, component });
        }
        let weights = ErrorWeights::new(&*f, opts.rtol, opts.atol);
        let ne = f.n_events();
        let mut stepper = Stepper {
            integrator: new_integrator::<F>(opts, &*f, weights),
            opts: opts.clone(),
            n,
            t_end,
            t: t0,
            y: y0.to_vec(),
            dy: vec![0.0; n],
            t_old: t0,
            h_step: 0.0,
            y_old: y0.to_vec(),
            dense_end: t0,
            y_is_step_end: true,
            h_next: 0.0,
            t_reached: t0,
            phase: Phase::Ready,
            ev: EventState::new(n, ne, t0),
            stats: SolverStats::default(),
            progress: Progress::new(t0, opts.max_wall),
            step_final: false,
            step_hooked: false,
            restart_before_next_step: false,
            f,
        };
        eval_rhs(
            &*stepper.f,
            t0,
            &stepper.y,
            &mut stepper.dy,
            &mut stepper.stats.rhs_evals,
        )?;
        stepper.integrator.restart(t0, &stepper.y, &stepper.dy);
        stepper.h_next = match (opts.fixed_step, opts.h0) {
            (Some(h), _) | (None, Some(h)) => h,
            (None, None) if t_end > t0 => {
                let h_cap = stepper.step_cap()?.min(t_end - t0);
                let start = Start {
                    t: t0,
                    y: &stepper.y,
                    f0: &stepper.dy,
                    h_cap,
                };
                stepper
                    .integrator
                    .initial_step(&*stepper.f, &start, &mut stepper.stats)?
            }
            (None, None) => 0.0,
        };
        stepper.init_events();
        Ok(stepper)
    }

    /// The method in use.
    #[must_use]
    pub fn method(&self) -> Method {
        self.integrator.method()
    }

    /// min(h_max, max_step(t, y)), checking the formulation's answer.
    fn step_cap(&self) -> Result<f64, SolveError> {
        let value = self.f.max_step(self.t, &self.y);
        if value.is_nan() || value <= 0.0 {
            return Err(SolveError::InvalidMaxStep { t: self.t, value });
        }
        Ok(value.min(self.opts.h_max))
    }

    /// Smallest step size that still moves t: 16 machine epsilons of max(|t|, |t_end|).
    fn h_floor(&self) -> f64 {
        16.0 * f64::EPSILON * self.t.abs().max(self.t_end.abs())
    }

    /// Advances the integration: takes a step, or locates and handles the next event in the
    /// last step. See [`Stop`] for what each answer means.
    pub fn step(&mut self) -> Result<Stop, SolveError> {
        loop {
            match self.phase {
                Phase::Done => return Ok(Stop::EndReached),
                Phase::Scanning => {
                    if let Some(stop) = self.scan_events()? {
                        return Ok(stop);
                    }
                    if self.ev.pending_restart {
                        self.restart()?;
                        self.phase = Phase::Ready;
                        continue;
                    }
                    return Ok(self.finish_step());
                }
                Phase::Ready => {
                    if self.t >= self.t_end {
                        self.phase = Phase::Done;
                        self.t_reached = self.t;
                        return Ok(Stop::EndReached);
                    }
                    if self.restart_before_next_step {
                        self.restart()?;
                    }
                    if self.advance()? {
                        self.begin_scan();
                        self.phase = Phase::Scanning;
                    } else {
                        return Ok(self.finish_step());
                    }
                }
            }
        }
    }

    /// Closes the current step once no event is left in it.
    fn finish_step(&mut self) -> Stop {
        self.finish_events();
        self.t_reached = self.t;
        self.step_final = self.h_step > 0.0;
        if self.t >= self.t_end {
            self.phase = Phase::Done;
            Stop::EndReached
        } else {
            self.phase = Phase::Ready;
            Stop::Step
        }
    }

    /// True once per accepted step, when it has become final (no event can cut it any more):
    /// the moment for [`Sink::on_step`](crate::solve::Sink::on_step).
    pub(crate) fn take_final_step(&mut self) -> bool {
        if self.step_final && !self.step_hooked {
            self.step_hooked = true;
            true
        } else {
            false
        }
    }

    /// Takes one accepted step (retrying rejected attempts). Returns `false` if t was already
    /// within rounding of t_end and was set to t_end without a step.
    fn advance(&mut self) -> Result<bool, SolveError> {
        let t = self.t;
        let floor = self.h_floor();
        let remaining = self.t_end - t;
        if remaining <= floor {
            // A restart left t a few ulps short of t_end: the state there is the end state.
            self.t_old = t;
            self.y_old.copy_from_slice(&self.y);
            self.h_step = 0.0;
            self.t = self.t_end;
            self.dense_end = self.t_end;
            self.y_is_step_end = true;
            self.ev.g_hi.copy_from_slice(&self.ev.g_lo);
            return Ok(false);
        }
        let cap_other = self.step_cap()?;
        let cap = cap_other.min(remaining);
        let mut h = self.opts.fixed_step.unwrap_or(self.h_next).min(cap);
        let mut non_finite: Option<usize> = None;
        // The last recoverable failure of a trial stage (see `FormulationError::is_recoverable`):
        // reported if the step cannot shrink any further.
        let mut recoverable: Option<SolveError> = None;
        let adaptive = self.opts.fixed_step.is_none();
        self.f.begin_step(t, &self.y);
        loop {
            let attempts = self.stats.steps + self.stats.rejected;
            if attempts >= self.opts.max_steps {
                return Err(SolveError::TooManySteps { t, steps: attempts });
            }
            self.progress
                .before_attempt(&AttemptAt {
                    t,
                    t_end: self.t_end,
                    attempts,
                    max_steps: self.opts.max_steps,
                    stiff: self.integrator.stiffness_detected(),
                })
                .map_err(|e| self.with_diagnosis(e))?;
            let last = remaining <= 1.01 * h && remaining <= cap_other;
            if last {
                h = remaining;
            }
            if !(h >= floor && h > 0.0) {
                return Err(match (recoverable, non_finite) {
                    (Some(e), _) => e,
                    (None, Some(component)) => SolveError::NonFinite { t, component },
                    (None, None) => SolveError::StepTooSmall { t, h },
                });
            }
            let t_new = if last { self.t_end } else { t + h };
            let trial = Trial {
                t,
                y: &self.y,
                h,
                t_new,
                error_control: adaptive,
            };
            let attempt = self.integrator.attempt(&*self.f, &trial, &mut self.stats);
            if let Some(ratio) = self.integrator.take_residual_stages() {
                self.f.residual_stages(ratio);
            }
            let h_next = match attempt {
                Ok(Attempt::Accepted { h_next }) => h_next,
                Ok(Attempt::Rejected { h_next, cause }) => {
                    self.stats.rejected += 1;
                    if cause == Rejection::NonFinite {
                        non_finite = first_non_finite(self.integrator.solution()).or(non_finite);
                    }
                    h = h_next.min(cap);
                    continue;
                }
                Err(SolveError::Formulation { t, source })
                    if source.is_recoverable() && adaptive =>
                {
                    self.stats.rejected += 1;
                    self.stats.recovered_rejections += 1;
                    recoverable = Some(SolveError::Formulation { t, source });
                    h = (0.25 * h).min(cap);
                    continue;
                }
                Err(e) => return Err(e),
            };
            let y_new = self.integrator.solution();
            if let Some(component) = first_non_finite(y_new) {
                return Err(SolveError::NonFinite {
                    t: t_new,
                    component,
                });
            }
            std::mem::swap(&mut self.y_old, &mut self.y);
            self.y.copy_from_slice(y_new);
            // What must hold at every accepted step, not only at samples (the DAE's |Φ|), with
            // the tolerances the method controls; the formulation may correct the step end, and
            // the method then restarts from it.
            match self
                .f
                .accept_step(t_new, &mut self.y, self.opts.controlled_tolerances())
            {
                Ok(EventResponse::Continue) => {}
                Ok(EventResponse::Restart) => self.restart_before_next_step = true,
                Err(source) => {
                    std::mem::swap(&mut self.y_old, &mut self.y);
                    return Err(SolveError::Formulation { t: t_new, source });
                }
            }
            self.t_old = t;
            self.t = t_new;
            self.h_step = h;
            self.dense_end = t_new;
            self.y_is_step_end = true;
            self.step_final = false;
            self.step_hooked = false;
            self.stats.record_step(h);
            self.h_next = if adaptive { h_next } else { h };
            return Ok(true);
        }
    }

    /// A no-progress error completed with the formulation's diagnosis at the stall state
    /// (t, y) ([`Formulation::diagnose`]); other errors pass unchanged.
    fn with_diagnosis(&self, e: SolveError) -> SolveError {
        match e {
            SolveError::NoProgress {
                t,
                h,
                advance,
                attempts,
                projected,
                budget,
                stiff,
                implicit,
                diagnosis: None,
            } => SolveError::NoProgress {
                t,
                h,
                advance,
                attempts,
                projected,
                budget,
                stiff,
                implicit,
                diagnosis: self.f.diagnose(self.t, &self.y),
            },
            other => other,
        }
    }

    /// The dense output of the last step with its valid range, as handed to sinks.
    pub(crate) fn dense_step(&mut self) -> DenseStep<'_, F> {
        DenseStep {
            f: &*self.f,
            integrator: &mut *self.integrator,
            stats: &mut self.stats,
            t_old: self.t_old,
            dense_end: self.dense_end,
            h_step: self.h_step,
            y_old: &self.y_old,
            end: self.y_is_step_end.then_some((self.t, &self.y[..])),
            end_is_solution: !self.restart_before_next_step,
        }
    }

    /// Writes the dense-output state at time t, which must lie in [`Stepper::dense_range`]
    /// (within a few ulps), into `out` (length n). DOP853 spends 3 RHS calls the first time a
    /// step is interpolated. Before the first step, and at the exact ends of a step, the stored
    /// states are returned as they are.
    pub fn interpolate(&mut self, t: f64, out: &mut [f64]) -> Result<(), SolveError> {
        self.dense_step().interpolate(t, out)
    }

    /// The method's dense output at t inside the last step, without the range check and the
    /// exact ends (for event location, which stays inside the step).
    pub(super) fn dense_raw(&mut self, t: f64, out: &mut [f64]) -> Result<(), SolveError> {
        if self.h_step == 0.0 {
            out.copy_from_slice(&self.y_old);
            return Ok(());
        }
        self.integrator
            .interpolate(&*self.f, t, out, &mut self.stats)
    }

    /// Number of states n.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n
    }

    /// Current time (s): start of the next step (see [`Stop`] for its value after an event).
    #[must_use]
    pub fn t(&self) -> f64 {
        self.t
    }

    /// State at [`Stepper::t`].
    #[must_use]
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// End time of the run (s).
    #[must_use]
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Time (s) up to which the trajectory is final: the step end after [`Stop::Step`], the
    /// event time after [`Stop::Event`]. Samples at or before it will not change.
    #[must_use]
    pub fn t_reached(&self) -> f64 {
        self.t_reached
    }

    /// Interval [t_start, t_end] (s) on which [`Stepper::interpolate`] works: the last step,
    /// cut at the event time if an event restarted the integrator.
    #[must_use]
    pub fn dense_range(&self) -> (f64, f64) {
        (self.t_old, self.dense_end)
    }

    /// Step size the method proposes for the next step (s), before the clamps.
    #[must_use]
    pub fn h_next(&self) -> f64 {
        self.opts.fixed_step.unwrap_or(self.h_next)
    }

    /// The most recent event, if any.
    #[must_use]
    pub fn last_event(&self) -> Option<&EventRecord> {
        self.ev.last.as_ref()
    }

    /// States at the most recent event: (before, after) [`Formulation::apply_event`]. Equal
    /// unless the formulation asked for a restart (with `Continue`, changes are discarded).
    #[must_use]
    pub fn event_states(&self) -> (&[f64], &[f64]) {
        (&self.ev.y_before, &self.ev.y_after)
    }

    /// Cost counters so far.
    #[must_use]
    pub fn stats(&self) -> &SolverStats {
        &self.stats
    }

    /// The formulation being integrated.
    #[must_use]
    pub fn formulation(&self) -> &F {
        self.f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::FormulationError;
    use crate::formulation::NoStepHooks;

    /// y' = cos t, y(0) = 0: y = sin t.
    struct Sine;
    impl NoStepHooks for Sine {}

    impl Formulation for Sine {
        fn n_states(&self) -> usize {
            1
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![0.0]
        }
        fn rhs(&self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = t.cos();
            Ok(())
        }
    }

    #[test]
    fn reaches_t_end_exactly_and_stays_there() -> Result<(), SolveError> {
        for method in Method::ALL {
            let opts = SolverOptions::default().method(method);
            let mut f = Sine;
            let mut s = Stepper::new(&mut f, 0.0, &[0.0], 3.0, &opts)?;
            let mut guard = 0;
            while s.step()? != Stop::EndReached {
                guard += 1;
                assert!(guard < 10_000, "{method}: runaway");
            }
            assert_eq!(s.t(), 3.0);
            assert_eq!(s.step()?, Stop::EndReached);
            // Default rtol 1e-8: a global error of a few 1e-9 on a quantity of size ~1.
            assert!(
                (s.y()[0] - 3f64.sin()).abs() < 1e-7,
                "{method}: {}",
                s.y()[0]
            );
        }
        Ok(())
    }

    #[test]
    fn interpolation_outside_the_step_is_an_error() -> Result<(), SolveError> {
        let mut f = Sine;
        let mut s = Stepper::new(&mut f, 0.0, &[0.0], 1.0, &SolverOptions::default())?;
        let mut out = [0.0];
        s.interpolate(0.0, &mut out)?;
        assert_eq!(out, [0.0]);
        s.step()?;
        let (a, b) = s.dense_range();
        assert!(matches!(
            s.interpolate(b + 1.0, &mut out),
            Err(SolveError::OutsideStep { .. })
        ));
        assert!(matches!(
            s.interpolate(a, &mut [0.0; 2]),
            Err(SolveError::StateLength { .. })
        ));
        Ok(())
    }

    #[test]
    fn fixed_step_takes_equal_steps() -> Result<(), SolveError> {
        let mut f = Sine;
        let opts = SolverOptions::with_fixed_step(0.1).method(Method::Dopri5);
        let mut s = Stepper::new(&mut f, 0.0, &[0.0], 1.0, &opts)?;
        while s.step()? != Stop::EndReached {}
        assert_eq!(s.stats().steps, 10);
        assert_eq!(s.stats().rejected, 0);
        // f(t0) only (no hinit), then 6 per step.
        assert_eq!(s.stats().rhs_evals, 1 + 6 * 10);
        Ok(())
    }

    #[test]
    fn rejects_bad_arguments() {
        let mut f = Sine;
        let opts = SolverOptions::default();
        assert!(matches!(
            Stepper::new(&mut f, 0.0, &[0.0, 1.0], 1.0, &opts),
            Err(SolveError::StateLength {
                expected: 1,
                got: 2,
                ..
            })
        ));
        assert!(matches!(
            Stepper::new(&mut f, 1.0, &[0.0], 0.0, &opts),
            Err(SolveError::InvalidOption {
                option: "t_end",
                ..
            })
        ));
        assert!(matches!(
            Stepper::new(&mut f, 0.0, &[f64::NAN], 1.0, &opts),
            Err(SolveError::NonFinite { component: 0, .. })
        ));
    }
}
