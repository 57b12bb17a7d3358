//! The absolute-coordinate DAE and the paper's reduced Lagrangian model are two independent
//! formulations of the same four-bar with a clearance joint: over two crank turns they must give
//! the same angles (to a bound set by the tolerance), the same journal orbit, the same impacts at
//! the same times, and the same contact force and crank torque (to bounds that follow from the
//! orbit's agreement).

mod cli_common;
mod common;
use cli_common::{linkdyn, path_arg, scratch};
use common::*;
use linkdyn::analysis::compare;
use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::solve::{Method, Recorder};

/// Relative tolerance of both runs; absolute tolerance far below every state's size.
const RTOL: f64 = 1e-11;
const ATOL: f64 = 1e-14;

/// Bound on the angle difference, as a multiple of `RTOL · max|θ|`. Each run keeps its local
/// error per step below `rtol·|y|`; over two turns the impacts amplify it into a global error
/// that `linkdyn compare` measured (2026-11-23) at 8–29 × rtol · max|θ| for every rtol from 1e-8 to
/// 1e-11 (so it is truncation error, scaling with rtol, not round-off). 300 is ten times the
/// worst: a larger difference means different physics, not a different step sequence.
const ANGLE_FACTOR: f64 = 300.0;

/// Generalised stiffness K (N/m^1.5) and exponent of the model's contact: the reference check
/// value of docs/reference_parameters.md (steel, R_J = 10 mm, c = 0.5 mm).
const K: f64 = 6.9494e10;
const N: f64 = 1.5;

/// Crank length L2 (m), docs/reference_parameters.md.
const CRANK: f64 = 0.25;

fn run<F: Formulation + Outputs>(f: &mut F, t_end: f64) -> Recorder {
    run_formulation(f, t_end, 1e-4, Method::Dop853, RTOL, ATOL).0
}

fn agree_over_two_turns(speed_rpm: f64) {
    let set = format!("drivers.motor.speed_rpm={speed_rpm}");
    let model = load("models/farahan2016.toml", &[&set]);
    let t_end = 2.0 * 60.0 / speed_rpm;
    let mut dae = Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let mut reduced = ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"));
    let a = run(&mut dae, t_end);
    let b = run(&mut reduced, t_end);
    let c = compare(&a, &b, 1);
    let diff = |column: &str| {
        c.column(column)
            .unwrap_or_else(|| panic!("{speed_rpm} rpm: no column {column}"))
    };
    let mut angle_bound: f64 = 0.0;
    for column in ["coupler.phi", "rocker.phi"] {
        let d = diff(column);
        let bound = ANGLE_FACTOR * RTOL * d.max_abs_value;
        angle_bound = angle_bound.max(bound);
        assert!(
            d.max_abs_difference < bound,
            "{speed_rpm} rpm {column}: DAE and reduced differ by {:e} rad at t = {}, bound {bound:e} rad",
            d.max_abs_difference,
            d.at_t
        );
    }
    assert!(c.impacts_a[0] > 0, "{speed_rpm} rpm: no impact at all");
    assert_eq!(
        c.impacts_a[0], c.impacts_b[0],
        "{speed_rpm} rpm: impact counts DAE vs reduced"
    );
    let dt = c.max_impact_time_difference[0].unwrap_or(f64::INFINITY);
    // 1e-7 s: the bound; impacts are located to 1e-12 relative on each run's dense output.
    assert!(
        dt <= 1e-7,
        "{speed_rpm} rpm: impact times differ by up to {dt:e} s"
    );
    // Journal orbit (m): the eccentricity is a difference of link-end positions, so it moves by
    // at most the longest link (the coupler, 0.75 m) times the angle bound.
    let e_bound = 0.75 * angle_bound;
    let mut de: f64 = 0.0;
    for column in ["B.ex", "B.ey"] {
        let d = diff(column);
        de = de.max(d.max_abs_difference);
        assert!(
            d.max_abs_difference < e_bound,
            "{speed_rpm} rpm {column}: DAE and reduced differ by {:e} m, bound {e_bound:e} m",
            d.max_abs_difference
        );
    }
    // Normal force: F_N = K δⁿ (1 + χ δ̇/δ̇⁽⁻⁾) with dF/dδ = n F/δ, so a penetration difference
    // Δδ ≤ √2 · max(Δex, Δey) moves F_N by at most n F_max Δδ/δ_max relative to the largest force,
    // δ_max = (F_max/K)^(1/n) being the deepest penetration; the damping term moves with δ̇ in the
    // same proportion, hence a factor 2 (χ < 1 for c_r = 0.9).
    let fn_diff = diff("B.fn");
    let f_max = fn_diff.max_abs_value;
    let delta_max = (f_max / K).powf(1.0 / N);
    let fn_relative = 2.0 * N * std::f64::consts::SQRT_2 * de / delta_max;
    assert!(
        f_max > 0.0 && fn_diff.max_abs_difference < fn_relative * f_max,
        "{speed_rpm} rpm B.fn: DAE and reduced differ by {:e} N at t = {} (max {f_max:e} N), bound {:e} N",
        fn_diff.max_abs_difference,
        fn_diff.at_t,
        fn_relative * f_max
    );
    // Crank torque: it passes the contact force to the crank through a lever no longer than the
    // crank; the inertial share differs far less (the angles agree to the bound above).
    let m_diff = diff("motor.torque");
    let m_bound = CRANK * fn_relative * f_max;
    assert!(
        m_diff.max_abs_difference < m_bound,
        "{speed_rpm} rpm motor.torque: DAE and reduced differ by {:e} N·m at t = {} (max {:e} N·m), bound {m_bound:e} N·m",
        m_diff.max_abs_difference,
        m_diff.at_t,
        m_diff.max_abs_value
    );
}

