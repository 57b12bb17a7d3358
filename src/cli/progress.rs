//! [`Watched`]: the sink wrapper of `run` that stops the run when a signal arrived and, for a
//! run longer than about 2 s with stderr on a terminal, shows progress there (simulated time,
//! driver turns, speed in simulated seconds per second, time left). Nothing is drawn when
//! stderr is not a terminal (a file, a pipe, a test).

use super::interrupt;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use linkdyn::simulation::{Sample, SampleSink, Simulation};
use linkdyn::solve::{EventRecord, SolveError};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Wall time after which the progress bar appears.
pub(super) const SHOW_AFTER: Duration = Duration::from_secs(2);
/// Resolution of the bar (positions per run).
const STEPS: u64 = 1000;

/// Forwards to `inner`; checks for a signal at every sample; draws progress.
pub struct Watched<'s, S: SampleSink> {
    inner: S,
    sim: &'s Simulation,
    started: Instant,
    terminal: bool,
    bar: Option<ProgressBar>,
}

impl<'s, S: SampleSink> Watched<'s, S> {
    /// Wraps `inner` for a run of `sim`.
    pub fn new(inner: S, sim: &'s Simulation) -> Self {
        Watched {
            inner,
            sim,
            started: Instant::now(),
            terminal: std::io::stderr().is_terminal(),
            bar: None,
        }
    }

    /// Removes the bar (call when the run is over, before printing).
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    fn show(&mut self, t: f64) {
        let elapsed = self.started.elapsed();
        if elapsed < SHOW_AFTER {
            return;
        }
        let bar = self.bar.get_or_insert_with(|| {
            let bar = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{wide_bar} {percent:>3}% {msg}, {eta} left")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style);
            bar
        });
        let (t0, t_end) = (self.sim.t0(), self.sim.t_end());
        let fraction = ((t - t0) / (t_end - t0)).clamp(0.0, 1.0);
        bar.set_position((fraction * STEPS as f64) as u64);
        let rate = (t - t0) / elapsed.as_secs_f64();
        let turns = self
            .sim
            .driver_turns(t)
            .map(|r| format!(", {r:.2} turns"))
            .unwrap_or_default();
        bar.set_message(format!(
            "t = {t:.4} s of {t_end:.4} s{turns}, {rate:.3e} s/s"
        ));
    }
}

impl<S: SampleSink> SampleSink for Watched<'_, S> {
    fn sample(&mut self, s: &Sample<'_>) -> Result<(), SolveError> {
        if interrupt::requested() {
            return Err(SolveError::Sink {
                t: s.t,
                reason: "interrupted".into(),
            });
        }
        if self.terminal {
            self.show(s.t);
        }
        self.inner.sample(s)
    }

    fn event(&mut self, event: &EventRecord) -> Result<(), SolveError> {
        self.inner.event(event)
    }
}
