//! Without the cargo feature `ida`, `--method ida` is refused with a message that says how to
//! rebuild, in the library (`Method::from_str`) and on the command line (exit code 2, bad input).
#![cfg(not(feature = "ida"))]

mod cli_common;

use cli_common::{linkdyn, path_arg, scratch};
use linkdyn::solve::Method;

const EXPECTED: &str = "invalid solver option `method`: \"ida\" (SUNDIALS IDA) is not in this build: rebuild with \"cargo build --release --features ida\" (needs cmake and libclang; see the README, \"SUNDIALS IDA (optional)\")";

#[test]
fn the_library_says_how_to_rebuild() {
    let err = "ida".parse::<Method>().err().map(|e| e.to_string());
    assert_eq!(err.as_deref(), Some(EXPECTED));
}

#[test]
fn the_cli_refuses_ida_with_exit_code_2() {
    let out = scratch("refused").join("ida.csv");
    let (code, _, stderr) = linkdyn(&[
        "run",
        "models/fourbar_ideal.toml",
        "--method",
        "ida",
        "--revs",
        "1",
        "--out",
        path_arg(&out),
    ]);
    assert_eq!(code, 2, "exit code; stderr: {stderr}");
    assert!(!out.exists(), "nothing written for a refused method");
    assert!(
        stderr.contains("rebuild with \"cargo build --release --features ida\""),
        "the message says how to rebuild: {stderr}"
    );
}
