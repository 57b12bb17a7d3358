//! `linkdyn spectrum MODEL --observe COL [--revs N --transient M] --out F.csv`: amplitude
//! spectrum of one output column after the transient, CSV `frequency_hz,amplitude`, and the
//! dominant peaks printed with their multiple of the driving frequency.

use super::Failure;
use super::poincare::{ModelArgs, csv_head, row, write_whole};
use clap::Args;
use linkdyn::output::format_number;
use linkdyn::simulation::analyses;
use std::path::PathBuf;

/// Arguments of `spectrum`.
#[derive(Debug, Args)]
pub struct SpectrumArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Output column to analyse (e.g. `B.ex`).
    #[arg(long)]
    observe: String,
    /// Driver turns dropped before the analysed window.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    transient: f64,
    /// Output CSV file: `frequency_hz,amplitude`.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `spectrum`.
pub fn run(args: &SpectrumArgs) -> Result<(), Failure> {
    let turns = window_turns(&args.model, args.transient)?;
    let sim = args.model.simulation(turns)?;
    // Before any work: a result is not lost to a folder that does not exist.
    linkdyn::output::check_output_file(&args.out, Some(&args.model.model))?;
    let (s, f_drive) = analyses::spectrum(&sim, &args.observe, args.transient)?;
    let mut text = csv_head(
        "frequency_hz,amplitude",
        sim.provenance(),
        &[
            ("observe", args.observe.clone()),
            ("transient_revs", format_number(args.transient)),
            ("window", format!("{:?}", s.window).to_lowercase()),
            ("driving_frequency_hz", format_number(f_drive)),
        ],
    );
    for (f, a) in s.frequencies.iter().zip(&s.amplitudes) {
        text.push_str(&row([*f, *a]));
    }
    write_whole(&args.out, &args.model.model, &text)?;
    eprintln!(
        "{} samples ({} to {} turns), {} bins to {}",
        s.n_samples,
        args.transient,
        turns,
        s.frequencies.len(),
        args.out.display()
    );
    println!("driving frequency: {f_drive:.6} Hz");
    for p in &s.peaks {
        let multiple = p
            .multiple
            .map(|m| format!(" = {m:.3} x driving"))
            .unwrap_or_default();
        println!(
            "peak: {:.6} Hz, amplitude {:.6e}{multiple}",
            p.frequency, p.amplitude
        );
    }
    Ok(())
}

/// Turns integrated: `--revs` (default transient + 10), more than `--transient`.
pub fn window_turns(model: &ModelArgs, transient: f64) -> Result<f64, Failure> {
    model.no_t_end()?;
    if !(transient.is_finite() && transient >= 0.0) {
        return Err(super::poincare::bad(
            "transient",
            format!("expected turns ≥ 0, got {transient}"),
        ));
    }
    let turns = model.solve.revs.unwrap_or(transient + 10.0);
    if !turns.is_finite() || turns <= transient {
        return Err(super::poincare::bad(
            "revs",
            format!("expected more turns than the {transient} transient turns, got {turns}"),
        ));
    }
    Ok(turns)
}
