//! How Radau IIA (order 5) treats a right-hand side that fails recoverably (a trial stage
//! overshooting into a contact, `FormulationError::is_recoverable`): the attempt is rejected
//! and retried with a smaller step; the error is reported, with its time, only when no step
//! size avoids it. Also: components masked out of error control do not drive the step size.
//! Radau5 runs through the common driver (`Stepper`, `Method::Radau5`), as in `linkdyn run`.

use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolveError, SolverOptions, SolverStats, Stepper, Stop};

/// Runs Radau5 on `f` from its initial state at t = 0 to `t_end`: the final state and the cost.
fn run_to_end<F: Formulation>(
    f: &mut F,
    t_end: f64,
    opts: SolverOptions,
) -> Result<(Vec<f64>, SolverStats), SolveError> {
    let opts = opts.method(Method::Radau5).build()?;
    let y0 = f.initial_state();
    let mut s = Stepper::new(f, 0.0, &y0, t_end, &opts)?;
    while s.step()? != Stop::EndReached {}
    Ok((s.y().to_vec(), s.stats().clone()))
}

/// y' = −y, y(0) = 1, whose RHS refuses trial states farther than `band` from the exact
/// solution e^{−t} (as a contact law refuses a penetration beyond its range), and refuses
/// everything after `t_wall` if given (a wall no step size can avoid).
struct Guarded {
    band: f64,
    t_wall: Option<f64>,
}
impl NoStepHooks for Guarded {}

impl Formulation for Guarded {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let off = (y[0] - (-t).exp()).abs();
        if off > self.band || self.t_wall.is_some_and(|w| t > w) {
            return Err(FormulationError::PenetrationTooDeep {
                t,
                joint: "guard".into(),
                penetration: off,
                limit: self.band,
            });
        }
        dy[0] = -y[0];
        Ok(())
    }
}

#[test]
fn overshooting_stages_are_retried_with_smaller_steps() -> Result<(), SolveError> {
    let mut f = Guarded {
        band: 1e-3,
        t_wall: None,
    };
    // h0 = 1: the first Newton iterate puts the stages at y = 1 for t up to 1, 0.63 off.
    let opts = SolverOptions::default().rtol(1e-8).atol(1e-10).h0(1.0);
    let (y, s) = run_to_end(&mut f, 3.0, opts)?;
    // Each retry divides h by 4; |1 − e^{−c₁h}| ≤ 1e-3 needs h ≲ 6.5e-3, so at least 3.
    assert!(
        s.recovered_rejections >= 3,
        "recovered rejections: {} ({s:?})",
        s.recovered_rejections
    );
    let exact = (-3f64).exp();
    // rtol = 1e-8 on a decaying solution: global error ≲ 1e-8·|y| summed over the run.
    assert!((y[0] - exact).abs() < 1e-9, "y(3) = {} vs {exact}", y[0]);
    Ok(())
}

#[test]
fn a_failure_no_step_avoids_is_reported_with_its_time() -> Result<(), SolveError> {
    let mut f = Guarded {
        band: 1.0,
        t_wall: Some(0.5),
    };
    let opts = SolverOptions::default().method(Method::Radau5).build()?;
    let mut r = Stepper::new(&mut f, 0.0, &[1.0], 1.0, &opts)?;
    let outcome = loop {
        match r.step() {
            Ok(Stop::EndReached) => break Ok(()),
            Ok(_) => {}
            Err(e) => break Err(e),
        }
    };
    match outcome {
        Err(SolveError::Formulation { t, source }) => {
            assert!(source.is_recoverable(), "{source}");
            // The last attempt starts at the wall to within the smallest step (16 ulps of 1).
            assert!(
                (t - 0.5).abs() < 1e-12,
                "reported at t = {t}, the wall is at 0.5"
            );
            assert!(
                (r.t() - 0.5).abs() < 1e-12,
                "integration stopped at t = {} instead of the wall 0.5",
                r.t()
            );
        }
        other => panic!("expected the guard's error, got {other:?}"),
    }
    Ok(())
}

/// y₁' = −y₁ (decay) and y₂' = 10⁶·cos(10³ t)·y₁: a fast-oscillating bookkeeping integral that
/// nothing depends on; with `masked`, the formulation marks y₂ as bookkeeping
/// ([`Formulation::error_controlled`]), as the DAE marks its energy integrals.
struct WithBookkeeping {
    masked: bool,
}
impl NoStepHooks for WithBookkeeping {}

impl Formulation for WithBookkeeping {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![1.0, 0.0]
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = -y[0];
        dy[1] = 1e6 * (1e3 * t).cos() * y[0];
        Ok(())
    }
    fn error_controlled(&self, controlled: &mut [bool]) {
        controlled[1] = !self.masked;
    }
}

#[test]
fn masked_components_do_not_drive_the_step_size() -> Result<(), SolveError> {
    let opts = || SolverOptions::default().rtol(1e-8).atol(1e-10);
    let (_, full) = run_to_end(&mut WithBookkeeping { masked: false }, 2.0, opts())?;
    let (y, masked) = run_to_end(&mut WithBookkeeping { masked: true }, 2.0, opts())?;
    let (n_full, n_masked) = (full.steps, masked.steps);
    // Resolving cos(10³ t) over [0, 2] (≈ 320 periods) takes thousands of steps; y₁ alone is
    // a smooth decay that needs a few dozen.
    assert!(
        n_masked * 10 < n_full,
        "steps with the bookkeeping state masked: {n_masked}, unmasked: {n_full}"
    );
    let exact = (-2f64).exp();
    // The controlled component keeps its accuracy (rtol 1e-8).
    assert!(
        (y[0] - exact).abs() < 1e-9,
        "masked run: y1(2) = {} vs {exact}",
        y[0]
    );
    Ok(())
}
