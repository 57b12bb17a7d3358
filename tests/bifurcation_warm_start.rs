//! Warm-started sweeps and transient detection of `linkdyn bifurcation`: a point started from
//! the previous point's state lands on the same attractor as one started from the model's
//! initial state where the attractor is unique, in the same files whatever the threads; the
//! transient ends once the section has settled, never before `--transient-min` and never after
//! `--transient`; `--direction both` writes both branches; combinations that cannot work are
//! refused with their reason before any file is touched.
//!
//! The case: the reference four-bar at 3500 rpm (reduced formulation, rtol 1e-6, Radau5, the
//! settings of the fast Fig. 6a diagram in docs/sweeps.md), clearances 0.1 to 0.3 mm, where
//! every point is period one, settled within about 6 turns (docs/sweeps.md).

mod cli_common;

use cli_common::{linkdyn, scratch};
use linkdyn::formulation::ReducedLagrangian;
use linkdyn::formulation::reduced_lagrangian::WarmState;
use std::collections::BTreeMap;
use std::path::Path;

const MODEL: &str = "models/farahan2016.toml";

fn s(p: &Path) -> String {
    p.display().to_string()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Rows after the header and the `#` lines, split into fields.
fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// A sweep of the clearance over 0.1–0.3 mm in 5 steps, 30 turns after at most 20, writing
/// `out` (reduced formulation unless `extra` names one); returns (exit code, stdout, stderr).
fn sweep(out: &Path, extra: &[&str]) -> (i32, String, String) {
    let o = s(out);
    let mut args = vec!["bifurcation", MODEL];
    if !extra.contains(&"--formulation") {
        args.extend(["--formulation", "reduced"]);
    }
    args.extend([
        "--method",
        "radau5",
        "--rtol",
        "1e-6",
        "--atol",
        "1e-9",
        "--set",
        "drivers.motor.speed_rpm=3500",
        "--param",
        "joints.B.clearance",
        "--from",
        "0.0001",
        "--to",
        "0.0003",
        "--steps",
        "5",
        "--revs",
        "50",
        "--transient",
        "20",
        "--observe",
        "coupler.phi",
        "--out",
        &o,
    ]);
    args.extend_from_slice(extra);
    linkdyn(&args)
}

/// Per index: the verdict row's fields.
fn verdicts(path: &Path) -> BTreeMap<usize, Vec<String>> {
    rows(&read(path))
        .into_iter()
        .map(|r| (r[0].parse().unwrap_or(usize::MAX), r))
        .collect()
}

/// Per index: (turns, values) of the data rows.
fn data(path: &Path) -> BTreeMap<usize, (Vec<usize>, Vec<f64>)> {
    let mut m: BTreeMap<usize, (Vec<usize>, Vec<f64>)> = BTreeMap::new();
    for r in rows(&read(path)) {
        let e = m.entry(r[0].parse().unwrap_or(usize::MAX)).or_default();
        e.0.push(r[2].parse().unwrap_or(usize::MAX));
        e.1.push(r[3].parse().unwrap_or(f64::NAN));
    }
    m
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn warm_starts_find_the_attractor_of_independent_starts_whatever_the_threads() {
    let dir = scratch("same");
    let cold = dir.join("cold.csv");
    let warm = dir.join("warm.csv");
    let warm1 = dir.join("warm1.csv");
    let (code, _, err) = sweep(&cold, &["--threads", "2"]);
    assert_eq!(code, 0, "independent starts: {err}");
    let flags = ["--warm-start", "--chunks", "2", "--settle"];
    let (code, _, err) = sweep(&warm, &[&flags[..], &["--threads", "2"]].concat());
    assert_eq!(code, 0, "warm-started: {err}");
    let (code, _, err) = sweep(&warm1, &[&flags[..], &["--threads", "1"]].concat());
    assert_eq!(code, 0, "warm-started on one thread: {err}");

    // The same files whatever the threads: the chunks, not the threads, fix who starts from
    // whom.
    for (a, b) in [
        (warm.clone(), warm1.clone()),
        (
            warm.with_extension("verdicts.csv"),
            warm1.with_extension("verdicts.csv"),
        ),
    ] {
        assert_eq!(read(&a), read(&b), "{} vs {}", a.display(), b.display());
    }

    let vc = verdicts(&cold.with_extension("verdicts.csv"));
    let vw = verdicts(&warm.with_extension("verdicts.csv"));
    assert_eq!(vc.len(), 6);
    assert_eq!(vw.len(), 6);
    let (dc, dw) = (data(&cold), data(&warm));
    for (i, w) in &vw {
        let c = &vc[i];
        assert_eq!(
            (&c[2], &c[3]),
            (&w[2], &w[3]),
            "point {i}: verdict of independent vs warm start"
        );
        assert_eq!(&w[2], "period", "point {i}: {w:?}");
        // Chunks {0, 1, 2} and {3, 4, 5}: their first points start cold.
        let expected = if *i == 0 || *i == 3 { "cold" } else { "warm" };
        assert_eq!(w[5], expected, "point {i}: start");
        // The same period-one point: the means of the recorded points agree to well below
        // the diagram's spread over this range (about 3e-4 rad); the integration jitter at
        // rtol 1e-6 is about 2e-6 rad, the settling tolerance 10 ε = 6.4e-6 rad. A warm start
        // at the wrong phase of the crank would be off by tenths of a radian.
        let (mc, mw) = (mean(&dc[i].1), mean(&dw[i].1));
        assert!(
            (mc - mw).abs() < 1e-5,
            "point {i}: coupler.phi {mc} (independent) vs {mw} (warm)"
        );
        assert_eq!(dw[i].1.len(), 30, "point {i}: 50 − 20 recorded turns");
    }
}

#[test]
fn the_default_chunks_fit_a_small_grid() {
    // One chunk per 25 points, at least one: the 6 points are one chunk, walked up.
    let dir = scratch("default-chunks");
    let out = dir.join("d.csv");
    let (code, _, err) = sweep(&out, &["--warm-start"]);
    assert_eq!(code, 0, "{err}");
    let marks = out.with_extension("verdicts.csv");
    assert!(
        read(&marks).contains("# warm_start_chunks = 1\n"),
        "{}",
        read(&marks)
    );
    let starts: Vec<String> = verdicts(&marks)
        .into_values()
        .map(|r| r[5].clone())
        .collect();
    assert_eq!(starts, ["cold", "warm", "warm", "warm", "warm", "warm"]);
}

#[test]
fn settling_ends_the_transient_early_but_not_before_the_minimum() {
    let dir = scratch("settle");
    for min in [3, 12] {
        let out = dir.join(format!("min{min}.csv"));
        let m = min.to_string();
        let (code, _, err) = sweep(&out, &["--settle", "--transient-min", &m]);
        assert_eq!(code, 0, "--transient-min {min}: {err}");
        let head = read(&out.with_extension("verdicts.csv"));
        assert!(
            head.starts_with("index,joints.B.clearance,verdict,k,transient_turns,start,message\n"),
            "{head}"
        );
        assert!(
            head.contains(&format!("# settle_min_revs = {min}\n")),
            "{head}"
        );
        let d = data(&out);
        for (i, v) in verdicts(&out.with_extension("verdicts.csv")) {
            let used: usize = v[4].parse().unwrap_or(usize::MAX);
            // Settled in about 6 turns (docs/sweeps.md): well before the 20 allowed.
            assert!(
                (min..20).contains(&used),
                "point {i}, --transient-min {min}: {used} transient turns"
            );
            assert_eq!(v[5], "cold", "point {i}: independent starts");
            let expected: Vec<usize> = (used..used + 30).collect();
            assert_eq!(d[&i].0, expected, "point {i}: recorded turns");
        }
    }
}

#[test]
fn both_directions_write_both_branches() {
    let dir = scratch("both");
    let out = dir.join("b.csv");
    let (code, stdout, err) = sweep(
        &out,
        &[
            "--warm-start",
            "--chunks",
            "1",
            "--direction",
            "both",
            "--settle",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(!out.exists(), "both branches go to b.up.csv and b.down.csv");
    for (branch, cold) in [("up", 0), ("down", 5)] {
        let path = dir.join(format!("b.{branch}.csv"));
        let marks = dir.join(format!("b.{branch}.verdicts.csv"));
        assert!(
            stdout.contains(&format!("6 points run to {}", s(&path))),
            "{stdout}"
        );
        let text = read(&marks);
        assert!(
            text.contains(&format!("# direction = {branch}\n")),
            "{text}"
        );
        assert!(text.contains("# warm_start_chunks = 1\n"), "{text}");
        // Rows in index order in both branches; only the branch's first point starts cold.
        let v = verdicts(&marks);
        assert_eq!(
            v.keys().copied().collect::<Vec<_>>(),
            (0..6).collect::<Vec<_>>()
        );
        for (i, r) in &v {
            let expected = if *i == cold { "cold" } else { "warm" };
            assert_eq!(r[5], expected, "{branch} point {i}");
        }
        assert_eq!(data(&path).len(), 6, "{branch}");
    }
}

#[test]
fn combinations_that_cannot_work_are_refused_before_any_file() {
    let dir = scratch("refused");
    let out = dir.join("r.csv");
    let cases: [(&[&str], &str); 8] = [
        (
            &["--warm-start", "--shard", "1/2"],
            "error: --shard: a warm-started sweep (--warm-start) cannot be sharded: each point starts from the one before it in its chunk, and a shard takes every n-th point; split it with --chunks and --threads instead",
        ),
        (
            &["--warm-start", "--formulation", "dae"],
            "error: --warm-start: needs --formulation reduced (only the reduced model can start from another point's state), got --formulation dae",
        ),
        (
            &["--chunks", "2"],
            "error: --chunks: applies to a warm-started sweep only; add --warm-start or leave it out",
        ),
        (
            &["--direction", "down"],
            "error: --direction: applies to a warm-started sweep only; add --warm-start or leave it out",
        ),
        (
            &["--transient-min", "3"],
            "error: --transient-min: sets the fewest transient turns of --settle; add --settle or leave it out",
        ),
        (
            &["--settle", "--transient-min", "21"],
            "error: --transient-min: expected at most the 20 turns of --transient (the most a transient may take), got 21",
        ),
        (
            &["--warm-start", "--chunks", "0"],
            "error: invalid --chunks: expected 1 to 6 chunks (one grid point at least in each), got 0",
        ),
        (
            &["--warm-start", "--chunks", "7"],
            "error: invalid --chunks: expected 1 to 6 chunks (one grid point at least in each), got 7",
        ),
    ];
    for (extra, message) in cases {
        let (code, _, err) = sweep(&out, extra);
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert_eq!(err.trim_end(), message, "{extra:?}");
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
    let (code, _, err) = sweep(&out, &["--warm-start", "--direction", "sideways"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("expected up, down or both, got \"sideways\""),
        "{err}"
    );
}

/// `text` without the rows (data or verdicts) of the points `drop`.
fn without(text: &str, drop: &[usize]) -> String {
    text.split_inclusive('\n')
        .filter(|l| {
            l.starts_with('#')
                || l.split(',')
                    .next()
                    .and_then(|i| i.parse::<usize>().ok())
                    .is_none_or(|i| !drop.contains(&i))
        })
        .collect()
}

#[test]
fn a_resumed_warm_sweep_equals_an_uninterrupted_one() {
    // Each point's end state is in its verdict row (`end_state`, exact digits), so a resumed
    // chunk carries on from its last finished point as if never stopped.
    let dir = scratch("resume");
    let out = dir.join("b.csv");
    let flags = [
        "--warm-start",
        "--chunks",
        "2",
        "--direction",
        "both",
        "--settle",
    ];
    let (code, _, err) = sweep(&out, &flags);
    assert_eq!(code, 0, "{err}");
    let files = |branch: &str| {
        [
            dir.join(format!("b.{branch}.csv")),
            dir.join(format!("b.{branch}.verdicts.csv")),
        ]
    };
    let whole: Vec<String> = ["up", "down"]
        .iter()
        .flat_map(|b| files(b))
        .map(|f| read(&f))
        .collect();
    assert!(
        whole[1].starts_with(
            "index,joints.B.clearance,verdict,k,transient_turns,start,end_state,message\n"
        ),
        "{}",
        whole[1]
    );
    // As if stopped: up lost points 2, 4, 5 (chunks 0–2 and 3–5), down lost point 1 (its
    // chunk runs 2, 1, 0: point 0, finished after the gap, runs again).
    for (branch, drop) in [("up", &[2, 4, 5][..]), ("down", &[1][..])] {
        for f in files(branch) {
            std::fs::write(&f, without(&read(&f), drop)).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    let (code, _, err) = sweep(&out, &[&flags[..], &["--resume"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("12 points, warm-started in 2 chunks up and down: 7 finished, 5 to run"),
        "{err}"
    );
    let resumed: Vec<String> = ["up", "down"]
        .iter()
        .flat_map(|b| files(b))
        .map(|f| read(&f))
        .collect();
    for (a, b) in whole.iter().zip(&resumed) {
        assert_eq!(a, b, "resumed vs uninterrupted");
    }
}

fn reduced(clearance: f64) -> ReducedLagrangian {
    let set = [
        "drivers.motor.speed_rpm=3500".to_string(),
        format!("joints.B.clearance={clearance}"),
        "joints.B.initial_eccentricity=[0.0001,0.00005]".to_string(),
    ];
    let model = linkdyn::model::load(MODEL.as_ref(), &set).unwrap_or_else(|e| panic!("{e}"));
    ReducedLagrangian::new(&model).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_warm_state_is_carried_into_the_new_clearance() {
    use linkdyn::formulation::Formulation;
    let a = reduced(0.4e-3);
    let from = a.warm_state(0.0, &a.initial_state());
    let close = |x: [f64; 2], y: [f64; 2], tol: f64| (x[0] - y[0]).hypot(x[1] - y[1]) <= tol;
    // Inside the clearance: the journal keeps its place relative to the wall (e scaled by
    // c/c′ = 1/2), and ė with it (0 here: assembled at rest relative to the bearing).
    let mut b = reduced(0.2e-3);
    b.start_from(0.0, &from).unwrap_or_else(|e| panic!("{e}"));
    let got = b.warm_state(b.t0(), &b.initial_state());
    assert!(
        close(got.eccentricity, [0.5e-4, 0.25e-4], 1e-12),
        "free: e = {:?}",
        got.eccentricity
    );
    assert!(
        close(got.eccentricity_rate, [0.0, 0.0], 1e-9),
        "free: ė = {:?}",
        got.eccentricity_rate
    );
    assert_eq!(got.y[4], 0.0, "free: no stored impact velocity");
    // In contact (|e| = c′ + 2 µm, moving at ė): the penetration, ė and the stored impact
    // velocity carry over, so the contact force does not jump.
    let contact = WarmState {
        eccentricity: [0.402e-3, 0.0],
        eccentricity_rate: [0.01, 0.02],
        y: [from.y[0], from.y[1], from.y[2], from.y[3], 0.05],
        clearance: 0.4e-3,
    };
    let mut b = reduced(0.2e-3);
    b.start_from(0.0, &contact)
        .unwrap_or_else(|e| panic!("{e}"));
    let got = b.warm_state(b.t0(), &b.initial_state());
    assert!(
        close(got.eccentricity, [0.202e-3, 0.0], 1e-12),
        "contact: e = {:?}",
        got.eccentricity
    );
    assert!(
        close(got.eccentricity_rate, [0.01, 0.02], 1e-9),
        "contact: ė = {:?}",
        got.eccentricity_rate
    );
    assert_eq!(
        got.y[4], 0.05,
        "contact: the stored impact velocity is kept"
    );
}
