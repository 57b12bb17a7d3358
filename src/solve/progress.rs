//! Bounds on a run that is not getting anywhere: the wall-clock limit `max_wall` and the
//! no-progress rule. Both are checked by the driver before every step attempt.
//!
//! **No-progress rule.** Let t_j be the time at which attempt j starts (accepted and rejected
//! attempts alike, event-shortened steps included). Before attempt a ≥ W (W = 1000), with
//! Δ = t_a − t_{a−W} the advance over the last W attempts, the pace projects
//! P = W·(t_end − t_a)/Δ more attempts to reach t_end (P = ∞ if Δ = 0). The run stops with
//! [`SolveError::NoProgress`] when P > 100·(max_steps − a): at this pace it would run into
//! `max_steps` even if the pace improved a hundredfold, so it is stopped now, within W attempts
//! (milliseconds) instead of after `max_steps` of them (minutes).
//!
//! Why it cannot stop a healthy run: such a run ends within `max_steps` attempts, so its
//! average pace is at least (t_end − t0)/max_steps per attempt; the rule needs a window of W
//! consecutive attempts that is more than 100× slower than the pace that would exhaust the
//! remaining budget. For the reference four-bar (models/farahan2016.toml, 2 turns at 250 and
//! 3500 rpm, the contact-rich cases, both formulations, both explicit pairs, rtol 1e-6 and
//! 1e-9) the slowest window is about 900× away from the threshold with the default
//! `max_steps` (worst: DAE, DOPRI5, rtol 1e-6 at 3500 rpm, in the first contact phase; checked
//! in `tests/no_progress.rs`). The explicit
//! pairs in a long contact phase take ~40 µs steps because the contact is stiff; that is slow
//! but steady progress and does not trigger the rule.
//!
//! **Stiff or collapsed.** When the rule fires, the message says the problem is stiff if the
//! method's stiffness test has fired ([`Integrator::stiffness_detected`]: for the explicit
//! pairs, Hairer's hλ estimate beyond the stability boundary on 15 recent steps) and suggests
//! an implicit method; otherwise it says that the step size collapsed (a near-discontinuity or
//! events piling up).
//!
//! [`Integrator::stiffness_detected`]: super::integrator::Integrator::stiffness_detected

use std::time::Instant;

use super::error::SolveError;
use super::options::implicit_methods;

/// Attempts in the no-progress window.
pub(crate) const WINDOW: usize = 1000;
/// Factor between the projected attempts and the remaining budget that stops a run.
pub(crate) const STALL_FACTOR: f64 = 100.0;

/// Wall clock and the window of attempt start times.
pub(crate) struct Progress {
    started: Instant,
    t0: f64,
    max_wall: Option<f64>,
    /// t at the start of each of the last `WINDOW` attempts (a ring).
    ring: Vec<f64>,
    next: usize,
    attempts: u64,
}

/// Where the run stands at an attempt.
pub(crate) struct AttemptAt {
    /// Start time of the attempt (s).
    pub t: f64,
    /// End time of the run (s).
    pub t_end: f64,
    /// Attempts made before this one.
    pub attempts: u64,
    /// The `max_steps` option.
    pub max_steps: u64,
    /// Whether the method reports stiffness.
    pub stiff: bool,
}

impl Progress {
    /// Starts the clock for a run from t0 (s).
    pub(crate) fn new(t0: f64, max_wall: Option<f64>) -> Self {
        Self {
            started: Instant::now(),
            t0,
            max_wall,
            ring: vec![0.0; WINDOW],
            next: 0,
            attempts: 0,
        }
    }

    /// Checks both bounds before an attempt and records its start time.
    pub(crate) fn before_attempt(&mut self, at: &AttemptAt) -> Result<(), SolveError> {
        if let Some(limit_s) = self.max_wall {
            let wall_s = self.started.elapsed().as_secs_f64();
            if wall_s > limit_s {
                return Err(SolveError::WallTimeExceeded {
                    t: at.t,
                    t_end: at.t_end,
                    wall_s,
                    limit_s,
                    rate: self.simulated_per_second(at.t, wall_s),
                });
            }
        }
        let Some(slot) = self.ring.get_mut(self.next) else {
            debug_assert!(false, "ring index out of range");
            return Ok(());
        };
        let oldest = std::mem::replace(slot, at.t);
        self.next = (self.next + 1) % WINDOW;
        self.attempts += 1;
        if self.attempts <= WINDOW as u64 {
            return Ok(());
        }
        let advance = at.t - oldest;
        let remaining = at.t_end - at.t;
        let projected = if advance > 0.0 {
            WINDOW as f64 * remaining / advance
        } else {
            f64::INFINITY
        };
        let budget = at.max_steps.saturating_sub(at.attempts) as f64;
        if remaining > 0.0 && projected > STALL_FACTOR * budget {
            return Err(SolveError::NoProgress {
                t: at.t,
                h: advance / WINDOW as f64,
                advance,
                attempts: WINDOW as u64,
                projected,
                stiff: at.stiff,
                implicit: implicit_methods(),
                // Filled in by the driver, which holds the state (`Stepper::advance`).
                diagnosis: None,
            });
        }
        Ok(())
    }

    /// Simulated seconds per wall-clock second since the start.
    fn simulated_per_second(&self, t: f64, wall_s: f64) -> f64 {
        if wall_s > 0.0 {
            (t - self.t0) / wall_s
        } else {
            0.0
        }
    }
}
