//! Command-line interface: one file per subcommand. Parses, calls the library, prints.
//!
//! Exit codes: 0 success; 2 bad input (model file, `--set`, options, `--out`, a linkage that
//! cannot be assembled or does not fit the formulation); 3 the solver failed (the message says
//! when and why); 4 a result file could not be written; 5 a sweep finished with failed points
//! (recorded in its files; `--resume` retries them); 130 interrupted (SIGINT, SIGTERM or
//! SIGHUP during `run`: no result file is left behind).

mod animate;
mod args;
mod bifurcation;
mod check;
mod clean;
mod compare;
mod compare_laws;
mod continuation;
mod interrupt;
mod lyapunov;
mod merge;
mod orbit;
mod phase;
mod plot;
mod poincare;
mod progress;
mod reproduce;
mod run;
mod schema;
mod spectrum;
mod stress;
mod wear;
mod workprecision;

use clap::{Parser, Subcommand};
use linkdyn::Error;
use linkdyn::analysis::AnalysisError;
use linkdyn::output::OutputError;
use linkdyn::solve::SolveError;
use std::path::Path;
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
    /// Run one scene once per contact law of a clearance joint; print and write peak forces,
    /// impact counts and the driver torque's RMS difference per law.
    CompareLaws(compare_laws::CompareLawsArgs),
    /// Poincaré section once per driver turn (CSV `turn,t,<cols>`) and its period verdict.
    Poincare(poincare::PoincareArgs),
    /// Bifurcation diagram: sweep a model field, record a column once per turn at each value.
    Bifurcation(bifurcation::BifurcationArgs),
    /// Join the shard files of a bifurcation sweep, checking no point is missing or doubled.
    Merge(merge::MergeArgs),
    /// Amplitude spectrum of an output column (CSV `frequency_hz,amplitude`) and its peaks.
    Spectrum(spectrum::SpectrumArgs),
    /// Phase-portrait data of an output column (CSV `t,value,rate`).
    Phase(phase::PhaseArgs),
    /// Largest Lyapunov exponent (CSV `t,lambda` of its convergence), printed with its error.
    Lyapunov(lyapunov::LyapunovArgs),
    /// Periodic orbit by shooting, with its Floquet multipliers (F.json, one period in F.csv).
    Orbit(orbit::OrbitArgs),
    /// Continue a periodic orbit in one model field (pseudo-arclength): F.csv one row per
    /// point, folds, period doublings, Neimark–Sacker points and grazing located.
    Continue(continuation::ContinueArgs),
    /// Archard wear of a clearance joint's bearing over many turns, the profile updated every
    /// M turns: wear depth per bin (DIR/wear.csv), summary (DIR/wear.json), polar figure.
    Wear(wear::WearArgs),
    /// Draw a figure (PNG or SVG) from result CSV files: series, orbit, poincare, bifurcation,
    /// spectrum, phase, lyapunov.
    Plot(plot::PlotArgs),
    /// The analogues of Figs. 3–7 of Farahan et al. (2016) per friction variant, with a report
    /// judging the paper's claims (DIR/report.md).
    Reproduce(reproduce::ReproduceArgs),
    /// Animate a model (run first) or a result file: self-contained HTML player, animated SVG
    /// or GIF.
    Animate(animate::AnimateArgs),
    /// Stiff and extreme cases × formulations × methods with a verdict each (ok, slow, failed, refused).
    Stress(stress::StressArgs),
    /// Error against run time for every formulation × method × tolerance (CSV, markdown, plot).
    Workprecision(workprecision::WorkPrecisionArgs),
    /// Complete or remove what runs killed outright left beside result files (temporary files,
    /// a commit cut between its renames, a stale lock); every run on a target does this first.
    Clean(clean::CleanArgs),
    /// Print the JSON Schema of the model file, for TOML editors (`linkdyn schema >
    /// linkdyn.schema.json`; docs/model_format.md, "Editor support").
    Schema(schema::SchemaArgs),
}

/// Loads a model file with its `--set` overrides, makes the clearance joints named by `--ideal`
/// ideal (`ideal`), and prints the model's notes (fields dropped by a law switch, for example) as
/// `note: …` lines on stderr.
pub fn load_model(
    path: &Path,
    set: &[String],
    ideal: &[String],
) -> Result<linkdyn::model::Model, linkdyn::model::ModelError> {
    let model = linkdyn::model::idealise(linkdyn::model::load(path, set)?, ideal)?;
    for note in &model.notes {
        eprintln!("note: {note}");
    }
    for warning in &model.warnings {
        eprintln!("warning: {warning}");
    }
    Ok(model)
}

/// Reads a result CSV as a table, first warning (a `note:` on stderr) if its commit journal is
/// there: a run writing it was killed between its renames (or is committing right now), so the
/// files beside it may be from two runs until the next run or `linkdyn clean` completes it.
pub fn read_result(path: &Path) -> Result<linkdyn::plot::Table, linkdyn::plot::PlotError> {
    let journal = linkdyn::output::journal_path(path);
    if journal.exists() {
        eprintln!(
            "note: {} exists: a run writing {} was killed between its renames (or is finishing them now), so it and the files beside it may be from different runs; `linkdyn clean {}` completes the commit",
            journal.display(),
            path.display(),
            path.display()
        );
    }
    linkdyn::plot::Table::read(path)
}

