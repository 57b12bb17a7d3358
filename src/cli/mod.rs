//! Command-line interface: one file per subcommand. Only calls the library.
//!
//! Exit codes: 0 success; 2 bad input (model file, `--set`, options, a linkage that cannot be
//! assembled or does not fit the formulation); 3 the solver failed (the message says when and
//! why); 4 a result file could not be written.

mod check;
mod compare;
mod run;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Dynamics of planar linkages with ideal and clearance revolute joints.
#[derive(Debug, Parser)]
#[command(name = "linkdyn", version = env!("CARGO_PKG_VERSION"), about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Validate and assemble a model; print bodies, joints, drivers, DOF, redundant constraints.
    Check(check::CheckArgs),
    /// Integrate a model and write a CSV of outputs and a JSON summary.
    Run(run::RunArgs),
    /// Run the DAE and the reduced formulation with the same settings; print their differences.
    Compare(compare::CompareArgs),
}

/// Exit code for bad input.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code for a solver failure.
pub const EXIT_SOLVER: u8 = 3;
/// Exit code for a result file that could not be written.
pub const EXIT_OUTPUT: u8 = 4;

/// An error with the exit code it maps to.
#[derive(Debug)]
pub struct Failure {
    code: u8,
    error: anyhow::Error,
}

impl From<crate::Error> for Failure {
    fn from(e: crate::Error) -> Self {
        let code = match &e {
            crate::Error::Model(_) | crate::Error::Formulation(_) => EXIT_BAD_INPUT,
            crate::Error::Solve(_) => EXIT_SOLVER,
            crate::Error::Output(_) => EXIT_OUTPUT,
        };
        Failure {
            code,
            error: e.into(),
        }
    }
}

impl Failure {
    /// Bad input with a message.
    pub fn bad_input(message: impl Into<String>) -> Self {
        Failure {
            code: EXIT_BAD_INPUT,
            error: anyhow::anyhow!(message.into()),
        }
    }
}

/// A formulation error about the model in `path` (e.g. it cannot be assembled): the message
/// names the file.
pub fn fail_model<E: Into<crate::Error>>(path: &std::path::Path, e: E) -> Failure {
    let mut f = fail(e);
    if f.code == EXIT_BAD_INPUT {
        f.error = f.error.context(path.display().to_string());
    }
    f
}

/// Converts any layer's error into a [`Failure`] through [`crate::Error`].
pub fn fail<E: Into<crate::Error>>(e: E) -> Failure {
    Failure::from(e.into())
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(EXIT_BAD_INPUT)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match cli.command {
        Command::Check(args) => check::run(&args),
        Command::Run(args) => run::run(&args),
        Command::Compare(args) => compare::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            let mut message = f.error.to_string();
            for cause in f.error.chain().skip(1) {
                let text = cause.to_string();
                if !message.contains(&text) {
                    message.push_str(": ");
                    message.push_str(&text);
                }
            }
            eprintln!("error: {message}");
            ExitCode::from(f.code)
        }
    }
}
