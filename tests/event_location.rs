//! Claim: events are located on the dense output to the event tolerance, restarts reproduce the
//! analytic bounce sequence, the earliest of several events in one step comes first, samples
//! at an event time show the state before the event, and a grazing event needs `max_step`.
//!
//! Free fall x'' = −g is integrated exactly by both methods (its solution is a quadratic and
//! both the methods and their dense outputs have order ≥ 2), so every discrepancy below comes
//! from the event location and rounding, not from truncation error.

mod common;

use common::ode::OdeRecorder;
use linkdyn::formulation::{Crossing, EventResponse, Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{EventRecord, Method, Sink, SolveError, SolverOptions, integrate};

/// Gravity (m/s²).
const G: f64 = 9.81;

/// A body in free fall, state (x, v), with the event g₀ = x (height above the floor).
/// `restitution`: `Some(e)` bounces (v → −e·v, restart) when falling through x = 0;
/// `None` only records the crossing (continue).
struct Ball {
    restitution: Option<f64>,
}

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
        dy[1] = -G;
        Ok(())
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
    fn apply_event(&mut self, _t: f64, y: &mut [f64], _i: usize, c: Crossing) -> EventResponse {
        match (self.restitution, c) {
            (Some(e), Crossing::Falling) => {
                y[1] *= -e;
                EventResponse::Restart
            }
            _ => EventResponse::Continue,
        }
    }
}

#[test]
fn falling_body_hits_the_floor_at_the_analytic_time() -> Result<(), SolveError> {
    let h0 = 10.0;
    let exact = (2.0 * h0 / G).sqrt();
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        let mut rec = OdeRecorder::default();
        integrate(
            &mut Ball { restitution: None },
            0.0,
            &[h0, 0.0],
            2.0,
            0.1,
            &opts,
            &mut rec,
        )?;
        assert_eq!(rec.events.len(), 1, "{method}: events {:?}", rec.events);
        let (ev, before, after) = &rec.events[0];
        assert_eq!(
            (ev.index, ev.crossing, ev.restarted),
            (0, Crossing::Falling, false)
        );
        // The bracket is at most event_tol·max(1, t) = 1e-12·t wide and reported from its far
        // end; a few ulps more come from evaluating x(t) near its root.
        let rel = (ev.t - exact).abs() / exact;
        assert!(
            rel <= 1e-12,
            "{method}: t = {} vs {exact}, relative error {rel:.2e}",
            ev.t
        );
        assert!(
            ev.t >= exact - 4.0 * f64::EPSILON * exact,
            "{method}: reported before the root"
        );
        assert_eq!(
            before, after,
            "{method}: Continue must not change the state"
        );
    }
    Ok(())
}

/// Bounce times of a ball dropped from h0 with restitution e: t₁ = √(2h₀/g),
/// t_{k+1} = t_k + 2 e^k v₁/g with v₁ = g t₁.
fn bounce_times(h0: f64, e: f64, n: usize) -> Vec<f64> {
    let t1 = (2.0 * h0 / G).sqrt();
    let v1 = G * t1;
    let mut t = vec![t1];
    for k in 1..n {
        let last = t[k - 1];
        t.push(last + 2.0 * e.powi(k as i32) * v1 / G);
    }
    t
}

#[test]
fn restarts_reproduce_five_bounces() -> Result<(), SolveError> {
    let (h0, e) = (10.0, 0.8);
    let exact = bounce_times(h0, e, 5);
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        let mut rec = OdeRecorder::default();
        let mut ball = Ball {
            restitution: Some(e),
        };
        let stats = integrate(&mut ball, 0.0, &[h0, 0.0], 8.5, 0.05, &opts, &mut rec)?;
        let times: Vec<f64> = rec.events.iter().map(|(ev, _, _)| ev.t).collect();
        assert_eq!(
            times.len(),
            5,
            "{method}: bounces at {times:?}, expected {exact:?}"
        );
        for (k, (t, te)) in times.iter().zip(&exact).enumerate() {
            // Each located time is ≤ 1e-12·t late; the restart state inherits that, so errors
            // add up over the bounces to a few 1e-12 — 1e-10 leaves a wide margin.
            assert!(
                (t - te).abs() < 1e-10,
                "{method}: bounce {k} at {t}, exact {te}"
            );
        }
        for (ev, before, after) in &rec.events {
            assert!(ev.restarted && ev.crossing == Crossing::Falling);
            assert!(
                (after[1] + e * before[1]).abs() < 1e-15,
                "{method}: v⁺ = −e v⁻"
            );
        }
        assert_eq!(
            (stats.events, stats.restarts),
            (5, 5),
            "{method}: {stats:?}"
        );
        // Each restart costs exactly one RHS call (the new FSAL stage f(t_ev, y⁺)).
        let per_step = match method {
            Method::Dopri5 => Some(6 * (stats.steps + stats.rejected)),
            Method::Dop853 => Some(12 * stats.steps + 11 * stats.rejected),
            // Newton iterations and Jacobians vary per step (counted in tests/radau5_*.rs).
            Method::Radau5 => None,
            #[cfg(feature = "ida")]
            Method::Ida => None,
        };
        if let Some(per_step) = per_step {
            let expected = 2 + per_step + stats.dense_evals + stats.restarts;
            assert_eq!(stats.rhs_evals, expected, "{method}: {stats:?}");
        }
        // After each bounce the ball is back above the floor: no sample below it (beyond the
        // ~1e-11 m the located time may lie past the root).
        let lowest = rec
            .samples
            .iter()
            .map(|(_, y)| y[0])
            .fold(f64::INFINITY, f64::min);
        assert!(lowest > -1e-9, "{method}: sample at height {lowest}");
    }
    Ok(())
}

