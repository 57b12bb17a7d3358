//! Ctrl-C during `linkdyn continue` (docs/periodic_orbits.md, "Continuation"): the branch ends
//! after the point in progress, both files are written with the points so far (whole: a CSV
//! whose every row has all its columns, a JSON whose `end` is `stopped`), and the command
//! exits with code 130 saying where the files are.
#![cfg(unix)]

mod cli_common;

use cli_common::scratch;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_linkdyn");

#[test]
fn ctrl_c_ends_the_branch_and_writes_what_was_computed() {
    let dir = scratch("continue_sigint");
    let out = dir.join("c.csv");
    // The whole bubble and its period-2 branch: about 8 s of CPU in a release build.
    let mut child = Command::new(BIN)
        .args([
            "continue",
            "models/farahan2016.toml",
            "--set",
            "drivers.motor.speed_rpm=3500",
            "--param",
            "joints.B.clearance",
            "--from",
            "0.00044",
            "--to",
            "0.0004",
            "--step",
            "0.000002",
            "--rtol",
            "1e-10",
            "--atol",
            "1e-12",
            "--follow-doublings",
            "1",
        ])
        .arg("--out")
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    std::thread::sleep(Duration::from_millis(1500));
    assert!(
        child.try_wait().ok().flatten().is_none(),
        "the continuation ended within 1.5 s"
    );
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(sent.is_ok_and(|s| s.success()), "kill -INT failed");
    let started = Instant::now();
    while child.try_wait().ok().flatten().is_none() {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no stop within 60 s of the signal"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap_or_else(|e| panic!("{e}"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "stderr: {stderr}");
    let json = out.with_extension("json");
    let expected = format!(
        "error: interrupted: the branches up to the last point are in {} and {}",
        out.display(),
        json.display()
    );
    assert!(
        stderr.lines().any(|l| l == expected),
        "stderr lacks \"{expected}\": {stderr}"
    );
    let csv = std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("{e}"));
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let columns = lines.next().unwrap_or_default().split(',').count();
    let rows: Vec<&str> = lines.collect();
    assert!(!rows.is_empty(), "{csv}");
    assert!(
        rows.iter().all(|r| r.split(',').count() == columns),
        "{csv}"
    );
    let last: f64 = rows[rows.len() - 1]
        .split(',')
        .next()
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    assert!(
        (0.0004..=0.00044).contains(&last),
        "last point at {last}, inside the range"
    );
    let summary = std::fs::read_to_string(&json).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        summary.contains("\"reason\": \"stopped\""),
        "the branch that was interrupted ends \"stopped\": {summary}"
    );
}
