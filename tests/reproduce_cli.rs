//! `linkdyn reproduce` refuses to write into a directory that is not a previous reproduction
//! (exit 2, naming it), leaving it and its parent untouched, and refuses a model that does not
//! load before any work; its default model is found from any directory. (The whole `--quick`
//! reproduction runs in CI: `.ci/run`.)

mod cli_common;

use cli_common::{linkdyn, scratch};

#[test]
fn an_existing_directory_without_a_report_is_refused_and_left_alone() {
    let parent = scratch("refused");
    let out = parent.join("mine");
    std::fs::create_dir_all(&out).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(out.join("notes.txt"), "keep me").unwrap_or_else(|e| panic!("{e}"));
    let out_s = out.to_string_lossy().into_owned();
    let (code, _, err) = linkdyn(&["reproduce", "--quick", "--out", &out_s]);
    assert_eq!(code, 2, "exit code; stderr: {err}");
    assert_eq!(
        err,
        format!(
            "error: --out {out_s}: exists and is not a previous reproduction (no report.md); choose a new directory\n"
        )
    );
    let mut left: Vec<String> = std::fs::read_dir(&parent)
        .unwrap_or_else(|e| panic!("{e}"))
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect();
    left.sort();
    assert_eq!(left, ["mine"], "temporary directories left behind");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt"))
            .ok()
            .as_deref(),
        Some("keep me")
    );

    // A model that does not load: exit 2 before any work, no directory.
    let fresh = parent.join("fresh");
    let (code, _, err) = linkdyn(&[
        "reproduce",
        "--quick",
        "--model",
        "models/no_such_model.toml",
        "--out",
        &fresh.to_string_lossy(),
    ]);
    assert_eq!(code, 2, "exit code; stderr: {err}");
    assert!(err.contains("models/no_such_model.toml"), "{err}");
    assert!(!fresh.exists(), "{} was created", fresh.display());
    let _ = std::fs::remove_dir_all(&parent);
}

/// From a directory other than the repository root, the default model is the one of the source
/// tree the binary was built from (said on stderr), found before any directory is made: here the
/// output is then refused as above, so nothing runs.
#[test]
fn the_default_model_is_found_from_any_directory() {
    let elsewhere = cli_common::scratch("elsewhere");
    let out = elsewhere.join("mine");
    std::fs::create_dir_all(&out).unwrap_or_else(|e| panic!("{e}"));
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_linkdyn"))
        .args(["reproduce", "--quick", "--out", "mine"])
        .current_dir(&elsewhere)
        .output()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    let err = String::from_utf8_lossy(&run.stderr);
    let model = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/farahan2016.toml");
    assert_eq!(
        err,
        format!(
            "reproduce: model {}\nerror: --out mine: exists and is not a previous reproduction (no report.md); choose a new directory\n",
            model.display()
        )
    );
    assert_eq!(run.status.code(), Some(2), "exit code; stderr: {err}");
    let _ = std::fs::remove_dir_all(&elsewhere);
}
