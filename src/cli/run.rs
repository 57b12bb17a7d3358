//! `linkdyn run MODEL …`: integrate and write `F.csv` (streamed), `F.npz` (`--format npz`) or
//! `F.mat` (`--format mat`; both written from memory after the run), the summary `F.json` and
//! the impact log `F.impacts.csv`, committed together (see [`linkdyn::output::ResultPair`]).

use super::args::SolveArgs;
use super::progress::Watched;
use super::{Failure, in_model, interrupt};
use clap::{Args, ValueEnum};
use linkdyn::model::DriverMotion;
use linkdyn::output::{
    CsvSink, OutputError, ResultPair, check_mat, check_npz_size, format_for_people, impacts_csv,
    impacts_path, write_mat, write_npz,
};
use linkdyn::simulation::{Columns, FormulationKind, Provenance, RunSummary, Simulation};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Arguments of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Model file (TOML).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion: `dae`, `reduced` (the four-bar with one clearance joint) or
    /// `generalized`.
    #[arg(long, value_parser = parse_formulation, default_value = "dae")]
    formulation: FormulationKind,
    /// Integrate the energy bookkeeping (DAE only): adds the `energy.*` columns and the energy
    /// balance to the summary.
    #[arg(long)]
    energy: bool,
    /// Output file (CSV, NPZ or MAT, see --format); the summary goes beside it with the
    /// extension `.json`, the impact log with `.impacts.csv`.
    #[arg(long)]
    out: PathBuf,
    /// Result file format: csv (streamed to disk as the run goes), npz (NumPy: one float64
    /// array per column and the provenance as JSON) or mat (MATLAB Level-5 MAT-file: one double
    /// column vector per column, `coupler.phi` as `coupler_phi`, the provenance and the
    /// names back in `columns`; docs/usage.md, "Output files"); npz and mat are kept in memory
    /// until the run ends.
    #[arg(long, value_enum, default_value_t = Format::Csv)]
    format: Format,
}

/// Result file format of `run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    /// Comma-separated text: a header row, `#` provenance lines, one row per sample.
    Csv,
    /// NumPy `.npz`: one array per column, `provenance` as a JSON string.
    Npz,
    /// MATLAB Level-5 `.mat`: one double column vector per column (`.` and `-` become `_`),
    /// `provenance` as JSON text, the linkdyn names in the char matrix `columns`.
    Mat,
}

/// `--formulation`'s parser for every command that takes one: the library's own names and message.
pub(super) fn parse_formulation(s: &str) -> Result<FormulationKind, String> {
    s.parse().map_err(|e: linkdyn::Error| e.to_string())
}

