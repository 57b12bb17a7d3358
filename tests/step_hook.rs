//! Claim: `Sink::on_step` sees every accepted step once, in order, with a dense output that
//! tiles the run without gaps (event-shortened steps included), so a sink can find the true
//! extremum of a quantity between the output samples.

mod common;

use common::ode::Oscillator;
use linkdyn::formulation::{Crossing, EventResponse, Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{DenseStep, Method, Sink, SolveError, SolverOptions, integrate};
use std::f64::consts::PI;

/// Samples the dense output of every step finely and keeps the smallest x(t) found, plus the
/// ranges of the steps and the smallest sampled x.
#[derive(Default)]
struct Extremum {
    ranges: Vec<(f64, f64)>,
    x_min: f64,
    t_min: f64,
    sampled_min: f64,
}

/// Points per step at which the hook looks (a golden-section refinement follows).
const PROBES: usize = 16;

impl<F: Formulation> Sink<F> for Extremum {
    fn sample(&mut self, _f: &F, _t: f64, y: &[f64]) -> Result<(), SolveError> {
        self.sampled_min = self.sampled_min.min(y[0]);
        Ok(())
    }

    fn on_step(&mut self, step: &mut DenseStep<'_, F>) -> Result<(), SolveError> {
        let (a, b) = step.range();
        self.ranges.push((a, b));
        let mut y = vec![0.0; step.n_states()];
        let mut x_at = |t: f64| -> Result<f64, SolveError> {
            step.interpolate(t, &mut y)?;
            Ok(y[0])
        };
        // Coarse scan, then golden-section search around the best probe.
        let mut best = (a, x_at(a)?);
        for j in 1..=PROBES {
            let t = a + (b - a) * j as f64 / PROBES as f64;
            let x = x_at(t.min(b))?;
            if x < best.1 {
                best = (t.min(b), x);
            }
        }
        let dt = (b - a) / PROBES as f64;
        let (mut lo, mut hi) = ((best.0 - dt).max(a), (best.0 + dt).min(b));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if x_at(c)? < x_at(d)? {
                hi = d;
            } else {
                lo = c;
            }
        }
        let t = 0.5 * (lo + hi);
        let x = x_at(t)?;
        if x < self.x_min {
            self.x_min = x;
            self.t_min = t;
        }
        Ok(())
    }
}

#[test]
fn the_hook_finds_the_true_minimum_between_samples() -> Result<(), SolveError> {
    for method in Method::ALL {
        let opts = SolverOptions::default()
            .method(method)
            .rtol(1e-10)
            .atol(1e-12);
        let mut sink = Extremum {
            x_min: f64::INFINITY,
            sampled_min: f64::INFINITY,
            ..Extremum::default()
        };
        // x = cos t over one period, sampled every 0.7 s: no sample near the minimum at t = π.
        let mut f = Oscillator { omega: 1.0 };
        let stats = integrate(&mut f, 0.0, &[1.0, 0.0], 2.0 * PI, 0.7, &opts, &mut sink)?;
        assert_eq!(
            sink.ranges.len() as u64,
            stats.steps,
            "{method}: one call per accepted step"
        );
        // The closest sample is 0.0584 s from π: x = −cos(0.0584) = −0.99829.
        assert!(
            sink.sampled_min > -0.999,
            "{method}: samples already see the minimum ({})",
            sink.sampled_min
        );
        // rtol 1e-10 over half a period: the dense output is good to ~1e-9; the minimum of a
        // smooth function is found to that accuracy in x and to its square root in t.
        assert!(
            (sink.x_min + 1.0).abs() < 1e-8,
            "{method}: minimum {} vs -1",
            sink.x_min
        );
        assert!(
            (sink.t_min - PI).abs() < 1e-4,
            "{method}: minimum at t = {} vs π",
            sink.t_min
        );
    }
    Ok(())
}

/// A ball dropped from 10 m that bounces elastically (v → −v, restart) on the floor x = 0.
struct Ball;

impl NoStepHooks for Ball {}

impl Formulation for Ball {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![10.0, 0.0]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = -9.81;
        Ok(())
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn apply_event(&mut self, _t: f64, y: &mut [f64], _i: usize, c: Crossing) -> EventResponse {
        if c == Crossing::Falling {
            y[1] = -y[1];
            return EventResponse::Restart;
        }
        EventResponse::Continue
    }
}

#[test]
fn event_shortened_steps_are_handed_over_and_the_steps_tile_the_run() -> Result<(), SolveError> {
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        let mut sink = Extremum {
            x_min: f64::INFINITY,
            sampled_min: f64::INFINITY,
            ..Extremum::default()
        };
        let t_end = 10.0;
        let stats = integrate(&mut Ball, 0.0, &[10.0, 0.0], t_end, 0.1, &opts, &mut sink)?;
        assert!(stats.restarts >= 3, "{method}: bounces {stats:?}");
        assert_eq!(sink.ranges.len() as u64, stats.steps, "{method}: {stats:?}");
        assert_eq!(sink.ranges.first().map(|r| r.0), Some(0.0), "{method}");
        assert_eq!(sink.ranges.last().map(|r| r.1), Some(t_end), "{method}");
        for pair in sink.ranges.windows(2) {
            // Exact equality: a step starts where the last one (or its cut at an event) ended.
            assert_eq!(pair[0].1, pair[1].0, "{method}: gap between steps {pair:?}");
            assert!(pair[1].0 < pair[1].1, "{method}: empty step {pair:?}");
        }
        // The ball touches the floor (x = 0) at each bounce; the cut steps end on the event,
        // where x is 0 to the event tolerance (1e-12 s × impact speed 14 m/s).
        assert!(
            sink.x_min.abs() < 1e-9,
            "{method}: lowest point {} m",
            sink.x_min
        );
    }
    Ok(())
}
