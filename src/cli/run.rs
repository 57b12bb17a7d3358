//! `linkdyn run MODEL …`: integrate and write `F.csv` plus the summary `F.json`, streamed and
//! committed together (see [`linkdyn::output::ResultPair`]).

use super::args::SolveArgs;
use super::progress::Watched;
use super::{Failure, in_model, interrupt};
use clap::Args;
use linkdyn::output::{CsvSink, ResultPair};
use linkdyn::simulation::{FormulationKind, Simulation};
use std::path::PathBuf;

/// Arguments of `run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Model file (TOML).
    model: PathBuf,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion.
    #[arg(long, value_parser = parse_formulation, default_value = "dae")]
    formulation: FormulationKind,
    /// Integrate the energy bookkeeping (DAE only): adds the `energy.*` columns and the energy
    /// balance to the summary.
    #[arg(long)]
    energy: bool,
    /// Output CSV file; the summary goes beside it with the extension `.json`.
    #[arg(long)]
    out: PathBuf,
}

fn parse_formulation(s: &str) -> Result<FormulationKind, String> {
    s.parse().map_err(|e: linkdyn::Error| e.to_string())
}

/// Runs `run`.
pub fn run(args: &RunArgs) -> Result<(), Failure> {
    interrupt::install();
    let model = super::load_model(&args.model, &args.solve.set)?;
    let options = args
        .solve
        .options()?
        .formulation(args.formulation)
        .energy(args.energy);
    let sim = Simulation::new(&model, options).map_err(|e| in_model(&args.model, e))?;
    let mut pair = ResultPair::begin(&args.out, Some(&args.model))?;
    interrupt::remove_on_abort(pair.scratch_paths());
    let provenance = sim.provenance();
    let label = args.out.display().to_string();
    let result = {
        let csv = CsvSink::new(pair.csv().writer(), label, &provenance, sim.column_names())
            .map_err(linkdyn::Error::from)?;
        let mut sink = Watched::new(csv, &sim);
        let result = sim.run(&mut sink);
        sink.finish();
        result
    };
    if interrupt::requested() {
        // Dropping the pair removes both temporary files and the lock file.
        drop(pair);
        return Err(Failure::interrupted());
    }
    let summary = result?;
    if !interrupt::begin_commit() {
        drop(pair);
        return Err(Failure::interrupted());
    }
    pair.commit(&summary)?;
    let impacts: usize = summary.clearance_joints.iter().map(|c| c.impacts).sum();
    let stats = &summary.solver_stats;
    eprintln!(
        "{} ({}): {} samples to {} in {:.3} s ({} steps, {} rejected, {} RHS evaluations, {} impacts, max |Phi| = {:.2e})",
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
    Ok(())
}
