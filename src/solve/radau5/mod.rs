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
//! **Allocation.** All buffers are allocated by [`Radau5::new`]; stepping allocates nothing.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
//!    Differential-Algebraic Problems*, 2nd ed., Springer, 1996, Sec. IV.8; Fortran code
//!    `radau5.f` (version of 1996/2002).
//! 2. K. Gustafsson, "Control-theoretic techniques for stepsize selection in implicit
//!    Runge–Kutta methods", *ACM Transactions on Mathematical Software* 20(4), 496–517, 1994.

mod linalg;
mod settings;
mod step;
mod tableau;

pub use settings::{Radau5Settings, Radau5Stats};

use crate::formulation::{Formulation, FormulationError};
use crate::solve::{SolveError, SolverOptions};
use linalg::{ComplexLu, RealLu};
use tableau::{C1M1, C2M1, Eigen};

/// Unit roundoff as RADAU5 uses it (`UROUND`).
const UROUND: f64 = 1e-16;

/// The Radau IIA (order 5) integrator of one run from t0 to t_end (forward only).
///
/// It does not hold the formulation: every call that evaluates the equations takes it, so
/// that an event handler may change it between steps (then call [`Radau5::restart`]).
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
    n: usize,
    opts: SolverOptions,
    settings: Radau5Settings,
    /// Tolerances in use (after Hairer's transform) and the Newton stopping tolerance.
    rtol: f64,
    atol: f64,
    newton_tol: f64,
    eig: Eigen,
    t_end: f64,
    /// Current time, state and f(t, y).
    t: f64,
    y: Vec<f64>,
    f0: Vec<f64>,
    /// Error scale atol' + rtol'·|y_i| at the current state.
    scal: Vec<f64>,
    /// Error-controlled components.
    controlled: Vec<bool>,
    n_controlled: usize,
    /// Jacobian (row-major), whether it was evaluated at the current (t, y), whether the next
    /// attempt must evaluate it.
    jac: Vec<f64>,
    jac_current: bool,
    need_jac: bool,
    jac_work: Vec<f64>,
    e1: RealLu,
    e2: ComplexLu,
    /// Step size of the LU factors in `e1`, `e2` (NaN: none valid).
    lu_h: f64,
    /// Stage increments Z_i, transformed W_i, stage values / Newton corrections.
    z: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fs: [Vec<f64>; 3],
    y_stage: Vec<f64>,
    err_vec: Vec<f64>,
    err_rhs: Vec<f64>,
    /// Last accepted step: [t_old, t_old + h_old], end state y_new, Newton-form coefficients
    /// of the collocation polynomial; the dense output is valid on [t_old, dense_end].
    t_old: f64,
    h_old: f64,
    dense_end: f64,
    y_old: Vec<f64>,
    y_new: Vec<f64>,
    cont: [Vec<f64>; 3],
    /// Step-size control state.
    h_next: f64,
    first: bool,
    reject: bool,
    faccon: f64,
    theta: f64,
    h_acc: f64,
    err_acc: f64,
    accepted_since_start: u64,
    stats: Radau5Stats,
}

