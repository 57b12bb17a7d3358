//! Running the built `linkdyn` binary from the command-line tests.

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
