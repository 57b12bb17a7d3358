//! The analysis tools on the reference four-bar with a clearance joint (reduced Lagrangian
//! formulation: contact events and a bookkeeping state, the stored impact velocity y[4]):
//! the Poincaré section is exactly the run's own samples at the section instants, and the
//! Lyapunov pair integrates the contacts of both trajectories.

mod common;
use common::load;

use linkdyn::analysis::lyapunov::{LyapunovOptions, largest_lyapunov};
use linkdyn::analysis::poincare::{SectionOptions, section_states};
use linkdyn::formulation::{Formulation, ReducedLagrangian};
use linkdyn::solve::{Sink, SolveError, SolverOptions, integrate};

/// The reference model at 250 rpm (many impacts per turn) and its crank period (s).
fn fourbar() -> (ReducedLagrangian, f64) {
    let model = load("models/farahan2016.toml", &[]);
    match ReducedLagrangian::new(&model) {
        Ok(f) => (f, 60.0 / 250.0),
        Err(e) => panic!("{e}"),
    }
}

fn options() -> SolverOptions {
    match SolverOptions::default().rtol(1e-8).atol(1e-11).build() {
        Ok(o) => o,
        Err(e) => panic!("{e}"),
    }
}

/// Keeps every sampled state.
struct States(Vec<(f64, Vec<f64>)>);
impl<F> Sink<F> for States {
    fn sample(&mut self, _f: &F, t: f64, y: &[f64]) -> Result<(), SolveError> {
        self.0.push((t, y.to_vec()));
        Ok(())
    }
}

/// Section over `n` periods (no transient) and its number of events.
fn section(n: usize) -> (Vec<(f64, Vec<f64>)>, u64) {
    let (mut f, period) = fourbar();
    let y0 = f.initial_state();
    let s = SectionOptions {
        period,
        phase_offset: 0.0,
        n_transient: 0,
        n_points: n + 1,
    };
    match section_states(&mut f, 0.0, &y0, &s, None, &options()) {
        Ok(s) => (s.times.into_iter().zip(s.points).collect(), s.stats.events),
        Err(e) => panic!("section of {n} periods: {e}"),
    }
}

#[test]
fn section_equals_the_runs_samples_at_the_section_instants() {
    // Same integrator, options and steps; integrate samples t0 + k·dt_out and the section
    // t0 + k·T from the same dense output: the numbers must be identical, impacts and all.
    let (points, events) = section(4);
    assert!(events > 0, "no impacts in 4 turns at 250 rpm");
    let (mut f, period) = fourbar();
    let y0 = f.initial_state();
    let mut run = States(Vec::new());
    let r = integrate(&mut f, 0.0, &y0, 4.0 * period, period, &options(), &mut run);
    assert!(r.is_ok(), "{r:?}");
    assert_eq!(run.0.len(), points.len());
    for (k, ((ts, ys), (tr, yr))) in points.iter().zip(&run.0).enumerate() {
        assert_eq!(ts, tr, "section time {k}");
        assert_eq!(ys, yr, "section point {k} at t = {ts} s");
    }
}

#[test]
fn lyapunov_pair_integrates_both_trajectories_contacts() {
    // The two trajectories start 1e-7 apart and stay close (the estimate is negative here), so
    // each has the reference's impacts: the pair sees twice the events of one trajectory after
    // the transient. Event counts from runs of 3 and 3 + 8 turns.
    let (f, period) = fourbar();
    let (_, events_transient) = section(3);
    let (_, events_total) = section(11);
    let lo = LyapunovOptions {
        d0: 1e-7,
        tau: period,
        n_intervals: 8,
        t_transient: 3.0 * period,
        bookkeeping: vec![false, false, false, false, true],
        ..LyapunovOptions::default()
    };
    let y0 = f.initial_state();
    let e = match largest_lyapunov(&f, 0.0, &y0, &lo, &options()) {
        Ok(e) => e,
        Err(e) => panic!("{e}"),
    };
    let expected = events_transient + 2 * (events_total - events_transient);
    eprintln!(
        "four-bar 250 rpm: λ = {:.3} 1/s ± {:.3}, events {} (expected {expected})",
        e.exponent, e.uncertainty, e.stats.events
    );
    assert!(e.exponent.is_finite() && e.history.len() == 8, "{e:?}");
    // ±2: an impact that falls on a renormalisation instant may be located in either interval.
    assert!(
        e.stats.events.abs_diff(expected) <= 2,
        "pair events {} vs {expected} (transient {events_transient}, one trajectory {events_total})",
        e.stats.events
    );
}
