//! Running the built `linkdyn` binary from the command-line tests.
#![allow(dead_code)] // each test file uses some of these

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `linkdyn ARGS…` in the crate root; returns (exit code, stdout, stderr). A process
/// ended by a signal reads as exit code −1.
pub fn linkdyn(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_linkdyn"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap_or_else(|e| panic!("cannot run linkdyn: {e}"));
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `linkdyn ARGS…` as [`linkdyn`] does; returns (exit code, stderr), for the tests that
/// read only what it says on stderr.
pub fn linkdyn_stderr(args: &[&str]) -> (i32, String) {
    let (code, _, stderr) = linkdyn(args);
    (code, stderr)
}

/// A fresh, empty folder for one test's files: `<temp>/linkdyn-<test file>-<name>-<pid>`
/// (the test file from the test binary's name, so that two files never share one).
pub fn scratch(name: &str) -> PathBuf {
    let suite = std::env::current_exe()
        .ok()
        .and_then(|exe| exe.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .map(|stem| {
            stem.rsplit_once('-')
                .map_or(stem.clone(), |(s, _)| s.to_string())
        })
        .unwrap_or_else(|| "tests".into());
    let dir = std::env::temp_dir().join(format!("linkdyn-{suite}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// A path as one `linkdyn` argument (the test folders above are valid UTF-8).
pub fn path_arg(path: &Path) -> &str {
    path.to_str()
        .unwrap_or_else(|| panic!("not UTF-8: {}", path.display()))
}
