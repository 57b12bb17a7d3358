//! Claim: a failing run stops with an error that says when and why — the sink's own error, the
//! formulation's error wrapped with the time of the failed call, NaN in the state, an
//! unreachable tolerance, or too many steps.

mod common;

use common::ode::{OdeRecorder, Oscillator};
use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, Sink, SolveError, SolverOptions, integrate};
use std::error::Error as _;

/// Fails when asked for a sample at or after `fail_at`.
struct FailingSink {
    fail_at: f64,
    received: usize,
}

impl<F> Sink<F> for FailingSink {
    fn sample(&mut self, _f: &F, t: f64, _y: &[f64]) -> Result<(), SolveError> {
        if t >= self.fail_at {
            return Err(SolveError::Sink {
                t,
                reason: "disk full".into(),
            });
        }
        self.received += 1;
        Ok(())
    }
}

#[test]
fn sink_error_aborts_the_run() {
    for method in Method::ALL {
        let mut sink = FailingSink {
            fail_at: 0.5,
            received: 0,
        };
        let opts = SolverOptions::default().method(method);
        let r = integrate(
            &mut Oscillator { omega: 1.0 },
            0.0,
            &[1.0, 0.0],
            10.0,
            0.1,
            &opts,
            &mut sink,
        );
        match r {
            Err(SolveError::Sink { t, reason }) => {
                assert!(
                    (t - 0.5).abs() < 1e-12 && reason == "disk full",
                    "{method}: {t}, {reason}"
                );
            }
            other => panic!("{method}: expected a sink error, got {other:?}"),
        }
        assert_eq!(sink.received, 5, "{method}: samples 0.0..0.4 only");
    }
}

/// y' = 1 whose right-hand side fails from t = 1 on (a singular position, say).
struct BreaksAtOne;

impl NoStepHooks for BreaksAtOne {}

impl Formulation for BreaksAtOne {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        if t >= 1.0 {
            return Err(FormulationError::SingularConstraints {
                t,
                constraint: "crank revolute".into(),
            });
        }
        dy[0] = 1.0;
        Ok(())
    }
}

#[test]
fn rhs_error_is_wrapped_with_its_time() {
    for method in Method::ALL {
        // h_max 0.1: the failing call lies within one step of t = 1.
        let opts = SolverOptions::default().method(method).h_max(0.1);
        let r = integrate(
            &mut BreaksAtOne,
            0.0,
            &[0.0],
            2.0,
            0.5,
            &opts,
            &mut OdeRecorder::default(),
        );
        match r {
            Err(err @ SolveError::Formulation { .. }) => {
                let SolveError::Formulation { t, .. } = err else {
                    unreachable!()
                };
                assert!((1.0..1.1).contains(&t), "{method}: failed at t = {t}");
                let msg = err.to_string();
                assert!(
                    msg.contains(&format!("{t:.9}")),
                    "{method}: message {msg:?} lacks the time"
                );
                let source = err.source().map(ToString::to_string).unwrap_or_default();
                assert!(
                    source.contains("crank revolute"),
                    "{method}: source {source:?}"
                );
            }
            other => panic!("{method}: expected a formulation error, got {other:?}"),
        }
    }
}

/// y' = y² from y(0) = 1: y = 1/(1 − t) blows up at t = 1.
struct BlowUp;

impl NoStepHooks for BlowUp {}

impl Formulation for BlowUp {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[0] * y[0];
        Ok(())
    }
}

#[test]
fn blow_up_stops_at_the_singularity() {
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        let r = integrate(
            &mut BlowUp,
            0.0,
            &[1.0],
            2.0,
            0.5,
            &opts,
            &mut OdeRecorder::default(),
        );
        match r {
            Err(SolveError::StepTooSmall { t, .. }) | Err(SolveError::NonFinite { t, .. }) => {
                // The discrete solution stays finite a little past the exact singularity.
                assert!((0.99..=1.01).contains(&t), "{method}: stopped at t = {t}");
            }
            other => panic!("{method}: expected a step-size or NaN error, got {other:?}"),
        }
    }
}

/// y' = NaN from t = 0.5 on (a broken force law).
struct NanAfterHalf;

impl NoStepHooks for NanAfterHalf {}

impl Formulation for NanAfterHalf {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 1.0;
        dy[1] = if t > 0.5 { f64::NAN } else { 1.0 };
        Ok(())
    }
}

#[test]
fn nan_in_the_state_is_reported_with_time_and_component() {
    for method in Method::ALL {
        for opts in [
            SolverOptions::default().method(method),
            SolverOptions::with_fixed_step(0.1).method(method),
        ] {
            let r = integrate(
                &mut NanAfterHalf,
                0.0,
                &[0.0, 0.0],
                1.0,
                0.5,
                &opts,
                &mut OdeRecorder::default(),
            );
            match r {
                Err(SolveError::NonFinite { t, component }) => {
                    assert_eq!(component, 1, "{method}");
                    // Adaptive: rejections shrink h until the step start (just before 0.5) is
                    // reported; fixed step: the first step end after 0.5.
                    assert!((0.49..=0.6 + 1e-12).contains(&t), "{method}: t = {t}");
                }
                other => panic!("{method}: expected NonFinite, got {other:?}"),
            }
        }
    }
}

#[test]
fn too_many_steps_says_where_it_stopped() {
    let opts = SolverOptions::default().max_steps(5).h0(0.01).h_max(0.01);
    let r = integrate(
        &mut Oscillator { omega: 1.0 },
        0.0,
        &[1.0, 0.0],
        1.0,
        0.5,
        &opts,
        &mut OdeRecorder::default(),
    );
    match r {
        Err(SolveError::TooManySteps { t, steps }) => {
            assert_eq!(steps, 5);
            assert!((t - 0.05).abs() < 1e-12, "stopped at t = {t}");
        }
        other => panic!("expected TooManySteps, got {other:?}"),
    }
}

#[test]
fn bad_arguments_are_rejected_before_any_work() {
    let opts = SolverOptions::default();
    let mut rec = OdeRecorder::default();
    let r = integrate(
        &mut Oscillator { omega: 1.0 },
        0.0,
        &[1.0, 0.0],
        1.0,
        0.0,
        &opts,
        &mut rec,
    );
    assert!(
        matches!(
            r,
            Err(SolveError::InvalidOption {
                option: "dt_out",
                ..
            })
        ),
        "{r:?}"
    );
    let r = integrate(
        &mut Oscillator { omega: 1.0 },
        0.0,
        &[1.0],
        1.0,
        0.1,
        &opts,
        &mut rec,
    );
    assert!(
        matches!(
            r,
            Err(SolveError::StateLength {
                expected: 2,
                got: 1,
                ..
            })
        ),
        "{r:?}"
    );
    let bad = SolverOptions::default().rtol(-1.0);
    let r = integrate(
        &mut Oscillator { omega: 1.0 },
        0.0,
        &[1.0, 0.0],
        1.0,
        0.1,
        &bad,
        &mut rec,
    );
    assert!(
        matches!(r, Err(SolveError::InvalidOption { option: "rtol", .. })),
        "{r:?}"
    );
    assert!(rec.samples.is_empty());
}
