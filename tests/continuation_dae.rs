//! Continuation of the DAE's periodic orbits (docs/periodic_orbits.md, "The DAE's orbits"): the
//! corrector steps in the consistent directions and makes every iterate consistent, as the
//! shooting does. Checked against the reduced formulation on the reference four-bar at
//! 3500 rpm (Farahan et al. 2016, Table 1, `models/farahan2016.toml`) over the clearance's
//! period-doubling bubble, 0.44 → 0.40 mm: the same two period doublings, at the same
//! clearances to within a few percent of the bubble's width (the multipliers in contact are
//! ~1e-3 accurate, which sets how well a crossing of −1 is located; docs/periodic_orbits.md,
//! "What is not done"), and the same orbit at the branch's end.

use linkdyn::analysis::orbit::{BranchEnd, SpecialKind};
use linkdyn::simulation::{FormulationKind, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions};
use linkdyn::studies::continuation::{ContinuationRequest, ContinuationResult, continuation};

const MODEL: &str = "models/farahan2016.toml";

fn branch(kind: FormulationKind) -> ContinuationResult {
    let text = std::fs::read_to_string(MODEL).unwrap_or_else(|e| panic!("{e}"));
    let overrides = vec!["drivers.motor.speed_rpm=3500".to_string()];
    continuation(&ContinuationRequest {
        model_path: MODEL.as_ref(),
        model_text: &text,
        overrides: &overrides,
        parameter: "joints.B.clearance",
        from: 0.44e-3,
        to: 0.40e-3,
        step: Some(5e-6),
        period_turns: 1,
        guess_from_turn: 3,
        follow_doublings: 0,
        options: SimulationOptions::default().formulation(kind).solver(
            SolverOptions::default()
                .method(Method::Dop853)
                .rtol(1e-10)
                .atol(1e-12),
        ),
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

fn doublings(r: &ContinuationResult) -> Vec<f64> {
    r.special_points
        .iter()
        .filter(|p| p.special == Some(SpecialKind::PeriodDoubling))
        .map(|p| p.parameter)
        .collect()
}

#[test]
fn the_dae_s_branch_has_the_reduced_formulation_s_period_doublings_and_end() {
    let reduced = branch(FormulationKind::Reduced);
    let dae = branch(FormulationKind::Dae);
    for r in [&reduced, &dae] {
        assert_eq!(r.end, BranchEnd::Reached, "{:?}", r.end);
        assert!(r.unlocated.is_empty(), "{:?}", r.unlocated);
    }
    let (pd_reduced, pd_dae) = (doublings(&reduced), doublings(&dae));
    assert_eq!(pd_reduced.len(), 2, "{pd_reduced:?}");
    assert_eq!(pd_dae.len(), 2, "{pd_dae:?}");
    // The bubble is 7e-6 m wide; measured 2.9e-7 and 6e-8 m apart (2026-11-28).
    for (a, b) in pd_dae.iter().zip(&pd_reduced) {
        assert!(
            (a - b).abs() < 5e-7,
            "period doublings at {pd_dae:?} and {pd_reduced:?}"
        );
    }
    // Every point's multipliers: four nontrivial ones; the DAE's constraint directions and
    // its stored impact velocity trivial (19 states, 4 coordinates).
    let dae_rows: Vec<_> = dae.rows.iter().filter(|r| r.turn == 0).collect();
    assert!(dae_rows.iter().all(|r| r.floquet_multipliers.len() == 4));
    // The orbit at the branch's end, c = 0.40 mm, where both branches stop exactly.
    let (a, b) = (
        dae_rows.last().unwrap_or_else(|| panic!("no rows")),
        reduced
            .rows
            .iter()
            .rfind(|r| r.turn == 0)
            .unwrap_or_else(|| panic!("no rows")),
    );
    assert_eq!((a.parameter, b.parameter), (0.40e-3, 0.40e-3));
    let rocker = |r: &ContinuationResult, row: &linkdyn::studies::continuation::ContinuationRow| {
        let k = r
            .names
            .iter()
            .position(|n| n == "rocker.phi")
            .unwrap_or_else(|| panic!("no rocker.phi in {:?}", r.names));
        row.state[k]
    };
    let (ra, rb) = (rocker(&dae, a), rocker(&reduced, b));
    assert!(
        (ra - rb).abs() < 1e-8,
        "rocker.phi at 0.40 mm: DAE {ra}, reduced {rb}"
    );
    assert!(
        (a.max_abs_mu - b.max_abs_mu).abs() < 1e-2,
        "largest |mu| at 0.40 mm: DAE {}, reduced {}",
        a.max_abs_mu,
        b.max_abs_mu
    );
    assert_eq!(a.stable, b.stable);
}