/// x' = 1 from x = 0 with two thresholds, both crossed inside one step.
struct Ramp {
    thresholds: [f64; 2],
    restart_on: Option<usize>,
}

impl NoStepHooks for Ramp {}

impl Formulation for Ramp {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 1.0;
        Ok(())
    }
    fn n_events(&self) -> usize {
        2
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0] - self.thresholds[0];
        g[1] = y[0] - self.thresholds[1];
    }
    fn apply_event(&mut self, _t: f64, y: &mut [f64], i: usize, _c: Crossing) -> EventResponse {
        if self.restart_on == Some(i) {
            y[0] += 0.0; // same state, but the integrator must restart from it
            EventResponse::Restart
        } else {
            EventResponse::Continue
        }
    }
}

#[test]
fn earliest_of_two_events_in_one_step_comes_first() -> Result<(), SolveError> {
    for method in Method::ALL {
        for restart_on in [None, Some(1)] {
            let mut f = Ramp {
                thresholds: [0.5, 0.3],
                restart_on,
            };
            // One fixed step of length 1 holds both crossings.
            let opts = SolverOptions::with_fixed_step(1.0).method(method);
            let mut rec = OdeRecorder::default();
            let stats = integrate(&mut f, 0.0, &[0.0], 1.0, 1.0, &opts, &mut rec)?;
            let got: Vec<(usize, Crossing)> = rec
                .events
                .iter()
                .map(|(e, _, _)| (e.index, e.crossing))
                .collect();
            assert_eq!(
                got,
                vec![(1, Crossing::Rising), (0, Crossing::Rising)],
                "{method}, restart on {restart_on:?}"
            );
            for ((ev, _, _), t) in rec.events.iter().zip([0.3, 0.5]) {
                assert!(
                    (ev.t - t).abs() <= 1e-12,
                    "{method}: event at {}, expected {t}",
                    ev.t
                );
            }
            let expected_steps = if restart_on.is_some() { 2 } else { 1 };
            assert_eq!(
                stats.steps, expected_steps,
                "{method}, restart on {restart_on:?}"
            );
        }
    }
    Ok(())
}

/// Logs samples and events in the order they arrive.
#[derive(Default)]
struct Log(Vec<(char, f64, f64)>);

impl<F> Sink<F> for Log {
    fn sample(&mut self, _f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        self.0.push(('s', t, y[0]));
        Ok(())
    }
    fn event(
        &mut self,
        _f: &F,
        ev: &EventRecord,
        _b: &[f64],
        after: &[f64],
    ) -> Result<(), SolveError> {
        self.0.push(('e', ev.t, after[0]));
        Ok(())
    }
}

/// x' = 1; at t = 0.5 the state jumps by +10 (restart). The event function g = t − 0.5 is
/// evaluated exactly near its root, so the located time is never before 0.5.
struct Jump;

impl NoStepHooks for Jump {}