/// Runs `run`.
pub fn run(args: &RunArgs) -> Result<(), Failure> {
    interrupt::install();
    let model = super::load_model(&args.model, &args.solve.set, &args.solve.ideal)?;
    let options = args
        .solve
        .options()?
        .formulation(args.formulation)
        .energy(args.energy);
    let sim = Simulation::new(&model, options).map_err(|e| in_model(&args.model, e))?;
    match args.format {
        Format::Csv => {}
        Format::Npz => check_npz_size(&args.out, sim.expected_samples(), sim.column_names())?,
        Format::Mat => check_mat(&args.out, sim.expected_samples(), sim.column_names())?,
    }
    let mut pair =
        ResultPair::begin_with(&args.out, Some(&args.model), &[impacts_path(&args.out)])?;
    for note in pair.notes() {
        eprintln!("note: {note}");
    }
    interrupt::remove_on_abort(pair.scratch_paths());
    let result = match args.format {
        Format::Csv => run_csv(&sim, &mut pair, args),
        Format::Npz => run_in_memory(&sim, &mut pair, args, write_npz),
        Format::Mat => run_in_memory(&sim, &mut pair, args, write_mat),
    };
    if interrupt::requested() {
        // Dropping the pair removes both temporary files and the lock file.
        drop(pair);
        return Err(Failure::interrupted());
    }
    let summary = result.map_err(Failure::from)?;
    if !interrupt::begin_commit() {
        drop(pair);
        return Err(Failure::interrupted());
    }
    let log = impacts_csv(&sim.provenance(), &summary);
    pair.commit_with_files(&summary, &[log])?;
    let impacts: usize = summary
        .clearance_joints
        .iter()
        .map(|c| c.impact_count)
        .sum();
    let stats = &summary.solver_stats;
    // Beside the clearance, a drift reads as what it is: a share of the gap under study.
    let relative = model
        .smallest_clearance()
        .map(|c| {
            format!(
                " = {:.2e} of the smallest clearance c = {c:.2e} m",
                summary.max_constraint_violation / c
            )
        })
        .unwrap_or_default();
    eprintln!(
        "{} ({}): {} samples to {} in {:.3} s ({} steps, {} rejected, {} RHS evaluations, {} impacts, max |Phi| = {:.2e}{relative})",
        model.name,
        args.formulation,
        summary.samples,
        args.out.display(),
        summary.wall_time_s,
        stats.steps,
        stats.rejected,
        stats.rhs_evals,
        impacts,
        summary.max_constraint_violation
    );
    // The speed in both units: a speed typed in the wrong one shows here at once.
    for driver in model.drivers.iter().filter(|d| d.speed != 0.0) {
        eprintln!(
            "driver {}: {} rpm = {} rad/s{}",
            driver.name,
            format_for_people(driver.speed * 30.0 / std::f64::consts::PI),
            format_for_people(driver.speed),
            if matches!(driver.motion, DriverMotion::ConstantSpeed) {
                ""
            } else {
                " (the final speed)"
            }
        );
    }
    for joint in &summary.clearance_joints {
        if let Some(p) = &joint.permanent_contact {
            eprintln!(
                "clearance joint {}: in permanent contact since t = {} s (from impact {} of {} to the end of the run, {} s; contact counts as permanent when it lasts at least {} s, {})",
                joint.joint,
                format_for_people(p.since),
                p.impact_index,
                joint.impact_count,
                format_for_people(p.duration),
                format_for_people(p.min_duration),
                match model.drivers.as_slice() {
                    [d] if d.speed != 0.0
                        && (p.min_duration * d.speed.abs() - std::f64::consts::TAU).abs()
                            < 1e-9 =>
                    {
                        "one driver turn"
                    }
                    _ => "a fifth of the run",
                }
            );
        }
    }
    if let Some(first) = summary.singular_passages.first() {
        eprintln!(
            "note: the DAE passed at least {} singular position(s) of the linkage (the first at t = {:.6} s): it keeps the assembly branch by projecting onto the joints near them, and the joint reactions there are not unique (a self-stress of the loop can be added); --formulation generalized integrates the same motion in independent coordinates (docs/formulations.md, \"The DAE at singular positions\")",
            summary.singular_passages.len(),
            first
        );
    }
    Ok(())
}

/// Streams the run into the CSV of `pair`.
fn run_csv(
    sim: &Simulation,
    pair: &mut ResultPair,
    args: &RunArgs,
) -> Result<RunSummary, linkdyn::Error> {
    let provenance = sim.provenance();
    let label = args.out.display().to_string();
    let csv = CsvSink::new(pair.csv().writer(), label, &provenance, sim.column_names())?;
    let mut sink = Watched::new(csv, sim);
    let result = sim.run(&mut sink);
    sink.finish();
    result
}

/// The writer of a result file made from columns in memory ([`write_npz`], [`write_mat`]).
type WriteColumns =
    fn(&mut BufWriter<File>, &Path, &Provenance, &[String], &Columns) -> Result<(), OutputError>;

/// Runs into memory, then writes the file with `write` into the data file of `pair` (not after
/// an interrupt: the pair is dropped then anyway).
fn run_in_memory(
    sim: &Simulation,
    pair: &mut ResultPair,
    args: &RunArgs,
    write: WriteColumns,
) -> Result<RunSummary, linkdyn::Error> {
    let mut columns = Columns::with_capacity(sim.column_names().len(), sim.expected_samples());
    let mut sink = Watched::new(&mut columns, sim);
    let result = sim.run(&mut sink);
    sink.finish();
    let summary = result?;
    if !interrupt::requested() {
        write(
            pair.csv().writer(),
            &args.out,
            &sim.provenance(),
            sim.column_names(),
            &columns,
        )?;
    }
    Ok(summary)
}
