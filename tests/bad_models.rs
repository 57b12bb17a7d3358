//! Every file in tests/bad_models/ is refused by `linkdyn check` with exit code 2 and exactly the
//! one-line message below (file, line:column, field, what was expected), never a panic.

use std::process::Command;

const CASES: &[(&str, &str)] = &[
    (
        "clearance_field_on_revolute",
        "tests/bad_models/clearance_field_on_revolute.toml:37:13: joints.A.clearance: field `clearance` does not belong to a revolute joint; expected only body_a, point_a, body_b, point_b",
    ),
    (
        "clearance_too_large_eccentricity",
        "tests/bad_models/clearance_too_large_eccentricity.toml:24:24: joints.C.initial_eccentricity: initial eccentricity |e| = 1.000000e-3 m exceeds the clearance 5.000000e-4 m; expected the journal inside the bearing",
    ),
    (
        "driver_on_prismatic",
        "tests/bad_models/driver_on_prismatic.toml:41:9: drivers.motor.joint: driver \"motor\" drives joint \"A\", which is prismatic; a constant-speed driver needs a revolute joint",
    ),
    (
        "driver_two_speeds",
        "tests/bad_models/driver_two_speeds.toml:43:9: drivers.motor.speed: give either `speed_rpm` or `speed` (rad/s), not both",
    ),
    (
        "driver_unknown_joint",
        "tests/bad_models/driver_unknown_joint.toml:41:9: drivers.motor.joint: unknown joint \"O2\" in driver \"motor\": did you mean \"O\"?",
    ),
    (
        "joint_to_itself",
        "tests/bad_models/joint_to_itself.toml:31:8: joints.A.name: joint \"A\" connects \"crank\" to itself; expected two different bodies",
    ),
    (
        "missing_model_name",
        "tests/bad_models/missing_model_name.toml:2:1: model: missing field `name`",
    ),
    (
        "negative_mass",
        "tests/bad_models/negative_mass.toml:10:8: bodies.crank.mass: expected a positive mass (kg), found -0.5",
    ),
    (
        "no_bodies",
        "tests/bad_models/no_bodies.toml: expected at least one [[bodies]] entry",
    ),
    (
        "non_finite_mass",
        "tests/bad_models/non_finite_mass.toml:10:8: bodies.crank.mass: expected a finite mass (kg), found NaN",
    ),
    (
        "syntax_error",
        "tests/bad_models/syntax_error.toml:6:26: (TOML syntax): missing comma between array elements, expected `,`",
    ),
    (
        "unassemblable",
        "tests/bad_models/unassemblable.toml: the linkage cannot be assembled: the constraint of joint \"B\" is still off by 2.000e-1 (m or rad) after 1 Newton iterations; check the link lengths and the bodies' initial guesses",
    ),
    (
        "unknown_body",
        "tests/bad_models/unknown_body.toml:35:10: joints.A.body_b: unknown body \"rood\" in joint \"A\": did you mean \"rod\"?",
    ),
    (
        "unknown_field",
        "tests/bad_models/unknown_field.toml:12:1: bodies.crank.colour: unknown field `colour`, expected one of `name`, `mass`, `inertia`, `points`, `initial`",
    ),
    (
        "unknown_joint_type",
        "tests/bad_models/unknown_joint_type.toml:32:8: joints.A.type: unknown joint type \"revolut\"; expected \"revolute\", \"prismatic\" or \"clearance\": did you mean \"revolute\"?",
    ),
    (
        "unknown_point",
        "tests/bad_models/unknown_point.toml:36:11: joints.A.point_b: unknown point \"Z\" on body \"rod\" in joint \"A\"; body \"rod\" has points A, B",
    ),
    (
        "wrong_type",
        "tests/bad_models/wrong_type.toml:10:8: bodies.crank.mass: invalid type: string \"heavy\", expected f64",
    ),
    (
        "zero_inertia",
        "tests/bad_models/zero_inertia.toml:11:11: bodies.crank.inertia: expected a positive moment of inertia (kg·m²), found 0",
    ),
];

fn linkdyn(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_linkdyn"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn each_bad_model_is_refused_with_its_exact_message_and_exit_code_2() {
    for (name, expected) in CASES {
        let path = format!("tests/bad_models/{name}.toml");
        let (code, stdout, stderr) = linkdyn(&["check", &path]);
        assert_eq!(code, 2, "{name}: exit code {code}, stderr {stderr}");
        assert_eq!(stderr.trim_end(), format!("error: {expected}"), "{name}");
        assert!(stdout.is_empty(), "{name}: nothing on stdout, got {stdout}");
    }
}