#[test]
fn formulations_agree_at_250_rpm() {
    agree_over_two_turns(250.0);
}

#[test]
fn formulations_agree_at_3500_rpm() {
    agree_over_two_turns(3500.0);
}

#[test]
fn reduced_formulation_refuses_another_topology_with_a_clear_reason() {
    let model = load("models/fourbar_ideal.toml", &[]);
    let err = ReducedLagrangian::new(&model).err().map(|e| e.to_string());
    assert_eq!(
        err.as_deref(),
        Some(
            "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0"
        )
    );
}

#[test]
fn compare_command_prints_and_writes_the_differences() {
    let dir = scratch("compare");
    let json = dir.join("cmp.json");
    let (code, stdout, stderr) = linkdyn(&[
        "compare",
        "models/farahan2016.toml",
        "--revs",
        "0.25",
        "--rtol",
        "1e-10",
        "--atol",
        "1e-13",
        "--out",
        path_arg(&json),
    ]);
    assert_eq!(code, 0, "{stderr}");
    for column in [
        "coupler.phi",
        "rocker.phi",
        "B.ex",
        "B.ey",
        "B.fn",
        "motor.torque",
    ] {
        assert!(stdout.contains(column), "{column} missing from:\n{stdout}");
    }
    let text = std::fs::read_to_string(&json).unwrap_or_default();
    let report: serde_json::Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"));
    let comparison = &report["comparison"];
    let a = comparison["impacts_a"][0].as_u64().unwrap_or(0);
    assert!(
        a > 0 && Some(a) == comparison["impacts_b"][0].as_u64(),
        "impact counts: {comparison}"
    );
    let theta3 = comparison["columns"]
        .as_array()
        .and_then(|c| c.iter().find(|c| c["column"] == "coupler.phi"))
        .and_then(|c| c["max_abs_difference"].as_f64())
        .unwrap_or(f64::INFINITY);
    // ANGLE_FACTOR · rtol · max|θ3| (0.94 rad), as in `agree_over_two_turns`.
    let bound = ANGLE_FACTOR * 1e-10 * 0.94;
    assert!(
        theta3 < bound,
        "compare --rtol 1e-10: theta3 difference {theta3:e} rad, bound {bound:e} rad"
    );
    assert!(report["provenance"]["linkdyn_version"].is_string());
    let _ = std::fs::remove_dir_all(&dir);
}
