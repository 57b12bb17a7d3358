//! Claim: every analysis CSV (poincare, bifurcation and its verdicts, spectrum, phase, lyapunov)
//! and a run's impact log are laid out as the run CSV: the header row first, then the `#` provenance lines, then the
//! numbers — so `np.genfromtxt(f, delimiter=",", names=True, comments="#")` takes the names from
//! the first line — and `merge` still joins shard files written that way.

mod cli_common;

use cli_common::{linkdyn, scratch};
use std::path::Path;

const MODEL: &str = "models/farahan2016.toml";

fn run(args: &[&str]) {
    let (code, _, err) = linkdyn(args);
    assert_eq!(code, 0, "linkdyn {}: {err}", args.join(" "));
}

/// Asserts the layout of `path`: line 1 is `header`, then one or more `#` lines, then rows of
/// numbers with as many fields as the header, and no `#` line among them.
fn assert_header_first(path: &Path, header: &str) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(header), "{}: first line", path.display());
    let rest: Vec<&str> = lines.collect();
    let comments = rest.iter().take_while(|l| l.starts_with('#')).count();
    assert!(
        comments >= 2,
        "{}: {comments} provenance lines after the header",
        path.display()
    );
    let fields = header.split(',').count();
    let rows = &rest[comments..];
    assert!(!rows.is_empty(), "{}: no rows", path.display());
    for (k, row) in rows.iter().enumerate() {
        assert!(
            !row.starts_with('#'),
            "{}: a # line among the rows at row {k}",
            path.display()
        );
        assert_eq!(
            row.split(',').count(),
            fields,
            "{}: row {k}: {row}",
            path.display()
        );
    }
}

#[test]
fn analysis_csvs_put_the_header_first_and_merge_still_joins_them() {
    let dir = scratch("header");
    let p = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let short = [
        "--revs", "3", "--dt", "1e-3", "--rtol", "1e-6", "--atol", "1e-8",
    ];
    let with = |cmd: &str, extra: &[&str], out: &str| {
        let mut a = vec![cmd, MODEL];
        a.extend_from_slice(&short);
        a.extend_from_slice(extra);
        a.extend_from_slice(&["--out", out]);
        run(&a);
    };
    with(
        "poincare",
        &["--transient", "1", "--observe", "coupler.phi,B.ex"],
        &p("p.csv"),
    );
    assert_header_first(&dir.join("p.csv"), "turn,t,coupler.phi,B.ex");
    with("spectrum", &["--observe", "coupler.phi"], &p("s.csv"));
    assert_header_first(&dir.join("s.csv"), "frequency_hz,amplitude");
    with("phase", &["--observe", "coupler.phi"], &p("f.csv"));
    assert_header_first(&dir.join("f.csv"), "t,value,rate");
    with("lyapunov", &[], &p("l.csv"));
    with("run", &[], &p("r.csv"));
    assert_header_first(
        &dir.join("r.impacts.csv"),
        "joint,index,t,driver_angle,impact_velocity,peak_normal_force,peak_penetration,duration",
    );
    assert_header_first(&dir.join("l.csv"), "t,lambda");
    let sweep = |extra: &[&str], out: &str| {
        let mut a = vec![
            "bifurcation",
            MODEL,
            "--param",
            "joints.B.clearance",
            "--from",
            "0.0003",
            "--to",
            "0.0005",
            "--steps",
            "2",
            "--revs",
            "3",
            "--transient",
            "1",
            "--observe",
            "B.ex",
            "--rtol",
            "1e-6",
            "--atol",
            "1e-8",
        ];
        a.extend_from_slice(extra);
        a.extend_from_slice(&["--out", out]);
        run(&a);
    };
    sweep(&[], &p("b.csv"));
    assert_header_first(&dir.join("b.csv"), "index,joints.B.clearance,turn,B.ex");
    // Two shards merged give the whole sweep's rows, each point once.
    sweep(&["--shard", "1/2"], &p("b1.csv"));
    sweep(&["--shard", "2/2"], &p("b2.csv"));
    run(&["merge", &p("b1.csv"), &p("b2.csv"), "--out", &p("m.csv")]);
    assert_header_first(&dir.join("m.csv"), "index,joints.B.clearance,turn,B.ex");
    let rows = |f: &str| -> Vec<String> {
        let text = std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        let mut r: Vec<String> = text
            .lines()
            .skip(1)
            .filter(|l| !l.starts_with('#'))
            .map(String::from)
            .collect();
        r.sort();
        r
    };
    assert_eq!(
        rows("m.csv"),
        rows("b.csv"),
        "merged shards differ from the whole sweep"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
