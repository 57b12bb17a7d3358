//! Radau IIA of order 5 (3 stages), the implicit integrator for stiff contact phases, after
//! Hairer & Wanner's code RADAU5 \[1, Sec. IV.8\].
//!
//! **Method.** The collocation method with nodes c = ((4 − √6)/10, (4 + √6)/10, 1) solves for
//! the stage increments Z_i = Y_i − y_n
//!
//! Z = h (A ⊗ I) F(y_n + Z),  y_{n+1} = y_n + Z₃  (stiffly accurate, L-stable, order 5).
//!
//! **Newton.** Simplified Newton iterations with the Jacobian J at (t_n, y_n) and the
//! transformation W = (T⁻¹ ⊗ I) Z that splits the 3n×3n system into one real n×n system with
//! γ̂/h·I − J and one complex n×n system with (α̂ + iβ̂)/h·I − J ([`tableau`], [`linalg`]).
//! Starting values come from the collocation polynomial of the previous step (zero on the
//! first step and after a restart). The iteration stops when κ·‖ΔW‖ ≤ `newton_tol`, with
//! κ = θ/(1 − θ) and the contraction rate θ = ‖ΔW_k‖/‖ΔW_{k−1}‖ (geometric mean of the last
//! two ratios); it is abandoned (h halved) if θ ≥ 0.99 or `max_newton_iter` is used up, and
//! the step is restarted smaller (h·0.8·q^{−1/(4+k_left)}) if the predicted final error
//! θ^{k_left}/(1 − θ)·‖ΔW‖ exceeds the tolerance \[1, eq. (8.26)–(8.29)\].
//!
//! **Error estimate** \[1, eq. (8.19)–(8.20)\]: err = (I − hγ₀J)⁻¹ [γ₀h f(t_n, y_n) +
//! Σ e_i Z_i], computed as (γ̂/h·I − J)⁻¹ [f(t_n, y_n) + Σ (e_i/h) Z_i] with the LU of the real
//! system. On the first step and after a rejection, if err ≥ 1, the filter is applied once
//! more, to f(t_n, y_n + err) + Σ (e_i/h) Z_i (one extra RHS call), which removes the
//! large-but-harmless estimates of very stiff components.
//!
//! **Step size.** h_new = h / clamp(err^{1/4}/fac, 1/8, 5) with fac = min(safety,
//! safety(1 + 2·nit)/(newt + 2·nit)), and after an accepted step Gustafsson's predictive
//! controller (h_new may only shrink further):
//! h_new ← min(h_new, safety·h·(h_acc/h_prev)·(err_prev/err²)^{1/4}) \[1, eq. (8.25)\].
//! If θ ≤ `theta_jac` and h_new/h ∈ `keep_h_range`, h is kept and the LU factors reused;
//! the Jacobian is re-evaluated after an accepted step only if θ > `theta_jac`, and after a
//! rejected step only if it was not already evaluated at the current point.
//!
//! **Dense output** (order 3, valid on the last step): the collocation polynomial through
//! (t_n, y_n), (t_n + c_i h, y_n + Z_i), written in Newton form around t_{n+1}.
//!
//! **Failures.** A recoverable RHS failure ([`FormulationError::is_recoverable`], a trial stage
//! that overshoots into a contact) rejects the attempt and retries with h/4; a singular
//! iteration matrix or a failed Newton iteration retries with h/2. The run stops with
//! [`SolveError::StepTooSmall`] (or the last recoverable error) when h falls below
//! 16 ulps of t.
//!
//! **Tolerances** (see [`Radau5Settings::hairer_tolerances`]): by default the code
//! works with rtol' = 0.1·rtol^{2/3}, as RADAU5 does; the error scale of component i is
//! atol' + rtol'·|y_i| at the start of the step, and components masked out by
//! [`Radau5Settings::error_mask`] are left out of the error and Newton norms.
//!
//! **Layout.** [`Radau5Core`] (`core.rs`) is the method: one attempt from a state the caller
//! owns, as the integrator trait of the driver wants it. [`Radau5`] is a small stand-alone
//! driver around it (clamps, recoverable retries, counters) without event location.
//!
//! **Allocation.** All buffers are allocated by [`Radau5::new`]; stepping allocates nothing.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
//!    Differential-Algebraic Problems*, 2nd ed., Springer, 1996, Sec. IV.8; Fortran code
//!    `radau5.f` (version of 1996/2002).
//! 2. K. Gustafsson, "Control-theoretic techniques for stepsize selection in implicit
//!    Runge–Kutta methods", *ACM Transactions on Mathematical Software* 20(4), 496–517, 1994.

