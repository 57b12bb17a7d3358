//! Claim (docs/formulations.md): the generalised-coordinate formulation, the absolute-coordinate DAE and
//! the paper's reduced Lagrangian model are three formulations of the same four-bar with a
//! clearance joint (models/farahan2016.toml): over two crank turns they give the same impacts
//! at the same times and the same angles to a bound set by the tolerance, and the generalised
//! formulation keeps |Φ| at Newton's tolerance (no drift) where the DAE's drifts.

mod common;
use common::*;
use linkdyn::analysis::compare;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Generalized, Outputs, ReducedLagrangian};
use linkdyn::solve::{Method, Recorder};

/// Tolerances of all runs (as tests/dae_vs_reduced.rs).
const RTOL: f64 = 1e-11;
const ATOL: f64 = 1e-14;

/// Bound on the angle difference, as a multiple of `RTOL · max|θ|`: the impacts amplify each
/// run's local errors into a global error that `linkdyn compare` measured at 8–29 × rtol ·
/// max|θ| for the DAE against the reduced model (tests/dae_vs_reduced.rs); the generalised
/// formulation's error is of the same kind. 300 is ten times the worst.
const ANGLE_FACTOR: f64 = 300.0;

fn run<F: Formulation + Outputs>(f: &mut F, t_end: f64) -> Recorder {
    run_formulation(f, t_end, 1e-4, Method::Dop853, RTOL, ATOL).0
}

fn agree_over_two_turns(speed_rpm: f64) {
    let set = format!("drivers.motor.speed_rpm={speed_rpm}");
    let model = load("models/farahan2016.toml", &[&set]);
    let t_end = 2.0 * 60.0 / speed_rpm;
    let mut generalized =
        Generalized::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        generalized.dof(),
        2,
        "the journal's two freedoms in the clearance"
    );
    let g = run(&mut generalized, t_end);
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let d = run(&mut dae, t_end);
    let mut reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let r = run(&mut reduced, t_end);
    for (other, name) in [(&d, "DAE"), (&r, "reduced")] {
        let c = compare(&g, other, 1);
        for column in ["coupler.phi", "rocker.phi"] {
            let diff = c
                .column(column)
                .unwrap_or_else(|| panic!("{speed_rpm} rpm: no column {column}"));
            let bound = ANGLE_FACTOR * RTOL * diff.max_abs_value;
            assert!(
                diff.max_abs_difference < bound,
                "{speed_rpm} rpm {column}: generalized and {name} differ by {:e} rad at t = {}, bound {bound:e} rad",
                diff.max_abs_difference,
                diff.at_t
            );
        }
        assert!(c.impacts_a[0] > 0, "{speed_rpm} rpm: no impact at all");
        assert_eq!(
            c.impacts_a[0], c.impacts_b[0],
            "{speed_rpm} rpm: impact counts generalized vs {name}"
        );
        let dt = c.max_impact_time_difference[0].unwrap_or(f64::INFINITY);
        // 1e-7 s: the bound of tests/dae_vs_reduced.rs; impacts are located to 1e-12
        // relative on each run's dense output.
        assert!(
            dt <= 1e-7,
            "{speed_rpm} rpm: impact times generalized vs {name} differ by up to {dt:e} s"
        );
    }
    // No drift: Newton's tolerance is 1e-12 L (L ≈ 1 m here); the DAE's |Φ| is the
    // Baumgarte-controlled drift, larger.
    assert!(
        g.max_constraint_violation < 1e-11,
        "{speed_rpm} rpm: generalized |Φ| = {:e}",
        g.max_constraint_violation
    );
}

#[test]
fn generalized_agrees_with_dae_and_reduced_at_250_rpm() {
    agree_over_two_turns(250.0);
}

#[test]
fn generalized_agrees_with_dae_and_reduced_at_3500_rpm() {
    agree_over_two_turns(3500.0);
}
