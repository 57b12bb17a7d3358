//! `linkdyn continue` (docs/periodic_orbits.md, "Continuation"): a short branch of the
//! reference four-bar at 3500 rpm writes its CSV and JSON, starts on the orbit that
//! `linkdyn orbit` finds, and ends exactly at --to; bad input is named before any work and
//! leaves no file; no orbit at --from is an error with the residual history.

use std::path::Path;

mod cli_common;
use cli_common::{linkdyn, scratch};

const MODEL: &str = "models/farahan2016.toml";

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_short_branch_starts_on_the_orbit_and_ends_at_to() {
    let dir = scratch("branch");
    let out = dir.join("c.csv");
    let (code, stdout, stderr) = linkdyn(&[
        "continue",
        MODEL,
        "--set",
        "drivers.motor.speed_rpm=3500",
        "--param",
        "joints.B.clearance",
        "--from",
        "0.00044",
        "--to",
        "0.00043",
        "--step",
        "0.000005",
        "--rtol",
        "1e-10",
        "--atol",
        "1e-12",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let csv = read(&out);
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    assert_eq!(header[0], "joints.B.clearance");
    assert_eq!(
        header[header.len() - 9..],
        [
            "period_s",
            "max_abs_mu",
            "stable",
            "impacts_per_period",
            "min_gap_m",
            "residual",
            "special",
            "branch",
            "turn"
        ]
    );
    let phi = header
        .iter()
        .position(|h| *h == "rocker.phi")
        .unwrap_or_else(|| panic!("{header:?}"));
    let rows: Vec<Vec<&str>> = lines
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect())
        .collect();
    assert!(rows.len() >= 3, "{csv}");
    let number = |s: &str| s.parse::<f64>().unwrap_or_else(|e| panic!("{s}: {e}"));
    assert_eq!(number(rows[0][0]), 0.00044);
    assert_eq!(number(rows[rows.len() - 1][0]), 0.00043);
    // The first point is the orbit of docs/periodic_orbits.md's worked example (`linkdyn
    // orbit`, same tolerances): rocker.phi = 1.452989445860; both close to within 1000 ε
    // (1.5e-7 rad) of the fixed point, whose |μ| = 0.25 makes that ~2e-7 rad.
    let first = number(rows[0][phi]);
    assert!(
        (first - 1.452989445860).abs() < 2e-7,
        "rocker.phi at 0.44 mm: {first}"
    );
    // Period-1 and stable over this stretch (docs/reproduce.md: period-1 there), one impact
    // per turn, and no special point: one branch, one row (turn 0) per point.
    for r in &rows {
        let n = r.len();
        assert_eq!(
            (r[n - 7], r[n - 6], r[n - 3], r[n - 2], r[n - 1]),
            ("1", "1", "", "0", "0"),
            "{r:?}"
        );
    }
    let json = read(&out.with_extension("json"));
    for key in [
        "\"end\": {\n    \"reason\": \"reached\"",
        "\"parameter\": \"joints.B.clearance\"",
        "\"linkdyn_version\"",
        "\"special_points\": []",
    ] {
        assert!(json.contains(key), "{key} not in {json}");
    }
    assert!(
        stdout.contains("points from joints.B.clearance = 0.00044 to 0.00043"),
        "{stdout}"
    );
}

#[test]
fn bad_input_is_named_and_leaves_no_file() {
    let dir = scratch("bad");
    let out = dir.join("c.csv");
    let o = out.display().to_string();
    let base = ["continue", MODEL, "--from", "0.00044", "--out", &o];
    let cases: [(&[&str], i32, &str); 3] = [
        (
            &["--param", "joints.B.clerance", "--to", "0.00043"],
            2,
            "error: --param joints.B.clerance: models/farahan2016.toml: joints.B.clerance: unknown field `clerance`: did you mean \"clearance\"?",
        ),
        (
            &["--param", "joints.B.clearance", "--to", "0.00044"],
            2,
            "error: --to: expected a value other than --from 0.00044 (a branch needs a range)",
        ),
        (
            // From the model's initial state the transient is far from the orbit
            // (docs/periodic_orbits.md, "Shooting formulation").
            &[
                "--param",
                "joints.B.clearance",
                "--to",
                "0.00043",
                "--set",
                "drivers.motor.speed_rpm=3500",
                "--guess-from-turn",
                "0",
            ],
            3,
            "error: continuation: no periodic orbit found: at the start (p = 0.00044): a Newton step halved 8 times still raises the residual; residual max|P(x) - x| by iteration, in units of the integration tolerance: ",
        ),
    ];
    for (extra, want_code, want) in cases {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let (code, _, stderr) = linkdyn(&args);
        assert_eq!(code, want_code, "{extra:?}: {stderr}");
        // The error is the last line; a run at the default rtol 1e-8 that got as far as the
        // shooting has printed its note on the tolerance before it.
        let error = stderr
            .lines()
            .find(|l| l.starts_with("error:"))
            .unwrap_or("");
        assert!(error.starts_with(want), "{extra:?}: {stderr}");
        assert_eq!(
            stderr.contains("note: at rtol 1e-8 the Floquet multipliers in contact are coarse"),
            want_code == 3,
            "{extra:?}: {stderr}"
        );
        assert!(!out.exists() && !out.with_extension("json").exists());
    }
}
