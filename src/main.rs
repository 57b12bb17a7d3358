//! The `linkdyn` command: parses arguments, runs the subcommand through the library, prints,
//! and maps errors to exit codes (see [`cli`]).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::main()
}
