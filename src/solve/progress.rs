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
//! **Sustained-pace rule.** The rule above lets a run go on whose pace projects between one
//! and a hundred times the remaining budget: it fires only once the budget is nearly spent,
//! after up to `max_steps` attempts — minutes, not seconds (a 1e300 kg crank crawled for 106 s
//! that way before model validation refused such masses). So, once a tenth of `max_steps` is
//! spent, with Δ_long the advance over the last W_long = 10 000 attempts: the run stops when
//! P_long = W_long·(t_end − t_a)/Δ_long exceeds the remaining budget max_steps − a itself, at a
//! tenth of the budget instead of at its end. It waits for that tenth because a pace alone
//! cannot tell a crawl that ends from one that does not: the as-printed friction law of
//! `linkdyn reproduce --quick` (a reproduction aid with sticking phases of tiny steps) has
//! windows of 10 000 attempts that project 1–30 times the budget in runs that then finish
//! within it. On the reference runs below the slowest such window projects at most 2.8e-3 of
//! the budget (`tests/no_progress.rs`).
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
/// Attempts in the window of the sustained-pace rule.
pub(crate) const LONG_WINDOW: usize = 10_000;
/// Fraction of `max_steps` after which the sustained-pace rule applies.
pub(crate) const LATE_FRACTION: f64 = 0.1;

/// Wall clock and the window of attempt start times.
pub(crate) struct Progress {
    started: Instant,
    t0: f64,
    max_wall: Option<f64>,
    /// t at the start of each of the last `LONG_WINDOW` attempts (a ring).
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
            ring: vec![0.0; LONG_WINDOW],
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
        // The start W attempts ago is the ring's entry W − 1 places behind the one about to be
        // overwritten (the oldest, LONG_WINDOW attempts ago).
        let n = LONG_WINDOW;
        let short_ago = self.ring.get((self.next + n - WINDOW) % n).copied();
        let Some(slot) = self.ring.get_mut(self.next) else {
            debug_assert!(false, "ring index out of range");
            return Ok(());
        };
        let long_ago = std::mem::replace(slot, at.t);
        self.next = (self.next + 1) % n;
        self.attempts += 1;
        let remaining = at.t_end - at.t;
        let budget = at.max_steps.saturating_sub(at.attempts) as f64;
        // Attempts that the last `window` attempts' pace needs to reach t_end.
        let projected = |window: usize, oldest: f64| {
            let advance = at.t - oldest;
            if advance > 0.0 {
                window as f64 * remaining / advance
            } else {
                f64::INFINITY
            }
        };
        // The error is built only when a rule fires (it names the implicit methods: a string).
        let stall = |window: usize, oldest: f64| {
            let advance = at.t - oldest;
            SolveError::NoProgress {
                t: at.t,
                h: advance / window as f64,
                advance,
                attempts: window as u64,
                projected: projected(window, oldest),
                budget,
                stiff: at.stiff,
                implicit: implicit_methods(),
                // Filled in by the driver, which holds the state (`Stepper::advance`).
                diagnosis: None,
            }
        };
        if remaining <= 0.0 {
            return Ok(());
        }
        if self.attempts > WINDOW as u64
            && let Some(oldest) = short_ago
            && projected(WINDOW, oldest) > STALL_FACTOR * budget
        {
            return Err(stall(WINDOW, oldest));
        }
        if self.attempts > n as u64
            && self.attempts as f64 >= LATE_FRACTION * at.max_steps as f64
            && projected(n, long_ago) > budget
        {
            return Err(stall(n, long_ago));
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
