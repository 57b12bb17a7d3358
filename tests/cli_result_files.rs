//! Result files appear whole or not at all (docs/usage.md): `--out` refuses what is not a
//! regular file (a directory, a device node, a FIFO), the model file and a CSV name ending in
//! `.json`; a failed or interrupted run (SIGTERM, SIGINT) leaves no temporary file and an
//! earlier pair untouched; two runs on the same `--out` never mix their files; provenance
//! values cannot inject lines into the CSV.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod cli_common;
use cli_common::{linkdyn, scratch};

const BIN: &str = env!("CARGO_BIN_EXE_linkdyn");

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

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A short successful run writing `out` (a quarter turn of the ideal four-bar).
fn short_run(out: &Path) {
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--revs",
        "0.25",
        "--dt",
        "1e-3",
        "--out",
        &out.display().to_string(),
    ]);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn out_refuses_targets_that_are_not_regular_files() {
    let dir = scratch("targets");
    let sub = dir.join("sub");
    let _ = std::fs::create_dir_all(&sub);
    let fifo = dir.join("pipe.csv");
    let made = Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    let model = dir.join("m.toml");
    let _ = std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fourbar_ideal.toml"),
        &model,
    );
    let model_text = read(&model);
    // The summary of busy.csv would go to busy.json, which is a directory.
    let _ = std::fs::create_dir_all(dir.join("busy.json"));
    let d = |p: &Path| p.display().to_string();
    let cases = [
        (
            d(&sub),
            format!(
                "--out {}: is a directory; expected a regular file or a new name",
                d(&sub)
            ),
        ),
        (
            "/dev/null".to_string(),
            "--out /dev/null: is a character device; expected a regular file or a new name"
                .to_string(),
        ),
        (
            d(&fifo),
            format!(
                "--out {}: is a FIFO (named pipe); expected a regular file or a new name",
                d(&fifo)
            ),
        ),
        (
            d(&model),
            format!(
                "--out {}: is the model file; choose another name",
                d(&model)
            ),
        ),
        (
            d(&dir.join("r.json")),
            format!(
                "--out {}: the CSV file name ends in .json, the name of its summary file; give a name such as F.csv",
                d(&dir.join("r.json"))
            ),
        ),
        (
            d(&dir.join("busy.csv")),
            format!(
                "--out {}: its summary {}: is a directory; expected a regular file or a new name",
                d(&dir.join("busy.csv")),
                d(&dir.join("busy.json"))
            ),
        ),
    ];
    for (out, expected) in &cases {
        let (code, _, stderr) = linkdyn(&[
            "run",
            &d(&model),
            "--revs",
            "0.1",
            "--dt",
            "1e-3",
            "--out",
            out,
        ]);
        assert_eq!(code, 2, "--out {out}: exit code {code}, stderr {stderr}");
        assert_eq!(
            stderr.trim_end(),
            format!("error: {expected}"),
            "--out {out}"
        );
    }
    assert_eq!(
        entries(&dir),
        ["busy.json", "m.toml", "pipe.csv", "sub"],
        "nothing written beside the refused targets"
    );
    assert!(
        entries(&sub).is_empty(),
        "nothing written into the directory"
    );
    assert_eq!(read(&model), model_text, "model file untouched");
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let null = std::fs::metadata("/dev/null").map(|m| m.file_type().is_char_device());
        assert!(null.unwrap_or(false), "/dev/null is still a device node");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_run_leaves_the_earlier_pair_untouched_and_no_temporary_files() {
    let dir = scratch("earlier");
    let csv = dir.join("r.csv");
    short_run(&csv);
    let (before_csv, before_json) = (read(&csv), read(&dir.join("r.json")));
    // The crank of 0.45 m locks the four-bar at t = 0.097 s (see tests/bad_models.rs): exit 3.
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--set",
        "bodies.crank.points.A=[0.225,0.0]",
        "--set",
        "bodies.crank.points.O2=[-0.225,0.0]",
        "--set",
        "bodies.crank.initial.x=0.225",
        "--revs",
        "1",
        "--out",
        &csv.display().to_string(),
    ]);
    assert_eq!(code, 3, "{stderr}");
    assert_eq!(
        entries(&dir),
        ["r.csv", "r.impacts.csv", "r.json"],
        "no temporary or lock file"
    );
    assert_eq!(read(&csv), before_csv, "earlier CSV untouched");
    assert_eq!(
        read(&dir.join("r.json")),
        before_json,
        "earlier summary untouched"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Starts a run that takes many seconds (400 turns of the clearance four-bar) writing `out`.
fn long_run(out: &Path) -> Child {
    Command::new(BIN)
        .args([
            "run",
            "models/farahan2016.toml",
            "--revs",
            "400",
            "--dt",
            "1e-4",
            "--out",
        ])
        .arg(out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"))
}

/// Waits until `path` exists and holds at least `bytes` bytes (the run is streaming rows).
fn wait_for(path: &Path, bytes: u64, child: &mut Child) {
    let started = Instant::now();
    loop {
        if std::fs::metadata(path).is_ok_and(|m| m.len() >= bytes) {
            return;
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("run ended before {} appeared: {status}", path.display());
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "{} did not appear",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The temporary file of `target` written by `child`: `.F.linkdyn-<pid>-<nonce>.tmp` in `dir`,
/// if there is one yet.
fn temp_of(dir: &Path, target: &str, child: &Child) -> Option<PathBuf> {
    let prefix = format!(".{target}.linkdyn-{}-", child.id());
    entries(dir)
        .into_iter()
        .find(|n| n.starts_with(&prefix) && n.ends_with(".tmp"))
        .map(|n| dir.join(n))
}

/// Waits until `child` has written at least `bytes` to its temporary file of `target` in `dir`
/// (as [`wait_for`]); returns the file.
fn wait_for_temp(dir: &Path, target: &str, bytes: u64, child: &mut Child) -> PathBuf {
    let started = Instant::now();
    loop {
        if let Some(t) = temp_of(dir, target, child) {
            wait_for(&t, bytes, child);
            return t;
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("run ended before its temporary file of {target} appeared: {status}");
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no temporary file of {target} appeared"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Child, name: &str) {
    let sent = Command::new("kill")
        .args([format!("-{name}"), child.id().to_string()])
        .status();
    assert!(sent.is_ok_and(|s| s.success()), "kill -{name} failed");
}

/// Waits for the child (killing it after 60 s, which fails the test).
fn finish(mut child: Child) -> (Option<i32>, String) {
    let started = Instant::now();
    while child.try_wait().ok().flatten().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("run did not stop within 60 s of the signal");
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
fn sigterm_or_sigint_mid_run_leaves_nothing_but_the_earlier_pair() {
    for name in ["TERM", "INT"] {
        let dir = scratch(&format!("signal-{name}"));
        let csv = dir.join("r.csv");
        short_run(&csv);
        let (before_csv, before_json) = (read(&csv), read(&dir.join("r.json")));
        let mut child = long_run(&csv);
        // 64 KiB: the header and hundreds of rows are in the temporary file (one buffer
        // flushed), so the run is integrating and streaming.
        wait_for_temp(&dir, "r.csv", 1 << 16, &mut child);
        assert!(
            dir.join("r.csv.lock").exists(),
            "{name}: lock held during the run"
        );
        signal(&child, name);
        let (code, stderr) = finish(child);
        assert_eq!(code, Some(130), "{name}: {stderr}");
        assert_eq!(
            stderr.trim_end(),
            "error: interrupted; no result files were written",
            "{name}: stderr not a terminal, so no progress either"
        );
        assert_eq!(
            entries(&dir),
            ["r.csv", "r.impacts.csv", "r.json"],
            "{name}: leftovers"
        );
        assert_eq!(read(&csv), before_csv, "{name}: earlier CSV untouched");
        assert_eq!(
            read(&dir.join("r.json")),
            before_json,
            "{name}: earlier summary"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn a_signal_between_distant_samples_still_leaves_nothing() {
    // Samples 100 s apart (minutes of integration between them): the sink cannot see the
    // signal in time, so the handler removes the scratch files itself after its 2 s grace.
    let dir = scratch("sparse");
    let csv = dir.join("r.csv");
    let mut child = Command::new(BIN)
        .args([
            "run",
            "models/farahan2016.toml",
            "--t-end",
            "1000",
            "--dt",
            "100",
        ])
        .arg("--out")
        .arg(&csv)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{e}"));
    wait_for_temp(&dir, "r.csv", 0, &mut child);
    std::thread::sleep(Duration::from_millis(200));
    signal(&child, "TERM");
    let (code, stderr) = finish(child);
    assert_eq!(code, Some(130), "{stderr}");
    assert_eq!(
        stderr.trim_end(),
        "error: interrupted; no result files were written"
    );
    assert!(entries(&dir).is_empty(), "left: {:?}", entries(&dir));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_second_run_on_the_same_out_is_refused_while_the_first_writes() {
    let dir = scratch("busy");
    let csv = dir.join("r.csv");
    let mut first = long_run(&csv);
    wait_for(&dir.join("r.csv.lock"), 0, &mut first);
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--revs",
        "0.1",
        "--out",
        &csv.display().to_string(),
    ]);
    assert_eq!(code, 4, "{stderr}");
    assert_eq!(
        stderr.trim_end(),
        format!(
            "error: {} is being written by another run (lock {}.lock is held); wait for it or choose another output name",
            csv.display(),
            csv.display()
        )
    );
    signal(&first, "TERM");
    let (code, stderr) = finish(first);
    assert_eq!(code, Some(130), "{stderr}");
    assert!(entries(&dir).is_empty(), "left: {:?}", entries(&dir));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn concurrent_runs_on_one_out_never_mix_their_pair() {
    // Six short runs with different output intervals race for one target; each either
    // commits its pair or is refused as busy (exit 4). Whatever pair is left must come from
    // one run: the dt in the CSV's provenance equals the summary's.
    let dir = scratch("race");
    let csv = dir.join("r.csv");
    let dts = ["1e-3", "2e-3", "5e-4", "4e-3", "2.5e-4", "8e-4"];
    let children: Vec<Child> = dts
        .iter()
        .map(|dt| {
            Command::new(BIN)
                .args([
                    "run",
                    "models/farahan2016.toml",
                    "--revs",
                    "0.5",
                    "--dt",
                    dt,
                ])
                .arg("--out")
                .arg(&csv)
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap_or_else(|e| panic!("{e}"))
        })
        .collect();
    let mut committed = 0;
    for child in children {
        let (code, stderr) = finish(child);
        match code {
            Some(0) => committed += 1,
            Some(4) => assert!(
                stderr.contains("is being written by another run"),
                "{stderr}"
            ),
            other => panic!("exit {other:?}: {stderr}"),
        }
    }
    assert!(committed >= 1, "at least the first run commits");
    assert_eq!(
        entries(&dir),
        ["r.csv", "r.impacts.csv", "r.json"],
        "no leftovers"
    );
    let dt_csv = read(&csv)
        .lines()
        .find_map(|l| l.strip_prefix("# dt = ").map(str::to_string));
    let json: serde_json::Value =
        serde_json::from_str(&read(&dir.join("r.json"))).unwrap_or_default();
    let dt_json = json["provenance"]["settings"]["dt"]
        .as_str()
        .map(str::to_string);
    assert!(
        dt_csv.is_some() && dt_csv == dt_json,
        "{dt_csv:?} vs {dt_json:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_path_with_line_breaks_cannot_inject_csv_lines() {
    // A model file in a directory whose name holds a newline and a fake CSV row: the
    // provenance line that names it must stay one `#` line.
    let dir = scratch("inject");
    let evil = dir.join("x\nt,a\n0,1");
    let _ = std::fs::create_dir_all(&evil);
    let model = evil.join("m.toml");
    let _ = std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("models/fourbar_ideal.toml"),
        &model,
    );
    let csv = dir.join("r.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        &model.display().to_string(),
        "--revs",
        "0.1",
        "--dt",
        "1e-3",
        "--out",
        &csv.display().to_string(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let text = read(&csv);
    // The header row first, then the provenance comments.
    let mut lines = text.lines().skip(1);
    let comments: Vec<&str> = lines.by_ref().take_while(|l| l.starts_with("# ")).collect();
    assert!(
        comments.iter().any(|l| l.contains("x\\nt,a\\n0,1/m.toml")),
        "escaped path in {comments:?}"
    );
    let header_cols = text
        .lines()
        .find(|l| l.starts_with("t,"))
        .map(|h| h.split(',').count())
        .unwrap_or(0);
    let rows: Vec<&str> = text.lines().skip(comments.len() + 1).collect();
    // 0.1 turn at 250 rpm is 24 ms: samples at 0, 1, …, 24 ms.
    assert_eq!(rows.len(), 25, "rows");
    for row in rows {
        let values: Vec<f64> = row.split(',').filter_map(|v| v.parse().ok()).collect();
        assert_eq!(
            values.len(),
            header_cols,
            "every row numeric and complete: {row}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every command that writes a result refuses, before any work, an `--out` whose folder does
/// not exist or is a file: exit 2 and a message naming the folder, nothing created. (Before,
/// the analyses computed everything and then failed on the lock file.)
#[test]
fn a_missing_output_folder_is_refused_before_any_work() {
    let dir = scratch("missing-folder");
    let model = "models/farahan2016.toml";
    let missing = dir.join("nodir");
    let out = missing.join("p.csv");
    let out = out.to_str().unwrap_or_default();
    let html = missing.join("p.html");
    let html = html.to_str().unwrap_or_default();
    let commands: [&[&str]; 8] = [
        &["run", model, "--revs", "1", "--out", out],
        &[
            "poincare",
            model,
            "--revs",
            "4",
            "--transient",
            "1",
            "--out",
            out,
        ],
        &[
            "spectrum",
            model,
            "--revs",
            "4",
            "--transient",
            "1",
            "--observe",
            "B.ex",
            "--out",
            out,
        ],
        &[
            "phase",
            model,
            "--revs",
            "2",
            "--observe",
            "coupler.phi",
            "--out",
            out,
        ],
        &["lyapunov", model, "--revs", "4", "--out", out],
        &["compare", model, "--revs", "1", "--out", out],
        &["animate", model, "--revs", "1", "--out", html],
        &[
            "bifurcation",
            model,
            "--param",
            "joints.B.clearance",
            "--from",
            "1e-4",
            "--to",
            "2e-4",
            "--steps",
            "1",
            "--revs",
            "3",
            "--transient",
            "1",
            "--observe",
            "B.ex",
            "--out",
            out,
        ],
    ];
    let folder = missing.display().to_string();
    for args in commands {
        let (code, _, stderr) = linkdyn(args);
        let target = args.last().copied().unwrap_or_default();
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert_eq!(
            stderr,
            format!(
                "error: --out {target}: the folder {folder} does not exist; create it first (mkdir -p {folder}) or choose another\n"
            ),
            "{args:?}"
        );
        assert!(
            entries(&dir).is_empty(),
            "{args:?} left {:?}",
            entries(&dir)
        );
    }
    // A file where the folder should be.
    let file = dir.join("afile");
    std::fs::write(&file, "x").unwrap_or_else(|e| panic!("{e}"));
    let inside = file.join("p.csv");
    let (code, _, stderr) = linkdyn(&["run", model, "--out", inside.to_str().unwrap_or_default()]);
    assert_eq!(code, 2, "{stderr}");
    assert_eq!(
        stderr,
        format!(
            "error: --out {}: {} is a file, not a folder\n",
            inside.display(),
            file.display()
        )
    );
}
