//! One failed point ended a whole `linkdyn bifurcation` sweep: on Fig. 6a with Radau5 the
//! point whose step size collapsed (`tests/issue_29_radau5_cut_at_step_start.rs`) stopped the
//! command with exit 3 after the other points' work, and `--resume` would have run it again
//! only to stop again. And bad input found late cost an earlier result: the files were cut to
//! their head before `--threads 0`, `--phase 7` or a `--to` the model refuses was noticed, and
//! `--steps 18446744073709551615` wrapped to zero points (exit 0) while `--steps 1000000000`
//! tried to allocate 8 GB.
//!
//! Now a failed point is recorded (NaN rows, verdict `failed` with its message), the other
//! points complete, the command exits 5 with a summary, and `--resume` runs only the failed
//! points; every option and both grid ends are checked before any file is touched.

mod cli_common;

use cli_common::{linkdyn, scratch};
use std::path::Path;

const MODEL: &str = "models/farahan2016.toml";

fn s(p: &Path) -> String {
    p.display().to_string()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Rows after the header and the `#` lines.
fn rows(text: &str) -> Vec<&str> {
    text.lines()
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .collect()
}

/// A sweep of the crank speed over −3500, 0, 3500 rpm (reduced formulation, 6 turns after 3):
/// the middle point has a driver that does not turn, so its end time of 6 turns does not
/// exist and it fails; the ends run.
fn speed_sweep(out: &Path, extra: &[&str]) -> (i32, String, String) {
    let o = s(out);
    let mut args = vec![
        "bifurcation",
        MODEL,
        "--formulation",
        "reduced",
        "--param",
        "drivers.motor.speed_rpm",
        "--from",
        "-3500",
        "--to",
        "3500",
        "--steps",
        "2",
        "--revs",
        "6",
        "--transient",
        "3",
        "--observe",
        "coupler.phi",
        "--threads",
        "2",
        "--out",
        &o,
    ];
    args.extend_from_slice(extra);
    linkdyn(&args)
}

#[test]
fn a_failed_point_is_recorded_and_the_others_complete() {
    let dir = scratch("failed");
    let out = dir.join("b.csv");
    let marks = dir.join("b.verdicts.csv");
    let (code, stdout, stderr) = speed_sweep(&out, &[]);
    let reason = "--revs: driver \"motor\" has zero speed: give --t-end instead";
    let expected = format!(
        "error: 2 of 3 points; point 1 (drivers.motor.speed_rpm = 0) failed: {reason}. The failed point is recorded as \"failed\" with its message in {}; run the same command with --resume to retry only it\n",
        marks.display()
    );
    assert_eq!(code, 5, "{stderr}");
    assert!(stderr.ends_with(&expected), "{stderr}");
    assert!(
        stdout.contains("3 points run to") && stdout.contains("verdicts: period-1: 2"),
        "{stdout}"
    );

    let data = read(&out);
    let data_rows = rows(&data);
    assert_eq!(
        data_rows.len(),
        3 * 3,
        "3 points × 3 recorded turns: {data}"
    );
    assert_eq!(
        &data_rows[3..6],
        ["1,0,3,NaN", "1,0,4,NaN", "1,0,5,NaN"],
        "the failed point's rows"
    );
    for row in data_rows.iter().filter(|r| !r.starts_with("1,")) {
        let value = row.rsplit(',').next().and_then(|v| v.parse::<f64>().ok());
        assert!(
            value.is_some_and(f64::is_finite),
            "a point that ran has a finite coupler angle: {row}"
        );
    }
    let verdict = read(&marks);
    assert_eq!(
        verdict.lines().next(),
        Some("index,drivers.motor.speed_rpm,verdict,k,message")
    );
    assert_eq!(
        rows(&verdict),
        [
            "0,-3500,period,1,".to_string(),
            format!("1,0,failed,0,\"{}\"", reason.replace('"', "\"\"")),
            "2,3500,period,1,".to_string(),
        ]
    );

    // --resume runs the failed point only; it fails again, and the files stay the same.
    let (code, _, stderr) = speed_sweep(&out, &["--resume"]);
    assert_eq!(code, 5, "{stderr}");
    assert!(
        stderr.contains("3 points: 2 finished, 1 to run"),
        "--resume: {stderr}"
    );
    assert!(stderr.ends_with(&expected), "{stderr}");
    assert_eq!(read(&out), data, "data after --resume");
    assert_eq!(read(&marks), verdict, "verdicts after --resume");
}

#[test]
fn solver_failures_are_counted_and_named() {
    let dir = scratch("solver");
    let out = dir.join("b.csv");
    // Every point fails: 200 step attempts do not reach the end of 6 turns.
    let (code, _, stderr) = speed_sweep(&out, &["--max-steps", "200"]);
    assert_eq!(code, 5, "{stderr}");
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.starts_with(
            "error: 0 of 3 points; point 0 (drivers.motor.speed_rpm = -3500) failed: "
        ) && last.contains("; point 1 (drivers.motor.speed_rpm = 0) failed: ")
            && last.contains("The failed points are recorded as \"failed\" with their messages in"),
        "{stderr}"
    );
    // The message of each point, as the solver gave it (one line; quoted only where RFC 4180
    // needs it).
    let verdict = read(&out.with_extension("verdicts.csv"));
    // Where the 200 attempts end depends on the last bits of the arithmetic, not on the
    // message: the time is checked to be a number inside the first turn, the rest exactly.
    let gave_up = |row: &str, point: &str| {
        let prefix =
            format!("{point},failed,0,Poincaré section: the integration failed: gave up at t = ");
        let suffix = " s after 200 step attempts (limit max_steps; raise it or loosen rtol/atol)";
        let t = row
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(suffix))
            .and_then(|t| t.parse::<f64>().ok());
        assert!(
            t.is_some_and(|t| t > 0.0 && t < 60.0 / 3500.0),
            "{point}: {row}"
        );
    };
    let rows = rows(&verdict);
    assert_eq!(rows.len(), 3, "{rows:?}");
    gave_up(rows[0], "0,-3500");
    assert_eq!(
        rows[1],
        "1,0,failed,0,\"--revs: driver \"\"motor\"\" has zero speed: give --t-end instead\""
    );
    gave_up(rows[2], "2,3500");
}

