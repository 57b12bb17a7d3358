//! `linkdyn reproduce` refuses to write into a directory that is not a previous reproduction
//! (exit 2, naming it), leaving it and its parent untouched, and refuses a model that does not
//! load before any work. (The whole `--quick` reproduction runs in CI: `.ci/run`.)

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