/// One CSV field, quoted as RFC 4180 says where needed.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Exit code for bad input.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code for a solver failure.
pub const EXIT_SOLVER: u8 = 3;
/// Exit code for a result file that could not be written.
pub const EXIT_OUTPUT: u8 = 4;
/// Exit code of a sweep that finished with failed points (each recorded in its files with the
/// message; `--resume` retries them).
pub const EXIT_FAILED_POINTS: u8 = 5;
/// Exit code after SIGINT/SIGTERM (128 + SIGINT, the shell's convention).
pub const EXIT_INTERRUPTED: u8 = 130;

/// An error message with the exit code it maps to.
#[derive(Debug)]
pub struct Failure {
    code: u8,
    message: String,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        let code = match &e {
            Error::Model(_) | Error::Formulation(_) | Error::Settings { .. } => EXIT_BAD_INPUT,
            Error::Solve(SolveError::Sink { .. }) => EXIT_OUTPUT,
            Error::Solve(_) => EXIT_SOLVER,
            Error::Output(o) if o.is_bad_input() => EXIT_BAD_INPUT,
            Error::Output(_) => EXIT_OUTPUT,
            Error::Analysis(
                AnalysisError::Solve { .. }
                | AnalysisError::Outputs { .. }
                | AnalysisError::NoConvergence { .. },
            ) => EXIT_SOLVER,
            Error::Analysis(_) => EXIT_BAD_INPUT,
        };
        Failure {
            code,
            message: message(&e),
        }
    }
}

impl From<OutputError> for Failure {
    fn from(e: OutputError) -> Self {
        Failure::from(Error::from(e))
    }
}

impl From<linkdyn::model::ModelError> for Failure {
    fn from(e: linkdyn::model::ModelError) -> Self {
        Failure::from(Error::from(e))
    }
}

impl Failure {
    /// The run was interrupted by a signal.
    fn interrupted() -> Self {
        Failure {
            code: EXIT_INTERRUPTED,
            message: "interrupted; no result files were written".into(),
        }
    }
}

/// A library error met while building a simulation of the model in `path`: a formulation
/// error (e.g. the linkage cannot be assembled) is prefixed with the file's name.
fn in_model(path: &Path, e: Error) -> Failure {
    let prefix = matches!(e, Error::Formulation(_));
    let mut f = Failure::from(e);
    if prefix {
        f.message = format!("{}: {}", path.display(), f.message);
    }
    f
}

/// The command-line spelling of a library option name: `t_end` → `--t-end`.
fn flag(option: &str) -> String {
    format!("--{}", option.replace('_', "-"))
}

/// The message of a library error for the command line: settings as flags, every cause once.
fn message(e: &Error) -> String {
    match e {
        Error::Settings { option, reason } => {
            // Other options are named in backticks by the library: spell them as flags.
            let mut text = String::new();
            for (k, part) in reason.split('`').enumerate() {
                if k % 2 == 1 {
                    text.push_str(&flag(part));
                } else {
                    text.push_str(part);
                }
            }
            format!("{}: {text}", flag(option))
        }
        Error::Output(OutputError::Target { path, reason }) => format!("--out {path}: {reason}"),
        _ => {
            let mut message = e.to_string();
            let mut cause = std::error::Error::source(e);
            while let Some(c) = cause {
                let text = c.to_string();
                if !message.contains(&text) {
                    message.push_str(": ");
                    message.push_str(&text);
                }
                cause = c.source();
            }
            message
        }
    }
}

/// Makes exceeding the file-size limit (`ulimit -f`) a write error instead of a kill.
///
/// By default the kernel ends a process with SIGXFSZ when a write would pass the limit, before
/// any cleanup can run: the temporary file and the lock stay. Ignored, the write fails with
/// EFBIG ("File too large"), which ends the run like any failed write (exit 4, temporary files
/// removed).
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN installs no handler code; it runs
    // before any thread is started.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    ignore_file_size_signal();
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
        Command::CompareLaws(args) => compare_laws::run(&args),
        Command::Poincare(args) => poincare::run(&args),
        Command::Bifurcation(args) => bifurcation::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Spectrum(args) => spectrum::run(&args),
        Command::Phase(args) => phase::run(&args),
        Command::Lyapunov(args) => lyapunov::run(&args),
        Command::Orbit(args) => orbit::run(&args),
        Command::Continue(args) => continuation::run(&args),
        Command::Wear(args) => wear::run(&args),
        Command::Plot(args) => plot::run(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Stress(args) => stress::run(&args),
        Command::Workprecision(args) => workprecision::run(&args),
        Command::Animate(args) => animate::run(&args),
        Command::Clean(args) => clean::run(&args),
        Command::Schema(args) => schema::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
