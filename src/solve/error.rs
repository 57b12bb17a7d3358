//! [`SolveError`]: why an integration stopped, and when.

use thiserror::Error;

use crate::formulation::FormulationError;

/// Errors raised by the integrators. Every variant met during a run says at which time t (s)
/// it happened.
#[derive(Debug, Error)]
pub enum SolveError {
    /// A solver option (or an argument of [`integrate`](fn@crate::solve::integrate)) is out of
    /// range.
    #[error("invalid solver option `{option}`: {reason}")]
    InvalidOption {
        /// Name of the option or argument (`rtol`, `dt_out`, …).
        option: &'static str,
        /// What was expected and what was given.
        reason: String,
    },

    /// A state vector (initial state or output buffer) has the wrong length.
    #[error("{what} has {got} components but the formulation has {expected} states")]
    StateLength {
        /// Which vector ("initial state", "output buffer").
        what: &'static str,
        /// Number of states of the formulation.
        expected: usize,
        /// Length given.
        got: usize,
    },

    /// The run took longer than [`SolverOptions::max_wall`](crate::solve::SolverOptions::max_wall).
    #[error(
        "stopped after {wall_s:.3} s of wall-clock time (limit max_wall = {limit_s} s) at t = {t:.9} s of t_end = {t_end} s, simulating {rate:.3e} s per wall-clock second"
    )]
    WallTimeExceeded {
        /// Time reached (s).
        t: f64,
        /// End time of the run (s).
        t_end: f64,
        /// Wall-clock time spent (s).
        wall_s: f64,
        /// The limit (s).
        limit_s: f64,
        /// Simulated time per wall-clock second so far.
        rate: f64,
    },

    /// The run stopped making progress: over the last attempts the step size collapsed so far
    /// that t_end could not be reached within `max_steps` (see `solve::progress`).
    #[error("{}", no_progress_message(*t, *h, *advance, *attempts, *projected, *budget, *stiff, implicit, diagnosis.as_deref()))]
    NoProgress {
        /// Time reached (s).
        t: f64,
        /// Mean step size over the window (s).
        h: f64,
        /// How far t advanced over the window (s).
        advance: f64,
        /// Attempts in the window.
        attempts: u64,
        /// Attempts still needed at this pace.
        projected: f64,
        /// Attempts that `max_steps` still allows.
        budget: f64,
        /// The method's stiffness test fired: the step is limited by stability.
        stiff: bool,
        /// Implicit methods available to suggest (`"a" or "b"`; empty if none).
        implicit: String,
        /// What the formulation found at the stall state
        /// ([`Formulation::diagnose`](crate::formulation::Formulation::diagnose)): the
        /// constraints or joints involved; `None` if it found nothing.
        diagnosis: Option<String>,
    },

    /// The step size fell below the resolution of t (16 machine epsilons of max(|t|, |t_end|)):
    /// the solution is (nearly) discontinuous there or the problem is too stiff for an explicit
    /// method.
    #[error(
        "step size h = {h:.3e} s at t = {t:.9} s is below the resolution of t (a discontinuity, a stiff contact or a singular position of the linkage such as a toggle; check the model, or loosen rtol/atol)"
    )]
    StepTooSmall {
        /// Time reached (s).
        t: f64,
        /// Step size that was too small (s).
        h: f64,
    },

    /// The limit [`SolverOptions::max_steps`](crate::solve::SolverOptions::max_steps) on step
    /// attempts (accepted and rejected) was reached.
    #[error(
        "gave up at t = {t:.9} s after {steps} step attempts (limit max_steps; raise it or loosen rtol/atol)"
    )]
    TooManySteps {
        /// Time reached (s).
        t: f64,
        /// Step attempts made.
        steps: u64,
    },

    /// A state component became NaN or infinite at a step boundary.
    #[error("non-finite value (NaN or infinity) in state component {component} at t = {t:.9} s")]
    NonFinite {
        /// Time of the step boundary (s).
        t: f64,
        /// Index of the first non-finite component of the state vector.
        component: usize,
    },

    /// The formulation could not evaluate its right-hand side.
    #[error("the equations of motion could not be evaluated at t = {t:.9} s")]
    Formulation {
        /// Time of the failed evaluation (s).
        t: f64,
        /// Why the formulation failed.
        #[source]
        source: FormulationError,
    },

    /// An integrator of an external library (SUNDIALS IDA, `--method ida`) gave up, with the
    /// library's return flag, what that flag means, and the library's own message.
    #[error("{method} failed at t = {t:.9} s: {flag}: {reason}")]
    MethodFailed {
        /// Time the method had reached (s).
        t: f64,
        /// Method name ("ida").
        method: &'static str,
        /// The library's return flag by name ("IDA_CONV_FAIL").
        flag: String,
        /// What the flag means and the library's message.
        reason: String,
    },

    /// The output sink failed (e.g. a write error); the run was aborted.
    #[error("output failed at t = {t:.9} s: {reason}")]
    Sink {
        /// Time of the sample or event being written (s).
        t: f64,
        /// What went wrong.
        reason: String,
    },

    /// The root of an event function could not be bracketed to the event tolerance.
    #[error(
        "event {index} near t = {t:.9} s could not be located to the event tolerance in {iterations} iterations"
    )]
    EventNotConverged {
        /// Best estimate of the event time (s).
        t: f64,
        /// Index of the event function.
        index: usize,
        /// Iterations spent.
        iterations: usize,
    },

    /// [`Formulation::max_step`](crate::formulation::Formulation::max_step) returned zero, a
    /// negative number or NaN.
    #[error(
        "the formulation's largest allowed step at t = {t:.9} s is {value} s (expected a positive number or infinity)"
    )]
    InvalidMaxStep {
        /// Time (s).
        t: f64,
        /// Value returned (s).
        value: f64,
    },

    /// [`Stepper::interpolate`](crate::solve::Stepper::interpolate) was asked for a time outside
    /// the last step.
    #[error(
        "cannot interpolate at t = {t:.9} s: the dense output covers [{t_start:.9}, {t_end:.9}] s only"
    )]
    OutsideStep {
        /// Time asked for (s).
        t: f64,
        /// Start of the last step (s).
        t_start: f64,
        /// End of the interpolable part of the last step (s).
        t_end: f64,
    },
}

