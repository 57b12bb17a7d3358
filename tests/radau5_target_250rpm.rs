//! The implicit integrator's target (docs/numerics.md), stated as work: on farahan2016 at 250
//! rpm over 2 crank turns, an angle error ≤ 1e-8 rad against a tight reference in fewer than
//! 35 000 right-hand-side evaluations (LSODA's count there). RHS counts are deterministic,
//! so this is an assertion, not a timing; wall time is in `benches/radau5.rs`.
//!
//! Met by the DAE (Radau5, rtol 5e-9) and by the reduced formulation (Radau5, rtol 1e-8), both
//! with the cut of steps at events and the friction law's kinks as event functions at which the
//! steps end, the reduced one also since Radau5 resets its Newton convergence estimate at
//! restarts (docs/numerics.md, "The reduced formulation meets the target").

mod common;

use common::{load, run_formulation};
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::solve::{Method, Recorder, SolverStats};

/// 2 turns at 250 rpm (s).
const T_END: f64 = 2.0 * 60.0 / 250.0;
/// The work-precision grid: 4000 samples over the run (s).
const DT: f64 = T_END / 4000.0;

/// Largest |Δφ| of the coupler and the rocker over the common samples (rad).
fn angle_error(a: &Recorder, b: &Recorder) -> f64 {
    let mut worst: f64 = 0.0;
    for col in ["coupler.phi", "rocker.phi"] {
        let (Some(x), Some(y)) = (a.column(col), b.column(col)) else {
            panic!("no column {col}");
        };
        assert_eq!(x.len(), y.len(), "{col}: sample counts differ");
        for (p, q) in x.iter().zip(&y) {
            worst = worst.max((p - q).abs());
        }
    }
    worst
}

/// Runs `f` with Radau5 at `rtol` (atol 1e-3 rtol) and with the DOP853 reference at rtol 1e-12,
/// checks that both see the same events in the same order and kind — impacts and separations
/// (event 0) and the friction kinks (events 1–4) — with the 43 impacts and separations of
/// farahan2016 at 250 rpm over 2 turns, and returns the angle error (rad) and the run's
/// statistics.
fn radau5_against_reference<F: Formulation + Outputs + Clone>(
    mut f: F,
    rtol: f64,
) -> (f64, SolverStats) {
    let (reference, _) = run_formulation(
        &mut f.clone(),
        T_END,
        DT,
        Method::Dop853,
        1e-12,
        1e-12 * 1e-3,
    );
    let (rec, stats) = run_formulation(&mut f, T_END, DT, Method::Radau5, rtol, rtol * 1e-3);
    let kinds =
        |r: &Recorder| -> Vec<_> { r.events.iter().map(|e| (e.index, e.crossing)).collect() };
    assert_eq!(
        kinds(&rec),
        kinds(&reference),
        "events: Radau5 {}, reference {}",
        rec.events.len(),
        reference.events.len()
    );
    let impacts = rec.events.iter().filter(|e| e.index == 0).count();
    assert_eq!(
        impacts, 43,
        "impacts and separations of farahan2016 at 250 rpm, 2 turns"
    );
    (angle_error(&rec, &reference), stats)
}

#[test]
fn dae_radau5_reaches_1e_8_rad_in_fewer_than_35k_rhs() {
    let model = load("models/farahan2016.toml", &[]);
    // With the friction kinks as events, as `Simulation` builds the DAE for Radau5.
    let dae = Dae::new(&model, &DaeOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .friction_kink_events(true);
    // DOP853 at rtol 1e-12: 1.7e-11 rad from DOPRI5 at the same tolerance (docs/numerics.md).
    let (err, stats) = radau5_against_reference(dae, 5e-9);
    // Measured (2026-11-26): 2.7e-9 rad with 33 630 RHS (Jacobians are analytic: no RHS
    // calls); margins 73 % (error) and 4 % (RHS). Both bounds are the issue's. Without the
    // kink events the same rtol gives 2.1e-8 rad (rtol 3e-9: 7.9e-9 rad with 34 924 RHS), so
    // undoing them shows here (docs/numerics.md, "The reduced formulation meets the target").
    assert!(
        err <= 1e-8 && stats.rhs_evals < 35_000,
        "DAE Radau5 rtol 5e-9: angle error {err:e} rad with {} RHS ({stats:?})",
        stats.rhs_evals
    );
}

#[test]
fn reduced_radau5_reaches_1e_8_rad_in_fewer_than_35k_rhs() {
    let model = load("models/farahan2016.toml", &[]);
    let reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    // DOP853 at rtol 1e-12: 6.6e-12 rad from DOPRI5 at the same tolerance (docs/numerics.md).
    let (err, stats) = radau5_against_reference(reduced, 1e-8);
    // Measured (2026-11-26): 8.4e-9 rad with 31 824 RHS (analytic Jacobian: no RHS calls in
    // it). The bounds are the issue's; the margins are 16 % (error) and 9 % (RHS). Without the
    // kink events the same run gives 4.9e-8 rad, without the reset of Newton's convergence
    // estimate at restarts 6.7e-7 rad, without both 8.7e-6 rad (docs/numerics.md), so either
    // change undone shows here.
    assert!(
        err <= 1e-8 && stats.rhs_evals < 35_000,
        "reduced Radau5 rtol 1e-8: angle error {err:e} rad with {} RHS ({stats:?})",
        stats.rhs_evals
    );
}
