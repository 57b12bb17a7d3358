//! The classic linkages shipped in models/ and written with parameters, templates, tables and
//! output points: each is accepted by `linkdyn check` and runs with `linkdyn run`; the
//! quick-return mechanism returns twice as fast as it cuts (2 acos(r/d) = 120° of crank turn
//! for the return stroke); the Watt six-bar's output rocker swings over the range its
//! position analysis gives.

mod cli_common;
mod common;
use cli_common::{linkdyn, scratch};
use common::*;
use linkdyn::solve::Method;

#[test]
fn the_new_models_check_and_run() {
    let dir = scratch("runs");
    for (model, extra) in [
        ("models/watt_sixbar.toml", vec!["--revs", "1"]),
        ("models/quick_return.toml", vec!["--revs", "1"]),
        ("models/slider_crank_gas.toml", vec!["--revs", "2"]),
        ("models/parallel_fourbar_chain.toml", vec!["--t-end", "0.5"]),
    ] {
        let (code, _, stderr) = linkdyn(&["check", model]);
        assert_eq!(code, 0, "check {model}: {stderr}");
        let out = dir.join("out.csv").display().to_string();
        let mut args = vec!["run", model, "--dt", "1e-3", "--out", &out];
        args.extend(extra);
        let (code, _, stderr) = linkdyn(&args);
        assert_eq!(code, 0, "run {model}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn quick_return_cuts_for_two_thirds_of_the_turn() {
    let m = load("models/quick_return.toml", &[]);
    // One turn at 60 rpm is 1 s; 1e-4 s samples resolve the fraction to 1e-4.
    let (rec, _) = run_dae(&m, 1.0, 1e-4, Method::Dop853, 1e-10, 1e-12);
    let vx = col(&rec, "ram.vx");
    let forward = vx.iter().filter(|v| **v > 0.0).count() as f64 / vx.len() as f64;
    assert!(
        (forward - 1.0 / 3.0).abs() < 1e-3,
        "quick return: ram moves +x for {forward} of the turn, expected 1/3"
    );
}

#[test]
fn watt_output_rocker_swings_over_its_geometric_range() {
    let m = load("models/watt_sixbar.toml", &[]);
    let (rec, _) = run_dae(&m, 0.5, 1e-4, Method::Dop853, 1e-10, 1e-12);
    let phi = col(&rec, "output.phi");
    let (lo, hi) = phi
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    // Position analysis of the two loops at 200 000 crank angles: 1.28700 … 1.59256 rad.
    // The sampled extremes fall short by at most ω² dt²/2 · |φ''| ~ 1e-6 rad.
    assert!(
        (lo - 1.28700).abs() < 2e-5,
        "Watt output: min φ6 = {lo}, expected 1.28700"
    );
    assert!(
        (hi - 1.59256).abs() < 2e-5,
        "Watt output: max φ6 = {hi}, expected 1.59256"
    );
}