/// The message of [`SolveError::NoProgress`]: the pace, the cause the method can tell
/// (stiff or collapsed), then the formulation's diagnosis if it has one.
#[allow(clippy::too_many_arguments)] // the variant's fields, one by one (thiserror's format)
fn no_progress_message(
    t: f64,
    h: f64,
    advance: f64,
    attempts: u64,
    projected: f64,
    budget: f64,
    stiff: bool,
    implicit: &str,
    diagnosis: Option<&str>,
) -> String {
    let head = format!(
        "no progress at t = {t:.9} s: the last {attempts} step attempts advanced t by {advance:.3e} s (mean step {h:.3e} s); reaching t_end at this pace needs about {projected:.1e} more attempts, max_steps allows {budget:.1e}"
    );
    let cause = if stiff {
        let advice = if implicit.is_empty() {
            "an implicit method (none is built into this version)".to_string()
        } else {
            format!("an implicit method (--method {implicit})")
        };
        format!(
            "{head}. The step size is limited by stability, not accuracy: the problem is stiff here (e.g. a long contact phase). Use {advice}; loosening rtol/atol will not help"
        )
    } else if attempts > super::progress::WINDOW as u64 {
        // The sustained-pace rule: a steady step, too small for the budget.
        format!(
            "{head}. The step size has stayed this small for {attempts} attempts: something keeps it there (a long contact phase, a stiff element, a step guard); raise --max-steps if the run must go on"
        )
    } else {
        format!(
            "{head}. The step size collapsed: the solution is (nearly) discontinuous here (a singular position of the linkage such as a toggle, a discontinuous force) or events pile up (chattering, a Zeno sequence of impacts); check the model"
        )
    };
    match diagnosis {
        Some(d) => format!("{cause}. At t = {t:.9} s: {d}"),
        None => cause,
    }
}

impl SolveError {
    /// Shorthand for [`SolveError::InvalidOption`].
    pub(crate) fn invalid(option: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidOption {
            option,
            reason: reason.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn formulation_error_is_the_source() {
        let err = SolveError::Formulation {
            t: 1.5,
            source: FormulationError::Unsupported {
                formulation: "test".into(),
                reason: "nothing".into(),
            },
        };
        assert!(err.to_string().contains("t = 1.500000000 s"), "{err}");
        let source = err.source().map(ToString::to_string);
        assert_eq!(source.as_deref(), Some("test formulation: nothing"));
    }

    #[test]
    fn messages_name_time_and_reason() {
        let err = SolveError::StepTooSmall { t: 0.25, h: 1e-18 };
        let msg = err.to_string();
        assert!(
            msg.contains("1.000e-18") && msg.contains("0.250000000"),
            "{msg}"
        );
        let err = SolveError::NonFinite {
            t: 2.0,
            component: 3,
        };
        assert!(err.to_string().contains("component 3"), "{err}");
    }
}
