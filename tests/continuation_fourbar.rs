//! The reference four-bar (Farahan et al. 2016, Table 1, `models/farahan2016.toml`) at
//! 3500 rpm: its period-1 orbit continued in the radial clearance from 0.44 mm down to
//! 0.40 mm, against brute-force Poincaré sections (what `linkdyn bifurcation` records per
//! point, docs/sweeps.md).
//!
//! The brute-force Fig. 6a sweeps (docs/reproduce.md, "Speed of Fig. 6a") read period-1
//! everywhere but a few grid points between 0.405 and 0.419 mm, which read period-2. The
//! continuation must find the same: the branch loses stability by a period doubling and
//! regains it by a second one inside that interval; a brute-force section in the middle of the
//! unstable stretch is period-2, and the sections at the period-1 points of the branch nearest
//! the interval on either side, and at both ends, are period-1 and sit on the branch.

use linkdyn::analysis::PeriodVerdict;
use linkdyn::analysis::orbit::{BranchEnd, SpecialKind};
use linkdyn::simulation::analyses::{self, SectionSpec};
use linkdyn::simulation::{FormulationKind, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolverOptions};
use linkdyn::studies::continuation::{ContinuationRequest, ContinuationResult, continuation};

const MODEL: &str = "models/farahan2016.toml";
const SPEED: &str = "drivers.motor.speed_rpm=3500";
const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;

fn options() -> SimulationOptions {
    SimulationOptions::default()
        .formulation(FormulationKind::Reduced)
        .solver(
            SolverOptions::default()
                .method(Method::Dop853)
                .rtol(RTOL)
                .atol(ATOL),
        )
}

fn branch() -> ContinuationResult {
    let text = std::fs::read_to_string(MODEL).unwrap_or_else(|e| panic!("{e}"));
    let overrides = vec![SPEED.to_string()];
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
        options: options(),
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The brute-force section of clearance `c`: 150 turns, the last 30 recorded (rocker.phi).
fn brute_force(c: f64) -> (PeriodVerdict, Vec<f64>) {
    let sets = vec![SPEED.to_string(), format!("joints.B.clearance={c}")];
    let model = linkdyn::model::load(MODEL.as_ref(), &sets).unwrap_or_else(|e| panic!("{e}"));
    let sim = Simulation::new(&model, options().revs(150.0)).unwrap_or_else(|e| panic!("{e}"));
    let section = analyses::poincare(
        &sim,
        &SectionSpec {
            turns: 150,
            transient: 120,
            phase: 0.0,
            observe: vec!["rocker.phi".into()],
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (
        section.period.verdict,
        section.section.points.iter().map(|p| p[0]).collect(),
    )
}

#[test]
fn the_branch_loses_period_one_where_the_brute_force_sections_do() {
    let b = branch();
    assert_eq!(b.end, BranchEnd::Reached);
    assert!(b.unlocated.is_empty(), "{:?}", b.unlocated);
    let phi = b
        .names
        .iter()
        .position(|n| n == "rocker.phi")
        .unwrap_or_else(|| panic!("no rocker.phi in {:?}", b.names));
    let specials: Vec<(SpecialKind, f64)> = b
        .special_points
        .iter()
        .filter_map(|r| r.special.map(|k| (k, r.parameter)))
        .collect();
    assert_eq!(specials.len(), 2, "{specials:?}");
    assert!(
        specials
            .iter()
            .all(|(k, c)| *k == SpecialKind::PeriodDoubling && (0.405e-3..0.419e-3).contains(c)),
        "two period doublings within the brute-force sweeps' period-2 points: {specials:?}"
    );
    let (lo, hi) = (specials[1].1, specials[0].1);
    for r in &b.rows {
        // One impact per turn along the whole branch: no grazing.
        assert_eq!(r.impacts_per_period, 1, "c = {}", r.parameter);
        assert!(
            r.residual <= 1e3,
            "c = {}: residual {}",
            r.parameter,
            r.residual
        );
        if r.special.is_none() {
            assert_eq!(
                r.stable,
                !(lo..=hi).contains(&r.parameter),
                "c = {}: unstable exactly between the period doublings {lo} and {hi}, max |μ| {}",
                r.parameter,
                r.max_abs_mu
            );
        }
    }

    // Brute force in the middle of the unstable stretch: period-2.
    let (verdict, _) = brute_force(0.5 * (lo + hi));
    assert!(
        matches!(verdict, PeriodVerdict::Period { k: 2, .. }),
        "c = {}: {verdict:?}",
        0.5 * (lo + hi)
    );
    // Brute force at the ends and at the period-1 points nearest the stretch whose transient
    // has died out within 120 turns (max |μ| ≤ 0.85: 0.85^120 ≈ 3e-9): period-1, on the branch.
    let settled = |r: &&linkdyn::studies::continuation::ContinuationRow| {
        r.special.is_none() && r.max_abs_mu <= 0.85
    };
    let above = b
        .rows
        .iter()
        .filter(|r| r.parameter > hi)
        .filter(settled)
        .min_by(|x, y| x.parameter.total_cmp(&y.parameter));
    let below = b
        .rows
        .iter()
        .filter(|r| r.parameter < lo)
        .filter(settled)
        .max_by(|x, y| x.parameter.total_cmp(&y.parameter));
    let ends = [b.rows.first(), b.rows.last()];
    for r in [above, below].into_iter().chain(ends).flatten() {
        let (verdict, points) = brute_force(r.parameter);
        assert!(
            matches!(verdict, PeriodVerdict::Period { k: 1, .. }),
            "c = {}: {verdict:?}",
            r.parameter
        );
        // The branch's points close to within 1000 ε (ε = atol + rtol|φ|); the fixed point
        // is then within 1000 ε/(1 − |μ|) of them.
        let eps = ATOL + RTOL * r.state[phi].abs();
        let bound = 1e3 * eps / (1.0 - r.max_abs_mu);
        for p in &points {
            assert!(
                (p - r.state[phi]).abs() < bound,
                "c = {}: branch rocker.phi {}, brute-force point {p}, bound {bound:.2e}",
                r.parameter,
                r.state[phi]
            );
        }
    }
}
