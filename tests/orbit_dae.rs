//! Periodic orbits of the DAE (absolute coordinates, any linkage; docs/periodic_orbits.md,
//! "The DAE's orbits"): the shooting steps in the directions a consistent state can move in and
//! makes every iterate consistent, so the DAE's constraint directions are neither unknowns nor
//! multipliers.
//!
//! * The reference four-bar at 3500 rpm, c = 0.44 mm: the DAE's orbit is the reduced
//!   formulation's (the same section state to 1e-8 rad and 1e-9 m, the same dominant
//!   multiplier to 1e-3, the same impact), with 2 × 7 constraint directions and the inactive
//!   stored impact velocity counted as trivial.
//! * A slider on a spring-damper under the force F0 sin(w t) (`tests/fixtures/
//!   forced_slider.toml`, a model without a driver, `period` in seconds): the orbit is the
//!   closed-form steady state and the multipliers are exp(λT), λ the free system's
//!   eigenvalues (L. Meirovitch, *Fundamentals of Vibrations*, McGraw-Hill, 2001, §3.2 and
//!   §1.10; G. Teschl, *Ordinary Differential Equations and Dynamical Systems*, AMS, 2012,
//!   §3.6).
//! * The slider-crank with clearance joints at both pins of its rod (`models/
//!   slider_crank_clearance.toml`, which the reduced formulation cannot take): both journals
//!   stay in contact all along, their stored impact velocities are parameters of the orbit
//!   (multiplier exactly 1, trivial), and the long run from the same start reaches the orbit.
//! * The generalised formulation is refused with the reason; a model the reduced formulation
//!   (the default) does not take is pointed to the DAE.

use linkdyn::simulation::{FormulationKind, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions};
use linkdyn::studies::orbit::{OrbitPeriod, OrbitRequest, OrbitResult, orbit};

fn load(path: &str, sets: &[&str]) -> linkdyn::model::Model {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    linkdyn::model::load(path.as_ref(), &sets).unwrap_or_else(|e| panic!("{e}"))
}

fn options(kind: FormulationKind, rtol: f64) -> SimulationOptions {
    SimulationOptions::default().formulation(kind).solver(
        SolverOptions::default()
            .method(Method::Dop853)
            .rtol(rtol)
            .atol(rtol * 1e-2),
    )
}

