//! The explicit embedded Runge–Kutta pairs as one [`Integrator`]: [`ExplicitRk`] runs any
//! [`Pair`] (its tableau, error norm and dense output, in `dopri5.rs` and `dop853.rs`) with
//! Hairer's controller (`control.rs`), FSAL, lazy dense output and Hairer's stiffness test.
//!
//! **Stiffness test** \[1, Sec. IV.2; codes `dopri5.f`, `dop853.f`\]: after each accepted step,
//! hλ ≈ h‖k_s − k_{s−1}‖/‖y_s − y_{s−1}‖ from the two stages at c = 1 (their arguments y_{s−1}
//! and y_s = y_new) estimates h times the dominant eigenvalue along the step. Above the
//! boundary of the method's stability region on the negative axis (3.25 for DOPRI5, 6.1 for
//! DOP853) the step is limited by stability rather than accuracy. The test runs on every 16th
//! accepted step, and on every step while stiff steps are being counted; 15 such steps without 6
//! non-stiff ones in between mark the problem as stiff ([`Integrator::stiffness_detected`]);
//! the driver only uses this to word its message when a run stops making progress.
//!
//! # References
//! 1. E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed., Springer,
//!    1996, Sec. IV.2 (automatic stiffness detection).

use std::marker::PhantomData;

use super::control::{ControlParams, Controller, Decision, InitialStep, initial_step};
use super::error::SolveError;
use super::integrator::{Attempt, ErrorWeights, Integrator, Rejection, Start, Trial};
use super::options::Method;
use super::rk::{StepBuffers, first_non_finite};
use super::stats::SolverStats;
use crate::formulation::Formulation;

/// Stiff steps (hλ beyond the stability boundary) after which the problem counts as stiff.
const STIFF_STEPS: u32 = 15;
/// Non-stiff steps that clear the count of stiff ones.
const NON_STIFF_STEPS: u32 = 6;
/// While no stiff step is being counted, the test runs on every this-many accepted steps
/// (Hairer's codes: every 1000th; more often here so that the no-progress rule, which looks at
/// 1000 attempts, already knows).
const STIFF_TEST_EVERY: u64 = 16;

/// What distinguishes one explicit pair from another: tableau, error norm, dense output.
pub(crate) trait Pair {
    /// The method.
    const METHOD: Method;
    /// Stage vectors kept (including the FSAL stage and dense-output stages).
    const STAGES: usize;
    /// Index of the FSAL stage f(t_new, y_new).
    const FSAL: usize;
    /// Index of the stage at c = 1 before the FSAL stage (its argument is left in `y_stage`).
    const LAST_STAGE: usize;
    /// Vectors of the dense output.
    const DENSE_VECTORS: usize;
    /// Controller constants.
    const CONTROL: ControlParams;
    /// Boundary of the stability region on the negative real axis (for the stiffness test).
    const STABILITY_BOUNDARY: f64;

    /// Stages and y_new of a step of size h from (t, y); k\[0\] holds f(t, y). Leaves the
    /// argument of stage [`Pair::LAST_STAGE`] in `y_stage`. The FSAL stage may be left for
    /// [`Pair::after_accept`].
    fn stages<F: Formulation + ?Sized>(
        f: &F,
        trial: &Trial<'_>,
        buf: StepBuffers<'_>,
        evals: &mut u64,
    ) -> Result<(), SolveError>;

    /// The error norm of the step (≤ 1: accept). `scratch` holds two vectors of length n.
    fn error_norm(
        h: f64,
        y: &[f64],
        y_new: &[f64],
        k: &[Vec<f64>],
        weights: &ErrorWeights,
        scratch: (&mut [f64], &mut [f64]),
    ) -> f64;

    /// Work done once a step is accepted (DOP853: the FSAL stage, 1 RHS call).
    fn after_accept<F: Formulation + ?Sized>(
        _f: &F,
        _t_new: f64,
        _y_new: &[f64],
        _k: &mut [Vec<f64>],
        _evals: &mut u64,
    ) -> Result<(), SolveError> {
        Ok(())
    }

    /// Fills the dense-output vectors of an accepted step (DOP853: 3 more RHS calls, counted
    /// in both `stats.rhs_evals` and `stats.dense_evals`).
    fn prepare_dense<F: Formulation + ?Sized>(
        f: &F,
        step: &DenseInput<'_>,
        k: &mut [Vec<f64>],
        dense: &mut [Vec<f64>],
        y_stage: &mut [f64],
        stats: &mut SolverStats,
    ) -> Result<(), SolveError>;

    /// Evaluates the dense output at θ ∈ [0, 1].
    fn eval_dense(theta: f64, y_old: &[f64], dense: &[Vec<f64>], out: &mut [f64]);
}

