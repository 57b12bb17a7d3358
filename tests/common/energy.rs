//! Runs of the reference four-bar with and without energy bookkeeping, and the check that the
//! bookkeeping leaves the motion unchanged (shared by the explicit/Radau5 and the IDA tests).

use super::ode::OdeRecorder;
use linkdyn::formulation::{Dae, DaeOptions, Formulation};
use linkdyn::solve::{EventRecord, SolverOptions, SolverStats, integrate};

/// farahan2016's DAE, two crank turns at 250 rpm (0.48 s), samples every ms, with `opts`.
/// Returns the samples and events, the statistics and the number of body states (coordinates
/// and velocities).
pub fn run_farahan(energy: bool, opts: &SolverOptions) -> (OdeRecorder, SolverStats, usize) {
    let model = super::load("models/farahan2016.toml", &[]);
    let options = DaeOptions {
        energy,
        ..DaeOptions::default()
    };
    let mut dae = Dae::new(&model, &options).unwrap_or_else(|e| panic!("{e}"));
    let body_states = 2 * dae.n_coordinates();
    let y0 = dae.initial_state();
    let mut rec = OdeRecorder::default();
    let stats = integrate(&mut dae, 0.0, &y0, 0.48, 1e-3, opts, &mut rec)
        .unwrap_or_else(|e| panic!("energy {energy}, {}: {e}", opts.method));
    (rec, stats, body_states)
}

/// Asserts the same sample times, the first `n` (body) states bit-identical at every sample,
/// and the same impacts (more than ten) in both runs; `label` names the case.
pub fn assert_same_motion(label: &str, plain: &OdeRecorder, booked: &OdeRecorder, n: usize) {
    let times = |r: &OdeRecorder| r.samples.iter().map(|(t, _)| *t).collect::<Vec<_>>();
    assert_eq!(times(plain), times(booked), "{label}: sample times");
    for ((t, a), (_, b)) in plain.samples.iter().zip(&booked.samples) {
        for i in 0..n {
            assert!(
                a[i].to_bits() == b[i].to_bits(),
                "{label}: state {i} at t = {t} s: {} without, {} with energy bookkeeping",
                a[i],
                b[i]
            );
        }
    }
    let events = |r: &OdeRecorder| r.events.iter().map(|e| e.0).collect::<Vec<EventRecord>>();
    assert!(plain.events.len() > 10, "{label}: expected impacts");
    assert_eq!(
        events(plain),
        events(booked),
        "{label}: impact and separation times"
    );
}