impl Radau5 {
    /// Prepares integration of `f` from (t0, y0) to t_end ≥ t0: validates the options and
    /// settings and evaluates f(t0, y0) (one RHS call). Of `opts`, `rtol`, `atol`, `h0`
    /// (default 10⁻⁶ s, as RADAU5), `h_max`, `max_steps` and `fixed_step` are used; `method`,
    /// `beta` and `event_tol` are not.
    ///
    /// With `fixed_step`, no error estimate is made; the step is still halved if Newton fails.
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
        if let Some(component) = y0.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite { t: t0, component });
        }
        let (rtol, atol) = if settings.hairer_tolerances {
            let r = 0.1 * opts.rtol.powf(2.0 / 3.0);
            (r, opts.atol * r / opts.rtol)
        } else {
            (opts.rtol, opts.atol)
        };
        let newton_tol = settings
            .newton_tol
            .unwrap_or_else(|| (10.0 * UROUND / rtol).max(0.03f64.min(rtol.sqrt())));
        let controlled = settings.error_mask.clone().unwrap_or_else(|| vec![true; n]);
        let n_controlled = controlled.iter().filter(|&&c| c).count();
        let h0 = opts.fixed_step.or(opts.h0).unwrap_or(1e-6);
        let vec3 = || [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut r = Radau5 {
            n,
            opts: opts.clone(),
            settings: settings.clone(),
            rtol,
            atol,
            newton_tol,
            eig: Eigen::new(),
            t_end,
            t: t0,
            y: y0.to_vec(),
            f0: vec![0.0; n],
            scal: vec![0.0; n],
            controlled,
            n_controlled,
            jac: vec![0.0; n * n],
            jac_current: false,
            need_jac: true,
            jac_work: vec![0.0; 2 * n],
            e1: RealLu::new(n),
            e2: ComplexLu::new(n),
            lu_h: f64::NAN,
            z: vec3(),
            w: vec3(),
            fs: vec3(),
            y_stage: vec![0.0; n],
            err_vec: vec![0.0; n],
            err_rhs: vec![0.0; n],
            t_old: t0,
            h_old: 0.0,
            dense_end: t0,
            y_old: y0.to_vec(),
            y_new: y0.to_vec(),
            cont: vec3(),
            h_next: h0,
            first: true,
            reject: false,
            faccon: 1.0,
            theta: settings.theta_jac.abs(),
            h_acc: 0.0,
            err_acc: 0.0,
            accepted_since_start: 0,
            stats: Radau5Stats::default(),
        };
        r.eval_f0(f)?;
        r.update_scale();
        Ok(r)
    }

    /// f(t, y) into `f0`, counted.
    fn eval_f0<F: Formulation + ?Sized>(&mut self, f: &F) -> Result<(), SolveError> {
        self.stats.rhs_evals += 1;
        f.rhs(self.t, &self.y, &mut self.f0)
            .map_err(|source| SolveError::Formulation { t: self.t, source })
    }

    /// Error scale atol' + rtol'·|y_i| at the current state.
    fn update_scale(&mut self) {
        for (s, &y) in self.scal.iter_mut().zip(&self.y) {
            *s = self.atol + self.rtol * y.abs();
        }
    }

    /// Restarts at (t, y) after an event changed the state or the equations: f(t, y) is
    /// re-evaluated (one RHS call), the Jacobian is marked stale, the next Newton iteration
    /// starts from zero, and the dense output is cut at t. The proposed step size is kept.
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
        self.eval_f0(f)?;
        self.update_scale();
        self.dense_end = self.dense_end.min(t);
        self.jac_current = false;
        self.need_jac = true;
        self.first = true;
        self.reject = false;
        self.accepted_since_start = 0;
        Ok(())
    }

    /// Takes steps until t_end.
    pub fn run_to_end<F: Formulation + ?Sized>(&mut self, f: &F) -> Result<(), SolveError> {
        while self.step(f)? {}
        Ok(())
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
        if self.h_old == 0.0 {
            out.copy_from_slice(&self.y_old);
            return Ok(());
        }
        let s = (t - (self.t_old + self.h_old)) / self.h_old;
        let [c1, c2, c3] = &self.cont;
        for i in 0..self.n {
            out[i] = self.y_new[i] + s * (c1[i] + (s - C2M1) * (c2[i] + (s - C1M1) * c3[i]));
        }
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

    /// f(t, y) at [`Radau5::t`].
    #[must_use]
    pub fn dy(&self) -> &[f64] {
        &self.f0
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

    /// Root-mean-square of v_i / scal_i over the error-controlled components.
    fn scaled_rms(&self, v: &[f64]) -> f64 {
        rms(v, &self.scal, &self.controlled, self.n_controlled)
    }
}

/// √(Σ_{i controlled} (v_i/scal_i)² / n_controlled); a zero scale counts a zero entry as 0 and
/// any other as infinitely large.
fn rms(v: &[f64], scal: &[f64], controlled: &[bool], n_controlled: usize) -> f64 {
    let mut sum = 0.0;
    for ((&x, &s), &c) in v.iter().zip(scal).zip(controlled) {
        if c {
            let q = if s > 0.0 {
                x / s
            } else if x == 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
            sum += q * q;
        }
    }
    (sum / n_controlled.max(1) as f64).sqrt()
}

/// Whether `e` is a recoverable formulation failure (a smaller step may avoid it).
fn is_recoverable(e: &SolveError) -> bool {
    matches!(e, SolveError::Formulation { source, .. } if FormulationError::is_recoverable(source))
}