/// The accepted step whose dense output is prepared.
pub(crate) struct DenseInput<'a> {
    /// Start time (s).
    pub t_old: f64,
    /// Step size (s).
    pub h: f64,
    /// State at the start.
    pub y_old: &'a [f64],
    /// State at the end.
    pub y_new: &'a [f64],
}

/// An explicit embedded pair `P` with error control and dense output.
pub(crate) struct ExplicitRk<P> {
    weights: ErrorWeights,
    /// f at the start of the next attempt (the FSAL stage of the last step, or f0 of a restart).
    f_start: Vec<f64>,
    k: Vec<Vec<f64>>,
    dense: Vec<Vec<f64>>,
    y_new: Vec<f64>,
    y_stage: Vec<f64>,
    scratch: (Vec<f64>, Vec<f64>),
    /// The last accepted step: from (t_old, y_old) with size h.
    t_old: f64,
    h: f64,
    y_old: Vec<f64>,
    dense_ready: bool,
    /// The accepted step's own dense output could not be prepared (see [`ExplicitRk::interpolate`]):
    /// its samples come from the cubic Hermite interpolant instead.
    dense_hermite: bool,
    controller: Controller,
    stiff_steps: u32,
    non_stiff_steps: u32,
    stiff: bool,
    accepted: u64,
    pair: PhantomData<P>,
}

impl<P: Pair> ExplicitRk<P> {
    /// An integrator for n states with error weights `weights` and PI exponent `beta`.
    pub(crate) fn new(n: usize, weights: ErrorWeights, beta: f64) -> Self {
        Self {
            weights,
            f_start: vec![0.0; n],
            k: vec![vec![0.0; n]; P::STAGES],
            dense: vec![vec![0.0; n]; P::DENSE_VECTORS],
            y_new: vec![0.0; n],
            y_stage: vec![0.0; n],
            scratch: (vec![0.0; n], vec![0.0; n]),
            t_old: 0.0,
            h: 0.0,
            y_old: vec![0.0; n],
            dense_ready: true,
            dense_hermite: false,
            controller: Controller::new(P::CONTROL, beta),
            stiff_steps: 0,
            non_stiff_steps: 0,
            stiff: false,
            accepted: 0,
            pair: PhantomData,
        }
    }

    /// Hairer's stiffness test on the accepted step of size h (see the module documentation).
    fn update_stiffness(&mut self, h: f64) {
        self.accepted += 1;
        if self.stiff_steps == 0 && !self.accepted.is_multiple_of(STIFF_TEST_EVERY) {
            return;
        }
        let (Some(k_last), Some(k_fsal)) = (self.k.get(P::LAST_STAGE), self.k.get(P::FSAL)) else {
            return;
        };
        let mut num = 0.0;
        let mut den = 0.0;
        for &i in &self.weights.controlled {
            let dk = k_fsal[i] - k_last[i];
            let dy = self.y_new[i] - self.y_stage[i];
            num += dk * dk;
            den += dy * dy;
        }
        if den <= 0.0 || den.is_nan() {
            return;
        }
        let h_lambda = h * (num / den).sqrt();
        if h_lambda > P::STABILITY_BOUNDARY {
            self.non_stiff_steps = 0;
            self.stiff_steps += 1;
            if self.stiff_steps >= STIFF_STEPS {
                self.stiff = true;
            }
        } else {
            self.non_stiff_steps += 1;
            if self.non_stiff_steps >= NON_STIFF_STEPS {
                self.stiff_steps = 0;
                self.stiff = false;
            }
        }
    }
}

impl<F: Formulation + ?Sized, P: Pair> Integrator<F> for ExplicitRk<P> {
    fn method(&self) -> Method {
        P::METHOD
    }

    fn restart(&mut self, _t: f64, _y: &[f64], f0: &[f64]) {
        self.f_start.copy_from_slice(f0);
        self.controller.reset();
    }

    fn initial_step(
        &mut self,
        f: &F,
        start: &Start<'_>,
        stats: &mut SolverStats,
    ) -> Result<f64, SolveError> {
        let p = InitialStep {
            t0: start.t,
            y0: start.y,
            f0: start.f0,
            h_cap: start.h_cap,
            weights: &self.weights,
            q: P::CONTROL.q,
        };
        let (y1, f1) = (&mut self.y_stage, &mut self.y_new);
        initial_step(f, &p, y1, f1, &mut stats.rhs_evals)
    }

