//! Hostile input and hostile ends of a run, each refused or cleaned up with an exact message
//! (a seeded corpus of the classes a fuzzing run found; the inputs are generated here because
//! some are megabytes):
//!
//! * input that overflowed the stack or took quadratic time: an expression of 15 000 terms in a
//!   `--set` value, a `--set` path of 20 000 parts, a chain of parameters each naming the
//!   previous; input too large to parse in bounded memory (a model file over 4 MiB);
//! * a file-size limit (`ulimit -f`) passed while writing: exit 4 and nothing left, where
//!   SIGXFSZ used to kill the process and leave its temporary file and lock;
//! * a run killed outright (SIGKILL): its leftovers are removed by `linkdyn clean` or by the
//!   next run on the same output; a commit cut between its renames is completed from its
//!   journal;
//! * `linkdyn merge` given a shard that lost rows, or an `--out` that is one of its inputs.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod cli_common;
use cli_common::{linkdyn, scratch};

const BIN: &str = env!("CARGO_BIN_EXE_linkdyn");
const MODEL: &str = "models/fourbar_ideal.toml";

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

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// As the library quotes a long value: its first 60 characters and its length.
fn abbreviated(text: &str) -> String {
    let head: String = text.chars().take(60).collect();
    format!("{head}… ({} characters)", text.chars().count())
}

#[test]
fn an_expression_of_15000_terms_in_a_set_value_is_refused_not_a_stack_overflow() {
    let sum = vec!["1"; 15_000].join("+");
    let assignment = format!("bodies.crank.mass={sum}");
    let (code, _, stderr) = linkdyn(&["check", MODEL, "--set", &assignment]);
    assert_eq!(
        (code, stderr),
        (
            2,
            format!(
                "error: {MODEL}:17:8: bodies.crank.mass: in expression \"{}\": expression longer than 1000 tokens (numbers, names, operators, parentheses); expected at most 1000: move parts of it into [parameters] (value from --set {})\n",
                abbreviated(&sum),
                abbreviated(&assignment)
            )
        )
    );
}