mod adapter;
mod core;
mod linalg;
mod settings;
mod tableau;

pub use self::core::{Outcome, Radau5Core, Rejection};
pub use adapter::Radau5Method;
pub use settings::{Radau5Settings, Radau5Stats};

use crate::formulation::Formulation;
use crate::solve::{SolveError, SolverOptions};

/// A stand-alone Radau IIA (order 5) run from t0 to t_end (forward only), without events.
///
/// It does not hold the formulation: every call that evaluates the equations takes it, so
/// that a caller may change it between steps (then call [`Radau5::restart`]).
///
/// ```
/// use linkdyn::formulation::{Formulation, FormulationError};
/// use linkdyn::solve::SolverOptions;
/// use linkdyn::solve::radau5::{Radau5, Radau5Settings};
///
/// /// y' = −1000 (y − cos t): stiff, y follows cos t closely.
/// struct Stiff;
/// impl Formulation for Stiff {
///     fn n_states(&self) -> usize { 1 }
///     fn initial_state(&self) -> Vec<f64> { vec![0.0] }
///     fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
///         dy[0] = -1000.0 * (y[0] - t.cos());
///         Ok(())
///     }
/// }
///
/// let opts = SolverOptions::default().rtol(1e-8).atol(1e-10).build()?;
/// let mut r = Radau5::new(&Stiff, 0.0, &[0.0], 2.0, &opts, &Radau5Settings::default())?;
/// r.run_to_end(&Stiff)?;
/// // y → cos t + sin t / 1000 + O(1e-6) after the transient.
/// assert!((r.y()[0] - (2f64.cos() + 2f64.sin() / 1000.0)).abs() < 1e-5);
/// assert!(r.stats().steps < 200, "stiff: {} steps", r.stats().steps);
/// # Ok::<(), linkdyn::solve::SolveError>(())
/// ```
pub struct Radau5 {
    core: Radau5Core,
    opts: SolverOptions,
    n: usize,
    t_end: f64,
    /// Current time and state.
    t: f64,
    y: Vec<f64>,
    /// f(t, y) at a restart.
    f0: Vec<f64>,
    /// The dense output is valid on [t_old, dense_end] (cut at a restart).
    t_old: f64,
    dense_end: f64,
    h_next: f64,
    stats: Radau5Stats,
}

impl Radau5 {
    /// Prepares integration of `f` from (t0, y0) to t_end ≥ t0: validates the options and
    /// settings and evaluates f(t0, y0) (one RHS call). Of `opts`, `rtol`, `atol`, `h0`
    /// (default 10⁻⁶ s, as RADAU5), `h_max`, `max_steps` and `fixed_step` are used; `method`,
    /// `beta` and `event_tol` are not.
    ///
    /// With `fixed_step`, no error estimate is made and `rtol`, `atol` are ignored: Newton is
    /// iterated to ~10⁻¹⁵ relative (up to 3·`max_newton_iter` iterations); the step is still
    /// halved if Newton fails.
    pub fn new<F: Formulation + ?Sized>(
        f: &F,
        t0: f64,
        y0: &[f64],
        t_end: f64,
        opts: &SolverOptions,
        settings: &Radau5Settings,
    ) -> Result<Self, SolveError> {
        opts.validate()?;
        let n = f.n_states();
        settings.validate(n)?;
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
        if y0.len() != n {
            return Err(SolveError::StateLength {
                what: "initial state",
                expected: n,
                got: y0.len(),
            });
        }
        let mut r = Radau5 {
            core: Radau5Core::new(n, opts.rtol, opts.atol, opts.h_max, settings),
            opts: opts.clone(),
            n,
            t_end,
            t: t0,
            y: vec![0.0; n],
            f0: vec![0.0; n],
            t_old: t0,
            dense_end: t0,
            h_next: opts.fixed_step.or(opts.h0).unwrap_or(1e-6),
            stats: Radau5Stats::default(),
        };
        r.restart(f, t0, y0)?;
        Ok(r)
    }