fn find(
    model: &linkdyn::model::Model,
    options: SimulationOptions,
    period: OrbitPeriod,
) -> OrbitResult {
    let request = OrbitRequest {
        options,
        period,
        guess_from_turn: 3,
        dt: 1e-4,
    };
    orbit(model, &request).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_dae_orbit_of_the_four_bar_is_the_reduced_formulation_s() {
    let model = load(
        "models/farahan2016.toml",
        &["drivers.motor.speed_rpm=3500", "joints.B.clearance=0.44e-3"],
    );
    let reduced = find(
        &model,
        options(FormulationKind::Reduced, 1e-10),
        OrbitPeriod::Turns(1),
    );
    let dae = find(
        &model,
        options(FormulationKind::Dae, 1e-10),
        OrbitPeriod::Turns(1),
    );
    for (name, tolerance) in [
        ("rocker.phi", 1e-8),
        ("coupler.phi", 1e-8),
        ("B.ex", 1e-9),
        ("B.ey", 1e-9),
    ] {
        let (a, b) = (dae.state[name], reduced.state[name]);
        assert!((a - b).abs() < tolerance, "{name}: DAE {a}, reduced {b}");
    }
    // Four nontrivial multipliers (the four-bar with a clearance joint has two degrees of
    // freedom); the DAE's 19 states less the 2 × 7 constraint directions and the stored impact
    // velocity, which the impact of the period overwrites and nothing reads at the section.
    assert_eq!(reduced.floquet_multipliers.len(), 4);
    assert_eq!(dae.floquet_multipliers.len(), 4);
    assert_eq!(dae.trivial_multipliers, 15);
    // The dominant multiplier (0.247): the monodromy in contact is ~1e-3 accurate
    // (docs/periodic_orbits.md, "What is not done"), the two formulations agree to 2e-4.
    let (a, b) = (dae.floquet_multipliers[0], reduced.floquet_multipliers[0]);
    assert!(a[1] == 0.0 && b[1] == 0.0, "{a:?} {b:?}");
    assert!(
        (a[0] - b[0]).abs() < 1e-3 * b[0].abs(),
        "DAE {a:?}, reduced {b:?}"
    );
    assert!(dae.stable && reduced.stable);
    assert_eq!(dae.impacts_per_period, 1);
    assert_eq!(reduced.impacts_per_period, 1);
    let (ga, gb) = (
        dae.min_gap_m.unwrap_or(0.0),
        reduced.min_gap_m.unwrap_or(0.0),
    );
    assert!(
        gb < 0.0 && (ga - gb).abs() < 1e-9,
        "smallest gaps {ga} and {gb}"
    );
    assert!(
        dae.closing_error < 1e3,
        "closing error {}",
        dae.closing_error
    );
}

#[test]
fn the_forced_slider_s_orbit_is_the_steady_state_and_its_multipliers_are_exp_lambda_t() {
    const OMEGA0: f64 = 3.0; // √(k/m), k = 9 N/m, m = 1 kg
    const ZETA: f64 = 0.05; // c/(2 m ω0), c = 0.3 N·s/m
    const W: f64 = 2.2;
    const F0: f64 = 2.0; // N, on 1 kg
    let period = std::f64::consts::TAU / W;
    let model = load("tests/fixtures/forced_slider.toml", &[]);
    let found = find(
        &model,
        options(FormulationKind::Dae, 1e-11),
        OrbitPeriod::Seconds(period),
    );
    // x(t) = A sin(w t − ϕ) at the section t0 = 3T, where w t0 is a whole number of turns.
    let amplitude =
        F0 / ((OMEGA0 * OMEGA0 - W * W).powi(2) + (2.0 * ZETA * OMEGA0 * W).powi(2)).sqrt();
    let lag = (2.0 * ZETA * OMEGA0 * W).atan2(OMEGA0 * OMEGA0 - W * W);
    let (x0, v0) = (-amplitude * lag.sin(), amplitude * W * lag.cos());
    assert!((found.t_section_s - 3.0 * period).abs() < 1e-12);
    for (name, want) in [("slider.x", x0), ("slider.vx", v0)] {
        let got = found.state[name];
        assert!(
            (got - want).abs() < 1e-8,
            "{name} = {got}, steady state {want}"
        );
    }
    for name in ["slider.y", "slider.phi", "slider.vy", "slider.omega"] {
        assert!(
            found.state[name].abs() < 1e-12,
            "{name} = {}",
            found.state[name]
        );
    }
    // One degree of freedom: two multipliers; the rail's two rows give 2 × 2 constraint
    // directions of the 6 states.
    assert_eq!(found.trivial_multipliers, 4);
    assert_eq!(found.floquet_multipliers.len(), 2);
    let decay = (-ZETA * OMEGA0 * period).exp();
    let turn = OMEGA0 * (1.0 - ZETA * ZETA).sqrt() * period;
    let want = [decay * turn.cos(), decay * turn.sin()];
    for mu in &found.floquet_multipliers {
        assert!(
            (mu[0] - want[0]).abs() < 1e-8 && (mu[1].abs() - want[1]).abs() < 1e-8,
            "multiplier {mu:?}, exp(λT) = {want:?} ± i"
        );
    }
    assert!(found.stable);
    assert_eq!(found.period_turns, None);
}

#[test]
fn the_slider_crank_s_orbit_with_both_pins_in_contact_is_where_the_long_run_goes() {
    let model = load("models/slider_crank_clearance.toml", &[]);
    let opts = options(FormulationKind::Dae, 1e-10);
    let found = find(&model, opts.clone(), OrbitPeriod::Turns(1));
    // Both journals press on their bearings all period: no impact, the deepest penetration
    // below zero gap, and the two stored impact velocities kept (multipliers exactly 1,
    // trivial) with the 2 × 5 constraint directions of the 20 states.
    assert_eq!(found.impacts_per_period, 0);
    assert!(
        found.min_gap_m.unwrap_or(0.0) < 0.0,
        "{:?}",
        found.min_gap_m
    );
    assert_eq!(found.trivial_multipliers, 12);
    assert_eq!(found.floquet_multipliers.len(), 8);
    assert!(found.stable, "{:?}", found.floquet_multipliers);
    // The long run from the same start, 9 turns past the section (the largest |μ| is ~0.03:
    // any remaining transient shrinks below 1e-13), is on the orbit at the same crank phase.
    let sim = Simulation::new(&model, opts.revs(12.0).dt(1e-3)).unwrap_or_else(|e| panic!("{e}"));
    let run = sim.run_to_memory().unwrap_or_else(|e| panic!("{e}"));
    let last = run.t.len() - 1;
    assert!(
        (run.t[last] - 12.0 * found.period_s).abs() < 1e-12,
        "{}",
        run.t[last]
    );
    for (name, tolerance) in [
        ("rod.phi", 1e-8),
        ("slider.x", 1e-9),
        ("A.ex", 1e-9),
        ("A.ey", 1e-9),
        ("B.ex", 1e-9),
        ("B.ey", 1e-9),
    ] {
        let k = run
            .names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        let (long, orbit) = (run.columns[k][last], found.state[name]);
        assert!(
            (long - orbit).abs() < tolerance,
            "{name}: long run {long}, orbit {orbit}"
        );
    }
}

/// The message of `orbit`'s refusal of `model` with the formulation `kind`.
fn refusal(model: &str, kind: FormulationKind, period: OrbitPeriod) -> String {
    let request = OrbitRequest {
        options: options(kind, 1e-8),
        period,
        guess_from_turn: 3,
        dt: 1e-3,
    };
    match orbit(&load(model, &[]), &request) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("{model} was accepted with the {kind} formulation"),
    }
}

#[test]
fn the_generalised_formulation_is_refused_with_the_reason() {
    assert_eq!(
        refusal(
            "tests/fixtures/forced_slider.toml",
            FormulationKind::Generalized,
            OrbitPeriod::Seconds(1.0)
        ),
        "formulation: periodic orbits are computed with the reduced formulation or the DAE: the generalized formulation recovers its dependent coordinates by Newton's method at every stage and corrects them at step ends, which the variational equations do not follow; use `formulation` dae (any linkage) or reduced (the four-bar with one clearance joint)"
    );
}

#[test]
fn a_model_the_reduced_formulation_refuses_is_pointed_to_the_dae() {
    assert_eq!(
        refusal(
            "models/slider_crank_clearance.toml",
            FormulationKind::Reduced,
            OrbitPeriod::Turns(1)
        ),
        "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 2; the dae formulation takes any linkage"
    );
}
