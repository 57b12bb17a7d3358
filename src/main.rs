//! The `linkdyn` command: parses arguments, runs the subcommand, maps errors to exit codes.

use std::process::ExitCode;

fn main() -> ExitCode {
    linkdyn::cli::main()
}
