//! `linkdyn lyapunov MODEL [--revs N --transient M --d0 X --renormalise-every-revs K] --out F.csv`:
//! the largest Lyapunov exponent, CSV `t,lambda` (the running estimate after each
//! renormalisation), and λ ± its batch-means uncertainty printed.

use super::Failure;
use super::poincare::{ModelArgs, csv_head, row, write_whole};
use super::spectrum::window_turns;
use clap::Args;
use linkdyn::output::format_number;
use linkdyn::simulation::analyses::{self, LyapunovSpec};
use std::path::PathBuf;

/// Arguments of `lyapunov`.
#[derive(Debug, Args)]
pub struct LyapunovArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Driver turns integrated before the estimate starts.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    transient: f64,
    /// Initial and renormalised separation in the scaled norm (angles in rad, positions in
    /// units of the longest body arm, velocities times 1/|ω|).
    #[arg(long, default_value_t = 1e-7, allow_negative_numbers = true)]
    d0: f64,
    /// Driver turns between renormalisations.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    renormalise_every_revs: f64,
    /// Output CSV file: `t,lambda`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `lyapunov`.
pub fn run(args: &LyapunovArgs) -> Result<(), Failure> {
    let turns = window_turns(&args.model, args.transient)?;
    let sim = args.model.simulation(turns)?;
    // Before any work: a result is not lost to a folder that does not exist.
    linkdyn::output::check_output_file(&args.out, Some(&args.model.model))?;
    let spec = LyapunovSpec {
        turns,
        transient: args.transient,
        d0: args.d0,
        renormalise_every: args.renormalise_every_revs,
    };
    let e = analyses::lyapunov(&sim, &spec)?;
    let mut text = csv_head(
        "t,lambda",
        sim.provenance(),
        &[
            ("transient_revs", format_number(args.transient)),
            ("d0", format_number(args.d0)),
            (
                "renormalise_every_revs",
                format_number(args.renormalise_every_revs),
            ),
        ],
    );
    for (t, l) in &e.history {
        text.push_str(&row([*t, *l]));
    }
    write_whole(&args.out, &args.model.model, &text)?;
    eprintln!(
        "{} renormalisations ({} steps, {} events) to {}",
        e.history.len(),
        e.stats.steps,
        e.stats.events,
        args.out.display()
    );
    println!(
        "lambda = {:.4} ± {:.4} 1/s (drift over the second half {:.4} 1/s)",
        e.exponent, e.uncertainty, e.drift
    );
    Ok(())
}