#[test]
fn every_file_in_the_corpus_has_a_case() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_models");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{e}"))
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            e.path()
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
        })
        .collect();
    files.sort();
    let cases: Vec<String> = CASES.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        files, cases,
        "tests/bad_models/ and CASES must list the same files"
    );
    assert!(cases.len() >= 12);
}

#[test]
fn bad_set_overrides_are_refused_with_exit_code_2() {
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "drivers.motr.speed_rpm=3500",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim_end(),
        "error: --set drivers.motr.speed_rpm=3500: no entry named \"motr\" in drivers: did you mean \"motor\"?"
    );
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.mass=-1",
    ]);
    assert_eq!(code, 2);
    // Located in the file where the overridden field stands, and naming the override.
    assert_eq!(
        stderr.trim_end(),
        "error: models/fourbar_ideal.toml:17:8: bodies.crank.mass: expected a positive mass (kg), found -1 (value from --set bodies.crank.mass=-1)"
    );
    let (code, _, stderr) = linkdyn(&[
        "check",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.colour=red",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim_end(),
        "error: models/fourbar_ideal.toml: bodies.crank.colour: unknown field `colour`, expected one of `name`, `mass`, `inertia`, `points`, `initial` (value from --set bodies.crank.colour=red)"
    );
}

#[test]
fn a_failed_run_writes_no_result_file() {
    let dir = std::env::temp_dir().join(format!("linkdyn-bad-run-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let out = dir.join("r.csv");
    let out_s = out.display().to_string();
    // An rtol of zero is refused before anything runs.
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--rtol",
        "0",
        "--out",
        &out_s,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        !out.exists() && !dir.join("r.json").exists(),
        "no partial result files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn same_model_and_settings_give_identical_numbers() {
    let dir = std::env::temp_dir().join(format!("linkdyn-repro-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let mut bodies = Vec::new();
    for k in 0..2 {
        let out = dir.join(format!("r{k}.csv"));
        let (code, _, stderr) = linkdyn(&[
            "run",
            "models/fourbar_ideal.toml",
            "--revs",
            "0.5",
            "--dt",
            "1e-3",
            "--out",
            &out.display().to_string(),
        ]);
        assert_eq!(code, 0, "{stderr}");
        let text = std::fs::read_to_string(&out).unwrap_or_default();
        let provenance: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
        assert!(
            provenance.iter().any(|l| l.starts_with("# linkdyn ")),
            "version recorded"
        );
        assert!(
            provenance.iter().any(|l| l.contains("sha256")),
            "model hash recorded"
        );
        assert!(
            provenance.iter().any(|l| l.starts_with("# rtol = ")),
            "settings recorded"
        );
        bodies.push(text);
    }
    assert_eq!(
        bodies[0], bodies[1],
        "two identical runs must write identical files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_solver_failure_says_when_and_exits_with_code_3_leaving_no_files() {
    // A crank of 0.4 m in the reference four-bar cannot turn fully: at θ2 = π the coupler and
    // rocker are stretched into a line (0.4 + 0.8 = 0.75 + 0.45) and the driven motion cannot
    // go on. The solver must stop there with a message, not hang or write half a file.
    let dir = std::env::temp_dir().join(format!("linkdyn-lock-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let out = dir.join("lock.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.points.A=[0.2,0.0]",
        "--set",
        "bodies.crank.points.O2=[-0.2,0.0]",
        "--set",
        "bodies.crank.initial.x=0.2",
        "--revs",
        "1",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 3, "{stderr}");
    // The toggle is at θ2 = π, i.e. t = 0.12 s at 250 rpm; the step size collapses there and
    // the no-progress rule stops the run within 1000 attempts.
    assert!(stderr.starts_with("error: no progress at t = "), "{stderr}");
    assert!(stderr.contains("toggle"), "{stderr}");
    assert!(stderr.contains("at t = 0.1199"), "{stderr}");
    assert!(
        !out.exists() && !dir.join("lock.json").exists(),
        "no partial result files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_linkage_driven_through_its_clearance_joint_stops_with_the_reason() {
    // Moving the crank's pivot point 1 m off its axis makes the reference four-bar unable to
    // turn: the driver pushes the journal through the bearing. Trial stages of too-large steps
    // that overshoot are retried smaller; only a real penetration beyond 0.1 R_J stops the run.
    let dir = std::env::temp_dir().join(format!("linkdyn-deep-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let out = dir.join("deep.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/farahan2016.toml",
        "--set",
        "bodies.crank.points.O2=[-0.125,-1.0]",
        "--revs",
        "0.05",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 3, "{stderr}");
    assert!(
        stderr.contains("penetration of clearance joint \"B\" reached")
            && stderr.contains("the linkage is being driven through the joint"),
        "{stderr}"
    );
    assert!(!out.exists(), "no partial result file");
    let _ = std::fs::remove_dir_all(&dir);
}
