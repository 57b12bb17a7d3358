//! [`SolverStats`]: what a run cost. Written into result files and snapshotted in tests, so a
//! change that doubles the work shows up in review.

use serde::Serialize;

/// Counters of one integration run.
///
/// Identities (checked in `tests/adaptive_tolerance.rs` and `tests/overshooting_stages.rs`):
///
/// * every rejection has exactly one cause:
///   `rejected = error_test_failures + newton_failures + recovered_rejections`;
/// * step attempts: `steps + rejected` (the quantity limited by `max_steps`);
/// * RHS calls of the explicit pairs, when no stage failed (`recovered_rejections = 0`):
///   * DOPRI5: `rhs_evals = 1 + [1 if hinit] + 6·(steps + rejected) + restarts`;
///   * DOP853: `rhs_evals = 1 + [1 if hinit] + 12·steps + 11·rejected + dense_evals + restarts`,
///
///   where the leading 1 is f(t0, y0) and `hinit` runs when no `h0` or fixed step is given
///   (a recovered rejection stops at the failing stage, so it costs fewer calls);
/// * the explicit pairs make no Newton iterations and no Jacobians: `newton_iterations`,
///   `newton_failures`, `jacobian_evals` and `jacobian_rhs_evals` are 0 for them.
/// * `jacobian_rhs_evals ≤ rhs_evals`; with forward differences on n states,
///   `jacobian_rhs_evals = n · jacobian_evals` for Radau5 (`tests/radau5_stiff_problems.rs`).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SolverStats {
    /// Accepted steps, including steps cut short at an event that restarted the integrator.
    pub steps: u64,
    /// Rejected step attempts, all causes: the sum of `error_test_failures`,
    /// `newton_failures` and `recovered_rejections`.
    pub rejected: u64,
    /// Rejections because the local error estimate was above tolerance (or NaN/∞).
    pub error_test_failures: u64,
    /// Rejections because a stage could not be evaluated at a trial state but a smaller step
    /// may avoid it: a recoverable
    /// [`FormulationError`](crate::formulation::FormulationError::is_recoverable), e.g. a trial
    /// stage that overshoots deep into a contact. The step is retried with a quarter of its size.
    pub recovered_rejections: u64,
    /// Rejections because the Newton iteration of an implicit method did not converge (0 for the
    /// explicit pairs).
    pub newton_failures: u64,
    /// Newton iterations of an implicit method, over all attempts (0 for the explicit pairs).
    pub newton_iterations: u64,
    /// Jacobian evaluations of an implicit method (0 for the explicit pairs).
    pub jacobian_evals: u64,
    /// LU factorisations of an implicit method's Newton matrices (Radau5: each one real and
    /// one complex); 0 for the explicit pairs and for IDA, which keeps its own.
    pub lu_decompositions: u64,
    /// Calls of [`Formulation::rhs`](crate::formulation::Formulation::rhs), all included.
    pub rhs_evals: u64,
    /// Of `rhs_evals`, those spent on finite-difference Jacobians
    /// ([`Formulation::jacobian`](crate::formulation::Formulation::jacobian)'s default, n per
    /// Jacobian for n states): Radau5, and IDA on a formulation it integrates as Ẏ − f(t, Y).
    /// 0 with analytic Jacobians (the DAE, the reduced four-bar, IDA's residual form of the
    /// DAE) and for the explicit pairs, so `rhs_evals − jacobian_rhs_evals` is what the method
    /// itself spent.
    pub jacobian_rhs_evals: u64,
    /// Of `rhs_evals`, the extra stages of DOP853's dense output (3 per interpolated step;
    /// always 0 for DOPRI5).
    pub dense_evals: u64,
    /// Events located and handed to
    /// [`Formulation::apply_event`](crate::formulation::Formulation::apply_event).
    pub events: u64,
    /// Restarts of the integrator after an event answered
    /// [`EventResponse::Restart`](crate::formulation::EventResponse::Restart).
    pub restarts: u64,
    /// Smallest accepted step size (s), including the shortened last step; 0 if no step.
    pub h_min_used: f64,
    /// Largest accepted step size (s); 0 if no step.
    pub h_max_used: f64,
}

impl SolverStats {
    /// Records an accepted step of size h (s).
    pub(crate) fn record_step(&mut self, h: f64) {
        if self.steps == 0 {
            self.h_min_used = h;
            self.h_max_used = h;
        } else {
            self.h_min_used = self.h_min_used.min(h);
            self.h_max_used = self.h_max_used.max(h);
        }
        self.steps += 1;
    }

    /// Adds the steps, rejections, RHS and dense-output evaluations, events and restarts of a
    /// later integration of the same study (the Lyapunov pair's segments, a shooting's periods)
    /// and widens the step-size range to cover both.
    pub(crate) fn add_run(&mut self, s: &SolverStats) {
        if s.steps > 0 {
            if self.steps == 0 {
                self.h_min_used = s.h_min_used;
                self.h_max_used = s.h_max_used;
            } else {
                self.h_min_used = self.h_min_used.min(s.h_min_used);
                self.h_max_used = self.h_max_used.max(s.h_max_used);
            }
        }
        self.steps += s.steps;
        self.rejected += s.rejected;
        self.rhs_evals += s.rhs_evals;
        self.dense_evals += s.dense_evals;
        self.events += s.events;
        self.restarts += s.restarts;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_sizes_are_tracked() {
        let mut s = SolverStats::default();
        assert_eq!((s.h_min_used, s.h_max_used), (0.0, 0.0));
        for h in [0.5, 0.1, 2.0] {
            s.record_step(h);
        }
        assert_eq!((s.steps, s.h_min_used, s.h_max_used), (3, 0.1, 2.0));
    }

    #[test]
    fn serialises_every_field() {
        let json = serde_json::to_string(&SolverStats::default()).unwrap_or_default();
        for field in [
            "steps",
            "rejected",
            "error_test_failures",
            "recovered_rejections",
            "newton_failures",
            "newton_iterations",
            "jacobian_evals",
            "lu_decompositions",
            "rhs_evals",
            "jacobian_rhs_evals",
            "dense_evals",
            "events",
            "restarts",
            "h_min_used",
            "h_max_used",
        ] {
            assert!(
                json.contains(&format!("\"{field}\"")),
                "{field} missing in {json}"
            );
        }
    }
}