    fn attempt(
        &mut self,
        f: &F,
        trial: &Trial<'_>,
        stats: &mut SolverStats,
    ) -> Result<Attempt, SolveError> {
        let h = trial.h;
        if let Some(k0) = self.k.first_mut() {
            k0.copy_from_slice(&self.f_start);
        }
        let buf = StepBuffers {
            k: &mut self.k,
            y_new: &mut self.y_new,
            y_stage: &mut self.y_stage,
        };
        P::stages(f, trial, buf, &mut stats.rhs_evals)?;
        let h_next = if trial.error_control {
            let (s1, s2) = (&mut self.scratch.0[..], &mut self.scratch.1[..]);
            let err = P::error_norm(h, trial.y, &self.y_new, &self.k, &self.weights, (s1, s2));
            match self.controller.decide(err, h) {
                Decision::Accept { h_next } => h_next,
                Decision::Reject { h_next } => {
                    stats.error_test_failures += 1;
                    let cause = if err.is_finite() {
                        Rejection::ErrorTest
                    } else {
                        Rejection::NonFinite
                    };
                    return Ok(Attempt::Rejected { h_next, cause });
                }
            }
        } else {
            h
        };
        if first_non_finite(&self.y_new).is_some() {
            // The driver reports it; no point evaluating f there.
            return Ok(Attempt::Accepted { h_next });
        }
        P::after_accept(
            f,
            trial.t_new,
            &self.y_new,
            &mut self.k,
            &mut stats.rhs_evals,
        )?;
        self.y_old.copy_from_slice(trial.y);
        self.t_old = trial.t;
        self.h = h;
        self.dense_ready = false;
        if let Some(k_fsal) = self.k.get(P::FSAL) {
            self.f_start.copy_from_slice(k_fsal);
        }
        self.update_stiffness(h);
        Ok(Attempt::Accepted { h_next })
    }

    fn solution(&self) -> &[f64] {
        &self.y_new
    }

    fn interpolate(
        &mut self,
        f: &F,
        t: f64,
        out: &mut [f64],
        stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        if !self.dense_ready {
            let step = DenseInput {
                t_old: self.t_old,
                h: self.h,
                y_old: &self.y_old,
                y_new: &self.y_new,
            };
            // DOP853's extra stages are RHS calls at points of an already accepted step that
            // nothing checked: at a loose tolerance in a stiff contact one can land deep in the
            // bearing wall (a recoverable failure). The step cannot be rejected any more, so that
            // step is interpolated by the cubic Hermite polynomial through its end values and
            // slopes (4th-order local error), instead of stopping the run. Preparing the extra
            // stages before acceptance would avoid it but costs ~35 % more RHS calls on runs that
            // sample rarely (sweeps), so it stays lazy.
            self.dense_hermite = match P::prepare_dense(
                f,
                &step,
                &mut self.k,
                &mut self.dense,
                &mut self.y_stage,
                stats,
            ) {
                Ok(()) => false,
                Err(SolveError::Formulation { source, .. }) if source.is_recoverable() => true,
                Err(e) => return Err(e),
            };
            self.dense_ready = true;
        }
        let theta = if self.h > 0.0 {
            (t - self.t_old) / self.h
        } else {
            0.0
        };
        if self.dense_hermite {
            let (Some(f_old), Some(f_new)) = (self.k.first(), self.k.get(P::FSAL)) else {
                return Ok(());
            };
            hermite(theta, self.h, &self.y_old, &self.y_new, f_old, f_new, out);
        } else {
            P::eval_dense(theta, &self.y_old, &self.dense, out);
        }
        Ok(())
    }

    fn stiffness_detected(&self) -> bool {
        self.stiff
    }

    fn step_slopes(&self) -> Option<(&[f64], &[f64])> {
        // k_0 = f(t, y) and the FSAL stage f(t_new, y_new) of the accepted step; the lazy
        // dense-output stages are stored after them and leave both as they are.
        Some((self.k.first()?, self.k.get(P::FSAL)?))
    }
}

/// The cubic Hermite interpolant at θ ∈ [0, 1] of a step of size h from (y0, f0) to (y1, f1).
fn hermite(theta: f64, h: f64, y0: &[f64], y1: &[f64], f0: &[f64], f1: &[f64], out: &mut [f64]) {
    let t2 = theta * theta;
    let t3 = t2 * theta;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    for (i, o) in out.iter_mut().enumerate() {
        *o = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
    }
}

#[cfg(test)]
mod hermite_tests {
    use super::hermite;

    /// The interpolant is exact for cubics: y = t³ on [1, 3] (h = 2).
    #[test]
    fn hermite_reproduces_a_cubic() {
        let (t0, h) = (1.0_f64, 2.0);
        let y = |t: f64| t.powi(3);
        let dy = |t: f64| 3.0 * t * t;
        for theta in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let mut out = [0.0];
            hermite(
                theta,
                h,
                &[y(t0)],
                &[y(t0 + h)],
                &[dy(t0)],
                &[dy(t0 + h)],
                &mut out,
            );
            let want = y(t0 + theta * h);
            assert!(
                (out[0] - want).abs() < 1e-12 * want.abs(),
                "θ = {theta}: {} vs {want}",
                out[0]
            );
        }
    }
}