impl Formulation for Jump {
    fn n_states(&self) -> usize {
        1
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn rhs(&self, _t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = 1.0;
        Ok(())
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, t: f64, _y: &[f64], g: &mut [f64]) {
        g[0] = t - 0.5;
    }
    fn apply_event(&mut self, _t: f64, y: &mut [f64], _i: usize, _c: Crossing) -> EventResponse {
        y[0] += 10.0;
        EventResponse::Restart
    }
}

#[test]
fn sample_at_the_event_time_shows_the_state_before_the_event() -> Result<(), SolveError> {
    for method in Method::ALL {
        let mut log = Log::default();
        let opts = SolverOptions::default().method(method);
        integrate(&mut Jump, 0.0, &[0.0], 1.0, 0.25, &opts, &mut log)?;
        let kinds: String = log.0.iter().map(|e| e.0).collect();
        assert_eq!(kinds, "sssess", "{method}: {:?}", log.0);
        let (_, t_half, x_half) = log.0[2];
        assert_eq!(t_half, 0.5);
        assert!(
            (x_half - 0.5).abs() < 1e-12,
            "{method}: sample at 0.5 is {x_half}"
        );
        let (_, t_ev, x_after) = log.0[3];
        assert!(
            (0.5..=0.5 + 1e-12).contains(&t_ev),
            "{method}: event at {t_ev}"
        );
        assert!(
            (x_after - 10.5).abs() < 1e-12,
            "{method}: state after the event {x_after}"
        );
        let (_, t_end, x_end) = log.0[5];
        assert_eq!(t_end, 1.0);
        assert!((x_end - 11.0).abs() < 1e-12, "{method}: x(1) = {x_end}");
    }
    Ok(())
}

/// Projectile x'' = −g thrown up at g·1 m/s (apex 4.905 m at t = 1 s) with the event
/// g₀ = x − (apex − 1 mm): above the threshold only for |t − 1| < √(2·1e-3/g) ≈ 14.3 ms.
struct Graze {
    max_step: f64,
}

impl NoStepHooks for Graze {}

impl Formulation for Graze {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, G]
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        dy[0] = y[1];
        dy[1] = -G;
        Ok(())
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, y: &[f64], g: &mut [f64]) {
        g[0] = y[0] - (0.5 * G - 1e-3);
    }
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        self.max_step
    }
}

#[test]
fn grazing_event_is_found_only_with_max_step() -> Result<(), SolveError> {
    let half_window = (2.0 * 1e-3 / G).sqrt();
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        // max_step 10 ms < the 28.6 ms window: some step ends inside it, both crossings found.
        let mut rec = OdeRecorder::default();
        let mut f = Graze { max_step: 0.01 };
        integrate(&mut f, 0.0, &[0.0, G], 2.0, 0.5, &opts, &mut rec)?;
        let got: Vec<(Crossing, f64)> = rec
            .events
            .iter()
            .map(|(e, _, _)| (e.crossing, e.t))
            .collect();
        assert_eq!(got.len(), 2, "{method}: {got:?}");
        assert_eq!((got[0].0, got[1].0), (Crossing::Rising, Crossing::Falling));
        assert!(
            (got[0].1 - (1.0 - half_window)).abs() < 1e-11,
            "{method}: {got:?}"
        );
        assert!(
            (got[1].1 - (1.0 + half_window)).abs() < 1e-11,
            "{method}: {got:?}"
        );
        // Unlimited: the solution is a quadratic, the error estimate ~0, so the step grows by
        // the controller's largest factor and strides over the window: both crossings missed.
        let mut rec_free = OdeRecorder::default();
        let mut f = Graze {
            max_step: f64::INFINITY,
        };
        let stats = integrate(&mut f, 0.0, &[0.0, G], 2.0, 0.5, &opts, &mut rec_free)?;
        assert_eq!(
            rec.events.len() - rec_free.events.len(),
            2,
            "{method}: without max_step the grazing event should be missed (steps {stats:?})"
        );
    }
    Ok(())
}

#[test]
fn event_function_zero_at_the_start_is_not_an_event() -> Result<(), SolveError> {
    // Thrown up from the floor (g₀ = x = 0 exactly at t0): the look-ahead sees the ball rise,
    // so the first event is the landing at 2v₀/g, not t0.
    let v0 = 5.0;
    for method in Method::ALL {
        let opts = SolverOptions::default().method(method);
        let mut rec = OdeRecorder::default();
        let mut ball = Ball { restitution: None };
        integrate(&mut ball, 0.0, &[0.0, v0], 1.5, 0.1, &opts, &mut rec)?;
        let got: Vec<(Crossing, f64)> = rec
            .events
            .iter()
            .map(|(e, _, _)| (e.crossing, e.t))
            .collect();
        assert_eq!(got.len(), 1, "{method}: {got:?}");
        let landing = 2.0 * v0 / G;
        assert_eq!(got[0].0, Crossing::Falling, "{method}");
        assert!(
            (got[0].1 - landing).abs() <= 1e-12,
            "{method}: {got:?} vs {landing}"
        );
    }
    Ok(())
}
