//! `linkdyn phase MODEL --observe COL [--revs N --transient M] --out F.csv`: phase-portrait data
//! of one output column, CSV `t,value,rate` (the rate column where the run has one, e.g.
//! `B.phi` → `B.omega`, else second-order differences).

use super::Failure;
use super::poincare::{ModelArgs, csv_head, row, write_whole};
use super::spectrum::window_turns;
use clap::Args;
use linkdyn::analysis::RateSource;
use linkdyn::output::format_number;
use linkdyn::simulation::analyses;
use std::path::PathBuf;

/// Arguments of `phase`.
#[derive(Debug, Args)]
pub struct PhaseArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Output column (e.g. `coupler.phi`).
    #[arg(long)]
    observe: String,
    /// Driver turns dropped before the portrait.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    transient: f64,
    /// Output CSV file: `t,value,rate`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `phase`.
pub fn run(args: &PhaseArgs) -> Result<(), Failure> {
    let turns = window_turns(&args.model, args.transient)?;
    let sim = args.model.simulation(turns)?;
    // Before any work: a result is not lost to a folder that does not exist.
    linkdyn::output::check_output_file(&args.out, Some(&args.model.model))?;
    let (t, p) = analyses::phase(&sim, &args.observe, args.transient)?;
    let source = match p.source {
        RateSource::Column => analyses::rate_column(&args.observe).unwrap_or_default(),
        RateSource::CentralDifference => "central differences".to_string(),
    };
    let mut text = csv_head(
        "t,value,rate",
        sim.provenance(),
        &[
            ("observe", args.observe.clone()),
            ("transient_revs", format_number(args.transient)),
            ("rate", source.clone()),
        ],
    );
    for ((t, v), r) in t.iter().zip(&p.value).zip(&p.rate) {
        text.push_str(&row([*t, *v, *r]));
    }
    write_whole(&args.out, &args.model.model, &text)?;
    eprintln!(
        "{} points of {} (rate: {source}) to {}",
        t.len(),
        args.observe,
        args.out.display()
    );
    Ok(())
}
