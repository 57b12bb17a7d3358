//! The constraint violation |Φ| is checked at every accepted step end, not only at the output
//! samples, against the bound of `linkdyn::formulation::dae::violation_limit`; a run whose
//! motion leaves the joints stops with exit 3 and a message naming the time, the constraint row
//! and the value, and the JSON's `max_constraint_violation` is the maximum over every step.
//! The shipped models never come near the bound at any tolerance from 1e-4 to 1e-12.

mod cli_common;

use cli_common::{linkdyn, path_arg, scratch};
use linkdyn::formulation::dae::violation_limit;
use linkdyn::formulation::{Dae, DaeOptions, FormulationError, StepHooks, Tolerances};
use linkdyn::simulation::{Discard, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolveError, SolverOptions};

/// The tolerances of the step-end checks below.
const TOLERANCES: Tolerances = Tolerances {
    rtol: 1e-8,
    atol: 1e-10,
};

fn load(path: &str, sets: &[&str]) -> linkdyn::model::Model {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    linkdyn::model::load(path.as_ref(), &sets).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn a_drifting_run_stops_with_the_time_the_row_and_the_value() {
    // The reference four-bar with Baumgarte's stabilisation switched off and a loose tolerance:
    // nothing pulls the integration error of the positions back, the joints drift apart and
    // pass the bound 100·(rtol·L + atol) ≈ 2e-2 m (L = 0.96 m) within the first second.
    let dir = scratch("drift");
    let out = dir.join("drift.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--set",
        "settings.baumgarte.alpha=0",
        "--set",
        "settings.baumgarte.beta=0",
        "--method",
        "dopri5",
        "--rtol",
        "1e-4",
        "--atol",
        "1e-4",
        "--revs",
        "20",
        "--dt",
        "1e-2",
        "--out",
        path_arg(&out),
    ]);
    assert_eq!(code, 3, "{stderr}");
    assert_eq!(
        stderr.trim_end(),
        "error: the equations of motion could not be evaluated at t = 2.003971632 s: constraint \"O4.y\" is violated by |Φ| = 2.001e-2 m at t = 2.003971632 s, beyond the bound 1.962e-2 m (min(0.1 L, 100·(rtol·L + atol)) with the length scale L = 9.624e-1 m and the controlled tolerances rtol = 1e-4, atol = 1e-4, at least the round-off floor 100 ε κ L with κ = 9.946e1): the motion no longer satisfies the joints; tighten rtol/atol, raise the Baumgarte factors, or check that the linkage can move as driven"
    );
    assert!(!out.exists(), "no partial result file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sample_between_step_ends_is_held_to_the_bound_too() {
    // At rtol 0.1, atol 1 every step end of the double pendulum passed the old check while the
    // dense output between them put samples 2.02 m off the joints (exit 0). The bound is the cap
    // 0.1 L = 0.1231 m here; the first sample beyond it, on the 1e-4 s output grid, stops the run.
    let dir = scratch("sample-drift");
    let out = dir.join("drift.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/double_pendulum.toml",
        "--t-end",
        "2",
        "--rtol",
        "0.1",
        "--atol",
        "1",
        "--out",
        path_arg(&out),
    ]);
    assert_eq!(code, 3, "{stderr}");
    assert!(
        stderr.starts_with("error: the equations of motion could not be evaluated at t = 0.469000000 s: constraint \"A.x\" is violated by |Φ| = 1.233e-1 m at t = 0.469000000 s, beyond the bound 1.231e-1 m"),
        "{stderr}"
    );
    assert!(!out.exists(), "no partial result file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_state_off_the_joints_is_refused_at_the_step_end() {
    use linkdyn::formulation::Formulation;
    let model = load("models/pendulum.toml", &[]);
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let mut y = dae.initial_state();
    let (limit, _) = violation_limit(dae.length_scale(), 1e-8, 1e-10);
    // Exactly on the bound passes (|Φ| ≤ bound); twice the bound in x does not.
    y[0] += 2.0 * limit;
    let err = dae.accept_step(0.5, &mut y, TOLERANCES).err();
    match err {
        Some(FormulationError::ConstraintViolation {
            t,
            constraint,
            value,
            limit: l,
            unit,
            ..
        }) => {
            assert_eq!(
                (t, &*constraint, unit.to_string().as_str()),
                (0.5, "O.x", "m")
            );
            // Φ_x moved by exactly the shift (to round-off of the assembled zero).
            assert!(
                (value - 2.0 * limit).abs() < 1e-12,
                "value {value} vs {}",
                2.0 * limit
            );
            assert_eq!(l, limit);
        }
        other => panic!("expected a constraint violation, got {other:?}"),
    }
    // A NaN coordinate is a violation too, never a pass.
    let mut y = dae.initial_state();
    y[1] = f64::NAN;
    assert!(dae.accept_step(0.5, &mut y, TOLERANCES).is_err());
}

#[test]
fn the_bound_follows_the_tolerance_up_to_its_cap() {
    // L = 1 m: 100·(rtol + atol) down to the tightest tolerance (no floor: the survey of
    // docs/numerics.md, "The constraint-violation bound", found none needed), cap 0.1 m.
    let (m, rad) = violation_limit(1.0, 1e-12, 1e-12);
    assert!(
        (m - 2e-10).abs() < 1e-24 && (rad - 2e-10).abs() < 1e-24,
        "{m} {rad}"
    );
    let (m, rad) = violation_limit(1.0, 1e-4, 0.0);
    assert!(
        (m - 1e-2).abs() < 1e-15 && (rad - 1e-2).abs() < 1e-15,
        "{m} {rad}"
    );
    assert_eq!(violation_limit(1.0, 0.1, 1.0), (0.1, 0.1));
}

/// Every shipped model at rtol = atol = tol: no run stops for its constraint violation, and
/// where the run succeeds, the maximum over every step end stays ten times below the bound.
#[test]
fn the_shipped_models_never_come_near_the_bound() {
    let mut checked = 0;
    for entry in std::fs::read_dir("models").unwrap_or_else(|e| panic!("{e}")) {
        let path = entry.unwrap_or_else(|e| panic!("{e}")).path();
        let name = path.display().to_string();
        let model = load(&name, &[]);
        let dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        for tol in [1e-4, 1e-8, 1e-12] {
            for method in [Method::Dopri5, Method::Dop853] {
                let solver = SolverOptions::default().method(method).rtol(tol).atol(tol);
                // Half a driver turn, or 1 s for models without a driver: long enough for the
                // drift to settle where Baumgarte's term holds it (1/β = 0.1 s).
                let options = if model.drivers.is_empty() {
                    SimulationOptions::default().t_end(1.0)
                } else {
                    SimulationOptions::default().revs(0.5)
                };
                let sim = Simulation::new(&model, options.dt(1e-2).solver(solver))
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                let (limit_m, limit_rad) = violation_limit(dae.length_scale(), tol, tol);
                let limit = limit_m.min(limit_rad);
                match sim.run(&mut Discard) {
                    Ok(summary) => {
                        checked += 1;
                        assert!(
                            summary.max_constraint_violation < 0.1 * limit,
                            "{name}, {method}, tol {tol:e}: max |Φ| {:e} vs a tenth of the bound {:e}",
                            summary.max_constraint_violation,
                            0.1 * limit
                        );
                    }
                    // Loose tolerances can fail for other reasons (a clearance joint at
                    // atol = 1e-4 > its clearance's tenth); never for the violation bound.
                    Err(linkdyn::Error::Solve(SolveError::Formulation {
                        source: e @ FormulationError::ConstraintViolation { .. },
                        ..
                    })) => panic!("{name}, {method}, tol {tol:e}: {e}"),
                    Err(_) => {}
                }
            }
        }
    }
    assert!(checked >= 30, "only {checked} runs succeeded");
}

#[test]
fn the_summary_maximum_covers_every_step_not_only_the_samples() {
    // The double pendulum at a loose tolerance sampled only at t = 0 and t = 3 s: between the
    // two samples some hundred steps drift and are pulled back by Baumgarte's term, so the
    // maximum over the step ends is larger than over the two samples.
    let model = load("models/double_pendulum.toml", &[]);
    let solver = SolverOptions::default().rtol(1e-4).atol(1e-4);
    let sim = Simulation::new(
        &model,
        SimulationOptions::default()
            .t_end(3.0)
            .dt(3.0)
            .solver(solver),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let run = sim.run_to_memory().unwrap_or_else(|e| panic!("{e}"));
    let at_samples = run
        .constraint_violation
        .iter()
        .fold(0.0_f64, |m, v| m.max(*v));
    assert_eq!(run.t.len(), 2, "two samples");
    assert!(
        run.summary.max_constraint_violation > at_samples,
        "max over steps {:e} vs over the samples {at_samples:e}",
        run.summary.max_constraint_violation
    );
}