#[test]
fn a_set_path_of_20000_parts_is_refused_not_a_stack_overflow() {
    let assignment = format!("{}=1", vec!["a"; 20_000].join("."));
    let (code, _, stderr) = linkdyn(&["check", MODEL, "--set", &assignment]);
    assert_eq!(
        (code, stderr),
        (
            2,
            format!(
                "error: --set {}: the path has 20000 parts; expected at most 16 (the deepest field of a model file is a few levels down)\n",
                abbreviated(&assignment)
            )
        )
    );
    // 16 parts is allowed (and then refused for what it names, not for its length).
    let (code, _, stderr) =
        linkdyn(&["check", MODEL, "--set", "a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p=1"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(!stderr.contains("parts"), "{stderr}");
}

#[test]
fn a_chain_of_parameters_is_evaluated_up_to_1000_long_and_refused_beyond() {
    let dir = scratch("chain");
    let base = read(Path::new(MODEL));
    let chain = |n: usize| {
        let mut text = format!("{base}\n[parameters]\np0 = 1.0\n");
        for k in 1..=n {
            text.push_str(&format!("p{k} = \"p{} + 0\"\n", k - 1));
        }
        text
    };
    let ok = dir.join("chain1000.toml");
    let _ = std::fs::write(&ok, chain(1000));
    let (code, stdout, stderr) = linkdyn(&["check", &s(&ok)]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let long = dir.join("chain1001.toml");
    let text = chain(1001);
    let _ = std::fs::write(&long, &text);
    let line = text
        .lines()
        .position(|l| l.starts_with("p1001 = "))
        .map_or(0, |k| k + 1);
    let (code, _, stderr) = linkdyn(&["check", &s(&long)]);
    assert_eq!(
        (code, stderr),
        (
            2,
            format!(
                "error: {}:{line}:1: parameters.p1001: parameter p1001 depends on a chain of more than 1000 parameters each naming the next; expected at most 1000\n",
                long.display()
            )
        )
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_model_file_over_4_mib_is_refused_before_it_is_parsed() {
    let dir = scratch("size");
    let big = dir.join("blank.toml");
    // Blank lines: the input that cost 50 bytes of memory per byte to parse.
    let _ = std::fs::write(&big, " \n".repeat((4 << 20) / 2 + 1));
    let (code, _, stderr) = linkdyn(&["check", &s(&big)]);
    assert_eq!(
        (code, stderr),
        (
            2,
            format!(
                "error: {}: the model file is larger than 4194304 bytes (4 MiB); expected at most that\n",
                big.display()
            )
        )
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs `linkdyn ARGS` under `ulimit -f 100` (a shell's file-size limit).
fn under_file_size_limit(args: &[String]) -> (Option<i32>, String) {
    let out = Command::new("sh")
        .arg("-c")
        .arg(r#"ulimit -f 100 && exec "$0" "$@""#)
        .arg(BIN)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap_or_else(|e| panic!("cannot run sh: {e}"));
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_file_size_limit_is_a_write_failure_that_leaves_nothing() {
    let dir = scratch("ulimit");
    let csv = dir.join("big.csv");
    let run = |out: &Path, format: &str| {
        under_file_size_limit(&[
            "run".into(),
            MODEL.into(),
            "--revs".into(),
            "20".into(),
            "--dt".into(),
            "1e-6".into(),
            "--format".into(),
            format.into(),
            "--out".into(),
            s(out),
        ])
    };
    let (code, stderr) = run(&csv, "csv");
    // Exit 153 (128 + SIGXFSZ) before: the process was killed mid-write.
    assert_eq!(code, Some(4), "{stderr}");
    let stderr = stderr.trim_end();
    let suffix = format!(
        ": cannot write {}: File too large (os error 27)",
        csv.display()
    );
    assert!(
        stderr.starts_with("error: output failed at t = ") && stderr.ends_with(&suffix),
        "{stderr}"
    );
    assert_eq!(
        entries(&dir),
        Vec::<String>::new(),
        "CSV: no temporary file, no lock"
    );
    let npz = dir.join("big.npz");
    let (code, stderr) = run(&npz, "npz");
    assert_eq!(
        (code, stderr.trim_end()),
        (
            Some(4),
            format!(
                "error: cannot write {}: File too large (os error 27)",
                npz.display()
            )
            .as_str()
        )
    );
    assert_eq!(
        entries(&dir),
        Vec::<String>::new(),
        "NPZ: no temporary file, no lock"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run long enough to be killed while it streams (minutes of integration).
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
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"))
}

/// Kills a run with SIGKILL once its temporary file of `target` in `dir` holds 64 KiB (it is
/// streaming); returns the temporary file's name.
fn kill_while_streaming(dir: &Path, target: &str, mut child: Child) -> String {
    let prefix = format!(".{target}.linkdyn-{}-", child.id());
    let started = Instant::now();
    let name = loop {
        let found = entries(dir)
            .into_iter()
            .find(|n| n.starts_with(&prefix) && n.ends_with(".tmp"));
        if let Some(n) = found
            && std::fs::metadata(dir.join(&n)).is_ok_and(|m| m.len() >= 1 << 16)
        {
            break n;
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("run ended before it was killed: {status}");
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no temporary file of {target} appeared"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let _ = child.kill();
    let _ = child.wait();
    name
}

#[test]
fn what_a_killed_run_leaves_is_removed_by_clean_and_by_the_next_run() {
    let dir = scratch("killed");
    let csv = dir.join("r.csv");
    let temp = kill_while_streaming(&dir, "r.csv", long_run(&csv));
    // A killed process cleans nothing: its temporary file and lock file stay.
    assert_eq!(entries(&dir), [temp.as_str(), "r.csv.lock"]);
    let (code, _, stderr) = linkdyn(&["clean", &s(&csv)]);
    assert_eq!(
        (code, stderr),
        (
            0,
            format!(
                "removed 1 temporary file of killed runs beside {}: {temp}\n",
                csv.display()
            )
        )
    );
    assert_eq!(entries(&dir), Vec::<String>::new());
    let (code, _, stderr) = linkdyn(&["clean", &s(&csv)]);
    assert_eq!(
        (code, stderr),
        (
            0,
            format!("{}: nothing left by killed runs\n", csv.display())
        )
    );

    // The next run on the same output does the same before it starts.
    let temp = kill_while_streaming(&dir, "r.csv", long_run(&csv));
    let (code, _, stderr) = linkdyn(&["run", MODEL, "--revs", "0.25", "--out", &s(&csv)]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(
        stderr.lines().next(),
        Some(
            format!(
                "note: removed 1 temporary file of killed runs beside {}: {temp}",
                csv.display()
            )
            .as_str()
        )
    );
    assert_eq!(entries(&dir), ["r.csv", "r.impacts.csv", "r.json"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_commit_killed_between_its_renames_is_completed_from_its_journal() {
    let dir = scratch("journal");
    let csv = dir.join("r.csv");
    // What a kill after the CSV's rename leaves: the new CSV beside the earlier summary and
    // impact log, the new ones still in their temporary files, the journal and the lock.
    // 4194305 = 2^22 + 1 is above the largest pid Linux gives, so the writer is dead.
    let json_temp = ".r.json.linkdyn-4194305-00000000000000ab.tmp";
    let log_temp = ".r.impacts.csv.linkdyn-4194305-00000000000000cd.tmp";
    let files = [
        ("r.csv", "new csv\n"),
        ("r.json", "old json\n"),
        ("r.impacts.csv", "old log\n"),
        (json_temp, "new json\n"),
        (log_temp, "new log\n"),
        ("r.csv.lock", ""),
        (
            "r.csv.commit",
            // The CSV's rename is done (its temporary file is gone); a line naming a file
            // outside the directory is ignored.
            &format!(
                "linkdyn commit journal\n.r.csv.linkdyn-4194305-00000000000000ef.tmp\tr.csv\n{json_temp}\t../victim\n{json_temp}\tr.json\n{log_temp}\tr.impacts.csv\n"
            ),
        ),
    ];
    for (name, text) in files {
        let _ = std::fs::write(dir.join(name), text);
    }
    // A command that reads the CSV meanwhile says that the files may be from two runs.
    let png = scratch("plot-meanwhile").join("p.png");
    let (_, _, stderr) = linkdyn(&["plot", "series", &s(&csv), "--y", "x", "--out", &s(&png)]);
    assert_eq!(
        stderr.lines().next(),
        Some(format!(
            "note: {}.commit exists: a run writing {} was killed between its renames (or is finishing them now), so it and the files beside it may be from different runs; `linkdyn clean {}` completes the commit",
            csv.display(),
            csv.display(),
            csv.display()
        ).as_str())
    );
    let (code, _, stderr) = linkdyn(&["clean", &s(&csv)]);
    assert_eq!(
        (code, stderr),
        (
            0,
            format!(
                "a run writing {} was killed between its renames; completed its commit (renamed its r.json, r.impacts.csv into place), so the files beside it are again from one run\n",
                csv.display()
            )
        )
    );
    assert_eq!(entries(&dir), ["r.csv", "r.impacts.csv", "r.json"]);
    assert_eq!(read(&dir.join("r.json")), "new json\n");
    assert_eq!(read(&dir.join("r.impacts.csv")), "new log\n");
    assert!(!dir.join("../victim").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two shards of a small sweep (3 points each, 4 recorded turns per point) in `dir`.
fn shards(dir: &Path) -> (PathBuf, PathBuf) {
    let (a, b) = (dir.join("s1.csv"), dir.join("s2.csv"));
    for (out, shard) in [(&a, "1/2"), (&b, "2/2")] {
        let (code, _, stderr) = linkdyn(&[
            "bifurcation",
            "models/farahan2016.toml",
            "--param",
            "joints.B.clearance",
            "--from",
            "0.0002",
            "--to",
            "0.0005",
            "--steps",
            "5",
            "--revs",
            "12",
            "--transient",
            "8",
            "--observe",
            "coupler.phi",
            "--set",
            "drivers.motor.speed_rpm=3500",
            "--formulation",
            "reduced",
            "--shard",
            shard,
            "--out",
            &s(out),
        ]);
        assert_eq!(code, 0, "{stderr}");
    }
    (a, b)
}

#[test]
fn merge_refuses_a_shard_that_lost_rows_and_an_out_that_is_an_input() {
    let dir = scratch("merge");
    let (a, b) = shards(&dir);
    let (before_a, before_b) = (read(&a), read(&b));
    // --out spelled differently, or naming an input's verdicts: refused, inputs untouched.
    let verdicts_a = dir.join("s1.verdicts.csv");
    for out in [dir.join(".").join("s1.csv"), verdicts_a.clone()] {
        let (code, _, stderr) = linkdyn(&["merge", &s(&a), &s(&b), "--out", &s(&out)]);
        let input = if out == verdicts_a { &verdicts_a } else { &a };
        assert_eq!(
            (code, stderr),
            (
                2,
                format!(
                    "error: --out: {} would overwrite {}, one of the files to merge; choose another name\n",
                    out.display(),
                    input.display()
                )
            )
        );
    }
    assert_eq!((read(&a), read(&b)), (before_a.clone(), before_b));
    // Three whole rows of point 2 (of its 4) lost: every point is still present, but not whole.
    let cut: String = before_a
        .split_inclusive('\n')
        .filter(|l| !(l.starts_with("2,") && l.split(',').nth(2) != Some("8")))
        .collect();
    assert_eq!(
        before_a.lines().count() - cut.lines().count(),
        3,
        "three rows dropped"
    );
    let _ = std::fs::write(&a, cut);
    let merged = dir.join("merged.csv");
    let (code, _, stderr) = linkdyn(&["merge", &s(&a), &s(&b), "--out", &s(&merged)]);
    assert_eq!(
        (code, stderr),
        (
            2,
            format!(
                "error: --files: {}: point 2 has 1 row, expected 4 (one per recorded turn, revs − transient_revs): the file lost or gained rows\n",
                a.display()
            )
        )
    );
    assert!(!merged.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
