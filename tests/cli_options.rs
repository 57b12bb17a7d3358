//! Options of `linkdyn run` are checked by the library before any work and refused with exit
//! code 2 and a message naming the option — negative numbers included, which clap must pass
//! on as values — and the library exposes no command-line types.

use std::path::Path;

mod cli_common;
use cli_common::{linkdyn, scratch};

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Runs `run` on `model` with `extra` options; asserts exit 2, the exact message, and that
/// nothing was written.
fn refused(model: &str, extra: &[&str], expected: &str) {
    let dir = scratch("refused");
    let out = dir.join("r.csv").display().to_string();
    let mut args = vec!["run", model];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", &out]);
    let (code, stdout, stderr) = linkdyn(&args);
    assert_eq!(code, 2, "{extra:?}: exit code {code}, stderr {stderr}");
    assert_eq!(stderr.trim_end(), format!("error: {expected}"), "{extra:?}");
    assert!(stdout.is_empty(), "{extra:?}: stdout {stdout}");
    assert!(
        entries(&dir).is_empty(),
        "{extra:?}: left {:?}",
        entries(&dir)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn negative_numbers_reach_the_range_checks() {
    let fourbar = "models/fourbar_ideal.toml";
    refused(
        fourbar,
        &["--dt", "-1"],
        "--dt: expected a positive time step, got -1",
    );
    refused(
        fourbar,
        &["--revs", "-1"],
        "--revs: expected a positive, finite number of turns, got -1",
    );
    refused(
        fourbar,
        &["--t-end", "-0.5"],
        "--t-end: expected a positive, finite end time, got -0.5 s",
    );
    // The range of rtol is SolverOptions::validate's: check the option and the value only.
    let dir = scratch("rtol");
    let out = dir.join("r.csv").display().to_string();
    let (code, _, stderr) = linkdyn(&["run", fourbar, "--rtol", "-1", "--out", &out]);
    assert_eq!(code, 2, "--rtol -1: {stderr}");
    assert!(
        stderr.starts_with("error: --rtol: expected ") && stderr.trim_end().ends_with("got -1"),
        "--rtol -1: {stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--rtol 1` and `--atol 0` are refused by the range rule of `SolverOptions::validate`
/// (rtol in [10ε, 0.1], atol in (0, 1]).
#[test]
fn out_of_range_tolerances_are_refused_naming_the_option() {
    for (option, value) in [("--rtol", "1"), ("--atol", "0")] {
        let dir = scratch("tol");
        let out = dir.join("r.csv").display().to_string();
        let (code, _, stderr) = linkdyn(&[
            "run",
            "models/fourbar_ideal.toml",
            option,
            value,
            "--out",
            &out,
        ]);
        assert_eq!(code, 2, "{option} {value}: {stderr}");
        assert!(
            stderr.starts_with(&format!("error: {option}: ")),
            "{option} {value}: {stderr}"
        );
        assert!(entries(&dir).is_empty(), "{option} {value}: files written");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn settings_that_do_not_fit_the_model_are_refused_before_any_work() {
    refused(
        "models/pendulum.toml",
        &[],
        "--revs: counts turns of the single driver, but model \"pendulum\" has 0 drivers: give --t-end",
    );
    refused(
        "models/farahan2016.toml",
        &["--formulation", "reduced", "--energy"],
        "--energy: the energy bookkeeping is available for the DAE formulation only",
    );
    refused(
        "models/fourbar_ideal.toml",
        &["--method", "rk4"],
        "--method: expected \"dopri5\", \"dop853\" or \"radau5\", got \"rk4\"",
    );
    refused(
        "models/fourbar_ideal.toml",
        &["--formulation", "reduced"],
        "models/fourbar_ideal.toml: reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0",
    );
    // 1e5 s at the default 1e-4 s is 1e9 samples of 47 values: refused before integrating
    // (which would take hours), not after.
    let dir = scratch("cap");
    let out = dir.join("r.csv").display().to_string();
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--t-end",
        "1e5",
        "--out",
        &out,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.starts_with("error: --dt: 1e-4 s over 1e5 s asks for 1.000e9 samples × ")
            && stderr
                .trim_end()
                .ends_with("at most 1e9 are allowed: raise --dt"),
        "{stderr}"
    );
    assert!(entries(&dir).is_empty(), "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_library_names_no_command_line_crate() {
    // The CLI lives in the binary (src/main.rs, src/cli/); the library must not depend on
    // clap or anyhow, so that the Python bindings and other front ends do not either.
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut stack = vec![src.clone()];
    let mut offenders = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .filter_map(|e| e.ok())
        {
            let path = entry.path();
            if path == src.join("cli") || path == src.join("main.rs") {
                continue;
            }
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                if text.contains("clap::") || text.contains("anyhow") || text.contains("mod cli") {
                    offenders.push(path.display().to_string());
                }
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "library files naming clap/anyhow/cli: {offenders:?}"
    );
}

#[test]
fn a_law_switch_prints_the_dropped_fields_as_a_note() {
    let (code, stdout, stderr) = linkdyn(&[
        "check",
        "models/farahan2016.toml",
        "--set",
        "joints.B.friction.law=none",
    ]);
    assert_eq!(code, 0, "stderr: {stderr}");
    assert!(
        stderr.starts_with(
            "note: --set joints.B.friction.law=none: dropped coefficient = 0.1, v0 = 0.0001, v1 = 0.001 from joints.B.friction, which friction law \"none\" does not take\n"
        ),
        "stderr: {stderr}"
    );
    assert!(stdout.contains("farahan2016"), "stdout: {stdout}");
}

#[test]
fn max_wall_bounds_a_run_with_exit_3_and_leaves_no_files() {
    let dir = scratch("wall");
    let out = dir.join("r.csv");
    let out_s = out.to_string_lossy().into_owned();
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/farahan2016.toml",
        "--revs",
        "200",
        "--max-wall",
        "1e-4",
        "--out",
        &out_s,
    ]);
    assert_eq!(code, 3, "stderr: {stderr}");
    assert!(
        stderr.starts_with("error: stopped after ")
            && stderr.contains(" s of wall-clock time (limit max_wall = 0.0001 s) at t = ")
            && stderr.contains(" of t_end = 48"),
        "stderr: {stderr}"
    );
    assert!(entries(&dir).is_empty(), "files left: {:?}", entries(&dir));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_help_lists_every_method_with_its_description() {
    let (code, stdout, _) = linkdyn(&["run", "--help"]);
    assert_eq!(code, 0);
    for m in linkdyn::solve::Method::ALL {
        let line = format!("{m}: {}", m.description());
        assert!(
            stdout.contains(&line),
            "`{line}` missing from run --help:\n{stdout}"
        );
    }
}
