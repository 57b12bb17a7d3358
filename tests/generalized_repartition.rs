//! Claim (docs/formulations.md): the generalised-coordinate formulation repartitions when the chosen
//! independent coordinate stops parametrising the motion, at a located event, and the run goes
//! on with no constraint drift, conserving energy and agreeing with the DAE.
//!
//! Fixture: a non-Grashof four-bar (tests/fixtures/triple_rocker.toml) circulating under
//! gravity round its single configuration circuit. Every link angle, the crank's included,
//! passes extrema on that circuit (the crank's where coupler and rocker are collinear), so the
//! first independent coordinate (crank.phi) must be given up there while Φ_q keeps full rank:
//! exactly the case repartitioning exists for, which no shipped model exercises.

mod common;
use common::*;
use linkdyn::analysis::compare;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Generalized};
use linkdyn::solve::Method;

const FIXTURE: &str = "tests/fixtures/triple_rocker.toml";
/// About six passages of the circuit's turning points.
const T_END: f64 = 3.0;
const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;

#[test]
fn a_degenerating_partition_is_switched_and_the_run_agrees_with_the_dae() {
    let model = load(FIXTURE, &[]);
    let mut generalized =
        Generalized::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let y0 = generalized.initial_state();
    assert_eq!(generalized.dof(), 1, "{FIXTURE}: one degree of freedom");
    assert_eq!(
        generalized.independent(&y0),
        vec![2],
        "{FIXTURE}: the crank angle is the first independent coordinate"
    );
    let (g, stats) = run_formulation(&mut generalized, T_END, 1e-3, Method::Dop853, RTOL, ATOL);
    let repartitions = generalized.repartitions();
    // The crank angle has two extrema per oscillation, and every angle taken up instead has its
    // own; measured 10 switches over 3 s (2026-11-23). At least 4 says that the switch happened
    // more than once and back (a single spurious switch would give 1).
    assert!(
        repartitions >= 4,
        "{FIXTURE}: only {repartitions} repartitions over {T_END} s"
    );
    // Each is one located event of the repartition function that restarted the integrator.
    let index = generalized.repartition_event();
    let switches = g
        .events
        .iter()
        .filter(|e| e.index == index && e.restarted)
        .count();
    assert_eq!(
        switches, repartitions,
        "{FIXTURE}: repartition events that restarted vs the formulation's count"
    );
    assert_eq!(
        stats.restarts as usize, repartitions,
        "{FIXTURE}: restarts vs repartitions (no clearance joint, so no other event)"
    );
    // The crank angle does turn back (so crank.phi cannot stay independent).
    let crank = col(&g, "crank.phi");
    let reversals = crank
        .windows(3)
        .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
        .count();
    assert!(
        reversals >= 2,
        "{FIXTURE}: the crank angle reversed {reversals} times only"
    );
    // No drift by construction: Newton's tolerance (1e-12 L, L ≈ 1.3 m) at every sample and
    // step end, through every switch; 1e-11 m leaves a factor of about 8.
    assert!(
        g.max_constraint_violation < 1e-11,
        "{FIXTURE}: |Φ| reached {:e} m",
        g.max_constraint_violation
    );
    // Energy: no driver, no damping, gravity only: T + U is conserved to the integration
    // error, measured (2026-11-23) at 2.4e-8 J of |E| ≤ 10.7 J for rtol 1e-10 (2.2e-9
    // relative); the bound 1e-7·|E| leaves a factor 45, while a switch that jumped the state
    // at the restart shows as a step far above it.
    let energy = mechanical_energy(&model, &g);
    let drift = energy
        .iter()
        .fold(0.0_f64, |m, e| m.max((e - energy[0]).abs()));
    let scale = energy.iter().fold(0.0_f64, |m, e| m.max(e.abs())).max(1.0);
    assert!(
        drift < 1e-7 * scale,
        "{FIXTURE}: energy drifts by {drift:e} J (scale {scale:e} J), bound {:e} J",
        1e-7 * scale
    );
    // The DAE integrates the same motion in absolute coordinates (no partition).
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let (d, _) = run_formulation(&mut dae, T_END, 1e-3, Method::Dop853, RTOL, ATOL);
    let c = compare(&g, &d, 0);
    for column in ["crank.phi", "coupler.phi", "rocker.phi"] {
        let diff = c
            .column(column)
            .unwrap_or_else(|| panic!("no column {column}"));
        // Both runs' global errors at rtol 1e-10 over 3 s of a smooth motion: measured
        // (2026-11-23) at 1.5–2.3e-8 rad; 1e-6 leaves a factor 40, while a switch that lost
        // the circuit's direction or jumped the state gives an O(1e-2) rad difference.
        let bound = 1e-6;
        println!(
            "{column}: {:e} rad at t = {} s",
            diff.max_abs_difference, diff.at_t
        );
        assert!(
            diff.max_abs_difference < bound,
            "{FIXTURE} {column}: generalized and DAE differ by {:e} rad at t = {} s, bound {bound:e} rad",
            diff.max_abs_difference,
            diff.at_t
        );
    }
}