    /// Restarts at (t, y) after a caller changed the state or the equations: f(t, y) is
    /// evaluated (one RHS call), the Jacobian is marked stale, the Newton iteration starts from
    /// zero, and the dense output is cut at t. The proposed step size is kept.
    pub fn restart<F: Formulation + ?Sized>(
        &mut self,
        f: &F,
        t: f64,
        y: &[f64],
    ) -> Result<(), SolveError> {
        if y.len() != self.n {
            return Err(SolveError::StateLength {
                what: "restart state",
                expected: self.n,
                got: y.len(),
            });
        }
        if let Some(component) = y.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite { t, component });
        }
        self.t = t;
        self.y.copy_from_slice(y);
        self.stats.rhs_evals += 1;
        f.rhs(t, y, &mut self.f0)
            .map_err(|source| SolveError::Formulation { t, source })?;
        self.core.restart(&self.f0);
        self.dense_end = self.dense_end.min(t);
        Ok(())
    }

    /// Takes steps until t_end.
    pub fn run_to_end<F: Formulation + ?Sized>(&mut self, f: &F) -> Result<(), SolveError> {
        while self.step(f)? {}
        Ok(())
    }

    /// Takes one accepted step (retrying rejected attempts with smaller steps). Returns
    /// `Ok(false)` without doing anything if t_end is already reached.
    pub fn step<F: Formulation + ?Sized>(&mut self, f: &F) -> Result<bool, SolveError> {
        let t = self.t;
        if t >= self.t_end {
            return Ok(false);
        }
        let floor = 16.0 * f64::EPSILON * t.abs().max(self.t_end.abs());
        let remaining = self.t_end - t;
        if remaining <= floor {
            // A restart left t a few ulps short of t_end: the state there is the end state.
            self.t = self.t_end;
            return Ok(true);
        }
        let cap = {
            let value = f.max_step(t, &self.y);
            if value.is_nan() || value <= 0.0 {
                return Err(SolveError::InvalidMaxStep { t, value });
            }
            value.min(self.opts.h_max)
        };
        let error_control = self.opts.fixed_step.is_none();
        let mut recoverable: Option<SolveError> = None;
        loop {
            let attempts = self.stats.steps + self.stats.rejected;
            if attempts >= self.opts.max_steps {
                return Err(SolveError::TooManySteps { t, steps: attempts });
            }
            let mut h = self.h_next.min(cap);
            let last = remaining <= 1.01 * h && remaining <= cap;
            if last {
                h = remaining;
            }
            if !(h >= floor && h > 0.0) {
                return Err(recoverable.unwrap_or(SolveError::StepTooSmall { t, h }));
            }
            let t_new = if last { self.t_end } else { t + h };
            let outcome =
                self.core
                    .attempt(f, (t, &self.y), (h, t_new), error_control, &mut self.stats);
            match outcome {
                Ok(Outcome::Accepted { h_next }) => {
                    if let Some(component) =
                        self.core.solution().iter().position(|v| !v.is_finite())
                    {
                        return Err(SolveError::NonFinite {
                            t: t_new,
                            component,
                        });
                    }
                    self.y.copy_from_slice(self.core.solution());
                    self.t_old = t;
                    self.t = t_new;
                    self.dense_end = t_new;
                    self.stats.record_step(h);
                    self.h_next = self.opts.fixed_step.unwrap_or(h_next);
                    return Ok(true);
                }
                Ok(Outcome::Rejected { h_next, .. }) => {
                    self.stats.rejected += 1;
                    self.h_next = h_next;
                }
                Err(SolveError::Formulation { t: te, source })
                    if source.is_recoverable() && error_control =>
                {
                    self.stats.rejected += 1;
                    self.stats.recovered_rejections += 1;
                    self.h_next = 0.25 * h;
                    recoverable = Some(SolveError::Formulation { t: te, source });
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Writes the dense-output state at time t ∈ [`Radau5::dense_range`] (a few ulps of slack)
    /// into `out` (length n): the cubic collocation polynomial of the last step.
    pub fn interpolate(&self, t: f64, out: &mut [f64]) -> Result<(), SolveError> {
        if out.len() != self.n {
            return Err(SolveError::StateLength {
                what: "output buffer",
                expected: self.n,
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
        if self.stats.steps == 0 {
            out.copy_from_slice(&self.y);
            return Ok(());
        }
        self.core.interpolate(t, out);
        Ok(())
    }

    /// Number of states n.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n
    }

    /// Current time (s).
    #[must_use]
    pub fn t(&self) -> f64 {
        self.t
    }

    /// State at [`Radau5::t`].
    #[must_use]
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// End time of the run (s).
    #[must_use]
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Interval on which [`Radau5::interpolate`] works: the last accepted step, cut at the
    /// time of a restart.
    #[must_use]
    pub fn dense_range(&self) -> (f64, f64) {
        (self.t_old, self.dense_end)
    }

    /// Step size proposed for the next attempt (s), before the clamps.
    #[must_use]
    pub fn h_next(&self) -> f64 {
        self.h_next
    }

    /// Cost counters so far.
    #[must_use]
    pub fn stats(&self) -> &Radau5Stats {
        &self.stats
    }
}
