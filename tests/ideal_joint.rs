//! Claim: making the clearance joint of `models/farahan2016.toml` ideal — `--ideal B` on the
//! command line, `idealise` in the library, or `ideal = true` in the file — gives the same model
//! as the separate all-ideal file `models/fourbar_ideal.toml` (same bodies, joint B an ideal pin),
//! so the same run to round-off; and a name that is no clearance joint is refused, naming it.

mod cli_common;
mod common;

use cli_common::{linkdyn, scratch};
use linkdyn::model::{JointKind, Model, idealise};
use linkdyn::simulation::{Simulation, SimulationOptions, Trajectory};

fn run(model: &Model) -> Trajectory {
    let options = SimulationOptions::default().revs(2.0).dt(1e-3);
    Simulation::new(model, options)
        .and_then(|s| s.run_to_memory())
        .unwrap_or_else(|e| panic!("{}: {e}", model.name))
}

/// Largest |a − b| over every sample of column `name`, and the largest |b| (its scale).
fn column_gap(a: &Trajectory, b: &Trajectory, name: &str) -> (f64, f64) {
    let (Some(x), Some(y)) = (a.column(name), b.column(name)) else {
        panic!("column {name} missing from one of the runs");
    };
    assert_eq!(x.len(), y.len(), "{name}: sample counts differ");
    x.iter().zip(y).fold((0.0, 0.0), |(gap, scale), (p, q)| {
        (f64::max(gap, (p - q).abs()), f64::max(scale, q.abs()))
    })
}

fn assert_same_run(case: &str, model: &Model) {
    let reference = common::load("models/fourbar_ideal.toml", &[]);
    let (a, b) = (run(model), run(&reference));
    assert_eq!(
        a.names, b.names,
        "{case}: output columns differ from fourbar_ideal.toml"
    );
    for name in &b.names {
        let (gap, scale) = column_gap(&a, &b, name);
        // The two models hold the same numbers in the same order, so the arithmetic is the
        // same: allow only round-off, 1e-12 of the column's scale (plus 1e-15 absolute for
        // columns that are zero throughout).
        assert!(
            gap <= 1e-12 * scale + 1e-15,
            "{case}: column {name} differs by {gap:e} (scale {scale:e})"
        );
    }
}

#[test]
fn idealised_clearance_joint_matches_the_ideal_file() {
    let model = common::load("models/farahan2016.toml", &[]);
    let ideal = idealise(model, &["B".to_string()]).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        ideal
            .joints
            .iter()
            .all(|j| !matches!(j.kind, JointKind::Clearance(_))),
        "joint B is still a clearance joint"
    );
    assert_eq!(
        ideal.source.overrides,
        vec!["joints.B.ideal=true".to_string()]
    );
    assert_same_run("idealise(B)", &ideal);
}

/// The file spelling, through the same override the provenance records: reloading a result's
/// model from its provenance gives the ideal model again.
#[test]
fn ideal_field_in_the_file_matches_the_ideal_file() {
    let model = common::load("models/farahan2016.toml", &["joints.B.ideal=true"]);
    assert_same_run("ideal = true", &model);
}

#[test]
fn unknown_or_ideal_joint_names_are_refused_naming_them() {
    let model = || common::load("models/farahan2016.toml", &[]);
    let unknown = idealise(model(), &["X".to_string()]).map(|_| ());
    assert_eq!(
        unknown.map_err(|e| e.to_string()),
        Err("models/farahan2016.toml: --ideal X: no joint named \"X\" in the model; its clearance joints are \"B\"".to_string())
    );
    let pin = idealise(model(), &["O2".to_string()]).map(|_| ());
    assert_eq!(
        pin.map_err(|e| e.to_string()),
        Err("models/farahan2016.toml: --ideal O2: joint \"O2\" is not a clearance joint (only a clearance joint can be made ideal); its clearance joints are \"B\"".to_string())
    );
}

/// The command line: `--ideal B` writes the same samples as the ideal file (header and data rows;
/// the `#` provenance lines differ by design), and `--ideal X` exits 2 naming X.
#[test]
fn cli_ideal_flag_matches_the_ideal_file_and_refuses_unknown_joints() {
    let dir = scratch("cli");
    let a = dir.join("a.csv");
    let b = dir.join("b.csv");
    let (a_s, b_s) = (a.to_string_lossy(), b.to_string_lossy());
    let args = ["--revs", "1", "--dt", "1e-3"];
    let (code, _, err) = linkdyn(
        &[
            &[
                "run",
                "models/farahan2016.toml",
                "--ideal",
                "B",
                "--out",
                &a_s,
            ][..],
            &args,
        ]
        .concat(),
    );
    assert_eq!(code, 0, "--ideal B: {err}");
    let (code, _, err) = linkdyn(
        &[
            &["run", "models/fourbar_ideal.toml", "--out", &b_s][..],
            &args,
        ]
        .concat(),
    );
    assert_eq!(code, 0, "fourbar_ideal: {err}");
    let data = |p: &std::path::Path| -> Vec<String> {
        std::fs::read_to_string(p)
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    let (rows_a, rows_b) = (data(&a), data(&b));
    assert_eq!(rows_a.len(), rows_b.len(), "row counts");
    // Same arithmetic (see above): the printed samples are the same to the last digit.
    for (k, (x, y)) in rows_a.iter().zip(&rows_b).enumerate() {
        assert_eq!(x, y, "row {k} differs");
    }
    let (code, _, err) = linkdyn(&[
        "run",
        "models/farahan2016.toml",
        "--ideal",
        "X",
        "--out",
        &a_s,
    ]);
    assert_eq!(code, 2, "--ideal X exit code; stderr: {err}");
    assert_eq!(
        err,
        "error: models/farahan2016.toml: --ideal X: no joint named \"X\" in the model; its clearance joints are \"B\"\n"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
