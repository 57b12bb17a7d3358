//! Without the cargo feature `ida`, `--method ida` is refused with a message that says how to
//! rebuild, in the library (`Method::from_str`) and on the command line (exit code 2, bad input).
#![cfg(not(feature = "ida"))]

use linkdyn::solve::Method;

const EXPECTED: &str = "invalid solver option `method`: \"ida\" (SUNDIALS IDA) is not in this build: rebuild with \"cargo build --release --features ida\" (needs cmake and libclang; see the README, \"SUNDIALS IDA (optional)\")";

#[test]
fn the_library_says_how_to_rebuild() {
    let err = "ida".parse::<Method>().err().map(|e| e.to_string());
    assert_eq!(err.as_deref(), Some(EXPECTED));
}

#[test]
fn the_cli_refuses_ida_with_exit_code_2() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_linkdyn"))
        .args([
            "run",
            "models/fourbar_ideal.toml",
            "--method",
            "ida",
            "--revs",
            "1",
            "--out",
        ])
        .arg(std::env::temp_dir().join(format!("linkdyn-no-ida-{}", std::process::id())))
        .output()
        .unwrap_or_else(|e| panic!("{e}"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "exit code; stderr: {stderr}");
    assert!(
        stderr.contains("rebuild with \"cargo build --release --features ida\""),
        "the message says how to rebuild: {stderr}"
    );
}
