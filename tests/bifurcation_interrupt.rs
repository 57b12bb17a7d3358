//! Ctrl-C during `linkdyn bifurcation` (docs/sweeps.md): the sweep stops starting points, writes the
//! points in flight, and exits with code 130 saying how many points are on disk; both files
//! then hold whole lines only, every point with a verdict has all its rows, and `--resume`
//! completes the sweep to files equal byte for byte to an uninterrupted run.
#![cfg(unix)]

mod cli_common;

use cli_common::scratch;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_linkdyn");
/// Grid points of the sweep (`--steps 11`).
const POINTS: usize = 12;
/// Rows per point: 40 turns, 30 transient.
const ROWS: usize = 10;

/// The sweep: 12 clearances at 3500 rpm, 40 turns each (about 0.2 s of CPU per point in a
/// release build, so a signal after the second point lands well before the end).
fn sweep(out: &Path, extra: &[&str]) -> Command {
    let mut c = Command::new(BIN);
    c.args([
        "bifurcation",
        "models/farahan2016.toml",
        "--formulation",
        "reduced",
        "--set",
        "drivers.motor.speed_rpm=3500",
        "--param",
        "joints.B.clearance",
        "--from",
        "0.0002",
        "--to",
        "0.0005",
        "--steps",
        "11",
        "--revs",
        "40",
        "--transient",
        "30",
        "--observe",
        "B.ex",
        "--threads",
        "2",
    ])
    .arg("--out")
    .arg(out)
    .args(extra)
    .current_dir(env!("CARGO_MANIFEST_DIR"))
    .stdout(Stdio::piped())
    .stderr(Stdio::piped());
    c
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Data rows (not the header, not provenance) of a result file.
fn rows(text: &str) -> Vec<&str> {
    text.split_inclusive('\n')
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .collect()
}

/// Waits for the child (killing it after 120 s, which fails the test).
fn finish(mut child: Child) -> (Option<i32>, String) {
    let started = Instant::now();
    while child.try_wait().ok().flatten().is_none() {
        if started.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("sweep did not stop within 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap_or_else(|e| panic!("{e}"));
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn ctrl_c_keeps_the_finished_points_and_resume_completes_the_sweep() {
    let dir = scratch("sigint");
    let out = dir.join("b.csv");
    let marks = dir.join("b.verdicts.csv");
    let mut child = sweep(&out, &[])
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    let started = Instant::now();
    // Two points finished (their verdicts are the last thing written for a point).
    while std::fs::read_to_string(&marks).map_or(0, |t| rows(&t).len()) < 2 {
        if let Ok(Some(status)) = child.try_wait() {
            panic!("sweep ended before two points were written: {status}");
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no two points in 120 s"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(sent.is_ok_and(|s| s.success()), "kill -INT failed");
    let (code, stderr) = finish(child);
    assert_eq!(code, Some(130), "exit code after SIGINT; stderr: {stderr}");

    // The message says how many points are kept and how to go on.
    let data = read(&out);
    let verdicts = read(&marks);
    let kept = rows(&verdicts).len();
    assert!(
        (2..POINTS).contains(&kept),
        "between 2 and {} points kept, got {kept}; stderr: {stderr}",
        POINTS - 1
    );
    let expected = format!(
        "error: interrupted: {kept} of {POINTS} points are finished in {} and {}; run the same command with --resume to compute the {} left",
        out.display(),
        marks.display(),
        POINTS - kept
    );
    assert!(
        stderr.lines().any(|l| l == expected),
        "stderr lacks \"{expected}\": {stderr}"
    );

    // Whole lines only; every point with a verdict has all its rows and nothing else is there.
    for (name, text) in [("data", &data), ("verdicts", &verdicts)] {
        assert!(text.ends_with('\n'), "{name} file ends in a cut-off line");
    }
    let finished: Vec<&str> = rows(&verdicts)
        .iter()
        .filter_map(|l| l.split(',').next())
        .collect();
    for i in &finished {
        let n = rows(&data)
            .iter()
            .filter(|l| l.split(',').next() == Some(*i))
            .count();
        assert_eq!(n, ROWS, "rows of finished point {i}");
    }
    assert_eq!(
        rows(&data).len(),
        kept * ROWS,
        "data rows of {kept} finished points"
    );

    // --resume runs only the rest and ends with the files of an uninterrupted sweep.
    let resumed = sweep(&out, &["--resume"])
        .output()
        .unwrap_or_else(|e| panic!("{e}"));
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert_eq!(resumed.status.code(), Some(0), "resume: {stderr}");
    let plan = format!("{kept} finished, {} to run", POINTS - kept);
    assert!(stderr.contains(&plan), "resume lacks \"{plan}\": {stderr}");
    let whole = dir.join("whole.csv");
    let straight = sweep(&whole, &[])
        .output()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        straight.status.code(),
        Some(0),
        "uninterrupted: {}",
        String::from_utf8_lossy(&straight.stderr)
    );
    assert_eq!(read(&out), read(&whole), "resumed vs uninterrupted data");
    assert_eq!(
        read(&marks),
        read(&dir.join("whole.verdicts.csv")),
        "resumed vs uninterrupted verdicts"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