/// A finished small sweep, then bad input against the same `--out`: refused with exit 2 and
/// the exact message, and the earlier files left byte for byte as they were.
#[test]
fn bad_input_is_refused_before_any_file_is_touched() {
    let dir = scratch("checks");
    let out = dir.join("b.csv");
    let marks = dir.join("b.verdicts.csv");
    let base = |extra: &[&str]| {
        let o = s(&out);
        let mut args = vec![
            "bifurcation",
            MODEL,
            "--formulation",
            "reduced",
            "--set",
            "drivers.motor.speed_rpm=3500",
            "--param",
            "joints.B.clearance",
            "--from",
            "0.0002",
            "--to",
            "0.0003",
            "--steps",
            "1",
            "--revs",
            "4",
            "--transient",
            "2",
            "--observe",
            "coupler.phi",
            "--out",
            &o,
        ];
        // `extra` as flag-value pairs: a flag already there gets the new value.
        for pair in extra.chunks(2) {
            match args.iter().position(|a| *a == pair[0]) {
                Some(k) => args[k + 1] = pair[1],
                None => args.extend_from_slice(pair),
            }
        }
        linkdyn(&args)
    };
    let (code, _, stderr) = base(&[]);
    assert_eq!(code, 0, "{stderr}");
    let (data, verdict) = (read(&out), read(&marks));
    assert_eq!(rows(&data).len(), 4, "{data}");

    let cases: [(&[&str], &str); 6] = [
        (
            &["--threads", "0"],
            "error: --threads: expected at least 1 thread, got 0\n",
        ),
        (
            &["--phase", "7"],
            "error: --phase: expected a phase in [0, 2π) rad, got 7\n",
        ),
        (
            &["--steps", "18446744073709551615"],
            "error: invalid parameter grid: expected at most 999999 steps (1000000 points, each a whole integration), got 18446744073709551615\n",
        ),
        (
            &["--steps", "1000000000"],
            "error: invalid parameter grid: expected at most 999999 steps (1000000 points, each a whole integration), got 1000000000\n",
        ),
        (
            &["--observe", "coupler.ph"],
            "error: --observe: no output column \"coupler.ph\"; the columns are ",
        ),
        (
            &["--to", "0.02"],
            "error: --param joints.B.clearance: models/farahan2016.toml:64:13: ",
        ),
    ];
    for (extra, message) in cases {
        let (code, _, stderr) = base(extra);
        assert_eq!(code, 2, "{extra:?}: {stderr}");
        let error = stderr
            .lines()
            .find(|l| l.starts_with("error: "))
            .map(|l| format!("{l}\n"))
            .unwrap_or_default();
        assert!(
            error.starts_with(message),
            "{extra:?}: expected {message:?}, got {stderr:?}"
        );
        assert_eq!(read(&out), data, "{extra:?}: the earlier result changed");
        assert_eq!(
            read(&marks),
            verdict,
            "{extra:?}: the earlier verdicts changed"
        );
    }
}
